//! Factoring by distributivity: in a sum, products that share a factor and are read by
//! nothing else, `p x + p y - p z`, become one product `p (x + y - z)`.
//!
//! A sum here is a tree of additions and subtractions whose inner nodes are read by
//! nothing but their parent (the lowering adds terms pairwise, so one sum of many
//! terms is such a tree); its leaves are the terms, each with its sign. Among the terms
//! that are products read only by this sum, the factor shared by the most of them is
//! taken out (k products and k - 1 additions become one product and k - 1 additions),
//! then the next, until no two of them share a factor. The number of additions stays
//! the same, so the program loses k - 1 multiplications per group and gains nothing:
//! no program gets dearer. The sum is written again at the place of its root, in the
//! order of its terms, so the program stays in topological order; the instructions it
//! no longer reads are dead code, removed afterwards.
//!
//! Where it pays in the robots' programs: the last link's wrench written in its
//! parent's frame (docs/dynamics.md#customised-newton-euler) shares products of the
//! angular velocity and the acceleration of the parent's origin with the parent's own
//! Euler equation and `MS x vd`, and the sum of the two moments multiplies them by
//! both links' parameters.

use super::{Instr, Program, Value, dce};

/// A term of a sum: a value and whether it is subtracted.
pub(super) type Term = (Value, bool);

/// The program with common factors taken out of its sums until none is left (taking
/// some out can leave two products of a new sum sharing another), dead code removed.
pub(in crate::program) fn factor_all(mut program: Program) -> Program {
    loop {
        let before = program.instrs.len();
        program = factor_sums(program);
        // Each pass that changes something removes instructions.
        if program.instrs.len() == before {
            return program;
        }
    }
}

/// The program with common factors taken out of its sums once, dead code removed.
fn factor_sums(program: Program) -> Program {
    let n = program.instrs.len();
    let mut uses = vec![0usize; n];
    let count = |v: Value, uses: &mut Vec<usize>| {
        if let Value::Temp(t) = v {
            uses[t as usize] += 1;
        }
    };
    for instr in &program.instrs {
        for v in instr.operands() {
            count(v, &mut uses);
        }
    }
    for o in &program.outputs {
        for &v in &o.values {
            count(v, &mut uses);
        }
    }
    let is_sum = |i: &Instr| matches!(i, Instr::Add(..) | Instr::Sub(..));
    // A sum read once, by a sum, is part of that sum's tree.
    let mut inner = vec![false; n];
    for instr in &program.instrs {
        if is_sum(instr) {
            for v in instr.operands() {
                if let Value::Temp(t) = v
                    && uses[t as usize] == 1
                    && is_sum(&program.instrs[t as usize])
                {
                    inner[t as usize] = true;
                }
            }
        }
    }
    let mut instrs: Vec<Instr> = Vec::with_capacity(n);
    let mut map: Vec<Value> = Vec::with_capacity(n);
    let mut changed = false;
    for (i, &instr) in program.instrs.iter().enumerate() {
        let rewritten = match is_sum(&instr) && !inner[i] {
            true => factored(&program.instrs, &uses, i),
            false => None,
        };
        let value = match rewritten {
            Some(terms) => {
                changed = true;
                let terms: Vec<Rebuilt> = terms
                    .into_iter()
                    .map(|t| match t {
                        Rebuilt::Plain((v, s)) => Rebuilt::Plain((mapped(&map, v), s)),
                        Rebuilt::Product(p, group, s) => Rebuilt::Product(
                            mapped(&map, p),
                            group
                                .into_iter()
                                .map(|(v, s)| (mapped(&map, v), s))
                                .collect(),
                            s,
                        ),
                    })
                    .collect();
                write_sum(&mut instrs, terms)
            }
            None => {
                instrs.push(instr.map(|v| mapped(&map, v)));
                Value::Temp(instrs.len() as u32 - 1)
            }
        };
        map.push(value);
    }
    if !changed {
        return program;
    }
    let outputs = mapped_outputs(&program.outputs, &map);
    dce::remove_dead_code(Program {
        inputs: program.inputs,
        constants: program.constants,
        instrs,
        outputs,
    })
}

pub(super) fn mapped(map: &[Value], v: Value) -> Value {
    match v {
        Value::Temp(t) => map[t as usize],
        other => other,
    }
}

/// The outputs with each temporary replaced by its value in the rewritten program.
pub(super) fn mapped_outputs(outputs: &[super::Output], map: &[Value]) -> Vec<super::Output> {
    outputs
        .iter()
        .map(|o| super::Output {
            group: o.group.clone(),
            values: o.values.iter().map(|&v| mapped(map, v)).collect(),
        })
        .collect()
}

