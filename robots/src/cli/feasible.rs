//! `robid feasible ROBOT.toml --identified RESULT.json [--bounds BOUNDS.toml]
//! [--method interior-point|cholesky|sdp|anneal] [--prior CAD.toml [--prior-weight W]]
//! [--restarts N] [--two-step] [--equal EQ]... [--mass-step DELTA] -o OUT`: physically
//! consistent link parameters that reproduce identified base parameters
//! (docs/experiments.md#feasible-parameters, docs/command-line.md#robid-feasible). Writes
//! OUT as TOML, or as URDF when OUT ends in `.urdf` or `.xml`: for a URDF description, the
//! user's own file with its chain links' `<inertial>` elements replaced; for a DH
//! description, a complete URDF in the DH frames.
//! Identified parameters with an empty expression that are not base parameters of the
//! description (the extra columns of an identification config) are kept as free terms,
//! at most [`MAX_FREE_TERMS`] of them.
//!
//! RESULT.json is checked before use ([`Identified::read`]); the solution is checked
//! before it is written (every value finite).

use std::path::{Path, PathBuf};

use robid_runtime::Num;
use robid_runtime::estimate::{QualityWarning, Sign, SignDefinite, base_signs};
use robid_runtime::feasible::{
    AnnealOptions, Bounds, DEFAULT_PRIOR_WEIGHT, Equality, GravityCoefficients, LinkBounds,
    LinkShape, Prior, Problem, STANDARD_GRAVITY, SdpOptions, SmoothOptions, Solution, Unsized,
    UrdfJoint, solve_anneal, solve_interior, solve_sdp, solve_smooth, solve_two_step, to_toml,
    to_urdf,
};
use robid_symbolic::Robot;
use robid_symbolic::robot::{Inertial, ParameterId, ParameterKind, UrdfChain, write_inertials};

use super::description::{self, DescriptionFlags};
use super::flags::{closed, count, only_for, positive, real};
use super::identified::{Identified, about_identified};
use super::{Error, files, out};

/// `robid feasible --help` on `--bounds`: the format with a complete example.
const BOUNDS_HELP: &str = "Bounds on masses, centres of mass, inertias and the total mass (TOML).

Links are numbered from 1; a link's table overrides the keys it gives; without the file every
link gets the [default] shown (see docs/command-line.md, \"Bounds file\"):

  total_mass = [15.0, 19.0]                       # kg, optional
  margin = 1e-6                                   # pseudo-inertia >= margin I (default 1e-6, or
                                                  # 1 % of the prior's smallest eigenvalue)
  [default]
  mass = [0.0, 50.0]                              # kg
  com = [[-1.0, 1.0], [-1.0, 1.0], [-1.0, 1.0]]   # box in the link frame, m
  inertia = [0.0, 5.0]                            # moments about the com, kg m^2
  [links.6]
  mass = [0.1, 0.5]
  inertia_tensor = { xx = [0.0, 0.004], xy = [-0.001, 0.001] }   # about the com";

/// The most entries of RESULT.json kept as free terms (not base parameters of the
/// description, no expression): each is a variable of the solvers, whose time grows
/// with the cube of their count (100 take about a second, 1000 minutes), and so many
/// mean a result of another robot rather than extra columns.
pub(crate) const MAX_FREE_TERMS: usize = 100;

/// Arguments of `robid feasible`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    #[arg(help = description::robot_help!())]
    robot: PathBuf,
    #[command(flatten)]
    description: DescriptionFlags,
    /// The identification result (JSON of `robid identify`: parameters with name, value, std).
    #[arg(long)]
    identified: PathBuf,
    /// Bounds on masses, centres of mass, inertias and the total mass (TOML).
    #[arg(long, long_help = BOUNDS_HELP)]
    bounds: Option<PathBuf>,
    /// `interior-point` (the convex fit's global optimum by a log-barrier method in the
    /// parameters: every iterate physically consistent; needs nothing but the Rust
    /// toolchain), `cholesky` (the same optimum over the Cholesky factors of every link's
    /// pseudo-inertia by argmin's trust region, an independent check; slow where the data
    /// are far firmer than the prior), `sdp` (the same convex fit by Clarabel; needs the
    /// `sdp` feature) or `anneal` (Gaz et al.'s global search).
    #[arg(long, default_value = "interior-point")]
    method: String,
    /// Prior standard parameters, e.g. CAD values (a parameter file with a `[standard]`
    /// table; parameters it does not list get the default prior, a solid along each link,
    /// except with `anneal`, which keeps the centre of the bounds for them). Default for a
    /// URDF: its own `<inertial>` elements.
    #[arg(long)]
    prior: Option<PathBuf>,
    /// Weight in [0, 1e6] of the pull towards the prior: a deviation of one parameter
    /// scale (a link's mass, its mass times its size, times its size squared) costs this
    /// many chi^2 units, so the prior counts as a measurement to 1 / sqrt(W) of each
    /// scale. With `--prior` or a URDF's inertials, the scales are each link's prior mass
    /// (at least 1 % of the heaviest link's) and the weight that prior's (default 100:
    /// each link trusted to 10 % of its own values, CAD's usual accuracy; the data decide
    /// what they determine better, the prior holds the rest; 0 leaves the fit to the data);
    /// without, the weight of the default prior of solid links (default 0.01: it settles
    /// what the data leave free; 0 leaves the fit to the data alone). Not with `anneal`
    /// without a prior (`--prior` or a URDF's): it has no default prior.
    #[arg(long, value_parser = real(closed(0.0, 1e6, "")))]
    prior_weight: Option<f64>,
    /// `anneal`: random restarts, each annealing then a local search (default 8; Gaz et al.
    /// use 1000).
    #[arg(long, value_parser = count(1, 10_000))]
    restarts: Option<usize>,
    /// `anneal`: Gaz et al.'s two-step extraction: first the masses and centres of mass from
    /// the gravity coefficients (the combinations of the identified base parameters that the
    /// gravity torques determine), then every other parameter with those held.
    #[arg(long)]
    two_step: bool,
    /// `anneal`: an equality constraint in the form of Gaz et al.'s eq. 15, e.g.
    /// "I7xz = c7x * c7z * m7" (m<link> mass, c<link>x|y|z centre of mass, I<link>xx..yz
    /// inertia about the centre of mass; links from 1); repeat for more.
    #[arg(long = "equal", value_name = "EQ")]
    equalities: Vec<String>,
    /// `anneal`: Gaz et al.'s step penalty, added to chi^2 when the total mass is outside
    /// the bounds' `total_mass` range (their delta), instead of the penalty proportional to
    /// the excess.
    #[arg(long, value_parser = real(positive(1e20, "")))]
    mass_step: Option<f64>,
    /// Output file: TOML, or a complete URDF (links with their inertials, joints from the
    /// description) for a `.urdf` / `.xml` name.
    #[arg(short, long)]
    output: PathBuf,
}

