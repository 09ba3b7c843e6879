//! Reading a robot from TOML, reporting every mistake at once, each with its
//! file, line and column.
//!
//! ```toml
//! name = "ur5e"                  # names the generated type (Ur5e): an identifier, not a Rust keyword
//! convention = "modified"        # or "standard"
//! gravity = [0, 0, -9.81]        # optional, world frame (frame 0 without [base]), m/s^2
//! drive = ["Ia", "Fv", "Fc"]     # optional default drive terms of every joint
//! calibrated = true              # optional: the table was measured; angles near right angles as written
//! [symbols]                      # optional values of geometric symbols
//! L3 = 0.425
//! [base]                         # optional: frame 0 in the world frame (gravity is in the world)
//! xyz = [0, 0, 0]                #   metres
//! rpy = ["pi/2", 0, 0]           #   radians, R = Rz(yaw) Ry(pitch) Rx(roll), as in URDF
//! [tool]                         # optional: the end-effector frame in frame n, same keys
//! xyz = [0, 0, 0.1]
//! [[joints]]
//! type = "revolute"              # or "prismatic"; default revolute
//! alpha = "pi/2"                 # a number, an exact angle, or a symbol expression (rad)
//! a = "-L3"                      # lengths in metres
//! d = 0.1625
//! theta = 0                      # offset of the joint angle
//! gamma = 0                      # optional, modified tables only: Khalil-Kleinfinger rotation
//! b = 0                          #   about and translation along z_(j-1), before the row
//! drive = ["Ia"]                 # optional, overrides the default
//! limits = { position = [-6.28, 6.28], velocity = 3.14, acceleration = 10, torque = 150 }
//! ```
//!
//! Every value is checked when the file is read, against the limits listed in
//! [`bounds`](super::bounds): lengths 0 or 1e-6 to 1e3 m in magnitude, angles
//! at most one turn and exactly `k pi/2` or at least 1e-5 rad from it,
//! gravity components 0 or 1e-3 to 1e3 m/s^2, finite `[symbols]` values
//! (each for a symbol some value uses), finite limits (position within
//! ±1e3, velocity up to 1e4, acceleration up to 1e6, torque up to 1e7),
//! 1 to 32 joints, at most 16 symbols, a file of at most 1 MiB, and
//! expressions within the reader's limits (4096 bytes, 64 levels of
//! parentheses, calls and signs, exponents within ±64).
//!
//! A TOML syntax error stops the reading (it is reported alone; a key or table
//! given twice is named at its second place, e.g. `` `d` is given a second time in
//! this table ``); every other
//! mistake (unknown keys, wrong types, missing keys, values out of range,
//! unused symbols) is reported together with the others.

use super::bounds::{ANGLE_RESOLUTION, MAX_ARM_LENGTH, MAX_DESCRIPTION_LEN, MAX_TURNING};
use super::check::{
    Dh, Item, Limit, Locate, and_more, listed, measured_twist_consequence, near_right_angle,
    quarter_text,
};
use super::read::{Reader, Spans};
use super::{DescriptionError, JointKind, Robot};
use std::f64::consts::FRAC_PI_2;
use std::io::Read;
use std::ops::Range;
use toml::de::DeTable;

/// Where a problem is: file name, the text (for line/column).
pub(super) struct Place<'a> {
    pub(super) file: &'a str,
    pub(super) text: &'a str,
}

impl Place<'_> {
    /// The 1-based line and column of byte `offset`.
    pub(super) fn line_column(&self, offset: usize) -> (usize, usize) {
        robid_core::text::line_column(self.text, offset)
    }

    /// A warning about the text at `offset`: `file:line:column: what`.
    pub(super) fn warning(&self, offset: usize, what: &str) -> String {
        let (line, column) = self.line_column(offset);
        format!("{}:{line}:{column}: {what}", self.file)
    }

    /// An error about the text at `span`.
    pub(super) fn invalid(
        &self,
        span: Range<usize>,
        message: String,
        help: impl Into<String>,
    ) -> DescriptionError {
        let (line, column) = self.line_column(span.start);
        DescriptionError::Invalid {
            file: self.file.to_owned(),
            line,
            column,
            message,
            help: help.into(),
            span: Some((span.start, span.end)),
        }
    }
}

