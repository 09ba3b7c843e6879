//! From config + files to a joint-side, uniformly sampled [`Dataset`].

use std::path::{Path, PathBuf};

use crate::data::time::{check_monotonic, interpolate, regularity, uniform_grid};
use crate::data::{AngleUnit, Config, Dataset, Source, Table, Warning, read_columns};
use crate::drive::DriveChain;
use crate::error::{Error, Result};

/// The roles a column block can have, in the order of `Loaded::blocks`.
const ROLES: [&str; 5] = [
    "position",
    "velocity",
    "acceleration",
    "torque",
    "motor_position",
];

fn role_columns(s: &Source, role: usize) -> Option<&crate::data::Columns> {
    [
        &s.position,
        &s.velocity,
        &s.acceleration,
        &s.torque,
        &s.motor_position,
    ][role]
        .as_ref()
}

/// Loads a data set for a `dof`-joint model. `files` pair with the config's
/// `[[source]]` tables in order; when empty, the sources' own `file` entries are used.
pub fn load(config: &Config, files: &[PathBuf], dof: usize) -> Result<Dataset> {
    config.check(dof)?;
    let paths = source_paths(config, files)?;
    let mut blocks: [Option<Vec<Vec<f64>>>; 5] = Default::default();
    let mut reference: Option<(Vec<f64>, PathBuf)> = None;
    let mut rows: Option<(usize, PathBuf)> = None;
    let mut warnings = Vec::new();

    for (src, path) in config.sources.iter().zip(&paths) {
        let mut names = Vec::new();
        let mut spans = Vec::new();
        for (role, role_name) in ROLES.iter().enumerate() {
            if let Some(cols) = role_columns(src, role) {
                let n = cols.names(dof);
                if n.len() != dof {
                    return Err(Error::JointCountMismatch {
                        context: format!("{}: `{}` columns {:?}", path.display(), role_name, n),
                        expected: dof,
                        found: n.len(),
                    });
                }
                spans.push((role, names.len()));
                names.extend(n);
            }
        }
        if let Some(t) = &config.time_column {
            names.push(t.clone());
        }
        let mut table = read_columns(path, &names)?;
        if table.rows() < 2 {
            return Err(Error::TooFewSamples {
                context: path.display().to_string(),
                found: table.rows(),
                required: 2,
                hint: "the file needs a header and data rows",
            });
        }
        let mut columns = std::mem::take(&mut table.columns);
        if config.time_column.is_some() {
            let mut t = columns.pop().unwrap_or_default();
            t.iter_mut().for_each(|v| *v *= config.time_scale);
            check_monotonic(&t, &table.lines, path)?;
            match &reference {
                None => reference = Some((t, path.clone())),
                Some((tref, _)) => {
                    columns = columns.iter().map(|x| interpolate(&t, x, tref)).collect();
                    let dropped = tref
                        .iter()
                        .filter(|&&s| s < t[0] || s > t[t.len() - 1])
                        .count();
                    if dropped > 0 {
                        warnings.push(Warning::PartialOverlap {
                            path: path.clone(),
                            dropped,
                        });
                    }
                }
            }
        } else {
            check_rows(&mut rows, &table)?;
        }
        for (role, start) in spans {
            if blocks[role].is_some() {
                return Err(Error::InvalidConfig {
                    key: format!("source.{}", ROLES[role]),
                    problem: "given by more than one [[source]]; keep it in one".into(),
                });
            }
            blocks[role] = Some(columns[start..start + dof].to_vec());
        }
    }

    let sample_time = match (&reference, config.sample_rate) {
        (Some((t, path)), _) => {
            let (step, warning) = regularity(t, path);
            if let Some(w) = warning {
                let grid = uniform_grid(t[0], step, t.len());
                for b in blocks.iter_mut().flatten() {
                    *b = b.iter().map(|x| interpolate(t, x, &grid)).collect();
                }
                warnings.push(w);
            }
            step
        }
        (None, Some(fs)) => 1.0 / fs,
        (None, None) => {
            return Err(Error::InvalidConfig {
                key: "sample_rate".into(),
                problem: "the data has no time column; set `sample_rate = ...` (Hz) or `time_column = \"...\"`".into(),
            });
        }
    };

    let [q, qd, qdd, tau, motor] = blocks;
    let missing = |role: &str| Error::InvalidConfig {
        key: format!("source.{role}"),
        problem: format!("no [[source]] gives `{role}` columns; add e.g. {role} = \"{role}{{}}\""),
    };
    let (q, tau) = (
        q.ok_or_else(|| missing("position"))?,
        tau.ok_or_else(|| missing("torque"))?,
    );
    let chain = DriveChain::new(&config.drive, dof)?;
    let angle = |x: Vec<Vec<f64>>| match config.units.angle {
        AngleUnit::Rad => x,
        AngleUnit::Deg => x
            .into_iter()
            .map(|v| v.into_iter().map(f64::to_radians).collect())
            .collect(),
    };
    let mut tau = tau;
    if let Some(s) = &config.units.torque_scale {
        for (t, s) in tau.iter_mut().zip(s.values(dof, "units.torque_scale")?) {
            t.iter_mut().for_each(|v| *v *= s);
        }
    }
    let name = paths
        .first()
        .and_then(|p| p.file_name())
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let mut data = Dataset::new(
        name,
        sample_time,
        chain.joint_positions(&angle(q)),
        chain.joint_torques(&tau),
    )?;
    if let Some(v) = qd {
        data = data.with_velocities(chain.joint_positions(&angle(v)))?;
    }
    if let Some(a) = qdd {
        data = data.with_accelerations(chain.joint_positions(&angle(a)))?;
    }
    if let Some(m) = motor {
        data = data.with_motor_positions(chain.reflected_motor_positions(&angle(m)))?;
    }
    if config.drive.rotor.is_some() && data.motor.is_none() {
        return Err(Error::InvalidConfig {
            key: "drive.rotor".into(),
            problem: "rotor compensation needs motor encoder columns: add motor_position = [...] to a [[source]]".into(),
        });
    }
    data.warnings = warnings;
    Ok(data)
}

