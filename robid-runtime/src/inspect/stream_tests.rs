//! The inspection read block by block against the whole record's, computed as it was
//! computed in memory before the blocks (each signal's spectrum at once, the velocity by
//! `Sos::filtfilt` and `central_difference` of the whole position).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::*;
use crate::data::{SpilledRecord, load};
use crate::rng::Rng;
use crate::signal::{Signals, central_difference};

/// The inspection of `data` with every signal in memory (the code before the streaming).
fn whole(data: &Dataset, config: &Config, torque_limits: &[Option<f64>]) -> Inspection {
    let rate = 1.0 / data.sample_time;
    let dof = data.dof();
    let rest_velocity = match &config.processing.rest_velocity {
        Some(v) => v.values(dof, "processing.rest_velocity").unwrap(),
        None => vec![DEFAULT_REST_VELOCITY; dof],
    };
    let cutoff = suggest_cutoff(data).unwrap();
    let velocity = match &data.qd {
        Some(v) => v.clone(),
        None => {
            let sos = butterworth_hz(4, cutoff.cutoff, rate).unwrap();
            data.q
                .try_map(|q| central_difference(&sos.filtfilt(q)?, data.sample_time))
                .unwrap()
        }
    };
    let joints = (0..dof)
        .map(|j| {
            let (q, tau) = (&data.q[j], &data.tau[j]);
            let sq = Spectrum::welch(q, rate).unwrap();
            let st = Spectrum::welch(tau, rate).unwrap();
            let n = q.len() as f64;
            let range = |x: &[f64]| {
                x.iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                        (a.min(*v), b.max(*v))
                    })
            };
            let ((lo, hi), (tlo, thi)) = (range(q), range(tau));
            let span = (thi - tlo).max(f64::MIN_POSITIVE);
            let at_extremes = tau
                .iter()
                .filter(|v| {
                    (thi - **v) <= EXTREME_TOLERANCE * span
                        || (**v - tlo) <= EXTREME_TOLERANCE * span
                })
                .count() as f64
                / n;
            let limit = torque_limits.get(j).copied().flatten();
            let at_limit =
                limit.map(|l| tau.iter().filter(|v| v.abs() >= 0.98 * l).count() as f64 / n);
            let at_rest = velocity[j]
                .iter()
                .filter(|v| v.abs() < rest_velocity[j])
                .count() as f64
                / n;
            let agreement = data.extremes().velocity.get(j).filter(|_| moves(&sq));
            JointReport {
                joint: j + 1,
                moves: moves(&sq),
                position_range: [lo, hi],
                position_bandwidth: position_bandwidth(&sq),
                position_signal_top: sq.above_floor(NOISE_RATIO),
                position_noise: sq.noise_rms(),
                torque_bandwidth: torque_bandwidth(&st),
                torque_noise: st.noise_rms(),
                torque_at_extremes: at_extremes,
                torque_at_limit: at_limit,
                at_rest,
                velocity_scale: agreement.and_then(|a| a.scale()),
                velocity_correlation: agreement.and_then(|a| a.correlation()),
            }
        })
        .collect();
    Inspection {
        name: data.name.clone(),
        sample_rate: rate,
        samples: data.samples(),
        sampling: data.sampling.clone(),
        joints,
        cutoff: Some(cutoff),
        rest_velocity,
    }
}

/// Samples of the test logs.
const SAMPLES: usize = 12_000;
/// Their mean step (s).
const STEP: f64 = 2e-3;

/// Three joints over [`SAMPLES`] samples: joint 1 moves and stops (held still for a
/// third of the time, so that it is at rest then), joint 2 moves all the time, joint 3
/// only vibrates in its noise; the torques follow the positions, joint 1's clipped at
/// +-2.5 N m (many samples at its extremes) and joint 2's reaching a 3 N m limit. Each row
/// is `t, q1..q3, [qd1..qd3,] tau1..tau3`.
fn rows(with_velocity: bool) -> Vec<Vec<f64>> {
    let mut rng = Rng::new(17);
    let two_pi = 2.0 * std::f64::consts::PI;
    let mut rows = Vec::with_capacity(SAMPLES);
    for k in 0..SAMPLES {
        let t = k as f64 * STEP;
        // joint 1: moves for 2 s, then holds for 1 s
        let phase = t % 3.0;
        let moving = phase.min(2.0);
        let q1 = (two_pi * 0.5 * moving).sin() * 0.8 + 1e-5 * rng.normal();
        let qd1 = if phase < 2.0 {
            0.8 * two_pi * 0.5 * (two_pi * 0.5 * moving).cos()
        } else {
            0.0
        };
        let q2 =
            0.6 * (two_pi * 0.7 * t).sin() + 0.1 * (two_pi * 3.0 * t).sin() + 1e-5 * rng.normal();
        let qd2 = 0.6 * two_pi * 0.7 * (two_pi * 0.7 * t).cos();
        let q3 = 1e-4 * rng.normal();
        let tau1 = (4.0 * q1 + 0.01 * rng.normal()).clamp(-2.5, 2.5);
        let tau2 = 5.5 * q2 + 0.01 * rng.normal();
        let tau3 = 0.2 + 0.01 * rng.normal();
        let mut row = vec![t, q1, q2, q3];
        if with_velocity {
            row.extend([qd1, qd2, 1e-3 * rng.normal()]);
        }
        row.extend([tau1, tau2, tau3]);
        rows.push(row);
    }
    rows
}

