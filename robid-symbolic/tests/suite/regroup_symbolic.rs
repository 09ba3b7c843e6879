//! Symbolic geometry regroups whenever numbers do.
//!
//! A robot written with some lengths as `[symbols]` (its symbolic twin) and
//! the same robot with the numbers (its numeric twin) have the same base
//! parameters and, at the symbols' values, the same torques; the base
//! parameters hold for every value of the symbols, not only where the
//! regrouping samples them ([0.2, 1]); a dependency coefficient that is a
//! ratio of the symbols (no value somewhere) is refused, naming the symbols.

use proptest::prelude::*;
use robid_core::rng::Rng;
use robid_symbolic::regroup::{BaseParameters, RegroupError};
use robid_symbolic::robot::Geometry;
use robid_symbolic::{Derivation, Drive, Num, Robot};

/// One joint of a random robot.
#[derive(Clone, Debug)]
struct JointSpec {
    prismatic: bool,
    alpha: String,
    theta: String,
    /// `a` and `d`: the value, and how the symbolic twin writes it (`None`:
    /// the number, as the numeric twin does).
    lengths: [(f64, Option<String>); 2],
    drive: Vec<&'static str>,
}

/// A random robot, written twice.
#[derive(Clone, Debug)]
struct Spec {
    convention: &'static str,
    gravity: [f64; 3],
    joints: Vec<JointSpec>,
    /// The symbols and their values.
    symbols: Vec<(String, f64)>,
}

/// An angle: a multiple of pi/2, another exact multiple of pi, or a number.
fn random_angle(rng: &mut Rng) -> String {
    match rng.below(6) {
        0 | 1 => "0".to_owned(),
        2 => "pi/2".to_owned(),
        3 => "-pi/2".to_owned(),
        4 => ["pi/6", "pi/3", "-pi/4", "2*pi/3"][rng.below(4)].to_owned(),
        _ => format!("{:.4}", rng.uniform(-3.0, 3.0)),
    }
}

/// 1 to 5 joints, revolute or prismatic, random twists (and offsets of
/// prismatic joints), lengths zero, numbers or symbols (some symbols used
/// twice, also negated or halved), random drive terms, either convention,
/// gravity along -z or tilted.
fn random_spec(seed: u64) -> Spec {
    let mut rng = Rng::from_state(seed);
    let dof = 1 + rng.below(5);
    let mut symbols: Vec<(String, f64)> = Vec::new();
    let mut joints = Vec::with_capacity(dof);
    for j in 1..=dof {
        let prismatic = rng.below(3) == 0;
        let alpha = random_angle(&mut rng);
        let theta = if prismatic {
            random_angle(&mut rng)
        } else {
            "0".to_owned()
        };
        let mut lengths = [(0.0, None), (0.0, None)];
        for (k, (value, text)) in lengths.iter_mut().enumerate() {
            if rng.below(4) == 0 {
                continue; // zero: a number in both twins
            }
            let fresh = (rng.uniform(-0.6, 0.6) * 1000.0).round() / 1000.0;
            if fresh == 0.0 {
                continue;
            }
            if !symbols.is_empty() && rng.below(4) == 0 {
                // A symbol used again: the same length elsewhere, possibly scaled.
                let (name, v) = symbols[rng.below(symbols.len())].clone();
                let (factor, written) = match rng.below(3) {
                    0 => (1.0, name.clone()),
                    1 => (-1.0, format!("-{name}")),
                    _ => (0.5, format!("{name}/2")),
                };
                *value = factor * v;
                *text = Some(written);
            } else if rng.below(5) == 0 {
                *value = fresh; // a number in both twins
            } else {
                let name = format!("{}{j}", ["a", "d"][k]);
                symbols.push((name.clone(), fresh));
                *value = fresh;
                *text = Some(name);
            }
        }
        let drive: Vec<&'static str> = ["Ia", "Fv", "Fc", "Fo"]
            .into_iter()
            .filter(|_| rng.below(2) == 0)
            .collect();
        joints.push(JointSpec {
            prismatic,
            alpha,
            theta,
            lengths,
            drive,
        });
    }
    let convention = ["modified", "standard"][rng.below(2)];
    let gravity = if rng.below(2) == 0 {
        [0.0, 0.0, -9.81]
    } else {
        // Tilted: components rounded to mm/s^2, none closer to 0 than allowed.
        let mut component = |low: f64, high: f64| {
            let g = (rng.uniform(low, high) * 1000.0).round() / 1000.0;
            if g.abs() < 0.01 { 0.0 } else { g }
        };
        [
            component(-5.0, 5.0),
            component(-5.0, 5.0),
            component(-9.0, -1.0),
        ]
    };
    Spec {
        convention,
        gravity,
        joints,
        symbols,
    }
}

