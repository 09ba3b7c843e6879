//! Acceptance (issue 5): the Staubli TX40 identified from its real log (FIGAROH example
//! data, `data/staubli_tx40`) with FIGAROH's processing (`robots/configs/tx40.toml`) and
//! the TX40 description with drive terms (`robots/configs/tx40_robot.toml`):
//!
//! - relative torque error <= 5.5 % (FIGAROH's data with pinocchio: 5.2 %);
//! - Fv and Fc of every joint within 3 % of FIGAROH's OLS values (or 0.03 N m);
//! - the base combinations quoted in the dataset README within 5 %, matched to ours by
//!   their expressions (FIGAROH's `reference/TX40_bp_5.csv` is parsed, not copied);
//! - every one of FIGAROH's 60 base expressions is one of ours (same regrouping);
//! - the temporal split of the README: train on rows 0-24750, predict rows 29250-45000.
//!
//! The torque offsets are poorly determined by this run (FIGAROH's own relative standard
//! deviations are 16-170 %); they are compared within three of our standard deviations.

use std::collections::BTreeMap;
use std::path::PathBuf;

use robid_runtime::data::{Config, Dataset, load_config_files};
use robid_runtime::estimate::Observation;
use robid_runtime::pipeline::{Identification, estimate, identify, observation};
use robid_runtime::validate::Prediction;
use robots::interpreted::{Chosen, model_for};

fn repo(p: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join(p)
}

/// A linear combination of standard parameters: name -> coefficient.
type Combination = BTreeMap<String, f64>;

/// Parses `a + 0.5*b - c` (our form and FIGAROH's, names mapped by `rename`).
fn parse(text: &str, rename: impl Fn(&str) -> String) -> Combination {
    let mut out = Combination::new();
    for term in text.replace(" - ", " + -").split(" + ") {
        let term = term.trim();
        let (sign, term) = match term.strip_prefix('-') {
            Some(t) => (-1.0, t.trim()),
            None => (1.0, term),
        };
        let (coef, name) = match term.split_once('*') {
            Some((c, n)) => (c.trim().parse::<f64>().expect(c), n.trim()),
            None => (1.0, term),
        };
        *out.entry(rename(name)).or_insert(0.0) += sign * coef;
    }
    out
}

/// FIGAROH's parameter names in ours: Izz1 -> ZZ1, mx2 -> MX2, m3 -> M3, fs1 -> Fc1, off1 -> Fo1.
fn figaroh_name(name: &str) -> String {
    let digits = name.trim_start_matches(|c: char| !c.is_ascii_digit());
    let stem = &name[..name.len() - digits.len()];
    let ours = match stem {
        "Ixx" | "Iyy" | "Izz" | "Ixy" | "Ixz" | "Iyz" => stem[1..].to_uppercase(),
        "mx" | "my" | "mz" | "m" => stem.to_uppercase(),
        "fv" => "Fv".into(),
        "fs" => "Fc".into(),
        "off" => "Fo".into(),
        "Iam" | "fvm" | "fsm" => return name.to_string(),
        other => other.to_string(),
    };
    format!("{ours}{digits}")
}

fn same(a: &Combination, b: &Combination) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|((n, x), (m, y))| n == m && (x - y).abs() <= 1e-4 * x.abs().max(1.0))
}

/// FIGAROH's base parameters: (combination, OLS value).
fn figaroh() -> Vec<(String, Combination, f64)> {
    let text = std::fs::read_to_string(repo("data/staubli_tx40/reference/TX40_bp_5.csv")).unwrap();
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[0].to_string(),
                parse(f[0], figaroh_name),
                f[1].parse().unwrap(),
            )
        })
        .collect()
}

struct Tx40 {
    chosen: Chosen,
    config: Config,
    data: Dataset,
}

fn setup() -> Tx40 {
    let text = std::fs::read_to_string(repo("robots/configs/tx40_robot.toml")).unwrap();
    let robot = robid_symbolic::Robot::from_toml(&text, "tx40_robot.toml").unwrap();
    let chosen = model_for(&robot, &text).unwrap();
    let config = Config::from_file(repo("robots/configs/tx40.toml")).unwrap();
    let data = load_config_files(&config, 6).unwrap();
    Tx40 {
        chosen,
        config,
        data,
    }
}

