//! The reference robots of `robots/` for tests: the one registry, `robots::REFERENCES`,
//! compiled in with `include_str!` so no test reads files at run time.

pub use robots::{REFERENCES as ROBOTS, Reference};

/// The reference robot called `name` (a test's typo is a panic naming it).
pub fn by_name(name: &str) -> &'static Reference {
    Reference::named(name).unwrap_or_else(|| panic!("no reference robot `{name}`"))
}
