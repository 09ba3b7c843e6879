//! Zomaya (1994) worked example: the first three joints of the Stanford arm.
//!
//! The paper (docs/references.md, "Zomaya 1994", section 5 and its appendix)
//! writes the torque of each of the first three joints (R R P) of the Stanford
//! arm in the Lagrange-Euler form of Paul, linear in the entries `w^i_jk` of
//! each link's pseudo-inertia matrix `W_i` (the "radius of gyration matrix",
//! about the origin of link frame i, in frame i), and prints the products
//! `tau_i = Omega_i^T Phi_i` in its eqs. (7)-(13). These tests derive robid's
//! closed-form torques for the same arm and check them term by term against
//! those equations and against a full closed form written out here.
//!
//! Reconstruction (the only text available is an OCR of the paper, in which
//! subscripts, superscripts and dots over the joint variables are garbled):
//!
//! - Frames: the paper points to its reference 17 for the arm; the terms it
//!   prints (a `d2` offset, `sin theta2` factors on `theta1` accelerations, a
//!   prismatic third joint along the arm) fit Paul's standard DH table of the
//!   Stanford arm, used here: joint 1 `alpha = -pi/2, a = 0, d = 0`; joint 2
//!   `alpha = pi/2, a = 0, d = d2`; joint 3 prismatic, `alpha = 0, a = 0,
//!   theta = 0, d = d3` (the variable). The paper keeps `d2` symbolic, so does
//!   the description below. Gravity is `g` along `-z0` (`g` symbolic too).
//! - Parameters: `w^i_jk` is the (j, k) entry of Paul's pseudo-inertia
//!   `W_i = integral of rbar rbar^T dm`, `rbar = (x, y, z, 1)` in frame i. In
//!   robid's standard parameters of link i (docs/conventions.md, inertia
//!   tensor about the frame origin, `XY` the tensor entry = minus the product
//!   of inertia): `w11 = (-XX + YY + ZZ)/2`, `w22 = (XX - YY + ZZ)/2`,
//!   `w33 = (XX + YY - ZZ)/2`, `w12 = -XY`, `w13 = -XZ`, `w23 = -YZ`,
//!   `w14 = MX`, `w24 = MY`, `w34 = MZ`, `w44 = M`. Inversely a torque's
//!   coefficient of `w11` is the sum of its coefficients of `YY` and `ZZ`,
//!   and so on ([`w_coefficients`]).
//! - Eq. (7), read as `tau3 = w^3_14 (-theta2'' - S2 C2 theta1'^2)
//!   + w^3_24 (-S2 theta1'') + w^3_34 (-S2^2 theta1'^2 - theta2'^2) + C`,
//!   `C = w^3_44 (-S2 d2 theta1'' + d3'' - S2^2 d3 theta1'^2 - d3 theta2'^2 - g)`;
//!   eqs. (8)-(9) are the same three terms as `Omega3 = [w^3_14 w^3_24 w^3_34]`
//!   and `Phi3`. The gravity term of `C` prints as `-g` with no angle: it is
//!   reconstructed as `-g_z C2`, `g_z` the signed z component of Paul's
//!   gravity row vector (`-9.81`), which is `+g C2` for a gravity `g` down;
//!   the OCR drops letters elsewhere in the same line, and a `C2` is needed
//!   (the arm points up at `theta2 = 0`, where gravity acts fully along the
//!   prismatic joint, and it is horizontal at `theta2 = pi/2`).
//! - Eqs. (10)-(11): `Omega2 = [w_14 w_34 (w^2_11 + w^3_11) (w^2_33 + w^3_33)]`
//!   and `Phi2 = [d2 S2 theta1'', -d2 C2 theta1'', (theta2'' + S2 C2 theta1'^2),
//!   (theta2'' - S2 C2 theta1'^2)]`. The link of the first two `w`s is lost in
//!   the OCR; read as link 2's (the coefficients printed are exactly link 2's
//!   once gravity is left out).
//! - Eqs. (12)-(13): `Omega1 = [(w^1_11 + w^1_33 + w^2_22 + w^3_22) w^2_24]`,
//!   `Phi1 = [theta1'', 2 d2 theta1'']`; the text after eq. (13) names the sum
//!   of four second moments as a combination in which the parameters appear.
//!
//! What is found (docs/dynamics.md, "Zomaya's Stanford arm"): eqs. (7)-(9)
//! are robid's `tau3` exactly, term by term. Eqs. (10)-(13) print only part
//! of `tau2` and `tau1`: every printed coefficient is robid's coefficient of
//! that parameter (for `tau2`, with gravity left out), but gravity, the
//! products of inertia and the terms in `d3` of link 3 are not printed. The
//! printed parts are asserted as printed, and the remainders are asserted
//! against the full closed form below. One point of eqs. (12)-(13) does not
//! hold as printed: its two regressors, `theta1''` and `2 d2 theta1''`, are
//! proportional, so `w^2_24` cannot be identified apart from the sum of
//! eq. (12); the identifiable combination is the sum plus `2 d2 w^2_24` (plus
//! `d2^2 w^2_44` when the masses are unknown), which is what robid's `ZZR1`
//! holds (with `w^2_11 + w^3_11`, identifiable on its own).

