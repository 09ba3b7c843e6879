//! Bad descriptions are located errors, all reported at once; bad library
//! calls are errors naming the argument; nothing panics.

use robid_core::ProgramKind;
use robid_symbolic::emit::{EmitError, emit_programs, emit_robot};
use robid_symbolic::program::RobotPrograms;
use robid_symbolic::robot::{Geometry, GeometryError};
use robid_symbolic::{Convention, DescriptionError, Joint, Robot};

const HEAD: &str = "name = \"arm\"\nconvention = \"modified\"\n";

/// Each problem of reading `text` as `file:line:column: message`.
fn errors(text: &str) -> Vec<String> {
    match Robot::from_toml(text, "arm.toml") {
        Ok(_) => Vec::new(),
        Err(e) => e.errors().iter().map(|e| e.to_string()).collect(),
    }
}

/// The single error of `text`, which must start with `arm.toml:LINE:COLUMN:`
/// and contain every part of `says`.
fn single(text: &str, at: &str, says: &[&str]) {
    let all = errors(text);
    assert_eq!(all.len(), 1, "{text}\n{all:#?}");
    let e = &all[0];
    assert!(e.starts_with(&format!("arm.toml:{at}: ")), "{e}");
    for part in says {
        assert!(e.contains(part), "`{part}` not in {e}");
    }
}

#[test]
fn every_mistake_of_a_file_is_reported_in_order() {
    let text = "name = \"my arm\"
convention = \"modified\"
gravity = [0, 0, -9810]
colour = \"red\"

[symbols]
l2 = 0.4

[[joints]]
alpha = 90
a = 0
d = 1e200
limits = { position = [1, 2, 3], velocity = -1 }

[[joints]]
alpha = \"pi/\"
a = \"L2\"
d = 1e-9
theta = \"3*pi\"

[[joints]]
a = \"2^1024\"
d = nan
tpye = \"revolute\"
";
    let all = errors(text);
    let expected = [
        ("1:8", "robot name `my arm` is not an identifier"),
        ("3:18", "gravity z = -9810 is beyond ±1000 m/s^2"),
        ("4:1", "unknown key `colour`"),
        (
            "7:1",
            "symbol `l2` has a value, but no DH value or gravity depends on it (an expression \
             in which it cancels, such as `L/L`, does not); did you mean `L2`?",
        ),
        ("10:9", "joint 1 `alpha` = 90 is more than a turn"),
        ("12:5", "joint 1 `d` = 1e200 is beyond ±1000 m"),
        ("13:23", "joint 1 position limit has 3 values"),
        (
            "13:45",
            "joint 1 velocity limit -1 is not a positive number",
        ),
        ("16:13", "joint 2 `alpha`: `pi/` is not an expression"),
        (
            "18:5",
            "joint 2 `d` = 1e-9 is shorter than 1e-6 m but not zero",
        ),
        ("19:9", "joint 2 `theta` = \"3*pi\" is more than a turn"),
        ("22:8", "the exponent 1024 is beyond ±64"),
        ("23:5", "joint 3 `d` is NaN, not a finite number"),
        ("24:1", "unknown key `tpye`; did you mean `type`?"),
    ];
    assert_eq!(all.len(), expected.len(), "{all:#?}");
    for (e, (at, says)) in all.iter().zip(expected) {
        assert!(
            e.starts_with(&format!("arm.toml:{at}: ")),
            "{e} (expected at {at})"
        );
        assert!(e.contains(says), "`{says}` not in {e}");
    }
}

/// `position = [1, 2, 3]` silently dropped the third value; every array has
/// its length checked, and every number read is checked.
#[test]
fn array_lengths_and_limits_are_checked() {
    let joint = |limits: &str| format!("{HEAD}[[joints]]\nlimits = {limits}\n");
    single(
        &joint("{ position = [1, 2, 3] }"),
        "4:23",
        &["position limit has 3 values", "[lower, upper]"],
    );
    single(&joint("{ position = [1] }"), "4:23", &["has 1 value;"]);
    single(
        &joint("{ position = [2, 1] }"),
        "4:23",
        &["not an increasing pair"],
    );
    single(
        &joint("{ position = [-1e9, 1] }"),
        "4:23",
        &["beyond ±1000"],
    );
    single(&joint("{ position = [nan, 1] }"), "4:23", &["finite"]);
    single(&joint("{ torque = inf }"), "4:21", &["torque limit inf"]);
    single(&joint("{ acceleration = 1e300 }"), "4:27", &["up to 1e6"]);
    single(&joint("{ velocity = \"fast\" }"), "4:23", &["is a string"]);
    single(&joint("{ speed = 1 }"), "4:12", &["unknown key `speed`"]);
    single(
        &format!("{HEAD}gravity = [0, -9.81]\n[[joints]]\n"),
        "3:11",
        &["gravity has 2 values"],
    );
}

