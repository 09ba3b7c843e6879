//! The streaming identification against the dense path (the whole observation matrix) on
//! the synthetic model: the same equations, estimates, statistics, fit and validation to
//! 1e-10.

use super::synthetic::{DOF, Synthetic};
use super::{config, dataset_with_noise};
use crate::data::{Config, Method, Signal};
use crate::estimate::Estimate;
use crate::model::Model;
use crate::pipeline::identify::{identify_dense_of, validate_dense};
use crate::pipeline::prepare::{Plan, Rows, prepare_rows};
use crate::pipeline::stream::Stream;
use crate::pipeline::{Identification, identify, observe, validate};
use crate::validate::{Fit, Prediction};

/// |a - b| <= tol max(|a|, |b|, floor).
fn close(a: f64, b: f64, tol: f64, floor: f64) -> bool {
    (a - b).abs() <= tol * a.abs().max(b.abs()).max(floor)
}

fn same_list(what: &str, a: &[f64], b: &[f64], tol: f64, floor: f64) {
    assert_eq!(a.len(), b.len(), "{what}");
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(close(*x, *y, tol, floor), "{what} {i}: {x} vs {y}");
    }
}

fn same_estimate(s: &Estimate, d: &Estimate) {
    assert_eq!((&s.names, s.rows, s.method), (&d.names, d.rows, d.method));
    for (i, (v, w)) in s.values.iter().zip(&d.values).enumerate() {
        assert!(close(*v, *w, 1e-10, d.std[i]), "{}: {v} vs {w}", s.names[i]);
    }
    same_list("std", &s.std, &d.std, 1e-10, 0.0);
    same_list("sigma2", &[s.sigma2], &[d.sigma2], 1e-10, 0.0);
    same_list(
        "cond",
        &[s.condition_number],
        &[d.condition_number],
        1e-10,
        0.0,
    );
    same_list(
        "scaled cond",
        &[s.scaled_condition_number.unwrap()],
        &[d.scaled_condition_number.unwrap()],
        1e-10,
        0.0,
    );
    same_list("bound", &[s.error_bound], &[d.error_bound], 1e-10, 0.0);
    same_list("rms", &s.residual_rms, &d.residual_rms, 1e-10, 0.0);
    match (&s.weights, &d.weights) {
        (Some(a), Some(b)) => same_list("weights", a, b, 1e-10, 0.0),
        (a, b) => assert_eq!(a, b),
    }
    // the Newey-West deviations: the streaming pass over the equations again gives the
    // dense path's (the same lag over the same samples)
    let (rs, rd) = (s.robust.as_ref().unwrap(), d.robust.as_ref().unwrap());
    assert_eq!((rs.lag, rs.samples), (rd.lag, rd.samples));
    same_list("robust std", &rs.std, &rd.std, 1e-10, 0.0);
    let said = |e: &Estimate| {
        e.warnings
            .iter()
            .map(|w| (w.kind(), w.parameters()))
            .collect::<Vec<_>>()
    };
    assert_eq!(said(s), said(d));
}

/// The parameters `e` names uncertain, and how many of them the classical deviations
/// alone leave below 100 %: each path judges by the larger of the classical and the
/// robust deviation ([`Estimate::judged_std`]), so the list is exactly the parameters
/// above 100 % by it.
fn judged_by_the_larger(e: &Estimate) -> usize {
    let named: Vec<String> = e
        .warnings
        .iter()
        .filter(|w| w.kind() == "uncertain")
        .flat_map(|w| w.parameters())
        .collect();
    let above = |std: &[f64]| -> Vec<String> {
        (0..e.names.len())
            .filter(|&i| std[i] > e.values[i].abs())
            .map(|i| e.names[i].clone())
            .collect()
    };
    assert_eq!(named, above(&e.judged_std()));
    named.len() - above(&e.std).len()
}

fn same_fit(s: &Fit, d: &Fit) {
    same_list(
        "relative error",
        &[s.relative_error],
        &[d.relative_error],
        1e-10,
        0.0,
    );
    same_list(
        "rms per joint",
        &s.rms_per_joint,
        &d.rms_per_joint,
        1e-10,
        0.0,
    );
    same_list(
        "nmse",
        &[s.nmse, s.nmse_eq22],
        &[d.nmse, d.nmse_eq22],
        1e-10,
        0.0,
    );
}

