//! The link tree of a URDF and the serial chain robid models in it: base and tip, the
//! movable joints between them (robid's joints 1..n), and the rigid body each of them
//! moves (docs/urdf.md#choosing-the-chain).

use super::super::DescriptionError;
use super::super::bounds::{MAX_ARM_LENGTH, MAX_JOINTS};
use super::super::check::{LISTED, and_more, listed, show};
use super::super::file::Place;
use super::rigid::{Rigid, scale};
use super::xml::{Joint, JointType, Mimic, Urdf};
use std::collections::HashMap;

/// Which part of a URDF robid models: the chain from `base` to `tip`.
///
/// `base` defaults to the root link. `tip` defaults to the link moved by the last
/// movable joint (revolute, continuous or prismatic) when the movable joints under the
/// base form a single path; otherwise a tip is needed and the error lists the leaves.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ChainSelection {
    /// The link that stays fixed (robid's base); `None`: the root link.
    pub base: Option<String>,
    /// The last link of the chain; `None`: see the type's documentation.
    pub tip: Option<String>,
}

/// The tree: per link its parent joint and child joints.
pub(super) struct Tree {
    /// Per link, the joint whose child it is.
    pub(super) parent: Vec<Option<usize>>,
    /// Per link, the joints whose parent it is, in file order.
    pub(super) children: Vec<Vec<usize>>,
    /// Per joint, its parent and child link.
    pub(super) ends: Vec<(usize, usize)>,
    /// The root link.
    pub(super) root: usize,
    /// Per link, its pose in the root link's frame with every joint at zero.
    pub(super) at_zero: Vec<Rigid>,
    /// Per joint, the value it is held at when it is not one of robid's joints ([`held`]).
    pub(super) held: Vec<f64>,
}

/// The chain robid models.
pub(super) struct Chain {
    pub(super) base: usize,
    pub(super) tip: usize,
    /// URDF joints of robid's joints 1..n.
    pub(super) joints: Vec<usize>,
    /// Per robid joint j (0-based), the URDF links of its body: the link it moves first,
    /// then the attached ones.
    pub(super) bodies: Vec<Vec<usize>>,
    /// Per link, its pose in the base link's frame with every joint at zero.
    pub(super) in_base: Vec<Rigid>,
    /// The joints from the root link down to joint 1's parent link, root first: those
    /// whose origins, with joint 1's, turn joint 1's axis against the root's vertical.
    pub(super) above: Vec<usize>,
}

