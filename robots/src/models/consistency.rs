//! The compiled models against the interpreter and the symbolic derivation,
//! at random states, for every reference robot:
//! emitted code == interpreted program for every program of the table, and
//! == `Arena::eval` for the regressor;
//! inverse dynamics == Y_b * base; M is symmetric and M qdd == tau(q, qd, qdd) - tau(q, qd, 0);
//! `f32` within `f32` tolerance. Gravity and Coriolis vectors are checked on their own
//! against an independent RNEA in `tests/tests/suite/emitted_vs_rnea.rs`.

use super::{Lwr4, Panda, Puma560, Rx90, Stanford, Tx40, Ur5e};
use robid_runtime::Model;
use robid_runtime::rng::Rng;
use robid_symbolic::Robot;
use robid_symbolic::program::RobotPrograms;

fn close(a: &[f64], b: &[f64], tol: f64, what: &str) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    let scale = b.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert!((x - y).abs() <= tol * scale, "{what}[{i}]: {x} vs {y}");
    }
}

fn with_geometry<'a>(mut inputs: Vec<&'a [f64]>, geometry: &'a [f64]) -> Vec<&'a [f64]> {
    if !geometry.is_empty() {
        inputs.push(geometry);
    }
    inputs
}

fn random(rng: &mut Rng, n: usize, range: f64) -> Vec<f64> {
    (0..n).map(|_| rng.uniform(-range, range)).collect()
}

/// Checks one compiled reference model against its description.
fn check(name: &str, model: &dyn Model) {
    check_file(&format!("descriptions/{name}.toml"), model);
}

/// Checks one compiled model against its description (`path` in the crate).
fn check_file(path: &str, model: &dyn Model) {
    let name = path;
    let path = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    let robot = Robot::from_file(std::path::Path::new(&path)).unwrap();
    let programs = RobotPrograms::derive(&robot).unwrap();
    let geometry: Vec<f64> = robot.symbols().iter().map(|(_, v)| v.unwrap()).collect();
    let n = model.dof();
    let (ns, nb) = (
        model.standard_parameter_count(),
        model.base_parameter_count(),
    );
    let mut rng = Rng::from_state(42);
    for _ in 0..10 {
        let (q, qd, qdd) = (
            random(&mut rng, n, 3.0),
            random(&mut rng, n, 2.0),
            random(&mut rng, n, 4.0),
        );
        let standard = random(&mut rng, ns, 1.0);
        let mut base = vec![0.0; nb];
        model.base_from_standard_into(&standard, &mut base).unwrap();

        // every program of the table: compiled == interpreted
        let sizes = model.sizes();
        for (info, program) in programs.iter() {
            let inputs: Vec<&[f64]> = info
                .inputs
                .iter()
                .map(|a| match a.name {
                    "q" => q.as_slice(),
                    "qd" => qd.as_slice(),
                    "qdd" => qdd.as_slice(),
                    "base" => base.as_slice(),
                    _ => standard.as_slice(),
                })
                .collect();
            let mut compiled = vec![0.0; info.output.size.len(sizes)];
            model.run(info.kind, &inputs, &mut compiled).unwrap();
            let interpreted = program.eval(&with_geometry(inputs, &geometry)).unwrap();
            close(&compiled, &interpreted[0], 1e-12, info.name);
        }

        // Y * standard == Y_b * base == inverse dynamics
        let mut y = vec![0.0; n * ns];
        model
            .standard_regressor_into(&q, &qd, &qdd, &mut y)
            .unwrap();
        let mut yb = vec![0.0; n * nb];
        model.base_regressor_into(&q, &qd, &qdd, &mut yb).unwrap();
        let product = |m: &[f64], p: &[f64]| -> Vec<f64> {
            (0..n)
                .map(|j| (0..p.len()).map(|k| m[j * p.len() + k] * p[k]).sum())
                .collect()
        };
        let tau_standard = product(&y, &standard);
        let tau_base = product(&yb, &base);
        close(&tau_base, &tau_standard, 1e-9, "Y_b base vs Y standard");
        let mut tau = vec![0.0; n];
        model
            .inverse_dynamics_into(&q, &qd, &qdd, &base, &mut tau)
            .unwrap();
        close(&tau, &tau_base, 1e-9, "inverse_dynamics vs Y_b base");

        // M qdd == tau(q, qd, qdd) - tau(q, qd, 0): every term but the inertial one cancels
        let mut m = vec![0.0; n * n];
        model.mass_matrix_into(&q, &base, &mut m).unwrap();
        let zero = vec![0.0; n];
        let mut tau_v = vec![0.0; n];
        model
            .inverse_dynamics_into(&q, &qd, &zero, &base, &mut tau_v)
            .unwrap();
        for j in 0..n {
            for k in 0..n {
                assert!(
                    (m[j * n + k] - m[k * n + j]).abs() <= 1e-12 * (1.0 + m[j * n + k].abs()),
                    "M symmetric"
                );
            }
            let mq: f64 = (0..n).map(|k| m[j * n + k] * qdd[k]).sum();
            assert!(
                (mq - (tau[j] - tau_v[j])).abs() <= 1e-9 * (1.0 + tau[j].abs()),
                "{name}: M qdd != tau(q, qd, qdd) - tau(q, qd, 0) at {j}"
            );
        }
        let mut g = vec![0.0; n];
        model.gravity_into(&q, &base, &mut g).unwrap();
        let mut g_id = vec![0.0; n];
        model
            .inverse_dynamics_into(&q, &zero, &zero, &base, &mut g_id)
            .unwrap();
        // With qd = 0 only gravity and the offsets Fo remain (sign(0) = 0 for Fc).
        for (j, gj) in g.iter_mut().enumerate() {
            let fo =
                (0..nb).find(|&b| model.base_parameter_name(b) == Some(&format!("Fo{}", j + 1)));
            *gj += fo.map_or(0.0, |b| base[b]);
        }
        close(
            &g,
            &g_id,
            1e-9,
            "gravity (+ offsets) vs inverse dynamics at rest",
        );
    }
}

