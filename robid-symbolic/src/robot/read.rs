//! From the TOML tree (with the span of every key and value) to the parts of
//! a robot: unknown keys, wrong types, missing keys, wrong array lengths and
//! unreadable values are collected, each with its span, and reading goes on
//! with a placeholder so that the checks can report the rest.

use super::check::{Dh, Item, Limit, Mount, Part, Parts, standard_gamma_b};
use super::file::Place;
use super::{
    Convention, DescriptionError, Drive, DriveTerm, Geometry, Joint, JointKind, Limits, Transform,
};
use robid_core::names::{self, short};
use std::collections::HashMap;
use std::ops::Range;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

type Value<'i> = Spanned<DeValue<'i>>;

/// Where each item was written.
#[derive(Default)]
pub(super) struct Spans {
    name: Option<Range<usize>>,
    joints: Option<Range<usize>>,
    joint_tables: Vec<Range<usize>>,
    values: HashMap<(usize, Dh), Range<usize>>,
    limits: HashMap<(usize, Limit), Range<usize>>,
    gravity: Option<Range<usize>>,
    gravity_values: HashMap<usize, Range<usize>>,
    symbols: HashMap<String, Range<usize>>,
    /// `[base]` and `[tool]`: the tables, their `xyz` and `rpy` arrays and each value.
    mounts: HashMap<Mount, Range<usize>>,
    parts: HashMap<(Mount, Part), Range<usize>>,
    components: HashMap<(Mount, Part, usize), Range<usize>>,
    /// The top-level `drive` key, and each joint's.
    drive: Option<Range<usize>>,
    joint_drives: Vec<(usize, Range<usize>)>,
}

impl Spans {
    /// The span of an item: where it was written, or where it would be.
    pub(super) fn of(&self, item: Item<'_>) -> Range<usize> {
        let joint = |j: usize| self.joint_tables.get(j).cloned();
        let found = match item {
            Item::Name => self.name.clone(),
            Item::Joints => self.joints.clone(),
            Item::Joint(j) => joint(j),
            Item::Value(j, dh) => self.values.get(&(j, dh)).cloned().or_else(|| joint(j)),
            Item::Limit(j, l) => self.limits.get(&(j, l)).cloned().or_else(|| joint(j)),
            Item::Gravity(i) => self
                .gravity_values
                .get(&i)
                .cloned()
                .or_else(|| self.gravity.clone()),
            Item::Transform(m, p, i) => self
                .components
                .get(&(m, p, i))
                .or_else(|| self.parts.get(&(m, p)))
                .or_else(|| self.mounts.get(&m))
                .cloned(),
            Item::Symbol(s) => self.symbols.get(s).cloned(),
        };
        found.unwrap_or(0..0)
    }

    /// The number of `[[joints]]` tables read.
    pub(super) fn joint_count(&self) -> usize {
        self.joint_tables.len()
    }

    /// A `drive` key that TOML gave to the last joint although it reads as the robot's:
    /// only the last of several joints has one and the top level has none. TOML attaches
    /// every key after a `[[joints]]` header to that table, so `drive = [...]` written at
    /// the end of a file silently becomes the last joint's.
    pub(super) fn stray_drive(&self) -> Option<Range<usize>> {
        let last = self.joint_tables.len().checked_sub(1)?;
        match self.joint_drives.as_slice() {
            [(j, span)] if *j == last && last > 0 && self.drive.is_none() => Some(span.clone()),
            _ => None,
        }
    }
}

/// Reads the TOML tree, collecting errors.
pub(super) struct Reader<'a> {
    place: &'a Place<'a>,
    errors: Vec<DescriptionError>,
    spans: Spans,
    /// The words of geometric values that could not be read (their symbols
    /// are unknown).
    unread_words: Vec<String>,
    /// The table's convention (`gamma` and `b` belong to the modified one).
    convention: Convention,
}

const ROBOT_KEYS: [&str; 9] = [
    "name",
    "convention",
    "gravity",
    "drive",
    "symbols",
    "joints",
    "base",
    "tool",
    "calibrated",
];
const JOINT_KEYS: [&str; 9] = [
    "type", "alpha", "a", "d", "theta", "drive", "limits", "gamma", "b",
];
const LIMIT_KEYS: [&str; 4] = ["position", "velocity", "acceleration", "torque"];
const TRANSFORM_KEYS: [&str; 2] = ["xyz", "rpy"];

