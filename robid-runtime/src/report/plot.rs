//! Plots of measured vs predicted torque per joint (SVG, with plotters).

use crate::OutputError;
use std::path::{Path, PathBuf};

use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::validate::Prediction;

/// Writes one SVG per joint, `{prefix}_joint{j}.svg` in `dir`, and returns the paths.
pub fn plot_torques(prediction: &Prediction, dir: &Path, prefix: &str) -> Result<Vec<PathBuf>> {
    crate::output::create_folder(dir)?;
    let mut paths = Vec::new();
    for (j, (m, p)) in prediction
        .measured
        .iter()
        .zip(&prediction.predicted)
        .enumerate()
    {
        let path = dir.join(format!("{prefix}_joint{}.svg", j + 1));
        let t = &prediction.time[j];
        let mut svg = String::new();
        plot_one(&mut svg, j + 1, t, m, p).map_err(|e| {
            Error::Output(OutputError::Write {
                path: path.clone(),
                reason: e.to_string(),
            })
        })?;
        crate::output::write_bytes(&path, svg.as_bytes())?;
        paths.push(path);
    }
    Ok(paths)
}

fn plot_one(
    svg: &mut String,
    joint: usize,
    t: &[f64],
    m: &[f64],
    p: &[f64],
) -> std::result::Result<(), Box<dyn std::error::Error>> {
    let root = SVGBackend::with_string(svg, (900, 360)).into_drawing_area();
    root.fill(&WHITE)?;
    let (t0, t1) = (
        t.first().copied().unwrap_or(0.0),
        t.last()
            .copied()
            .unwrap_or(1.0)
            .max(t.first().copied().unwrap_or(0.0) + 1e-9),
    );
    let lo = m.iter().chain(p).copied().fold(f64::INFINITY, f64::min);
    let hi = m.iter().chain(p).copied().fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if lo.is_finite() && hi > lo {
        (lo, hi)
    } else {
        (-1.0, 1.0)
    };
    let margin = 0.05 * (hi - lo);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("joint {joint}: measured vs predicted torque"),
            ("sans-serif", 18),
        )
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(t0..t1, (lo - margin)..(hi + margin))?;
    chart
        .configure_mesh()
        .x_desc("time [s]")
        .y_desc("torque [N m]")
        .draw()?;
    chart
        .draw_series(LineSeries::new(
            t.iter().copied().zip(m.iter().copied()),
            &BLUE,
        ))?
        .label("measured")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
    chart
        .draw_series(LineSeries::new(
            t.iter().copied().zip(p.iter().copied()),
            &RED,
        ))?
        .label("predicted")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()?;
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
        let dir = std::env::temp_dir().join(format!("robid-plot-{}", std::process::id()));
        let paths = plot_torques(&pred, &dir, "fit").unwrap();
        assert_eq!(paths.len(), 2);
        let svg = std::fs::read_to_string(&paths[1]).unwrap();
        assert!(
            svg.starts_with("<svg") && svg.contains("polyline") && svg.contains("joint 2"),
            "{}",
            &svg[..200.min(svg.len())]
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
