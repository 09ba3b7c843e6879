//! The link wrench matrix A(omega, omegadot, vdot, g) of `robid_runtime::wrench`
//! (docs/dynamics.md#link-wrench-matrix), checked against the Newton-Euler equations written
//! at the centre of mass, a different formula path: random mass, centre of mass and inertia
//! about the centre of mass, turned into the ten standard values by the parallel-axis
//! theorem, and random link states.

use robid_runtime::feasible::LinkInertial;
use robid_runtime::rng::Rng;
use robid_runtime::wrench::{apply, wrench_matrix};

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn mul(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

fn vector(rng: &mut Rng, scale: f64) -> [f64; 3] {
    [0; 3].map(|_| rng.uniform(-scale, scale))
}

/// A random physical link: inertia about the centre of mass R diag(d) R' with principal
/// moments from random point-mass distributions (so the triangle inequalities hold).
fn link(rng: &mut Rng) -> LinkInertial {
    let mass = rng.uniform(0.1, 10.0);
    let s = [0; 3].map(|_| rng.uniform(0.0, 0.05) * mass);
    let d = [s[1] + s[2], s[0] + s[2], s[0] + s[1]];
    // A rotation from a random unit quaternion.
    let q = {
        let v = [0; 4].map(|_| rng.normal());
        let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        v.map(|x| x / n)
    };
    let (w, x, y, z) = (q[0], q[1], q[2], q[3]);
    let r = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    let mut inertia = [[0.0; 3]; 3];
    for (i, row) in inertia.iter_mut().enumerate() {
        for (k, v) in row.iter_mut().enumerate() {
            *v = (0..3).map(|j| r[i][j] * d[j] * r[k][j]).sum();
        }
    }
    LinkInertial {
        mass,
        com: vector(rng, 0.3),
        inertia,
    }
}

/// Newton-Euler at the centre of mass, moved to the frame origin: F = m a_c,
/// N_O = I_c wd + w x (I_c w) + c x F.
fn newton_euler(
    l: &LinkInertial,
    w: [f64; 3],
    wd: [f64; 3],
    vd: [f64; 3],
    g: [f64; 3],
) -> [f64; 6] {
    let c = l.com;
    let a0 = [vd[0] - g[0], vd[1] - g[1], vd[2] - g[2]];
    let ac = add(add(a0, cross(wd, c)), cross(w, cross(w, c)));
    let f = ac.map(|x| l.mass * x);
    let n = add(
        add(mul(&l.inertia, wd), cross(w, mul(&l.inertia, w))),
        cross(c, f),
    );
    [f[0], f[1], f[2], n[0], n[1], n[2]]
}

#[test]
fn wrench_matrix_agrees_with_newton_euler_at_the_centre_of_mass() {
    let mut rng = Rng::new(17);
    let mut worst = 0.0f64;
    for _ in 0..1000 {
        let l = link(&mut rng);
        let (w, wd, vd) = (
            vector(&mut rng, 3.0),
            vector(&mut rng, 20.0),
            vector(&mut rng, 10.0),
        );
        let g = vector(&mut rng, 9.81);
        let a = wrench_matrix(&w, &wd, &vd, &g);
        let from_matrix = apply(&a, &l.to_standard());
        let direct = newton_euler(&l, w, wd, vd, g);
        for (x, y) in from_matrix.iter().zip(&direct) {
            let err = (x - y).abs() / (1.0 + y.abs());
            worst = worst.max(err);
        }
    }
    println!("largest relative difference from Newton-Euler at the centre of mass: {worst:e}");
    // Measured: 7.4e-15 at most (rounding only).
    assert!(worst < 1e-12, "largest relative difference {worst:e}");
}

#[test]
fn wrench_matrix_is_linear_in_the_parameters() {
    let mut rng = Rng::new(18);
    for _ in 0..200 {
        let a = wrench_matrix(
            &vector(&mut rng, 3.0),
            &vector(&mut rng, 20.0),
            &vector(&mut rng, 10.0),
            &vector(&mut rng, 9.81),
        );
        // Any ten numbers (not only physical ones): A is a plain matrix.
        let p1 = [0; 10].map(|_| rng.uniform(-2.0, 2.0));
        let p2 = [0; 10].map(|_| rng.uniform(-2.0, 2.0));
        let sum: [f64; 10] = std::array::from_fn(|k| p1[k] + p2[k]);
        let (w1, w2, w12) = (apply(&a, &p1), apply(&a, &p2), apply(&a, &sum));
        for r in 0..6 {
            assert!(
                (w12[r] - w1[r] - w2[r]).abs() <= 1e-12 * (1.0 + w12[r].abs()),
                "row {r}: {} vs {}",
                w12[r],
                w1[r] + w2[r]
            );
        }
    }
}

#[test]
fn wrench_of_a_resting_link_is_its_weight() {
    // At rest the link needs only its weight held up and the moment of that weight.
    let l = LinkInertial {
        mass: 3.0,
        com: [0.1, 0.2, 0.3],
        inertia: [[0.01, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.03]],
    };
    let g = [0.0, 0.0, -9.81];
    let w = apply(
        &wrench_matrix(&[0.0; 3], &[0.0; 3], &[0.0; 3], &g),
        &l.to_standard(),
    );
    let weight = [0.0, 0.0, 3.0 * 9.81];
    let moment = cross(l.com, weight);
    for r in 0..3 {
        assert!((w[r] - weight[r]).abs() < 1e-12);
        assert!((w[3 + r] - moment[r]).abs() < 1e-12);
    }
}
