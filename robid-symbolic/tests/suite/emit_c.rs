//! The C emitter (`robid emit --lang c`): for every reference robot (the descriptions in
//! `robots/descriptions/`) and the UR5e with every drive term, the C99 code compiled by the
//! system C compiler agrees with the interpreter on every program of the table, at random
//! states, to 1e-12 (relative to the output's largest entry); with `float` it compiles
//! warning-free too and agrees to float precision. The interpreter is the reference the
//! compiled Rust models are checked against (`robots/src/models/consistency.rs`), so the
//! test lives here, where a change to the emitter rebuilds only this crate (mutation
//! testing, README "Mutation testing"). Skipped, with a message, when no C compiler is
//! installed.

use std::fmt::Write;
use std::path::Path;
use std::process::{Command, Stdio};

use robid_core::rng::Rng;
use robid_core::{PROGRAMS, Sizes};
use robid_symbolic::emit::{CScalar, emit_c};
use robid_symbolic::program::RobotPrograms;
use robid_symbolic::{Drive, Robot};

/// The reference descriptions of the workspace, by name.
fn references() -> Vec<Robot> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/descriptions");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    assert!(
        paths.len() >= 8,
        "the reference descriptions in {}",
        dir.display()
    );
    paths.iter().map(|p| Robot::from_file(p).unwrap()).collect()
}

/// Every program's output for one state, by the interpreter (in the table's order).
fn interpret(programs: &RobotPrograms, inputs: &[&[f64]; 5]) -> Vec<Vec<f64>> {
    let geometry: Vec<f64> = programs
        .geometry
        .iter()
        .map(|(s, v)| v.unwrap_or_else(|| panic!("reference symbol {s} has a value")))
        .collect();
    let sizes = sizes(programs);
    let mut temps = Vec::new();
    PROGRAMS
        .iter()
        .zip(&programs.programs)
        .map(|(p, program)| {
            let mut all: Vec<&[f64]> = p
                .inputs
                .iter()
                .map(|a| match a.name {
                    "q" => inputs[0],
                    "qd" => inputs[1],
                    "qdd" => inputs[2],
                    "base" => inputs[3],
                    _ => inputs[4],
                })
                .collect();
            if !geometry.is_empty() {
                all.push(&geometry);
            }
            let mut out = vec![0.0; p.output.size.len(sizes)];
            program.run(&all, &mut [&mut out], &mut temps).unwrap();
            out
        })
        .collect()
}

/// The C compiler, if there is one (`$CC`, else `cc`).
fn compiler() -> Option<String> {
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".to_owned());
    let found = Command::new(&cc)
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    found.then_some(cc)
}

/// A `main` that reads q, qd, qdd, base and standard from standard input, runs every
/// program of the table and prints each output on one line.
fn driver(programs: &RobotPrograms, header: &str, real: &str) -> String {
    let prefix = programs.robot.name().to_lowercase();
    let sizes = sizes(programs);
    let mut c = format!("#include <stdio.h>\n#include \"{header}\"\n\nint main(void)\n{{\n");
    let arrays = [
        ("q", sizes.joints),
        ("qd", sizes.joints),
        ("qdd", sizes.joints),
        ("base", sizes.base),
        ("standard", sizes.standard),
    ];
    for (name, n) in arrays {
        let _ = writeln!(c, "    static {real} {name}[{n}];");
        let _ = writeln!(
            c,
            "    for (int i = 0; i < {n}; i++) {{ double x; if (scanf(\"%lf\", &x) != 1) return 2; {name}[i] = ({real})x; }}"
        );
    }
    let geometry = if programs.geometry.is_empty() {
        String::new()
    } else {
        let fields: Vec<String> = programs
            .geometry
            .iter()
            .map(|(s, v)| format!(".{s} = {:?}", v.expect("reference symbols have values")))
            .collect();
        let _ = writeln!(
            c,
            "    const {prefix}_geometry g = {{{}}};",
            fields.join(", ")
        );
        "&g, ".to_owned()
    };
    for p in &PROGRAMS {
        let n = p.output.size.len(sizes);
        let inputs: Vec<&str> = p.inputs.iter().map(|a| a.name).collect();
        let _ = writeln!(c, "    {{\n        static {real} out[{n}];");
        let _ = writeln!(
            c,
            "        {prefix}_{}({geometry}{}, out);",
            p.name,
            inputs.join(", ")
        );
        let _ = writeln!(
            c,
            "        for (int i = 0; i < {n}; i++) printf(\"%.17g \", (double)out[i]);\n        printf(\"\\n\");\n    }}"
        );
    }
    c.push_str("    return 0;\n}\n");
    c
}

fn sizes(programs: &RobotPrograms) -> Sizes {
    Sizes {
        joints: programs.robot.dof(),
        base: programs.base.len(),
        standard: programs.standard.len(),
    }
}

