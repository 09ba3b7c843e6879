//! Khalil and Kleinfinger's general frames (gamma, b) and the base transform
//! (docs/conventions.md#khalil-kleinfinger-general-frames,
//! docs/conventions.md#base-and-tool-frames), for random robots with both joint kinds:
//! Newton-Euler equals Lagrange-Euler; the base-parameter count equals the numeric rank of
//! the standard regressor and regrouped torques equal the unregrouped ones; the interpreted
//! customised programs (inverse dynamics, base regressor, mass matrix, gravity, Coriolis)
//! equal the Lagrange-Euler expressions; a wall mount equals a rotated gravity; explicit
//! zeros change nothing; random tables of either convention, with symbols, whose last link
//! is written in its parent's frame, give the Lagrange-Euler model.

use robid_core::ProgramKind;
use robid_core::rng::Rng;
use robid_symbolic::program::{Program, RobotPrograms};
use robid_symbolic::{Arena, Derivation, Drive, Robot, Values};

/// A random modified-DH description with random `gamma`, `b` and `[base]`, 2 to 4 joints:
/// each angle (gamma, alpha, the base's roll, pitch and yaw) a multiple of pi/2 or a
/// number, each length zero or a number, a prismatic joint now and then.
pub(crate) fn random_general(seed: u64) -> String {
    let mut rng = Rng::from_state(seed);
    let angle = |rng: &mut Rng| match rng.below(5) {
        0 => "0".to_owned(),
        1 => "\"pi/2\"".to_owned(),
        2 => "\"-pi/2\"".to_owned(),
        3 => "\"pi\"".to_owned(),
        _ => format!("{:.3}", rng.uniform(-3.0, 3.0)),
    };
    let length = |rng: &mut Rng| {
        if rng.below(3) == 0 {
            "0".to_owned()
        } else {
            format!("{:.3}", rng.uniform(0.05, 0.5) * [-1.0, 1.0][rng.below(2)])
        }
    };
    let drive = ["[]", "[\"Ia\", \"Fv\", \"Fc\", \"Fo\"]"][rng.below(2)];
    let mut text = format!(
        "name = \"general\"\nconvention = \"modified\"\ndrive = {drive}\n\
         gravity = [0, 0, -9.81]\n[base]\nxyz = [{}, {}, {}]\nrpy = [{}, {}, {}]\n",
        length(&mut rng),
        length(&mut rng),
        length(&mut rng),
        angle(&mut rng),
        angle(&mut rng),
        angle(&mut rng)
    );
    let dof = 2 + rng.below(3);
    for _ in 0..dof {
        let kind = if rng.below(4) == 0 {
            "prismatic"
        } else {
            "revolute"
        };
        text += &format!(
            "[[joints]]\ntype = \"{kind}\"\ngamma = {}\nb = {}\nalpha = {}\na = {}\nd = {}\ntheta = {}\n",
            angle(&mut rng),
            length(&mut rng),
            angle(&mut rng),
            length(&mut rng),
            length(&mut rng),
            angle(&mut rng)
        );
    }
    text
}

