//! The convex formulation: standard parameters are linear, physical consistency is
//! the linear matrix inequality P_j(p) >= margin * I on every link's pseudo-inertia
//! (Wensing, Kim, Slotine, IEEE RA-L 3(1), 2018;
//! docs/references.md#wensing-kim-and-slotine-2018), bounds on mass, centre of mass and
//! total mass are linear (m c_lo <= h <= m c_hi), so
//!
//! ```text
//! minimise   || A p - b ||  +  (a weak or prior-weighted pull  || D (p - p0) ||, stacked)
//! subject to P_j(p) - margin I  in the PSD cone,  linear bounds,  Ia, Fv, Fc >= 0
//! ```
//!
//! is a second-order-cone / semidefinite program with a global optimum, solved with
//! Clarabel (interior point). For the base-parameter fit A = L^-1 K and b = L^-1 beta
//! (L L' the covariance of beta); on data, A = R K and b = Q' y from the thin QR of the
//! base observation matrix, which is physically consistent least squares.

//!
//! The program goes to a [`ConicSolver`]: the `robid-sdp` crate's Clarabel, whose
//! semidefinite cones need BLAS/LAPACK (OpenBLAS), which a machine with only the Rust
//! toolchain does not have; `robid_sdp::solver()` says how to get it where it is missing.

use std::time::Instant;

use nalgebra::{DMatrix, DVector};

use super::bounds::Bounds;
use super::conic::ConicSolver;
use super::prior::Prior;
use super::problem::Problem;
use super::solution::Solution;
use crate::{Error, Result};

/// Options of the semidefinite formulation.
#[derive(Debug, Clone, PartialEq)]
pub struct SdpOptions {
    /// Optional prior.
    pub prior: Option<Prior>,
    /// Weight of the pull towards the centre of the bounds when there is no prior: it only
    /// settles the directions the base parameters leave free (default 1e-6).
    pub regularization: f64,
}

impl Default for SdpOptions {
    fn default() -> SdpOptions {
        SdpOptions {
            prior: None,
            regularization: 1e-6,
        }
    }
}

/// Physically consistent standard parameters closest (in the covariance metric) to the
/// identified base parameters of `problem`, the conic program solved by `solver`.
pub fn solve_sdp(
    problem: &Problem,
    bounds: &Bounds,
    options: &SdpOptions,
    solver: &dyn ConicSolver,
) -> Result<Solution> {
    let start = Instant::now();
    options.check()?;
    let a = &problem.whitening * &problem.k;
    let b = &problem.whitening * &problem.target;
    solve(problem, bounds, &a, &b, options, solver, start)
}

impl SdpOptions {
    /// Checks the regularization and the prior: finite, non-negative weights, prior values
    /// finite with magnitude at most [`MAX_PARAMETER`](crate::limits::MAX_PARAMETER).
    pub fn check(&self) -> Result<()> {
        let bad = |key: &str, problem: String| Err(Error::setting("SdpOptions", key, problem));
        if !(self.regularization >= 0.0 && self.regularization <= 1e12) {
            return bad(
                "regularization",
                format!("{} must lie in [0, 1e12]", self.regularization),
            );
        }
        if let Some(p) = &self.prior {
            if !(p.weight >= 0.0 && p.weight <= 1e12) {
                return bad(
                    "prior.weight",
                    format!("{} must lie in [0, 1e12]", p.weight),
                );
            }
            if let Some(i) = p
                .standard
                .iter()
                .position(|v| v.is_some_and(|v| !(v.abs() <= crate::limits::MAX_PARAMETER)))
            {
                return bad(
                    "prior.standard",
                    format!(
                        "standard parameter {} of the prior is {:?}; give finite values of magnitude at most {:e}",
                        i + 1,
                        p.standard[i],
                        crate::limits::MAX_PARAMETER
                    ),
                );
            }
        }
        Ok(())
    }
}