/// Compiles the robot's C code with the driver into `dir`, with warnings as errors.
fn build(cc: &str, dir: &Path, programs: &RobotPrograms, scalar: CScalar) -> std::path::PathBuf {
    let name = programs.robot.name().to_lowercase();
    let real = if scalar == CScalar::Float {
        "float"
    } else {
        "double"
    };
    let code = emit_c(programs, scalar, &format!("{name}.h")).unwrap();
    std::fs::write(dir.join(format!("{name}.h")), &code.header).unwrap();
    std::fs::write(dir.join(format!("{name}.c")), &code.source).unwrap();
    std::fs::write(
        dir.join("main.c"),
        driver(programs, &format!("{name}.h"), real),
    )
    .unwrap();
    let exe = dir.join(format!("{name}_{real}"));
    let out = Command::new(cc)
        .current_dir(dir)
        .args([
            "-std=c99",
            "-O0",
            "-Wall",
            "-Wextra",
            "-pedantic",
            "-Werror",
        ])
        .args(["-Wno-unused-but-set-variable"])
        .arg("-o")
        .arg(&exe)
        .args(["main.c", &format!("{name}.c"), "-lm"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{name} ({real}) does not compile:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    exe
}

/// Runs the driver on one state and returns each program's output.
fn run(exe: &Path, inputs: &[&[f64]]) -> Vec<Vec<f64>> {
    let text: String = inputs
        .iter()
        .flat_map(|v| v.iter())
        .map(|x| format!("{x:?} "))
        .collect();
    let mut child = Command::new(exe)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    std::io::Write::write_all(&mut child.stdin.take().unwrap(), text.as_bytes()).unwrap();
    let out = child.wait_with_output().unwrap();
    assert!(out.status.success());
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| l.split_whitespace().map(|x| x.parse().unwrap()).collect())
        .collect()
}

/// The largest difference between `a` and `b`, relative to `b`'s largest entry.
fn relative(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(1e-300_f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / scale)
        .fold(0.0, f64::max)
}

#[test]
fn c_code_agrees_with_the_interpreter() {
    let Some(cc) = compiler() else {
        eprintln!("emit_c: skipped, no C compiler (set CC or install cc)");
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut rng = Rng::from_state(11);
    let mut worst = (0.0_f64, 0.0_f64);
    // every reference robot, and the UR5e with every drive term (sign() for Coulomb
    // friction, Ia, Fo)
    let mut robots = references();
    let ur5e = robots.iter().find(|r| r.name() == "ur5e").unwrap().clone();
    robots.push(ur5e.with_drive(Drive::ALL).with_name("ur5e_drive").unwrap());
    // small chains whose programs leave whole input groups unread (one joint: no Coriolis,
    // so its regressor reads no velocity), which the C code must mark `(void)` to compile
    // warning-free, while reading the first input
    for (name, joints) in [
        ("one_r", "[[joints]]\nalpha = \"pi/2\"\n"),
        (
            "one_p",
            "[[joints]]\ntype = \"prismatic\"\nalpha = \"pi/2\"\n",
        ),
    ] {
        let text = format!("name = \"{name}\"\nconvention = \"modified\"\n{joints}");
        robots.push(Robot::from_toml(&text, "small.toml").unwrap());
    }
    for robot in &robots {
        let programs = RobotPrograms::derive(robot).unwrap();
        let name = programs.robot.name();
        let sizes = sizes(&programs);
        let double = build(&cc, dir, &programs, CScalar::Double);
        let float = build(&cc, dir, &programs, CScalar::Float);
        for _ in 0..3 {
            let mut random =
                |n: usize, r: f64| -> Vec<f64> { (0..n).map(|_| rng.uniform(-r, r)).collect() };
            let (q, qd, qdd) = (
                random(sizes.joints, 3.0),
                random(sizes.joints, 2.0),
                random(sizes.joints, 4.0),
            );
            let (base, standard) = (random(sizes.base, 1.0), random(sizes.standard, 1.0));
            let all: [&[f64]; 5] = [&q, &qd, &qdd, &base, &standard];
            let (c, c32) = (run(&double, &all), run(&float, &all));
            let reference = interpret(&programs, &all);
            for (k, p) in PROGRAMS.iter().enumerate() {
                let (e, e32) = (
                    relative(&c[k], &reference[k]),
                    relative(&c32[k], &reference[k]),
                );
                assert!(e <= 1e-12, "{} {}: C double off by {e:e}", name, p.name);
                // measured at most 5.2e-16 (double) and 8.8e-7 (float, the UR5e's Coriolis
                // with drive terms), a few float roundings of 6e-8; over 2000 random states
                // the inverse dynamics, gravity and Coriolis programs interpreted in f32 reach
                // 1e-6 to 2e-6 (with the last link's wrench in its own frame or its parent's
                // alike), so the bound leaves that room
                assert!(e32 <= 2e-6, "{} {}: C float off by {e32:e}", name, p.name);
                worst = (worst.0.max(e), worst.1.max(e32));
            }
        }
    }
    eprintln!(
        "emit_c: worst relative difference {:e} (double), {:e} (float)",
        worst.0, worst.1
    );
}

/// A geometric symbol named like a C keyword cannot become a field of the geometry struct:
/// the C emitter refuses it by name (the Rust emitter accepts it).
#[test]
fn a_symbol_named_like_c_is_refused() {
    for symbol in ["float", "double", "int"] {
        let text = format!(
            "name = \"arm\"\nconvention = \"modified\"\n[[joints]]\nalpha = \"pi/2\"\n\
             [[joints]]\na = \"{symbol}\"\n"
        );
        let robot = Robot::from_toml(&text, "arm.toml").unwrap();
        let programs = RobotPrograms::derive(&robot).unwrap();
        match emit_c(&programs, CScalar::Double, "arm.h") {
            Err(robid_symbolic::emit::EmitError::Name { name, .. }) => assert_eq!(name, symbol),
            other => panic!("{symbol}: {:?}", other.map(|_| ())),
        }
    }
}

/// A negative constant is written in parentheses, so that negating it is `-(-1.5)` and not
/// the decrement `--1.5`: a program whose output adds the negation of a negative constant
/// compiles warning-free and agrees with the interpreter.
#[test]
fn a_negated_negative_constant_compiles() {
    use robid_symbolic::program::{Instr, Value};
    let Some(cc) = compiler() else {
        eprintln!("emit_c: skipped, no C compiler (set CC or install cc)");
        return;
    };
    let text = "name = \"neg\"\nconvention = \"modified\"\n[[joints]]\nalpha = \"pi/2\"\n";
    let mut programs = RobotPrograms::derive(&Robot::from_toml(text, "neg.toml").unwrap()).unwrap();
    let gravity = &mut programs[robid_core::ProgramKind::Gravity];
    let k = gravity.constants.len() as u32;
    gravity.constants.push(-1.5);
    let t = gravity.instrs.len() as u32;
    let old = gravity.outputs[0].values[0];
    gravity.instrs.push(Instr::Neg(Value::Const(k)));
    gravity.instrs.push(Instr::Add(old, Value::Temp(t)));
    gravity.outputs[0].values[0] = Value::Temp(t + 1);
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let exe = build(&cc, dir, &programs, CScalar::Double);
    let q = [0.7];
    let base: Vec<f64> = (0..programs.base.len()).map(|i| 0.1 + i as f64).collect();
    let standard = vec![0.0; programs.standard.len()];
    let inputs: [&[f64]; 5] = [&q, &q, &q, &base, &standard];
    let out = run(&exe, &inputs);
    let reference = interpret(&programs, &inputs);
    let gravity = PROGRAMS
        .iter()
        .position(|p| p.kind == robid_core::ProgramKind::Gravity)
        .unwrap();
    assert!(relative(&out[gravity], &reference[gravity]) <= 1e-15);
}

/// URDF values for the C array must be one finite number per standard parameter: a wrong
/// count or a NaN is refused naming the array or the parameter, never emitted.
#[test]
fn urdf_values_that_do_not_fit_are_refused() {
    use robid_symbolic::emit::{EmitError, emit_c_model};
    let text = "name = \"arm\"\nconvention = \"modified\"\n[[joints]]\nalpha = \"pi/2\"\n";
    let programs = RobotPrograms::derive(&Robot::from_toml(text, "arm.toml").unwrap()).unwrap();
    let n = programs.standard.len();
    let ok = emit_c_model(&programs, CScalar::Float, "arm.h", Some(&vec![0.5; n])).unwrap();
    assert!(
        ok.header
            .contains("extern const float arm_urdf_standard_parameters[")
    );
    assert!(
        ok.source
            .contains("arm_urdf_standard_parameters[10] = {0.5f, 0.5f")
    );
    match emit_c_model(&programs, CScalar::Double, "arm.h", Some(&vec![0.0; n - 1])) {
        Err(EmitError::Program { function, problem }) => {
            assert_eq!(function, "urdf_standard_parameters");
            assert_eq!(
                problem,
                format!("{} values for {n} standard parameters", n - 1)
            );
        }
        other => panic!("{:?}", other.map(|_| ())),
    }
    let mut values = vec![0.0; n];
    values[9] = f64::NAN;
    match emit_c_model(&programs, CScalar::Double, "arm.h", Some(&values)) {
        Err(EmitError::NotFinite { what, .. }) => {
            assert_eq!(
                what,
                format!("the URDF's value of `{}`", programs.standard[9])
            );
        }
        other => panic!("{:?}", other.map(|_| ())),
    }
}