/// What is valid but probably not meant, each with its place and what to do.
fn warnings(place: &Place<'_>, spans: &Spans, robot: &Robot) -> Vec<String> {
    let mut out = Vec::new();
    // A revolute joint's theta is taken as written (an offset of its variable, see
    // check.rs `Role::Offset`); one typed for a right angle is told once (in a
    // calibrated table such offsets are what was measured).
    let near: Vec<(usize, f64, String)> = robot
        .joints()
        .iter()
        .enumerate()
        .filter(|(_, joint)| joint.kind == JointKind::Revolute && !robot.measured)
        .filter_map(|(j, joint)| {
            near_right_angle(&joint.theta, false).map(|(off, _, exact)| (j, off, exact))
        })
        .collect();
    if let Some((j, off, exact)) = near.first() {
        let (line, column) = place.line_column(spans.of(Item::Value(*j, Dh::Theta)).start);
        let more = and_more(near.len() - 1, " joint", " joints");
        out.push(format!(
            "{}:{line}:{column}: joint {} `theta` is {off:.1e} rad from {exact}{more}: taken \
             as written, an offset of the joint's zero; write \"{exact}\" if {exact} is \
             meant (its sine and cosine then fold into the model)",
            place.file,
            j + 1
        ));
    }
    // A calibrated table's twists near a right angle are taken as measured
    // (check.rs `Measured::Angle`); what that does to the base parameters is told once.
    let twists: Vec<(usize, Dh, f64, i64, String)> = if robot.measured {
        robot
            .joints()
            .iter()
            .enumerate()
            .flat_map(|(j, joint)| {
                let theta =
                    (joint.kind == JointKind::Prismatic).then_some((Dh::Theta, &joint.theta));
                [(Dh::Alpha, &joint.alpha), (Dh::Gamma, &joint.gamma)]
                    .into_iter()
                    .chain(theta)
                    .filter_map(move |(dh, g)| {
                        near_right_angle(g, true).map(|(off, k, exact)| (j, dh, off, k, exact))
                    })
            })
            .collect()
    } else {
        Vec::new()
    };
    if let Some((j, dh, off, k, exact)) = twists.first() {
        let (line, column) = place.line_column(spans.of(Item::Value(*j, *dh)).start);
        let more = and_more(twists.len() - 1, " angle", " angles");
        let parallel = k % 2 == 0;
        out.push(format!(
            "{}:{line}:{column}: joint {} `{}` is {off:.1e} rad from {exact}{more}: taken as \
             measured (`calibrated = true`); {}; to identify the nominal set, write \"{exact}\"",
            place.file,
            j + 1,
            dh.key(),
            measured_twist_consequence(parallel),
        ));
    }
    // (a length in millimetres is written as one, or as a `[symbols]` value); every such
    // length is named, the first at its place (only the first was, and the next one
    // showed only once it was repaired; one through a symbol was not named at all)
    let rows = robot.numeric_rows().ok();
    let long: Vec<(usize, Dh, f64, &str)> = robot
        .joints()
        .iter()
        .enumerate()
        .flat_map(|(j, joint)| {
            let rows = rows.as_ref();
            [
                (Dh::A, &joint.a, 1),
                (Dh::D, &joint.d, 2),
                (Dh::B, &joint.b, 5),
            ]
            .into_iter()
            .filter_map(move |(dh, g, at)| {
                let value = match g.symbols() {
                    [] => g.as_str().trim().parse::<f64>().ok()?,
                    _ => rows?.get(j)?[at],
                };
                Some((dh, value, g.symbols().first().map(|_| g.as_str())))
            })
            .filter(|(_, v, _)| v.abs() > MAX_ARM_LENGTH)
            .map(move |(dh, v, text)| (j, dh, v, text.unwrap_or("")))
        })
        .collect();
    // `a` or, through symbols, `a = "L3"`
    let named = |dh: Dh, text: &str| match text {
        "" => format!("`{}`", dh.key()),
        text => format!("`{} = \"{text}\"`", dh.key()),
    };
    if let Some(&(j, dh, value, text)) = long.first() {
        let (line, column) = place.line_column(spans.of(Item::Value(j, dh)).start);
        let others = match &long[1..] {
            [] => String::new(),
            rest => format!(
                " (so are {})",
                listed(rest.iter().map(|(j, dh, v, text)| format!(
                    "joint {} {} {v} m",
                    j + 1,
                    named(*dh, text)
                )))
            ),
        };
        // a value of `[symbols]` is mended there, not in the joint's expression
        let there = if long.iter().any(|(_, _, _, text)| !text.is_empty()) {
            " (in `[symbols]` for a length given through a symbol)"
        } else {
            ""
        };
        out.push(format!(
            "{}:{line}:{column}: joint {} {} is {value} m, longer than an arm's \
             {MAX_ARM_LENGTH} m{others}: {LENGTH_FIX}{there}",
            place.file,
            j + 1,
            named(dh, text)
        ));
    }
    if let Some(w) = special_symbol_values(place, spans, robot) {
        out.push(w);
    }
    if let Some((j, [lower, upper])) = turning_too_far(robot) {
        let (line, column) = place.line_column(spans.of(Item::Limit(j, Limit::Position)).start);
        out.push(format!(
            "{}:{line}:{column}: joint {} `position` limits [{lower}, {upper}] reach beyond \
             {MAX_TURNING:.2} rad (a turn and a quarter): {TURNING_FIX}",
            place.file,
            j + 1,
        ));
    }
    if let Some(span) = spans.stray_drive() {
        let (line, column) = place.line_column(span.start);
        let joint = spans.joint_count();
        out.push(format!(
            "{}:{line}:{column}: only joint {joint}, the last, has a `drive` key: TOML gives \
             every key after a `[[joints]]` header to that joint; to give every joint these \
             drive terms move the line above the first `[[joints]]` (or pass --drive), or \
             write `drive = []` in the other joints to keep it for joint {joint} alone",
            place.file
        ));
    }
    out
}

