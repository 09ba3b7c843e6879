//! Checking a robot against the rules of [`bounds`](super::bounds) and the
//! naming rules, collecting every problem, each located where the checked
//! item was written: a file's line and column (`file.rs`) or the argument of
//! a library call ([`Code`]).

use super::bounds::{
    ANGLE_RESOLUTION, LENGTH_SNAP, MAX_ACCELERATION, MAX_ANGLE, MAX_CALIBRATED_LENGTH, MAX_GRAVITY,
    MAX_JOINTS, MAX_LENGTH, MAX_NAME_LEN, MAX_POSITION, MAX_SAMPLED, MAX_SYMBOLS, MAX_TORQUE,
    MAX_VELOCITY, MIN_GRAVITY, MIN_LENGTH, RIGHT_ANGLE_SNAP, SYMBOL_SAMPLES, calibrated_pair,
};
use super::interval::magnitude_bound;
use super::{Convention, DescriptionError, Geometry, Joint, JointKind, Limits, Robot, Transform};
use crate::emit::type_name;
use crate::expr::Arena;
use std::f64::consts::FRAC_PI_2;

/// The parts of a robot before they are checked.
pub(super) struct Parts {
    pub(super) name: String,
    pub(super) convention: Convention,
    pub(super) gravity: [Geometry; 3],
    pub(super) joints: Vec<Joint>,
    /// Frame 0 in the world frame, if given.
    pub(super) base: Option<Transform>,
    /// The tool frame in frame n, if given.
    pub(super) tool: Option<Transform>,
    /// Values given to symbols, in the order given.
    pub(super) values: Vec<(String, f64)>,
    /// The words of values that could not be read (their symbols are
    /// unknown): a value given to one of them is not reported as unused.
    pub(super) unread_words: Vec<String>,
    /// Whether the DH values were measured (fitted to a URDF's origins and axes, or a
    /// description's `calibrated = true`) rather than typed: an angle near a right angle is
    /// then what was measured, not a typed approximation, and is not refused for it.
    pub(super) measured: bool,
    /// Where a description file first used each symbol (`file:line:column`), kept from a
    /// robot read from a file through its `with_*` changes ([`Robot::symbol_place`]).
    pub(super) uses: Vec<(String, String)>,
    /// Where a description file wrote each joint's table (`file:line:column`), kept like
    /// `uses` ([`Robot::joint_place`]).
    pub(super) joint_places: Vec<String>,
}

/// A geometric value of a joint: the DH row and Khalil and Kleinfinger's `gamma` and `b`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Dh {
    Alpha,
    A,
    D,
    Theta,
    Gamma,
    B,
}

impl Dh {
    pub(super) const ALL: [Dh; 6] = [Dh::Alpha, Dh::A, Dh::D, Dh::Theta, Dh::Gamma, Dh::B];

    pub(super) fn key(self) -> &'static str {
        match self {
            Dh::Alpha => "alpha",
            Dh::A => "a",
            Dh::D => "d",
            Dh::Theta => "theta",
            Dh::Gamma => "gamma",
            Dh::B => "b",
        }
    }

    pub(super) fn of(self, joint: &Joint) -> &Geometry {
        match self {
            Dh::Alpha => &joint.alpha,
            Dh::A => &joint.a,
            Dh::D => &joint.d,
            Dh::Theta => &joint.theta,
            Dh::Gamma => &joint.gamma,
            Dh::B => &joint.b,
        }
    }

    fn role(self, kind: JointKind) -> Role {
        match (self, kind) {
            (Dh::Theta, JointKind::Revolute) => Role::Offset,
            (Dh::Alpha | Dh::Theta | Dh::Gamma, _) => Role::Angle,
            (Dh::A | Dh::D | Dh::B, _) => Role::Length,
        }
    }
}

/// Which constant transform of a description: `[base]` or `[tool]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Mount {
    Base,
    Tool,
}

impl Mount {
    pub(super) fn key(self) -> &'static str {
        match self {
            Mount::Base => "base",
            Mount::Tool => "tool",
        }
    }
}

/// The translation or the rotation of a transform.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Part {
    Xyz,
    Rpy,
}

impl Part {
    pub(super) fn key(self) -> &'static str {
        match self {
            Part::Xyz => "xyz",
            Part::Rpy => "rpy",
        }
    }

    /// The name of component `i` in messages.
    fn component(self, i: usize) -> &'static str {
        match self {
            Part::Xyz => ["x", "y", "z"][i.min(2)],
            Part::Rpy => ["roll", "pitch", "yaw"][i.min(2)],
        }
    }
}