fn same_prediction(s: &Prediction, d: &Prediction) {
    let scale = d
        .measured
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    for j in 0..d.measured.len() {
        same_list("measured", &s.measured[j], &d.measured[j], 1e-10, scale);
        same_list("predicted", &s.predicted[j], &d.predicted[j], 1e-10, scale);
        assert_eq!(s.time[j], d.time[j]);
    }
    match (&s.unfiltered, &d.unfiltered) {
        (Some(a), Some(b)) => assert_eq!(a, b),
        (a, b) => assert_eq!(a.is_some(), b.is_some()),
    }
    assert_eq!(s.used, d.used);
    same_fit(&s.fit(), &d.fit());
}

fn same_identification(s: &Identification, d: &Identification) {
    same_estimate(&s.estimate, &d.estimate);
    same_fit(&s.fit, &d.fit);
    same_prediction(&s.prediction, &d.prediction);
    assert_eq!(s.used, d.used);
}

/// 60,000 samples, joints 4 to 6 noisier: several blocks of the stream.
fn data() -> crate::data::Dataset {
    dataset_with_noise(60_000, 1000.0, [0.05, 0.05, 0.05, 1.0, 1.0, 1.0])
}

fn with(extra: &str, method: Method) -> Config {
    let text = extra.to_string();
    let mut c = if text.contains("decimation") {
        let base = super::synthetic::CONFIG.replace("decimation = 10\n", "");
        Config::from_toml_str(
            &base.replace("[processing]\n", &format!("[processing]\n{text}\n")),
            std::path::Path::new("synthetic.toml"),
        )
        .unwrap()
    } else {
        config(extra)
    };
    c.estimation.method = method;
    c
}

/// The blocks' equations (each block prepared from the data set with its margins) are the
/// dense observation's of the whole prepared record (joint-major there, sample-major in
/// the stream), to 1e-12 of the column's magnitude: with one decimation stage, two, and
/// none (no overlap).
#[test]
fn the_blocks_hold_the_dense_equations() {
    let data = data();
    let model = Synthetic::default();
    for decimation in ["decimation = 10", "decimation = [10, 2]", "decimation = 1"] {
        let config = with(decimation, Method::Ols);
        let rows = prepare_rows(&data, &config, Rows::Estimation).unwrap();
        let dense = observe(&model, &rows.prepared, &config).unwrap();
        let plan = Plan::new(&data, &config, Rows::Estimation).unwrap();
        let stream = Stream::new(&model, &data, &plan, &config, true).unwrap();
        let mut eqs: Vec<(usize, usize, Vec<f64>, f64)> = Vec::new();
        let mut blocks = 0;
        stream
            .run(|eq| {
                blocks += 1;
                eqs.extend(
                    (0..eq.y.len())
                        .map(|i| (eq.joint[i], eq.sample[i], eq.row(i).to_vec(), eq.y[i])),
                );
                Ok(())
            })
            .unwrap();
        // several blocks (measured 3 with each decimation)
        assert!(blocks >= 2, "{decimation}: {blocks} blocks");
        eqs.sort_by_key(|e| (e.0, e.1));
        assert_eq!(eqs.len(), dense.rows(), "{decimation}");
        let big: Vec<f64> = dense
            .w
            .column_iter()
            .map(|c| c.amax())
            .chain(std::iter::once(dense.y.amax()))
            .collect();
        let mut worst = 0.0f64;
        for (r, (j, k, row, y)) in eqs.iter().enumerate() {
            assert_eq!(dense.sample_of_row[r], *k);
            assert!(dense.joint_rows[*j].contains(&r));
            for (c, v) in row.iter().enumerate() {
                worst = worst.max((v - dense.w[(r, c)]).abs() / big[c].max(1e-300));
            }
            worst = worst.max((y - dense.y[r]).abs() / big[big.len() - 1]);
        }
        eprintln!("{decimation}: {blocks} blocks, largest difference {worst:e} of the column");
        // Each block's positions are low-passed apart from the whole record's, so they
        // differ by the recursive filter's rounding (measured: 8.4e-15 of q), which the two
        // differences of the accelerations divide by dt^2 = 1e-6: about 1e-8 of the
        // columns (measured: 1.3e-10 without decimation, 1.9e-11 and 2.1e-14 with; 1e-14
        // when the blocks shared the whole record's preparation).
        assert!(worst < 1e-8, "{decimation}: {worst:e}");
    }
}