/// Writes `rows` under `header` to `path`; with `jitter`, each time stamp moves by up to
/// 0.3 of a step (a clock that jitters, which the loader resamples).
fn write(path: &Path, header: &str, rows: &[Vec<f64>], jitter: bool) {
    let mut rng = Rng::new(5);
    let mut text = header.to_string() + "\n";
    for row in rows {
        let mut row = row.clone();
        if jitter && row[0] > 0.0 {
            row[0] += 0.3 * STEP * rng.uniform(-1.0, 1.0);
        }
        let fields: Vec<String> = row.iter().map(|v| format!("{v:.9}")).collect();
        let _ = writeln!(text, "{}", fields.join(","));
    }
    std::fs::write(path, text).unwrap();
}

/// The two inspections as text, every number to the bit (the Debug form of a double is
/// the shortest that reads back as it), but the velocity columns' scale and correlation:
/// a record kept on disk gathers them window by window, each window's strides started
/// afresh, so they agree to 1e-3 (`data::DerivativeAgreement`).
fn same(streamed: &Inspection, whole: &Inspection, what: &str) {
    let mut streamed = streamed.clone();
    for (s, w) in streamed.joints.iter_mut().zip(&whole.joints) {
        for (a, b) in [
            (&mut s.velocity_scale, w.velocity_scale),
            (&mut s.velocity_correlation, w.velocity_correlation),
        ] {
            let close = match (*a, b) {
                (Some(x), Some(y)) => (x - y).abs() <= 1e-3 * y.abs().max(1.0),
                (x, y) => x == y,
            };
            assert!(close, "{what}: joint {}: {a:?} against {b:?}", s.joint);
            *a = b;
        }
    }
    assert_eq!(format!("{streamed:?}"), format!("{whole:?}"), "{what}");
}

