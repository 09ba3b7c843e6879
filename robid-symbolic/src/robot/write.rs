//! A robot as the text of a description file (the format `file.rs` reads), which reads
//! back to an equal robot: the way to keep the DH table robid fitted to a URDF, or a
//! robot built in code, as a description.

use super::check::Dh;
use super::{Geometry, JointKind, Limits, Robot, Transform};
use std::fmt::Write;

impl Robot {
    /// The robot as the text of a description file, which [`Robot::from_toml`] reads back
    /// to an equal robot: numbers in the shortest form that reads back to the same `f64`,
    /// exact angles and symbol expressions as written (`"pi/2"`, `"-L3"`), the symbols'
    /// values, `[base]` and `[tool]`, each joint's drive terms and limits, and
    /// `calibrated = true` for a table that was measured (fitted to a URDF, or read with
    /// that key), whose angles near right angles are then taken as written again.
    ///
    /// # Examples
    /// ```
    /// use robid_symbolic::Robot;
    /// let text = "name = \"arm\"\nconvention = \"modified\"\n[[joints]]\nd = 0.3\n\
    ///             [[joints]]\nalpha = \"pi/2\"\na = 0.425\n";
    /// let robot = Robot::from_toml(text, "arm.toml")?;
    /// let written = robot.to_toml();
    /// assert!(written.contains("alpha = \"pi/2\"") && written.contains("a = 0.425"));
    /// assert_eq!(Robot::from_toml(&written, "again.toml")?, robot);
    /// # Ok::<(), robid_symbolic::DescriptionError>(())
    /// ```
    pub fn to_toml(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "name = \"{}\"", self.name);
        let _ = writeln!(out, "convention = \"{}\"", self.convention.as_str());
        if self.measured {
            out.push_str(
                "# measured (fitted to a URDF, or calibrated): angles near right angles as written\n\
                 calibrated = true\n",
            );
        }
        let _ = writeln!(out, "gravity = {}", list(&self.gravity));
        let values: Vec<(&str, f64)> = self
            .symbols
            .iter()
            .filter_map(|(name, value)| Some((name.as_str(), (*value)?)))
            .collect();
        if !values.is_empty() {
            out.push_str("\n[symbols]\n");
            for (name, value) in values {
                let _ = writeln!(out, "{name} = {value:?}");
            }
        }
        for (table, transform) in [("base", &self.base), ("tool", &self.tool)] {
            if let Some(Transform { xyz, rpy }) = transform {
                let _ = write!(
                    out,
                    "\n[{table}]\nxyz = {}\nrpy = {}\n",
                    list(xyz),
                    list(rpy)
                );
            }
        }
        for joint in &self.joints {
            out.push_str("\n[[joints]]\n");
            let kind = match joint.kind {
                JointKind::Revolute => "revolute",
                JointKind::Prismatic => "prismatic",
            };
            let _ = writeln!(out, "type = \"{kind}\"");
            for dh in Dh::ALL {
                let g = dh.of(joint);
                // gamma and b only where a row has them (a plain DH row has neither)
                if matches!(dh, Dh::Gamma | Dh::B) && g.is_zero() {
                    continue;
                }
                let _ = writeln!(out, "{} = {}", dh.key(), value(g));
            }
            let terms: Vec<String> = joint
                .drive
                .terms()
                .map(|t| format!("\"{}\"", t.stem()))
                .collect();
            let _ = writeln!(out, "drive = [{}]", terms.join(", "));
            if let Some(limits) = limits(&joint.limits) {
                let _ = writeln!(out, "limits = {{ {limits} }}");
            }
        }
        out
    }
}

/// A geometric value as TOML: a number in its shortest exact form, an expression as a
/// string.
fn value(g: &Geometry) -> String {
    match g {
        Geometry::Number(n) => format!("{:?}", n.value()),
        Geometry::Expression(_) => {
            format!(
                "\"{}\"",
                g.as_str().replace('\\', "\\\\").replace('"', "\\\"")
            )
        }
    }
}

fn list(values: &[Geometry; 3]) -> String {
    format!(
        "[{}, {}, {}]",
        value(&values[0]),
        value(&values[1]),
        value(&values[2])
    )
}

/// The limits given, as the inside of an inline table.
fn limits(l: &Limits) -> Option<String> {
    let mut parts = Vec::new();
    if let Some([low, high]) = l.position {
        parts.push(format!("position = [{low:?}, {high:?}]"));
    }
    for (key, v) in [
        ("velocity", l.velocity),
        ("acceleration", l.acceleration),
        ("torque", l.torque),
    ] {
        if let Some(v) = v {
            parts.push(format!("{key} = {v:?}"));
        }
    }
    (!parts.is_empty()).then(|| parts.join(", "))
}

