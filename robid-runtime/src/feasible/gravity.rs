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

    /// The terms of combination `i`: (base parameter, coefficient), the one that leads it
    /// first (coefficient 1), then those of the base parameters it absorbs, in order;
    /// coefficients within 1e-9 of zero (the numeric fit's rounding) left out.
    pub fn terms(&self, i: usize) -> Vec<(usize, f64)> {
        let lead = self.kept[i];
        std::iter::once((lead, 1.0))
            .chain(
                (0..self.map.ncols())
                    .filter(|&b| b != lead)
                    .map(|b| (b, self.map[(i, b)]))
                    .filter(|(_, c)| c.abs() > 1e-9),
            )
            .collect()
    }

    /// Combination `i` as text with the base parameters named by `name`, e.g. `MY2 - MZ3`
    /// or `MX2 + 0.425 M3`: a coefficient within 1e-9 of 1 in size is a sign, others have
    /// six significant digits.
    pub fn expression(&self, i: usize, name: impl Fn(usize) -> String) -> String {
        let mut text = String::new();
        for (k, (b, c)) in self.terms(i).into_iter().enumerate() {
            let sign = if c < 0.0 { "-" } else { "+" };
            let size = if (c.abs() - 1.0).abs() <= 1e-9 {
                String::new()
            } else {
                let rounded: f64 = format!("{:.5e}", c.abs()).parse().unwrap_or(c.abs());
                format!("{} ", crate::num(rounded))
            };
            text += &match (k, sign) {
                (0, "+") => format!("{size}{}", name(b)),
                (0, _) => format!("-{size}{}", name(b)),
                _ => format!(" {sign} {size}{}", name(b)),
            };
        }
        text
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
        // G Sigma G' of a floored covariance is positive definite, though as ill-conditioned
        // as Sigma (a parameter known exactly has the floor's variance beside deviations of
        // 1e3): with_covariance's test for exact combinations is for covariances as given
        let problem = problem.floored(&target, covariance)?;
        match &full.shapes {
            Some(shapes) => problem.with_shapes(shapes.clone()),
            None => Ok(problem),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasible::fixture::problem;
    use crate::model::{LengthError, ProgramKind, check_arguments};

    /// A 2-joint model whose base regressor is written by hand (base parameters A..E):
    /// at rest row 1 is [cos q1, 2 cos q1, sin(q1 + q2), 0, 1] and row 2
    /// [0, 0, sin(q1 + q2), 0, 0], so B's gravity column is twice A's, D has none and E is
    /// a constant offset; D's column is qdd1 + qdd2 in row 1 and qdd2 in row 2, its mass
    /// matrix [[1, 1], [., 1]]. `poison` puts a NaN in E's column.
    /// With `dof` above 2, joint j >= 3 adds the row `[0, 0, 0, qdd_j, 0]` and its
    /// acceleration to D's entry in row 1.
    struct Hand {
        names: Vec<String>,
        poison: bool,
        dof: usize,
        /// Factors of C's and E's columns.
        scale: [f64; 2],
    }

    impl Hand {
        fn new(poison: bool) -> Self {
            let names = ["A", "B", "C", "D", "E"].map(String::from).to_vec();
            Self {
                names,
                poison,
                dof: 2,
                scale: [1.0; 2],
            }
        }
    }

    impl Model for Hand {
        fn name(&self) -> &str {
            "hand"
        }
        fn dof(&self) -> usize {
            self.dof
        }
        fn standard_parameter_count(&self) -> usize {
            5
        }
        fn standard_parameter_name(&self, index: usize) -> Option<&str> {
            self.names.get(index).map(String::as_str)
        }
        fn base_parameter_count(&self) -> usize {
            5
        }
        fn base_parameter_name(&self, index: usize) -> Option<&str> {
            self.names.get(index).map(String::as_str)
        }
        fn run(
            &self,
            program: ProgramKind,
            inputs: &[&[f64]],
            output: &mut [f64],
        ) -> std::result::Result<(), LengthError> {
            check_arguments(program, self.sizes(), inputs, output)?;
            output.fill(0.0);
            if let (ProgramKind::BaseRegressor, [q, _, qdd]) = (program, inputs) {
                let (c1, s12) = (q[0].cos(), (q[0] + q[1]).sin());
                let e = if self.poison { f64::NAN } else { self.scale[1] };
                let (all, c): (f64, f64) = (qdd.iter().sum(), s12 * self.scale[0]);
                output[..5].copy_from_slice(&[c1, 2.0 * c1, c, all, e]);
                output[5..10].copy_from_slice(&[0.0, 0.0, c, qdd[1], 0.0]);
                for j in 2..self.dof {
                    output[5 * j + 3] = qdd[j];
                }
            }
            Ok(())
        }
    }

    #[test]
    fn dependent_columns_fold_into_the_kept_and_zero_ones_drop() {
        let g = GravityCoefficients::of_model(&Hand::new(false)).unwrap();
        assert_eq!(g.names, ["A", "C", "E"]);
        assert_eq!(g.kept, [0, 2, 4]);
        let want = DMatrix::from_row_slice(
            3,
            5,
            &[
                1.0, 2.0, 0.0, 0.0, 0.0, //
                0.0, 0.0, 1.0, 0.0, 0.0, //
                0.0, 0.0, 0.0, 0.0, 1.0,
            ],
        );
        // the fold's coefficient 2 comes from a least-squares solve: to rounding
        assert!((&g.map - want).amax() < 1e-12, "{}", g.map);
        let v = g.values(&[1.0, 0.5, -2.0, 7.0, 3.0]).unwrap();
        assert!(
            (v[0] - 2.0).abs() < 1e-12 && v[1] == -2.0 && v[2] == 3.0,
            "{v:?}"
        );
        assert!(matches!(
            g.values(&[1.0; 4]),
            Err(Error::DimensionMismatch {
                expected: 5,
                found: 4,
                ..
            })
        ));
    }

    /// A combination's terms and text: its leading parameter, then those it absorbs with
    /// their coefficients (a coefficient of one in size a sign, rounding left out).
    #[test]
    fn a_combination_is_written_with_the_parameters_it_absorbs() {
        let hand = Hand::new(false);
        let g = GravityCoefficients::of_model(&hand).unwrap();
        let name = |b: usize| hand.names[b].clone();
        let terms = g.terms(0);
        assert_eq!(terms.iter().map(|t| t.0).collect::<Vec<_>>(), [0, 1]);
        assert!((terms[0].1 - 1.0).abs() < 1e-12 && (terms[1].1 - 2.0).abs() < 1e-12);
        assert_eq!(
            [0, 1, 2].map(|i| g.expression(i, name)),
            ["A + 2 B", "C", "E"]
        );
        let fitted = GravityCoefficients {
            names: vec!["A".into()],
            kept: vec![0],
            map: DMatrix::from_row_slice(1, 5, &[1.0, -1.0 + 1e-13, 1e-12, 0.4250000001, -3.0]),
        };
        assert_eq!(fitted.expression(0, name), "A - B + 0.425 D - 3 E");
    }

    #[test]
    fn the_mass_matrix_determines_only_what_the_accelerations_see() {
        let m = GravityCoefficients::of_mass_matrix(&Hand::new(false)).unwrap();
        assert_eq!(m.names, ["D"]);
        assert_eq!(m.map.shape(), (1, 5));
        assert_eq!(m.map[(0, 3)], 1.0);
        assert_eq!(m.map.sum(), 1.0);
    }

    /// The stack has 3 x base + 8 poses of one row per joint at rest, and room for the
    /// n (n + 1) / 2 rows of a mass matrix's upper triangle (6 for three joints).
    #[test]
    fn the_stack_has_its_poses_and_room_for_the_upper_triangle() {
        let hand = Hand::new(false);
        let w = stack(&hand, |_, _, _| Ok(2)).unwrap();
        assert_eq!(w.shape(), ((3 * 5 + 8) * 2, 5));
        let three = Hand { dof: 3, ..hand };
        let w = stack(&three, |_, _, rows| {
            rows.fill(1.0);
            Ok(6)
        })
        .unwrap();
        assert_eq!(w.nrows(), (3 * 5 + 8) * 6);
        let m = GravityCoefficients::of_mass_matrix(&three).unwrap();
        assert_eq!(m.names, ["D"]);
    }

    /// A column below 1e-10 of the largest is zero (E at 1e-11 against B's 9.6); a small
    /// one above that is independent when its part outside the others' span is above
    /// 1e-8 of its own norm, whatever its size (C at 1e-6).
    #[test]
    fn small_columns_are_judged_relative_to_their_sizes() {
        let hand = Hand {
            scale: [1e-6, 1e-11],
            ..Hand::new(false)
        };
        let g = GravityCoefficients::of_model(&hand).unwrap();
        assert_eq!(g.names, ["A", "C"]);
    }

    #[test]
    fn a_non_finite_regressor_is_refused() {
        let e = GravityCoefficients::of_model(&Hand::new(true)).unwrap_err();
        assert!(matches!(e, Error::NonFiniteResult { .. }), "{e}");
    }

    /// The coefficients' problem: K_g = G K, target G beta and covariance G Sigma G'
    /// (with the solvers' variance floor), the shapes carried over.
    #[test]
    fn the_coefficients_problem_maps_k_the_target_and_the_covariance() {
        let g = GravityCoefficients::of_model(&Hand::new(false)).unwrap();
        let full = problem(&[0.0; 11]);
        let mut k = DMatrix::zeros(5, 11);
        for (b, s) in [(0, 9), (1, 6), (2, 7), (3, 0), (4, 10)] {
            k[(b, s)] = 1.0 + b as f64;
        }
        let names = ["A", "B", "C", "D", "E"].map(String::from).to_vec();
        let full = Problem::new(full.standard_names, names, k.clone())
            .unwrap()
            .with_target(&[1.0, 0.5, -2.0, 7.0, 3.0], &[0.1, 0.2, 0.3, 0.4, 0.5])
            .unwrap()
            .with_shapes(vec![crate::feasible::LinkShape {
                from: [0.0; 3],
                to: [0.0, 0.0, 0.4],
            }])
            .unwrap();
        let p = g.problem(&full).unwrap();
        assert_eq!(p.base_names, ["A", "C", "E"]);
        assert!((&p.k - &g.map * &k).amax() < 1e-15);
        assert!((p.target[0] - 2.0).abs() < 1e-12 && p.target[1] == -2.0 && p.target[2] == 3.0);
        // var(A + 2B) = 0.1^2 + 4 * 0.2^2 plus the floors of the full problem's variances
        let sigma = full.std.map(|s| s * s);
        let want = sigma[0] + 4.0 * sigma[1];
        let floor = |v: f64| (1e-5 * v + 1e-8 * 3.0 + 1e-12).powi(2);
        assert!(
            (p.std[0] * p.std[0] - want - floor(2.0)).abs() < 1e-12,
            "{}",
            p.std
        );
        assert!(
            (p.std[2] * p.std[2] - sigma[4] - floor(3.0)).abs() < 1e-12,
            "{}",
            p.std
        );
        assert!(p.shapes.is_some());
        // parameters known exactly (deviation 0, the floor's variance) beside a loose one:
        // the coefficients A + B and A + 2 C are correlated to 1 - 1e-16, yet a covariance
        let loose = Problem::new(
            p.standard_names.clone(),
            ["A", "B", "C"].map(String::from).to_vec(),
            k.rows(0, 3).into_owned(),
        )
        .unwrap()
        .with_target(&[1.0, 0.5, -2.0], &[1e3, 0.0, 0.0])
        .unwrap();
        let tied = GravityCoefficients {
            names: vec!["A".into(), "A2".into()],
            kept: vec![0, 0],
            map: DMatrix::from_row_slice(2, 3, &[1.0, 1.0, 0.0, 1.0, 0.0, 2.0]),
        };
        let p = tied.problem(&loose).unwrap();
        assert!((p.target[0] - 1.5).abs() < 1e-12 && (p.target[1] + 3.0).abs() < 1e-12);
        let wrong = problem(&[0.0; 11]);
        assert!(matches!(
            g.problem(&wrong),
            Err(Error::DimensionMismatch {
                expected: 5,
                found: 11,
                ..
            })
        ));
    }
}
