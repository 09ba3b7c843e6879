//! Partial sums shared between sums: where two sums (trees of additions and
//! subtractions, as in `factor.rs`) both add `x + y` (or both `x - y`, either sign of the
//! whole), `x +- y` is computed once and each reads it. The pair found in the most sums
//! is taken first, then the next (a pair may hold a pair), until no two sums share one;
//! each pair found in k sums saves k - 1 additions. A sum whose terms all end up
//! subtracted is negated, which costs what the pair saved in it, so no program gets
//! dearer; the pass keeps the program as it was if it would (it never does on the
//! reference robots).

use super::factor::{Term, flatten, mapped, mapped_outputs, pairwise};
use super::{Instr, Program, Value, dce};
use rustc_hash::FxHashMap;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// A term of a rewritten sum: a value of the old program or a shared pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Item {
    Old(Value),
    Pair(usize),
}

/// A pair of items and whether they have opposite signs (the lesser item first).
type Key = (Item, Item, bool);

/// The pair counts of the sums: the number of sums holding each pair, and the pairs held
/// by at least two, most held first.
#[derive(Default)]
struct Counts {
    all: FxHashMap<Key, usize>,
    /// Every count of two or more a pair reached, the largest first (of equal counts the
    /// least pair): those that are still the pair's count are the pairs to share. A heap
    /// with stale entries instead of a scan of all shared pairs for each one taken (which
    /// was half of a 20-joint chain's derivation).
    most: BinaryHeap<(usize, Reverse<Key>)>,
    /// Items of the old program found once in all the sums: a pair of two of them can
    /// never be counted twice (a pair replaces its items, so an old item is never found
    /// more often than at first; a pair with an item found twice in one sum, `x + y + x`,
    /// can), so such pairs are not counted. Most terms of long sums are such (a 12-joint
    /// chain's programs: 77 of the derivation's 98 MB were pair counts).
    lone: rustc_hash::FxHashSet<Item>,
}

impl Counts {
    /// Adds `delta` to the count of every pair of `sum`.
    fn recount(&mut self, sum: &[(Item, bool)], delta: isize) {
        for at in 0..sum.len() {
            self.count_pairs_with(sum, at, at + 1..sum.len(), delta);
        }
    }

    /// Adds `delta` to the count of the pair of `sum[at]` with each term at `others`
    /// (but itself): each pair of two terms is counted once, unless they are one item or
    /// both lone.
    fn count_pairs_with(
        &mut self,
        sum: &[(Item, bool)],
        at: usize,
        others: impl Iterator<Item = usize>,
        delta: isize,
    ) {
        let (x, sx) = sum[at];
        let x_lone = self.lone.contains(&x);
        for m in others.filter(|&m| m != at) {
            let (y, sy) = sum[m];
            if y == x || (x_lone && self.lone.contains(&y)) {
                continue;
            }
            let key = match x < y {
                true => (x, y, sx != sy),
                false => (y, x, sx != sy),
            };
            let c = self.all.entry(key).or_insert(0);
            *c = c
                .checked_add_signed(delta)
                .expect("a pair counted where it was");
            match *c {
                0 => _ = self.all.remove(&key),
                1 => {}
                c => self.most.push((c, Reverse(key))),
            }
        }
    }

    /// Replaces the terms at `i` and `j` of `sum` by `pair` (with the sign of the one at
    /// `i`), counting only the pairs that change: those of the two terms, then those of
    /// the pair.
    fn replace(&mut self, sum: &mut Vec<(Item, bool)>, i: usize, j: usize, pair: Item) {
        self.count_pairs_with(sum, i, 0..sum.len(), -1);
        self.count_pairs_with(sum, j, (0..sum.len()).filter(|&m| m != i), -1);
        let sign = sum[i].1;
        let (first, second) = (i.min(j), i.max(j));
        sum.remove(second);
        sum[first] = (pair, sign);
        self.count_pairs_with(sum, first, 0..sum.len(), 1);
    }

    /// The unit tests' check: the counts kept up to date are those of the sums now.
    #[cfg(test)]
    fn check(&self, terms: &[Vec<(Item, bool)>]) {
        let mut fresh = Counts {
            lone: self.lone.clone(),
            ..Counts::default()
        };
        for sum in terms {
            fresh.recount(sum, 1);
        }
        assert_eq!(fresh.all, self.all);
    }

