//! From URDF text to plain structs: the `<link>` and `<joint>` elements that are direct
//! children of `<robot>`, every number checked, every mistake located
//! (docs/urdf.md#reading).
//!
//! Angles go through the angle rule of `rigid.rs` (docs/urdf.md#the-angle-rule); axes are
//! normalised. Only the first `<origin>` of a joint counts (as in URDF parsers), with a
//! warning for the others.

use super::super::DescriptionError;
use super::super::bounds::{
    MAX_ARM_LENGTH, MAX_DESCRIPTION_LEN, MAX_NAME_LEN, MAX_TORQUE, MAX_TURNING, MAX_URDF_DEPTH,
    MAX_VELOCITY,
};
use super::super::check::{and_more, listed};
use super::super::file::Place;
use super::rigid::{NEAR_RIGHT_ANGLE, Rigid, near_right_angle, norm, right_angle_multiple, scale};
use robid_core::names::short;
use roxmltree::{Document, Node};
use std::ops::Range;

/// Largest magnitude of a number in a URDF: no robot has larger lengths (m), masses (kg),
/// inertias (kg m^2) or limits, and products of such values stay finite.
const MAX_VALUE: f64 = 1e9;

/// Largest mass (kg) or inertia element (kg m^2) of a URDF link: the largest parameter
/// value robid's parameter files take (`robid_runtime::limits::MAX_PARAMETER`), so that
/// what `robid model` writes of a URDF is read back (1e9 kg links were read, their files
/// refused, and their simulation stopped with the runtime's own check).
const MAX_INERTIAL: f64 = 1e6;

/// A URDF joint type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum JointType {
    Revolute,
    Continuous,
    Prismatic,
    Fixed,
    Floating,
    Planar,
}

impl JointType {
    /// Whether robid can take the joint as one of its joints.
    pub(super) fn movable(self) -> bool {
        matches!(
            self,
            JointType::Revolute | JointType::Continuous | JointType::Prismatic
        )
    }
}

/// `<inertial>`: the centre of mass frame, the mass, the inertia about the centre of mass in
/// that frame.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Inertial {
    /// The `<origin>`: the centre of mass frame in the link frame.
    pub(super) origin: Rigid,
    pub(super) mass: f64,
    /// `ixx ixy ixz iyy iyz izz`.
    pub(super) inertia: [f64; 6],
    /// The element's bytes.
    pub(super) range: Range<usize>,
    /// The `<mass>`'s `value`.
    pub(super) mass_at: Range<usize>,
    /// The `<inertia>` element.
    pub(super) inertia_at: Range<usize>,
}

/// `<link>`.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Link {
    pub(super) name: String,
    /// The element's bytes.
    pub(super) range: Range<usize>,
    /// Whether the element is written `<link .../>`.
    pub(super) empty: bool,
    pub(super) inertial: Option<Inertial>,
}

/// `<limit>`.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Limit {
    pub(super) lower: Option<f64>,
    pub(super) upper: Option<f64>,
    /// Whether `lower` or `upper` is beyond ±[`MAX_VALUE`] (ROS and Gazebo files write
    /// ±1e16 for none): the joint has no position limits.
    pub(super) unbounded: bool,
    pub(super) effort: Option<f64>,
    pub(super) velocity: Option<f64>,
    /// Whether `effort` and `velocity` are written (a placeholder above the largest value
    /// taken is written, and read as no limit).
    pub(super) written: [bool; 2],
    /// Whether the `<limit>` follows robid's note that its zeros stand for no limit
    /// ([`robid_core::URDF_NO_LIMIT_NOTE`]): no warning about them.
    pub(super) zeros_noted: bool,
    pub(super) range: Range<usize>,
}

/// `<mimic joint multiplier offset>`: the joint is `multiplier * joint + offset`.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Mimic {
    /// The joint followed.
    pub(super) joint: String,
    /// Where its name is.
    pub(super) at: Range<usize>,
    /// Default 1.
    pub(super) multiplier: f64,
    /// Default 0.
    pub(super) offset: f64,
}

/// `<joint>`.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Joint {
    pub(super) name: String,
    pub(super) kind: JointType,
    /// The element's bytes.
    pub(super) range: Range<usize>,
    pub(super) parent: String,
    /// The `link` attribute of `<parent>`.
    pub(super) parent_at: Range<usize>,
    pub(super) child: String,
    /// The `link` attribute of `<child>`.
    pub(super) child_at: Range<usize>,
    /// The first `<origin>`: the joint frame in the parent link frame.
    pub(super) origin: Rigid,
    /// The unit axis in the joint frame.
    pub(super) axis: [f64; 3],
    pub(super) limit: Option<Limit>,
    /// `<mimic>`: the joint this one follows.
    pub(super) mimic: Option<Mimic>,
    /// Where `<dynamics>` is.
    pub(super) dynamics: Option<Range<usize>>,
}

/// A read URDF.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Urdf {
    pub(super) name: String,
    /// Where the robot name is.
    pub(super) name_at: Range<usize>,
    pub(super) links: Vec<Link>,
    pub(super) joints: Vec<Joint>,
    pub(super) warnings: Vec<String>,
}

