//! Reading a robot from TOML, with errors that name file, line and column.
//!
//! ```toml
//! name = "ur5e"
//! convention = "modified"        # or "standard"
//! gravity = [0, 0, -9.81]        # optional, base frame
//! drive = ["Ia", "Fv", "Fc"]     # optional default drive terms of every joint
//! [symbols]                      # optional values of geometric symbols
//! L3 = 0.425
//! [[joints]]
//! type = "revolute"              # or "prismatic"; default revolute
//! alpha = "pi/2"                 # a number, an exact angle, or a symbol expression
//! a = "-L3"
//! d = 0.1625
//! theta = 0                      # offset of the joint angle
//! drive = ["Ia"]                 # optional, overrides the default
//! limits = { position = [-6.28, 6.28], velocity = 3.14, acceleration = 10, torque = 150 }
//! ```

use super::{Convention, DescriptionError, Drive, Geometry, Joint, JointKind, Limits, Robot};
use crate::expr::{Arena, Node};
use serde::Deserialize;
use serde::de::{self, Deserializer, Visitor};
use std::collections::BTreeMap;
use std::fmt;
use std::ops::Range;
use toml::Spanned;

/// A geometric value as written: a number or a text expression.
#[derive(Debug, Clone)]
enum RawValue {
    Number(f64),
    Text(String),
}