use nalgebra::DMatrix;
use robid_core::rng::Rng;
use robid_symbolic::regroup::BaseParameters;
use robid_symbolic::{Derivation, Robot};

/// Paul's standard DH table of the Stanford arm's first three joints, `d2`
/// and gravity symbolic.
const STANFORD3: &str = r#"
name = "zomaya_stanford"
convention = "standard"
gravity = [0, 0, "-g"]

[symbols]
d2 = 0.154
g = 9.81

[[joints]]
alpha = "-pi/2"
a = 0
d = 0

[[joints]]
alpha = "pi/2"
a = 0
d = "d2"

[[joints]]
type = "prismatic"
alpha = 0
a = 0
d = 0
theta = 0
"#;

/// Index of a pseudo-inertia entry `w_jk` (j <= k, 1-based) in a link's list
/// `[w11 w12 w13 w14 w22 w23 w24 w33 w34 w44]`.
fn w(j: usize, k: usize) -> usize {
    match (j, k) {
        (1, 1) => 0,
        (1, 2) => 1,
        (1, 3) => 2,
        (1, 4) => 3,
        (2, 2) => 4,
        (2, 3) => 5,
        (2, 4) => 6,
        (3, 3) => 7,
        (3, 4) => 8,
        (4, 4) => 9,
        _ => panic!("w{j}{k}"),
    }
}

/// A link's pseudo-inertia entries from robid's ten standard parameters
/// `XX XY XZ YY YZ ZZ MX MY MZ M`.
fn pseudo_inertia(p: &[f64]) -> [f64; 10] {
    let [xx, xy, xz, yy, yz, zz, mx, my, mz, m] = p.try_into().unwrap();
    [
        (-xx + yy + zz) / 2.0,
        -xy,
        -xz,
        mx,
        (xx - yy + zz) / 2.0,
        -yz,
        my,
        (xx + yy - zz) / 2.0,
        mz,
        m,
    ]
}

/// A torque's coefficients of a link's pseudo-inertia entries, from its
/// coefficients `c` of the link's standard parameters `XX .. M`: with
/// `XX = w22 + w33`, `YY = w11 + w33`, `ZZ = w11 + w22`, `XY = -w12`, ...
fn w_coefficients(c: &[f64]) -> [f64; 10] {
    let [xx, xy, xz, yy, yz, zz, mx, my, mz, m] = c.try_into().unwrap();
    [yy + zz, -xy, -xz, mx, xx + zz, -yz, my, xx + yy, mz, m]
}

/// A state of the arm, `d2` and `g`.
#[derive(Clone, Copy, Debug)]
struct State {
    q: [f64; 3],
    qd: [f64; 3],
    qdd: [f64; 3],
    d2: f64,
    g: f64,
}

impl State {
    fn random(rng: &mut Rng) -> State {
        let mut three = |low: f64, high: f64| {
            [
                rng.uniform(low, high),
                rng.uniform(low, high),
                rng.uniform(low, high),
            ]
        };
        let mut q = three(-3.0, 3.0);
        q[2] = q[2].abs() * 0.3 + 0.2; // d3 in [0.2, 1.1] m
        let qd = three(-2.0, 2.0);
        let qdd = three(-5.0, 5.0);
        State {
            q,
            qd,
            qdd,
            d2: rng.uniform(0.05, 0.5),
            g: rng.uniform(0.0, 12.0),
        }
    }

    fn pairs(&self) -> Vec<(String, f64)> {
        let mut out = vec![("d2".to_owned(), self.d2), ("g".to_owned(), self.g)];
        for j in 0..3 {
            out.push((format!("q{}", j + 1), self.q[j]));
            out.push((format!("qd{}", j + 1), self.qd[j]));
            out.push((format!("qdd{}", j + 1), self.qdd[j]));
        }
        out
    }
}

