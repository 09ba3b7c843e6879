//! The reference robots of `robots/` for tests: the one registry, `robots::REFERENCES`,
//! compiled in with `include_str!` so no test reads files at run time.

pub use robots::{REFERENCES as ROBOTS, Reference};

/// The reference robot called `name` (a test's typo is a panic naming it).
pub fn by_name(name: &str) -> &'static Reference {
    Reference::named(name).unwrap_or_else(|| panic!("no reference robot `{name}`"))
}

/// A random Fourier trajectory of reference robot `name` (no drive terms) within its
/// description's position, velocity and acceleration limits, `seconds` long at `rate` Hz:
/// the excitation of the simulated-identification tests.
pub fn random_fourier(
    name: &str,
    seed: u64,
    seconds: f64,
    rate: f64,
) -> robid_runtime::simulate::Trajectory {
    use robid_runtime::excite::{FourierDesign, JointLimits};
    let robot = by_name(name)
        .robot()
        .with_drive(robid_symbolic::Drive::NONE);
    let limits: Vec<JointLimits> = robot
        .joints()
        .iter()
        .map(|j| JointLimits {
            position: j.limits.position.expect("position limits"),
            velocity: j.limits.velocity.expect("velocity limit"),
            acceleration: j.limits.acceleration.expect("acceleration limit"),
            torque: j.limits.torque,
        })
        .collect();
    FourierDesign {
        seed,
        ..FourierDesign::default()
    }
    .random(&limits)
    .unwrap()
    .sample(seconds, rate)
    .unwrap()
}