fn robot(seed: u64) -> Robot {
    let text = random_general(seed);
    Robot::from_toml(&text, "general.toml").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Joint symbols at random values, and standard parameters at `parameters` when given.
fn state(arena: &mut Arena, robot: &Robot, rng: &mut Rng, parameters: Option<&[f64]>) -> Values {
    let mut names = Vec::new();
    for j in 1..=robot.dof() {
        names.push((format!("q{j}"), rng.uniform(-3.0, 3.0)));
        let qd = rng.uniform(0.2, 2.0) * [-1.0, 1.0][rng.below(2)];
        names.push((format!("qd{j}"), qd));
        names.push((format!("qdd{j}"), rng.uniform(-3.0, 3.0)));
    }
    if let Some(p) = parameters {
        for (id, v) in robot.standard_parameters().iter().zip(p) {
            names.push((id.to_string(), *v));
        }
    }
    let pairs: Vec<(&str, f64)> = names.iter().map(|(n, v)| (n.as_str(), *v)).collect();
    arena.values(&pairs)
}

fn close(a: f64, b: f64, what: &str) {
    assert!(
        (a - b).abs() <= 1e-9 * (1.0 + a.abs().max(b.abs())),
        "{what}: {a} vs {b}"
    );
}

/// The rank of `rows` (row-major, `columns` wide) by Gaussian elimination with a relative
/// threshold.
fn rank(mut rows: Vec<Vec<f64>>, columns: usize) -> usize {
    let scale = rows
        .iter()
        .flatten()
        .fold(0.0_f64, |m, x| m.max(x.abs()))
        .max(1.0);
    let mut r = 0;
    for c in 0..columns {
        let Some(pivot) =
            (r..rows.len()).max_by(|&a, &b| rows[a][c].abs().total_cmp(&rows[b][c].abs()))
        else {
            break;
        };
        if rows[pivot][c].abs() <= 1e-9 * scale {
            continue;
        }
        rows.swap(r, pivot);
        let (top, below) = rows.split_at_mut(r + 1);
        let pivot_row = &top[r];
        for row in below {
            let f = row[c] / pivot_row[c];
            for (x, p) in row[c..columns].iter_mut().zip(&pivot_row[c..columns]) {
                *x -= f * p;
            }
        }
        r += 1;
    }
    r
}

/// Newton-Euler and Lagrange-Euler regressors agree.
#[test]
fn newton_euler_equals_lagrange_euler() {
    for seed in 0..12 {
        let robot = robot(seed);
        let mut d = Derivation::new(&robot);
        let ne = d.regressor();
        let le = d.lagrange_regressor();
        let mut roots = ne.entries();
        let count = roots.len();
        roots.extend(le.entries());
        let mut rng = Rng::from_state(seed ^ 0xF4A3);
        for _ in 0..5 {
            let values = state(&mut d.arena, &robot, &mut rng, None);
            let v = d.arena.eval(&roots, &values).unwrap();
            for k in 0..count {
                close(
                    v[k],
                    v[count + k],
                    &format!("seed {seed}, entry {k}: NE vs LE"),
                );
            }
        }
    }
}

/// The base-parameter count is the numeric rank of the standard regressor at random
/// states, and Y_b (K p) = Y p.
#[test]
fn regrouping_is_minimal_and_exact() {
    for seed in 0..12 {
        let robot = robot(seed);
        let mut d = Derivation::new(&robot);
        let y = d.regressor();
        let b = d.base_parameters().unwrap();
        let k = b.k_matrix(&mut d.arena);
        let (n, ns, nb) = (robot.dof(), b.standard.len(), b.base.len());
        let mut rng = Rng::from_state(seed ^ 0x8E6);
        let p: Vec<f64> = (0..ns).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let mut rows = Vec::new();
        for _ in 0..ns / n + 10 {
            let values = state(&mut d.arena, &robot, &mut rng, None);
            let yv = d.arena.eval(&y.entries(), &values).unwrap();
            let ybv = d.arena.eval(&b.columns.concat(), &values).unwrap();
            let kv = d.arena.eval(&k.concat(), &values).unwrap();
            let beta: Vec<f64> = (0..nb)
                .map(|i| (0..ns).map(|s| kv[i * ns + s] * p[s]).sum())
                .collect();
            for j in 0..n {
                let full: f64 = (0..ns).map(|s| yv[s * n + j] * p[s]).sum();
                let based: f64 = (0..nb).map(|i| ybv[i * n + j] * beta[i]).sum();
                close(
                    full,
                    based,
                    &format!("seed {seed}, joint {j}: Y p vs Y_b K p"),
                );
                rows.push((0..ns).map(|s| yv[s * n + j]).collect::<Vec<f64>>());
            }
        }
        assert_eq!(rank(rows, ns), nb, "seed {seed}: rank vs base parameters");
    }
}

/// The inputs of `program` by group name.
fn run(program: &Program, inputs: &[(&str, &[f64])]) -> Vec<f64> {
    let groups: Vec<&[f64]> = program
        .inputs
        .iter()
        .map(|g| {
            inputs
                .iter()
                .find(|(name, _)| *name == g.name)
                .unwrap_or_else(|| panic!("no input {}", g.name))
                .1
        })
        .collect();
    program.eval(&groups).unwrap().remove(0)
}

/// Every customised program of `programs`, interpreted at the state `[q, qd, qdd]` with the
/// standard parameters `p` (and the inputs `extra`, such as run-time geometry), against the
/// Lagrange-Euler values `le`: the torques, the mass matrix row by row, gravity, Coriolis.
fn check_programs(
    programs: &RobotPrograms,
    le: &[f64],
    p: &[f64],
    extra: &[(&str, &[f64])],
    [q, qd, qdd]: [&[f64]; 3],
    what: &dyn Fn(usize, &str) -> String,
) {
    let n = q.len();
    let (tau, rest) = le.split_at(n);
    let (mass, rest) = rest.split_at(n * n);
    let (gravity, coriolis) = rest.split_at(n);
    let mut standard = vec![("standard", p)];
    standard.extend_from_slice(extra);
    let base = run(&programs[ProgramKind::BaseFromStandard], &standard);
    let mut inputs = vec![
        ("q", q),
        ("qd", qd),
        ("qdd", qdd),
        ("base", base.as_slice()),
    ];
    inputs.extend_from_slice(extra);
    let id = run(&programs[ProgramKind::InverseDynamics], &inputs);
    let yb = run(&programs[ProgramKind::BaseRegressor], &inputs);
    let m = run(&programs[ProgramKind::MassMatrix], &inputs);
    let g = run(&programs[ProgramKind::Gravity], &inputs);
    let c = run(&programs[ProgramKind::Coriolis], &inputs);
    let nb = base.len();
    for j in 0..n {
        close(id[j], tau[j], &what(j, "inverse dynamics"));
        let ybb: f64 = (0..nb).map(|k| yb[j * nb + k] * base[k]).sum();
        close(ybb, tau[j], &what(j, "base regressor times base"));
        close(g[j], gravity[j], &what(j, "gravity"));
        close(c[j], coriolis[j], &what(j, "Coriolis"));
        for k in 0..n {
            close(m[j * n + k], mass[j * n + k], &what(j, "mass matrix"));
        }
    }
}

/// The customised programs, interpreted, equal the Lagrange-Euler model. Without the
/// constant offsets Fo: with a prismatic joint along gravity an offset's column is a mass's
/// (docs/regrouping.md#special-geometry), so the gravity program, which leaves the drive
/// terms out, would differ from g(q) by the offset folded into the mass.
#[test]
fn programs_equal_lagrange_euler() {
    for seed in 0..8 {
        let robot = robot(seed).with_drive(Drive {
            fo: false,
            ..Drive::ALL
        });
        let programs = RobotPrograms::derive(&robot).unwrap();
        let mut d = Derivation::new(&robot);
        let symbols = d.parameter_symbols();
        let le = d.lagrange(&symbols);
        let n = robot.dof();
        let mut rng = Rng::from_state(seed ^ 0x1A6);
        for _ in 0..4 {
            let p: Vec<f64> = (0..symbols.len()).map(|_| rng.uniform(-1.0, 1.0)).collect();
            let values = state(&mut d.arena, &robot, &mut rng, Some(&p));
            let mut roots = le.torques.clone();
            roots.extend(le.mass_matrix.iter().flatten());
            roots.extend(&le.gravity);
            roots.extend(&le.coriolis);
            let v = d.arena.eval(&roots, &values).unwrap();
            let mut joint = |name: &str| -> Vec<f64> {
                (1..=n)
                    .map(|j| {
                        let id = d.arena.var(&format!("{name}{j}"));
                        d.arena.eval(&[id], &values).unwrap()[0]
                    })
                    .collect()
            };
            let (q, qd, qdd) = (joint("q"), joint("qd"), joint("qdd"));
            let what = |j: usize, w: &str| format!("seed {seed}, joint {j}: {w}");
            check_programs(&programs, &v, &p, &[], [&q, &qd, &qdd], &what);
        }
    }
}

const TABLE: &str = "[[joints]]\nalpha = 0\n[[joints]]\nalpha = \"pi/2\"\nd = 0.1\n\
                     [[joints]]\na = 0.4\n[[joints]]\ntype = \"prismatic\"\nalpha = \"-pi/2\"\n\
                     a = 0.05\ntheta = \"pi/2\"\n";

/// A robot on a wall (`[base] rpy = ["pi/2", 0, 0]`, gravity [0, 0, -9.81] in the world)
/// is the robot on the floor with gravity R' g = [0, -9.81, 0]: the same base parameters
/// and the same programs, text for text (the angle is exact, so the rotation folds).
#[test]
fn a_wall_mount_is_a_rotated_gravity() {
    let wall = Robot::from_toml(
        &format!(
            "name = \"arm\"\nconvention = \"modified\"\ngravity = [0, 0, -9.81]\n\
             [base]\nxyz = [0.1, 0, 1.2]\nrpy = [\"pi/2\", 0, 0]\n{TABLE}"
        ),
        "wall.toml",
    )
    .unwrap();
    let floor = Robot::from_toml(
        &format!("name = \"arm\"\nconvention = \"modified\"\ngravity = [0, -9.81, 0]\n{TABLE}"),
        "floor.toml",
    )
    .unwrap();
    let (pw, pf) = (
        RobotPrograms::derive(&wall).unwrap(),
        RobotPrograms::derive(&floor).unwrap(),
    );
    assert_eq!(pw.base.len(), pf.base.len());
    for kind in ProgramKind::ALL {
        assert_eq!(pw[kind].to_string(), pf[kind].to_string(), "{kind:?}");
    }
    // the emitted type says how it is mounted
    let emitted = robid_symbolic::emit::emit_programs(&pw).unwrap();
    assert!(
        emitted.contains("base transform (xyz [0.1, 0, 1.2], rpy [pi/2, 0, 0])"),
        "{emitted}"
    );
    let plain = robid_symbolic::emit::emit_programs(&pf).unwrap();
    assert!(!plain.contains("base transform"));
    // and a base turned the other way is another robot
    let mut turned = robid_symbolic::Transform::identity();
    turned.rpy[0] = robid_symbolic::robot::Geometry::text("-pi/2").unwrap();
    let other = wall.clone().with_base(Some(turned));
    let po = RobotPrograms::derive(&other.unwrap()).unwrap();
    assert_ne!(
        po[ProgramKind::Gravity].to_string(),
        pf[ProgramKind::Gravity].to_string()
    );
}

/// A table with `gamma = 0` and `b = 0` written out (and an identity `[base]`) gives the
/// programs of the table without them, text for text.
#[test]
fn explicit_zeros_change_nothing() {
    let plain = Robot::from_toml(
        &format!("name = \"arm\"\nconvention = \"modified\"\n{TABLE}"),
        "plain.toml",
    )
    .unwrap();
    let zeros = TABLE.replace("[[joints]]\n", "[[joints]]\ngamma = 0\nb = 0.0\n");
    let explicit = Robot::from_toml(
        &format!(
            "name = \"arm\"\nconvention = \"modified\"\n[base]\nxyz = [0, 0, 0]\nrpy = [0, 0, 0]\n{zeros}"
        ),
        "explicit.toml",
    )
    .unwrap();
    assert!(explicit.base().is_some());
    let (pp, pe) = (
        RobotPrograms::derive(&plain).unwrap(),
        RobotPrograms::derive(&explicit).unwrap(),
    );
    for kind in ProgramKind::ALL {
        assert_eq!(pp[kind].to_string(), pe[kind].to_string(), "{kind:?}");
        assert_eq!(pp[kind].operations(), pe[kind].operations(), "{kind:?}");
    }
    // the comparison can fail: a gamma that is not zero changes the programs
    let turned = TABLE.replacen("[[joints]]\na = 0.4", "[[joints]]\ngamma = 0.3\na = 0.4", 1);
    let turned = Robot::from_toml(
        &format!("name = \"arm\"\nconvention = \"modified\"\n{turned}"),
        "turned.toml",
    )
    .unwrap();
    let pt = RobotPrograms::derive(&turned).unwrap();
    assert_ne!(
        pt[ProgramKind::InverseDynamics].to_string(),
        pp[ProgramKind::InverseDynamics].to_string()
    );
}

/// `gamma`, `b` and the base angles may be symbols: the base parameters and the programs
/// keep them (a run-time `geometry` input) and equal the Lagrange-Euler model at their
/// values.
#[test]
fn symbolic_gamma_b_and_base() {
    let text = "name = \"arm\"\nconvention = \"modified\"\n[base]\nrpy = [\"tilt\", 0, 0]\n\
                [[joints]]\n[[joints]]\ngamma = \"g2\"\nb = \"b2\"\nalpha = \"pi/2\"\na = 0.2\n\
                [[joints]]\ntype = \"prismatic\"\ngamma = 0.3\nalpha = \"-pi/2\"\na = 0.1\n\
                [symbols]\ntilt = 0.4\ng2 = 0.7\nb2 = 0.15\n";
    let robot = Robot::from_toml(text, "arm.toml").unwrap();
    assert_eq!(robot.symbols().len(), 3);
    let programs = RobotPrograms::derive(&robot).unwrap();
    let geometry: Vec<f64> = robot.symbols().iter().map(|(_, v)| v.unwrap()).collect();
    let mut d = Derivation::new(&robot);
    let symbols = d.parameter_symbols();
    let le = d.lagrange(&symbols);
    let mut rng = Rng::from_state(3);
    let n = robot.dof();
    for _ in 0..4 {
        let p: Vec<f64> = (0..symbols.len()).map(|_| rng.uniform(-1.0, 1.0)).collect();
        let (q, qd, qdd): (Vec<f64>, Vec<f64>, Vec<f64>) = (
            (0..n).map(|_| rng.uniform(-3.0, 3.0)).collect(),
            (0..n).map(|_| rng.uniform(-2.0, 2.0)).collect(),
            (0..n).map(|_| rng.uniform(-3.0, 3.0)).collect(),
        );
        let mut names: Vec<(String, f64)> = Vec::new();
        for j in 0..n {
            names.push((format!("q{}", j + 1), q[j]));
            names.push((format!("qd{}", j + 1), qd[j]));
            names.push((format!("qdd{}", j + 1), qdd[j]));
        }
        for (id, v) in robot.standard_parameters().iter().zip(&p) {
            names.push((id.to_string(), *v));
        }
        for (s, v) in robot.symbols() {
            names.push((s.clone(), v.unwrap()));
        }
        let pairs: Vec<(&str, f64)> = names.iter().map(|(s, v)| (s.as_str(), *v)).collect();
        let values = d.arena.values(&pairs);
        let tau = d.arena.eval(&le.torques, &values).unwrap();
        let base = run(
            &programs[ProgramKind::BaseFromStandard],
            &[("standard", &p), ("geometry", &geometry)],
        );
        let inputs: [(&str, &[f64]); 5] = [
            ("q", &q),
            ("qd", &qd),
            ("qdd", &qdd),
            ("base", &base),
            ("geometry", &geometry),
        ];
        let id = run(&programs[ProgramKind::InverseDynamics], &inputs);
        for j in 0..n {
            close(id[j], tau[j], &format!("joint {j}: inverse dynamics"));
        }
    }
}

/// A random table of 2 or 3 joints in either convention whose last joint is revolute about
/// a coordinate axis of its parent's frame (the case where the customised Newton-Euler
/// writes the last link in its parent's frame and takes entries of its `U` from the
/// parent's, docs/dynamics.md#customised-newton-euler), the joint before it prismatic now
/// and then, lengths numbers or symbols, every drive term but `Fo`.
fn random_tip(seed: u64) -> String {
    let mut rng = Rng::from_state(seed);
    let convention = ["modified", "standard"][rng.below(2)];
    let quarter = |rng: &mut Rng| ["0", "\"pi/2\"", "\"-pi/2\"", "\"pi\""][rng.below(4)];
    let mut symbols = String::new();
    let mut length = |rng: &mut Rng, name: String| match rng.below(3) {
        0 => "0".to_owned(),
        1 => format!("{:.3}", rng.uniform(-0.5, 0.5)),
        _ => {
            symbols += &format!("{name} = {:.3}\n", rng.uniform(0.2, 0.8));
            format!("\"{name}\"")
        }
    };
    let dof = 2 + rng.below(2);
    let mut rows = String::new();
    for j in 1..=dof {
        let kind = if j + 1 == dof && rng.below(2) == 0 {
            "prismatic"
        } else {
            "revolute"
        };
        let alpha = if j == dof || rng.below(2) == 0 {
            quarter(&mut rng).to_owned()
        } else {
            format!("{:.3}", rng.uniform(-3.0, 3.0))
        };
        let (a, d) = (
            length(&mut rng, format!("A{j}")),
            length(&mut rng, format!("D{j}")),
        );
        let theta = quarter(&mut rng);
        rows += &format!(
            "[[joints]]\ntype = \"{kind}\"\nalpha = {alpha}\na = {a}\nd = {d}\ntheta = {theta}\n"
        );
    }
    format!(
        "name = \"tip\"\nconvention = \"{convention}\"\ndrive = [\"Ia\", \"Fv\", \"Fc\"]\n\
         gravity = [0.5, -1.0, -9.81]\n{rows}[symbols]\n{symbols}"
    )
}

/// The interpreted programs of [`random_tip`] robots equal the Lagrange-Euler model.
#[test]
fn last_links_in_their_parents_frame_equal_lagrange_euler() {
    for seed in 0..40 {
        let text = random_tip(seed);
        let robot = Robot::from_toml(&text, "tip.toml").unwrap_or_else(|e| panic!("{e}\n{text}"));
        let programs = RobotPrograms::derive(&robot).unwrap();
        let geometry: Vec<f64> = robot.symbols().iter().map(|(_, v)| v.unwrap()).collect();
        let mut d = Derivation::new(&robot);
        let symbols = d.parameter_symbols();
        let le = d.lagrange(&symbols);
        let n = robot.dof();
        let mut rng = Rng::from_state(seed ^ 0x71B);
        for _ in 0..3 {
            let p: Vec<f64> = (0..symbols.len()).map(|_| rng.uniform(-1.0, 1.0)).collect();
            let mut names: Vec<(String, f64)> = Vec::new();
            let (mut q, mut qd, mut qdd) = (Vec::new(), Vec::new(), Vec::new());
            for j in 1..=n {
                q.push(rng.uniform(-3.0, 3.0));
                qd.push(rng.uniform(0.2, 2.0) * [-1.0, 1.0][rng.below(2)]);
                qdd.push(rng.uniform(-3.0, 3.0));
                names.push((format!("q{j}"), q[j - 1]));
                names.push((format!("qd{j}"), qd[j - 1]));
                names.push((format!("qdd{j}"), qdd[j - 1]));
            }
            for (id, v) in robot.standard_parameters().iter().zip(&p) {
                names.push((id.to_string(), *v));
            }
            for (s, v) in robot.symbols() {
                names.push((s.clone(), v.unwrap()));
            }
            let pairs: Vec<(&str, f64)> = names.iter().map(|(s, v)| (s.as_str(), *v)).collect();
            let values = d.arena.values(&pairs);
            let mut roots = le.torques.clone();
            roots.extend(le.mass_matrix.iter().flatten());
            roots.extend(&le.gravity);
            roots.extend(&le.coriolis);
            let v = d.arena.eval(&roots, &values).unwrap();
            let what = |j: usize, w: &str| format!("seed {seed}, joint {j}: {w}\n{text}");
            let geometry = [("geometry", geometry.as_slice())];
            check_programs(&programs, &v, &p, &geometry, [&q, &qd, &qdd], &what);
        }
    }
}
