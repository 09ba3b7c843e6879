//! Identification from samples of a numeric model at static poses, as Gaz, Flacco, De Luca
//! (ICRA 2016, Sec. II-D) identify the KUKA LWR IV+ from the gravity vector and the inertia
//! matrix its controller reports (docs/identification.md#static-samples): pairs
//! (q, g(q)) give the combinations of base parameters the gravity torques determine, pairs
//! (q, M(q)) those the mass matrix determines, each by least squares on the stacked rows.
//!
//! A CSV file holds `q1..qn` and either `g1..gn` (gravity torques, N m) or the upper
//! triangle of the mass matrix `M11 M12 .. M1n M22 .. Mnn` (`Mij` with i <= j, row i and
//! column j, kg m^2 or kg for a prismatic joint).

use std::path::Path;

use nalgebra::{DMatrix, DVector};

use crate::data::{read_columns, read_header};
use crate::estimate::{Estimate, Observation, equations_needed, ols_with};
use crate::feasible::GravityCoefficients;
use crate::limits::Quantity;
use crate::{Count, Error, Model, Result};

/// What the samples hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StaticKind {
    /// Gravity torques `g1..gn`.
    Gravity,
    /// The upper triangle of the mass matrix, `M11 M12 .. Mnn`.
    MassMatrix,
}

impl StaticKind {
    /// The value columns of a robot with `dof` joints.
    ///
    /// ```
    /// use robid_runtime::pipeline::StaticKind;
    /// assert_eq!(StaticKind::Gravity.columns(2), ["g1", "g2"]);
    /// assert_eq!(StaticKind::MassMatrix.columns(2), ["M11", "M12", "M22"]);
    /// ```
    pub fn columns(self, dof: usize) -> Vec<String> {
        match self {
            StaticKind::Gravity => (1..=dof).map(|i| format!("g{i}")).collect(),
            StaticKind::MassMatrix => (1..=dof)
                .flat_map(|i| (i..=dof).map(move |j| format!("M{i}{j}")))
                .collect(),
        }
    }

    /// Lower-case name (`gravity`, `mass matrix`).
    pub fn name(self) -> &'static str {
        match self {
            StaticKind::Gravity => "gravity",
            StaticKind::MassMatrix => "mass matrix",
        }
    }
}

/// The base-regressor rows of one pose, row-major with `base_parameter_count` columns, in
/// the order of [`StaticKind::columns`]: for gravity `Y_b(q, 0, 0)`; for the mass matrix the
/// entry `M_ij` (i <= j) is row i of `Y_b(q, 0, e_j) - Y_b(q, 0, 0)` (M's column j is the
/// inverse dynamics at unit acceleration of joint j, gravity removed).
pub fn static_rows(model: &dyn Model, q: &[f64], kind: StaticKind) -> Result<Vec<f64>> {
    let (n, nb) = (model.dof(), model.base_parameter_count());
    let zero = vec![0.0; n];
    let mut rest = vec![0.0; n * nb];
    model.base_regressor_into(q, &zero, &zero, &mut rest)?;
    if kind == StaticKind::Gravity {
        return Ok(rest);
    }
    let mut columns = Vec::with_capacity(n);
    let mut unit = zero.clone();
    let mut y = vec![0.0; n * nb];
    for j in 0..n {
        unit[j] = 1.0;
        model.base_regressor_into(q, &zero, &unit, &mut y)?;
        unit[j] = 0.0;
        columns.push(
            y.iter()
                .zip(&rest)
                .map(|(a, b)| a - b)
                .collect::<Vec<f64>>(),
        );
    }
    let mut out = Vec::with_capacity(n * (n + 1) / 2 * nb);
    for i in 0..n {
        for column in &columns[i..] {
            out.extend_from_slice(&column[i * nb..(i + 1) * nb]);
        }
    }
    Ok(out)
}

/// The result of [`identify_static`].
#[derive(Debug, Clone)]
pub struct StaticFit {
    /// What the samples held.
    pub kind: StaticKind,
    /// The combinations of base parameters such samples determine (`map` from the base
    /// parameters), named after the base parameter that leads each.
    pub determined: GravityCoefficients,
    /// The base parameters that lead no determined combination: these samples say nothing
    /// about them (or only through a combination led by another).
    pub undetermined: Vec<String>,
    /// The least-squares estimate of the determined combinations, with its statistics.
    pub estimate: Estimate,
    /// What the file holds that is fitted but probably not meant: a value column of one
    /// value at every pose where the model's changes with the pose (a dead channel).
    pub warnings: Vec<String>,
}

