//! sin(x)^2 + cos(x)^2 = 1, also inside products: c m sin^2 + c m cos^2 = c m.

use crate::expr::{Arena, Id, Node, Num};

/// Merges pairs of collected terms `(c, m sin(x)^2)` and `(c, m cos(x)^2)`.
pub(crate) fn sin2_plus_cos2(arena: &mut Arena, terms: &mut Vec<(Num, Option<Id>)>) {
    let mut i = 0;
    while i < terms.len() {
        let (c, Some(m)) = terms[i] else {
            i += 1;
            continue;
        };
        let merged = partner(arena, m).and_then(|(partner, rest)| {
            let j = terms
                .iter()
                .position(|&(d, n)| n == Some(partner) && d == c && !d.is_zero())?;
            Some((j, rest))
        });
        match merged {
            Some((j, rest)) => {
                terms[i].0 = Num::ZERO;
                terms[j].0 = Num::ZERO;
                match terms.iter().position(|&(_, n)| n == rest) {
                    Some(k) => terms[k].0 = terms[k].0 + c,
                    None => terms.push((c, rest)),
                }
                terms.retain(|(d, _)| !d.is_zero());
                i = 0;
            }
            None => i += 1,
        }
    }
}

/// For a monomial holding sin(x)^2: the existing monomial with cos(x)^2 in its
/// place, and the monomial without it (`None` = 1).
fn partner(arena: &mut Arena, m: Id) -> Option<(Id, Option<Id>)> {
    let factors: Vec<Id> = match arena.node(m) {
        Node::Mul(f) => f.to_vec(),
        _ => vec![m],
    };
    for (k, &f) in factors.iter().enumerate() {
        let Node::Pow(base, 2) = *arena.node(f) else {
            continue;
        };
        let Node::Sin(x) = *arena.node(base) else {
            continue;
        };
        let cos_x = arena.lookup(&Node::Cos(x))?;
        let cos2 = arena.lookup(&Node::Pow(cos_x, 2))?;
        let mut swapped = factors.clone();
        swapped[k] = cos2;
        swapped.sort_unstable();
        let partner = match swapped.len() {
            1 => cos2,
            _ => arena.lookup(&Node::Mul(swapped.into()))?,
        };
        let mut rest = factors.clone();
        rest.remove(k);
        let rest = match rest.len() {
            0 => None,
            1 => Some(rest[0]),
            _ => Some(arena.intern(Node::Mul(rest.into()))),
        };
        return Some((partner, rest));
    }
    None
}

#[cfg(test)]
mod tests {
    use crate::expr::Arena;

    #[test]
    fn pythagoras_in_sums_and_products() {
        let mut a = Arena::new();
        let one = a.parse("sin(q)^2 + cos(q)^2").unwrap();
        assert!(a.is_one(one));
        let e = a.parse("3*L*sin(q)^2*y + 3*L*y*cos(q)^2 + 1").unwrap();
        let f = a.parse("3*L*y + 1").unwrap();
        assert_eq!(e, f);
    }
}
