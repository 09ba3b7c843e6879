//! Pipeline tests on the synthetic model with known parameters.

use crate::DataError;
use crate::EstimateError;
use std::path::Path;

use crate::Model;
use crate::data::{Config, Dataset, load};
use crate::drive::ExtraColumn;
use crate::error::Error;
// used by the synthetic model (a child module, also built by benches/pipeline.rs at the workspace root)
#[allow(unused_imports)]
use crate::Real;
#[allow(unused_imports)]
use crate::model::{LengthError, ProgramKind, check_arguments, check_length};
use crate::pipeline::{identify, validate};
use crate::signal::{Signals, central_difference};

mod milella;
mod runs;
mod stream;
#[path = "synthetic.rs"]
pub(crate) mod synthetic;
use synthetic::{CONFIG, DOF, Synthetic, csv_with_noise, trajectory, true_parameters};

fn config(extra: &str) -> Config {
    Config::from_toml_str(&format!("{CONFIG}{extra}"), Path::new("synthetic.toml")).unwrap()
}

fn dataset(n: usize, rate: f64, noise: f64) -> Dataset {
    dataset_with_noise(n, rate, [noise; DOF])
}

fn dataset_with_noise(n: usize, rate: f64, noise: [f64; DOF]) -> Dataset {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("run.csv");
    std::fs::write(&file, csv_with_noise(n, rate, noise)).unwrap();
    load(&config(""), &[file], DOF).unwrap()
}

#[test]
fn csv_to_parameters_recovers_the_truth() {
    let data = dataset(20_000, 1000.0, 0.0);
    let id = identify(&Synthetic::default(), &data, &config("")).unwrap();
    let truth = true_parameters();
    // noise-free: what is left is the filtering and differentiation (measured 1.03e-5 relative
    // at worst, relative error of the fit 1.04e-6)
    for (i, (v, t)) in id.estimate.values.iter().zip(&truth).enumerate() {
        assert!(
            (v - t).abs() < 2e-5 * t.abs().max(1.0),
            "{}: {v} vs {t}",
            id.estimate.names[i]
        );
    }
    assert!(id.fit.relative_error < 2e-6, "{:?}", id.fit);
    // measured 46.0
    let cond = id.estimate.condition_number;
    assert!((23.0..92.0).contains(&cond), "{cond}");
}

#[test]
fn wls_is_no_worse_than_ols_with_unequal_noise() {
    // joints 4 to 6 twenty times noisier than joints 1 to 3
    let data = dataset_with_noise(20_000, 1000.0, [0.1, 0.1, 0.1, 2.0, 2.0, 2.0]);
    let ols = identify(&Synthetic::default(), &data, &config("")).unwrap();
    let mut cfg = config("");
    cfg.estimation.method = crate::data::Method::Wls;
    let wls = identify(&Synthetic::default(), &data, &cfg).unwrap();
    let truth = true_parameters();
    let within = |e: &crate::estimate::Estimate| {
        e.values
            .iter()
            .zip(&e.std)
            .zip(&truth)
            .filter(|((v, s), t)| (*v - *t).abs() <= 3.0 * *s + 1e-9)
            .count()
    };
    // measured 47 of the 48 within 3 sigma (seeded)
    assert!(
        within(&wls.estimate) as f64 >= 0.9 * truth.len() as f64,
        "{}",
        within(&wls.estimate)
    );
    // in the distance to the truth (not the torque residual, which OLS minimises by
    // construction), WLS does better: it trusts the quiet joints more (measured: relative
    // parameter error 1.75e-3 against 1.99e-3)
    let error = |e: &crate::estimate::Estimate| {
        let d: f64 = e
            .values
            .iter()
            .zip(&truth)
            .map(|(v, t)| (v - t).powi(2))
            .sum();
        let t: f64 = truth.iter().map(|t| t * t).sum();
        (d / t).sqrt()
    };
    let (e_wls, e_ols) = (error(&wls.estimate), error(&ols.estimate));
    eprintln!("relative parameter error: WLS {e_wls:.3e}, OLS {e_ols:.3e}");
    assert!(e_wls < e_ols, "WLS {e_wls} vs OLS {e_ols}");
}

#[test]
fn validation_on_other_data_predicts_well() {
    let data = dataset(12_000, 1000.0, 0.0);
    let train = data.slice(0, 8000).unwrap();
    let test = data.slice(8000, 12_000).unwrap();
    let model = Synthetic::default();
    let id = identify(&model, &train, &config("")).unwrap();
    let pred = validate(&model, &test, &config(""), &id.estimate.values).unwrap();
    // measured 1.12e-6 (noise-free data)
    assert!(pred.fit().relative_error < 2.5e-6, "{:?}", pred.fit());
    assert!(matches!(
        validate(&model, &test, &config(""), &[1.0]),
        Err(Error::DimensionMismatch { .. })
    ));
}

/// `n` samples at 1 kHz of the exciting trajectory with joint `still` (0-based) held at
/// 0.3 rad, noise-free torques.
fn with_joint_at_rest(n: usize, still: usize) -> Dataset {
    let (mut q, mut qd, mut qdd) = ([0.0; DOF], [0.0; DOF], [0.0; DOF]);
    let mut qs = Signals::zeros(DOF, n);
    let mut taus = Signals::zeros(DOF, n);
    let model = Synthetic::default();
    let beta = true_parameters();
    for k in 0..n {
        trajectory(k as f64 * 1e-3, &mut q, &mut qd, &mut qdd);
        q[still] = 0.3;
        qd[still] = 0.0;
        qdd[still] = 0.0;
        let mut tau = [0.0; DOF];
        model
            .inverse_dynamics_into(&q, &qd, &qdd, &beta, &mut tau)
            .unwrap();
        for j in 0..DOF {
            qs[j][k] = q[j];
            taus[j][k] = tau[j];
        }
    }
    Dataset::new(format!("still{}", still + 1), 1e-3, qs, taus).unwrap()
}

/// A config without `processing.rest_velocity` drops the equations near rest at
/// [`DEFAULT_REST_VELOCITY`](crate::data::DEFAULT_REST_VELOCITY), as the example config
/// says; 0 keeps them all. They were all kept: a positions-only log of pybullet's cart-pole
/// (Coulomb friction 5 N on the cart, a trajectory that comes to rest twice) had the cart's
/// torque fitted to 3 times its noise and Fc 6 standard deviations off.
#[test]
fn rest_velocity_defaults_to_the_documented_threshold() {
    let data = dataset(20_000, 1000.0, 0.0);
    let model = Synthetic::default();
    let without = CONFIG.replace("rest_velocity = 0.02\n", "");
    assert_ne!(without, CONFIG);
    let cfg = |text: &str| Config::from_toml_str(text, Path::new("synthetic.toml")).unwrap();
    let default = crate::data::DEFAULT_REST_VELOCITY;
    let absent = identify(&model, &data, &cfg(&without)).unwrap();
    let given = identify(
        &model,
        &data,
        &cfg(&format!("{without}rest_velocity = {default}\n")),
    );
    let zero = identify(
        &model,
        &data,
        &cfg(&format!("{without}rest_velocity = 0\n")),
    )
    .unwrap();
    let given = given.unwrap();
    assert_eq!(absent.estimate.rows, given.estimate.rows);
    assert_eq!(absent.estimate.values, given.estimate.values);
    assert!(
        absent.estimate.rows < zero.estimate.rows,
        "{} equations without the key, {} with 0",
        absent.estimate.rows,
        zero.estimate.rows
    );
}

/// A joint that never moves leaves its drive and link terms unexcited, and is named.
#[test]
fn a_joint_at_rest_gives_rank_deficiency_naming_its_parameters() {
    let model = Synthetic::default();
    let data = with_joint_at_rest(6000, 5);
    let mut cfg = config("");
    // every equation kept (the default threshold would remove all of joint 6's)
    cfg.processing.rest_velocity = Some(crate::data::PerJoint::All(0.0));
    match identify(&model, &data, &cfg) {
        Err(Error::Estimate(EstimateError::StillJoints {
            unexcited,
            rank,
            columns,
            joints,
        })) => {
            assert!(rank < columns);
            assert_eq!(joints, [6]);
            assert!(unexcited.iter().any(|n| n == "Ia6"), "{unexcited:?}");
            assert!(unexcited.iter().any(|n| n == "Fv6"), "{unexcited:?}");
        }
        other => panic!("expected rank deficiency, got {other:?}"),
    }
}

