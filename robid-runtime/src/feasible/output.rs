//! Writing a solution: a TOML parameter file (a `[standard]` table that `robid torques`
//! reads, plus per link mass, centre of mass and inertia about it) and URDF `<inertial>`
//! elements.

use std::fmt::Write;

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

/// The solution as URDF `<inertial>` elements, one per link, each preceded by a comment
/// naming the link. The origin is the centre of mass in the link's DH frame; if the URDF's
/// link frames differ from the DH frames, transform accordingly.
pub fn to_urdf(solution: &Solution, robot: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<!-- Physically consistent inertial elements of {robot} (method {}), in the DH link frames. -->",
        solution.method.name()
    );
    for (j, link) in solution.links.iter().enumerate() {
        let _ = writeln!(s, "<!-- link {} -->", j + 1);
        let (m, c, i) = match link {
            Some(l) => (l.mass, l.com, l.inertia),
            None => (0.0, [0.0; 3], [[0.0; 3]; 3]),
        };
        let _ = writeln!(s, "<inertial>");
        let _ = writeln!(
            s,
            "  <origin xyz=\"{:e} {:e} {:e}\" rpy=\"0 0 0\"/>",
            c[0], c[1], c[2]
        );
        let _ = writeln!(s, "  <mass value=\"{m:e}\"/>");
        let _ = writeln!(
            s,
            "  <inertia ixx=\"{:e}\" ixy=\"{:e}\" ixz=\"{:e}\" iyy=\"{:e}\" iyz=\"{:e}\" izz=\"{:e}\"/>",
            i[0][0], i[0][1], i[0][2], i[1][1], i[1][2], i[2][2]
        );
        let _ = writeln!(s, "</inertial>");
    }
    s
}