impl Spec {
    /// The description; `symbolic` writes the symbols where chosen.
    fn toml(&self, symbolic: bool) -> String {
        let mut out = format!(
            "name = \"twin\"\nconvention = \"{}\"\ngravity = [{:?}, {:?}, {:?}]\n",
            self.convention, self.gravity[0], self.gravity[1], self.gravity[2]
        );
        if symbolic && !self.symbols.is_empty() {
            out.push_str("[symbols]\n");
            for (name, value) in &self.symbols {
                out.push_str(&format!("{name} = {value:?}\n"));
            }
        }
        for j in &self.joints {
            out.push_str("[[joints]]\n");
            if j.prismatic {
                out.push_str("type = \"prismatic\"\n");
            }
            out.push_str(&format!(
                "alpha = \"{}\"\ntheta = \"{}\"\n",
                j.alpha, j.theta
            ));
            for (key, (value, text)) in ["a", "d"].iter().zip(&j.lengths) {
                match text {
                    Some(t) if symbolic => out.push_str(&format!("{key} = \"{t}\"\n")),
                    _ => out.push_str(&format!("{key} = {value:?}\n")),
                }
            }
            let drive: Vec<String> = j.drive.iter().map(|d| format!("\"{d}\"")).collect();
            out.push_str(&format!("drive = [{}]\n", drive.join(", ")));
        }
        out
    }
}

/// Torques at `states` random states with the symbols at `symbols`: the base
/// model `Y_b K p` and the full one `Y p`, every joint of every state.
fn torques(
    d: &mut Derivation,
    b: &BaseParameters,
    p: &[f64],
    symbols: &[(&str, f64)],
    seed: u64,
    states: usize,
) -> (Vec<f64>, Vec<f64>) {
    let y = d.regressor();
    let k = b.k_matrix(&mut d.arena);
    let n = d.robot.dof();
    let ns = p.len();
    let mut rng = Rng::from_state(seed);
    let (mut base, mut full) = (Vec::new(), Vec::new());
    for _ in 0..states {
        let values = crate::common::random_state(&mut d.arena, n, symbols, &mut rng);
        let yv = d.arena.eval(&y.entries(), &values).unwrap();
        let ybv = d.arena.eval(&b.columns.concat(), &values).unwrap();
        let kv = d.arena.eval(&k.concat(), &values).unwrap();
        let beta: Vec<f64> = (0..b.base.len())
            .map(|i| (0..ns).map(|s| kv[i * ns + s] * p[s]).sum())
            .collect();
        for j in 0..n {
            full.push((0..ns).map(|s| yv[s * n + j] * p[s]).sum());
            base.push((0..beta.len()).map(|i| ybv[i * n + j] * beta[i]).sum());
        }
    }
    (base, full)
}

