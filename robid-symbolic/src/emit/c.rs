//! C99 emission: the programs of a robot as a header and a source file.
//!
//! The same programs and table as the Rust emitter (one function per entry of
//! [`PROGRAMS`](robid_core::PROGRAMS)), so the same operation counts: each input array is read into named
//! values, every temporary is one `const` local, and the output array is written at
//! the end. No allocation, no global state; `double` or `float`; only `<math.h>`
//! (`sin`, `cos`, `sqrt`). Geometric symbols are the fields of a `NAME_geometry`
//! struct passed first to every function of a robot that has them.

use super::EmitError;
use super::names::value_name;
use crate::program::{Instr, Program, RobotPrograms, Value};
use robid_core::{ProgramInfo, Sizes};
use std::fmt::Write;

/// The scalar type of emitted C code.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CScalar {
    /// `double`, with `sin`, `cos`, `sqrt`.
    #[default]
    Double,
    /// `float`, with `sinf`, `cosf`, `sqrtf` (constants rounded to `float`).
    Float,
}

impl CScalar {
    fn name(self) -> &'static str {
        match self {
            CScalar::Double => "double",
            CScalar::Float => "float",
        }
    }

    fn function(self, f: &str) -> String {
        match self {
            CScalar::Double => f.to_owned(),
            CScalar::Float => format!("{f}f"),
        }
    }

    /// A literal that reads back as `x` (shortest round trip; `f` suffix for float).
    fn literal(self, x: f64) -> String {
        let text = match self {
            CScalar::Double => format!("{x:?}"),
            CScalar::Float => format!("{:?}", x as f32),
        };
        let text = if text.contains(['.', 'e', 'E']) {
            text
        } else {
            format!("{text}.0")
        };
        match self {
            CScalar::Double => text,
            CScalar::Float => format!("{text}f"),
        }
    }
}

/// A robot as C99: a header (`#include` it) and a source (compile it).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CCode {
    /// The header: sizes, parameter names, the geometry struct, one prototype per program.
    pub header: String,
    /// The source: the functions.
    pub source: String,
}

/// Words C reserves (C99 keywords and the `<math.h>` functions the code calls), which
/// cannot name a geometric symbol in C.
const RESERVED: &[&str] = &[
    "auto", "break", "case", "char", "const", "continue", "default", "do", "double", "else",
    "enum", "extern", "float", "for", "goto", "if", "inline", "int", "long", "register",
    "restrict", "return", "short", "signed", "sizeof", "static", "struct", "switch", "typedef",
    "union", "unsigned", "void", "volatile", "while", "sin", "cos", "sqrt", "sinf", "cosf",
    "sqrtf",
];

/// The C code of `programs`; `header_file` is the name the source includes
/// (`ur5e.h`).
///
/// ```
/// use robid_symbolic::Robot;
/// use robid_symbolic::emit::{CScalar, emit_c};
/// use robid_symbolic::program::RobotPrograms;
/// let text = "name = \"arm\"\nconvention = \"modified\"\n[[joints]]\n[[joints]]\na = 0.5\n";
/// let programs = RobotPrograms::derive(&Robot::from_toml(text, "arm.toml").unwrap()).unwrap();
/// let c = emit_c(&programs, CScalar::Double, "arm.h").unwrap();
/// assert!(c.header.contains("void arm_inverse_dynamics(const double q[2]"));
/// assert!(c.source.contains("#include \"arm.h\""));
/// ```
pub fn emit_c(
    programs: &RobotPrograms,
    scalar: CScalar,
    header_file: &str,
) -> Result<CCode, EmitError> {
    emit_c_model(programs, scalar, header_file, None)
}

