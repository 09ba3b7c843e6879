//! The gravity coefficients of a model: the combinations of base parameters that the
//! gravity torques g(q) determine (docs/experiments.md#two-step-extraction; Gaz, Flacco,
//! De Luca, "Extracting feasible robot parameters from dynamic coefficients using nonlinear
//! optimization methods", IEEE ICRA 2016, eqs. 7 and 8).
//!
//! g(q) is the inverse dynamics at rest, `g(q) = Y_b(q, 0, 0) beta`. Only the base
//! parameters whose column of `Y_b(q, 0, 0)` is not identically zero enter it (first
//! moments and masses, and a drive's torque offset), and those columns may be dependent
//! once velocities and accelerations are gone. The columns are therefore sampled at random
//! poses and stacked; a column that is zero at every pose is left out; the others are
//! taken in base order and kept when they are independent of the ones kept before (a
//! Gram-Schmidt test on the stack), and each dependent column is folded into the kept ones
//! with the coefficients that reproduce it. Coefficient i is then `beta[kept_i] + sum_j
//! T[i][j] beta[dependent_j]`, named after `kept_i`.

use nalgebra::{DMatrix, DVector};

use super::problem::Problem;
use crate::rng::Rng;
use crate::{Error, Model, Result};

/// The stacked rows `fill` writes (row-major, `base` columns, at most `dof * (dof + 1) / 2`
/// rows per pose) at `3 * base + 8` seeded random poses, joint values uniform in [-pi, pi].
fn stack(
    model: &dyn Model,
    fill: impl Fn(&dyn Model, &[f64], &mut [f64]) -> Result<usize>,
) -> Result<DMatrix<f64>> {
    let (n, nb) = (model.dof(), model.base_parameter_count());
    let per = n * (n + 1) / 2;
    let poses = 3 * nb + 8;
    let mut rows: Vec<f64> = Vec::with_capacity(poses * per * nb);
    let mut rng = Rng::new(0x6A2_2016);
    let mut buffer = vec![0.0; per * nb];
    let mut count = 0;
    for _ in 0..poses {
        let q: Vec<f64> = (0..n)
            .map(|_| rng.uniform(-std::f64::consts::PI, std::f64::consts::PI))
            .collect();
        let written = fill(model, &q, &mut buffer)?;
        rows.extend_from_slice(&buffer[..written * nb]);
        count += written;
    }
    let w = DMatrix::from_row_slice(count, nb, &rows);
    if let Some(v) = w.iter().find(|v| !v.is_finite()) {
        return Err(Error::NonFiniteResult {
            what: "the base regressor at rest".into(),
            cause: format!("the model gave {v}; check the description's geometry"),
        });
    }
    Ok(w)
}

/// A column whose stacked norm is below this share of the largest is zero.
const ZERO_COLUMN: f64 = 1e-10;
/// A column whose part outside the kept columns' span is below this share of its norm is
/// dependent.
const DEPENDENT: f64 = 1e-8;

/// The gravity coefficients of a model as linear combinations of its base parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct GravityCoefficients {
    /// Each coefficient's name: the base parameter it is led by.
    pub names: Vec<String>,
    /// The base parameters (indices) each coefficient is led by.
    pub kept: Vec<usize>,
    /// G, `coefficients x base`: coefficients = G beta.
    pub map: DMatrix<f64>,
}

impl GravityCoefficients {
    /// The gravity coefficients of `model`, found from its base regressor at rest at
    /// `3 * base + 8` random poses (joint values uniform in [-pi, pi], seeded: the result is
    /// reproducible).
    ///
    /// ```
    /// # fn f(model: &dyn robid_runtime::Model) -> robid_runtime::Result<()> {
    /// use robid_runtime::feasible::GravityCoefficients;
    /// let g = GravityCoefficients::of_model(model)?;
    /// println!("gravity determines {} combinations: {:?}", g.names.len(), g.names);
    /// # Ok(()) }
    /// ```
    pub fn of_model(model: &dyn Model) -> Result<GravityCoefficients> {
        let w = stack(model, |model, q, rows| {
            let n = model.dof();
            let zero = vec![0.0; n];
            model.base_regressor_into(
                q,
                &zero,
                &zero,
                &mut rows[..n * model.base_parameter_count()],
            )?;
            Ok(n)
        })?;
        Self::of_columns(model, &w)
    }