/// The twins of `seed` regroup to the same parameters, and their torques
/// (base and full models, symbols at their values) agree to 1e-12 of the
/// largest torque, the bound issue 12 sets (measured: at most 4.3e-15 over
/// seeds 3000 to 5999). Returns the worst difference relative to that scale.
fn check(seed: u64) -> f64 {
    let spec = random_spec(seed);
    let (numeric_text, symbolic_text) = (spec.toml(false), spec.toml(true));
    let numeric = Robot::from_toml(&numeric_text, "numeric.toml").unwrap();
    let symbolic = Robot::from_toml(&symbolic_text, "symbolic.toml")
        .unwrap_or_else(|e| panic!("seed {seed}: {e}\n{symbolic_text}"));
    let mut dn = Derivation::new(&numeric);
    let bn = dn
        .base_parameters()
        .unwrap_or_else(|e| panic!("seed {seed}: numeric twin: {e}\n{numeric_text}"));
    let mut ds = Derivation::new(&symbolic);
    let bs = ds
        .base_parameters()
        .unwrap_or_else(|e| panic!("seed {seed}: symbolic twin: {e}\n{symbolic_text}"));
    // The same candidates kept (a grouped term that is rounding in one twin
    // may add an `R` to a name in it).
    let stems = |b: &BaseParameters| b.base.iter().map(|p| p.name.on).collect::<Vec<_>>();
    assert_eq!(
        stems(&bs),
        stems(&bn),
        "seed {seed}: base parameters differ\n{symbolic_text}"
    );
    let mut rng = Rng::from_state(seed ^ 0x5151);
    let p: Vec<f64> = bn.standard.iter().map(|_| rng.uniform(-1.0, 1.0)).collect();
    let states = bn.standard.len() / numeric.dof() + 4;
    let values: Vec<(&str, f64)> = spec.symbols.iter().map(|(s, v)| (s.as_str(), *v)).collect();
    let (tau_s, full_s) = torques(&mut ds, &bs, &p, &values, seed, states);
    let (tau_n, full_n) = torques(&mut dn, &bn, &p, &[], seed, states);
    let scale = full_n.iter().fold(0.0_f64, |m, t| m.max(t.abs()));
    let mut worst = 0.0_f64;
    for (row, (((s, n), fs), f)) in tau_s
        .iter()
        .zip(&tau_n)
        .zip(&full_s)
        .zip(&full_n)
        .enumerate()
    {
        let here = [(s - n).abs(), (s - f).abs(), (n - f).abs(), (fs - f).abs()]
            .into_iter()
            .fold(0.0, f64::max);
        assert!(
            here <= 1e-12 * scale,
            "seed {seed}: row {row}: symbolic {s}, numeric {n}, full {fs} and {f} (scale {scale})\n{symbolic_text}"
        );
        worst = worst.max(here / scale);
    }
    worst
}

proptest! {
    #![proptest_config(crate::common::proptest_config(128))]
    #[test]
    fn symbolic_twins_regroup_like_numeric_twins(seed in any::<u64>()) {
        check(seed);
    }
}

/// Seeds that failed while this was written: 1273 and 1409 (a least-squares
/// solve by nalgebra's SVD wrong by 1e-5; a twist 1e-4 from pi/2), 257 (a
/// coefficient 2 cos(pi/4) 0.553 taken for the decimal 0.7820601), 939 and
/// 1673 (an `R` from a rounding term in the numeric twin only).
#[test]
fn symbolic_twins_of_past_failures() {
    for seed in [257, 939, 1273, 1409, 1673] {
        check(seed);
    }
}

fn derive(text: &str) -> (Derivation, Result<BaseParameters, RegroupError>) {
    let robot = Robot::from_toml(text, "inline.toml").unwrap();
    let mut d = Derivation::new(&robot);
    let b = d.base_parameters();
    (d, b)
}

/// The coefficient of standard parameter `standard` in base parameter `base`.
fn coefficient(b: &BaseParameters, base: &str, standard: &str) -> robid_symbolic::Id {
    let s = b
        .standard
        .iter()
        .position(|p| p.to_string() == standard)
        .unwrap();
    let p = b.base.iter().find(|p| p.name.to_string() == base).unwrap();
    p.terms.iter().find(|&&(t, _)| t == s).unwrap().1
}

fn names(b: &BaseParameters) -> Vec<String> {
    b.base.iter().map(|p| p.name.to_string()).collect()
}

/// One prismatic joint along gravity, its offset `L1 = 0.3` as a symbol or
/// as the number.
fn slider(symbolic: bool) -> String {
    let (symbols, d) = if symbolic {
        ("[symbols]\nL1 = 0.3\n", "\"L1\"")
    } else {
        ("", "0.3")
    };
    format!(
        "name = \"slider\"\nconvention = \"modified\"\n{symbols}[[joints]]\ntype = \"prismatic\"\nalpha = 0\nd = {d}\ndrive = [\"Ia\", \"Fo\"]\n"
    )
}