#[test]
fn magnitudes_that_broke_the_derivation_are_errors() {
    let joint = |values: &str| format!("{HEAD}[[joints]]\n{values}\n");
    // inf/NaN in base expressions, "base parameters (0)", NaN coefficients:
    single(&joint("d = 1e308"), "4:5", &["beyond ±1000 m"]);
    single(&joint("d = 1e200"), "4:5", &["beyond ±1000 m"]);
    single(&joint("alpha = \"2^1024\""), "4:12", &["exponent 1024"]);
    single(
        &joint("alpha = \"2^64 * 2^64\""),
        "4:9",
        &["more than a turn"],
    );
    single(&joint("a = \"1e300*1e300\""), "4:17", &["out of the range"]);
    single(&joint("a = -1e-7"), "4:5", &["shorter than 1e-6 m"]);
    single(&joint("alpha = \"pi/2 + 1e-7\""), "4:9", &["from pi/2"]);
    single(&joint("gamma = 3.1415926"), "4:9", &["from pi", "\"pi\""]);
    single(&joint("alpha = 2e-9"), "4:9", &["from 0"]);
    // A symbol's value is checked where it is used.
    single(
        &format!("{HEAD}[symbols]\nL = 5000\n[[joints]]\na = \"L\"\n"),
        "6:5",
        &["is 5000 at the [symbols] values, beyond ±1000 m"],
    );
    single(
        &format!("{HEAD}[symbols]\nL = nan\n[[joints]]\na = \"L\"\n"),
        "4:1",
        &["value of symbol `L` is NaN"],
    );
    // Symbols are sampled between 0.2 and 1 by the regrouping.
    single(
        &joint("a = \"1e5*L\""),
        "4:5",
        &["reaches 100000", "between 0.2 and 1"],
    );
    single(&joint("a = \"1/(L1 - L2)\""), "4:5", &["reaches inf"]);
    single(&joint("a = \"L^(-64)\""), "4:5", &["reaches"]);
    // Gravity: units and tiny components.
    single(
        &format!("{HEAD}gravity = [1e-6, 0, -9.81]\n[[joints]]\n"),
        "3:12",
        &["gravity x = 1e-6 is smaller than 0.001 m/s^2 but not zero"],
    );
    // ... and one that a small tilt of the base makes in frame 0, where the dynamics use
    // it: 9.81 sin(2e-5) = 1.962e-4 m/s^2 (it gave two base parameters that only it
    // excites); a tilt through a symbol too, and the angle blamed is the tilt, not pi/2
    single(
        &format!("{HEAD}[base]\nrpy = [2e-5, 0, 0]\n[[joints]]\n"),
        "4:8",
        &[
            "[base] rpy roll = 2e-5 turns gravity [0, 0, -9.81] in frame 0 (where the dynamics use it) into one whose y component is -1.962e-4 m/s^2, smaller than 0.001 m/s^2",
            "write \"0\" for this angle (2.0e-5 rad from it)",
        ],
    );
    single(
        &format!("{HEAD}[symbols]\nT = 2e-5\n[base]\nrpy = [\"pi/2\", \"T\", 0]\n[[joints]]\n"),
        "6:16",
        &[
            "[base] rpy pitch = 2e-5 turns gravity",
            "smaller than 0.001 m/s^2",
        ],
    );
    // a written component that small is told once, by its own rule
    single(
        &format!("{HEAD}gravity = [1e-6, 0, -9.81]\n[base]\nrpy = [2e-5, 0, 0]\n[[joints]]\n"),
        "3:12",
        &["gravity x = 1e-6 is smaller"],
    );
    // Accepted: the ends of every range, and tilts that leave gravity a component of at
    // least 1e-3 m/s^2 (or none)
    for rpy in ["[1.1e-4, 0, 0]", "[\"pi/2\", \"-pi\", 0.3]", "[0, 0, 1e-5]"] {
        let text = format!("{HEAD}[base]\nrpy = {rpy}\n[[joints]]\n");
        assert_eq!(errors(&text), Vec::<String>::new(), "{rpy}");
    }
    let ok = format!(
        "{HEAD}gravity = [1e-3, -1e3, 0]\n[symbols]\nL = 1e3\n[[joints]]\nalpha = \"2*pi\"\na = 1e-6\nd = \"L\"\ntheta = 1e-5\n\
         limits = {{ position = [-1e3, 1e3], velocity = 1e4, acceleration = 1e6, torque = 1e7 }}\n"
    );
    assert_eq!(errors(&ok), Vec::<String>::new());
}

/// A file saved with a byte-order mark (Windows editors) is read, and its first line's
/// places are where an editor shows them (`arm.toml:1:9` before).
#[test]
fn a_byte_order_mark_is_no_column() {
    single(
        "\u{feff}name = \"a-b\"\nconvention = \"modified\"\n[[joints]]\n",
        "1:8",
        &["robot name `a-b` is not an identifier"],
    );
}

#[test]
fn names_must_name_a_rust_type() {
    for name in ["self", "Self", "fn", "crate", "super", "self_", "type"] {
        single(
            &format!("name = \"{name}\"\nconvention = \"modified\"\n[[joints]]\n"),
            "1:8",
            &["Rust keyword"],
        );
    }
    for name in ["my arm", "1arm", "arm-2", ""] {
        single(
            &format!("name = \"{name}\"\nconvention = \"modified\"\n[[joints]]\n"),
            "1:8",
            &["not an identifier"],
        );
    }
    single(
        "convention = \"modified\"\n[[joints]]\n",
        "1:1",
        &["has no `name`"],
    );
}

