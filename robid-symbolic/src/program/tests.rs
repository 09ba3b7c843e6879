//! The program against the arena's evaluation on the UR5e.

use super::{Group, Operations, Program};
use crate::{Derivation, Robot};
use robid_core::ProgramKind;
use robid_core::rng::Rng;

const UR5E: &str = include_str!("../../../robots/descriptions/ur5e.toml");

#[test]
fn regressor_program_equals_arena_eval() {
    let robot = Robot::from_toml(UR5E, "ur5e.toml").unwrap();
    let mut d = Derivation::new(&robot);
    let y = d.regressor();
    let entries = y.entries();
    let groups: Vec<Group> = ["q", "qd", "qdd"]
        .iter()
        .map(|g| Group::new(g, (1..=6).map(|j| format!("{g}{j}")).collect()))
        .collect();
    let out = Group::new("y", (0..entries.len()).map(|i| format!("y{i}")).collect());
    let program = Program::build(&d.arena, groups, vec![(out, entries.clone())]).unwrap();
    eprintln!("{}", program.operations());
    let mut rng = Rng::from_state(7);
    for _ in 0..20 {
        let x: Vec<Vec<f64>> = (0..3)
            .map(|_| (0..6).map(|_| rng.uniform(-3.0, 3.0)).collect())
            .collect();
        let mut pairs = Vec::new();
        let names: Vec<String> = ["q", "qd", "qdd"]
            .iter()
            .flat_map(|g| (1..=6).map(move |j| format!("{g}{j}")))
            .collect();
        for (k, name) in names.iter().enumerate() {
            pairs.push((name.as_str(), x[k / 6][k % 6]));
        }
        let values = d.arena.values(&pairs);
        let expected = d.arena.eval(&entries, &values).unwrap();
        let got = program.eval(&[&x[0], &x[1], &x[2]]).unwrap();
        for (e, g) in expected.iter().zip(&got[0]) {
            assert!((e - g).abs() <= 1e-12 * (1.0 + e.abs()), "{e} vs {g}");
        }
    }
}

/// Guards the operation counts against regressions of the lowering (the
/// figures reached when this was written: inverse dynamics 474 flops with
/// the customised Newton-Euler, base regressor 624 with the link wrenches
/// projected on the joint axes; 467 since the last link's wrench is written in its
/// parent's frame; 466 since common factors are taken out of sums; 464 since the last link's U
/// entries about its joint axis are its parent's; gravity 52 since the torque of joint 1,
/// whose axis is vertical, is 0 at rest; Coriolis 402 since a sum written twice by the
/// factoring is merged).
#[test]
fn ur5e_programs_counts() {
    let robot = Robot::from_toml(UR5E, "ur5e.toml").unwrap();
    let t = std::time::Instant::now();
    let p = super::RobotPrograms::derive(&robot).unwrap();
    eprintln!("derive {:?}", t.elapsed());
    for (name, prog) in [
        ("id", &p[ProgramKind::InverseDynamics]),
        ("yb", &p[ProgramKind::BaseRegressor]),
        ("y", &p[ProgramKind::StandardRegressor]),
        ("m", &p[ProgramKind::MassMatrix]),
        ("g", &p[ProgramKind::Gravity]),
        ("c", &p[ProgramKind::Coriolis]),
        ("k", &p[ProgramKind::BaseFromStandard]),
    ] {
        eprintln!(
            "{name}: {} flops {}",
            prog.operations(),
            prog.operations().flops()
        );
    }
    // The counts of today, exactly: the lowering is deterministic, and a change of its
    // sharing or reuse shows here. A lowering that saves operations updates these figures
    // (and the README's); one that adds operations is a regression.
    let ops = |mul, add, neg, trig| Operations {
        mul,
        add,
        neg,
        sin: trig,
        cos: trig,
        ..Operations::default()
    };
    for (kind, expected, flops) in [
        (ProgramKind::InverseDynamics, ops(240, 224, 0, 5), 464),
        (ProgramKind::BaseRegressor, ops(342, 252, 20, 5), 614),
        (ProgramKind::StandardRegressor, ops(726, 463, 23, 5), 1212),
        (ProgramKind::MassMatrix, ops(148, 124, 0, 5), 272),
        (ProgramKind::Gravity, ops(34, 18, 0, 5), 52),
        (ProgramKind::Coriolis, ops(221, 181, 0, 5), 402),
        (ProgramKind::BaseFromStandard, ops(17, 37, 0, 0), 54),
    ] {
        let got = p[kind].operations();
        assert_eq!(got, expected, "{kind:?}");
        assert_eq!(got.flops(), flops, "{kind:?}");
        // every instruction is counted once, of its kind
        let total = got.mul + got.add + got.neg + got.div + got.sin + got.cos + got.sign + got.sqrt;
        assert_eq!(total, p[kind].instrs.len(), "{kind:?}");
    }
}