/// Reads static samples from `path` (see the module docs) and identifies, by ordinary least
/// squares with relative singular-value threshold `tolerance`, the combinations of base
/// parameters they determine. A file with neither or both kinds of value columns, a
/// missing column, or poses too few or too alike to determine every combination is an
/// error that says so.
pub fn identify_static(model: &dyn Model, path: &Path, tolerance: f64) -> Result<StaticFit> {
    let n = model.dof();
    let (q, g, m) = (series("q", n), series("g", n), mass_columns(n));
    let header = read_header(path)?;
    let positions: Vec<String> = (1..=n).map(|i| format!("q{i}")).collect();
    // a missing column: the header the file needs (the columns are not mapped)
    let header_needed =
        |e: Error| crate::data::header_needed(e, format!("{q} with {g}, or with {m}"));
    if positions.iter().any(|q| !header.contains(q)) {
        // the reader's own error about the header: an empty file, one that is not text, a
        // separator it does not read, a missing column (an empty file was "holds neither
        // gravity columns nor mass-matrix columns")
        read_columns(path, &positions).map_err(header_needed)?;
    }
    let has = |kind: StaticKind| kind.columns(n).iter().any(|c| header.contains(c));
    let kind = match (has(StaticKind::Gravity), has(StaticKind::MassMatrix)) {
        (true, false) => StaticKind::Gravity,
        (false, true) => StaticKind::MassMatrix,
        (g, _) => {
            return Err(Error::setting(
                "static samples",
                &path.display().to_string(),
                format!(
                    "{}; give {q} and either {g} (gravity torques) or {m} (the upper \
                     triangle of the mass matrix), in separate files",
                    if g {
                        "holds both gravity (g) and mass-matrix (M) columns"
                    } else {
                        "holds neither gravity columns g1.. nor mass-matrix columns M11.."
                    }
                ),
            ));
        }
    };
    let values = kind.columns(n);
    let mut names = positions;
    names.extend(values.iter().cloned());
    let table = read_columns(path, &names).map_err(header_needed)?;
    let value = match kind {
        StaticKind::Gravity => Quantity::Torque,
        StaticKind::MassMatrix => Quantity::Inertia,
    };
    for (c, name) in names.iter().enumerate() {
        table.check_range(c, name, if c < n { Quantity::Position } else { value })?;
    }
    let determined = match kind {
        StaticKind::Gravity => GravityCoefficients::of_model(model)?,
        StaticKind::MassMatrix => GravityCoefficients::of_mass_matrix(model)?,
    };
    // a robot whose static values no base parameter enters (no gravity, or gravity along
    // every joint axis that moves a mass: a horizontal planar arm, a turntable on a vertical
    // axis, a slider across gravity): the samples determine nothing, whatever their number or poses (the
    // least squares said "least squares with 0 parameters: 60 samples, at least 1 is
    // needed; use more data, less decimation, or fewer parameters")
    if determined.kept.is_empty() {
        return Err(Error::setting(
            "static samples",
            &path.display().to_string(),
            match kind {
                StaticKind::Gravity => format!(
                    "the gravity torques of `{}` are 0 at every pose whatever its parameters \
                     (no gravity, or gravity along every joint axis that moves a mass and \
                     across every slider), so gravity samples determine none of its base parameters; \
                     identify it from mass-matrix samples (columns {m}) or from \
                     motion data (--data)",
                    model.name()
                ),
                StaticKind::MassMatrix => format!(
                    "the mass matrix of `{}` is 0 at every pose whatever its parameters, so \
                     mass-matrix samples determine none of its base parameters; identify it \
                     from motion data (--data)",
                    model.name()
                ),
            },
        ));
    }
    let (rows, nb) = (table.rows(), model.base_parameter_count());
    let per = values.len();
    let nc = determined.kept.len();
    // too few poses for the combinations: said by the file, with its fix (the least
    // squares said "1 samples, at least 2 are needed; use more data, less decimation",
    // which named no file and a setting static samples do not have); as many equations as
    // combinations fit any poses exactly, leaving no residual for the deviations
    if rows * per < equations_needed(nc) {
        return Err(Error::TooFewSamples {
            context: format!(
                "{}: static samples, {} per pose, for the {} of base parameters that {} \
                 determine (and one equation more)",
                path.display(),
                Count(per, "equation"),
                Count(nc, "combination"),
                match kind {
                    StaticKind::Gravity => "gravity torques",
                    StaticKind::MassMatrix => "mass matrices",
                }
            ),
            found: rows,
            required: equations_needed(nc).div_ceil(per),
            hint: "add rows to the file, each at a pose unlike the others",
        });
    }
    let mut w = DMatrix::zeros(rows * per, nc);
    let mut y = DVector::zeros(rows * per);
    for r in 0..rows {
        let q: Vec<f64> = (0..n).map(|i| table.columns[i][r]).collect();
        let full = static_rows(model, &q, kind)?;
        for e in 0..per {
            for (c, &b) in determined.kept.iter().enumerate() {
                w[(r * per + e, c)] = full[e * nb + b];
            }
            y[r * per + e] = table.columns[n + e][r];
        }
    }
    let warnings = dead_columns(&w, &y, &values, path, kind);
    // poses, not a time series: no lag to take the robust deviations over
    let estimate = ols_with(
        &Observation::single(w, y, determined.names.clone())?,
        tolerance,
        false,
    )
    .map_err(|e| match e {
        // the poses, not a trajectory: said by the file, with its fix (it was the
        // estimators' "use a richer trajectory or remove these parameters")
        Error::Estimate(crate::estimate::EstimateError::RankDeficient {
            rank,
            columns,
            unexcited,
        }) => Error::setting(
            "static samples",
            &path.display().to_string(),
            format!(
                "its {rows} poses determine {rank} of the {columns} combinations that static \
                 {} determine (undetermined: {}): the poses repeat or vary too little; add \
                 rows at poses unlike the others, moving every joint",
                match kind {
                    StaticKind::Gravity => "gravity torques",
                    StaticKind::MassMatrix => "mass matrices",
                },
                // the columns the missing directions mix: one of two is determined alone
                // ("not: MX2, MY2" named both where one combination was missing)
                match unexcited.as_slice() {
                    [one] => one.clone(),
                    all => format!(
                        "{} of {}",
                        Count(columns - rank, "combination"),
                        all.join(", ")
                    ),
                }
            ),
        ),
        e => e,
    })?;
    let undetermined = (0..nb)
        .filter(|b| !determined.kept.contains(b))
        .filter_map(|b| model.base_parameter_name(b).map(str::to_owned))
        .collect();
    Ok(StaticFit {
        kind,
        determined,
        undetermined,
        estimate,
        warnings,
    })
}

