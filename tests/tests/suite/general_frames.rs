//! Khalil and Kleinfinger's general frames and the base transform
//! (docs/conventions.md#khalil-kleinfinger-general-frames,
//! docs/conventions.md#base-and-tool-frames) against the independent RNEA of `tests::rnea`,
//! which lays the chain out in the world frame from homogeneous transforms and uses gravity
//! as given, and two known answers: Rz(theta_j) Tz(d_j) Rz(gamma_(j+1)) Tz(b_(j+1)) =
//! Rz(theta_j + gamma_(j+1)) Tz(d_j + b_(j+1)), so a general table is a DH table whose
//! theta_j and d_j absorb the next row's gamma and b (link j's parameters expressed in the
//! frame turned by gamma_(j+1) and shifted by b_(j+1)); and the first row's gamma and b are
//! a base transform.

use robid_runtime::rng::Rng;
use robid_symbolic::{Derivation, Drive, Robot};
use tests::rnea::{
    Chain, H4, express_in_parent, h_identity, homogeneous_product, links_from_standard, rot_z,
    standard_from_links,
};
use tests::state::{bind, close, random_parameters, random_state, regressor_times};

/// See rnea_agrees.rs.
const RELATIVE: f64 = 1e-9;

/// One random table row: kind, gamma, b, alpha, a, d, theta (as written in TOML).
struct Row {
    prismatic: bool,
    values: [String; 6],
}

fn angle(rng: &mut Rng) -> String {
    match rng.below(5) {
        0 => "0".to_owned(),
        1 => "\"pi/2\"".to_owned(),
        2 => "\"-pi/2\"".to_owned(),
        3 => "\"pi\"".to_owned(),
        _ => format!("{:.3}", rng.uniform(-3.0, 3.0)),
    }
}

fn length(rng: &mut Rng) -> String {
    if rng.below(3) == 0 {
        "0".to_owned()
    } else {
        format!("{:.3}", rng.uniform(0.05, 0.5) * [-1.0, 1.0][rng.below(2)])
    }
}

fn rows(rng: &mut Rng, dof: usize) -> Vec<Row> {
    (0..dof)
        .map(|_| Row {
            prismatic: rng.below(4) == 0,
            values: [
                angle(rng),
                length(rng),
                angle(rng),
                length(rng),
                length(rng),
                angle(rng),
            ],
        })
        .collect()
}

/// The description of `rows` (modified, all drive terms), with `head` after the name.
fn description(head: &str, rows: &[Row]) -> Robot {
    description_in("modified", head, rows)
}

/// The description of `rows` in `convention` (a standard table leaves gamma and b out).
fn description_in(convention: &str, head: &str, rows: &[Row]) -> Robot {
    let mut text = format!("name = \"general\"\nconvention = \"{convention}\"\n{head}\n");
    for r in rows {
        let kind = if r.prismatic { "prismatic" } else { "revolute" };
        let [gamma, b, alpha, a, d, theta] = &r.values;
        text += &format!(
            "[[joints]]\ntype = \"{kind}\"\nalpha = {alpha}\na = {a}\nd = {d}\ntheta = {theta}\n"
        );
        if convention == "modified" {
            text += &format!("gamma = {gamma}\nb = {b}\n");
        }
    }
    Robot::from_toml(&text, "general.toml")
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
        .with_drive(Drive::ALL)
}

/// A random base transform (`[base]` table text).
fn base(rng: &mut Rng) -> String {
    format!(
        "gravity = [0, 0, -9.81]\n[base]\nxyz = [{}, {}, {}]\nrpy = [{}, {}, {}]",
        length(rng),
        length(rng),
        length(rng),
        angle(rng),
        angle(rng),
        angle(rng)
    )
}

/// The torques of `robot` with standard parameters `p` at a state, by the symbolic
/// Newton-Euler regressor, the Lagrange-Euler regressor and the RNEA.
fn torques(robot: &Robot, p: &[f64], state: &tests::state::State) -> [Vec<f64>; 3] {
    let mut d = Derivation::new(robot);
    let ne = d.regressor();
    let le = d.lagrange_regressor();
    let values = bind(&mut d.arena, robot, state, None);
    let n = robot.dof();
    let tau_ne = regressor_times(&d.arena.eval(&ne.entries(), &values).unwrap(), n, p);
    let tau_le = regressor_times(&d.arena.eval(&le.entries(), &values).unwrap(), n, p);
    let links = links_from_standard(robot, p);
    let tau = Chain::from_robot(robot).inverse_dynamics(&links, &state.q, &state.qd, &state.qdd);
    [tau, tau_ne, tau_le]
}