#[test]
fn sizes_are_limited() {
    let joints = "[[joints]]\na = 0.1\n".repeat(33);
    single(
        &format!("{HEAD}{joints}"),
        "3:1",
        &["33 joints", "at most 32"],
    );
    let sum: Vec<String> = (1..=17).map(|i| format!("L{i}")).collect();
    single(
        &format!("{HEAD}[[joints]]\na = \"({})/17\"\n", sum.join(" + ")),
        "4:5",
        &["symbol number 17", "at most 16"],
    );
    // The 40 kB alpha and the 40,000 minus signs that overflowed the stack.
    let deep = format!("{}x{}", "(".repeat(20_000), ")".repeat(20_000));
    single(
        &format!("{HEAD}[[joints]]\nalpha = \"{deep}\"\n"),
        "4:9",
        &["40001 bytes long, more than the 4096"],
    );
    let minus = format!("{}x", "-".repeat(4000));
    single(
        &format!("{HEAD}[[joints]]\nalpha = \"{minus}\"\n"),
        "4:75",
        &["nest deeper than 64 levels"],
    );
    // Many mistakes: the first 50 and a count of the others.
    let bad = "[[joints]]\na = 1e9\nd = 1e9\n".repeat(30);
    let all = errors(&format!("{HEAD}{bad}"));
    assert_eq!(all.len(), 51, "{all:#?}");
    assert!(
        all[49].starts_with("arm.toml:77:5: joint 25 `d` = 1e9 is beyond"),
        "{}",
        all[49]
    );
    assert!(all[50].starts_with("arm.toml:79:5: "), "{}", all[50]);
    assert!(
        all[50].contains("more mistakes from here on are not shown"),
        "{}",
        all[50]
    );
    let big = format!("{HEAD}# {}\n[[joints]]\n", "x".repeat(1 << 20));
    single(&big, "1:1", &["more than the 1048576"]);
}

/// A value for a symbol no joint uses (the typo `l2` for `L2`) is an error
/// naming the nearest used symbol; without it, `L2` would silently become a
/// run-time input of the generated type, which lists its run-time inputs.
#[test]
fn unused_symbols_are_errors_and_run_time_inputs_are_documented() {
    let text = format!("{HEAD}[symbols]\nl2 = 0.4\nL3 = 0.3\n[[joints]]\na = \"L2\"\nd = \"L3\"\n");
    single(
        &text,
        "4:1",
        &[
            "symbol `l2` has a value, but no DH value or gravity depends on it",
            "did you mean `L2`?",
        ],
    );
    let fixed = text.replace("l2 = 0.4", "L2 = 0.4");
    let robot = Robot::from_toml(&fixed, "arm.toml").unwrap();
    assert!(robot.run_time_symbols().is_empty());
    let without = text.replace("l2 = 0.4\n", "");
    let robot = Robot::from_toml(&without, "arm.toml").unwrap();
    assert_eq!(robot.run_time_symbols(), ["L2"]);
    let code = emit_robot(&robot).unwrap();
    assert!(
        code.contains("/// Run-time inputs: the geometric symbols without a value in the description, fields `L2`;"),
        "{code}"
    );
    assert!(code.contains("/// Geometric symbol `L2`: a run-time input"));
    assert!(code.contains("/// Geometric symbol `L3` (description value: 0.3)."));
    // No symbol used at all.
    single(
        &format!("{HEAD}[symbols]\nL = 1\n[[joints]]\n"),
        "4:1",
        &[
            "symbol `L` has a value, but no DH value or gravity depends on it",
            "; remove the entry, or write the symbol where it belongs",
        ],
    );
    // one that cancels is no use of it; `pi` is the constant, not a symbol
    single(
        &format!("{HEAD}[symbols]\nL = 0.4\n[[joints]]\na = \"L/L\"\n"),
        "4:1",
        &["symbol `L` has a value, but no DH value or gravity depends on it"],
    );
    single(
        &format!("{HEAD}[symbols]\npi = 3\n[[joints]]\n"),
        "4:1",
        &["`pi` is the constant of the expressions, not a symbol"],
    );
}

#[test]
fn library_calls_are_checked_and_name_the_argument() {
    assert!(matches!(
        Geometry::text("pi/"),
        Err(GeometryError::Parse { .. })
    ));
    assert!(matches!(
        Geometry::number(f64::NAN),
        Err(GeometryError::NotFinite(_))
    ));
    let joint = || Joint::revolute("0", 0.1, 0.0, "0").unwrap();
    let robot = Robot::new("arm", Convention::Modified, None, vec![joint()]).unwrap();
    let argument = |r: Result<Robot, DescriptionError>| match r {
        Err(DescriptionError::Argument { argument, .. }) => argument,
        other => panic!("expected an argument error, got {other:?}"),
    };
    assert_eq!(
        argument(robot.clone().with_gravity([f64::NAN, 0.0, -9.81])),
        "`gravity[0]` of `Robot::with_gravity`"
    );
    assert_eq!(
        argument(robot.clone().with_gravity([0.0, 0.0, -9810.0])),
        "`gravity[2]`"
    );
    assert_eq!(
        argument(robot.clone().with_name("my arm")),
        "the robot name"
    );
    assert_eq!(argument(robot.clone().with_name("self")), "the robot name");
    assert_eq!(
        argument(robot.clone().with_symbol_value("L2", 0.4)),
        "the value of symbol `L2`"
    );
    assert!(
        robot
            .clone()
            .with_joint_drive(1, robid_symbolic::Drive::ALL)
            .is_err()
    );
    let mut far = joint();
    far.d = Geometry::number(2e3).unwrap();
    assert_eq!(
        argument(Robot::new(
            "arm",
            Convention::Modified,
            None,
            vec![joint(), far]
        )),
        "`joints[1].d`"
    );
    let mut limited = joint();
    limited.limits.velocity = Some(f64::INFINITY);
    assert_eq!(
        argument(Robot::new("arm", Convention::Modified, None, vec![limited])),
        "`joints[0].limits.velocity`"
    );
    assert!(Robot::new("arm", Convention::Modified, None, Vec::new()).is_err());
}

