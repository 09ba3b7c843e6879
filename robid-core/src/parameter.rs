//! What a parameter is: the typed identity behind names such as `XX2`, `Fv3` and `ZZR1`
//! (docs/conventions.md#standard-parameters).
//!
//! Every name robid reads or writes (descriptions' drive terms, regrouping results,
//! parameter files, the feasible problem's layout, the command line) is parsed here and
//! nowhere else, and every name it writes is this module's `Display`.
//!
//! ```
//! use robid_core::{BaseName, DriveTerm, Inertial, ParameterId, ParameterKind};
//!
//! let p: ParameterId = "MZ3".parse().unwrap();
//! assert_eq!(p, ParameterId::new(2, ParameterKind::Inertial(Inertial::MZ)));
//! assert_eq!(p.to_string(), "MZ3");
//! assert!("Fv0".parse::<ParameterId>().is_err()); // links count from 1
//!
//! let b: BaseName = "ZZR1".parse().unwrap();
//! assert!(b.regrouped);
//! assert_eq!(b.on.to_string(), "ZZ1");
//! assert_eq!("Fc".parse::<DriveTerm>(), Ok(DriveTerm::Fc));
//! ```

use core::fmt;
use core::str::FromStr;

/// The ten inertial parameters of a link about its frame origin, in the standard order
/// `XX XY XZ YY YZ ZZ MX MY MZ M`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[allow(clippy::upper_case_acronyms)] // the literature's names
pub enum Inertial {
    /// Inertia tensor entry xx about the frame origin.
    XX,
    /// Inertia tensor entry xy (the tensor's entry, -sum m x y).
    XY,
    /// Inertia tensor entry xz.
    XZ,
    /// Inertia tensor entry yy.
    YY,
    /// Inertia tensor entry yz.
    YZ,
    /// Inertia tensor entry zz.
    ZZ,
    /// First moment of mass along x (mass times centre-of-mass x).
    MX,
    /// First moment of mass along y.
    MY,
    /// First moment of mass along z.
    MZ,
    /// Mass.
    M,
}

impl Inertial {
    /// All ten, in the standard order.
    pub const ALL: [Inertial; 10] = [
        Inertial::XX,
        Inertial::XY,
        Inertial::XZ,
        Inertial::YY,
        Inertial::YZ,
        Inertial::ZZ,
        Inertial::MX,
        Inertial::MY,
        Inertial::MZ,
        Inertial::M,
    ];

    /// The name stem (`XX` .. `M`).
    pub const fn stem(self) -> &'static str {
        ["XX", "XY", "XZ", "YY", "YZ", "ZZ", "MX", "MY", "MZ", "M"][self as usize]
    }

    /// Position in the standard order (0..10).
    pub const fn index(self) -> usize {
        self as usize
    }
}

/// A drive term of a joint (docs/conventions.md#drive-terms).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DriveTerm {
    /// Rotor inertia reflected to the joint (Ia qdd).
    Ia,
    /// Viscous friction (Fv qd).
    Fv,
    /// Coulomb friction (Fc sign(qd)).
    Fc,
    /// Constant offset (Fo).
    Fo,
}

impl DriveTerm {
    /// All four, in the standard order.
    pub const ALL: [DriveTerm; 4] = [DriveTerm::Ia, DriveTerm::Fv, DriveTerm::Fc, DriveTerm::Fo];

    /// The name stem (`Ia`, `Fv`, `Fc`, `Fo`).
    pub const fn stem(self) -> &'static str {
        ["Ia", "Fv", "Fc", "Fo"][self as usize]
    }

    /// What it is, in words ("a rotor inertia").
    pub const fn meaning(self) -> &'static str {
        [
            "a rotor inertia",
            "a viscous friction coefficient",
            "a Coulomb friction coefficient",
            "a torque offset",
        ][self as usize]
    }

    /// Whether the term must be non-negative to be physical (all but the offset).
    pub const fn non_negative(self) -> bool {
        !matches!(self, DriveTerm::Fo)
    }
}

/// What a standard parameter is: one of a link's inertial parameters or one of its
/// joint's drive terms.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ParameterKind {
    /// An inertial parameter of the link.
    Inertial(Inertial),
    /// A drive term of the joint.
    Drive(DriveTerm),
}

impl ParameterKind {
    /// All fourteen, in the standard order: the inertial ones, then the drive terms.
    pub const ALL: [ParameterKind; 14] = {
        let mut all = [ParameterKind::Inertial(Inertial::XX); 14];
        let mut i = 0;
        while i < 10 {
            all[i] = ParameterKind::Inertial(Inertial::ALL[i]);
            i += 1;
        }
        while i < 14 {
            all[i] = ParameterKind::Drive(DriveTerm::ALL[i - 10]);
            i += 1;
        }
        all
    };

    /// The name stem (`XX`, `M`, `Fv`, ..).
    pub const fn stem(self) -> &'static str {
        match self {
            ParameterKind::Inertial(i) => i.stem(),
            ParameterKind::Drive(d) => d.stem(),
        }
    }

    /// Position in the standard order of a joint's parameters (0..14).
    pub const fn index(self) -> usize {
        match self {
            ParameterKind::Inertial(i) => i.index(),
            ParameterKind::Drive(d) => 10 + d as usize,
        }
    }

    /// The kind whose stem is `stem`.
    fn from_stem(stem: &str) -> Option<ParameterKind> {
        ParameterKind::ALL.into_iter().find(|k| k.stem() == stem)
    }
}