/// The full closed form, written independently of robid: `coef[i][l][e]` is
/// joint i's torque per unit of pseudo-inertia entry e of link l (index
/// [`w`]), from Paul's Lagrange-Euler form `tau_i = sum_l (sum_j tr(U_li W_l
/// (dU_l/dt)^T) ... )` worked out for this table with a computer-algebra system (SymPy, outside robid) and typed in. The paper's printed
/// terms are the parts so marked.
fn closed_form(s: &State) -> [[[f64; 10]; 3]; 3] {
    let ([_, t2, d3], [t1d, t2d, d3d], [t1dd, t2dd, d3dd]) = (s.q, s.qd, s.qdd);
    let (d2, g) = (s.d2, s.g);
    let (s2, c2) = t2.sin_cos();
    let (s22, c22) = (2.0 * t2).sin_cos();
    let mut c = [[[0.0; 10]; 3]; 3];
    // Joint 1.
    let t1 = &mut c[0];
    t1[0][w(1, 1)] = t1dd; // eq. (12)-(13)
    t1[0][w(3, 3)] = t1dd; // eq. (12)-(13)
    for link in &mut t1[1..3] {
        link[w(1, 1)] = (t1dd * (1.0 + c22) - 2.0 * t1d * t2d * s22) / 2.0;
        link[w(3, 3)] = (t1dd * (1.0 - c22) + 2.0 * t1d * t2d * s22) / 2.0;
        link[w(1, 2)] = t2d * t2d * c2 + t2dd * s2;
        link[w(1, 3)] = 2.0 * t1d * t2d * c22 + t1dd * s22;
        link[w(2, 2)] = t1dd; // eq. (12)-(13)
        link[w(2, 3)] = t2d * t2d * s2 - t2dd * c2;
        link[w(1, 4)] = d2 * (t2d * t2d * c2 + t2dd * s2);
        link[w(2, 4)] = 2.0 * d2 * t1dd; // eq. (12)-(13) for link 2
        link[w(3, 4)] = d2 * (t2d * t2d * s2 - t2dd * c2);
        link[w(4, 4)] = d2 * d2 * t1dd;
    }
    // Link 3, displaced by d3 along z2.
    t1[2][w(1, 4)] += d3 * (2.0 * t1d * t2d * c22 + t1dd * s22) + d3d * t1d * s22;
    t1[2][w(2, 4)] += d3 * (t2d * t2d * s2 - t2dd * c2) - 2.0 * d3d * t2d * c2 - d3dd * s2;
    t1[2][w(3, 4)] += d3 * (2.0 * t1d * t2d * s22 + t1dd * (1.0 - c22)) + d3d * t1d * (1.0 - c22);
    t1[2][w(4, 4)] +=
        d2 * d3 * (t2d * t2d * s2 - t2dd * c2) - 2.0 * d2 * d3d * t2d * c2 - d2 * d3dd * s2
            + d3 * d3 * (t1d * t2d * s22 + t1dd * (1.0 - c22) / 2.0)
            + d3 * d3d * t1d * (1.0 - c22);
    // Joint 2.
    let t2c = &mut c[1];
    for link in &mut t2c[1..3] {
        link[w(1, 1)] = t2dd + s2 * c2 * t1d * t1d; // eq. (10)-(11)
        link[w(3, 3)] = t2dd - s2 * c2 * t1d * t1d; // eq. (10)-(11)
        link[w(1, 2)] = t1dd * s2;
        link[w(1, 3)] = -t1d * t1d * c22;
        link[w(2, 3)] = -t1dd * c2;
        link[w(1, 4)] = d2 * t1dd * s2 - g * c2; // eq. (10)-(11) without gravity
        link[w(3, 4)] = -d2 * t1dd * c2 - g * s2; // eq. (10)-(11) without gravity
    }
    t2c[2][w(1, 4)] += -d3 * t1d * t1d * c22 - d3dd;
    t2c[2][w(2, 4)] = -d3 * t1dd * c2;
    t2c[2][w(3, 4)] += -d3 * t1d * t1d * s22 + 2.0 * d3 * t2dd + 2.0 * d3d * t2d;
    t2c[2][w(4, 4)] =
        -d3 * (d2 * t1dd * c2 + d3 * t1d * t1d * s2 * c2 - d3 * t2dd - 2.0 * d3d * t2d + g * s2);
    // Joint 3: eq. (7).
    let t3 = &mut c[2][2];
    t3[w(1, 4)] = -(t2dd + s2 * c2 * t1d * t1d);
    t3[w(2, 4)] = -s2 * t1dd;
    t3[w(3, 4)] = -(s2 * s2 * t1d * t1d + t2d * t2d);
    t3[w(4, 4)] = -s2 * d2 * t1dd + d3dd - s2 * s2 * d3 * t1d * t1d - d3 * t2d * t2d + g * c2;
    c
}