/// A joint limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub(super) enum Limit {
    Position,
    Velocity,
    Acceleration,
    Torque,
}

impl Limit {
    pub(super) const ALL: [Limit; 4] = [
        Limit::Position,
        Limit::Velocity,
        Limit::Acceleration,
        Limit::Torque,
    ];

    pub(super) fn key(self) -> &'static str {
        match self {
            Limit::Position => "position",
            Limit::Velocity => "velocity",
            Limit::Acceleration => "acceleration",
            Limit::Torque => "torque",
        }
    }
}

/// What an error is about.
#[derive(Clone, Copy, Debug)]
pub(super) enum Item<'a> {
    Name,
    Joints,
    /// The table of joint `j` (0-based).
    Joint(usize),
    /// A DH value of joint `j` (0-based).
    Value(usize, Dh),
    /// Gravity component `i`.
    Gravity(usize),
    Limit(usize, Limit),
    /// Component `i` of the translation or rotation of `[base]` or `[tool]`.
    Transform(Mount, Part, usize),
    /// The value given to a symbol.
    Symbol(&'a str),
}

/// Makes an error located where `item` was written.
pub(super) trait Locate {
    fn error(&self, item: Item<'_>, message: String, help: String) -> DescriptionError;

    /// Where `item` was written, as `file:line:column`, when it was read from a file.
    fn place(&self, _item: Item<'_>) -> Option<String> {
        None
    }
}

/// Items given in code: errors name the argument.
pub(super) struct Code;

impl Locate for Code {
    fn error(&self, item: Item<'_>, message: String, help: String) -> DescriptionError {
        let argument = match item {
            Item::Name => "the robot name".to_owned(),
            Item::Joints => "`joints`".to_owned(),
            Item::Joint(j) => format!("`joints[{j}]`"),
            Item::Value(j, dh) => format!("`joints[{j}].{}`", dh.key()),
            Item::Gravity(i) => format!("`gravity[{i}]`"),
            Item::Limit(j, l) => format!("`joints[{j}].limits.{}`", l.key()),
            Item::Transform(m, p, i) => format!("`{}.{}[{i}]`", m.key(), p.key()),
            Item::Symbol(s) => format!("the value of symbol `{s}`"),
        };
        DescriptionError::Argument {
            argument,
            message,
            help,
        }
    }
}

/// The Rust keywords of every edition (strict, reserved and weak); a robot
/// name names generated code, so it cannot be one.
const KEYWORDS: [&str; 55] = [
    "Self",
    "abstract",
    "as",
    "async",
    "await",
    "become",
    "box",
    "break",
    "const",
    "continue",
    "crate",
    "do",
    "dyn",
    "else",
    "enum",
    "extern",
    "false",
    "final",
    "fn",
    "for",
    "gen",
    "if",
    "impl",
    "in",
    "let",
    "loop",
    "macro",
    "macro_rules",
    "match",
    "mod",
    "move",
    "mut",
    "override",
    "priv",
    "pub",
    "raw",
    "ref",
    "return",
    "safe",
    "self",
    "static",
    "struct",
    "super",
    "trait",
    "true",
    "try",
    "type",
    "typeof",
    "union",
    "unsafe",
    "unsized",
    "use",
    "virtual",
    "where",
    "while",
];

/// Why `name` cannot name a robot (message, help), if it cannot.
pub(crate) fn name_problem(name: &str) -> Option<(String, String)> {
    let help = "use letters, digits and `_`, starting with a letter: it names the generated type (`ur5e` -> `Ur5e`)";
    let length = name.chars().count();
    if length > MAX_NAME_LEN {
        let head: String = name.chars().take(32).collect();
        return Some((
            format!("robot name `{head}..` has {length} characters, more than {MAX_NAME_LEN}"),
            "give a shorter name: it names the generated type".to_owned(),
        ));
    }
    if !name.starts_with(|c: char| c.is_ascii_alphabetic())
        || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
    {
        return Some((
            format!("robot name `{name}` is not an identifier"),
            help.to_owned(),
        ));
    }
    let ty = type_name(name);
    if KEYWORDS.contains(&name) || KEYWORDS.contains(&ty.as_str()) {
        return Some((
            format!("robot name `{name}` is a Rust keyword or makes one (type `{ty}`)"),
            "choose another name, e.g. `my_arm`: it names the generated type".to_owned(),
        ));
    }
    None
}

/// What a geometric value is, for its range.
#[derive(Clone, Copy, PartialEq)]
enum Role {
    Length,
    Angle,
    /// The `theta` of a revolute joint: an offset of its variable, which shifts the
    /// regressor's columns along `q` without changing what they span, so the base
    /// parameters are the same at any value; a calibration's few microradians from a
    /// right angle are taken as written.
    Offset,
    Gravity,
}

impl Role {
    /// The unit of a value in this role (and of a symbol whose first use it is).
    fn unit(self) -> &'static str {
        match self {
            Role::Length => "m",
            Role::Angle | Role::Offset => "rad",
            Role::Gravity => "m/s^2",
        }
    }
}