/// Warnings for value columns of one value at every pose where the model's rows for them
/// change with the pose (a gravity torque of 0 at every pose fitted every combination to
/// 0 +- 0 without a word): a column of one nonzero value, which no parameters give, and a
/// file whose every such column is 0. A single column of zeros is not told: a link whose
/// centre of mass is on its axis has no gravity torque there at any pose (the UR5e's
/// wrist, simulated without noise). `w` and `y` are stacked pose by pose, one row per
/// column of `values`.
fn dead_columns(
    w: &DMatrix<f64>,
    y: &DVector<f64>,
    values: &[String],
    path: &Path,
    kind: StaticKind,
) -> Vec<String> {
    let per = values.len();
    let poses = y.len() / per.max(1);
    if poses < 2 {
        return Vec::new();
    }
    let spread = |v: &mut dyn Iterator<Item = f64>| {
        v.fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], x| {
            [lo.min(x), hi.max(x)]
        })
    };
    let scale = w.amax();
    // the columns the model changes with the pose (beyond the rounding of its rows) that
    // hold one value at every pose
    let moving: Vec<usize> = (0..per)
        .filter(|&e| {
            (0..w.ncols()).any(|c| {
                let [a, b] = spread(&mut (0..poses).map(|r| w[(r * per + e, c)]));
                b - a > 1e-9 * scale
            })
        })
        .collect();
    let constant: Vec<usize> = (moving.iter().copied())
        .filter(|&e| {
            let [lo, hi] = spread(&mut (0..poses).map(|r| y[r * per + e]));
            lo == hi
        })
        .collect();
    let (one, all) = match kind {
        StaticKind::Gravity => ("gravity torque", "gravity torques"),
        StaticKind::MassMatrix => ("mass-matrix entry", "mass-matrix entries"),
    };
    let mut warnings: Vec<String> = (constant.iter())
        .filter(|&&e| y[e] != 0.0)
        .map(|&e| {
            format!(
                "{}: column `{}` is {} at every pose while the model's {one} there changes \
                 with the pose: a dead channel or the wrong column; check the logger and the \
                 file's columns",
                path.display(),
                values[e],
                crate::Num(y[e]),
            )
        })
        .collect();
    if !moving.is_empty() && constant.len() == moving.len() && constant.iter().all(|&e| y[e] == 0.0)
    {
        let names: Vec<&str> = constant.iter().map(|&e| values[e].as_str()).collect();
        warnings.push(format!(
            "{}: every column whose {one} the model changes with the pose ({}) is 0 at every \
             pose: the file holds no {all}; check the logger and the file's columns",
            path.display(),
            names.join(", ")
        ));
    }
    warnings
}