/// The warning for values written with symbols that the `[symbols]` values put where the
/// structure changes: a length or a gravity component of 0, a twist at a multiple of pi/2.
/// The regrouping samples every symbol away from such values, so the base parameters hold
/// there but may not be minimal: some have no effect on this robot's torques, which
/// identification then calls not excited and `excite` cannot excite, whatever the
/// trajectory (`a = "L2"` with `L2 = 0` kept MX2 and MY2 of a planar arm). A revolute
/// joint's `theta` and a prismatic joint's `d` only shift its variable and are not judged.
fn special_symbol_values(place: &Place<'_>, spans: &Spans, robot: &Robot) -> Option<String> {
    let rows = robot.numeric_rows().ok()?;
    let quarter = |v: f64| {
        let k = (v / FRAC_PI_2).round();
        ((v - k * FRAC_PI_2).abs() < ANGLE_RESOLUTION).then(|| match quarter_text(k) {
            zero if k == 0.0 => zero,
            text => format!("\"{text}\""),
        })
    };
    let mut found: Vec<(Item<'static>, String, String)> = Vec::new();
    for (j, joint) in robot.joints().iter().enumerate() {
        let prismatic = joint.kind == JointKind::Prismatic;
        for (dh, at) in [
            (Dh::Alpha, 0),
            (Dh::A, 1),
            (Dh::D, 2),
            (Dh::Theta, 3),
            (Dh::Gamma, 4),
            (Dh::B, 5),
        ] {
            let g = dh.of(joint);
            let v = rows[j][at];
            let special = match dh {
                _ if g.symbols().is_empty() => None,
                Dh::Theta if !prismatic => None,
                Dh::D if prismatic => None,
                Dh::Alpha | Dh::Gamma | Dh::Theta => quarter(v),
                Dh::A | Dh::D | Dh::B => (v == 0.0).then(|| "0".to_owned()),
            };
            if let Some(exact) = special {
                let what = format!("joint {} `{} = \"{}\"`", j + 1, dh.key(), g.as_str());
                found.push((Item::Value(j, dh), what, exact));
            }
        }
    }
    let gravity = robot.gravity_values().ok()?;
    for (i, g) in robot.gravity().iter().enumerate() {
        if !g.symbols().is_empty() && gravity[i] == 0.0 {
            let what = format!("gravity {} `\"{}\"`", ["x", "y", "z"][i], g.as_str());
            found.push((Item::Gravity(i), what, "0".to_owned()));
        }
    }
    let (item, what, exact) = found.first()?;
    let (line, column) = place.line_column(spans.of(*item).start);
    let more = and_more(found.len() - 1, " value", " values");
    Some(format!(
        "{}:{line}:{column}: {what} is {exact} at the [symbols] values{more}: the base \
         parameters are derived for any value of the symbols and hold at this one, but some \
         may have no effect on this robot's torques (identification then calls them not \
         excited and `excite` cannot excite them, whatever the trajectory); write {exact} \
         in the table for this robot's own base parameters",
        place.file
    ))
}

/// What a length beyond [`MAX_ARM_LENGTH`] likely is, and the fix.
pub(super) const LENGTH_FIX: &str = "lengths are in metres; in millimetres? write 0.425 for \
     425 mm";

/// What a revolute limit beyond [`MAX_TURNING`] likely is, and the fix.
pub(super) const TURNING_FIX: &str = "revolute limits are in radians; in degrees? write \
     them in radians (-2.967 for -170 degrees), or leave the limits out for a joint that \
     turns freely";

/// The first revolute joint (0-based) whose position limits reach beyond [`MAX_TURNING`],
/// with its limits.
pub(super) fn turning_too_far(robot: &Robot) -> Option<(usize, [f64; 2])> {
    robot.joints().iter().enumerate().find_map(|(j, joint)| {
        let limits = joint.limits.position?;
        (joint.kind == JointKind::Revolute && limits.iter().any(|v| v.abs() > MAX_TURNING))
            .then_some((j, limits))
    })
}

/// The message of a TOML syntax error. toml says only "duplicate key" for a key or table
/// given twice; its span holds the key, so the message names it and says what to do.
fn syntax_message(text: &str, e: &toml::de::Error) -> String {
    let message = e.message().trim();
    if let Some(what) = other_format(text) {
        return format!("{message}; {what}");
    }
    if message.contains("recursion depth") {
        // toml's "cannot recurse further; max recursion depth met" said what the reader
        // did, not what is wrong with the file
        return "arrays or inline tables are nested deeper than the TOML reader follows; a \
                description nests them two deep (`limits = { position = [-3, 3] }`): close \
                the brackets this value opens"
            .to_owned();
    }
    let key = e
        .span()
        .filter(|_| message == "duplicate key")
        .and_then(|span| Some((text.get(span.clone())?, span.start)));
    let Some((key, start)) = key else {
        return message.to_owned();
    };
    let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
    if text[line_start..start].trim_start().starts_with('[') {
        format!(
            "the table `{key}` is given a second time; TOML allows each table once: merge \
             the two into one (a list of joints is written `[[joints]]`, each header one joint)"
        )
    } else {
        format!(
            "`{key}` is given a second time in this table; TOML allows each key once per table \
             (each `[[joints]]` header starts the next joint's): delete the one not meant"
        )
    }
}

/// What a file that is not TOML holds instead, when it says so by its first line: a URDF
/// or other XML (read as TOML because of its extension), or a CSV data file given where
/// the description goes (the first argument of every subcommand).
fn other_format(text: &str) -> Option<&'static str> {
    let first = text
        .trim_start_matches('\u{feff}')
        .lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))?;
    if first.starts_with('<') {
        return Some(
            "the file is XML, not a TOML description: robid reads a URDF by its `.urdf` \
             extension (give the file that name; expand a xacro file first, `xacro \
             robot.urdf.xacro > robot.urdf`)",
        );
    }
    // a CSV header: names separated by commas, `;` or tabs, or three or more plain names
    // separated by spaces (`name "arm"` is a TOML slip), and no TOML key or table
    let separated = first.split([',', ';', '\t']).count() > 1;
    let plain = |w: &str| {
        w.chars()
            .all(|c| c.is_alphanumeric() || "_-.()[]".contains(c))
    };
    let spaced = first.split_whitespace().count() > 2 && first.split_whitespace().all(plain);
    let csv = (separated || spaced) && !first.contains('=') && !first.starts_with('[');
    csv.then_some(
        "the file looks like a CSV data file, not a robot description: the description \
         (TOML or URDF) is the first argument and the data come after it (`--data`, or \
         the files of `--config`)",
    )
}

