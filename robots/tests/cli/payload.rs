//! `robid payload` end to end: `robid simulate` of the UR5e carrying a known payload
//! (its reference parameters with the payload added to link 6), then `robid payload` with
//! the reference parameters recovers the payload's mass.

use std::path::Path;

use robid_runtime::feasible::LinkInertial;

use crate::common::{asset, fails_with, folder, most_digits, robid, stderr, stdout, write};

/// A 1.5 kg tool, centre of mass 5 cm out along the flange axis.
fn tool() -> [f64; 10] {
    LinkInertial {
        mass: 1.5,
        com: [0.0, 0.01, 0.05],
        inertia: [[0.003, 0.0, 0.0], [0.0, 0.003, 0.0], [0.0, 0.0, 0.002]],
    }
    .to_standard()
}

/// The UR5e's reference parameter file with `payload` added to link 6.
fn with_payload(payload: &[f64; 10]) -> String {
    let text = std::fs::read_to_string(asset("parameters/ur5e.toml")).unwrap();
    let stems = ["XX", "XY", "XZ", "YY", "YZ", "ZZ", "MX", "MY", "MZ", "M"];
    text.lines()
        .map(|line| {
            let Some((name, value)) = line.split_once(" = ") else {
                return line.to_string();
            };
            match stems.iter().position(|s| format!("{s}6") == name) {
                Some(k) => format!("{name} = {:?}", value.parse::<f64>().unwrap() + payload[k]),
                None => line.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Every joint on its own sine, 20 s at 100 Hz, within the UR5e's limits.
fn trajectory() -> String {
    let mut text = String::from("t");
    for p in ["q", "qd", "qdd"] {
        for j in 1..=6 {
            text.push_str(&format!(",{p}{j}"));
        }
    }
    text.push('\n');
    for k in 0..=2000 {
        let t = 0.01 * k as f64;
        let w = [0.5, 0.7, 0.9, 1.3, 1.7, 2.1];
        let a = [1.0, 0.6, 0.8, 1.2, 1.2, 1.5];
        let q: Vec<f64> = (0..6).map(|j| a[j] * (w[j] * t + j as f64).sin()).collect();
        let qd: Vec<f64> = (0..6)
            .map(|j| a[j] * w[j] * (w[j] * t + j as f64).cos())
            .collect();
        let qdd: Vec<f64> = (0..6).map(|j| -w[j] * w[j] * q[j]).collect();
        text.push_str(&format!("{t}"));
        for v in q.iter().chain(&qd).chain(&qdd) {
            text.push_str(&format!(",{v:e}"));
        }
        text.push('\n');
    }
    text
}

/// `robid payload` of the UR5e with its reference parameters, and `args`.
fn payload(args: &[&str]) -> std::process::Output {
    let mut all = vec![
        "payload",
        "descriptions/ur5e.toml",
        "--parameters",
        "parameters/ur5e.toml",
    ];
    all.extend_from_slice(args);
    robid(&all)
}

/// The mass and its standard deviation that `robid payload` printed, and their line
/// ("mass: 1.500123 +- 4.44e-4 kg").
fn printed_mass(text: &str) -> (f64, f64, &str) {
    let line = text.lines().find(|l| l.starts_with("mass: ")).unwrap();
    let words: Vec<&str> = line.split_whitespace().collect();
    (words[1].parse().unwrap(), words[3].parse().unwrap(), line)
}

/// `robid simulate` of the UR5e carrying [`tool`] along [`trajectory`], with torque noise
/// and `args`, written to `dir`'s `name`.
fn simulate_with_tool(dir: &Path, name: &str, args: &[&str]) -> std::path::PathBuf {
    let params = write(dir, "truth.toml", &with_payload(&tool()));
    let traj = write(dir, "trajectory.csv", &trajectory());
    let data = dir.join(name);
    let mut all = vec![
        "simulate",
        "descriptions/ur5e.toml",
        "--parameters",
        params.to_str().unwrap(),
        "--trajectory",
        traj.to_str().unwrap(),
        "--torque-noise",
        "0.2,0.2,0.1,0.05,0.05,0.02",
        "-o",
        data.to_str().unwrap(),
    ];
    all.extend_from_slice(args);
    let o = robid(&all);
    assert!(o.status.success(), "{}", stderr(&o));
    data
}

#[test]
fn payload_of_a_simulated_ur5e_prints_its_mass_and_writes_toml() {
    let dir = folder();
    let data = simulate_with_tool(dir.path(), "data.csv", &[]);
    let out = dir.path().join("payload.toml");
    let o = payload(&[
        "--data",
        data.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    println!("{text}");
    let (mass, std, line) = printed_mass(&text);
    // Measured: 1.500123 +- 4.44e-4 kg (WLS, 12006 equations, condition number 8.8), the
    // centre of mass (-0.00004, 0.00999, 0.05002) m. Bounds: 3 sigma, twice the measured sigma.
    assert!((mass - 1.5).abs() <= 3.0 * std, "{line}");
    assert!(std < 9e-4, "{line}");
    assert!(text.contains("physically consistent: yes"), "{text}");
    let toml = std::fs::read_to_string(&out).unwrap();
    assert!(toml.contains("[payload]") && toml.contains("[payload.physical]"));
    assert!(
        toml.contains("consistent = true\nverdict = \"consistent\""),
        "{toml}"
    );
    assert!(!stderr(&o).contains("ill-conditioned"), "{}", stderr(&o));
    assert!(!stderr(&o).contains("dead channel") && !stderr(&o).contains("repeat"));
    // the data checks `identify` makes: a sixth torque of zeros (it was "physically
    // consistent: yes" without a word), the file appended to itself (the standard
    // deviations shrank by the square root of 2)
    let text = std::fs::read_to_string(&data).unwrap();
    let tau6 = text
        .lines()
        .next()
        .unwrap()
        .split(',')
        .position(|c| c == "tau6")
        .unwrap();
    let zeroed: String = text
        .lines()
        .enumerate()
        .map(|(k, l)| {
            let mut f: Vec<&str> = l.split(',').collect();
            if k > 0 {
                f[tau6] = "0";
            }
            f.join(",") + "\n"
        })
        .collect();
    let zeroed = write(dir.path(), "zeroed.csv", &zeroed);
    let o = payload(&["--data", zeroed.to_str().unwrap()]);
    let told = "joint 6's torque is 0 over the whole record while the joint moves";
    assert!(stderr(&o).contains(told), "{}", stderr(&o));
    let body: Vec<&str> = text.lines().skip(1).collect();
    let twice = write(
        dir.path(),
        "twice.csv",
        &(text.clone() + &body.join("\n") + "\n"),
    );
    let o = payload(&["--data", twice.to_str().unwrap()]);
    let rows = body.len();
    let told = format!("{rows} rows of {} repeat an earlier row exactly", 2 * rows);
    assert!(stderr(&o).contains(&told), "{}", stderr(&o));
    // four samples of the same data: the fit's uncertain parameters are warned about, as
    // identify warns (it said only whether the payload is physically consistent)
    let text = std::fs::read_to_string(&data).unwrap();
    let few: Vec<&str> = text.lines().take(5).collect();
    let few = write(dir.path(), "few.csv", &(few.join("\n") + "\n"));
    let few_out = dir.path().join("few.toml");
    let o = payload(&[
        "--data",
        few.to_str().unwrap(),
        "-o",
        few_out.to_str().unwrap(),
    ]);
    assert!(
        stderr(&o).contains("relative standard deviation above 100 %"),
        "{}",
        stderr(&o)
    );
    // nor is it consistent: within 3 standard deviations as large as these, every
    // estimate passed the checks ("yes" and `consistent = true` of XX = -6.9e9 kg m^2 and
    // a centre of mass 1.7 km away); so too the first 0.5 s, whose moments were -1.6 kg m^2
    let half: Vec<&str> = text.lines().take(51).collect();
    let half = write(dir.path(), "half.csv", &(half.join("\n") + "\n"));
    let half_out = dir.path().join("half.toml");
    let o_half = payload(&[
        "--data",
        half.to_str().unwrap(),
        "-o",
        half_out.to_str().unwrap(),
    ]);
    for (o, out) in [(&o, &few_out), (&o_half, &half_out)] {
        assert!(o.status.success(), "{}", stderr(o));
        let line = stdout(o)
            .lines()
            .find(|l| l.starts_with("physically consistent: "))
            .unwrap()
            .to_string();
        assert!(
            line.starts_with("physically consistent: undetermined, the data cannot tell: ")
                && line.contains("the data do not determine XX")
                && line.contains("record a longer or more exciting trajectory"),
            "{line}"
        );
        let toml = std::fs::read_to_string(out).unwrap();
        assert!(
            toml.contains("consistent = false\nverdict = \"undetermined\""),
            "{toml}"
        );
    }
    // one sample: six equations for ten parameters, told to give more samples (it was
    // told to use less decimation or fewer parameters, which a payload has not), counted
    // in samples, the file's rows (it said "6 samples, at least 11", equations)
    let one: Vec<&str> = text.lines().take(2).collect();
    let one = write(dir.path(), "one.csv", &(one.join("\n") + "\n"));
    let o = payload(&["--data", one.to_str().unwrap()]);
    fails_with(
        &o,
        &["1 sample, at least 2 are needed", "give more samples"],
    );
    assert!(!stderr(&o).contains("decimation"), "{}", stderr(&o));
    // the header alone: no rows, as `torques` says it (it said "0 samples, at least 11",
    // counting equations, after six warnings of torques reaching -inf)
    let header = write(
        dir.path(),
        "header.csv",
        &(text.lines().next().unwrap().to_string() + "\n"),
    );
    let o = payload(&["--data", header.to_str().unwrap()]);
    fails_with(
        &o,
        &["no rows of joint states (the file has its header alone)"],
    );
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
}

/// A real log holds positions and torques (or currents) alone: with a config, `payload`
/// reads and processes it as `identify` does (here currents scaled to torques,
/// positions low-passed and differentiated) and recovers the payload; without
/// one it refuses the log, pointing to `--config`.
#[test]
fn payload_from_a_log_of_positions_and_currents_with_a_config() {
    let dir = folder();
    let d = dir.path();
    let data = simulate_with_tool(
        d,
        "log.csv",
        &[
            "--columns",
            "positions",
            "--currents",
            "10,10,10,5,5,5",
            "--position-noise",
            "1e-5",
        ],
    );
    let o = payload(&["--data", data.to_str().unwrap()]);
    fails_with(&o, &["log.csv", "--config"]);
    let config = write(
        d,
        "log.toml",
        "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"i{}\"\n\
         [units]\ntorque_scale = [10, 10, 10, 5, 5, 5]\n\
         [processing]\nlowpass = { cutoff = 3.0, order = 4, signals = [\"q\"] }\n",
    );
    let out = d.join("payload.toml");
    let (data, config) = (data.to_str().unwrap(), config.to_str().unwrap());
    let o = payload(&[
        "--data",
        data,
        "--config",
        config,
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    println!("{text}");
    let (mass, std, line) = printed_mass(&text);
    assert!((mass - 1.5).abs() <= 3.0 * std, "{line}");
    assert!(std < 2e-3, "{line}");
    assert!(out.exists());
    assert!(!stderr(&o).contains("is not applied"), "{}", stderr(&o));
    // keys of the robot's own identification are not applied, and said so at their place
    // (a decimation was dropped without a word: the same values for 1, 2 and 10)
    let shared = write(
        d,
        "shared.toml",
        &format!(
            "{}decimation = 10\n[estimation]\nmethod = \"rls\"\n",
            std::fs::read_to_string(config).unwrap()
        ),
    );
    let o = payload(&["--data", data, "--config", shared.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    for (place, key, why) in [
        (
            "9:1",
            "processing.decimation",
            "its least squares take every processed sample",
        ),
        (
            "10:2",
            "estimation",
            "--ols chooses the method, weighted least squares by default",
        ),
    ] {
        let said =
            format!("shared.toml:{place}: `{key}` is not applied by `robid payload` ({why})");
        assert!(stderr(&o).contains(&said), "{said} in {}", stderr(&o));
    }
    // the config is an input: not overwritten by -o
    let o = payload(&["--config", config, "--data", data, "-o", config]);
    assert!(!o.status.success());
    assert!(
        std::fs::read_to_string(config)
            .unwrap()
            .contains("torque_scale")
    );
}

#[test]
fn payload_from_a_robot_at_rest_is_an_error_naming_the_unexcited_parameters() {
    let dir = folder();
    let mut text = String::from("t");
    for p in ["q", "qd", "qdd", "tau"] {
        for j in 1..=6 {
            text.push_str(&format!(",{p}{j}"));
        }
    }
    text.push('\n');
    for k in 0..50 {
        text.push_str(&format!(
            "{},0.1,-1,1,0,0.5,0,0,0,0,0,0,0,0,0,0,0,0,0,1,2,3,0.1,0.1,0.1\n",
            0.01 * k as f64
        ));
    }
    let data = write(dir.path(), "rest.csv", &text);
    let out = dir.path().join("payload.toml");
    let o = payload(&[
        "--data",
        data.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    fails_with(&o, &["rest.csv", "not excited", "XX"]);
    assert!(!out.exists());
}

/// A torque beyond the data files' limit (1e7 N m) is named at its row and column, as
/// `robid identify` names it, before the fit: a 1e308 went into it (in exciting data it
/// ended with "the WLS weights is not finite: the OLS residual overflowed", without a
/// place; in these data at rest, with the rank deficiency).
#[test]
fn payload_names_a_torque_out_of_range_at_its_row() {
    let dir = folder();
    let mut text = String::from("t");
    for p in ["q", "qd", "qdd", "tau"] {
        for j in 1..=6 {
            text.push_str(&format!(",{p}{j}"));
        }
    }
    text.push('\n');
    for k in 0..50 {
        let tau2 = if k == 7 { "1e308" } else { "2" };
        text.push_str(&format!(
            "{},0.1,-1,1,0,0.5,0,0,0,0,0,0,0,0,0,0,0,0,0,1,{tau2},3,0.1,0.1,0.1\n",
            0.01 * k as f64
        ));
    }
    let data = write(dir.path(), "huge.csv", &text);
    let out = dir.path().join("payload.toml");
    let o = payload(&[
        "--data",
        data.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    fails_with(
        &o,
        &["huge.csv:9: column `tau2` is 1e308, outside the range of a joint torque"],
    );
    assert!(!out.exists());
}

/// A payload of data without one: what is printed is written to the table's seven
/// significant digits at most. The mass line used to read "mass: -0.000144 +- 8.20e-4 kg"
/// (-0.000000 for a smaller mass), and the verdict "the mass -0.00014373054988615016 kg
/// is not positive".
#[test]
fn payload_messages_write_computed_values_short() {
    let dir = folder();
    let traj = write(dir.path(), "trajectory.csv", &trajectory());
    let data = dir.path().join("data.csv");
    let o = robid(&[
        "simulate",
        "descriptions/ur5e.toml",
        "--parameters",
        "parameters/ur5e.toml",
        "--trajectory",
        traj.to_str().unwrap(),
        "--torque-noise",
        "0.2,0.2,0.1,0.05,0.05,0.02",
        "-o",
        data.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let printed = |data: &Path| {
        let o = payload(&["--data", data.to_str().unwrap()]);
        assert!(o.status.success(), "{}", stderr(&o));
        stdout(&o)
    };
    let text = printed(&data);
    // no payload: a mass within its uncertainty of zero, whose centre and inertia the data
    // cannot tell, said so (it was "not a body", then "yes, within its uncertainty")
    let verdict = text
        .lines()
        .find(|l| l.starts_with("physically consistent: undetermined, the data cannot tell: "))
        .unwrap_or_else(|| panic!("no payload is not said as such: {text}"));
    assert!(
        verdict.contains(
            // the larger of the classical (0.00044 kg) and the robust deviation
            "3 standard deviations of zero (one is 0.00045 kg): the data may hold no payload"
        ),
        "{verdict}"
    );
    let (count, number) = most_digits(&text);
    assert!(count <= 7, "{number} has {count} digits: {text}");
    // the verdict gives four digits
    let (count, number) = most_digits(verdict);
    assert!(count <= 4, "{number}: {verdict}");
    // without noise the mass is a rounding error (measured -8e-11 kg): written as one, not
    // as -0.000000
    let exact = write(dir.path(), "exact.csv", "");
    let o = robid(&[
        "simulate",
        "descriptions/ur5e.toml",
        "--parameters",
        "parameters/ur5e.toml",
        "--trajectory",
        traj.to_str().unwrap(),
        "-o",
        exact.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = printed(&exact);
    let (value, _, mass) = printed_mass(&text);
    assert!(value != 0.0 && value.abs() < 1e-6, "{mass}");

    let (count, number) = most_digits(&text);
    assert!(count <= 7, "{number} has {count} digits: {text}");
}

/// A robot whose joint torques determine fewer than ten combinations of a payload (the
/// two-link arm: 8) is told so, and the rank said is at most that many: with noisy
/// torques the least squares counted 9 and the message said "rank 9 ... at most 8".
#[test]
fn the_rank_said_is_at_most_what_the_joint_torques_determine() {
    let dir = folder();
    let d = dir.path();
    let path = |name: &str| d.join(name).display().to_string();
    let robot = "tests/fixtures/two_link.toml";
    let parameters = write(
        d,
        "p.toml",
        "[standard]\nZZ1 = 0.5\nM2 = 3.0\nMX2 = 0.6\nXX2 = 0.2\nYY2 = 0.3\nZZ2 = 0.25\n",
    );
    for args in [
        vec![
            "excite",
            robot,
            "--duration",
            "10",
            "--rate",
            "100",
            "-o",
            &path("t.csv"),
        ],
        vec![
            "simulate",
            robot,
            "--parameters",
            parameters.to_str().unwrap(),
            "--trajectory",
            &path("t.csv"),
            "--torque-noise",
            "0.05",
            "-o",
            &path("s.csv"),
        ],
    ] {
        let o = robid(&args);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    let o = robid(&[
        "payload",
        robot,
        "--parameters",
        parameters.to_str().unwrap(),
        "--data",
        &path("s.csv"),
    ]);
    fails_with(
        &o,
        &[
            "rank 8 of the payload's 10 parameters",
            "determine at most 8 combinations of the ten",
        ],
    );
}

/// The description's warnings are printed once: payload read the description twice (for
/// the model and for the limits' check) and printed each of its warnings twice.
#[test]
fn payload_prints_the_descriptions_warnings_once() {
    let dir = folder();
    let text = std::fs::read_to_string("descriptions/ur5e.toml").unwrap();
    // a length in millimetres read as metres, which robid warns of
    let robot = write(
        dir.path(),
        "ur5e_mm.toml",
        &text.replacen("d = 0.1625", "d = 162.5", 1),
    );
    let robot = robot.to_str().unwrap();
    let traj = write(dir.path(), "trajectory.csv", &trajectory());
    let data = dir.path().join("data.csv");
    let o = robid(&[
        "simulate",
        robot,
        "--parameters",
        "parameters/ur5e.toml",
        "--trajectory",
        traj.to_str().unwrap(),
        "--torque-noise",
        "0.1",
        "-o",
        data.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = robid(&[
        "payload",
        robot,
        "--parameters",
        "parameters/ur5e.toml",
        "--data",
        data.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let said = stderr(&o);
    assert_eq!(
        said.matches("longer than an arm's 10 m").count(),
        1,
        "{said}"
    );
}
