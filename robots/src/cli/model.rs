//! `robid model ROBOT.toml [--json]`: the robot, its standard and base
//! parameters with expressions, the unidentifiable parameters and the
//! operation counts of the derived programs; with `--schedule P`, the parallel schedule of
//! one program (`schedule.rs`); with `--standard-parameters FILE`, a URDF's own inertials
//! written as a `[standard]` parameter file; with `--write-description FILE`, the robot
//! (a URDF's fitted DH table) as a description file.

use super::description::{self, DescriptionFlags};
use super::{Error, files, flags, out, schedule};
use robid_runtime::model::ProgramKind;
use robid_runtime::progress::Progress;
use robid_symbolic::program::Operations;
use robid_symbolic::program::RobotPrograms;
use robid_symbolic::program::schedule::MAX_PROCESSORS;
use robid_symbolic::regroup::BaseParameters;
use robid_symbolic::robot::UrdfChain;
use robid_symbolic::{Arena, Robot};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Arguments of `robid model`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    #[arg(help = description::robot_help!())]
    robot: PathBuf,
    #[command(flatten)]
    description: DescriptionFlags,
    /// Print JSON instead of text.
    #[arg(long)]
    json: bool,
    /// Also schedule a program's task graph on P identical processors by Zomaya's
    /// first-fit and best-fit decreasing rules (critical path, loads, speed-up).
    #[arg(long, value_name = "P", value_parser = flags::count(1, MAX_PROCESSORS))]
    schedule: Option<usize>,
    /// The program `--schedule` analyses.
    #[arg(long, value_name = "NAME")]
    schedule_program: Option<String>,
    /// URDF only: also write the file's own `<inertial>` elements, as the chain's standard
    /// parameters, to this `[standard]` parameter file (for `--parameters` of `torques`,
    /// `simulate` and `excite`, `--prior` of `feasible`, `--reference` of `identify`).
    #[arg(long, value_name = "FILE")]
    standard_parameters: Option<PathBuf>,
    /// Also write the robot as a description file (TOML) that reads back to the same
    /// model: for a URDF, the DH table robid fitted to its chain (with its limits, base
    /// and tool frames, `calibrated = true`), to read, edit or give to any subcommand.
    #[arg(long, value_name = "FILE")]
    write_description: Option<PathBuf>,
}

#[derive(Serialize)]
struct Term {
    parameter: String,
    coefficient: serde_json::Value,
}

#[derive(Serialize)]
struct Base {
    name: String,
    expression: String,
    terms: Vec<Term>,
    /// Its value from a URDF's own inertials (none for a TOML description, or when a
    /// term is a drive term, which a URDF does not give).
    #[serde(skip_serializing_if = "Option::is_none")]
    value: Option<f64>,
}

#[derive(Serialize)]
struct Counts {
    mul: usize,
    add: usize,
    neg: usize,
    sin: usize,
    cos: usize,
    sign: usize,
}

impl From<Operations> for Counts {
    fn from(o: Operations) -> Counts {
        Counts {
            mul: o.mul,
            add: o.add,
            neg: o.neg,
            sin: o.sin,
            cos: o.cos,
            sign: o.sign,
        }
    }
}

/// A `[base]` or `[tool]` transform as written.
#[derive(Serialize)]
struct Mount {
    xyz: [String; 3],
    rpy: [String; 3],
}

impl Mount {
    fn of(t: Option<&robid_symbolic::Transform>) -> Option<Mount> {
        t.map(|t| Mount {
            xyz: t.xyz.clone().map(|g| g.as_str().to_owned()),
            rpy: t.rpy.clone().map(|g| g.as_str().to_owned()),
        })
    }
}

#[derive(Serialize)]
struct Report {
    name: String,
    dof: usize,
    convention: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    base: Option<Mount>,
    #[serde(skip_serializing_if = "Option::is_none")]
    tool: Option<Mount>,
    standard_parameters: Vec<String>,
    base_parameters: Vec<Base>,
    unidentifiable: Vec<String>,
    operations: serde_json::Map<String, serde_json::Value>,
    #[serde(skip_serializing_if = "Option::is_none")]
    schedule: Option<schedule::Report>,
}

