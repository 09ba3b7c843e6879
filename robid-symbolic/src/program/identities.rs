//! Identities found by running the program: instructions that are zero for every input,
//! folded to an exact 0, and instructions equal to an earlier one for every input,
//! replaced by it.
//!
//! The customised recursions build some entries as a difference of two products that
//! are equal for every input but whose factors were multiplied in another order, e.g. a
//! `ZZ2` entry of the base regressor `s (c qd1 qd2) - c (s qd1 qd2)` (a second axis
//! perpendicular to the first), and compute some values twice by different routes (a
//! regressor entry of one parameter equal to another's). Hash-consing sees different
//! operations; computed, the difference is rounding (1e-17), not 0, so the program
//! spends operations on noise and a regressor column that should be exactly zero in that
//! row is not (a least-squares fit scales such a column to unit norm).
//!
//! The program is run at a few random inputs with a running bound on each value's
//! rounding error (each operation's own rounding plus what its operands carry, to first
//! order). An instruction within a few times that bound of 0 at every sample is zero, as
//! a polynomial identity would be (a nonzero function of random inputs is not that small
//! at all of them); one within the two bounds of an earlier instruction at every sample
//! is that instruction. Either replacement moves the outputs by no more than the rounding
//! the program already carried there. The instructions that read a zero are simplified
//! exactly (`x * 0 = 0`, `x + 0 = x`, `cos 0 = 1`), and what is no longer read is
//! removed.

use super::factor::{mapped, mapped_outputs};
use super::{Instr, Program, Value, dce};
use robid_core::rng::Rng;

/// Random inputs at which the program is run.
const SAMPLES: usize = 4;

/// A value within this many times its rounding bound of 0 is zero at that sample.
const MARGIN: f64 = 4.0;

/// The unit roundoff of `f64`.
const UNIT: f64 = f64::EPSILON / 2.0;

/// A computed value and a bound on its rounding error.
#[derive(Clone, Copy, Debug)]
struct Bounded {
    value: f64,
    error: f64,
}

impl Bounded {
    fn exact(value: f64) -> Bounded {
        Bounded { value, error: 0.0 }
    }

    /// `value` computed from operands carrying `carried`, then rounded.
    fn rounded(value: f64, carried: f64) -> Bounded {
        Bounded {
            value,
            error: carried + UNIT * value.abs(),
        }
    }

    /// Zero to within its rounding; a value that is not finite (a square root of a
    /// negative sample) never is.
    fn is_zero(self) -> bool {
        self.value.is_finite() && self.error.is_finite() && self.value.abs() <= MARGIN * self.error
    }
}

/// Runs `instr` on bounded operands.
fn step(instr: &Instr, get: impl Fn(Value) -> Bounded) -> Bounded {
    match *instr {
        Instr::Add(a, b) | Instr::Sub(a, b) => {
            let (a, b) = (get(a), get(b));
            let value = if matches!(instr, Instr::Add(..)) {
                a.value + b.value
            } else {
                a.value - b.value
            };
            Bounded::rounded(value, a.error + b.error)
        }
        Instr::Mul(a, b) => {
            let (a, b) = (get(a), get(b));
            let carried = a.value.abs() * b.error + b.value.abs() * a.error + a.error * b.error;
            Bounded::rounded(a.value * b.value, carried)
        }
        Instr::Div(a, b) => {
            let (a, b) = (get(a), get(b));
            let value = a.value / b.value;
            let carried = if b.value.abs() > b.error {
                (a.error + value.abs() * b.error) / (b.value.abs() - b.error)
            } else {
                f64::INFINITY
            };
            Bounded::rounded(value, carried)
        }
        Instr::Neg(a) => {
            let a = get(a);
            Bounded {
                value: -a.value,
                error: a.error,
            }
        }
        // Slopes of at most 1, and the library's own rounding (an ulp of at most 1).
        Instr::Sin(a) => {
            let a = get(a);
            Bounded::rounded(a.value.sin(), a.error + f64::EPSILON)
        }
        Instr::Cos(a) => {
            let a = get(a);
            Bounded::rounded(a.value.cos(), a.error + f64::EPSILON)
        }
        // Piecewise (see `piecewise`): never judged by their runs, nor what reads them,
        // so no bound is kept.
        Instr::Sign(a) => {
            let a = get(a).value;
            Bounded::exact(if a == 0.0 { 0.0 } else { a.signum() })
        }
        Instr::Sqrt(a) => Bounded::exact(get(a).value.sqrt()),
    }
}

