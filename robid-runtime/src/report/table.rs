//! The human-readable identification report: a parameter table and the fit.

use std::fmt::Write;

use crate::report::Report;

/// The width of a table's parameter-name column: the longest name, at least that of the
/// header `parameter`.
pub(crate) fn name_width<'a>(names: impl Iterator<Item = &'a str>) -> usize {
    names.map(str::len).max().unwrap_or(0).max(9)
}

/// Formats a report as a text table.
pub fn text_table(report: &Report) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "robot {}  method {}  equations {}  cond(W) {:.1}  error bound {:.1} % (worst case: \
         cond(W) x relative residual)",
        report.robot,
        report.method,
        report.samples,
        report.condition_number,
        report.error_bound_percent
    );
    if let Some(scaled) = report.scaled_condition_number {
        let _ = writeln!(
            s,
            "cond(W) with unit-norm columns {scaled:.1} (the same in any units of the \
             parameters; cond(W) above, and the error bound with it, are of W in its units)"
        );
    }
    if let Some(rows) = &report.estimation {
        let _ = writeln!(s, "estimation rows: {rows}");
    }
    if let Some(pieces) = &report.pieces {
        // the rows above are those the fit covers; the estimate used only the pieces
        let windows: Vec<String> = pieces
            .iter()
            .map(|[a, b]| format!("{}-{}", crate::Num(*a), crate::Num(*b)))
            .collect();
        let _ = writeln!(
            s,
            "estimated on {} of them (processing.pieces, s from the record's first sample: \
             {}); the fit below covers all of the rows",
            crate::Count(pieces.len(), "piece"),
            windows.join(", ")
        );
    }
    if let Some(g) = &report.segments {
        s.push_str(&g.text("estimation"));
    }
    let width = name_width(report.parameters.iter().map(|p| p.name.as_str()));
    // the robust deviations after the classical columns, which keep their places
    let robust = report.parameters.iter().any(|p| p.robust_std.is_some());
    let _ = writeln!(
        s,
        "{:<width$}  {:>14}  {:>12}  {:>9}  {}expression",
        "parameter",
        "value",
        "std",
        "rel.std%",
        if robust {
            format!("{:>12}  ", "robust std")
        } else {
            String::new()
        }
    );
    for p in &report.parameters {
        let rel = match p.rel_std_percent {
            _ if p.known => "known".to_string(),
            Some(r) => fixed(r, 2),
            None => "-".to_string(),
        };
        let robust_std = match p.robust_std {
            Some(r) if robust => format!("{r:>12.3e}  "),
            _ if robust => format!("{:>12}  ", "-"),
            _ => String::new(),
        };
        let _ = writeln!(
            s,
            "{:<width$}  {:>14}  {:>12.3e}  {:>9}  {robust_std}{}",
            p.name,
            value(p.value),
            p.std,
            rel,
            p.expression
        );
    }
    if let Some(lag) = report.robust_lag.filter(|_| robust) {
        let _ = writeln!(
            s,
            "std: sigma^2 (W'W)^-1, for independent residuals; robust std: Newey-West over \
             {lag} lags (docs/identification.md#statistics), for the residuals' correlation \
             by the filters: believe the larger"
        );
    }
    let joints = |v: &[f64]| v.iter().map(|x| fixed(*x, 3)).collect::<Vec<_>>().join(" ");
    if let Some(c) = &report.cutoff {
        let _ = writeln!(s, "low-pass cutoff (auto): {} Hz: {}", c.cutoff, c.reason);
    }
    let f = &report.fit;
    let unit = &report.torque_unit;
    let _ = writeln!(
        s,
        "fit: relative error {} %{}, NMSE {} (eq. 22: {} {unit}), RMS per joint [{}]",
        fixed(100.0 * f.relative_error, 2),
        against(f.torque.as_deref(), f.unfiltered_relative_error),
        fixed(f.nmse, 4),
        fixed(f.nmse_eq22, 1),
        joints(&f.rms_per_joint)
    );
    for v in &report.validation {
        let file = v
            .rows
            .as_ref()
            .map_or_else(|| v.file.clone(), |r| r.to_string());
        let _ = writeln!(
            s,
            "validation {file}: relative error {} %{}, NMSE {} (eq. 22: {} {unit}), RMS per joint [{}]",
            fixed(100.0 * v.relative_error, 2),
            against(v.torque.as_deref(), v.unfiltered_relative_error),
            fixed(v.nmse, 4),
            fixed(v.nmse_eq22, 1),
            joints(&v.rms_per_joint)
        );
        if let Some(g) = &v.segments {
            s.push_str(&g.text("  validation"));
        }
        if let Some(r) = &v.reference {
            let improvement = r.relative_improvement_percent.map_or_else(
                || "none (the reference predicts these data to rounding)".to_string(),
                improvement,
            );
            let _ = writeln!(
                s,
                "  against the reference {}: relative error {} % (identified {} %); NMSE (eq. 22) {} {unit}, identified {} {unit}, relative improvement {improvement}",
                r.file,
                small_too(100.0 * r.relative_error, 2),
                fixed(100.0 * v.relative_error, 2),
                small_too(r.nmse_eq22, 1),
                small_too(v.nmse_eq22, 1)
            );
        }
    }
    if let Some(r) = &report.runs {
        s.push_str(&r.text());
    }
    for w in &report.warnings {
        let _ = writeln!(s, "warning: {}", w.message);
    }
    s
}