/// A data set of `n` samples at 1 kHz in which no joint moves.
fn at_rest(n: usize) -> Dataset {
    let q = Signals::from_fn(DOF, n, |j, _| 0.1 * j as f64);
    Dataset::new("still", 1e-3, q, Signals::from_fn(DOF, n, |_, _| 1.0)).unwrap()
}

/// A `processing.rest_velocity` above every joint's speed removes every equation: the
/// error names the key at its line, its value, the count and the fix, the same in the
/// streaming (OLS) and the dense (RLS) path, and for validation data at rest; it used to
/// be the least squares' "0 samples, at least 48 are needed" with no place.
#[test]
fn rest_removal_of_every_equation_names_rest_velocity() {
    let model = Synthetic::default();
    let data = dataset(3000, 1000.0, 0.0);
    let cfg = config("");
    let text = CONFIG.replace("rest_velocity = 0.02", "rest_velocity = 1000.0");
    let high = Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap();
    let line = text
        .lines()
        .position(|l| l.starts_with("rest_velocity"))
        .unwrap()
        + 1;
    let mut rls = high.clone();
    rls.estimation.method = crate::data::Method::Rls;
    let streamed = identify(&model, &data, &high).unwrap_err();
    let dense = identify(&model, &data, &rls).unwrap_err();
    let reference = crate::pipeline::identify::identify_dense_of(&model, &data, &high).unwrap_err();
    for e in [&streamed, &dense, &reference] {
        assert!(
            matches!(e, Error::Data(DataError::ConfigKey { key, line: Some(l), .. })
                if key == "processing.rest_velocity" && *l == line),
            "{e}"
        );
        let text = e.to_string();
        for part in [
            "1000 rad/s removes 1548 of the 1548 equations",
            "leaving 0, fewer than the 49 equations the 48 parameters need",
            "lower rest_velocity",
            "units.angle",
        ] {
            assert!(text.contains(part), "`{part}` in {text}");
        }
    }
    assert_eq!(streamed.to_string(), reference.to_string());
    // every joint prismatic: each threshold and the fastest speed in m/s; one of them
    // prismatic: each threshold in its joint's unit
    for (prismatic, value) in [
        (vec![true; DOF], "1000 m/s removes"),
        (
            vec![false, true],
            "[1000 rad/s, 1000 m/s, 1000 rad/s, 1000 rad/s, 1000 rad/s, 1000 rad/s] removes",
        ),
    ] {
        let mut high = high.clone();
        high.prismatic = prismatic.clone();
        let mut rls = rls.clone();
        rls.prismatic = prismatic.clone();
        for e in [
            identify(&model, &data, &high).unwrap_err(),
            identify(&model, &data, &rls).unwrap_err(),
        ] {
            let text = e.to_string();
            assert!(text.contains(value), "`{value}` in {text}");
            if prismatic.iter().all(|&p| p) {
                assert!(!text.contains("rad/s"), "{text}");
            }
        }
    }
    // validation data in which no joint moves
    let values = identify(&model, &data, &cfg).unwrap().estimate.values;
    let e = validate(&model, &at_rest(3000), &cfg, &values).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("`processing.rest_velocity`: no joint moves in these data")
            && text.contains("0.02 rad/s removes all")
            && text.contains("leaving 0, fewer than")
            && text.contains("a prediction of still needs"),
        "{text}"
    );
}

/// A rank deficiency because `processing.rest_velocity` removed (nearly) all equations of
/// a joint that moves slower than its threshold (a slow prismatic joint under the default
/// 0.05, which is m/s for it) names the key at its line, the joint, its largest speed and
/// the fix, in the streaming (OLS) and the dense (RLS) path; it was the least squares'
/// "use a richer trajectory or remove these parameters". A joint that does not move at all
/// is no threshold's doing: its rank deficiency is told as before.
#[test]
fn a_rank_deficiency_from_rest_velocity_names_it() {
    let model = Synthetic::default();
    let data = dataset(3000, 1000.0, 0.0);
    // joint 2 moves at up to about 2 rad/s: a threshold of 100 for it removes its equations
    let text = CONFIG.replace(
        "rest_velocity = 0.02",
        "rest_velocity = [0.02, 100, 0.02, 0.02, 0.02, 0.02]",
    );
    let line = text
        .lines()
        .position(|l| l.starts_with("rest_velocity"))
        .unwrap()
        + 1;
    let high = Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap();
    let mut rls = high.clone();
    rls.estimation.method = crate::data::Method::Rls;
    // each speed in its joint's unit: rad/s, or m/s when joint 2 is prismatic
    for (prismatic, unit) in [(false, "rad/s"), (true, "m/s")] {
        let (mut high, mut rls) = (high.clone(), rls.clone());
        high.prismatic = vec![false, prismatic];
        rls.prismatic = high.prismatic.clone();
        let streamed = identify(&model, &data, &high).unwrap_err();
        let dense = identify(&model, &data, &rls).unwrap_err();
        for e in [&streamed, &dense] {
            assert!(
                matches!(e, Error::Data(DataError::ConfigKey { key, line: Some(l), .. })
                    if key == "processing.rest_velocity" && *l == line),
                "{e}"
            );
            let message = e.to_string();
            for part in [
                "rank-deficient data (rank ",
                "because rest_velocity removed all or nearly all of a joint's equations: \
                 joint 2 keeps 0 of its ",
                &format!(" {unit}; its threshold 100 {unit})"),
                "lower `rest_velocity` (default 0.05) in the config's [processing] for it, \
                 e.g. `rest_velocity = [0.02, 0.",
                "or 0 to keep every equation",
            ] {
                assert!(message.contains(part), "`{part}` in {message}");
            }
            assert!(!message.contains("remove these parameters"), "{message}");
            assert!(!message.contains("without --config"), "{message}");
            let other = if prismatic { "rad/s" } else { "m/s" };
            assert!(!message.contains(other), "{message}");
        }
    }
    // joint 3 at rest in the whole record: not the threshold's doing, the joint named
    let e = identify(&model, &with_joint_at_rest(3000, 2), &config("")).unwrap_err();
    assert!(
        matches!(&e, Error::Estimate(EstimateError::StillJoints { joints, .. }) if joints == &[3]),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains("joint 3 does not move in the equations used (velocity 0 at every sample"),
        "{e}"
    );
}