/// The text of `path`, a `what` (at most `robid_runtime::limits::MAX_TEXT_BYTES`: an
/// endless device such as `--identified /dev/zero` filled the memory).
fn read(path: &Path, what: &str) -> Result<String, Error> {
    Ok(robid_runtime::data::read_text(path, what)?)
}

/// Refuses, before any work, an output that is an input, an unknown method and options
/// of the other method.
fn check(args: &Args) -> Result<(), Error> {
    let mut inputs = vec![args.robot.as_path(), args.identified.as_path()];
    inputs.extend(args.bounds.as_deref());
    inputs.extend(args.prior.as_deref());
    files::refuse(&inputs, &[("--output", &args.output)])?;
    // the extension chooses the format: another one got TOML silently (`-o x.json`)
    if let Some(ext) = args.output.extension().and_then(|e| e.to_str())
        && !["toml", "urdf", "xml"].contains(&ext.to_ascii_lowercase().as_str())
    {
        return Err(format!(
            "--output {}: robid feasible writes TOML (`.toml`) or URDF (`.urdf`, `.xml`), not \
             `.{}`; name the file for the format you want",
            robid_runtime::names::short(&args.output.display().to_string()),
            robid_runtime::names::short(ext)
        )
        .into());
    }
    if !["interior-point", "cholesky", "sdp", "anneal"].contains(&args.method.as_str()) {
        return Err(format!(
            "--method {}: unknown; use interior-point, cholesky, sdp or anneal",
            args.method
        )
        .into());
    }
    // a method this build lacks is said before any file is read: fixing the inputs first
    // would be work for nothing
    if args.method == "sdp" {
        robid_sdp::solver()?;
    }
    if args.method != "anneal" {
        let (owner, method) = ("--method anneal", format!("--method {}", args.method));
        only_for(args.restarts.is_some(), "--restarts", owner, &method)?;
        only_for(args.two_step, "--two-step", owner, &method)?;
        only_for(!args.equalities.is_empty(), "--equal", owner, &method)?;
        only_for(args.mass_step.is_some(), "--mass-step", owner, &method)?;
    }
    if args.prior_weight.is_some()
        && args.prior.is_none()
        && !description::is_urdf(&args.robot)
        && args.method == "anneal"
    {
        return Err(
            "--prior-weight: anneal has no default prior to weigh; give --prior FILE or drop \
                    --prior-weight"
                .into(),
        );
    }
    Ok(())
}

/// A runtime error about the content of `path` (the identified result or the bounds),
/// named as that file: the runtime reports such keys as settings given in code. (A bounds
/// file that is not TOML is named by the runtime: "invalid bounds file".)
fn about(path: &Path, e: robid_runtime::Error) -> Error {
    match e {
        robid_runtime::Error::Setting { key, problem, .. } => {
            format!("{}: `{key}`: {problem}", path.display()).into()
        }
        other => other.into(),
    }
}

