//! A calibrated arm: two consecutive axes a few 1e-5 rad off parallel, whose common normal
//! meets them hundreds of metres away (docs/urdf.md#fitting-the-dh-table). Its frames keep
//! their origins near the joints, and its torques equal an independent Newton-Euler on the
//! URDF's own frames.

use super::super::rigid::{add, cross, dot, mat_vec, mul, norm, scale, sub, transpose};
use super::*;
use robid_core::rng::Rng;

const INERTIAL: &str = r#"<inertial><origin xyz="0.1 0.02 0.03" rpy="0.1 0.2 0.3"/><mass value="2"/><inertia ixx="0.02" ixy="0.001" ixz="0" iyy="0.03" iyz="0" izz="0.025"/></inertial>"#;

/// A UR-like arm: shoulder pan, then shoulder lift, elbow and wrist 1 parallel as a
/// nominal UR's, but the elbow rolled by `skew` rad and placed 5 mm off the lift axis's
/// plane, as a calibration writes it (the common normal of the lift and elbow axes then
/// lies about 0.005 / `skew` m from them), then wrist 2 at a right angle. With `meeting`,
/// the elbow is instead pitched by `skew` towards the lift axis, in their plane, as the UR5
/// of example-robot-data with its elbow rolled: the two axes meet about 0.4 / `skew` m away.
fn calibrated(skew: f64, meeting: bool) -> String {
    let limit = r#"<limit lower="-3" upper="3" effort="100" velocity="2"/>"#;
    let joint = |name: &str, parent: &str, child: &str, origin: &str| {
        format!(
            r#"<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/><origin {origin}/><axis xyz="0 0 1"/>{limit}</joint>"#
        )
    };
    let mut text = String::from(r#"<robot name="calibrated"><link name="base"/>"#);
    for l in 1..=5 {
        text += &format!(r#"<link name="l{l}">{INERTIAL}</link>"#);
    }
    // where the axes meet, the arm turned on its base by no right angle, so that no
    // direction is exact
    let pan = match meeting {
        false => r#"xyz="0 0 0.1""#,
        true => r#"xyz="0 0 0.1" rpy="0.3 -0.2 0.1""#,
    };
    text += &joint("pan", "base", "l1", pan);
    text += &joint(
        "lift",
        "l1",
        "l2",
        r#"xyz="0 0.1 0.2" rpy="1.5707963267948966 0 0""#,
    );
    text += &joint(
        "elbow",
        "l2",
        "l3",
        &match meeting {
            false => format!(r#"xyz="0.4 0.005 0" rpy="{skew} 0 0""#),
            true => format!(r#"xyz="0.4 0 0" rpy="0 {skew} 0""#),
        },
    );
    text += &joint(
        "wrist_1",
        "l3",
        "l4",
        r#"xyz="0.35 0.01 -0.02" rpy="0 0 0.1""#,
    );
    text += &joint(
        "wrist_2",
        "l4",
        "l5",
        r#"xyz="0 0.05 0.1" rpy="1.5707963267948966 0 0""#,
    );
    text + "</robot>"
}

/// Joint torques by a plain Newton-Euler on the URDF's frames (every chain link one body,
/// gravity -9.81 along the base link's z): velocities and accelerations of each link at
/// its joint's point (the child link's origin, on the axis), wrenches about the same
/// points, everything in the base link frame.
fn direct_torques(text: &str, names: &[&str], q: &[f64], qd: &[f64], qdd: &[f64]) -> Vec<f64> {
    let urdf = xml::read(&Place { file: "t", text }).unwrap();
    let joints = direct_joints(text);
    let values: HashMap<String, f64> = names
        .iter()
        .zip(q)
        .map(|(n, &v)| ((*n).to_owned(), v))
        .collect();
    let poses = direct_poses(&joints, "base", &values);
    let n = names.len();
    let chain: Vec<&DirectJoint> = names
        .iter()
        .map(|name| joints.iter().find(|j| j.name == *name).unwrap())
        .collect();
    let (mut w, mut wd) = ([0.0; 3], [0.0; 3]);
    let mut acc = [0.0, 0.0, 9.81];
    let mut previous = [0.0; 3];
    let mut frames = Vec::new();
    for (i, joint) in chain.iter().enumerate() {
        let pose = poses[&joint.child];
        let u = pose.apply_vector(joint.axis);
        let point = pose.p;
        // the joint's point is fixed in the previous link
        let r = sub(point, previous);
        acc = add(acc, add(cross(wd, r), cross(w, cross(w, r))));
        let spin = scale(u, qd[i]);
        wd = add(add(wd, scale(u, qdd[i])), cross(w, spin));
        w = add(w, spin);
        previous = point;
        let link = urdf.links.iter().find(|l| l.name == joint.child).unwrap();
        let inertial = link.inertial.as_ref().unwrap();
        let at = pose.then(&inertial.origin);
        let c = sub(at.p, point);
        let [xx, xy, xz, yy, yz, zz] = inertial.inertia;
        let inertia = mul(
            &mul(&at.r, &[[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]),
            &transpose(&at.r),
        );
        let force = scale(
            add(acc, add(cross(wd, c), cross(w, cross(w, c)))),
            inertial.mass,
        );
        let moment = add(
            add(mat_vec(&inertia, wd), cross(w, mat_vec(&inertia, w))),
            cross(c, force),
        );
        frames.push((u, point, force, moment));
    }
    let mut tau = vec![0.0; n];
    let (mut f, mut m, mut next) = ([0.0; 3], [0.0; 3], [0.0; 3]);
    for i in (0..n).rev() {
        let (u, point, force, moment) = frames[i];
        let arm = if i + 1 < n {
            sub(next, point)
        } else {
            [0.0; 3]
        };
        m = add(add(moment, m), cross(arm, f));
        f = add(force, f);
        next = point;
        tau[i] = dot(u, m);
    }
    tau
}

const NAMES: [&str; 5] = ["pan", "lift", "elbow", "wrist_1", "wrist_2"];

/// robid's frame origins lie within the chain's length of their joints, and robid's
/// torques (its Newton-Euler in the fitted frames, with the URDF's inertials taken about
/// those origins) equal the direct ones to 1e-12 of the largest, or where the common normal
/// lies farther than 1 km, to 16 x 2^-52 of its distance over a metre (measured: 4e-13 at
/// 1e-6 rad, 3.7e-11 at 1e-7 rad, 3.4e-11 at 2e-8 rad).
fn check(skew: f64, meeting: bool) -> f64 {
    // the elbow row's b and d are about the common normal's distance, 0.005 / skew m (0.4 /
    // skew m where the axes meet), and f64 keeps their sum to 2^-52 of it
    // (docs/urdf.md#fitting-the-dh-table)
    let far = if meeting { 0.4 } else { 0.005 } / skew;
    let digits = 1e-12_f64.max(8.0 * f64::EPSILON * far);
    let text = calibrated(skew, meeting);
    let chain = Robot::from_urdf(&text, "calibrated.urdf", &ChainSelection::default())
        .unwrap_or_else(|e| panic!("skew {skew}: {e}"));
    let joints = direct_joints(&text);
    let at_zero = direct_poses(&joints, "base", &HashMap::new());
    let points: Vec<[f64; 3]> = chain.links.iter().map(|l| at_zero[&l.link].p).collect();
    let size: f64 = points.windows(2).map(|p| norm(sub(p[1], p[0]))).sum();
    let frames = dh_frames(&chain, &[0.0; 5]);
    for (k, (frame, point)) in frames.iter().zip(&points).enumerate() {
        let reach = norm(sub(frame.p, *point));
        assert!(
            reach <= size,
            "skew {skew}: frame {} lies {reach} m from its joint (chain {size} m)",
            k + 1
        );
    }
    // the origin moved off the far foot is carried by the elbow row's b
    let b = general_rows(&chain.robot)[2][4];
    assert_eq!(b.abs() > 100.0, skew != 0.0, "skew {skew}: b3 = {b}");
    let mut rng = Rng::new(20261202);
    for _ in 0..4 {
        let q: Vec<f64> = (0..5).map(|_| rng.uniform(-2.0, 2.0)).collect();
        check_kinematics(&text, &chain, "base", "l5", &q, digits);
    }
    let mut torques = own_inertials_torques(&chain);
    let (mut worst, mut largest) = (0.0_f64, 0.0_f64);
    for _ in 0..20 {
        let state: Vec<Vec<f64>> = [2.0, 3.0, 10.0]
            .iter()
            .map(|&range| (0..5).map(|_| rng.uniform(-range, range)).collect())
            .collect();
        let got = torques(&state[0], &state[1], &state[2]);
        let want = direct_torques(&text, &NAMES, &state[0], &state[1], &state[2]);
        for (g, w) in got.iter().zip(&want) {
            worst = worst.max((g - w).abs());
            largest = largest.max(w.abs());
        }
    }
    let relative = worst / largest;
    assert!(
        relative <= 2.0 * digits,
        "skew {skew}: torques differ by {worst:e} N m, {relative:e} of the largest {largest}"
    );
    relative
}

#[test]
fn a_calibrated_arm_keeps_its_frames_near_its_joints_and_its_torques() {
    // the common normal of lift and elbow 250 m to 250 km away: below 1e-5 rad
    // (bounds::ANGLE_RESOLUTION) the elbow row is a calibrated pair (bounds::calibrated_pair),
    // down to 2e-8 rad (`rpy` values below 1e-8 rad are taken as 0, the angle rule)
    for skew in [2e-5, 1.0000001e-5, 1e-6, 1e-7, 2e-8] {
        check(skew, false);
    }
}

/// The same arm with the lift and elbow axes meeting far away (the common normal of zero
/// length there): the feet of the normal on both axes are computed about 0.4 / `skew` m
/// from the joints, so their difference is rounding of about 2^-52 times that, not a
/// direction. Taken as one once (x along that rounding, nearly along the axes), it gave the
/// elbow row an `a` and `d` of 1e-9 to 8e-7 m, refused as shorter than 1 µm, at 10 of 31
/// skews between 1e-8 and 1e-4 rad of the UR5's elbow.
#[test]
fn a_calibrated_arm_whose_nearly_parallel_axes_meet_far_away() {
    for skew in [
        5.412e-5, 1.848e-6, 2.512e-6, 2.929e-7, 3.981e-7, 5.412e-7, 7.356e-7, 1e-7, 5e-8, 2e-8,
        1.2e-8,
    ] {
        check(skew, true);
    }
}

#[test]
fn the_direct_newton_euler_agrees_on_the_nominal_arm() {
    // the same check with the axes exactly parallel, which robid always fitted with
    // frames at the common normals (no b): the direct computation is the reference
    check(0.0, false);
}

/// Skew axes at an ordinary angle (5 to 45 degrees, 0.1 m apart) whose common normal's foot
/// lies farther from the first joint than a short chain is long (joint 2's point placed
/// off the normal) are fitted as always: frames at the common normal's feet, no `b`. The
/// move of a frame origin off its foot is for nearly parallel axes only (within
/// `NEAR_PARALLEL`); it used to apply to any pair whose foot was beyond the chain's
/// length, so that a 20-degree pair got a `b` and link parameters about another origin.
#[test]
fn ordinary_skew_axes_keep_their_frames_at_the_feet() {
    let limit = r#"<limit lower="-3" upper="3" effort="100" velocity="2"/>"#;
    for degrees in [5.0f64, 10.0, 20.0, 45.0] {
        for third in [false, true] {
            let mut text = format!(
                r#"<robot name="skew"><link name="base"/><link name="l1">{INERTIAL}</link><link name="l2">{INERTIAL}</link>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>{limit}</joint>
<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.1 -0.05 0" rpy="{} 0 0"/><axis xyz="0 0 1"/>{limit}</joint>"#,
                -degrees.to_radians()
            );
            if third {
                text += &format!(
                    r#"<link name="l3">{INERTIAL}</link><joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0.05 0 0"/><axis xyz="1 0 0"/>{limit}</joint>"#
                );
            }
            text += "</robot>";
            let chain = Robot::from_urdf(&text, "skew.urdf", &ChainSelection::default())
                .unwrap_or_else(|e| panic!("{degrees} degrees: {e}"));
            let rows = general_rows(&chain.robot);
            assert!(
                rows.iter().all(|r| r[4] == 0.0),
                "{degrees} degrees, third joint {third}: {rows:?}"
            );
            // frame 1 (and frame 0 on it) at the foot, 0.05 cot(angle) up axis 1
            let frames = dh_frames(&chain, &[0.0; 3][..rows.len()]);
            let foot = 0.05 / degrees.to_radians().tan();
            assert!(
                (frames[0].p[2] - foot).abs() < 1e-12,
                "{degrees} degrees: frame 1 at {:?}, foot at z = {foot}",
                frames[0].p
            );
            let q = [0.3, -0.7, 1.1];
            check_kinematics(
                &text,
                &chain,
                "base",
                if third { "l3" } else { "l2" },
                &q[..rows.len()],
                1e-12,
            );
        }
    }
}

/// A leg as the Minitaur's of PyBullet writes it: a motor axis, a fixed joint whose
/// `rpy` is a right angle mistyped (`-1.57075`, 4.6e-5 rad off), and a knee axis 1 cm away
/// that the typo turns 4.6e-5 rad off antiparallel to the motor's: a calibrated pair whose
/// common normal lies 2.5 km away. It is read (exactly), and the warning names the pair,
/// their angle and the element that tilts them; with the right angle written exactly there
/// is no pair and no warning.
#[test]
fn a_mistyped_right_angle_between_two_axes_is_named_with_their_calibrated_pair() {
    let leg = |rpy: &str| {
        format!(
            r#"<robot name="leg"><link name="body"/>
<link name="motor">{INERTIAL}</link><link name="upper"/><link name="lower">{INERTIAL}</link>
<joint name="motor_joint" type="continuous"><parent link="body"/><child link="motor"/><origin rpy="1.5707963267948966 0 0" xyz="0.21 -0.025 0"/><axis xyz="0 0 1"/></joint>
<joint name="hip" type="fixed"><parent link="motor"/><child link="upper"/><origin rpy="{rpy} 0 0" xyz="0 0.06 -0.015"/></joint>
<joint name="knee" type="continuous"><parent link="upper"/><child link="lower"/><origin xyz="0 0.01 0.055"/><axis xyz="0 1 0"/></joint>
</robot>"#
        )
    };
    let chain = Robot::from_urdf(&leg("-1.57075"), "t.urdf", &ChainSelection::default()).unwrap();
    let told = one_warning(&chain, "calibrated pair");
    for part in [
        "t.urdf:5:",
        "joints `motor_joint` and `knee` are 4.6e-5 rad from antiparallel",
        "lies 2482",
        "fixed joint `hip` is 4.6e-5 rad from a right angle",
        "`1.5708`",
    ] {
        assert!(told.contains(part), "{part}: {told}");
    }
    let exact = Robot::from_urdf(
        &leg("-1.5707963267948966"),
        "t.urdf",
        &ChainSelection::default(),
    )
    .unwrap();
    assert!(
        exact
            .warnings
            .iter()
            .all(|w| !w.contains("calibrated pair")),
        "{:?}",
        exact.warnings
    );
    // a calibration's roll of the elbow by 1e-6 rad: its origin named
    let calibrated = Robot::from_urdf(
        &calibrated(1e-6, false),
        "t.urdf",
        &ChainSelection::default(),
    )
    .unwrap();
    let told = one_warning(&calibrated, "calibrated pair");
    assert!(
        told.contains("joints `lift` and `elbow` are 1.0e-6 rad from parallel"),
        "{told}"
    );
    assert!(
        told.contains("the `<origin>` rotation of joint `elbow` is 1.0e-6 rad"),
        "{told}"
    );
}
