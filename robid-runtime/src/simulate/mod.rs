//! Simulation with known truth (docs/identification.md#simulation): forward dynamics of a
//! model in base parameters, integrated along a reference trajectory under a PD tracking
//! controller with computed-torque feed-forward, with Gaussian noise on torques and
//! positions and encoder quantization, reproducible from a seed.
//!
//! ```
//! # use robid_runtime::simulate::{Noise, Simulation};
//! let sim = Simulation { noise: Noise { torque: vec![0.1], ..Noise::default() }, ..Simulation::default() };
//! assert!(sim.check(6).is_ok());
//! ```

mod error;
mod flexible;
mod forward;
mod run;
mod trajectory;

pub use error::SimulateError;
pub use flexible::{Flexibility, FlexibleJoint, FlexibleRecord, TemperatureProfile};
pub use forward::ForwardDynamics;
pub use run::{
    DIVERGENCE_FACTOR, MAX_BANDWIDTH, MAX_SIMULATION_STEPS, MAX_SUBSTEPS, Noise, Simulated,
    Simulation,
};
pub use trajectory::{ACCELERATION_DRIFT, Record, Trajectory};

#[cfg(test)]
pub(crate) mod tests;

#[cfg(test)]
pub(crate) mod run_tests {
    use super::tests::Pendulum;
    use super::*;
    use crate::signal::Signals;
    use crate::{DataError, Error, Model};

    /// A smooth reference starting at rest.
    pub(crate) fn reference(seconds: f64, rate: f64) -> Trajectory {
        let n = (seconds * rate) as usize;
        let t: Vec<f64> = (0..n).map(|k| k as f64 / rate).collect();
        let mut tr = Trajectory::zeros(2, t.clone());
        for (k, &t) in t.iter().enumerate() {
            for j in 0..2 {
                let w = 1.3 + 0.7 * j as f64;
                let a = 0.8 / (j + 1) as f64;
                tr.q[j][k] = a * (1.0 - (w * t).cos()) + 0.2 * (1.0 - (2.9 * w * t).cos());
                tr.qd[j][k] = a * w * (w * t).sin() + 0.2 * 2.9 * w * (2.9 * w * t).sin();
                tr.qdd[j][k] =
                    a * w * w * (w * t).cos() + 0.2 * 2.9 * 2.9 * w * w * (2.9 * w * t).cos();
            }
        }
        tr
    }

    #[test]
    fn tracks_the_reference_and_torques_match_the_inverse_dynamics() {
        let p = Pendulum::default();
        let base = p.base();
        let r = reference(5.0, 500.0);
        let out = Simulation::default().run(&p, &base, &r).unwrap();
        let tr = &out.truth.trajectory;
        let err = (0..r.samples())
            .map(|k| {
                (tr.q[0][k] - r.q[0][k])
                    .abs()
                    .max((tr.q[1][k] - r.q[1][k]).abs())
            })
            .fold(0.0, f64::max);
        // measured 6.1e-13 rad (the comment said 2.48e-5, from an earlier integrator)
        assert!(err < 5e-5, "tracking error {err}");
        // the recorded (q, qd, qdd, tau) satisfy the model
        let mut tau = [0.0; 2];
        for k in (10..r.samples()).step_by(37) {
            let s = |v: &Signals| [v[0][k], v[1][k]];
            p.inverse_dynamics_into(&s(&tr.q), &s(&tr.qd), &s(&tr.qdd), &base, &mut tau)
                .unwrap();
            for (t, truth) in tau.iter().zip(out.truth.tau.joints()) {
                assert!((t - truth[k]).abs() < 1e-9);
            }
        }
        // without noise the measurement is the truth; the run is reproducible
        assert_eq!(out.measured.tau, out.truth.tau);
        let noisy = Simulation {
            noise: Noise {
                torque: vec![0.5],
                position: 1e-4,
                quantization: 1e-3,
                ..Noise::default()
            },
            ..Simulation::default()
        };
        let a = noisy.run(&p, &base, &r).unwrap();
        let b = noisy.run(&p, &base, &r).unwrap();
        assert_eq!(a.measured.tau, b.measured.tau);
        let d: Vec<f64> = (0..r.samples())
            .map(|k| a.measured.tau[0][k] - a.truth.tau[0][k])
            .collect();
        let sd = (d.iter().map(|x| x * x).sum::<f64>() / d.len() as f64).sqrt();
        // 4 standard errors of a standard deviation from n = 2500 samples: 4 * 0.5 / sqrt(2n)
        // (measured 0.4988)
        let se = 0.5 / (2.0 * d.len() as f64).sqrt();
        assert!((sd - 0.5).abs() < 4.0 * se, "{sd}");
    }