/// Reads `place.text` (at most [`MAX_DESCRIPTION_LEN`] bytes).
pub(super) fn read(place: &Place<'_>) -> Result<Urdf, DescriptionError> {
    if place.text.len() > MAX_DESCRIPTION_LEN {
        return Err(place.invalid(
            0..0,
            format!(
                "the URDF is {} bytes long, more than the {MAX_DESCRIPTION_LEN} robid reads",
                place.text.len()
            ),
            "check that this is the right file (meshes belong in their own files)",
        ));
    }
    let (text, foreign) = undeclared_prefixes(place.text);
    let doc = Document::parse(&text).map_err(|e| {
        if matches!(e, roxmltree::Error::DtdDetected) {
            // well-formed, but a DTD can define entities that expand without bound
            let at = place.text.find("<!DOCTYPE").unwrap_or(0);
            return place.invalid(
                at..at,
                "the URDF has a document type declaration (`<!DOCTYPE ...>`), and robid does \
                 not read DTDs (their entities can expand without bound)"
                    .to_owned(),
                "remove the `<!DOCTYPE ...>`: a URDF needs none (write out any entity it \
                 defines where the file uses it)",
            );
        }
        // a file that ends too soon is told at its end, where the parser gives no place
        // (it said 1:1 of a file cut in its fourth line)
        let cut = matches!(
            e,
            roxmltree::Error::UnexpectedEndOfStream | roxmltree::Error::UnclosedRootNode
        );
        let (line, column) = if cut {
            place.line_column(place.text.trim_end().len())
        } else {
            (e.pos().row as usize, e.pos().col as usize)
        };
        DescriptionError::Invalid {
            file: place.file.to_owned(),
            line,
            column,
            message: format!("the URDF is not well-formed XML: {e}"),
            help: if looks_like_xacro(place.text) {
                format!("this looks like an unexpanded xacro file: {EXPAND_XACRO}")
            } else if cut {
                "the file ends here, before its elements are closed: is it cut short? Copy it \
                 again whole"
                    .to_owned()
            } else {
                "fix the XML at this place (every tag closed, attribute values quoted)".to_owned()
            },
            span: None,
        }
    })?;
    let root = doc.root_element();
    if let Some(deep) = too_deep(root) {
        return Err(place.invalid(
            deep.range(),
            format!(
                "`<{}>` is nested more than {MAX_URDF_DEPTH} elements deep",
                deep.tag_name().name()
            ),
            "a URDF nests its elements a few deep (`<robot><link><visual><geometry><mesh>`): \
             check that this is a URDF, and close the elements where they end",
        ));
    }
    if let Some((at, what)) = xacro_left(root) {
        return Err(place.invalid(
            at,
            format!("the URDF is an unexpanded xacro file ({what})"),
            EXPAND_XACRO,
        ));
    }
    let mut warnings = Vec::new();
    if let Some((prefix, at)) = foreign.first() {
        let more = match foreign.len() - 1 {
            0 => String::new(),
            n => format!(" (and {n} more prefixes)"),
        };
        warnings.push(place.warning(
            *at,
            &format!(
                "the URDF uses the namespace prefix `{prefix}:`{more} without declaring it \
                 (`xmlns:{prefix}=\"...\"` on `<robot>`), as a simulator's extensions do: its \
                 elements and attributes are not URDF and are ignored, as URDF parsers \
                 ignore them"
            ),
        ));
    }
    let mut reader = Reader {
        place,
        errors: Vec::new(),
        warnings,
        printed: Vec::new(),
        near: Vec::new(),
        unbounded: Vec::new(),
        placeholders: Vec::new(),
        non_finite: Vec::new(),
    };
    if urdf_name(root) != Some("robot") {
        return Err(place.invalid(
            root.range(),
            format!(
                "the top element is `<{}>`, not `<robot>`",
                written_name(root)
            ),
            "give a URDF file, whose elements are inside `<robot name=\"...\">`",
        ));
    }
    if let Some(w) = declared_extensions(place, root) {
        reader.warnings.push(w);
    }
    let (name, name_at) = reader
        .required(root, "name")
        .unwrap_or((String::new(), root.range()));
    let mut links = Vec::new();
    let mut joints = Vec::new();
    for node in root.children().filter(Node::is_element) {
        match urdf_name(node).unwrap_or_default() {
            "link" => links.extend(reader.link(node)),
            "joint" => joints.extend(reader.joint(node)),
            _ => {}
        }
    }
    if let Some((word, at)) = reader.printed.first() {
        let more = match reader.printed.len() - 1 {
            0 => String::new(),
            1 => " and 1 more".to_owned(),
            n => format!(" and {n} more"),
        };
        let w = place.warning(
            *at,
            &format!(
                "`rpy` angles printed to a few decimals of a right angle (`{word}`{more}) are \
                 taken as that right angle exactly (docs/urdf.md#the-angle-rule); write \
                 them to 10 decimals or more to say so yourself"
            ),
        );
        reader.warnings.push(w);
    }
    if let Some((word, at, k, off)) = reader.near.first() {
        let more = match reader.near.len() - 1 {
            0 => String::new(),
            n => {
                let farthest = reader.near.iter().map(|n| n.3).fold(0.0, f64::max);
                format!(", and {n} more, none farther than {farthest:.1e} rad")
            }
        };
        let w = place.warning(
            *at,
            &format!(
                "`rpy` angles within {NEAR_RIGHT_ANGLE:e} rad of a right angle (`{word}`, \
                 {off:.1e} rad from {}{more}) are taken as that right angle exactly \
                 (docs/urdf.md#the-angle-rule): right angles computed from a rounded pi, such \
                 as xacro's `pi = 3.14159265`, are that far off, and no calibration resolves \
                 a skew this small; write them exactly (`1.5707963267948966` for pi/2) to \
                 say so yourself",
                multiple_text(*k)
            ),
        );
        reader.warnings.push(w);
    }
    if let Some((written, at, joint)) = reader.unbounded.first() {
        let more = and_more(reader.unbounded.len() - 1, " such value", " such values");
        let w = place.warning(
            *at,
            &format!(
                "`{written}` of joint `{joint}`{more} is beyond ±{MAX_VALUE:e}: taken as no \
                 position limit, as ROS and Gazebo files mean it (the joint is read as if \
                 `lower` and `upper` were left out); write the joint's real range if it has one"
            ),
        );
        reader.warnings.push(w);
    }
    if let Some((written, at, joint, max)) = reader.placeholders.first() {
        let more = and_more(reader.placeholders.len() - 1, " such value", " such values");
        let w = place.warning(
            *at,
            &format!(
                "`{written}` of joint `{joint}`{more} is above {max:e}, the largest robid takes \
                 (rad/s or m/s for a velocity, N m or N for an effort): taken as no limit, for \
                 which such files write it (`robid excite` then asks for --velocity-limits \
                 where it needs one); write the joint's real limit if it has one"
            ),
        );
        reader.warnings.push(w);
    }
    if let Some(joint) = joints
        .iter()
        .find(|j| j.origin.p.iter().any(|v| v.abs() > MAX_ARM_LENGTH))
    {
        let [x, y, z] = joint.origin.p;
        let w = place.warning(
            joint.range.start,
            &format!(
                "joint `{}`'s origin is at `{x} {y} {z}` m, farther than an arm's \
                 {MAX_ARM_LENGTH} m: {}",
                joint.name,
                super::super::file::LENGTH_FIX
            ),
        );
        reader.warnings.push(w);
    }
    // a centre of mass in millimetres is as far off as a joint origin, and gave torques
    // of thousands of N m without a word
    let far_mass = links.iter().find_map(|l| {
        let inertial = l.inertial.as_ref()?;
        let far = inertial.origin.p.iter().any(|v| v.abs() > MAX_ARM_LENGTH);
        far.then_some((l, inertial))
    });
    if let Some((link, inertial)) = far_mass {
        let [x, y, z] = inertial.origin.p;
        let w = place.warning(
            inertial.range.start,
            &format!(
                "link `{}`'s centre of mass (its `<inertial>`'s `<origin>`) is at `{x} {y} {z}` \
                 m, farther than an arm's {MAX_ARM_LENGTH} m: {}",
                link.name,
                super::super::file::LENGTH_FIX
            ),
        );
        reader.warnings.push(w);
    }
    let turning = joints.iter().find_map(|j| {
        let limit = j.limit.as_ref().filter(|_| j.kind == JointType::Revolute)?;
        let far = [limit.lower, limit.upper]
            .iter()
            .flatten()
            .any(|v| v.abs() > MAX_TURNING);
        far.then_some((j, limit))
    });
    if let Some((joint, limit)) = turning {
        let show = |v: Option<f64>| v.map_or("none".to_owned(), |v| format!("{v}"));
        let w = place.warning(
            limit.range.start,
            &format!(
                "joint `{}`'s limits [{}, {}] reach beyond {MAX_TURNING:.2} rad (a turn and a \
                 quarter): {}",
                joint.name,
                show(limit.lower),
                show(limit.upper),
                super::super::file::TURNING_FIX
            ),
        );
        reader.warnings.push(w);
    }
    if let Some(w) = without_limits(place, &joints) {
        reader.warnings.push(w);
    }
    if let Some(w) = incomplete_limits(place, &joints) {
        reader.warnings.push(w);
    }
    for (span, message) in non_finite(root, &reader.non_finite) {
        reader.error(
            span,
            message,
            "write finite numbers (robid copies the file's other elements into the URDFs it \
             writes, `robid feasible -o`), or remove the value",
        );
    }
    reader.duplicates(links.iter().map(|l| (&l.name, &l.range)), "link");
    reader.duplicates(joints.iter().map(|j| (&j.name, &j.range)), "joint");
    // with another mistake, told with it (a `<robot>` that xacro left empty was told only
    // that it had no name); alone, the chain's check tells it
    if links.is_empty() && !reader.errors.is_empty() {
        reader.error(
            root.range().start..root.range().start,
            "the robot has no `<link>`".to_owned(),
            "a URDF describes links connected by joints: is this the right file (xacro \
             writes an empty `<robot>` when the macro it expands is not called)?",
        );
    }
    if reader.errors.is_empty() {
        Ok(Urdf {
            name,
            name_at,
            links,
            joints,
            warnings: reader.warnings,
        })
    } else {
        Err(DescriptionError::from_errors(reader.errors))
    }
}