fn nearest(names: &[&str], wanted: &str) -> String {
    robid_core::names::nearest(wanted, names.iter().copied())
        .iter()
        .take(3)
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Builds the tree: every parent and child names a link, every link has at most one
/// parent, there is no cycle and there is one root. A `<mimic>` naming no joint is told in
/// `warnings` (the joint is then held at its `offset` off the chain, and refused on it).
pub(super) fn tree(
    place: &Place<'_>,
    urdf: &Urdf,
    warnings: &mut Vec<String>,
) -> Result<Tree, DescriptionError> {
    let names: Vec<&str> = urdf.links.iter().map(|l| l.name.as_str()).collect();
    let index: HashMap<&str, usize> = names.iter().enumerate().map(|(i, &n)| (n, i)).collect();
    let mut errors = Vec::new();
    let n = urdf.links.len();
    let mut parent = vec![None; n];
    let mut children = vec![Vec::new(); n];
    let mut ends = Vec::new();
    for (k, joint) in urdf.joints.iter().enumerate() {
        let mut find = |name: &str, at: &std::ops::Range<usize>, role: &str| {
            let found = index.get(name).copied();
            if found.is_none() {
                errors.push(place.invalid(
                    at.clone(),
                    format!(
                        "the {role} link `{name}` of joint `{}` is no `<link>` of the robot",
                        joint.name
                    ),
                    if names.is_empty() {
                        "add the `<link>` elements".to_owned()
                    } else {
                        format!("the nearest link names are {}", nearest(&names, name))
                    },
                ));
            }
            found
        };
        let p = find(&joint.parent, &joint.parent_at, "parent");
        let c = find(&joint.child, &joint.child_at, "child");
        let (Some(p), Some(c)) = (p, c) else {
            ends.push((0, 0));
            continue;
        };
        ends.push((p, c));
        if let Some(first) = parent[c] {
            let first: usize = first;
            errors.push(place.invalid(
                joint.child_at.clone(),
                format!(
                    "link `{}` has two parents: it is the child of joint `{}` and of joint `{}`",
                    joint.child, urdf.joints[first].name, joint.name
                ),
                "a URDF is a tree: give each link one parent joint (close loops are not modelled)",
            ));
            continue;
        }
        parent[c] = Some(k);
        children[p].push(k);
    }
    let joint_names: Vec<&str> = urdf.joints.iter().map(|j| j.name.as_str()).collect();
    let unknown: Vec<(&Joint, &Mimic)> = urdf
        .joints
        .iter()
        .filter_map(|j| Some((j, j.mimic.as_ref()?)))
        .filter(|(_, m)| !joint_names.contains(&m.joint.as_str()))
        .collect();
    if let Some((joint, mimic)) = unknown.first() {
        let naming = " `<mimic>` naming no joint";
        let more = and_more(unknown.len() - 1, naming, naming);
        warnings.push(place.warning(
            mimic.at.start,
            &format!(
                "joint `{}` mimics joint `{}`, which is no `<joint>` of the robot{more}: off the \
                 chain it is held at its `offset`, as if that joint were at 0, and on the chain \
                 it is refused; the nearest joint names are {}",
                joint.name,
                mimic.joint,
                nearest(&joint_names, &mimic.joint)
            ),
        ));
    }
    if !errors.is_empty() {
        return Err(DescriptionError::from_errors(errors));
    }
    let roots: Vec<usize> = (0..n).filter(|&l| parent[l].is_none()).collect();
    if roots.len() > 1 {
        let list = listed(roots.iter().map(|&l| format!("`{}`", names[l])));
        return Err(place.invalid(
            urdf.links[roots[1]].range.clone(),
            format!("the robot has several root links (links no joint moves): {list}"),
            "connect every link but one to a parent through a `<joint>`",
        ));
    }
    // Every link must be reached from the root; the others lie on a cycle or hang from one.
    let mut reached = vec![false; n];
    let mut stack: Vec<usize> = roots.clone();
    while let Some(l) = stack.pop() {
        reached[l] = true;
        stack.extend(children[l].iter().map(|&j| ends[j].1));
    }
    if let Some(l) = (0..n).find(|&l| !reached[l]) {
        // walk up to a joint on the cycle
        let mut at = l;
        for _ in 0..n {
            at = parent[at].map_or(at, |j| ends[j].0);
        }
        let joint = parent[at].map_or(0, |j| j);
        let j = &urdf.joints[joint];
        return Err(place.invalid(
            j.range.clone(),
            format!(
                "joint `{}` closes a cycle of links (through link `{}`)",
                j.name, names[at]
            ),
            "a URDF is a tree: remove the joint that closes the loop",
        ));
    }
    let Some(&root) = roots.first() else {
        return Err(place.invalid(
            urdf.name_at.clone(),
            "the robot has no `<link>`".to_owned(),
            "a URDF describes links connected by joints",
        ));
    };
    let held = held(place, urdf)?;
    let mut at_zero = vec![Rigid::IDENTITY; n];
    let mut stack = vec![root];
    while let Some(l) = stack.pop() {
        for &j in &children[l] {
            let c = ends[j].1;
            let joint = &urdf.joints[j];
            at_zero[c] = at_zero[l].then(&joint.origin);
            if held[j] != 0.0 {
                at_zero[c] = at_zero[c].then(&match joint.kind {
                    JointType::Prismatic => Rigid::translation(scale(joint.axis, held[j])),
                    _ => Rigid::rotation(joint.axis, held[j]),
                });
            }
            stack.push(c);
        }
    }
    Ok(Tree {
        parent,
        children,
        ends,
        root,
        at_zero,
        held,
    })
}

/// Per joint, the value it is held at when it is not one of robid's joints: 0, but for a
/// revolute, continuous or prismatic joint with `<mimic>`, where its relation puts it,
/// `multiplier * (the followed joint's value) + offset` (`offset` when that joint is held
/// at 0; `tree` has checked that it names a joint). Joints following each other in a cycle
/// are an error.
fn held(place: &Place<'_>, urdf: &Urdf) -> Result<Vec<f64>, DescriptionError> {
    let index: HashMap<&str, usize> = urdf
        .joints
        .iter()
        .enumerate()
        .map(|(k, j)| (j.name.as_str(), k))
        .collect();
    let followed = |j: usize| {
        let joint = &urdf.joints[j];
        let mimic = joint.mimic.as_ref().filter(|_| joint.kind.movable())?;
        Some((mimic, index.get(mimic.joint.as_str()).copied()))
    };
    let mut held: Vec<Option<f64>> = vec![None; urdf.joints.len()];
    for start in 0..urdf.joints.len() {
        // the joints from `start` to one whose value is known or that follows no joint
        let mut walk = vec![start];
        let mut at = start;
        while held[at].is_none() {
            let Some((_, Some(next))) = followed(at) else {
                break;
            };
            if let Some(k) = walk.iter().position(|&j| j == next) {
                let names: Vec<String> = walk[k..]
                    .iter()
                    .map(|&j| format!("`{}`", urdf.joints[j].name))
                    .collect();
                let mimic = followed(at).map_or(0..0, |(m, _)| m.at.clone());
                let (what, fix) = match names.as_slice() {
                    [one] => (
                        format!("the joint {one} follows itself through `<mimic>`"),
                        "a mimic joint follows another joint that moves on its own: name that \
                         joint in `<mimic joint=...>`, or remove the `<mimic>`",
                    ),
                    _ => (
                        format!(
                            "the joints {} follow each other through `<mimic>` in a cycle",
                            listed(names.iter().cloned())
                        ),
                        "a mimic joint follows a joint that moves on its own: remove one `<mimic>`",
                    ),
                };
                return Err(place.invalid(mimic, what, fix));
            }
            walk.push(next);
            at = next;
        }
        for &j in walk.iter().rev() {
            if held[j].is_some() {
                continue;
            }
            held[j] = Some(match followed(j) {
                Some((mimic, master)) => {
                    let master = master.and_then(|m| held[m]).unwrap_or(0.0);
                    mimic.multiplier * master + mimic.offset
                }
                None => 0.0,
            });
        }
    }
    Ok(held.into_iter().map(|v| v.unwrap_or(0.0)).collect())
}

/// A warning when joint `j`, a revolute or prismatic joint with `<mimic>` held off the
/// chain, is held (where its relation puts it) outside its own `<limit>`'s `lower` and
/// `upper`: the URDF places the links it moves where the joint cannot go. robid places
/// them there all the same, as the URDF's own tools do, so the file is read.
fn mimic_beyond_limits(place: &Place<'_>, urdf: &Urdf, tree: &Tree, j: usize) -> Option<String> {
    let joint = &urdf.joints[j];
    let mimic = joint.mimic.as_ref()?;
    let limit = joint.limit.as_ref()?;
    if !matches!(joint.kind, JointType::Revolute | JointType::Prismatic) {
        return None;
    }
    // as the robot's limits are read: missing values are 0, equal ones mean none
    let (lower, upper) = (limit.lower.unwrap_or(0.0), limit.upper.unwrap_or(0.0));
    let value = tree.held[j];
    if lower >= upper || (lower..=upper).contains(&value) {
        return None;
    }
    let followed = urdf.joints.iter().position(|m| m.name == mimic.joint)?;
    // computed values: to six digits (0.1 * 3 + 0.8 is 1.1, not 1.1000000000000001)
    let short = |v: f64| show(format!("{v:.5e}").parse().unwrap_or(v));
    let unit = if joint.kind == JointType::Prismatic {
        "m"
    } else {
        "rad"
    };
    Some(place.warning(
        mimic.at.start,
        &format!(
            "joint `{}`, off the chain, follows joint `{}` through `<mimic>` (multiplier {}, \
             offset {}), which holds it at {} {unit} where joint `{}` is held at {}, outside \
             its own `<limit>` [{}, {}]: robid places the links it moves there, as the URDF's \
             relation says (docs/urdf.md#choosing-the-chain), though the joint cannot go \
             there; check the mimic's `offset` and `multiplier` against the joint's `lower` \
             and `upper`",
            joint.name,
            mimic.joint,
            show(mimic.multiplier),
            show(mimic.offset),
            short(value),
            mimic.joint,
            short(tree.held[followed]),
            show(lower),
            show(upper)
        ),
    ))
}

/// A warning when joint `j`, a prismatic joint with `<mimic>` held off the chain, is held
/// farther than [`MAX_ARM_LENGTH`] from its origin: an `offset` in millimetres (20 for
/// 20 mm) places the links it moves metres away, as a joint's `<origin>` would, which is
/// warned of alike (`xml::read`). The links are placed there all the same, as the URDF says.
fn mimic_far(place: &Place<'_>, urdf: &Urdf, tree: &Tree, j: usize) -> Option<String> {
    let joint = &urdf.joints[j];
    let mimic = joint.mimic.as_ref()?;
    let value = tree.held[j];
    if joint.kind != JointType::Prismatic || value.abs() <= MAX_ARM_LENGTH {
        return None;
    }
    let short = |v: f64| show(format!("{v:.5e}").parse().unwrap_or(v));
    Some(place.warning(
        mimic.at.start,
        &format!(
            "joint `{}`, off the chain, is held at {} m by its `<mimic>` (joint `{}`, \
             multiplier {}, offset {}), which places the links it moves farther than an arm's \
             {MAX_ARM_LENGTH} m from its origin: {}",
            joint.name,
            short(value),
            mimic.joint,
            show(mimic.multiplier),
            show(mimic.offset),
            super::super::file::LENGTH_FIX
        ),
    ))
}

/// The help of the error for a tree without a tip: the tips that give a chain robid
/// models. Per leaf below a movable joint (not the antennas or sensors fixed to the base)
/// the leaf itself, or when its chain fails (a `<mimic>` joint in it or moving with it, a
/// floating joint, more than [`MAX_JOINTS`] movable joints) the deepest link moved by a
/// joint of its path whose chain does not; then the link above the branches (moved by the
/// last movable joint above the links where the movable joints' paths part), each once per
/// set of joints. Leaves that fail are named with the first reason. At most
/// [`LISTED`] tips and as many failing leaves are named; the leaves left untried then are
/// counted as not checked.
fn tips(
    place: &Place<'_>,
    urdf: &Urdf,
    tree: &Tree,
    base: usize,
    below: &[usize],
    ends: &[usize],
    names: &[&str],
) -> String {
    let movable = |j: usize| urdf.joints[j].kind.movable();
    let joints_to = |l: usize| -> Vec<usize> {
        tree.path(base, l)
            .unwrap_or_default()
            .into_iter()
            .filter(|&j| movable(j))
            .collect()
    };
    // why a chain from the base to `l` fails, if it does
    let fails = |l: usize| -> Option<String> {
        let count = joints_to(l).len();
        if count > MAX_JOINTS {
            return Some(format!(
                "the chain has {count} movable joints, and robid derives at most {MAX_JOINTS}"
            ));
        }
        let selection = ChainSelection {
            base: Some(names[base].to_owned()),
            tip: Some(names[l].to_owned()),
        };
        let error = choose(place, urdf, tree, &selection, &mut Vec::new()).err()?;
        let first = error.errors()[0];
        Some(match first {
            DescriptionError::Invalid { message, .. }
            | DescriptionError::Argument { message, .. } => message.clone(),
            other => other.to_string(),
        })
    };
    let leaves: Vec<usize> = below
        .iter()
        .copied()
        .filter(|&l| {
            tree.children[l].is_empty()
                && l != base
                && tree
                    .path(base, l)
                    .unwrap_or_default()
                    .iter()
                    .any(|&j| movable(j))
        })
        .collect();
    let mut good: Vec<(usize, Vec<usize>)> = Vec::new();
    let add = |l: usize, good: &mut Vec<(usize, Vec<usize>)>| {
        let joints = joints_to(l);
        if !good.iter().any(|(_, g)| *g == joints) {
            good.push((l, joints));
        }
    };
    let mut failing: Vec<usize> = Vec::new();
    let mut reason: Option<(usize, String)> = None;
    let mut unchecked = 0;
    for &leaf in &leaves {
        if good.len() >= LISTED || failing.len() >= LISTED {
            unchecked += 1;
            continue;
        }
        match fails(leaf) {
            None => add(leaf, &mut good),
            Some(why) => {
                failing.push(leaf);
                reason.get_or_insert((leaf, why));
                // the deepest link moved by a joint of the path whose chain is modelled
                let path = joints_to(leaf);
                if let Some(l) = path[..path.len().min(MAX_JOINTS)]
                    .iter()
                    .rev()
                    .map(|&j| tree.ends[j].1)
                    .find(|&l| fails(l).is_none())
                {
                    add(l, &mut good);
                }
            }
        }
    }
    // the link above the branches: moved by the last movable joint on the path that the
    // paths to the last moved links (no movable joint below them) share
    let mut end_below = vec![false; urdf.links.len()];
    let mut is_end = vec![false; urdf.links.len()];
    for &e in ends {
        is_end[e] = true;
    }
    // `below` is depth first, so a link's children come after it
    for &l in below.iter().rev() {
        end_below[l] = tree.children[l].iter().any(|&j| {
            let c = tree.ends[j].1;
            is_end[c] || end_below[c]
        });
    }
    let shared = ends
        .iter()
        .filter(|&&e| !end_below[e])
        .map(|&l| tree.path(base, l).unwrap_or_default())
        .reduce(|a, b| {
            a.into_iter()
                .zip(b)
                .take_while(|(x, y)| x == y)
                .map(|(x, _)| x)
                .collect()
        });
    let branch = shared
        .unwrap_or_default()
        .into_iter()
        .rev()
        .find(|&j| movable(j))
        .map(|j| tree.ends[j].1)
        .filter(|&l| fails(l).is_none());
    let quoted = |ls: &[usize]| -> String {
        ls.iter()
            .map(|&l| format!("`{}`", names[l]))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let mut help = if good.is_empty() {
        format!(
            "no leaf below link `{}` ends a chain robid models",
            names[base]
        )
    } else {
        let listed: Vec<usize> = good.iter().map(|(l, _)| *l).collect();
        let mut text = if listed.len() == 1 {
            format!("choose the tip `{}`", names[listed[0]])
        } else {
            format!("choose the tip among {}", quoted(&listed))
        };
        if let Some(b) = branch {
            if listed == [b] {
                text += ", where the chain branches (the joints below it are held)";
            } else if listed.contains(&b) {
                text += &format!(" (`{}`: where the chain branches)", names[b]);
            } else if !good.iter().any(|(_, g)| *g == joints_to(b)) {
                text += &format!(
                    ", or `{}`, where the chain branches (the joints below it are held)",
                    names[b]
                );
            }
        }
        text
    };
    if let Some((leaf, why)) = reason {
        let coupled = if why.contains(" mimics ") {
            " (robid models independent joints)"
        } else {
            ""
        };
        help += &format!(
            "; not {} {}: with `{}` as the tip, {why}{coupled}",
            if failing.len() == 1 {
                "the leaf"
            } else {
                "the leaves"
            },
            quoted(&failing),
            names[leaf]
        );
    }
    // counted apart from the tips: they were not tried, so they are neither good nor bad
    // (they were counted as more tips, which a comb of 3500 failing leaves was told)
    match unchecked {
        0 => {}
        1 => help += "; 1 more leaf was not checked",
        n => help += &format!("; {n} more leaves were not checked"),
    }
    help
}

fn argument(which: &str, message: String, help: String) -> DescriptionError {
    DescriptionError::Argument {
        argument: format!("the chain's {which} link (`ChainSelection::{which}`)"),
        message,
        help,
    }
}

impl Tree {
    /// The links below `link` (itself included), depth first in file order.
    pub(super) fn subtree(&self, link: usize) -> Vec<usize> {
        let mut out = Vec::new();
        let mut stack = vec![link];
        while let Some(l) = stack.pop() {
            out.push(l);
            stack.extend(self.children[l].iter().rev().map(|&j| self.ends[j].1));
        }
        out
    }

    /// The joints from `top` down to `link`, top first (`None`: `link` is not below `top`).
    pub(super) fn path(&self, top: usize, link: usize) -> Option<Vec<usize>> {
        let mut out = Vec::new();
        let mut at = link;
        while at != top {
            let j = self.parent[at]?;
            out.push(j);
            at = self.ends[j].0;
        }
        out.reverse();
        Some(out)
    }
}

/// Chooses the chain (see [`ChainSelection`]) and splits the links below the base into
/// the bodies of robid's joints. `warnings` gets the `<dynamics>` warning.
pub(super) fn choose(
    place: &Place<'_>,
    urdf: &Urdf,
    tree: &Tree,
    selection: &ChainSelection,
    warnings: &mut Vec<String>,
) -> Result<Chain, DescriptionError> {
    let names: Vec<&str> = urdf.links.iter().map(|l| l.name.as_str()).collect();
    let find = |which: &str, name: &str| {
        names.iter().position(|&n| n == name).ok_or_else(|| {
            argument(
                which,
                format!("the URDF has no link `{name}`"),
                format!("the nearest link names are {}", nearest(&names, name)),
            )
        })
    };
    let base = match &selection.base {
        Some(name) => find("base", name)?,
        None => tree.root,
    };
    let below = tree.subtree(base);
    let movable = |j: usize| urdf.joints[j].kind.movable();
    let tip = match &selection.tip {
        Some(name) => find("tip", name)?,
        None => {
            let mut ends: Vec<usize> = below
                .iter()
                .filter_map(|&l| tree.parent[l].filter(|&j| l != base && movable(j)))
                .map(|j| tree.ends[j].1)
                .collect();
            // a single path: every movable joint's child lies on the path to the deepest one
            let mut depth = vec![0_usize; urdf.links.len()];
            for &l in &below {
                if let Some(j) = tree.parent[l].filter(|_| l != base) {
                    depth[l] = depth[tree.ends[j].0] + 1;
                }
            }
            ends.sort_by_key(|&l| depth[l]);
            let single = ends.last().is_some_and(|&last| {
                let path: std::collections::HashSet<usize> = tree
                    .path(base, last)
                    .unwrap_or_default()
                    .into_iter()
                    .collect();
                ends.iter()
                    .all(|&l| tree.parent[l].is_some_and(|j| path.contains(&j)))
            });
            match ends.last() {
                Some(&last) if single => last,
                Some(_) => {
                    return Err(argument(
                        "tip",
                        format!(
                            "the movable joints below link `{}` do not form a single path, so the chain's tip must be chosen",
                            names[base]
                        ),
                        tips(place, urdf, tree, base, &below, &ends, &names),
                    ));
                }
                None if !urdf.joints.iter().any(|j| j.kind.movable()) => {
                    return Err(place.invalid(
                        urdf.name_at.clone(),
                        format!(
                            "the URDF has no revolute, continuous or prismatic joint ({}), so it has no chain to model",
                            if urdf.joints.is_empty() {
                                "it has no joint".to_owned()
                            } else {
                                "its joints are fixed, floating or planar".to_owned()
                            }
                        ),
                        "give the URDF of a robot whose joints move, or make the joints that move \
                         `type=\"revolute\"`, `\"continuous\"` or `\"prismatic\"`",
                    ));
                }
                None => {
                    return Err(argument(
                        "base",
                        format!(
                            "no movable (revolute, continuous or prismatic) joint lies below link `{}`",
                            names[base]
                        ),
                        format!(
                            "choose a base above the joints to model, such as the root link `{}` (the default)",
                            names[tree.root]
                        ),
                    ));
                }
            }
        }
    };
    let Some(path) = tree.path(base, tip) else {
        return Err(argument(
            "tip",
            format!(
                "link `{}` is not below the base link `{}`",
                names[tip], names[base]
            ),
            format!(
                "choose a tip in the subtree of `{}`, or a base above `{}`",
                names[base], names[tip]
            ),
        ));
    };
    let joints: Vec<usize> = path.iter().copied().filter(|&j| movable(j)).collect();
    if joints.is_empty() && selection.base.is_some() {
        // both links were chosen (a base without a tip ends at a movable joint, or fails
        // above): the pair is at fault, not one of them
        return Err(DescriptionError::Argument {
            argument: "the chain's base and tip links (`ChainSelection::base` and \
                       `ChainSelection::tip`)"
                .to_owned(),
            message: format!(
                "no movable (revolute, continuous or prismatic) joint lies between the base \
                 link `{}` and the tip link `{}`",
                names[base], names[tip]
            ),
            help: format!(
                "choose a base and a tip below it with the joints to model between them (the \
                 base may be the root link `{}`, the default)",
                names[tree.root]
            ),
        });
    }
    if joints.is_empty() {
        return Err(argument(
            "tip",
            format!(
                "no movable joint lies between links `{}` and `{}`",
                names[base], names[tip]
            ),
            "choose a tip that revolute, continuous or prismatic joints move".to_owned(),
        ));
    }
    // A floating or planar joint between the base and the chain lets the chain's support
    // move; taking it as fixed would be a fixed-base model of a floating robot, which is
    // wrong. Choosing a base below it (or above it, a revolute joint alike) states that
    // the support stands still, so only this part of the path is checked.
    let support = path.iter().take_while(|&&j| !movable(j));
    if let Some(&j) = support
        .filter(|&&j| matches!(urdf.joints[j].kind, JointType::Floating | JointType::Planar))
        .last()
    {
        let joint = &urdf.joints[j];
        let kind = if joint.kind == JointType::Floating {
            "floating"
        } else {
            "planar"
        };
        return Err(place.invalid(
            joint.range.clone(),
            format!(
                "joint `{}` is {kind}: the chain hangs from link `{}`, which it lets move, \
                 and robid models a fixed base (a fixed-base model of a moving base is wrong)",
                joint.name, joint.child
            ),
            format!(
                "if the base is bolted down, make the joint `type=\"fixed\"`; to model the \
                 chain as if link `{0}` stood still during the experiments, choose `{0}` as \
                 the chain's base (`--base {0}` on the command line, `base = \"{0}\"` in \
                 `robot_model!`)",
                joint.child
            ),
        ));
    }
    // body of every link below the base: 0 the fixed base, j robid joint j
    let position: HashMap<usize, usize> = joints.iter().enumerate().map(|(k, &j)| (j, k)).collect();
    let mut body = vec![usize::MAX; urdf.links.len()];
    let mut bodies = vec![Vec::new(); joints.len()];
    body[base] = 0;
    for &l in &below {
        if l == base {
            continue;
        }
        let Some(j) = tree.parent[l] else { continue };
        let p = tree.ends[j].0;
        body[l] = match position.get(&j) {
            Some(&k) => k + 1,
            None => body[p],
        };
        if body[l] > 0 {
            let list = &mut bodies[body[l] - 1];
            if joints[body[l] - 1] == j {
                list.insert(0, l);
            } else {
                list.push(l);
            }
        }
    }
    let path_names: HashMap<&str, usize> = joints
        .iter()
        .enumerate()
        .map(|(k, &j)| (urdf.joints[j].name.as_str(), k))
        .collect();
    let mut errors = Vec::new();
    let mut dynamics = None;
    for &l in &below {
        let Some(j) = tree.parent[l].filter(|_| l != base && body[l] > 0) else {
            continue;
        };
        let joint = &urdf.joints[j];
        let on_path = path_names.contains_key(joint.name.as_str());
        if let Some(mimic) = &joint.mimic
            && (on_path || path_names.contains_key(mimic.joint.as_str()))
        {
            let mimicked = &mimic.joint;
            let exists = urdf.joints.iter().any(|j| &j.name == mimicked);
            errors.push(place.invalid(
                    mimic.at.clone(),
                    if on_path && !exists {
                        format!(
                            "joint `{}` of the chain mimics joint `{mimicked}`, which is no \
                             `<joint>` of the robot",
                            joint.name
                        )
                    } else if on_path {
                        format!("joint `{}` of the chain mimics joint `{mimicked}`", joint.name)
                    } else {
                        format!(
                            "joint `{}` mimics joint `{mimicked}` of the chain: it would move with it",
                            joint.name
                        )
                    },
                    "robid models independent joints: choose a chain without coupled joints, or make the joint fixed",
                ));
        }
        if matches!(joint.kind, JointType::Floating | JointType::Planar) {
            errors.push(place.invalid(
                joint.range.clone(),
                format!(
                    "joint `{}` is {}: robid models revolute and prismatic joints",
                    joint.name,
                    if joint.kind == JointType::Floating {
                        "floating"
                    } else {
                        "planar"
                    }
                ),
                "make it fixed, or choose a chain that does not contain it",
            ));
        }
        if dynamics.is_none() {
            dynamics = joint.dynamics.clone();
        }
    }
    if !errors.is_empty() {
        return Err(DescriptionError::from_errors(errors));
    }
    // the mimic joints held off the chain where the model uses them: in a body, or
    // between the root and the base (they turn gravity)
    let held_joints = below
        .iter()
        .filter(|&&l| l != base && body[l] > 0)
        .filter_map(|&l| tree.parent[l])
        .filter(|j| !path_names.contains_key(urdf.joints[*j].name.as_str()))
        .chain(tree.path(tree.root, base).unwrap_or_default());
    let mut far = None;
    for j in held_joints {
        if let Some(w) = mimic_beyond_limits(place, urdf, tree, j) {
            warnings.push(w);
        }
        far = far.or_else(|| mimic_far(place, urdf, tree, j));
    }
    warnings.extend(far);
    if let Some(at) = dynamics {
        warnings.push(place.warning(
            at.start,
            "`<dynamics damping friction>` is ignored (here and in every other joint): it is not \
             part of the rigid-body model; joint friction belongs to robid's drive terms Fv and \
             Fc (--drive), which identification estimates",
        ));
    }
    let to_base = tree.at_zero[base].inverse();
    let in_base = tree.at_zero.iter().map(|t| to_base.then(t)).collect();
    let above = tree
        .path(tree.root, tree.ends[joints[0]].0)
        .unwrap_or_default();
    Ok(Chain {
        base,
        tip,
        joints,
        bodies,
        in_base,
        above,
    })
}