/// For every reference robot (rigid and with every drive term), at random
/// states: the inverse dynamics with base parameters equals the standard
/// regressor (lowered from the arena) times the standard parameters, and
/// M qdd equals tau(q, qd, qdd) - tau(q, qd, 0). Gravity and Coriolis are checked on
/// their own against an independent RNEA in `tests/tests/suite/emitted_vs_rnea.rs`.
#[test]
fn programs_agree_for_reference_robots() {
    let close = |a: f64, b: f64, what: &str| {
        assert!(
            (a - b).abs() <= 1e-9 * (1.0 + b.abs()),
            "{what}: {a} vs {b}"
        );
    };
    let mut robots: Vec<(String, Robot)> = [
        "ur5e", "puma560", "rx90", "tx40", "lwr4", "panda", "stanford",
    ]
    .iter()
    .map(|name| {
        let path = format!(
            "{}/../robots/descriptions/{name}.toml",
            env!("CARGO_MANIFEST_DIR")
        );
        (
            name.to_string(),
            Robot::from_file(std::path::Path::new(&path)).unwrap(),
        )
    })
    .collect();
    // small chains where the customised programs' special cases meet their edges: one
    // joint about gravity (its link's mass acts on nothing), one across it, a planar 2R,
    // and a prismatic last joint
    for (name, joints) in [
        ("1R vertical", "[[joints]]\n"),
        ("1R horizontal", "[[joints]]\nalpha = \"pi/2\"\n"),
        (
            "2R planar",
            "[[joints]]\nalpha = \"pi/2\"\n[[joints]]\na = 0.4\n",
        ),
        (
            "RRP",
            "[[joints]]\n[[joints]]\nalpha = \"pi/2\"\nd = 0.2\n\
             [[joints]]\ntype = \"prismatic\"\nalpha = \"-pi/2\"\na = 0.1\n",
        ),
    ] {
        let text = format!("name = \"small\"\nconvention = \"modified\"\n{joints}");
        robots.push((
            name.to_string(),
            Robot::from_toml(&text, "small.toml").unwrap(),
        ));
    }
    for (name, robot) in &robots {
        for drive in [crate::Drive::NONE, crate::Drive::ALL] {
            let robot = robot.clone().with_drive(drive);
            let p = super::RobotPrograms::derive(&robot).unwrap();
            let n = robot.dof();
            let geometry: Vec<f64> = robot.symbols().iter().map(|(_, v)| v.unwrap()).collect();
            let run = |prog: &Program, inputs: Vec<&[f64]>| {
                let mut inputs = inputs.clone();
                if !geometry.is_empty() {
                    inputs.push(geometry.as_slice());
                }
                prog.eval(&inputs).unwrap().remove(0)
            };
            let mut rng = Rng::from_state(11);
            for _ in 0..5 {
                let mut random =
                    |k: usize, r: f64| -> Vec<f64> { (0..k).map(|_| rng.uniform(-r, r)).collect() };
                let (q, qd, qdd) = (random(n, 3.0), random(n, 2.0), random(n, 4.0));
                let standard = random(p.standard.len(), 1.0);
                let zero = vec![0.0; n];
                let base = run(&p[ProgramKind::BaseFromStandard], vec![&standard]);
                let y = run(&p[ProgramKind::StandardRegressor], vec![&q, &qd, &qdd]);
                let yb = run(&p[ProgramKind::BaseRegressor], vec![&q, &qd, &qdd]);
                let tau = run(&p[ProgramKind::InverseDynamics], vec![&q, &qd, &qdd, &base]);
                let tau_v = run(
                    &p[ProgramKind::InverseDynamics],
                    vec![&q, &qd, &zero, &base],
                );
                let m = run(&p[ProgramKind::MassMatrix], vec![&q, &base]);
                let (ns, nb) = (standard.len(), base.len());
                for j in 0..n {
                    let ys: f64 = (0..ns).map(|k| y[j * ns + k] * standard[k]).sum();
                    let ybb: f64 = (0..nb).map(|k| yb[j * nb + k] * base[k]).sum();
                    close(tau[j], ys, &format!("{name}: tau vs Y standard, joint {j}"));
                    close(
                        ybb,
                        ys,
                        &format!("{name}: Y_b base vs Y standard, joint {j}"),
                    );
                    let mq: f64 = (0..n).map(|k| m[j * n + k] * qdd[k]).sum();
                    close(mq, tau[j] - tau_v[j], &format!("{name}: M qdd"));
                }
            }
        }
    }
}

