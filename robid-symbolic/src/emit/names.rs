//! Identifiers in emitted code.

use proc_macro2::{Ident, Span};

/// The type name of a robot: `ur5e` -> `Ur5e`, `puma560` -> `Puma560`, `my_arm` -> `MyArm`.
pub fn type_name(robot_name: &str) -> String {
    robot_name
        .split('_')
        .filter(|p| !p.is_empty())
        .map(|p| {
            let mut c = p.chars();
            match c.next() {
                Some(first) => first.to_ascii_uppercase().to_string() + c.as_str(),
                None => String::new(),
            }
        })
        .collect()
}

/// An identifier for a symbol name, prefixed with `s_` when it could clash
/// with a temporary (`t3`), a constant (`c3`), the result array (`out`) or a
/// keyword. `name` is checked by [`value_name`] first.
pub(crate) fn value_ident(name: &str) -> Ident {
    let numbered = |p: char| {
        name.strip_prefix(p)
            .is_some_and(|r| !r.is_empty() && r.chars().all(|c| c.is_ascii_digit()))
    };
    let clash =
        numbered('t') || numbered('c') || name == "out" || syn::parse_str::<Ident>(name).is_err();
    if clash {
        Ident::new(&format!("s_{name}"), Span::call_site())
    } else {
        Ident::new(name, Span::call_site())
    }
}

/// A plain identifier, when `name` is one (and not a keyword).
pub(crate) fn ident(name: &str) -> Option<Ident> {
    syn::parse_str::<Ident>(name)
        .ok()
        .map(|_| Ident::new(name, Span::call_site()))
}

/// True when [`value_ident`] makes an identifier of `name`.
pub(crate) fn value_name(name: &str) -> bool {
    !name.is_empty() && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

#[cfg(test)]
mod tests {
    #[test]
    fn type_names() {
        assert_eq!(super::type_name("ur5e"), "Ur5e");
        assert_eq!(super::type_name("my_arm"), "MyArm");
        assert_eq!(super::value_ident("t3").to_string(), "s_t3");
        assert_eq!(super::value_ident("type").to_string(), "s_type");
        assert_eq!(super::value_ident("out").to_string(), "s_out");
        assert_eq!(super::value_ident("L3").to_string(), "L3");
        // only `t` or `c` followed by digits clashes: `t`, `c`, `tool` and `c3x` stay as named
        for name in ["t", "c", "tool", "c3x"] {
            assert_eq!(super::value_ident(name).to_string(), name);
        }
        assert_eq!(super::value_ident("c12").to_string(), "s_c12");
        assert!(super::ident("self").is_none() && super::ident("a b").is_none());
        assert!(super::value_name("L_3") && !super::value_name("a b") && !super::value_name(""));
    }
}
