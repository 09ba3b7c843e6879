//! The reference robots, compiled by `robot_model!` from `descriptions/`.

mod lwr4;
mod panda;
mod puma560;
mod rx90;
mod stanford;
mod tx40;
mod ur5e;

#[cfg(test)]
mod consistency;
#[cfg(test)]
mod generated;

pub use lwr4::Lwr4;
pub use panda::Panda;
pub use puma560::Puma560;
pub use rx90::Rx90;
pub use stanford::Stanford;
pub use tx40::Tx40;
pub use ur5e::Ur5e;

/// The names of the reference robots (their description files are `descriptions/NAME.toml`).
pub const REFERENCE_ROBOTS: [&str; 7] = [
    "ur5e", "puma560", "rx90", "tx40", "lwr4", "panda", "stanford",
];

/// The compiled model of a reference robot, by name (geometric symbols at
/// their description values).
#[allow(clippy::default_constructed_unit_structs)] // the robots with symbols are not unit structs
pub fn reference_model(name: &str) -> Option<Box<dyn robid_runtime::Model>> {
    Some(match name {
        "ur5e" => Box::new(Ur5e::default()),
        "puma560" => Box::new(Puma560::default()),
        "rx90" => Box::new(Rx90::default()),
        "tx40" => Box::new(Tx40::default()),
        "lwr4" => Box::new(Lwr4::default()),
        "panda" => Box::new(Panda::default()),
        "stanford" => Box::new(Stanford::default()),
        _ => return None,
    })
}