/// `Program::run` never panics on inputs or outputs of any count or length:
/// it runs when every group has its length and returns a `LengthError`
/// naming the first group that does not, otherwise (the rx90's programs also
/// read a `geometry` group).
#[test]
fn run_checks_every_length_and_never_panics() {
    let text = include_str!("../../../robots/descriptions/rx90.toml");
    let robot = Robot::from_toml(text, "rx90.toml").unwrap();
    let p = super::RobotPrograms::derive(&robot).unwrap();
    let mut rng = Rng::from_state(11);
    for program in [
        &p[ProgramKind::InverseDynamics],
        &p[ProgramKind::MassMatrix],
        &p[ProgramKind::BaseFromStandard],
    ] {
        let inputs: Vec<usize> = program.inputs.iter().map(Group::len).collect();
        let outputs: Vec<usize> = program.outputs.iter().map(|o| o.values.len()).collect();
        let mut temps = Vec::new();
        for case in 0..400 {
            // Mostly the right shapes, each count or length off now and then.
            let vary = |rng: &mut Rng, n: usize| match rng.below(6) {
                0 => rng.below(2 * n + 2),
                _ => n,
            };
            let input_count = vary(&mut rng, inputs.len());
            let output_count = vary(&mut rng, outputs.len());
            let xs: Vec<Vec<f64>> = (0..input_count)
                .map(|g| vec![0.5; vary(&mut rng, inputs.get(g).copied().unwrap_or(3))])
                .collect();
            let mut ys: Vec<Vec<f64>> = (0..output_count)
                .map(|g| vec![0.0; vary(&mut rng, outputs.get(g).copied().unwrap_or(3))])
                .collect();
            let x: Vec<&[f64]> = xs.iter().map(Vec::as_slice).collect();
            let mut y: Vec<&mut [f64]> = ys.iter_mut().map(Vec::as_mut_slice).collect();
            let right = x.iter().map(|s| s.len()).eq(inputs.iter().copied())
                && y.iter().map(|s| s.len()).eq(outputs.iter().copied());
            let result = program.run(&x, &mut y, &mut temps);
            assert_eq!(result.is_ok(), right, "case {case}: {result:?}");
            if right {
                assert!(ys.iter().flatten().all(|v| v.is_finite()), "case {case}");
            }
        }
    }
}