impl<'a> Reader<'a> {
    pub(super) fn new(place: &'a Place<'a>) -> Reader<'a> {
        Reader {
            place,
            errors: Vec::new(),
            spans: Spans::default(),
            unread_words: Vec::new(),
            convention: Convention::Modified,
        }
    }

    /// The errors found and the spans kept.
    pub(super) fn finish(self) -> (Vec<DescriptionError>, Spans) {
        (self.errors, self.spans)
    }

    fn error(&mut self, span: Range<usize>, message: String, help: impl Into<String>) {
        self.errors.push(self.place.invalid(span, message, help));
    }

    /// The robot's parts, with placeholders where something could not be read.
    pub(super) fn robot(&mut self, table: &DeTable<'_>) -> Parts {
        let values = self.keys(table, &ROBOT_KEYS, "at the top of a description");
        // A name that cannot be read is reported here; a placeholder that
        // passes the checks keeps them from reporting it again.
        let name = match values[0] {
            Some(v) => {
                self.spans.name = Some(v.span());
                self.string(v, "the robot name")
            }
            None => {
                self.error(
                    0..0,
                    "the description has no `name`".to_owned(),
                    "add `name = \"my_arm\"` (it names the generated type)",
                );
                None
            }
        };
        let convention = match values[1] {
            Some(v) => self.convention(v),
            None => {
                self.error(
                    0..0,
                    "the description has no `convention`".to_owned(),
                    "add `convention = \"modified\"` (Craig/Khalil) or `convention = \"standard\"` (classic)",
                );
                Convention::Modified
            }
        };
        self.convention = convention;
        let gravity = values[2].map(|g| self.gravity(g));
        self.spans.drive = values[3].map(|v| v.span());
        let default_drive = values[3].map_or(Drive::NONE, |d| self.drive(d));
        let symbols = values[4].map(|s| self.symbols(s)).unwrap_or_default();
        let joints = match values[5] {
            Some(v) => {
                self.spans.joints = Some(v.span());
                self.joints(v, default_drive)
            }
            None => Vec::new(),
        };
        let base = values[6].map(|v| self.transform(Mount::Base, v));
        let tool = values[7].map(|v| self.transform(Mount::Tool, v));
        let calibrated = values[8].is_some_and(|v| self.boolean(v, "`calibrated`"));
        Parts {
            name: name.unwrap_or_else(|| "robot".to_owned()),
            convention,
            gravity: gravity.unwrap_or_else(super::default_gravity),
            joints,
            base,
            tool,
            values: symbols,
            unread_words: std::mem::take(&mut self.unread_words),
            measured: calibrated,
            uses: Vec::new(),
            joint_places: Vec::new(),
        }
    }

    /// The values of `known` keys in `table`, in that order; unknown keys are errors.
    fn keys<'t, 'i>(
        &mut self,
        table: &'t DeTable<'i>,
        known: &[&str],
        context: &str,
    ) -> Vec<Option<&'t Value<'i>>> {
        let mut out = vec![None; known.len()];
        for (key, value) in table.iter() {
            match known.iter().position(|k| *k == key.get_ref().as_ref()) {
                Some(i) => out[i] = Some(value),
                None => {
                    let key_name = key.get_ref().as_ref();
                    let list = known
                        .iter()
                        .map(|k| format!("`{k}`"))
                        .collect::<Vec<_>>()
                        .join(", ");
                    let nearest = names::nearest(key_name, known.iter().copied())
                        .into_iter()
                        .next()
                        .filter(|k| names::distance_ignoring_case(k, key_name) <= 2);
                    let help = match nearest {
                        Some(k) => format!("did you mean `{k}`? The keys {context} are {list}"),
                        None => format!("the keys {context} are {list}"),
                    };
                    self.error(
                        key.span(),
                        format!("unknown key `{}`", short(key_name)),
                        help,
                    );
                }
            }
        }
        out
    }

    fn type_error(&mut self, v: &Value<'_>, what: &str, expected: &str) {
        self.error(
            v.span(),
            format!(
                "{what} is {} {}",
                article(v.get_ref().type_str()),
                v.get_ref().type_str()
            ),
            format!("write {expected}"),
        );
    }

    fn string(&mut self, v: &Value<'_>, what: &str) -> Option<String> {
        match v.get_ref() {
            DeValue::String(s) => Some(s.to_string()),
            _ => {
                self.type_error(v, what, "a string in double quotes");
                None
            }
        }
    }

    /// `true` or `false`; anything else is an error (and `false`).
    fn boolean(&mut self, v: &Value<'_>, what: &str) -> bool {
        match v.get_ref() {
            DeValue::Boolean(b) => *b,
            _ => {
                self.type_error(v, what, "`true` or `false`");
                false
            }
        }
    }

    /// A number (integer or float), possibly NaN or infinite.
    fn number(&mut self, v: &Value<'_>, what: &str) -> Option<f64> {
        match number(v.get_ref()) {
            Some(x) => Some(x),
            None if matches!(v.get_ref(), DeValue::Integer(_)) => {
                self.error(
                    v.span(),
                    format!("{what} is an integer out of range"),
                    "write it as a float, e.g. `1.5e3`",
                );
                None
            }
            None => {
                self.type_error(v, what, "a number");
                None
            }
        }
    }

    fn array<'t, 'i>(
        &mut self,
        v: &'t Value<'i>,
        what: &str,
        expected: &str,
    ) -> Option<&'t [Value<'i>]> {
        match v.get_ref() {
            DeValue::Array(items) => Some(&items[..]),
            _ => {
                self.type_error(v, what, expected);
                None
            }
        }
    }

    fn convention(&mut self, v: &Value<'_>) -> Convention {
        match self.string(v, "`convention`").as_deref() {
            Some("modified") | None => Convention::Modified,
            Some("standard") => Convention::Standard,
            Some(other) => {
                self.error(
                    v.span(),
                    format!("unknown DH convention `{}`", short(other)),
                    "write `convention = \"modified\"` (Craig/Khalil) or `convention = \"standard\"` (classic)",
                );
                Convention::Modified
            }
        }
    }

    fn gravity(&mut self, v: &Value<'_>) -> [Geometry; 3] {
        self.spans.gravity = Some(v.span());
        let mut g = super::default_gravity();
        let Some(items) = self.array(
            v,
            "`gravity`",
            "three values, e.g. `gravity = [0, 0, -9.81]`",
        ) else {
            return g;
        };
        if items.len() != 3 {
            self.error(
                v.span(),
                format!("gravity has {}", count_values(items.len())),
                "give three values in the base frame, e.g. `gravity = [0, 0, -9.81]`",
            );
            return g;
        }
        for (i, item) in items.iter().enumerate() {
            self.spans.gravity_values.insert(i, item.span());
            let what = format!("gravity {}", ["x", "y", "z"][i]);
            if let Some(value) = self.geometry(item, &what) {
                g[i] = value;
            }
        }
        g
    }

    fn drive(&mut self, v: &Value<'_>) -> Drive {
        let mut d = Drive::NONE;
        let expected = "drive terms such as `drive = [\"Ia\", \"Fv\"]`";
        for term in self.array(v, "`drive`", expected).unwrap_or_default() {
            let Some(name) = self.string(term, "a drive term") else {
                continue;
            };
            match name.parse::<DriveTerm>() {
                Ok(t) if d.has(t) => self.error(
                    term.span(),
                    format!("the drive term `{}` is named twice", short(&name)),
                    "name each drive term once",
                ),
                Ok(t) => d.add(t),
                Err(e) => self.error(
                    term.span(),
                    format!("unknown drive term `{}`", short(&name)),
                    e.expected,
                ),
            }
        }
        d
    }

    fn symbols(&mut self, v: &Value<'_>) -> Vec<(String, f64)> {
        let DeValue::Table(table) = v.get_ref() else {
            self.type_error(
                v,
                "`symbols`",
                "a table `[symbols]` of `NAME = number` lines",
            );
            return Vec::new();
        };
        let mut out = Vec::new();
        for (key, value) in table.iter() {
            let name = key.get_ref().to_string();
            self.spans.symbols.insert(name.clone(), key.span());
            if let Some(x) = self.number(value, &format!("symbol `{}`", short(&name))) {
                out.push((name, x));
            }
        }
        out
    }

    fn joints(&mut self, v: &Value<'_>, default_drive: Drive) -> Vec<Joint> {
        let expected = "one `[[joints]]` table per DH row";
        let Some(items) = self.array(v, "`joints`", expected) else {
            return Vec::new();
        };
        let mut joints = Vec::with_capacity(items.len());
        for (j, item) in items.iter().enumerate() {
            self.spans.joint_tables.push(item.span());
            let DeValue::Table(table) = item.get_ref() else {
                self.type_error(item, &format!("joint {}", j + 1), expected);
                continue;
            };
            joints.push(self.joint(j, table, default_drive));
        }
        joints
    }

    fn joint(&mut self, j: usize, table: &DeTable<'_>, default_drive: Drive) -> Joint {
        let values = self.keys(table, &JOINT_KEYS, "of a joint");
        let kind = match values[0] {
            None => JointKind::Revolute,
            Some(v) => match self.string(v, "`type`").as_deref() {
                Some("revolute") | None => JointKind::Revolute,
                Some("prismatic") => JointKind::Prismatic,
                Some(other) => {
                    self.error(
                        v.span(),
                        format!("unknown joint type `{}`", short(other)),
                        "write `type = \"revolute\"` or `type = \"prismatic\"`",
                    );
                    JointKind::Revolute
                }
            },
        };
        let mut dh = [(); 6].map(|_| Geometry::zero());
        for (k, key) in Dh::ALL.into_iter().enumerate() {
            let Some(v) = values[joint_key(key)] else {
                continue;
            };
            self.spans.values.insert((j, key), v.span());
            if matches!(key, Dh::Gamma | Dh::B) && self.convention == Convention::Standard {
                // reported here, where it was written; the robot gets 0 so the checks
                // do not report it again
                let (message, help) = standard_gamma_b(j, key);
                self.error(v.span(), message, help);
                continue;
            }
            let what = format!("joint {} `{}`", j + 1, key.key());
            if let Some(g) = self.geometry(v, &what) {
                dh[k] = g;
            }
        }
        if let Some(d) = values[5] {
            self.spans.joint_drives.push((j, d.span()));
        }
        let drive = values[5].map_or(default_drive, |d| self.drive(d));
        let limits = values[6].map(|l| self.limits(j, l)).unwrap_or_default();
        let [alpha, a, d, theta, gamma, b] = dh;
        Joint {
            kind,
            gamma,
            b,
            alpha,
            a,
            d,
            theta,
            limits,
            drive,
        }
    }

    /// A `[base]` or `[tool]` table: `xyz` and `rpy`, each optional (zero when left out).
    fn transform(&mut self, mount: Mount, v: &Value<'_>) -> Transform {
        let mut t = Transform::identity();
        self.spans.mounts.insert(mount, v.span());
        let name = mount.key();
        let DeValue::Table(table) = v.get_ref() else {
            self.type_error(
                v,
                &format!("`{name}`"),
                &format!(
                    "a table `[{name}]` with `xyz = [x, y, z]` and `rpy = [roll, pitch, yaw]`"
                ),
            );
            return t;
        };
        let context = format!("of `[{name}]`");
        let values = self.keys(table, &TRANSFORM_KEYS, &context);
        for (part, value) in [(Part::Xyz, values[0]), (Part::Rpy, values[1])] {
            let Some(value) = value else { continue };
            self.spans.parts.insert((mount, part), value.span());
            let example = match part {
                Part::Xyz => "`xyz = [0, 0, 0.1]` (m)",
                Part::Rpy => "`rpy = [\"pi/2\", 0, 0]` (rad, R = Rz(yaw) Ry(pitch) Rx(roll))",
            };
            let what = format!("[{name}] `{}`", part.key());
            let Some(items) = self.array(value, &what, &format!("three values, e.g. {example}"))
            else {
                continue;
            };
            if items.len() != 3 {
                self.error(
                    value.span(),
                    format!("{what} has {}", count_values(items.len())),
                    format!("give three values, e.g. {example}"),
                );
                continue;
            }
            for (i, item) in items.iter().enumerate() {
                self.spans.components.insert((mount, part, i), item.span());
                let component = match part {
                    Part::Xyz => ["x", "y", "z"][i],
                    Part::Rpy => ["roll", "pitch", "yaw"][i],
                };
                if let Some(g) = self.geometry(item, &format!("[{name}] {component}")) {
                    match part {
                        Part::Xyz => t.xyz[i] = g,
                        Part::Rpy => t.rpy[i] = g,
                    }
                }
            }
        }
        t
    }

    fn limits(&mut self, j: usize, v: &Value<'_>) -> Limits {
        let mut limits = Limits::default();
        let DeValue::Table(table) = v.get_ref() else {
            self.type_error(
                v,
                "`limits`",
                "a table such as `limits = { position = [-3.14, 3.14], velocity = 2 }`",
            );
            return limits;
        };
        let values = self.keys(table, &LIMIT_KEYS, "of `limits`");
        for (k, key) in Limit::ALL.into_iter().enumerate() {
            let Some(value) = values[k] else { continue };
            self.spans.limits.insert((j, key), value.span());
            let what = format!("joint {} {} limit", j + 1, key.key());
            match key {
                Limit::Position => limits.position = self.pair(value, &what),
                Limit::Velocity => limits.velocity = self.number(value, &what),
                Limit::Acceleration => limits.acceleration = self.number(value, &what),
                Limit::Torque => limits.torque = self.number(value, &what),
            }
        }
        limits
    }

    /// `[lower, upper]`: exactly two numbers.
    fn pair(&mut self, v: &Value<'_>, what: &str) -> Option<[f64; 2]> {
        let expected = "`position = [lower, upper]`";
        let items = self.array(v, what, expected)?;
        if items.len() != 2 {
            self.error(
                v.span(),
                format!("{what} has {}", count_values(items.len())),
                format!("write {expected}, two numbers"),
            );
            return None;
        }
        let lower = self.number(&items[0], what);
        let upper = self.number(&items[1], what);
        Some([lower?, upper?])
    }

    /// A geometric value: a finite number or an expression in text.
    fn geometry(&mut self, v: &Value<'_>, what: &str) -> Option<Geometry> {
        let g = self.read_geometry(v, what);
        if g.is_none()
            && let DeValue::String(text) = v.get_ref()
        {
            let words = text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'));
            self.unread_words
                .extend(words.filter(|w| !w.is_empty()).map(str::to_owned));
        }
        g
    }

    fn read_geometry(&mut self, v: &Value<'_>, what: &str) -> Option<Geometry> {
        if let DeValue::String(text) = v.get_ref() {
            return match Geometry::text(text) {
                Ok(g) => Some(g),
                Err(e) => {
                    let span = inside(self.place.text, v.span(), text, e.position());
                    self.error(span, format!("{what}: {}", e.message()), e.help());
                    None
                }
            };
        }
        let x = self.number(v, what)?;
        match Geometry::number(x) {
            Ok(g) => Some(g),
            Err(_) => {
                self.error(
                    v.span(),
                    format!("{what} is {x}, not a finite number"),
                    "geometric values (DH values, gravity, `[base]`, `[tool]`) are finite numbers, exact angles such as \"pi/2\" or symbols such as \"L3\"",
                );
                None
            }
        }
    }
}