/// The paper's eqs. (7)-(13) as printed (reconstructed as in the module
/// comment): `(Omega_i, Phi_i)` pairs per joint, each `Omega` entry a list of
/// `(link, entry)` summed, plus eq. (7)'s constant `C` for joint 3. `g_z` is
/// the signed z component of gravity.
fn paper(s: &State, p: &[[f64; 10]; 3]) -> [f64; 3] {
    let ([_, t2, d3], [t1d, t2d, _], [t1dd, t2dd, d3dd]) = (s.q, s.qd, s.qdd);
    let (d2, g_z) = (s.d2, -s.g);
    let (s2, c2) = t2.sin_cos();
    let sum = |terms: &[(usize, (usize, usize))]| -> f64 {
        terms.iter().map(|&(l, (j, k))| p[l - 1][w(j, k)]).sum()
    };
    let dot =
        |omega: &[f64], phi: &[f64]| -> f64 { omega.iter().zip(phi).map(|(a, b)| a * b).sum() };
    // Eqs. (12)-(13).
    let omega1 = [
        sum(&[(1, (1, 1)), (1, (3, 3)), (2, (2, 2)), (3, (2, 2))]),
        sum(&[(2, (2, 4))]),
    ];
    let phi1 = [t1dd, 2.0 * d2 * t1dd];
    // Eqs. (10)-(11).
    let omega2 = [
        sum(&[(2, (1, 4))]),
        sum(&[(2, (3, 4))]),
        sum(&[(2, (1, 1)), (3, (1, 1))]),
        sum(&[(2, (3, 3)), (3, (3, 3))]),
    ];
    let phi2 = [
        d2 * s2 * t1dd,
        -d2 * c2 * t1dd,
        t2dd + s2 * c2 * t1d * t1d,
        t2dd - s2 * c2 * t1d * t1d,
    ];
    // Eqs. (7)-(9).
    let omega3 = [
        sum(&[(3, (1, 4))]),
        sum(&[(3, (2, 4))]),
        sum(&[(3, (3, 4))]),
    ];
    let phi3 = [
        -(t2dd + s2 * c2 * t1d * t1d),
        -s2 * t1dd,
        -(s2 * s2 * t1d * t1d + t2d * t2d),
    ];
    let constant = p[2][w(4, 4)]
        * (-s2 * d2 * t1dd + d3dd - s2 * s2 * d3 * t1d * t1d - d3 * t2d * t2d - g_z * c2);
    [
        dot(&omega1, &phi1),
        dot(&omega2, &phi2),
        dot(&omega3, &phi3) + constant,
    ]
}

/// robid's derivation of the arm, its symbolic torques `tau(q, qd, qdd, p)`
/// and its regressor.
struct Model {
    d: Derivation,
    torques: Vec<robid_symbolic::expr::Id>,
    regressor: Vec<robid_symbolic::expr::Id>,
}

fn model() -> Model {
    let robot = Robot::from_toml(STANFORD3, "zomaya_stanford.toml").unwrap();
    assert_eq!(robot.dof(), 3);
    let mut d = Derivation::new(&robot);
    let symbols = d.parameter_symbols();
    assert_eq!(
        symbols.len(),
        30,
        "ten standard parameters per link, no drive terms"
    );
    let torques = d.inverse_dynamics(&symbols);
    let regressor = d.regressor().entries();
    Model {
        d,
        torques,
        regressor,
    }
}

/// Random standard parameters (three links of ten) and their pseudo-inertias.
fn random_parameters(rng: &mut Rng) -> (Vec<f64>, [[f64; 10]; 3]) {
    let p: Vec<f64> = (0..30).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let w = [0, 1, 2].map(|l| pseudo_inertia(&p[10 * l..10 * l + 10]));
    (p, w)
}

impl Model {
    /// robid's torques at a state for standard parameters `p`.
    fn torques(&self, s: &State, p: &[f64]) -> Vec<f64> {
        let names: Vec<String> = self
            .d
            .standard_parameters()
            .iter()
            .map(ToString::to_string)
            .collect();
        let mut pairs = s.pairs();
        pairs.extend(names.into_iter().zip(p.iter().copied()));
        let refs: Vec<(&str, f64)> = pairs.iter().map(|(n, v)| (n.as_str(), *v)).collect();
        let mut arena = self.d.arena.clone();
        let values = arena.values(&refs);
        arena.eval(&self.torques, &values).unwrap()
    }

    /// `coef[i][l][e]`: joint i's torque per unit of pseudo-inertia entry e of
    /// link l, from robid's regressor columns.
    fn w_coefficients(&self, s: &State) -> [[[f64; 10]; 3]; 3] {
        let pairs = s.pairs();
        let refs: Vec<(&str, f64)> = pairs.iter().map(|(n, v)| (n.as_str(), *v)).collect();
        let mut arena = self.d.arena.clone();
        let values = arena.values(&refs);
        let y = arena.eval(&self.regressor, &values).unwrap(); // column-major, 3 rows
        let mut out = [[[0.0; 10]; 3]; 3];
        for (i, joint) in out.iter_mut().enumerate() {
            for (l, link) in joint.iter_mut().enumerate() {
                let c: Vec<f64> = (0..10).map(|k| y[(10 * l + k) * 3 + i]).collect();
                *link = w_coefficients(&c);
            }
        }
        out
    }
}