/// Each instruction's bounded value at [`SAMPLES`] random inputs (each input element of
/// magnitude 0.5 to 2 with a random sign, so no velocity is 0).
fn run_at_random_inputs(program: &Program) -> Vec<[Bounded; SAMPLES]> {
    let mut rng = Rng::from_state(0x2E80);
    let mut runs = vec![[Bounded::exact(0.0); SAMPLES]; program.instrs.len()];
    let mut values: Vec<Bounded> = Vec::with_capacity(program.instrs.len());
    for k in 0..SAMPLES {
        let inputs: Vec<f64> = (0..program.input_len())
            .map(|_| {
                let size = rng.uniform(0.5, 2.0);
                if rng.below(2) == 0 { size } else { -size }
            })
            .collect();
        values.clear();
        for instr in &program.instrs {
            let get = |v: Value| match v {
                Value::Temp(t) => values[t as usize],
                Value::Input(i) => Bounded::exact(inputs[i as usize]),
                Value::Const(c) => Bounded::exact(program.constants[c as usize]),
            };
            let b = step(instr, get);
            values.push(b);
        }
        for (run, b) in runs.iter_mut().zip(&values) {
            run[k] = *b;
        }
    }
    runs
}

/// The same value within both rounding bounds.
fn same(a: Bounded, b: Bounded) -> bool {
    a.value.is_finite()
        && b.value.is_finite()
        && (a.value - b.value).abs() <= MARGIN * (a.error + b.error)
}

/// Which instructions read, at some depth, a sign or a square root: functions that are
/// not polynomials in the inputs and their sines and cosines, so that agreeing at a few
/// random inputs proves nothing (`sign(qd1)` and `sign(qd2)` agree at four samples one
/// time in 16, `sqrt(x^2)` and `x` wherever `x` was drawn positive).
fn piecewise(program: &Program) -> Vec<bool> {
    let mut out: Vec<bool> = Vec::with_capacity(program.instrs.len());
    for instr in &program.instrs {
        let reads = instr
            .operands()
            .into_iter()
            .any(|v| matches!(v, Value::Temp(t) if out[t as usize]));
        out.push(reads || matches!(instr, Instr::Sign(_) | Instr::Sqrt(_)));
    }
    out
}

/// For each instruction, the earliest earlier instruction equal to it at every sample
/// (instructions zero at every sample left out: they fold to 0; piecewise ones too).
fn earlier_equals(
    runs: &[[Bounded; SAMPLES]],
    zero: &[bool],
    piecewise: &[bool],
) -> Vec<Option<usize>> {
    let mut order: Vec<usize> = (0..runs.len())
        .filter(|&t| !zero[t] && !piecewise[t] && runs[t][0].value.is_finite())
        .collect();
    order.sort_by(|&a, &b| runs[a][0].value.total_cmp(&runs[b][0].value));
    // Values equal at every sample are equal at the first, so they sit in one stretch of
    // that order whose neighbours are the same at the first sample; each such stretch is
    // compared pair by pair.
    let mut equal: Vec<Option<usize>> = vec![None; runs.len()];
    let mut start = 0;
    while start < order.len() {
        let mut end = start + 1;
        while end < order.len() && same(runs[order[end - 1]][0], runs[order[end]][0]) {
            end += 1;
        }
        let stretch = &order[start..end];
        for &t in stretch {
            equal[t] = stretch
                .iter()
                .copied()
                .filter(|&s| s < t && (0..SAMPLES).all(|k| same(runs[s][k], runs[t][k])))
                .min();
        }
        start = end;
    }
    equal
}

