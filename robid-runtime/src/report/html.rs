//! One self-contained HTML page of an identification (docs/identification.md#reports):
//! the fit and validation figures, the condition number, the warnings, the parameter table
//! with relative standard deviations, and per data set and joint the measured vs predicted
//! torque with its residual, on the log's own time axis, as inline SVG. No script, no
//! style sheet or font from the network: the file opens anywhere.

use super::table::fixed;
use std::fmt::Write as _;
use std::path::Path;

use crate::error::Result;
use crate::report::{FitEntry, Report, torque_svg};
use crate::validate::Prediction;

/// `text` with `&`, `<`, `>` and `"` escaped for HTML.
pub(crate) fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// One row of the figures table.
fn figures_row(html: &mut String, what: &str, f: &FitEntry) {
    let against = match (f.torque.as_deref(), f.unfiltered_relative_error) {
        (Some("filtered"), Some(u)) => {
            format!(
                "filtered torque; {} % against the measured",
                fixed(100.0 * u, 2)
            )
        }
        (Some(t), _) => format!("{t} torque"),
        (None, _) => String::new(),
    };
    let rms: Vec<String> = f.rms_per_joint.iter().map(|v| fixed(*v, 3)).collect();
    let _ = writeln!(
        html,
        "<tr><td>{}</td><td>{} %</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
        escape(what),
        fixed(100.0 * f.relative_error, 2),
        escape(&against),
        fixed(f.nmse, 4),
        fixed(f.nmse_eq22, 1),
        rms.join(" ")
    );
}

/// The validation files against the reference model, in the form of Madsen et al.'s
/// Table 5 (nothing without a reference).
fn reference_table(h: &mut String, report: &Report) {
    let rows: Vec<_> = report
        .validation
        .iter()
        .filter_map(|v| v.reference.as_ref().map(|r| (v, r)))
        .collect();
    let Some((_, first)) = rows.first() else {
        return;
    };
    let _ = writeln!(
        h,
        "<h2>Against the reference {}</h2>\n<table>\n<tr><th>data</th>\
         <th>relative error reference</th><th>relative error identified</th>\
         <th>NMSE eq. 22 reference [{unit}]</th><th>NMSE eq. 22 identified [{unit}]</th>\
         <th>relative improvement</th></tr>",
        escape(&first.file),
        unit = report.torque_unit
    );
    for (v, r) in rows {
        let name = v
            .rows
            .as_ref()
            .map_or_else(|| v.file.clone(), |r| r.to_string());
        let improvement = r
            .relative_improvement_percent
            .map_or_else(|| "-".to_string(), super::table::improvement);
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{} %</td><td>{} %</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&name),
            super::table::small_too(100.0 * r.relative_error, 2),
            fixed(100.0 * v.relative_error, 2),
            super::table::small_too(r.nmse_eq22, 1),
            super::table::small_too(v.nmse_eq22, 1),
            improvement
        );
    }
    h.push_str("</table>\n");
}