/// Refuses a solution with a value that is not a finite number.
fn check_solution(solution: &Solution) -> Result<(), Error> {
    let bad = solution
        .names
        .iter()
        .zip(&solution.standard)
        .find(|(_, x)| !x.is_finite())
        .map(|(n, x)| format!("{n} = {}", Num(*x)))
        .or_else(|| {
            (!solution.chi2.is_finite()).then(|| format!("chi^2 = {}", Num(solution.chi2)))
        });
    if let Some(what) = bad {
        return Err(format!(
            "the {} solution has {what}, not a finite number; nothing was written: check the \
             bounds and the identified values",
            solution.method.name()
        )
        .into());
    }
    if solution.unmet.is_empty() {
        return Ok(());
    }
    Err(unmet(solution, ""))
}

/// The error of a result outside bounds its method imposes; `note` ends it. The likely
/// cause depends on the fit: far from the identified values (some |z| beyond
/// [`PUSHED`]) the data may push against the bounds; within their uncertainty they do
/// not, and the bounds contradict each other or the physical consistency.
fn unmet(solution: &Solution, note: &str) -> Error {
    let (chi2, z) = (solution.chi2, solution.max_normalized_residual());
    let cause = if z > PUSHED {
        format!(
            "The data push hard against these bounds (chi^2 {chi2:.3e}, max |z| {z:.3}), or \
             the bounds contradict each other or the physical consistency"
        )
    } else {
        format!(
            "The fit is within the identified values' uncertainty (chi^2 {chi2:.3e}, max |z| \
             {z:.3}), so the data do not push against these bounds: they contradict each \
             other or the physical consistency"
        )
    };
    // an unmet --equal is checked there first (one that only a zero mass meets, such as
    // `m2 = 2 * m2`, cannot hold: masses are positive); else the bounds
    let check = if solution.unmet.iter().any(|u| u.starts_with("equality")) {
        "the --equal equalities (one that only a zero mass or a massless link meets, such as \
         `m2 = 2 * m2`, cannot hold), the bounds and the identified values"
    } else {
        "the bounds file and the identified values"
    };
    format!(
        "the {} fit ended outside bounds it imposes: {}; nothing was written. {cause}; check \
         {check}{note}",
        solution.method.name(),
        solution.unmet.join("; "),
    )
    .into()
}

/// The largest normalised residual |z| of a fit that the data can be said to push: beyond
/// three standard deviations of an identified value.
const PUSHED: f64 = 3.0;

/// The default method: the interior-point fit, or where it ends outside a bound it
/// imposes (the bounds on the inertia about the centre of mass are penalties of its
/// objective, which can stall where the data push hard against them; the masses, boxes
/// and total mass are in its barrier), the same convex optimum by the Cholesky method's
/// path, said on standard error, when that one meets them.
fn interior_or_cholesky(
    problem: &Problem,
    bounds: &Bounds,
    smooth: &SmoothOptions,
) -> Result<Solution, Error> {
    let first = solve_interior(problem, bounds, smooth)?;
    if first.unmet.is_empty() {
        return Ok(first);
    }
    let other = solve_smooth(problem, bounds, smooth)?;
    if !other.unmet.is_empty() {
        return Err(unmet(
            &first,
            " (the cholesky method, tried next, ended outside them too)",
        ));
    }
    out::warn(format_args!(
        "interior-point: ended outside {}; the cholesky method, the same optimum by another \
         path, meets every bound: its result is written",
        first.unmet.join("; ")
    ));
    Ok(other)
}

/// `--method cholesky`: its fit, checked against the interior-point method's optimum of
/// the same objective (found in a tenth of the time or less); where it stopped short
/// ([`Solution::short_of`]) a warning says so and by how much. Its own result is written,
/// as asked.
fn cholesky_checked(
    problem: &Problem,
    bounds: &Bounds,
    smooth: &SmoothOptions,
) -> Result<Solution, Error> {
    let solution = solve_smooth(problem, bounds, smooth)?;
    if let Ok(optimum) = solve_interior(problem, bounds, smooth)
        && optimum.unmet.is_empty()
        && let Some(short) = solution.short_of(&optimum)
    {
        out::warn(format_args!("warning: {short}"));
    }
    Ok(solution)
}