/// Our combination of each estimated parameter (extra columns are their own name).
fn ours(chosen: &Chosen, id: &Identification) -> Vec<Combination> {
    id.estimate
        .names
        .iter()
        .map(|n| match chosen.expression(n) {
            Some(e) => parse(&e, str::to_string),
            None => Combination::from([(n.clone(), 1.0)]),
        })
        .collect()
}

#[test]
fn tx40_reproduces_figaroh() {
    let t = setup();
    let id = identify(t.chosen.model.as_ref(), &t.data, &t.config).unwrap();
    let e = &id.estimate;
    println!(
        "TX40: {} equations, {} parameters, cond {:.0}, relative error {:.2} %, RMS {:?}",
        e.rows,
        e.names.len(),
        e.condition_number,
        100.0 * id.fit.relative_error,
        id.fit.rms_per_joint
    );
    assert!(id.fit.relative_error <= 0.055, "{}", id.fit.relative_error);

    let combos = ours(&t.chosen, &id);
    let reference = figaroh();
    assert_eq!(reference.len(), 60);
    // (index of ours, FIGAROH value, FIGAROH text) for every FIGAROH parameter
    let matched: Vec<(usize, f64, &str)> = reference
        .iter()
        .map(|(text, c, v)| {
            let i = combos
                .iter()
                .position(|o| same(o, c))
                .unwrap_or_else(|| panic!("FIGAROH's `{text}` is none of our base parameters"));
            (i, *v, text.as_str())
        })
        .collect();
    let check = |what: &str, pred: &dyn Fn(&str) -> bool, tol: &dyn Fn(f64, usize) -> f64| {
        for &(i, v, text) in matched.iter().filter(|m| pred(m.2)) {
            let (x, tol) = (e.values[i], tol(v, i));
            println!(
                "{what:9} {:6} {x:>10.5}  FIGAROH {v:>10.5}  ({text})",
                e.names[i]
            );
            assert!(
                (x - v).abs() <= tol,
                "{} = {x}, FIGAROH {v}, tolerance {tol}",
                e.names[i]
            );
        }
    };
    let stem = |s: &'static str| move |t: &str| t.starts_with(s) && t.len() <= s.len() + 1;
    check("friction", &stem("fv"), &|v, _| (0.03 * v.abs()).max(0.03));
    check("friction", &stem("fs"), &|v, _| (0.03 * v.abs()).max(0.03));
    let quoted = |t: &str| {
        t.starts_with("Izz1 + ")
            || t.starts_with("Izz2 + ")
            || t.starts_with("mx2 + ")
            || t.starts_with("my3 - ")
            || ["Ia3", "Ia4", "Ia5", "fvm6", "fsm6"].contains(&t)
    };
    check("base", &quoted, &|v, _| 0.05 * v.abs());
    check("offset", &stem("off"), &|_, i| 3.0 * e.std[i]);
}

/// The observation of rows `a..b` of the log, cut before processing: `prepare` pads the
/// low-pass with one settling time of odd extension and trims as much at the cut ends,
/// so that a cut made during motion leaves no filter transient in the equations.
fn rows(t: &Tx40, a: usize, b: usize) -> Observation {
    let data = t.data.slice(a, b).unwrap();
    observation(t.chosen.model.as_ref(), &data, &t.config)
        .unwrap()
        .0
}

#[test]
fn tx40_temporal_split_predicts_held_out_rows() {
    let t = setup();
    let train = rows(&t, 0, 24750);
    let held_out = rows(&t, 29250, 45000);
    let e = estimate(&train, &t.config).unwrap();
    let dt = 100.0 / 5000.0;
    let fit = Prediction::new(&train, &e.values, dt).fit();
    let v = Prediction::new(&held_out, &e.values, dt).fit();
    println!(
        "TX40 split: train {:.2} %, held out {:.2} % (RMS {:?})",
        100.0 * fit.relative_error,
        100.0 * v.relative_error,
        v.rms_per_joint
    );
    assert!(fit.relative_error <= 0.055, "{}", fit.relative_error);
    // the held-out part is predicted nearly as well as the whole run is fitted
    assert!(v.relative_error <= 0.08, "{}", v.relative_error);
}
