//! Writing a solution: a TOML parameter file (a `[standard]` table that `robid torques`
//! reads, plus per link mass, centre of mass and inertia about it) and URDF `<inertial>`
//! elements.

use std::f64::consts::PI;
use std::fmt::Write;

use nalgebra::{Matrix3, Rotation3};

use super::solution::Solution;

/// The solution as TOML: `[standard]` (name = value) and one `[[links]]` table per link
/// with `mass`, `com` and `inertia` (about the centre of mass, link-frame axes).
pub fn to_toml(solution: &Solution, robot: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Physically consistent link parameters of {robot} (method {}).",
        solution.method.name()
    );
    let _ = writeln!(
        s,
        "# chi^2 = {:.6e} over {} base parameters, max |z| = {:.4} (|z| <= 1: within one std); {:.3} s.",
        solution.chi2,
        solution.base.len(),
        solution.max_normalized_residual(),
        solution.seconds
    );
    if !solution.dont_care.is_empty() {
        let _ = writeln!(
            s,
            "# Not from the data (no effect on the dynamics), {}.",
            solution.dont_care_note()
        );
    }
    for v in &solution.violations {
        let _ = writeln!(s, "# bound not met: {v}");
    }
    for v in &solution.at_bounds {
        let _ = writeln!(s, "# at a bound: {v}");
    }
    for v in &solution.implausible {
        let _ = writeln!(s, "# warning: {v}");
    }
    if !solution.determined.is_empty() {
        // a parameter no prior pulls and no datum fixes is 0 too: not the prior's
        let unpulled = if solution.unpulled.is_empty() {
            ""
        } else {
            "; 0 for those no prior pulls (above): the solver's, within the constraints"
        };
        let _ = writeln!(
            s,
            "# Share determined by the data (1) rather than the prior (0), per link{unpulled}:"
        );
        for j in 0..solution.links.len() {
            let share = |stems: &[&str]| {
                let values: Vec<f64> = stems
                    .iter()
                    .filter_map(|stem| {
                        let name = format!("{stem}{}", j + 1);
                        let i = solution.names.iter().position(|n| *n == name)?;
                        solution.determined.get(i).copied()
                    })
                    .collect();
                let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                if (hi - lo).abs() < 0.005 {
                    format!("{lo:.2}")
                } else {
                    format!("{lo:.2}-{hi:.2}")
                }
            };
            let _ = writeln!(
                s,
                "#   link {}: mass {}, first moments {}, inertia {}",
                j + 1,
                share(&["M"]),
                share(&["MX", "MY", "MZ"]),
                share(&["XX", "XY", "XZ", "YY", "YZ", "ZZ"])
            );
        }
    }
    let (standard, extra): (Vec<_>, Vec<_>) = solution
        .names
        .iter()
        .zip(&solution.standard)
        .partition(|(n, _)| solution.is_chain_parameter(n));
    let _ = writeln!(s, "\n[standard]");
    for (n, v) in standard {
        let _ = writeln!(s, "{n} = {v:e}");
    }
    if !extra.is_empty() {
        // not the description's parameters: a [standard] table with them is refused by
        // every reader of the robot's parameters
        let _ = writeln!(
            s,
            "\n# The identification config's extra columns (not parameters of the description;\n\
             # readers of this file take [standard] and pass over this table).\n[extra]"
        );
        for (n, v) in extra {
            let _ = writeln!(s, "{n} = {v:e}");
        }
    }
    for (j, link) in solution.links.iter().enumerate() {
        let _ = writeln!(s, "\n[[links]]\nlink = {}", j + 1);
        let _ = writeln!(
            s,
            "pseudo_inertia_min_eigenvalue = {:e}",
            solution.min_eigenvalues[j]
        );
        match link {
            Some(l) => {
                let _ = writeln!(s, "mass = {:e}", l.mass);
                let _ = writeln!(s, "com = [{:e}, {:e}, {:e}]", l.com[0], l.com[1], l.com[2]);
                let rows: Vec<String> = l
                    .inertia
                    .iter()
                    .map(|r| format!("[{:e}, {:e}, {:e}]", r[0], r[1], r[2]))
                    .collect();
                let _ = writeln!(s, "inertia = [{}]", rows.join(", "));
            }
            None => {
                let _ = writeln!(s, "mass = 0.0");
            }
        }
    }
    s
}

