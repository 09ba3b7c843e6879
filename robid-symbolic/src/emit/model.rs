//! `impl ::robid_runtime::Model`: the slice-based view of the emitted functions.

use proc_macro2::{Ident, TokenStream};
use quote::quote;

/// The `Model` implementation of type `ty`, calling its generic functions with `f64`.
pub(crate) fn model_impl(ty: &Ident) -> TokenStream {
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
            fn standard_parameter_name(&self, index: usize) -> &str {
                Self::STANDARD_PARAMETER_NAMES[index]
            }
            fn base_parameter_count(&self) -> usize {
                Self::BASE_PARAMETERS
            }
            fn base_parameter_name(&self, index: usize) -> &str {
                Self::BASE_PARAMETER_NAMES[index]
            }
            fn base_regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
                out.copy_from_slice(&#ty::base_regressor::<f64>(self, ::core::convert::TryInto::try_into(q).expect("`q` has the length of the model (see the `Model` trait)"), ::core::convert::TryInto::try_into(qd).expect("`qd` has the length of the model (see the `Model` trait)"), ::core::convert::TryInto::try_into(qdd).expect("`qdd` has the length of the model (see the `Model` trait)")));
            }
            fn standard_regressor(&self, q: &[f64], qd: &[f64], qdd: &[f64], out: &mut [f64]) {
                out.copy_from_slice(&#ty::standard_regressor::<f64>(self, ::core::convert::TryInto::try_into(q).expect("`q` has the length of the model (see the `Model` trait)"), ::core::convert::TryInto::try_into(qd).expect("`qd` has the length of the model (see the `Model` trait)"), ::core::convert::TryInto::try_into(qdd).expect("`qdd` has the length of the model (see the `Model` trait)")));
            }
            fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64], base: &[f64], tau: &mut [f64]) {
                tau.copy_from_slice(&#ty::inverse_dynamics::<f64>(self, ::core::convert::TryInto::try_into(q).expect("`q` has the length of the model (see the `Model` trait)"), ::core::convert::TryInto::try_into(qd).expect("`qd` has the length of the model (see the `Model` trait)"), ::core::convert::TryInto::try_into(qdd).expect("`qdd` has the length of the model (see the `Model` trait)"), ::core::convert::TryInto::try_into(base).expect("`base` has the length of the model (see the `Model` trait)")));
            }
            fn mass_matrix(&self, q: &[f64], base: &[f64], out: &mut [f64]) {
                out.copy_from_slice(&#ty::mass_matrix::<f64>(self, ::core::convert::TryInto::try_into(q).expect("`q` has the length of the model (see the `Model` trait)"), ::core::convert::TryInto::try_into(base).expect("`base` has the length of the model (see the `Model` trait)")));
            }
            fn gravity(&self, q: &[f64], base: &[f64], out: &mut [f64]) {
                out.copy_from_slice(&#ty::gravity::<f64>(self, ::core::convert::TryInto::try_into(q).expect("`q` has the length of the model (see the `Model` trait)"), ::core::convert::TryInto::try_into(base).expect("`base` has the length of the model (see the `Model` trait)")));
            }
            fn coriolis(&self, q: &[f64], qd: &[f64], base: &[f64], out: &mut [f64]) {
                out.copy_from_slice(&#ty::coriolis::<f64>(self, ::core::convert::TryInto::try_into(q).expect("`q` has the length of the model (see the `Model` trait)"), ::core::convert::TryInto::try_into(qd).expect("`qd` has the length of the model (see the `Model` trait)"), ::core::convert::TryInto::try_into(base).expect("`base` has the length of the model (see the `Model` trait)")));
            }
            fn base_from_standard(&self, standard: &[f64], base: &mut [f64]) {
                base.copy_from_slice(&#ty::base_parameters::<f64>(self, ::core::convert::TryInto::try_into(standard).expect("`standard` has the length of the model (see the `Model` trait)")));
            }
        }
    }
}
