//! Shared helpers of the workspace-level integration tests.
//!
//! - [`reference`](mod@reference): the reference robots (descriptions and parameter sets, compiled in);
//! - [`rnea`]: an independent plain-`f64` recursive Newton-Euler, the numeric reference;
//! - [`urdf_rnea`]: the same on a URDF's own frames (whole tree, read with `urdf-rs`), the
//!   reference of robid's URDF reader, anchored to Pinocchio (`tests/reference/urdf/`);
//! - [`scratch`]: a fresh temporary folder per test, removed when the test ends;
//! - [`state`]: random states, smooth trajectories and symbol bindings for evaluation;
//! - [`fuzz_data`]: the known-good UR5e record, the seeds and the cases of the
//!   identification fuzzer (the suite's bad-input tests and `examples/fuzz_identify.rs`).

pub mod fuzz_data;
pub mod reference;
pub mod rnea;
pub mod scratch;
pub mod state;
pub mod urdf_rnea;

/// Defines one `#[test]` per reference robot, each calling `$check("name")`,
/// so a failure names the robot.
#[macro_export]
macro_rules! per_robot {
    ($check:ident) => {
        #[test]
        fn ur5e() {
            $check("ur5e");
        }
        #[test]
        fn puma560() {
            $check("puma560");
        }
        #[test]
        fn rx90() {
            $check("rx90");
        }
        #[test]
        fn tx40() {
            $check("tx40");
        }
        #[test]
        fn lwr4() {
            $check("lwr4");
        }
        #[test]
        fn panda() {
            $check("panda");
        }
        #[test]
        fn stanford() {
            $check("stanford");
        }
    };
}