/// The program with every instruction that is zero for every input replaced by 0 and
/// every one equal to an earlier one by that one, what reads a zero simplified, dead code
/// removed; the program itself when there is neither.
pub(super) fn fold_identities(program: Program) -> Program {
    let runs = run_at_random_inputs(&program);
    let piecewise = piecewise(&program);
    let zero: Vec<bool> = runs
        .iter()
        .zip(&piecewise)
        .map(|(r, &p)| !p && r.iter().all(|b| b.is_zero()))
        .collect();
    let equal = earlier_equals(&runs, &zero, &piecewise);
    if !zero.contains(&true) && equal.iter().all(Option::is_none) {
        return program;
    }
    let mut constants = program.constants.clone();
    let mut constant = |x: f64| {
        let i = constants
            .iter()
            .position(|c| c.to_bits() == x.to_bits())
            .unwrap_or_else(|| {
                constants.push(x);
                constants.len() - 1
            });
        Value::Const(i as u32)
    };
    let (nought, one) = (constant(0.0), constant(1.0));
    let is_nought = |v: Value| v == nought;
    // Instruction t stays at t (a folded one becomes a placeholder that nothing reads,
    // removed as dead code), so the map is to itself or to the value it folds to.
    let mut instrs: Vec<Instr> = Vec::with_capacity(program.instrs.len());
    let mut map: Vec<Value> = Vec::with_capacity(program.instrs.len());
    for (t, instr) in program.instrs.iter().enumerate() {
        let instr = instr.map(|v| mapped(&map, v));
        let folded = if zero[t] {
            Some(nought)
        } else if let Some(s) = equal[t] {
            Some(map[s])
        } else {
            match instr {
                Instr::Add(a, b) if is_nought(a) => Some(b),
                Instr::Add(a, b) | Instr::Sub(a, b) if is_nought(b) => Some(a),
                Instr::Mul(a, b) if is_nought(a) || is_nought(b) => Some(nought),
                Instr::Div(a, _)
                | Instr::Neg(a)
                | Instr::Sin(a)
                | Instr::Sign(a)
                | Instr::Sqrt(a)
                    if is_nought(a) =>
                {
                    Some(nought)
                }
                Instr::Cos(a) if is_nought(a) => Some(one),
                _ => None,
            }
        };
        map.push(folded.unwrap_or(Value::Temp(t as u32)));
        instrs.push(match (folded, instr) {
            (Some(_), _) => Instr::Neg(nought),
            (None, Instr::Sub(a, b)) if is_nought(a) => Instr::Neg(b),
            (None, instr) => instr,
        });
    }
    let outputs = mapped_outputs(&program.outputs, &map);
    dce::remove_dead_code(Program {
        inputs: program.inputs,
        constants,
        instrs,
        outputs,
    })
}

#[cfg(test)]
mod tests {
    use super::super::{Group, Instr, Output, Program, Value};
    use super::fold_identities;
    use robid_core::rng::Rng;

    const S: Value = Value::Input(0);
    const C: Value = Value::Input(1);
    const V: Value = Value::Input(2);
    const W: Value = Value::Input(3);
    const T: fn(u32) -> Value = Value::Temp;

    /// Inputs `s c v w`, constants `1 + 1e-9` and `2`.
    fn program(instrs: Vec<Instr>, outputs: Vec<Value>) -> Program {
        let names = ["s", "c", "v", "w"].map(str::to_owned).to_vec();
        let out = (0..outputs.len()).map(|k| format!("out{k}")).collect();
        Program {
            inputs: vec![Group::new("in", names)],
            constants: vec![1.0 + 1e-9, 2.0],
            instrs,
            outputs: vec![Output {
                group: Group::new("out", out),
                values: outputs,
            }],
        }
    }

