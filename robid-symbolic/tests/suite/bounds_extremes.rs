//! The documented ranges (`robot::bounds`) are safe for the regrouping: the
//! reference robots with their values at the ends of each accepted range have
//! as many base parameters as their nominal twins (the same zeros, signs and
//! directions, nominal magnitudes), with and without drive terms. Values just
//! outside a range are refused (see `description_errors.rs`); before the
//! ranges, `d = 1e200` gave no base parameter at all.

use robid_core::rng::Rng;
use robid_symbolic::robot::bounds::{
    ANGLE_RESOLUTION, MAX_GRAVITY, MAX_LENGTH, MIN_GRAVITY, MIN_LENGTH,
};
use robid_symbolic::{Derivation, Drive, Robot};

const ROBOTS: [(&str, &str); 7] = [
    (
        "ur5e",
        include_str!("../../../robots/descriptions/ur5e.toml"),
    ),
    (
        "puma560",
        include_str!("../../../robots/descriptions/puma560.toml"),
    ),
    (
        "rx90",
        include_str!("../../../robots/descriptions/rx90.toml"),
    ),
    (
        "tx40",
        include_str!("../../../robots/descriptions/tx40.toml"),
    ),
    (
        "lwr4",
        include_str!("../../../robots/descriptions/lwr4.toml"),
    ),
    (
        "panda",
        include_str!("../../../robots/descriptions/panda.toml"),
    ),
    (
        "stanford",
        include_str!("../../../robots/descriptions/stanford.toml"),
    ),
];

/// Base-parameter counts without and with every drive term.
fn counts(text: &str, what: &str) -> [usize; 2] {
    let robot = Robot::from_toml(text, what).unwrap_or_else(|e| panic!("{what}: {e}"));
    [Drive::NONE, Drive::ALL].map(|drive| {
        let r = robot.clone().with_drive(drive);
        let b = Derivation::new(&r)
            .base_parameters()
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        b.base.len()
    })
}

/// `text` with each `key = value` line passed through `edit` (`None`: kept).
fn edit(text: &str, mut f: impl FnMut(&str, &str) -> Option<String>) -> String {
    let mut out = String::new();
    for line in text.lines() {
        let replaced = line
            .split_once(" = ")
            .and_then(|(k, v)| Some(format!("{k} = {}", f(k.trim(), v.trim())?)));
        out += &replaced.unwrap_or_else(|| line.to_owned());
        out.push('\n');
    }
    out
}

/// The numeric DH lengths, each through `f(index, value)` (zeros kept).
fn lengths(text: &str, f: impl Fn(usize, f64) -> f64) -> String {
    let mut k = 0;
    edit(text, |key, v| {
        let x: f64 = v.parse().ok()?;
        if !(key == "a" || key == "d") || x == 0.0 {
            return None;
        }
        k += 1;
        Some(format!("{:e}", f(k, x)))
    })
}

fn gravity(text: &str, g: [f64; 3]) -> String {
    let text = edit(text, |key, _| {
        (key == "gravity").then(|| format!("[{:e}, {:e}, {:e}]", g[0], g[1], g[2]))
    });
    assert!(
        text.contains("\ngravity = ["),
        "every reference robot states gravity"
    );
    text
}

/// (The RX-90's lengths are symbols, which the regrouping samples whatever
/// their values: it has no numeric length to move.)
#[test]
fn lengths_at_both_ends_keep_the_base_parameters() {
    let mut tested = 0;
    for (name, text) in ROBOTS {
        if lengths(text, |_, x| x) == lengths(text, |_, x| 2.0 * x) {
            continue;
        }
        tested += 1;
        let nominal = counts(text, name);
        for (case, scaled) in [
            ("shortest", lengths(text, |_, x| x.signum() * MIN_LENGTH)),
            ("longest", lengths(text, |_, x| x.signum() * MAX_LENGTH)),
            (
                "both",
                lengths(text, |k, x| {
                    x.signum() * if k % 2 == 0 { MIN_LENGTH } else { MAX_LENGTH }
                }),
            ),
        ] {
            assert_eq!(counts(&scaled, name), nominal, "{name}, {case} lengths");
        }
    }
    assert_eq!(tested, 6);
}