/// Physically consistent least squares on data: minimises ||W K p - y|| over standard
/// parameters p under the same constraints, `w` being the base observation matrix
/// (rows x base) and `y` the stacked torques. The solution's normalised residual compares
/// K p with the problem's target (e.g. the unconstrained estimate and its deviations).
pub fn consistent_least_squares(
    problem: &Problem,
    w: &DMatrix<f64>,
    y: &DVector<f64>,
    bounds: &Bounds,
    options: &SdpOptions,
    solver: &dyn ConicSolver,
) -> Result<Solution> {
    let start = Instant::now();
    options.check()?;
    let nb = problem.base_names.len();
    if w.ncols() != nb {
        return Err(Error::DimensionMismatch {
            what: "columns of the observation matrix".to_owned(),
            expected: nb,
            found: w.ncols(),
        });
    }
    if w.nrows() != y.len() {
        return Err(Error::DimensionMismatch {
            what: "torque samples".to_owned(),
            expected: w.nrows(),
            found: y.len(),
        });
    }
    if w.nrows() < nb {
        return Err(Error::TooFewSamples {
            context: "consistent least squares".to_owned(),
            found: w.nrows(),
            required: nb,
            hint: "give at least as many equations as base parameters",
        });
    }
    if w.iter().chain(y.iter()).any(|v| !v.is_finite()) {
        return Err(Error::setting(
            "consistent_least_squares",
            "w",
            "the observation holds NaN or infinite values; remove those samples",
        ));
    }
    let qr = w.clone().qr();
    let a = qr.r() * &problem.k;
    let b = qr.q().transpose() * y;
    solve(problem, bounds, &a, &b, options, solver, start)
}