/// Runs the subcommand.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    check(args)?;
    let description = description::load(&args.robot, &args.description)?;
    let robot = &description.robot;
    let identified = Identified::read(&args.identified)?;
    let mut problem = robots::extraction::problem(robot)?;
    if let Some(chain) = &description.urdf {
        // the links' segments between the URDF's joints, not between the fitted frames'
        // origins, which can lie metres away at the feet of common normals
        let segments = chain.link_segments().map_err(|e| e.to_string())?;
        problem = problem.with_shapes(
            segments
                .into_iter()
                .map(|[from, to]| LinkShape { from, to })
                .collect(),
        )?;
    }
    // Extra columns of the identification config (no expression, not a base parameter,
    // e.g. a coupled wrist's `Iam6`) are kept as free terms.
    let extra: Vec<String> = identified
        .parameters
        .iter()
        .filter(|p| p.expression.is_empty() && !problem.base_names.contains(&p.name))
        .map(|p| p.name.clone())
        .collect();
    if extra.len() > MAX_FREE_TERMS {
        return Err(format!(
            "{}: {} entries are not base parameters of {} (`{}`, `{}`, ...), more than the \
             {MAX_FREE_TERMS} extra columns kept as free terms; give the description (and \
             --drive) the result was identified with",
            args.identified.display(),
            extra.len(),
            args.robot.display(),
            extra[0],
            extra[1]
        )
        .into());
    }
    let problem = problem
        .with_extra_columns(&extra)
        .map_err(|e| about_identified(&args.identified, e))?;
    let names: Vec<String> = identified
        .parameters
        .iter()
        .map(|p| p.name.clone())
        .collect();
    let values: Vec<f64> = identified.parameters.iter().map(|p| p.value).collect();
    let std: Vec<f64> = identified.parameters.iter().map(|p| p.std).collect();
    // each value weighed by the larger of its classical and robust deviations, as identify
    // judges it (a parameter without a robust deviation by its classical one)
    let robust: Vec<f64> = identified
        .parameters
        .iter()
        .map(|p| p.robust_std.unwrap_or(p.std))
        .collect();
    let judged: Vec<f64> = std.iter().zip(&robust).map(|(s, r)| s.max(*r)).collect();
    let problem = problem
        .with_identified(&names, &values, &judged)
        .map_err(|e| about_identified(&args.identified, e))?;
    // the names agree (else the error names them, or the drive terms): now what they are
    identified.check_expressions(&args.identified, &problem, robot, &args.robot)?;
    // identified values no physical robot has (a sum of masses, inertias or frictions
    // below zero beyond its uncertainty): what a result far from the data comes from
    let unphysical = not_physical(&problem, &names, &values, &std, &robust);
    let weight = args.prior_weight.unwrap_or(Prior::DEFAULT_WEIGHT);
    let prior = match (&args.prior, &description.urdf) {
        (Some(path), _) => Some(Prior {
            standard: description::read_parameters(path, false)?.prior(&problem.standard_names)?,
            weight,
        }),
        // a URDF's own inertials are its CAD values
        (None, Some(_)) => {
            out::warn(format_args!(
                "prior: the URDF's own <inertial> elements (weight {}; --prior FILE \
                 replaces them, --prior-weight 0 leaves the fit to the data)",
                Num(weight)
            ));
            Some(Prior {
                standard: problem
                    .standard_names
                    .iter()
                    .map(|name| description.urdf_inertial(name))
                    .collect(),
                weight,
            })
        }
        (None, None) => None,
    };
    let prior_given = prior.is_some();
    let links = problem.layout.links.len();
    let bounds_file = match &args.bounds {
        Some(path) => Some((path.display().to_string(), read(path, "bounds file")?)),
        None => None,
    };
    let bounds = match (&bounds_file, &args.bounds) {
        (Some((name, text)), Some(path)) => {
            Bounds::from_toml(text, name, links).map_err(|e| about(path, e))?
        }
        // wide, and wider for a robot whose prior links are heavier or larger
        _ => Bounds::wide_for(&problem, prior.as_ref()),
    };
    // the solvers' errors about the bounds (below the margin) named in the bounds file
    let in_bounds_file = |e: Error| match (e.downcast::<robid_runtime::Error>(), &bounds_file) {
        (Ok(e), Some((name, text))) => Bounds::locate(text, name, *e).into(),
        (Ok(e), None) => (*e).into(),
        (Err(e), _) => e,
    };
    // the default prior's weight: --prior-weight without a prior, else the default
    let default_weight = match (&prior, args.prior_weight) {
        (None, Some(w)) => w,
        _ => DEFAULT_PRIOR_WEIGHT,
    };
    let smooth = SmoothOptions {
        prior: prior.clone(),
        default_weight,
        ..SmoothOptions::default()
    };
    // anneal takes the default prior only for what a user's prior omits, and falls back
    // to the centre of the bounds for links without a size as the default prior does
    if args.method != "anneal"
        && let Some(reason) = problem.unsized_links()
    {
        unsized_links(args, &problem, &bounds, prior.as_ref(), reason)?;
    }
    let solution = match args.method.as_str() {
        "anneal" => anneal(args, robot, &problem, &bounds, prior, extra.is_empty()),
        "sdp" => robid_sdp::solver()
            .and_then(|solver| {
                let options = SdpOptions {
                    prior,
                    regularization: default_weight,
                };
                solve_sdp(&problem, &bounds, &options, solver)
            })
            .map_err(Error::from),
        "cholesky" => cholesky_checked(&problem, &bounds, &smooth),
        _ => interior_or_cholesky(&problem, &bounds, &smooth),
    }
    .map_err(in_bounds_file)?;
    check_solution(&solution)?;
    let urdf = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| ["urdf", "xml"].contains(&e.to_ascii_lowercase().as_str()));
    let text = if let (true, Some(chain)) = (urdf, &description.urdf) {
        urdf_written_back(&args.robot, chain, &solution)?
    } else if urdf {
        let tool = robot.tool_placement().map_err(|e| e.to_string())?;
        let gravity = robot.gravity_values().map_err(|e| e.to_string())?;
        to_urdf(
            &solution,
            robot.name(),
            &urdf_joints(robot)?,
            tool.as_ref(),
            gravity,
        )
    } else {
        to_toml(&solution, robot.name())
    };
    files::write(&args.output, &text)?;
    if urdf {
        warn_not_in_urdf(&args.output, &solution);
    }
    if urdf && description.urdf.is_none() {
        let gravity = robot.gravity_values().map_err(|e| e.to_string())?;
        if let Some(w) = urdf_gravity_warning(&args.output, gravity) {
            out::warn(format_args!("{w}"));
        }
    }
    out::warn(format_args!(
        "{}: chi^2 {:.3e}, max |z| {:.3}, smallest pseudo-inertia eigenvalue {:.3e}, {:.3} s{}",
        solution.method.name(),
        solution.chi2,
        solution.max_normalized_residual(),
        solution
            .min_eigenvalues
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min),
        solution.seconds,
        if solution.violations.is_empty() {
            String::new()
        } else {
            format!("; bounds not met: {}", solution.violations.join("; "))
        }
    ));
    if !solution.dont_care.is_empty() {
        out::warn(format_args!(
            "not from the data (no effect on the torques), {}",
            solution.dont_care_note()
        ));
    }
    for at in &solution.at_bounds {
        out::warn(format_args!("warning: {at}"));
    }
    warn_implausible(args, &solution, prior_given);
    warn_far_from_the_data(&solution, &problem, args.two_step, &unphysical);
    Ok(())
}