const NAMES: [&str; 10] = [
    "w11", "w12", "w13", "w14", "w22", "w23", "w24", "w33", "w34", "w44",
];

fn close(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= 1e-12 * scale.max(1.0)
}

/// robid's torques equal the full closed form at 500 random states and
/// parameter values (d2 and g random too), to 1e-12 relative.
#[test]
fn zomaya_torques_match_full_closed_form() {
    let m = model();
    let mut rng = Rng::from_state(1994);
    let mut worst = 0.0_f64;
    for case in 0..500 {
        let s = State::random(&mut rng);
        let (p, pw) = random_parameters(&mut rng);
        let tau = m.torques(&s, &p);
        let c = closed_form(&s);
        for i in 0..3 {
            let terms: Vec<f64> = (0..3)
                .flat_map(|l| (0..10).map(move |e| (l, e)))
                .map(|(l, e)| c[i][l][e] * pw[l][e])
                .collect();
            let expected: f64 = terms.iter().sum();
            let scale: f64 = terms.iter().map(|t| t.abs()).sum();
            assert!(
                close(tau[i], expected, scale),
                "case {case}, joint {}: robid {} vs closed form {expected}\n{s:?}",
                i + 1,
                tau[i]
            );
            worst = worst.max((tau[i] - expected).abs() / scale.max(1.0));
        }
    }
    eprintln!("worst relative difference {worst:e}");
}

/// Coefficient by coefficient: each of the 90 (joint, link, pseudo-inertia
/// entry) coefficients of robid's regressor equals the closed form's, at 200
/// random states.
#[test]
fn zomaya_regressor_coefficients_match_closed_form() {
    let m = model();
    let mut rng = Rng::from_state(41);
    for case in 0..200 {
        let s = State::random(&mut rng);
        let robid = m.w_coefficients(&s);
        let expected = closed_form(&s);
        for i in 0..3 {
            for l in 0..3 {
                for e in 0..10 {
                    let (a, b) = (robid[i][l][e], expected[i][l][e]);
                    assert!(
                        close(a, b, b.abs()),
                        "case {case}: tau{} coefficient of {}^{}: robid {a}, closed form {b}\n{s:?}",
                        i + 1,
                        NAMES[e],
                        l + 1
                    );
                }
            }
        }
    }
}

/// Eqs. (7)-(9): `tau3 = Omega3^T Phi3 + C` is robid's `tau3` exactly, and
/// robid's regressor row of joint 3 is `Phi3` on `MX3 MY3 MZ3`, `C / M3` on
/// `M3`, and zero on every other parameter (no second moment of link 3 and
/// nothing of links 1 and 2 acts along the prismatic joint).
#[test]
fn zomaya_eq7_tau3_term_by_term() {
    let m = model();
    let mut rng = Rng::from_state(7);
    for case in 0..300 {
        let s = State::random(&mut rng);
        let (p, pw) = random_parameters(&mut rng);
        let tau = m.torques(&s, &p);
        let printed = paper(&s, &pw);
        let scale = 1.0 + tau[2].abs() + printed[2].abs() + 10.0 * s.g;
        assert!(
            close(tau[2], printed[2], scale),
            "case {case}: tau3 robid {} vs eq. (7) {}",
            tau[2],
            printed[2]
        );
        let robid = m.w_coefficients(&s);
        let c = closed_form(&s);
        for (l, link) in robid[2].iter().enumerate() {
            for (e, &a) in link.iter().enumerate() {
                let expected = if l == 2 { c[2][2][e] } else { 0.0 };
                assert!(
                    close(a, expected, expected.abs()),
                    "case {case}: {}^{}",
                    NAMES[e],
                    l + 1
                );
            }
        }
        for e in [w(1, 1), w(1, 2), w(1, 3), w(2, 2), w(2, 3), w(3, 3)] {
            assert!(
                robid[2][2][e].abs() < 1e-12,
                "case {case}: {} of link 3 in tau3",
                NAMES[e]
            );
        }
    }
}