    /// The pair held by the most sums (at least two; of equals the least pair).
    fn take_most_shared(&mut self) -> Option<Key> {
        while let Some((c, Reverse(key))) = self.most.pop() {
            if self.all.get(&key) == Some(&c) {
                return Some(key);
            }
        }
        None
    }
}

/// The program with partial sums shared between its sums, dead code removed.
pub(super) fn share_pairs(program: Program) -> Program {
    share(program, true)
}

/// [`share_pairs`], with the pairs of two items found once counted (`!skip_lone`) or not: the
/// same program either way, only the memory differs.
fn share(program: Program, skip_lone: bool) -> Program {
    let n = program.instrs.len();
    let mut uses = vec![0usize; n];
    let mut count = |v: Value| {
        if let Value::Temp(t) = v {
            uses[t as usize] += 1;
        }
    };
    program
        .instrs
        .iter()
        .flat_map(Instr::operands)
        .for_each(&mut count);
    program
        .outputs
        .iter()
        .flat_map(|o| o.values.iter().copied())
        .for_each(&mut count);
    let is_sum = |i: &Instr| matches!(i, Instr::Add(..) | Instr::Sub(..));
    let mut inner = vec![false; n];
    for instr in program.instrs.iter().filter(|i| is_sum(i)) {
        for v in instr.operands() {
            if let Value::Temp(t) = v
                && uses[t as usize] == 1
                && is_sum(&program.instrs[t as usize])
            {
                inner[t as usize] = true;
            }
        }
    }
    // The sums (roots of sum trees) and their signed terms.
    let roots: Vec<usize> = (0..n)
        .filter(|&i| is_sum(&program.instrs[i]) && !inner[i])
        .collect();
    let mut terms: Vec<Vec<(Item, bool)>> = roots
        .iter()
        .map(|&r| {
            let mut t: Vec<Term> = Vec::new();
            flatten(&program.instrs, &uses, r, false, &mut t);
            t.into_iter().map(|(v, s)| (Item::Old(v), s)).collect()
        })
        .collect();
    // Pairs (x, y, x and y of opposite signs), greedily, the most shared first (of
    // equals the least by the order of items, for determinism). The counts are kept up to
    // date as sums change; most pairs occur once, so the ones that occur more are few.
    let mut holders: FxHashMap<Item, Vec<usize>> = FxHashMap::default();
    for (k, sum) in terms.iter().enumerate() {
        for t in sum {
            holders.entry(t.0).or_default().push(k);
        }
    }
    let mut counts = Counts {
        lone: holders
            .iter()
            .filter(|(_, sums)| skip_lone && sums.len() == 1)
            .map(|(&item, _)| item)
            .collect(),
        ..Counts::default()
    };
    for sum in &terms {
        counts.recount(sum, 1);
    }
    let mut pairs: Vec<Key> = Vec::new();
    while let Some((x, y, opposite)) = counts.take_most_shared() {
        let p = Item::Pair(pairs.len());
        pairs.push((x, y, opposite));
        let mut sums = holders.get(&x).cloned().unwrap_or_default();
        sums.sort_unstable();
        sums.dedup();
        let mut replaced = false;
        for k in sums {
            let sum = &terms[k];
            // an x and a y with the pair's signs (a sum can hold x twice, `x + y - x`)
            let Some((i, j)) =
                sum.iter()
                    .enumerate()
                    .filter(|(_, t)| t.0 == x)
                    .find_map(|(i, tx)| {
                        let j = sum
                            .iter()
                            .position(|ty| ty.0 == y && (tx.1 != ty.1) == opposite);
                        j.map(|j| (i, j))
                    })
            else {
                continue;
            };
            replaced = true;
            // x + y (or x - y) with the sign of x
            counts.replace(&mut terms[k], i, j, p);
            holders.entry(p).or_default().push(k);
            #[cfg(test)]
            counts.check(&terms);
        }
        if !replaced {
            // cannot happen while the counts are right; never loop on a pair
            debug_assert!(false, "pair {:?} counted but in no sum", pairs.last());
            pairs.pop();
        }
    }
    if pairs.is_empty() {
        return program;
    }
    // The program again, each rewritten sum at its root's place, each pair written before
    // the first sum that reads it.
    let mut instrs: Vec<Instr> = Vec::with_capacity(n);
    let mut map: Vec<Value> = Vec::with_capacity(n);
    let mut written: Vec<Option<Value>> = vec![None; pairs.len()];
    let mut root_terms: FxHashMap<usize, Vec<(Item, bool)>> =
        roots.into_iter().zip(terms).collect();
    let mut emit = |instrs: &mut Vec<Instr>, i: Instr| {
        instrs.push(i);
        Value::Temp(instrs.len() as u32 - 1)
    };
    for (i, &instr) in program.instrs.iter().enumerate() {
        let value = match root_terms.remove(&i) {
            Some(sum) => {
                let flat: Vec<Term> = sum
                    .into_iter()
                    .map(|(item, s)| (item_value(item, &pairs, &mut written, &map, &mut instrs), s))
                    .collect();
                // an added term first, so that the sum needs no negation where it has one
                let mut flat = flat;
                if let Some(k) = flat.iter().position(|t| !t.1) {
                    let t = flat.remove(k);
                    flat.insert(0, t);
                }
                let (v, negative) = pairwise(&mut instrs, &flat, &mut emit);
                match negative {
                    true => emit(&mut instrs, Instr::Neg(v)),
                    false => v,
                }
            }
            None => emit(&mut instrs, instr.map(|v| mapped(&map, v))),
        };
        map.push(value);
    }
    let outputs = mapped_outputs(&program.outputs, &map);
    let shared = dce::remove_dead_code(Program {
        inputs: program.inputs.clone(),
        constants: program.constants.clone(),
        instrs,
        outputs,
    });
    match shared.operations().flops() < program.operations().flops() {
        true => shared,
        false => program,
    }
}