/// One joint of the chain a URDF is written for, with what the description knows of it
/// (`robid_symbolic::Robot::joint_placements` gives the poses).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UrdfJoint {
    /// Prismatic (else revolute).
    pub prismatic: bool,
    /// The joint's frame (joint variable at zero, z its axis) in the previous joint's
    /// frame (the base's for the first), a 4x4 homogeneous transform, row-major.
    pub origin: [[f64; 4]; 4],
    /// The link's DH frame (in which the solution's values are) in the joint's frame.
    pub link_frame: [[f64; 4]; 4],
    /// Lower and upper position, if known.
    pub position: Option<[f64; 2]>,
    /// Largest velocity, if known.
    pub velocity: Option<f64>,
    /// Largest torque or force, if known.
    pub effort: Option<f64>,
}

/// `xyz` and `rpy` (URDF's fixed-axis roll, pitch, yaw: R = Rz(yaw) Ry(pitch) Rx(roll)) of
/// a pose.
fn xyz_rpy(pose: &[[f64; 4]; 4]) -> String {
    let r = Matrix3::from_fn(|i, k| pose[i][k]);
    let (roll, pitch, yaw) = Rotation3::from_matrix_unchecked(r).euler_angles();
    // + 0.0 turns a negative zero into zero (it was written `-0e0`)
    let [x, y, z, roll, pitch, yaw] =
        [pose[0][3], pose[1][3], pose[2][3], roll, pitch, yaw].map(|v| v + 0.0);
    format!("xyz=\"{x:e} {y:e} {z:e}\" rpy=\"{roll:e} {pitch:e} {yaw:e}\"")
}