/// Per-axis and link-by-link identification, which solve joint by joint, with a joint
/// whose equations `processing.rest_velocity` all removes (the joint at rest in the whole
/// record) name the joint, the key at its line and the fixes, and so when it leaves the
/// joint fewer equations than the parameters it is solved for. Per axis it was "the
/// per-axis identification of joint 3: 0 samples, at least 1 are needed; use more data or
/// less decimation", which blamed the record's length; link by link "least squares with 8
/// parameters: 2 samples, at least 8 are needed; use more data, less decimation, or fewer
/// parameters" (or, for a joint at rest, a rank deficiency that did not say its equations
/// were removed).
#[test]
fn joint_by_joint_methods_name_a_joint_whose_equations_rest_velocity_removes() {
    let model = Synthetic::default();
    for (method, solves, own) in [
        (
            "per-axis",
            "per-axis identification solves each joint's equations on their own",
            "parameters of its own equation",
        ),
        (
            "link-by-link",
            "link-by-link identification estimates each link's parameters from its own \
             joint's equations",
            "parameters its step estimates",
        ),
    ] {
        let text = format!("{CONFIG}[estimation]\nmethod = \"{method}\"\n");
        let line = text
            .lines()
            .position(|l| l.starts_with("rest_velocity"))
            .unwrap()
            + 1;
        let with = |text: &str| Config::from_toml_str(text, Path::new("synthetic.toml")).unwrap();
        let at_the_key = |e: &Error| {
            matches!(e, Error::Data(DataError::ConfigKey { key, line: Some(l), .. })
                if key == "processing.rest_velocity" && *l == line)
        };
        // joint 3 at rest in the whole record
        let e = identify(&model, &with_joint_at_rest(3000, 2), &with(&text)).unwrap_err();
        assert!(at_the_key(&e), "{method}: {e}");
        let message = e.to_string();
        for part in [
            "0.02 rad/s removes every equation of joint 3: its |velocity| stays below it in \
             the whole record",
            solves,
            "move joint 3 in the trajectory",
            "lower rest_velocity for it (`rest_velocity = [0.02, 0.02, 0, 0.02, 0.02, 0.02]` \
             keeps all its equations)",
        ] {
            assert!(message.contains(part), "`{part}` in {message}");
        }
        assert!(!message.contains("more data"), "{message}");
        // joint 3 prismatic: its threshold in m/s
        let mut prismatic = with(&text);
        prismatic.prismatic = vec![false, false, true];
        let e = identify(&model, &with_joint_at_rest(3000, 2), &prismatic).unwrap_err();
        let message = e.to_string();
        assert!(
            message.contains("0.02 m/s removes every equation of joint 3")
                && message.contains("if it moves slower than 0.02 m/s, lower")
                && !message.contains("rad/s"),
            "{method}: {message}"
        );
        // joint 2 moving, but faster than 0.83 rad/s in a few samples only
        let data = dataset(3500, 1000.0, 0.0);
        let slow = text.replace(
            "rest_velocity = 0.02",
            "rest_velocity = [0.02, 0.83, 0.02, 0.02, 0.02, 0.02]",
        );
        let e = identify(&model, &data, &with(&slow)).unwrap_err();
        assert!(at_the_key(&e), "{method}: {e}");
        let message = e.to_string();
        assert!(
            message.contains("0.83 rad/s leaves joint 2 ")
                && message.contains("equations (where its |velocity| reaches it), fewer than the")
                && message.contains(own)
                && message.contains(solves)
                && message.contains("move joint 2 more in the trajectory")
                && message.contains("`rest_velocity = [0.02, 0, 0.02, 0.02, 0.02, 0.02]`"),
            "{message}"
        );
        // the same data identify when every joint keeps its equations
        identify(&model, &data, &with(&text)).unwrap();
    }
}

/// A decimation too large for the record is an error at `processing.decimation` with
/// the largest factor that fits, in the streaming (OLS) and the dense (RLS) path: when
/// its anti-alias filters need more samples (it was "zero-phase filter: 3 samples, at
/// least 28 are needed") and when it leaves fewer equations than parameters (it was the
/// least squares' "36 samples, at least 48").
#[test]
fn a_decimation_too_large_for_the_record_names_its_key() {
    let model = Synthetic::default();
    let data = dataset(3000, 1000.0, 0.0);
    for (factor, samples, expected, fits) in [
        (
            "5000",
            3000,
            "a total factor of 5000 needs at least 27001 samples for its anti-alias filters, \
             but 2600 of {name} are used (after processing.range and the trims); lower the \
             factor (at most 216 for this record, as `decimation = [9, 8, 3]`)",
            "[9, 8, 3]",
        ),
        (
            "100",
            1000,
            "a total factor of 100 keeps 6 of the 600 samples of {name} used (after \
             processing.range and the trims), 2 without the 2 at each end that its filter does \
             not settle (they carry an end sample's noise whole): 12 equations, fewer than the \
             49 equations the 48 parameters need; lower the factor (at most 49 for this \
             record, as `decimation = [7, 7]`)",
            "[7, 7]",
        ),
        // the factor asked for fits in other stages: [10, 10, 2] needs 2701 samples,
        // [2, 10, 10] fewer (it said "lower the factor")
        (
            "200",
            3000,
            "a total factor of 200 needs at least 2701 samples for its anti-alias filters, \
             but 2600 of {name} are used (after processing.range and the trims); give the same \
             factor in other stages, `decimation = [2, 10, 10]`, which fit (at most ",
            "[2, 10, 10]",
        ),
        // the stages matter: in stages of 10 first it said at most 90, where 98 in
        // [2, 7, 7] fits
        (
            "100",
            1588,
            "lower the factor (at most 98 for this record, as `decimation = [2, 7, 7]`)",
            "[2, 7, 7]",
        ),
    ] {
        let data = data.slice(0, samples).unwrap();
        let text = CONFIG.replace("decimation = 10", &format!("decimation = {factor}"));
        let line = text
            .lines()
            .position(|l| l.starts_with("decimation"))
            .unwrap()
            + 1;
        let mut config = Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap();
        for method in [crate::data::Method::Ols, crate::data::Method::Rls] {
            config.estimation.method = method;
            let e = identify(&model, &data, &config).unwrap_err();
            assert!(
                matches!(&e, Error::Data(DataError::ConfigKey { key, line: Some(l), .. })
                    if key == "processing.decimation" && *l == line),
                "{e}"
            );
            let expected = expected.replace("{name}", &data.name);
            assert!(e.to_string().contains(&expected), "{method:?}: {e}");
        }
        // and the stages said fit (a record this short may still not excite every
        // parameter: that is the data's, not the decimation's)
        let text = CONFIG.replace("decimation = 10", &format!("decimation = {fits}"));
        let config = Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap();
        if let Err(e) = identify(&model, &data, &config) {
            assert!(
                matches!(e, Error::Estimate(EstimateError::RankDeficient { .. })),
                "{fits}: {e}"
            );
        }
    }
}

/// A record too long for the methods that hold the observation matrix is refused before
/// it is read (it was read whole, then refused by the observation's size): a record of
/// 2^28 samples whose reading would fail the test.
#[test]
fn a_record_too_long_for_a_dense_method_is_refused_before_it_is_read() {
    struct Endless(Dataset);
    impl crate::data::Record for Endless {
        fn name(&self) -> &str {
            &self.0.name
        }
        fn sample_time(&self) -> f64 {
            self.0.sample_time
        }
        fn samples(&self) -> usize {
            1 << 28
        }
        fn dof(&self) -> usize {
            self.0.dof()
        }
        fn warnings(&self) -> &[crate::data::Warning] {
            &[]
        }
        fn file(&self) -> Option<&Path> {
            None
        }
        fn extremes(&self) -> &crate::data::Extremes {
            &self.0.extremes
        }
        fn line(&self, _: usize) -> Option<u64> {
            None
        }
        fn read(&self, _: usize, _: usize) -> crate::Result<std::borrow::Cow<'_, Dataset>> {
            panic!("read before the size check")
        }
    }
    let model = Synthetic::default();
    let mut config = Config::from_toml_str(CONFIG, Path::new("synthetic.toml")).unwrap();
    config.estimation.method = crate::data::Method::Rls;
    let e = identify(&model, &Endless(dataset(3000, 1000.0, 0.0)), &config)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("regressor values before decimation (268435056 samples x")
            && e.contains("by WLS or OLS"),
        "{e}"
    );
}

/// Data in which no joint moves are told as such, by the streamed and the dense paths: the
/// removal of samples at rest takes every equation, but no threshold is the cause (it
/// read "lower rest_velocity below the joints' speeds ... the fastest joint velocity is 0").
#[test]
fn data_in_which_nothing_moves_are_told_so() {
    let model = Synthetic::default();
    let mut data = dataset(3000, 1000.0, 0.0);
    data.q = Signals::from_fn(DOF, 3000, |j, _| 0.1 * j as f64);
    let cfg = Config::from_toml_str(CONFIG, Path::new("synthetic.toml")).unwrap();
    let mut rls = cfg.clone();
    rls.estimation.method = crate::data::Method::Rls;
    for config in [&cfg, &rls] {
        let e = identify(&model, &data, config).unwrap_err().to_string();
        assert!(
            e.contains(
                "`processing.rest_velocity`: no joint moves in these data (every joint \
                        velocity is 0 rad/s), so 0.02 rad/s removes all"
            ) && e.contains("use a record in which the joints move"),
            "{e}"
        );
    }
}

