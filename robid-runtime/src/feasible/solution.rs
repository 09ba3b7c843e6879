//! What a feasible-parameter extraction returns, and the checks applied to it.

use std::time::Duration;

use serde::Serialize;

use super::bounds::{Bounds, TENSOR_ELEMENTS};
use super::inertial::{LinkInertial, pseudo_inertia_min_eigenvalue};
use super::problem::Problem;
use crate::Num;

/// How the parameters were found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Semidefinite program (pseudo-inertia LMIs), global optimum.
    Sdp,
    /// Simulated annealing with random restarts and Nelder-Mead (Gaz et al.).
    Anneal,
    /// Trust-region Newton over the Cholesky factors of the pseudo-inertias.
    Cholesky,
    /// Interior-point method on the convex fit (the command line's default).
    Interior,
}

impl Method {
    /// Whether the method imposes bounds of this kind, so that a result outside one is a
    /// failure of the fit (or of bounds that contradict each other or the physics) rather
    /// than a limit of the method: every method imposes the masses, the centres of mass and
    /// the total mass; all but the SDP the single elements of the inertia tensor, which are
    /// not convex in its variables; the global search also the upper bound on the principal
    /// moments, which its parametrisation holds as variables (it raises its penalty until
    /// every bound is met). The convex methods cannot impose that upper bound (not convex;
    /// the smooth methods bound the diagonal instead).
    pub fn imposes(self, kind: BoundKind) -> bool {
        match kind {
            BoundKind::Mass | BoundKind::Com | BoundKind::TotalMass => true,
            BoundKind::Element => self != Method::Sdp,
            BoundKind::PrincipalMoment => self == Method::Anneal,
        }
    }

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Method::Sdp => "sdp",
            Method::Anneal => "anneal",
            Method::Cholesky => "cholesky",
            Method::Interior => "interior-point",
        }
    }

    /// Where the values of the parameters the data do not see ([`Solution::dont_care`])
    /// come from, for messages: the prior (the user's, else the default one) where the
    /// physical constraints and bounds let them be, or for `anneal` without a user's
    /// prior, the search within the bounds. (The constraints can move them: a mass the
    /// data do not see is pushed to its bound by first moments the data do see.)
    pub fn dont_care_source(self) -> &'static str {
        match self {
            Method::Anneal => {
                "from the prior if one is given (the default prior where it gives none, or \
                 as near to them as the physical constraints and bounds allow; values held \
                 fixed or tied by an equality stay the search's), else from the search \
                 within the bounds"
            }
            Method::Sdp | Method::Cholesky | Method::Interior => {
                "from the prior (the default prior where none is given), or the nearest to \
                 them that the physical constraints and bounds allow"
            }
        }
    }
}

/// What a bound limits, for [`Method::imposes`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BoundKind {
    /// A link's mass.
    Mass,
    /// A coordinate of a link's centre of mass.
    Com,
    /// One element of a link's inertia tensor about its centre of mass.
    Element,
    /// A principal moment of a link's inertia about its centre of mass.
    PrincipalMoment,
    /// The sum of the link masses.
    TotalMass,
}