    /// `s (c v) - c (s v)` is zero for every input, though computed it is rounding: it
    /// becomes the constant 0, and what reads it is simplified exactly (a product by it
    /// 0, a sum with it the other term, `0 - w` a negation, its cosine 1, its sign and
    /// square root 0). `c (s v)` is `s (c v)`, computed once. Values a little off it
    /// (1e-9 of the terms) and the sum of the two products stay as they were.
    #[test]
    fn a_difference_of_equal_products_is_zero() {
        let one_more = Value::Const(0);
        let before = program(
            vec![
                Instr::Mul(C, V),           // t0
                Instr::Mul(S, V),           // t1
                Instr::Mul(S, T(0)),        // t2 = s c v
                Instr::Mul(C, T(1)),        // t3 = c s v
                Instr::Sub(T(2), T(3)),     // t4 = 0
                Instr::Mul(T(4), W),        // t5 = 0
                Instr::Add(T(4), W),        // t6 = w
                Instr::Sub(T(4), W),        // t7 = -w
                Instr::Cos(T(4)),           // t8 = 1
                Instr::Sign(T(4)),          // t9 = 0
                Instr::Sqrt(T(4)),          // t10 = 0
                Instr::Add(T(2), T(3)),     // t11 = 2 s c v
                Instr::Mul(T(2), one_more), // t12
                Instr::Sub(T(12), T(3)),    // t13 = 1e-9 s c v
                Instr::Sub(W, T(4)),        // t14 = w
            ],
            vec![
                T(4),
                T(5),
                T(6),
                T(7),
                T(8),
                T(9),
                T(10),
                T(11),
                T(13),
                T(14),
            ],
        );
        let after = fold_identities(before.clone());
        let nought = after.constants.iter().position(|&c| c == 0.0).unwrap() as u32;
        let one = after.constants.iter().position(|&c| c == 1.0).unwrap() as u32;
        let outputs = &after.outputs[0].values;
        for k in [0, 1, 5, 6] {
            assert_eq!(outputs[k], Value::Const(nought), "output {k}");
        }
        assert_eq!(outputs[2], W);
        assert_eq!(outputs[9], W);
        assert_eq!(outputs[4], Value::Const(one));
        let Value::Temp(negated) = outputs[3] else {
            panic!("{:?}", outputs[3]);
        };
        assert_eq!(after.instrs[negated as usize], Instr::Neg(W));
        // s c v once (2 products), its double, the scaled one and its difference, -w
        assert_eq!(after.instrs.len(), 6, "{:?}", after.instrs);
        assert!(
            after.instrs.contains(&Instr::Add(T(1), T(1))),
            "{:?}",
            after.instrs
        );
        let mut rng = Rng::from_state(3);
        for _ in 0..20 {
            let x: Vec<f64> = (0..4).map(|_| rng.uniform(-2.0, 2.0)).collect();
            let (u, v) = (before.eval(&[&x]).unwrap(), after.eval(&[&x]).unwrap());
            for (k, (p, q)) in u[0].iter().zip(&v[0]).enumerate() {
                if ![0, 1, 4, 5, 6].contains(&k) {
                    assert!((p - q).abs() <= 1e-15 * (1.0 + p.abs()), "{k}: {p} vs {q}");
                }
            }
            // the kept difference is the 1e-9 it should be, not rounding
            let expected = 1e-9 * x[0] * x[1] * x[2];
            assert!(
                (v[0][8] - expected).abs() < 1e-6 * expected.abs(),
                "{}",
                v[0][8]
            );
        }
    }