/// The message about a cutoff that settles over the record writes the Nyquist frequency
/// of a sample time measured from time stamps rounded, as the other messages do: from
/// Unix time stamps at 1 kHz (`1.7e9 + k / 1000`, whose mean step is 1 ms to 1e-8) it
/// wrote "499.9999879160976 Hz" and "249.9999939580488 Hz". So does the load's message
/// about a cutoff beyond the Nyquist frequency.
#[test]
fn the_settling_message_writes_the_nyquist_frequency_rounded() {
    let model = Synthetic::default();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("unix.csv");
    let text = csv_with_noise(3000, 1000.0, [0.0; DOF]);
    let mut lines = text.lines();
    let mut csv = lines.next().unwrap().to_string() + "\n";
    for line in lines {
        let (t, rest) = line.split_once(',').unwrap();
        let t: f64 = t.parse().unwrap();
        csv += &format!("{},{rest}\n", 1.7e9 + t);
    }
    std::fs::write(&file, csv).unwrap();
    for cutoff in ["0.01", "499.9"] {
        let text = CONFIG.replace("cutoff = 20.0", &format!("cutoff = {cutoff}"));
        let config = Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap();
        let data = load(&config, std::slice::from_ref(&file), DOF).unwrap();
        assert_ne!(0.5 / data.sample_time, 500.0);
        let e = identify(&model, &data, &config).unwrap_err().to_string();
        assert!(
            e.contains(&format!(
                "`processing.lowpass.cutoff`: {cutoff} Hz settles over "
            )) && e.contains("the Nyquist frequency, 500 Hz, settles slowly")
                && e.contains("settles fastest near half the Nyquist frequency, 250 Hz;"),
            "{e}"
        );
    }
    let text = CONFIG.replace("cutoff = 20.0", "cutoff = 600");
    let config = Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap();
    let e = load(&config, std::slice::from_ref(&file), DOF)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("600 Hz is outside [0.005, 499.995] Hz for data sampled at 1000 Hz"),
        "{e}"
    );
    // closer to the Nyquist frequency than 1e-5 of it the filter cannot be represented
    // (order 20 within 5e-9 of it had gain 0, and the record was refused by a filter of
    // "4 samples, at least 64" at no key)
    let text = CONFIG.replace(
        "cutoff = 20.0, order = 4",
        "cutoff = 499.999999, order = 20",
    );
    let config = Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap();
    let e = load(&config, std::slice::from_ref(&file), DOF)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`processing.lowpass.cutoff`: 499.999999 Hz is outside [0.005, 499.995] Hz"),
        "{e}"
    );
}

/// A low-pass whose settling takes the whole record is an error at its cutoff that says
/// which way to move it: down for a cutoff near the Nyquist frequency (499.9 Hz at 1 kHz
/// used to be told to "raise the low-pass cutoff", which the Nyquist frequency forbids),
/// up for a very low one.
#[test]
fn a_cutoff_that_settles_over_the_record_is_moved_the_right_way() {
    let model = Synthetic::default();
    let data = dataset(3000, 1000.0, 0.0);
    for (cutoff, expected) in [
        (
            "499.9",
            "(a cutoff close to the Nyquist frequency, 500 Hz, settles slowly), which leaves 0 \
             of the 3000 samples of run.csv (at least 2 are needed); lower it: the filter \
             settles fastest near half the Nyquist frequency, 250 Hz",
        ),
        (
            "0.01",
            "(a cutoff far below the Nyquist frequency, 500 Hz, settles slowly)",
        ),
    ] {
        let text = CONFIG.replace("cutoff = 20.0", &format!("cutoff = {cutoff}"));
        let line = text.lines().position(|l| l.starts_with("lowpass")).unwrap() + 1;
        let config = Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap();
        let e = identify(&model, &data, &config).unwrap_err();
        assert!(
            matches!(&e, Error::Data(DataError::ConfigKey { key, line: Some(l), .. })
                if key == "processing.lowpass.cutoff" && *l == line),
            "{e}"
        );
        let text = e.to_string();
        assert!(
            text.contains(&format!(
                "`processing.lowpass.cutoff`: {cutoff} Hz settles over "
            )),
            "{text}"
        );
        assert!(text.contains(expected), "{text}");
        let way = if cutoff == "0.01" {
            "raise it"
        } else {
            "lower it"
        };
        assert!(text.contains(way), "{text}");
    }
}

#[test]
fn extra_coupled_wrist_columns_are_identified() {
    // torque with TX40-style coupled-wrist terms added on joints 5 and 6
    let (iam, fvm, fsm) = (0.02, 0.6, 1.9);
    let n = 20_000;
    let model = Synthetic::default();
    let beta = true_parameters();
    let (mut q, mut qd, mut qdd) = ([0.0; DOF], [0.0; DOF], [0.0; DOF]);
    let mut qs = Signals::zeros(DOF, n);
    let mut taus = Signals::zeros(DOF, n);
    for k in 0..n {
        trajectory(k as f64 * 1e-3, &mut q, &mut qd, &mut qdd);
        let mut tau = [0.0; DOF];
        model
            .inverse_dynamics_into(&q, &qd, &qdd, &beta, &mut tau)
            .unwrap();
        let s = crate::Real::sign(qd[4] + qd[5]);
        tau[4] += iam * qdd[5] + fvm * qd[5] + fsm * s;
        tau[5] += iam * qdd[4] + fvm * qd[4] + fsm * s;
        for j in 0..DOF {
            qs[j][k] = q[j];
            taus[j][k] = tau[j];
        }
    }
    let data = Dataset::new("wrist", 1e-3, qs, taus).unwrap();
    let mut cfg = config("");
    cfg.extra_columns = ExtraColumn::coupled_wrist(5, 6);
    let id = identify(&model, &data, &cfg).unwrap();
    let e = &id.estimate;
    assert_eq!(e.names.len(), model.base_parameter_count() + 3);
    // noise-free, what is left is the filtering and differentiation: measured 2.1e-7,
    // 2.9e-6 and 1.1e-6
    assert!(
        (e.value("Iam6").unwrap() - iam).abs() < 4.1e-7,
        "{:?}",
        e.value("Iam6")
    );
    assert!(
        (e.value("fvm6").unwrap() - fvm).abs() < 5.7e-6,
        "{:?}",
        e.value("fvm6")
    );
    assert!(
        (e.value("fsm6").unwrap() - fsm).abs() < 2.2e-6,
        "{:?}",
        e.value("fsm6")
    );
}

#[test]
fn bad_inputs_for_the_pipeline() {
    let model = Synthetic::default();
    let data = Dataset::new("five", 1e-3, Signals::zeros(5, 100), Signals::zeros(5, 100)).unwrap();
    assert!(matches!(
        identify(&model, &data, &config("")),
        Err(Error::Data(DataError::JointCountMismatch {
            expected: 6,
            found: 5,
            ..
        }))
    ));
    let short = Dataset::new("short", 1e-3, Signals::zeros(6, 30), Signals::zeros(6, 30)).unwrap();
    assert!(matches!(
        identify(&model, &short, &config("")),
        Err(Error::TooFewSamples { .. })
    ));
    let data = dataset(3000, 1000.0, 0.0);
    let dup =
        "[[extra_column]]\nname = \"Fv1\"\nterms = [{ row = 1, signal = \"qd\", joints = [1] }]\n";
    let e = identify(&model, &data, &config(dup)).unwrap_err();
    assert!(
        matches!(&e, Error::Data(DataError::ConfigKey { path, key, line: Some(_), .. }) if path.ends_with("synthetic.toml") && key == "extra_column[1].name"),
        "{e}"
    );
    assert!(
        e.to_string().contains("`Fv1` is already a parameter"),
        "{e}"
    );
}

/// Madsen's rotor compensation: measured motor torque = tau_J + B thetaddot + Fv thetadot;
/// with the motor encoder and known B, F_v the link-side parameters come out unchanged.
#[test]
fn rotor_compensation_removes_rotor_inertia_and_friction() {
    let n = 12_000;
    let (b, fv) = (0.7, 0.3);
    let model = Synthetic::default();
    let beta = true_parameters();
    let (mut q, mut qd, mut qdd) = ([0.0; DOF], [0.0; DOF], [0.0; DOF]);
    let mut qs = Signals::zeros(DOF, n);
    let mut taus = Signals::zeros(DOF, n);
    for k in 0..n {
        trajectory(k as f64 * 1e-3, &mut q, &mut qd, &mut qdd);
        let mut tau = [0.0; DOF];
        model
            .inverse_dynamics_into(&q, &qd, &qdd, &beta, &mut tau)
            .unwrap();
        for j in 0..DOF {
            qs[j][k] = q[j];
            taus[j][k] = tau[j] + b * qdd[j] + fv * qd[j];
        }
    }
    let data = Dataset::new("rotor", 1e-3, qs.clone(), taus)
        .unwrap()
        .with_motor_positions(qs)
        .unwrap();
    let extra = "[drive.rotor]\ninertia = 0.7\nviscous = 0.3\n";
    let id = identify(&model, &data, &config(extra)).unwrap();
    let ia1 = id.estimate.value("Ia1").unwrap();
    // measured 7.5e-6 both ways
    assert!((ia1 - beta[4]).abs() < 1.5e-5, "Ia1 {ia1} vs {}", beta[4]);
    let plain = identify(&model, &data, &config("")).unwrap();
    assert!((plain.estimate.value("Ia1").unwrap() - beta[4] - b).abs() < 1.5e-5);
}