/// Powers (positive, negative, odd and even, of negative terms), quotients and
/// negations lowered and interpreted equal the arena's evaluation; an output that is an
/// input itself counts as a use of that input's group, and an unread group as unused.
#[test]
fn powers_quotients_and_inputs_lower_exactly() {
    let mut a = crate::expr::Arena::new();
    let (x, y, z) = (a.var("x"), a.var("y"), a.var("z"));
    let minus_x = a.neg(x);
    let mut outputs = Vec::new();
    for n in [-3, -2, -1, 2, 3, 5, 6, 7, 13] {
        outputs.push(a.pow(x, n));
        outputs.push(a.pow(minus_x, n));
    }
    let xy = a.mul2(x, y);
    outputs.push(a.div(xy, z));
    outputs.push(a.sub(y, xy));
    let three = a.int(3);
    let scaled = a.mul2(three, minus_x);
    outputs.push(a.add2(scaled, y));
    outputs.push(y);
    let z2 = a.mul2(z, z);
    outputs.push(a.sqrt(z2));
    outputs.push(a.sign(xy));
    outputs.push(a.int(-3));
    let inputs = vec![
        Group::new("x", vec!["x".into()]),
        Group::new("y", vec!["y".into()]),
        Group::new("z", vec!["z".into()]),
        Group::new("w", vec!["w".into()]),
    ];
    let group = Group::new("out", (0..outputs.len()).map(|i| format!("o{i}")).collect());
    let program = Program::build(&a, inputs, vec![(group.clone(), outputs.clone())]).unwrap();
    for (xv, yv, zv) in [(0.7, -1.3, 2.5), (-1.9, 0.4, -0.3)] {
        let values = a.values(&[("x", xv), ("y", yv), ("z", zv)]);
        let expected = a.eval(&outputs, &values).unwrap();
        let got = program.eval(&[&[xv], &[yv], &[zv], &[0.0]]).unwrap();
        for (i, (e, g)) in expected.iter().zip(&got[0]).enumerate() {
            assert!(
                (e - g).abs() <= 1e-13 * e.abs().max(1.0),
                "output {i}: {e} vs {g}"
            );
        }
    }
    let ops = program.operations();
    // measured 4 divisions (the negative powers and x y / z)
    assert!(
        (2..=8).contains(&ops.div) && ops.sign == 1 && ops.sqrt == 1,
        "{ops}"
    );
    let total = ops.mul + ops.add + ops.neg + ops.div + ops.sin + ops.cos + ops.sign + ops.sqrt;
    assert_eq!(total, program.instrs.len());
    assert!((0..3).all(|g| program.uses_input_group(g)));
    assert!(!program.uses_input_group(3));
    // y is read by instructions and by an output; an output alone is a use too
    let only = Program::build(
        &a,
        vec![Group::new("y", vec!["y".into()])],
        vec![(Group::new("out", vec!["o".into()]), vec![y])],
    )
    .unwrap();
    assert!(only.instrs.is_empty() && only.uses_input_group(0));
    assert!(!group.is_empty() && Group::new("none", Vec::new()).is_empty());
}

/// Powers by repeated squaring: x^5 takes three multiplications (x^2, x^4, x x^4), x^-2
/// one and a division, and nothing more.
#[test]
fn powers_cost_what_repeated_squaring_costs() {
    let mut a = crate::expr::Arena::new();
    let x = a.var("x");
    for (n, mul, div) in [(5, 3, 0), (-2, 1, 1), (8, 3, 0), (3, 2, 0)] {
        let p = a.pow(x, n);
        let program = Program::build(
            &a,
            vec![Group::new("x", vec!["x".into()])],
            vec![(Group::new("out", vec!["o".into()]), vec![p])],
        )
        .unwrap();
        let ops = program.operations();
        assert_eq!(
            (ops.mul, ops.div, program.instrs.len()),
            (mul, div, mul + div),
            "x^{n}"
        );
        let got = program.eval(&[&[1.3]]).unwrap()[0][0];
        assert!(
            (got - 1.3f64.powi(n)).abs() < 1e-14 * got.abs(),
            "x^{n}: {got}"
        );
    }
}

/// Every program's outputs are named `{group}{index}`, which the emitter relies on.
#[test]
fn output_elements_are_numbered() {
    let robot = Robot::from_toml(UR5E, "ur5e.toml").unwrap();
    let p = super::RobotPrograms::derive(&robot).unwrap();
    let program = &p[ProgramKind::InverseDynamics];
    for output in &program.outputs {
        let names: Vec<String> = (0..output.values.len())
            .map(|i| format!("{}{i}", output.group.name))
            .collect();
        assert_eq!(output.group.elements, names);
    }
}

