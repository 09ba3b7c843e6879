//! From the checked input to tokens: the emitted model (robid-symbolic does
//! the work), the `include_str!` that makes Cargo track a description file,
//! or the errors plus a placeholder type.

use crate::check::{Failed, check};
use crate::input::Input;
use proc_macro2::{Span, TokenStream};
use quote::quote;
use robid_symbolic::emit::{model_tokens, stub_tokens};
use robid_symbolic::program::RobotPrograms;

/// Expands the macro; never panics.
pub(crate) fn expand(input: Input) -> TokenStream {
    let checked = match check(&input) {
        Ok(c) => c,
        Err(failed) => return failure(failed),
    };
    let name = checked.robot.name().to_owned();
    let fail = |err: &dyn std::fmt::Display| {
        failure(Failed {
            errors: vec![syn::Error::new(Span::call_site(), err)],
            name: Some(name.clone()),
        })
    };
    let programs = match RobotPrograms::derive(&checked.robot) {
        Ok(p) => p,
        Err(err) => return fail(&err),
    };
    // the type, and a URDF's own inertials: the code `robid emit` prints
    let model = match model_tokens(&programs, checked.urdf_standard.as_deref()) {
        Ok(m) => m,
        Err(err) => return fail(&err),
    };
    let track = checked.tracked.map(|path| {
        let path = path.to_string_lossy().into_owned();
        quote! { const _: &str = ::core::include_str!(#path); }
    });
    quote! {
        #track
        #model
    }
}

fn failure(failed: Failed) -> TokenStream {
    let errors = failed.errors.into_iter().reduce(|mut a, b| {
        a.combine(b);
        a
    });
    let errors = errors.map(syn::Error::into_compile_error);
    let stub = failed.name.and_then(|n| stub_tokens(&n));
    quote! {
        #errors
        #stub
    }
}