    #[test]
    fn bad_settings_are_rejected() {
        let p = Pendulum::default();
        let r = reference(0.1, 100.0);
        let bad = Simulation {
            substeps: 0,
            ..Simulation::default()
        };
        assert!(bad.run(&p, &p.base(), &r).is_err());
        let bad = Simulation {
            noise: Noise {
                torque: vec![0.1; 3],
                ..Noise::default()
            },
            ..Simulation::default()
        };
        assert!(bad.run(&p, &p.base(), &r).is_err());
    }

    /// The step cap counts the Runge-Kutta splits of every substep: a plant whose second
    /// link has a viscous friction of 1e6 N m s/rad on 0.3 kg m^2 splits every substep
    /// hundreds of times, and a run the check before it allows (samples x substeps within
    /// the cap) ran that many times longer than the check bounds (up to 1,000: hours).
    /// Here the cap is lowered to 1e5 for this thread so that the run that crosses it stops
    /// at once: 400 samples x 10 substeps pass the check before the run, their splits do
    /// not (without the count the run ends, after more than a million steps). The stiff
    /// plant is named with the fix; 10 samples of it run.
    #[test]
    fn the_step_cap_counts_the_splits_of_a_stiff_plant() {
        let p = Pendulum::default();
        let mut stiff = p.base();
        stiff[8] = 1e6;
        let r = reference(0.8, 500.0);
        let cap = 100_000;
        run::STEP_CAP.with(|c| c.set(cap));
        let result = Simulation::default().run(&p, &stiff, &r);
        // a plant as stiff, but for a run within the cap: it runs
        let short = Simulation::default().run(&p, &stiff, &reference(0.02, 500.0));
        run::STEP_CAP.with(|c| c.set(MAX_SIMULATION_STEPS));
        assert!(short.is_ok(), "{short:?}");
        let e = result.unwrap_err().to_string();
        assert!(
            e.starts_with("Runge-Kutta steps of the simulation, reached after reference sample ")
                && e.contains("splits each substep into")
                && e.contains(&format!("is more than the limit of {cap}"))
                && e.contains("a large viscous friction")
                && e.contains("lower the bandwidth (--bandwidth)"),
            "{e}"
        );
    }

    /// A viscous friction whose rate over its link's inertia needs each substep split
    /// beyond the cap (Fv2 = 1e6 N m s/rad on the second link at 100 Hz and 10 substeps:
    /// 2690 Runge-Kutta steps) stops at its first sample, naming the rate, the split, Fv2 with
    /// its value and the inertia; the split clamped to 1,000 let the run diverge, and the
    /// message said to raise the bandwidth. The same plant at 500 Hz (538 steps) runs.
    #[test]
    fn a_viscous_friction_beyond_the_split_cap_is_named() {
        let p = Pendulum::default();
        let mut stiff = p.base();
        assert_eq!(p.base_parameter_name(8), Some("Fv2"));
        stiff[8] = 1e6;
        let e = Simulation::default()
            .run(&p, &stiff, &reference(0.1, 100.0))
            .unwrap_err();
        let text = e.to_string();
        assert!(
            matches!(
                e,
                Error::Simulate(SimulateError::TooStiff { sample: 0, .. })
            ) && text.starts_with("the simulation cannot follow the plant at t = 0 s")
                && text.contains("more than the limit of 1000")
                && text.contains("nothing was written")
                && text.contains("the viscous friction of joint 2, Fv2 = 1e6 N m s/rad")
                && text.contains("kg m^2 at this state, 1 / (M^-1)22"),
            "{text}"
        );
        Simulation::default()
            .run(&p, &stiff, &reference(0.1, 500.0))
            .unwrap();
    }