/// Every generated function of `$ty` run with `Lanes<3>` (three argument sets side by
/// side, the second with zero velocities so that Coulomb friction's sign(0) is taken)
/// gives each lane what the `f64` function gives that lane's arguments, to the bit.
macro_rules! lanes_equal_f64 {
    ($model:expr, $ty:ty) => {{
        use robid_runtime::lanes::Lanes;
        const N: usize = <$ty>::DOF;
        const NB: usize = <$ty>::BASE_PARAMETERS;
        const NS: usize = <$ty>::STANDARD_PARAMETERS;
        let m = $model;
        let mut rng = Rng::from_state(7);
        let mut sets = |n: usize, scale: f64, zero: bool| -> [Vec<f64>; 3] {
            core::array::from_fn(|l| {
                let v = random(&mut rng, n, scale);
                if zero && l == 1 { vec![0.0; n] } else { v }
            })
        };
        let wide = |v: &[Vec<f64>; 3]| -> Vec<Lanes<3>> {
            (0..v[0].len())
                .map(|i| Lanes([v[0][i], v[1][i], v[2][i]]))
                .collect()
        };
        let (q, qd, qdd) = (sets(N, 3.0, false), sets(N, 2.0, true), sets(N, 4.0, false));
        let (base, standard) = (sets(NB, 1.0, false), sets(NS, 1.0, false));
        let (wq, wqd, wqdd, wb, ws) = (
            wide(&q),
            wide(&qd),
            wide(&qdd),
            wide(&base),
            wide(&standard),
        );
        let a = |v: &Vec<Lanes<3>>| v.clone();
        for l in 0..3 {
            let f = |v: &[Vec<f64>; 3]| v[l].clone();
            let outputs: [(&str, Vec<f64>, Vec<Lanes<3>>); 7] = [
                (
                    "standard_regressor",
                    m.standard_regressor(
                        &f(&q).try_into().unwrap(),
                        &f(&qd).try_into().unwrap(),
                        &f(&qdd).try_into().unwrap(),
                    )
                    .to_vec(),
                    m.standard_regressor(
                        &a(&wq).try_into().unwrap(),
                        &a(&wqd).try_into().unwrap(),
                        &a(&wqdd).try_into().unwrap(),
                    )
                    .to_vec(),
                ),
                (
                    "base_regressor",
                    m.base_regressor(
                        &f(&q).try_into().unwrap(),
                        &f(&qd).try_into().unwrap(),
                        &f(&qdd).try_into().unwrap(),
                    )
                    .to_vec(),
                    m.base_regressor(
                        &a(&wq).try_into().unwrap(),
                        &a(&wqd).try_into().unwrap(),
                        &a(&wqdd).try_into().unwrap(),
                    )
                    .to_vec(),
                ),
                (
                    "inverse_dynamics",
                    m.inverse_dynamics(
                        &f(&q).try_into().unwrap(),
                        &f(&qd).try_into().unwrap(),
                        &f(&qdd).try_into().unwrap(),
                        &f(&base).try_into().unwrap(),
                    )
                    .to_vec(),
                    m.inverse_dynamics(
                        &a(&wq).try_into().unwrap(),
                        &a(&wqd).try_into().unwrap(),
                        &a(&wqdd).try_into().unwrap(),
                        &a(&wb).try_into().unwrap(),
                    )
                    .to_vec(),
                ),
                (
                    "mass_matrix",
                    m.mass_matrix(&f(&q).try_into().unwrap(), &f(&base).try_into().unwrap())
                        .to_vec(),
                    m.mass_matrix(&a(&wq).try_into().unwrap(), &a(&wb).try_into().unwrap())
                        .to_vec(),
                ),
                (
                    "gravity",
                    m.gravity(&f(&q).try_into().unwrap(), &f(&base).try_into().unwrap())
                        .to_vec(),
                    m.gravity(&a(&wq).try_into().unwrap(), &a(&wb).try_into().unwrap())
                        .to_vec(),
                ),
                (
                    "coriolis",
                    m.coriolis(
                        &f(&q).try_into().unwrap(),
                        &f(&qd).try_into().unwrap(),
                        &f(&base).try_into().unwrap(),
                    )
                    .to_vec(),
                    m.coriolis(
                        &a(&wq).try_into().unwrap(),
                        &a(&wqd).try_into().unwrap(),
                        &a(&wb).try_into().unwrap(),
                    )
                    .to_vec(),
                ),
                (
                    "base_from_standard",
                    m.base_from_standard(&f(&standard).try_into().unwrap())
                        .to_vec(),
                    m.base_from_standard(&a(&ws).try_into().unwrap()).to_vec(),
                ),
            ];
            for (name, narrow, wide) in outputs {
                assert_eq!(narrow.len(), wide.len());
                for (e, (x, w)) in narrow.iter().zip(&wide).enumerate() {
                    assert_eq!(x.to_bits(), w.0[l].to_bits(), "{name} lane {l} value {e}");
                }
            }
        }
    }};
}