/// The solution as a complete URDF robot: a base link, one link per joint carrying its
/// `<inertial>` (mass, centre of mass, inertia about it, placed by the link's DH frame)
/// and the joints from the description's geometry (`joints`, one per link), with the
/// limits it gives. A revolute joint without position limits is `continuous`; a prismatic
/// one without them has a `<limit>` without `lower` and `upper` (URDF's default 0 and 0,
/// which robid's reader takes for no limits; a range such as +-1e9 m would be refused
/// by it), said in a comment. The first joint's origin is in
/// `base_link`, the world frame (the description's base transform is part of it). With
/// `tool`, the pose of the description's tool frame in the last joint's frame
/// (`robid_symbolic::Robot::tool_placement`), a massless link `tool` hangs from the last
/// link on a fixed joint `tool_joint`. `gravity` is the description's, in the world frame:
/// a URDF has none of its own, its readers take -z of the root link, so gravity along
/// another direction puts a root link `world` above `base_link`, on a fixed joint turning
/// that direction to -z (a robot on a wall, or a planar arm with gravity in its plane, kept
/// its gravity only for robid; read back, it lost it).
pub fn to_urdf(
    solution: &Solution,
    robot: &str,
    joints: &[UrdfJoint],
    tool: Option<&[[f64; 4]; 4]>,
    gravity: [f64; 3],
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        s,
        "<!-- {robot}: physically consistent link parameters (robid feasible, method {}); \
         each link frame is its joint's frame. -->",
        solution.method.name()
    );
    let _ = writeln!(s, "<robot name=\"{robot}\">");
    if let Some(turn) = gravity_turn(gravity) {
        let _ = writeln!(
            s,
            "  <!-- the description's gravity [{:e}, {:e}, {:e}] m/s^2 in base_link: this \
             fixed joint turns it to -z of `world`, where URDF readers put gravity -->",
            gravity[0], gravity[1], gravity[2]
        );
        let _ = writeln!(s, "  <link name=\"world\"/>");
        let _ = writeln!(s, "  <joint name=\"world_joint\" type=\"fixed\">");
        let _ = writeln!(s, "    <parent link=\"world\"/>");
        let _ = writeln!(s, "    <child link=\"base_link\"/>");
        let _ = writeln!(s, "    <origin {}/>", xyz_rpy(&turn));
        let _ = writeln!(s, "  </joint>");
    }
    let magnitude = gravity.iter().map(|g| g * g).sum::<f64>().sqrt();
    if (magnitude - STANDARD_GRAVITY).abs() > 1e-9 * STANDARD_GRAVITY {
        let _ = writeln!(
            s,
            "  <!-- the description's gravity is {magnitude:e} m/s^2; a URDF reader applies \
             its own (robid's URDF reader {STANDARD_GRAVITY}) -->"
        );
    }
    let _ = writeln!(s, "  <link name=\"base_link\"/>");
    for (j, link) in solution.links.iter().enumerate() {
        let (m, c, i) = match link {
            Some(l) => (l.mass, l.com, l.inertia),
            None => (0.0, [0.0; 3], [[0.0; 3]; 3]),
        };
        let frame = joints.get(j).map_or(IDENTITY, |joint| joint.link_frame);
        // the centre of mass in the joint's frame, the axes those of the DH frame
        let mut at = frame;
        for (r, row) in at.iter_mut().enumerate().take(3) {
            row[3] = frame[r][3] + (0..3).map(|k| frame[r][k] * c[k]).sum::<f64>();
        }
        let _ = writeln!(s, "  <link name=\"link{}\">", j + 1);
        let _ = writeln!(s, "    <inertial>");
        let _ = writeln!(s, "      <origin {}/>", xyz_rpy(&at));
        let _ = writeln!(s, "      <mass value=\"{m:e}\"/>");
        let _ = writeln!(
            s,
            "      <inertia ixx=\"{:e}\" ixy=\"{:e}\" ixz=\"{:e}\" iyy=\"{:e}\" iyz=\"{:e}\" izz=\"{:e}\"/>",
            i[0][0], i[0][1], i[0][2], i[1][1], i[1][2], i[2][2]
        );
        let _ = writeln!(s, "    </inertial>");
        let _ = writeln!(s, "  </link>");
    }
    for (j, joint) in joints.iter().enumerate().take(solution.links.len()) {
        let kind = match (joint.prismatic, joint.position) {
            (true, _) => "prismatic",
            (false, Some(_)) => "revolute",
            (false, None) => "continuous",
        };
        let parent = if j == 0 {
            "base_link".to_owned()
        } else {
            format!("link{j}")
        };
        let _ = writeln!(s, "  <joint name=\"joint{}\" type=\"{kind}\">", j + 1);
        let _ = writeln!(s, "    <parent link=\"{parent}\"/>");
        let _ = writeln!(s, "    <child link=\"link{}\"/>", j + 1);
        let _ = writeln!(s, "    <origin {}/>", xyz_rpy(&joint.origin));
        let _ = writeln!(s, "    <axis xyz=\"0 0 1\"/>");
        let effort = joint.effort.unwrap_or(0.0);
        let velocity = joint.velocity.unwrap_or(0.0);
        if joint.effort.is_none() || joint.velocity.is_none() {
            let _ = writeln!(s, "    <!-- {} -->", robid_core::URDF_NO_LIMIT_NOTE);
        }
        match (kind, joint.position) {
            (_, Some([lower, upper])) => {
                let _ = writeln!(
                    s,
                    "    <limit lower=\"{lower:e}\" upper=\"{upper:e}\" effort=\"{effort:e}\" velocity=\"{velocity:e}\"/>"
                );
            }
            ("prismatic", None) => {
                let _ = writeln!(
                    s,
                    "    <!-- the description gives no position limits: lower and upper are left out (0 and 0, no limits for robid) -->\n    <limit effort=\"{effort:e}\" velocity=\"{velocity:e}\"/>"
                );
            }
            _ if joint.effort.is_some() || joint.velocity.is_some() => {
                let _ = writeln!(
                    s,
                    "    <limit effort=\"{effort:e}\" velocity=\"{velocity:e}\"/>"
                );
            }
            _ => {}
        }
        let _ = writeln!(s, "  </joint>");
    }
    let last = solution.links.len().min(joints.len());
    if let Some(pose) = tool
        && last > 0
    {
        let _ = writeln!(s, "  <link name=\"tool\"/>");
        let _ = writeln!(s, "  <joint name=\"tool_joint\" type=\"fixed\">");
        let _ = writeln!(s, "    <parent link=\"link{last}\"/>");
        let _ = writeln!(s, "    <child link=\"tool\"/>");
        let _ = writeln!(s, "    <origin {}/>", xyz_rpy(pose));
        let _ = writeln!(s, "  </joint>");
    }
    let _ = writeln!(s, "</robot>");
    s
}

/// The gravity robid's URDF reader (and most others) applies, m/s^2: a URDF carries none.
pub const STANDARD_GRAVITY: f64 = 9.81;