/// Eqs. (10)-(11): each printed coefficient of `tau2` is robid's coefficient
/// of that parameter without gravity (`g = 0`): `w^2_11` and `w^3_11` both
/// with `theta2'' + S2 C2 theta1'^2`, `w^2_33` and `w^3_33` both with
/// `theta2'' - S2 C2 theta1'^2` (hence the sums the paper identifies),
/// `w^2_14` with `d2 S2 theta1''`, `w^2_34` with `-d2 C2 theta1''`. With
/// gravity, robid adds `-g C2` and `-g S2` to the last two; and the printed
/// `tau2` leaves out the products of inertia, the first moments of link 3 and
/// its mass: robid's `tau2` minus the printed one is exactly those terms of
/// the closed form.
#[test]
fn zomaya_eq10_11_tau2_printed_terms() {
    let m = model();
    let mut rng = Rng::from_state(10);
    for case in 0..300 {
        let mut s = State::random(&mut rng);
        let (p, pw) = random_parameters(&mut rng);
        let ([_, t2, _], [t1d, _, _], [t1dd, t2dd, _]) = (s.q, s.qd, s.qdd);
        let (s2, c2) = t2.sin_cos();
        let g = s.g;
        let robid = m.w_coefficients(&s);
        let pairs = [
            ((1, (1, 1)), t2dd + s2 * c2 * t1d * t1d, 0.0),
            ((2, (1, 1)), t2dd + s2 * c2 * t1d * t1d, 0.0),
            ((1, (3, 3)), t2dd - s2 * c2 * t1d * t1d, 0.0),
            ((2, (3, 3)), t2dd - s2 * c2 * t1d * t1d, 0.0),
            ((1, (1, 4)), s.d2 * s2 * t1dd, -g * c2),
            ((1, (3, 4)), -s.d2 * c2 * t1dd, -g * s2),
        ];
        for ((l, (j, k)), printed, gravity) in pairs {
            let a = robid[1][l][w(j, k)];
            assert!(
                close(a, printed + gravity, printed.abs() + gravity.abs()),
                "case {case}: tau2 coefficient of w{j}{k}^{}: robid {a}, printed {printed}, gravity {gravity}",
                l + 1
            );
        }
        // The omitted remainder.
        let tau = m.torques(&s, &p);
        let printed = paper(&s, &pw)[1];
        let c = closed_form(&s);
        let mut omitted = 0.0;
        let mut scale = 1.0 + printed.abs();
        for (l, link) in c[1].iter().enumerate() {
            for (e, coefficient) in link.iter().enumerate() {
                let in_print = matches!((l, e), (1 | 2, 0 | 7) | (1, 3 | 8));
                let shown = if in_print {
                    // printed coefficients, plus the gravity the print leaves out
                    match (l, e) {
                        (1, 3) => -g * c2,
                        (1, 8) => -g * s2,
                        _ => 0.0,
                    }
                } else {
                    *coefficient
                };
                omitted += shown * pw[l][e];
                scale += (coefficient * pw[l][e]).abs();
            }
        }
        assert!(
            close(tau[1], printed + omitted, scale),
            "case {case}: tau2 robid {} vs printed {printed} + omitted {omitted}",
            tau[1]
        );
        // Without gravity, products of inertia and link 3's first moments and
        // mass, the printed tau2 is robid's.
        s.g = 0.0;
        let mut p0 = p.clone();
        for l in 0..3 {
            for k in [1, 2, 4] {
                p0[10 * l + k] = 0.0; // XY XZ YZ
            }
        }
        for k in 6..10 {
            p0[20 + k] = 0.0; // MX3 MY3 MZ3 M3
        }
        let pw0 = [0, 1, 2].map(|l| pseudo_inertia(&p0[10 * l..10 * l + 10]));
        let tau0 = m.torques(&s, &p0)[1];
        let printed0 = paper(&s, &pw0)[1];
        assert!(
            close(tau0, printed0, scale),
            "case {case}: {tau0} vs {printed0}"
        );
    }
}

/// Eqs. (12)-(13): robid's `tau1` has `theta1''` as the coefficient of each
/// of `w^1_11`, `w^1_33`, `w^2_22` and `w^3_22` (so only their sum acts, the
/// combination the paper names) and `2 d2 theta1''` as that of `w^2_24`. The
/// print leaves out every other term of `tau1` (the second moments of links 2
/// and 3 in `cos 2 theta2`, their products of inertia, first moments and the
/// terms in `d3`, as in the closed form).
#[test]
fn zomaya_eq12_13_tau1_printed_terms() {
    let m = model();
    let mut rng = Rng::from_state(12);
    for case in 0..300 {
        let s = State::random(&mut rng);
        let t1dd = s.qdd[0];
        let robid = m.w_coefficients(&s);
        for (l, (j, k), printed) in [
            (0, (1, 1), t1dd),
            (0, (3, 3), t1dd),
            (1, (2, 2), t1dd),
            (2, (2, 2), t1dd),
            (1, (2, 4), 2.0 * s.d2 * t1dd),
        ] {
            let a = robid[0][l][w(j, k)];
            assert!(
                close(a, printed, printed.abs()),
                "case {case}: tau1 coefficient of w{j}{k}^{}: robid {a}, printed {printed}",
                l + 1
            );
        }
        // Link 1's other entries have no effect at all.
        for e in [
            w(1, 2),
            w(1, 3),
            w(1, 4),
            w(2, 2),
            w(2, 3),
            w(2, 4),
            w(3, 4),
            w(4, 4),
        ] {
            assert!(
                robid[0][0][e].abs() < 1e-12,
                "case {case}: {}^1 in tau1",
                NAMES[e]
            );
        }
    }
}

