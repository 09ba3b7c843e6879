//! `cutoff = "auto"` on the bundled real logs: the cutoff chosen from the spectra
//! (robid_runtime::inspect) predicts held-out data within 10 % of the best of a sweep of
//! manual cutoffs. The measure is the relative error against the torque as measured:
//! against the filtered torque a lower cutoff also smooths the target itself, which
//! favours the lowest cutoff whatever it does to the dynamics.
//!
//! - TX40 (5 kHz, positions filtered, torque decimated): trained on rows 0-24750, predicting
//!   rows 29250-45000;
//! - LWR4 (200 Hz, positions, velocities and torques filtered): trained on run 1,
//!   predicting runs 2 and 3.

use std::path::PathBuf;

use robid_runtime::data::{Config, Cutoff, Dataset, load, load_config_files};
use robid_runtime::inspect::resolve_cutoff;
use robid_runtime::pipeline::{identify, validate};
use robots::interpreted::model_for;

fn repo(p: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join(p)
}

/// The prediction errors (against the measured torque) of the validation sets with the
/// cutoff `cutoff`, after training on `train`.
fn errors(
    robot: &str,
    config: &Config,
    cutoff: Cutoff,
    train: &Dataset,
    validation: &[Dataset],
) -> Vec<f64> {
    let text = std::fs::read_to_string(repo(robot)).unwrap();
    let robot = robid_symbolic::Robot::from_toml(&text, robot).unwrap();
    let chosen = model_for(&robot).unwrap();
    let model = chosen.model.as_ref();
    let mut config = config.clone();
    config.processing.lowpass.as_mut().unwrap().cutoff = cutoff;
    let auto = resolve_cutoff(&mut config, train).unwrap();
    assert_eq!(auto.is_some(), cutoff == Cutoff::Auto);
    let id = identify(model, train, &config).unwrap();
    validation
        .iter()
        .map(|d| {
            let p = validate(model, d, &config, &id.estimate.values).unwrap();
            p.unfiltered_fit().unwrap_or_else(|| p.fit()).relative_error
        })
        .collect()
}

/// Asserts that auto's errors are within 10 % of the best of the sweep, set by set.
fn check(name: &str, auto: &[f64], sweep: &[(f64, Vec<f64>)]) {
    for (k, a) in auto.iter().enumerate() {
        let (best_cutoff, best) = sweep
            .iter()
            .map(|(c, e)| (*c, e[k]))
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .unwrap();
        println!(
            "{name} set {k}: auto {:.2} %, best {:.2} % at {best_cutoff} Hz",
            100.0 * a,
            100.0 * best
        );
        assert!(
            *a <= 1.1 * best,
            "{name} set {k}: auto {a} vs {best} at {best_cutoff} Hz"
        );
    }
}

#[test]
fn auto_cutoff_on_the_tx40_log_is_within_10_percent_of_the_best() {
    let robot = "robots/configs/tx40_robot.toml";
    let mut config = Config::from_file(repo("robots/configs/tx40.toml")).unwrap();
    let data = load_config_files(&config, 6).unwrap();
    config.processing.range = Some([0, 24750]);
    config.processing.validation_range = Some([29250, 45000]);
    let run = |c: Cutoff| errors(robot, &config, c, &data, std::slice::from_ref(&data));
    // measured (release): 3 Hz 21.6 %, 8 Hz 17.5 %, 15 Hz 16.7 %, 40 Hz 16.5 %; auto 15 Hz
    let sweep: Vec<(f64, Vec<f64>)> = [3.0, 8.0, 15.0, 25.0, 40.0]
        .into_iter()
        .map(|c| (c, run(Cutoff::Hz(c))))
        .collect();
    check("TX40", &run(Cutoff::Auto), &sweep);
}

#[test]
fn auto_cutoff_on_the_lwr4_logs_is_within_10_percent_of_the_best() {
    let robot = "robots/configs/lwr4_robot.toml";
    let config = Config::from_file(repo("robots/configs/lwr4.toml")).unwrap();
    let train = load_config_files(&config, 7).unwrap();
    let validation: Vec<Dataset> = [2, 3]
        .map(|r| {
            load(
                &config,
                &[repo(&format!(
                    "data/kuka_lwr4/data/measurements_{r}.csv.gz"
                ))],
                7,
            )
            .unwrap()
        })
        .into();
    let run = |c: Cutoff| errors(robot, &config, c, &train, &validation);
    // measured: 1 Hz 2.10 % / 12.88 %, 3 Hz 2.03 % / 13.16 %, 8 Hz 2.03 % / 13.14 %; auto 3.7 Hz
    let sweep: Vec<(f64, Vec<f64>)> = [1.0, 2.0, 4.0, 8.0, 20.0]
        .into_iter()
        .map(|c| (c, run(Cutoff::Hz(c))))
        .collect();
    check("LWR4", &run(Cutoff::Auto), &sweep);
}