struct Reader<'a> {
    place: &'a Place<'a>,
    errors: Vec<DescriptionError>,
    warnings: Vec<String>,
    /// The `rpy` values taken as the right angle they print ([`printed_right_angle`])
    /// that the 1e-9 rule alone would not take (`1.5708`, not `1.57079632679`): the word
    /// and where it is.
    printed: Vec<(String, usize)>,
    /// The `rpy` values taken as the right angle within [`NEAR_RIGHT_ANGLE`] of them
    /// ([`near_right_angle`]): the word, where it is, the multiple of pi/2 and the distance.
    near: Vec<(String, usize, i64, f64)>,
    /// The `lower` and `upper` values beyond ±[`MAX_VALUE`] ([`Reader::position_bound`]):
    /// the attribute as written, where it is, and the joint.
    unbounded: Vec<(String, usize, String)>,
    /// The `effort` and `velocity` values above the largest robid takes
    /// ([`Reader::rate_limit`]): the attribute as written, where it is, the joint and the
    /// largest value taken.
    placeholders: Vec<(String, usize, String, f64)>,
    /// Where the values [`Reader::numbers`] refused as not finite begin: [`non_finite`]
    /// does not tell them twice.
    non_finite: Vec<usize>,
}

/// The largest `rpy` angle read (rad): a turn, and a hundredth more for a printed 2 pi
/// (`6.2832`); beyond it, an angle is degrees read as radians.
const MAX_TURN: f64 = std::f64::consts::TAU + 0.01;

/// The most namespace prefixes [`undeclared_prefixes`] takes as undeclared.
const MAX_UNDECLARED: usize = 16;

/// `text` with the undeclared namespace prefixes of element and attribute names (other
/// than `xacro`, which [`looks_like_xacro`] tells) turned into plain names of the same
/// length (`<drake:member>` -> `<drake_member>`, `drake:acceleration="2"` ->
/// `drake_acceleration="2"`): no URDF element or attribute has such a name, so they are
/// ignored, as URDF parsers ignore them (Drake's `drake:` extensions made the whole file
/// unreadable: "an unknown namespace prefix"). Offsets are kept, so places in the
/// text are those of the file. Also the prefixes and the first place of each.
fn undeclared_prefixes(text: &str) -> (std::borrow::Cow<'_, str>, Vec<(String, usize)>) {
    let mut text = std::borrow::Cow::Borrowed(text);
    let mut found: Vec<(String, usize)> = Vec::new();
    while found.len() < MAX_UNDECLARED {
        let prefix = match Document::parse(&text) {
            Err(roxmltree::Error::UnknownNamespace(prefix, _)) if prefix != "xacro" => prefix,
            _ => break,
        };
        let (patched, first) = plain_names(&text, &prefix);
        let Some(first) = first else { break };
        found.push((prefix, first));
        text = std::borrow::Cow::Owned(patched);
    }
    (text, found)
}

/// `text` with `prefix:` turned into `prefix_` where it begins a name inside a tag (after
/// `<`, `</` or white space, outside quoted values), and where it first did.
fn plain_names(text: &str, prefix: &str) -> (String, Option<usize>) {
    let bytes = text.as_bytes();
    let mut out = bytes.to_vec();
    let (mut in_tag, mut quote, mut first) = (false, None, None);
    for (i, &b) in bytes.iter().enumerate() {
        match (in_tag, quote) {
            (false, _) => in_tag = b == b'<',
            (true, Some(q)) => {
                if b == q {
                    quote = None;
                }
            }
            (true, None) => match b {
                b'"' | b'\'' => quote = Some(b),
                b'>' => in_tag = false,
                _ => {
                    let starts =
                        i > 0 && matches!(bytes[i - 1], b'<' | b'/' | b' ' | b'\t' | b'\n' | b'\r');
                    let named = bytes[i..].starts_with(prefix.as_bytes())
                        && bytes.get(i + prefix.len()) == Some(&b':');
                    if starts && named {
                        out[i + prefix.len()] = b'_';
                        first.get_or_insert(i);
                    }
                }
            },
        }
    }
    // only an ASCII `:` became an ASCII `_`: still UTF-8
    (
        String::from_utf8(out).unwrap_or_else(|_| text.to_owned()),
        first,
    )
}

