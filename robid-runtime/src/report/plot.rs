//! Plots of measured vs predicted torque per joint and its residual (SVG, with plotters),
//! as files or as text for the HTML report.

use crate::OutputError;
use std::path::{Path, PathBuf};

use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::validate::Prediction;

/// Writes one SVG per joint, `{prefix}_joint{j}.svg` in `dir`, and returns the paths;
/// `units` gives each joint's torque unit ([`Report::joint_units`](crate::report::Report),
/// "N m" where it gives none).
pub fn plot_torques<S: AsRef<str>>(
    prediction: &Prediction,
    units: &[S],
    dir: &Path,
    prefix: &str,
) -> Result<Vec<PathBuf>> {
    crate::output::create_folder(dir)?;
    let mut paths = Vec::new();
    for j in 0..prediction.measured.len() {
        let path = dir.join(format!("{prefix}_joint{}.svg", j + 1));
        let unit = units.get(j).map_or(super::REVOLUTE, AsRef::as_ref);
        let svg = torque_svg(prediction, j, unit).map_err(|e| match e {
            Error::Output(OutputError::Write { reason, fix, .. }) => {
                Error::Output(OutputError::Write {
                    path: path.clone(),
                    reason,
                    fix,
                })
            }
            e => e,
        })?;
        crate::output::write_bytes(&path, svg.as_bytes())?;
        paths.push(path);
    }
    Ok(paths)
}

/// The SVG of joint `joint` (0-based) of a prediction: measured and predicted torque over
/// the log's own time, and below it the residual (measured - predicted), with the RMS of
/// the residual in the title. Samples left out (near rest) leave gaps: the lines are not
/// drawn across them. `unit` is the joint's torque unit ("N m", or "N" for a prismatic
/// joint).
pub fn torque_svg(prediction: &Prediction, joint: usize, unit: &str) -> Result<String> {
    let mut svg = String::new();
    let t = &prediction.time[joint];
    let m = &prediction.measured[joint];
    let p = &prediction.predicted[joint];
    plot_one(&mut svg, (joint + 1, unit), t, m, p).map_err(|e| {
        Error::Output(OutputError::Write {
            path: PathBuf::from(format!("<joint {} plot>", joint + 1)),
            reason: e.to_string(),
            fix: crate::output::CHECK_FOLDER,
        })
    })?;
    Ok(svg)
}

/// The index ranges of `t` between gaps: a step longer than 1.5 times the median step.
fn segments(t: &[f64]) -> Vec<std::ops::Range<usize>> {
    if t.len() < 2 {
        return std::iter::once(0..t.len()).collect();
    }
    let mut steps: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let gap = 1.5 * steps[steps.len() / 2];
    let mut out = Vec::new();
    let mut start = 0;
    for k in 1..t.len() {
        if t[k] - t[k - 1] > gap {
            out.push(start..k);
            start = k;
        }
    }
    out.push(start..t.len());
    out
}

/// An axis label: `v` to 4 significant digits, a tick within 1e-9 of the axis's `width`
/// of zero written 0 (the tick arithmetic left -2.8e-17 where 0 was meant, drawn -0.0).
fn tick(v: f64, width: f64) -> String {
    let v = if v.abs() <= 1e-9 * width.abs() {
        0.0
    } else {
        v
    };
    crate::Num::rounded(v, 4).to_string()
}

/// The range of `values` with a 5 % margin ((-1, 1) when empty or flat).
fn span<'a>(values: impl Iterator<Item = &'a f64>) -> std::ops::Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(*v), b.max(*v))
    });
    let (lo, hi) = if lo.is_finite() && hi > lo {
        (lo, hi)
    } else {
        (-1.0, 1.0)
    };
    let margin = 0.05 * (hi - lo);
    (lo - margin)..(hi + margin)
}

