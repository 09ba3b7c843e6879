#!/bin/sh
# Builds the no_std firmware example for a Cortex-M4F. A host build of a no_std
# crate does not catch a dependency that enables std, so the embedded target is
# the real check; when it cannot be installed, fall back to a host build and say so.
set -eu
cd "$(dirname "$0")"
TARGET=thumbv7em-none-eabihf
if rustup target list --installed 2>/dev/null | grep -qx "$TARGET" || rustup target add "$TARGET"; then
    echo "robid-firmware: building for $TARGET"
    cargo build -p robid-firmware --release --target "$TARGET"
else
    echo "robid-firmware: WARNING: cannot install $TARGET; host build only (does not prove no_std)" >&2
    cargo build -p robid-firmware --release
fi
