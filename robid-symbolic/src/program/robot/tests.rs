//! The composite-rigid-body mass matrix against the construction it replaced (the
//! customised Newton-Euler algorithm run with `qd = 0`, `qdd = e_k`), on random robots
//! (docs/dynamics.md#composite-rigid-body-mass-matrix).

use super::Context;
use crate::Robot;
use robid_core::ProgramKind;
use robid_core::rng::Rng;

/// A random description: either convention, 2 to 5 joints, prismatic joints now and
/// then, twists and offsets in {0, +-pi/2, pi} or a number, lengths zero, a number or
/// the symbol `L` (of random value), Khalil-Kleinfinger `gamma` and `b` in the modified
/// convention, every drive term or none, a base transform now and then.
fn random_description(seed: u64) -> String {
    let mut rng = Rng::from_state(seed);
    let angle = |rng: &mut Rng| match rng.below(6) {
        0 | 1 => "0".to_owned(),
        2 => "\"pi/2\"".to_owned(),
        3 => "\"-pi/2\"".to_owned(),
        4 => "\"pi\"".to_owned(),
        _ => format!("{:.3}", rng.uniform(-3.0, 3.0)),
    };
    let length = |rng: &mut Rng| match rng.below(4) {
        0 => "0".to_owned(),
        1 => "\"L\"".to_owned(),
        _ => format!("{:.3}", rng.uniform(0.05, 0.5) * [-1.0, 1.0][rng.below(2)]),
    };
    let modified = rng.below(2) == 0;
    let convention = ["standard", "modified"][usize::from(modified)];
    let drive = ["[]", "[\"Ia\", \"Fv\", \"Fc\", \"Fo\"]"][rng.below(2)];
    let mut text = format!(
        "name = \"random\"\nconvention = \"{convention}\"\ndrive = {drive}\n\
         gravity = [0, 0, -9.81]\n"
    );
    let symbol = format!("[symbols]\nL = {:.3}\n", rng.uniform(0.05, 0.5));
    if rng.below(3) == 0 {
        text += &format!(
            "[base]\nxyz = [0.1, 0, 0.2]\nrpy = [{}, {}, {}]\n",
            angle(&mut rng),
            angle(&mut rng),
            angle(&mut rng)
        );
    }
    let mut joints = String::new();
    for _ in 0..2 + rng.below(4) {
        let kind = ["revolute", "revolute", "revolute", "prismatic"][rng.below(4)];
        joints += &format!(
            "[[joints]]\ntype = \"{kind}\"\nalpha = {}\na = {}\nd = {}\ntheta = {}\n",
            angle(&mut rng),
            length(&mut rng),
            length(&mut rng),
            angle(&mut rng)
        );
        if modified && rng.below(2) == 0 {
            joints += &format!("gamma = {}\nb = {}\n", angle(&mut rng), length(&mut rng));
        }
    }
    if joints.contains("\"L\"") {
        text += &symbol;
    }
    text + &joints
}

/// The composite-rigid-body program equals the Newton-Euler columns to 1e-12 at random
/// joint positions, base parameters and symbol values; the two constructions share the
/// frames and the link parameters in their slots, nothing of the algorithms.
#[test]
fn composite_rigid_body_equals_newton_euler_columns() {
    let (mut prismatic, mut general, mut standard, mut drives) = (0, 0, 0, 0);
    for seed in 0..60 {
        let text = random_description(seed);
        let robot =
            Robot::from_toml(&text, "random.toml").unwrap_or_else(|e| panic!("{e}\n{text}"));
        let mut cx = Context::new(&robot).unwrap_or_else(|e| panic!("{e}\n{text}"));
        let crba = cx.build(ProgramKind::MassMatrix).unwrap();
        let columns = cx.mass_matrix_by_columns().unwrap();
        assert_eq!(crba.inputs, columns.inputs);
        prismatic += usize::from(text.contains("prismatic"));
        general += usize::from(text.contains("gamma"));
        standard += usize::from(text.contains("standard"));
        drives += usize::from(text.contains("Ia"));
        let mut rng = Rng::from_state(1000 + seed);
        for _ in 0..10 {
            let inputs: Vec<Vec<f64>> = crba
                .inputs
                .iter()
                .map(|g| (0..g.len()).map(|_| rng.uniform(-2.0, 2.0)).collect())
                .collect();
            let slices: Vec<&[f64]> = inputs.iter().map(|v| v.as_slice()).collect();
            let a = &crba.eval(&slices).unwrap()[0];
            let b = &columns.eval(&slices).unwrap()[0];
            let scale = b.iter().fold(1.0f64, |s, x| s.max(x.abs()));
            for (e, (x, y)) in a.iter().zip(b).enumerate() {
                assert!(
                    (x - y).abs() <= 1e-12 * scale,
                    "seed {seed}, entry {e}: {x} vs {y}\n{text}"
                );
            }
        }
    }
    // every feature was drawn (measured 43, 31, 27 and 28 times, seeded)
    assert!(
        prismatic > 22 && general > 16 && standard > 14 && drives > 14,
        "{prismatic} {general} {standard} {drives}"
    );
}