impl<'de> Deserialize<'de> for RawValue {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<RawValue, D::Error> {
        struct V;
        impl Visitor<'_> for V {
            type Value = RawValue;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(
                    "a number, an exact angle such as \"pi/2\", or a symbol name such as \"L3\"",
                )
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<RawValue, E> {
                Ok(RawValue::Number(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<RawValue, E> {
                Ok(RawValue::Number(v as f64))
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<RawValue, E> {
                Ok(RawValue::Number(v))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<RawValue, E> {
                Ok(RawValue::Text(v.to_owned()))
            }
        }
        deserializer.deserialize_any(V)
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRobot {
    name: Spanned<String>,
    convention: Spanned<String>,
    gravity: Option<Spanned<Vec<Spanned<RawValue>>>>,
    drive: Option<Spanned<Vec<Spanned<String>>>>,
    #[serde(default)]
    symbols: BTreeMap<String, Spanned<f64>>,
    joints: Vec<RawJoint>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawJoint {
    #[serde(rename = "type")]
    kind: Option<Spanned<String>>,
    alpha: Option<Spanned<RawValue>>,
    a: Option<Spanned<RawValue>>,
    d: Option<Spanned<RawValue>>,
    theta: Option<Spanned<RawValue>>,
    drive: Option<Spanned<Vec<Spanned<String>>>>,
    #[serde(default)]
    limits: RawLimits,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawLimits {
    position: Option<Spanned<[f64; 2]>>,
    velocity: Option<Spanned<f64>>,
    acceleration: Option<Spanned<f64>>,
    torque: Option<Spanned<f64>>,
}

/// Where a problem is: file name, the text (for line/column), and a span.
struct Place<'a> {
    file: &'a str,
    text: &'a str,
}

impl Place<'_> {
    fn line_column(&self, offset: usize) -> (usize, usize) {
        let before = &self.text[..offset.min(self.text.len())];
        let line = before.matches('\n').count() + 1;
        let column = before.chars().rev().take_while(|&c| c != '\n').count() + 1;
        (line, column)
    }

    fn invalid(&self, span: Range<usize>, message: String, help: &str) -> DescriptionError {
        let (line, column) = self.line_column(span.start);
        DescriptionError::Invalid {
            file: self.file.to_owned(),
            line,
            column,
            message,
            help: help.to_owned(),
            span: Some((span.start, span.end)),
        }
    }
}

impl Robot {
    /// Reads a description file.
    pub fn from_file(path: &std::path::Path) -> Result<Robot, DescriptionError> {
        let text = std::fs::read_to_string(path).map_err(|e| DescriptionError::Read {
            file: path.display().to_string(),
            reason: e.to_string(),
        })?;
        Robot::from_toml(&text, &path.display().to_string())
    }

    /// Parses a description from TOML text; `file` names it in errors.
    pub fn from_toml(text: &str, file: &str) -> Result<Robot, DescriptionError> {
        let place = Place { file, text };
        let raw: RawRobot = toml::from_str(text).map_err(|e| {
            let (line, column) = e
                .span()
                .map(|s| place.line_column(s.start))
                .unwrap_or((1, 1));
            DescriptionError::Syntax {
                file: file.to_owned(),
                line,
                column,
                message: e.message().trim().to_owned(),
            }
        })?;
        let name = raw.name.get_ref();
        if name.is_empty()
            || !name.starts_with(|c: char| c.is_ascii_alphabetic())
            || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        {
            return Err(place.invalid(
                raw.name.span(),
                format!("robot name `{name}` is not an identifier"),
                "use letters, digits and `_`, starting with a letter (it names the generated type)",
            ));
        }
        let convention = match raw.convention.get_ref().as_str() {
            "modified" => Convention::Modified,
            "standard" => Convention::Standard,
            other => {
                return Err(place.invalid(
                    raw.convention.span(),
                    format!("unknown DH convention `{other}`"),
                    "write `convention = \"modified\"` (Craig/Khalil) or `convention = \"standard\"` (classic)",
                ));
            }
        };
        let default_drive = match &raw.drive {
            Some(d) => drive(&place, d)?,
            None => Drive::NONE,
        };
        let gravity = match &raw.gravity {
            None => None,
            Some(g) if g.get_ref().len() != 3 => {
                return Err(place.invalid(
                    g.span(),
                    format!("gravity has {} values", g.get_ref().len()),
                    "give three values in the base frame, e.g. `gravity = [0, 0, -9.81]`",
                ));
            }
            Some(g) => {
                let v: Result<Vec<Geometry>, _> =
                    g.get_ref().iter().map(|x| geometry(&place, x)).collect();
                let v = v?;
                Some([v[0].clone(), v[1].clone(), v[2].clone()])
            }
        };
        if raw.joints.is_empty() {
            return Err(place.invalid(
                0..0,
                "the robot has no joints".into(),
                "add one `[[joints]]` table per DH row",
            ));
        }
        let mut joints = Vec::with_capacity(raw.joints.len());
        let mut spans = Vec::new();
        for rj in &raw.joints {
            let kind = match rj.kind.as_ref().map(|k| (k.get_ref().as_str(), k.span())) {
                None | Some(("revolute", _)) => JointKind::Revolute,
                Some(("prismatic", _)) => JointKind::Prismatic,
                Some((other, span)) => {
                    return Err(place.invalid(
                        span,
                        format!("unknown joint type `{other}`"),
                        "write `type = \"revolute\"` or `type = \"prismatic\"`",
                    ));
                }
            };
            let value = |v: &Option<Spanned<RawValue>>| match v {
                Some(v) => geometry(&place, v).map(|g| (g, Some(v.span()))),
                None => Ok((Geometry::zero(), None)),
            };
            let (alpha, sa) = value(&rj.alpha)?;
            let (a, s_a) = value(&rj.a)?;
            let (d, sd) = value(&rj.d)?;
            let (theta, st) = value(&rj.theta)?;
            spans.extend([sa, s_a, sd, st]);
            let drive = match &rj.drive {
                Some(d) => drive(&place, d)?,
                None => default_drive,
            };
            joints.push(Joint {
                kind,
                alpha,
                a,
                d,
                theta,
                limits: limits(&place, &rj.limits)?,
                drive,
            });
        }
        let mut robot = Robot {
            name: name.clone(),
            convention,
            gravity: gravity
                .unwrap_or_else(|| [Geometry::zero(), Geometry::zero(), Geometry::number(-9.81)]),
            joints,
            symbols: Vec::new(),
        };
        let symbols = check_geometry(&robot, &spans).map_err(|e| relocate(&place, e))?;
        for (name, value) in &raw.symbols {
            if !value.get_ref().is_finite() {
                return Err(place.invalid(
                    value.span(),
                    format!("symbol `{name}` is not finite"),
                    "give a finite number",
                ));
            }
        }
        robot.symbols = symbols
            .into_iter()
            .map(|(s, _)| {
                let v = raw.symbols.get(&s).map(|v| *v.get_ref());
                (s, v)
            })
            .collect();
        Ok(robot)
    }
}

/// Turns an error with a span from `check_geometry` into one with line and column.
fn relocate(place: &Place<'_>, e: DescriptionError) -> DescriptionError {
    match e {
        DescriptionError::Invalid {
            message,
            help,
            span: Some((s, t)),
            ..
        } => place.invalid(s..t, message, &help),
        other => other,
    }
}

fn geometry(place: &Place<'_>, v: &Spanned<RawValue>) -> Result<Geometry, DescriptionError> {
    match v.get_ref() {
        RawValue::Number(x) if !x.is_finite() => Err(place.invalid(
            v.span(),
            format!("`{x}` is not a finite number"),
            "DH values and gravity must be finite numbers, exact angles or symbols",
        )),
        RawValue::Number(x) => Ok(Geometry::number(*x)),
        RawValue::Text(t) => Ok(Geometry::text(t)),
    }
}

fn drive(
    place: &Place<'_>,
    names: &Spanned<Vec<Spanned<String>>>,
) -> Result<Drive, DescriptionError> {
    let mut d = Drive::NONE;
    for n in names.get_ref() {
        match n.get_ref().as_str() {
            "Ia" => d.ia = true,
            "Fv" => d.fv = true,
            "Fc" => d.fc = true,
            "Fo" => d.fo = true,
            other => {
                return Err(place.invalid(
                    n.span(),
                    format!("unknown drive term `{other}`"),
                    "drive terms are \"Ia\" (rotor inertia), \"Fv\" (viscous), \"Fc\" (Coulomb), \"Fo\" (offset)",
                ));
            }
        }
    }
    Ok(d)
}

fn limits(place: &Place<'_>, raw: &RawLimits) -> Result<Limits, DescriptionError> {
    let positive = |v: &Option<Spanned<f64>>, what: &str| match v {
        Some(x) if !(x.get_ref().is_finite() && *x.get_ref() > 0.0) => Err(place.invalid(
            x.span(),
            format!(
                "{what} limit {} is not a positive finite number",
                x.get_ref()
            ),
            "limits are maximum absolute values, e.g. `velocity = 3.14`",
        )),
        Some(x) => Ok(Some(*x.get_ref())),
        None => Ok(None),
    };
    let position = match &raw.position {
        Some(p) => {
            let [lo, hi] = *p.get_ref();
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(place.invalid(
                    p.span(),
                    format!(
                        "position limits [{lo}, {hi}] are not an increasing pair of finite numbers"
                    ),
                    "write `position = [lower, upper]` with lower < upper",
                ));
            }
            Some([lo, hi])
        }
        None => None,
    };
    Ok(Limits {
        position,
        velocity: positive(&raw.velocity, "velocity")?,
        acceleration: positive(&raw.acceleration, "acceleration")?,
        torque: positive(&raw.torque, "torque")?,
    })
}

/// True for names the derivation uses itself (joint variables, parameters).
fn reserved(name: &str) -> bool {
    let prefixes = [
        "qdd", "qd", "q", "XX", "XY", "XZ", "YY", "YZ", "ZZ", "MX", "MY", "MZ", "M", "Ia", "Fv",
        "Fc", "Fo",
    ];
    prefixes.iter().any(|p| {
        name.strip_prefix(p)
            .is_some_and(|rest| !rest.is_empty() && rest.chars().all(|c| c.is_ascii_digit()))
    }) || name == "pi"
}

/// Checks that every geometric value is an expression in numbers, `pi` and
/// free symbol names, and returns the symbols in order of first use.
/// `spans[i]` is the span of value i (alpha, a, d, theta of each joint), if known.
pub(super) fn check_geometry(
    robot: &Robot,
    spans: &[Option<Range<usize>>],
) -> Result<Vec<(String, Option<f64>)>, DescriptionError> {
    let mut arena = Arena::new();
    let mut symbols: Vec<(String, Option<f64>)> = Vec::new();
    let values = robot
        .joints
        .iter()
        .enumerate()
        .flat_map(|(j, joint)| {
            [
                ("alpha", &joint.alpha),
                ("a", &joint.a),
                ("d", &joint.d),
                ("theta", &joint.theta),
            ]
            .into_iter()
            .map(move |(what, g)| (format!("joint {} `{what}`", j + 1), g))
        })
        .chain(robot.gravity.iter().map(|g| ("gravity".to_owned(), g)));
    for (i, (what, g)) in values.enumerate() {
        let span = spans.get(i).cloned().flatten();
        let fail = |message: String, help: &str| DescriptionError::Invalid {
            file: "<code>".to_owned(),
            line: 0,
            column: 0,
            message,
            help: help.to_owned(),
            span: span.as_ref().map(|s| (s.start, s.end)),
        };
        let e = arena.parse(g.as_str()).map_err(|err| {
            fail(
                format!("{what} `{}` is not an expression ({err})", g.as_str()),
                "write a number, an angle such as \"pi/2\" or \"-pi/2\", or a symbol such as \"L3\" or \"-d4\"",
            )
        })?;
        let seen = arena.reachable(&[e]);
        for node in (0..seen.len())
            .filter(|&k| seen[k])
            .map(|k| arena.node_at(k))
        {
            match node {
                Node::Sym(s) => {
                    let name = arena.symbol_name(*s);
                    if reserved(name) {
                        return Err(fail(
                            format!(
                                "{what} uses `{name}`, a name robid gives to joint variables and parameters"
                            ),
                            "rename the symbol, e.g. `L3` or `d_tool`",
                        ));
                    }
                    if !symbols.iter().any(|(n, _)| n == name) {
                        symbols.push((name.to_owned(), None));
                    }
                }
                Node::Sin(_) | Node::Cos(_) | Node::Sign(_) | Node::Sqrt(_) => {
                    return Err(fail(
                        format!("{what} `{}` calls a function", g.as_str()),
                        "geometric values are sums and products of numbers, pi and symbols",
                    ));
                }
                _ => {}
            }
        }
    }
    Ok(symbols)
}