/// `emit_programs` returns errors instead of panicking on programs that
/// cannot become Rust (possible only when built or changed by hand).
#[test]
fn emission_fails_without_panicking() {
    let text = format!("{HEAD}[[joints]]\na = 0.5\n[[joints]]\nalpha = \"pi/2\"\n");
    let robot = Robot::from_toml(&text, "arm.toml").unwrap();
    let programs = RobotPrograms::derive(&robot).unwrap();
    assert!(emit_programs(&programs).is_ok());
    let mut nan = programs.clone();
    nan[ProgramKind::Gravity].constants.push(f64::NAN);
    assert!(matches!(
        emit_programs(&nan),
        Err(EmitError::NotFinite { .. })
    ));
    let mut group = programs.clone();
    group[ProgramKind::MassMatrix].inputs[0].name = "not an ident".to_owned();
    assert!(matches!(emit_programs(&group), Err(EmitError::Name { .. })));
    let mut element = programs.clone();
    element[ProgramKind::Coriolis].inputs[0].elements[0] = "q 1".to_owned();
    assert!(matches!(
        emit_programs(&element),
        Err(EmitError::Name { .. })
    ));
    let mut operand = programs.clone();
    operand[ProgramKind::Gravity].outputs[0].values[0] =
        robid_symbolic::program::Value::Temp(u32::MAX);
    assert!(matches!(
        emit_programs(&operand),
        Err(EmitError::Program { .. })
    ));
    let mut empty = programs;
    empty[ProgramKind::Gravity].outputs.clear();
    assert!(matches!(
        emit_programs(&empty),
        Err(EmitError::Program { .. })
    ));
}

/// Operands one past the last temporary, input or constant (and an instruction reading its
/// own result) are refused by the Rust and the C emitters; the last valid ones are not.
#[test]
fn emission_refuses_operands_one_past_the_end() {
    use robid_symbolic::emit::{CScalar, emit_c};
    use robid_symbolic::program::{Instr, Value};
    let text = format!("{HEAD}[[joints]]\na = 0.5\n[[joints]]\nalpha = \"pi/2\"\n");
    let programs = RobotPrograms::derive(&Robot::from_toml(&text, "arm.toml").unwrap()).unwrap();
    let kind = ProgramKind::InverseDynamics;
    let p = &programs[kind];
    let (temps, inputs, constants) = (
        p.instrs.len() as u32,
        p.input_len() as u32,
        p.constants.len() as u32,
    );
    assert!(temps > 0 && constants > 0);
    let both = |programs: &RobotPrograms| {
        (
            emit_programs(programs).is_ok(),
            emit_c(programs, CScalar::Double, "arm.h").is_ok(),
        )
    };
    // an output reading each kind of value at its last valid index, then one past it
    for (last, past) in [
        (Value::Temp(temps - 1), Value::Temp(temps)),
        (Value::Input(inputs - 1), Value::Input(inputs)),
        (Value::Const(constants - 1), Value::Const(constants)),
    ] {
        let mut ok = programs.clone();
        ok[kind].outputs[0].values[0] = last;
        assert_eq!(both(&ok), (true, true), "{last:?}");
        let mut bad = programs.clone();
        bad[kind].outputs[0].values[0] = past;
        assert_eq!(both(&bad), (false, false), "{past:?}");
    }
    // an instruction reading its own result, and one reading the one before
    let last = p.instrs.len() - 1;
    let mut own = programs.clone();
    own[kind].instrs[last] = Instr::Neg(Value::Temp(last as u32));
    assert_eq!(both(&own), (false, false));
    let mut before = programs.clone();
    before[kind].instrs[last] = Instr::Neg(Value::Temp(last as u32 - 1));
    assert_eq!(both(&before), (true, true));
}

/// A `drive` key that TOML attaches to the last joint only is warned about with its line;
/// the intended forms are not.
#[test]
fn a_drive_key_given_to_the_last_joint_by_accident_is_warned_about() {
    let head = "name = \"arm\"\nconvention = \"modified\"\n";
    let joint = "[[joints]]\nalpha = 0\n";
    let warned = |text: &str| Robot::from_toml_with_warnings(text, "arm.toml").unwrap().1;
    let stray = format!("{head}{joint}{joint}{joint}\ndrive = [\"Fv\", \"Fc\"]\n");
    let w = warned(&stray);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("arm.toml:10:9: only joint 3, the last"),
        "{w:?}"
    );
    assert!(w[0].contains("above the first `[[joints]]`"), "{w:?}");
    // what TOML did: the last joint alone has the terms
    let (robot, _) = Robot::from_toml_with_warnings(&stray, "arm.toml").unwrap();
    let counts: Vec<usize> = robot
        .joints()
        .iter()
        .map(|j| j.drive.terms().count())
        .collect();
    assert_eq!(counts, [0, 0, 2]);
    for quiet in [
        format!("{head}drive = [\"Fv\"]\n{joint}{joint}"),
        format!("{head}{joint}drive = []\n{joint}drive = [\"Fv\"]\n"),
        format!("{head}{joint}drive = [\"Fv\"]\n{joint}"),
        format!("{head}{joint}drive = [\"Fv\"]\n"),
        format!("{head}drive = [\"Fc\"]\n{joint}{joint}drive = [\"Fv\"]\n"),
    ] {
        assert!(warned(&quiet).is_empty(), "{quiet}");
    }
}