/// For every reference robot (robots/descriptions), the composite-rigid-body mass
/// matrix costs no more flops than the Newton-Euler columns did; the table of both and
/// of the inverse dynamics is printed (docs/performance.md#mass-matrix-counts).
#[test]
fn composite_rigid_body_is_no_dearer_for_reference_robots() {
    let paths = reference_descriptions();
    assert!(paths.len() >= 8, "{paths:?}");
    eprintln!("| robot | mass matrix before | mass matrix after | inverse dynamics |");
    for path in paths {
        let robot = Robot::from_file(&path).unwrap();
        let mut cx = Context::new(&robot).unwrap();
        let crba = cx.build(ProgramKind::MassMatrix).unwrap().operations();
        let columns = cx.mass_matrix_by_columns().unwrap().operations();
        let id = cx.build(ProgramKind::InverseDynamics).unwrap().operations();
        eprintln!(
            "| {} | {} ({columns}) | {} ({crba}) | {} ({id}) |",
            robot.name(),
            columns.flops(),
            crba.flops(),
            id.flops()
        );
        assert!(
            crba.flops() <= columns.flops(),
            "{}: {crba} vs {columns}",
            robot.name()
        );
        assert!(crba.sin <= columns.sin && crba.cos <= columns.cos);
    }
}

/// The flops (mul + add + neg) of the inverse dynamics, base regressor, gravity, mass
/// matrix and Coriolis programs of every reference robot (robots/descriptions), in that
/// order: the figures of today (docs/performance.md#operation-counts).
const REFERENCE_FLOPS: [(&str, [usize; 5]); 8] = [
    ("kr6r900", [517, 713, 62, 280, 437]),
    ("lwr4", [568, 1193, 93, 331, 533]),
    ("panda", [599, 1220, 93, 371, 564]),
    ("puma560", [476, 698, 62, 280, 423]),
    ("rx90", [452, 642, 62, 242, 407]),
    ("stanford", [131, 101, 11, 38, 100]),
    ("tx40", [467, 689, 62, 268, 418]),
    ("ur5e", [464, 614, 52, 272, 402]),
];

/// No reference robot's program costs more flops than [`REFERENCE_FLOPS`] says, and none
/// costs fewer either (a lowering that saves operations updates the table, so the table
/// stays the floor). Prints the table of the counts.
#[test]
fn reference_robot_counts_are_the_recorded_floor() {
    let kinds = [
        ProgramKind::InverseDynamics,
        ProgramKind::BaseRegressor,
        ProgramKind::Gravity,
        ProgramKind::MassMatrix,
        ProgramKind::Coriolis,
    ];
    let paths = reference_descriptions();
    assert_eq!(paths.len(), REFERENCE_FLOPS.len(), "{paths:?}");
    eprintln!("| robot | inverse dynamics | base regressor | gravity | mass matrix | Coriolis |");
    let mut mismatches = Vec::new();
    for (path, (name, expected)) in paths.iter().zip(REFERENCE_FLOPS) {
        let robot = Robot::from_file(path).unwrap();
        assert_eq!(robot.name(), name);
        let mut cx = Context::new(&robot).unwrap();
        let mut row = format!("| {name} |");
        for (kind, want) in kinds.into_iter().zip(expected) {
            let ops = cx.build(kind).unwrap().operations();
            row += &format!(" {} ({ops}) |", ops.flops());
            if ops.flops() != want {
                mismatches.push(format!(
                    "{name} {kind:?}: {} flops, recorded {want}",
                    ops.flops()
                ));
            }
        }
        eprintln!("{row}");
    }
    assert!(mismatches.is_empty(), "{mismatches:#?}");
}