/// Derives the model and prints it.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    let scheduled = match (args.schedule, &args.schedule_program) {
        (Some(p), name) => Some((
            p,
            schedule::program_kind(name.as_deref().unwrap_or("inverse_dynamics"))?,
        )),
        (None, Some(_)) => {
            return Err("--schedule-program needs --schedule P (the number of processors)".into());
        }
        (None, None) => None,
    };
    let outputs: Vec<(&str, &Path)> = [
        ("--standard-parameters", &args.standard_parameters),
        ("--write-description", &args.write_description),
    ]
    .into_iter()
    .filter_map(|(flag, path)| Some((flag, path.as_deref()?)))
    .collect();
    files::refuse(&[&args.robot], &outputs)?;
    if args.standard_parameters.is_some() && !description::is_urdf(&args.robot) {
        return Err(format!(
            "--standard-parameters writes a URDF's own <inertial> elements, but {} is a \
             TOML description, which carries no inertial values; give the robot's .urdf \
             file, or write the [standard] table by hand (docs/command-line.md, \
             \"Parameter files\")",
            args.robot.display()
        )
        .into());
    }
    let description = description::load(&args.robot, &args.description)?;
    if let Some(path) = &args.write_description {
        files::write(path, &description_file(&description, &args.robot))?;
    }
    let mut text = render(&description, args.json, scheduled)?;
    if let (Some(path), Some(chain)) = (&args.standard_parameters, &description.urdf) {
        files::write(path, &standard_file(chain, &args.robot))?;
    }
    if let (false, Some(chain)) = (args.json, &description.urdf) {
        // which URDF joint each row is, and what its link carries
        let mut names = String::from(
            "\nfrom the URDF (robid's frames fitted to its joint axes, docs/urdf.md):\n",
        );
        for (j, link) in chain.links.iter().enumerate() {
            let attached: Vec<&str> = link.attached.iter().map(|a| a.name.as_str()).collect();
            let _ = writeln!(
                names,
                "  {:<2} joint `{}` moves `{}`{}",
                j + 1,
                link.joint,
                link.link,
                if attached.is_empty() {
                    String::new()
                } else {
                    format!(", with {} attached", attached.join(", "))
                }
            );
        }
        if let Some(at) = text.find("\nstandard parameters") {
            text.insert_str(at, &names);
        }
    }
    out::print(&text)?;
    Ok(())
}

/// The robot as a description file (`Robot::to_toml`) under a comment naming its source;
/// for a URDF, each joint's table under a comment naming its URDF joint and link.
fn description_file(description: &description::Description, path: &Path) -> String {
    let Some(chain) = &description.urdf else {
        return format!(
            "# {} as robid reads it\n{}",
            path.display(),
            description.robot.to_toml()
        );
    };
    let mut text = format!(
        "# The DH table robid fitted to the chain of {} (docs/urdf.md), as a description\n",
        path.display()
    );
    let mut tables = description.robot.to_toml();
    for (j, link) in chain.links.iter().enumerate().rev() {
        let Some(at) = tables
            .match_indices("[[joints]]\n")
            .nth(j)
            .map(|(at, _)| at)
        else {
            continue;
        };
        let mut note = format!(
            "# joint {}: URDF joint `{}` moves `{}`\n",
            j + 1,
            link.joint,
            link.link
        );
        if link.continuous {
            // excite keeps a URDF's continuous joint within a turn; a description has no
            // such joint type, so its limit is told here, where it would go
            note.push_str(
                "# continuous in the URDF: no position limit here; `robid excite` needs one, \
                 `position = [-3.1416, 3.1416]` in `limits` keeps it within a turn, as \
                 excite on the URDF does\n",
            );
        }
        tables.insert_str(at, &note);
    }
    text.push_str(&tables);
    text
}

/// A URDF chain's own inertials as a `[standard]` parameter file
/// (robid_runtime::data::ParameterFile reads it): every inertial parameter of every chain
/// link, in robid's frames, each link under a comment naming its URDF joint and links.
/// Values are written in the shortest form that reads back to the same `f64`.
fn standard_file(chain: &UrdfChain, path: &Path) -> String {
    let robot = &chain.robot;
    let mut text = format!(
        "# The standard parameters of `{}` from the <inertial> elements of {} (robid link j:\n\
         # the body its joint j moves, docs/urdf.md#inertials): XX..ZZ (kg m^2) the inertia about\n\
         # the origin of robid frame j, MX MY MZ (kg m) the first moments, M (kg) the mass, in\n\
         # frame j. For `robid torques --parameters`, `simulate`, `excite`, `feasible --prior` and\n\
         # `identify --reference`, with the same description and --base/--tip.\n\n[standard]\n",
        robot.name(),
        path.display()
    );
    let standard = robot.standard_parameters();
    for (j, link) in chain.links.iter().enumerate() {
        let attached: Vec<String> = link
            .attached
            .iter()
            .map(|a| format!("`{}`", a.name))
            .collect();
        let _ = writeln!(
            text,
            "# link {}: joint `{}` moves `{}`{}{}",
            j + 1,
            link.joint,
            link.link,
            if attached.is_empty() {
                String::new()
            } else {
                format!(" with {} attached", attached.join(", "))
            },
            if link.inertial.iter().all(|&v| v == 0.0) {
                " (no mass: no <inertial>, or an empty one)"
            } else if chain.empty(j) {
                " (no mass: values negligible beside the chain's largest)"
            } else {
                ""
            }
        );
        for &id in standard.iter().filter(|id| id.link == j) {
            if let Some(value) = chain.inertial_value(id) {
                let _ = writeln!(text, "{id} = {value:e}");
            }
        }
    }
    text
}

