//! The placeholder `robot_model!` emits after an error, so the caller sees the
//! error once instead of once per use of the missing type (as thiserror's
//! `fallback.rs` does).

use super::names::type_name;
use crate::robot::name_problem;
use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;
use robid_core::PROGRAMS;

/// A type named after `robot_name` with the constants and functions of a real
/// model, accepting any sizes, whose bodies are unreachable (the crate does
/// not compile anyway: the error is emitted next to it); `None` when the name
/// cannot name a robot (then there is no type to stand in for).
pub fn stub_tokens(robot_name: &str) -> Option<TokenStream> {
    if name_problem(robot_name).is_some() {
        return None;
    }
    let ident = |name: &str| Ident::new(name, Span::call_site());
    let ty = ident(&type_name(robot_name));
    // every program of the table, each argument with its own length
    let fns = PROGRAMS.iter().map(|p| {
        let name = ident(p.name);
        let lengths: Vec<Ident> = (0..p.inputs.len()).map(|i| ident(&format!("A{i}"))).collect();
        let args = p.inputs.iter().zip(&lengths).map(|(a, n)| {
            let a = ident(a.name);
            quote!(#a: &[T; #n])
        });
        // an output as long as an input takes its length (so `let tau = ...` infers)
        let same = p.inputs.iter().position(|a| a.size == p.output.size);
        let (out, extra) = match same {
            Some(i) => {
                let n = &lengths[i];
                (quote!(#n), quote!())
            }
            None => (quote!(M), quote!(const M: usize,)),
        };
        quote! {
            /// Placeholder after an error in `robot_model!`.
            pub fn #name<T: ::robid_runtime::Real, #(const #lengths: usize,)* #extra>(&self, #(#args),*) -> [T; #out] {
                ::core::unreachable!()
            }
        }
    });
    Some(quote! {
        /// Placeholder after an error in `robot_model!`.
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        pub struct #ty;

        impl #ty {
            /// Placeholder.
            pub const NAME: &'static str = #robot_name;
            /// Placeholder.
            pub const DOF: usize = 0;
            /// Placeholder.
            pub const STANDARD_PARAMETERS: usize = 0;
            /// Placeholder.
            pub const BASE_PARAMETERS: usize = 0;
            #(#fns)*
        }
    })
}
