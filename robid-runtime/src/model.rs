//! The slice-based model trait the identification pipeline works with.
//!
//! Implemented by the code `robot_model!` emits (compiled, fixed size) and by the
//! interpreter of a derived program (any description file, at run time). All
//! matrices are row-major slices; every output slice is overwritten completely.

/// A robot's dynamic model in base parameters, as the runtime sees it.
///
/// Conventions: `q`, `qd`, `qdd` have `dof()` entries; `base` has
/// `base_parameter_count()` entries, in the order of `base_parameter_name`.
/// Geometric symbols (lengths kept symbolic in the description) are part of the
/// implementing value, set when it is constructed.
pub trait Model {
    /// Name of the robot, as in its description.
    fn name(&self) -> &str;
    /// Number of joints.
    fn dof(&self) -> usize;
    /// Number of standard parameters (10 per link plus the enabled drive terms).
    fn standard_parameter_count(&self) -> usize;
    /// Name of standard parameter `index` (e.g. `XX1`, `MZ3`, `Fv2`).
    fn standard_parameter_name(&self, index: usize) -> &str;
    /// Number of base parameters.
    fn base_parameter_count(&self) -> usize;
    /// Name of base parameter `index` (e.g. `ZZR1`, `MXR2`).
    fn base_parameter_name(&self, index: usize) -> &str;

    /// Base regressor Y_b(q, qd, qdd): `out` is `dof x base_parameter_count`, row-major,
    /// so that tau = Y_b * base.
    fn base_regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]);
    /// Standard regressor Y(q, qd, qdd): `out` is `dof x standard_parameter_count`, row-major.
    fn standard_regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]);
    /// Inverse dynamics with base parameters, friction and offsets included: `tau` has `dof` entries.
    fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64], base: &[f64], tau: &mut [f64]);
    /// Joint-space inertia matrix M(q) (rotor inertias included): `out` is `dof x dof`, row-major.
    fn mass_matrix(&self, q: &[f64], base: &[f64], out: &mut [f64]);
    /// Gravity torques g(q): `out` has `dof` entries.
    fn gravity(&self, q: &[f64], base: &[f64], out: &mut [f64]);
    /// Coriolis and centripetal torques c(q, qd) (no gravity, no friction): `out` has `dof` entries.
    fn coriolis(&self, q: &[f64], qd: &[f64], base: &[f64], out: &mut [f64]);
    /// Maps standard parameters to base parameters (base = K * standard).
    fn base_from_standard(&self, standard: &[f64], base: &mut [f64]);
}