/// Revolute limits beyond a turn and a quarter are likely degrees read as radians
/// (`robid excite` designed within [-170, 170] rad): warned about at the limits, once;
/// a multi-turn wrist's ±450 degrees (7.85 rad) and a prismatic joint's 10 m are not.
/// Lengths beyond 10 m (millimetres read as metres) are warned about the same way.
#[test]
fn revolute_limits_in_degrees_are_warned_about() {
    let head = "name = \"arm\"\nconvention = \"modified\"\n";
    let joint =
        |limits: &str| format!("[[joints]]\nalpha = 0\nlimits = {{ position = {limits} }}\n");
    let warned = |text: &str| Robot::from_toml_with_warnings(text, "arm.toml").unwrap().1;
    let degrees = format!("{head}{}{}", joint("[-1, 1]"), joint("[-170, 170]"));
    let w = warned(&degrees);
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].starts_with("arm.toml:8:23:")
            && w[0].contains("joint 2 `position` limits [-170, 170] reach beyond 7.86 rad")
            && w[0].contains("in degrees?"),
        "{w:?}"
    );
    // a length in millimetres, likewise
    let mm = format!("{head}[[joints]]\nalpha = 0\n[[joints]]\nalpha = 0\na = 425\n");
    let w = warned(&mm);
    assert!(
        w.len() == 1
            && w[0].starts_with("arm.toml:7:5:")
            && w[0].contains("joint 2 `a` is 425 m")
            && w[0].contains("in millimetres?"),
        "{w:?}"
    );
    // every such length is named, the first at its place (the second showed only once
    // the first was repaired)
    let two = format!("{head}[[joints]]\nalpha = 0\na = 1000\n[[joints]]\nalpha = 0\nd = 999\n");
    let w = warned(&two);
    assert!(
        w.len() == 1
            && w[0].starts_with("arm.toml:5:5:")
            && w[0].contains(
                "joint 1 `a` is 1000 m, longer than an arm's 10 m (so are joint 2 `d` 999 m)"
            ),
        "{w:?}"
    );
    // and through `[symbols]`: `L3 = 425` was not named; a short one is not either
    let symbols = format!(
        "{head}[[joints]]\nalpha = 0\na = \"-L3\"\n[[joints]]\nalpha = 0\nd = \"L4 + 0.1\"\n\
         [symbols]\nL3 = 425\nL4 = 0.2\n"
    );
    let w = warned(&symbols);
    assert!(
        w.len() == 1
            && w[0].starts_with("arm.toml:5:5:")
            && w[0].contains("joint 1 `a = \"-L3\"` is -425 m, longer than an arm's 10 m:")
            && w[0].ends_with("(in `[symbols]` for a length given through a symbol)"),
        "{w:?}"
    );
    let wrist = format!("{head}{}", joint("[-7.854, 7.854]"));
    assert!(warned(&wrist).is_empty());
    let slide =
        format!("{head}[[joints]]\ntype = \"prismatic\"\nlimits = {{ position = [0, 10] }}\n");
    assert!(warned(&slide).is_empty());
}

/// A value written with symbols that the `[symbols]` values make 0 (a length, a gravity
/// component) or a right angle (a twist) is warned about at its place: the base parameters
/// are derived for any value of the symbols and are not minimal there. The warning is
/// true: written as a number, the same robot has fewer base parameters (a planar arm's
/// `a = "L2"` with `L2 = 0`: 4 against 2, whose MX2 and MY2 no trajectory excites); at
/// other values, and for an offset that only shifts a joint's variable, nothing is said.
#[test]
fn symbol_values_where_the_structure_changes_are_warned_about() {
    let warned = |text: &str| Robot::from_toml_with_warnings(text, "arm.toml").unwrap().1;
    let count = |text: &str| {
        let robot = Robot::from_toml(text, "arm.toml").unwrap();
        robid_symbolic::Derivation::new(&robot)
            .base_parameters()
            .unwrap()
            .base
            .len()
    };
    let arm = |a2: &str, alpha2: &str, symbols: &str| {
        format!(
            "{HEAD}[symbols]\n{symbols}\n[[joints]]\nalpha = 0\n[[joints]]\nalpha = {alpha2}\na = {a2}\n"
        )
    };
    let cases = [
        (
            arm("\"L2\"", "0", "L2 = 0"),
            arm("0", "0", ""),
            "arm.toml:9:5:",
            "joint 2 `a = \"L2\"` is 0 at the [symbols] values: ",
            "write 0 in the table",
        ),
        (
            arm("0.3", "\"A\"", "A = 0"),
            arm("0.3", "0", ""),
            "arm.toml:8:9:",
            "joint 2 `alpha = \"A\"` is 0 at the [symbols] values",
            "write 0 in the table",
        ),
        (
            arm("0.3", "\"pi - A\"", "A = 0"),
            arm("0.3", "\"pi\"", ""),
            "arm.toml:8:9:",
            "is \"pi\" at the [symbols] values",
            "write \"pi\" in the table",
        ),
    ];
    for (text, written, at, says, fix) in &cases {
        let w = warned(text);
        assert!(
            w.len() == 1 && w[0].starts_with(at) && w[0].contains(says) && w[0].contains(fix),
            "{text}\n{w:?}"
        );
        println!(
            "{says}: {} base parameters, {} written as a number",
            count(text),
            count(written)
        );
        assert!(
            count(written) < count(text),
            "{text}: {} vs {}",
            count(written),
            count(text)
        );
    }
    // gravity through a symbol at 0, with a second value counted
    let g = format!(
        "{HEAD}gravity = [\"gx\", 0, \"gz\"]\n[symbols]\ngx = 0\ngz = 0\n[[joints]]\nalpha = 0\n"
    );
    let w = warned(&g);
    assert!(
        w.len() == 1
            && w[0].starts_with(
                "arm.toml:3:12: gravity x `\"gx\"` is 0 at the [symbols] values (and 1 more value)"
            ),
        "{w:?}"
    );
    // ordinary values, a revolute joint's offset and a prismatic joint's `d` at 0: nothing
    for quiet in [
        arm("\"L2\"", "\"A\"", "L2 = 0.3\nA = 0.2"),
        format!("{HEAD}[symbols]\nT = 0\n[[joints]]\ntheta = \"T\"\n"),
        format!("{HEAD}[symbols]\nD = 0\n[[joints]]\ntype = \"prismatic\"\nd = \"D\"\n"),
    ] {
        assert_eq!(warned(&quiet), Vec::<String>::new(), "{quiet}");
    }
}

