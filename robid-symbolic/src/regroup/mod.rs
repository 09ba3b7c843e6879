//! Gautier-Khalil regrouping: the minimal set of base parameters.
//!
//! 1. The link parameters are moved into modified-DH frames (expressions in
//!    the user's standard parameters) and the closed-form rules (`rules.rs`)
//!    group them symbolically from the last joint down.
//! 2. The regressor column of each remaining parameter is sampled at random
//!    states (`rank.rs`): zero columns have no effect; a column dependent on
//!    earlier ones is folded into them with exact coefficients (`exact.rs`),
//!    e.g. Ia1 into ZZR1 or the extra groupings of parallel axes.
//!
//! The result is minimal: its size equals the numeric rank of the regressor.

mod atoms;
mod exact;
mod fold;
mod rank;
mod rules;

use crate::dynamics::{Derivation, LinkParameters, newton_euler};
use crate::expr::{Arena, Id, Node};
use crate::robot::bounds::SYMBOL_SAMPLES;
use crate::robot::{ParameterId, ParameterKind};
use rank::Status;
use robid_core::BaseName;
use robid_core::rng::Rng;

/// One base parameter.
#[derive(Clone, Debug)]
pub struct BaseParameter {
    /// Name in the literature's style: the parameter it is built on, with `R`
    /// when something was grouped into it (`ZZR1`, `XY2`, `MXR2`).
    pub name: BaseName,
    /// Its expression in the standard parameters (and geometric symbols).
    pub expression: Id,
    /// Its terms: (standard-parameter index, coefficient), nonzero only.
    pub terms: Vec<(usize, Id)>,
}

/// The base parameters of a robot and everything derived with them.
#[derive(Clone, Debug)]
pub struct BaseParameters {
    /// The standard parameters (columns of K).
    pub standard: Vec<ParameterId>,
    /// The base parameters (rows of K).
    pub base: Vec<BaseParameter>,
    /// Base regressor: `columns[b][joint]`, so tau = sum over b of `columns[b]` times base parameter b.
    pub columns: Vec<Vec<Id>>,
    /// Standard parameters with no effect at all (indices into `standard`).
    pub unidentifiable: Vec<usize>,
}

impl BaseParameters {
    /// The map K (base = K standard) as coefficient expressions, row-major.
    pub fn k_matrix(&self, arena: &mut Arena) -> Vec<Vec<Id>> {
        let zero = arena.zero();
        self.base
            .iter()
            .map(|b| {
                let mut row = vec![zero; self.standard.len()];
                for &(s, c) in &b.terms {
                    row[s] = c;
                }
                row
            })
            .collect()
    }
}

/// A drive offset that the regrouping folded into other base parameters: its joint's weight
/// has a constant part along the joint's axis, a constant force as the offset is, so only
/// their sum is identifiable and the gravity vector holds the offset
/// (docs/dynamics.md#drive-offsets-inside-the-weight).
#[derive(Clone, Debug, PartialEq)]
pub struct FoldedOffset {
    /// The offset (`Fo` of some joint).
    pub offset: ParameterId,
    /// The base parameters it was folded into.
    pub into: Vec<BaseName>,
}