/// `prefix1..prefixn`, or `prefix1` alone for one joint.
fn series(prefix: &str, n: usize) -> String {
    if n == 1 {
        format!("{prefix}1")
    } else {
        format!("{prefix}1..{prefix}{n}")
    }
}

/// The mass-matrix columns in words: `M11 M12 .. Mnn`, or `M11` alone for one joint.
fn mass_columns(n: usize) -> String {
    if n == 1 {
        "M11".to_owned()
    } else {
        format!("M11 M12 .. M{n}{n}")
    }
}

#[cfg(test)]
mod tests {
    use super::{StaticKind, identify_static};
    use crate::model::{LengthError, Model, ProgramKind, check_arguments};

    /// A turntable: one revolute joint on a vertical axis, its one base parameter `ZZR1`
    /// (torque `ZZR1 qdd`): no gravity torque at any pose.
    struct Turntable;

    impl Model for Turntable {
        fn name(&self) -> &str {
            "turntable"
        }
        fn dof(&self) -> usize {
            1
        }
        fn standard_parameter_count(&self) -> usize {
            1
        }
        fn standard_parameter_name(&self, index: usize) -> Option<&str> {
            (index == 0).then_some("ZZ1")
        }
        fn base_parameter_count(&self) -> usize {
            1
        }
        fn base_parameter_name(&self, index: usize) -> Option<&str> {
            (index == 0).then_some("ZZR1")
        }
        fn run(
            &self,
            program: ProgramKind,
            inputs: &[&[f64]],
            output: &mut [f64],
        ) -> Result<(), LengthError> {
            check_arguments(program, self.sizes(), inputs, output)?;
            match (program, inputs) {
                (ProgramKind::BaseRegressor | ProgramKind::StandardRegressor, [_, _, qdd]) => {
                    output[0] = qdd[0];
                }
                (ProgramKind::InverseDynamics, [_, _, qdd, base]) => output[0] = base[0] * qdd[0],
                (ProgramKind::MassMatrix, [_, base]) => output[0] = base[0],
                (ProgramKind::BaseFromStandard, [standard]) => output[0] = standard[0],
                _ => output.fill(0.0),
            }
            Ok(())
        }
    }

    /// Gravity samples of a robot whose gravity torques are 0 at every pose determine no
    /// base parameter, whatever their number: said so, with the samples that do determine
    /// some. It was the least squares' "least squares with 0 parameters: 60 samples, at
    /// least 1 is needed; use more data, less decimation, or fewer parameters" (found with
    /// a one-joint slider across gravity, `robid identify --static`, 7 December 2026).
    /// Its mass-matrix samples determine `ZZR1`.
    #[test]
    fn gravity_samples_of_a_robot_without_gravity_torques_are_told_they_determine_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let gravity = dir.path().join("gravity.csv");
        let rows: String = (0..60)
            .map(|i| format!("{},0\n", 0.1 * f64::from(i)))
            .collect();
        std::fs::write(&gravity, format!("q1,g1\n{rows}")).unwrap();
        let e = identify_static(&Turntable, &gravity, 1e-10)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("gravity.csv`: the gravity torques of `turntable` are 0 at every pose")
                && e.contains("determine none of its base parameters")
                && e.contains("mass-matrix samples (columns M11)"),
            "{e}"
        );
        assert!(!e.contains("more data"), "{e}");
        let mass = dir.path().join("mass.csv");
        let rows: String = (0..10)
            .map(|i| format!("{},0.7\n", 0.3 * f64::from(i)))
            .collect();
        std::fs::write(&mass, format!("q1,M11\n{rows}")).unwrap();
        let fit = identify_static(&Turntable, &mass, 1e-10).unwrap();
        assert_eq!(fit.kind, StaticKind::MassMatrix);
        assert_eq!(fit.determined.names, ["ZZR1"]);
        assert!((fit.estimate.values[0] - 0.7).abs() < 1e-12);
        // poses, not a time series: no robust deviations
        assert!(fit.estimate.robust.is_none());
    }
}
