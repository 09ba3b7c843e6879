//! `robid friction`: the nonlinear rotor friction from a synthetic two-encoder log whose
//! friction is known, and its refusals of incomplete input.

use std::fmt::Write as _;
use std::path::Path;

use robid_runtime::Num;
use robid_runtime::drive::{FrictionModel, JointFriction};

use crate::common::{folder, most_digits, robid, stderr, stdout, write};

/// Two joints, no gravity (the model is read but tau_J comes from the sensor columns).
const ROBOT: &str = "name = \"arm\"\nconvention = \"modified\"\ngravity = [0, 0, 0]\n\
                     [[joints]]\nalpha = 0\n[[joints]]\nalpha = \"pi/2\"\na = 0.3\n";

/// Gear ratios, torque constants (the torque columns are currents) and rotor inertias.
const RATIOS: [f64; 2] = [10.0, -20.0];
const CONSTANTS: [f64; 2] = [0.1, 0.05];
const INERTIA: [f64; 2] = [0.4, 0.2];

fn truth() -> FrictionModel {
    truth_smoothed(1e-3)
}

/// [`truth`] with the smooth sign's `eps` `smoothing`.
fn truth_smoothed(smoothing: f64) -> FrictionModel {
    let joint = |coulomb: f64, viscous: f64| JointFriction {
        coulomb,
        load: 0.03,
        stribeck: 0.8,
        stribeck_velocity: 0.1,
        viscous,
        coulomb_temperature: 0.01,
        viscous_temperature: 0.02,
        reference_temperature: 40.0,
        smoothing,
    };
    FrictionModel::new(vec![joint(2.0, 3.0), joint(1.0, 1.5)]).unwrap()
}

/// The analytic link position, velocity, acceleration of joint `j` at `t`, and the
/// deflection's (theta = q + d).
fn motion(j: usize, t: f64) -> ([f64; 3], [f64; 3]) {
    let mut q = [0.0; 3];
    for (h, (a, w)) in [(0.8, 0.9), (0.3, 2.3)].into_iter().enumerate() {
        let w = w * (1.0 + 0.2 * j as f64);
        let p = h as f64 + j as f64;
        q[0] += a * (w * t + p).sin();
        q[1] += a * w * (w * t + p).cos();
        q[2] -= a * w * w * (w * t + p).sin();
    }
    let w = 7.0;
    let d = [
        0.01 * (w * t).sin(),
        0.01 * w * (w * t).cos(),
        -0.01 * w * w * (w * t).sin(),
    ];
    (q, d)
}

/// A log of `n` samples at 500 Hz: link positions, motor encoder positions (motor side),
/// motor currents, joint-torque sensor, and temperatures rising from 30 deg C by
/// `temperature` K when it is given. The currents
/// are Madsen's eq. 14 solved for them: `N K i = tau_J + B thetaddot + f(thetadot, tau_J, T)`.
fn log(n: usize, temperature: Option<f64>) -> String {
    log_of(&truth(), n, temperature)
}

/// [`log`] of the friction `model`.
fn log_of(model: &FrictionModel, n: usize, temperature: Option<f64>) -> String {
    let mut text = String::from("t,q1,q2,m1,m2,i1,i2,tj1,tj2");
    if temperature.is_some() {
        text.push_str(",T1,T2");
    }
    text.push('\n');
    for k in 0..n {
        let t = k as f64 / 500.0;
        let temp = match temperature {
            Some(span) => 30.0 + span * k as f64 / n as f64,
            None => 25.0,
        };
        // columns by group: q, m, i, tj, T
        let mut groups = vec![String::new(); 5];
        for j in 0..2 {
            let (q, d) = motion(j, t);
            let (thetad, thetadd) = (q[1] + d[1], q[2] + d[2]);
            let tau_j = 15.0 * (0.7 * t + j as f64).sin() + 5.0 * q[2];
            let f = model.evaluate(j, thetad, tau_j, temp);
            let current = (tau_j + INERTIA[j] * thetadd + f) / (RATIOS[j] * CONSTANTS[j]);
            let values = [q[0], RATIOS[j] * (q[0] + d[0]), current, tau_j, temp];
            for (g, v) in groups.iter_mut().zip(values) {
                let _ = write!(g, ",{v}");
            }
        }
        if temperature.is_none() {
            groups.pop();
        }
        let _ = writeln!(text, "{t}{}", groups.concat());
    }
    text
}