/// OLS and WLS end to end (estimate, statistics, fit, prediction, validation) equal the
/// dense path to 1e-10.
#[test]
fn streaming_identification_equals_the_dense_path() {
    let data = data();
    let (train, test) = (
        data.slice(0, 45_000).unwrap(),
        data.slice(45_000, 60_000).unwrap(),
    );
    let model = Synthetic::default();
    for method in [Method::Ols, Method::Wls] {
        for extra in ["decimation = 10", "decimation = [10, 2]", "decimation = 1"] {
            let config = with(extra, method);
            let s = identify(&model, &train, &config).unwrap();
            let d = identify_dense_of(&model, &train, &config).unwrap();
            same_identification(&s, &d);
            judged_by_the_larger(&s.estimate);
            let vs = validate(&model, &test, &config, &s.estimate.values).unwrap();
            let vd = validate_dense(&model, &test, &config, &s.estimate.values).unwrap();
            same_prediction(&vs, &vd);
        }
    }
}

/// `estimation.robust_std = false` (read from the config) leaves the robust deviations out
/// of both paths, where the default gives them, and changes nothing else of the estimate.
#[test]
fn robust_std_false_leaves_them_out_of_both_paths() {
    let data = data().slice(0, 45_000).unwrap();
    let model = Synthetic::default();
    for method in [Method::Ols, Method::Wls] {
        let mut on = config("");
        on.estimation.method = method;
        let mut off = config("[estimation]\nrobust_std = false\n");
        off.estimation.method = method;
        assert!(on.estimation.robust_std && !off.estimation.robust_std);
        let (s_on, d_on) = (
            identify(&model, &data, &on).unwrap(),
            identify_dense_of(&model, &data, &on).unwrap(),
        );
        let (s, d) = (
            identify(&model, &data, &off).unwrap(),
            identify_dense_of(&model, &data, &off).unwrap(),
        );
        assert!(s_on.estimate.robust.is_some() && d_on.estimate.robust.is_some());
        assert!(s.estimate.robust.is_none() && d.estimate.robust.is_none());
        assert_eq!(s.estimate.values, s_on.estimate.values);
        assert_eq!(s.estimate.std, s_on.estimate.std);
        assert_eq!(d.estimate.values, d_on.estimate.values);
    }
}

/// The estimation rows say the samples of the equations, not only the processed range:
/// with a decimation of 10 the first and the last equation's samples (those of the
/// prediction's first and last time) and the step, in both paths and in the report's
/// line; the range alone was said before ("samples 0..45000" of equations from sample 70
/// on, every 10th).
#[test]
fn the_estimation_rows_say_the_samples_of_the_equations() {
    let data = data().slice(0, 45_000).unwrap();
    let model = Synthetic::default();
    for (extra, step) in [("decimation = 10", 10), ("decimation = 1", 1)] {
        let config = with(extra, Method::Wls);
        let s = identify(&model, &data, &config).unwrap();
        let d = identify_dense_of(&model, &data, &config).unwrap();
        assert_eq!(s.used, d.used, "{extra}");
        let times = s.prediction.time.iter().flatten();
        let sample = |t: f64| (t / data.sample_time).round() as usize;
        let first = sample(times.clone().fold(f64::INFINITY, |a, &t| a.min(t)));
        let last = sample(times.fold(0.0, |a: f64, &t| a.max(t)));
        let text = format!("{}", s.used);
        match s.used.equations {
            Some(e) => {
                assert_eq!((e.first, e.last, e.step), (first, last, step), "{extra}");
                assert!(
                    s.used.samples[0] < first && last < s.used.samples[1],
                    "{extra}"
                );
                assert!(
                    text.contains(&format!(
                        "; equations at samples {first} to {last}, every 10th"
                    )),
                    "{extra}: {text}"
                );
            }
            // every sample of the range: the range says it
            None => {
                assert_eq!(
                    (first, last + 1, step),
                    (s.used.samples[0], s.used.samples[1], 1)
                );
                assert!(!text.contains("equations"), "{text}");
            }
        }
    }
}

