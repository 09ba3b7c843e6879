//! Class "warnings on poor identifications" of issue 11: a run with condition number 6.9e9
//! and a parameter of -2.2e6 +- 1.0e6 was written without a warning. An identification
//! whose condition number is above `CONDITION_WARNING` or whose parameters have relative
//! standard deviations above `REL_STD_WARNING` percent now says so, naming them, in the
//! estimate (for the caller to print on stderr), the text table and the JSON report.

use tests::fuzz_data;
use tests::scratch::Scratch;

use robid_runtime::data::{Config, PerJoint, load};
use robid_runtime::estimate::{CONDITION_WARNING, QualityWarning, REL_STD_WARNING};
use robid_runtime::pipeline::identify;
use robid_runtime::report::{Report, text_table};
use robots::Ur5e;

fn run(name: &str, motion: &fuzz_data::Motion) -> robid_runtime::pipeline::Identification {
    let tmp = Scratch::new();
    let f = tmp.write(name, &fuzz_data::motion_csv(motion));
    let mut config = Config::default_mapping();
    // every equation, the barely moving joints' too: their poor excitation is the subject
    config.processing.rest_velocity = Some(PerJoint::All(0.0));
    identify(&Ur5e, &load(&config, &[f], 6).unwrap(), &config).unwrap()
}

#[test]
fn a_well_excited_run_has_no_conditioning_warning() {
    let id = run("good.csv", &fuzz_data::motion(600));
    assert!(id.estimate.condition_number < CONDITION_WARNING);
    assert!(
        !id.estimate
            .warnings
            .iter()
            .any(|w| matches!(w, QualityWarning::IllConditioned { .. })),
        "{:?}",
        id.estimate.warnings
    );
}

#[test]
fn a_poorly_excited_run_is_reported_with_the_parameters_named() {
    // the shoulder barely moves: the arm's parameters are nearly confounded
    let id = run(
        "poor.csv",
        &fuzz_data::motion_scaled(600, [1.0, 1e-3, 1.0, 1.0, 1.0, 1.0]),
    );
    let e = &id.estimate;
    assert!(
        e.condition_number > CONDITION_WARNING,
        "{}",
        e.condition_number
    );
    let ill = e
        .warnings
        .iter()
        .find(|w| matches!(w, QualityWarning::IllConditioned { .. }))
        .unwrap_or_else(|| panic!("{:?}", e.warnings));
    assert!(ill.to_string().contains("ill-conditioned"));
    // judged by the larger of each parameter's classical and robust deviations
    let uncertain: Vec<String> = e
        .names
        .iter()
        .zip(e.judged_std().iter().zip(&e.values))
        .filter(|(_, (s, v))| 100.0 * **s / v.abs() > REL_STD_WARNING)
        .map(|(n, _)| n.clone())
        .collect();
    assert!(!uncertain.is_empty());
    match e
        .warnings
        .iter()
        .find(|w| matches!(w, QualityWarning::Uncertain { .. }))
    {
        Some(QualityWarning::Uncertain { parameters, .. }) => assert_eq!(parameters, &uncertain),
        other => panic!("{other:?}"),
    }
    // the table and the JSON say it, naming the parameters
    let report = Report::from_identification(&id, |_| None);
    let table = text_table(&report);
    assert!(
        table.contains("warning: the observation matrix is ill-conditioned")
            && table.contains(&format!("{} (", uncertain[0])),
        "{table}"
    );
    let kinds: Vec<&str> = report.warnings.iter().map(|w| w.kind.as_str()).collect();
    assert!(
        kinds.contains(&"ill_conditioned") && kinds.contains(&"uncertain"),
        "{kinds:?}"
    );
    let named = report
        .warnings
        .iter()
        .find(|w| w.kind == "uncertain")
        .map(|w| w.parameters.clone())
        .unwrap_or_default();
    assert_eq!(named, uncertain);
    let json = report.to_json();
    assert!(
        json.contains("\"kind\": \"ill_conditioned\"")
            && json.contains(&format!("\"parameters\": [\n        \"{}\"", uncertain[0])),
        "{json}"
    );
}

/// Noise-free torques leave the parameters whose value is about 0 with relative standard
/// deviations of 100 % and more, but known to the data's rounding
/// (`robid_runtime::estimate::ROUNDING_EFFECT`): no `uncertain` warning then, while the
/// same motion with its noise has some.
#[test]
fn noise_free_data_leave_no_parameter_uncertain() {
    // 700 samples: relative standard deviations up to 3 300 % (without the noise)
    let noisy = fuzz_data::motion(700);
    let mut exact = noisy.clone();
    let base = fuzz_data::ur5e_base();
    let mut tau = [0.0; 6];
    for k in 0..exact.t.len() {
        let state: [[f64; 6]; 3] =
            std::array::from_fn(|s| std::array::from_fn(|j| exact.signals[s][j][k]));
        robid_runtime::Model::inverse_dynamics_into(
            &Ur5e, &state[0], &state[1], &state[2], &base, &mut tau,
        )
        .unwrap();
        for (j, t) in tau.iter().enumerate() {
            exact.signals[3][j][k] = *t;
        }
    }
    let uncertain = |id: &robid_runtime::pipeline::Identification| {
        id.estimate
            .warnings
            .iter()
            .any(|w| matches!(w, QualityWarning::Uncertain { .. }))
    };
    let id = run("exact.csv", &exact);
    let e = &id.estimate;
    assert!(
        e.rel_std_percent.iter().any(|r| *r > REL_STD_WARNING),
        "{:?}",
        e.rel_std_percent
    );
    assert!(!uncertain(&id), "{:?}", e.warnings);
    assert!(uncertain(&run("noisy.csv", &noisy)));
}