/// A complete, physically consistent set of link parameters.
#[derive(Debug, Clone, Serialize)]
pub struct Solution {
    /// The method.
    pub method: Method,
    /// Standard parameter names, then the extra columns' ([`Solution::extra_columns`]).
    pub names: Vec<String>,
    /// The free terms among `names`: extra columns of the identification config, not
    /// parameters of the chain, whatever their names (an extra column `Fv1` of a robot
    /// without drive terms was written as its friction, where it was negative).
    pub extra_columns: Vec<String>,
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
    /// Those of [`Solution::dont_care`] that no prior pulls (a weight of 0: `--prior-weight
    /// 0`): nothing sets them but the start of the solver and the physical constraints and
    /// bounds, so they are not the prior's values ([`Solution::dont_care_note`]). Empty
    /// when every one is pulled, or when the method was given no pull (`anneal` without a
    /// prior: [`Method::dont_care_source`] says so).
    pub unpulled: Vec<String>,
    /// Bounds that the result does not meet (the SDP cannot impose the upper bound on the
    /// principal moments about the centre of mass, which is not convex).
    pub violations: Vec<String>,
    /// Those of [`Solution::violations`] that the method imposes ([`Method::imposes`]):
    /// the fit did not reach the bounds it was asked to meet, so the result is no answer
    /// (the command line writes nothing then).
    pub unmet: Vec<String>,
    /// Values that sit at one of their bounds (within 0.1 % of the range, 1e-6 of it from a
    /// bound of zero): the data or a bound pushed them there, worth a look before the
    /// values go into a simulator.
    pub at_bounds: Vec<String>,
    /// Links that no body of their size can be: a centre of mass far outside the link, or
    /// a speck of mass with a beam's inertia (`prior::implausible`). The fit is
    /// consistent, but the data left these links free and nothing held them: worth a bound
    /// or a prior before the values go into a simulator. Empty without link shapes.
    pub implausible: Vec<String>,
    /// Per standard parameter, the share the data determine (1) rather than the prior (0);
    /// empty when not computed.
    pub determined: Vec<f64>,
    /// Wall-clock time of the solve.
    pub seconds: f64,
    /// Steps of the method: Newton steps (interior point), trust-region steps (smooth),
    /// restarts run (global search; fewer than asked when one met the target first); 0 for
    /// the others.
    pub iterations: usize,
    /// The pure-Rust methods' objective at the result without the bounds' penalty: the
    /// data's chi^2 plus the prior's, in chi^2 units. The interior-point and Cholesky fits
    /// minimise the same, so where both meet the bounds the lower value is the better fit.
    /// `None` for the other methods.
    pub objective: Option<f64>,
}

/// See [`Solution::short_of`]: the share of the optimum's prior part (chi^2 units) by
/// which another fit's objective may exceed it. Fits that reach the optimum were measured
/// within 1.6e-4 of the objective (UR5e, Panda, TX40, 1 % noise), a stopped Cholesky fit
/// 33 % to 50 % above it.
pub const SHORT_SHARE: f64 = 1e-2;

/// The axes of a centre of mass, for messages.
const AXES: [&str; 3] = ["x", "y", "z"];

/// A bound's range in a message, each end written short.
fn range(r: [f64; 2]) -> String {
    format!("[{}, {}]", Num(r[0]), Num(r[1]))
}

/// A computed value outside a bound, for a message: eight significant digits, which tell
/// it from the bound (it is outside by at least 1e-6 of the bound's size) without the
/// arithmetic's every digit (`7.998630808139301`).
fn outside(v: f64) -> Num {
    Num::rounded(v, 8)
}

impl Solution {
    /// Where the values of [`Solution::dont_care`] come from, for messages: `values
    /// {source}: NAMES` ([`Method::dont_care_source`]) for those a prior pulls, and for those
    /// none pulls ([`Solution::unpulled`]) that they are wherever the solver stopped, not the
    /// prior's: with `--prior-weight 0` the message said "values from the prior" of values
    /// the prior had only started the solver from (a mass at its lower bound of 0.05 kg).
    /// Empty when the data see every parameter.
    pub fn dont_care_note(&self) -> String {
        let (free, pulled): (Vec<&str>, Vec<&str>) = self
            .dont_care
            .iter()
            .map(String::as_str)
            .partition(|n| self.unpulled.iter().any(|u| u == n));
        let mut parts = Vec::new();
        if !pulled.is_empty() {
            parts.push(format!(
                "values {}: {}",
                self.method.dont_care_source(),
                pulled.join(" ")
            ));
        }
        if !free.is_empty() {
            parts.push(format!(
                "values that no prior pulls (its weight is 0), so wherever the solver stopped \
                 within the physical constraints and bounds, not the prior's (a prior weight \
                 above 0 or --bounds settle them): {}",
                free.join(" ")
            ));
        }
        parts.join("; ")
    }

