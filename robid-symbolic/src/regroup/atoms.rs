//! The geometric atoms of regressor columns: the quantities in which a
//! dependency coefficient that varies with the geometric symbols is fitted
//! as a polynomial (`exact.rs`).
//!
//! A column is a function of the joint states and of the geometric symbols
//! (lengths, angles or gravity written as symbols). Where a symbol enters
//! polynomially (a length), the symbol itself is an atom. Where it enters
//! through a sine or cosine (a twist or an offset written as a symbol, also
//! added to a joint variable: `sin(q1 + th)`), the sine and cosine of its
//! geometric part are two atoms, tied by `sin^2 + cos^2 = 1` (the fit uses
//! the cosine to the first power only). Any other function of symbols alone
//! (`sqrt(L)`, `1/L`) is an atom as it is.

use crate::expr::{Arena, Id, Node, Symbol};

/// One atom.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Atom {
    /// Its expression (in the geometric symbols only).
    pub(crate) id: Id,
    /// The cosine of an angle whose sine is also an atom: its powers above
    /// one are not independent of the sine's.
    pub(crate) paired_cosine: bool,
    /// The sine or cosine of an angle.
    pub(crate) trig: bool,
}

/// The symbols that enter `atoms` only through sines and cosines: angles,
/// which the fits may sample over a whole turn.
pub(crate) fn angle_symbols(arena: &Arena, atoms: &[Atom]) -> Vec<Symbol> {
    let ids = |trig: bool| -> Vec<Id> {
        atoms
            .iter()
            .filter(|a| a.trig == trig)
            .map(|a| a.id)
            .collect()
    };
    let other = arena.free_symbols(&ids(false));
    arena
        .free_symbols(&ids(true))
        .into_iter()
        .filter(|s| !other.contains(s))
        .collect()
}

/// The atoms of the expressions `roots`, for the geometric symbols
/// `geometry` (every other symbol is a joint state). Sorted and without
/// repetition, so the result does not depend on the order of `roots`.
pub(crate) fn find(arena: &mut Arena, roots: &[Id], geometry: &[Symbol]) -> Vec<Atom> {
    let seen = arena.reachable(roots);
    // For each reachable node: does it depend on geometry, on the states?
    let mut geometric = vec![false; seen.len()];
    let mut state = vec![false; seen.len()];
    for index in (0..seen.len()).filter(|&i| seen[i]) {
        let node = arena.node_at(index);
        let (g, s) = match node {
            Node::Sym(symbol) => {
                let g = geometry.contains(symbol);
                (g, !g)
            }
            _ => node.children().iter().fold((false, false), |(g, s), c| {
                (g || geometric[c.index()], s || state[c.index()])
            }),
        };
        geometric[index] = g;
        state[index] = s;
    }
    let only_geometry = |id: Id| geometric[id.index()] && !state[id.index()];
    let mut plain: Vec<Id> = Vec::new();
    let mut angles: Vec<Id> = Vec::new();
    let mut visited = vec![false; seen.len()];
    let mut stack: Vec<Id> = roots.to_vec();
    while let Some(id) = stack.pop() {
        if std::mem::replace(&mut visited[id.index()], true) || !geometric[id.index()] {
            continue;
        }
        match arena.node(id).clone() {
            Node::Sym(_) => plain.push(id),
            Node::Sin(x) | Node::Cos(x) => {
                if only_geometry(x) {
                    angles.push(x);
                    continue;
                }
                // sin(q + th): the geometric terms of the sum are the angle.
                let terms: Vec<Id> = match arena.node(x) {
                    Node::Add(terms) => terms.to_vec(),
                    _ => Vec::new(),
                };
                let mixed = terms.is_empty()
                    || terms
                        .iter()
                        .any(|&t| geometric[t.index()] && state[t.index()]);
                if mixed {
                    stack.push(x);
                } else {
                    let geometric_terms: Vec<Id> =
                        terms.into_iter().filter(|t| geometric[t.index()]).collect();
                    angles.push(arena.add(&geometric_terms));
                }
            }
            node @ (Node::Sqrt(_) | Node::Sign(_) | Node::Pow(..)) => {
                let inner = node.children()[0];
                let negative_power = matches!(node, Node::Pow(_, k) if k < 0);
                let function = !matches!(node, Node::Pow(..)) || negative_power;
                if function && only_geometry(inner) {
                    plain.push(id);
                } else {
                    stack.push(inner);
                }
            }
            node => stack.extend_from_slice(node.children()),
        }
    }
    let mut atoms: Vec<Atom> = plain
        .into_iter()
        .map(|id| Atom {
            id,
            paired_cosine: false,
            trig: false,
        })
        .collect();
    for angle in angles {
        let (sin, cos) = (arena.sin(angle), arena.cos(angle));
        atoms.push(Atom {
            id: sin,
            paired_cosine: false,
            trig: true,
        });
        atoms.push(Atom {
            id: cos,
            paired_cosine: true,
            trig: true,
        });
    }
    atoms.sort_by_key(|a| (a.id, a.paired_cosine));
    atoms.dedup_by_key(|a| a.id);
    // An atom that is a number (a sine that folded) carries no variation.
    atoms.retain(|a| arena.as_num(a.id).is_none());
    atoms
}