#[test]
fn lanes_equal_f64_ur5e() {
    lanes_equal_f64!(Ur5e, Ur5e);
}

#[test]
fn lanes_equal_f64_panda() {
    lanes_equal_f64!(Panda, Panda);
}

/// An arm with a symbolic twist and length, a prismatic joint and every drive term: the
/// paths of the emitted code that no reference robot reaches (sine and cosine computed as
/// a pair, non-zero constants among the outputs of a matrix).
mod symbolic_drive_arm {
    robid_macros::robot_model!(file = "tests/fixtures/symbolic_drive_arm.toml");
}

#[test]
fn symbolic_drive_arm_agrees_with_its_description() {
    check_file(
        "tests/fixtures/symbolic_drive_arm.toml",
        &symbolic_drive_arm::SymbolicDriveArm::default(),
    );
    lanes_equal_f64!(
        symbolic_drive_arm::SymbolicDriveArm::default(),
        symbolic_drive_arm::SymbolicDriveArm
    );
}

/// Khalil and Kleinfinger's gamma and b written inline (`gamma = ...`, `b = ...` after a
/// joint's DH values), and a base pose: the compiled model equals the interpreted
/// programs of the same robot read from a file, so the macro reads them as the file does
/// (dropping any of them changes the programs).
mod general_frames_arm {
    robid_macros::robot_model! {
        name = "general_frames_arm",
        convention = "modified",
        gravity = [0, 0, -9.81],
        drive = [Ia, Fv],
        base = pose(xyz = [0.1, 0, 0.5], rpy = ["pi/2", 0.3, 0]),
        joints = [
            revolute(0, 0, 0.3, 0),
            revolute("pi/2", 0.1, 0, "pi/2", gamma = "pi/4", b = 0.05),
            prismatic("-pi/2", 0.2, 0.1, 0, b = -0.08),
            revolute(0, 0.25, 0, 0, gamma = 0.3),
        ],
    }
}

#[test]
fn inline_gamma_b_and_base_agree_with_a_description_file() {
    check_file(
        "tests/fixtures/general_frames_arm.toml",
        &general_frames_arm::GeneralFramesArm,
    );
}