/// The index of a joint value's key in [`JOINT_KEYS`].
fn joint_key(key: Dh) -> usize {
    match key {
        Dh::Alpha => 1,
        Dh::A => 2,
        Dh::D => 3,
        Dh::Theta => 4,
        Dh::Gamma => 7,
        Dh::B => 8,
    }
}

/// The number of a TOML integer or float.
fn number(v: &DeValue<'_>) -> Option<f64> {
    match v {
        DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
            Ok(n) => Some(n as f64),
            // Too large for 64 bits: a decimal integer is still a number.
            Err(_) if i.radix() == 10 => i.as_str().parse::<f64>().ok(),
            Err(_) => None,
        },
        DeValue::Float(f) => f.as_str().parse::<f64>().ok(),
        _ => None,
    }
}

/// The span of byte `position` of a string value, when the string is
/// written without escapes (else the whole value).
fn inside(text: &str, span: Range<usize>, value: &str, position: Option<usize>) -> Range<usize> {
    let raw = text.get(span.clone()).unwrap_or("");
    let plain = raw.len() == value.len() + 2
        && (raw.starts_with('"') || raw.starts_with('\''))
        && raw.get(1..raw.len() - 1) == Some(value);
    match position {
        Some(p) if plain && p <= value.len() => {
            // The value was trimmed before reading: count from its first non-space.
            let start = span.start + 1 + (value.len() - value.trim_start().len()) + p;
            start..span.end.max(start)
        }
        _ => span,
    }
}

fn article(word: &str) -> &'static str {
    if word.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    }
}

/// `n values`, or `1 value`.
fn count_values(n: usize) -> String {
    format!("{n} value{}", if n == 1 { "" } else { "s" })
}