    /// What reads a zero is simplified exactly, also where it is piecewise (a product by
    /// a sign is never taken for zero by the runs, only by the simplification) and where
    /// no earlier instruction has its value (`w - 0` is the input `w`).
    #[test]
    fn what_reads_a_zero_is_simplified_exactly() {
        let before = program(
            vec![
                Instr::Mul(C, V),       // t0
                Instr::Mul(S, V),       // t1
                Instr::Mul(S, T(0)),    // t2
                Instr::Mul(C, T(1)),    // t3
                Instr::Sub(T(2), T(3)), // t4 = 0
                Instr::Sign(V),         // t5
                Instr::Mul(T(4), T(5)), // t6 = 0
                Instr::Sub(W, T(4)),    // t7 = w
                Instr::Mul(T(5), T(4)), // t8 = 0
            ],
            vec![T(6), T(7), T(8)],
        );
        let after = fold_identities(before);
        let nought = after.constants.iter().position(|&c| c == 0.0).unwrap() as u32;
        assert_eq!(
            after.outputs[0].values,
            [Value::Const(nought), W, Value::Const(nought)]
        );
        assert!(after.instrs.is_empty(), "{:?}", after.instrs);
    }

    /// One value computed by three routes, beside others of the same value at some
    /// inputs only (`s c v` and `s c w` agree where `v = w`, never at all samples): the
    /// later two routes read the first, the others stay.
    #[test]
    fn three_routes_to_one_value_read_the_first() {
        let before = program(
            vec![
                Instr::Mul(C, V),       // t0
                Instr::Mul(S, T(0)),    // t1 = s c v
                Instr::Mul(S, V),       // t2
                Instr::Mul(C, T(2)),    // t3 = c s v
                Instr::Mul(S, C),       // t4
                Instr::Mul(V, T(4)),    // t5 = v s c
                Instr::Mul(W, T(4)),    // t6 = w s c
                Instr::Add(T(3), T(5)), // t7 = 2 s c v
            ],
            vec![T(1), T(3), T(5), T(6), T(7)],
        );
        let after = fold_identities(before);
        let outputs = &after.outputs[0].values;
        assert_eq!(outputs[0], outputs[1]);
        assert_eq!(outputs[0], outputs[2]);
        assert_ne!(outputs[3], outputs[0]);
        // c v, s c v; s c, w s c; their sum read as s c v + s c v
        assert_eq!(after.instrs.len(), 5, "{:?}", after.instrs);
        let Value::Temp(sum) = outputs[4] else {
            panic!("{:?}", outputs[4]);
        };
        assert_eq!(
            after.instrs[sum as usize],
            Instr::Add(outputs[0], outputs[0])
        );
    }

    /// Signs agree at a few random inputs by chance, and a square root of a square is
    /// its argument wherever that was drawn positive: neither is taken for another
    /// value or for zero. (`sign(v) - sign(w)` is 0 at each sample one time in two.)
    #[test]
    fn piecewise_functions_are_never_taken_for_others() {
        let before = program(
            vec![
                Instr::Sign(V),         // t0
                Instr::Sign(W),         // t1
                Instr::Sub(T(0), T(1)), // t2
                Instr::Mul(C, C),       // t3
                Instr::Sqrt(T(3)),      // t4 = |c|
                Instr::Mul(S, T(0)),    // t5
                Instr::Mul(S, T(1)),    // t6
            ],
            vec![T(0), T(1), T(2), T(4), C, T(5), T(6)],
        );
        // whatever the samples drew, by these seeds and others
        assert_eq!(fold_identities(before.clone()), before);
        assert_eq!(
            super::piecewise(&before),
            [true, true, true, false, true, true, true]
        );
    }

    /// A program without such an instruction is returned as it is; a square root of a
    /// negative sample (not finite) is never taken for zero.
    #[test]
    fn nothing_to_fold_changes_nothing() {
        let before = program(
            vec![
                Instr::Mul(S, C),
                Instr::Sub(T(0), V),
                Instr::Sqrt(W),
                Instr::Div(T(1), Value::Const(1)),
            ],
            vec![T(1), T(2), T(3)],
        );
        assert_eq!(fold_identities(before.clone()), before);
    }
}