fn source_paths(config: &Config, files: &[PathBuf]) -> Result<Vec<PathBuf>> {
    if config.sources.is_empty() {
        return Err(Error::InvalidConfig {
            key: "source".into(),
            problem: "no [[source]] table; add one per file with its position and torque columns"
                .into(),
        });
    }
    if !files.is_empty() {
        if files.len() != config.sources.len() {
            return Err(Error::InvalidConfig {
                key: "source".into(),
                problem: format!(
                    "{} files given but the config has {} [[source]] tables; give one file per table",
                    files.len(),
                    config.sources.len()
                ),
            });
        }
        return Ok(files.to_vec());
    }
    config
        .sources
        .iter()
        .enumerate()
        .map(|(i, s)| {
            s.file
                .as_deref()
                .map(|f| config.resolve(f))
                .ok_or_else(|| Error::InvalidConfig {
                    key: format!("source[{}].file", i + 1),
                    problem: "no file given; set `file = \"...\"` or pass the files explicitly"
                        .into(),
                })
        })
        .collect()
}

fn check_rows(rows: &mut Option<(usize, PathBuf)>, table: &Table) -> Result<()> {
    match rows {
        None => *rows = Some((table.rows(), table.path.clone())),
        Some((n, first)) if *n != table.rows() => {
            return Err(Error::RowCountMismatch {
                first: first.clone(),
                first_rows: *n,
                second: table.path.clone(),
                second_rows: table.rows(),
            });
        }
        _ => {}
    }
    Ok(())
}

/// Loads with the sources' own `file` entries (relative to the config file).
pub fn load_config_files(config: &Config, dof: usize) -> Result<Dataset> {
    load(config, &[], dof)
}

/// Convenience: reads the config at `path` and loads its files.
pub fn load_from_config_file(path: &Path, dof: usize) -> Result<Dataset> {
    load(&Config::from_file(path)?, &[], dof)
}