/// The inspection read block by block equals the whole record's, to the bit, on a
/// jittered log kept on disk (in windows of a few hundred rows) and loaded in memory, with
/// and without measured velocities, and on two files joined as two sources; for blocks
/// that divide the record and that do not, down to one sample, and the low-pass's padding
/// and one more. The velocities behind the time at rest equal the whole record's too.
#[test]
fn streamed_inspection_equals_the_whole_record_s() {
    let dir = tempfile::tempdir().unwrap();
    let limits = [None, Some(3.0), Some(10.0)];
    for with_velocity in [false, true] {
        let file = dir.path().join(format!("log_{with_velocity}.csv"));
        let header = if with_velocity {
            "t,q1,q2,q3,qd1,qd2,qd3,tau1,tau2,tau3"
        } else {
            "t,q1,q2,q3,tau1,tau2,tau3"
        };
        write(&file, header, &rows(with_velocity), true);
        let velocity = if with_velocity {
            "velocity = \"qd{}\"\n"
        } else {
            ""
        };
        let config = Config::from_toml_str(
            &format!(
                "dof = 3\ntime_column = \"t\"\n[[source]]\nposition = \"q{{}}\"\n{velocity}\
                 torque = \"tau{{}}\"\n[processing]\nrest_velocity = [0.05, 0.02, 0.01]\n"
            ),
            Path::new("log.toml"),
        )
        .unwrap();
        let files = [file.clone()];
        let data = load(&config, &files, 3).unwrap();
        assert!(!data.warnings.is_empty(), "the clock jitters: resampled");
        let reference = whole(&data, &config, &limits);
        // the test means something: joint 1 rests, clips and joint 2 reaches its limit
        let j = &reference.joints;
        // measured 0.277: the low-pass smears the stops
        assert!(j[0].at_rest > 0.2 && j[0].at_rest < 0.4, "{j:?}");
        assert!(j[0].torque_at_extremes > 0.1, "{j:?}");
        assert!(j[1].torque_at_limit.unwrap() > 0.05, "{j:?}");
        // joint 1's velocity column is its positions' derivative, joint 2's leaves out
        // their 3 Hz part (measured: scale 0.66, correlation 0.81), joint 3 does not move
        let scale = j[0].velocity_scale.map(|s| (s * 100.0).round() / 100.0);
        assert_eq!(scale, with_velocity.then_some(1.0), "{j:?}");
        let r = j[1].velocity_correlation;
        assert!(r.is_none_or(|r| r > 0.5 && r < 0.9) && r.is_some() == with_velocity);
        assert_eq!(j[2].velocity_scale, None, "{j:?}");
        let spilled = SpilledRecord::open_in(&config, &files, 3, 20_000)
            .unwrap()
            .expect("one source with a jittered clock is kept on disk");
        assert_eq!(spilled.sampling(), &data.sampling[0]);
        for block in [4096, 1000, 7777, SAMPLES] {
            let s = inspect_in(
                &spilled,
                vec![spilled.sampling().clone()],
                &config,
                &limits,
                block,
            )
            .unwrap();
            same(&s, &reference, &format!("on disk, blocks of {block}"));
        }
        let pad = butterworth_hz(
            4,
            reference.cutoff.as_ref().unwrap().cutoff,
            1.0 / data.sample_time,
        )
        .unwrap()
        .pad_length();
        for block in [1, 2, pad, pad + 1, 999, SAMPLES - 1, SAMPLES + 5] {
            let s = inspect_in(&data, data.sampling.clone(), &config, &limits, block).unwrap();
            same(&s, &reference, &format!("in memory, blocks of {block}"));
        }
    }
    // two sources: positions and torques in two files, at a sample rate, joined
    let all = rows(false);
    let (positions, torques) = (dir.path().join("q.csv"), dir.path().join("tau.csv"));
    let pick = |columns: std::ops::Range<usize>| -> Vec<Vec<f64>> {
        all.iter().map(|r| r[columns.clone()].to_vec()).collect()
    };
    write(&positions, "q1,q2,q3", &pick(1..4), false);
    write(&torques, "tau1,tau2,tau3", &pick(4..7), false);
    let config = Config::from_toml_str(
        &format!(
            "dof = 3\nsample_rate = {}\n[[source]]\nposition = \"q{{}}\"\n[[source]]\ntorque = \"tau{{}}\"\n",
            1.0 / STEP
        ),
        Path::new("two.toml"),
    )
    .unwrap();
    let files: Vec<PathBuf> = vec![positions, torques];
    let data = load(&config, &files, 3).unwrap();
    assert_eq!(data.sampling.len(), 2);
    let reference = whole(&data, &config, &limits);
    for block in [1, 3000, 4097] {
        let s = inspect_in(&data, data.sampling.clone(), &config, &limits, block).unwrap();
        same(&s, &reference, &format!("two sources, blocks of {block}"));
    }
}

/// The velocities the time at rest is counted from, block by block, are those of the
/// whole record (its positions low-passed forward and backward, then differentiated), to
/// the bit, at every sample (the counts alone could hide a wrong value far from the rest
/// velocity).
#[test]
fn streamed_velocities_equal_the_whole_record_s() {
    let rows = rows(false);
    let q: Vec<Vec<f64>> = (1..4)
        .map(|c| rows.iter().map(|r| r[c]).collect())
        .collect();
    let tau: Vec<Vec<f64>> = (4..7)
        .map(|c| rows.iter().map(|r| r[c]).collect())
        .collect();
    let data = Dataset::new(
        "log",
        STEP,
        Signals::new(q).unwrap(),
        Signals::new(tau).unwrap(),
    )
    .unwrap();
    for (order, cutoff) in [(4, 3.0), (3, 40.0), (5, 0.5)] {
        let sos = butterworth_hz(order, cutoff, 1.0 / STEP).unwrap();
        let want: Vec<Vec<f64>> = data
            .q
            .joints()
            .map(|q| central_difference(&sos.filtfilt(q).unwrap(), STEP).unwrap())
            .collect();
        for block in [1, 2, sos.pad_length(), 1000, 4096, SAMPLES - 1, SAMPLES] {
            let mut got = vec![vec![f64::NAN; SAMPLES]; 3];
            let mut visited = 0;
            rest::velocities(
                &data,
                &sos,
                block,
                |part| visited += part.samples(),
                |j, k, v| {
                    for (i, v) in v.iter().enumerate() {
                        assert!(got[j][k + i].is_nan(), "sample {} twice", k + i);
                        got[j][k + i] = *v;
                    }
                },
            )
            .unwrap();
            assert_eq!(visited, SAMPLES, "order {order}, blocks of {block}");
            for (j, (g, w)) in got.iter().zip(&want).enumerate() {
                let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                assert!(
                    bits(g) == bits(w),
                    "order {order}, blocks of {block}, joint {}: first difference at sample {:?}",
                    j + 1,
                    g.iter()
                        .zip(w)
                        .position(|(a, b)| a.to_bits() != b.to_bits())
                );
            }
        }
    }
}