/// One warning for the elements of declared namespaces (`<drake:joint>` under
/// `xmlns:drake="..."`), at the first, naming its prefix and counting the other prefixes:
/// they are ignored ([`urdf_name`]), as those of undeclared ones are.
fn declared_extensions(place: &Place<'_>, root: Node<'_, '_>) -> Option<String> {
    let mut prefixes: Vec<(&str, Node<'_, '_>)> = Vec::new();
    for node in root.descendants().filter(Node::is_element) {
        if let Some((prefix, _)) = written_name(node).split_once(':')
            && !prefixes.iter().any(|(p, _)| *p == prefix)
        {
            prefixes.push((prefix, node));
        }
    }
    let ((prefix, first), rest) = prefixes.split_first()?;
    let more = match rest.len() {
        0 => String::new(),
        n => format!(" (and {n} more prefixes)"),
    };
    Some(place.warning(
        first.range().start,
        &format!(
            "`<{0}>` and the other elements of the namespace prefix `{prefix}:`{more} are a \
             simulator's or another tool's extensions, not URDF: they are ignored, as URDF \
             parsers ignore them (`<{0}>` is no `<{1}>`)",
            written_name(*first),
            first.tag_name().name()
        ),
    ))
}

/// Every value of the URDF's own elements (no namespace prefix, [`urdf_name`]) that is
/// numbers, one of them not finite (`nan`, `inf`), which the reader has not refused yet
/// (`told`: where those begin): an attribute but a name, or the text of an element without
/// elements, with its place and message. robid does not use most of them
/// (`<dynamics damping="nan">`), but the URDFs it writes copy them, and a `nan` in an
/// output is refused by whatever reads it next. `lower` and `upper` of `<limit>` may be
/// infinite: no position limit ([`Reader::position_bound`]).
fn non_finite(root: Node<'_, '_>, told: &[usize]) -> Vec<(Range<usize>, String)> {
    // numbers, one of them not finite; names are not numbers, even a link named `inf`
    let bad = |text: &str| {
        let words: Vec<Option<f64>> = text.split_whitespace().map(|w| w.parse().ok()).collect();
        !words.is_empty()
            && words.iter().all(Option::is_some)
            && words.iter().flatten().any(|v| !v.is_finite())
    };
    let mut found = Vec::new();
    let elements = root.descendants().filter(|n| n.is_element());
    for node in elements.filter(|n| {
        n.ancestors()
            .all(|a| !a.is_element() || urdf_name(a).is_some())
    }) {
        let owner = node
            .ancestors()
            .find(|a| attribute(*a, "name").is_some())
            .filter(|a| *a != node)
            .map_or(String::new(), |a| format!(" of {}", describe(a)));
        for a in node.attributes().filter(|a| a.namespace().is_none()) {
            let named = matches!(a.name(), "name" | "link" | "joint" | "filename" | "type");
            let unbounded = node.has_tag_name("limit")
                && matches!(a.name(), "lower" | "upper")
                && a.value().trim().parse::<f64>().is_ok_and(f64::is_infinite);
            if named || unbounded || told.contains(&a.range_value().start) || !bad(a.value()) {
                continue;
            }
            found.push((
                a.range_value(),
                format!(
                    "`{}=\"{}\"` of {}{owner} is not finite",
                    a.name(),
                    short(a.value()),
                    describe(node)
                ),
            ));
        }
        if node.children().all(|c| c.is_text())
            && let Some(text) = node.text().filter(|t| bad(t))
            && let Some(first) = node.first_child()
        {
            found.push((
                first.range(),
                format!(
                    "the text `{}` of {}{owner} is not finite",
                    short(text.trim()),
                    describe(node)
                ),
            ));
        }
    }
    found
}

/// The fix for an unexpanded xacro file.
const EXPAND_XACRO: &str = "expand it with xacro first (`xacro robot.urdf.xacro > \
     robot.urdf`) and give robid the URDF it writes";

/// Whether a text that is not well-formed XML looks like a xacro file: `xacro:` elements
/// whose namespace is not declared, or `${...}` expressions, outside comments (xarm7's
/// URDF keeps a commented-out `${prefix}` link: any typo in it was called a xacro file).
fn looks_like_xacro(text: &str) -> bool {
    let mut rest = text;
    loop {
        let (before, after) = rest.split_once("<!--").unwrap_or((rest, ""));
        if before.contains("<xacro:") || before.contains("${") {
            return true;
        }
        match after.split_once("-->") {
            Some((_, next)) => rest = next,
            None => return false,
        }
    }
}

/// The first element nested deeper than [`MAX_URDF_DEPTH`] (`root` at depth 1), found by
/// one walk of the tree.
fn too_deep<'a, 'input>(root: Node<'a, 'input>) -> Option<Node<'a, 'input>> {
    let mut stack = vec![(root, 1)];
    while let Some((node, depth)) = stack.pop() {
        if depth > MAX_URDF_DEPTH {
            return Some(node);
        }
        stack.extend(
            node.children()
                .filter(Node::is_element)
                .map(|c| (c, depth + 1)),
        );
    }
    None
}

/// The first trace of xacro in a parsed file, where and what: an element of the xacro
/// namespace (`<xacro:property>`, `<xacro:macro>`) anywhere, or a `${...}` expression in an
/// attribute of a `<link>` or `<joint>`. A declaration `xmlns:xacro` alone is not one:
/// xacro keeps it in the URDFs it writes.
fn xacro_left(root: Node<'_, '_>) -> Option<(Range<usize>, String)> {
    for node in root.descendants().filter(Node::is_element) {
        if node
            .tag_name()
            .namespace()
            .is_some_and(|ns| ns.contains("xacro"))
        {
            return Some((
                node.range(),
                format!("`<xacro:{}>`", node.tag_name().name()),
            ));
        }
        // the ancestors only for an attribute with an expression: every element's cost
        // the depth, the whole walk its square
        let inside = || {
            node.ancestors()
                .any(|a| a.has_tag_name("link") || a.has_tag_name("joint"))
        };
        if let Some(a) = node
            .attributes()
            .find(|a| a.value().contains("${") && inside())
        {
            return Some((a.range_value(), format!("`{}=\"{}\"`", a.name(), a.value())));
        }
    }
    None
}

/// The element's name when it is a URDF name: written without a namespace prefix. An
/// element of a declared namespace (`<drake:joint type="ball">` of Drake's extension, under
/// `xmlns:drake="..."`) is another tool's, as for URDF parsers, which ignore namespaces and
/// so see `drake:joint`, no URDF element: it was read as a `<joint>`. The prefix is read
/// from the text, since a default namespace (`xmlns="..."`) puts unprefixed elements in one
/// too, and URDF parsers read those.
fn urdf_name<'a>(node: Node<'a, '_>) -> Option<&'a str> {
    (!written_name(node).contains(':')).then_some(node.tag_name().name())
}