/// What a relative error compares with: ` (measured torque)`, or for a filtered torque
/// ` (filtered torque; X % against the measured torque)`; nothing when not known.
fn against(torque: Option<&str>, unfiltered: Option<f64>) -> String {
    match (torque, unfiltered) {
        (Some("filtered"), Some(u)) => format!(
            " (filtered torque; {} % against the measured torque)",
            fixed(100.0 * u, 2)
        ),
        (Some(t), _) => format!(" ({t} torque)"),
        (None, _) => String::new(),
    }
}

/// `x` with `decimals` decimals while that is short (|x| < 1e6), else to 4 significant
/// digits ([`Num::rounded`](crate::Num::rounded)): an NMSE of 218822021577.1579 is
/// 2.188e11.
/// A parameter value for the table: six decimals from 1e-3 up, five significant digits
/// in exponent form below (a rotor inertia of 2.3e-5 kg m^2 read 0.000023, a value of
/// -1e-9 read -0.000000), and a zero as 0.
pub(crate) fn value(x: f64) -> String {
    if x == 0.0 {
        "0".to_owned()
    } else if x.abs() < 1e-3 {
        format!("{x:.4e}")
    } else {
        fixed(x, 6)
    }
}

/// `x` with `decimals` decimals below 1e6 in magnitude, else to four significant digits
/// in exponent form (a relative deviation of 3332612825004613.00 % was written whole).
///
/// ```
/// use robid_runtime::report::fixed;
/// assert_eq!(fixed(12.345, 2), "12.35");
/// assert_eq!(fixed(3332612825004613.0, 2), "3.333e15");
/// ```
pub fn fixed(x: f64, decimals: usize) -> String {
    if x.abs() < 1e6 {
        format!("{x:.decimals$}")
    } else {
        crate::Num::rounded(x, 4).to_string()
    }
}

/// [`fixed`], but a value too small for its decimals in three significant digits: the
/// NMSE of a model that predicts its data to 1e-8 was written "0.0" beside a relative
/// improvement of -7.4e10 %.
pub(crate) fn small_too(x: f64, decimals: usize) -> String {
    if x != 0.0 && x.abs() < 0.5 * 10f64.powi(-(decimals as i32)) {
        crate::Num::rounded(x, 3).to_string()
    } else {
        fixed(x, decimals)
    }
}