impl Parts {
    /// The robot, or every problem found.
    pub(super) fn check(mut self, locate: &dyn Locate) -> Result<Robot, Vec<DescriptionError>> {
        self.snap_roundings();
        let mut errors = Vec::new();
        let mut error = |item: Item<'_>, message: String, help: &str| {
            errors.push(locate.error(item, message, help.to_owned()));
        };
        if let Some((message, help)) = name_problem(&self.name) {
            error(Item::Name, message, &help);
        }
        if self.joints.is_empty() {
            error(
                Item::Joints,
                "the robot has no joints".to_owned(),
                "add one joint (a `[[joints]]` table) per DH row",
            );
        } else if self.joints.len() > MAX_JOINTS {
            error(
                Item::Joints,
                format!("the robot has {} joints", self.joints.len()),
                &format!(
                    "robid derives serial chains of at most {MAX_JOINTS} joints: describe a \
                     part of the robot with at most {MAX_JOINTS} rows"
                ),
            );
        }
        let values = self.values();
        let mut symbols: Vec<String> = Vec::new();
        let mut uses: Vec<(String, String)> = Vec::new();
        // each symbol's unit, by the value that first uses it
        let mut units: Vec<&'static str> = Vec::new();
        for (item, g, role) in &values {
            for s in g.symbols() {
                if symbols.contains(s) {
                    continue;
                }
                symbols.push(s.clone());
                units.push(role.unit());
                let place = locate.place(*item).or_else(|| {
                    let kept = self.uses.iter().find(|(name, _)| name == s);
                    kept.map(|(_, place)| place.clone())
                });
                if let Some(place) = place {
                    uses.push((s.clone(), place));
                }
                if symbols.len() == MAX_SYMBOLS + 1 {
                    error(
                        *item,
                        format!("`{s}` is geometric symbol number {}", MAX_SYMBOLS + 1),
                        &format!(
                            "robid handles at most {MAX_SYMBOLS} symbols; give numbers for the others"
                        ),
                    );
                }
            }
        }
        for (s, v) in &self.values {
            if !v.is_finite() {
                error(
                    Item::Symbol(s),
                    format!("the value of symbol `{s}` is {v}"),
                    "give a finite number",
                );
            }
            if s == "pi" {
                error(
                    Item::Symbol(s),
                    "`pi` is the constant of the expressions, not a symbol".to_owned(),
                    "remove the entry (\"pi/2\" is read as the constant), or name the symbol \
                     otherwise",
                );
            } else if !symbols.contains(s) && !self.unread_words.contains(s) {
                error(
                    Item::Symbol(s),
                    format!(
                        "symbol `{s}` has a value, but no DH value or gravity depends on it (an \
                         expression in which it cancels, such as `L/L`, does not)"
                    ),
                    &unused_help(s, &symbols),
                );
            }
        }
        let given = |s: &str| {
            self.values
                .iter()
                .find(|(n, _)| n == s)
                .map(|&(_, v)| v)
                .filter(|v| v.is_finite())
        };
        let pairs: Vec<Pair> = self
            .joints
            .iter()
            .map(|joint| match self.convention {
                Convention::Modified => Pair::of(joint),
                Convention::Standard => Pair::None,
            })
            .collect();
        for (item, g, role) in &values {
            let pair = match item {
                Item::Value(j, Dh::Alpha | Dh::B | Dh::D) => pairs[*j],
                _ => Pair::None,
            };
            let measured = match (item, role) {
                (_, _) if matches!(pair, Pair::Calibrated) => Measured::Pair,
                (Item::Value(..), Role::Angle) if self.measured => Measured::Angle,
                _ => Measured::No,
            };
            if let Some((message, help)) = value_problem(*item, g, *role, &given, pair, measured) {
                error(*item, message, &help);
            }
        }
        if let Some((i, message, help)) = tilted_gravity(self.base.as_ref(), &self.gravity, &given)
        {
            error(Item::Transform(Mount::Base, Part::Rpy, i), message, &help);
        }
        if self.convention == Convention::Standard {
            for (j, joint) in self.joints.iter().enumerate() {
                for dh in [Dh::Gamma, Dh::B] {
                    if !dh.of(joint).is_zero() {
                        let (message, help) = standard_gamma_b(j, dh);
                        error(Item::Value(j, dh), message, &help);
                    }
                }
            }
        }
        for (j, joint) in self.joints.iter().enumerate() {
            for (limit, message, help) in limit_problems(&joint.limits) {
                error(
                    Item::Limit(j, limit),
                    format!("joint {} {message}", j + 1),
                    &help,
                );
            }
        }
        if !errors.is_empty() {
            return Err(errors);
        }
        let symbols = symbols
            .into_iter()
            .map(|s| {
                let v = given(&s);
                (s, v)
            })
            .collect();
        // read from a file: each joint's table; changed in code: the places kept
        let read: Vec<String> = (0..self.joints.len())
            .filter_map(|j| locate.place(Item::Joint(j)))
            .collect();
        let joint_places = if read.len() == self.joints.len() {
            read
        } else {
            self.joint_places
        };
        Ok(Robot {
            name: self.name,
            convention: self.convention,
            gravity: self.gravity,
            joints: self.joints,
            base: self.base,
            tool: self.tool,
            symbols,
            symbol_units: units,
            measured: self.measured,
            uses: super::SymbolUses(uses),
            joint_places: super::JointPlaces(joint_places),
        })
    }

    /// Numeric angles (DH angles, `rpy` of `[base]` and `[tool]`) within
    /// [`RIGHT_ANGLE_SNAP`] of a multiple of pi/2 become that multiple exactly: how programs
    /// print right angles (`1.5707963267948966`, Python's `math.pi / 2`, is 6e-17 rad from
    /// pi/2; `1.57079632679` 4.9e-12), which were refused as "0.0e0 rad from pi/2". Numeric
    /// lengths below [`LENGTH_SNAP`] become 0 (a script's computed zero).
    fn snap_roundings(&mut self) {
        let zero = |g: &mut Geometry| {
            if let Geometry::Number(n) = g
                && n.value() != 0.0
                && n.value().abs() < LENGTH_SNAP
            {
                *g = Geometry::zero();
            }
        };
        let snap = |g: &mut Geometry| {
            let Geometry::Number(n) = g else { return };
            let v = n.value();
            let k = (v / FRAC_PI_2).round();
            if k.abs() <= 4.0 && (v - k * FRAC_PI_2).abs() <= RIGHT_ANGLE_SNAP {
                *g = if k == 0.0 {
                    Geometry::zero()
                } else {
                    Geometry::text(&quarter_text(k)).unwrap_or_else(|_| g.clone())
                };
            }
        };
        for joint in &mut self.joints {
            for g in [&mut joint.alpha, &mut joint.theta, &mut joint.gamma] {
                snap(g);
            }
            for g in [&mut joint.a, &mut joint.d, &mut joint.b] {
                zero(g);
            }
        }
        for t in [&mut self.base, &mut self.tool].into_iter().flatten() {
            t.rpy.iter_mut().for_each(snap);
            t.xyz.iter_mut().for_each(zero);
        }
    }

    /// Every geometric value with its item and role, joints first.
    fn values(&self) -> Vec<(Item<'static>, Geometry, Role)> {
        let mut out = Vec::with_capacity(6 * self.joints.len() + 15);
        for (j, joint) in self.joints.iter().enumerate() {
            for dh in Dh::ALL {
                out.push((
                    Item::Value(j, dh),
                    dh.of(joint).clone(),
                    dh.role(joint.kind),
                ));
            }
        }
        for (i, g) in self.gravity.iter().enumerate() {
            out.push((Item::Gravity(i), g.clone(), Role::Gravity));
        }
        for (mount, transform) in [(Mount::Base, &self.base), (Mount::Tool, &self.tool)] {
            let Some(t) = transform else { continue };
            for (part, values, role) in [
                (Part::Xyz, &t.xyz, Role::Length),
                (Part::Rpy, &t.rpy, Role::Angle),
            ] {
                for (i, g) in values.iter().enumerate() {
                    out.push((Item::Transform(mount, part, i), g.clone(), role));
                }
            }
        }
        out
    }
}

