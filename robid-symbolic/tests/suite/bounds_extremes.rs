//! The documented ranges (`robot::bounds`) are safe for the regrouping: the
//! reference robots with their values at the ends of each accepted range have
//! as many base parameters as their nominal twins (the same zeros, signs and
//! directions, nominal magnitudes), with and without drive terms. Values just
//! outside a range are refused (see `description_errors.rs`); before the
//! ranges, `d = 1e200` gave no base parameter at all.

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