/// A standard-parameter row (30 entries) for a combination of pseudo-inertia
/// entries `(link, (j, k), factor)`: the row r with `r . p = sum factor w^l_jk`.
fn row(terms: &[(usize, (usize, usize), f64)]) -> Vec<f64> {
    let mut r = vec![0.0; 30];
    for &(l, (j, k), f) in terms {
        let base = 10 * (l - 1);
        // w in XX XY XZ YY YZ ZZ MX MY MZ M (see pseudo_inertia)
        let add: &[(usize, f64)] = match (j, k) {
            (1, 1) => &[(0, -0.5), (3, 0.5), (5, 0.5)],
            (2, 2) => &[(0, 0.5), (3, -0.5), (5, 0.5)],
            (3, 3) => &[(0, 0.5), (3, 0.5), (5, -0.5)],
            (1, 2) => &[(1, -1.0)],
            (1, 3) => &[(2, -1.0)],
            (2, 3) => &[(4, -1.0)],
            (1, 4) => &[(6, 1.0)],
            (2, 4) => &[(7, 1.0)],
            (3, 4) => &[(8, 1.0)],
            _ => &[(9, 1.0)],
        };
        for &(i, a) in add {
            r[base + i] += f * a;
        }
    }
    r
}

/// A direction in the standard parameters (30 entries) that moves the
/// pseudo-inertia entries `(link, (j, k), amount)` and no other: with
/// `XX = w22 + w33`, `YY = w11 + w33`, `ZZ = w11 + w22`, `XY = -w12`, ...
fn direction(terms: &[(usize, (usize, usize), f64)]) -> Vec<f64> {
    let mut v = vec![0.0; 30];
    for &(l, (j, k), f) in terms {
        let base = 10 * (l - 1);
        let moves: &[(usize, f64)] = match (j, k) {
            (1, 1) => &[(3, 1.0), (5, 1.0)],
            (2, 2) => &[(0, 1.0), (5, 1.0)],
            (3, 3) => &[(0, 1.0), (3, 1.0)],
            (1, 2) => &[(1, -1.0)],
            (1, 3) => &[(2, -1.0)],
            (2, 3) => &[(4, -1.0)],
            (1, 4) => &[(6, 1.0)],
            (2, 4) => &[(7, 1.0)],
            (3, 4) => &[(8, 1.0)],
            _ => &[(9, 1.0)],
        };
        for &(i, a) in moves {
            v[base + i] += f * a;
        }
    }
    v
}

fn rank(rows: &[Vec<f64>]) -> usize {
    let m = DMatrix::from_fn(rows.len(), rows[0].len(), |i, j| rows[i][j]);
    m.svd(false, false).rank(1e-9)
}