/// Newton-Euler, Lagrange-Euler and the RNEA agree for random general robots on random
/// bases, with both joint kinds and every drive term (every fourth a standard table on a
/// base).
#[test]
fn rnea_agrees_with_gamma_b_and_a_base() {
    let mut rng = Rng::from_state(0x6A33_0001);
    for case in 0..16 {
        let dof = 2 + rng.below(4);
        let rows = rows(&mut rng, dof);
        let head = base(&mut rng);
        let convention = if case % 4 == 3 {
            "standard"
        } else {
            "modified"
        };
        let robot = description_in(convention, &head, &rows);
        for _ in 0..4 {
            let p = random_parameters(robot.standard_parameters().len(), &mut rng);
            let state = random_state(&robot, &mut rng);
            let [rnea, ne, le] = torques(&robot, &p, &state);
            for j in 0..dof {
                assert!(
                    close(rnea[j], ne[j], RELATIVE, 1.0) && close(rnea[j], le[j], RELATIVE, 1.0),
                    "case {case}, joint {}: RNEA {} NE {} LE {}\n{head}",
                    j + 1,
                    rnea[j],
                    ne[j],
                    le[j]
                );
            }
        }
    }
}

/// The RNEA comparison can fail: the base turned by a tenth of a radian more in the RNEA
/// alone moves the torques.
#[test]
fn a_different_base_is_detected() {
    let mut rng = Rng::from_state(5);
    let rows = rows(&mut rng, 3);
    let robot = description("gravity = [0, 0, -9.81]\n[base]\nrpy = [0.3, 0, 0]", &rows);
    let turned = description("gravity = [0, 0, -9.81]\n[base]\nrpy = [0.4, 0, 0]", &rows);
    let p = random_parameters(robot.standard_parameters().len(), &mut rng);
    let state = random_state(&robot, &mut rng);
    let [_, ne, _] = torques(&robot, &p, &state);
    let links = links_from_standard(&robot, &p);
    let rnea = Chain::from_robot(&turned).inverse_dynamics(&links, &state.q, &state.qd, &state.qdd);
    assert!((0..3).any(|j| !close(rnea[j], ne[j], RELATIVE, 1.0)));
}

/// The plain DH rows equivalent to `rows` (whose first row has gamma = b = 0): row j's
/// theta and d absorb row j+1's gamma and b.
fn absorbed(rows: &[Row]) -> Vec<Row> {
    (0..rows.len())
        .map(|j| {
            let [_, _, alpha, a, d, theta] = rows[j].values.clone();
            let (theta, d) = match rows.get(j + 1) {
                Some(next) => {
                    let unquote = |s: &str| s.trim_matches('"').to_owned();
                    (
                        format!("\"{} + {}\"", unquote(&theta), unquote(&next.values[0])),
                        format!("\"{} + {}\"", unquote(&d), unquote(&next.values[1])),
                    )
                }
                None => (theta, d),
            };
            Row {
                prismatic: rows[j].prismatic,
                values: ["0".to_owned(), "0".to_owned(), alpha, a, d, theta],
            }
        })
        .collect()
}

/// A general table equals the DH table whose theta_j, d_j absorb gamma_(j+1), b_(j+1), when
/// link j's parameters are expressed in the DH frame j (KK frame j turned by gamma_(j+1)
/// about z_j and shifted by b_(j+1) along it): the same torques by every route, and the
/// same number of base parameters.
#[test]
fn gamma_and_b_are_the_previous_rows_theta_and_d() {
    let mut rng = Rng::from_state(0x6A33_0002);
    for case in 0..12 {
        let dof = 2 + rng.below(4);
        let mut general = rows(&mut rng, dof);
        general[0].values[0] = "0".to_owned();
        general[0].values[1] = "0".to_owned();
        // at least one gamma and one b, so the case is not a DH table already
        general[1].values[0] = format!("{:.3}", rng.uniform(0.1, 3.0));
        general[1].values[1] = format!("{:.3}", rng.uniform(0.05, 0.5));
        let head = "gravity = [1.5, -2.0, -9.81]";
        let kk = description(head, &general);
        let dh = description(head, &absorbed(&general));
        assert!(
            dh.joints()
                .iter()
                .all(|j| j.gamma.is_zero() && j.b.is_zero())
        );
        let shifts: Vec<(f64, f64)> = Chain::from_robot(&kk)
            .rows
            .iter()
            .skip(1)
            .map(|r| (r.gamma, r.b))
            .chain([(0.0, 0.0)])
            .collect();
        for _ in 0..4 {
            let p = random_parameters(kk.standard_parameters().len(), &mut rng);
            let links: Vec<_> = links_from_standard(&kk, &p)
                .iter()
                .zip(&shifts)
                .map(|(link, &(gamma, b))| express_in_parent(link, &rot_z(-gamma), [0.0, 0.0, -b]))
                .collect();
            let p_dh = standard_from_links(&dh, &links);
            let state = random_state(&kk, &mut rng);
            let general_torques = torques(&kk, &p, &state);
            let dh_torques = torques(&dh, &p_dh, &state);
            for j in 0..dof {
                let reference = dh_torques[1][j];
                for (what, x) in [
                    ("general RNEA", general_torques[0][j]),
                    ("general NE", general_torques[1][j]),
                    ("general LE", general_torques[2][j]),
                    ("DH RNEA", dh_torques[0][j]),
                    ("DH LE", dh_torques[2][j]),
                ] {
                    assert!(
                        close(reference, x, RELATIVE, 1.0),
                        "case {case}, joint {}: DH NE {reference} vs {what} {x}",
                        j + 1
                    );
                }
            }
        }
        let count = |r: &Robot| Derivation::new(r).base_parameters().unwrap().base.len();
        assert_eq!(count(&kk), count(&dh), "case {case}");
    }
}