/// One standard parameter: a kind on a link (0-based; names count from 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ParameterId {
    /// Link (or joint), 0-based.
    pub link: usize,
    /// What it is.
    pub kind: ParameterKind,
}

impl ParameterId {
    /// The parameter `kind` of link `link` (0-based).
    pub const fn new(link: usize, kind: ParameterKind) -> ParameterId {
        ParameterId { link, kind }
    }
}

impl fmt::Display for ParameterId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}{}", self.kind.stem(), self.link + 1)
    }
}

/// A name that is not a parameter name (see [`ParameterId`], [`BaseName`], [`DriveTerm`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParseNameError {
    /// What was expected.
    pub expected: &'static str,
}

impl fmt::Display for ParseNameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.expected)
    }
}

impl core::error::Error for ParseNameError {}

const PARAMETER_NAME: ParseNameError = ParseNameError {
    expected: "a standard parameter name is a stem XX XY XZ YY YZ ZZ MX MY MZ M Ia Fv Fc Fo \
               followed by the link number from 1, e.g. `MZ3`",
};

/// Splits `XX12` into (`XX`, 11); the number must count from 1, without leading zeros.
fn split_link(name: &str) -> Option<(&str, usize)> {
    let at = name.find(|c: char| c.is_ascii_digit())?;
    let (stem, digits) = name.split_at(at);
    if digits.starts_with('0') || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let link: usize = digits.parse().ok()?;
    Some((stem, link - 1))
}

impl FromStr for ParameterId {
    type Err = ParseNameError;

    fn from_str(name: &str) -> Result<ParameterId, ParseNameError> {
        let (stem, link) = split_link(name).ok_or(PARAMETER_NAME)?;
        let kind = ParameterKind::from_stem(stem).ok_or(PARAMETER_NAME)?;
        Ok(ParameterId { link, kind })
    }
}

/// The name of a base parameter: the standard parameter it is built on, with `R` after the
/// stem when other parameters were grouped into it (`ZZR1`, `XY2`, `MXR2`;
/// docs/regrouping.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BaseName {
    /// The standard parameter it is built on.
    pub on: ParameterId,
    /// Whether others were grouped into it.
    pub regrouped: bool,
}

impl fmt::Display for BaseName {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = if self.regrouped { "R" } else { "" };
        write!(f, "{}{r}{}", self.on.kind.stem(), self.on.link + 1)
    }
}

impl FromStr for BaseName {
    type Err = ParseNameError;

    fn from_str(name: &str) -> Result<BaseName, ParseNameError> {
        const BASE_NAME: ParseNameError = ParseNameError {
            expected: "a base parameter name is a standard parameter name, with `R` after the \
                       stem when others were grouped into it, e.g. `ZZR1` or `XY2`",
        };
        let (stem, link) = split_link(name).ok_or(BASE_NAME)?;
        // `M` followed by `R` is the regrouped mass `MR`, never a stem of its own
        let (stem, regrouped) = match stem.strip_suffix('R') {
            Some(s) => (s, true),
            None => (stem, false),
        };
        let kind = ParameterKind::from_stem(stem).ok_or(BASE_NAME)?;
        Ok(BaseName {
            on: ParameterId { link, kind },
            regrouped,
        })
    }
}

impl FromStr for DriveTerm {
    type Err = ParseNameError;

    fn from_str(name: &str) -> Result<DriveTerm, ParseNameError> {
        DriveTerm::ALL
            .into_iter()
            .find(|d| d.stem() == name)
            .ok_or(ParseNameError {
                expected: "drive terms are `Ia` (rotor inertia), `Fv` (viscous friction), `Fc` \
                           (Coulomb friction) and `Fo` (offset)",
            })
    }
}

impl fmt::Display for DriveTerm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.stem())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::string::ToString;

    #[test]
    fn every_name_reads_back_as_written() {
        for link in [0, 1, 8, 31] {
            for (index, kind) in ParameterKind::ALL.into_iter().enumerate() {
                assert_eq!(kind.index(), index);
                let p = ParameterId::new(link, kind);
                let name = p.to_string();
                assert_eq!(name.parse::<ParameterId>(), Ok(p), "{name}");
                for regrouped in [false, true] {
                    let b = BaseName { on: p, regrouped };
                    let name = b.to_string();
                    assert_eq!(name.parse::<BaseName>(), Ok(b), "{name}");
                }
            }
        }
        assert_eq!(
            ParameterId::new(11, ParameterKind::Drive(DriveTerm::Fv)).to_string(),
            "Fv12"
        );
    }

    #[test]
    fn names_that_are_not_parameters_are_refused() {
        for bad in [
            "", "XX", "XX0", "XX01", "XX1a", "xx1", "Iam6", "XXR1", "R1", "M-1", "1XX",
        ] {
            assert!(bad.parse::<ParameterId>().is_err(), "{bad}");
        }
        for bad in ["XXRR1", "R1", "Fv0", "ZZr1"] {
            assert!(bad.parse::<BaseName>().is_err(), "{bad}");
        }
        assert_eq!(
            "MR2".parse::<BaseName>().map(|b| (b.on.kind, b.regrouped)),
            Ok((ParameterKind::Inertial(Inertial::M), true))
        );
        assert!("Fx".parse::<DriveTerm>().is_err());
        assert!(DriveTerm::Fv.non_negative() && !DriveTerm::Fo.non_negative());
    }
}
