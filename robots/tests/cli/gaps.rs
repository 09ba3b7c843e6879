//! `robid identify` of a log with gaps in its time stamps
//! (docs/identification.md#gaps-in-the-time-stamps): refused by default, naming the
//! setting; with `[processing] gaps = "split"` identified from its segments, the text
//! report and the JSON saying which segments were used and which left out, for the
//! estimation and a validation log alike; `robid inspect` inspects each segment.

use crate::common;

use std::path::{Path, PathBuf};

use common::{fails_with, folder, robid, stderr, stdout, write};

/// excite and simulate a UR5e log of 30 s at 200 Hz (`t,q1..,tau1..`) in `dir`, and write
/// it with the rows `cut` (0-based ranges) left out as `dir/name`.
fn logs(dir: &Path, cuts: &[(&str, &[[usize; 2]])]) -> Vec<PathBuf> {
    let path = |name: &str| dir.join(name).display().to_string();
    let (traj, data) = (path("traj.csv"), path("data.csv"));
    for args in [
        vec![
            "excite",
            "descriptions/ur5e.toml",
            "-o",
            &traj,
            "--duration",
            "30",
            "--rate",
            "200",
            "--evaluations",
            "200",
        ],
        vec![
            "simulate",
            "descriptions/ur5e.toml",
            "--parameters",
            "parameters/ur5e.toml",
            "--trajectory",
            &traj,
            "--torque-noise",
            "0.2",
            "--quantization",
            "1e-5",
            "--columns",
            "positions",
            "-o",
            &data,
        ],
    ] {
        let o = robid(&args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    }
    let text = std::fs::read_to_string(&data).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap();
    let rows: Vec<&str> = lines.collect();
    cuts.iter()
        .map(|(name, cut)| {
            let mut out = format!("{header}\n");
            for (k, row) in rows.iter().enumerate() {
                if !cut.iter().any(|[a, b]| (*a..*b).contains(&k)) {
                    out.push_str(row);
                    out.push('\n');
                }
            }
            write(dir, name, &out)
        })
        .collect()
}

#[test]
fn a_log_with_gaps_is_identified_from_its_segments() {
    let dir = folder();
    let d = dir.path();
    // 2 s cut out of the middle; in the validation log also a short piece at the end
    let files = logs(
        d,
        &[
            ("gapped.csv", &[[3000, 3400]]),
            ("validation.csv", &[[1000, 1400], [5000, 5980]]),
        ],
    );
    let (gapped, validation) = (
        files[0].display().to_string(),
        files[1].display().to_string(),
    );
    let mapping = "time_column = \"t\"\n[[source]]\nposition = \"q{}\"\ntorque = \"tau{}\"\n\
                   [processing]\nlowpass = { cutoff = \"auto\" }\n";
    let refuse = write(d, "refuse.toml", mapping).display().to_string();
    let split = write(d, "split.toml", &format!("{mapping}gaps = \"split\"\n"))
        .display()
        .to_string();
    let robot = "descriptions/ur5e.toml";

    let o = robid(&["identify", robot, "--data", &gapped, "--config", &refuse]);
    fails_with(
        &o,
        &[
            "gapped.csv:3002: the time stamps jump from 14.995 s to 17 s",
            "set `gaps = \"split\"` in [processing]",
        ],
    );

    let json = d.join("out.json");
    let o = robid(&[
        "identify",
        robot,
        "--data",
        &gapped,
        "--config",
        &split,
        "--validate",
        &validation,
        "--json",
        json.to_str().unwrap(),
    ]);
    let (out, err) = (stdout(&o), stderr(&o));
    assert!(o.status.success(), "{err}");
    for part in [
        "estimation segments of",
        "(1 gap): 2 used, 0 left out",
        "used lines 2 to 3001 (0 to 14.995 s, 3000 samples)",
        "used lines 3002 to 5602 (17 to 30 s, 2601 samples)",
        "validation segments of",
        "(2 gaps): 2 used, 1 left out",
        "left out lines 4602 to 4622 (29.9 to 30 s, 21 samples): 21 samples, fewer than the",
    ] {
        assert!(out.contains(part), "{part}: {out}");
    }
    assert!(
        err.contains("1 of the 3 segments between its gaps left out: lines 4602 to 4622"),
        "{err}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let s = &v["segments"];
    assert_eq!(s["gaps"][0][1], 17.0, "{s}");
    assert_eq!(s["used"][1]["lines"][0], 3002, "{s}");
    assert_eq!(s["used"][1]["seconds"][0], 17.0, "{s}");
    assert_eq!(s["dropped"].as_array().map(Vec::len), Some(0), "{s}");
    let dropped = &v["validation"][0]["segments"]["dropped"][0];
    assert_eq!(dropped["lines"][0], 4602, "{dropped}");
    assert!(dropped["needed"].as_u64().unwrap() > 21, "{dropped}");
    let kinds: Vec<&str> = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|w| w["kind"].as_str())
        .collect();
    assert!(kinds.contains(&"segments_left_out"), "{kinds:?}");
    // the fit is good: the segments were not bridged
    let fit = v["fit"]["relative_error"].as_f64().unwrap();
    assert!(fit < 0.05, "{fit}");

    // inspect cuts the record as identify does and inspects each segment (it refused the
    // config); the JSON is one inspection per segment
    let o = robid(&["inspect", robot, "--data", &gapped, "--config", &split]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    let segments = text.lines().next().unwrap();
    assert!(segments.ends_with("(gaps = \"split\")"), "{text}");
    let count: usize = segments
        .split(": ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(
        text.contains("segment 1 (lines 2 to ")
            && text.contains(&format!("segment {count} (lines ")),
        "{text}"
    );
    assert_eq!(
        text.matches("suggested low-pass cutoff").count(),
        count,
        "{text}"
    );
    let o = robid(&[
        "inspect", robot, "--data", &gapped, "--config", &split, "--json",
    ]);
    let v: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
    assert_eq!(v.as_array().unwrap().len(), count);
    assert_eq!(v[0]["segment"]["lines"][0], 2, "{v}");
    assert!(v[0]["inspection"]["joints"].is_array(), "{v}");
    // the validation log's short piece at the end is left out, as identify leaves it out
    // (the whole inspection failed on its spectrum)
    let o = robid(&["inspect", robot, "--data", &validation, "--config", &split]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("segments too short to inspect: lines ")
            && stderr(&o).contains("samples are needed"),
        "{}",
        stderr(&o)
    );
}