/// Warns of each link no body of its size can be ([`Solution::implausible`]), with the
/// flags that settle it: `--bounds` on its centre of mass or mass, or a prior (`--prior`; a
/// larger `--prior-weight` where a prior pulls, which `anneal` without one has not).
fn warn_implausible(args: &Args, solution: &Solution, prior_given: bool) {
    for link in &solution.implausible {
        let weight = if args.method == "anneal" && !prior_given {
            ""
        } else {
            ", or a larger --prior-weight"
        };
        out::warn(format_args!(
            "warning: {link}: --bounds with that table, --prior with the link's values{weight}"
        ));
    }
}

/// A base parameter reproduced this many standard deviations from its identified value
/// is one the result does not fit: the bounds, the prior or the method overrule the data,
/// unless the identified values themselves are not physical ([`not_physical`]).
const FAR: f64 = 10.0;

/// The identified base parameters (`names`, `values`, `std`, the `robust` deviations)
/// whose sign every physical robot fixes, by `problem`'s K, and that lie on the other side
/// of zero by more than three of the larger of their deviations (`robid identify`'s
/// `not_physical` warnings). The free terms (extra columns, of any sign in the problem)
/// are not judged.
fn not_physical(
    problem: &Problem,
    names: &[String],
    values: &[f64],
    std: &[f64],
    robust: &[f64],
) -> Vec<QualityWarning> {
    // a free term's name may read as a drive term (`Fv1`): it is not one here
    let standard: Vec<String> = problem
        .standard_names
        .iter()
        .enumerate()
        .map(|(s, n)| {
            if problem.layout.extra.contains(&s) {
                String::new()
            } else {
                n.clone()
            }
        })
        .collect();
    let signs: Vec<(String, SignDefinite)> = problem
        .base_names
        .iter()
        .zip(base_signs(&problem.k, &standard))
        .filter_map(|(n, s)| Some((n.clone(), s?)))
        .collect();
    robid_runtime::estimate::not_physical(names, values, std, Some(robust), &signs)
}

/// Warns when the result reproduces a base parameter more than [`FAR`] standard
/// deviations from its identified value, naming the worst (a two-step extraction that
/// held a mass the gravity coefficients leave free gave max |z| 435, silently). When
/// identified values are not physical (`unphysical`, [`not_physical`]), no consistent
/// parameters are near them whatever the bounds, prior or method: the warning names them
/// and points at the identification's model and data instead.
fn warn_far_from_the_data(
    solution: &Solution,
    problem: &Problem,
    two_step: bool,
    unphysical: &[QualityWarning],
) {
    let Some((k, z)) = solution
        .normalized_residual
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.abs().total_cmp(&b.1.abs()))
    else {
        return;
    };
    if z.abs() <= FAR {
        return;
    }
    let name = problem.base_names.get(k).map_or("?", String::as_str);
    if let Some(text) = not_physical_text(unphysical) {
        out::warn(format_args!(
            "warning: the result is {:.0} standard deviations from the identified `{name}` (max \
             |z|; |z| <= 3 fits the data), because the identified values themselves are not \
             physical: {text}. No physically consistent parameters come near them, whatever \
             the bounds, the prior or the method: fix the identification first (robid \
             identify warns of the same, `not_physical`): check its model (friction or drive \
             terms it lacks, such as Fv, Fc or Ia per joint, or a coupling of the drives) and \
             its data (the torques' units and gear ratios, the column order, the sign of each \
             joint's position and torque)",
            z.abs()
        ));
        return;
    }
    out::warn(format_args!(
        "warning: the result is {:.0} standard deviations from the identified `{name}` (max \
         |z|; |z| <= 3 fits the data): the bounds, the prior{} overrule the data there; check \
         them before using these values",
        z.abs(),
        if two_step {
            " or the gravity step's held masses and centres of mass (--two-step)"
        } else {
            " or the method"
        }
    ));
}

