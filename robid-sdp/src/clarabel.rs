//! [`ConicSolver`] by Clarabel: the program's triplets as a compressed-column matrix, its
//! cones as Clarabel's.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};
use robid_runtime::feasible::{Cone, ConicFailure, ConicProgram, ConicSolver};

// Clarabel's BLAS and LAPACK symbols: the system OpenBLAS (it holds LAPACK too).
#[link(name = "openblas")]
unsafe extern "C" {}

/// Clarabel's interior-point method (at most 400 iterations, its default tolerances).
#[derive(Debug, Clone, Copy, Default)]
pub struct Clarabel;

impl ConicSolver for Clarabel {
    fn solve(&self, program: &ConicProgram) -> Result<Vec<f64>, ConicFailure> {
        let n = program.variables;
        let a = CscMatrix::new_from_triplets(
            program.b.len(),
            n,
            program.rows.clone(),
            program.columns.clone(),
            program.values.clone(),
        );
        let p = CscMatrix::<f64>::zeros((n, n));
        let cones: Vec<SupportedConeT<f64>> = program
            .cones
            .iter()
            .map(|cone| match *cone {
                Cone::Zero(k) => SupportedConeT::ZeroConeT(k),
                Cone::Nonnegative(k) => SupportedConeT::NonnegativeConeT(k),
                Cone::SecondOrder(k) => SupportedConeT::SecondOrderConeT(k),
                Cone::PsdTriangle(k) => SupportedConeT::PSDTriangleConeT(k),
            })
            .collect();
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .max_iter(400)
            .build()
            .map_err(|e| ConicFailure::Stopped(format!("solver settings: {e}")))?;
        let mut solver = DefaultSolver::new(&p, &program.q, &a, &program.b, &cones, settings)
            .map_err(|e| ConicFailure::Stopped(format!("solver setup: {e:?}")))?;
        solver.solve();
        match solver.solution.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(solver.solution.x.clone()),
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                Err(ConicFailure::Infeasible)
            }
            other => Err(ConicFailure::Stopped(format!("status {other:?}"))),
        }
    }
}