    /// An encoder resolution below `MIN_RESOLUTION` (1e-320, meant as 0) is refused naming
    /// the setting; it used to overflow `q / resolution` and end the run as "diverged" at
    /// its first sample. 0 and the smallest accepted resolution run.
    #[test]
    fn a_resolution_too_fine_for_any_encoder_is_refused() {
        let p = Pendulum::default();
        let r = reference(0.1, 100.0);
        let with = |quantization: f64| Simulation {
            noise: Noise {
                quantization,
                ..Noise::default()
            },
            ..Simulation::default()
        };
        for tiny in [1e-320, 1e-300, 1e-13] {
            let e = with(tiny).run(&p, &p.base(), &r).unwrap_err().to_string();
            assert!(
                e.contains("`noise.quantization`") && e.contains("must be 0 or at least 1e-12"),
                "{e}"
            );
        }
        for fine in [0.0, crate::limits::MIN_RESOLUTION] {
            with(fine).run(&p, &p.base(), &r).unwrap();
        }
    }

    #[test]
    fn csv_round_trip() {
        let r = reference(0.2, 100.0);
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("traj.csv");
        r.write_csv(&f).unwrap();
        let back = Trajectory::read_csv(&f, 2).unwrap();
        assert_eq!(back.samples(), r.samples());
        // written to ten significant digits: at most half a unit of the last, 5e-10 of the
        // value, plus the parse's rounding (measured 4.8e-11 of 0.0202)
        assert!((back.q[1][7] - r.q[1][7]).abs() < 6e-10 * r.q[1][7].abs());
        assert!(Trajectory::read_csv(&f, 3).is_err());
        // a negative zero is written as zero (-0.000000000e0 was written)
        let mut z = reference(0.2, 100.0);
        z.qd[0][0] = -0.0;
        z.write_csv(&f).unwrap();
        let text = std::fs::read_to_string(&f).unwrap();
        assert!(!text.contains("-0.000000000e0"), "{}", &text[..200]);
    }