/// Errors of the checks, located through the spans the reader kept.
struct FileLocator<'a> {
    place: &'a Place<'a>,
    spans: &'a Spans,
}

impl Locate for FileLocator<'_> {
    fn error(&self, item: Item<'_>, message: String, help: String) -> DescriptionError {
        self.place.invalid(self.spans.of(item), message, help)
    }

    fn place(&self, item: Item<'_>) -> Option<String> {
        let (line, column) = self.place.line_column(self.spans.of(item).start);
        Some(format!("{}:{line}:{column}", self.place.file))
    }
}

impl Robot {
    /// Reads a description file (at most
    /// [`MAX_DESCRIPTION_LEN`] bytes).
    pub fn from_file(path: &std::path::Path) -> Result<Robot, DescriptionError> {
        Robot::from_file_with_warnings(path).map(|(robot, _)| robot)
    }

    /// Reads a description file like [`Robot::from_file`], with the warnings about what
    /// is valid but probably not meant (each `file:line:column: what; what to do`), for
    /// example a `drive` key at the end of the file, which TOML gives to the last joint.
    pub fn from_file_with_warnings(
        path: &std::path::Path,
    ) -> Result<(Robot, Vec<String>), DescriptionError> {
        let file = path.display().to_string();
        let read_error = |reason: String| DescriptionError::Read {
            file: file.clone(),
            reason,
        };
        let handle =
            std::fs::File::open(path).map_err(|e| read_error(robid_core::names::io_problem(&e)))?;
        let mut bytes = Vec::new();
        handle
            .take(MAX_DESCRIPTION_LEN as u64 + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| read_error(robid_core::names::io_problem(&e)))?;
        if bytes.len() > MAX_DESCRIPTION_LEN {
            return Err(read_error(format!(
                "it is longer than {MAX_DESCRIPTION_LEN} bytes, the most a description may have; is it a description?"
            )));
        }
        if bytes.starts_with(&[0x1f, 0x8b]) {
            return Err(read_error(
                "it is gzip-compressed, not a description (a compressed data file?): the \
                 description (TOML or URDF text) is the first argument and the data come after \
                 it (`--data`, or the files of `--config`)"
                    .to_owned(),
            ));
        }
        let text = String::from_utf8(bytes).map_err(|e| {
            read_error(format!(
                "it is not UTF-8 text (invalid byte at offset {}); save it as UTF-8",
                e.utf8_error().valid_up_to()
            ))
        })?;
        Robot::from_toml_with_warnings(&text, &file)
    }

