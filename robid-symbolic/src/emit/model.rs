//! `impl ::robid_runtime::Model`: the slice-based view of the emitted functions.
//!
//! `run` has one arm per entry of the program table
//! ([`PROGRAMS`](robid_core::PROGRAMS)): it checks the number of inputs,
//! turns each slice into the fixed-size array of the generic function (a wrong length
//! is a `LengthError`, returned before the output is touched), calls it with `f64` (or,
//! on a processor with AVX2 and FMA, its instance for them: `robid_runtime::fused`),
//! which writes the result straight into the output.

use super::function::instance_names;
use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};
use robid_core::{PROGRAMS, ProgramInfo};

/// The `run` arm of one program: `ProgramKind::X => { .. }`. On x86-64 it calls the
/// function's AVX2 instance when `robid_runtime::fused::dispatch()` allows.
fn arm(ty: &Ident, p: &ProgramInfo) -> TokenStream {
    let kind = format_ident!("{}", format!("{:?}", p.kind));
    let function = format_ident!("{}", p.name);
    let (inlined, avx2) = instance_names(&function);
    let count = p.inputs.len();
    let names: Vec<Ident> = p
        .inputs
        .iter()
        .map(|a| format_ident!("{}", a.name))
        .collect();
    let argument = p.inputs.iter().map(|a| a.name);
    let output = p.output.name;
    quote! {
        ::robid_runtime::model::ProgramKind::#kind => {
            let [#(#names),*] = inputs else {
                return ::core::result::Result::Err(::robid_runtime::LengthError {
                    argument: "inputs",
                    expected: #count,
                    found: inputs.len(),
                });
            };
            #(let #names = ::robid_runtime::model::fixed(#argument, #names)?;)*
            let out = ::robid_runtime::model::fixed_mut(#output, output)?;
            #[cfg(target_arch = "x86_64")]
            if ::robid_runtime::fused::dispatch() {
                // SAFETY: `dispatch` has confirmed that the processor executes AVX2 and FMA
                unsafe { #ty::#avx2(self, #(#names,)* out) };
                return ::core::result::Result::Ok(());
            }
            #ty::#inlined::<f64>(self, #(#names,)* out);
        }
    }
}

/// The `Model` implementation of type `ty`, calling its generic functions with `f64`.
pub(crate) fn model_impl(ty: &Ident) -> TokenStream {
    let arms = PROGRAMS.iter().map(|p| arm(ty, p));
    quote! {
        impl ::robid_runtime::Model for #ty {
            fn name(&self) -> &str {
                Self::NAME
            }
            fn dof(&self) -> usize {
                Self::DOF
            }
            fn standard_parameter_count(&self) -> usize {
                Self::STANDARD_PARAMETERS
            }
            fn standard_parameter_name(&self, index: usize) -> ::core::option::Option<&str> {
                Self::STANDARD_PARAMETER_NAMES.get(index).copied()
            }
            fn base_parameter_count(&self) -> usize {
                Self::BASE_PARAMETERS
            }
            fn base_parameter_name(&self, index: usize) -> ::core::option::Option<&str> {
                Self::BASE_PARAMETER_NAMES.get(index).copied()
            }
            fn run(
                &self,
                program: ::robid_runtime::model::ProgramKind,
                inputs: &[&[f64]],
                output: &mut [f64],
            ) -> ::core::result::Result<(), ::robid_runtime::LengthError> {
                match program {
                    #(#arms)*
                }
                ::core::result::Result::Ok(())
            }
        }
    }
}
