//! The placeholder `robot_model!` emits after an error, so the caller sees the
//! error once instead of once per use of the missing type (as thiserror's
//! `fallback.rs` does).

use super::names::type_name;
use crate::robot::name_problem;
use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;

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
    let f = |name: &str, args: &[&str]| {
        let name = ident(name);
        let args = args.iter().map(|a| {
            let a = ident(a);
            quote!(#a: &[T; N])
        });
        quote! {
            /// Placeholder after an error in `robot_model!`.
            pub fn #name<T: ::robid_runtime::Real, const N: usize, const M: usize>(&self, #(#args),*) -> [T; M] {
                ::core::unreachable!()
            }
        }
    };
    let fns = [
        f("standard_regressor", &["q", "qd", "qdd"]),
        f("base_regressor", &["q", "qd", "qdd"]),
        f("mass_matrix", &["q", "base"]),
        f("gravity", &["q", "base"]),
        f("coriolis", &["q", "qd", "base"]),
        f("base_parameters", &["standard"]),
    ];
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
            /// Placeholder.
            pub fn inverse_dynamics<T: ::robid_runtime::Real, const N: usize, const B: usize>(
                &self, q: &[T; N], qd: &[T; N], qdd: &[T; N], base: &[T; B],
            ) -> [T; N] {
                ::core::unreachable!()
            }
            #(#fns)*
        }
    })
}