#[test]
fn gravity_at_both_ends_keeps_the_base_parameters() {
    for (name, text) in ROBOTS {
        let upright = counts(&gravity(text, [0.0, 0.0, -9.81]), name);
        for g in [MIN_GRAVITY, MAX_GRAVITY] {
            assert_eq!(
                counts(&gravity(text, [0.0, 0.0, -g]), name),
                upright,
                "{name}, gravity {g}"
            );
        }
        // A tilted base: two components, each at either end.
        let tilted = counts(&gravity(text, [3.0, 0.0, -9.81]), name);
        for (x, z) in [
            (MIN_GRAVITY, MIN_GRAVITY),
            (MIN_GRAVITY, MAX_GRAVITY),
            (MAX_GRAVITY, MIN_GRAVITY),
            (MAX_GRAVITY, MAX_GRAVITY),
        ] {
            assert_eq!(
                counts(&gravity(text, [x, 0.0, -z]), name),
                tilted,
                "{name}, gravity [{x}, 0, -{z}]"
            );
        }
    }
}

/// An angle just far enough from a quarter turn to be accepted is treated as
/// a generic angle, like one far from it.
#[test]
fn angles_near_quarter_turns_count_as_generic() {
    for (name, text) in ROBOTS {
        for (exact, value) in [("\"pi/2\"", std::f64::consts::FRAC_PI_2), ("0", 0.0)] {
            let with = |offset: f64| {
                let mut done = false;
                edit(text, |key, v| {
                    (key == "alpha" && v == exact && !std::mem::replace(&mut done, true))
                        .then(|| format!("{:.17e}", value + offset))
                })
            };
            let near = with(1.001 * ANGLE_RESOLUTION);
            if near == text {
                continue;
            }
            assert_eq!(
                counts(&near, name),
                counts(&with(0.3), name),
                "{name}: alpha {exact} + 1.001e-5 against {exact} + 0.3"
            );
        }
    }
}

/// A revolute joint's `theta` is an offset of its variable, taken as written at any
/// value: the TX40 with each `theta` moved off its quarter turn by a calibration's few
/// microradians (or `1.5707963` typed for pi/2) has the nominal base parameters, and its
/// base regressor at `q` is the nominal one at `q + offset`.
#[test]
fn revolute_theta_offsets_keep_the_base_parameters() {
    let text = ROBOTS[3].1;
    let offsets = [1.4e-7, -2.7e-8, 3e-6, -9.9e-6, 5e-7, 2e-8];
    let mut k = 0;
    let shifted_text = edit(text, |key, v| {
        (key == "theta").then(|| {
            let exact: f64 = match v.trim_matches('"') {
                "0" => 0.0,
                "pi/2" => std::f64::consts::FRAC_PI_2,
                "-pi/2" => -std::f64::consts::FRAC_PI_2,
                "pi" => std::f64::consts::PI,
                other => panic!("TX40 theta {other}"),
            };
            k += 1;
            format!("{:.17e}", exact + offsets[k - 1])
        })
    });
    assert_eq!(k, 6, "every TX40 joint has its theta line");
    let nominal = Robot::from_toml(text, "tx40").unwrap();
    let shifted = Robot::from_toml(&shifted_text, "tx40 shifted").unwrap_or_else(|e| panic!("{e}"));
    let (mut dn, mut ds) = (Derivation::new(&nominal), Derivation::new(&shifted));
    let (bn, bs) = (dn.base_parameters().unwrap(), ds.base_parameters().unwrap());
    let names = |b: &robid_symbolic::regroup::BaseParameters| {
        b.base
            .iter()
            .map(|p| p.name.to_string())
            .collect::<Vec<_>>()
    };
    assert_eq!(names(&bs), names(&bn));
    let mut rng = Rng::new(11);
    for _ in 0..5 {
        let state: Vec<[f64; 3]> = (0..6)
            .map(|_| [0; 3].map(|_| rng.uniform(-2.0, 2.0)))
            .collect();
        let pairs = |shift: bool| -> Vec<(String, f64)> {
            let mut out = Vec::new();
            for (j, [q, qd, qdd]) in state.iter().enumerate() {
                let q = if shift { q + offsets[j] } else { *q };
                out.push((format!("q{}", j + 1), q));
                out.push((format!("qd{}", j + 1), *qd));
                out.push((format!("qdd{}", j + 1), *qdd));
            }
            out
        };
        let eval = |d: &mut Derivation, b: &robid_symbolic::regroup::BaseParameters, shift| {
            let owned = pairs(shift);
            let refs: Vec<(&str, f64)> = owned.iter().map(|(n, v)| (n.as_str(), *v)).collect();
            let values = d.arena.values(&refs);
            d.arena.eval(&b.columns.concat(), &values).unwrap()
        };
        let (yn, ys) = (eval(&mut dn, &bn, true), eval(&mut ds, &bs, false));
        let scale = yn.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        for (a, b) in yn.iter().zip(&ys) {
            assert!((a - b).abs() <= 1e-12 * scale, "{a} vs {b}");
        }
    }
}

