//! Whether ten identified values can be a real body: positive mass, inertia about the
//! centre of mass positive semidefinite, principal moments satisfying the triangle
//! inequalities (equivalently, the pseudo-inertia positive semidefinite:
//! docs/experiments.md#physical-consistency-and-the-pseudo-inertia).

use crate::Num;
use crate::feasible::{LinkInertial, pseudo_inertia_min_eigenvalue};

/// Relative slack of the checks, against the largest principal moment: rounding of an
/// exactly flat or point-like body must not make it inconsistent.
const SLACK: f64 = 1e-9;

/// Significant digits of the values in [`Consistency::problems`]: computed values, which
/// carry every digit of their arithmetic (a mass of -4.7123414472056454e-11 kg).
const DIGITS: usize = 4;

/// The physical reading of ten standard values and its verdict.
#[derive(Debug, Clone, PartialEq)]
pub struct Consistency {
    /// Mass, kg.
    pub mass: f64,
    /// Centre of mass and inertia about it (`None` when the mass is not positive).
    pub physical: Option<LinkInertial>,
    /// Principal moments of the inertia about the centre of mass, ascending.
    pub principal_moments: Option<[f64; 3]>,
    /// Smallest eigenvalue of the pseudo-inertia (negative: no mass distribution has
    /// these values).
    pub pseudo_inertia_min_eigenvalue: f64,
    /// Why the values are not physical (empty when they are).
    pub problems: Vec<String>,
}

impl Consistency {
    /// Checks ten standard values `XX XY XZ YY YZ ZZ MX MY MZ M`.
    pub fn of(p: &[f64; 10]) -> Consistency {
        let mut problems = Vec::new();
        let physical = LinkInertial::from_standard(p);
        let principal_moments = physical.as_ref().map(LinkInertial::principal_moments);
        match principal_moments {
            None => problems.push(format!(
                "the mass {} kg is not positive",
                Num::rounded(p[9], DIGITS)
            )),
            Some(d) => {
                let slack = SLACK * d[2].abs();
                if !(d[0] >= -slack) {
                    problems.push(format!(
                        "the inertia about the centre of mass has a negative principal moment \
                         ({} kg m^2)",
                        Num::rounded(d[0], DIGITS)
                    ));
                }
                // Ascending order: only the largest can exceed the sum of the other two.
                if !(d[2] <= d[0] + d[1] + slack) {
                    // the excess too: rounded, the moments may seem to keep the inequality
                    let [a, b, c] = d.map(|m| Num::rounded(m, DIGITS));
                    problems.push(format!(
                        "the principal moments {a}, {b}, {c} kg m^2 break the triangle \
                         inequality (the largest exceeds the sum of the other two by {} kg m^2)",
                        Num::rounded(d[2] - d[0] - d[1], 2)
                    ));
                }
            }
        }
        Consistency {
            mass: p[9],
            physical,
            principal_moments,
            pseudo_inertia_min_eigenvalue: pseudo_inertia_min_eigenvalue(p),
            problems,
        }
    }

    /// Whether the values are those of a real body.
    pub fn is_consistent(&self) -> bool {
        self.problems.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_solid_box_is_consistent_and_a_negative_mass_is_not() {
        let solid = LinkInertial {
            mass: 1.0,
            com: [0.0, 0.0, 0.1],
            inertia: [[0.02, 0.0, 0.0], [0.0, 0.03, 0.0], [0.0, 0.0, 0.04]],
        };
        assert!(Consistency::of(&solid.to_standard()).is_consistent());
        let mut p = solid.to_standard();
        p[9] = -1.0;
        let c = Consistency::of(&p);
        assert!(!c.is_consistent());
        assert!(c.problems[0].contains("not positive"), "{:?}", c.problems);
        // 0.1 > 0.02 + 0.03: no body has these moments.
        let thin = LinkInertial {
            inertia: [[0.02, 0.0, 0.0], [0.0, 0.03, 0.0], [0.0, 0.0, 0.1]],
            ..solid
        };
        let c = Consistency::of(&thin.to_standard());
        assert!(c.problems[0].contains("triangle"), "{:?}", c.problems);
        assert!(c.pseudo_inertia_min_eigenvalue < 0.0);
    }

    /// The values in the problems are written to four digits: they used to carry every
    /// digit ("the mass -0.000000000047123414472056454 kg is not positive", "the
    /// principal moments 2.0000000000000004e-2, ..").
    #[test]
    fn the_problems_write_values_short() {
        let solid = LinkInertial {
            mass: 1.0,
            com: [0.0, 0.0, 0.1],
            inertia: [[0.02, 0.0, 0.0], [0.0, 0.03, 0.0], [0.0, 0.0, 0.04]],
        };
        let mut p = solid.to_standard();
        p[9] = -4.7123414472056454e-11;
        assert_eq!(
            Consistency::of(&p).problems,
            ["the mass -4.712e-11 kg is not positive"]
        );
        let negative = LinkInertial {
            inertia: [
                [-0.0012345678901234, 0.0, 0.0],
                [0.0, 0.03, 0.0],
                [0.0, 0.0, 0.02],
            ],
            ..solid
        };
        assert_eq!(
            Consistency::of(&negative.to_standard()).problems,
            [
                "the inertia about the centre of mass has a negative principal moment \
                 (-0.001235 kg m^2)",
                "the principal moments -0.001235, 0.02, 0.03 kg m^2 break the triangle \
                 inequality (the largest exceeds the sum of the other two by 0.011 kg m^2)"
            ]
        );
        let thin = LinkInertial {
            inertia: [
                [0.02000000001, 0.0, 0.0],
                [0.0, 0.03, 0.0],
                [0.0, 0.0, 0.0500001234],
            ],
            ..solid
        };
        assert_eq!(
            Consistency::of(&thin.to_standard()).problems,
            [
                "the principal moments 0.02, 0.03, 0.05 kg m^2 break the triangle inequality \
                 (the largest exceeds the sum of the other two by 1.2e-7 kg m^2)"
            ]
        );
    }
}