/// A log cut during motion, with no manual trim: the long odd padding of the low-pass
/// and the automatic trim keep the filter's edge transients out of the equations.
#[test]
fn a_log_cut_during_motion_needs_no_manual_trim() {
    let data = dataset(12_000, 1000.0, 0.0);
    let cut = data.slice(3_137, 11_000).unwrap();
    let mut cfg = config("");
    cfg.processing.trim = 0;
    let id = identify(&Synthetic::default(), &cut, &cfg).unwrap();
    // measured: relative error 9.6e-4, parameters 1.3e-3 relative at worst
    assert!(id.fit.relative_error < 1e-3, "{:?}", id.fit);
    let truth = true_parameters();
    for (i, (v, t)) in id.estimate.values.iter().zip(&truth).enumerate() {
        assert!(
            (v - t).abs() < 2.5e-3 * t.abs().max(1.0),
            "{}: {v} vs {t}",
            id.estimate.names[i]
        );
    }
    // the automatic trim is one settling time of the 20 Hz low-pass at 1 kHz (measured 56)
    let auto = crate::pipeline::automatic_trim(&cfg, 1e-3).unwrap();
    assert!((28..112).contains(&auto), "{auto}");
}

/// With a filtered torque (a decimation's anti-alias filter, or a low-pass on `tau`) the
/// prediction carries the torque as measured at its samples: the file's values at the
/// rows' own times (checked against the model's torque there), and the report labels
/// both errors; with an unfiltered torque it carries nothing and says "measured".
#[test]
fn the_fit_is_also_measured_against_the_unfiltered_torque() {
    let rate = 1000.0;
    let data = dataset(20_000, rate, 0.0);
    let model = Synthetic::default();
    let beta = true_parameters();
    let id = identify(&model, &data, &config("")).unwrap();
    let unfiltered = id
        .prediction
        .unfiltered
        .as_ref()
        .expect("decimation filters");
    // times are on the log's own axis: the first row used is at its own time
    let start = id.used.samples[0] as f64 / rate;
    assert!(id.prediction.time.iter().all(|t| t[0] >= start - 1e-12));
    let (mut q, mut qd, mut qdd, mut tau) = ([0.0; DOF], [0.0; DOF], [0.0; DOF], [0.0; DOF]);
    let mut rows = 0;
    for (j, (times, values)) in id.prediction.time.iter().zip(unfiltered).enumerate() {
        assert_eq!(times.len(), values.len());
        for (t, v) in times.iter().zip(values) {
            synthetic::trajectory(*t, &mut q, &mut qd, &mut qdd);
            model
                .inverse_dynamics_into(&q, &qd, &qdd, &beta, &mut tau)
                .unwrap();
            assert!(
                (v - tau[j]).abs() <= 1e-9 * tau[j].abs().max(1.0),
                "joint {j} t {t}: {v} vs {}",
                tau[j]
            );
            rows += 1;
        }
    }
    // measured 11 083 rows
    assert!(rows > 5600);
    let report = crate::report::Report::from_identification(&id, |_| None);
    assert_eq!(report.fit.torque.as_deref(), Some("filtered"));
    let raw = id.prediction.unfiltered_fit().unwrap().relative_error;
    assert_eq!(report.fit.unfiltered_relative_error, Some(raw));
    let text = crate::report::text_table(&report);
    assert!(
        text.contains("(filtered torque; ") && text.contains("against the measured torque"),
        "{text}"
    );

    // no decimation, no low-pass on tau: the measured torque is the torque as measured
    let plain = config("").clone();
    let mut plain = plain;
    plain.processing.decimation = crate::data::Decimation::Total(1);
    let id = identify(&model, &data, &plain).unwrap();
    assert!(id.prediction.unfiltered.is_none());
    let report = crate::report::Report::from_identification(&id, |_| None);
    assert_eq!(report.fit.torque.as_deref(), Some("measured"));
    assert!(crate::report::text_table(&report).contains("% (measured torque)"));

    // a low-pass on tau alone also filters it
    let mut on_tau = plain;
    on_tau
        .processing
        .lowpass
        .as_mut()
        .unwrap()
        .signals
        .push(crate::data::Signal::Tau);
    let id = identify(&model, &data, &on_tau).unwrap();
    assert!(id.prediction.unfiltered.is_some());
}

/// A two-encoder log of the synthetic model without link-side friction: the link follows
/// the trajectory, the motor `theta = q + delta` with a known deflection, and the motor
/// torque is Madsen's eq. 14 solved for K_r i with a known nonlinear friction model:
/// `K_r i = tau_J + B thetaddot + f(thetadot, tau_J, T)`, where (their eq. 15) `tau_J =
/// Y_b gamma_b + Fc~ sgn(thetadot) + Fv~ thetadot`. thetadot and thetaddot are the central
/// differences the pipeline takes of theta (no low-pass), so that a noise-free log is
/// exactly consistent. Returns the data, the friction model and the residuals (Fc~, Fv~).
#[allow(clippy::needless_range_loop)] // joint and sample index several signals at once
fn two_encoder_log(n: usize) -> (Dataset, crate::drive::FrictionModel, [f64; 2]) {
    use crate::drive::{FrictionModel, JointFriction};
    let dt = 1e-3;
    let (b, residual) = (0.7, [0.4, 0.25]);
    let model = Synthetic::without(&["Fv", "Fc"]);
    let gamma = model.truth();
    let friction = FrictionModel::new(
        (0..DOF)
            .map(|j| JointFriction {
                coulomb: 1.5 + 0.1 * j as f64,
                load: 0.02,
                stribeck: 0.8,
                stribeck_velocity: 0.1,
                viscous: 2.0,
                coulomb_temperature: 0.01,
                viscous_temperature: 0.015,
                reference_temperature: 35.0,
                smoothing: 1e-3,
            })
            .collect(),
    )
    .unwrap();
    let (mut q, mut qd, mut qdd) = ([0.0; DOF], [0.0; DOF], [0.0; DOF]);
    let mut s = [
        Signals::zeros(DOF, n),
        Signals::zeros(DOF, n),
        Signals::zeros(DOF, n),
        Signals::zeros(DOF, n),
        Signals::zeros(DOF, n),
    ];
    for k in 0..n {
        let t = k as f64 * dt;
        trajectory(t, &mut q, &mut qd, &mut qdd);
        for j in 0..DOF {
            s[0][j][k] = q[j];
            s[1][j][k] = qd[j];
            s[2][j][k] = qdd[j];
            // deflection: 0.02 rad at 5 rad/s, 0.1 rad/s of rotor velocity beside the link's
            s[3][j][k] = q[j] + 0.02 * (5.0 * t + j as f64).sin();
            // temperature rising by 15 K over the log
            s[4][j][k] = 30.0 + 15.0 * k as f64 / n as f64 + j as f64;
        }
    }
    let [qs, qds, qdds, theta, temp] = s;
    let thetad = theta.try_map(|v| central_difference(v, dt)).unwrap();
    let thetadd = thetad.try_map(|v| central_difference(v, dt)).unwrap();
    let mut motor = Signals::zeros(DOF, n);
    let mut tau = [0.0; DOF];
    for k in 0..n {
        let at = |x: &Signals| -> [f64; DOF] { std::array::from_fn(|j| x[j][k]) };
        model
            .inverse_dynamics_into(&at(&qs), &at(&qds), &at(&qdds), &gamma, &mut tau)
            .unwrap();
        for j in 0..DOF {
            let w = thetad[j][k];
            let tau_j = tau[j] + residual[0] * Real::sign(w) + residual[1] * w;
            motor[j][k] = tau_j + b * thetadd[j][k] + friction.evaluate(j, w, tau_j, temp[j][k]);
        }
    }
    let data = Dataset::new("two-encoder", dt, qs, motor)
        .unwrap()
        .with_velocities(qds)
        .unwrap()
        .with_accelerations(qdds)
        .unwrap()
        .with_motor_positions(theta)
        .unwrap()
        .with_temperatures(temp)
        .unwrap();
    (data, friction, residual)
}