/// The inverse dynamics' flops stage by stage (forward recursion per link: vd, w and
/// wd, U; backward per link: F, Euler's N, MS x vd, the transfer of f and n, the
/// torque), printed for the UR5e and the PUMA 560; the stages add up to the program's
/// count before the common factors are taken out of its sums, and that less what
/// taking them out saves is the program's count.
#[test]
fn inverse_dynamics_flops_by_stage() {
    use super::super::customised::{Choices, RunInputs, frame_exprs};
    use super::super::lower::Lowering;
    for name in ["ur5e", "puma560"] {
        let path = format!(
            "{}/../robots/descriptions/{name}.toml",
            env!("CARGO_MANIFEST_DIR")
        );
        let robot = Robot::from_file(std::path::Path::new(&path)).unwrap();
        let mut cx = Context::new(&robot).unwrap();
        let program = cx.build(ProgramKind::InverseDynamics).unwrap();
        let info = ProgramKind::InverseDynamics.info();
        let groups: Vec<&str> = info.inputs.iter().map(|a| a.name).collect();
        let links = cx.slots(true);
        let q = cx.d.inputs.q.clone();
        let frames = frame_exprs(&mut cx.d.arena, &cx.d.robot, &q);
        let inputs = cx.inputs(&groups);
        let mut l = Lowering::new(&cx.d.arena, &inputs);
        let sym = &cx.d.inputs;
        let run = RunInputs {
            qd: &sym.qd,
            qdd: &sym.qdd,
            gravity: sym.gravity,
        };
        let tau = l.newton_euler(&frames, &run, &links, Choices::ALL).unwrap();
        l.mark(|| "outputs".to_owned());
        let outputs: Vec<_> = tau.into_iter().map(|t| l.output(t)).collect();
        let stages = l.stage_flops(&outputs);
        eprintln!(
            "{name}: inverse dynamics {} flops",
            program.operations().flops()
        );
        for (label, flops) in &stages {
            eprintln!("  {label}: {flops}");
        }
        let total: usize = stages.iter().map(|s| s.1).sum();
        // The stages count the program as the lowering wrote it; the common factors
        // taken out of its sums afterwards (`factor.rs`) are the difference.
        let group = super::Group::new("tau", super::element_names("tau", outputs.len()));
        let unfactored = l.finish_unfactored(inputs.clone(), vec![(group, outputs)]);
        assert_eq!(total, unfactored.operations().flops(), "{name}");
        let factored = super::super::factor::factor_all(unfactored)
            .operations()
            .flops();
        eprintln!("  common factors taken out of sums: -{}", total - factored);
        assert_eq!(factored, program.operations().flops(), "{name}");
    }
}

/// The inverse dynamics with the last link's wrench in its parent's frame equals the one
/// with it in its own frame to 1e-12, on random robots (twists, offsets and
/// Khalil-Kleinfinger gamma and b of any value, prismatic joints, drive terms) at random
/// states: both variants are built whichever is the cheaper, and the variant is taken
/// on at least a third of the robots.
#[test]
fn last_link_in_its_parents_frame_changes_no_torque() {
    use super::super::customised::{Choices, RunInputs, frame_exprs};
    use super::super::lower::Lowering;
    let mut differ = 0u64;
    let seeds = 60u64;
    for seed in 0..seeds {
        let text = random_description(seed);
        let robot =
            Robot::from_toml(&text, "random.toml").unwrap_or_else(|e| panic!("{e}\n{text}"));
        let mut cx = Context::new(&robot).unwrap_or_else(|e| panic!("{e}\n{text}"));
        let info = ProgramKind::InverseDynamics.info();
        let groups: Vec<&str> = info.inputs.iter().map(|a| a.name).collect();
        let links = cx.slots(true);
        let q = cx.d.inputs.q.clone();
        let frames = frame_exprs(&mut cx.d.arena, &cx.d.robot, &q);
        let inputs = cx.inputs(&groups);
        let sym = cx.d.inputs.clone();
        let run = RunInputs {
            qd: &sym.qd,
            qdd: &sym.qdd,
            gravity: sym.gravity,
        };
        let [own, parent] = [false, true].map(|tip| {
            let mut l = Lowering::new(&cx.d.arena, &inputs);
            let tau = l
                .newton_euler(
                    &frames,
                    &run,
                    &links,
                    Choices {
                        tip,
                        ..Choices::ALL
                    },
                )
                .unwrap();
            let values: Vec<_> = tau.into_iter().map(|t| l.output(t)).collect();
            let group = super::Group::new("tau", super::element_names("tau", values.len()));
            l.finish(inputs.clone(), vec![(group, values)])
        });
        differ += u64::from(own.instrs != parent.instrs);
        let mut rng = Rng::from_state(2000 + seed);
        for _ in 0..10 {
            let values: Vec<Vec<f64>> = own
                .inputs
                .iter()
                .map(|g| (0..g.len()).map(|_| rng.uniform(-2.0, 2.0)).collect())
                .collect();
            let slices: Vec<&[f64]> = values.iter().map(|v| v.as_slice()).collect();
            let a = &parent.eval(&slices).unwrap()[0];
            let b = &own.eval(&slices).unwrap()[0];
            assert_torques_agree(a, b, || format!("seed {seed}\n{text}"));
        }
    }
    assert!(differ * 3 >= seeds, "{differ} of {seeds}");
}

