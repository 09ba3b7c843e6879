//! Collecting: nested sums and products are flattened, like terms of a sum
//! add their coefficients (2x + 3x = 5x) and equal bases of a product add
//! their exponents (x * x^2 = x^3).

use crate::expr::{Arena, Id, Node, Num};
use rustc_hash::FxHashMap;

/// Operands with nested operations of the same kind spliced in.
pub(crate) fn flatten(
    arena: &Arena,
    operands: &[Id],
    same_kind: impl Fn(&Node) -> Option<&[Id]>,
) -> Vec<Id> {
    let mut out = Vec::with_capacity(operands.len());
    for &x in operands {
        match same_kind(arena.node(x)) {
            Some(inner) => out.extend_from_slice(inner),
            None => out.push(x),
        }
    }
    out
}

/// Groups terms by monomial, summing coefficients; first-seen order.
pub(crate) fn like_terms(arena: &mut Arena, terms: &[Id]) -> Vec<(Num, Option<Id>)> {
    let mut index: FxHashMap<Option<Id>, usize> =
        FxHashMap::with_capacity_and_hasher(terms.len(), Default::default());
    let mut out: Vec<(Num, Option<Id>)> = Vec::with_capacity(terms.len());
    for &t in terms {
        let (c, m) = arena.split_term(t);
        match index.get(&m) {
            Some(&i) => out[i].0 = out[i].0 + c,
            None => {
                index.insert(m, out.len());
                out.push((c, m));
            }
        }
    }
    out
}

/// Groups factors by base, summing exponents; first-seen order.
pub(crate) fn like_factors(arena: &mut Arena, factors: &[Id]) -> Vec<Id> {
    let mut index: FxHashMap<Id, usize> =
        FxHashMap::with_capacity_and_hasher(factors.len(), Default::default());
    let mut grouped: Vec<(Id, i32)> = Vec::with_capacity(factors.len());
    for &f in factors {
        let (base, exponent) = match arena.node(f) {
            Node::Pow(b, e) => (*b, *e),
            _ => (f, 1),
        };
        // A sum of exponents that does not fit stays a separate factor.
        let merged = index
            .get(&base)
            .and_then(|&i| Some((i, grouped[i].1.checked_add(exponent)?)));
        match merged {
            Some((i, sum)) => grouped[i].1 = sum,
            None => {
                index.insert(base, grouped.len());
                grouped.push((base, exponent));
            }
        }
    }
    if grouped.len() == factors.len() {
        return factors.to_vec();
    }
    grouped
        .into_iter()
        .filter(|&(_, e)| e != 0)
        .map(|(b, e)| arena.pow(b, e))
        .collect()
}

#[cfg(test)]
mod tests {
    use crate::expr::Arena;

    #[test]
    fn like_terms_and_powers_collect() {
        let mut a = Arena::new();
        let e = a.parse("2*x*y + 3*y*x - x*y").unwrap();
        let f = a.parse("4*x*y").unwrap();
        assert_eq!(e, f);
        let p = a.parse("x * x^2 * y / x").unwrap();
        let q = a.parse("x^2 * y").unwrap();
        assert_eq!(p, q);
        let z = a.parse("x - x").unwrap();
        assert!(a.is_zero(z));
    }
}