/// The config of [`two_encoder_log`] in `dir` (with its friction file): no low-pass,
/// measured link velocities, `[drive.rotor]` with the friction model, plus `extra`.
fn two_encoder_config(dir: &Path, friction: &crate::drive::FrictionModel, extra: &str) -> Config {
    std::fs::create_dir_all(dir).unwrap();
    friction.write(&dir.join("friction.toml")).unwrap();
    let text = format!(
        "{}\n[drive.rotor]\ninertia = 0.7\nfriction = \"friction.toml\"\n{extra}",
        CONFIG.replace(
            "lowpass = { cutoff = 20.0, order = 4, signals = [\"q\"] }\n",
            ""
        )
    );
    Config::from_toml_str(&text, &dir.join("rotor.toml")).unwrap()
}

/// Madsen's eqs. 14-15 end to end: the nonlinear compensation from `friction = ...` and
/// the rotor-side residual columns recover the residuals and the base parameters to
/// rounding; the link-side Fc, Fv columns in their place fit measurably worse.
#[test]
fn rotor_side_residuals_after_the_nonlinear_compensation() {
    let (data, friction, [fc, fv]) = two_encoder_log(12_000);
    let folder = tempfile::tempdir().unwrap();
    let dir = folder.path();
    let cfg = two_encoder_config(dir, &friction, "residual = [\"Fc\", \"Fv\"]\n");
    let rotor_model = Synthetic::without(&["Fv", "Fc"]);
    let id = identify(&rotor_model, &data, &cfg).unwrap();
    let truth = rotor_model.truth();
    let mut worst = 0.0_f64;
    for (v, t) in id.estimate.values.iter().zip(&truth) {
        worst = worst.max((v - t).abs() / t.abs().max(1.0));
    }
    for j in 1..=DOF {
        let (c, v) = (
            id.estimate.value(&format!("Fc{j}_rotor")).unwrap(),
            id.estimate.value(&format!("Fv{j}_rotor")).unwrap(),
        );
        worst = worst.max((c - fc).abs()).max((v - fv).abs());
    }
    // measured: parameters 6.9e-14 (relative, or absolute below 1), relative fit error
    // 2.3e-14 (condition number 60): rounding of the solve and the decimation filter
    assert!(worst < 1e-11, "worst parameter error {worst}");
    assert!(id.fit.relative_error < 1e-12, "{:?}", id.fit);

    // the link-side columns on the same log: the deflection's velocity is left unmodelled
    let link = two_encoder_config(dir, &friction, "");
    let linked = identify(&Synthetic::default(), &data, &link).unwrap();
    let fv1 = linked.estimate.value("Fv1").unwrap();
    // measured: relative fit error 1.55e-2, Fv1 = 0.775 for Fv~ = 0.25, Fc1 = 0.036 for
    // Fc~ = 0.4
    assert!(
        linked.fit.relative_error > 7.8e-3,
        "link side {:?} vs rotor side {:?}",
        linked.fit,
        id.fit
    );
    assert!((fv1 - fv).abs() > 0.27, "Fv1 {fv1}");

    // both sides for one joint: refused, naming the fix
    let e = identify(&Synthetic::default(), &data, &cfg)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("drive.rotor.residual") && e.contains("nearly collinear"),
        "{e}"
    );
    // a friction file of another joint count, and friction with viscous: errors on the key
    let one = crate::drive::FrictionModel::new(vec![friction.joints()[0]]).unwrap();
    let e = identify(&rotor_model, &data, &two_encoder_config(dir, &one, ""))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("drive.rotor.friction") && e.contains("1 [[friction]] table,"),
        "{e}"
    );
    // a friction file that is not there: the key, its place in the config and the fix
    let mut missing = two_encoder_config(dir, &friction, "");
    if let Some(rotor) = missing.drive.rotor.as_mut() {
        rotor.friction = Some("absent.toml".into());
    }
    let e = identify(&rotor_model, &data, &missing)
        .unwrap_err()
        .to_string();
    for part in [
        "drive.rotor.friction",
        "absent.toml does not exist",
        "`robid friction` writes it",
        "remove the line",
    ] {
        assert!(e.contains(part), "{part}: {e}");
    }
    let e = identify(
        &rotor_model,
        &data,
        &two_encoder_config(dir, &friction, "viscous = 0.1\n"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("subtracted twice"), "{e}");
    // rotor-side columns need the motor encoders
    let mut no_motor = data.clone();
    no_motor.motor = None;
    let mut plain = config("");
    plain.extra_columns.push(
        toml::from_str("name = \"w1\"\nterms = [{ row = 1, signal = \"theta_d\", joints = [1] }]")
            .unwrap(),
    );
    let e = identify(&rotor_model, &no_motor, &plain)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("extra_column[1].terms[1].signal") && e.contains("motor_position"),
        "{e}"
    );
}

/// A record with fewer samples than the parameters need (one equation per joint and
/// sample) names its file and rows, the parameters and the samples needed, the same with
/// every method that solves the torque equations, in the streaming (OLS) and the dense
/// path; it was the least squares' "least squares with 48 parameters: 30 samples, at least
/// 48 are needed; use more data, less decimation, or fewer parameters" (equations counted
/// as samples, no file), or per axis "the per-axis identification of joint 6: ..".
#[test]
fn a_record_too_short_for_the_parameters_names_its_file() {
    let model = Synthetic::default();
    let plain = CONFIG.split("[processing]").next().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("short.csv");
    // the identification of a record of `samples` with the config `text`
    let identified = |text: &str, samples: usize| {
        let cfg = Config::from_toml_str(text, Path::new("short.toml")).unwrap();
        std::fs::write(&file, csv_with_noise(samples, 1000.0, [0.0; DOF])).unwrap();
        let data = load(&cfg, std::slice::from_ref(&file), DOF).unwrap();
        identify(&model, &data, &cfg)
    };
    let too_short = |e: &Error, samples: usize| matches!(e, Error::TooFewSamples { found, required: 9, .. } if *found == samples);
    let mut messages = Vec::new();
    for method in ["ols", "rls", "per-axis", "link-by-link"] {
        let e =
            identified(&format!("{plain}[estimation]\nmethod = \"{method}\"\n"), 5).unwrap_err();
        assert!(too_short(&e, 5), "{method}: {e}");
        messages.push(e.to_string());
        // trimmed to 5 of 9 samples
        let trimmed =
            format!("{plain}[processing]\ntrim = 2\n[estimation]\nmethod = \"{method}\"\n");
        let e = identified(&trimmed, 9).unwrap_err().to_string();
        assert!(
            e.contains(
                ": too short, after processing.range and the trims of its 9 samples, for \
                 the 48 parameters of the model"
            ) && e.contains("5 samples, at least 9 are needed; record a longer trajectory"),
            "{method}: {e}"
        );
    }
    assert_eq!(
        messages[0],
        format!(
            "{} lines 2-6 (samples 0..5): too short for the 48 parameters of the model (each \
             sample gives 6 equations, one per joint, and the fit needs more equations than \
             parameters): 5 samples, at least 9 are needed; record a longer trajectory",
            file.display()
        )
    );
    for m in &messages[1..] {
        assert_eq!(m, &messages[0]);
    }
    // 8 samples: 48 equations for the 48 parameters fit any data exactly, with no
    // residual for the standard deviations (they were a rounding error's, 0.00 %)
    let e = identified(plain, 8).unwrap_err();
    assert!(too_short(&e, 8), "{e}");
    // 9 samples: no longer too short for the parameters (the data then lack excitation)
    if let Err(e) = identified(plain, 9) {
        assert!(!matches!(e, Error::TooFewSamples { .. }), "{e}");
    }
}