/// The element's name as written, with its namespace prefix if any (`drake:joint`).
fn written_name<'a>(node: Node<'a, '_>) -> &'a str {
    let text = &node.document().input_text()[node.range()];
    let name = text.strip_prefix('<').unwrap_or(text);
    let end = name
        .find(|c: char| c.is_whitespace() || c == '/' || c == '>')
        .unwrap_or(name.len());
    &name[..end]
}

/// The attribute `name` of `node` without a namespace prefix (`drake:type` is not `type`;
/// roxmltree's own lookup by a plain name matches a prefixed attribute too).
fn attribute<'a, 'i>(node: Node<'a, 'i>, name: &str) -> Option<roxmltree::Attribute<'a, 'i>> {
    node.attributes()
        .find(|a| a.namespace().is_none() && a.name() == name)
}

/// `<tag name="...">` for messages.
fn describe(node: Node<'_, '_>) -> String {
    match attribute(node, "name").map(|a| a.value()) {
        Some(name) => format!("`<{} name=\"{}\">`", node.tag_name().name(), short(name)),
        None => format!("`<{}>`", node.tag_name().name()),
    }
}

impl Reader<'_> {
    fn error(&mut self, span: Range<usize>, message: String, help: impl Into<String>) {
        self.errors.push(self.place.invalid(span, message, help));
    }

    /// The first `<tag>` child of `node`, as URDF parsers take it, with a warning at the
    /// second when there are several (a second `<inertial>` or `<axis>` is otherwise
    /// ignored without a word).
    fn child<'a, 'i>(&mut self, node: Node<'a, 'i>, tag: &str) -> Option<Node<'a, 'i>> {
        let mut all = node
            .children()
            .filter(|c| c.is_element() && urdf_name(*c) == Some(tag));
        let first = all.next();
        if let Some(second) = all.next() {
            let w = self.place.warning(
                second.range().start,
                &format!(
                    "{} has {} `<{tag}>` elements: the first is used, as URDF parsers do; \
                     remove the others",
                    describe(node),
                    2 + all.count()
                ),
            );
            self.warnings.push(w);
        }
        first
    }

    /// A required attribute and where its value is.
    fn required(&mut self, node: Node<'_, '_>, name: &str) -> Option<(String, Range<usize>)> {
        match attribute(node, name) {
            Some(a) if a.value().chars().nth(MAX_NAME_LEN).is_some() => {
                self.error(
                    a.range_value(),
                    format!(
                        "`{name}=\"{}\"` of {} is longer than {MAX_NAME_LEN} characters, the \
                         most robid reads",
                        short(a.value()),
                        describe(node)
                    ),
                    "give it a shorter name",
                );
                None
            }
            Some(a) => Some((a.value().to_owned(), a.range_value())),
            None => {
                self.error(
                    node.range(),
                    format!("{} has no `{name}` attribute", describe(node)),
                    format!("add `{name}=\"...\"` (the URDF format requires it)"),
                );
                None
            }
        }
    }

    /// An optional attribute of `count` finite numbers (`count` = 1: a scalar).
    fn numbers(&mut self, node: Node<'_, '_>, name: &str, count: usize) -> Option<Vec<f64>> {
        let attribute = attribute(node, name)?;
        let text = attribute.value();
        let span = attribute.range_value();
        let mut values = Vec::new();
        let max = match node.tag_name().name() {
            "mass" | "inertia" => MAX_INERTIAL,
            _ => MAX_VALUE,
        };
        for word in text.split_whitespace() {
            match word.parse::<f64>() {
                Ok(v) if v.abs() <= max => values.push(v),
                Ok(v) if v.is_finite() => {
                    let help = unit_help(node.tag_name().name(), name);
                    self.error(
                        span,
                        format!(
                            "`{name}=\"{}\"` of {}: `{}` is beyond ±{max:e}, not a value of a robot",
                            short(text),
                            describe(node),
                            short(word)
                        ),
                        help,
                    );
                    return None;
                }
                Ok(_) => {
                    self.non_finite.push(span.start);
                    self.error(
                        span,
                        format!("`{name}=\"{text}\"` of {} is not finite", describe(node)),
                        "write finite numbers",
                    );
                    return None;
                }
                Err(_) => {
                    self.error(
                        span,
                        format!(
                            "`{name}=\"{text}\"` of {}: `{word}` is not a number",
                            describe(node)
                        ),
                        "write decimal numbers such as `0.5` or `-1.2e-3`",
                    );
                    return None;
                }
            }
        }
        if values.len() != count {
            let expected = if count == 1 {
                "one number".to_owned()
            } else {
                format!("{count} numbers separated by spaces")
            };
            // `1 number`: it said "has 1 numbers" of `xyz="0"`
            let found = match values.len() {
                1 => "1 number".to_owned(),
                n => format!("{n} numbers"),
            };
            self.error(
                span,
                format!("`{name}=\"{text}\"` of {} has {found}", describe(node)),
                format!("write {expected}"),
            );
            return None;
        }
        Some(values)
    }

    fn scalar(&mut self, node: Node<'_, '_>, name: &str) -> Option<f64> {
        self.numbers(node, name, 1).map(|v| v[0])
    }

    /// `lower` or `upper` of a `<limit>`: a number beyond ±[`MAX_VALUE`], infinities
    /// included, is no bound (`(None, true)`), noted for one warning.
    fn position_bound(&mut self, l: Node<'_, '_>, name: &str, joint: &str) -> (Option<f64>, bool) {
        if let Some(a) = attribute(l, name)
            && let Ok(v) = a.value().trim().parse::<f64>()
            && v.abs() > MAX_VALUE
        {
            let written = format!("{name}=\"{}\"", a.value());
            self.unbounded
                .push((written, a.range_value().start, joint.to_owned()));
            return (None, true);
        }
        (self.scalar(l, name), false)
    }

    /// `effort` or `velocity` of a `<limit>`: a number above `max` (the largest robid
    /// takes, [`MAX_TORQUE`], [`MAX_VELOCITY`]) is a placeholder for no limit, as iCub's
    /// `velocity="50000"` (`None`), noted for one warning; the file was refused.
    fn rate_limit(&mut self, l: Node<'_, '_>, name: &str, max: f64, joint: &str) -> Option<f64> {
        let v = self.scalar(l, name)?;
        if v <= max {
            return Some(v);
        }
        if let Some(a) = attribute(l, name) {
            let written = format!("{name}=\"{}\"", a.value());
            self.placeholders
                .push((written, a.range_value().start, joint.to_owned(), max));
        }
        None
    }

    fn required_scalar(&mut self, node: Node<'_, '_>, name: &str) -> Option<f64> {
        if attribute(node, name).is_none() {
            self.required(node, name);
            return None;
        }
        self.scalar(node, name)
    }

    fn vector(&mut self, node: Node<'_, '_>, name: &str) -> Option<[f64; 3]> {
        self.numbers(node, name, 3).map(|v| [v[0], v[1], v[2]])
    }

    /// An `<origin xyz rpy>` (each default 0).
    fn origin(&mut self, node: Option<Node<'_, '_>>) -> Rigid {
        let Some(node) = node else {
            return Rigid::IDENTITY;
        };
        let xyz = self.vector(node, "xyz").unwrap_or([0.0; 3]);
        let mut rpy = self.vector(node, "rpy").unwrap_or([0.0; 3]);
        if let Some(attribute) = attribute(node, "rpy") {
            let words = attribute.value().split_whitespace();
            for (angle, word) in rpy.iter_mut().zip(words) {
                let at = attribute.range_value().start;
                if angle.abs() > MAX_TURN {
                    // degrees read as radians (`rpy="90 0 0"`): a silently other robot
                    self.error(
                        attribute.range_value(),
                        format!(
                            "`rpy=\"{}\"` of {} has the angle `{word}`, more than a turn: \
                             URDF angles are in radians",
                            attribute.value(),
                            describe(node.parent_element().unwrap_or(node))
                        ),
                        "write the angles in radians (1.5707963267948966 for 90 degrees); an \
                         angle of more than a turn, if meant, is its remainder after whole turns",
                    );
                } else if right_angle_multiple(*angle).is_some() {
                    // the 1e-9 rule takes it as the right angle (`1.57079632679`,
                    // `3.14159265358979`): as written, nothing to warn about
                } else if let Some(exact) = printed_right_angle(word) {
                    *angle = exact;
                    self.printed.push((word.to_owned(), at));
                } else if let Some((k, off)) = near_right_angle(*angle) {
                    *angle = k as f64 * std::f64::consts::FRAC_PI_2;
                    self.near.push((word.to_owned(), at, k, off));
                }
            }
        }
        Rigid::from_xyz_rpy(xyz, rpy)
    }

    fn link(&mut self, node: Node<'_, '_>) -> Option<Link> {
        let (name, _) = self.required(node, "name")?;
        let inertial = self.child(node, "inertial").and_then(|i| self.inertial(i));
        let text = &self.place.text[node.range()];
        Some(Link {
            name,
            range: node.range(),
            empty: text.trim_end().ends_with("/>"),
            inertial,
        })
    }

    fn inertial(&mut self, node: Node<'_, '_>) -> Option<Inertial> {
        let origin = self.child(node, "origin");
        let origin = self.origin(origin);
        let mass_node = self.child(node, "mass");
        let mass = match mass_node {
            Some(m) => self.required_scalar(m, "value"),
            None => {
                self.error(
                    node.range(),
                    "`<inertial>` has no `<mass value=\"...\">`".to_owned(),
                    "add the mass in kg, or remove `<inertial>` for a massless link",
                );
                None
            }
        };
        // a negative mass and an inertia that is not positive semidefinite are checked
        // only for the links of the chain's bodies (`inertial::check`)
        let mass_at = mass_node.map_or(node.range(), |m| {
            attribute(m, "value").map_or(m.range(), |a| a.range_value())
        });
        let mut inertia_at = node.range();
        let inertia = match self.child(node, "inertia") {
            Some(i) => {
                let mut values = [0.0; 6];
                let mut complete = true;
                for (k, name) in ["ixx", "ixy", "ixz", "iyy", "iyz", "izz"]
                    .iter()
                    .enumerate()
                {
                    match self.required_scalar(i, name) {
                        Some(v) => values[k] = v,
                        None => complete = false,
                    }
                }
                inertia_at = i.range();
                complete.then_some(values)
            }
            None => {
                self.error(
                    node.range(),
                    "`<inertial>` has no `<inertia ixx=... izz=...>`".to_owned(),
                    "add the inertia about the centre of mass (kg m^2)",
                );
                None
            }
        };
        Some(Inertial {
            origin,
            mass: mass?,
            inertia: inertia?,
            range: node.range(),
            mass_at,
            inertia_at,
        })
    }

    fn joint(&mut self, node: Node<'_, '_>) -> Option<Joint> {
        let name = self.required(node, "name");
        let kind = self.required(node, "type").and_then(|(t, span)| {
            Some(match t.as_str() {
                "revolute" => JointType::Revolute,
                "continuous" => JointType::Continuous,
                "prismatic" => JointType::Prismatic,
                "fixed" => JointType::Fixed,
                "floating" => JointType::Floating,
                "planar" => JointType::Planar,
                other => {
                    self.error(
                        span,
                        format!("{} has the unknown joint type `{other}`", describe(node)),
                        "write one of revolute, continuous, prismatic, fixed, floating, planar",
                    );
                    return None;
                }
            })
        });
        let parent = self.link_reference(node, "parent");
        let child = self.link_reference(node, "child");
        let origin = self.child(node, "origin");
        let origin = self.origin(origin);
        let axis = match self.child(node, "axis") {
            None => Some([1.0, 0.0, 0.0]),
            Some(a) => match attribute(a, "xyz") {
                None => Some([1.0, 0.0, 0.0]),
                Some(attribute) => {
                    let span = attribute.range_value();
                    let fixed = matches!(kind, Some(JointType::Fixed));
                    self.vector(a, "xyz").and_then(|v| {
                        // over its largest component first: the norm of `0 0 1e-200`
                        // underflows to zero, that of `3e300 4e300 0` overflows; divided,
                        // not times the reciprocal, which overflows for `1e-320 0 0`
                        let largest = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                        // subnormal components carry no digits, so their direction is
                        // rounding (`0 4e-320 4e-320` was read as `0 1 1`): 0, as a
                        // subnormal mass is (`robot::negligible`)
                        if largest >= f64::MIN_POSITIVE && largest.is_finite() {
                            let u = v.map(|x| x / largest);
                            Some(scale(u, 1.0 / norm(u)))
                        } else if fixed && largest < f64::MIN_POSITIVE {
                            // a fixed joint's axis is not used (Kinova's Gen3 URDF writes
                            // `0 0 0` there)
                            Some([1.0, 0.0, 0.0])
                        } else {
                            let subnormal = if largest > 0.0 {
                                " (its components are below 2.2e-308, subnormal numbers \
                                 without the digits of a direction: 0)"
                                    .to_owned()
                            } else {
                                String::new()
                            };
                            self.error(
                                span,
                                format!(
                                    "the axis of {} has no direction{subnormal}",
                                    describe(node)
                                ),
                                "give the axis as a non-zero vector, e.g. `0 0 1`",
                            );
                            None
                        }
                    })
                }
            },
        };
        let joint_name = name.as_ref().map_or("", |(n, _)| n.as_str()).to_owned();
        let limit = self.child(node, "limit").map(|l| {
            let (lower, below) = self.position_bound(l, "lower", &joint_name);
            let (upper, above) = self.position_bound(l, "upper", &joint_name);
            Limit {
                lower,
                upper,
                unbounded: below || above,
                effort: self.rate_limit(l, "effort", MAX_TORQUE, &joint_name),
                velocity: self.rate_limit(l, "velocity", MAX_VELOCITY, &joint_name),
                written: ["effort", "velocity"].map(|a| attribute(l, a).is_some()),
                zeros_noted: l
                    .prev_siblings()
                    .skip(1)
                    .find(|n| !(n.is_text() && n.text().is_some_and(|t| t.trim().is_empty())))
                    .is_some_and(|n| {
                        n.is_comment()
                            && n.text().map(str::trim) == Some(robid_core::URDF_NO_LIMIT_NOTE)
                    }),
                range: l.range(),
            }
        });
        let mimic = self.child(node, "mimic").and_then(|m| {
            let multiplier = self.scalar(m, "multiplier").unwrap_or(1.0);
            let offset = self.scalar(m, "offset").unwrap_or(0.0);
            let (joint, at) = self.required(m, "joint")?;
            Some(Mimic {
                joint,
                at,
                multiplier,
                offset,
            })
        });
        let dynamics = self.child(node, "dynamics").map(|d| d.range());
        let (name, _) = name?;
        let (parent, parent_at) = parent?;
        let (child, child_at) = child?;
        Some(Joint {
            name,
            kind: kind?,
            range: node.range(),
            parent,
            parent_at,
            child,
            child_at,
            origin,
            axis: axis?,
            limit,
            mimic,
            dynamics,
        })
    }

    /// `<parent link="...">` or `<child link="...">`.
    fn link_reference(&mut self, joint: Node<'_, '_>, tag: &str) -> Option<(String, Range<usize>)> {
        match self.child(joint, tag) {
            Some(node) => self.required(node, "link"),
            None => {
                self.error(
                    joint.range(),
                    format!("{} has no `<{tag} link=\"...\"/>`", describe(joint)),
                    format!("add `<{tag} link=\"...\"/>` naming the {tag} link"),
                );
                None
            }
        }
    }

    /// An error for every name used a second time.
    fn duplicates<'n>(
        &mut self,
        items: impl Iterator<Item = (&'n String, &'n Range<usize>)>,
        what: &str,
    ) {
        let mut seen: std::collections::HashMap<&str, usize> = Default::default();
        for (name, range) in items {
            if let Some(&first) = seen.get(name.as_str()) {
                let (line, _) = self.place.line_column(first);
                self.error(
                    range.clone(),
                    format!("a second {what} is named `{name}` (the first is on line {line})"),
                    format!("give every {what} its own name"),
                );
            } else {
                seen.insert(name, range.start);
            }
        }
    }
}