/// The pose of `base_link` in a root frame whose -z is along `gravity` (given in
/// `base_link`): the smallest turn taking its direction to -z, a half turn about x when it
/// points up; `None` when it is along -z already, or zero.
fn gravity_turn(gravity: [f64; 3]) -> Option<[[f64; 4]; 4]> {
    let g = nalgebra::Vector3::from(gravity);
    let norm = g.norm();
    if norm == 0.0 || !norm.is_finite() {
        return None;
    }
    let down = -nalgebra::Vector3::z();
    let u = g / norm;
    if (u - down).norm() <= 1e-12 {
        return None;
    }
    let turn = Rotation3::rotation_between(&u, &down)
        .unwrap_or_else(|| Rotation3::from_axis_angle(&nalgebra::Vector3::x_axis(), PI));
    let mut pose = IDENTITY;
    for (i, row) in pose.iter_mut().enumerate().take(3) {
        for (k, x) in row.iter_mut().enumerate().take(3) {
            *x = turn[(i, k)];
        }
    }
    Some(pose)
}

const IDENTITY: [[f64; 4]; 4] = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasible::fixture::{link, problem, target};
    use crate::feasible::{Bounds, LinkInertial, Method};

    /// Gravity along -z, where a URDF reader puts it.
    const G: [f64; 3] = [0.0, 0.0, -9.81];

    fn solution() -> Solution {
        let t = target(link(), 0.1);
        let mut off = t;
        off[9] += 0.002;
        let mut s = Solution::assemble(
            &problem(&t),
            &Bounds::wide(1),
            Method::Interior,
            off.to_vec(),
            std::time::Duration::from_millis(250),
        )
        .unwrap();
        s.dont_care = vec!["XY1".into(), "YZ1".into()];
        s.violations = vec!["link 1: mass 2 outside [0.0, 1.9]".into()];
        s.at_bounds = vec!["link 1: mass 2 at its upper bound 2".into()];
        s.implausible = vec!["link 1: no body of its size".into()];
        s.determined = vec![0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.2, 0.9, 0.4, 1.0, 1.0];
        s
    }

    #[test]
    fn the_toml_has_the_summary_the_standard_table_and_the_links() {
        let s = solution();
        let text = to_toml(&s, "arm");
        let z = s.max_normalized_residual();
        for want in [
            "# Physically consistent link parameters of arm (method interior-point).\n".to_string(),
            format!("# chi^2 = {:.6e} over 11 base parameters, max |z| = {z:.4} (|z| <= 1: within one std); 0.250 s.\n", s.chi2),
            "# Not from the data (no effect on the dynamics), values from the prior (the default prior where none is given), or the nearest to them that the physical constraints and bounds allow: XY1 YZ1.\n".into(),
            "# bound not met: link 1: mass 2 outside [0.0, 1.9]\n".into(),
            "# at a bound: link 1: mass 2 at its upper bound 2\n".into(),
            "# warning: link 1: no body of its size\n".into(),
            "# Share determined by the data (1) rather than the prior (0), per link:\n".into(),
            "#   link 1: mass 1.00, first moments 0.20-0.90, inertia 0.50\n".into(),
            "\n[standard]\nXX1 = 3e-2\nXY1 = 0e0\n".into(),
            "M1 = 2.002e0\nIa1 = 1e-1\n".into(),
            "\n[[links]]\nlink = 1\npseudo_inertia_min_eigenvalue = ".into(),
            "mass = 2.002e0\ncom = [0e0, 0e0, 0e0]\ninertia = [[3e-2, 0e0, 0e0], [0e0, 2e-2, 0e0], [0e0, 0e0, 1.5e-2]]\n".into(),
        ] {
            assert!(text.contains(&want), "{want:?} not in\n{text}");
        }
        // the values read back as written
        let table: toml::Table = toml::from_str(&text).unwrap();
        for (n, v) in s.names.iter().zip(&s.standard) {
            assert_eq!(table["standard"][n.as_str()].as_float(), Some(*v), "{n}");
        }
        // without the optional parts, and a massless link
        let mut bare = s.clone();
        bare.dont_care.clear();
        bare.violations.clear();
        bare.at_bounds.clear();
        bare.implausible.clear();
        bare.determined.clear();
        bare.links[0] = None;
        let text = to_toml(&bare, "arm");
        for absent in [
            "Not from the data",
            "bound not met",
            "at a bound",
            "warning",
            "Share",
            "com =",
        ] {
            assert!(!text.contains(absent), "{absent} in\n{text}");
        }
        assert!(text.ends_with("mass = 0.0\n"), "{text}");
    }

    /// Parameters that no prior pulls (`--prior-weight 0`) are not said to be the prior's:
    /// the note names them apart, after those a prior does pull.
    #[test]
    fn unpulled_values_are_not_called_the_priors() {
        let mut s = solution();
        s.unpulled = vec!["YZ1".into()];
        let text = to_toml(&s, "arm");
        let want = "# Not from the data (no effect on the dynamics), values from the prior (the \
                    default prior where none is given), or the nearest to them that the physical \
                    constraints and bounds allow: XY1; values that no prior pulls (its weight is \
                    0), so wherever the solver stopped within the physical constraints and \
                    bounds, not the prior's (a prior weight above 0 or --bounds settle them): \
                    YZ1.\n";
        assert!(text.contains(want), "{want:?} not in\n{text}");
        // the shares' 0 is not the prior's either
        let shares = "rather than the prior (0), per link; 0 for those no prior pulls (above): \
                      the solver's, within the constraints:\n";
        assert!(!s.determined.is_empty() && text.contains(shares), "{text}");
        let pulled = to_toml(&solution(), "arm");
        assert!(
            pulled.contains("rather than the prior (0), per link:\n"),
            "{pulled}"
        );
        s.unpulled = s.dont_care.clone();
        let text = to_toml(&s, "arm");
        assert!(!text.contains("from the prior"), "{text}");
        assert!(
            text.contains(
                "not the prior's (a prior weight above 0 or --bounds settle them): XY1 YZ1.\n"
            ),
            "{text}"
        );
    }

    /// Shares that differ by less than 0.005 show as one value, by 0.005 or more as a
    /// range.
    #[test]
    fn the_shares_show_a_range_from_half_a_percent_on() {
        let mut s = solution();
        s.determined = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.005, 0.3, 0.304, 0.3, 1.0, 1.0];
        let text = to_toml(&s, "arm");
        let want = "#   link 1: mass 1.00, first moments 0.30, inertia 0.00-0.01\n";
        assert!(text.contains(want), "{want:?} not in\n{text}");
    }

    fn pose(yaw: f64, xyz: [f64; 3]) -> [[f64; 4]; 4] {
        let (s, c) = yaw.sin_cos();
        [
            [c, -s, 0.0, xyz[0]],
            [s, c, 0.0, xyz[1]],
            [0.0, 0.0, 1.0, xyz[2]],
            [0.0, 0.0, 0.0, 1.0],
        ]
    }

    /// Links carry their inertials placed by the link frames, joints their kinds and
    /// limits, and a tool hangs from the last link.
    #[test]
    fn the_urdf_places_inertials_and_gives_each_joint_its_kind() {
        let mut s = solution();
        let body = LinkInertial {
            mass: 1.5,
            com: [0.1, 0.0, 0.0],
            inertia: [[0.01, 0.001, 0.0], [0.001, 0.02, 0.002], [0.0, 0.002, 0.03]],
        };
        s.links = vec![Some(body), None, Some(body)];
        let yaw = std::f64::consts::FRAC_PI_2;
        let joint = UrdfJoint {
            prismatic: false,
            origin: pose(0.0, [0.0, 0.0, 0.3]),
            link_frame: pose(yaw, [0.0, 0.0, 0.05]),
            position: Some([-1.0, 2.0]),
            velocity: Some(3.0),
            effort: Some(40.0),
        };
        let joints = [
            joint,
            UrdfJoint {
                position: None,
                effort: None,
                ..joint
            },
            UrdfJoint {
                prismatic: true,
                position: None,
                ..joint
            },
        ];
        let tool = pose(0.0, [0.0, 0.0, 0.1]);
        let urdf = to_urdf(&s, "arm", &joints, Some(&tool), G);
        for want in [
            "<robot name=\"arm\">\n  <link name=\"base_link\"/>\n  <link name=\"link1\">\n",
            // the centre of mass (0.1, 0, 0) of the link frame turned by 90 degrees: y
            "<origin xyz=\"6.123233995736766e-18 1e-1 5e-2\" rpy=\"0e0 0e0 1.5707963267948966e0\"/>\n      <mass value=\"1.5e0\"/>\n",
            "<inertia ixx=\"1e-2\" ixy=\"1e-3\" ixz=\"0e0\" iyy=\"2e-2\" iyz=\"2e-3\" izz=\"3e-2\"/>",
            "<link name=\"link2\">\n    <inertial>\n      <origin xyz=\"0e0 0e0 5e-2\"",
            "<mass value=\"0e0\"/>",
            "<joint name=\"joint1\" type=\"revolute\">\n    <parent link=\"base_link\"/>\n    <child link=\"link1\"/>\n    <origin xyz=\"0e0 0e0 3e-1\" rpy=\"0e0 0e0 0e0\"/>\n    <axis xyz=\"0 0 1\"/>\n    <limit lower=\"-1e0\" upper=\"2e0\" effort=\"4e1\" velocity=\"3e0\"/>\n  </joint>",
            "<joint name=\"joint2\" type=\"continuous\">\n    <parent link=\"link1\"/>",
            "<!-- 0: the description gives no torque or no velocity limit -->\n    <limit effort=\"0e0\" velocity=\"3e0\"/>",
            "<joint name=\"joint3\" type=\"prismatic\">\n    <parent link=\"link2\"/>",
            "<!-- the description gives no position limits: lower and upper are left out (0 and 0, no limits for robid) -->\n    <limit effort=\"4e1\" velocity=\"3e0\"/>",
            "<joint name=\"tool_joint\" type=\"fixed\">\n    <parent link=\"link3\"/>\n    <child link=\"tool\"/>\n    <origin xyz=\"0e0 0e0 1e-1\"",
        ] {
            assert!(urdf.contains(want), "{want:?} not in\n{urdf}");
        }
        assert_eq!(urdf.matches("<limit").count(), 3, "{urdf}");
        assert!(urdf.ends_with("</robot>\n"));
        // a revolute joint with no limit at all has no <limit>, and no tool without a pose
        let free = UrdfJoint {
            position: None,
            effort: None,
            velocity: None,
            ..joint
        };
        let urdf = to_urdf(&s, "arm", &[free], None, G);
        assert!(!urdf.contains("<limit") && !urdf.contains("tool"), "{urdf}");
        assert_eq!(urdf.matches("<joint ").count(), 1);
        // no joints: the inertials stay in their own frames
        let urdf = to_urdf(&s, "arm", &[], Some(&tool), G);
        assert!(
            urdf.contains("<origin xyz=\"1e-1 0e0 0e0\" rpy=\"0e0 0e0 0e0\"/>"),
            "{urdf}"
        );
        assert!(!urdf.contains("<joint") && !urdf.contains("tool"), "{urdf}");
    }

    /// Gravity off -z puts a root `world` above `base_link`, turned so that the gravity is
    /// -z of it (a quarter turn about x for -y, a half turn for +z); along -z, or zero,
    /// nothing; a magnitude other than 9.81 m/s^2 is said in a comment.
    #[test]
    fn gravity_off_the_vertical_turns_a_root_link() {
        for (g, angle) in [([0.0, -9.81, 0.0], PI / 2.0), ([0.0, 0.0, 9.81], PI)] {
            let turn = gravity_turn(g).unwrap();
            let r = Matrix3::from_fn(|i, k| turn[i][k]);
            let down = r * nalgebra::Vector3::from(g);
            assert!(
                (down - nalgebra::Vector3::new(0.0, 0.0, -9.81)).norm() < 1e-12,
                "{g:?}"
            );
            let rotation = Rotation3::from_matrix_unchecked(r);
            assert!((rotation.angle() - angle).abs() < 1e-12, "{g:?}");
        }
        assert!(gravity_turn(G).is_none() && gravity_turn([0.0; 3]).is_none());
        let s = solution();
        let urdf = to_urdf(&s, "arm", &[], None, [0.0, -1.62, 0.0]);
        assert!(urdf.contains("<link name=\"world\"/>"), "{urdf}");
        assert!(urdf.contains("gravity is 1.62e0 m/s^2"), "{urdf}");
        let plain = to_urdf(&s, "arm", &[], None, G);
        assert!(
            !plain.contains("world") && !plain.contains("gravity"),
            "{plain}"
        );
    }
}