/// The drive offsets of `standard` that no base parameter is built on but some hold (with
/// a nonzero coefficient): those the regrouping found dependent on other columns, which
/// only a constant part of the weight along a prismatic axis makes so.
///
/// ```
/// use robid_symbolic::{Derivation, Drive, Robot, regroup::folded_offsets};
/// // a prismatic first joint with a part of gravity along it, and a drive offset
/// let toml = "name = \"slide\"\nconvention = \"modified\"\ngravity = [0, 3, -9.3]\n\
///             [[joints]]\ntype = \"prismatic\"\nalpha = 0\na = 0\nd = 0\ntheta = 0\n";
/// let robot = Robot::from_toml(toml, "slide.toml").unwrap().with_drive(Drive::ALL);
/// let base = Derivation::new(&robot).base_parameters().unwrap();
/// let folded = folded_offsets(&base.standard, &base.base);
/// assert_eq!(folded.len(), 1);
/// assert_eq!(folded[0].offset.to_string(), "Fo1");
/// // level, the offset is a parameter of its own
/// let level = Robot::from_toml(&toml.replace("[0, 3, -9.3]", "[0, 9.8, 0]"), "slide.toml")
///     .unwrap()
///     .with_drive(Drive::ALL);
/// let base = Derivation::new(&level).base_parameters().unwrap();
/// assert!(folded_offsets(&base.standard, &base.base).is_empty());
/// ```
pub fn folded_offsets(standard: &[ParameterId], base: &[BaseParameter]) -> Vec<FoldedOffset> {
    use crate::robot::DriveTerm;
    standard
        .iter()
        .enumerate()
        .filter(|(_, p)| p.kind == ParameterKind::Drive(DriveTerm::Fo))
        .filter(|&(_, &p)| base.iter().all(|b| b.name.on != p))
        .filter_map(|(s, &offset)| {
            let into: Vec<BaseName> = base
                .iter()
                .filter(|b| b.terms.iter().any(|&(t, _)| t == s))
                .map(|b| b.name)
                .collect();
            (!into.is_empty()).then_some(FoldedOffset { offset, into })
        })
        .collect()
}

/// Why the regrouping failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RegroupError {
    /// A dependency's coefficient varies with the geometric symbols in a way
    /// that is not a polynomial in them and in the sines and cosines of those
    /// used as angles (of degree at most four, and at most 160 monomials), so
    /// no expression robid writes holds for every value of the symbols.
    #[error(
        "the dependency of `{parameter}` on `{on}` has a coefficient that varies with the geometric symbols {} in a way robid cannot write for every value of them: it is not a polynomial of degree {degree} or less in them (and in the sines and cosines of those used as angles){}; give {} numeric values (write the numbers in the description in place of the symbols)",
        quoted(.symbols),
        limit_note(*.degree),
        quoted(.symbols)
    )]
    NotExpressible {
        /// The dependent parameter.
        parameter: String,
        /// A parameter it depends on.
        on: String,
        /// The geometric symbols the coefficient varies with.
        symbols: Vec<String>,
        /// The highest degree of the polynomials tried (lower than four when
        /// a higher one would have more than 160 terms).
        degree: usize,
    },
    /// The sampled regressor is not finite, its kept columns are not
    /// independent, or a dependency found at one value of the geometric
    /// symbols does not hold at another.
    #[error(
        "the numeric rank analysis of the regressor failed ({0}); keep the description's values within robid's limits (robid_symbolic::robot::bounds)"
    )]
    Numeric(String),
}

/// What bounded the polynomials tried for a coefficient, for the message.
fn limit_note(degree: usize) -> String {
    if degree < exact::MAX_DEGREE {
        format!(" with at most {} terms", exact::MAX_MONOMIALS)
    } else {
        ", such as a ratio like 1/g or tan(alpha), which has no value where its denominator vanishes"
            .to_owned()
    }
}