/// Milella's pieces select the equations of the estimate; the prediction keeps them all.
#[test]
fn pieces_stream_like_the_dense_path() {
    let data = data();
    let model = Synthetic::default();
    let config = with("", Method::Wls);
    let mut pieced = config.clone();
    pieced.processing.pieces = Some(vec![[1.0, 20.0], [31.5, 50.0]]);
    let s = identify(&model, &data, &pieced).unwrap();
    let d = identify_dense_of(&model, &data, &pieced).unwrap();
    same_identification(&s, &d);
    assert!(s.estimate.rows < identify(&model, &data, &config).unwrap().estimate.rows);
    // too few equations in the pieces: the dense path's error
    pieced.processing.pieces = Some(vec![[1.0, 1.05]]);
    let (s, d) = (
        identify(&model, &data, &pieced).unwrap_err().to_string(),
        identify_dense_of(&model, &data, &pieced)
            .unwrap_err()
            .to_string(),
    );
    assert_eq!(s, d);
    assert!(s.contains("processing.pieces"), "{s}");
    let _ = DOF;
}

/// Stacked repeated acquisitions (`[runs] mode = "stacked"`): OLS and WLS on every run's
/// equations at once, and the stacked prediction, equal the dense stacked observation's.
#[test]
fn stacked_runs_stream_like_the_dense_path() {
    let data = data();
    let runs: Vec<_> = [0, 20_000, 40_000]
        .iter()
        .map(|&a| data.slice(a, a + 20_000).unwrap())
        .collect();
    let model = Synthetic::default();
    for method in [Method::Ols, Method::Wls] {
        let config = with("", method);
        let (es, ps) = crate::pipeline::stream::stacked_streaming(&model, &runs, &config).unwrap();
        let (ed, pd) = crate::pipeline::runs::stacked_dense(&model, &runs, &config).unwrap();
        same_estimate(&es, &ed);
        same_prediction(&ps, &pd);
    }
}

/// The same log identified and validated from a record kept on disk (read in windows of
/// 64 KiB, several per block of the stream) and from the data set in memory: the same
/// estimate, fit and prediction to the bit, since every block holds the same samples.
/// The record on disk is read and identified with the progress shown (`Config::progress`,
/// as `robid identify` sets it), which changes nothing in the results.
#[test]
fn a_record_on_disk_identifies_as_the_data_set_in_memory() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("run.csv");
    let noise = [0.05, 0.05, 0.05, 1.0, 1.0, 1.0];
    std::fs::write(
        &file,
        super::synthetic::csv_with_noise(60_000, 1000.0, noise),
    )
    .unwrap();
    let model = Synthetic::default();
    for method in [Method::Ols, Method::Wls] {
        let config = with("", method);
        assert!(!config.progress, "a library call is silent");
        let shown = Config {
            progress: true,
            ..config.clone()
        };
        let files = [file.clone()];
        let memory = crate::data::load(&config, &files, DOF).unwrap();
        let disk = crate::data::SpilledRecord::open_in(&shown, &files, DOF, 64 << 10)
            .unwrap()
            .expect("one file on a regular clock is kept on disk");
        let (a, b) = (
            identify(&model, &disk, &shown).unwrap(),
            identify(&model, &memory, &config).unwrap(),
        );
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(
            bits(&a.estimate.values),
            bits(&b.estimate.values),
            "{method:?}"
        );
        assert_eq!(bits(&a.estimate.std), bits(&b.estimate.std));
        assert_eq!(a.prediction.predicted, b.prediction.predicted);
        assert_eq!(a.prediction.measured, b.prediction.measured);
        assert_eq!(
            (&a.used, a.fit.relative_error),
            (&b.used, b.fit.relative_error)
        );
        let values = &b.estimate.values;
        let (a, b) = (
            validate(&model, &disk, &shown, values).unwrap(),
            validate(&model, &memory, &config, values).unwrap(),
        );
        assert_eq!((a.predicted, a.used), (b.predicted, b.used));
    }
}

