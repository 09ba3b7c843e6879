//! The flexible-joint simulation against its own equations, checked from the outside:
//! the logged positions, differentiated, and the logged currents must satisfy the link and
//! rotor equations with the logged joint torque.

use super::*;
use crate::simulate::Noise;
use crate::simulate::run_tests::reference;
use crate::simulate::tests::Pendulum;

fn friction() -> JointFriction {
    JointFriction {
        coulomb: 1.5,
        load: 0.02,
        stribeck: 0.5,
        stribeck_velocity: 0.05,
        viscous: 2.0,
        coulomb_temperature: 0.005,
        viscous_temperature: 0.01,
        reference_temperature: 25.0,
        smoothing: crate::drive::DEFAULT_SMOOTHING,
    }
}

fn flexibility() -> Flexibility {
    let joint = |stiffness: f64, rotor_inertia: f64| FlexibleJoint {
        gear_ratio: 100.0,
        rotor_inertia,
        torque_constant: 0.1,
        stiffness,
        hardening: 1e9,
        damping: 5.0,
        friction: friction(),
    };
    Flexibility {
        joints: vec![joint(2e4, 0.3), joint(8e3, 0.1)],
        temperature: TemperatureProfile {
            start: 25.0,
            end: 45.0,
            time_constant: 2.0,
        },
    }
}

/// Second derivative by central differences of samples `h` apart.
fn second(v: &[f64], k: usize, h: f64) -> f64 {
    (v[k + 1] - 2.0 * v[k] + v[k - 1]) / (h * h)
}

fn first(v: &[f64], k: usize, h: f64) -> f64 {
    (v[k + 1] - v[k - 1]) / (2.0 * h)
}

/// Without noise, at 2 kHz: the link equation M(q) q'' + h(q, q') = tau_J, the rotor
/// equation B theta'' + f(theta', tau_J, T) + tau_J = N k i and the transmission's
/// tau_J = K1 d + K3 d^3 + D d' hold on the logged signals to
/// the central differences' truncation error (measured residuals 1.2e-4 and 1.1e-5 of the
/// largest torque, the rotor's away from speed reversals); the link tracks its reference;
/// the largest deflection is that of the largest joint torque (1e-3 to 2e-3 rad here, as
/// on a UR5e under load).
#[test]
fn flexible_log_satisfies_the_link_and_rotor_equations() {
    let p = Pendulum::default();
    let base = p.base();
    let flex = flexibility();
    let r = reference(3.0, 2000.0);
    let sim = Simulation::default();
    let log = sim.run_flexible(&p, &base, &flex, &r).unwrap();
    let h = 1.0 / 2000.0;
    let (mut link, mut rotor, mut largest, mut spring) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let mut tau = [0.0; 2];
    for k in (5..r.samples() - 5).step_by(7) {
        let q: Vec<f64> = log.true_q.joints().map(|v| v[k]).collect();
        let qd: Vec<f64> = log.true_q.joints().map(|v| first(v, k, h)).collect();
        let qdd: Vec<f64> = log.true_q.joints().map(|v| second(v, k, h)).collect();
        p.inverse_dynamics_into(&q, &qd, &qdd, &base, &mut tau)
            .unwrap();
        for (j, g) in flex.joints.iter().enumerate() {
            let tau_j = log.joint_torque[j][k];
            largest = largest.max(tau_j.abs());
            link = link.max((tau[j] - tau_j).abs());
            let theta = &log.true_theta[j];
            // the transmission: tau_J = K1 d + K3 d^3 + D d'
            let d = theta[k] - log.true_q[j][k];
            let dd = first(theta, k, h) - first(&log.true_q[j], k, h);
            spring = spring.max((g.elastic(d) + g.damping * dd - tau_j).abs());
            // the friction's smooth sign turns within a few eps of zero speed, faster
            // than differences over 1 ms can follow: those samples are left out
            if first(theta, k, h).abs() < 50.0 * g.friction.smoothing {
                continue;
            }
            let u = log.current[j][k] * g.gear_ratio * g.torque_constant;
            let f = g
                .friction
                .evaluate(first(theta, k, h), tau_j, log.temperature[j][k]);
            rotor = rotor.max((g.rotor_inertia * second(theta, k, h) + f + tau_j - u).abs());
        }
    }
    eprintln!(
        "largest torque {largest}, link residual {link}, rotor residual {rotor}, \
         transmission residual {spring}"
    );
    assert!(
        link <= 2.4e-4 * largest,
        "link equation: {link} of {largest}"
    );
    assert!(
        rotor <= 2.2e-5 * largest,
        "rotor equation: {rotor} of {largest}"
    );
    // measured 2.0e-5 of the largest torque (the damping term reaches 1e-3 of it)
    assert!(
        spring <= 4e-5 * largest,
        "transmission: {spring} of {largest}"
    );
    // tracking (measured 1.6e-4 rad) and the deflection of the load (2.0e-3 and 1.1e-3 rad,
    // within 2.7e-6 and 2.4e-5 of the deflection of the largest torque)
    let tracking = (0..r.samples())
        .map(|k| {
            (log.true_q[0][k] - r.q[0][k])
                .abs()
                .max((log.true_q[1][k] - r.q[1][k]).abs())
        })
        .fold(0.0, f64::max);
    assert!(tracking < 3.2e-4, "tracking {tracking}");
    let d = log.largest_deflection();
    let expected: Vec<f64> = (0..2)
        .map(|j| {
            let g = &flex.joints[j];
            let tau_max = log.joint_torque[j]
                .iter()
                .fold(0.0f64, |m, t| m.max(t.abs()));
            g.deflection(tau_max)
        })
        .collect();
    for j in 0..2 {
        assert!(
            (d[j] / expected[j] - 1.0).abs() < [5.4e-6, 4.8e-5][j],
            "{d:?} vs {expected:?}"
        );
    }
    // the temperature warms from 25 towards 45 deg C with a 2 s time constant
    let last = r.samples() - 1;
    let t = log.temperature[0][last];
    assert!(
        (t - (45.0 - 20.0 * (-r.t[last] / 2.0f64).exp())).abs() < 1e-12,
        "{t}"
    );
}