    /// Parses a description from TOML text; `file` names it in errors. Every
    /// mistake is reported (in [`DescriptionError::Several`] when there are
    /// more than one), except that a TOML syntax error is reported alone.
    /// Values are checked against the limits of [`bounds`](super::bounds).
    pub fn from_toml(text: &str, file: &str) -> Result<Robot, DescriptionError> {
        Robot::from_toml_with_warnings(text, file).map(|(robot, _)| robot)
    }

    /// Parses a description like [`Robot::from_toml`], with the warnings of
    /// [`Robot::from_file_with_warnings`].
    ///
    /// ```
    /// use robid_symbolic::Robot;
    /// let text = "name = \"arm\"\nconvention = \"modified\"\n\
    ///             [[joints]]\nalpha = 0\n[[joints]]\nalpha = 0\n\ndrive = [\"Fv\"]\n";
    /// let (robot, warnings) = Robot::from_toml_with_warnings(text, "arm.toml").unwrap();
    /// assert!(robot.joints()[0].drive.terms().next().is_none());
    /// assert!(warnings[0].starts_with("arm.toml:8:9: only joint 2, the last, has a `drive` key"));
    /// ```
    pub fn from_toml_with_warnings(
        text: &str,
        file: &str,
    ) -> Result<(Robot, Vec<String>), DescriptionError> {
        let place = Place { file, text };
        if text.len() > MAX_DESCRIPTION_LEN {
            return Err(place.invalid(
                0..0,
                format!(
                    "the description is {} bytes long, more than the {MAX_DESCRIPTION_LEN} robid reads",
                    text.len()
                ),
                "a description is a short DH table; check that this is the right file",
            ));
        }
        let document = DeTable::parse(text).map_err(|e| {
            let (line, column) = e
                .span()
                .map(|s| place.line_column(s.start))
                .unwrap_or((1, 1));
            DescriptionError::Syntax {
                file: file.to_owned(),
                line,
                column,
                message: syntax_message(text, &e),
            }
        })?;
        let mut reader = Reader::new(&place);
        let parts = reader.robot(document.get_ref());
        let (mut errors, spans) = reader.finish();
        let checked = parts.check(&FileLocator {
            place: &place,
            spans: &spans,
        });
        match checked {
            Ok(robot) if errors.is_empty() => {
                let warnings = warnings(&place, &spans, &robot);
                return Ok((robot, warnings));
            }
            Ok(_) => {}
            Err(more) => errors.extend(more),
        }
        errors.sort_by_key(|e| e.span().map_or(0, |(start, _)| start));
        Err(DescriptionError::from_errors(errors))
    }
}
