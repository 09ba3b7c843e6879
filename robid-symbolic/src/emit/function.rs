//! One program as a generic straight-line function.

use super::EmitError;
use super::fuse::{Fused, Fusion};
use super::names::{ident, value_ident, value_name};
use super::trig::{Role, TrigBatch};
use crate::program::{Instr, Program, Value};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::{format_ident, quote};

/// The name of the input group holding geometric symbols; it is read from
/// `self` instead of being an argument.
pub(crate) const GEOMETRY: &str = "geometry";

/// `pub fn name<T: Real>(&self, q: &[T; 6], ...) -> [T; N]` computing `program`
/// (its first output group), with `doc` as the first lines of its doc comment, and its
/// two private instances: `name_inlined`, the body, which writes the results into the
/// array it is given and which the public function and the other instance inline, and
/// for x86-64 `name_avx2`, the body for
/// `robid_runtime::fused::Fused` compiled with AVX2 and FMA, which `Model::run` calls
/// when `robid_runtime::fused::dispatch()` allows, writing straight into the caller's
/// array (returned by value and copied, a base regressor's 301 values were copied once
/// more per call).
///
/// Fails, instead of emitting code that does not compile, when a name is not
/// an identifier, a constant is not finite or an operand reads a value that
/// does not exist (possible only for programs built by hand).
pub fn function_tokens(name: &str, doc: &str, program: &Program) -> Result<TokenStream, EmitError> {
    check(name, program)?;
    let name = ident(name).ok_or_else(|| EmitError::Name {
        what: "function".to_owned(),
        name: name.to_owned(),
    })?;
    let mut args = Vec::new();
    let mut arg_names = Vec::new();
    let mut lens = Vec::new();
    let mut bindings = Vec::new();
    // The sines and cosines of the angles that need no trigonometry themselves come
    // from one batched call before the rest (`trig.rs`). The inputs it does not read are
    // bound after it: bound before, they would live across its calls (libm's), which
    // clobber every vector register, and be copied to the stack and back.
    let batch = TrigBatch::new(program);
    let mut before_batch = vec![batch.angles.is_empty(); program.input_len()];
    let hoisted = program
        .instrs
        .iter()
        .enumerate()
        .filter(|&(i, _)| batch.role[i] == Role::Hoisted)
        .flat_map(|(_, instr)| instr.operands());
    // (and the outputs that are inputs, which a matrix stores before everything)
    let outputs = program
        .outputs
        .iter()
        .flat_map(|o| o.values.iter().copied());
    for v in hoisted.chain(batch.angles.iter().copied()).chain(outputs) {
        if let Value::Input(k) = v {
            before_batch[k as usize] = true;
        }
    }
    let mut after_batch = Vec::new();
    let mut doc_lines: Vec<String> = doc.lines().map(|l| format!(" {l}")).collect();
    doc_lines.push(String::new());
    for (g, group) in program.inputs.iter().enumerate() {
        let used = program.uses_input_group(g);
        if group.name == GEOMETRY {
            for (k, e) in group.elements.iter().enumerate() {
                let reads = program.instrs.iter().any(|i| {
                    i.operands()
                        .into_iter()
                        .any(|v| v == input_value(program, g, k))
                });
                if reads {
                    let id = value_ident(e);
                    bindings.push(quote! { let #id = T::from_f64(self.#id); });
                }
            }
            continue;
        }
        let arg = ident(&group.name).ok_or_else(|| EmitError::Name {
            what: "input group".to_owned(),
            name: group.name.clone(),
        })?;
        let len = Literal::usize_unsuffixed(group.len());
        let arg_name = if used { quote!(#arg) } else { quote!(_) };
        args.push(quote! { #arg_name: &[T; #len] });
        arg_names.push(arg.clone());
        lens.push(len.clone());
        doc_lines.push(format!(
            " - `{}`: {}",
            group.name,
            describe(&group.elements)
        ));
        if used {
            let names = (0..group.len()).map(|k| {
                let v = input_value(program, g, k);
                if reads_value(program, v) {
                    let id = value_ident(&group.elements[k]);
                    quote!(#id)
                } else {
                    quote!(_)
                }
            });
            let first: usize = program.inputs[..g].iter().map(|g| g.len()).sum();
            let early = before_batch[first..first + group.len()].contains(&true);
            let binding = quote! { let [#(#names),*] = *#arg; };
            if early {
                bindings.push(binding);
            } else {
                after_batch.push(binding);
            }
        }
    }
    let Some(output) = program.outputs.first() else {
        return Err(EmitError::Program {
            function: name.to_string(),
            problem: "it has no output".to_owned(),
        });
    };
    let out_len = Literal::usize_unsuffixed(output.values.len());
    doc_lines.push(String::new());
    doc_lines.push(format!(" Operations: {}.", program.operations()));
    let constants = program.constants.iter().enumerate().filter_map(|(i, &c)| {
        let used = program
            .instrs
            .iter()
            .any(|ins| ins.operands().contains(&Value::Const(i as u32)));
        used.then(|| {
            let id = format_ident!("c{}", i);
            let lit = Literal::f64_unsuffixed(c);
            quote! { let #id = T::from_f64(#lit); }
        })
    });
    // Of the sines and cosines not batched, sin(x) and cos(x) of the same x are computed
    // together, where the first of the two is.
    let mut pair_of: Vec<Option<usize>> = vec![None; program.instrs.len()];
    for (i, instr) in program.instrs.iter().enumerate() {
        if batch.role[i] != Role::InOrder {
            continue;
        }
        if let Instr::Sin(x) = *instr
            && let Some(k) = program
                .instrs
                .iter()
                .position(|other| *other == Instr::Cos(x))
        {
            pair_of[i] = Some(k);
            pair_of[k] = Some(i);
        }
    }
    // More outputs than registers (a matrix): each element is stored as soon
    // as it is computed instead of staying live until the end (measured on
    // the UR5e: base regressor and mass matrix about 2 ns faster each; the
    // joint vectors are faster returned as one array expression). The zero elements are
    // stored one by one too, not by zeroing the whole array first (a `memset` call, then
    // the other elements stored again: the Panda's standard regressor 245 -> 224 ns, its
    // base regressor 197 -> 181 ns, `robid bench` in turn, 4 December 2026).
    let eager = output.values.len() > EAGER_STORES_ABOVE;
    let mut stores_of: Vec<Vec<usize>> = vec![Vec::new(); program.instrs.len()];
    let mut early = Vec::new();
    for (k, &v) in output.values.iter().enumerate().filter(|_| eager) {
        match v {
            Value::Temp(i) => stores_of[i as usize].push(k),
            Value::Const(c) if program.constants[c as usize] == 0.0 => {
                let k = Literal::usize_unsuffixed(k);
                early.push(quote! { out[#k] = T::ZERO; });
            }
            other => {
                let rhs = result_tokens(program, other);
                let k = Literal::usize_unsuffixed(k);
                early.push(quote! { out[#k] = #rhs; });
            }
        }
    }
    let store = |i: usize| {
        let id = format_ident!("t{}", i);
        let ks = stores_of[i].iter().map(|&k| Literal::usize_unsuffixed(k));
        quote! { #(out[#ks] = #id;)* }
    };
    let fusion = Fusion::new(program, &batch.role);
    let emit = |i: usize, instr: &Instr| {
        let id = format_ident!("t{}", i);
        if fusion.absorbed[i] {
            return None;
        }
        if let Some(fused) = fusion.fused[i] {
            let rhs = fused_tokens(program, fused);
            let st = store(i);
            return Some(quote! { let #id = #rhs; #st });
        }
        match (pair_of[i], instr) {
            (Some(k), _) if k < i => None,
            (Some(k), Instr::Sin(x) | Instr::Cos(x)) => {
                let (s, c) = if matches!(instr, Instr::Sin(_)) {
                    (id, format_ident!("t{}", k))
                } else {
                    (format_ident!("t{}", k), id)
                };
                let x = value_tokens(program, *x);
                let (si, sk) = (store(i), store(k));
                Some(quote! { let (#s, #c) = #x.sin_cos(); #si #sk })
            }
            _ => {
                let rhs = instr_tokens(program, instr);
                let st = store(i);
                Some(quote! { let #id = #rhs; #st })
            }
        }
    };
    let (emit, role_of) = (&emit, &batch.role);
    let in_role = |role: Role| {
        program
            .instrs
            .iter()
            .enumerate()
            .filter(move |&(i, _)| role_of[i] == role)
            .filter_map(move |(i, instr)| emit(i, instr))
    };
    let mut lets: Vec<TokenStream> = in_role(Role::Hoisted).collect();
    if !batch.angles.is_empty() {
        let bind = |slot: &Option<usize>| match *slot {
            Some(i) => {
                let id = format_ident!("t{}", i);
                quote!(#id)
            }
            None => quote!(_),
        };
        let sins = batch.sin.iter().map(bind);
        let coss = batch.cos.iter().map(bind);
        let angles = batch.angles.iter().map(|&x| value_tokens(program, x));
        let stores = (0..program.instrs.len())
            .filter(|&i| batch.role[i] == Role::Batched)
            .map(store);
        lets.push(quote! {
            let ([#(#sins),*], [#(#coss),*]) = T::sin_cos_array([#(#angles),*]);
            #(#stores)*
            #(#after_batch)*
        });
        for (i, role) in batch.role.iter().enumerate() {
            if let Role::Copy { of } = *role {
                let (id, of) = (format_ident!("t{}", i), format_ident!("t{}", of));
                let st = store(i);
                lets.push(quote! { let #id = #of; #st });
            }
        }
    }
    lets.extend(in_role(Role::InOrder));
    let body = if eager {
        quote! {
            #(#early)*
            #(#lets)*
        }
    } else {
        let results = output.values.iter().map(|&v| result_tokens(program, v));
        quote! {
            #(#lets)*
            *out = [#(#results),*];
        }
    };
    // the constants are the description's values as literals (cos(pi/4) is written as
    // 0.7071067811865476, which clippy takes for an approximate FRAC_1_SQRT_2)
    let (inlined, avx2) = instance_names(&name);
    Ok(quote! {
        #(#[doc = #doc_lines])*
        pub fn #name<T: ::robid_runtime::Real>(
            &self,
            #(#arg_names: &[T; #lens]),*
        ) -> [T; #out_len] {
            let mut out = [T::ZERO; #out_len];
            self.#inlined::<T>(#(#arg_names,)* &mut out);
            out
        }

        #[inline(always)]
        #[allow(
            non_snake_case,
            clippy::too_many_lines,
            clippy::unreadable_literal,
            clippy::approx_constant
        )]
        fn #inlined<T: ::robid_runtime::Real>(&self, #(#args,)* out: &mut [T; #out_len]) {
            #(#bindings)*
            #(#constants)*
            #body
        }

        #[cfg(target_arch = "x86_64")]
        #[target_feature(enable = "avx2,fma")]
        fn #avx2(&self, #(#arg_names: &[f64; #lens],)* out: &mut [f64; #out_len]) {
            self.#inlined::<::robid_runtime::fused::Fused>(
                #(::robid_runtime::fused::as_array(#arg_names),)*
                ::robid_runtime::fused::as_array_mut(out),
            );
        }
    })
}

/// The private instances of the emitted function `name`: its body, always inlined, and
/// its AVX2 instance (x86-64 only).
pub(crate) fn instance_names(name: &Ident) -> (Ident, Ident) {
    (
        format_ident!("{name}_inlined"),
        format_ident!("{name}_avx2"),
    )
}

/// The checks of [`function_tokens`].
fn check(function: &str, program: &Program) -> Result<(), EmitError> {
    for group in &program.inputs {
        if let Some(e) = group.elements.iter().find(|e| !value_name(e)) {
            return Err(EmitError::Name {
                what: format!("element of input group `{}`", group.name),
                name: e.clone(),
            });
        }
    }
    if let Some((i, &c)) = program
        .constants
        .iter()
        .enumerate()
        .find(|(_, c)| !c.is_finite())
    {
        return Err(EmitError::NotFinite {
            what: format!("constant c{i} of program `{function}`"),
            value: c,
        });
    }
    let inputs = program.input_len();
    let valid = |v: Value, temps: usize| match v {
        Value::Temp(t) => (t as usize) < temps,
        Value::Input(i) => (i as usize) < inputs,
        Value::Const(c) => (c as usize) < program.constants.len(),
    };
    let instrs = program.instrs.iter().enumerate();
    let bad_instr = instrs
        .clone()
        .find(|(i, ins)| ins.operands().into_iter().any(|v| !valid(v, *i)));
    let bad_output = program
        .outputs
        .iter()
        .flat_map(|o| &o.values)
        .find(|&&v| !valid(v, program.instrs.len()));
    if bad_instr.is_some() || bad_output.is_some() {
        return Err(EmitError::Program {
            function: function.to_owned(),
            problem: "an operand reads a temporary, input or constant that does not exist"
                .to_owned(),
        });
    }
    Ok(())
}

fn describe(elements: &[String]) -> String {
    match elements {
        [] => String::new(),
        [one] => one.clone(),
        [first, .., last] if elements.len() > 4 => format!("{first} .. {last}"),
        _ => elements.join(", "),
    }
}

fn input_value(program: &Program, group: usize, k: usize) -> Value {
    let offset: usize = program.inputs[..group].iter().map(|g| g.len()).sum();
    Value::Input((offset + k) as u32)
}

fn reads_value(program: &Program, v: Value) -> bool {
    program.instrs.iter().any(|i| i.operands().contains(&v))
        || program.outputs.iter().any(|o| o.values.contains(&v))
}

fn value_tokens(program: &Program, v: Value) -> TokenStream {
    match v {
        Value::Temp(t) => {
            let id = format_ident!("t{}", t);
            quote!(#id)
        }
        Value::Input(i) => {
            let id = value_ident(program.input_name(i));
            quote!(#id)
        }
        Value::Const(c) => {
            let id = format_ident!("c{}", c);
            quote!(#id)
        }
    }
}

/// Outputs up to this many are returned as one array expression at the end
/// (they fit in the vector registers); more are stored as they are computed.
const EAGER_STORES_ABOVE: usize = 16;

/// An output element: constants are written out (`T::ZERO` for the many zeros).
fn result_tokens(program: &Program, v: Value) -> TokenStream {
    match v {
        Value::Const(c) => match program.constants[c as usize] {
            0.0 => quote!(T::ZERO),
            1.0 => quote!(T::ONE),
            x => {
                let lit = Literal::f64_unsuffixed(x);
                quote!(T::from_f64(#lit))
            }
        },
        other => value_tokens(program, other),
    }
}

/// `T::mul_add(a, b, c)` for a sum that absorbed its product (`fuse.rs`).
fn fused_tokens(program: &Program, fused: Fused) -> TokenStream {
    let v = |x: Value| value_tokens(program, x);
    match fused {
        Fused::Plus { a, b, c } => {
            let (a, b, c) = (v(a), v(b), v(c));
            quote!(T::mul_add(#a, #b, #c))
        }
        Fused::Minus { a, b, c } => {
            let (a, b, c) = (v(a), v(b), v(c));
            quote!(T::mul_add(#a, #b, -#c))
        }
        Fused::From { a, b, c } => {
            let (a, b, c) = (v(a), v(b), v(c));
            quote!(T::mul_add(-#a, #b, #c))
        }
    }
}

fn instr_tokens(program: &Program, instr: &Instr) -> TokenStream {
    let v = |x: Value| value_tokens(program, x);
    match *instr {
        Instr::Add(a, b) => {
            let (a, b) = (v(a), v(b));
            quote!(#a + #b)
        }
        Instr::Sub(a, b) => {
            let (a, b) = (v(a), v(b));
            quote!(#a - #b)
        }
        Instr::Mul(a, b) => {
            let (a, b) = (v(a), v(b));
            quote!(#a * #b)
        }
        Instr::Div(a, b) => {
            let (a, b) = (v(a), v(b));
            quote!(#a / #b)
        }
        Instr::Neg(a) => {
            let a = v(a);
            quote!(-#a)
        }
        Instr::Sin(a) => {
            let a = v(a);
            quote!(#a.sin())
        }
        Instr::Cos(a) => {
            let a = v(a);
            quote!(#a.cos())
        }
        Instr::Sign(a) => {
            let a = v(a);
            quote!(#a.sign())
        }
        Instr::Sqrt(a) => {
            let a = v(a);
            quote!(#a.sqrt())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::describe;

    /// Input groups are described in the generated docs by their elements, up to four
    /// written out, longer ones by their ends.
    #[test]
    fn input_groups_are_described_by_their_elements() {
        let names = |n: usize| (1..=n).map(|k| format!("q{k}")).collect::<Vec<_>>();
        assert_eq!(describe(&names(0)), "");
        assert_eq!(describe(&names(1)), "q1");
        assert_eq!(describe(&names(4)), "q1, q2, q3, q4");
        assert_eq!(describe(&names(5)), "q1 .. q5");
    }
}
