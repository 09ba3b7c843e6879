//! Helpers shared by the integration tests of robid-symbolic.
#![allow(dead_code, unreachable_pub)]

use robid_core::rng::Rng;
use robid_symbolic::{Arena, Robot, Values};

/// A reference robot description from robots/descriptions.
pub fn reference(name: &str) -> Robot {
    let text = match name {
        "ur5e" => include_str!("../../../robots/descriptions/ur5e.toml"),
        "puma560" => include_str!("../../../robots/descriptions/puma560.toml"),
        "rx90" => include_str!("../../../robots/descriptions/rx90.toml"),
        "tx40" => include_str!("../../../robots/descriptions/tx40.toml"),
        "lwr4" => include_str!("../../../robots/descriptions/lwr4.toml"),
        "panda" => include_str!("../../../robots/descriptions/panda.toml"),
        "stanford" => include_str!("../../../robots/descriptions/stanford.toml"),
        other => panic!("no reference robot {other}"),
    };
    Robot::from_toml(text, name).unwrap()
}

/// Random joint states (and random values for any extra symbols given).
pub fn random_state(arena: &mut Arena, dof: usize, extra: &[(&str, f64)], rng: &mut Rng) -> Values {
    let mut names = Vec::new();
    for j in 1..=dof {
        for p in ["q", "qd", "qdd"] {
            names.push((format!("{p}{j}"), rng.uniform(-2.0, 2.0)));
        }
    }
    let mut pairs: Vec<(&str, f64)> = names.iter().map(|(n, v)| (n.as_str(), *v)).collect();
    pairs.extend_from_slice(extra);
    arena.values(&pairs)
}

/// The configuration of the property tests: `cases` cases from a fixed seed, so that
/// every run (and CI) tests the same cases and a failure reproduces; no regression
/// files. To explore other cases, change the seed here and run the tests.
pub fn proptest_config(cases: u32) -> proptest::test_runner::Config {
    proptest::test_runner::Config {
        cases,
        rng_seed: proptest::test_runner::RngSeed::Fixed(20_261_123),
        failure_persistence: None,
        ..proptest::test_runner::Config::default()
    }
}