/// A sum reuses the largest earlier sum among its terms: with x + y, x + y + z and
/// x + y + z + w + v as outputs, each later sum adds to the one before (4 additions); a
/// smaller earlier sum would cost one more.
#[test]
fn a_sum_reuses_the_largest_earlier_sum() {
    let mut a = crate::expr::Arena::new();
    let names = ["x", "y", "z", "w", "v"];
    let vars: Vec<_> = names.iter().map(|n| a.var(n)).collect();
    let sums: Vec<_> = [2, 3, 5].iter().map(|&k| a.add(&vars[..k])).collect();
    let inputs: Vec<Group> = names
        .iter()
        .map(|n| Group::new(n, vec![n.to_string()]))
        .collect();
    let out = Group::new("out", vec!["a".into(), "b".into(), "c".into()]);
    for _ in 0..20 {
        // the candidates are visited in a hash map's order: every order must find the largest
        let program =
            Program::build(&a, inputs.clone(), vec![(out.clone(), sums.clone())]).unwrap();
        assert_eq!(program.operations().add, 4, "{}", program.operations());
    }
}

/// The last joint's torque shifted to its parent's origin (no mass, no MZ, a_n = 0 after
/// regrouping) applies from two joints on: an RR with crossed axes and a_2 = 0 costs 31
/// multiplications and 25 additions (44 and 33 without the shift; 32 and 25 when the
/// scaled accelerations were always reused).
#[test]
fn the_last_joint_shift_applies_from_two_joints() {
    let text = "name = \"rr\"\nconvention = \"modified\"\n[[joints]]\n[[joints]]\n\
                alpha = \"pi/2\"\nd = 0.3\n";
    let robot = Robot::from_toml(text, "rr.toml").unwrap();
    let p = super::RobotPrograms::derive(&robot).unwrap();
    let ops = p[ProgramKind::InverseDynamics].operations();
    assert_eq!((ops.mul, ops.add, ops.neg), (31, 25, 0), "{ops}");
}

/// The compact form computes every program of the rx90 (which reads a `geometry` group,
/// bound here) and of the UR5e with every drive term to the bit as `Program::run` does,
/// refuses a binding that does not cover whole trailing groups, and names a group of the
/// wrong length as `Program::run` does.
#[test]
fn compact_programs_equal_the_interpreter_to_the_bit() {
    let rx90 = Robot::from_toml(
        include_str!("../../../robots/descriptions/rx90.toml"),
        "rx90.toml",
    )
    .unwrap();
    let ur5e = Robot::from_toml(UR5E, "ur5e.toml")
        .unwrap()
        .with_drive(crate::Drive::ALL);
    let mut rng = Rng::from_state(5);
    for robot in [rx90, ur5e] {
        let p = super::RobotPrograms::derive(&robot).unwrap();
        let geometry: Vec<f64> = robot.symbols().iter().map(|(_, v)| v.unwrap()).collect();
        for info in robid_core::PROGRAMS {
            let program = &p[info.kind];
            let compact = program.compact(&geometry).unwrap();
            let (mut temps, mut registers) = (Vec::new(), Vec::new());
            for _ in 0..4 {
                let xs: Vec<Vec<f64>> = info
                    .inputs
                    .iter()
                    .zip(&program.inputs)
                    .map(|(_, g)| (0..g.len()).map(|_| rng.uniform(-2.0, 2.0)).collect())
                    .collect();
                let mut all: Vec<&[f64]> = xs.iter().map(Vec::as_slice).collect();
                let free = all.clone();
                if !geometry.is_empty() {
                    all.push(&geometry);
                }
                let len = program.outputs[0].values.len();
                let (mut want, mut got) = (vec![0.0; len], vec![f64::NAN; len]);
                program.run(&all, &mut [&mut want], &mut temps).unwrap();
                compact.run(&free, &mut [&mut got], &mut registers).unwrap();
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&got), bits(&want), "{} {}", robot.name(), info.name);
                if let Some(first) = xs.first() {
                    let mut short = free.clone();
                    short[0] = &first[1..];
                    let e = compact.run(&short, &mut [&mut got], &mut registers);
                    let mut all_short = all.clone();
                    all_short[0] = &first[1..];
                    let want_e = program.run(&all_short, &mut [&mut want], &mut temps);
                    assert_eq!(e.unwrap_err(), want_e.unwrap_err());
                }
            }
        }
        if !geometry.is_empty() {
            let e = p[ProgramKind::MassMatrix]
                .compact(&geometry[1..])
                .unwrap_err();
            assert_eq!(e.found, geometry.len() - 1);
        }
    }
}

