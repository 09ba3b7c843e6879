//! The human-readable identification report: a parameter table and the fit.

use std::fmt::Write;

use crate::report::Report;

/// Formats a report as a text table.
pub fn text_table(report: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "robot {}  method {}  equations {}  cond(W) {:.1}",
        report.robot, report.method, report.samples, report.condition_number
    );
    let width = report
        .parameters
        .iter()
        .map(|p| p.name.len())
        .max()
        .unwrap_or(4)
        .max(9);
    let _ = writeln!(
        s,
        "{:<width$}  {:>14}  {:>12}  {:>9}  expression",
        "parameter", "value", "std", "rel.std%"
    );
    for p in &report.parameters {
        let rel = p
            .rel_std_percent
            .map_or_else(|| "-".to_string(), |r| format!("{r:.2}"));
        let _ = writeln!(
            s,
            "{:<width$}  {:>14.6}  {:>12.3e}  {:>9}  {}",
            p.name, p.value, p.std, rel, p.expression
        );
    }
    let joints = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.3}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    let f = &report.fit;
    let _ = writeln!(
        s,
        "fit: relative error {:.2} %, NMSE {:.4}, RMS per joint [{}]",
        100.0 * f.relative_error,
        f.nmse,
        joints(&f.rms_per_joint)
    );
    for v in &report.validation {
        let _ = writeln!(
            s,
            "validation {}: relative error {:.2} %, NMSE {:.4}, RMS per joint [{}]",
            v.file,
            100.0 * v.relative_error,
            v.nmse,
            joints(&v.rms_per_joint)
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimate::{Estimate, Estimator};
    use crate::validate::Fit;

    fn report() -> Report {
        let e = Estimate {
            method: Estimator::Wls,
            names: vec!["MXR2".into(), "Fv1".into()],
            values: vec![2.24, 0.0],
            std: vec![0.04, 0.01],
            rel_std_percent: vec![100.0 * 0.04 / 2.24, f64::INFINITY],
            sigma2: 1.0,
            condition_number: 1019.0,
            residual_rms: vec![1.5],
            rows: 2079,
            weights: None,
        };
        let fit = Fit {
            relative_error: 0.052,
            rms_per_joint: vec![1.5],
            nmse: 3.1,
        };
        Report::new("tx40", &e, &fit, |n| {
            (n == "MXR2").then(|| "MX2 + 0.225 M3".to_string())
        })
        .with_validation(
            "run2.csv",
            &Fit {
                relative_error: 0.02,
                rms_per_joint: vec![0.2],
                nmse: 0.4,
            },
        )
    }

    #[test]
    fn json_has_the_documented_shape() {
        let v: serde_json::Value = serde_json::from_str(&report().to_json()).unwrap();
        assert_eq!(v["robot"], "tx40");
        assert_eq!(v["method"], "wls");
        assert_eq!(v["samples"], 2079);
        assert_eq!(v["condition_number"], 1019.0);
        assert_eq!(v["parameters"][0]["name"], "MXR2");
        assert_eq!(v["parameters"][0]["expression"], "MX2 + 0.225 M3");
        assert!((v["parameters"][0]["rel_std_percent"].as_f64().unwrap() - 1.7857).abs() < 1e-3);
        assert!(v["parameters"][1]["rel_std_percent"].is_null());
        assert_eq!(v["fit"]["nmse"], 3.1);
        assert_eq!(v["validation"][0]["file"], "run2.csv");
        let back: Report = serde_json::from_value(v).unwrap();
        assert_eq!(back, report());
    }

    #[test]
    fn table_lists_parameters_and_fit() {
        let t = text_table(&report());
        assert!(
            t.contains("MXR2") && t.contains("2.240000") && t.contains("MX2 + 0.225 M3"),
            "{t}"
        );
        assert!(t.contains("relative error 5.20 %"), "{t}");
        assert!(t.contains("validation run2.csv"), "{t}");
    }
}