#[cfg(test)]
mod tests {
    use crate::robot::urdf::ChainSelection;
    use crate::robot::{Drive, Geometry, Robot, Transform};
    use std::path::Path;

    fn repository(path: &str) -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path)
    }

    fn round_trip(robot: &Robot, what: &str) {
        let text = robot.to_toml();
        let again = Robot::from_toml(&text, what).unwrap_or_else(|e| panic!("{what}: {e}\n{text}"));
        assert_eq!(&again, robot, "{what}:\n{text}");
        assert_eq!(again.to_toml(), text, "{what}: written twice");
    }

    /// Every reference description and test fixture (symbols, gamma and b, a base, a
    /// calibrated table, drive terms), as read and with every drive term.
    #[test]
    fn descriptions_read_back_equal() {
        let mut files = Vec::new();
        for dir in ["robots/descriptions", "robots/tests/fixtures"] {
            for entry in std::fs::read_dir(repository(dir)).unwrap() {
                let path = entry.unwrap().path();
                if path.extension().is_some_and(|e| e == "toml") {
                    files.push(path);
                }
            }
        }
        assert!(files.len() >= 10, "{files:?}");
        for path in files {
            let what = path.display().to_string();
            let Ok(robot) = Robot::from_file(&path) else {
                // parameter files and bounds live beside the fixtures
                assert!(!what.contains("descriptions"), "{what}");
                continue;
            };
            round_trip(&robot, &what);
            round_trip(&robot.clone().with_drive(Drive::ALL), &what);
        }
        // a tool frame (no reference robot has one), with an exact angle and a number
        let ur5e = Robot::from_file(&repository("robots/descriptions/ur5e.toml")).unwrap();
        let tool = Transform {
            xyz: [0.0, 0.02, 0.1].map(|v| Geometry::number(v).unwrap()),
            rpy: [
                Geometry::text("pi/2").unwrap(),
                Geometry::zero(),
                Geometry::number(0.3).unwrap(),
            ],
        };
        let tooled = ur5e.with_tool(Some(tool)).unwrap();
        assert!(
            tooled
                .to_toml()
                .contains("[tool]\nxyz = [0.0, 0.02, 0.1]\nrpy = [\"pi/2\", 0.0, 0.3]")
        );
        round_trip(&tooled, "ur5e with a tool");
    }

    /// The DH tables fitted to the repository's URDFs read back equal, `calibrated = true`
    /// with them: a twist measured a few microradians off a right angle (the UR5's
    /// shoulder axis tilted by 3e-6 rad) is refused without it.
    #[test]
    fn urdf_tables_read_back_equal() {
        let tip = |t: &str| ChainSelection {
            base: None,
            tip: Some(t.to_owned()),
        };
        for (path, selection) in [
            (
                "data/example_robot_data/panda/panda.urdf",
                tip("panda_hand"),
            ),
            (
                "data/example_robot_data/ur5/ur5_robot.urdf",
                ChainSelection::default(),
            ),
            (
                "data/kuka_lwr4/description/kuka_lwr4.urdf",
                ChainSelection::default(),
            ),
            (
                "data/staubli_tx40/description/tx40_mdh_modified.urdf",
                ChainSelection::default(),
            ),
            (
                "data/example_robot_data/kinova/kinova.urdf",
                ChainSelection::default(),
            ),
            (
                "data/example_robot_data/xarm7/xarm7.urdf",
                ChainSelection::default(),
            ),
            (
                "data/example_robot_data/so101/so101.urdf",
                ChainSelection::default(),
            ),
            ("tests/reference/urdf/skewed_arm.urdf", tip("payload")),
        ] {
            let text = std::fs::read_to_string(repository(path)).unwrap();
            let chain =
                Robot::from_urdf(&text, path, &selection).unwrap_or_else(|e| panic!("{path}: {e}"));
            round_trip(&chain.robot, path);
        }
        let ur5 = "data/example_robot_data/ur5/ur5_robot.urdf";
        let text = std::fs::read_to_string(repository(ur5)).unwrap();
        let tilted = text.replacen("<axis xyz=\"0 1 0\"/>", "<axis xyz=\"0.000003 1 0\"/>", 1);
        assert_ne!(tilted, text, "the UR5's shoulder axis");
        let chain = Robot::from_urdf(&tilted, ur5, &ChainSelection::default()).unwrap();
        round_trip(&chain.robot, "tilted UR5");
        let written = chain.robot.to_toml().replace("calibrated = true\n", "");
        let error = Robot::from_toml(&written, "typed.toml")
            .unwrap_err()
            .to_string();
        assert!(error.contains("rad from"), "{error}");
    }
}