/// A twist a calibration measured a few microradians off a right angle is refused as a
/// typo in a typed table, with the way out in the help, and taken as written (measured)
/// in one marked `calibrated = true`: one warning at its line, and the base parameters of
/// a generic angle, as an angle far from the right angle gives.
#[test]
fn calibrated_descriptions_take_measured_twists() {
    let text = ROBOTS[0].1;
    let twist = |value: f64| {
        let mut done = false;
        edit(text, |key, v| {
            (key == "alpha" && v == "\"pi/2\"" && !std::mem::replace(&mut done, true))
                .then(|| format!("{value:?}"))
        })
    };
    let measured = std::f64::consts::FRAC_PI_2 + 3.2e-6;
    // and a measured offset of joint 3 near pi/2, which a typed table is told about
    let offset = format!(
        "a = -0.425\ntheta = {:?}\n",
        std::f64::consts::FRAC_PI_2 - 4e-6
    );
    let typed = twist(measured).replacen("a = -0.425\n", &offset, 1);
    assert!(typed.contains("theta = 1.57079"));
    let error = Robot::from_toml(&typed, "ur5e.toml")
        .unwrap_err()
        .to_string();
    assert!(error.contains("ur5e.toml:14:"), "{error}");
    assert!(error.contains("`calibrated = true`"), "{error}");
    let calibrated = format!("calibrated = true\n{typed}");
    let (robot, warnings) =
        Robot::from_toml_with_warnings(&calibrated, "ur5e.toml").unwrap_or_else(|e| panic!("{e}"));
    let told: Vec<&String> = warnings.iter().filter(|w| w.contains("measured")).collect();
    assert_eq!(told.len(), 1, "{warnings:?}");
    assert_eq!(
        warnings.len(),
        1,
        "no offset warning in a calibrated table: {warnings:?}"
    );
    let (_, typed_warnings) = Robot::from_toml_with_warnings(
        &typed.replacen(&format!("{measured:?}"), "\"pi/2\"", 1),
        "t",
    )
    .unwrap();
    assert!(
        typed_warnings.iter().any(|w| w.contains("joint 3 `theta`")),
        "{typed_warnings:?}"
    );
    assert!(
        told[0].starts_with("ur5e.toml:15:")
            && told[0].contains("joint 2 `alpha` is 3.2e-6 rad from pi/2"),
        "{}",
        told[0]
    );
    assert_eq!(robot.joints()[1].alpha.as_str(), format!("{measured:?}"));
    let generic = format!(
        "calibrated = true\n{}",
        twist(std::f64::consts::FRAC_PI_2 + 0.3)
    );
    assert_eq!(
        counts(&calibrated, "calibrated"),
        counts(&generic, "generic")
    );
    assert_ne!(counts(&calibrated, "calibrated"), counts(text, "nominal"));
    // An exact right angle stays exact in a calibrated table, and nothing is told.
    let (_, warnings) =
        Robot::from_toml_with_warnings(&format!("calibrated = true\n{text}"), "ur5e.toml").unwrap();
    assert!(
        warnings.iter().all(|w| !w.contains("measured")),
        "{warnings:?}"
    );
    let wrong = Robot::from_toml(&format!("calibrated = \"yes\"\n{text}"), "ur5e.toml")
        .unwrap_err()
        .to_string();
    assert!(
        wrong.contains("ur5e.toml:1:") && wrong.contains("`true` or `false`"),
        "{wrong}"
    );
}
