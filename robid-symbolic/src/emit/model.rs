//! `impl ::robid_runtime::Model`: the slice-based view of the emitted functions.
//!
//! Each method turns its slices into the fixed-size arrays of the generic function
//! (a wrong length is a `LengthError`, returned before the output is touched), calls
//! it with `f64` and stores the result.

use proc_macro2::{Ident, TokenStream};
use quote::{format_ident, quote};

/// One `Model` method: `name(&self, inputs.., output) -> Result` calling `function`.
fn method(ty: &Ident, name: &str, function: &str, inputs: &[&str], output: &str) -> TokenStream {
    let name = format_ident!("{name}");
    let function = format_ident!("{function}");
    let output_id = format_ident!("{output}");
    let args = inputs.iter().map(|a| format_ident!("{a}"));
    let calls = inputs.iter().map(|a| {
        let id = format_ident!("{a}");
        quote!(::robid_runtime::model::fixed(#a, #id)?)
    });
    quote! {
        fn #name(&self, #(#args: &[f64],)* #output_id: &mut [f64]) -> ::core::result::Result<(), ::robid_runtime::LengthError> {
            let value = #ty::#function::<f64>(self, #(#calls),*);
            *::robid_runtime::model::fixed_mut(#output, #output_id)? = value;
            ::core::result::Result::Ok(())
        }
    }
}

/// The `Model` implementation of type `ty`, calling its generic functions with `f64`.
pub(crate) fn model_impl(ty: &Ident) -> TokenStream {
    let methods = [
        method(
            ty,
            "base_regressor",
            "base_regressor",
            &["q", "qd", "qdd"],
            "out",
        ),
        method(
            ty,
            "standard_regressor",
            "standard_regressor",
            &["q", "qd", "qdd"],
            "out",
        ),
        method(
            ty,
            "inverse_dynamics",
            "inverse_dynamics",
            &["q", "qd", "qdd", "base"],
            "tau",
        ),
        method(ty, "mass_matrix", "mass_matrix", &["q", "base"], "out"),
        method(ty, "gravity", "gravity", &["q", "base"], "out"),
        method(ty, "coriolis", "coriolis", &["q", "qd", "base"], "out"),
        method(
            ty,
            "base_from_standard",
            "base_parameters",
            &["standard"],
            "base",
        ),
    ];
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
            #(#methods)*
        }
    }
}
