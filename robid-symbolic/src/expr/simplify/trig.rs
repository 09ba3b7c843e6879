//! Exact sine and cosine of DH angles: multiples of pi/2 (also as an offset
//! added to a joint variable) fold exactly, and parity moves signs out
//! (sin(-x) = -sin(x), cos(-x) = cos(x)).

use crate::expr::{Arena, Id, Node, Num};

/// Which function.
#[derive(Clone, Copy, PartialEq)]
enum Fun {
    Sin,
    Cos,
}

/// Sine with the exact rules applied.
pub(crate) fn sin(arena: &mut Arena, x: Id) -> Id {
    build(arena, Fun::Sin, x)
}

/// Cosine with the exact rules applied.
pub(crate) fn cos(arena: &mut Arena, x: Id) -> Id {
    build(arena, Fun::Cos, x)
}

/// `x = c * pi` for a number `c`: returns `c`.
fn pi_multiple(arena: &Arena, x: Id) -> Option<Num> {
    match arena.node(x) {
        Node::Pi => Some(Num::ONE),
        Node::Mul(f) if f.len() == 2 && matches!(arena.node(f[1]), Node::Pi) => arena.as_num(f[0]),
        _ => None,
    }
}

/// `c` as a whole number of quarter turns (c = k/2), reduced mod 4.
fn quarter_turns(c: Num) -> Option<i128> {
    let twice = (c * Num::int(2)).as_integer()?;
    Some(twice.rem_euclid(4))
}

fn build(arena: &mut Arena, fun: Fun, x: Id) -> Id {
    if let Some(c) = arena.as_num(x) {
        let v = c.to_f64();
        let value = match fun {
            Fun::Sin if c.is_zero() => Num::ZERO,
            Fun::Cos if c.is_zero() => Num::ONE,
            Fun::Sin => Num::Float(v.sin()),
            Fun::Cos => Num::Float(v.cos()),
        };
        return arena.num(value);
    }
    if let Some(c) = pi_multiple(arena, x) {
        if let Some(k) = quarter_turns(c) {
            // sin(k pi/2) = [0, 1, 0, -1][k]; cos(k pi/2) = [1, 0, -1, 0][k].
            let table = match fun {
                Fun::Sin => [0, 1, 0, -1],
                Fun::Cos => [1, 0, -1, 0],
            };
            return arena.int(table[k as usize]);
        }
        let v = c.to_f64() * std::f64::consts::PI;
        let value = if fun == Fun::Sin { v.sin() } else { v.cos() };
        return arena.num(Num::Float(value));
    }
    match arena.node(x).clone() {
        // sin(y + k pi/2): a quarter-turn shift swaps sin and cos and flips signs.
        Node::Add(terms) => {
            let shift = terms
                .iter()
                .position(|&t| pi_multiple(arena, t).and_then(quarter_turns).is_some());
            if let Some(p) = shift {
                let k = pi_multiple(arena, terms[p])
                    .and_then(quarter_turns)
                    .unwrap_or(0);
                let rest: Vec<Id> = terms
                    .iter()
                    .enumerate()
                    .filter(|&(i, _)| i != p)
                    .map(|(_, &t)| t)
                    .collect();
                let y = arena.add(&rest);
                // sin(y + k pi/2) = [sin, cos, -sin, -cos][k](y); cos(y + k pi/2) = [cos, -sin, -cos, sin][k](y)
                let (base, negate) = match (fun, k) {
                    (Fun::Sin, 0) => (Fun::Sin, false),
                    (Fun::Sin, 1) => (Fun::Cos, false),
                    (Fun::Sin, 2) => (Fun::Sin, true),
                    (Fun::Sin, _) => (Fun::Cos, true),
                    (Fun::Cos, 0) => (Fun::Cos, false),
                    (Fun::Cos, 1) => (Fun::Sin, true),
                    (Fun::Cos, 2) => (Fun::Cos, true),
                    (Fun::Cos, _) => (Fun::Sin, false),
                };
                let value = build(arena, base, y);
                return if negate { arena.neg(value) } else { value };
            }
        }
        // Parity: pull a negative coefficient out.
        Node::Mul(factors) => {
            if let Some(c) = arena.as_num(factors[0]).filter(|c| c.is_negative()) {
                let mut positive = factors.to_vec();
                positive[0] = arena.num(-c);
                let y = arena.mul(&positive);
                let value = build(arena, fun, y);
                return if fun == Fun::Sin {
                    arena.neg(value)
                } else {
                    value
                };
            }
        }
        _ => {}
    }
    arena.intern(match fun {
        Fun::Sin => Node::Sin(x),
        Fun::Cos => Node::Cos(x),
    })
}

#[cfg(test)]
mod tests {
    use crate::expr::Arena;

    #[test]
    fn dh_angles_are_exact() {
        let mut a = Arena::new();
        for (text, expected) in [
            ("sin(pi/2)", "1"),
            ("cos(pi/2)", "0"),
            ("cos(-pi/2)", "0"),
            ("sin(-pi/2)", "-1"),
            ("cos(pi)", "-1"),
            ("sin(3*pi/2)", "-1"),
            ("sin(q + pi/2)", "cos(q)"),
            ("cos(q - pi/2)", "sin(q)"),
            ("sin(q + pi)", "-sin(q)"),
            ("cos(-q)", "cos(q)"),
            ("sin(-q)", "-sin(q)"),
        ] {
            let e = a.parse(text).unwrap();
            assert_eq!(a.display(e), expected, "{text}");
        }
    }
}