/// The flexible log of a reference on Unix time stamps (1.7336e9 s, 500 Hz) is written with
/// the reference's very time stamps, and loaded as data without a repair: written to ten
/// significant digits, every stamp within a second was one value (1.733600000e9), which
/// the loader refused.
#[test]
fn flexible_log_keeps_large_time_stamps() {
    let p = Pendulum::default();
    let mut r = reference(0.2, 500.0);
    r.t.iter_mut().for_each(|t| *t += 1.7336e9);
    let log = Simulation::default()
        .run_flexible(&p, &p.base(), &flexibility(), &r)
        .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("flex.csv");
    log.write_csv(&f, 1, true).unwrap();
    assert_eq!(crate::simulate::run_tests::written_times(&f), r.t);
    let config = crate::data::Config::from_toml_str(
        "dof = 2\ntime_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tauJ{}\"\n",
        std::path::Path::new("flex.toml"),
    )
    .unwrap();
    let data = crate::data::load(&config, std::slice::from_ref(&f), 2);
    let data = data.unwrap();
    assert_eq!(data.q.samples(), r.samples());
    assert!(data.warnings.is_empty(), "{:?}", data.warnings);
}

/// A transmission damping whose rate over its inertias needs each substep split beyond the
/// cap (1e7 N m s/rad on joint 2, over a rotor of 0.1 and a link of 0.3 kg m^2, at 1 kHz:
/// thousands of steps) stops at its first sample naming the damping of joint 2 and its
/// value; the split clamped to 1,000 let the run diverge, blamed on "a stiffness or rotor
/// inertia".
#[test]
fn a_damping_beyond_the_split_cap_is_named() {
    let p = Pendulum::default();
    let mut flex = flexibility();
    flex.joints[1].damping = 1e7;
    let e = Simulation::default()
        .run_flexible(&p, &p.base(), &flex, &reference(0.1, 1000.0))
        .unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(
            e,
            Error::Simulate(crate::SimulateError::TooStiff { sample: 0, .. })
        ) && text.starts_with("the simulation cannot follow the plant at t = 0 s")
            && text.contains("more than the limit of 1000")
            && text.contains("nothing was written")
            && text.contains("the transmission damping of joint 2, damping = 1e7 N m s/rad")
            && text.contains("check joint 2's `damping`"),
        "{text}"
    );
}