/// The synthetic model with regressor entry `column` (joint 1's row first, then joint
/// 2's, ...) set to `value` wherever joint 1's position exceeds `above` (an entry that is
/// zero elsewhere: its inverse dynamics the regressor times the parameters still);
/// infinite, a model that overflows on some samples.
struct Overflowing {
    inner: Synthetic,
    /// The regressor entries (row-major) set to `value`.
    columns: Vec<usize>,
    above: f64,
    value: f64,
}

impl Model for Overflowing {
    fn name(&self) -> &str {
        "overflowing"
    }
    fn dof(&self) -> usize {
        self.inner.dof()
    }
    fn standard_parameter_count(&self) -> usize {
        self.inner.standard_parameter_count()
    }
    fn standard_parameter_name(&self, index: usize) -> Option<&str> {
        self.inner.standard_parameter_name(index)
    }
    fn base_parameter_count(&self) -> usize {
        self.inner.base_parameter_count()
    }
    fn base_parameter_name(&self, index: usize) -> Option<&str> {
        self.inner.base_parameter_name(index)
    }
    fn run(
        &self,
        program: crate::model::ProgramKind,
        inputs: &[&[f64]],
        output: &mut [f64],
    ) -> Result<(), crate::model::LengthError> {
        self.inner.run(program, inputs, output)?;
        if inputs[0][0] > self.above {
            // the inverse dynamics stay the regressor times the parameters
            let p = self.base_parameter_count();
            match program {
                crate::model::ProgramKind::BaseRegressor => {
                    for &c in &self.columns {
                        output[c] = self.value;
                    }
                }
                crate::model::ProgramKind::InverseDynamics => {
                    for &column in &self.columns {
                        let (j, c) = (column / p, column % p);
                        output[j] += self.value * inputs[3][c];
                    }
                }
                _ => {}
            }
        }
        Ok(())
    }
}

/// A regressor that overflows is a named error, the same by both paths: the data row of
/// the first sample where it does, the joint and the parameter, never a NaN estimate.
#[test]
fn an_overflowing_regressor_is_named_by_both_paths() {
    let data = data();
    let peak = data.q[0].iter().fold(f64::MIN, |m, v| m.max(*v));
    let model = Overflowing {
        inner: Synthetic::default(),
        columns: vec![2],
        above: peak - 0.01,
        value: f64::INFINITY,
    };
    let config = with("", Method::Ols);
    let named = |e: crate::Error| match e {
        crate::Error::Estimate(crate::estimate::EstimateError::NonFiniteObservation {
            location,
            joint,
            parameter,
            ..
        }) => (location, joint, parameter),
        e => panic!("{e}"),
    };
    let streamed = named(identify(&model, &data, &config).unwrap_err());
    let dense = named(identify_dense_of(&model, &data, &config).unwrap_err());
    assert_eq!(streamed, dense);
    assert!(
        streamed
            .0
            .starts_with(data.location(0).split(':').next().unwrap())
    );
    assert_eq!(
        (streamed.1, streamed.2.as_str()),
        (1, model.base_parameter_name(2).unwrap())
    );
    // late in the record, in a later block of the stream: placed there by both paths (the
    // block's own sample, not shifted by where the block starts, passed unnoticed)
    let mut late = data;
    if let Some(q1) = late.q.joints_mut().next() {
        q1[50_000..50_100].fill(peak + 1.0);
    }
    let model = Overflowing {
        above: peak + 0.5,
        ..model
    };
    let streamed = named(identify(&model, &late, &config).unwrap_err());
    let dense = named(identify_dense_of(&model, &late, &config).unwrap_err());
    assert_eq!(streamed, dense);
    let line: usize = streamed.0.rsplit(':').next().unwrap().parse().unwrap();
    assert!((49_000..50_100).contains(&line), "{streamed:?}");
}