/// The identified values of `unphysical` in words: "`ZZ7` = -0.212 +- 0.00513 (41.4
/// standard deviations below 0, though ZZ7 is >= 0 for every physical robot); ..."; `None`
/// when there are none.
fn not_physical_text(unphysical: &[QualityWarning]) -> Option<String> {
    let parts: Vec<String> = unphysical
        .iter()
        .filter_map(|w| match w {
            QualityWarning::NotPhysical {
                parameter,
                value,
                std,
                robust,
                sign,
                expression,
                ..
            } => Some(format!(
                "`{parameter}` = {} +- {} ({:.1} {}standard deviations {} 0, though \
                 {expression} is {} 0 for every physical robot)",
                Num::rounded(*value, 3),
                Num::rounded(*std, 3),
                sign.beyond(*value, *std),
                if *robust { "robust " } else { "" },
                match sign {
                    Sign::NonNegative => "below",
                    Sign::NonPositive => "above",
                },
                match sign {
                    Sign::NonNegative => ">=",
                    Sign::NonPositive => "<=",
                },
            )),
            _ => None,
        })
        .collect();
    (!parts.is_empty()).then(|| parts.join("; "))
}

/// Where the default prior cannot size the links ([`Unsized`]), the links it would settle
/// (those `prior` does not give in full) take the centre of their bounds: refused, naming
/// the bounds entries to write, for a link whose bounds are the defaults (their centre,
/// 25 kg, is no knowledge of the robot; a robot without length got 9.5e5 kg from specks of
/// solid before), else said on standard error.
fn unsized_links(
    args: &Args,
    problem: &Problem,
    bounds: &Bounds,
    prior: Option<&Prior>,
    reason: Unsized,
) -> Result<(), Error> {
    let open: Vec<usize> = (0..problem.layout.links.len())
        .filter(|&j| {
            problem.layout.links[j]
                .iter()
                .any(|&s| prior.is_none_or(|p| p.standard[s].is_none()))
        })
        .collect();
    let list = |links: &[usize]| {
        let numbers: Vec<String> = links.iter().map(|j| (j + 1).to_string()).collect();
        format!(
            "link{} {}",
            if links.len() == 1 { "" } else { "s" },
            numbers.join(", ")
        )
    };
    let blind: Vec<usize> = open
        .iter()
        .copied()
        .filter(|&j| args.bounds.is_none() || bounds.links[j] == LinkBounds::default())
        .collect();
    if let Some(&first) = blind.first() {
        return Err(format!(
            "{}: {reason}; give ranges for {} in --bounds (e.g. `[links.{}]` with `mass = \
             [lo, hi]`, `com = [[x0, x1], [y0, y1], [z0, z1]]`, `inertia = [lo, hi]`: the prior \
             is their centre) or values in --prior",
            args.robot.display(),
            list(&blind),
            first + 1
        )
        .into());
    }
    if let (false, Some(path)) = (open.is_empty(), &args.bounds) {
        out::warn(format_args!(
            "warning: {reason}; the prior of {} is the centre of the bounds in {}",
            list(&open),
            path.display()
        ));
    }
    Ok(())
}

/// The settings of `AnnealOptions` that flags fill, and their flags: an equality naming a
/// link beyond the robot is told as `--equal: ...`, not as the library's type.
const ANNEAL_FLAGS: &[(&str, &str)] = &[("equalities", "--equal"), ("restarts", "--restarts")];

