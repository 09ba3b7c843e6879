//! The KUKA LWR IV+ of Gaz, Flacco, De Luca, "Extracting feasible robot parameters from
//! dynamic coefficients using nonlinear optimization methods", IEEE ICRA 2016 (issue 17,
//! items 2 and 3; docs/experiments.md#two-step-extraction): the paper's symbolic gravity
//! coefficients (eq. 8) against robid's, its numbers (eq. 12, Table II), and the two-step
//! extraction inside its boxes (Tables I and III, eqs. 15 and 18).
//!
//! The description `robots/tests/fixtures/lwr4_gaz2016.toml` is the paper's frames (Fig. 2:
//! only d1 = 0.4 m and d2 = 0.39 m); robid's base parameters of the gravity part then equal
//! the paper's coefficients up to sign ([`PAPER_TO_ROBID`]), which the first test checks at
//! random parameters.

use std::path::PathBuf;
use std::time::Instant;

use robid_runtime::Model;
use robid_runtime::feasible::{
    AnnealOptions, Bounds, GravityCoefficients, LinkInertial, Problem, Quantity, TENSOR_ELEMENTS,
    pseudo_inertia_min_eigenvalue, solve_gravity_step, solve_two_step,
};
use robid_runtime::pipeline::{StaticKind, identify_static};
use robid_runtime::rng::Rng;
use robid_symbolic::{Drive, Robot};
use robots::interpreted::Interpreted;

fn fixture(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../robots/tests/fixtures")
        .join(name)
}

/// The paper's two lengths (Sec. III, p. 3), m.
const D1: f64 = 0.4;
const D2: f64 = 0.39;

/// Gaz et al. 2016, Table II (p. 4), "final solution for gravity parameters", as printed:
/// masses m1..m7 (kg) and centres of mass c_ix, c_iy, c_iz (m) in the DH frame of link i.
/// The paper's don't-care values (m1, c1x, c1y, c1z, c2y, printed `*`) are taken from its
/// Table I's V-REP column (p. 3): they do not enter the gravity coefficients.
const MASS: [f64; 7] = [
    2.7, // V-REP (don't care)
    4.2996847737,
    3.658530333,
    2.3846673548,
    1.7035567183,
    0.4000713156,
    0.6501439811,
];
const COM: [[f64; 3]; 7] = [
    [0.001340, -0.087777, -0.026220],        // V-REP (don't care)
    [0.0003284751, -0.026220, 0.0823647642], // c2y: V-REP (don't care)
    [0.0002593328, 0.1137431845, -0.000100257],
    [-0.0014648843, -0.0000461, 0.148580959],
    [-0.0003791484, -0.0553526131, -0.0101255137],
    [0.0020739022, 0.0586184696, -0.044799983],
    [-0.0004601303, 0.0014789221, 0.0715608282],
];

/// Gaz et al. 2016, eq. 12 (p. 3): the identified gravity coefficients, m kg, as printed.
const PI_HAT: [f64; 12] = [
    9.5457e-4, -2.9826e-4, 8.3524e-4, 0.0286, -0.0407, -6.5637e-4, 1.334, -0.0035, -4.7258e-4,
    0.0014, 9.4532e-4, 3.4568,
];

/// The paper's coefficient k (eq. 8 order) is `sign * ` robid's gravity coefficient `name`.
const PAPER_TO_ROBID: [(&str, f64); 12] = [
    ("MY7", 1.0),
    ("MX7", 1.0),
    ("MX6", 1.0),
    ("MYR6", 1.0),
    ("MYR5", -1.0),
    ("MX5", 1.0),
    ("MYR4", -1.0),
    ("MX4", 1.0),
    ("MYR3", 1.0),
    ("MX2", 1.0),
    ("MX3", 1.0),
    ("MYR2", 1.0),
];