/// [`emit_c`], with for a URDF `urdf_standard`, the file's own inertials as the values of
/// the standard parameters (what the Rust code holds as `URDF_STANDARD_PARAMETERS`,
/// [`emit_model`](super::emit_model)): the array `NAME_urdf_standard_parameters`, in the
/// order of `NAME_standard_parameter_names`, declared in the header and defined in the
/// source, to pass to `NAME_base_from_standard`.
///
/// ```
/// use robid_symbolic::Robot;
/// use robid_symbolic::emit::{CScalar, emit_c_model};
/// use robid_symbolic::program::RobotPrograms;
/// use robid_symbolic::robot::ChainSelection;
/// let urdf = r#"<robot name="arm">
///   <link name="base"/>
///   <link name="upper"><inertial><mass value="2"/>
///     <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.05"/></inertial></link>
///   <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
///     <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
/// </robot>"#;
/// let chain = Robot::from_urdf(urdf, "arm.urdf", &ChainSelection::default()).unwrap();
/// let programs = RobotPrograms::derive(&chain.robot).unwrap();
/// let values = chain.standard_values(&chain.robot);
/// let c = emit_c_model(&programs, CScalar::Double, "arm.h", Some(&values)).unwrap();
/// assert!(c.header.contains("extern const double arm_urdf_standard_parameters[10];"));
/// assert!(c.source.contains("const double arm_urdf_standard_parameters[10] = {"));
/// ```
pub fn emit_c_model(
    programs: &RobotPrograms,
    scalar: CScalar,
    header_file: &str,
    urdf_standard: Option<&[f64]>,
) -> Result<CCode, EmitError> {
    let robot = &programs.robot;
    let prefix = robot.name().to_lowercase();
    let upper = robot.name().to_uppercase();
    for (s, v) in &programs.geometry {
        if !value_name(s) || RESERVED.contains(&s.as_str()) {
            return Err(EmitError::Name {
                what: "geometric symbol (in C)".to_owned(),
                name: s.clone(),
            });
        }
        if let Some(x) = v.filter(|x| !x.is_finite()) {
            return Err(EmitError::NotFinite {
                what: format!("the value of geometric symbol `{s}`"),
                value: x,
            });
        }
    }
    let sizes = Sizes {
        joints: robot.dof(),
        base: programs.base.len(),
        standard: programs.standard.len(),
    };
    let real = scalar.name();
    let geometry_type = format!("{prefix}_geometry");
    let geometry_arg = if programs.geometry.is_empty() {
        String::new()
    } else {
        format!("const {geometry_type} *geometry, ")
    };

    let mut h = String::new();
    let guard = format!("ROBID_{upper}_H");
    let _ = writeln!(
        h,
        "/* @generated by robid from the description of `{}`; do not edit. */",
        robot.name()
    );
    let _ = writeln!(h, "#ifndef {guard}\n#define {guard}\n");
    let _ = writeln!(
        h,
        "/* Dynamic model of `{}`: {}, {} DH, {} standard and {} base parameters.\n   Matrices are row-major. */\n",
        robot.name(),
        super::count(sizes.joints, "joint"),
        robot.convention().as_str(),
        sizes.standard,
        sizes.base
    );
    let _ = writeln!(h, "#ifdef __cplusplus\nextern \"C\" {{\n#endif\n");
    let _ = writeln!(h, "#define {upper}_DOF {}", sizes.joints);
    let _ = writeln!(h, "#define {upper}_STANDARD_PARAMETERS {}", sizes.standard);
    let _ = writeln!(h, "#define {upper}_BASE_PARAMETERS {}\n", sizes.base);
    let _ = writeln!(
        h,
        "/* Names of the standard and of the base parameters, in order. */"
    );
    let _ = writeln!(
        h,
        "extern const char *const {prefix}_standard_parameter_names[{}];",
        sizes.standard
    );
    let _ = writeln!(
        h,
        "extern const char *const {prefix}_base_parameter_names[{}];\n",
        sizes.base
    );
    if let Some(values) = urdf_standard {
        check_urdf_standard(programs, values)?;
        let _ = writeln!(
            h,
            "/* The URDF's own <inertial> elements as the standard parameters, in the order of\n   \
             {prefix}_standard_parameter_names (per link XX XY XZ YY YZ ZZ MX MY MZ M in robid's\n   \
             frames, drive terms 0): pass them to {prefix}_base_from_standard for the URDF's\n   \
             rigid-body dynamics. */"
        );
        let _ = writeln!(
            h,
            "extern const {real} {prefix}_urdf_standard_parameters[{}];\n",
            sizes.standard
        );
    }
    if !programs.geometry.is_empty() {
        let _ = writeln!(
            h,
            "/* Geometric symbols kept symbolic in the description. */"
        );
        let _ = writeln!(h, "typedef struct {{");
        for (s, v) in &programs.geometry {
            match v {
                Some(x) => {
                    let _ = writeln!(h, "    {real} {s}; /* description value: {x} */");
                }
                None => {
                    let _ = writeln!(h, "    {real} {s}; /* a run-time input */");
                }
            }
        }
        let _ = writeln!(h, "}} {geometry_type};\n");
    }

    let mut c = String::new();
    let _ = writeln!(
        c,
        "/* @generated by robid from the description of `{}`; do not edit. */",
        robot.name()
    );
    let _ = writeln!(c, "#include \"{header_file}\"\n#include <math.h>\n");
    let names = |list: Vec<String>| {
        list.iter()
            .map(|n| format!("\"{n}\""))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let _ = writeln!(
        c,
        "const char *const {prefix}_standard_parameter_names[{}] = {{{}}};",
        sizes.standard,
        names(programs.standard.clone())
    );
    let _ = writeln!(
        c,
        "const char *const {prefix}_base_parameter_names[{}] = {{{}}};",
        sizes.base,
        names(programs.base.iter().map(|b| b.name.to_string()).collect())
    );
    if let Some(values) = urdf_standard {
        let values: Vec<String> = values.iter().map(|&x| scalar.literal(x)).collect();
        let _ = writeln!(
            c,
            "const {real} {prefix}_urdf_standard_parameters[{}] = {{{}}};",
            sizes.standard,
            values.join(", ")
        );
    }

    for (info, program) in programs.iter() {
        let signature = signature(&prefix, info, sizes, real, &geometry_arg);
        let ops = program.operations();
        let _ = writeln!(
            h,
            "/* {}\n   Output `{}`: {} ({}). Operations: {ops}. */\n{signature};\n",
            info.summary,
            info.output.name,
            info.output.size.describe(),
            super::count(info.output.size.len(sizes), "value")
        );
        let _ = writeln!(c, "\n{signature}\n{{");
        body(&mut c, info, program, scalar)?;
        let _ = writeln!(c, "}}");
    }
    let _ = writeln!(h, "#ifdef __cplusplus\n}}\n#endif\n\n#endif /* {guard} */");
    Ok(CCode {
        header: h,
        source: c,
    })
}

/// Refuses URDF values that are not one finite number per standard parameter.
fn check_urdf_standard(programs: &RobotPrograms, values: &[f64]) -> Result<(), EmitError> {
    if values.len() != programs.standard.len() {
        return Err(EmitError::Program {
            function: "urdf_standard_parameters".to_owned(),
            problem: format!(
                "{} values for {} standard parameters",
                values.len(),
                programs.standard.len()
            ),
        });
    }
    match programs
        .standard
        .iter()
        .zip(values)
        .find(|(_, v)| !v.is_finite())
    {
        Some((name, &value)) => Err(EmitError::NotFinite {
            what: format!("the URDF's value of `{name}`"),
            value,
        }),
        None => Ok(()),
    }
}

/// `void ur5e_gravity(const double q[6], const double base[36], double out[6])`.
fn signature(
    prefix: &str,
    info: &ProgramInfo,
    sizes: Sizes,
    real: &str,
    geometry_arg: &str,
) -> String {
    let inputs: Vec<String> = info
        .inputs
        .iter()
        .map(|a| format!("const {real} {}[{}]", a.name, a.size.len(sizes)))
        .collect();
    format!(
        "void {prefix}_{}({geometry_arg}{}, {real} {}[{}])",
        info.name,
        inputs.join(", "),
        info.output.name,
        info.output.size.len(sizes)
    )
}

/// The statements of one function.
fn body(
    c: &mut String,
    info: &ProgramInfo,
    program: &Program,
    scalar: CScalar,
) -> Result<(), EmitError> {
    let invalid = |problem: &str| EmitError::Program {
        function: info.name.to_owned(),
        problem: problem.to_owned(),
    };
    let real = scalar.name();
    let output = program
        .outputs
        .first()
        .ok_or_else(|| invalid("it has no output"))?;
    // inputs: the table's arrays, in order; the geometry group from the struct
    let mut argument = info.inputs.iter();
    let mut flat = 0u32;
    for group in &program.inputs {
        let first = flat;
        let used = (0..group.len()).any(|k| reads(program, Value::Input(first + k as u32)));
        let geometry = group.name == super::function::GEOMETRY;
        let array = if geometry {
            None
        } else {
            Some(
                argument
                    .next()
                    .ok_or_else(|| invalid("it has more input groups than the table"))?,
            )
        };
        if !used {
            let _ = match array {
                Some(a) => writeln!(c, "    (void){};", a.name),
                None => writeln!(c, "    (void)geometry;"),
            };
        }
        for (k, element) in group.elements.iter().enumerate() {
            let v = Value::Input(flat);
            flat += 1;
            if !reads(program, v) {
                continue;
            }
            if !value_name(element) {
                return Err(EmitError::Name {
                    what: format!("element of input group `{}`", group.name),
                    name: element.clone(),
                });
            }
            let _ = match array {
                Some(a) => writeln!(
                    c,
                    "    const {real} {} = {}[{k}];",
                    local(program, v),
                    a.name
                ),
                None => writeln!(
                    c,
                    "    const {real} {} = geometry->{element};",
                    local(program, v)
                ),
            };
        }
    }
    for (i, x) in program.constants.iter().enumerate() {
        if !x.is_finite() {
            return Err(EmitError::NotFinite {
                what: format!("constant c{i} of program `{}`", info.name),
                value: *x,
            });
        }
    }
    let inputs = program.input_len();
    let exists = |v: Value, temps: usize| match v {
        Value::Temp(t) => (t as usize) < temps,
        Value::Input(i) => (i as usize) < inputs,
        Value::Const(k) => (k as usize) < program.constants.len(),
    };
    for (i, instr) in program.instrs.iter().enumerate() {
        if instr.operands().into_iter().any(|v| !exists(v, i)) {
            return Err(invalid(
                "an operand reads a temporary, input or constant that does not exist",
            ));
        }
        let v = |x: Value| operand(program, x, scalar);
        let f = |name: &str| scalar.function(name);
        let rhs = match *instr {
            Instr::Add(a, b) => format!("{} + {}", v(a), v(b)),
            Instr::Sub(a, b) => format!("{} - {}", v(a), v(b)),
            Instr::Mul(a, b) => format!("{} * {}", v(a), v(b)),
            Instr::Div(a, b) => format!("{} / {}", v(a), v(b)),
            Instr::Neg(a) => format!("-{}", v(a)),
            Instr::Sin(a) => format!("{}({})", f("sin"), v(a)),
            Instr::Cos(a) => format!("{}({})", f("cos"), v(a)),
            Instr::Sqrt(a) => format!("{}({})", f("sqrt"), v(a)),
            // -1, 0 or 1, 0 at exactly zero (and for NaN), as the Rust code's `sign`
            Instr::Sign(a) => format!("({real})(({0} > 0) - ({0} < 0))", v(a)),
        };
        let _ = writeln!(c, "    const {real} t{i} = {rhs};");
    }
    for (k, &value) in output.values.iter().enumerate() {
        if !exists(value, program.instrs.len()) {
            return Err(invalid(
                "an output reads a temporary, input or constant that does not exist",
            ));
        }
        let _ = writeln!(
            c,
            "    {}[{k}] = {};",
            info.output.name,
            operand(program, value, scalar)
        );
    }
    Ok(())
}

/// The local holding input `v` (`in_q1`; prefixed so that no name clashes with C).
fn local(program: &Program, v: Value) -> String {
    match v {
        Value::Input(i) => format!("in_{}", program.input_name(i)),
        Value::Temp(t) => format!("t{t}"),
        Value::Const(k) => format!("c{k}"),
    }
}

/// An operand: a temporary, an input's local, or a constant written out.
fn operand(program: &Program, v: Value, scalar: CScalar) -> String {
    match v {
        Value::Const(k) => {
            let x = program.constants[k as usize];
            let text = scalar.literal(x);
            if x < 0.0 { format!("({text})") } else { text }
        }
        other => local(program, other),
    }
}

fn reads(program: &Program, v: Value) -> bool {
    program.instrs.iter().any(|i| i.operands().contains(&v))
        || program.outputs.iter().any(|o| o.values.contains(&v))
}
