#!/bin/sh
# Time rustc spends expanding macros in the firmware crate, in the dev profile:
# robot_model! for the UR5e and for the Panda with all drive terms (Ia, Fv, Fc, Fo).
# rustc's -Z time-passes is unstable; RUSTC_BOOTSTRAP=1 enables it on a stable toolchain.
# Prints rustc's `macro_expand_crate` line (seconds) and the crate's total compile time.
set -eu
cd "$(dirname "$0")"
touch src/lib.rs
RUSTC_BOOTSTRAP=1 cargo rustc -q -p robid-firmware -- -Z time-passes 2>&1 |
    grep -E "(macro_expand_crate|total)$"