/// A regressor channel zero at the samples the stream probes but not at a few others
/// (late in the record, between two probes) is found by the check of every sample, and
/// the block is taken again with every channel: the same estimate as the dense path,
/// which never leaves a channel out.
#[test]
fn a_channel_zero_at_the_probes_is_still_taken() {
    let mut data = data();
    let model = Synthetic::default();
    let p = model.base_parameter_count();
    // an entry of joint 2's row that is zero at every state: a channel the probes leave out
    let row = |k: usize| {
        let state = |s: &crate::signal::Signals| s.joints().map(|v| v[k]).collect::<Vec<_>>();
        let (q, qd, qdd) = (state(&data.q), state(&data.q), state(&data.q));
        let mut out = vec![0.0; DOF * p];
        model.base_regressor_into(&q, &qd, &qdd, &mut out).unwrap();
        out
    };
    let zero_at = |c: usize| (0..20).all(|i| row(i * 2_999)[c] == 0.0);
    let column = (p..DOF * p)
        .find(|&c| zero_at(c))
        .expect("joint 2's row has a zero entry");
    // two neighbours, both zero at the probes, set to the same value: the check of the
    // channels taken as zero must not let equal values cancel
    let twins = (p..DOF * p - 1)
        .find(|&c| (c + 1) % p != 0 && zero_at(c) && zero_at(c + 1))
        .expect("joint 2's row has two neighbouring zero entries");
    let peak = data.q[0].iter().fold(f64::MIN, |m, v| m.max(*v));
    if let Some(q1) = data.q.joints_mut().next() {
        q1[50_001..50_011].fill(peak + 5.0);
    }
    let model = Overflowing {
        inner: model,
        columns: vec![column],
        above: peak + 0.5,
        value: 3.0,
    };
    let config = with("", Method::Ols);
    let streamed = identify(&model, &data, &config).unwrap();
    let dense = identify_dense_of(&model, &data, &config).unwrap();
    same_identification(&streamed, &dense);
    let paired = Overflowing {
        inner: Synthetic::default(),
        columns: vec![twins, twins + 1],
        above: peak + 0.5,
        value: 3.0,
    };
    same_identification(
        &identify(&paired, &data, &config).unwrap(),
        &identify_dense_of(&paired, &data, &config).unwrap(),
    );
    // the entry moves the estimate (it is not filtered away before it counts)
    let without = Overflowing {
        value: 0.0,
        ..model
    };
    let other = identify(&without, &data, &config).unwrap();
    assert_ne!(other.estimate.values, streamed.estimate.values);
}

/// Torques low-passed with the positions leave each equation's residual correlated with
/// its neighbours' (no decimation: the 20 Hz cutoff spans 50 samples): the robust
/// deviations are several times the classical ones, and both paths name uncertain exactly
/// the parameters whose larger deviation is above their value, some of them below it by
/// the classical deviation alone (measured: one of the 48 at a noise of 20, four at 40,
/// OLS and WLS alike, one run or the record's halves stacked).
#[test]
fn both_paths_judge_uncertainty_by_the_larger_deviation() {
    let model = Synthetic::default();
    for noise in [20.0, 40.0] {
        let data = dataset_with_noise(20_000, 1000.0, [noise; DOF]);
        for method in [Method::Ols, Method::Wls] {
            let mut c = with("decimation = 1", method);
            c.processing.lowpass.as_mut().unwrap().signals = vec![Signal::Q, Signal::Tau];
            let s = identify(&model, &data, &c).unwrap();
            let d = identify_dense_of(&model, &data, &c).unwrap();
            let more = judged_by_the_larger(&s.estimate);
            assert_eq!(more, judged_by_the_larger(&d.estimate));
            assert!(more > 0, "noise {noise}, {method:?}");
            // the record's halves stacked as two runs
            let runs = [
                data.slice(0, 10_000).unwrap(),
                data.slice(10_000, 20_000).unwrap(),
            ];
            let (s, _) = crate::pipeline::stream::stacked_streaming(&model, &runs, &c).unwrap();
            let (d, _) = crate::pipeline::runs::stacked_dense(&model, &runs, &c).unwrap();
            let more = judged_by_the_larger(&s);
            assert_eq!(more, judged_by_the_larger(&d));
            assert!(more > 0, "noise {noise}, {method:?}, stacked");
            // without the robust deviations both paths judge by the classical ones alone
            c.estimation.robust_std = false;
            for e in [
                identify(&model, &data, &c).unwrap().estimate,
                identify_dense_of(&model, &data, &c).unwrap().estimate,
                crate::pipeline::stream::stacked_streaming(&model, &runs, &c)
                    .unwrap()
                    .0,
                crate::pipeline::runs::stacked_dense(&model, &runs, &c)
                    .unwrap()
                    .0,
            ] {
                assert!(e.robust.is_none());
                assert_eq!(judged_by_the_larger(&e), 0);
            }
        }
    }
}