/// One warning for the revolute and prismatic joints without `<limit>`, at the first,
/// naming it and the others: robid reads them without limits, but the URDF format requires
/// the element there, and urdfdom (the parser of ROS tools and Pinocchio) refuses the file.
/// A continuous joint needs none.
fn without_limits(place: &Place<'_>, joints: &[Joint]) -> Option<String> {
    let bare: Vec<&Joint> = joints
        .iter()
        .filter(|j| matches!(j.kind, JointType::Revolute | JointType::Prismatic))
        .filter(|j| j.limit.is_none())
        .collect();
    let (first, rest) = bare.split_first()?;
    let kind = |j: &Joint| {
        if j.kind == JointType::Prismatic {
            "prismatic"
        } else {
            "revolute"
        }
    };
    let others = match rest {
        [] => String::new(),
        [one] => format!(" (joint `{}` has none either)", one.name),
        more => {
            let names: Vec<String> = more.iter().map(|j| format!("`{}`", j.name)).collect();
            format!(" (joints {} have none either)", listed(names))
        }
    };
    Some(place.warning(
        first.range.start,
        &format!(
            "joint `{}` is {} but has no `<limit>`: robid reads it without position, velocity \
             or torque limits, but the URDF format requires the element for revolute and \
             prismatic joints, and urdfdom, the parser of ROS tools and Pinocchio, refuses \
             the file; add `<limit lower=\"..\" upper=\"..\" effort=\"..\" velocity=\"..\"/>`, \
             or make a joint that turns without end `type=\"continuous\"`{others}",
            first.name,
            kind(first)
        ),
    ))
}

