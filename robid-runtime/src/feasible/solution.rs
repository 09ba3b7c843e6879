//! What a feasible-parameter extraction returns, and the checks applied to it.

use std::time::Duration;

use serde::Serialize;

use super::bounds::{Bounds, TENSOR_ELEMENTS};
use super::inertial::{LinkInertial, pseudo_inertia_min_eigenvalue};
use super::problem::Problem;

/// How the parameters were found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Semidefinite program (pseudo-inertia LMIs), global optimum.
    Sdp,
    /// Simulated annealing with random restarts and Nelder-Mead (Gaz et al.).
    Anneal,
    /// Trust-region Newton over the Cholesky factors of the pseudo-inertias (the default).
    Cholesky,
    /// Interior-point method on the convex fit.
    Interior,
}

impl Method {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Method::Sdp => "sdp",
            Method::Anneal => "anneal",
            Method::Cholesky => "cholesky",
            Method::Interior => "interior-point",
        }
    }
}

/// A complete, physically consistent set of link parameters.
#[derive(Debug, Clone, Serialize)]
pub struct Solution {
    /// The method.
    pub method: Method,
    /// Standard parameter names.
    pub names: Vec<String>,
    /// Standard parameter values (about each frame origin).
    pub standard: Vec<f64>,
    /// Per link: mass, centre of mass, inertia about the centre of mass (`None` for a link
    /// whose mass came out zero, possible only with a zero margin and lower mass bound).
    pub links: Vec<Option<LinkInertial>>,
    /// Base parameters K p reproduced by `standard`.
    pub base: Vec<f64>,
    /// Whitened misfit z = L^-1 (K p - beta) per base parameter (|z| <= 1: within one std).
    pub normalized_residual: Vec<f64>,
    /// Sum of z^2.
    pub chi2: f64,
    /// Smallest eigenvalue of each link's pseudo-inertia.
    pub min_eigenvalues: Vec<f64>,
    /// Standard parameters with no effect on the base parameters: their values are the
    /// stated don't-care values (centre of the bounds, or the prior).
    pub dont_care: Vec<String>,
    /// Bounds that the result does not meet (the SDP cannot impose the upper bound on the
    /// principal moments about the centre of mass, which is not convex).
    pub violations: Vec<String>,
    /// Values that sit at one of their bounds (within 0.1 % of the range): the data or a
    /// bound pushed them there, worth a look before the values go into a simulator.
    pub at_bounds: Vec<String>,
    /// Per standard parameter, the share the data determine (1) rather than the prior (0);
    /// empty when not computed.
    pub determined: Vec<f64>,
    /// Wall-clock time of the solve.
    pub seconds: f64,
    /// Newton steps of the interior-point method (0 for the other methods).
    pub iterations: usize,
}

