//! Writing a solution: a TOML parameter file (a `[standard]` table that `robid torques`
//! reads, plus per link mass, centre of mass and inertia about it) and URDF `<inertial>`
//! elements.

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
            "# No effect on the dynamics (don't-care values): {}.",
            solution.dont_care.join(" ")
        );
    }
    for v in &solution.violations {
        let _ = writeln!(s, "# bound not met: {v}");
    }
    for v in &solution.at_bounds {
        let _ = writeln!(s, "# at a bound: {v}");
    }
    if !solution.determined.is_empty() {
        let _ = writeln!(
            s,
            "# Share determined by the data (1) rather than the prior (0), per link:"
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
    let _ = writeln!(s, "\n[standard]");
    for (n, v) in solution.names.iter().zip(&solution.standard) {
        let _ = writeln!(s, "{n} = {v:e}");
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
    format!(
        "xyz=\"{:e} {:e} {:e}\" rpy=\"{roll:e} {pitch:e} {yaw:e}\"",
        pose[0][3], pose[1][3], pose[2][3]
    )
}

/// The solution as a complete URDF robot: a base link, one link per joint carrying its
/// `<inertial>` (mass, centre of mass, inertia about it, placed by the link's DH frame)
/// and the joints from the description's geometry (`joints`, one per link), with the
/// limits it gives. A revolute joint without position limits is `continuous`; a prismatic
/// one without them gets +-1e9 m, said in a comment. The first joint's origin is in
/// `base_link`, the world frame (the description's base transform is part of it). With
/// `tool`, the pose of the description's tool frame in the last joint's frame
/// (`robid_symbolic::Robot::tool_placement`), a massless link `tool` hangs from the last
/// link on a fixed joint `tool_joint`.
pub fn to_urdf(
    solution: &Solution,
    robot: &str,
    joints: &[UrdfJoint],
    tool: Option<&[[f64; 4]; 4]>,
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
            let _ = writeln!(
                s,
                "    <!-- 0: the description gives no torque or no velocity limit -->"
            );
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
                    "    <!-- the description gives no position limits -->\n    <limit lower=\"-1e9\" upper=\"1e9\" effort=\"{effort:e}\" velocity=\"{velocity:e}\"/>"
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

const IDENTITY: [[f64; 4]; 4] = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];