/// Gaz et al. 2016, eq. 8 (p. 2), typed in: the gravity coefficients in the masses m[i]
/// and centres of mass c[i] (index 0 = link 1).
fn eq8(m: &[f64; 7], c: &[[f64; 3]; 7]) -> [f64; 12] {
    let (x, y, z) = (0, 1, 2);
    [
        c[6][y] * m[6],
        c[6][x] * m[6],
        c[5][x] * m[5],
        c[5][z] * m[5] + c[6][z] * m[6],
        c[4][z] * m[4] - c[5][y] * m[5],
        c[4][x] * m[4],
        c[4][y] * m[4] + c[3][z] * m[3] + D2 * (m[4] + m[5] + m[6]),
        c[3][x] * m[3],
        c[3][y] * m[3] + c[2][z] * m[2],
        c[1][x] * m[1],
        c[2][x] * m[2],
        c[1][z] * m[1] - c[2][y] * m[2] + D1 * (m[2] + m[3] + m[4] + m[5] + m[6]),
    ]
}

struct Lwr {
    model: Interpreted,
    full: Problem,
    gravity: GravityCoefficients,
}

fn lwr() -> Lwr {
    let robot = Robot::from_file(&fixture("lwr4_gaz2016.toml"))
        .unwrap()
        .with_drive(Drive::NONE);
    let model = Interpreted::new(&robot).unwrap();
    let full = Problem::from_model(&model).unwrap();
    let gravity = GravityCoefficients::of_model(&model).unwrap();
    Lwr {
        model,
        full,
        gravity,
    }
}

impl Lwr {
    /// The standard vector of per-link masses, centres of mass and inertias about them.
    fn standard(&self, m: &[f64; 7], c: &[[f64; 3]; 7], inertia: &[[[f64; 3]; 3]; 7]) -> Vec<f64> {
        let mut p = vec![0.0; self.full.standard_names.len()];
        for j in 0..7 {
            let link = LinkInertial {
                mass: m[j],
                com: c[j],
                inertia: inertia[j],
            };
            for (&i, v) in self.full.layout.links[j].iter().zip(link.to_standard()) {
                p[i] = v;
            }
        }
        p
    }