    /// Whether `name` is a standard parameter of the chain (an inertial parameter or a drive
    /// term of one of its links), not an extra column of the identification config.
    pub fn is_chain_parameter(&self, name: &str) -> bool {
        !self.extra_columns.iter().any(|e| e == name)
            && name
                .parse::<robid_core::ParameterId>()
                .is_ok_and(|id| id.link < self.links.len())
    }

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
        let mut unmet = Vec::new();
        let mut violated = |kind: BoundKind, text: String| {
            if method.imposes(kind) {
                unmet.push(text.clone());
            }
            violations.push(text);
        };
        let mut at_bounds = Vec::new();
        let tol = 1e-6;
        let out = |v: f64, r: [f64; 2]| {
            v < r[0] - tol * (1.0 + r[0].abs()) || v > r[1] + tol * (1.0 + r[1].abs())
        };
        for (j, b) in bounds.links.iter().enumerate() {
            let p = layout.link_values(j, &standard);
            min_eigenvalues.push(pseudo_inertia_min_eigenvalue(&p));
            let link = LinkInertial::from_standard(&p);
            if let Some(l) = &link {
                let mut at = |what: String, v: f64, r: [f64; 2]| {
                    if !out(v, r) {
                        let link = at_bound(&what, v, r).map(|t| format!("link {}: {t}", j + 1));
                        at_bounds.extend(link);
                    }
                };
                at("mass".into(), l.mass, b.mass);
                for (a, axis) in AXES.iter().enumerate() {
                    at(format!("centre of mass {axis}"), l.com[a], b.com[a]);
                }
                // a moment near a lower bound of zero is a small link, not a pinned one
                let moments = [b.inertia[0].max(f64::MIN_POSITIVE), b.inertia[1]];
                for (a, m) in l.principal_moments().iter().enumerate() {
                    if b.inertia[0] > 0.0 || (*m - b.inertia[1]).abs() < (*m - moments[0]).abs() {
                        at(format!("principal moment {}", a + 1), *m, b.inertia);
                    }
                }
                if out(l.mass, b.mass) {
                    violated(
                        BoundKind::Mass,
                        format!(
                            "link {}: mass {} outside {}",
                            j + 1,
                            outside(l.mass),
                            range(b.mass)
                        ),
                    );
                }
                for (a, axis) in AXES.iter().enumerate() {
                    if out(l.com[a], b.com[a]) {
                        violated(
                            BoundKind::Com,
                            format!(
                                "link {}: centre of mass {axis} {} outside {}",
                                j + 1,
                                outside(l.com[a]),
                                range(b.com[a])
                            ),
                        );
                    }
                }
                for (given, (name, row, column)) in b.tensor.iter().zip(TENSOR_ELEMENTS) {
                    let Some(r) = *given else { continue };
                    let v = l.inertia[row][column];
                    at(format!("inertia {name}"), v, r);
                    if out(v, r) {
                        violated(
                            BoundKind::Element,
                            format!(
                                "link {}: inertia {name} {} outside {}",
                                j + 1,
                                outside(v),
                                range(r)
                            ),
                        );
                    }
                }
                for (a, m) in l.principal_moments().iter().enumerate() {
                    if out(*m, b.inertia) {
                        violated(
                            BoundKind::PrincipalMoment,
                            format!(
                                "link {}: principal moment {} {} outside {}",
                                j + 1,
                                a + 1,
                                outside(*m),
                                range(b.inertia)
                            ),
                        );
                    }
                }
            }
            links.push(link);
        }
        if let Some(t) = bounds.total_mass {
            let total: f64 = (0..layout.links.len())
                .map(|j| standard[layout.links[j][9]])
                .sum();
            if out(total, t) {
                violated(
                    BoundKind::TotalMass,
                    format!("total mass {} outside {}", outside(total), range(t)),
                );
            } else {
                // it was never named, though every method can end on it
                at_bounds.extend(at_bound("total mass", total, t));
            }
        }
        let dont_care = problem
            .no_effect()
            .into_iter()
            .map(|s| problem.standard_names[s].clone())
            .collect();
        let implausible = super::prior::implausible(problem, bounds, &links);
        let solution = Solution {
            method,
            names: problem.standard_names.clone(),
            extra_columns: problem
                .layout
                .extra
                .iter()
                .map(|&i| problem.standard_names[i].clone())
                .collect(),
            base: problem.base_of(&standard).iter().copied().collect(),
            chi2: z.norm_squared(),
            normalized_residual: z.iter().copied().collect(),
            standard,
            links,
            min_eigenvalues,
            dont_care,
            unpulled: Vec::new(),
            violations,
            unmet,
            at_bounds,
            implausible,
            determined: Vec::new(),
            seconds: elapsed.as_secs_f64(),
            iterations: 0,
            objective: None,
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

    /// Where this fit's objective ([`Solution::objective`]) lies above `optimum`'s, a fit
    /// of the same problem that reached the optimum, by more than [`SHORT_SHARE`] of the
    /// optimum's prior part (plus 1e-6 of its objective), the message saying by how much
    /// and which value differs most; `None` when it does not, or either has no objective.
    ///
    /// The Cholesky fit can stop short where the data are far firmer than the prior
    /// (docs/experiments.md#cholesky-parametrisation): on noise-free UR5e data its
    /// objective was 50 % above the interior-point method's and a mass 0.49 kg off, in
    /// directions only the prior decides, where fits that reach the optimum agree within
    /// 0.02 % of the objective.
    pub fn short_of(&self, optimum: &Solution) -> Option<String> {
        let (mine, best) = (self.objective?, optimum.objective?);
        let prior = (best - optimum.chi2).max(0.0);
        if mine - best <= SHORT_SHARE * prior + 1e-6 * (1.0 + best.abs()) {
            return None;
        }
        let (k, difference) = self
            .standard
            .iter()
            .zip(&optimum.standard)
            .map(|(a, b)| (a - b).abs())
            .enumerate()
            .fold(
                (0, 0.0f64),
                |worst, (k, d)| if d > worst.1 { (k, d) } else { worst },
            );
        Some(format!(
            "the {} fit stopped short of the optimum: objective {} against {} (data and \
             prior, chi^2 units) by the {} method, whose values differ by up to {} (`{}`: {} \
             against {}); this happens where the data are far firmer than the prior, in what \
             only the prior decides: the {} result is the optimum",
            self.method.name(),
            Num::rounded(mine, 4),
            Num::rounded(best, 4),
            optimum.method.name(),
            Num::rounded(difference, 3),
            self.names.get(k).map_or("", String::as_str),
            Num::rounded(self.standard[k], 4),
            Num::rounded(optimum.standard[k], 4),
            optimum.method.name(),
        ))
    }

    /// Largest |z|: at most 1 means every base parameter is reproduced within one std.
    pub fn max_normalized_residual(&self) -> f64 {
        self.normalized_residual
            .iter()
            .fold(0.0, |a, z| a.max(z.abs()))
    }
}

/// The bound of `r` that `v` (inside it) sits at, as "WHAT V at its lower bound B": within
/// 1e-3 of the range, or 1e-6 of it for a bound of zero (a small value above a zero bound is
/// a small link, a 12 g jaw under the default 50 kg range, not one pushed against the
/// bound); a closed range is one bound, said once (it was at its lower and at its upper
/// bound).
fn at_bound(what: &str, v: f64, r: [f64; 2]) -> impl Iterator<Item = String> {
    let range = (r[1] - r[0]).max(1e-12);
    let sides: Vec<(&str, f64)> = if r[0] == r[1] {
        vec![("", r[0])]
    } else {
        vec![(" lower", r[0]), (" upper", r[1])]
    };
    let what = what.to_owned();
    sides.into_iter().filter_map(move |(side, bound)| {
        let near = if bound == 0.0 { 1e-6 } else { 1e-3 } * range;
        ((v - bound).abs() <= near).then(|| {
            format!(
                "{what} {} at its{side} bound {}",
                Num::rounded(v, 7),
                Num(bound)
            )
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasible::fixture::{link, problem, target};
    use crate::feasible::{Bounds, LinkBounds};

    fn assemble(standard: &[f64], bounds: &Bounds) -> crate::Result<Solution> {
        let t = target(link(), 0.1);
        Solution::assemble(
            &problem(&t),
            bounds,
            Method::Interior,
            standard.to_vec(),
            Duration::from_millis(1500),
        )
    }

    /// The misfit, the links and the checks of a solution that is the target itself, and
    /// of one 2 mm off in the mass (z = 2).
    #[test]
    fn a_solution_carries_its_misfit_and_links() {
        let t = target(link(), 0.1);
        let s = assemble(&t, &Bounds::wide(1)).unwrap();
        assert_eq!(
            (s.method, s.seconds, s.iterations),
            (Method::Interior, 1.5, 0)
        );
        assert_eq!(s.names.len(), 11);
        assert_eq!(s.chi2, 0.0);
        assert_eq!(s.base, t.to_vec());
        assert!(s.violations.is_empty() && s.at_bounds.is_empty() && s.dont_care.is_empty());
        let l = s.links[0].unwrap();
        assert!((l.mass - 2.0).abs() < 1e-15 && l.com == [0.0; 3]);
        // P's eigenvalues: m = 2 and half the sums of pairs minus one moment, the least
        // (0.02 + 0.015 - 0.03) / 2 = 0.0025
        assert!(
            (s.min_eigenvalues[0] - 0.0025).abs() < 1e-15,
            "{:?}",
            s.min_eigenvalues
        );
        // the mass's deviation is 1e-3 with the solvers' floor added (problem.rs)
        let z = 0.002 / problem(&t).std[9];
        // sqrt(1 + (2e-5 / 1e-3)^2) = 1 + 2.0e-4: measured 2 - 4.0e-4
        assert!((z - 2.0).abs() < 8e-4, "{z}");
        let mut off = t;
        off[9] += 0.002;
        let s = assemble(&off, &Bounds::wide(1)).unwrap();
        // rounding (measured 8.8e-13 and 2.2e-13)
        assert!((s.chi2 - z * z).abs() < 1.8e-12, "{}", s.chi2);
        assert!((s.max_normalized_residual() - z).abs() < 4.4e-13);
        off[9] -= 0.004;
        let s = assemble(&off, &Bounds::wide(1)).unwrap();
        assert!((s.max_normalized_residual() - z).abs() < 4.4e-13);
        assert_eq!(Method::Cholesky.name(), "cholesky");
        assert_eq!(Method::Interior.name(), "interior-point");
        assert_eq!(Method::Sdp.name(), "sdp");
        assert_eq!(Method::Anneal.name(), "anneal");
    }

    /// Each kind of bound that the values break is reported, and a value at a bound is
    /// noted; within the tolerance 1e-6 (1 + |bound|) a value is not a violation.
    #[test]
    fn broken_bounds_are_reported_and_values_at_bounds_noted() {
        let t = target(link(), 0.1);
        let tight = LinkBounds {
            mass: [0.0, 1.9],
            com: [[0.01, 0.5], [-0.5, 0.5], [-0.5, 0.5]],
            inertia: [0.0, 0.025],
            tensor: [None, None, None, Some([0.001, 0.01]), None, None],
        };
        let bounds = Bounds {
            links: vec![tight],
            total_mass: Some([0.0, 1.95]),
            margin: Some(0.0),
        };
        let s = assemble(&t, &bounds).unwrap();
        let v = s.violations.join("\n");
        for want in [
            "link 1: mass 2 outside [0, 1.9]",
            "link 1: centre of mass x 0 outside [0.01, 0.5]",
            "link 1: inertia xy 0 outside [0.001, 0.01]",
            "link 1: principal moment",
            "total mass 2 outside [0, 1.95]",
        ] {
            assert!(v.contains(want), "{want} not in\n{v}");
        }
        // the moments are 0.03, 0.02, 0.015: only 0.03 is above 0.025
        assert_eq!(s.violations.len(), 5, "{v}");
        // all but the principal moment are imposed by the interior-point method, so unmet
        assert_eq!(s.unmet.len(), 4, "{:?}", s.unmet);
        assert!(s.unmet.iter().all(|u| !u.contains("principal")));
        // the SDP does not impose single elements either
        let sdp = Solution::assemble(
            &problem(&t),
            &bounds,
            Method::Sdp,
            t.to_vec(),
            Duration::ZERO,
        )
        .unwrap();
        assert_eq!(sdp.violations.len(), 5);
        assert_eq!(sdp.unmet.len(), 3, "{:?}", sdp.unmet);
        assert!(sdp.unmet.iter().all(|u| !u.contains("inertia")));
        // values are written short (a mass of 1e20 had its 21 digits)
        let mut heavy = t;
        heavy[9] = 1e20;
        let mut far = Bounds::wide(1);
        far.total_mass = Some([1e-300, 50.0]);
        let s = assemble(&heavy, &far).unwrap();
        let v = s.violations.join("\n");
        for want in [
            "link 1: mass 1e20 outside [",
            "total mass 1e20 outside [1e-300, 50]",
        ] {
            assert!(v.contains(want), "{want} not in\n{v}");
        }
        // a computed value has eight digits, not the arithmetic's seventeen
        let mut odd = heavy;
        odd[9] = 7.998630808139301;
        let mut above = Bounds::wide(1);
        above.total_mass = Some([8.0, 20.0]);
        let s = assemble(&odd, &above).unwrap();
        let v = s.violations.join("\n");
        assert!(v.contains("total mass 7.9986308 outside [8, 20]"), "{v}");
        // just inside the tolerance, at the bounds
        let edge = LinkBounds {
            mass: [0.0, 2.0 - 1e-6],
            com: [[1e-6, 0.5], [-0.5, 0.0], [-0.5, 0.5]],
            inertia: [0.0, 0.03],
            tensor: [None; 6],
        };
        let bounds = Bounds {
            links: vec![edge],
            total_mass: Some([2.0 + 0.5e-6, 3.0]),
            margin: Some(0.0),
        };
        let s = assemble(&t, &bounds).unwrap();
        assert!(s.violations.is_empty(), "{:?}", s.violations);
        let at = s.at_bounds.join("\n");
        for want in [
            "link 1: mass 2 at its upper bound",
            "link 1: centre of mass x 0 at its lower bound",
            "link 1: centre of mass y 0 at its upper bound",
            "link 1: principal moment 3 0.03 at its upper bound",
            // the total mass was never named at its bound
            "total mass 2 at its lower bound 2.0000005",
        ] {
            assert!(at.contains(want), "{want} not in\n{at}");
        }
        assert_eq!(s.at_bounds.len(), 5, "{at}");
    }

    /// A closed range (`mass = [2, 2]`) is one bound: a value on it is said once, short
    /// (it was "mass 2.000000e0 at its lower bound 2" and again "at its upper bound 2").
    #[test]
    fn a_value_on_a_closed_range_is_said_once() {
        let t = target(link(), 0.1);
        let b = Bounds {
            links: vec![LinkBounds {
                mass: [2.0, 2.0],
                ..LinkBounds::default()
            }],
            ..Bounds::wide(1)
        };
        let at = assemble(&t, &b).unwrap().at_bounds;
        assert_eq!(at, ["link 1: mass 2 at its bound 2"]);
    }

    /// A moment near a lower bound of zero is a small link, not a pinned one; a positive
    /// lower bound is a bound like any other.
    #[test]
    fn a_small_moment_is_at_a_bound_only_when_the_bound_is_positive() {
        let t = target(link(), 0.1);
        let with = |inertia: [f64; 2]| {
            let b = Bounds {
                links: vec![LinkBounds {
                    inertia,
                    ..LinkBounds::default()
                }],
                ..Bounds::wide(1)
            };
            assemble(&t, &b).unwrap().at_bounds
        };
        assert!(with([0.0, 5.0]).is_empty());
        assert!(with([0.0, 10.0]).is_empty());
        let at = with([0.015, 5.0]);
        assert_eq!(at.len(), 1, "{at:?}");
        assert!(
            at[0].contains("principal moment 1 0.015 at its lower bound"),
            "{at:?}"
        );
        // a range of 0.03 with the upper end at 0.03: 0.03 is at it, nothing else is
        let at = with([0.0, 0.03]);
        assert_eq!(at.len(), 1, "{at:?}");
    }

    /// A non-finite value is an error naming the parameter and the method.
    #[test]
    fn a_non_finite_value_is_refused_by_name() {
        let mut t = target(link(), 0.1);
        t[6] = f64::NAN;
        let e = assemble(&t, &Bounds::wide(1)).unwrap_err().to_string();
        assert!(e.contains("`MX1`") && e.contains("interior-point"), "{e}");
        // finite values whose misfit overflows
        let mut t = target(link(), 0.1);
        t[10] = 1e306;
        assert!(assemble(&t, &Bounds::wide(1)).is_err());
    }

    /// A link whose mass came out zero has no inertial description; its eigenvalue is
    /// still reported.
    #[test]
    fn a_massless_link_has_no_inertial() {
        let s = assemble(&[0.0; 11], &Bounds::wide(1)).unwrap();
        assert!(s.links[0].is_none());
        assert_eq!(s.min_eigenvalues[0], 0.0);
    }
}

#[cfg(test)]
mod edges {
    use super::*;
    use crate::feasible::fixture::{link, problem, target};
    use crate::feasible::{Bounds, LinkBounds, LinkInertial};

    fn assemble(standard: &[f64], bounds: &Bounds) -> Solution {
        let t = target(link(), 0.1);
        Solution::assemble(
            &problem(&t),
            bounds,
            Method::Interior,
            standard.to_vec(),
            Duration::ZERO,
        )
        .unwrap()
    }

    /// The tolerances are inclusive: a value exactly `tol (1 + |bound|)` outside a bound
    /// (a link's or the total mass's) is not a violation.

    #[test]
    fn a_value_exactly_at_the_tolerance_is_not_a_violation() {
        let mut t = target(link(), 0.1);
        // centre of mass x = MX / M = 2e-6 / 2 = 1e-6 exactly (halving is exact)
        t[6] = 2e-6;
        let b = Bounds {
            links: vec![LinkBounds {
                com: [[-1.0, 0.0], [-1.0, 1.0], [-1.0, 1.0]],
                ..LinkBounds::default()
            }],
            ..Bounds::wide(1)
        };
        assert!(assemble(&t, &b).violations.is_empty());
        t[6] = -2e-6;
        let b = Bounds {
            links: vec![LinkBounds {
                com: [[0.0, 1.0], [-1.0, 1.0], [-1.0, 1.0]],
                ..LinkBounds::default()
            }],
            ..Bounds::wide(1)
        };
        assert!(assemble(&t, &b).violations.is_empty());
        // a total mass of 3 - 1e-6 against a range from 3, and 1 + 1e-6 against one to 1
        let mut t = target(link(), 0.1);
        t[9] = 3.0 - 1e-6;
        let b = Bounds {
            total_mass: Some([3.0, 4.0]),
            ..Bounds::wide(1)
        };
        assert!(assemble(&t, &b).violations.is_empty());
        t[9] = 1.0 + 1e-6;
        let b = Bounds {
            total_mass: Some([0.5, 1.0]),
            ..Bounds::wide(1)
        };
        assert!(assemble(&t, &b).violations.is_empty());
        // the tolerance is relative, 1e-6 (1 + |bound|) as for every bound: 1 + 3e-6 is
        // outside (an absolute 1e-6 took 200 + 1e-4 for a violation of [0, 200])
        t[9] = 1.0 + 3e-6;
        assert_eq!(assemble(&t, &b).violations.len(), 1);
    }

    /// A light link (12 g under the default 0 to 50 kg) is not "at its lower bound 0"; a
    /// massless one (1e-7 kg, where the data pushed it) is.
    #[test]
    fn a_light_link_is_not_at_a_zero_mass_bound() {
        let at = |mass: f64| {
            let l = LinkInertial {
                mass,
                com: [0.0; 3],
                inertia: [[2e-6, 0.0, 0.0], [0.0, 5e-6, 0.0], [0.0, 0.0, 6e-6]],
            };
            assemble(&target(l.to_standard(), 0.1), &Bounds::wide(1)).at_bounds
        };
        assert!(at(0.012).is_empty(), "{:?}", at(0.012));
        let massless = at(1e-7);
        assert_eq!(massless.len(), 1, "{massless:?}");
        assert!(massless[0].contains("mass 1e-7 at its lower bound 0"));
    }

    /// A thin link (a principal moment of 1e-4 kg m^2) with a lower bound of zero is not
    /// "at its bound"; with a positive lower bound near it, it is.
    #[test]
    fn a_thin_link_is_at_a_zero_bound_only_when_it_is_a_real_bound() {
        let thin = LinkInertial {
            mass: 2.0,
            com: [0.0; 3],
            inertia: [[1e-4, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.02]],
        }
        .to_standard();
        let t = target(thin, 0.1);
        let with = |inertia: [f64; 2]| {
            let b = Bounds {
                links: vec![LinkBounds {
                    inertia,
                    ..LinkBounds::default()
                }],
                ..Bounds::wide(1)
            };
            assemble(&t, &b).at_bounds
        };
        assert!(with([0.0, 1.0]).is_empty(), "{:?}", with([0.0, 1.0]));
        let at = with([1e-4, 1.0]);
        assert_eq!(at.len(), 1, "{at:?}");
        assert!(
            at[0].contains("principal moment 1 0.0001 at its lower bound"),
            "{at:?}"
        );
    }
}