/// Draws joint `joint.0` (1-based), whose torque is in `joint.1`.
fn plot_one(
    svg: &mut String,
    (joint, unit): (usize, &str),
    t: &[f64],
    m: &[f64],
    p: &[f64],
) -> std::result::Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::with_string(svg, (900, 480)).into_drawing_area();
    root.fill(&WHITE)?;
    let (upper, lower) = root.split_vertically(320);
    let t0 = t.first().copied().unwrap_or(0.0);
    let t1 = t.last().copied().unwrap_or(1.0).max(t0 + 1e-9);
    let residual: Vec<f64> = m.iter().zip(p).map(|(m, p)| m - p).collect();
    let rms = (residual.iter().map(|r| r * r).sum::<f64>() / residual.len().max(1) as f64).sqrt();
    let pieces = segments(t);
    // a prismatic joint's generalised force is a force
    let what = if unit == super::PRISMATIC {
        "force"
    } else {
        "torque"
    };
    let torque_span = span(m.iter().chain(p));
    let residual_span = span(residual.iter());
    let mut chart = ChartBuilder::on(&upper)
        .caption(
            format!(
                "joint {joint}: measured vs predicted {what} (residual RMS {} {unit})",
                crate::Num::rounded(rms, 4)
            ),
            ("sans-serif", 18),
        )
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(60)
        .build_cartesian_2d(t0..t1, torque_span.clone())?;
    chart
        .configure_mesh()
        .x_label_formatter(&|v| tick(*v, t1 - t0))
        .y_label_formatter(&|v| tick(*v, torque_span.end - torque_span.start))
        .y_desc(format!("{what} [{unit}]"))
        .draw()?;
    for (values, colour, name) in [(m, BLUE, "measured"), (p, RED, "predicted")] {
        for (i, r) in pieces.iter().enumerate() {
            let series = chart.draw_series(LineSeries::new(
                r.clone().map(|s| (t[s], values[s])),
                &colour,
            ))?;
            if i == 0 {
                series
                    .label(name)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
            }
        }
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
    let mut below = ChartBuilder::on(&lower)
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(t0..t1, residual_span.clone())?;
    below
        .configure_mesh()
        .x_label_formatter(&|v| tick(*v, t1 - t0))
        .y_label_formatter(&|v| tick(*v, residual_span.end - residual_span.start))
        .x_desc("time [s]")
        .y_desc(format!("residual [{unit}]"))
        .draw()?;
    for r in &pieces {
        below.draw_series(LineSeries::new(
            r.clone().map(|s| (t[s], residual[s])),
            &BLACK,
        ))?;
    }
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_one_svg_per_joint() {
        let t: Vec<f64> = (0..50).map(|k| k as f64 * 0.02).collect();
        let m: Vec<f64> = t.iter().map(|x| x.sin()).collect();
        let p: Vec<f64> = t.iter().map(|x| x.sin() + 0.01).collect();
        let pred = Prediction {
            measured: vec![m.clone(), m],
            predicted: vec![p.clone(), p],
            time: vec![t.clone(), t],
            unfiltered: None,
            used: None,
        };
        let folder = tempfile::tempdir().unwrap();
        let dir = folder.path().join("plots");
        let paths = plot_torques(&pred, &["N m", "N"], &dir, "fit").unwrap();
        assert_eq!(paths.len(), 2);
        let svg = std::fs::read_to_string(&paths[1]).unwrap();
        assert!(
            svg.starts_with("<svg") && svg.contains("polyline") && svg.contains("joint 2"),
            "{}",
            &svg[..200.min(svg.len())]
        );
    }

    /// Axis labels read as numbers: a tick at zero is 0 (the tick arithmetic drew -0.0),
    /// the others to four digits.
    #[test]
    fn ticks_are_written_short() {
        assert_eq!(tick(-2.7755575615628914e-17, 2.0), "0");
        assert_eq!(tick(-0.0, 2.0), "0");
        assert_eq!(tick(0.30000000000000004, 2.0), "0.3");
        assert_eq!(tick(-1.25e-5, 1e-4), "-1.25e-5");
        // zero within 1e-9 of the width, not beyond: 5e-12 on a width of 1e-4 is a value
        assert_eq!(tick(5e-12, 1e-4), "5e-12");
        assert_eq!(tick(5e-14, 1e-4), "0");
        // a residual symmetric about zero: no label is a negative zero
        let t: Vec<f64> = (0..200).map(|k| k as f64 * 0.01).collect();
        let m: Vec<f64> = t.iter().map(|x| (3.0 * x).sin()).collect();
        let p: Vec<f64> = t
            .iter()
            .map(|x| (3.0 * x).sin() + 0.1 * (7.0 * x).sin())
            .collect();
        let pred = Prediction {
            measured: vec![m],
            predicted: vec![p],
            time: vec![t],
            unfiltered: None,
            used: None,
        };
        let svg = torque_svg(&pred, 0, "N m").unwrap();
        let labels: Vec<&str> = svg
            .split("</text>")
            .filter_map(|part| part.rsplit('>').next())
            .map(str::trim)
            .collect();
        assert!(labels.contains(&"0"), "{labels:?}");
        // the default labels drew a tick of -2.8e-17 as -0.0
        assert!(
            !labels
                .iter()
                .any(|l| l.starts_with('-') && l.parse::<f64>() == Ok(0.0)),
            "{labels:?}"
        );
        assert!(
            labels.iter().any(|l| l.contains("residual RMS 0.07")),
            "{labels:?}"
        );
    }

    /// A gap (samples dropped at rest) splits the lines; regular steps do not.
    #[test]
    fn lines_stop_at_gaps() {
        let t = [0.0, 0.1, 0.2, 0.9, 1.0, 1.1, 1.2];
        assert_eq!(segments(&t), [0..3, 3..7]);
        assert_eq!(
            segments(&[0.0, 0.1, 0.2]),
            std::iter::once(0..3).collect::<Vec<_>>()
        );
        assert_eq!(segments(&[0.5]), std::iter::once(0..1).collect::<Vec<_>>());
        // drawn as separate polylines: two per series (plus its legend line)
        let m: Vec<f64> = t.iter().map(|x| x.sin()).collect();
        let p: Vec<f64> = t.iter().map(|x| x.sin() + 0.01).collect();
        let pred = Prediction {
            measured: vec![m],
            predicted: vec![p],
            time: vec![t.to_vec()],
            unfiltered: None,
            used: None,
        };
        let svg = torque_svg(&pred, 0, "N m").unwrap();
        for colour in ["#0000FF", "#FF0000"] {
            let lines = svg
                .lines()
                .filter(|l| l.starts_with("<polyline") && l.contains(colour))
                .count();
            assert_eq!(lines, 3, "{colour}");
        }
        assert!(svg.contains("residual RMS 0.01 N m"), "{svg}");
    }
}