/// One warning for the joints robid can move (revolute, continuous, prismatic) whose
/// `<limit>` lacks `effort` or `velocity`, at the first such `<limit>`, naming the joints and
/// what each lacks: robid reads a missing value as no limit (as it reads `0`), but the URDF
/// format requires both attributes, and urdfdom (the parser of ROS tools and Pinocchio)
/// refuses the file. Vendor files omit them, so this is a warning, not an error.
fn incomplete_limits(place: &Place<'_>, joints: &[Joint]) -> Option<String> {
    let lacking: Vec<(&Joint, &Limit, &str)> = joints
        .iter()
        .filter(|j| j.kind.movable())
        .filter_map(|j| {
            let limit = j.limit.as_ref()?;
            let what = match (!limit.written[0], !limit.written[1]) {
                (true, true) => "`effort` or `velocity`",
                (true, false) => "`effort`",
                (false, true) => "`velocity`",
                (false, false) => return None,
            };
            Some((j, limit, what))
        })
        .collect();
    let ((joint, limit, what), rest) = lacking.split_first()?;
    let others = if rest.is_empty() {
        String::new()
    } else {
        let named: Vec<String> = rest
            .iter()
            .map(|(j, _, what)| format!("joint `{}` has no {what}", j.name))
            .collect();
        format!(" (also: {})", listed(named))
    };
    let missing = |key: &str| lacking.iter().any(|(_, _, what)| what.contains(key));
    let assumed = match (missing("effort"), missing("velocity")) {
        (true, true) => {
            "a missing `effort` as no torque limit and a missing `velocity` as no velocity \
             limit (`robid excite` then leaves the torque unbounded and asks for \
             --velocity-limits)"
        }
        (true, false) => {
            "a missing `effort` as no torque limit (`robid excite` then leaves the torque \
             unbounded)"
        }
        _ => {
            "a missing `velocity` as no velocity limit (`robid excite` then asks for \
             --velocity-limits)"
        }
    };
    Some(place.warning(
        limit.range.start,
        &format!(
            "the `<limit>` of joint `{}` has no {what}{others}: robid takes {assumed}, but the \
             URDF format requires `effort` and `velocity` in every `<limit>`, and urdfdom, the \
             parser of ROS tools and Pinocchio, refuses the file; add the robot's values \
             (`effort` in N m or N, `velocity` in rad/s or m/s)",
            joint.name
        ),
    ))
}