#[cfg(test)]
mod tests {
    use super::find;
    use crate::expr::Arena;

    fn atoms_of(text: &str, geometry: &[&str]) -> Vec<String> {
        let mut a = Arena::new();
        let e = a.parse(text).unwrap();
        let symbols: Vec<_> = geometry.iter().map(|s| a.symbol(s)).collect();
        let mut out: Vec<String> = find(&mut a, &[e], &symbols)
            .iter()
            .map(|atom| {
                let text = a.display(atom.id);
                if atom.paired_cosine {
                    format!("{text} (paired)")
                } else {
                    text
                }
            })
            .collect();
        out.sort();
        out
    }

    #[test]
    fn lengths_are_atoms_and_states_are_not() {
        assert_eq!(
            atoms_of("L1*cos(q1)*qd1^2 + L2^2*qdd2 + 3*q2", &["L1", "L2"]),
            ["L1", "L2"]
        );
        assert!(atoms_of("cos(q1)*qd1 + 0.3", &["L1"]).is_empty());
    }

    #[test]
    fn symbolic_angles_give_a_sine_and_a_paired_cosine() {
        assert_eq!(
            atoms_of("L1*sin(al)*qdd1 + cos(al)^2*q1", &["L1", "al"]),
            ["L1", "cos(al) (paired)", "sin(al)"]
        );
        // An offset added to a joint variable.
        assert_eq!(
            atoms_of("sin(q1 + th)*qdd1", &["th"]),
            ["cos(th) (paired)", "sin(th)"]
        );
        // A geometric factor inside a function of the state is found inside it.
        assert_eq!(atoms_of("sin(L*q1)*qdd1", &["L"]), ["L"]);
    }

    #[test]
    fn angle_symbols_are_those_only_inside_sines_and_cosines() {
        let mut a = Arena::new();
        let e = a.parse("L*sin(al)*qdd1 + cos(th)*q1 + th*qd1").unwrap();
        let symbols: Vec<_> = ["L", "al", "th"].iter().map(|s| a.symbol(s)).collect();
        let atoms = super::find(&mut a, &[e], &symbols);
        let angles: Vec<&str> = super::angle_symbols(&a, &atoms)
            .into_iter()
            .map(|s| a.symbol_name(s))
            .collect();
        assert_eq!(angles, ["al"]);
    }

    #[test]
    fn other_functions_of_symbols_are_atoms_as_they_are() {
        assert_eq!(
            atoms_of("qdd1/L1 + sqrt(L2)*qd1", &["L1", "L2"]),
            ["L1^(-1)", "sqrt(L2)"]
        );
    }
}