/// Khalil-Kleinfinger `gamma` and `b` belong to a modified table; `[base]` and `[tool]` are
/// tables of `xyz` and `rpy`, three finite values each within the bounds of lengths and
/// angles. Every mistake is located at its key or value.
#[test]
fn general_frames_base_and_tool_are_checked() {
    let standard = "name = \"arm\"\nconvention = \"standard\"\n[[joints]]\na = 0.1\ngamma = \"pi/2\"\nb = 0.2\n";
    let all = errors(standard);
    assert_eq!(all.len(), 2, "{all:#?}");
    assert!(
        all[0].starts_with("arm.toml:5:9: joint 1 has `gamma`"),
        "{}",
        all[0]
    );
    assert!(
        all[1].starts_with("arm.toml:6:5: joint 1 has `b`"),
        "{}",
        all[1]
    );
    assert!(
        all[0].contains("write the table in the modified convention"),
        "{}",
        all[0]
    );
    // even a zero is refused: the key says the table was meant as a modified one
    single(
        "name = \"arm\"\nconvention = \"standard\"\n[[joints]]\ngamma = 0\n",
        "4:9",
        &["joint 1 has `gamma`", "convention = \"modified\""],
    );
    // in a modified table they read, with the checks of angles and lengths
    let ok = format!("{HEAD}[[joints]]\ngamma = \"pi/2\"\nb = \"L\"\n[symbols]\nL = 0.3\n");
    let robot = Robot::from_toml(&ok, "arm.toml").unwrap();
    assert_eq!(robot.joints()[0].gamma.as_str(), "pi/2");
    assert_eq!(robot.symbols(), [("L".to_owned(), Some(0.3))]);
    single(
        &format!("{HEAD}[[joints]]\ngamma = 1.5707963\n"),
        "4:9",
        &["joint 1 `gamma` = 1.5707963 is only", "write \"pi/2\""],
    );
    single(
        &format!("{HEAD}[[joints]]\nb = 2e3\n"),
        "4:5",
        &["joint 1 `b` = 2000 is beyond ±1000 m"],
    );
    // [base] and [tool]
    for (table, at, says) in [
        ("[base]\nxyz = [0, 0]\n", "4:7", "[base] `xyz` has 2 values"),
        (
            "[base]\nrpy = [0, 0, 0, 0]\n",
            "4:7",
            "[base] `rpy` has 4 values",
        ),
        (
            "[tool]\nxyz = [0, 0, nan]\n",
            "4:14",
            "[tool] z is NaN, not a finite number",
        ),
        (
            "[tool]\nrpy = [inf, 0, 0]\n",
            "4:8",
            "[tool] roll is inf, not a finite number",
        ),
        ("[base]\nxzy = [0, 0, 0]\n", "4:1", "unknown key `xzy`"),
        (
            "[base]\nrpy = [0, 90, 0]\n",
            "4:11",
            "[base] rpy pitch = 90 is more than a turn",
        ),
        (
            "[tool]\nxyz = [0, 0, 5e3]\n",
            "4:14",
            "[tool] xyz z = 5000 is beyond ±1000 m",
        ),
        ("base = 3\n", "3:8", "`base` is an integer"),
        (
            "[tool]\nxyz = \"0 0 1\"\n",
            "4:7",
            "[tool] `xyz` is a string",
        ),
    ] {
        let text = format!("{HEAD}{table}[[joints]]\n");
        single(&text, at, &[says]);
    }
    // a pose's angle near a right one is refused in a calibrated table too, which is not
    // told to say it is calibrated
    let near = "[base]\nrpy = [0, 0, 1.5707968]\n[[joints]]\n";
    single(
        &format!("{HEAD}{near}"),
        "4:14",
        &[
            "[base] rpy yaw = 1.5707968 is only 4.7e-7 rad from pi/2",
            "not the [base] and [tool] poses'",
        ],
    );
    let all = errors(&format!("{HEAD}calibrated = true\n{near}")).join("\n");
    assert!(
        all.contains("not the [base] and [tool] poses'") && !all.contains("at the top of its"),
        "{all}"
    );
    // in code: the argument is named
    let joint = Joint::revolute("0", 0.1, 0.0, "0")
        .unwrap()
        .with_gamma_b(Geometry::text("pi/2").unwrap(), Geometry::zero());
    let e = Robot::new("arm", Convention::Standard, None, vec![joint]).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("`joints[0].gamma`: joint 1 has `gamma`"),
        "{e}"
    );
    let arm = Robot::new(
        "arm",
        Convention::Modified,
        None,
        vec![Joint::revolute("0", 0.1, 0.0, "0").unwrap()],
    )
    .unwrap();
    let mut far = robid_symbolic::Transform::identity();
    far.xyz[1] = Geometry::number(-3e3).unwrap();
    let e = arm.with_tool(Some(far)).unwrap_err();
    assert!(
        e.to_string()
            .starts_with("`tool.xyz[1]`: [tool] xyz y = -3000"),
        "{e}"
    );
}