/// The error (message, help) for a nonzero `gamma` or `b` (`dh`) of joint `j` (0-based) in a
/// standard-DH table.
pub(super) fn standard_gamma_b(j: usize, dh: Dh) -> (String, String) {
    (
        format!(
            "joint {} has `{}`, which a standard-DH table cannot have",
            j + 1,
            dh.key()
        ),
        "`gamma` and `b` (Khalil and Kleinfinger's rotation about and translation along z_(j-1)) extend the modified convention: write the table in the modified convention (`convention = \"modified\"`, see docs/conventions.md#khalil-kleinfinger-general-frames)".to_owned(),
    )
}

/// The help for a value given to a symbol nothing uses: the nearest used one.
fn unused_help(symbol: &str, used: &[String]) -> String {
    let nearest = robid_core::names::nearest(symbol, used.iter().map(String::as_str))
        .into_iter()
        .next();
    match nearest {
        Some(n) => format!(
            "did you mean `{n}`? (names are case-sensitive) A symbol without a value becomes a run-time input of the model; remove the entry or use it in a DH value"
        ),
        None => {
            "remove the entry, or write the symbol where it belongs (e.g. `a = \"L2\"`)".to_owned()
        }
    }
}

/// What the item is, in messages.
fn describe(item: Item<'_>) -> String {
    match item {
        Item::Value(j, dh) => format!("joint {} `{}`", j + 1, dh.key()),
        Item::Gravity(i) => format!("gravity {}", ["x", "y", "z"][i.min(2)]),
        Item::Limit(j, l) => format!("joint {} {} limit", j + 1, l.key()),
        Item::Transform(m, p, i) => format!("[{}] {} {}", m.key(), p.key(), p.component(i)),
        Item::Name => "the name".to_owned(),
        Item::Joints => "the joints".to_owned(),
        Item::Joint(j) => format!("joint {}", j + 1),
        Item::Symbol(s) => format!("symbol `{s}`"),
    }
}