/// The config of [`log`]; `rotor` false leaves out `[drive.rotor]`.
fn config(temperature: bool, rotor: bool) -> String {
    let mut c = format!(
        "dof = 2\ntime_column = \"t\"\n[[source]]\nfile = \"log.csv\"\nposition = \"q{{}}\"\n\
         motor_position = \"m{{}}\"\ntorque = \"i{{}}\"\njoint_torque = \"tj{{}}\"\n{}\
         [drive]\ntorque_side = \"motor\"\ngear_ratios = {RATIOS:?}\n\
         torque_constants = {CONSTANTS:?}\n",
        if temperature {
            "temperature = \"T{}\"\n"
        } else {
            ""
        }
    );
    if rotor {
        let _ = write!(c, "[drive.rotor]\ninertia = {INERTIA:?}\n");
    }
    c
}

fn setup(dir: &Path, temperature: bool, rotor: bool) -> (String, String) {
    let robot = write(dir, "arm.toml", ROBOT);
    write(dir, "log.csv", &log(5000, temperature.then_some(20.0)));
    let cfg = write(dir, "cfg.toml", &config(temperature, rotor));
    (
        robot.to_str().unwrap().to_string(),
        cfg.to_str().unwrap().to_string(),
    )
}

/// The largest difference between two models' friction over the log's range of rotor
/// velocity (beyond the smooth sign's 0.01 rad/s), load and temperature, relative to the
/// largest friction there.
fn curve_error(fitted: &FrictionModel, truth: &FrictionModel, temps: [f64; 2]) -> f64 {
    let mut worst = 0.0_f64;
    for j in 0..2 {
        let mut scale = 0.0_f64;
        let mut diff = 0.0_f64;
        for iw in 0..=200 {
            let w = -2.5 + 5.0 * iw as f64 / 200.0;
            if w.abs() < 0.01 {
                continue;
            }
            for load in [-20.0, -5.0, 0.0, 10.0, 20.0] {
                for temp in temps {
                    let t = truth.evaluate(j, w, load, temp);
                    scale = scale.max(t.abs());
                    diff = diff.max((fitted.evaluate(j, w, load, temp) - t).abs());
                }
            }
        }
        worst = worst.max(diff / scale);
    }
    worst
}

#[test]
fn recovers_the_friction_of_a_two_encoder_log() {
    let dir = folder();
    let (robot, cfg) = setup(dir.path(), true, true);
    let out = dir.path().join("friction.toml");
    let o = robid(&[
        "friction",
        &robot,
        "--config",
        &cfg,
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("joint 1: ") && text.contains("joint 2: ") && text.contains("RMS residual"),
        "{text}"
    );
    assert!(text.contains("joint_torque columns"), "{text}");
    // each estimated parameter with its standard deviation, a positive number
    let coulomb: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("  coulomb "))
        .collect();
    assert_eq!(coulomb.len(), 2, "{text}");
    for line in coulomb {
        let std = line.split("+- ").nth(1).and_then(|r| r.split(' ').next());
        let std: f64 = std.and_then(|v| v.parse().ok()).expect(line);
        assert!(std > 0.0 && std.is_finite(), "{line}");
    }
    let fitted = FrictionModel::read(&out).unwrap();
    let e = curve_error(&fitted, &truth(), [30.0, 50.0]);
    // measured 4.0e-4 of the largest friction (the residual's RMS is 5e-3 N m, from the
    // central differences of the motor encoder through velocity reversals)
    assert!(e < 0.01, "friction curve off by {e}\n{text}");
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
}

