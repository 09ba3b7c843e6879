//! Class "validation" of issue 11: `--validate` with `processing.range` in the config applied
//! the estimation range to the validation file too, so the "validation" repeated the
//! training fit without a word. Each validation file is now processed on its own
//! (`processing.validation_range` when given, else the whole file), and the reports state
//! which rows of which file were used for estimation and for validation; a validation that
//! uses rows of the estimation is a warning.

use tests::fuzz_data;
use tests::scratch::Scratch;

use std::path::PathBuf;

use robid_runtime::data::{Config, load};
use robid_runtime::pipeline::{identify, validate};
use robid_runtime::report::{Report, text_table};
use robots::Ur5e;

const MAPPING: &str = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\nvelocity = \"qd{}\"\n\
                       acceleration = \"qdd{}\"\ntorque = \"tau{}\"\n";

/// A config and two runs in a fresh folder (kept alive by the returned [`Scratch`]).
fn setup(processing: &str) -> (Scratch, Config, PathBuf, PathBuf) {
    let tmp = Scratch::new();
    let d = tmp.dir();
    let config = Config::from_toml_str(
        &format!("{MAPPING}[processing]\n{processing}"),
        &d.join("v.toml"),
    )
    .unwrap();
    let run1 = d.join("run1.csv");
    let run2 = d.join("run2.csv");
    std::fs::write(&run1, fuzz_data::motion_csv(&fuzz_data::motion(500))).unwrap();
    std::fs::write(&run2, fuzz_data::motion_csv(&fuzz_data::motion(450))).unwrap();
    (tmp, config, run1, run2)
}

#[test]
fn the_estimation_range_does_not_apply_to_a_validation_file() {
    let (_tmp, config, run1, run2) = setup("range = [0, 300]\n");
    let data = load(&config, std::slice::from_ref(&run1), 6).unwrap();
    let id = identify(&Ur5e, &data, &config).unwrap();
    assert_eq!(id.used.samples, [0, 300]);
    assert_eq!(id.used.lines, Some([2, 301]));
    // another file: all of it
    let other = load(&config, std::slice::from_ref(&run2), 6).unwrap();
    let p = validate(&Ur5e, &other, &config, &id.estimate.values).unwrap();
    let used = p.used.clone().unwrap();
    assert_eq!(used.samples, [0, 450]);
    assert!(used.file.ends_with("run2.csv"));
    let report = Report::from_identification(&id, |_| None).with_prediction(&p);
    assert!(
        report
            .warnings
            .iter()
            .all(|w| w.kind != "validation_repeats_estimation")
    );
    let table = text_table(&report);
    assert!(
        table.contains("estimation rows: ")
            && table.contains("run1.csv lines 2-301 (samples 0..300)"),
        "{table}"
    );
    assert!(
        table.contains("run2.csv lines 2-451 (samples 0..450)"),
        "{table}"
    );
    let json = report.to_json();
    assert!(
        json.contains("\"estimation\": {") && json.contains("\"rows\": {"),
        "{json}"
    );
    // the same file: the whole of it, which overlaps the estimation rows: a warning
    let p = validate(&Ur5e, &data, &config, &id.estimate.values).unwrap();
    assert_eq!(p.used.as_ref().unwrap().samples, [0, 500]);
    let report = Report::from_identification(&id, |_| None).with_prediction(&p);
    let w = report
        .warnings
        .iter()
        .find(|w| w.kind == "validation_repeats_estimation")
        .expect("a warning");
    assert!(w.message.contains("run1.csv lines 2-501"), "{}", w.message);
}

#[test]
fn a_validation_range_selects_the_validation_rows() {
    let (_tmp, config, run1, _) = setup("range = [0, 300]\nvalidation_range = [320, 500]\n");
    let data = load(&config, std::slice::from_ref(&run1), 6).unwrap();
    let id = identify(&Ur5e, &data, &config).unwrap();
    let p = validate(&Ur5e, &data, &config, &id.estimate.values).unwrap();
    assert_eq!(p.used.as_ref().unwrap().samples, [320, 500]);
    let report = Report::from_identification(&id, |_| None).with_prediction(&p);
    assert!(
        report
            .warnings
            .iter()
            .all(|w| w.kind != "validation_repeats_estimation")
    );
    // an estimation range that ends beyond the file is named, not cut short in silence
    let (_tmp, config, run1, _) = setup("range = [0, 501]\n");
    let data = load(&config, std::slice::from_ref(&run1), 6).unwrap();
    let e = identify(&Ur5e, &data, &config).unwrap_err().to_string();
    assert!(
        e.contains("`processing.range`") && e.contains("which has 500 samples"),
        "{e}"
    );
    // a validation range outside a file is named by its key
    let (_tmp, config, _, run2) = setup("validation_range = [600, 700]\n");
    let other = load(&config, &[run2], 6).unwrap();
    let e = validate(&Ur5e, &other, &config, &id.estimate.values).unwrap_err();
    assert!(
        e.to_string().contains("v.toml:")
            && e.to_string().contains("`processing.validation_range`"),
        "{e}"
    );
}
