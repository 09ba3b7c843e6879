//! Joint states, smooth trajectories and symbol bindings for evaluating derivations.

use robid_runtime::rng::Rng;
use robid_symbolic::{Arena, JointKind, Robot, Values};

/// A joint state.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Positions.
    pub q: Vec<f64>,
    /// Velocities.
    pub qd: Vec<f64>,
    /// Accelerations.
    pub qdd: Vec<f64>,
}

/// A random state: positions within the joint limits when given (else [-pi, pi], or
/// [0.1, 1] m for a prismatic joint), velocities in [-2, 2], accelerations in [-5, 5].
pub fn random_state(robot: &Robot, rng: &mut Rng) -> State {
    let q = robot
        .joints()
        .iter()
        .map(|j| {
            let [lo, hi] = j.limits.position.unwrap_or(match j.kind {
                JointKind::Revolute => [-std::f64::consts::PI, std::f64::consts::PI],
                JointKind::Prismatic => [0.1, 1.0],
            });
            rng.uniform(lo, hi)
        })
        .collect();
    let n = robot.dof();
    State {
        q,
        qd: (0..n).map(|_| rng.uniform(-2.0, 2.0)).collect(),
        qdd: (0..n).map(|_| rng.uniform(-5.0, 5.0)).collect(),
    }
}

/// Random values for `count` standard parameters, in [-1, 1].
pub fn random_parameters(count: usize, rng: &mut Rng) -> Vec<f64> {
    (0..count).map(|_| rng.uniform(-1.0, 1.0)).collect()
}

/// Values binding `q1.. qd1.. qdd1..`, the robot's geometric symbols (their default values)
/// and, when given, the standard parameters by name.
pub fn bind(arena: &mut Arena, robot: &Robot, state: &State, parameters: Option<&[f64]>) -> Values {
    let mut owned: Vec<(String, f64)> = Vec::new();
    for j in 0..robot.dof() {
        owned.push((format!("q{}", j + 1), state.q[j]));
        owned.push((format!("qd{}", j + 1), state.qd[j]));
        owned.push((format!("qdd{}", j + 1), state.qdd[j]));
    }
    for (name, value) in robot.symbols() {
        let v = value.unwrap_or_else(|| panic!("symbol {name} has no default value"));
        owned.push((name.clone(), v));
    }
    if let Some(values) = parameters {
        for (p, &v) in robot.standard_parameters().iter().zip(values) {
            owned.push((p.to_string(), v));
        }
    }
    let pairs: Vec<(&str, f64)> = owned.iter().map(|(n, v)| (n.as_str(), *v)).collect();
    arena.values(&pairs)
}

/// One sine term (amplitude, angular frequency, phase).
pub type Sine = (f64, f64, f64);

/// A smooth joint trajectory: per joint, q(t) = c + sum_k a_k sin(w_k t + phi_k).
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    /// Per joint: offset c and terms (a_k, w_k, phi_k).
    pub joints: Vec<(f64, Vec<Sine>)>,
}

impl Trajectory {
    /// A random trajectory of three sines per joint (0.1 to 1 Hz) around the middle of the
    /// position limits (or 0, or 0.5 m for a prismatic joint), amplitudes up to 0.3.
    pub fn random(robot: &Robot, rng: &mut Rng) -> Trajectory {
        let joints = robot
            .joints()
            .iter()
            .map(|j| {
                let centre = match (j.limits.position, j.kind) {
                    (Some([lo, hi]), _) => 0.5 * (lo + hi),
                    (None, JointKind::Revolute) => 0.0,
                    (None, JointKind::Prismatic) => 0.5,
                };
                let terms = (0..3)
                    .map(|_| {
                        let a = rng.uniform(-0.3, 0.3);
                        let w = 2.0 * std::f64::consts::PI * rng.uniform(0.1, 1.0);
                        let phi = rng.uniform(0.0, 2.0 * std::f64::consts::PI);
                        (a, w, phi)
                    })
                    .collect();
                (centre, terms)
            })
            .collect();
        Trajectory { joints }
    }

    /// The state at time t (exact derivatives).
    pub fn at(&self, t: f64) -> State {
        let mut s = State {
            q: Vec::new(),
            qd: Vec::new(),
            qdd: Vec::new(),
        };
        for (c, terms) in &self.joints {
            let (mut q, mut qd, mut qdd) = (*c, 0.0, 0.0);
            for &(a, w, phi) in terms {
                let (sn, cs) = (w * t + phi).sin_cos();
                q += a * sn;
                qd += a * w * cs;
                qdd -= a * w * w * sn;
            }
            s.q.push(q);
            s.qd.push(qd);
            s.qdd.push(qdd);
        }
        s
    }
}

/// Dot product of a regressor evaluated column by column (`entries[p * dof + j]`, the
/// layout of `Regressor::entries`) with parameter values: the torques.
pub fn regressor_times(entries: &[f64], dof: usize, parameters: &[f64]) -> Vec<f64> {
    assert_eq!(entries.len(), dof * parameters.len());
    let mut tau = vec![0.0; dof];
    for (column, &p) in entries.chunks(dof).zip(parameters) {
        for (t, &y) in tau.iter_mut().zip(column) {
            *t += y * p;
        }
    }
    tau
}

/// True when `a` and `b` agree to `relative` times the larger of `scale` and their size.
pub fn close(a: f64, b: f64, relative: f64, scale: f64) -> bool {
    (a - b).abs() <= relative * scale.max(a.abs()).max(b.abs())
}
