//! The type emitted for a robot: constants and one function per program.

use super::EmitError;
use super::function::function_tokens;
use super::model::model_impl;
use super::names::{ident, type_name, value_ident, value_name};
use crate::program::RobotPrograms;
use proc_macro2::{Literal, TokenStream};
use quote::quote;
use robid_core::{ProgramInfo, Sizes};

/// The type (named after the robot) with its constants, functions and `Model`
/// impl; its documentation lists the run-time inputs (geometric symbols
/// without a value in the description, which are fields of the type).
///
/// Fails instead of producing code that does not compile (see
/// [`function_tokens`]); a `RobotPrograms` from `RobotPrograms::derive` never fails.
pub fn robot_tokens(p: &RobotPrograms) -> Result<TokenStream, EmitError> {
    let robot = &p.robot;
    let ty = ident(&type_name(robot.name())).ok_or_else(|| EmitError::Name {
        what: "the robot's type name".to_owned(),
        name: type_name(robot.name()),
    })?;
    for (s, v) in &p.geometry {
        if !value_name(s) {
            return Err(EmitError::Name {
                what: "geometric symbol".to_owned(),
                name: s.clone(),
            });
        }
        if let Some(x) = v.filter(|x| !x.is_finite()) {
            return Err(EmitError::NotFinite {
                what: format!("the value of geometric symbol `{s}`"),
                value: x,
            });
        }
    }
    let n = robot.dof();
    let dof = Literal::usize_unsuffixed(n);
    let ns = Literal::usize_unsuffixed(p.standard.len());
    let nb = Literal::usize_unsuffixed(p.base.len());
    let name = robot.name();
    let standard = &p.standard;
    let base_names = p.base.iter().map(|b| b.name.to_string());
    let base_expressions = p.base.iter().map(|b| &b.expression);
    let mut type_doc = vec![format!(
        " Dynamic model of `{name}`: {}, {} DH, {} standard and {} base parameters.",
        super::count(n, "joint"),
        robot.convention().as_str(),
        p.standard.len(),
        p.base.len()
    )];
    // general frames and mounts (docs/conventions.md#khalil-kleinfinger-general-frames,
    // docs/conventions.md#base-and-tool-frames), said only when the description has them
    if robot
        .joints()
        .iter()
        .any(|j| !j.gamma.is_zero() || !j.b.is_zero())
    {
        type_doc.push(String::new());
        type_doc.push(
            " Some rows carry Khalil-Kleinfinger `gamma` and `b` (Rz(gamma) Tz(b) before the row)."
                .to_owned(),
        );
    }
    if let Some(base) = robot.base() {
        type_doc.push(String::new());
        type_doc.push(format!(
            " Mounted by the description's base transform (xyz [{}], rpy [{}]): gravity, given in the world frame, is turned into frame 0.",
            base.xyz.iter().map(|g| g.as_str()).collect::<Vec<_>>().join(", "),
            base.rpy.iter().map(|g| g.as_str()).collect::<Vec<_>>().join(", ")
        ));
    }
    let inputs: Vec<String> = p
        .geometry
        .iter()
        .filter(|(_, v)| v.is_none())
        .map(|(s, _)| format!("`{}`", value_ident(s)))
        .collect();
    if !inputs.is_empty() {
        type_doc.push(String::new());
        type_doc.push(format!(
            " Run-time inputs: the geometric symbols without a value in the description, fields {}; set them when building the value.",
            inputs.join(", ")
        ));
    }
    let (fields, derive) = if p.geometry.is_empty() {
        (
            quote!(;),
            quote!(#[derive(Clone, Copy, Debug, Default, PartialEq)]),
        )
    } else {
        let f = p.geometry.iter().map(|(s, v)| {
            let id = value_ident(s);
            let doc = match v {
                Some(x) => format!(" Geometric symbol `{s}` (description value: {x})."),
                None => format!(
                    " Geometric symbol `{s}`: a run-time input (no value in the description)."
                ),
            };
            quote! { #[doc = #doc] pub #id: f64, }
        });
        (
            quote!({ #(#f)* }),
            quote!(#[derive(Clone, Copy, Debug, PartialEq)]),
        )
    };
    let default_impl = default_impl(p, &ty);
    let sizes = Sizes {
        joints: n,
        base: p.base.len(),
        standard: p.standard.len(),
    };
    let f = p
        .iter()
        .map(|(info, program)| function_tokens(info.name, &function_doc(info, sizes), program))
        .collect::<Result<Vec<TokenStream>, EmitError>>()?;
    let model = model_impl(&ty);
    Ok(quote! {
        #(#[doc = #type_doc])*
        #derive
        pub struct #ty #fields

        #default_impl

        impl #ty {
            /// Name of the robot, as in its description.
            pub const NAME: &'static str = #name;
            /// Number of joints.
            pub const DOF: usize = #dof;
            /// Number of standard parameters.
            pub const STANDARD_PARAMETERS: usize = #ns;
            /// Number of base parameters.
            pub const BASE_PARAMETERS: usize = #nb;
            /// Names of the standard parameters, in order.
            pub const STANDARD_PARAMETER_NAMES: [&'static str; #ns] = [#(#standard),*];
            /// Names of the base parameters, in order.
            pub const BASE_PARAMETER_NAMES: [&'static str; #nb] = [#(#base_names),*];
            /// Each base parameter as an expression in the standard parameters.
            pub const BASE_PARAMETER_EXPRESSIONS: [&'static str; #nb] = [#(#base_expressions),*];

            #(#f)*
        }

        #model
    })
}

/// A URDF's own `<inertial>` elements as the associated constant
/// `URDF_STANDARD_PARAMETERS` of the robot's type (`standard`: the values of
/// `p.standard`, drive terms 0), what `robot_model!(file = "x.urdf")` and `robid emit
/// x.urdf` add to the model.
pub fn urdf_parameters_tokens(
    p: &RobotPrograms,
    standard: &[f64],
) -> Result<TokenStream, EmitError> {
    let ty = ident(&type_name(p.robot.name())).ok_or_else(|| EmitError::Name {
        what: "the robot's type name".to_owned(),
        name: type_name(p.robot.name()),
    })?;
    if standard.len() != p.standard.len() {
        return Err(EmitError::Program {
            function: "URDF_STANDARD_PARAMETERS".to_owned(),
            problem: format!(
                "{} values for {} standard parameters",
                standard.len(),
                p.standard.len()
            ),
        });
    }
    if let Some((name, &value)) = p
        .standard
        .iter()
        .zip(standard)
        .find(|(_, v)| !v.is_finite())
    {
        return Err(EmitError::NotFinite {
            what: format!("the URDF's value of `{name}`"),
            value,
        });
    }
    let n = Literal::usize_unsuffixed(standard.len());
    Ok(quote! {
        impl #ty {
            /// The URDF's own `<inertial>` elements as this model's standard parameters
            /// (per link `XX XY XZ YY YZ ZZ MX MY MZ M` in robid's frames, drive terms
            /// 0): pass them to `base_from_standard` for the URDF's rigid-body dynamics.
            pub const URDF_STANDARD_PARAMETERS: [f64; #n] = [#(#standard),*];
        }
    })
}

/// The documentation of a generated function: the table's summary and the output's shape.
pub(crate) fn function_doc(info: &ProgramInfo, sizes: Sizes) -> String {
    let output = info.output;
    format!(
        "{}\n\nReturns `{}`: {} ({}).",
        info.summary,
        output.name,
        output.size.describe(),
        super::count(output.size.len(sizes), "value")
    )
}

/// `Default` with the description's values of the geometric symbols, when it gives them all.
fn default_impl(p: &RobotPrograms, ty: &proc_macro2::Ident) -> TokenStream {
    let values: Option<Vec<(&String, f64)>> =
        p.geometry.iter().map(|(s, v)| Some((s, (*v)?))).collect();
    let Some(values) = values.filter(|v| !v.is_empty()) else {
        return quote!();
    };
    let f = values.into_iter().map(|(s, v)| {
        let id = value_ident(s);
        let lit = Literal::f64_unsuffixed(v);
        quote!(#id: #lit)
    });
    quote! {
        impl ::core::default::Default for #ty {
            fn default() -> Self {
                Self { #(#f),* }
            }
        }
    }
}