/// `a`, `b` and `c`, each in backquotes.
fn quoted(names: &[String]) -> String {
    let names: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
    match names.as_slice() {
        [] => "(none)".to_owned(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    }
}

/// The unit of a parameter's regressor column, for the test of no effect
/// ([`rank::analyse`]): the inertias (kg m^2), the first moments (kg m), the mass (kg),
/// and each drive term apart (a rotor inertia's column is the joint's acceleration, a
/// friction's its velocity or sign, an offset's 1).
fn unit(kind: ParameterKind) -> usize {
    use crate::robot::Inertial;
    match kind {
        ParameterKind::Inertial(Inertial::MX | Inertial::MY | Inertial::MZ) => 1,
        ParameterKind::Inertial(Inertial::M) => 2,
        ParameterKind::Inertial(_) => 0,
        ParameterKind::Drive(d) => 3 + d as usize,
    }
}

/// A parameter that survived the rules: where it lives and its expression.
struct Candidate {
    id: ParameterId,
    expression: Id,
    column: Vec<Id>,
}

/// What `Derivation::fold_dependencies` finds: the candidates kept (in candidate order),
/// the dependent ones, and each dependent one's exact coefficients on the kept (index into
/// `kept`, coefficient).
struct Folding {
    kept: Vec<usize>,
    dependencies: Vec<fold::Dependency>,
    coefficients: Vec<Vec<(usize, Id)>>,
}

impl Derivation {
    /// Derives the base parameters (docs/regrouping.md#overview-of-the-method).
    pub fn base_parameters(&mut self) -> Result<BaseParameters, RegroupError> {
        let user = self.parameter_symbols();
        let mut links = self.link_parameters(&user);
        let rows = self.robot.frame_rows();
        rules::apply(&mut self.arena, &rows, &mut links);
        let candidates = self.candidates(&links);
        let geometry: Vec<Id> = self
            .robot
            .symbols()
            .iter()
            .map(|(s, _)| self.arena.var(s))
            .collect();
        let mut rng = Rng::from_state(0x5EED);
        let first_geometry: Vec<f64> = geometry
            .iter()
            .map(|_| rng.uniform(SYMBOL_SAMPLES[0], SYMBOL_SAMPLES[1]))
            .collect();
        let columns: Vec<&[Id]> = candidates.iter().map(|c| c.column.as_slice()).collect();
        let sampled = self.sample(&columns, &geometry, &first_geometry, &mut rng);
        let units: Vec<usize> = candidates.iter().map(|c| unit(c.id.kind)).collect();
        // of two columns of one unit the larger is kept; where that makes a coefficient
        // robid cannot write for every value of the geometric symbols (the reciprocal of
        // one it can), the earlier is kept, as without the preference
        let Folding {
            kept,
            dependencies,
            coefficients,
        } = match self.fold_dependencies(&candidates, &sampled, &units, &geometry, &mut rng, true) {
            Err(RegroupError::NotExpressible { .. }) => {
                self.fold_dependencies(&candidates, &sampled, &units, &geometry, &mut rng, false)?
            }
            folded => folded?,
        };
        let mut expressions: Vec<Id> = kept.iter().map(|&i| candidates[i].expression).collect();
        for (dependency, exact) in dependencies.iter().zip(coefficients) {
            for (k, c) in exact {
                let t = self
                    .arena
                    .mul2(c, candidates[dependency.candidate].expression);
                expressions[k] = self.arena.add2(expressions[k], t);
            }
        }

        let standard = self.robot.standard_parameters();
        let mut base = Vec::with_capacity(kept.len());
        for (&i, &expression) in kept.iter().zip(&expressions) {
            let c = &candidates[i];
            let plain = self.arena.var(&c.id.to_string());
            let name = BaseName {
                on: c.id,
                regrouped: expression != plain,
            };
            // The expression is linear in the standard parameters: each
            // coefficient is a derivative, taken only for the symbols it holds.
            let present = self.arena.free_symbols(&[expression]);
            let terms: Vec<(usize, Id)> = user
                .iter()
                .enumerate()
                .filter_map(|(s, &parameter)| {
                    let &Node::Sym(symbol) = self.arena.node(parameter) else {
                        return None;
                    };
                    if !present.contains(&symbol) {
                        return None;
                    }
                    let coefficient = self.arena.diff(expression, symbol);
                    (!self.arena.is_zero(coefficient)).then_some((s, coefficient))
                })
                .collect();
            let expression = self.shortest_form(expression, &terms, &user);
            base.push(BaseParameter {
                name,
                expression,
                terms,
            });
        }
        let unidentifiable = (0..standard.len())
            .filter(|&s| base.iter().all(|b| b.terms.iter().all(|&(t, _)| t != s)))
            .collect();
        let columns = kept.iter().map(|&i| candidates[i].column.clone()).collect();
        Ok(BaseParameters {
            standard,
            base,
            columns,
            unidentifiable,
        })
    }

    /// `expression` or, when it prints shorter, the same value rebuilt from its `terms`
    /// (standard-parameter index, coefficient), the parameters of one coefficient summed
    /// under it: the rules add each grouping as it comes, so a parameter moved twice
    /// keeps both moves, `(M3 + M4)*(L2^2 + D3^2) - (M3 + M4)*D3^2`, where its coefficient,
    /// a derivative, is simplified, `(M3 + M4)*L2^2`.
    fn shortest_form(&mut self, expression: Id, terms: &[(usize, Id)], user: &[Id]) -> Id {
        let mut groups: Vec<(Id, Vec<Id>)> = Vec::new();
        for &(s, coefficient) in terms {
            match groups.iter_mut().find(|(c, _)| *c == coefficient) {
                Some((_, parameters)) => parameters.push(user[s]),
                None => groups.push((coefficient, vec![user[s]])),
            }
        }
        let parts: Vec<Id> = groups
            .into_iter()
            .map(|(coefficient, parameters)| {
                let sum = self.arena.add(&parameters);
                self.arena.mul2(coefficient, sum)
            })
            .collect();
        let rebuilt = self.arena.add(&parts);
        if self.arena.display(rebuilt).len() < self.arena.display(expression).len() {
            rebuilt
        } else {
            expression
        }
    }

    /// The kept candidates, the dependent ones and their exact coefficients ([`Folding`]),
    /// from the columns `sampled` at the first geometry; `prefer_larger` chooses [`rank::analyse_preferring_larger`] over
    /// [`rank::analyse`].
    fn fold_dependencies(
        &mut self,
        candidates: &[Candidate],
        sampled: &[Vec<f64>],
        units: &[usize],
        geometry: &[Id],
        rng: &mut Rng,
        prefer_larger: bool,
    ) -> Result<Folding, RegroupError> {
        let status = if prefer_larger {
            rank::analyse_preferring_larger(sampled, units)
        } else {
            rank::analyse(sampled, units)
        };
        let status = status.ok_or_else(|| {
            RegroupError::Numeric(
                "a sampled regressor value is not finite, or the columns kept are not independent"
                    .to_owned(),
            )
        })?;
        let columns: Vec<&[Id]> = candidates.iter().map(|c| c.column.as_slice()).collect();
        self.check_zero_columns(&columns, candidates, geometry, &status)?;
        let kept: Vec<usize> = (0..candidates.len())
            .filter(|&i| matches!(status[i], Status::Kept(_)))
            .collect();
        let dependencies: Vec<fold::Dependency> = status
            .iter()
            .enumerate()
            .filter_map(|(i, s)| match s {
                Status::Dependent(numeric) => Some(fold::Dependency {
                    candidate: i,
                    numeric: numeric.clone(),
                }),
                _ => None,
            })
            .collect();
        let coefficients =
            self.dependency_coefficients(&dependencies, &kept, candidates, geometry, rng)?;
        Ok(Folding {
            kept,
            dependencies,
            coefficients,
        })
    }

    /// A column below rounding at the sampled geometry (a high power of a symbol that was
    /// drawn small) may still act elsewhere: where every symbol is at the top of the
    /// interval, which is where a product of lengths is largest, a column found zero must be
    /// zero too. (Dependent columns are checked at other geometries by the fold.)
    fn check_zero_columns(
        &mut self,
        columns: &[&[Id]],
        candidates: &[Candidate],
        geometry: &[Id],
        status: &[Status],
    ) -> Result<(), RegroupError> {
        // zero, or dependent with every coefficient below rounding: no effect here
        let nothing = |s: &Status| match s {
            Status::Zero => true,
            Status::Dependent(c) => c.is_empty(),
            Status::Kept(_) => false,
        };
        if geometry.is_empty() || !status.iter().any(nothing) {
            return Ok(());
        }
        // its own random states, so the rest of the derivation draws what it always drew
        let mut rng = Rng::from_state(0x70B);
        let top = vec![SYMBOL_SAMPLES[1]; geometry.len()];
        let sampled = self.sample(columns, geometry, &top, &mut rng);
        let units: Vec<usize> = candidates.iter().map(|c| unit(c.id.kind)).collect();
        let at_top = rank::analyse(&sampled, &units).ok_or_else(|| {
            RegroupError::Numeric("a sampled regressor value is not finite".to_owned())
        })?;
        let Some(i) = (0..status.len()).find(|&i| nothing(&status[i]) && !nothing(&at_top[i]))
        else {
            return Ok(());
        };
        let symbols: Vec<String> = geometry.iter().map(|&g| self.arena.display(g)).collect();
        Err(RegroupError::Numeric(format!(
            "`{}` has no effect at one value of the geometric symbols {} in [{}, {}] but has one where they are {}: a value whose size changes by many orders of magnitude over that interval (a high power of a symbol) leaves part of the model below rounding; write the value with fewer factors or give the symbols numeric values",
            candidates[i].id,
            quoted(&symbols),
            SYMBOL_SAMPLES[0],
            SYMBOL_SAMPLES[1],
            SYMBOL_SAMPLES[1]
        )))
    }

    /// Every slot the rules left, with its regressor column (modified frames): the
    /// non-zero ones (the rules zero what they move into the parent, and a drive term the
    /// joint does not have is no parameter).
    fn candidates(&mut self, links: &[LinkParameters]) -> Vec<Candidate> {
        let n = links.len();
        let mut out = Vec::new();
        for j in 0..n {
            let slots = rules::slots(&links[j]);
            for (slot, &expression) in slots.iter().enumerate() {
                if self.arena.is_zero(expression) {
                    continue;
                }
                let mut params: Vec<LinkParameters> = (0..n)
                    .map(|_| LinkParameters::zero(&mut self.arena))
                    .collect();
                params[j] = rules::unit(&mut self.arena, slot);
                let column = newton_euler::inverse_dynamics(
                    &mut self.arena,
                    &self.kinematics,
                    &self.inputs.qd,
                    &self.inputs.qdd,
                    &params,
                );
                out.push(Candidate {
                    id: ParameterId::new(j, ParameterKind::ALL[slot]),
                    expression,
                    column,
                });
            }
        }
        out
    }

    /// The columns evaluated at random states for one geometry sample,
    /// each as a vector of `states * dof` values.
    fn sample(
        &mut self,
        columns: &[&[Id]],
        geometry: &[Id],
        values: &[f64],
        rng: &mut Rng,
    ) -> Vec<Vec<f64>> {
        let n = self.robot.dof();
        let states = (3 * columns.len() / n.max(1) + 12).max(20);
        let entries: Vec<Id> = columns.iter().flat_map(|c| c.iter().copied()).collect();
        let mut out = vec![Vec::with_capacity(states * n); columns.len()];
        let names: Vec<String> = (1..=n)
            .flat_map(|j| [format!("q{j}"), format!("qd{j}"), format!("qdd{j}")])
            .collect();
        let mut points = Vec::with_capacity(states);
        for _ in 0..states {
            let mut pairs: Vec<(&str, f64)> = names
                .iter()
                .enumerate()
                .map(|(k, s)| {
                    let v = match k % 3 {
                        0 => rng.uniform(-3.0, 3.0),
                        // Velocities away from zero so sign(qd) is defined.
                        1 => rng.uniform(0.2, 2.0) * if rng.below(2) == 0 { -1.0 } else { 1.0 },
                        _ => rng.uniform(-3.0, 3.0),
                    };
                    (s.as_str(), v)
                })
                .collect();
            let geometry_names: Vec<String> =
                geometry.iter().map(|&g| self.arena.display(g)).collect();
            pairs.extend(
                geometry_names
                    .iter()
                    .map(|s| s.as_str())
                    .zip(values.iter().copied()),
            );
            points.push(self.arena.values(&pairs));
        }
        // one walk of the columns' nodes for every state
        let results = self
            .arena
            .eval_points(&entries, &points)
            .expect("every symbol of a regressor column is bound");
        for result in results {
            for (c, column) in out.iter_mut().enumerate() {
                column.extend_from_slice(&result[c * n..(c + 1) * n]);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::rules;
    use crate::dynamics::Derivation;
    use crate::expr::Id;
    use crate::robot::{ParameterId, ParameterKind, Robot};

    /// A parameter moved twice keeps one coefficient: M3 and M4 move into link 2 with
    /// `L2^2 + D3^2` and out of it again with `-D3^2`, written `(M3 + M4)*L2^2`; where the
    /// rules' own form is already the shortest (every reference robot), it stays, and
    /// either way the expression is the sum of its terms.
    #[test]
    fn a_parameter_moved_twice_is_written_with_its_one_coefficient() {
        let robot = Robot::from_toml(
            r#"
name = "sym3"
convention = "modified"
[symbols]
L2 = 0.45
D3 = 0.12
[[joints]]
d = 0.3
[[joints]]
alpha = "-pi/2"
[[joints]]
a = "L2"
d = "D3"
[[joints]]
alpha = "-pi/2"
d = 0.4
"#,
            "sym3.toml",
        )
        .unwrap();
        let mut d = Derivation::new(&robot);
        let base = d.base_parameters().unwrap();
        let text = |name: &str, d: &Derivation| {
            let b = base
                .base
                .iter()
                .find(|b| b.name.to_string() == name)
                .unwrap();
            d.arena.display(b.expression)
        };
        assert_eq!(text("ZZR2", &d), "ZZ2 + (M3 + M4)*L2^2");
        assert_eq!(text("MXR2", &d), "MX2 + L2*(M3 + M4)");
        assert_eq!(text("ZZR3", &d), "ZZ3 + YY4 + 0.8*MZ4 + 0.16*M4");
        let user = d.parameter_symbols();
        for b in &base.base {
            let terms: Vec<Id> = b
                .terms
                .iter()
                .map(|&(s, c)| d.arena.mul2(c, user[s]))
                .collect();
            let sum = d.arena.add(&terms);
            // at values of every symbol: the factored form is not expanded symbolically
            let mut values = crate::expr::Values::new();
            for (k, symbol) in d
                .arena
                .free_symbols(&[b.expression, sum])
                .into_iter()
                .enumerate()
            {
                values.set(symbol, 0.3 + 0.17 * k as f64);
            }
            let at = d.arena.eval(&[b.expression, sum], &values).unwrap();
            assert!(
                (at[0] - at[1]).abs() <= 1e-14 * at[1].abs().max(1.0),
                "{}: {at:?}",
                b.name
            );
        }
    }

    /// The rules zero exactly what they move into the parent link (for a revolute joint
    /// after the first YY, MZ and M, for a prismatic one the six inertia terms), a drive
    /// term the joint does not have is zero, and the candidates are the other slots.
    #[test]
    fn candidates_are_the_slots_the_rules_left() {
        let robot = Robot::from_toml(
            r#"
name = "mixed"
convention = "modified"
[[joints]]
alpha = 0
a = 0
d = 0
drive = ["Ia"]
[[joints]]
alpha = "-pi/2"
a = 0.1
d = 0.2
drive = ["Fv", "Fc"]
[[joints]]
type = "prismatic"
alpha = "pi/2"
a = 0.3
theta = 0
[[joints]]
alpha = 0.4
a = 0.2
d = 0
drive = ["Ia", "Fv", "Fc", "Fo"]
"#,
            "mixed.toml",
        )
        .unwrap();
        let mut d = Derivation::new(&robot);
        let user = d.parameter_symbols();
        let mut links = d.link_parameters(&user);
        let rows = d.robot.frame_rows();
        rules::apply(&mut d.arena, &rows, &mut links);
        let candidates: Vec<ParameterId> = d.candidates(&links).iter().map(|c| c.id).collect();
        let moved: [&[usize]; 4] = [&[], &[3, 8, 9], &[0, 1, 2, 3, 4, 5], &[3, 8, 9]];
        let mut left = 0;
        for (j, link) in links.iter().enumerate() {
            let drive = robot.joints()[j].drive;
            let enabled = [drive.ia, drive.fv, drive.fc, drive.fo];
            let slots = rules::slots(link);
            for (slot, kind) in ParameterKind::ALL.iter().enumerate() {
                let id = ParameterId::new(j, *kind);
                let zero = moved[j].contains(&slot) || (slot >= 10 && !enabled[slot - 10]);
                assert_eq!(d.arena.is_zero(slots[slot]), zero, "{id:?}");
                assert_eq!(candidates.contains(&id), !zero, "{id:?}");
                left += usize::from(!zero);
            }
        }
        assert_eq!(candidates.len(), left);
    }

    /// A revolute joint about the gravity axis: its rotation sees only ZZ1, every other
    /// parameter of the link is unidentifiable (named in the standard order).
    #[test]
    fn a_vertical_joint_leaves_all_but_zz_unidentifiable() {
        let robot = Robot::from_toml(
            "name = \"one\"\nconvention = \"modified\"\n[[joints]]\nalpha = 0\na = 0\nd = 0\n",
            "one.toml",
        )
        .unwrap();
        let mut derivation = Derivation::new(&robot);
        assert_eq!(
            derivation.standard_parameters(),
            robot.standard_parameters().as_slice()
        );
        let base = derivation.base_parameters().unwrap();
        let names = |list: Vec<usize>| -> Vec<String> {
            list.into_iter()
                .map(|s| base.standard[s].to_string())
                .collect()
        };
        assert_eq!(base.base.len(), 1);
        assert_eq!(
            names(base.unidentifiable.clone()),
            ["XX1", "XY1", "XZ1", "YY1", "YZ1", "MX1", "MY1", "MZ1", "M1"]
        );
    }

    /// The sampled states keep every velocity between 0.2 and 2 in size (so sign(qd) is
    /// defined and Coulomb columns are not degenerate), and positions and accelerations
    /// spread over [-3, 3].
    #[test]
    fn sampled_velocities_stay_away_from_zero() {
        let robot = Robot::from_toml(
            "name = \"two\"\nconvention = \"modified\"\n[[joints]]\nalpha = 0\na = 0\nd = 0\n\
             [[joints]]\nalpha = \"pi/2\"\na = 0\nd = 0\n",
            "two.toml",
        )
        .unwrap();
        let mut d = Derivation::new(&robot);
        let velocities = d.inputs.qd.clone();
        let others = [d.inputs.q[0], d.inputs.qdd[1]];
        let mut rng = super::Rng::from_state(7);
        let sampled = d.sample(&[&velocities, &others], &[], &[], &mut rng);
        // measured 40
        assert!(sampled[0].len() >= 40);
        for v in &sampled[0] {
            assert!((0.2..=2.0).contains(&v.abs()), "velocity {v}");
        }
        assert!(sampled[0].iter().any(|v| *v < 0.0) && sampled[0].iter().any(|v| *v > 0.0));
        assert!(sampled[1].iter().all(|v| v.abs() <= 3.0));
        assert!(
            sampled[1].iter().any(|v| v.abs() < 0.2) && sampled[1].iter().any(|v| v.abs() > 2.0)
        );
    }

    #[test]
    fn a_refusal_says_what_bounded_the_fit() {
        let error = |degree| {
            super::RegroupError::NotExpressible {
                parameter: "MZ2".to_owned(),
                on: "MY2".to_owned(),
                symbols: vec!["al".to_owned(), "g".to_owned()],
                degree,
            }
            .to_string()
        };
        let full = error(super::exact::MAX_DEGREE);
        assert!(
            full.contains("degree 4 or less") && full.contains("ratio"),
            "{full}"
        );
        assert!(full.contains("`al` and `g`"), "{full}");
        let capped = error(2);
        assert!(capped.contains("degree 2 or less") && capped.contains("at most 160 terms"));
    }
}