/// A calibrated table written inline (`calibrated = true`, twists a few microradians off
/// their right angles): the compiled model equals the interpreted programs of the same
/// table read from a file, so the macro takes the measured twists as the file does
/// (without the key, both refuse them).
mod calibrated_arm {
    robid_macros::robot_model! {
        name = "calibrated_arm",
        convention = "modified",
        calibrated = true,
        gravity = [0, 0, -9.81],
        drive = [Ia, Fv],
        joints = [
            revolute(0, 0, 0.3, 0),
            revolute(1.5707995267948966, 0, 0, 0),
            revolute(4.1e-6, 0.4, 0, 0),
            revolute("-pi/2", 0.05, 0.35, 0),
        ],
    }
}

#[test]
fn inline_calibrated_table_agrees_with_a_description_file() {
    check_file(
        "tests/fixtures/calibrated_arm.toml",
        &calibrated_arm::CalibratedArm,
    );
}

/// The symbolic regressor evaluated by the arena equals the compiled one (UR5e).
#[test]
fn ur5e_regressor_equals_symbolic_evaluation() {
    let path = format!("{}/descriptions/ur5e.toml", env!("CARGO_MANIFEST_DIR"));
    let robot = Robot::from_file(std::path::Path::new(&path)).unwrap();
    let mut d = robid_symbolic::Derivation::new(&robot);
    let entries = d.regressor().entries();
    let mut rng = Rng::from_state(3);
    for _ in 0..5 {
        let (q, qd, qdd) = (
            random(&mut rng, 6, 3.0),
            random(&mut rng, 6, 2.0),
            random(&mut rng, 6, 4.0),
        );
        let names: Vec<String> = ["q", "qd", "qdd"]
            .iter()
            .flat_map(|g| (1..=6).map(move |j| format!("{g}{j}")))
            .collect();
        let pairs: Vec<(&str, f64)> = names
            .iter()
            .enumerate()
            .map(|(k, s)| (s.as_str(), [&q, &qd, &qdd][k / 6][k % 6]))
            .collect();
        let values = d.arena.values(&pairs);
        let columns = d.arena.eval(&entries, &values).unwrap();
        let y = Ur5e.standard_regressor(
            &q.clone().try_into().unwrap(),
            &qd.clone().try_into().unwrap(),
            &qdd.clone().try_into().unwrap(),
        );
        // entries are column-major (parameter, joint); the compiled one is row-major.
        for p in 0..60 {
            for j in 0..6 {
                let (a, b) = (columns[p * 6 + j], y[j * 60 + p]);
                assert!(
                    (a - b).abs() <= 1e-12 * (1.0 + a.abs()),
                    "Y[{j}][{p}]: {a} vs {b}"
                );
            }
        }
    }
}

#[test]
fn ur5e_f32_within_f32_tolerance() {
    let mut rng = Rng::from_state(9);
    for _ in 0..20 {
        let q: [f64; 6] = random(&mut rng, 6, 3.0).try_into().unwrap();
        let qd: [f64; 6] = random(&mut rng, 6, 2.0).try_into().unwrap();
        let qdd: [f64; 6] = random(&mut rng, 6, 4.0).try_into().unwrap();
        let standard: [f64; 60] = random(&mut rng, 60, 1.0).try_into().unwrap();
        let base = Ur5e.base_from_standard(&standard);
        let tau = Ur5e.inverse_dynamics(&q, &qd, &qdd, &base);
        let f = |x: &[f64]| -> Vec<f32> { x.iter().map(|&v| v as f32).collect() };
        let tau32 = Ur5e.inverse_dynamics(
            &f(&q).try_into().unwrap(),
            &f(&qd).try_into().unwrap(),
            &f(&qdd).try_into().unwrap(),
            &f(&base).try_into().unwrap(),
        );
        let scale = tau.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        for j in 0..6 {
            let err = (tau32[j] as f64 - tau[j]).abs();
            assert!(
                err <= 1e-4 * scale,
                "joint {j}: f32 {} vs f64 {}",
                tau32[j],
                tau[j]
            );
        }
    }
}

#[test]
fn ur5e() {
    check("ur5e", &Ur5e);
}

#[test]
fn puma560() {
    check("puma560", &Puma560);
}

#[test]
fn rx90() {
    check("rx90", &Rx90::default());
}

#[test]
fn tx40() {
    check("tx40", &Tx40);
}

#[test]
fn lwr4() {
    check("lwr4", &Lwr4);
}

#[test]
fn panda() {
    check("panda", &Panda);
}

#[test]
fn stanford() {
    check("stanford", &Stanford);
}