/// One prismatic joint along gravity, its offset a symbol: the offset
/// `Fo1` acts like gravity on `M1` (and on `Ia1`, which acts like `M1` on
/// the acceleration), with the constant 1/9.81 = 100/981, kept exact, as
/// the numeric twin does.
#[test]
fn prismatic_joint_along_gravity_with_a_symbolic_offset() {
    let (symbolic, bs) = derive(&slider(true));
    let bs = bs.unwrap();
    let (numeric, bn) = derive(&slider(false));
    let bn = bn.unwrap();
    assert_eq!(names(&bs), ["MR1", "IaR1"]);
    assert_eq!(names(&bn), names(&bs));
    for (base, sign) in [("MR1", 1_i128), ("IaR1", -1)] {
        let c = coefficient(&bs, base, "Fo1");
        assert_eq!(symbolic.arena.as_num(c), Num::ratio(sign * 100, 981));
        // The issue's five digits.
        assert!((symbolic.arena.as_num(c).unwrap().to_f64() - sign as f64 * 0.10194).abs() < 5e-6);
        let own = coefficient(&bs, base, &base.replace('R', ""));
        assert!(symbolic.arena.is_one(own));
    }
    let text = |d: &Derivation, b: &BaseParameters| {
        b.base
            .iter()
            .map(|p| d.arena.display(p.expression))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        text(&symbolic, &bs),
        ["M1 + 100/981*Fo1", "Ia1 - 100/981*Fo1"]
    );
    assert_eq!(text(&numeric, &bn), text(&symbolic, &bs));
}

/// A revolute joint, then a prismatic joint with twist `alpha` and a
/// symbolic offset: of link 2's first moment only its part along the
/// horizontal axis of frame 1, `cos(alpha) MY2 - sin(alpha) MZ2`, has an
/// effect, so `MYR2 = MY2 - tan(alpha) MZ2`: an irrational constant for
/// pi/6 and pi/3, a number close to 0 for a calibrated 0.001 rad.
#[test]
fn prismatic_joint_with_a_twist_and_a_symbolic_offset() {
    for (alpha, tangent) in [
        ("\"pi/6\"", (std::f64::consts::PI / 6.0).tan()),
        ("\"pi/3\"", (std::f64::consts::PI / 3.0).tan()),
        ("0.001", 0.001_f64.tan()),
    ] {
        let text = |symbolic: bool| {
            let (symbols, d) = if symbolic {
                ("[symbols]\nL2 = 0.3\n", "\"L2\"")
            } else {
                ("", "0.3")
            };
            format!(
                "name = \"twist\"\nconvention = \"modified\"\n{symbols}[[joints]]\n[[joints]]\ntype = \"prismatic\"\nalpha = {alpha}\nd = {d}\n"
            )
        };
        let (d, b) = derive(&text(true));
        let b = b.unwrap_or_else(|e| panic!("alpha {alpha}: {e}"));
        assert_eq!(names(&b), ["ZZR1", "MX2", "MYR2", "M2"], "alpha {alpha}");
        let c = d
            .arena
            .as_num(coefficient(&b, "MYR2", "MZ2"))
            .unwrap_or_else(|| panic!("alpha {alpha}: a number"))
            .to_f64();
        // Measured: at most 3.8e-16 relative (2.2e-16 between the twins).
        assert!(
            (c + tangent).abs() <= 8e-16 * tangent,
            "alpha {alpha}: {c} vs {}",
            -tangent
        );
        let (dn, bn) = derive(&text(false));
        let bn = bn.unwrap();
        assert_eq!(names(&bn), names(&b));
        let cn = dn
            .arena
            .as_num(coefficient(&bn, "MYR2", "MZ2"))
            .unwrap()
            .to_f64();
        assert!(
            (c - cn).abs() <= 5e-16 * tangent,
            "alpha {alpha}: {c} vs {cn}"
        );
    }
    // The issue's numbers: MYR2 = MY2 - 0.57735 MZ2 for pi/6.
    assert!(((std::f64::consts::PI / 6.0).tan() - 0.57735).abs() < 5e-6);
}