/// The motor encoder and the current carry the noise and quantization; the same seed
/// gives the same log; the torque noise reaches the current divided by N k.
#[test]
fn flexible_noise_reaches_both_encoders_and_the_current() {
    let p = Pendulum::default();
    let flex = flexibility();
    let r = reference(0.5, 1000.0);
    let quiet = Simulation::default()
        .run_flexible(&p, &p.base(), &flex, &r)
        .unwrap();
    let noisy = Simulation {
        noise: Noise {
            torque: vec![0.5],
            quantization: 1e-4,
            ..Noise::default()
        },
        ..Simulation::default()
    };
    let a = noisy.run_flexible(&p, &p.base(), &flex, &r).unwrap();
    let b = noisy.run_flexible(&p, &p.base(), &flex, &r).unwrap();
    assert_eq!(a.current, b.current);
    for k in 0..r.samples() {
        // quantized to the count on each side: round(x / r) r / r is the count after two
        // roundings of half an ulp, so within about eps |m| (measured 0.82 eps |m|, with
        // |m| up to 4.2e5)
        let m = a.motor[0][k] / 1e-4;
        assert!((m - m.round()).abs() <= 2.0 * f64::EPSILON * m.abs(), "{m}");
        let q = a.q[1][k] / 1e-4;
        assert!((q - q.round()).abs() <= 2.0 * f64::EPSILON * q.abs(), "{q}");
    }
    // the current carries 0.5 / (100 x 0.1) = 0.05 A of noise on top of what the
    // controller commands: against the same run without it (the same quantized loop, the
    // same random draws) the difference is that noise alone, its variance 0.05^2 within
    // 4 standard errors (sqrt(2 / n) of it; measured 1.015, seeded). The quiet run is no
    // reference: its loop is not quantized, so its current differs by more than the noise.
    let same_loop = Simulation {
        noise: Noise {
            torque: vec![0.0],
            quantization: 1e-4,
            ..Noise::default()
        },
        ..Simulation::default()
    }
    .run_flexible(&p, &p.base(), &flex, &r)
    .unwrap();
    assert_eq!(same_loop.motor, a.motor);
    let n = r.samples() as f64;
    let variance = (0..r.samples())
        .map(|k| (a.current[0][k] - same_loop.current[0][k]).powi(2))
        .sum::<f64>()
        / n;
    let ratio = variance / (0.05 * 0.05);
    assert!((ratio - 1.0).abs() < 4.0 * (2.0 / n).sqrt(), "{ratio}");
    assert_ne!(quiet.current, a.current);
}

/// The PD loop reads the motor encoder the log writes: against the same run without
/// position noise, the motor torque differs by the loop's gain on that noise in link
/// radians, `kp sigma / N` (variance ratio measured 1.088, seeded; within 0.8 to 1.25).
/// The loop read `quantize(N theta) / N + noise`, the noise a link angle: N = 100 times
/// the logged motor encoder's (variance ratio measured 1.09e4).
#[test]
fn the_loop_reads_the_logged_motor_encoder() {
    let p = Pendulum::default();
    let flex = flexibility();
    let r = reference(0.5, 1000.0);
    let sigma = 1e-5;
    let noisy = Simulation {
        noise: Noise {
            position: sigma,
            ..Noise::default()
        },
        ..Simulation::default()
    };
    let a = noisy.run_flexible(&p, &p.base(), &flex, &r).unwrap();
    let quiet = Simulation::default()
        .run_flexible(&p, &p.base(), &flex, &r)
        .unwrap();
    // the loop's gain on joint 1, as `run_flexible` sets it: the rotor's and the link's
    // inertia at the start times the bandwidth squared
    let n = p.dof();
    let mut q0 = [vec![0.0; n], vec![0.0; n], vec![0.0; n]];
    {
        let [a, b, c] = &mut q0;
        r.state(0, a, b, c);
    }
    let mut mass = vec![0.0; n * n];
    p.mass_matrix_into(&q0[0], &p.base(), &mut mass).unwrap();
    let g = &flex.joints[0];
    let wn = std::f64::consts::TAU * noisy.bandwidth;
    let kp = (g.rotor_inertia + mass[0]) * wn * wn;
    let per_amp = g.gear_ratio * g.torque_constant;
    let samples = r.samples();
    let variance = (0..samples)
        .map(|k| ((a.current[0][k] - quiet.current[0][k]) * per_amp).powi(2))
        .sum::<f64>()
        / samples as f64;
    let ratio = variance / (kp * sigma / g.gear_ratio).powi(2);
    assert!((0.8..1.25).contains(&ratio), "{ratio}");
}