    /// robid's gravity coefficients of a standard vector, in the paper's order and signs.
    fn paper_coefficients(&self, standard: &[f64]) -> [f64; 12] {
        let base: Vec<f64> = self.full.base_of(standard).iter().copied().collect();
        let values = self.gravity.values(&base).unwrap();
        PAPER_TO_ROBID.map(|(name, sign)| {
            let i = self.gravity.names.iter().position(|n| n == name).unwrap();
            sign * values[i]
        })
    }
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn gaz_lwr_gravity_coefficients_match_table_ii() {
    let lwr = lwr();
    // twelve coefficients, as the paper's pruning found (Sec. II-C)
    assert_eq!(lwr.gravity.names.len(), 12, "{:?}", lwr.gravity.names);
    assert_eq!(lwr.model.base_parameter_count(), lwr.full.base_names.len());
    // eq. 8 and robid's coefficients agree as functions: at random masses, centres of mass
    // and inertias (rounding only: sums of a few terms of order 1)
    let mut rng = Rng::new(2016);
    for _ in 0..20 {
        let m: [f64; 7] = std::array::from_fn(|_| rng.uniform(0.5, 6.0));
        let c: [[f64; 3]; 7] =
            std::array::from_fn(|_| std::array::from_fn(|_| rng.uniform(-0.2, 0.2)));
        let inertia: [[[f64; 3]; 3]; 7] = std::array::from_fn(|_| {
            let (a, b) = (rng.uniform(0.01, 0.05), rng.uniform(-0.005, 0.005));
            [[a, b, 0.0], [b, a, 0.0], [0.0, 0.0, a]]
        });
        let p = lwr.standard(&m, &c, &inertia);
        let d = max_difference(&lwr.paper_coefficients(&p), &eq8(&m, &c));
        assert!(d < 1e-12, "eq. 8 and robid differ by {d}");
    }
    // Table II in eq. 8 against eq. 12: the paper's Table II is its own (inexact) solution,
    // so the agreement is to its residual, not to every printed digit; measured: largest
    // difference 1.23e-5 m kg (coefficient 10, c2x m2: 1.41234e-3 against 1.4e-3 printed
    // with one significant digit), sum of squares 5.1e-10 (the paper reports a cost of
    // 3.2073e-4 for Table II, which we cannot reproduce from eqs. 8, 12 and Table II).
    let zero = [[[0.0; 3]; 3]; 7];
    let p = lwr.standard(&MASS, &COM, &zero);
    let ours = lwr.paper_coefficients(&p);
    assert!(max_difference(&ours, &eq8(&MASS, &COM)) < 1e-12);
    let d = max_difference(&ours, &PI_HAT);
    assert!(d < 2.5e-5, "Table II reproduces eq. 12 to {d}: {ours:?}");
    // the two large coefficients (the d1, d2 terms) to their printed digits
    assert!((ours[6] - 1.334).abs() < 0.5e-3, "{}", ours[6]);
    assert!((ours[11] - 3.4568).abs() < 0.5e-4, "{}", ours[11]);
}

/// The torques at rest (gravity, and a drive's offset) of random base parameters at random
/// poses, and the same from the
/// kept columns of the base regressor at rest times the coefficients: their largest
/// difference relative to the largest torque.
fn gravity_through_coefficients(model: &dyn Model, g: &GravityCoefficients, seed: u64) -> f64 {
    let (n, nb) = (model.dof(), model.base_parameter_count());
    let mut rng = Rng::new(seed);
    let (mut worst, mut largest) = (0.0f64, 0.0f64);
    for _ in 0..10 {
        let q: Vec<f64> = (0..n).map(|_| rng.uniform(-3.0, 3.0)).collect();
        let beta: Vec<f64> = (0..nb).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let mut tau = vec![0.0; n];
        let zero = vec![0.0; n];
        model
            .inverse_dynamics_into(&q, &zero, &zero, &beta, &mut tau)
            .unwrap();
        let mut y = vec![0.0; n * nb];
        model.base_regressor_into(&q, &zero, &zero, &mut y).unwrap();
        let coefficients = g.values(&beta).unwrap();
        for i in 0..n {
            let through: f64 = g
                .kept
                .iter()
                .zip(&coefficients)
                .map(|(&b, c)| y[i * nb + b] * c)
                .sum();
            worst = worst.max((through - tau[i]).abs());
            largest = largest.max(tau[i].abs());
        }
    }
    worst / largest
}

#[test]
fn gaz_gravity_coefficients_reproduce_the_gravity_torques() {
    // the LWR: twelve independent columns, nothing folded; rounding only
    // (measured 1.4e-16 relative)
    let lwr = lwr();
    let d = gravity_through_coefficients(&lwr.model, &lwr.gravity, 3);
    assert!(d < 1e-13, "LWR: {d}");
    // the gravity problem carries the identified values and their deviations over: here
    // G selects, so each coefficient keeps its base parameter's value and deviation (the
    // deviation up to the variance floor of Problem::with_covariance, applied twice:
    // at most (1e-5 * 2 + 1e-8 * 2)^2 / (2 * 0.05^2) = 4e-8 relative; measured 3.1e-8)
    let mut rng = Rng::new(5);
    let nb = lwr.full.base_names.len();
    let beta: Vec<f64> = (0..nb).map(|_| rng.uniform(-2.0, 2.0)).collect();
    let std: Vec<f64> = (0..nb).map(|_| rng.uniform(0.05, 0.2)).collect();
    let full = lwr.full.clone().with_target(&beta, &std).unwrap();
    let gp = lwr.gravity.problem(&full).unwrap();
    let mut worst = 0.0f64;
    for (i, &b) in lwr.gravity.kept.iter().enumerate() {
        assert_eq!(gp.target[i], beta[b]);
        worst = worst.max((gp.std[i] / full.std[b] - 1.0).abs());
    }
    assert!(worst < 4e-8, "deviations carried over to {worst} relative");
    // one vertical prismatic joint with a torque offset: the mass's column (9.81) and the
    // offset's (1) are dependent at rest, so one coefficient folds both,
    // M1 + Fo1 / 9.81 (measured 2.3e-16 relative)
    let text = "name = \"lift\"\nconvention = \"modified\"\ngravity = [0, 0, -9.81]\n\
                [[joints]]\ntype = \"prismatic\"\nalpha = 0\na = 0\ntheta = 0\n\
                limits = { position = [-1, 1], velocity = 1, torque = 100 }\n";
    let drive = Drive {
        fo: true,
        ..Drive::NONE
    };
    let robot = Robot::from_toml(text, "lift.toml")
        .unwrap()
        .with_drive(drive);
    let model = Interpreted::new(&robot).unwrap();
    let g = GravityCoefficients::of_model(&model).unwrap();
    let names: Vec<&str> = (0..model.base_parameter_count())
        .map(|b| model.base_parameter_name(b).unwrap())
        .collect();
    assert_eq!(g.names.len(), 1, "{names:?} -> {:?}", g.names);
    assert_eq!(g.map.shape(), (1, 2));
    let fold = g.map[(0, 1)] / g.map[(0, 0)];
    assert!((fold - 1.0 / 9.81).abs() < 1e-12, "{names:?}: {}", g.map);
    let d = gravity_through_coefficients(&model, &g, 4);
    assert!(d < 1e-13, "lift: {d}");
}

/// Gaz et al. 2016, eq. 15 (p. 3).
const EQ15: [&str; 2] = ["I7xz = c7x * c7z * m7", "I7yz = c7y * c7z * m7"];

#[test]
fn gaz_two_step_extraction_inside_the_boxes_reproduces_the_coefficients() {
    let lwr = lwr();
    let text = std::fs::read_to_string(fixture("lwr4_gaz2016_bounds.toml")).unwrap();
    let bounds = Bounds::from_toml(&text, "lwr4_gaz2016_bounds.toml", 7).unwrap();
    // Step 1's target: eq. 12 in robid's order and signs; one deviation for all, so the
    // whitened fit is the paper's unweighted f1 (eq. 16) scaled.
    let mut target = vec![0.0; 12];
    for (k, (name, sign)) in PAPER_TO_ROBID.iter().enumerate() {
        let i = lwr.gravity.names.iter().position(|n| n == name).unwrap();
        target[i] = sign * PI_HAT[k];
    }
    let gravity = lwr
        .gravity
        .problem(&lwr.full)
        .unwrap()
        .with_target(&target, &[1e-4; 12])
        .unwrap();
    let options = AnnealOptions {
        restarts: 2,
        iterations: 4000,
        local_evaluations: 4000,
        seed: 17,
        // no early stop: every restart runs, so the two calls below agree
        target_chi2: Some(0.0),
        equalities: EQ15.iter().map(|e| e.parse().unwrap()).collect(),
        ..AnnealOptions::default()
    };
    let start = Instant::now();
    let (first, held) = solve_gravity_step(&gravity, &bounds, &options).unwrap();
    println!("step 1 {:.2} s", start.elapsed().as_secs_f64());
    // Step 1 holds the paper's 23 gravity unknowns (Sec. III: m2..m7 and every c but c1x,
    // c1y, c1z and c2y).
    let names: Vec<String> = held.iter().map(|(v, _)| v.to_string()).collect();
    let mut expected = Vec::new();
    for j in 2..=7 {
        expected.push(format!("m{j}"));
        for a in ["x", "y", "z"] {
            if (j, a) != (2, "y") {
                expected.push(format!("c{j}{a}"));
            }
        }
    }
    assert_eq!(names, expected);
    // 12 equations in 23 unknowns with solutions inside the boxes (Table II is one, to
    // 1.2e-5): the fit is exact to rounding (measured 4.4e-16 m kg)
    let step1 = lwr.paper_coefficients(&first.standard);
    let d = max_difference(&step1, &PI_HAT);
    assert!(d < 1e-12, "step 1 reproduces eq. 12 to {d}");
    assert!(first.violations.is_empty(), "{:?}", first.violations);
    // Step 2's target: the paper's inertia coefficients are in its reference [17], not in
    // the paper. Stand-in: the base parameters of one robot whose gravity parameters are
    // those step 1 found (the paper's situation: both coefficient vectors come from one
    // robot), the first link's don't-care mass and centre of mass from Table I's V-REP
    // column, inertias at the centre of Table III's boxes (diagonal at mid-box, products
    // zero) except link 7's products, set by eq. 15.
    let (mut m, mut c) = (MASS, COM);
    for (v, value) in &held {
        match v.quantity {
            Quantity::Mass => m[v.link] = *value,
            Quantity::Com(a) => c[v.link][a] = *value,
            Quantity::Inertia(_) => unreachable!("step 1 holds masses and centres of mass"),
        }
    }
    let inertia: [[[f64; 3]; 3]; 7] = std::array::from_fn(|j| {
        let mid = |e: usize| {
            let r = bounds.links[j].tensor[e].unwrap();
            0.5 * (r[0] + r[1])
        };
        let (xz, yz) = if j == 6 {
            (c[6][0] * c[6][2] * m[6], c[6][1] * c[6][2] * m[6])
        } else {
            (mid(4), mid(5))
        };
        [[mid(0), mid(3), xz], [mid(3), mid(1), yz], [xz, yz, mid(2)]]
    });
    let reference = lwr.standard(&m, &c, &inertia);
    for j in 0..7 {
        let p = lwr.full.layout.link_values(j, &reference);
        assert!(
            pseudo_inertia_min_eigenvalue(&p) > 0.0,
            "stand-in link {}",
            j + 1
        );
    }
    let beta: Vec<f64> = lwr.full.base_of(&reference).iter().copied().collect();
    let full = lwr
        .full
        .clone()
        .with_target(&beta, &vec![1e-5; beta.len()])
        .unwrap();
    let start = Instant::now();
    let result = solve_two_step(&gravity, &full, &bounds, &options).unwrap();
    let seconds = start.elapsed().as_secs_f64();
    // measured 1.2 s in a debug build (2 restarts)
    println!("two steps {seconds:.2} s");
    assert_eq!(result.held, held, "the first step is reproducible");
    let sol = &result.solution;
    // inside Table I's and Table III's boxes and the total-mass range of eq. 18 (the
    // solution's own check, to 1e-6 relative), and every link consistent
    assert!(sol.violations.is_empty(), "{:?}", sol.violations);
    assert!(sol.min_eigenvalues.iter().all(|e| *e > 0.0));
    let total: f64 = sol.links.iter().flatten().map(|l| l.mass).sum();
    assert!((13.0..=19.0).contains(&total), "total mass {total}");
    for (j, (l, b)) in sol.links.iter().zip(&bounds.links).enumerate() {
        let l = l.as_ref().unwrap();
        for (range, (name, row, column)) in b.tensor.iter().zip(TENSOR_ELEMENTS) {
            let r = range.unwrap();
            let v = l.inertia[row][column];
            assert!(
                r[0] <= v && v <= r[1],
                "I{}{name} = {v} outside {r:?}",
                j + 1
            );
        }
    }
    // the held gravity parameters keep eq. 12 (rounding, as in step 1; measured 4.4e-16)
    let d = max_difference(&lwr.paper_coefficients(&sol.standard), &PI_HAT);
    assert!(d < 1e-12, "the result reproduces eq. 12 to {d}");
    // eq. 15, a penalty row of weight 1e10 per (box scale 5e-4 kg m^2)^2: measured
    // 7.2e-12 kg m^2 at most
    let l7 = sol.links[6].as_ref().unwrap();
    let eq15 = [
        l7.inertia[0][2] - l7.com[0] * l7.com[2] * l7.mass,
        l7.inertia[1][2] - l7.com[1] * l7.com[2] * l7.mass,
    ];
    assert!(
        eq15.iter().all(|r| r.abs() < 1.5e-11),
        "eq. 15 residuals {eq15:?}"
    );
    // every base parameter reproduced: measured 1.09e-5 at most (chi^2 1.32 with a
    // deviation of 1e-5 each)
    let d = max_difference(full.base_of(&sol.standard).as_slice(), &beta);
    println!("base parameters to {d:.3e}, chi^2 {}", sol.chi2);
    assert!(d < 2.2e-5, "base parameters reproduced to {d}");
}

/// Writes static samples of the LWR at `poses` random poses: `q1..q7` and the values of
/// `kind` computed by the model's gravity or mass-matrix program (not the regressor) for
/// base parameters `beta`.
fn write_samples(lwr: &Lwr, kind: StaticKind, beta: &[f64], poses: usize, path: &std::path::Path) {
    let n = 7;
    let mut header: Vec<String> = (1..=n).map(|i| format!("q{i}")).collect();
    header.extend(kind.columns(n));
    let mut text = header.join(",") + "\n";
    let mut rng = Rng::new(1994);
    for _ in 0..poses {
        let q: Vec<f64> = (0..n).map(|_| rng.uniform(-2.9, 2.9)).collect();
        let values: Vec<f64> = match kind {
            StaticKind::Gravity => {
                let mut g = vec![0.0; n];
                lwr.model.gravity_into(&q, beta, &mut g).unwrap();
                g
            }
            StaticKind::MassMatrix => {
                let mut m = vec![0.0; n * n];
                lwr.model.mass_matrix_into(&q, beta, &mut m).unwrap();
                (0..n)
                    .flat_map(|i| (i..n).map(move |j| (i, j)))
                    .map(|(i, j)| m[i * n + j])
                    .collect()
            }
        };
        let row: Vec<String> = q.iter().chain(&values).map(|v| format!("{v:e}")).collect();
        text += &(row.join(",") + "\n");
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn gaz_static_samples_identify_the_coefficients_they_determine() {
    let lwr = lwr();
    let inertia = [[[0.02, 0.001, 0.0], [0.001, 0.03, 0.002], [0.0, 0.002, 0.01]]; 7];
    let beta: Vec<f64> = lwr
        .full
        .base_of(&lwr.standard(&MASS, &COM, &inertia))
        .iter()
        .copied()
        .collect();
    let dir = tempfile::tempdir().unwrap();
    // gravity: the twelve of eq. 8; the mass matrix: every base parameter but the first
    // moments MX2 MYR2 MX3 MYR3, which only gravity sees (robid's rank analysis)
    for (kind, expected) in [(StaticKind::Gravity, 12), (StaticKind::MassMatrix, 39)] {
        let path = dir.path().join("samples.csv");
        write_samples(&lwr, kind, &beta, 40, &path);
        let fit = identify_static(&lwr.model, &path, 1e-10).unwrap();
        assert_eq!(fit.kind, kind);
        let truth = fit.determined.values(&beta).unwrap();
        let nd = truth.len();
        assert_eq!(
            nd,
            expected,
            "{}: undetermined {:?}",
            kind.name(),
            fit.undetermined
        );
        assert_eq!(nd + fit.undetermined.len(), lwr.full.base_names.len());
        let largest = truth.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        // exact samples: rounding only (measured 6.0e-16 and 1.5e-15 relative)
        let d = max_difference(&fit.estimate.values, &truth) / largest;
        assert!(d < 1e-10, "{}: recovered to {d:e} relative", kind.name());
    }
    // bad files: a missing column, neither or both kinds, too few poses
    let path = dir.path().join("bad.csv");
    let error = |text: &str| {
        std::fs::write(&path, text).unwrap();
        identify_static(&lwr.model, &path, 1e-10)
            .unwrap_err()
            .to_string()
    };
    let q = "q1,q2,q3,q4,q5,q6,q7";
    let e = error(&format!(
        "{q},g1,g2,g3,g4,g5,g6\n0,0,0,0,0,0,0,1,2,3,4,5,6\n"
    ));
    assert!(e.contains("no column `g7`"), "{e}");
    let e = error(&format!("{q},tau1\n0,0,0,0,0,0,0,1\n"));
    assert!(e.contains("holds neither gravity columns"), "{e}");
    let e = error(&format!("{q},g1,M11\n0,0,0,0,0,0,0,1,2\n"));
    assert!(
        e.contains("holds both gravity (g) and mass-matrix (M) columns"),
        "{e}"
    );
    write_samples(&lwr, StaticKind::Gravity, &beta, 1, &path);
    let e = identify_static(&lwr.model, &path, 1e-10)
        .unwrap_err()
        .to_string();
    // by the file, in poses (the least squares said "7 samples, at least 12 are needed",
    // counting equations as samples, and advised less decimation)
    assert!(
        e.contains(
            "bad.csv: static samples, 7 equations per pose, for the 12 combinations of base \
             parameters that gravity torques determine (and one equation more): 1 sample, at \
             least 2 are needed; add rows to the file"
        ),
        "{e}"
    );
    // one pose three times: enough rows, too alike; said by the file, with the poses' fix
    // (it was the estimators' "use a richer trajectory or remove these parameters")
    let text = std::fs::read_to_string(&path).unwrap();
    let (head, row) = (text.lines().next().unwrap(), text.lines().nth(1).unwrap());
    let e = error(&format!("{head}\n{row}\n{row}\n{row}\n"));
    assert!(
        e.contains("bad.csv")
            && e.contains("its 3 poses determine 6 of the 12 combinations")
            // the 6 missing directions, not the columns they mix as if each were missing
            && e.contains("(undetermined: 6 combinations of ")
            && e.contains("add rows at poses unlike the others"),
        "{e}"
    );
}