/// A log whose friction has `smoothing = 0.02` is fitted with that `eps` by
/// `--smoothing 0.02`, which the output file keeps. The fit used 1e-3 whatever the data's
/// model (the Stribeck velocity came out 53 times too large and the Coulomb friction 15 %
/// low with exit 0, and the file said `smoothing = 0.001`); the default still does.
#[test]
fn the_fit_uses_the_smoothing_given() {
    let dir = folder();
    let robot = write(dir.path(), "arm.toml", ROBOT);
    let truth = truth_smoothed(0.02);
    write(dir.path(), "log.csv", &log_of(&truth, 5000, Some(20.0)));
    let cfg = write(dir.path(), "cfg.toml", &config(true, true));
    let fit = |extra: &[&str]| {
        let out = dir.path().join("friction.toml");
        let (robot, cfg, path) = (robot.to_str().unwrap(), cfg.to_str().unwrap(), out.to_str());
        let mut args = vec!["friction", robot, "--config", cfg, "-o", path.unwrap()];
        args.extend(extra);
        let o = robid(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        (FrictionModel::read(&out).unwrap(), stdout(&o))
    };
    let (fitted, text) = fit(&["--smoothing", "0.02"]);
    let e = curve_error(&fitted, &truth, [30.0, 50.0]);
    assert!(e < 0.01, "friction curve off by {e}\n{text}");
    for j in fitted.joints() {
        assert_eq!(j.smoothing, 0.02);
    }
    let (fitted, _) = fit(&[]);
    assert_eq!(fitted.joints()[0].smoothing, 1e-3);
    assert!(curve_error(&fitted, &truth, [30.0, 50.0]) > 0.01);
    // out of the friction file's range: refused, naming the range
    let o = robid(&[
        "friction",
        "x.toml",
        "--config",
        "c.toml",
        "-o",
        "f.toml",
        "--smoothing",
        "0",
    ]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--smoothing"), "{}", stderr(&o));
}

/// A `--smoothing` wider than the samples' speeds is told as the flag's, with every joint
/// it hides and a smoothing that fits: `--smoothing 1` counts motion from 10 rad/s, and the
/// error was joint 1's alone, "no velocity reversal: 0 samples move forward and 0 backward",
/// "record motion in both directions" (which the log held); the smoothing it gives fits.
#[test]
fn a_smoothing_wider_than_the_motion_is_the_flags() {
    let dir = folder();
    let (robot, cfg) = setup(dir.path(), true, true);
    let out = dir.path().join("friction.toml");
    let run = |smoothing: &str| {
        robid(&[
            "friction",
            &robot,
            "--config",
            &cfg,
            "-o",
            out.to_str().unwrap(),
            "--smoothing",
            smoothing,
        ])
    };
    let o = run("1");
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert!(
        e.contains("--smoothing 1 rad/s: the fit counts a sample as moving from ten times")
            && e.contains("joint 1 (")
            && e.contains("joint 2 (")
            && !e.contains("record motion in both directions"),
        "{e}"
    );
    assert!(!out.exists(), "nothing is written on an error");
    let advised = e
        .split("give a smoothing below ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .unwrap_or_else(|| panic!("no smoothing advised: {e}"));
    let o = run(advised);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// A drive chain that contradicts the data, or a dead channel, gave a friction file of
/// zeros (or nonsense) with exit 0 and no word; each is now told: a gear ratio of the
/// wrong sign (the motor encoder moves -0.998 times its link encoder, and both frictions are
/// pulled below 0), a torque constant 1000 times too large, motor positions in degrees,
/// joint torques and currents of zeros.
#[test]
fn a_drive_chain_that_contradicts_the_data_is_told() {
    let dir = folder();
    let (robot, _) = setup(dir.path(), false, true);
    let d = dir.path();
    let run = |config: &str, log: &str| {
        let cfg = write(d, "bad.toml", config);
        let log = write(d, "bad.csv", log);
        let out = d.join("friction.toml");
        let cfg = cfg.to_str().unwrap();
        let o = robid(
            &[
                "friction",
                &robot,
                "--config",
                cfg,
                "--data",
                log.to_str().unwrap(),
            ]
            .into_iter()
            .chain(["-o", out.to_str().unwrap()])
            .collect::<Vec<_>>(),
        );
        // the fit may also fail on what it is given (motor positions in degrees: a
        // Stribeck velocity of 3.7e8 rad/s), after the warning
        stderr(&o)
    };
    let (good, text) = (config(false, true), log(3000, None));
    let sign = good.replace("gear_ratios = [10.0, -20.0]", "gear_ratios = [10.0, 20.0]");
    let e = run(&sign, &text);
    assert!(
        e.contains("joint 2's motor encoder, through its gear ratio, moves -0.99")
            && e.contains("(of the opposite sign: is the gear ratio's sign")
            && e.contains(
                "joint 2: the data pull both its Coulomb and its viscous friction below 0"
            ),
        "{e}"
    );
    let constant = good.replace(
        "torque_constants = [0.1, 0.05]",
        "torque_constants = [100.0, 0.05]",
    );
    let e = run(&constant, &text);
    assert!(e.contains("joint 1: the data pull both"), "{e}");
    // a torque constant of the wrong sign: no friction fits, and the error names the
    // chain's key at its place and what makes the samples (it named neither)
    let negative = good.replace(
        "torque_constants = [0.1, 0.05]",
        "torque_constants = [0.1, -0.05]",
    );
    let e = run(&negative, &text);
    assert!(
        e.contains("bad.toml:12:1: `drive.torque_constants`: joint 2: its friction samples")
            && e.contains("the signs and units of joint 2's torque constant and gear ratio"),
        "{e}"
    );
    // a column of the log replaced: `column` from 1 after the time, by `f(value)`
    let with = |column: usize, f: &dyn Fn(f64) -> f64| -> String {
        let mut lines = text.lines();
        let mut out = lines.next().unwrap().to_string() + "\n";
        for l in lines {
            let mut v: Vec<String> = l.split(',').map(str::to_string).collect();
            v[column] = f(v[column].parse().unwrap()).to_string();
            out += &(v.join(",") + "\n");
        }
        out
    };
    let e = run(&good, &with(3, &f64::to_degrees));
    assert!(
        e.contains("joint 1's motor encoder, through its gear ratio, moves 57.")
            && e.contains("are the motor positions in degrees?"),
        "{e}"
    );
    let e = run(&good, &with(7, &|_| 0.0));
    assert!(
        e.contains("joint 1's joint torque is 0 over the whole record while the joint moves"),
        "{e}"
    );
    let e = run(&good, &with(5, &|_| 0.0));
    assert!(
        e.contains("joint 1's torque is 0 over the whole record while the joint moves"),
        "{e}"
    );
}

#[test]
fn without_temperatures_the_coefficients_are_held_and_said() {
    let dir = folder();
    let (robot, cfg) = setup(dir.path(), false, true);
    let out = dir.path().join("friction.toml");
    let o = robid(&[
        "friction",
        &robot,
        "--config",
        &cfg,
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("no temperature columns") && text.contains("held coulomb_temperature = 0"),
        "{text}"
    );
    let fitted = FrictionModel::read(&out).unwrap();
    assert!(
        fitted
            .joints()
            .iter()
            .all(|f| f.coulomb_temperature == 0.0 && f.viscous_temperature == 0.0)
    );
    // at the log's one temperature the curve is recovered
    let e = curve_error(&fitted, &truth(), [25.0, 25.0]);
    // measured 1.9e-4 of the largest friction
    assert!(e < 0.01, "friction curve off by {e}\n{text}");
}

/// A temperature span too small to tell its coefficients: the table says so with the
/// span to three digits, and every number printed has the table's seven digits at most.
/// It used to read "held coulomb_temperature = 0: the temperature spans
/// 0.32316743358400046 K, less than 1 K".
#[test]
fn what_is_held_is_written_short() {
    let dir = folder();
    let (robot, cfg) = setup(dir.path(), true, true);
    // 30 + 0.32323208 k / n: the span is computed, 0.32316743358400046 K
    write(dir.path(), "log.csv", &log(5000, Some(0.32323208)));
    let out = dir.path().join("friction.toml");
    let o = robid(&[
        "friction",
        &robot,
        "--config",
        &cfg,
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains(
            "  held coulomb_temperature = 0: the temperature spans 0.323 K, less than 1 K: its \
             effect cannot be told from the Coulomb and viscous levels\n"
        ),
        "{text}"
    );
    let (count, number) = most_digits(&text);
    assert!(count <= 7, "{number} has {count} digits: {text}");
    // the file keeps every digit: the reference temperature is the mean of the log's
    let fitted = FrictionModel::read(&out).unwrap();
    let t0 = fitted.joints()[0].reference_temperature;
    assert!(
        t0 > 30.16 && t0 < 30.17 && Num::rounded(t0, 7).0 != t0,
        "{t0}"
    );
}

#[test]
fn incomplete_input_is_a_clear_error() {
    let dir = folder();
    let (robot, cfg) = setup(dir.path(), false, false);
    let out = dir.path().join("friction.toml");
    let run = |cfg: &str, extra: &[&str]| {
        let mut args = vec![
            "friction",
            &robot,
            "--config",
            cfg,
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        let o = robid(&args);
        assert!(!o.status.success());
        assert_eq!(o.status.code(), Some(1));
        let e = stderr(&o);
        assert!(!e.contains("panicked"), "{e}");
        e
    };
    // no [drive.rotor]: the key and the fix
    let e = run(&cfg, &[]);
    assert!(e.contains("drive.rotor") && e.contains("inertia"), "{e}");
    // no joint torque and no --parameters
    let bare = config(false, true).replace("joint_torque = \"tj{}\"\n", "");
    let bare = write(dir.path(), "bare.toml", &bare);
    let e = run(bare.to_str().unwrap(), &[]);
    assert!(
        e.contains("no joint torque") && e.contains("--parameters"),
        "{e}"
    );
    // a data file that is not there, and one without the motor columns
    let e = run(
        write(dir.path(), "rotor.toml", &config(false, true))
            .to_str()
            .unwrap(),
        &["--data", dir.path().join("missing.csv").to_str().unwrap()],
    );
    assert!(e.contains("missing.csv"), "{e}");
    let short = write(
        dir.path(),
        "short.csv",
        "t,q1,q2,i1,i2,tj1,tj2\n0,0,0,0,0,0,0\n0.002,0,0,0,0,0,0\n",
    );
    let e = run(
        dir.path().join("rotor.toml").to_str().unwrap(),
        &["--data", short.to_str().unwrap()],
    );
    assert!(
        e.contains("no column `m1`") && e.contains("source[1].motor_position"),
        "{e}"
    );
    // a negative rotor inertia, at its entry, by friction and identify alike (friction
    // used to accept it and write a model)
    let negative = config(false, true).replace("inertia = [0.4, 0.2]", "inertia = [0.4, -0.2]");
    let negative = write(dir.path(), "negative.toml", &negative);
    let negative = negative.to_str().unwrap();
    let e = run(negative, &[]);
    let at = format!("{negative}:14:17: `drive.rotor.inertia[2]`: joint 2 has -0.2 kg m^2");
    assert!(e.contains(&at) && e.contains("cannot be negative"), "{e}");
    let o = robid(&["identify", &robot, "--config", negative]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains(&at), "{}", stderr(&o));
    // joints that only move forward: said as the joint's samples from the data, not by the
    // library's names (it was "identify_friction `samples`: no velocity reversal")
    let mut forward = String::from("t,q1,q2,m1,m2,i1,i2,tj1,tj2\n");
    for k in 0..2000 {
        let t = k as f64 / 500.0;
        let q = 0.5 * t + 0.2 * t * t;
        let _ = writeln!(
            forward,
            "{t},{q},{q},{},{},{},{},{},{}",
            RATIOS[0] * q,
            RATIOS[1] * q,
            1.0 + (3.0 * t).sin(),
            0.5 + (2.0 * t).cos(),
            (1.7 * t).sin(),
            (1.1 * t).cos()
        );
    }
    let forward = write(dir.path(), "forward.csv", &forward);
    let e = run(
        dir.path().join("rotor.toml").to_str().unwrap(),
        &["--data", forward.to_str().unwrap()],
    );
    assert!(
        e.contains("joint 1: its friction samples from ")
            && e.contains("no velocity reversal")
            && !e.contains("identify_friction"),
        "{e}"
    );
    assert!(!out.exists(), "nothing is written on an error");
}

/// Keys the friction's fit does not apply are said at their place (`[runs]` was dropped
/// without a word: the result was that of the first record alone), each with its own
/// reason (an `[estimation]` was told that a decimation's filter would smear the
/// friction's reversals), and not checked (a `[runs]` of one file, which identify refuses,
/// was refused after the warning); a config without them gets no such warning.
#[test]
fn keys_friction_does_not_apply_are_said() {
    let dir = folder();
    let (robot, cfg) = setup(dir.path(), true, true);
    let text = std::fs::read_to_string(&cfg).unwrap();
    let shared = write(
        dir.path(),
        "shared.toml",
        &format!("{text}\n[runs]\nfiles = [\"log.csv\"]\n[estimation]\nmethod = \"wls\"\n"),
    );
    let line = text.lines().count() + 2;
    for (config, warned) in [(cfg.as_str(), false), (shared.to_str().unwrap(), true)] {
        let out = dir.path().join("friction.toml");
        let o = robid(&[
            "friction",
            &robot,
            "--config",
            config,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let said = format!("shared.toml:{line}:2: `runs` is not applied by `robid friction`");
        assert_eq!(
            stderr(&o).contains(&said),
            warned,
            "{said} in {}",
            stderr(&o)
        );
        let said = format!(
            "shared.toml:{}:2: `estimation` is not applied by `robid friction` (it fits each \
             joint's friction by its own nonlinear least squares)",
            line + 2
        );
        assert_eq!(
            stderr(&o).contains(&said),
            warned,
            "{said} in {}",
            stderr(&o)
        );
        // no decimation given, none spoken of
        assert!(!stderr(&o).contains("decimation"), "{}", stderr(&o));
    }
}

/// Columns identify reads and leaves out of the fit are said at their key: a two-encoder
/// log identified without `[drive.rotor]` fitted the currents as link torques, without a
/// word on the motor encoders, temperatures and joint torques it had read; with the rotor
/// only the temperatures are left (no friction file uses them), and the joint torques,
/// which `robid friction` reads from the same config, are not named.
#[test]
fn identify_names_the_columns_it_reads_and_does_not_use() {
    let dir = folder();
    for (rotor, unused) in [
        (
            false,
            &["motor_position", "temperature", "joint_torque"][..],
        ),
        (true, &["temperature"][..]),
    ] {
        let (robot, cfg) = setup(dir.path(), true, rotor);
        let o = robid(&["identify", &robot, "--config", &cfg]);
        let e = stderr(&o);
        for (role, line) in [
            ("motor_position", 6),
            ("temperature", 9),
            ("joint_torque", 8),
        ] {
            let said = format!("cfg.toml:{line}:1: `source[1].{role}` is read but not used");
            assert_eq!(e.contains(&said), unused.contains(&role), "{said} in {e}");
        }
    }
}
