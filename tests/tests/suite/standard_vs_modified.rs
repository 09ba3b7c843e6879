//! A standard-DH robot and its modified-DH equivalent give the same torques when the link
//! parameters are mapped between the two frame sets: the KUKA LWR4 (a = 0) and the PUMA 560
//! (a != 0, so the frames differ by translations too).
//!
//! The modified table is written here from the standard one (alpha'_j = alpha_(j-1),
//! a'_j = a_(j-1), same d and theta); standard frame j is modified frame j moved by
//! Tx(a_j) Rx(alpha_j), so the parameters are moved with `rnea::express_in_parent`, code
//! independent of robid-symbolic's own conversion.

use robid_runtime::rng::Rng;
use robid_symbolic::{Derivation, Drive, JointKind, Robot};
use tests::reference::by_name;
use tests::rnea::{Chain, express_in_parent, links_from_standard, rot_x, standard_from_links};
use tests::state::{bind, close, random_parameters, random_state, regressor_times};

const RELATIVE: f64 = 1e-9;

/// The modified-DH description equivalent to a standard-DH one.
fn modified_equivalent(standard: &Robot) -> Robot {
    let mut text = format!(
        "name = \"{}_modified\"\nconvention = \"modified\"\ngravity = [{}, {}, {}]\n",
        standard.name(),
        standard.gravity()[0].as_str(),
        standard.gravity()[1].as_str(),
        standard.gravity()[2].as_str()
    );
    for (j, joint) in standard.joints().iter().enumerate() {
        let (alpha, a) = if j == 0 {
            ("0", "0")
        } else {
            (
                standard.joints()[j - 1].alpha.as_str(),
                standard.joints()[j - 1].a.as_str(),
            )
        };
        let kind = match joint.kind {
            JointKind::Revolute => "revolute",
            JointKind::Prismatic => "prismatic",
        };
        text += &format!(
            "[[joints]]\ntype = \"{kind}\"\nalpha = \"{alpha}\"\na = \"{a}\"\nd = \"{}\"\ntheta = \"{}\"\n",
            joint.d.as_str(),
            joint.theta.as_str()
        );
    }
    Robot::from_toml(&text, "<modified equivalent>")
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
        .with_drive(Drive::ALL)
}

/// Standard-frame parameter values mapped into the modified frames.
fn to_modified(standard: &Robot, modified: &Robot, values: &[f64]) -> Vec<f64> {
    let chain = Chain::from_robot(standard);
    let links: Vec<_> = links_from_standard(standard, values)
        .iter()
        .zip(&chain.rows)
        .map(|(link, row)| express_in_parent(link, &rot_x(row.alpha), [row.a, 0.0, 0.0]))
        .collect();
    standard_from_links(modified, &links)
}

fn check(name: &str) {
    let r = by_name(name);
    let standard = r.robot().with_drive(Drive::ALL);
    let modified = modified_equivalent(&standard);
    let n = standard.dof();
    let mut ds = Derivation::new(&standard);
    let mut dm = Derivation::new(&modified);
    let ys = ds.regressor();
    let ym = dm.regressor();
    let (chain_s, chain_m) = (Chain::from_robot(&standard), Chain::from_robot(&modified));
    let mut rng = Rng::from_state(0x5eed_0006);
    let reference = r.parameter_values(&standard);
    for s in 0..40 {
        let ps = if s % 2 == 0 {
            reference.clone()
        } else {
            random_parameters(reference.len(), &mut rng)
        };
        let pm = to_modified(&standard, &modified, &ps);
        let state = random_state(&standard, &mut rng);
        let vs = bind(&mut ds.arena, &standard, &state, None);
        let vm = bind(&mut dm.arena, &modified, &state, None);
        let tau_s = regressor_times(&ds.arena.eval(&ys.entries(), &vs).unwrap(), n, &ps);
        let tau_m = regressor_times(&dm.arena.eval(&ym.entries(), &vm).unwrap(), n, &pm);
        let rnea_s = chain_s.inverse_dynamics(
            &links_from_standard(&standard, &ps),
            &state.q,
            &state.qd,
            &state.qdd,
        );
        let rnea_m = chain_m.inverse_dynamics(
            &links_from_standard(&modified, &pm),
            &state.q,
            &state.qd,
            &state.qdd,
        );
        for j in 0..n {
            for (what, x) in [
                ("modified-DH regressor", tau_m[j]),
                ("standard-frame RNEA", rnea_s[j]),
                ("modified-frame RNEA", rnea_m[j]),
            ] {
                assert!(
                    close(tau_s[j], x, RELATIVE, 1.0),
                    "{name} sample {s}: joint {}: standard-DH regressor {} vs {what} {x}",
                    j + 1,
                    tau_s[j]
                );
            }
        }
    }
}

#[test]
fn lwr4() {
    check("lwr4");
}

#[test]
fn puma560() {
    check("puma560");
}

/// The comparison can fail: without the parameter mapping the two descriptions disagree.
#[test]
fn unmapped_parameters_disagree() {
    let standard = by_name("puma560").robot().with_drive(Drive::ALL);
    let modified = modified_equivalent(&standard);
    let values = by_name("puma560").parameter_values(&standard);
    let state = random_state(&standard, &mut Rng::from_state(3));
    let links = links_from_standard(&modified, &values);
    let tau_s = Chain::from_robot(&standard).inverse_dynamics(
        &links_from_standard(&standard, &values),
        &state.q,
        &state.qd,
        &state.qdd,
    );
    let tau_m =
        Chain::from_robot(&modified).inverse_dynamics(&links, &state.q, &state.qd, &state.qdd);
    assert!((0..standard.dof()).any(|j| !close(tau_s[j], tau_m[j], 1e-3, 1.0)));
}
