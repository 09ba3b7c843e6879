//! A `no_std` firmware example: the models a real-time torque loop needs,
//! compiled by `robot_model!`, with no `std` and no `alloc`.
//!
//! `check.sh` builds it for a Cortex-M4F (`thumbv7em-none-eabihf`), which is the
//! real check that nothing pulls in `std`.
#![no_std]

use robid_runtime::online::{OnlineRls, OnlineRlsError};

robid_macros::robot_model!(file = "../descriptions/ur5e.toml");

robid_macros::robot_model!(
    file = "../descriptions/panda.toml",
    name = "panda_drive",
    drive = [Ia, Fv, Fc, Fo]
);

/// One step of a computed-torque loop for the UR5e in `f32`: the feed-forward
/// torque of the desired state plus a PD correction.
pub fn ur5e_torque(
    base: &[f32; Ur5e::BASE_PARAMETERS],
    desired: (&[f32; 6], &[f32; 6], &[f32; 6]),
    measured: (&[f32; 6], &[f32; 6]),
    gains: (f32, f32),
) -> [f32; 6] {
    let (q, qd, qdd) = desired;
    let mut tau = Ur5e.inverse_dynamics(q, qd, qdd, base);
    for j in 0..6 {
        tau[j] = tau[j] + gains.0 * (q[j] - measured.0[j]) + gains.1 * (qd[j] - measured.1[j]);
    }
    tau
}

/// The Panda's torque with friction and offsets (base parameters with drive terms), in `f32`.
pub fn panda_torque(
    base: &[f32; PandaDrive::BASE_PARAMETERS],
    q: &[f32; 7],
    qd: &[f32; 7],
    qdd: &[f32; 7],
) -> [f32; 7] {
    PandaDrive.inverse_dynamics(q, qd, qdd, base)
}

/// One control period of on-line identification for the UR5e: the base regressor of the
/// measured state (in `f64`) and one recursive least-squares update per joint, with no
/// allocation (Zomaya's Table 1; docs/identification.md#online-recursive-least-squares).
/// The state lives in the caller's memory, e.g. a `static` (about 10 KB for 36 parameters).
pub fn ur5e_identify(
    rls: &mut OnlineRls<{ Ur5e::BASE_PARAMETERS }>,
    state: (&[f64; 6], &[f64; 6], &[f64; 6]),
    tau: &[f64; 6],
) -> Result<(), OnlineRlsError> {
    let rows = Ur5e.base_regressor(state.0, state.1, state.2);
    rls.update_rows(&rows, tau)
}