/// The value of `item` in the new program, writing the pairs it needs first.
fn item_value(
    item: Item,
    pairs: &[(Item, Item, bool)],
    written: &mut [Option<Value>],
    map: &[Value],
    instrs: &mut Vec<Instr>,
) -> Value {
    match item {
        Item::Old(v) => mapped(map, v),
        Item::Pair(k) => {
            if let Some(v) = written[k] {
                return v;
            }
            let (x, y, opposite) = pairs[k];
            let a = item_value(x, pairs, written, map, instrs);
            let b = item_value(y, pairs, written, map, instrs);
            instrs.push(match opposite {
                true => Instr::Sub(a, b),
                false => Instr::Add(a, b),
            });
            let v = Value::Temp(instrs.len() as u32 - 1);
            written[k] = Some(v);
            v
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Group, Instr, Output, Program, Value};
    use super::{share, share_pairs};
    use robid_core::rng::Rng;

    const X: Value = Value::Input(0);
    const Y: Value = Value::Input(1);
    const Z: Value = Value::Input(2);
    const W: Value = Value::Input(3);
    const T: fn(u32) -> Value = Value::Temp;

    /// A program of inputs `x y z w` with these instructions and outputs.
    fn program(instrs: Vec<Instr>, outputs: Vec<Value>) -> Program {
        let names = ["x", "y", "z", "w"].map(str::to_owned).to_vec();
        program_of(names, instrs, outputs)
    }

    /// A program of these inputs, instructions and outputs.
    fn program_of(names: Vec<String>, instrs: Vec<Instr>, outputs: Vec<Value>) -> Program {
        let out = (0..outputs.len()).map(|k| format!("out{k}")).collect();
        Program {
            inputs: vec![Group::new("in", names)],
            constants: vec![],
            instrs,
            outputs: vec![Output {
                group: Group::new("out", out),
                values: outputs,
            }],
        }
    }

    /// Both programs give the same outputs at random inputs.
    fn same_values(a: &Program, b: &Program) {
        let mut rng = Rng::from_state(5);
        for _ in 0..20 {
            let x: Vec<f64> = (0..a.inputs[0].elements.len())
                .map(|_| rng.uniform(-2.0, 2.0))
                .collect();
            let (u, v) = (a.eval(&[&x]).unwrap(), b.eval(&[&x]).unwrap());
            for (p, q) in u[0].iter().zip(&v[0]) {
                assert!((p - q).abs() <= 1e-14 * (1.0 + p.abs()), "{p} vs {q}");
            }
        }
    }

    /// `x + y + z` and `w - x - y` share `x + y` (added in one, subtracted in the other):
    /// 3 additions instead of 4, the same values; and `x - z` in `x - z + w` and
    /// `y + x - z` (a pair of opposite signs) is shared the same way.
    #[test]
    fn a_pair_in_two_sums_is_added_once() {
        let before = program(
            vec![
                Instr::Add(X, Y),    // t0
                Instr::Add(T(0), Z), // t1 = x + y + z
                Instr::Sub(W, X),    // t2
                Instr::Sub(T(2), Y), // t3 = w - x - y
            ],
            vec![T(1), T(3)],
        );
        let after = share_pairs(before.clone());
        assert_eq!(before.operations().add, 4);
        assert_eq!(after.operations().add, 3, "{after}");
        assert_eq!(after.operations().neg, 0);
        same_values(&before, &after);
        let before = program(
            vec![
                Instr::Sub(X, Z),    // t0
                Instr::Add(T(0), W), // t1 = x - z + w
                Instr::Add(Y, X),    // t2
                Instr::Sub(T(2), Z), // t3 = y + x - z
            ],
            vec![T(1), T(3)],
        );
        let after = share_pairs(before.clone());
        assert_eq!(after.operations().add, 3, "{after}");
        same_values(&before, &after);
    }

    /// Sums that share no pair, or share one with the other relative sign (`x + y` and
    /// `x - y`), are left as they are.
    #[test]
    fn sums_without_a_common_pair_are_unchanged() {
        let before = program(
            vec![
                Instr::Add(X, Y),    // t0
                Instr::Add(T(0), Z), // t1 = x + y + z
                Instr::Sub(X, Y),    // t2
                Instr::Add(T(2), W), // t3 = x - y + w
            ],
            vec![T(1), T(3)],
        );
        assert_eq!(share_pairs(before.clone()), before);
    }

    /// Random sums of random signed terms: the same values, never more operations.
    #[test]
    fn shared_pairs_keep_values_and_never_cost() {
        let mut rng = Rng::from_state(8);
        let inputs = [X, Y, Z, W];
        let mut saved = 0;
        for _ in 0..200 {
            let mut instrs = Vec::new();
            let mut outputs = Vec::new();
            for _ in 0..1 + rng.below(4) {
                // a sum of 2 to 4 distinct inputs with random signs, added left to right
                let mut pick = inputs.to_vec();
                let k = 2 + rng.below(3);
                let mut acc = pick.remove(rng.below(pick.len()));
                for _ in 1..k {
                    let v = pick.remove(rng.below(pick.len()));
                    instrs.push(match rng.below(2) {
                        0 => Instr::Add(acc, v),
                        _ => Instr::Sub(acc, v),
                    });
                    acc = T(instrs.len() as u32 - 1);
                }
                outputs.push(acc);
            }
            let before = program(instrs, outputs);
            let after = share_pairs(before.clone());
            same_values(&before, &after);
            let (b, a) = (before.operations().flops(), after.operations().flops());
            assert!(a <= b, "{before}\n{after}");
            saved += b - a;
        }
        assert!(saved > 50, "{saved}");
    }

    /// Leaving out the pairs of two items found once changes no program, also where an
    /// item is found twice in one sum (`x - (y - x)`: the pair of x and y is in it twice),
    /// and a sum holding an item with both signs (`x + y - x`) ends (the pass looped on such
    /// a pair, taking the first x whatever its sign).
    #[test]
    fn pairs_of_lone_items_are_not_counted_and_change_nothing() {
        let mut rng = Rng::from_state(9);
        let inputs: Vec<Value> = (0..8).map(Value::Input).collect();
        let mut repeated = 0;
        for _ in 0..300 {
            let mut instrs = Vec::new();
            let mut outputs = Vec::new();
            for _ in 0..1 + rng.below(4) {
                // inputs drawn with replacement, some sums nested in others
                let mut acc = inputs[rng.below(8)];
                for _ in 0..1 + rng.below(5) {
                    let v = match rng.below(4) {
                        0 if !instrs.is_empty() => T(rng.below(instrs.len()) as u32),
                        _ => inputs[rng.below(8)],
                    };
                    repeated += usize::from(v == acc);
                    instrs.push(match rng.below(2) {
                        0 => Instr::Add(acc, v),
                        _ => Instr::Sub(v, acc),
                    });
                    acc = T(instrs.len() as u32 - 1);
                }
                outputs.push(acc);
            }
            let before = program_of((0..8).map(|k| format!("x{k}")).collect(), instrs, outputs);
            let (fast, full) = (share(before.clone(), true), share(before.clone(), false));
            assert_eq!(fast.to_string(), full.to_string(), "{before}");
            same_values(&before, &fast);
            assert!(fast.operations().flops() <= before.operations().flops());
        }
        assert!(repeated > 20, "{repeated}");
    }
}