/// The page of `report`, with the plots of `predictions` (a title and a prediction each,
/// e.g. the fit and each validation).
pub fn html_report(report: &Report, predictions: &[(&str, &Prediction)]) -> Result<String> {
    let mut h = String::new();
    let title = format!("robid identification: {}", report.robot);
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n\
         <style>\nbody {{ font-family: sans-serif; margin: 2em; max-width: 960px; }}\n\
         table {{ border-collapse: collapse; margin: 1em 0; }}\n\
         td, th {{ border: 1px solid #bbb; padding: 0.2em 0.6em; text-align: right; white-space: nowrap; }}\n\
         th {{ background: #eee; }} td.name, td.expr {{ text-align: left; white-space: normal; }}\n\
         .warning {{ color: #a00; }}\n</style>\n</head>\n<body>\n<h1>{}</h1>\n",
        escape(&title),
        escape(&title)
    );
    let _ = writeln!(
        h,
        "<p>Method <b>{}</b>, {} equations, condition number {:.1}, upper bound on the \
         relative estimation error {:.1} % (cond(W) ||residual|| / ||torque||, Milella).</p>",
        escape(&report.method),
        report.samples,
        report.condition_number,
        report.error_bound_percent
    );
    if let Some(scaled) = report.scaled_condition_number {
        let _ = writeln!(
            h,
            "<p>Condition number with unit-norm columns {scaled:.1} (the same in any units of \
             the parameters; the one above, and the bound with it, are of W in its units).</p>"
        );
    }
    if let Some(rows) = &report.estimation {
        let _ = writeln!(h, "<p>Estimation rows: {}.</p>", escape(&rows.to_string()));
    }
    if let Some(g) = &report.segments {
        h.push_str(&g.html("Estimation"));
    }
    if let Some(c) = &report.cutoff {
        let _ = writeln!(
            h,
            "<p>Low-pass cutoff (auto): {} Hz: {}.</p>",
            c.cutoff,
            escape(&c.reason)
        );
    }
    let _ = writeln!(
        h,
        "<h2>Fit and validation</h2>\n<table>\n<tr><th>data</th><th>relative error</th>\
         <th>against</th><th>NMSE</th><th>NMSE eq. 22 [{unit}]</th><th>RMS per joint [{unit}]</th></tr>",
        unit = report.torque_unit
    );
    figures_row(&mut h, "fit", &report.fit);
    for v in &report.validation {
        let name = v
            .rows
            .as_ref()
            .map_or_else(|| v.file.clone(), |r| r.to_string());
        let f = FitEntry {
            relative_error: v.relative_error,
            rms_per_joint: v.rms_per_joint.clone(),
            nmse: v.nmse,
            nmse_eq22: v.nmse_eq22,
            torque: v.torque.clone(),
            unfiltered_relative_error: v.unfiltered_relative_error,
        };
        figures_row(&mut h, &format!("validation {name}"), &f);
    }
    h.push_str("</table>\n");
    for v in &report.validation {
        if let Some(g) = &v.segments {
            h.push_str(&g.html("Validation"));
        }
    }
    reference_table(&mut h, report);
    if !report.warnings.is_empty() {
        h.push_str("<h2>Warnings</h2>\n<ul>\n");
        for w in &report.warnings {
            let _ = writeln!(h, "<li class=\"warning\">{}</li>", escape(&w.message));
        }
        h.push_str("</ul>\n");
    }
    h.push_str(
        "<h2>Parameters</h2>\n<table>\n<tr><th>parameter</th><th>value</th><th>std</th>\
         <th>rel. std [%]</th><th>robust std</th><th>expression</th></tr>\n",
    );
    for p in &report.parameters {
        let rel = match p.rel_std_percent {
            _ if p.known => "known".to_string(),
            Some(r) => format!("{r:.2}"),
            None => "-".to_string(),
        };
        let _ = writeln!(
            h,
            "<tr><td class=\"name\">{}</td><td>{}</td><td>{:.3e}</td><td>{rel}</td><td>{}</td><td class=\"expr\">{}</td></tr>",
            escape(&p.name),
            super::table::value(p.value),
            p.std,
            p.robust_std
                .map_or_else(|| "-".to_string(), |r| format!("{r:.3e}")),
            escape(&p.expression)
        );
    }
    h.push_str("</table>\n");
    if let Some(r) = &report.runs {
        h.push_str(&r.html(&report.torque_unit));
    }
    for (name, prediction) in predictions {
        let _ = writeln!(h, "<h2>{}: torque per joint</h2>", escape(name));
        for j in 0..prediction.measured.len() {
            let svg = torque_svg(prediction, j, report.joint_unit(j))?;
            let _ = writeln!(h, "<figure>\n{svg}\n</figure>");
        }
    }
    h.push_str("</body>\n</html>\n");
    Ok(h)
}

/// Writes [`html_report`] to `path` (through a temporary file and a rename).
pub fn write_html(path: &Path, report: &Report, predictions: &[(&str, &Prediction)]) -> Result<()> {
    crate::output::write_bytes(path, html_report(report, predictions)?.as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::{ParameterEntry, ReportWarning};

    fn report() -> Report {
        Report {
            robot: "arm<1>".into(),
            method: "wls".into(),
            samples: 100,
            condition_number: 12.5,
            scaled_condition_number: Some(3.2),
            error_bound_percent: 3.5,
            estimation: None,
            robust_lag: None,
            parameters: vec![ParameterEntry {
                name: "ZZR1".into(),
                expression: "ZZ1 + 0.5*M2".into(),
                value: 1.25,
                std: 0.01,
                rel_std_percent: Some(0.8),
                robust_std: None,
                known: false,
            }],
            fit: FitEntry {
                relative_error: 0.052,
                rms_per_joint: vec![0.1, 0.2],
                nmse: 0.3,
                nmse_eq22: 12.5,
                torque: Some("filtered".into()),
                unfiltered_relative_error: Some(0.09),
            },
            validation: Vec::new(),
            cutoff: None,
            warnings: vec![ReportWarning {
                kind: "uncertain".into(),
                parameters: vec!["ZZR1".into()],
                message: "a & b".into(),
            }],
            runs: None,
            segments: None,
            pieces: None,
            torque_unit: "N m".into(),
            joint_units: Vec::new(),
        }
    }

    /// The page holds every figure, escapes text, has one inline SVG per joint and data
    /// set, and refers to nothing outside itself.
    #[test]
    fn the_page_is_complete_and_self_contained() {
        let t: Vec<f64> = (0..40).map(|k| 3.0 + 0.01 * k as f64).collect();
        let p = Prediction {
            measured: vec![t.clone(), t.iter().map(|x| -x).collect()],
            predicted: vec![
                t.iter().map(|x| x + 0.1).collect(),
                t.iter().map(|x| 0.1 - x).collect(),
            ],
            time: vec![t.clone(), t],
            unfiltered: None,
            used: None,
        };
        let html = html_report(&report(), &[("fit", &p), ("validation 1", &p)]).unwrap();
        assert!(html.starts_with("<!DOCTYPE html>"));
        assert!(html.contains("robid identification: arm&lt;1&gt;"));
        assert!(
            html.contains("<td>5.20 %</td><td>filtered torque; 9.00 % against the measured</td>")
        );
        assert!(html.contains("ZZ1 + 0.5*M2") && html.contains("<td>0.80</td>"));
        assert!(html.contains("a &amp; b"));
        assert!(html.contains("condition number 12.5"));
        assert!(
            html.contains("Condition number with unit-norm columns 3.2 "),
            "{html}"
        );
        assert!(html.contains("relative estimation error 3.5 %"), "{html}");
        assert_eq!(html.matches("<svg").count(), 4);
        for external in ["src=\"http", "href=\"http", "<script", "@import", "url("] {
            assert!(!html.contains(external), "{external}");
        }
        // every figure in N m for a revolute arm; a prismatic joint's in N (every figure
        // was labelled N m)
        assert_eq!(html.matches("torque [N m]").count(), 4);
        let mut r = report();
        r.set_units(&crate::report::joint_units(&[false, true], 2));
        let html = html_report(&r, &[("fit", &p)]).unwrap();
        let figures: Vec<&str> = html.split("<figure>").skip(1).collect();
        assert_eq!(figures.len(), 2);
        assert!(figures[0].contains("torque [N m]") && figures[0].contains("residual [N m]"));
        assert!(
            figures[1].contains("force [N]")
                && figures[1].contains("residual [N]")
                && !figures[1].contains("N m"),
            "{}",
            figures[1]
        );
    }
}
