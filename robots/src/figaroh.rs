//! FIGAROH's published base parameters of the Stäubli TX40 example
//! (`data/staubli_tx40/reference/TX40_bp_5.csv`), read in robid's names, and the
//! comparison of base parameters by their expressions: used by `robid demo` and the TX40
//! test.
//!
//! ```
//! use robots::figaroh::{self, Combination};
//!
//! let reference = figaroh::tx40();
//! assert_eq!(reference.len(), 60);
//! let zz1 = figaroh::combination("Izz1 + 0.5*m2 - fs1", figaroh::our_name).unwrap();
//! assert_eq!(zz1, Combination::from([("ZZ1".into(), 1.0), ("M2".into(), 0.5), ("Fc1".into(), -1.0)]));
//! assert!(figaroh::same(&zz1, &zz1));
//! ```

use std::collections::BTreeMap;

use robid_runtime::model::{DriveTerm, Inertial, ParameterId, ParameterKind};

/// A base parameter as a combination of standard parameters: name -> coefficient.
pub type Combination = BTreeMap<String, f64>;

/// FIGAROH's file: `expression, OLS value, rel. std %, WLS value, rel. std %` per line.
const TX40: &str = include_str!("../../data/staubli_tx40/reference/TX40_bp_5.csv");

/// One of FIGAROH's base parameters.
#[derive(Debug, Clone)]
pub struct Published {
    /// The expression as FIGAROH writes it (`Izz1 + 0.5*m2`).
    pub text: String,
    /// The expression in robid's names.
    pub combination: Combination,
    /// FIGAROH's OLS value.
    pub value: f64,
    /// FIGAROH's OLS relative standard deviation, in %.
    pub relative_std_percent: f64,
}

/// FIGAROH's 60 base parameters of the TX40 log, in file order (lines that do not read as
/// an expression and two numbers are left out).
pub fn tx40() -> Vec<Published> {
    TX40.lines()
        .filter_map(|line| {
            let f: Vec<&str> = line.split(',').map(str::trim).collect();
            Some(Published {
                text: f.first()?.to_string(),
                combination: combination(f.first()?, our_name)?,
                value: f.get(1)?.parse().ok()?,
                relative_std_percent: f.get(2)?.parse().ok()?,
            })
        })
        .collect()
}

/// Reads `a + 0.5*b - c` (robid's and FIGAROH's expression text), with every name passed
/// through `rename`; `None` when a coefficient is not a finite number or a name is not
/// one (empty, or with characters other than letters, digits, `_` and `.`).
pub fn combination(text: &str, rename: impl Fn(&str) -> String) -> Option<Combination> {
    let mut out = Combination::new();
    for term in text.replace(" - ", " + -").split(" + ") {
        let term = term.trim();
        let (sign, term) = match term.strip_prefix('-') {
            Some(t) => (-1.0, t.trim()),
            None => (1.0, term),
        };
        let (coef, name) = match term.split_once('*') {
            Some((c, n)) => (c.trim().parse::<f64>().ok()?, n.trim()),
            None => (1.0, term),
        };
        // any text was taken for a name: "((((" read as 1 times a parameter "(((("
        let named = name.starts_with(|c: char| c.is_alphabetic() || c == '_')
            && name
                .chars()
                .all(|c| c.is_alphanumeric() || c == '_' || c == '.');
        if !(named && coef.is_finite()) {
            return None;
        }
        *out.entry(rename(name)).or_insert(0.0) += sign * coef;
    }
    Some(out)
}

/// A FIGAROH name in robid's: `Izz1` -> `ZZ1`, `mx2` -> `MX2`, `m3` -> `M3`, `fv1` -> `Fv1`,
/// `fs1` -> `Fc1`, `off1` -> `Fo1`, `Ia1` -> `Ia1`; other names (extra columns such as
/// `Iam6`) are kept.
pub fn our_name(name: &str) -> String {
    let digits = name.trim_start_matches(|c: char| !c.is_ascii_digit());
    let stem = &name[..name.len() - digits.len()];
    let kind = match stem {
        "Ixx" => ParameterKind::Inertial(Inertial::XX),
        "Ixy" => ParameterKind::Inertial(Inertial::XY),
        "Ixz" => ParameterKind::Inertial(Inertial::XZ),
        "Iyy" => ParameterKind::Inertial(Inertial::YY),
        "Iyz" => ParameterKind::Inertial(Inertial::YZ),
        "Izz" => ParameterKind::Inertial(Inertial::ZZ),
        "mx" => ParameterKind::Inertial(Inertial::MX),
        "my" => ParameterKind::Inertial(Inertial::MY),
        "mz" => ParameterKind::Inertial(Inertial::MZ),
        "m" => ParameterKind::Inertial(Inertial::M),
        "Ia" => ParameterKind::Drive(DriveTerm::Ia),
        "fv" => ParameterKind::Drive(DriveTerm::Fv),
        "fs" => ParameterKind::Drive(DriveTerm::Fc),
        "off" => ParameterKind::Drive(DriveTerm::Fo),
        _ => return name.to_string(),
    };
    match digits.parse::<usize>() {
        Ok(link) if link >= 1 => ParameterId::new(link - 1, kind).to_string(),
        _ => name.to_string(),
    }
}

/// Whether two combinations have the same names and coefficients within 1e-4 relative
/// (FIGAROH prints five decimals).
pub fn same(a: &Combination, b: &Combination) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|((n, x), (m, y))| n == m && (x - y).abs() <= 1e-4 * x.abs().max(1.0))
}

#[cfg(test)]
mod tests {
    #[test]
    fn names_map_to_robid_names() {
        for (figaroh, ours) in [
            ("Izz1", "ZZ1"),
            ("Ixy3", "XY3"),
            ("mx2", "MX2"),
            ("m6", "M6"),
            ("fs4", "Fc4"),
            ("off2", "Fo2"),
            ("fv5", "Fv5"),
            ("Iam6", "Iam6"),
            ("fvm6", "fvm6"),
        ] {
            assert_eq!(super::our_name(figaroh), ours);
        }
    }

    /// Text that is no expression gave a combination of a parameter named after it
    /// (`((((` read as 1 times "((((", review 147); it is refused, as are empty terms and
    /// coefficients that are not finite.
    #[test]
    fn text_that_is_no_expression_is_refused() {
        let read = |t: &str| super::combination(t, str::to_string);
        for bad in [
            "((((", "", "a + + b", "inf*a", "2*", "a + 3b", "-", "0.5*(a)",
        ] {
            assert_eq!(read(bad), None, "{bad:?}");
        }
        let c = read("Izz1 + 0.5*m2 - fs1 - 1e-3*X_y.z").unwrap();
        assert_eq!(c.len(), 4);
        assert_eq!(
            (c["Izz1"], c["m2"], c["fs1"], c["X_y.z"]),
            (1.0, 0.5, -1.0, -1e-3)
        );
        // every published expression still reads
        assert_eq!(super::tx40().len(), 60);
    }
}