/// The first row's gamma and b place frame 1 the way a base rotation about z and a lift
/// along it do: the same torques for the same parameters, and the same base parameters.
#[test]
fn the_first_rows_gamma_and_b_are_a_base() {
    let mut rng = Rng::from_state(0x6A33_0003);
    for case in 0..8 {
        let dof = 2 + rng.below(3);
        let mut general = rows(&mut rng, dof);
        general[0].values[0] = format!("{:.3}", rng.uniform(-3.0, 3.0));
        let (gamma, b) = (general[0].values[0].clone(), general[0].values[1].clone());
        let head = "gravity = [2.0, 1.0, -9.81]";
        let kk = description(head, &general);
        general[0].values[0] = "0".to_owned();
        general[0].values[1] = "0".to_owned();
        let based = description(
            &format!("{head}\n[base]\nxyz = [0, 0, {b}]\nrpy = [0, 0, {gamma}]"),
            &general,
        );
        for _ in 0..4 {
            let p = random_parameters(kk.standard_parameters().len(), &mut rng);
            let state = random_state(&kk, &mut rng);
            let a = torques(&kk, &p, &state);
            let c = torques(&based, &p, &state);
            for j in 0..dof {
                assert!(
                    close(a[1][j], c[1][j], RELATIVE, 1.0)
                        && close(a[0][j], c[0][j], RELATIVE, 1.0),
                    "case {case}, joint {}: first-row gamma {:?} vs base {:?}",
                    j + 1,
                    (a[0][j], a[1][j]),
                    (c[0][j], c[1][j])
                );
            }
        }
        let count = |r: &Robot| Derivation::new(r).base_parameters().unwrap().base.len();
        assert_eq!(count(&kk), count(&based), "case {case}");
    }
}

/// The numeric poses robid writes (URDF joint origins, the tool) place every frame where
/// the RNEA's chain does: the product of the joint placements (the base under the first)
/// is frame j in the world at q = 0, and with the tool placement the tool frame, frame n
/// times the description's tool pose; the last link's default solid runs to the tool.
#[test]
fn joint_placements_and_the_tool_follow_the_chain() {
    let mut rng = Rng::from_state(0x6A33_0004);
    for case in 0..8 {
        let dof = 2 + rng.below(4);
        let rows = rows(&mut rng, dof);
        let head = format!(
            "{}\n[tool]\nxyz = [{}, {}, {}]\nrpy = [{}, {}, {}]",
            base(&mut rng),
            length(&mut rng),
            length(&mut rng),
            length(&mut rng),
            angle(&mut rng),
            angle(&mut rng),
            angle(&mut rng)
        );
        let convention = if case % 2 == 1 {
            "standard"
        } else {
            "modified"
        };
        let robot = description_in(convention, &head, &rows);
        let poses = Chain::from_robot(&robot).poses(&vec![0.0; dof]);
        let placements = robot.joint_placements().unwrap();
        let mut world = h_identity();
        let largest_difference = |a: &H4, b: &H4| {
            (0..12)
                .map(|k| (a[k / 4][k % 4] - b[k / 4][k % 4]).abs())
                .fold(0.0, f64::max)
        };
        let near = |a: &H4, p: &tests::rnea::Pose, what: &str| {
            assert!(
                largest_difference(a, &h_from(p)) < 1e-12,
                "case {case}: {what}"
            );
        };
        for (j, place) in placements.iter().enumerate() {
            world = homogeneous_product(&[world, place.origin]);
            near(
                &homogeneous_product(&[world, place.link_frame]),
                &poses[j],
                &format!("frame {}", j + 1),
            );
        }
        let tool = robot.tool_placement().unwrap().unwrap();
        let expected =
            homogeneous_product(&[h_from(&poses[dof - 1]), robot.tool_pose().unwrap().unwrap()]);
        let got = homogeneous_product(&[world, tool]);
        assert!(
            largest_difference(&got, &expected) < 1e-12,
            "case {case}: tool"
        );
        if convention == "modified" {
            let segments = robot.link_segments().unwrap();
            let t = robot.tool_pose().unwrap().unwrap();
            assert_eq!(segments[dof - 1], [[0.0; 3], [t[0][3], t[1][3], t[2][3]]]);
        }
    }
}

/// A pose as a homogeneous transform.
fn h_from(p: &tests::rnea::Pose) -> H4 {
    let mut h = h_identity();
    for ((row, rotation), position) in h.iter_mut().zip(&p.rotation).zip(p.position) {
        row[..3].copy_from_slice(rotation);
        row[3] = position;
    }
    h
}