/// A key or table given twice is a TOML error that names the key at its second place, with
/// the fix; toml itself says only "duplicate key".
#[test]
fn a_key_given_twice_is_named_at_its_place() {
    let joint = "[[joints]]\nalpha = 0\nd = 0.1\n";
    for (text, at, says) in [
        (
            format!("{HEAD}{joint}{joint}d = 0.2\n"),
            "9:1",
            "`d` is given a second time in this table",
        ),
        (
            format!("{HEAD}name = \"other\"\n{joint}"),
            "3:1",
            "`name` is given a second time",
        ),
        (
            format!("{HEAD}[base]\nxyz = [0, 0, 0]\n[base]\nrpy = [0, 0, 0]\n{joint}"),
            "5:2",
            "the table `base` is given a second time",
        ),
        (
            format!("{HEAD}{joint}limits = {{ torque = 1, torque = 2 }}\n"),
            "6:24",
            "`torque` is given a second time",
        ),
    ] {
        let all = errors(&text);
        assert_eq!(all.len(), 1, "{text}\n{all:#?}");
        assert!(
            all[0].starts_with(&format!("arm.toml:{at}: {says}")),
            "{all:?}"
        );
        assert!(
            all[0].contains("delete") || all[0].contains("merge"),
            "{all:?}"
        );
    }
}

/// A value nested deeper than the TOML reader follows is told at its place with what is
/// wrong and what to do: toml's "cannot recurse further; max recursion depth met" said what
/// the reader did.
#[test]
fn a_value_nested_too_deep_is_told_what_to_do() {
    for (open, close) in [("[", "]"), ("{ a = ", "}")] {
        let text = format!(
            "{HEAD}[[joints]]\nalpha = 0\nlimits = {}1{}\n",
            open.repeat(5000),
            close.repeat(5000)
        );
        let all = errors(&text);
        assert_eq!(all.len(), 1, "{all:?}");
        assert!(
            all[0].starts_with("arm.toml:5:")
                && all[0].contains("nested deeper than the TOML reader follows")
                && all[0].ends_with("close the brackets this value opens")
                && !all[0].contains("recurse"),
            "{all:?}"
        );
    }
}

/// A calibrated pair of nearly parallel axes (`bounds::calibrated_pair`), as a calibration
/// of an arm writes it (UR controllers' own DH tables have such rows): `b` and `d` beyond
/// 1 km but nearly opposite, the frame within 1 km of the previous one, a twist of 1e-6 rad.
/// Accepted, and its kinematics are the pair's; anything else stays refused.
#[test]
fn a_calibrated_pair_of_nearly_parallel_axes_is_accepted_and_nothing_else() {
    let row = |alpha: &str, b: &str, d: &str| {
        format!(
            "{HEAD}[[joints]]\nalpha = \"pi/2\"\n[[joints]]\nalpha = {alpha}\na = 0.425\nd = {d}\nb = {b}\n"
        )
    };
    // axes 1e-6 rad from parallel, 0.1 m apart across the plane of the normal
    let robot = Robot::from_toml(&row("1e-6", "-100000.05", "100000"), "arm.toml")
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(robot.joints()[1].b.as_str(), "-100000.05");
    // near pi too (b and d then have the same sign)
    assert!(Robot::from_toml(&row("3.1415916535897934", "1e5", "1e5"), "arm.toml").is_ok());
    // the frame 0.05 m along the axes: at 1e-4 rad near pi, d is just beyond 1 km and b
    // just within it (both were asked to be beyond, and near 0 the same arm was accepted)
    for (alpha, b, d) in [
        ("3.141492653589793", "-999.9500016666", "-1000.0000016666"),
        ("1e-4", "1000.0500001666", "-1000.0000001666"),
    ] {
        Robot::from_toml(&row(alpha, b, d), "arm.toml").unwrap_or_else(|e| panic!("{e}"));
    }
    let refused = |text: &str, says: &[&str]| {
        let all = errors(text).join("\n");
        for part in says {
            assert!(all.contains(part), "`{part}` not in {all}");
        }
    };
    // only one long length, the frame 5 km away: told the rule
    refused(
        &row("1e-6", "0", "5000"),
        &["8:5: joint 2 `d` = 5000 is beyond ±1000 m", "(here 5000 m)"],
    );
    // the same lengths not cancelling: the frame 200 km away; each value told
    refused(
        &row("1e-6", "100000", "100000"),
        &[
            "arm.toml:6:9: joint 2 `alpha` = 1e-6 is only 1.0e-6 rad from 0",
            "arm.toml:8:5: joint 2 `d` = 100000 is beyond ±1000 m",
            "arm.toml:9:5: joint 2 `b` = 100000 is beyond ±1000 m",
            "only as a calibrated pair of nearly parallel axes",
            "(here 200000 m), each at most 1e9 m",
        ],
    );
    // long b and d at an ordinary twist: the frame 48 km off; no pair to tell of
    let all = errors(&row("0.5", "-100000", "100000")).join("\n");
    assert!(
        all.contains("8:5: joint 2 `d` = 100000 is beyond ±1000 m"),
        "{all}"
    );
    assert!(!all.contains("calibrated pair"), "{all}");
    // a twist of 1e-6 rad without the long pair is a rounded 0, as always
    single(&row("1e-6", "-0.05", "0.1"), "6:9", &["from 0"]);
    // beyond what f64 keeps the sum of to 1 µm
    refused(
        &row("1e-10", "-2e9", "2e9"),
        &[
            "8:5: joint 2 `d` = 2e9 is beyond ±1000 m",
            "each at most 1e9 m",
        ],
    );
}