/// One warning for the joints of the chain robid moves (revolute, continuous, prismatic:
/// `joints`, in the chain's order; a joint off the chain, such as a gripper's finger left
/// out by `--tip`, is none of robid's concern) whose `<limit>` writes `effort="0"` or `velocity="0"`, at the first such `<limit>`, naming the
/// joints and which of the two each has at 0: robid reads 0 as no limit (URDF's default),
/// but exporters write 0 as a placeholder for a limit they do not know, so a robot that
/// has limits probably lost them; the fix is the real values in the URDF, or for the
/// velocity `robid excite --velocity-limits`. The format allows 0 (urdfdom reads it), so
/// this is a warning, not an error.
pub(super) fn zero_limits<'a>(
    place: &Place<'_>,
    joints: impl IntoIterator<Item = &'a Joint>,
) -> Option<String> {
    let zero = |value: Option<f64>| value == Some(0.0);
    let zeros: Vec<(&Joint, &Limit, &str)> = joints
        .into_iter()
        .filter(|j| j.kind.movable())
        .filter_map(|j| {
            let limit = j.limit.as_ref().filter(|l| !l.zeros_noted)?;
            let what = match (zero(limit.effort), zero(limit.velocity)) {
                (true, true) => "`effort=\"0\"` and `velocity=\"0\"`",
                (true, false) => "`effort=\"0\"`",
                (false, true) => "`velocity=\"0\"`",
                (false, false) => return None,
            };
            Some((j, limit, what))
        })
        .collect();
    let ((joint, limit, what), rest) = zeros.split_first()?;
    let others = if rest.is_empty() {
        String::new()
    } else {
        let named: Vec<String> = rest
            .iter()
            .map(|(j, _, what)| format!("joint `{}` has {what}", j.name))
            .collect();
        format!(" (also: {})", listed(named))
    };
    let effort = zeros.iter().any(|(_, _, what)| what.contains("effort"));
    let velocity = zeros.iter().any(|(_, _, what)| what.contains("velocity"));
    let (taken, fix) = match (effort, velocity) {
        (true, true) => (
            "no torque limit and no velocity limit (`robid excite` then leaves the torque \
             unbounded and asks for --velocity-limits)",
            "write the robot's limits in the URDF (`effort` in N m or N, `velocity` in rad/s \
             or m/s), or give the velocity limits to `robid excite` as --velocity-limits",
        ),
        (true, false) => (
            "no torque limit (`robid excite` then leaves the torque unbounded)",
            "write the robot's torque limits in the URDF (`effort` in N m or N)",
        ),
        _ => (
            "no velocity limit (`robid excite` then asks for --velocity-limits)",
            "write the robot's limits in the URDF (`velocity` in rad/s or m/s), or give them \
             to `robid excite` as --velocity-limits",
        ),
    };
    Some(place.warning(
        limit.range.start,
        &format!(
            "the `<limit>` of joint `{}` has {what}{others}: robid takes 0 as {taken}, but \
             URDF exporters write 0 where they do not know a limit; if the robot has limits, \
             {fix}",
            joint.name
        ),
    ))
}

/// The fix for position limits written as huge numbers to mean none.
pub(super) const NO_POSITION_LIMITS: &str = "a joint that turns without end is `type=\"continuous\"`; \
     leave `lower` and `upper` out (or write them equal) for a joint without position limits";

/// The nonzero multiple of pi/2 that `word` prints to its own number of decimals, when it
/// has at least [`PRINTED_DECIMALS`] of them: `1.5708` and `-3.1416` are pi/2 and -pi
/// written to four decimals (as CAD exports and Kinova's URDFs write them), while
/// `1.57079` is not pi/2 to five decimals (that would be `1.57080`) and stays what it is.
/// The decimals are those of the value however it is written: `1.5708E+00` (C's `%E`),
/// `0.15708e1` and `15708e-4` have four, like `1.5708`.
pub(super) fn printed_right_angle(word: &str) -> Option<f64> {
    let (mantissa, exponent) = match word.split_once(['e', 'E']) {
        Some((m, e)) => (m, e.parse::<i64>().ok()?),
        None => (word, 0),
    };
    let fraction = mantissa.split_once('.').map_or(0, |(_, f)| f.len());
    let decimals = usize::try_from(i64::try_from(fraction).ok()? - exponent).ok()?;
    let value: f64 = word.parse().ok()?;
    if decimals < PRINTED_DECIMALS || !value.is_finite() {
        return None;
    }
    let k = (value / std::f64::consts::FRAC_PI_2).round();
    if k == 0.0 || k.abs() > 4.0 {
        return None;
    }
    let exact = k * std::f64::consts::FRAC_PI_2;
    let printed: f64 = format!("{exact:.decimals$}").parse().ok()?;
    (printed == value).then_some(exact)
}

/// `k pi/2` for messages: `0`, `pi/2`, `-pi`, `3*pi/2`.
fn multiple_text(k: i64) -> String {
    match k {
        0 => "0".to_owned(),
        1 => "pi/2".to_owned(),
        -1 => "-pi/2".to_owned(),
        k if k % 2 == 0 => match k / 2 {
            1 => "pi".to_owned(),
            -1 => "-pi".to_owned(),
            m => format!("{m}*pi"),
        },
        k => format!("{k}*pi/2"),
    }
}

/// Fewest decimals of a value [`printed_right_angle`] takes for a right angle: `3.14` or
/// `1.571` may be meant as written.
const PRINTED_DECIMALS: usize = 4;

/// The fix for a value of attribute `name` of an element `tag` too large for a robot:
/// the unit robid reads it in.
fn unit_help(tag: &str, name: &str) -> &'static str {
    match (tag, name) {
        ("limit", "lower" | "upper") => NO_POSITION_LIMITS,
        ("limit", "velocity") => {
            "write the joint's velocity limit in rad/s (m/s for a prismatic joint), or leave \
             `velocity` out for no limit"
        }
        ("limit", "effort") => {
            "write the joint's effort limit in N m (N for a prismatic joint), or leave \
             `effort` out for no limit"
        }
        ("mass", _) => "write the link's mass in kg",
        ("inertia", _) => "write the inertia about the centre of mass in kg m^2",
        ("origin", "xyz") => "write the position in m",
        ("origin", "rpy") => "write the angles in rad",
        // a direction has no unit: only its ratios count
        ("axis", _) => "write the axis as a direction of moderate components, e.g. `0 0 1`",
        _ => "write lengths in m, masses in kg, inertias in kg m^2, angles in rad",
    }
}
