//! Acceptance (issue 5): the KUKA LWR4+ (FloBaRoID hardware runs, `data/kuka_lwr4`),
//! trained on run 1 and predicting runs 2 and 3, with the processing of the dataset README
//! (`robots/configs/lwr4.toml`) and the LWR4 description with Fv, Fc and Fo per joint
//! (`robots/configs/lwr4_robot.toml`).
//!
//! - run 2 repeats run 1's trajectory: relative error <= 2.5 % (README, pinocchio: 2.03 %);
//! - run 3 is a different, faster trajectory that run 1 does not excite fully (README:
//!   13.1 %). It is printed; only a loose bound is asserted (better than the a-priori URDF
//!   models of the README, 9.6-24.9 %, would need friction too: we assert < 20 %).

use std::path::PathBuf;

use robid_runtime::data::{Config, load, load_config_files};
use robid_runtime::pipeline::{identify, validate};
use robots::interpreted::model_for;

fn repo(p: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join(p)
}

#[test]
fn lwr4_run1_predicts_run2_and_run3() {
    let text = std::fs::read_to_string(repo("robots/configs/lwr4_robot.toml")).unwrap();
    let robot = robid_symbolic::Robot::from_toml(&text, "lwr4_robot.toml").unwrap();
    let chosen = model_for(&robot).unwrap();
    let model = chosen.model.as_ref();
    let config = Config::from_file(repo("robots/configs/lwr4.toml")).unwrap();
    let data = load_config_files(&config, 7).unwrap();
    // the time stamps jitter: resampled with a warning
    assert!(!data.warnings.is_empty());
    let id = identify(model, &data, &config).unwrap();
    let e = &id.estimate;
    println!(
        "LWR4 run 1: {} parameters, {} equations, cond {:.0}, relative error {:.2} %",
        e.names.len(),
        e.rows,
        e.condition_number,
        100.0 * id.fit.relative_error
    );
    assert_eq!(
        e.names.len(),
        64,
        "43 inertial + 21 friction (README: rank 64)"
    );
    let mut errors = Vec::new();
    for run in [2, 3] {
        let file = repo(&format!("data/kuka_lwr4/data/measurements_{run}.csv.gz"));
        let d = load(&config, &[file], 7).unwrap();
        let f = validate(model, &d, &config, &e.values).unwrap().fit();
        println!(
            "LWR4 run {run}: relative error {:.2} %, NMSE {:.4}, RMS {:?}",
            100.0 * f.relative_error,
            f.nmse,
            f.rms_per_joint
        );
        errors.push(f.relative_error);
    }
    // measured: run 2 2.03 %, run 3 13.14 % (a different, faster motion); bounds 1.2x
    assert!(errors[0] <= 0.025, "run 2: {}", errors[0]);
    assert!(errors[1] <= 0.16, "run 3: {}", errors[1]);
}