/// Planar angular motion, projected moments and the shifted last moment
/// (docs/dynamics.md#customised-newton-euler) are taken always, not searched like the
/// last link's frame: for every reference robot, the inverse dynamics, gravity and
/// Coriolis programs built without one of them (the last link's frame and the reused
/// accelerations still searched) cost no fewer flops. Prints what each costs left out
/// (docs/performance.md#operation-counts).
#[test]
fn every_other_choice_pays() {
    use super::super::customised::Choices;
    let paths = reference_descriptions();
    eprintln!("| robot | program | all | no plane | no projection | no shift |");
    for path in paths {
        let robot = Robot::from_file(&path).unwrap();
        let mut cx = Context::new(&robot).unwrap();
        for kind in [
            ProgramKind::InverseDynamics,
            ProgramKind::Gravity,
            ProgramKind::Coriolis,
        ] {
            let info = kind.info();
            let groups: Vec<&str> = info.inputs.iter().map(|a| a.name).collect();
            let (runs, friction) = match kind {
                ProgramKind::InverseDynamics => (vec![cx.d.inputs.clone()], true),
                ProgramKind::Gravity => (vec![cx.constant_inputs(false, None, true)], false),
                _ => (vec![cx.constant_inputs(true, None, false)], false),
            };
            let mut flops = |off: fn(&mut Choices)| {
                let variants: Vec<Choices> = (0..4)
                    .map(|k| {
                        let mut c = Choices {
                            tip: k & 2 != 0,
                            reuse: k & 1 == 0,
                            ..Choices::ALL
                        };
                        off(&mut c);
                        c
                    })
                    .collect();
                let single = |t: &[Vec<super::Value>]| t[0].clone();
                cx.newton_euler_variants(&groups, "out", &runs, friction, single, &variants)
                    .unwrap()
                    .operations()
                    .flops()
            };
            let all = flops(|_| {});
            let without = [
                flops(|c| c.plane = false),
                flops(|c| c.projection = false),
                flops(|c| c.shift = false),
            ];
            eprintln!(
                "| {} | {kind:?} | {all} | {} | {} | {} |",
                robot.name(),
                without[0],
                without[1],
                without[2]
            );
            assert_eq!(all, cx.build(kind).unwrap().operations().flops());
            assert!(without.iter().all(|&w| w >= all), "{}", robot.name());
        }
    }
}

/// The gravity program equals the inverse dynamics at rest (`qd = qdd = 0`) with the
/// friction terms' base parameters at 0, to 1e-12, on random robots; with the torques
/// of the leading vertical joints written as 0 (drive term alone) where gravity is
/// along z_0, which at least a third of the robots draw (docs/dynamics.md#customised-newton-euler).
#[test]
fn gravity_is_the_inverse_dynamics_at_rest() {
    use crate::robot::DriveTerm;
    use robid_core::ParameterKind;
    let seeds = 60u64;
    let mut vertical = 0u64;
    for seed in 0..seeds {
        let text = random_description(seed);
        let robot =
            Robot::from_toml(&text, "random.toml").unwrap_or_else(|e| panic!("{e}\n{text}"));
        let p = super::RobotPrograms::derive(&robot).unwrap_or_else(|e| panic!("{e}\n{text}"));
        let gravity = &p[ProgramKind::Gravity];
        let id = &p[ProgramKind::InverseDynamics];
        // a joint's torque that is the constant 0
        vertical +=
            u64::from(gravity.outputs[0].values.iter().any(
                |&v| matches!(v, super::Value::Const(c) if gravity.constants[c as usize] == 0.0),
            ));
        let n = robot.dof();
        let geometry: Vec<f64> = robot.symbols().iter().map(|(_, v)| v.unwrap()).collect();
        let mut rng = Rng::from_state(3000 + seed);
        for _ in 0..10 {
            let q: Vec<f64> = (0..n).map(|_| rng.uniform(-3.0, 3.0)).collect();
            let base: Vec<f64> = p
                .base
                .iter()
                .map(|b| match b.name.on.kind {
                    ParameterKind::Drive(t) if t != DriveTerm::Ia => 0.0,
                    _ => rng.uniform(-1.0, 1.0),
                })
                .collect();
            let zero = vec![0.0; n];
            let (mut g_in, mut t_in): (Vec<&[f64]>, Vec<&[f64]>) =
                (vec![&q, &base], vec![&q, &zero, &zero, &base]);
            if !geometry.is_empty() {
                g_in.push(&geometry);
                t_in.push(&geometry);
            }
            let g = &gravity.eval(&g_in).unwrap()[0];
            let t = &id.eval(&t_in).unwrap()[0];
            assert_torques_agree(g, t, || format!("seed {seed}\n{text}"));
        }
    }
    // measured 41 of 60, seeded
    assert!(vertical * 3 >= seeds, "{vertical} of {seeds}");
}