/// A term of the rewritten sum: a term of the old one, or a factor times the sum of
/// the other factors of a group of products, with the sign of the whole.
enum Rebuilt {
    Plain(Term),
    Product(Value, Vec<Term>, bool),
}

/// The terms of sum `root` with its common factors taken out, or `None` when no two of
/// its products (read by nothing else) share a factor.
fn factored(instrs: &[Instr], uses: &[usize], root: usize) -> Option<Vec<Rebuilt>> {
    let mut terms: Vec<Term> = Vec::new();
    flatten(instrs, uses, root, false, &mut terms);
    // The products read only by this sum, as (index in terms, factors).
    let product = |&(v, _): &Term| match v {
        Value::Temp(t) if uses[t as usize] == 1 => match instrs[t as usize] {
            Instr::Mul(a, b) => Some((a, b)),
            _ => None,
        },
        _ => None,
    };
    let mut free: Vec<bool> = terms.iter().map(|t| product(t).is_some()).collect();
    let mut out: Vec<Rebuilt> = Vec::new();
    let mut taken = vec![false; terms.len()];
    loop {
        // The factor shared by the most free products (the first such, for determinism).
        let mut best: Option<(Value, usize)> = None;
        let mut candidates: Vec<Value> = Vec::new();
        for (k, t) in terms.iter().enumerate() {
            if let (true, Some((a, b))) = (free[k], product(t)) {
                candidates.push(a);
                candidates.push(b);
            }
        }
        for &f in &candidates {
            let count = terms
                .iter()
                .enumerate()
                .filter(|&(k, t)| free[k] && product(t).is_some_and(|(a, b)| a == f || b == f))
                .count();
            if count >= 2 && best.is_none_or(|(_, c)| count > c) {
                best = Some((f, count));
            }
        }
        let Some((f, _)) = best else { break };
        let mut group: Vec<Term> = Vec::new();
        for (k, t) in terms.iter().enumerate() {
            if let (true, Some((a, b))) = (free[k], product(t))
                && (a == f || b == f)
            {
                let other = if a == f { b } else { a };
                group.push((other, t.1));
                free[k] = false;
                taken[k] = true;
            }
        }
        // The sign of the whole is that of the group's first term, so that the inner
        // sum begins with a term added.
        let negative = group[0].1;
        let group = group.into_iter().map(|(v, s)| (v, s != negative)).collect();
        out.push(Rebuilt::Product(f, group, negative));
    }
    if out.is_empty() {
        return None;
    }
    // The terms left, in their order, then the products.
    let mut rebuilt: Vec<Rebuilt> = terms
        .into_iter()
        .zip(taken)
        .filter(|(_, taken)| !taken)
        .map(|(t, _)| Rebuilt::Plain(t))
        .collect();
    rebuilt.extend(out);
    Some(rebuilt)
}

/// The terms of the sum tree at `at`, with signs, into `terms`.
pub(super) fn flatten(
    instrs: &[Instr],
    uses: &[usize],
    at: usize,
    negative: bool,
    terms: &mut Vec<Term>,
) {
    let (a, b, sub) = match instrs[at] {
        Instr::Add(a, b) => (a, b, false),
        Instr::Sub(a, b) => (a, b, true),
        _ => unreachable!("flatten is called on sums"),
    };
    for (v, s) in [(a, negative), (b, negative != sub)] {
        match v {
            Value::Temp(t)
                if uses[t as usize] == 1
                    && matches!(instrs[t as usize], Instr::Add(..) | Instr::Sub(..)) =>
            {
                flatten(instrs, uses, t as usize, s, terms)
            }
            _ => terms.push((v, s)),
        }
    }
}

/// Writes the sum of `terms` (pairwise, as the lowering adds) at the end of `instrs`;
/// returns its value. Its first term is added, so the sum needs no negation.
fn write_sum(instrs: &mut Vec<Instr>, terms: Vec<Rebuilt>) -> Value {
    let mut emit = |instrs: &mut Vec<Instr>, i: Instr| {
        instrs.push(i);
        Value::Temp(instrs.len() as u32 - 1)
    };
    let mut flat: Vec<Term> = Vec::with_capacity(terms.len());
    for t in terms {
        match t {
            Rebuilt::Plain(t) => flat.push(t),
            Rebuilt::Product(f, group, negative) => {
                let (inner, inner_negative) = pairwise(instrs, &group, &mut emit);
                let p = emit(instrs, Instr::Mul(f, inner));
                flat.push((p, negative != inner_negative));
            }
        }
    }
    // An added term first (there is one: the first term of the old sum is added, and
    // the group it went into carries its sign).
    if let Some(k) = flat.iter().position(|t| !t.1) {
        let t = flat.remove(k);
        flat.insert(0, t);
    }
    let (value, negative) = pairwise(instrs, &flat, &mut emit);
    debug_assert!(!negative, "a sum with an added term is not negative");
    value
}