/// Largest |Y_b K p - Y p| over random states and parameters with the
/// symbols at `values`, relative to the largest |Y p|.
fn identity_error(robot: &Robot, values: &[(&str, f64)], seed: u64) -> f64 {
    let mut d = Derivation::new(robot);
    let b = d.base_parameters().unwrap();
    let mut rng = Rng::from_state(seed);
    let p: Vec<f64> = b.standard.iter().map(|_| rng.uniform(-1.0, 1.0)).collect();
    let (base, full) = torques(&mut d, &b, &p, values, seed, 8);
    let scale = full.iter().fold(0.0_f64, |m, t| m.max(t.abs()));
    base.iter()
        .zip(&full)
        .fold(0.0_f64, |m, (b, f)| m.max((b - f).abs()))
        / scale
}

/// A dependency whose coefficient varies with a length: the base parameter
/// carries it as an expression, `sqrt(2) L`, exact for every value of `L`
/// (negative, zero, far outside the interval where it was sampled).
#[test]
fn a_coefficient_that_varies_with_a_length_holds_for_every_length() {
    let text = r#"
name = "offset_slider"
convention = "modified"
[symbols]
L = 0.553
[[joints]]
[[joints]]
type = "prismatic"
theta = "-pi/4"
a = "L"
"#;
    let (mut d, b) = derive(text);
    let b = b.unwrap();
    assert_eq!(names(&b), ["ZZR1", "M2"]);
    for moment in ["MX2", "MY2"] {
        let c = coefficient(&b, "ZZR1", moment);
        for l in [-3.0, 0.0, 0.553, 7.0] {
            let v = d.arena.values(&[("L", l)]);
            let got = d.arena.eval(&[c], &v).unwrap()[0];
            // Measured: at most 1.4e-15.
            assert!(
                (got - std::f64::consts::SQRT_2 * l).abs() <= 3e-15 * (1.0 + l.abs()),
                "{moment} at L = {l}: {got}"
            );
        }
    }
    let robot = Robot::from_toml(text, "inline.toml").unwrap();
    // The bound of issue 12 (measured: at most 3.2e-15).
    for l in [-3.0, 0.0, 0.553, 7.0] {
        let e = identity_error(&robot, &[("L", l)], 5);
        assert!(e <= 1e-12, "L = {l}: {e}");
    }
}

/// A length that is a high power of a symbol (`a = L^16`, 1.5e-5 m at L = 0.5) is below
/// rounding wherever L is drawn small, so one sample of the geometry can see no effect of
/// MX2 that other values of L have: regrouping must refuse it, not return a base model that
/// is wrong by 31 % at L = 1 (as it did). A fourth power regroups and holds at every L.
#[test]
fn a_length_below_rounding_at_the_sample_is_refused() {
    let text = |power: usize| {
        let a = vec!["L"; power].join("*");
        format!(
            "name = \"p\"\nconvention = \"modified\"\n[symbols]\nL = 0.5\n[[joints]]\n\
             [[joints]]\ntype = \"prismatic\"\ntheta = \"-pi/4\"\na = \"{a}\"\n\
             [[joints]]\nalpha = \"pi/2\"\na = \"L\"\nd = 0.1\n"
        )
    };
    for power in [16, 19] {
        let e = derive(&text(power)).1.unwrap_err().to_string();
        assert!(
            e.contains("`MX2` has no effect at one value") && e.contains("below rounding"),
            "L^{power}: {e}"
        );
    }
    let (_, b) = derive(&text(4));
    assert_eq!(b.unwrap().base.len(), 9);
    let robot = Robot::from_toml(&text(4), "inline.toml").unwrap();
    for l in [0.5, 0.9, 1.0, 1.2] {
        // measured at most 1.2e-14
        let e = identity_error(&robot, &[("L", l)], 5);
        assert!(e <= 1e-12, "L = {l}: {e}");
    }
}