/// The conic program with the pull of `options` (the prior, else the centre of the bounds).
fn solve(
    problem: &Problem,
    bounds: &Bounds,
    a: &DMatrix<f64>,
    b: &DVector<f64>,
    options: &SdpOptions,
    solver: &dyn ConicSolver,
    start: Instant,
) -> Result<Solution> {
    bounds.check_for(problem.layout.links.len())?;
    let pull = super::prior::Pull::new(
        problem,
        bounds,
        options.prior.as_ref(),
        options.regularization,
    )?;
    let p = super::conic::solve(problem, bounds, a, b, &pull, solver)?;
    let mut solution = Solution::assemble(
        problem,
        bounds,
        super::solution::Method::Sdp,
        p,
        start.elapsed(),
    )?;
    solution.determined = super::prior::determined(problem, &pull);
    solution.unpulled = super::prior::unpulled(problem, &pull);
    Ok(solution)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasible::LinkInertial;
    use crate::feasible::conic::{Cone, ConicFailure, ConicProgram};
    use crate::feasible::fixture::{link, problem, target};

    /// The shapes of the data are checked before any solver runs (a solver that never
    /// solves stands in); settings out of range are refused by name.
    #[test]
    fn data_and_settings_are_checked_first() {
        let p = problem(&target(link(), 0.1));
        let b = Bounds::wide(1);
        let o = SdpOptions::default();
        let w = DMatrix::identity(11, 11);
        let y = DVector::zeros(11);
        let e = consistent_least_squares(&p, &DMatrix::zeros(11, 10), &y, &b, &o, &Stopping)
            .unwrap_err();
        assert!(
            matches!(
                e,
                Error::DimensionMismatch {
                    expected: 11,
                    found: 10,
                    ..
                }
            ),
            "{e}"
        );
        let e =
            consistent_least_squares(&p, &w, &DVector::zeros(12), &b, &o, &Stopping).unwrap_err();
        assert!(
            matches!(
                e,
                Error::DimensionMismatch {
                    expected: 11,
                    found: 12,
                    ..
                }
            ),
            "{e}"
        );
        let e = consistent_least_squares(
            &p,
            &DMatrix::zeros(10, 11),
            &DVector::zeros(10),
            &b,
            &o,
            &Stopping,
        )
        .unwrap_err();
        assert!(
            matches!(
                e,
                Error::TooFewSamples {
                    found: 10,
                    required: 11,
                    ..
                }
            ),
            "{e}"
        );
        let mut bad = w.clone();
        bad[(3, 4)] = f64::NAN;
        let e = consistent_least_squares(&p, &bad, &y, &b, &o, &Stopping).unwrap_err();
        assert!(e.to_string().contains("NaN"), "{e}");
        let mut y_bad = y.clone();
        y_bad[2] = f64::INFINITY;
        assert!(consistent_least_squares(&p, &w, &y_bad, &b, &o, &Stopping).is_err());
        // a prior without values, of weight w
        let weighted = |weight: f64| SdpOptions {
            prior: Some(Prior {
                standard: Vec::new(),
                weight,
            }),
            ..SdpOptions::default()
        };
        for (options, key) in [
            (
                SdpOptions {
                    regularization: -1.0,
                    ..SdpOptions::default()
                },
                "regularization",
            ),
            (
                SdpOptions {
                    regularization: 2e12,
                    ..SdpOptions::default()
                },
                "regularization",
            ),
            (weighted(f64::NAN), "prior.weight"),
            (weighted(-1.0), "prior.weight"),
            (weighted(2e12), "prior.weight"),
            (
                SdpOptions {
                    prior: Some(Prior {
                        standard: vec![None, Some(2e6)],
                        weight: 1.0,
                    }),
                    ..SdpOptions::default()
                },
                "standard parameter 2",
            ),
        ] {
            let e = solve_sdp(&p, &b, &options, &Stopping)
                .unwrap_err()
                .to_string();
            assert!(e.contains(key), "{key}: {e}");
            let e = consistent_least_squares(&p, &w, &y, &b, &options, &Stopping)
                .unwrap_err()
                .to_string();
            assert!(e.contains(key), "{key}: {e}");
        }
        assert!(
            SdpOptions {
                regularization: 1e12,
                ..SdpOptions::default()
            }
            .check()
            .is_ok()
        );
    }

    /// A solver's failures are told as such, after the bounds are checked; the program it
    /// is given is well formed: every entry in its rows and columns, the cones' rows those
    /// of `b`, one PSD cone of dimension 4 per link, the objective the epigraph variable.
    #[test]
    fn the_solver_gets_a_well_formed_program_and_its_failures_are_told() {
        let p = problem(&target(link(), 0.1));
        let mut bad = Bounds::wide(1);
        bad.margin = Some(2.0);
        let e = solve_sdp(&p, &bad, &SdpOptions::default(), &Stopping).unwrap_err();
        assert!(e.to_string().contains("margin"), "{e}");
        let told = |failure: ConicFailure| {
            let solver = Recording {
                program: Default::default(),
                answer: Err(failure),
            };
            let e = solve_sdp(&p, &Bounds::wide(1), &SdpOptions::default(), &solver);
            (e.unwrap_err().to_string(), solver.program.take().unwrap())
        };
        let (e, program) = told(ConicFailure::Infeasible);
        assert!(e.contains("exclude every solution"), "{e}");
        let (e, _) = told(ConicFailure::Stopped("out of iterations".into()));
        assert!(e.contains("stopped (out of iterations)"), "{e}");
        let n = program.variables;
        assert_eq!(n, p.standard_names.len() + 1);
        assert_eq!(program.q.len(), n);
        assert_eq!(program.q.iter().sum::<f64>(), 1.0);
        assert_eq!(program.q[n - 1], 1.0);
        let rows = program.b.len();
        let (r, c, v) = (&program.rows, &program.columns, &program.values);
        assert!(r.len() == c.len() && c.len() == v.len());
        assert!(r.iter().all(|&i| i < rows) && c.iter().all(|&j| j < n));
        assert!(v.iter().all(|x| x.is_finite() && *x != 0.0));
        let covered: usize = program
            .cones
            .iter()
            .map(|cone| match *cone {
                Cone::Zero(k) | Cone::Nonnegative(k) | Cone::SecondOrder(k) => k,
                Cone::PsdTriangle(k) => k * (k + 1) / 2,
            })
            .sum();
        assert_eq!(covered, rows);
        let psd = program.cones.iter().filter(|c| **c == Cone::PsdTriangle(4));
        assert_eq!(psd.count(), p.layout.links.len());
        // a solver's answer of the wrong length is refused, not sliced
        let short = Recording {
            program: Default::default(),
            answer: Ok(vec![0.0; 3]),
        };
        let e = solve_sdp(&p, &Bounds::wide(1), &SdpOptions::default(), &short).unwrap_err();
        assert!(e.to_string().contains("3 values for"), "{e}");
    }

    /// The program's constraints are the bounds', the drive terms' signs and the
    /// pseudo-inertia's, one by one, whatever solver reads them: a consistent link within
    /// its bounds meets every cone, each bound crossed alone breaks one row of the
    /// nonnegative cone (two where the link's and the total mass's ranges both exclude
    /// it), an inertia outside the triangle inequality breaks its PSD cone, and the
    /// second-order cone's rows hold the whitened misfit with the epigraph variable bounding
    /// their norm.
    #[test]
    fn the_program_holds_exactly_the_constraints() {
        let p = problem(&target(link(), 0.1));
        let mut bounds = Bounds::wide(1);
        bounds.links[0].mass = [1.0, 3.0];
        bounds.links[0].com = [[-0.1, 0.1]; 3];
        bounds.total_mass = Some([1.5, 2.5]);
        bounds.margin = Some(1e-6);
        let solver = Recording {
            program: Default::default(),
            answer: Err(ConicFailure::Infeasible),
        };
        solve_sdp(&p, &bounds, &SdpOptions::default(), &solver).unwrap_err();
        let program = solver.program.take().unwrap();
        // the standard values of a link of mass `m` with its centre of mass at `com` and
        // principal moments `moments`, the rotor inertia `ia`, and the epigraph variable
        let at = |m: f64, com: [f64; 3], moments: [f64; 3], ia: f64, t: f64| {
            let inertia = std::array::from_fn(|i| {
                std::array::from_fn(|j| if i == j { moments[i] } else { 0.0 })
            });
            let link = LinkInertial {
                mass: m,
                com,
                inertia,
            }
            .to_standard();
            let mut x = target(link, ia).to_vec();
            x.push(t);
            x
        };
        let moments = [0.03, 0.02, 0.015];
        let broken = |x: &[f64]| broken_rows(&program, x);
        assert_eq!(broken(&at(2.0, [0.0; 3], moments, 0.1, 1e6)), vec![]);
        assert_eq!(
            broken(&at(2.0, [0.09, -0.09, 0.09], moments, 0.0, 1e6)),
            vec![]
        );
        // each linear bound alone: the nonnegative cone's rows, not another cone
        let linear = program
            .cones
            .iter()
            .position(|c| matches!(c, Cone::Nonnegative(_)))
            .unwrap();
        for (m, com, ia, rows) in [
            (1.2, [0.0; 3], 0.1, 1), // below the total mass
            (2.7, [0.0; 3], 0.1, 1), // above it
            (0.8, [0.0; 3], 0.1, 2), // below both
            (3.2, [0.0; 3], 0.1, 2), // above both
            (2.0, [0.12, 0.0, 0.0], 0.1, 1),
            (2.0, [-0.12, 0.0, 0.0], 0.1, 1),
            (2.0, [0.0, 0.12, 0.0], 0.1, 1),
            (2.0, [0.0, -0.12, 0.0], 0.1, 1),
            (2.0, [0.0, 0.0, 0.12], 0.1, 1),
            (2.0, [0.0, 0.0, -0.12], 0.1, 1),
            (2.0, [0.0; 3], -0.01, 1), // a negative rotor inertia
        ] {
            let x = at(m, com, moments, ia, 1e6);
            assert_eq!(
                broken(&x),
                vec![(linear, rows)],
                "mass {m}, com {com:?}, Ia {ia}"
            );
        }
        // an inertia no body has (0.06 > 0.03 + 0.02): its PSD cone alone
        let psd = program
            .cones
            .iter()
            .position(|c| matches!(c, Cone::PsdTriangle(_)))
            .unwrap();
        let x = at(2.0, [0.0; 3], [0.03, 0.02, 0.06], 0.1, 1e6);
        assert_eq!(broken(&x), vec![(psd, 1)]);
        // the second-order cone: its first rows are the whitened misfit K p - beta, and the
        // epigraph variable (the objective) bounds the norm of all its other rows
        let Cone::SecondOrder(n) = program.cones[0] else {
            panic!("the second-order cone comes first: {:?}", program.cones)
        };
        let x = at(2.4, [0.05, 0.0, -0.02], moments, 0.2, 0.0);
        let s = slacks(&program, &x);
        let misfit = p.normalized_residual(&x[..x.len() - 1]);
        assert!(misfit.norm() > 1.0, "{misfit}");
        for (k, z) in misfit.iter().enumerate() {
            assert!(
                (s[1 + k] - z).abs() < 1e-9 * misfit.norm(),
                "{k}: {} vs {z}",
                s[1 + k]
            );
        }
        let tail = s[1..n].iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut x = x;
        *x.last_mut().unwrap() = tail * (1.0 + 1e-9);
        assert_eq!(broken(&x), vec![]);
        *x.last_mut().unwrap() = tail * (1.0 - 1e-6);
        assert_eq!(broken(&x), vec![(0, 1)]);
    }

    /// `s = b - A x` of `program` at `x`: in the cones where `x` meets the constraints.
    fn slacks(program: &ConicProgram, x: &[f64]) -> Vec<f64> {
        let mut s = program.b.clone();
        for ((&i, &j), &v) in program
            .rows
            .iter()
            .zip(&program.columns)
            .zip(&program.values)
        {
            s[i] -= v * x[j];
        }
        s
    }

    /// The cones of `program` that `x` breaks, each with its number of broken rows (1 for
    /// a second-order or PSD cone), to a tolerance of 1e-12.
    fn broken_rows(program: &ConicProgram, x: &[f64]) -> Vec<(usize, usize)> {
        let s = slacks(program, x);
        let mut start = 0;
        let mut broken = Vec::new();
        for (k, cone) in program.cones.iter().enumerate() {
            let (rows, count) = match *cone {
                Cone::Zero(n) => (
                    n,
                    s[start..start + n]
                        .iter()
                        .filter(|v| v.abs() > 1e-12)
                        .count(),
                ),
                Cone::Nonnegative(n) => (
                    n,
                    s[start..start + n].iter().filter(|&&v| v < -1e-12).count(),
                ),
                Cone::SecondOrder(n) => {
                    let tail = s[start + 1..start + n].iter().map(|v| v * v).sum::<f64>();
                    (n, usize::from(s[start] < tail.sqrt()))
                }
                Cone::PsdTriangle(d) => {
                    // the upper triangle column by column, off-diagonals times sqrt(2)
                    let mut m = DMatrix::zeros(d, d);
                    let mut r = start;
                    for j in 0..d {
                        for i in 0..=j {
                            let v = if i == j {
                                s[r]
                            } else {
                                s[r] / std::f64::consts::SQRT_2
                            };
                            m[(i, j)] = v;
                            m[(j, i)] = v;
                            r += 1;
                        }
                    }
                    let lowest = m.symmetric_eigenvalues().min();
                    (d * (d + 1) / 2, usize::from(lowest < -1e-12))
                }
            };
            if count > 0 {
                broken.push((k, count));
            }
            start += rows;
        }
        assert_eq!(start, s.len());
        broken
    }

    /// A solver that never solves.
    #[derive(Debug)]
    struct Stopping;

    impl ConicSolver for Stopping {
        fn solve(&self, _: &ConicProgram) -> std::result::Result<Vec<f64>, ConicFailure> {
            Err(ConicFailure::Stopped("the test's solver".into()))
        }
    }

    /// A solver that keeps the program it is given and gives `answer`.
    #[derive(Debug)]
    struct Recording {
        program: std::cell::RefCell<Option<ConicProgram>>,
        answer: std::result::Result<Vec<f64>, ConicFailure>,
    }

    impl ConicSolver for Recording {
        fn solve(&self, program: &ConicProgram) -> std::result::Result<Vec<f64>, ConicFailure> {
            self.program.replace(Some(program.clone()));
            self.answer.clone()
        }
    }
}