/// The pairwise sum of signed terms: its value and whether it is the negative of it.
pub(super) fn pairwise(
    instrs: &mut Vec<Instr>,
    terms: &[Term],
    emit: &mut impl FnMut(&mut Vec<Instr>, Instr) -> Value,
) -> (Value, bool) {
    match terms {
        [] => unreachable!("sums have terms"),
        [one] => *one,
        _ => {
            let (left, right) = terms.split_at(terms.len() / 2);
            let (a, an) = pairwise(instrs, left, emit);
            let (b, bn) = pairwise(instrs, right, emit);
            match (an, bn) {
                (false, false) => (emit(instrs, Instr::Add(a, b)), false),
                (true, true) => (emit(instrs, Instr::Add(a, b)), true),
                (false, true) => (emit(instrs, Instr::Sub(a, b)), false),
                (true, false) => (emit(instrs, Instr::Sub(b, a)), false),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Group, Instr, Output, Program, Value};
    use super::factor_all;
    use robid_core::rng::Rng;

    /// A program of inputs `p x y z w` with these instructions and one output, the last.
    fn program(instrs: Vec<Instr>) -> Program {
        let last = Value::Temp(instrs.len() as u32 - 1);
        let names = ["p", "x", "y", "z", "w"].map(str::to_owned).to_vec();
        Program {
            inputs: vec![Group::new("in", names)],
            constants: vec![],
            instrs,
            outputs: vec![Output {
                group: Group::new("out", vec!["out0".to_owned()]),
                values: vec![last],
            }],
        }
    }

    const P: Value = Value::Input(0);
    const X: Value = Value::Input(1);
    const Y: Value = Value::Input(2);
    const Z: Value = Value::Input(3);
    const W: Value = Value::Input(4);

    /// Both programs give the same output at random inputs.
    fn same_values(a: &Program, b: &Program) {
        let mut rng = Rng::from_state(3);
        for _ in 0..20 {
            let x: Vec<f64> = (0..5).map(|_| rng.uniform(-2.0, 2.0)).collect();
            let (u, v) = (a.eval(&[&x]).unwrap(), b.eval(&[&x]).unwrap());
            assert!((u[0][0] - v[0][0]).abs() <= 1e-14 * (1.0 + u[0][0].abs()));
        }
    }

    /// `p x + z - p y` (the products in different branches of the sum's tree) is
    /// `z + p (x - y)`: one multiplication fewer, the same additions, no negation.
    #[test]
    fn a_shared_factor_is_taken_out_of_a_sum() {
        let before = program(vec![
            Instr::Mul(P, X),                           // t0
            Instr::Mul(Y, P),                           // t1
            Instr::Add(Value::Temp(0), Z),              // t2
            Instr::Sub(Value::Temp(2), Value::Temp(1)), // t3
        ]);
        let after = factor_all(before.clone());
        let (b, a) = (before.operations(), after.operations());
        assert_eq!((b.mul, b.add), (2, 2));
        assert_eq!((a.mul, a.add, a.neg), (1, 2, 0), "{after}");
        same_values(&before, &after);
    }

    /// A sum whose every product is subtracted, `w - p x - p y`, keeps `w` first: `w - p
    /// (x + y)`; and of `p x + p y + z x`, `p` is taken out once and `x` not again.
    #[test]
    fn signs_are_kept_and_a_product_goes_to_one_group() {
        let before = program(vec![
            Instr::Mul(P, X),                           // t0
            Instr::Mul(P, Y),                           // t1
            Instr::Sub(W, Value::Temp(0)),              // t2
            Instr::Sub(Value::Temp(2), Value::Temp(1)), // t3
        ]);
        let after = factor_all(before.clone());
        assert_eq!(after.operations().mul, 1, "{after}");
        assert_eq!(after.operations().neg, 0, "{after}");
        same_values(&before, &after);
        let before = program(vec![
            Instr::Mul(P, X),                           // t0
            Instr::Mul(P, Y),                           // t1
            Instr::Mul(Z, X),                           // t2
            Instr::Add(Value::Temp(0), Value::Temp(1)), // t3
            Instr::Add(Value::Temp(3), Value::Temp(2)), // t4
        ]);
        let after = factor_all(before.clone());
        assert_eq!(after.operations().mul, 2, "{after}");
        assert_eq!(after.operations().add, 2, "{after}");
        same_values(&before, &after);
    }

    /// A product that something else reads too stays as it is (taking the factor out
    /// would not remove it), and so does a sum read twice (each reader keeps its value).
    #[test]
    fn products_read_elsewhere_are_kept() {
        let before = program(vec![
            Instr::Mul(P, X),                           // t0
            Instr::Mul(P, Y),                           // t1
            Instr::Add(Value::Temp(0), Value::Temp(1)), // t2
            Instr::Mul(Value::Temp(2), Value::Temp(0)), // t3: t0 read twice
        ]);
        let after = factor_all(before.clone());
        assert_eq!(after, before);
    }

    /// Random programs of sums, differences, products and negations (products sharing
    /// factors, sums read twice, products read elsewhere, squares, constants), at
    /// integer inputs small enough that every value is exact in f64: the factored
    /// program gives exactly the values of the program as written, in topological
    /// order, with no operation more.
    #[test]
    fn random_programs_keep_their_values() {
        let mut rng = Rng::from_state(11);
        let mut factored = 0;
        for case in 0..3000 {
            let inputs = 5;
            let constants = [2.0, -3.0, 0.5];
            // a factor: mostly one of few inputs or a constant, so that products share it
            let factor = |rng: &mut Rng, temps: usize| -> Value {
                match rng.below(8) {
                    0 if temps > 0 => Value::Temp(rng.below(temps) as u32),
                    1 => Value::Const(rng.below(constants.len()) as u32),
                    k => Value::Input((k % 3) as u32 + rng.below(2) as u32),
                }
            };
            let n = 2 + rng.below(60);
            let mut instrs = Vec::new();
            // values not read yet: sums take two of them, so that most sums are trees
            // of terms read once, and some are read again
            let mut open: Vec<Value> = Vec::new();
            for i in 0..n {
                let take = |rng: &mut Rng, open: &mut Vec<Value>| match open.len() {
                    0 => Value::Input(rng.below(inputs) as u32),
                    k if rng.below(8) == 0 => open[rng.below(k)],
                    k => open.swap_remove(rng.below(k)),
                };
                let instr = match rng.below(10) {
                    0..=4 => Instr::Mul(factor(&mut rng, i), factor(&mut rng, i)),
                    5..=6 => Instr::Add(take(&mut rng, &mut open), take(&mut rng, &mut open)),
                    7..=8 => Instr::Sub(take(&mut rng, &mut open), take(&mut rng, &mut open)),
                    _ => Instr::Neg(take(&mut rng, &mut open)),
                };
                instrs.push(instr);
                open.push(Value::Temp(i as u32));
            }
            let mut values = vec![Value::Temp(n as u32 - 1)];
            for _ in 0..rng.below(4) {
                values.push(Value::Temp(rng.below(n) as u32));
            }
            let names = (0..inputs).map(|k| format!("x{k}")).collect();
            let outs = (0..values.len()).map(|k| format!("o{k}")).collect();
            let before = Program {
                inputs: vec![Group::new("in", names)],
                constants: constants.to_vec(),
                instrs,
                outputs: vec![Output {
                    group: Group::new("out", outs),
                    values,
                }],
            };
            // a bound of every value of both programs (each a sum of the same
            // products): below 2^50, integer arithmetic is exact
            let bound = |v: Value, b: &[f64]| match v {
                Value::Temp(t) => b[t as usize],
                Value::Input(_) => 3.0,
                Value::Const(k) => constants[k as usize].abs(),
            };
            let mut b: Vec<f64> = Vec::new();
            for instr in &before.instrs {
                let x = match *instr {
                    Instr::Add(p, q) | Instr::Sub(p, q) => bound(p, &b) + bound(q, &b),
                    Instr::Mul(p, q) => bound(p, &b) * bound(q, &b),
                    Instr::Neg(p) => bound(p, &b),
                    _ => unreachable!(),
                };
                b.push(x);
            }
            if b.iter().any(|&x| x > 2f64.powi(40)) {
                continue;
            }
            let after = factor_all(before.clone());
            factored += usize::from(after.operations().mul < before.operations().mul);
            for (i, instr) in after.instrs.iter().enumerate() {
                for v in instr.operands() {
                    if let Value::Temp(t) = v {
                        assert!((t as usize) < i, "case {case}: {after}");
                    }
                }
            }
            let (ob, oa) = (before.operations(), after.operations());
            assert!(
                oa.mul <= ob.mul && oa.add <= ob.add && oa.neg <= ob.neg,
                "case {case}:\n{before}\n->\n{after}"
            );
            for _ in 0..5 {
                let x: Vec<f64> = (0..inputs).map(|_| rng.below(7) as f64 - 3.0).collect();
                let (u, v) = (before.eval(&[&x]).unwrap(), after.eval(&[&x]).unwrap());
                assert_eq!(u, v, "case {case} at {x:?}:\n{before}\n->\n{after}");
            }
        }
        // the pass has work in many of them
        assert!(factored > 500, "{factored} programs factored");
    }
}