/// The `anneal` method with its options, in one step or in Gaz et al.'s two.
fn anneal(
    args: &Args,
    robot: &Robot,
    problem: &Problem,
    bounds: &Bounds,
    prior: Option<Prior>,
    no_extra: bool,
) -> Result<Solution, Error> {
    let equalities = args
        .equalities
        .iter()
        .map(|e| {
            e.parse::<Equality>()
                .map_err(|err| Error::from(format!("--equal: {}", problem_of(err))))
        })
        .collect::<Result<Vec<_>, _>>()?;
    if args.mass_step.is_some() && bounds.total_mass.is_none() {
        return Err(
            "--mass-step: the bounds give no `total_mass` range to hold; add one to \
                    --bounds or drop --mass-step"
                .into(),
        );
    }
    let options = AnnealOptions {
        prior,
        restarts: args.restarts.unwrap_or(AnnealOptions::default().restarts),
        equalities,
        mass_step: args.mass_step,
        progress: true,
        ..AnnealOptions::default()
    };
    if !args.two_step {
        return solve_anneal(problem, bounds, &options)
            .map_err(|e| e.on_flags(ANNEAL_FLAGS).into());
    }
    if !no_extra {
        return Err(format!(
            "--two-step: {} holds columns that are not base parameters of the description \
             (extra config columns); the gravity step needs the model's base parameters only",
            args.identified.display()
        )
        .into());
    }
    let model = robots::interpreted::model_for(robot)?;
    let names: Vec<&str> = (0..model.model.base_parameter_count())
        .filter_map(|b| model.model.base_parameter_name(b))
        .collect();
    if names != problem.base_names {
        return Err(format!(
            "--two-step: the model's base parameters ({}) differ from the extraction \
             problem's ({}); please report this",
            names.join(" "),
            problem.base_names.join(" ")
        )
        .into());
    }
    let gravity = GravityCoefficients::of_model(model.model.as_ref())?;
    if gravity.names.is_empty() {
        return Err(
            "--two-step: gravity determines no combination of base parameters for \
                    this description (no gravity along a joint's motion); drop --two-step"
                .into(),
        );
    }
    let result = solve_two_step(&gravity.problem(problem)?, problem, bounds, &options)
        .map_err(|e| e.on_flags(ANNEAL_FLAGS))?;
    out::warn(format_args!(
        "gravity step: chi^2 {:.3e} over {} gravity coefficients ({}); holds {}",
        result.gravity.chi2,
        gravity.names.len(),
        gravity.names.join(" "),
        result
            .held
            .iter()
            .map(|(v, x)| format!("{v} = {x:.6e}"))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    Ok(result.solution)
}

/// The problem a runtime setting error states, without its owner.
fn problem_of(e: robid_runtime::Error) -> String {
    match e {
        robid_runtime::Error::Setting { problem, .. } => problem,
        other => other.to_string(),
    }
}

/// Says which values of `solution` the URDF `output` cannot hold: a URDF has `<inertial>`
/// elements only, so the drive terms and the extra columns are left out (a URDF's
/// `<dynamics>` damping and friction are not the identified terms' model, and robid does
/// not read them).
fn warn_not_in_urdf(output: &Path, solution: &Solution) {
    let left: Vec<&str> = solution
        .names
        .iter()
        .filter(|n| {
            !solution.is_chain_parameter(n)
                || !matches!(
                    n.parse::<ParameterId>(),
                    Ok(ParameterId {
                        kind: ParameterKind::Inertial(_),
                        ..
                    })
                )
        })
        .map(String::as_str)
        .collect();
    if !left.is_empty() {
        let stem = output.with_extension("toml");
        out::warn(format_args!(
            "warning: {} holds the links' inertials only, not {} ({}): a URDF has no place \
             for drive terms or extra columns; write them with -o {} as well",
            output.display(),
            robid_runtime::Count(left.len(), "identified value"),
            left.join(" "),
            stem.display()
        ));
    }
}

/// The warning for a URDF `output` of a description whose gravity's magnitude is not the
/// [`STANDARD_GRAVITY`] URDF readers apply: a URDF carries no gravity (the file says so
/// only in a comment), so its gravity torques differ from the description's by the ratio
/// (`gravity = [3, -4, -8]`, 9.434 m/s^2: 4 %, read back without a word).
fn urdf_gravity_warning(output: &Path, gravity: [f64; 3]) -> Option<String> {
    let magnitude = gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
    if (magnitude - STANDARD_GRAVITY).abs() <= 1e-9 * STANDARD_GRAVITY {
        return None;
    }
    let off = if magnitude > 0.0 {
        format!(
            "{:.2} % off the description's",
            100.0 * (STANDARD_GRAVITY / magnitude - 1.0).abs()
        )
    } else {
        "not the description's zero".to_owned()
    };
    Some(format!(
        "warning: {}: the description's gravity is {} m/s^2, but a URDF carries no gravity and \
         its readers (robid's too) apply {STANDARD_GRAVITY}: its gravity torques are {off}; \
         for this gravity use the TOML output (-o {}) with the description",
        output.display(),
        Num::rounded(magnitude, 4),
        output.with_extension("toml").display()
    ))
}

/// The user's URDF with each chain link's `<inertial>` replaced by the solution's, in the
/// URDF's own link frames, every other byte as it was (docs/urdf.md#inertials-both-ways).
fn urdf_written_back(path: &Path, chain: &UrdfChain, solution: &Solution) -> Result<String, Error> {
    let text = read(path, "URDF")?;
    let mut inertials = vec![[0.0; 10]; chain.links.len()];
    for (name, value) in solution.names.iter().zip(&solution.standard) {
        if let Ok(ParameterId {
            link,
            kind: ParameterKind::Inertial(inertial),
        }) = name.parse::<ParameterId>()
            && let Some(k) = Inertial::ALL.iter().position(|&i| i == inertial)
            && let Some(row) = inertials.get_mut(link)
        {
            row[k] = *value;
        }
    }
    let (written, warnings) =
        write_inertials(&text, &path.display().to_string(), chain, &inertials)?;
    for w in &warnings {
        out::warn(format_args!("warning: {w}"));
    }
    Ok(written)
}

/// The description's joints for a URDF: placements and limits.
fn urdf_joints(robot: &Robot) -> Result<Vec<UrdfJoint>, Error> {
    let placements = robot.joint_placements().map_err(|e| e.to_string())?;
    Ok(robot
        .joints()
        .iter()
        .zip(placements)
        .map(|(joint, place)| UrdfJoint {
            prismatic: joint.kind == robid_symbolic::JointKind::Prismatic,
            origin: place.origin,
            link_frame: place.link_frame,
            position: joint.limits.position,
            velocity: joint.limits.velocity,
            effort: joint.limits.torque,
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use robid_runtime::feasible::Method;

    fn solution(standard: Vec<f64>, chi2: f64) -> Solution {
        Solution {
            method: Method::Anneal,
            names: vec!["M1".into(), "MX1".into()],
            standard,
            links: Vec::new(),
            base: Vec::new(),
            normalized_residual: Vec::new(),
            chi2,
            min_eigenvalues: Vec::new(),
            dont_care: Vec::new(),
            unpulled: Vec::new(),
            violations: Vec::new(),
            unmet: Vec::new(),
            extra_columns: Vec::new(),
            at_bounds: Vec::new(),
            implausible: Vec::new(),
            determined: Vec::new(),
            seconds: 0.0,
            iterations: 0,
            objective: None,
        }
    }

    #[test]
    fn a_solution_with_a_non_finite_value_is_not_written() {
        assert!(check_solution(&solution(vec![1.0, 0.2], 3.0)).is_ok());
        let e = check_solution(&solution(vec![1.0, f64::NAN], 3.0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("the anneal solution has MX1 = NaN"), "{e}");
        let e = check_solution(&solution(vec![1.0, 0.2], f64::INFINITY))
            .unwrap_err()
            .to_string();
        assert!(e.contains("chi^2 = inf"), "{e}");
    }

    /// A URDF of a description whose gravity is not 9.81 m/s^2 is warned of with the
    /// magnitude and the error (it was said in an XML comment only), no gravity too;
    /// gravity of that magnitude along another axis is not.
    #[test]
    fn a_urdf_warns_of_a_gravity_it_cannot_carry() {
        let out = Path::new("links.urdf");
        let w = urdf_gravity_warning(out, [3.0, -4.0, -8.0]).unwrap();
        assert!(
            w.contains("links.urdf: the description's gravity is 9.434 m/s^2")
                && w.contains("apply 9.81: its gravity torques are 3.99 % off")
                && w.contains("-o links.toml"),
            "{w}"
        );
        assert_eq!(urdf_gravity_warning(out, [0.0, 9.81, 0.0]), None);
        let w = urdf_gravity_warning(out, [0.0; 3]).unwrap();
        assert!(w.contains("are not the description's zero"), "{w}");
    }

    /// The URDF written for a DH description reads back with robid's own reader, each
    /// joint with its kind and limits: a prismatic joint without position limits had
    /// lower="-1e9" upper="1e9", which the reader refuses (beyond +-1000).
    #[test]
    fn the_urdf_of_a_description_reads_back() {
        use robid_runtime::feasible::LinkInertial;
        use robid_symbolic::robot::ChainSelection;
        let text = "name = \"rrp\"\nconvention = \"modified\"\ngravity = [0, 0, -9.81]\n\
                    [[joints]]\nalpha = 0\nd = 0.4\nlimits = { position = [-2.5, 2.5], torque = 50 }\n\
                    [[joints]]\nalpha = \"-pi/2\"\nd = 0.15\n\
                    [[joints]]\ntype = \"prismatic\"\nalpha = \"pi/2\"\ntheta = 0\n\
                    limits = { velocity = 0.5 }\n";
        let robot = Robot::from_toml(text, "rrp.toml").unwrap();
        let body = LinkInertial {
            mass: 2.0,
            com: [0.0, 0.0, 0.1],
            inertia: [[0.02, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.01]],
        };
        let mut s = solution(Vec::new(), 0.0);
        s.links = vec![Some(body); 3];
        let urdf = to_urdf(
            &s,
            robot.name(),
            &urdf_joints(&robot).unwrap(),
            None,
            [0.0, 0.0, -9.81],
        );
        let back = Robot::from_urdf(&urdf, "rrp.urdf", &ChainSelection::default())
            .unwrap_or_else(|e| panic!("{e}\n{urdf}"));
        let joints = back.robot.joints();
        assert_eq!(joints.len(), 3);
        assert_eq!(joints[2].kind, robid_symbolic::JointKind::Prismatic);
        assert!(back.links[1].continuous);
        for (read, written) in joints.iter().zip(robot.joints()) {
            assert_eq!(read.limits, written.limits);
        }
        assert_eq!(back.links[2].inertial[9], 2.0);
    }
}