/// Lane-major runs equal one run per argument set to the bit, for every program of a robot
/// with every drive term (sign, sqrt-free friction, offsets) and several lane counts; a
/// group whose length is not lanes times its element count, and zero lanes, are refused.
#[test]
fn compact_lanes_equal_one_run_per_set_to_the_bit() {
    let ur5e = Robot::from_toml(UR5E, "ur5e.toml")
        .unwrap()
        .with_drive(crate::Drive::ALL);
    let p = super::RobotPrograms::derive(&ur5e).unwrap();
    let geometry: Vec<f64> = ur5e.symbols().iter().map(|(_, v)| v.unwrap()).collect();
    let mut rng = Rng::from_state(9);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for info in robid_core::PROGRAMS {
        let program = &p[info.kind];
        let compact = program.compact(&geometry).unwrap();
        let len = program.outputs[0].values.len();
        let groups: Vec<usize> = info
            .inputs
            .iter()
            .zip(&program.inputs)
            .map(|(_, g)| g.len())
            .collect();
        let mut registers = Vec::new();
        for lanes in [1, 3, 8] {
            // set l of group g: sets[l][g]; a zero velocity in one set exercises sign(0)
            let sets: Vec<Vec<Vec<f64>>> = (0..lanes)
                .map(|l| {
                    groups
                        .iter()
                        .map(|&n| {
                            (0..n)
                                .map(|_| if l == 1 { 0.0 } else { rng.uniform(-2.0, 2.0) })
                                .collect()
                        })
                        .collect()
                })
                .collect();
            let lane_major: Vec<Vec<f64>> = groups
                .iter()
                .enumerate()
                .map(|(g, &n)| {
                    (0..n * lanes)
                        .map(|k| sets[k % lanes][g][k / lanes])
                        .collect()
                })
                .collect();
            let inputs: Vec<&[f64]> = lane_major.iter().map(Vec::as_slice).collect();
            let mut got = vec![f64::NAN; len * lanes];
            compact
                .run_lanes(lanes, &inputs, &mut [&mut got], &mut registers)
                .unwrap();
            for (l, set) in sets.iter().enumerate() {
                let one: Vec<&[f64]> = set.iter().map(Vec::as_slice).collect();
                let mut want = vec![f64::NAN; len];
                compact
                    .run(&one, &mut [&mut want], &mut Vec::new())
                    .unwrap();
                let lane: Vec<f64> = (0..len).map(|i| got[i * lanes + l]).collect();
                assert_eq!(
                    bits(&lane),
                    bits(&want),
                    "{} lane {l} of {lanes}",
                    info.name
                );
            }
            if let Some(first) = inputs.first().filter(|s| !s.is_empty()) {
                let mut short = inputs.clone();
                short[0] = &first[1..];
                let e = compact
                    .run_lanes(lanes, &short, &mut [&mut got], &mut registers)
                    .unwrap_err();
                assert_eq!((e.found, e.expected), (first.len() - 1, first.len()));
            }
        }
        assert!(
            compact
                .run_lanes(0, &[], &mut [&mut []], &mut registers)
                .is_err()
        );
    }
}