/// The paper's identifiability statement against robid's base parameters:
/// robid regroups the 30 standard parameters of the three links into
/// base parameters whose map K (evaluated at the description's d2) leaves
/// the torques unchanged along `w^1_11 - w^2_22`, `w^1_33 - w^2_22`,
/// `w^3_22 - w^2_22` (only the sum of eq. (12) acts), and along
/// `w^2_11 - w^3_11`, `w^2_33 - w^3_33` (eq. (10)'s sums). The sum of eq. (12)
/// itself is identifiable once the masses are known, as the paper assumes:
/// robid, which takes the masses as unknown, identifies it only together with
/// `d2^2 M2`.
#[test]
fn zomaya_identifiable_combinations_match_base_parameters() {
    let robot = Robot::from_toml(STANFORD3, "zomaya_stanford.toml").unwrap();
    let mut d = Derivation::new(&robot);
    let b: BaseParameters = d.base_parameters().unwrap();
    let names: Vec<String> = b.base.iter().map(|p| p.name.to_string()).collect();
    // Symbolically (d2 kept as a symbol): the twelve base parameters.
    let written: Vec<String> = b
        .base
        .iter()
        .map(|p| format!("{} = {}", p.name, d.arena.display(p.expression)))
        .collect();
    assert_eq!(
        written,
        [
            "ZZR1 = YY1 + ZZ2 + ZZ3 + 2*d2*MY2 + M2*d2^2",
            "XXR2 = XX2 + XX3 - ZZ2 - ZZ3",
            "XYR2 = -XZ2 - XZ3",
            "XZR2 = XY2 + XY3",
            "YZR2 = -YZ2 - YZ3",
            "ZZR2 = YY2 + YY3",
            "MX2 = MX2",
            "MYR2 = -MZ2",
            "MX3 = MX3",
            "MY3 = MY3",
            "MZ3 = MZ3",
            "M3 = M3",
        ]
    );
    let k_ids = b.k_matrix(&mut d.arena);
    let mut rng = Rng::from_state(13);
    let d2 = rng.uniform(0.05, 0.5);
    let values = d.arena.values(&[("d2", d2), ("g", 9.81)]);
    let k: Vec<Vec<f64>> = k_ids
        .iter()
        .map(|r| d.arena.eval(r, &values).unwrap())
        .collect();
    let null = |v: &[f64]| -> f64 {
        k.iter()
            .map(|r| r.iter().zip(v).map(|(a, b)| a * b).sum::<f64>().abs())
            .fold(0.0, f64::max)
    };
    for (a, bb) in [
        ((1, (1, 1)), (2, (2, 2))),
        ((1, (3, 3)), (2, (2, 2))),
        ((3, (2, 2)), (2, (2, 2))),
        ((2, (1, 1)), (3, (1, 1))),
        ((2, (3, 3)), (3, (3, 3))),
    ] {
        let v = direction(&[(a.0, a.1, 1.0), (bb.0, bb.1, -1.0)]);
        assert!(
            null(&v) < 1e-12,
            "{a:?} - {bb:?} moves a base parameter by {}",
            null(&v)
        );
    }
    // robid's ZZR1 is the paper's sum plus `w^2_11 + w^3_11` (itself
    // identifiable, eq. (10)), `2 d2 w^2_24` and `d2^2 w^2_44`.
    let zzr1 = names.iter().position(|n| n == "ZZR1").expect("a ZZR1");
    let expected = row(&[
        (1, (1, 1), 1.0),
        (1, (3, 3), 1.0),
        (2, (2, 2), 1.0),
        (3, (2, 2), 1.0),
        (2, (1, 1), 1.0),
        (3, (1, 1), 1.0),
        (2, (2, 4), 2.0 * d2),
        (2, (4, 4), d2 * d2),
    ]);
    for (i, (a, e)) in k[zzr1].iter().zip(&expected).enumerate() {
        assert!(
            (a - e).abs() < 1e-12,
            "ZZR1 coefficient of {}: {a} vs {e}",
            b.standard[i]
        );
    }
    let base_rank = rank(&k);
    assert_eq!(base_rank, b.base.len());
    let sum = [
        (1, (1, 1), 1.0),
        (1, (3, 3), 1.0),
        (2, (2, 2), 1.0),
        (3, (2, 2), 1.0),
    ];
    let in_span = |r: Vec<f64>| {
        let mut rows = k.clone();
        rows.push(r);
        rank(&rows) == base_rank
    };
    // With the masses unknown: neither the sum alone nor with `d2^2 M2` is
    // identifiable; with `2 d2 w^2_24` as well it is (eq. (13)'s two
    // regressors, `theta1''` and `2 d2 theta1''`, are proportional, so its two
    // parameters only act together).
    assert!(!in_span(row(&sum)));
    let mut with_mass = sum.to_vec();
    with_mass.push((2, (4, 4), d2 * d2));
    assert!(!in_span(row(&with_mass)));
    with_mass.push((2, (2, 4), 2.0 * d2));
    assert!(in_span(row(&with_mass)));
    assert!(!in_span(row(&[(2, (2, 4), 1.0)])), "w^2_24 alone");
    // With the masses known (their rows added to K), the sum is identifiable
    // with `2 d2 w^2_24`, still not alone.
    let mut known = k.clone();
    for l in 1..=3 {
        known.push(row(&[(l, (4, 4), 1.0)]));
    }
    let known_rank = rank(&known);
    let in_known = |r: Vec<f64>| {
        let mut rows = known.clone();
        rows.push(r);
        rank(&rows) == known_rank
    };
    assert!(!in_known(row(&sum)));
    let mut with_moment = sum.to_vec();
    with_moment.push((2, (2, 4), 2.0 * d2));
    assert!(in_known(row(&with_moment)));
    // So are eq. (10)'s sums and the first moments of eqs. (8) and (10).
    for terms in [
        vec![(2, (1, 1), 1.0), (3, (1, 1), 1.0)],
        vec![(2, (3, 3), 1.0), (3, (3, 3), 1.0)],
        vec![(2, (1, 4), 1.0)],
        vec![(2, (3, 4), 1.0)],
        vec![(3, (1, 4), 1.0)],
        vec![(3, (2, 4), 1.0)],
        vec![(3, (3, 4), 1.0)],
    ] {
        assert!(in_span(row(&terms)), "{terms:?} not identifiable");
    }
}