/// The model of `description` as text or JSON, with the schedule of a program on a number
/// of processors when asked; for a URDF, the base parameters' values from its inertials.
fn render(
    description: &description::Description,
    json: bool,
    scheduled: Option<(usize, ProgramKind)>,
) -> Result<String, Error> {
    let robot = &description.robot;
    let mut report = derive(robot, scheduled)?;
    if description.urdf.is_some() {
        for b in &mut report.base_parameters {
            b.value = urdf_value(description, &b.terms);
        }
    }
    Ok(if json {
        serde_json::to_string_pretty(&report)? + "\n"
    } else {
        let mut t = text(robot, &report);
        if let Some(s) = &report.schedule {
            t.push_str(&schedule::text(s));
        }
        t
    })
}

fn derive(robot: &Robot, scheduled: Option<(usize, ProgramKind)>) -> Result<Report, Error> {
    // a stage at a time, as other long commands show theirs (robid_runtime::progress): a
    // chain of 32 joints with general twists and symbolic lengths takes seconds of CPU,
    // and showed nothing (the standard regressor's program is about two thirds of the
    // time, one stage)
    let progress = Progress::new(
        true,
        "model: derivation",
        RobotPrograms::STAGES as u64,
        "stages",
    );
    // the base parameters' terms as the programs' derivation finds them (a derivation of
    // their own cost a quarter of the time on long chains)
    let mut shown = None;
    let programs =
        RobotPrograms::derive_showing(robot, &mut |_| progress.tick(), &mut |arena, b| {
            description::warn_folded_offsets(&b.standard, &b.base);
            shown = Some(base_parameters(arena, b))
        })?;
    progress.finish();
    let Some(shown) = shown else {
        unreachable!("derive_showing hands the base parameters on before it succeeds")
    };
    let parameters = shown?;
    let mut operations = serde_json::Map::new();
    for (info, program) in programs.iter() {
        operations.insert(
            info.name.to_owned(),
            serde_json::to_value(Counts::from(program.operations()))?,
        );
    }
    let schedule = match scheduled {
        Some((p, kind)) => Some(schedule::analyse(&programs, kind, p)?),
        None => None,
    };
    Ok(Report {
        name: robot.name().to_owned(),
        dof: robot.dof(),
        convention: robot.convention().as_str(),
        base: Mount::of(robot.base()),
        tool: Mount::of(robot.tool()),
        standard_parameters: parameters.standard,
        base_parameters: parameters.base,
        unidentifiable: parameters.unidentifiable,
        operations,
        schedule,
    })
}

/// The value of a base parameter with `terms` from a URDF's inertials: the sum of its
/// terms, each coefficient (a number: a URDF's geometry has no symbols) times the
/// standard parameter's value; `None` when a term has no value (a drive term).
fn urdf_value(description: &description::Description, terms: &[Term]) -> Option<f64> {
    terms.iter().try_fold(0.0, |sum, t| {
        Some(sum + t.coefficient.as_f64()? * description.urdf_inertial(&t.parameter)?)
    })
}

/// The parameters of the report.
struct Parameters {
    standard: Vec<String>,
    base: Vec<Base>,
    unidentifiable: Vec<String>,
}

/// The standard parameters' names, the base parameters with their terms and the
/// unidentifiable parameters' names.
fn base_parameters(arena: &Arena, b: &BaseParameters) -> Result<Parameters, Error> {
    let mut base_parameters = Vec::with_capacity(b.base.len());
    for p in &b.base {
        let mut terms = Vec::with_capacity(p.terms.len());
        for &(s, c) in &p.terms {
            let parameter = b.standard[s].to_string();
            let coefficient = match arena.as_num(c) {
                Some(n) if !n.to_f64().is_finite() => {
                    return Err(format!(
                        "the coefficient of {parameter} in base parameter {} is {}: the \
                         description's geometric values are beyond the range of f64 (about \
                         1.8e308) in this product; use values in metres and radians",
                        p.name,
                        n.to_f64()
                    )
                    .into());
                }
                Some(n) => serde_json::json!(n.to_f64()),
                None => serde_json::json!(arena.display(c)),
            };
            terms.push(Term {
                parameter,
                coefficient,
            });
        }
        base_parameters.push(Base {
            name: p.name.to_string(),
            expression: arena.display(p.expression),
            terms,
            value: None,
        });
    }
    let names = |i: &[usize]| i.iter().map(|&s| b.standard[s].to_string()).collect();
    Ok(Parameters {
        standard: b.standard.iter().map(|p| p.to_string()).collect(),
        base: base_parameters,
        unidentifiable: names(&b.unidentifiable),
    })
}