/// A regressor entry that is zero for every state is exactly 0 in the program, not the
/// rounding of a difference of equal products: `ZZ2`'s entry in `tau1` when the second
/// axis is perpendicular to the first (the torque of link 2's spin about `z2` on `z1`)
/// was `s (c qd1 qd2) - c (s qd1 qd2)`, 1e-17 instead of 0.
#[test]
fn a_regressor_entry_zero_for_every_state_is_exactly_zero() {
    let robot = Robot::from_toml(
        "name = \"r2\"\nconvention = \"modified\"\n[[joints]]\nalpha = 0\na = 0\nd = 0\n\
         [[joints]]\nalpha = \"pi/2\"\na = 0\nd = 0\n",
        "r2.toml",
    )
    .unwrap();
    let p = crate::program::RobotPrograms::derive(&robot).unwrap();
    let column = p
        .base
        .iter()
        .position(|b| b.name.to_string() == "ZZ2")
        .unwrap();
    let program = &p[ProgramKind::BaseRegressor];
    let super::Value::Const(c) = program.outputs[0].values[column] else {
        panic!("{:?}", program.outputs[0].values[column]);
    };
    assert_eq!(program.constants[c as usize], 0.0);
    // and nowhere a state where the program leaves rounding in it
    let mut rng = Rng::from_state(11);
    for _ in 0..50 {
        let x: Vec<Vec<f64>> = (0..3)
            .map(|_| (0..2).map(|_| rng.uniform(-3.0, 3.0)).collect())
            .collect();
        let y = program.eval(&[&x[0], &x[1], &x[2]]).unwrap();
        assert_eq!(y[0][column], 0.0);
    }
}

/// A sum in which the arena keeps one value twice (`q3 (qdd1 + qdd2) - q3 (-qdd1 - qdd2)`
/// in the standard regressor of this robot, a prismatic joint after two parallel revolute
/// ones) is computed with both copies: the lowering's reuse of earlier sums keyed its terms
/// by value, dropped both copies when it took a subset out, and the `MZ3` entry of `tau1`
/// was off by 2.9 (found by the random robots of `tests/tests/suite/emitted_vs_rnea.rs`
/// run past the suite's eight seeds: seed 77).
#[test]
fn a_sum_with_a_repeated_term_keeps_both() {
    let text = "name = \"random77\"\nconvention = \"modified\"\n\
        gravity = [0.47084624141297177, -0.6060886274044435, -9.798693985269022]\n\
        [[joints]]\nalpha = \"-pi/2\"\nd = -0.10918609384108396\ntheta = \"pi/2\"\n\
        [[joints]]\nalpha = 0\nd = -0.1432951830775141\ntheta = -0.6983026545267688\n\
        [[joints]]\ntype = \"prismatic\"\nalpha = \"-pi/2\"\na = -0.4021968383241944\n\
        theta = 0\n";
    let robot = Robot::from_toml(text, "random77.toml").unwrap();
    let mut d = Derivation::new(&robot);
    let entries = d.regressor().entries();
    let groups: Vec<Group> = ["q", "qd", "qdd"]
        .iter()
        .map(|g| Group::new(g, (1..=3).map(|j| format!("{g}{j}")).collect()))
        .collect();
    let out = Group::new("y", (0..entries.len()).map(|i| format!("y{i}")).collect());
    let program = Program::build(&d.arena, groups, vec![(out, entries.clone())]).unwrap();
    let names: Vec<String> = ["q", "qd", "qdd"]
        .iter()
        .flat_map(|g| (1..=3).map(move |j| format!("{g}{j}")))
        .collect();
    let mut rng = Rng::from_state(7);
    for _ in 0..20 {
        let x: Vec<Vec<f64>> = (0..3)
            .map(|_| (0..3).map(|_| rng.uniform(-3.0, 3.0)).collect())
            .collect();
        let pairs: Vec<(&str, f64)> = names
            .iter()
            .enumerate()
            .map(|(k, name)| (name.as_str(), x[k / 3][k % 3]))
            .collect();
        let values = d.arena.values(&pairs);
        let expected = d.arena.eval(&entries, &values).unwrap();
        let got = program.eval(&[&x[0], &x[1], &x[2]]).unwrap();
        for (i, (e, g)) in expected.iter().zip(&got[0]).enumerate() {
            assert!(
                (e - g).abs() <= 1e-12 * (1.0 + e.abs()),
                "entry {i}: {e} vs {g}"
            );
        }
    }
}