/// A record joined from several `[[source]]` files that is too short names every file,
/// not only the first (the positions' file was named, the torques' file left out): for
/// the parameters, and for the trims.
#[test]
fn a_joined_record_too_short_names_all_its_files() {
    let model = Synthetic::default();
    let dir = tempfile::tempdir().unwrap();
    let (pos, tau) = (dir.path().join("pos.csv"), dir.path().join("tau.csv"));
    let text = csv_with_noise(5, 1000.0, [0.0; DOF]);
    // the columns t,q1..q6 and t,tau1..tau6 of the same rows
    let columns = |range: std::ops::Range<usize>| -> String {
        text.lines()
            .map(|l| {
                let f: Vec<&str> = l.split(',').collect();
                std::iter::once(f[0])
                    .chain(f[range.clone()].iter().copied())
                    .collect::<Vec<_>>()
                    .join(",")
                    + "\n"
            })
            .collect()
    };
    std::fs::write(&pos, columns(1..7)).unwrap();
    std::fs::write(&tau, columns(7..13)).unwrap();
    let two = "dof = 6\ntime_column = \"t\"\n[[source]]\nposition = \"q{}\"\n\
               [[source]]\ntorque = \"tau{}\"\n";
    let files = [pos.clone(), tau.clone()];
    let cfg = Config::from_toml_str(two, Path::new("two.toml")).unwrap();
    let data = load(&cfg, &files, DOF).unwrap();
    let e = identify(&model, &data, &cfg).unwrap_err();
    assert!(
        matches!(
            e,
            Error::TooFewSamples {
                found: 5,
                required: 9,
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        format!(
            "{} lines 2-6 (samples 0..5), joined with {}: too short for the 48 parameters of \
             the model (each sample gives 6 equations, one per joint, and the fit needs more \
             equations than parameters): 5 samples, at least 9 are needed; record a longer \
             trajectory",
            pos.display(),
            tau.display()
        )
    );
    let trimmed = format!("{two}[processing]\ntrim = 3\n");
    let cfg = Config::from_toml_str(&trimmed, Path::new("two.toml")).unwrap();
    let e = identify(&model, &load(&cfg, &files, DOF).unwrap(), &cfg)
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(&format!(
            "pos.csv, joined with {}, after trimming 3 samples at each end",
            tau.display()
        )),
        "{e}"
    );
}

/// The samples a run needs ([`super::prepare::samples_needed`], checked for every run of
/// `[runs]` before any is identified) are what the pipeline needs: one sample fewer
/// fails with an error about the length (the trims, the low-pass, the decimation, the
/// range, the parameters), that many does not, whatever the setting that takes most.
#[test]
fn the_samples_a_run_needs_are_what_the_pipeline_needs() {
    let model = Synthetic::default();
    let plain = CONFIG.split("[processing]").next().unwrap();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("run.csv");
    let length_keys = [
        "processing.trim",
        "processing.range",
        "processing.decimation",
        "processing.lowpass.cutoff",
        "processing.differentiation.window",
    ];
    let about_length = |e: &Error| match e {
        Error::TooFewSamples { .. } => true,
        Error::Data(DataError::ConfigKey { key, .. }) => length_keys.contains(&key.as_str()),
        _ => false,
    };
    for (processing, takes) in [
        // the trims, then the parameters after decimation
        (
            "lowpass = { cutoff = 20.0, order = 4 }\ntrim = 200\ndecimation = 10",
            "trim",
        ),
        // the low-pass's settling
        ("lowpass = { cutoff = 2.0, order = 4 }", "settle"),
        // the parameters after a decimation in two stages
        ("decimation = [10, 10]", "decimation"),
        // the parameters alone
        ("", "parameters"),
        // the range, which the record must contain
        (
            "lowpass = { cutoff = 20.0, order = 4 }\ntrim = 10\nrange = [100, 400]",
            "range",
        ),
        // a Savitzky-Golay window longer than the rest
        (
            "differentiation = { method = \"savitzky-golay\", window = 31, order = 3 }",
            "window",
        ),
    ] {
        let text = format!("{plain}[processing]\n{processing}\n");
        let cfg = Config::from_toml_str(&text, Path::new("run.toml")).unwrap();
        std::fs::write(&file, csv_with_noise(3000, 1000.0, [0.5; DOF])).unwrap();
        let long = load(&cfg, std::slice::from_ref(&file), DOF).unwrap();
        let parameters = super::identify::estimated_parameters(&model, &cfg).unwrap();
        assert_eq!(parameters, 48);
        let need = super::prepare::samples_needed(&long, &cfg, parameters).unwrap();
        let n = need.samples;
        for (samples, short) in [(n - 1, true), (n, false)] {
            std::fs::write(&file, csv_with_noise(samples, 1000.0, [0.5; DOF])).unwrap();
            let data = load(&cfg, std::slice::from_ref(&file), DOF).unwrap();
            assert_eq!(
                super::prepare::samples_needed(&data, &cfg, parameters),
                Some(need.clone())
            );
            match identify(&model, &data, &cfg) {
                Err(e) => assert_eq!(about_length(&e), short, "{takes}, {samples} samples: {e}"),
                Ok(_) => assert!(!short, "{takes}: {samples} samples identified"),
            }
        }
        let expected = match takes {
            "trim" => "200 samples at each end (processing.trim",
            "settle" => "samples at each end for the low-pass to settle and 9 between them",
            "decimation" => {
                "1201 between them for more equations than the 48 parameters at 6 \
                 equations per sample, one sample in 100 kept by processing.decimation less 2 \
                 at each end that its filter does not settle"
            }
            "parameters" => {
                "9 between them for more equations than the 48 parameters at 6 equations per \
                 sample"
            }
            "range" => "processing.range [100, 400] less",
            _ => "31 in all for the Savitzky-Golay window",
        };
        assert!(need.why.contains(expected), "{takes}: {n}: {}", need.why);
    }
    // settings at their extremes give an answer, never an overflow
    let data = dataset(100, 1000.0, 0.0);
    for processing in [
        "range = [18446744073709551614, 18446744073709551615]",
        "range = [0, 18446744073709551615]\ntrim = 50000000",
        "trim = 50000000\ndecimation = 10000",
    ] {
        let text = format!("{plain}[processing]\n{processing}\n");
        let cfg = Config::from_toml_str(&text, Path::new("run.toml")).unwrap();
        let need = super::prepare::samples_needed(&data, &cfg, usize::MAX);
        assert!(
            need.as_ref().is_none_or(|n| n.samples > 100),
            "{processing}: {need:?}"
        );
    }
}

/// Under a decimation that leaves few samples, the standard deviations still describe the
/// estimates' spread over acquisitions of the same trajectory: the decimated samples at
/// the record's ends, which carry one sample's noise whole (the filter's odd extension
/// pins them to it), are left out. Over 40 acquisitions decimated by 500 (24 samples), the
/// spread was 1.08 times the deviations (median over the parameters), 1.30 at most; with
/// the end samples kept, 0.93 and 2.07 (a UR5e from rest, 20 samples: 2.5 in the median).
#[test]
fn heavily_decimated_deviations_describe_the_spread() {
    let model = Synthetic::default();
    let text = CONFIG.replace("decimation = 10", "decimation = 500");
    let config = Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("run.csv");
    let (mut values, mut stds) = (Vec::new(), Vec::new());
    for seed in 0..40 {
        std::fs::write(
            &file,
            synthetic::csv_seeded(12_400, 1000.0, [2.0; DOF], seed),
        )
        .unwrap();
        let data = load(&config, std::slice::from_ref(&file), DOF).unwrap();
        let id = identify(&model, &data, &config).unwrap();
        values.push(id.estimate.values.clone());
        stds.push(id.estimate.std.clone());
    }
    let runs = values.len() as f64;
    let mut ratios: Vec<f64> = (0..values[0].len())
        .map(|c| {
            let mean = values.iter().map(|v| v[c]).sum::<f64>() / runs;
            let spread =
                (values.iter().map(|v| (v[c] - mean).powi(2)).sum::<f64>() / (runs - 1.0)).sqrt();
            let std = (stds.iter().map(|s| s[c] * s[c]).sum::<f64>() / runs).sqrt();
            spread / std
        })
        .collect();
    ratios.sort_by(f64::total_cmp);
    let (median, most) = (ratios[ratios.len() / 2], ratios[ratios.len() - 1]);
    assert!(
        (0.7..1.4).contains(&median) && most < 1.6,
        "{median}, {most}"
    );
}

/// An energy window shorter than half a sample is an error at its key with the sample
/// time; it was taken as one sample (a UR5e at 500 Hz with 0.001 s: 10 000 windows of one
/// step, fit 132 %). Half a sample and more is one window of a step.
#[test]
fn an_energy_window_shorter_than_a_sample_names_its_key() {
    let model = Synthetic::default();
    let data = dataset(3000, 1000.0, 0.0);
    let with = |window: &str| {
        let text = format!("{CONFIG}[estimation]\nmethod = \"energy\"\nenergy_window = {window}\n");
        Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap()
    };
    let e = identify(&model, &data, &with("0.0004")).unwrap_err();
    assert!(
        matches!(&e, Error::Data(DataError::ConfigKey { key, line: Some(_), .. })
            if key == "estimation.energy_window"),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains("0.0004 s is less than half of the sample time (0.001 s)"),
        "{e}"
    );
    let e = identify(&model, &data, &with("0.0006")).map(|_| ());
    assert!(
        !matches!(&e, Err(Error::Data(DataError::ConfigKey { key, .. })) if key == "estimation.energy_window"),
        "{e:?}"
    );
    // windows too long for one equation per parameter and one more: the key and the
    // longest window that gives enough (told as "2 samples ... less decimation" before)
    let p = model.base_parameter_count();
    let e = identify(&model, &data, &with("1.5")).unwrap_err();
    assert!(
        matches!(&e, Error::Data(DataError::ConfigKey { key, line: Some(_), .. })
            if key == "estimation.energy_window"),
        "{e}"
    );
    let text = e.to_string();
    assert!(
        text.contains(&format!(
            "1.5 s windows give 1 window of the record's 2.599 s (one equation each), and the \
             {p} parameters need at least {}",
            p + 1
        )),
        "{text}"
    );
    // the longest window it offers is enough
    let longest: f64 = text
        .split("use windows of at most ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{text}"));
    let e = identify(&model, &data, &with(&longest.to_string())).map(|_| ());
    assert!(
        !matches!(&e, Err(Error::Data(DataError::ConfigKey { key, .. })) if key == "estimation.energy_window"),
        "{e:?}"
    );
}