    /// The same for the mass matrix (the name notwithstanding): the combinations of base
    /// parameters that M(q) determines, from the stacked rows of its upper triangle,
    /// `M(q) e_k = Y_b(q, 0, e_k) beta - Y_b(q, 0, 0) beta` (row i of column k is entry
    /// `M_ik`; see [`static_rows`](crate::pipeline::static_rows)).
    pub fn of_mass_matrix(model: &dyn Model) -> Result<GravityCoefficients> {
        let w = stack(model, |model, q, rows| {
            let upper =
                crate::pipeline::static_rows(model, q, crate::pipeline::StaticKind::MassMatrix)?;
            rows[..upper.len()].copy_from_slice(&upper);
            Ok(upper.len() / model.base_parameter_count().max(1))
        })?;
        Self::of_columns(model, &w)
    }

    /// The combinations that the stacked columns `w` (one per base parameter) determine.
    fn of_columns(model: &dyn Model, w: &DMatrix<f64>) -> Result<GravityCoefficients> {
        let nb = model.base_parameter_count();
        let largest = (0..nb).map(|b| w.column(b).norm()).fold(0.0, f64::max);
        let mut kept: Vec<usize> = Vec::new();
        let mut basis: Vec<DVector<f64>> = Vec::new();
        let mut dependent: Vec<usize> = Vec::new();
        for b in 0..nb {
            let column = w.column(b).into_owned();
            let norm = column.norm();
            if norm <= ZERO_COLUMN * largest {
                continue;
            }
            let mut rest = column.clone();
            for e in &basis {
                rest -= e * e.dot(&column);
            }
            // a second pass keeps the basis orthogonal to rounding level
            for e in &basis {
                rest -= e * e.dot(&rest);
            }
            if rest.norm() > DEPENDENT * norm {
                basis.push(rest.normalize());
                kept.push(b);
            } else {
                dependent.push(b);
            }
        }
        let mut map = DMatrix::zeros(kept.len(), nb);
        for (i, &b) in kept.iter().enumerate() {
            map[(i, b)] = 1.0;
        }
        if !dependent.is_empty() {
            let wk = DMatrix::from_columns(&kept.iter().map(|&b| w.column(b)).collect::<Vec<_>>());
            let svd = wk
                .try_svd(true, true, f64::EPSILON, crate::limits::SVD_ITERATIONS)
                .ok_or_else(|| Error::Singular {
                    what: "the kept gravity columns".into(),
                    hint: "the base regressor at rest is too ill-conditioned; check the geometry",
                })?;
            for &d in &dependent {
                let t = svd
                    .solve(&w.column(d).into_owned(), 1e-12)
                    .map_err(|e| Error::Singular {
                        what: format!("the gravity column of base parameter {d}: {e}"),
                        hint: "the base regressor at rest is too ill-conditioned; check the geometry",
                    })?;
                for i in 0..kept.len() {
                    map[(i, d)] = t[i];
                }
            }
        }
        let names = kept
            .iter()
            .map(|&b| model.base_parameter_name(b).unwrap_or("?").to_owned())
            .collect();
        Ok(GravityCoefficients { names, kept, map })
    }

    /// The coefficients G beta of base parameters `base`.
    pub fn values(&self, base: &[f64]) -> Result<Vec<f64>> {
        if base.len() != self.map.ncols() {
            return Err(Error::DimensionMismatch {
                what: "base parameters for the gravity coefficients".into(),
                expected: self.map.ncols(),
                found: base.len(),
            });
        }
        Ok((&self.map * DVector::from_column_slice(base))
            .iter()
            .copied()
            .collect())
    }

    /// The extraction problem of the gravity coefficients: K_g = G K over the same standard
    /// parameters as `full` (whose base parameters must be the model's, without extra
    /// columns), with `full`'s target mapped (G beta) and its covariance (G Sigma G'); set
    /// another with [`Problem::with_target`].
    pub fn problem(&self, full: &Problem) -> Result<Problem> {
        if full.k.nrows() != self.map.ncols() {
            return Err(Error::DimensionMismatch {
                what: "base parameters of the problem (rows of K) for the gravity coefficients"
                    .into(),
                expected: self.map.ncols(),
                found: full.k.nrows(),
            });
        }
        let k = &self.map * &full.k;
        let problem = Problem::new(full.standard_names.clone(), self.names.clone(), k)?;
        // Sigma = L L' with L the inverse of the whitening
        let l = full
            .whitening
            .clone()
            .try_inverse()
            .ok_or_else(|| Error::Singular {
                what: "the whitening of the identified base parameters".into(),
                hint: "every base parameter needs a positive, finite variance",
            })?;
        let gl = &self.map * l;
        let covariance = &gl * gl.transpose();
        let target: Vec<f64> = (&self.map * &full.target).iter().copied().collect();
        let problem = problem.with_covariance(&target, &covariance)?;
        match &full.shapes {
            Some(shapes) => problem.with_shapes(shapes.clone()),
            None => Ok(problem),
        }
    }
}