    /// A trajectory's time stamps follow the rule of identification data: a mean step
    /// giving a rate outside [1e-3, 1e7] Hz is refused, by the reader naming the file and
    /// by `Simulation::run` naming the trajectory, exactly when the loader refuses the
    /// same file as data (steps of 1e6 s used to be simulated, or diverge, and write data
    /// that `robid identify` refuses).
    #[test]
    fn time_stamps_at_a_rate_identification_refuses_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let p = Pendulum::default();
        // mean steps: the last two accepted, the others not
        for (steps, accepted) in [
            (vec![1e6; 4], false),
            (vec![1e-9; 4], false),
            // regular steps with one gap of 1e6 s: a mean step of 2e5 s
            (vec![0.01, 0.01, 0.01, 0.01, 1e6], false),
            (vec![1e3 + 1.0; 3], false),
            (vec![1e3; 3], true),
            (vec![0.001, 0.004, 0.002], true),
        ] {
            let t: Vec<f64> = std::iter::once(0.0)
                .chain(steps.iter().scan(0.0, |t, d| {
                    *t += d;
                    Some(*t)
                }))
                .collect();
            let (f, read, loaded) = read_both_ways(dir.path(), &t);
            assert_eq!(read.is_ok(), accepted, "{steps:?}: {read:?}");
            assert_eq!(loaded.is_ok(), accepted, "{steps:?}: {:?}", loaded.err());
            if accepted {
                continue;
            }
            let run = Simulation::default().run(&p, &p.base(), &Trajectory::zeros(2, t));
            for (e, place) in [
                (read.unwrap_err(), f.display().to_string()),
                (run.unwrap_err(), "reference trajectory".to_string()),
            ] {
                let text = e.to_string();
                assert!(
                    matches!(e, Error::Data(DataError::SampleRate { .. }))
                        && text.starts_with(&format!("{place}: time stamps "))
                        && text.contains("outside [1e-3, 1e7] Hz")
                        && text.contains("`t` must be in seconds"),
                    "{text}"
                );
            }
        }
    }

    /// The time column of the CSV file `f`, as written.
    pub(crate) fn written_times(f: &std::path::Path) -> Vec<f64> {
        std::fs::read_to_string(f)
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').next().unwrap().parse().unwrap())
            .collect()
    }

    /// A reference on Unix time stamps (from 1.7336e9 s at 500 Hz) or from 1e6 s at 2 kHz
    /// is simulated, and its record, its log and the reference itself are written with the
    /// very time stamps of the reference, which the data loader and the trajectory reader
    /// take back without a repair: the time was written to ten significant digits, which
    /// repeated every stamp within a second (1.733600000e9) or a millisecond
    /// (1.000000000e6), and `robid identify` refused the file `simulate` had written.
    #[test]
    fn large_time_stamps_are_written_as_they_were_given() {
        let dir = tempfile::tempdir().unwrap();
        let p = Pendulum::default();
        for (start, rate) in [(1.7336e9, 500.0), (1e6, 2000.0)] {
            let mut r = reference(0.2, rate);
            r.t.iter_mut().for_each(|t| *t += start);
            let sim = Simulation::default().run(&p, &p.base(), &r).unwrap();
            let (record, log, traj) = (
                dir.path().join("record.csv"),
                dir.path().join("log.csv"),
                dir.path().join("traj.csv"),
            );
            sim.measured.write_csv(&record).unwrap();
            sim.measured.write_log_csv(&log, 1, None).unwrap();
            r.write_csv(&traj).unwrap();
            for f in [&record, &log, &traj] {
                assert_eq!(written_times(f), r.t, "{start}: {}", f.display());
            }
            let back = Trajectory::read_csv(&traj, 2).unwrap();
            assert_eq!(back.t, r.t);
            for f in [&record, &log] {
                let header: Vec<String> = std::fs::read_to_string(f)
                    .unwrap()
                    .lines()
                    .next()
                    .unwrap()
                    .split(',')
                    .map(str::to_string)
                    .collect();
                let data = crate::data::load(
                    &crate::data::Config::default_mapping_for(&header),
                    std::slice::from_ref(f),
                    2,
                )
                .unwrap();
                assert_eq!(data.q.samples(), r.samples(), "{start}: {}", f.display());
                assert!(
                    (data.sample_time * rate - 1.0).abs() < 1e-3 && data.warnings.is_empty(),
                    "{start}: {} {:?}",
                    data.sample_time,
                    data.warnings
                );
            }
        }
    }

    /// A still two-joint trajectory at the times `t` written to `traj.csv` in `dir`, read
    /// as a trajectory and loaded as data: (its path, the trajectory, the data set).
    fn read_both_ways(
        dir: &std::path::Path,
        t: &[f64],
    ) -> (
        std::path::PathBuf,
        crate::Result<Trajectory>,
        crate::Result<crate::data::Dataset>,
    ) {
        let f = dir.join("traj.csv");
        let rows: Vec<String> = t.iter().map(|t| format!("{t},0,0,0,0,0,0,0,0")).collect();
        let header = "t,q1,q2,qd1,qd2,qdd1,qdd2,tau1,tau2";
        std::fs::write(&f, format!("{header}\n{}\n", rows.join("\n"))).unwrap();
        let read = Trajectory::read_csv(&f, 2);
        let loaded = crate::data::load(
            &crate::data::Config::default_mapping(),
            std::slice::from_ref(&f),
            2,
        );
        (f, read, loaded)
    }

    /// A trajectory whose time stamps pause (a step of more than `GAP_RATIO` median
    /// steps) is refused, by the reader naming the file and line and by `Simulation::run`
    /// naming the sample, exactly when the loader refuses the same file as data: the data
    /// simulated across the gap used to be written, for `robid identify` to refuse.
    #[test]
    fn time_stamps_with_a_gap_are_refused_as_identification_refuses_them() {
        let dir = tempfile::tempdir().unwrap();
        let p = Pendulum::default();
        for (gap, accepted) in [(0.2, false), (0.11, false), (0.09, true)] {
            // 30 steps of 10 ms, the 21st replaced by the gap
            let t: Vec<f64> = (0..=30)
                .map(|k| 0.01 * k as f64 + if k > 20 { gap - 0.01 } else { 0.0 })
                .collect();
            let (f, read, loaded) = read_both_ways(dir.path(), &t);
            assert_eq!(read.is_ok(), accepted, "{gap}: {read:?}");
            assert_eq!(loaded.is_ok(), accepted, "{gap}: {:?}", loaded.err());
            if accepted {
                continue;
            }
            let run = Simulation::default().run(&p, &p.base(), &Trajectory::zeros(2, t));
            for (e, place) in [
                (read.unwrap_err(), format!("{}:23", f.display())),
                (
                    run.unwrap_err(),
                    "reference trajectory, sample 21 (t = ".to_string(),
                ),
            ] {
                let text = e.to_string();
                assert!(
                    matches!(e, Error::Data(DataError::TimeGap { .. }))
                        && text.starts_with(&place)
                        && text.contains("the time stamps jump from 0.2 s to ")
                        && text.contains("split it at the gap into two trajectories"),
                    "{text}"
                );
            }
        }
    }
}