fn text(robot: &Robot, r: &Report) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "robot {} ({} DOF, {} DH)", r.name, r.dof, r.convention);
    // gamma and b (docs/conventions.md#khalil-kleinfinger-general-frames) only when a
    // joint has them, so a DH table prints as it always has
    let general = robot
        .joints()
        .iter()
        .any(|j| !j.gamma.is_zero() || !j.b.is_zero());
    // each column as wide as its widest entry: a URDF's fitted values print in full
    // (`0.289486614543747`) and used to push the columns after them out of line
    let mut header = vec!["j", "type"];
    if general {
        header.extend(["gamma", "b"]);
    }
    header.extend(["alpha", "a", "d", "theta"]);
    let mut rows: Vec<Vec<String>> = vec![header.iter().map(|h| h.to_string()).collect()];
    for (j, joint) in robot.joints().iter().enumerate() {
        let kind = match joint.kind {
            robid_symbolic::JointKind::Revolute => "revolute",
            robid_symbolic::JointKind::Prismatic => "prismatic",
        };
        let mut row = vec![(j + 1).to_string(), kind.to_string()];
        if general {
            row.extend([
                joint.gamma.as_str().to_string(),
                joint.b.as_str().to_string(),
            ]);
        }
        for value in [&joint.alpha, &joint.a, &joint.d, &joint.theta] {
            row.push(value.as_str().to_string());
        }
        rows.push(row);
    }
    // the widths the table always had (2, 10, then 12), wider where an entry is (with a
    // space more, so that two spaces part it from the next)
    let widths: Vec<usize> = (0..rows[0].len())
        .map(|c| {
            let least = [2, 10].get(c).copied().unwrap_or(12);
            rows.iter()
                .map(|r| r[c].chars().count())
                .fold(least, |w, len| if len < least { w } else { w.max(len + 1) })
        })
        .collect();
    for (k, row) in rows.iter().enumerate() {
        let mut line = String::from(if k == 0 { "\n " } else { " " });
        for (c, cell) in row.iter().enumerate() {
            line.push_str(&format!(" {cell:<w$}", w = widths[c]));
        }
        let _ = writeln!(out, "{}", line.trim_end());
    }
    for (what, mount) in [
        ("base (frame 0 in the world)", &r.base),
        ("tool (in frame n)", &r.tool),
    ] {
        if let Some(m) = mount {
            let _ = writeln!(
                out,
                "  {what}: xyz [{}], rpy [{}]",
                m.xyz.join(", "),
                m.rpy.join(", ")
            );
        }
    }
    let _ = writeln!(
        out,
        "\nstandard parameters ({}):",
        r.standard_parameters.len()
    );
    for chunk in r.standard_parameters.chunks(14) {
        let _ = writeln!(out, "  {}", chunk.join(" "));
    }
    let _ = writeln!(out, "\nbase parameters ({}):", r.base_parameters.len());
    let width = r
        .base_parameters
        .iter()
        .map(|b| b.name.len())
        .max()
        .unwrap_or(0);
    for b in &r.base_parameters {
        let _ = writeln!(out, "  {:<width$} = {}", b.name, b.expression);
    }
    if r.base_parameters.iter().any(|b| b.value.is_some()) {
        let _ = writeln!(
            out,
            "\nbase parameters from the URDF's inertials (6 digits; all of them in --json):"
        );
        for b in &r.base_parameters {
            let value = b
                .value
                .map_or("(a drive term: not in a URDF)".to_owned(), |v| {
                    robid_runtime::Num::rounded(v, 6).to_string()
                });
            let _ = writeln!(out, "  {:<width$} = {value}", b.name);
        }
    }
    let _ = writeln!(
        out,
        "\nunidentifiable (no effect on any torque, {}):",
        r.unidentifiable.len()
    );
    for chunk in r.unidentifiable.chunks(14) {
        let _ = writeln!(out, "  {}", chunk.join(" "));
    }
    let _ = writeln!(out, "\noperation counts:");
    for (name, counts) in &r.operations {
        let c = |k: &str| counts.get(k).and_then(|v| v.as_u64()).unwrap_or(0);
        let _ = writeln!(
            out,
            "  {:<20} {:>5} mul {:>5} add {:>4} neg {:>3} sin {:>3} cos {:>3} sign",
            name,
            c("mul"),
            c("add"),
            c("neg"),
            c("sin"),
            c("cos"),
            c("sign")
        );
    }
    out
}