/// A relative improvement `p` (percent) in words: to one decimal, or, where the
/// identified model's NMSE is more than ten times the reference's, as that ratio
/// ("-74009615578.6 %" of a reference that predicts the data to 5e-8 said little).
pub(crate) fn improvement(p: f64) -> String {
    if p < -900.0 {
        format!(
            "none: the identified model's NMSE is {} times the reference's",
            crate::Num::rounded(1.0 - p / 100.0, 3)
        )
    } else {
        // `-0.0 %` for a change that rounds to nothing
        format!("{:.1} %", if p.abs() < 0.05 { 0.0 } else { p })
    }
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
            scaled_condition_number: Some(41.3),
            error_bound: 0.25,
            residual_rms: vec![1.5],
            rows: 2079,
            weights: None,
            warnings: crate::estimate::assess(
                1019.0,
                &["MXR2".into(), "Fv1".into()],
                &[100.0 * 0.04 / 2.24, f64::INFINITY],
                &[f64::INFINITY; 2],
            ),
            known: Vec::new(),
            robust: None,
        };
        let fit = Fit {
            relative_error: 0.052,
            rms_per_joint: vec![1.5],
            nmse: 3.1,
            nmse_eq22: 250.0,
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
                nmse_eq22: 30.0,
            },
        )
    }

    /// The torque unit follows the joints (eq. 22's NMSE of a prismatic-only robot was
    /// labelled N m), in the text, the HTML and the JSON read back; figures too large for
    /// fixed decimals are rounded (an NMSE of 218822021577.1579 was written whole).
    #[test]
    fn the_figures_are_in_the_joints_unit_and_rounded_when_huge() {
        let mut r = report().with_validation(
            "wild.csv",
            &Fit {
                relative_error: 4.2e7,
                rms_per_joint: vec![3.5e9],
                nmse: 218822021577.1579,
                nmse_eq22: 1.5e13,
            },
        );
        r.set_units(&crate::report::joint_units(&[true], 1));
        let t = text_table(&r);
        assert!(t.contains("(eq. 22: 250.0 N), RMS"), "{t}");
        assert!(
            t.contains("validation wild.csv: relative error 4.2e9 %, NMSE 2.188e11 (eq. 22: 1.5e13 N), RMS per joint [3.5e9]"),
            "{t}"
        );
        let h = crate::report::html_report(&r, &[]).unwrap();
        assert!(
            h.contains("NMSE eq. 22 [N]</th><th>RMS per joint [N]"),
            "{h}"
        );
        assert!(h.contains("<td>2.188e11</td>"), "{h}");
        let back: Report = serde_json::from_str(&r.to_json()).unwrap();
        assert_eq!(back.torque_unit, "N");
        assert_eq!(back.joint_units, ["N"]);
        // a report written before the unit was recorded is of a revolute arm
        let mut old: serde_json::Value = serde_json::from_str(&report().to_json()).unwrap();
        old.as_object_mut().unwrap().remove("torque_unit");
        let old: Report = serde_json::from_value(old).unwrap();
        assert_eq!(old.torque_unit, "N m");
    }

    /// A reference model's prediction of a validation file: its eq. 22 NMSE and the
    /// relative improvement of the identified model (Madsen et al.'s Table 5, row 1:
    /// 325.9 -> 233.0 is 28.5 %), in the JSON, the table and the check; none when the
    /// reference is exact.
    #[test]
    fn a_reference_gives_the_relative_improvement() {
        let fit = |nmse_eq22| Fit {
            relative_error: 0.03,
            rms_per_joint: vec![0.3],
            nmse: 0.5,
            nmse_eq22,
        };
        let r = report()
            .with_validation("run3.csv", &fit(233.0))
            .with_reference(1, "cad.toml", &fit(325.9));
        let v: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
        assert!(v["validation"][0]["reference"].is_null());
        let reference = &v["validation"][1]["reference"];
        assert_eq!(reference["file"], "cad.toml");
        assert_eq!(reference["nmse_eq22"], 325.9);
        let p = reference["relative_improvement_percent"].as_f64().unwrap();
        // (325.9 - 233) / 325.9 = 28.5057 %, to two decimals: half a unit is 0.005
        assert!((p - 28.51).abs() < 0.005, "{p}");
        assert!(r.check().is_ok());
        let t = text_table(&r);
        assert!(
            t.contains("against the reference cad.toml: relative error 3.00 % (identified 3.00 %); NMSE (eq. 22) 325.9 N m, identified 233.0 N m, relative improvement 28.5 %"),
            "{t}"
        );
        let exact = report().with_reference(0, "truth.toml", &fit(0.0));
        assert!(
            exact.validation[0]
                .reference
                .as_ref()
                .unwrap()
                .relative_improvement_percent
                .is_none()
        );
        assert!(
            text_table(&exact).contains("none (the reference predicts these data to rounding)")
        );
        // a reference far better than the identified model: the ratio, and NMSEs that
        // do not round to 0.0
        let near = Fit {
            relative_error: 5e-8,
            nmse_eq22: 5e-11,
            ..fit(0.0)
        };
        let t = text_table(&report().with_reference(0, "near.toml", &near));
        assert!(
            t.contains("against the reference near.toml: relative error 5e-6 % (identified 2.00 %); NMSE (eq. 22) 5e-11 N m, identified 30.0 N m, relative improvement none: the identified model's NMSE is 6e11 times the reference's"),
            "{t}"
        );
        // two rounding errors have no relative improvement (it said -13 %)
        let rounding = Fit {
            relative_error: 1e-14,
            nmse_eq22: 1e-20,
            ..fit(0.0)
        };
        let both = report()
            .with_validation(
                "run3.csv",
                &Fit {
                    nmse_eq22: 1.13e-20,
                    ..rounding.clone()
                },
            )
            .with_reference(1, "truth.toml", &rounding);
        assert!(
            both.validation[1]
                .reference
                .as_ref()
                .unwrap()
                .relative_improvement_percent
                .is_none()
        );
        let bad = report().with_reference(0, "cad.toml", &fit(f64::NAN));
        assert!(bad.check().is_err());
    }

    /// A parameter fixed by known values says so in the table and the JSON, and the others
    /// carry no flag.
    #[test]
    fn known_parameters_are_marked() {
        let mut r = report();
        let row = |t: &str| {
            t.lines()
                .find(|l| l.starts_with("MXR2"))
                .unwrap()
                .to_string()
        };
        assert!(!row(&text_table(&r)).contains("known"));
        let v: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
        assert!(v["parameters"][0].get("known").is_none());
        r.parameters[0].known = true;
        assert!(row(&text_table(&r)).contains("known"));
        let v: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
        assert_eq!(v["parameters"][0]["known"], true);
    }

    #[test]
    fn json_has_the_documented_shape() {
        let v: serde_json::Value = serde_json::from_str(&report().to_json()).unwrap();
        assert_eq!(v["robot"], "tx40");
        assert_eq!(v["method"], "wls");
        assert_eq!(v["samples"], 2079);
        assert_eq!(v["condition_number"], 1019.0);
        // Milella's bound, as a percentage, in the JSON and the table
        assert_eq!(v["error_bound_percent"], 25.0);
        assert!(v["runs"].is_null());
        // the bound is said to be a worst case (a headline of 15686 % read as the error)
        assert!(text_table(&report()).contains(
            "cond(W) 1019.0  error bound 25.0 % (worst case: cond(W) x relative residual)\n"
        ));
        // beside it, the units-free figure (a new line: the raw one's is unchanged)
        assert_eq!(v["scaled_condition_number"], 41.3);
        assert!(text_table(&report()).contains(
            "residual)\ncond(W) with unit-norm columns 41.3 (the same in any units of the parameters"
        ));
        let mut bad = report();
        bad.scaled_condition_number = Some(f64::NAN);
        assert!(bad.check().is_err());
        // a report written before it was recorded reads back without it
        let mut old = v.clone();
        old.as_object_mut()
            .unwrap()
            .remove("scaled_condition_number");
        let old: Report = serde_json::from_value(old).unwrap();
        assert_eq!(old.scaled_condition_number, None);
        assert!(!text_table(&old).contains("unit-norm"));
        let mut bad = report();
        bad.error_bound_percent = f64::INFINITY;
        assert!(bad.check().is_err());
        assert_eq!(v["parameters"][0]["name"], "MXR2");
        assert_eq!(v["parameters"][0]["expression"], "MX2 + 0.225 M3");
        // 1.785714... to four decimals: half a unit is 5e-5
        assert!((v["parameters"][0]["rel_std_percent"].as_f64().unwrap() - 1.7857).abs() < 5e-5);
        assert!(v["parameters"][1]["rel_std_percent"].is_null());
        assert_eq!(v["fit"]["nmse"], 3.1);
        assert_eq!(v["fit"]["nmse_eq22"], 250.0);
        assert_eq!(v["validation"][0]["nmse_eq22"], 30.0);
        assert_eq!(v["validation"][0]["file"], "run2.csv");
        assert_eq!(v["warnings"][0]["kind"], "uncertain");
        assert_eq!(v["warnings"][0]["parameters"][0], "Fv1");
        let back: Report = serde_json::from_value(v).unwrap();
        assert_eq!(back, report());
    }

    /// The run of the issue: cond 6.9e9 and a parameter of -2.2e6 +- 1.0e6 was written
    /// without a word; now the table and the JSON say so and name the parameter.
    #[test]
    fn an_ill_conditioned_run_is_reported_as_such() {
        let names: Vec<String> = vec!["ZZR1".into(), "MXR2".into()];
        let e = Estimate {
            method: Estimator::Ols,
            names: names.clone(),
            values: vec![1.2, -2.2e6],
            std: vec![0.01, 1.0e6],
            rel_std_percent: vec![0.83, 45.45],
            sigma2: 1.0,
            condition_number: 6.9e9,
            scaled_condition_number: Some(3.5e3),
            error_bound: 12.0,
            residual_rms: vec![1.0],
            rows: 100,
            weights: None,
            warnings: crate::estimate::assess(6.9e9, &names, &[0.83, 45.45], &[f64::INFINITY; 2]),
            known: Vec::new(),
            robust: None,
        };
        let fit = Fit {
            relative_error: 0.1,
            rms_per_joint: vec![1.0],
            nmse: 1.0,
            nmse_eq22: 1.0,
        };
        let r = Report::new("x", &e, &fit, |_| None);
        let t = text_table(&r);
        assert!(
            t.contains(
                "warning: the observation matrix is ill-conditioned (condition number 6.900e9"
            ),
            "{t}"
        );
        let v: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
        assert_eq!(v["warnings"][0]["kind"], "ill_conditioned");
        // a parameter known to worse than its size is named
        let e2 = Estimate {
            rel_std_percent: vec![0.83, 145.0],
            warnings: crate::estimate::assess(10.0, &names, &[0.83, 145.0], &[f64::INFINITY; 2]),
            ..e
        };
        let r = Report::new("x", &e2, &fit, |_| None);
        assert_eq!(r.warnings.len(), 1);
        assert_eq!(r.warnings[0].parameters, vec!["MXR2"]);
        assert!(text_table(&r).contains("MXR2 (145 %)"));
    }

    /// Validation rows are reported, and rows that repeat the estimation rows of the same
    /// file are a warning.
    #[test]
    fn validation_rows_and_repeats_are_reported() {
        use crate::validate::{Prediction, UsedRows};
        let used = |a: usize, b: usize| UsedRows {
            file: "run.csv".into(),
            samples: [a, b],
            lines: Some([a as u64 + 2, b as u64 + 1]),
            equations: None,
        };
        let mut r = report();
        r.estimation = Some(used(0, 500));
        let p = |u: UsedRows| Prediction {
            measured: vec![vec![1.0, 2.0]],
            predicted: vec![vec![1.0, 2.1]],
            time: vec![vec![0.0, 0.1]],
            unfiltered: None,
            used: Some(u),
        };
        let before = r.warnings.len();
        let r = r.with_prediction(&p(used(600, 900)));
        assert_eq!(r.warnings.len(), before);
        let r = r.with_prediction(&p(used(0, 900)));
        assert_eq!(r.warnings.len(), before + 1);
        assert_eq!(r.warnings[before].kind, "validation_repeats_estimation");
        let t = text_table(&r);
        assert!(
            t.contains("estimation rows: run.csv lines 2-501 (samples 0..500)"),
            "{t}"
        );
        assert!(
            t.contains("validation run.csv lines 602-901 (samples 600..900)"),
            "{t}"
        );
        let v: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
        assert_eq!(v["validation"][1]["rows"]["samples"][0], 600);
        assert_eq!(v["estimation"]["lines"][1], 501);
    }

    /// Pieces are said under the estimation rows (which only name the rows the fit
    /// covers: a record identified on 41 % of it was given as "estimation rows" whole),
    /// and kept in the JSON; a report without them says nothing of pieces.
    #[test]
    fn pieces_are_said_beside_the_rows() {
        let mut r = report();
        assert!(!text_table(&r).contains("piece"));
        assert!(!r.to_json().contains("pieces"));
        r.pieces = Some(vec![[1.5, 3.25], [4.0, 5.0]]);
        let t = text_table(&r);
        assert!(
            t.contains(
                "estimated on 2 pieces of them (processing.pieces, s from the record's first \
                 sample: 1.5-3.25, 4-5); the fit below covers all of the rows"
            ),
            "{t}"
        );
        let v: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
        assert_eq!(v["pieces"][1][0], 4.0);
    }

    /// The robust deviations are a column after the classical ones, which keep their
    /// places and digits (tools read them), with a line saying what each is; the JSON has
    /// `robust_std` per parameter and `robust_lag`, neither when the estimate has none.
    #[test]
    fn robust_deviations_are_a_column_beside_the_classical_ones() {
        let plain = text_table(&report());
        assert!(!plain.contains("robust"), "{plain}");
        let v: serde_json::Value = serde_json::from_str(&report().to_json()).unwrap();
        assert!(v.get("robust_lag").is_none() && v["parameters"][0].get("robust_std").is_none());
        let mut r = report();
        r.robust_lag = Some(24);
        r.parameters[0].robust_std = Some(0.12);
        let t = text_table(&r);
        let header = t.lines().find(|l| l.starts_with("parameter")).unwrap();
        let row = t.lines().find(|l| l.starts_with("MXR2")).unwrap();
        let fields: Vec<&str> = row.split_whitespace().collect();
        // the classical columns where they were: name, value, std, rel.std%
        assert_eq!(
            &fields[..5],
            ["MXR2", "2.240000", "4.000e-2", "1.79", "1.200e-1"]
        );
        assert!(
            header.contains("rel.std%    robust std  expression"),
            "{header}"
        );
        let fv1 = t.lines().find(|l| l.starts_with("Fv1")).unwrap();
        assert_eq!(fv1.split_whitespace().nth(4), Some("-"), "{fv1}");
        assert!(t.contains("robust std: Newey-West over 24 lags"), "{t}");
        // the classical std's line is the old one with the column added after it
        let old = plain.lines().find(|l| l.starts_with("MXR2")).unwrap();
        assert_eq!(row.replacen("    1.200e-1  ", "", 1), old);
        let v: serde_json::Value = serde_json::from_str(&r.to_json()).unwrap();
        assert_eq!(
            (
                v["robust_lag"].clone(),
                v["parameters"][0]["robust_std"].clone()
            ),
            (24.into(), 0.12.into())
        );
        assert_eq!(v["parameters"][0]["std"], 0.04);
        assert_eq!(serde_json::from_value::<Report>(v).unwrap(), r);
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

    /// Small values keep their digits and sign (2.3e-5 read 0.000023, -1e-9 -0.000000); a
    /// zero reads 0.
    #[test]
    fn small_values_keep_their_digits() {
        assert_eq!(value(2.2345678e-5), "2.2346e-5");
        assert_eq!(value(-1e-9), "-1.0000e-9");
        assert_eq!(value(0.0), "0");
        assert_eq!(value(-0.0), "0");
        assert_eq!(value(1e-3), "0.001000");
        assert_eq!(value(-12.5), "-12.500000");
        assert_eq!(value(2.5e7), "2.5e7");
    }

    /// A figure keeps its fixed decimals down to the smallest that still shows (half the
    /// last decimal rounds up to it) and takes three significant digits below; an
    /// improvement is a percentage down to exactly ten times the reference's NMSE (-900 %),
    /// the ratio beyond.
    #[test]
    fn small_figures_and_large_losses_are_written_so_they_say_something() {
        assert_eq!(small_too(0.3, 2), "0.30");
        assert_eq!(small_too(0.005, 2), "0.01");
        assert_eq!(small_too(0.05, 1), "0.1");
        assert_eq!(small_too(0.0049, 2), "0.0049");
        assert_eq!(small_too(-1.23456e-8, 1), "-1.23e-8");
        assert_eq!(small_too(0.0, 1), "0.0");
        assert_eq!(improvement(-900.0), "-900.0 %");
        assert_eq!(
            improvement(-900.5),
            "none: the identified model's NMSE is 10 times the reference's"
        );
        assert_eq!(improvement(0.04), "0.0 %");
        assert_eq!(improvement(28.51), "28.5 %");
    }
}