/// A twist written as a symbol: the reference arms with one twist replaced
/// by a symbol regroup (generic twist, so as the numeric robot with a
/// generic twist), and the base model holds at every angle, also at the
/// multiples of pi/2 where the numeric robot would need fewer parameters.
#[test]
fn a_twist_written_as_a_symbol_holds_at_every_angle() {
    for (name, joint) in [("ur5e", 1), ("stanford", 2), ("puma560", 3)] {
        let reference = crate::common::reference(name).with_drive(Drive::ALL);
        let with = |alpha: &str| {
            let mut joints = reference.joints().to_vec();
            joints[joint].alpha = Geometry::text(alpha).unwrap();
            Robot::new(
                name,
                reference.convention(),
                Some(reference.gravity().clone()),
                joints,
            )
            .unwrap()
            .with_drive(Drive::ALL)
        };
        let symbolic = with("al");
        let count = |r: &Robot| Derivation::new(r).base_parameters().unwrap().base.len();
        assert_eq!(count(&symbolic), count(&with("0.4")), "{name}");
        // The bound of issue 12 (measured: at most 6.6e-16).
        let half_pi = std::f64::consts::FRAC_PI_2;
        for angle in [-3.0, -half_pi, 0.0, 0.4, half_pi, 2.5] {
            let e = identity_error(&symbolic, &[("al", angle)], 11);
            assert!(e <= 1e-12, "{name}, alpha = {angle}: {e}");
        }
    }
}

/// An offset angle and a length written as symbols: the coefficient is
/// `2 L cos(th)` (and `-2 L sin(th)`), a polynomial in `L` and the sine and
/// cosine of `th`, exact at every angle and length.
#[test]
fn an_offset_angle_written_as_a_symbol_holds_at_every_angle() {
    let text = r#"
name = "turned_slider"
convention = "modified"
[[joints]]
[[joints]]
type = "prismatic"
theta = "th"
a = "L"
"#;
    let (_, b) = derive(text);
    assert_eq!(names(&b.unwrap()), ["ZZR1", "M2"]);
    let robot = Robot::from_toml(text, "inline.toml").unwrap();
    // The bound of issue 12 (measured: at most 2.7e-16).
    for th in [-3.0, 0.0, std::f64::consts::FRAC_PI_2, 2.5] {
        for l in [-2.0, 0.0, 0.5] {
            let e = identity_error(&robot, &[("th", th), ("L", l)], 13);
            assert!(e <= 1e-12, "th = {th}, L = {l}: {e}");
        }
    }
}

/// `tan(alpha)` (the case above with the twist a symbol) and `1/g` (the
/// slider with gravity a symbol) have no value somewhere: refused, naming
/// the parameters and only the symbols the coefficient varies with.
#[test]
fn a_coefficient_that_is_a_ratio_is_refused_naming_its_symbols() {
    let twist = "name = \"twist\"\nconvention = \"modified\"\n[symbols]\nL2 = 0.3\nal = 0.5\n[[joints]]\n[[joints]]\ntype = \"prismatic\"\nalpha = \"al\"\nd = \"L2\"\n";
    let slider = "name = \"slider\"\nconvention = \"modified\"\ngravity = [0, 0, \"-g\"]\n[symbols]\nL1 = 0.3\n[[joints]]\ntype = \"prismatic\"\nd = \"L1\"\ndrive = [\"Ia\", \"Fo\"]\n";
    for (text, parameter, on, symbol) in [(twist, "MZ2", "MY2", "al"), (slider, "Fo1", "M1", "g")] {
        let (_, b) = derive(text);
        let e = b.unwrap_err();
        assert_eq!(
            e,
            RegroupError::NotExpressible {
                parameter: parameter.to_owned(),
                on: on.to_owned(),
                symbols: vec![symbol.to_owned()],
                degree: 4,
            }
        );
        let message = e.to_string();
        assert!(
            message.contains(&format!("give `{symbol}` numeric values"))
                && message.contains("not a polynomial"),
            "{message}"
        );
    }
}