/// A number for a message: plain when moderate, else in exponent form.
pub(super) fn show(v: f64) -> String {
    if v == 0.0 || (1e-4..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// What a modified-DH row's `alpha`, `b` and `d` are (numbers only).
#[derive(Clone, Copy)]
enum Pair {
    /// A [calibrated pair](calibrated_pair): its values are measured.
    Calibrated,
    /// A twist within 1e-2 rad of 0 or pi and `b` or `d` beyond [`MAX_LENGTH`] that do not
    /// make a calibrated pair: the row's frame origin is this far (m) from the previous one.
    Broken(f64),
    /// Anything else.
    None,
}

impl Pair {
    fn of(joint: &Joint) -> Pair {
        let number = |g: &Geometry| match g {
            Geometry::Number(n) => Some(n.value()),
            // a right angle written (or snapped to) `pi`, `-pi/2`, ...
            Geometry::Expression(_) => g.quarter_turns().map(|k| k as f64 * FRAC_PI_2),
        };
        let (Some(alpha), Some(b), Some(d)) =
            (number(&joint.alpha), number(&joint.b), number(&joint.d))
        else {
            return Pair::None;
        };
        let (s, c) = alpha.sin_cos();
        if calibrated_pair(alpha, b, d) {
            Pair::Calibrated
        } else if s.abs() < 1e-2 && (b.abs() > MAX_LENGTH || d.abs() > MAX_LENGTH) {
            Pair::Broken((b + d * c).hypot(d * s))
        } else {
            Pair::None
        }
    }
}

/// What of a geometric value was measured rather than typed.
#[derive(Clone, Copy, PartialEq)]
enum Measured {
    /// Nothing: typed values keep every rule.
    No,
    /// The `alpha`, `b` and `d` of a [calibrated pair](calibrated_pair): bounded by the
    /// pair's own rule, its twist measured.
    Pair,
    /// An angle fitted to a URDF: taken at any distance from a right angle.
    Angle,
}

/// Why a geometric value does not suit its role (message, help), if it does not. The
/// `alpha`, `b` and `d` of a [calibrated pair](calibrated_pair) are bounded by the pair's
/// own rule and its twist is measured; `b` and `d` of a broken one are told the rule.
fn value_problem(
    item: Item<'_>,
    g: &Geometry,
    role: Role,
    given: &dyn Fn(&str) -> Option<f64>,
    pair: Pair,
    measured: Measured,
) -> Option<(String, String)> {
    let what = format!("{} = {}", describe(item), quoted(g));
    let mut arena = Arena::new();
    let id = g.to_expr(&mut arena);
    if !g.symbols().is_empty() {
        let bound = magnitude_bound(&arena, id, |_| SYMBOL_SAMPLES);
        if bound.is_nan() || bound > MAX_SAMPLED {
            let [low, high] = SYMBOL_SAMPLES;
            return Some((
                format!(
                    "{what} reaches {} in magnitude for symbol values between {low} and {high}, beyond {}",
                    show(bound),
                    show(MAX_SAMPLED)
                ),
                format!(
                    "robid samples every geometric symbol between {low} and {high} to find the base parameters; write the value so that it stays within {} there (lengths in metres, no division by an expression that can be zero)",
                    show(MAX_SAMPLED)
                ),
            ));
        }
    }
    // The value where the description gives it.
    let mut pairs = Vec::new();
    for s in g.symbols() {
        pairs.push((s.as_str(), given(s)?));
    }
    let values = arena.values(&pairs);
    let v = arena.eval(&[id], &values).ok()?.first().copied()?;
    if !v.is_finite() {
        return Some((
            format!("{what} is {v} at the [symbols] values"),
            "give the symbols values that make it a finite number".to_owned(),
        ));
    }
    let is = if pairs.is_empty() {
        format!("{what} is")
    } else {
        format!("{what} is {} at the [symbols] values,", show(v))
    };
    match role {
        Role::Length if v.abs() > MAX_LENGTH && measured != Measured::Pair => Some((
            format!("{is} beyond ±{} m", show(MAX_LENGTH)),
            match pair {
                Pair::Broken(away) => format!(
                    "DH lengths are in metres; robid accepts lengths up to 1 km, and a longer \
                     `b` and `d` only as a calibrated pair of nearly parallel axes: nearly \
                     opposite, so that the row's frame lies within 1 km of the previous one \
                     (here {} m), each at most {} m",
                    show(format!("{away:.4e}").parse().unwrap_or(away)),
                    show(MAX_CALIBRATED_LENGTH)
                ),
                _ => "DH lengths are in metres; robid accepts lengths up to 1 km".to_owned(),
            },
        )),
        Role::Length if v != 0.0 && v.abs() < MIN_LENGTH => Some((
            format!("{is} shorter than {} m but not zero", show(MIN_LENGTH)),
            "DH lengths are in metres; write 0 for no length".to_owned(),
        )),
        Role::Gravity if v.abs() > MAX_GRAVITY => Some((
            format!("{is} beyond ±{} m/s^2", show(MAX_GRAVITY)),
            "gravity is in m/s^2, e.g. `gravity = [0, 0, -9.81]`".to_owned(),
        )),
        Role::Gravity if v != 0.0 && v.abs() < MIN_GRAVITY => Some((
            format!("{is} smaller than {} m/s^2 but not zero", show(MIN_GRAVITY)),
            "write 0: the regrouping cannot tell a component this small from zero".to_owned(),
        )),
        Role::Angle | Role::Offset if v.abs() > MAX_ANGLE => Some((
            format!("{is} more than a turn (2 pi rad)"),
            "DH angles are in radians: write \"pi/2\" for 90 degrees".to_owned(),
        )),
        Role::Angle
            if pairs.is_empty() && g.quarter_turns().is_none() && measured == Measured::No =>
        {
            let k = (v / FRAC_PI_2).round();
            let off = (v - k * FRAC_PI_2).abs();
            (off < ANGLE_RESOLUTION).then(|| {
                let exact = quarter_text(k);
                // `calibrated` takes the joints' angles as written, not a pose's: a base
                // turned that little off a right angle can leave gravity a component below
                // MIN_GRAVITY, which the regrouping does not tell from zero
                let calibrated = if matches!(item, Item::Transform(..)) {
                    "`calibrated = true` takes the joint table's angles as written, not the \
                     [base] and [tool] poses'"
                } else {
                    "a table measured by a calibration is taken as written with `calibrated = \
                     true` at the top of its description"
                };
                (
                    format!("{is} only {off:.1e} rad from {exact}"),
                    format!(
                        "write \"{exact}\" for the exact angle, or an angle at least {} rad from every multiple of pi/2; {calibrated}",
                        show(ANGLE_RESOLUTION)
                    ),
                )
            })
        }
        _ => None,
    }
}

/// The problem of a `[base]` rotation that turns gravity into a component below
/// [`MIN_GRAVITY`] in frame 0 (where the dynamics use it, `R_base' g`), as (the `rpy`
/// index to blame, message, help): the rule of a gravity component written that small,
/// which the regrouping cannot tell from zero (a tilt of 2e-5 rad gave two more base
/// parameters, MXR1 and MYR1, which 2e-4 m/s^2 of gravity barely excites: `excite`'s
/// condition number 52 000 against 3.15). A written component already that small is told
/// by its own rule; values without symbol values are not judged.
fn tilted_gravity(
    base: Option<&Transform>,
    gravity: &[Geometry; 3],
    given: &dyn Fn(&str) -> Option<f64>,
) -> Option<(usize, String, String)> {
    let base = base.filter(|b| !b.rotation_is_identity())?;
    let mut arena = Arena::new();
    let world = [0, 1, 2].map(|i| gravity[i].to_expr(&mut arena));
    let rpy = [0, 1, 2].map(|i| base.rpy[i].to_expr(&mut arena));
    let r = base.rotation(&mut arena);
    let frame0 = crate::dynamics::vector::mat_t_vec(&mut arena, &r, world);
    let mut pairs = Vec::new();
    for g in gravity.iter().chain(&base.rpy) {
        for s in g.symbols() {
            pairs.push((s.as_str(), given(s)?));
        }
    }
    let values = arena.values(&pairs);
    let small = |v: &f64| *v != 0.0 && v.abs() < MIN_GRAVITY;
    let written = arena.eval(&world, &values).ok()?;
    if written.iter().any(small) {
        return None;
    }
    let turned = arena.eval(&frame0, &values).ok()?;
    let axis = turned.iter().position(small)?;
    // the angle nearest a right angle without being one is the tilt
    let angles = arena.eval(&rpy, &values).ok()?;
    let off = |v: f64| (v - (v / FRAC_PI_2).round() * FRAC_PI_2).abs();
    let (i, tilt) = angles
        .iter()
        .enumerate()
        .filter(|(_, v)| off(**v) > 0.0)
        .min_by(|a, b| off(*a.1).total_cmp(&off(*b.1)))?;
    let exact = quarter_text((tilt / FRAC_PI_2).round());
    let item = describe(Item::Transform(Mount::Base, Part::Rpy, i));
    Some((
        i,
        format!(
            "{item} = {} turns gravity [{}] in frame 0 (where the dynamics use it) into one \
             whose {} component is {:.3e} m/s^2, smaller than {} m/s^2 but not zero",
            show(*tilt),
            written
                .iter()
                .map(|v| show(*v))
                .collect::<Vec<_>>()
                .join(", "),
            ["x", "y", "z"][axis],
            turned[axis],
            show(MIN_GRAVITY)
        ),
        format!(
            "the regrouping cannot tell a component this small from zero, as for one written \
             in `gravity`: write \"{exact}\" for this angle ({:.1e} rad from it), or a tilt \
             of at least 1e-4 rad",
            off(*tilt)
        ),
    ))
}

/// How far (rad) a numeric angle without symbols lies from the multiple k of pi/2 it
/// nearly is (k, and that multiple as text), when that is less than [`ANGLE_RESOLUTION`]
/// but not 0: `1.5707963` typed for `"pi/2"`; k = 0 only `with_zero`.
pub(super) fn near_right_angle(g: &Geometry, with_zero: bool) -> Option<(f64, i64, String)> {
    if !g.symbols().is_empty() || g.quarter_turns().is_some() {
        return None;
    }
    let mut arena = Arena::new();
    let id = g.to_expr(&mut arena);
    let values = arena.values(&[]);
    let v = arena.eval(&[id], &values).ok()?.first().copied()?;
    let k = (v / FRAC_PI_2).round();
    let off = (v - k * FRAC_PI_2).abs();
    ((with_zero || k != 0.0) && off > 0.0 && off < ANGLE_RESOLUTION)
        .then(|| (off, k as i64, quarter_text(k)))
}

/// What taking a measured twist near a right angle means, for the warnings of URDFs and
/// calibrated descriptions: `parallel` when the right angle is 0 or pi.
pub(super) fn measured_twist_consequence(parallel: bool) -> String {
    let axes = if parallel {
        "parallel"
    } else {
        "perpendicular"
    };
    format!(
        "where {axes} axes let the regrouping fold more parameters, the base parameters then \
         hold combinations that only this angle separates, which data determine poorly (large \
         standard deviations)"
    )
}

/// What a warning about its first place adds for the `n` others: `" (and 1 more joint)"`,
/// `" (and 3 more joints)"` (`one` and `many` each with a leading space, or empty), nothing
/// for none.
pub(super) fn and_more(n: usize, one: &str, many: &str) -> String {
    match n {
        0 => String::new(),
        1 => format!(" (and 1 more{one})"),
        n => format!(" (and {n} more{many})"),
    }
}

/// How many items a list in a message names; the rest are counted.
pub(super) const LISTED: usize = 8;

/// `items` joined by commas: the first [`LISTED`], then a count of the others (a URDF of
/// 3000 joints without `<limit>` named them all in one warning).
pub(super) fn listed(items: impl IntoIterator<Item = String>) -> String {
    let mut items = items.into_iter();
    let shown: Vec<String> = items.by_ref().take(LISTED).collect();
    shown.join(", ") + &and_more(items.count(), "", "")
}

/// `k pi/2` as text.
pub(super) fn quarter_text(k: f64) -> String {
    match k as i64 {
        0 => "0".to_owned(),
        k if k % 2 == 0 => match k / 2 {
            1 => "pi".to_owned(),
            -1 => "-pi".to_owned(),
            h => format!("{h}*pi"),
        },
        1 => "pi/2".to_owned(),
        -1 => "-pi/2".to_owned(),
        k => format!("{k}*pi/2"),
    }
}

/// The value as written, quoted when it is text.
fn quoted(g: &Geometry) -> String {
    match g {
        Geometry::Number(n) => show(n.value()),
        Geometry::Expression(_) => format!("\"{}\"", super::geometry::excerpt(g.as_str())),
    }
}

/// Problems of one joint's limits.
fn limit_problems(limits: &Limits) -> Vec<(Limit, String, String)> {
    let mut out = Vec::new();
    if let Some([lo, hi]) = limits.position {
        let shown = format!("[{}, {}]", show(lo), show(hi));
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            out.push((
                Limit::Position,
                format!("position limits {shown} are not an increasing pair of finite numbers"),
                "write `position = [lower, upper]` with lower < upper".to_owned(),
            ));
        } else if lo.abs().max(hi.abs()) > MAX_POSITION {
            out.push((
                Limit::Position,
                format!("position limits {shown} go beyond ±{}", show(MAX_POSITION)),
                "positions are in radians (revolute) or metres (prismatic)".to_owned(),
            ));
        }
    }
    for (limit, value, max, unit) in [
        (
            Limit::Velocity,
            limits.velocity,
            MAX_VELOCITY,
            "rad/s or m/s",
        ),
        (
            Limit::Acceleration,
            limits.acceleration,
            MAX_ACCELERATION,
            "rad/s^2 or m/s^2",
        ),
        (Limit::Torque, limits.torque, MAX_TORQUE, "N m or N"),
    ] {
        let Some(x) = value else { continue };
        if !(x.is_finite() && x > 0.0 && x <= max) {
            out.push((
                limit,
                format!(
                    "{} limit {} is not a positive number up to {}",
                    limit.key(),
                    show(x),
                    show(max)
                ),
                format!(
                    "limits are maximum absolute values in {unit}, e.g. `{} = 3.14`",
                    limit.key()
                ),
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{MAX_NAME_LEN, and_more, name_problem, quarter_text, show};

    /// The count of a warning's other places, singular and plural, nothing for none.
    #[test]
    fn the_other_places_of_a_warning() {
        assert_eq!(and_more(0, " joint", " joints"), "");
        assert_eq!(and_more(1, " joint", " joints"), " (and 1 more joint)");
        assert_eq!(and_more(3, " joint", " joints"), " (and 3 more joints)");
        assert_eq!(and_more(2, "", ""), " (and 2 more)");
    }

    #[test]
    fn names_that_cannot_name_a_type() {
        for bad in [
            "self", "Self", "self_", "fn", "crate", "super", "type", "my arm", "", "1arm", "_x",
            "arm-2", "é",
        ] {
            assert!(name_problem(bad).is_some(), "{bad}");
        }
        for good in ["ur5e", "my_arm", "Arm2", "selfie", "crate_arm"] {
            assert!(name_problem(good).is_none(), "{good}");
        }
        assert!(name_problem(&"a".repeat(MAX_NAME_LEN)).is_none());
        let (message, _) = name_problem(&"a".repeat(MAX_NAME_LEN + 1)).unwrap();
        assert!(
            message.ends_with("has 257 characters, more than 256"),
            "{message}"
        );
    }

    #[test]
    fn helpers() {
        assert_eq!(quarter_text(1.0), "pi/2");
        assert_eq!(quarter_text(-2.0), "-pi");
        assert_eq!(quarter_text(3.0), "3*pi/2");
        assert_eq!(show(1e200), "1e200");
        assert_eq!(show(0.5), "0.5");
    }
}