/// `a` and `b` equal to 1e-12 of the larger of 1 and `b`'s largest magnitude, joint by
/// joint; `context` says which case failed.
fn assert_torques_agree(a: &[f64], b: &[f64], context: impl Fn() -> String) {
    let scale = b.iter().fold(1.0f64, |s, x| s.max(x.abs()));
    for (j, (x, y)) in a.iter().zip(b).enumerate() {
        assert!(
            (x - y).abs() <= 1e-12 * scale,
            "joint {j}: {x} vs {y}, {}",
            context()
        );
    }
}

/// The reference descriptions (robots/descriptions/*.toml), sorted by name.
fn reference_descriptions() -> Vec<std::path::PathBuf> {
    let dir = format!("{}/../robots/descriptions", env!("CARGO_MANIFEST_DIR"));
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    paths
}

/// `derive_reporting` reports each of its `STAGES` stages once, in order (the base
/// parameters, then every program as `ProgramKind::ALL` lists them), and derives what
/// `derive` does: `robid model` shows a long chain's progress from it.
#[test]
fn derive_reports_every_stage_in_order() {
    let robot = Robot::from_toml(&random_description(11), "random.toml").unwrap();
    let mut stages = Vec::new();
    let reported =
        super::RobotPrograms::derive_reporting(&robot, &mut |s| stages.push(s.to_owned())).unwrap();
    let mut expected = vec!["base parameters".to_owned()];
    expected.extend(ProgramKind::ALL.iter().map(|k| k.info().name.to_owned()));
    assert_eq!(stages, expected);
    assert_eq!(stages.len(), super::RobotPrograms::STAGES);
    let plain = super::RobotPrograms::derive(&robot).unwrap();
    assert_eq!(reported.base, plain.base);
    for ((a, p), (b, q)) in reported.iter().zip(plain.iter()) {
        assert_eq!((a.name, p.operations()), (b.name, q.operations()));
    }
}

/// `derive_showing` hands on, once and before the first program, the base parameters a
/// derivation of their own gives (their terms, expressions and the unidentifiable ones):
/// `robid model` reports them from it.
#[test]
fn derive_shows_the_base_parameters_of_a_derivation() {
    let robot = Robot::from_toml(&random_description(7), "random.toml").unwrap();
    let mut own = crate::Derivation::new(&robot);
    let expected = own.base_parameters().unwrap();
    let text = |arena: &crate::Arena, b: &crate::regroup::BaseParameters| {
        let base: Vec<_> = b
            .base
            .iter()
            .map(|p| {
                let terms: Vec<_> = p
                    .terms
                    .iter()
                    .map(|&(s, c)| (s, arena.display(c)))
                    .collect();
                (p.name.to_string(), arena.display(p.expression), terms)
            })
            .collect();
        (b.standard.clone(), base, b.unidentifiable.clone())
    };
    let expected = text(&own.arena, &expected);
    let stages = std::cell::Cell::new(0);
    let mut shown = Vec::new();
    super::RobotPrograms::derive_showing(
        &robot,
        &mut |_| stages.set(stages.get() + 1),
        &mut |arena, b| {
            assert_eq!(stages.get(), 0, "shown after a stage");
            shown.push(text(arena, b));
        },
    )
    .unwrap();
    assert_eq!(shown, [expected]);
}
