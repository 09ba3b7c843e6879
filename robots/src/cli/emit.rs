//! `robid emit ROBOT.toml [--lang rust|c] [--scalar double|float] [-o FILE]`: the
//! generated code of a robot. Rust (the default): the pretty-printed module that
//! `robot_model!` compiles (for a URDF with `URDF_STANDARD_PARAMETERS`, the file's own
//! inertials, through the same `robid_symbolic::emit::model_tokens`) and that is checked
//! into robots/generated/ for the reference robots. C: a C99 header and source with the
//! same functions and operation counts (for a URDF with `NAME_urdf_standard_parameters`,
//! the same values).

use super::description::{self, Description, DescriptionFlags};
use super::{Error, files, out};
use robid_runtime::{Error as RuntimeError, OutputError};
use robid_symbolic::emit::{CScalar, emit_c_model, emit_model};
use robid_symbolic::program::RobotPrograms;
use std::path::{Path, PathBuf};

/// The language of `robid emit`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Lang {
    /// A Rust module (`no_std`, generic over the scalar).
    Rust,
    /// A C99 header and source (`-o FILE.c`; the header is written next to it as `FILE.h`).
    C,
}

/// The scalar type of emitted C.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(crate) enum Scalar {
    /// `double`.
    Double,
    /// `float`.
    Float,
}

/// Arguments of `robid emit`.
#[derive(Debug, clap::Args)]
pub(crate) struct Args {
    #[arg(help = description::robot_help!())]
    robot: PathBuf,
    #[command(flatten)]
    description: DescriptionFlags,
    /// Language of the generated code.
    #[arg(long, value_enum, default_value = "rust")]
    lang: Lang,
    /// Scalar type of C code (`--lang c` only; Rust code is generic over it).
    #[arg(long, value_enum)]
    scalar: Option<Scalar>,
    /// Write to this file instead of standard output (required for C: `FILE.c`, with
    /// the header `FILE.h` next to it).
    #[arg(short, long)]
    output: Option<PathBuf>,
}

/// Emits the code.
pub(crate) fn run(args: &Args) -> Result<(), Error> {
    match args.lang {
        Lang::Rust => rust(args),
        Lang::C => c(args),
    }
}

fn rust(args: &Args) -> Result<(), Error> {
    if args.scalar.is_some() {
        return Err("`--scalar` is for `--lang c`; Rust code is generic over the scalar".into());
    }
    if let Some(path) = &args.output {
        files::refuse(&[&args.robot], &[("--output", path)])?;
    }
    let description = description::load(&args.robot, &args.description)?;
    warn_unloaded(args, &description, "URDF_STANDARD_PARAMETERS");
    // a URDF's own inertials, as `robot_model!(file = "x.urdf")` adds them
    let urdf_standard = description
        .urdf
        .as_ref()
        .map(|chain| chain.standard_values(&description.robot));
    let programs = derive(&description)?;
    let code = emit_model(&programs, urdf_standard.as_deref())?;
    match &args.output {
        Some(path) => files::write(path, &code)?,
        None => out::print(&code)?,
    }
    Ok(())
}

fn c(args: &Args) -> Result<(), Error> {
    let Some(source) = args.output.as_deref() else {
        return Err(
            "`--lang c` writes a header and a source: give `-o FILE.c` (the header is written \
             next to it as FILE.h)"
                .into(),
        );
    };
    if source.extension().and_then(|e| e.to_str()) != Some("c") {
        return Err(format!(
            "`-o {}`: the C source must end in `.c` (the header is written next to it as .h)",
            source.display()
        )
        .into());
    }
    let header = source.with_extension("h");
    files::refuse(&[&args.robot], &[("--output", source)])?;
    files::refuse(
        &[&args.robot],
        &[("--output", source), ("its C header", &header)],
    )
    .map_err(|e| header_error(source, &header, e))?;
    let description = description::load(&args.robot, &args.description)?;
    let constant = format!(
        "{}_urdf_standard_parameters",
        description.robot.name().to_lowercase()
    );
    warn_unloaded(args, &description, &constant);
    // a URDF's own inertials, as the Rust code holds them
    let urdf_standard = description
        .urdf
        .as_ref()
        .map(|chain| chain.standard_values(&description.robot));
    let scalar = match args.scalar {
        Some(Scalar::Float) => CScalar::Float,
        Some(Scalar::Double) | None => CScalar::Double,
    };
    let header_name = file_name(&header);
    let programs = derive(&description)?;
    let code = emit_c_model(&programs, scalar, &header_name, urdf_standard.as_deref())?;
    files::write(&header, &code.header)?;
    files::write(source, &code.source)?;
    Ok(())
}

/// The programs of the description, warning about the drive offsets its gravity vector
/// holds ([`description::warn_folded_offsets`]).
fn derive(description: &Description) -> Result<RobotPrograms, Error> {
    Ok(RobotPrograms::derive_showing(
        &description.robot,
        &mut |_| {},
        &mut |_, base| description::warn_folded_offsets(&base.standard, &base.base),
    )?)
}

/// With a URDF: warns about the joints whose torque the file's own inertials, which the
/// code holds as `constant`, leave 0 or without gravity ([`Description::warn_unloaded`]);
/// the code is written all the same, since its functions take any parameters.
fn warn_unloaded(args: &Args, description: &Description, constant: &str) {
    description.warn_unloaded(
        &args.robot,
        &format!("with the URDF's own inertials (`{constant}` in the code)"),
        "at every state",
        "or give the generated functions parameters of your own",
    );
}

/// The error `e` of the header path `header` of the C source `source`: a name the user did
/// not type, named as the header of `-o source`, with a fix that holds for it.
fn header_error(source: &Path, header: &Path, e: Error) -> Error {
    let (s, h) = (source.display(), header.display());
    match e.downcast_ref::<RuntimeError>() {
        Some(RuntimeError::Output(OutputError::Folder { .. })) => format!(
            "{h}: is a folder, and `-o {s}` writes the C header there; give `-o` another \
             name, or move {h} away"
        )
        .into(),
        Some(RuntimeError::Output(OutputError::OutputIsInput { input, .. })) => format!(
            "{h}, the C header that `-o {s}` writes, is also an input of this run ({}); give \
             `-o` another name",
            input.display()
        )
        .into(),
        _ => format!("{e} (the C header that `-o {s}` writes)").into(),
    }
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}