/// A rank tolerance raised far above the default is named at its key when the fit is
/// rank deficient (0.5 was told as "use a richer trajectory"); at the default the same
/// data are of full rank.
#[test]
fn a_raised_rank_tolerance_is_named_when_it_cuts_the_rank() {
    let model = Synthetic::default();
    let data = dataset(3000, 1000.0, 0.0);
    for method in ["ols", "wls", "energy"] {
        let text = format!("{CONFIG}[estimation]\nmethod = \"{method}\"\nrank_tolerance = 0.999\n");
        let config = Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap();
        let e = identify(&model, &data, &config).unwrap_err();
        assert!(
            matches!(&e, Error::Data(DataError::ConfigKey { key, line: Some(_), .. })
                if key == "estimation.rank_tolerance"),
            "{method}: {e}"
        );
        assert!(
            e.to_string()
                .contains("0.999 counts singular values below 0.999 times the largest as zero"),
            "{e}"
        );
    }
    assert!(identify(&model, &data, &config("")).is_ok());
}

/// The rest removal's error says when its threshold is the default (the config has no
/// `rest_velocity`, and the error is placed at `[processing]`), and names the decimation
/// too when that left few equations before the removal: a UR5e decimated by 1000 kept 60
/// equations for 58 parameters, of which the default removed a few, and the error told of
/// the threshold alone.
#[test]
fn rest_removal_after_a_heavy_decimation_names_both() {
    let model = Synthetic::default();
    let data = with_joint_at_rest(1700, 2);
    let text = CONFIG
        .replace("rest_velocity = 0.02\n", "")
        .replace("decimation = 10", "decimation = 100");
    let config = Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap();
    let mut rls = config.clone();
    rls.estimation.method = crate::data::Method::Rls;
    for config in [&config, &rls] {
        let e = identify(&model, &data, config).unwrap_err();
        let text = e.to_string();
        for part in [
            "`processing.rest_velocity`: 0.05 rad/s (the default: the config sets no \
             rest_velocity) removes",
            "or lower processing.decimation (its factor of 100 leaves 54 equations before the \
             removal)",
        ] {
            assert!(text.contains(part), "`{part}` in {text}");
        }
    }
}

/// A validation record that the decimation leaves no settled sample of is refused at
/// `processing.decimation` naming the record and that a prediction needs one equation (it
/// said "fewer than the 1 parameters", without the file).
#[test]
fn a_validation_record_too_short_for_the_decimation_is_named() {
    let model = Synthetic::default();
    let text = CONFIG.replace("decimation = 10", "decimation = 100");
    let config = Config::from_toml_str(&text, Path::new("synthetic.toml")).unwrap();
    let values = identify(&model, &dataset(6000, 1000.0, 0.0), &config)
        .unwrap()
        .estimate
        .values;
    let short = dataset(800, 1000.0, 0.0);
    let e = validate(&model, &short, &config, &values).unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(&e, Error::Data(DataError::ConfigKey { key, .. }) if key == "processing.decimation"),
        "{text}"
    );
    for part in [
        format!("keeps 4 of the 400 samples of {} used", short.name),
        "0 without the 2 at each end that its filter does not settle".into(),
        "0 equations, fewer than the one a prediction needs".into(),
    ] {
        assert!(text.contains(&part), "`{part}` in {text}");
    }
}

/// A joint at rest whose positions differ only in their last bits moves at the rounding of
/// its positions (velocities of about 1e-13 rad/s): that is no excitation. Its velocity
/// columns scaled to unit norm were columns of noise and the sign of the noise a Coulomb
/// column of +-1, which counted as excited: with `rest_velocity = 0` the record was
/// identified (six samples at rest: condition number 1.8e17, values of 1e15, exit 0). Its
/// drive parameters are not excited, as for positions exactly constant, and the joint is
/// named as not moving.
#[test]
fn velocities_at_the_rounding_of_the_positions_are_no_excitation() {
    let model = Synthetic::default();
    let config = Config::from_toml_str(
        &CONFIG.replace("rest_velocity = 0.02", "rest_velocity = 0"),
        Path::new("synthetic.toml"),
    )
    .unwrap();
    let mut data = dataset(3000, 1000.0, 0.0);
    // given velocities and accelerations (as `robid simulate` writes them), the last
    // joint's at the rounding of its position, 0.7
    let mut seed = 11u64;
    let mut noise = |scale: f64| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * scale
    };
    let (mut q, mut qd, mut qdd) = ([0.0; DOF], [0.0; DOF], [0.0; DOF]);
    let mut given = [
        Signals::zeros(DOF, 3000),
        Signals::zeros(DOF, 3000),
        Signals::zeros(DOF, 3000),
    ];
    for k in 0..3000 {
        trajectory(k as f64 * 1e-3, &mut q, &mut qd, &mut qdd);
        (q[DOF - 1], qd[DOF - 1], qdd[DOF - 1]) = (0.7, noise(1e-13), noise(1e-10));
        for (s, v) in given.iter_mut().zip([&q, &qd, &qdd]) {
            for (joint, x) in s.joints_mut().zip(v) {
                joint[k] = *x;
            }
        }
    }
    let [q, qd, qdd] = given;
    (data.q, data.qd, data.qdd) = (q, Some(qd), Some(qdd));
    for method in [crate::data::Method::Ols, crate::data::Method::Rls] {
        let mut config = config.clone();
        config.estimation.method = method;
        match identify(&model, &data, &config) {
            Err(Error::Estimate(EstimateError::StillJoints {
                unexcited, joints, ..
            })) => {
                for name in ["Ia6", "Fv6", "Fc6"] {
                    assert!(unexcited.iter().any(|n| n == name), "{unexcited:?}");
                }
                // the joint that does not move is named (it was "use a richer trajectory")
                assert_eq!(joints, [6]);
            }
            Err(other) => panic!("{method:?}: {other}"),
            Ok(id) => panic!(
                "{method:?}: identified, condition number {:e}, {:?}",
                id.estimate.condition_number,
                &id.estimate.values[40..]
            ),
        }
    }
}