impl Solution {
    /// Assembles the result and its checks; a non-finite number in it is an error.
    pub(crate) fn assemble(
        problem: &Problem,
        bounds: &Bounds,
        method: Method,
        standard: Vec<f64>,
        elapsed: Duration,
    ) -> crate::Result<Solution> {
        if let Some(i) = standard.iter().position(|v| !v.is_finite()) {
            return Err(crate::Error::NonFiniteResult {
                what: format!(
                    "the feasible value of `{}`",
                    problem.standard_names.get(i).cloned().unwrap_or_default()
                ),
                cause: format!(
                    "the {} solver diverged; check the identified values and deviations and the bounds",
                    method.name()
                ),
            });
        }
        let layout = &problem.layout;
        let z = problem.normalized_residual(&standard);
        let mut links = Vec::new();
        let mut min_eigenvalues = Vec::new();
        let mut violations = Vec::new();
        let mut at_bounds = Vec::new();
        let tol = 1e-6;
        for (j, b) in bounds.links.iter().enumerate() {
            let p = layout.link_values(j, &standard);
            min_eigenvalues.push(pseudo_inertia_min_eigenvalue(&p));
            let link = LinkInertial::from_standard(&p);
            if let Some(l) = &link {
                let out = |v: f64, r: [f64; 2]| {
                    v < r[0] - tol * (1.0 + r[0].abs()) || v > r[1] + tol * (1.0 + r[1].abs())
                };
                let mut at = |what: String, v: f64, r: [f64; 2]| {
                    let near = 1e-3 * (r[1] - r[0]).max(1e-12);
                    for (side, bound) in [("lower", r[0]), ("upper", r[1])] {
                        if (v - bound).abs() <= near {
                            at_bounds.push(format!(
                                "link {}: {what} {v:.6e} at its {side} bound {bound}",
                                j + 1
                            ));
                        }
                    }
                };
                at("mass".into(), l.mass, b.mass);
                for a in 0..3 {
                    at(format!("centre of mass [{a}]"), l.com[a], b.com[a]);
                }
                // a moment near a lower bound of zero is a small link, not a pinned one
                let moments = [b.inertia[0].max(f64::MIN_POSITIVE), b.inertia[1]];
                for (a, m) in l.principal_moments().iter().enumerate() {
                    if b.inertia[0] > 0.0 || (*m - b.inertia[1]).abs() < (*m - moments[0]).abs() {
                        at(format!("principal moment {a}"), *m, b.inertia);
                    }
                }
                if out(l.mass, b.mass) {
                    violations.push(format!(
                        "link {}: mass {} outside {:?}",
                        j + 1,
                        l.mass,
                        b.mass
                    ));
                }
                for a in 0..3 {
                    if out(l.com[a], b.com[a]) {
                        violations.push(format!(
                            "link {}: com[{a}] {} outside {:?}",
                            j + 1,
                            l.com[a],
                            b.com[a]
                        ));
                    }
                }
                for (range, (name, row, column)) in b.tensor.iter().zip(TENSOR_ELEMENTS) {
                    let Some(r) = *range else { continue };
                    let v = l.inertia[row][column];
                    at(format!("inertia {name}"), v, r);
                    if out(v, r) {
                        violations
                            .push(format!("link {}: inertia {name} {v} outside {r:?}", j + 1));
                    }
                }
                for (a, m) in l.principal_moments().iter().enumerate() {
                    if out(*m, b.inertia) {
                        violations.push(format!(
                            "link {}: principal moment {a} {m} outside {:?}",
                            j + 1,
                            b.inertia
                        ));
                    }
                }
            }
            links.push(link);
        }
        if let Some(t) = bounds.total_mass {
            let total: f64 = (0..layout.links.len())
                .map(|j| standard[layout.links[j][9]])
                .sum();
            if total < t[0] - tol || total > t[1] + tol {
                violations.push(format!("total mass {total} outside {t:?}"));
            }
        }
        let dont_care = problem
            .no_effect()
            .into_iter()
            .map(|s| problem.standard_names[s].clone())
            .collect();
        let solution = Solution {
            method,
            names: problem.standard_names.clone(),
            base: problem.base_of(&standard).iter().copied().collect(),
            chi2: z.norm_squared(),
            normalized_residual: z.iter().copied().collect(),
            standard,
            links,
            min_eigenvalues,
            dont_care,
            violations,
            at_bounds,
            determined: Vec::new(),
            seconds: elapsed.as_secs_f64(),
            iterations: 0,
        };
        let numbers = solution
            .base
            .iter()
            .chain(&solution.normalized_residual)
            .chain(&solution.min_eigenvalues)
            .chain(std::iter::once(&solution.chi2));
        if numbers.clone().any(|v| !v.is_finite()) {
            return Err(crate::Error::NonFiniteResult {
                what: "the misfit (chi^2) of the feasible parameters".into(),
                cause: "the identified values or their deviations are too extreme for the whitened misfit; check the identification's warnings".into(),
            });
        }
        Ok(solution)
    }

    /// Largest |z|: at most 1 means every base parameter is reproduced within one std.
    pub fn max_normalized_residual(&self) -> f64 {
        self.normalized_residual
            .iter()
            .fold(0.0, |a, z| a.max(z.abs()))
    }
}
