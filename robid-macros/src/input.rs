//! The macro input as written: `key = value` pairs, each value kept as a
//! `syn::Expr` with its span, so the checks (`check.rs`) can point at it.

use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{Expr, Ident, Token};

/// One `key = value` item.
pub(crate) struct Item {
    pub(crate) key: Ident,
    pub(crate) value: Expr,
}

impl Parse for Item {
    fn parse(input: ParseStream<'_>) -> syn::Result<Item> {
        let key: Ident = input.parse()?;
        input.parse::<Token![=]>()?;
        let value: Expr = input.parse()?;
        Ok(Item { key, value })
    }
}

/// The whole input: comma-separated items.
pub(crate) struct Input {
    pub(crate) items: Vec<Item>,
}

impl Parse for Input {
    fn parse(input: ParseStream<'_>) -> syn::Result<Input> {
        let items = Punctuated::<Item, Token![,]>::parse_terminated(input)?;
        Ok(Input {
            items: items.into_iter().collect(),
        })
    }
}