/// File errors name the file, the key with its line and the fix; a joint count that
/// differs from the robot's is refused.
#[test]
fn flexible_file_errors_name_the_key() {
    let text = |stiffness: &str, second: &str| {
        format!(
            "[temperature]\nstart = 25.0\nend = 40.0\ntime_constant = 60.0\n\
             [[joint]]\njoint = 1\ngear_ratio = 100.0\nrotor_inertia = 0.3\n\
             torque_constant = 0.1\nstiffness = {stiffness}\n\
             friction = {{ coulomb = 1.0, load = 0.0, stribeck = 0.0, stribeck_velocity = 0.1, \
             viscous = 1.0, coulomb_temperature = 0.0, viscous_temperature = 0.0, \
             reference_temperature = 25.0 }}\n{second}"
        )
    };
    let path = Path::new("flex.toml");
    let ok = Flexibility::from_toml_str(&text("2e4", ""), path).unwrap();
    assert_eq!(ok.joints[0].hardening, 0.0);
    let e = Flexibility::from_toml_str(&text("-1.0", ""), path)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("flex.toml:10") && e.contains("joint[1].stiffness"),
        "{e}"
    );
    // a torque constant too small to divide by: the currents were written as `inf`
    let tiny = text("2e4", "").replace("torque_constant = 0.1", "torque_constant = 1e-320");
    let e = Flexibility::from_toml_str(&tiny, path)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("flex.toml:9")
            && e.contains("joint[1].torque_constant")
            && e.contains("1e-320 N m/A must lie in [1e-12, 1e6] N m/A"),
        "{e}"
    );
    // every factor the simulation divides by has the same floor, through the same table:
    // a rotor inertia of 1e-320 ended the run as "diverged" at its first sample, naming
    // no key; a stiffness of 1e-320 made every deflection infinite
    for (line, key, written, told) in [
        (
            8,
            "rotor_inertia = 0.3",
            "rotor_inertia = 1e-320",
            "1e-320 kg m^2 must lie in [1e-12, 1e6] kg m^2",
        ),
        (
            8,
            "rotor_inertia = 0.3",
            "rotor_inertia = 1e-13",
            "1e-13 kg m^2 must lie in",
        ),
        (
            10,
            "stiffness = 2e4",
            "stiffness = 1e-320",
            "1e-320 N m/rad must lie in [1e-12, 1e9] N m/rad",
        ),
        (
            7,
            "gear_ratio = 100.0",
            "gear_ratio = -1e-320",
            "-1e-320 must be of magnitude 1e-3 to 1e6",
        ),
    ] {
        let bad = text("2e4", "").replace(key, written);
        let e = Flexibility::from_toml_str(&bad, path)
            .unwrap_err()
            .to_string();
        let field = key.split(' ').next().unwrap();
        assert!(
            e.starts_with(&format!(
                "flex.toml:{line}:1: `joint[1].{field}`: joint 1: {told}"
            )),
            "{e}"
        );
    }
    let twice = "[[joint]]\njoint = 1\ngear_ratio = 1.0\nrotor_inertia = 1.0\n\
                 torque_constant = 1.0\nstiffness = 1.0\nfriction = { coulomb = 1.0, \
                 load = 0.0, stribeck = 0.0, stribeck_velocity = 0.1, viscous = 1.0, \
                 coulomb_temperature = 0.0, viscous_temperature = 0.0, \
                 reference_temperature = 25.0 }\n";
    let e = Flexibility::from_toml_str(&text("2e4", twice), path)
        .unwrap_err()
        .to_string();
    assert!(e.contains("second table"), "{e}");
    let e = Flexibility::from_toml_str(&text("2e4", "colour = 3\n"), path)
        .unwrap_err()
        .to_string();
    assert!(e.contains("colour"), "{e}");
    let p = Pendulum::default();
    let e = Simulation::default()
        .run_flexible(&p, &p.base(), &ok, &reference(0.1, 100.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("joint-flexibility file"), "{e}");
}