/// A revolute joint's `theta` offsets its variable and changes no base parameter, so a
/// value a few microradians from a right angle (a calibrated offset, or `1.5707963` typed
/// for pi/2) is taken as written; one near a nonzero right angle is told once, with the
/// exact form. A prismatic joint's `theta` turns its link for good and keeps the rule.
#[test]
fn a_revolute_theta_near_a_right_angle_is_taken_as_an_offset() {
    let text = format!(
        "{HEAD}[[joints]]\nd = 0.3\ntheta = 1.4e-7\n\n[[joints]]\nalpha = \"pi/2\"\n\
         theta = 1.5707963\n\n[[joints]]\na = 0.4\ntheta = \"-3.1415926\"\n"
    );
    let (robot, warnings) = Robot::from_toml_with_warnings(&text, "arm.toml").unwrap();
    assert_eq!(robot.joints()[0].theta.as_str(), "0.00000014");
    assert_eq!(warnings.len(), 1, "{warnings:#?}");
    for part in [
        "arm.toml:9:9: joint 2 `theta` is 2.7e-8 rad from pi/2 (and 1 more joint)",
        "write \"pi/2\" if pi/2 is meant",
    ] {
        assert!(
            warnings[0].contains(part),
            "`{part}` not in {}",
            warnings[0]
        );
    }
    // a calibrated offset near 0 is no typed right angle: no warning
    let calibrated = format!("{HEAD}[[joints]]\nd = 0.3\ntheta = -7.2e-7\n");
    let (_, warnings) = Robot::from_toml_with_warnings(&calibrated, "arm.toml").unwrap();
    assert!(warnings.is_empty(), "{warnings:#?}");
    single(
        &format!("{HEAD}[[joints]]\ntype = \"prismatic\"\ntheta = 1.5707963\n"),
        "5:9",
        &["joint 1 `theta` = 1.5707963 is only 2.7e-8 rad from pi/2"],
    );
}

/// A right angle printed by a program is that right angle: `1.5707963267948966`
/// (Python's `math.pi / 2`, 6e-17 rad from pi/2) and `1.57079632679` (4.9e-12) were
/// refused as "only 0.0e0 rad from pi/2", so every DH table a script wrote (Corke's
/// Robotics Toolbox models, exported) was; within 1e-9 rad an angle is the multiple of
/// pi/2 exactly, in `[base]` and `[tool]` too, while 2e-9 rad is still refused; a length
/// below 1e-12 m (a computed zero) is 0.
#[test]
fn right_angles_printed_by_programs_are_exact() {
    let text = format!(
        "{HEAD}[base]\nrpy = [3.141592653589793, 0, 0]\n\n[[joints]]\nalpha = 1.5707963267948966\n\
         theta = -1.5707963267948966\nd = 4.440892098500626e-17\n\n[[joints]]\n\
         alpha = -1.57079632679\na = 0.4\ntheta = 6.123233995736766e-17\n"
    );
    let robot = Robot::from_toml(&text, "arm.toml").unwrap_or_else(|e| panic!("{e}"));
    let j = robot.joints();
    let shown: Vec<&str> = [&j[0].alpha, &j[0].theta, &j[1].alpha, &j[1].theta]
        .iter()
        .map(|g| g.as_str())
        .collect();
    assert_eq!(shown, ["pi/2", "-pi/2", "-pi/2", "0"]);
    // a script's computed zero length is 0
    assert_eq!(j[0].d.as_str(), "0");
    assert_eq!(robot.base().unwrap().rpy[0].as_str(), "pi");
    single(
        &format!("{HEAD}[[joints]]\nalpha = 1.570796324794897\n"),
        "4:9",
        &["is only 2.0e-9 rad from pi/2"],
    );
}

/// A file that is not TOML says what it looks like: XML (a URDF read as TOML because of
/// its name), a CSV data file given where the description goes (commas, or aligned
/// columns), gzip; a TOML slip that looks like neither says nothing more.
#[test]
fn a_file_of_another_format_says_what_it_looks_like() {
    let xml = "<?xml version=\"1.0\"?>\n<robot name=\"arm\">\n</robot>\n";
    single(xml, "1:7", &["the file is XML", "`.urdf` extension"]);
    for csv in [
        "t,q1,q2\n0,1,2\n",
        "\u{feff}# log\ntime;q1\n0;1\n",
        "     t        q1        q2\n   0.000   0.1   0.2\n",
    ] {
        let all = errors(csv);
        assert!(
            all.len() == 1
                && all[0].contains("looks like a CSV data file")
                && all[0].contains("first argument"),
            "{csv:?}: {all:?}"
        );
    }
    for slip in ["name \"arm\"\n", "name arm\n"] {
        let all = errors(slip);
        assert!(
            all.len() == 1 && !all[0].contains("CSV") && !all[0].contains("XML"),
            "{all:?}"
        );
    }
    let dir = tempfile::tempdir().unwrap();
    let gz = dir.path().join("log.csv.gz");
    std::fs::write(&gz, [0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 3]).unwrap();
    let e = Robot::from_file(&gz).unwrap_err().to_string();
    assert!(e.contains("gzip-compressed, not a description"), "{e}");
}
