//! Property test: for random DH tables (joint types, twists in {0, +-pi/2,
//! random}, lengths, gravity direction) the number of base parameters equals
//! the numeric rank of the full regressor, and Y_b K p = Y p.

use crate::common::random_state;
use proptest::prelude::*;
use robid_core::rng::Rng;
use robid_symbolic::robot::Geometry;
use robid_symbolic::robot::bounds::MIN_GRAVITY;
use robid_symbolic::{Convention, Derivation, Drive, Joint, JointKind, Robot};

fn random_robot(seed: u64) -> Robot {
    let mut rng = Rng::from_state(seed);
    let dof = 2 + rng.below(4);
    let joints = (0..dof)
        .map(|_| {
            let alpha = match rng.below(4) {
                0 => "0".to_owned(),
                1 => "pi/2".to_owned(),
                2 => "-pi/2".to_owned(),
                _ => format!("{:.3}", rng.uniform(-3.0, 3.0)),
            };
            let length = |rng: &mut Rng| {
                if rng.below(3) == 0 {
                    0.0
                } else {
                    (rng.uniform(-0.5, 0.5) * 1000.0).round() / 1000.0
                }
            };
            let mut j = Joint::revolute(&alpha, length(&mut rng), length(&mut rng), "0").unwrap();
            if rng.below(4) == 0 {
                j.kind = JointKind::Prismatic;
                j.theta = Geometry::text(["0", "pi/2", "-pi/2"][rng.below(3)]).unwrap();
            }
            j.drive = [Drive::NONE, Drive::ALL][rng.below(2)];
            j
        })
        .collect();
    let convention = if rng.below(2) == 0 {
        Convention::Modified
    } else {
        Convention::Standard
    };
    let gravity = if rng.below(2) == 0 {
        [0.0, 0.0, -9.81]
    } else {
        // A component closer to zero than robid accepts is zero.
        [
            rng.uniform(-5.0, 5.0),
            rng.uniform(-5.0, 5.0),
            rng.uniform(-9.0, -1.0),
        ]
        .map(|g| if g.abs() < MIN_GRAVITY { 0.0 } else { g })
    };
    Robot::new("random", convention, None, joints)
        .unwrap()
        .with_gravity(gravity)
        .unwrap()
}

fn check(seed: u64) {
    let robot = random_robot(seed);
    let mut d = Derivation::new(&robot);
    let y = d.regressor();
    let b = d.base_parameters().unwrap();
    let k = b.k_matrix(&mut d.arena);
    let n = robot.dof();
    let mut rng = Rng::from_state(seed ^ 0xABCD);
    let ns = b.standard.len();
    let p: Vec<f64> = (0..ns).map(|_| rng.uniform(-1.0, 1.0)).collect();
    let mut full_rows: Vec<f64> = Vec::new();
    let states = ns / n + 10;
    for _ in 0..states {
        let values = random_state(&mut d.arena, n, &[], &mut rng);
        let yv = d.arena.eval(&y.entries(), &values).unwrap();
        let ybv = d.arena.eval(&b.columns.concat(), &values).unwrap();
        let kv = d.arena.eval(&k.concat(), &values).unwrap();
        let beta: Vec<f64> = (0..b.base.len())
            .map(|i| (0..ns).map(|s| kv[i * ns + s] * p[s]).sum())
            .collect();
        for j in 0..n {
            let full: f64 = (0..ns).map(|s| yv[s * n + j] * p[s]).sum();
            let base: f64 = (0..beta.len()).map(|i| ybv[i * n + j] * beta[i]).sum();
            assert!(
                (full - base).abs() <= 1e-8 * (1.0 + full.abs()),
                "seed {seed}: {full} vs {base}"
            );
            full_rows.extend((0..ns).map(|s| yv[s * n + j]));
        }
    }
    let m = nalgebra::DMatrix::from_row_slice(states * n, ns, &full_rows);
    let sv = m.singular_values();
    let largest = sv.max();
    let rank = sv.iter().filter(|&&s| s > 1e-9 * largest).count();
    assert_eq!(b.base.len(), rank, "seed {seed}: {robot:?}");
}

proptest! {
    #![proptest_config(crate::common::proptest_config(40))]
    #[test]
    fn base_count_equals_numeric_rank(seed in any::<u64>()) {
        check(seed);
    }
}