/// The Stribeck term's slope bound holds over every speed at or above the slowest one, is
/// its peak sqrt(2/e)/ws through a reversal, and vanishes far from one (it was 1/ws at any
/// speed, which split every substep to the cap for a small ws).
#[test]
fn stribeck_slope_bounds_the_term_beyond_the_slowest_speed() {
    for ws in [0.05, 1e-3, 1e-6] {
        let term = |w: f64| (-(w / ws) * (w / ws)).exp();
        for slowest in [0.0, 0.3 * ws, ws, 3.0 * ws, 10.0 * ws] {
            let bound = stribeck_slope(ws, slowest);
            for k in 0..2000 {
                let w = slowest + k as f64 * ws / 200.0;
                let h = ws * 1e-6;
                let slope = ((term(w + h) - term(w - h)) / (2.0 * h)).abs();
                assert!(
                    slope <= bound * (1.0 + 1e-6),
                    "ws {ws} slowest {slowest} w {w}: {slope} > {bound}"
                );
            }
        }
        let peak = (2.0 / std::f64::consts::E).sqrt() / ws;
        assert!((stribeck_slope(ws, 0.0) - peak).abs() < 1e-12 * peak);
        assert_eq!(stribeck_slope(ws, 40.0 * ws), 0.0);
    }
    assert!(stribeck_slope(1e-6, 0.1) < 1e-300);
}

/// A rotor far lighter than its link (0.01 kg m^2 on joint 1 against a link of about
/// 2 kg m^2): the PD loop's derivative term acts on the rotor alone, at `kd / B`, about
/// 25,000 1/s, where the rate counted `kd / (B + M_jj)`, 125. At 100 Hz (10 substeps of
/// 1 ms) the classical Runge-Kutta step went unstable unsplit; the run must agree with the
/// same run on substeps 40 times finer, which no split is needed to keep stable.
#[test]
fn a_light_rotor_on_a_heavy_link_is_integrated_stably() {
    let p = Pendulum::default();
    let base = p.base();
    let mut flex = flexibility();
    flex.joints[0].rotor_inertia = 0.01;
    let r = reference(1.0, 100.0);
    let coarse = Simulation::default()
        .run_flexible(&p, &base, &flex, &r)
        .unwrap();
    let fine = Simulation {
        substeps: 400,
        ..Simulation::default()
    }
    .run_flexible(&p, &base, &flex, &r)
    .unwrap();
    let largest = |a: &Signals, b: &Signals| {
        a.joints()
            .zip(b.joints())
            .flat_map(|(x, y)| x.iter().zip(y).map(|(x, y)| (x - y).abs()))
            .fold(0.0f64, f64::max)
    };
    let dq = largest(&coarse.true_q, &fine.true_q);
    let di = largest(&coarse.current, &fine.current);
    let scale = fine
        .current
        .joints()
        .flatten()
        .fold(0.0f64, |m, i| m.max(i.abs()));
    eprintln!("q {dq:e} rad, current {di:e} A of {scale} A");
    assert!(
        dq < 2e-6 && di < 1e-4 * scale,
        "q {dq:e}, current {di:e} of {scale}"
    );
}

/// A rotor so light that the PD loop's rate on it, `kd / B`, needs each substep split
/// beyond the cap (1e-6 kg m^2 under a link of about 2: 2.5e8 1/s, 1e5 steps per 1 ms
/// substep) is refused at its first sample naming the bandwidth; with the loop's rate
/// counted over the rotor plus link inertia the run went on and diverged at once, blamed
/// on "a stiffness or rotor inertia".
#[test]
fn a_loop_beyond_the_split_cap_on_a_light_rotor_is_refused() {
    let p = Pendulum::default();
    let mut flex = flexibility();
    let g = &mut flex.joints[0];
    (g.rotor_inertia, g.damping, g.friction.viscous) = (1e-6, 0.0, 0.0);
    let e = Simulation::default()
        .run_flexible(&p, &p.base(), &flex, &reference(0.1, 100.0))
        .unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(
            e,
            Error::Simulate(crate::SimulateError::TooStiff { sample: 0, .. })
        ) && text.contains("the controller bandwidth, 10 Hz, makes most of it"),
        "{text}"
    );
}
