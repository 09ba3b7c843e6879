//! Turns the parsed input into a validated `Robot`, collecting every problem
//! with the span of the item it is about (serde_derive's `Ctxt` pattern: one
//! function per rule, all errors reported together).

use crate::input::{Input, Item};
use proc_macro2::Span;
use robid_symbolic::robot::DriveTerm;
use robid_symbolic::robot::Geometry;
use robid_symbolic::robot::UrdfChain;
use robid_symbolic::robot::bounds::MAX_DESCRIPTION_LEN;
use robid_symbolic::{Convention, DescriptionError, Drive, Joint, JointKind, Robot, Transform};
use std::path::PathBuf;
use syn::spanned::Spanned;
use syn::{Expr, ExprLit, Lit, LitStr, UnOp};

const KEYS: [&str; 10] = [
    "file",
    "base",
    "tip",
    "name",
    "convention",
    "gravity",
    "drive",
    "symbols",
    "joints",
    "calibrated",
];

/// A checked input: the robot and the file to track, if it came from one.
pub(crate) struct Checked {
    pub(crate) robot: Robot,
    pub(crate) tracked: Option<PathBuf>,
    /// For a URDF: its `<inertial>` elements as the robot's standard parameters (in robid's
    /// frames, drive terms 0), emitted as `URDF_STANDARD_PARAMETERS`.
    pub(crate) urdf_standard: Option<Vec<f64>>,
}

/// What a description gave: the robot, the file to track, a URDF's chain.
type Read = (Robot, Option<PathBuf>, Option<UrdfChain>);

/// The problems found, and the robot name for the placeholder type if known.
pub(crate) struct Failed {
    pub(crate) errors: Vec<syn::Error>,
    pub(crate) name: Option<String>,
}

#[derive(Default)]
struct Ctxt {
    errors: Vec<syn::Error>,
}

impl Ctxt {
    fn error(&mut self, span: Span, message: impl std::fmt::Display) {
        self.errors.push(syn::Error::new(span, message));
    }

    /// Every problem of a description error, each at the span `at` gives it.
    fn description(&mut self, err: &DescriptionError, at: impl Fn(&DescriptionError) -> Span) {
        self.description_spanning(err, |e| (at(e), None));
    }

    /// [`Ctxt::description`] where `at` may give a range: from its first span to its
    /// second, when it has one (both of two arguments at fault, and what lies between).
    fn description_spanning(
        &mut self,
        err: &DescriptionError,
        at: impl Fn(&DescriptionError) -> (Span, Option<Span>),
    ) {
        for e in err.errors() {
            let message = match e {
                // The span says which argument: the message and the fix suffice.
                DescriptionError::Argument { message, help, .. } => format!("{message}; {help}"),
                other => other.to_string(),
            };
            match at(e) {
                (span, None) => self.error(span, message),
                (start, Some(end)) => self.errors.push(spanning(start, end, message)),
            }
        }
    }
}

/// An error whose span runs from `start` to `end`: syn places an error made from tokens
/// from the first token's span to the last's, which a compiler without `Span::join`
/// (stable Rust) still shows as one range.
fn spanning(start: Span, end: Span, message: impl std::fmt::Display) -> syn::Error {
    let tokens: proc_macro2::TokenStream = [
        proc_macro2::TokenTree::Ident(proc_macro2::Ident::new("start", start)),
        proc_macro2::TokenTree::Ident(proc_macro2::Ident::new("end", end)),
    ]
    .into_iter()
    .collect();
    syn::Error::new_spanned(tokens, message)
}

/// Where the parts of an inline description were written.
struct Spans {
    name: Span,
    gravity: Option<[Span; 3]>,
    /// alpha, a, d, theta, gamma, b of each joint (gamma and b: the call's span when not
    /// written).
    joints: Vec<[Span; 6]>,
}

impl Spans {
    /// The span of the argument an error of `Robot::new` names (`joints[2].a`,
    /// `gravity[0]`, the robot name), else the call site.
    fn of(&self, err: &DescriptionError) -> Span {
        let DescriptionError::Argument { argument, .. } = err else {
            return Span::call_site();
        };
        let argument = argument.trim_matches('`');
        let index = |rest: &str| rest.split(']').next().and_then(|i| i.parse::<usize>().ok());
        if argument == "the robot name" {
            return self.name;
        }
        if let Some(rest) = argument.strip_prefix("gravity[") {
            return index(rest)
                .and_then(|i| self.gravity?.get(i).copied())
                .unwrap_or_else(Span::call_site);
        }
        if let Some(rest) = argument.strip_prefix("joints[")
            && let Some(j) = index(rest)
            && let Some(spans) = self.joints.get(j)
        {
            let key = rest.split("].").nth(1).unwrap_or("");
            let k = JOINT_VALUES.iter().position(|k| *k == key);
            return k.map_or(spans[0], |k| spans[k]);
        }
        Span::call_site()
    }
}

/// Checks the input and builds the robot.
pub(crate) fn check(input: &Input) -> Result<Checked, Failed> {
    let mut cx = Ctxt::default();
    let mut found: Vec<&Item> = Vec::new();
    for item in &input.items {
        let key = item.key.to_string();
        if !KEYS.contains(&key.as_str()) {
            cx.error(
                item.key.span(),
                format!(
                    "unknown key `{key}`; expected one of {}",
                    KEYS.map(|k| format!("`{k}`")).join(", ")
                ),
            );
        } else if found.iter().any(|f| f.key == item.key) {
            cx.error(item.key.span(), format!("`{key}` is given twice"));
        } else {
            found.push(item);
        }
    }
    let get = |k: &str| lookup(&found, k);
    let name = get("name").and_then(|i| string(&mut cx, &i.value, "the robot name"));
    let drive = get("drive").map(|i| drive(&mut cx, &i.value));
    let result = match get("file") {
        Some(file) => {
            for k in ["convention", "gravity", "symbols", "joints", "calibrated"] {
                if let Some(i) = get(k) {
                    let urdf = literal(&file.value)
                        .is_some_and(|f| f.value().to_ascii_lowercase().ends_with(".urdf"));
                    let fix = match k {
                        "calibrated" if urdf => {
                            "a URDF's angles are taken as measured already: leave it out"
                        }
                        _ => "write it in the file",
                    };
                    cx.error(
                        i.key.span(),
                        format!("`{k}` cannot be combined with `file`; {fix}"),
                    );
                }
            }
            // both links chosen: from the first key written to the last value
            let at = |k: &str| found.iter().position(|i| i.key == k);
            let both = at("base").zip(at("tip")).map(|(b, t)| {
                let (first, last) = (found[b.min(t)], found[b.max(t)]);
                (first.key.span(), last.value.span())
            });
            let chain = ChainSelection {
                base: get("base").and_then(|i| string(&mut cx, &i.value, "the base link")),
                tip: get("tip").and_then(|i| string(&mut cx, &i.value, "the tip link")),
                both,
            };
            from_file(&mut cx, &file.value, &chain)
        }
        None => {
            if let Some(i) = get("tip") {
                cx.error(
                    i.key.span(),
                    "`tip` chooses the chain of a URDF `file`; an inline description is one chain already",
                );
            }
            inline(&mut cx, &found, name.as_ref())
        }
    };
    let stub_name = name
        .as_ref()
        .map(|n| n.value())
        .or_else(|| result.as_ref().map(|(r, _, _)| r.name().to_owned()))
        .or_else(|| {
            let file = get("file").and_then(|i| literal(&i.value))?;
            let path = PathBuf::from(file.value());
            Some(path.file_stem()?.to_string_lossy().into_owned())
        });
    match result {
        Some((mut robot, tracked, inertials)) if cx.errors.is_empty() => {
            if let Some(n) = &name {
                match robot.with_name(&n.value()) {
                    Ok(r) => robot = r,
                    Err(err) => {
                        cx.description(&err, |_| n.span());
                        return Err(Failed {
                            errors: cx.errors,
                            name: None,
                        });
                    }
                }
            }
            if let Some(Some(d)) = drive {
                robot = robot.with_drive(d);
            }
            let urdf_standard = inertials.map(|chain| chain.standard_values(&robot));
            Ok(Checked {
                robot,
                tracked,
                urdf_standard,
            })
        }
        _ => Err(Failed {
            errors: cx.errors,
            name: stub_name,
        }),
    }
}

fn literal(e: &Expr) -> Option<&LitStr> {
    match e {
        Expr::Lit(ExprLit {
            lit: Lit::Str(s), ..
        }) => Some(s),
        _ => None,
    }
}

/// `true` or `false`.
fn boolean(cx: &mut Ctxt, e: &Expr, what: &str) -> Option<bool> {
    match e {
        Expr::Lit(ExprLit {
            lit: Lit::Bool(b), ..
        }) => Some(b.value),
        _ => {
            cx.error(e.span(), format!("expected `true` or `false` for {what}"));
            None
        }
    }
}

fn string(cx: &mut Ctxt, e: &Expr, what: &str) -> Option<LitStr> {
    let s = literal(e).cloned();
    if s.is_none() {
        cx.error(e.span(), format!("expected a string for {what}"));
    }
    s
}

/// `base = "..."` and `tip = "..."` as written, for a URDF file.
struct ChainSelection {
    base: Option<LitStr>,
    tip: Option<LitStr>,
    /// With both: from the first of the two keys written to the last of the two values.
    both: Option<(Span, Span)>,
}

fn from_file(cx: &mut Ctxt, e: &Expr, chain: &ChainSelection) -> Option<Read> {
    let lit = string(cx, e, "the description file")?;
    let relative = lit.value();
    let dir = std::env::var("CARGO_MANIFEST_DIR").unwrap_or_default();
    let mut path = PathBuf::from(dir).join(&relative);
    // Not there: relative to the invoking source file (e.g. under trybuild,
    // whose crates have another manifest directory).
    if !path.exists()
        && let Some(beside) = proc_macro::Span::call_site()
            .local_file()
            .and_then(|f| Some(f.parent()?.join(&relative)))
        && beside.exists()
    {
        path = beside;
    }
    // Larger than a description may be: refused before reading it.
    if let Ok(meta) = std::fs::metadata(&path)
        && meta.len() > MAX_DESCRIPTION_LEN as u64
    {
        cx.error(
            lit.span(),
            format!(
                "`{relative}` is {} bytes, more than the {MAX_DESCRIPTION_LEN} a description may have; check the path",
                meta.len()
            ),
        );
        return None;
    }
    let text = match std::fs::read_to_string(&path) {
        Ok(t) => t,
        Err(err) => {
            cx.error(
                lit.span(),
                format!(
                    "cannot read `{relative}`: {err}; the path is relative to the directory of the crate's Cargo.toml (or of the file invoking the macro)"
                ),
            );
            return None;
        }
    };
    let urdf = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("urdf"));
    if !urdf {
        for given in [&chain.base, &chain.tip].into_iter().flatten() {
            cx.error(
                given.span(),
                format!("`{relative}` is a TOML description: `base` and `tip` choose the chain of a URDF (`.urdf`) file"),
            );
        }
        if chain.base.is_some() || chain.tip.is_some() {
            return None;
        }
    }
    // Every mistake of the file, each at the path (the message says where in the file).
    let read = if urdf {
        let selection = robid_symbolic::robot::ChainSelection {
            base: chain.base.as_ref().map(LitStr::value),
            tip: chain.tip.as_ref().map(LitStr::value),
        };
        Robot::from_urdf(&text, &relative, &selection)
            .map(|chain| (chain.robot.clone(), Some(chain)))
    } else {
        Robot::from_toml(&text, &relative).map(|robot| (robot, None))
    };
    match read {
        Ok((robot, inertials)) => Some((robot, Some(path), inertials)),
        Err(err) => {
            // an error about the chain's choice at `base = ..` or `tip = ..` (about both,
            // from one to the other), the rest at the path
            cx.description_spanning(&err, |e| match e {
                DescriptionError::Argument { argument, .. } => {
                    let (base, tip) = (
                        argument.contains("ChainSelection::base"),
                        argument.contains("ChainSelection::tip"),
                    );
                    if base
                        && tip
                        && let Some((start, end)) = chain.both
                    {
                        return (start, Some(end));
                    }
                    let given = match (base, tip) {
                        (_, true) => &chain.tip,
                        (true, false) => &chain.base,
                        (false, false) => &None,
                    };
                    (
                        given.as_ref().map_or_else(|| lit.span(), LitStr::span),
                        None,
                    )
                }
                _ => (lit.span(), None),
            });
            None
        }
    }
}

fn lookup<'a>(found: &[&'a Item], key: &str) -> Option<&'a Item> {
    found.iter().find(|i| i.key == key).copied()
}

fn inline(cx: &mut Ctxt, found: &[&Item], name: Option<&LitStr>) -> Option<Read> {
    let get = |k: &str| lookup(found, k);
    let span = Span::call_site();
    if name.is_none() && get("name").is_none() {
        cx.error(span, "missing `name = \"...\"` (or `file = \"...\"`)");
    }
    let convention = match get("convention") {
        None => {
            cx.error(
                span,
                "missing `convention = \"modified\"` or `convention = \"standard\"`",
            );
            None
        }
        Some(i) => convention(cx, &i.value),
    };
    let gravity = get("gravity").map(|i| gravity(cx, &i.value));
    let mut spans = Spans {
        name: name.map_or(span, LitStr::span),
        gravity: get("gravity").and_then(|i| match &i.value {
            Expr::Array(a) if a.elems.len() == 3 => {
                let s: Vec<Span> = a.elems.iter().map(Spanned::span).collect();
                Some([s[0], s[1], s[2]])
            }
            _ => None,
        }),
        joints: Vec::new(),
    };
    let joints = match get("joints") {
        None => {
            cx.error(
                span,
                "missing `joints = [revolute(alpha, a, d, theta), ...]`",
            );
            None
        }
        Some(i) => joints(cx, &i.value, &mut spans.joints),
    };
    let symbols = get("symbols").map(|i| symbols(cx, &i.value));
    let calibrated = match get("calibrated") {
        Some(i) => boolean(cx, &i.value, "`calibrated`"),
        None => Some(false),
    };
    let (name, convention, joints, calibrated) = (name?, convention?, joints?, calibrated?);
    let gravity = match gravity {
        Some(g) => Some(g?),
        None => None,
    };
    // a table measured by a calibration: its angles near right angles as written
    let new = if calibrated {
        Robot::new_calibrated
    } else {
        Robot::new
    };
    let mut robot = match new(&name.value(), convention, gravity, joints) {
        Ok(r) => r,
        Err(err) => {
            cx.description(&err, |e| spans.of(e));
            return None;
        }
    };
    for (symbol, value, span) in symbols.into_iter().flatten() {
        match robot.clone().with_symbol_value(&symbol, value) {
            Ok(r) => robot = r,
            Err(err) => cx.description(&err, |_| span),
        }
    }
    // frame 0 in the world, as a file's [base] (gravity is given in the world); a tool
    // frame ([tool]) places nothing in the compiled model, so it has no inline form
    if let Some(item) = get("base")
        && let Some(pose) = pose(cx, &item.value)
    {
        match robot.clone().with_base(Some(pose)) {
            Ok(r) => robot = r,
            Err(err) => cx.description(&err, |_| item.value.span()),
        }
    }
    Some((robot, None, None))
}

/// The syntax of a pose, for messages.
const POSE_SYNTAX: &str = "`pose(xyz = [x, y, z], rpy = [roll, pitch, yaw])` (metres and radians, \
     R = Rz(yaw) Ry(pitch) Rx(roll) as in URDF; either part may be left out)";

/// `pose(xyz = [...], rpy = [...])`: an inline description's `base`.
fn pose(cx: &mut Ctxt, e: &Expr) -> Option<Transform> {
    let call = match e {
        Expr::Call(call) if matches!(&*call.func, Expr::Path(p) if p.path.is_ident("pose")) => call,
        _ => {
            cx.error(
                e.span(),
                format!(
                    "`base` of an inline description is {POSE_SYNTAX}; a link name chooses the chain of a URDF `file`"
                ),
            );
            return None;
        }
    };
    let mut pose = Transform::identity();
    let mut seen = [false; 2];
    let Arguments {
        positional, named, ..
    } = arguments(call);
    let mut ok = positional.is_empty();
    for a in positional {
        cx.error(a.span(), format!("write {POSE_SYNTAX}"));
    }
    for (part, value) in named {
        let k = match part.to_string().as_str() {
            "xyz" => 0,
            "rpy" => 1,
            other => {
                cx.error(
                    part.span(),
                    format!("unknown part `{other}` of a pose; write {POSE_SYNTAX}"),
                );
                ok = false;
                continue;
            }
        };
        if std::mem::replace(&mut seen[k], true) {
            cx.error(part.span(), format!("`{part}` is given twice"));
            ok = false;
            continue;
        }
        let values = array(cx, value, "three values")?;
        if values.len() != 3 {
            cx.error(
                value.span(),
                format!("`{part}` has {} values; give three", values.len()),
            );
            ok = false;
            continue;
        }
        let v: Vec<Option<Geometry>> = values.iter().map(|x| self::value(cx, x)).collect();
        let [x, y, z] = [v[0].clone(), v[1].clone(), v[2].clone()];
        match (x, y, z) {
            (Some(x), Some(y), Some(z)) if k == 0 => pose.xyz = [x, y, z],
            (Some(x), Some(y), Some(z)) => pose.rpy = [x, y, z],
            _ => ok = false,
        }
    }
    ok.then_some(pose)
}

fn convention(cx: &mut Ctxt, e: &Expr) -> Option<Convention> {
    let s = string(cx, e, "the convention")?;
    match s.value().as_str() {
        "modified" => Some(Convention::Modified),
        "standard" => Some(Convention::Standard),
        other => {
            cx.error(
                s.span(),
                format!(
                    "unknown DH convention `{other}`; write \"modified\" (Craig/Khalil) or \"standard\" (classic)"
                ),
            );
            None
        }
    }
}

fn array<'a>(cx: &mut Ctxt, e: &'a Expr, what: &str) -> Option<Vec<&'a Expr>> {
    match e {
        Expr::Array(a) => Some(a.elems.iter().collect()),
        _ => {
            cx.error(e.span(), format!("expected a list `[...]` of {what}"));
            None
        }
    }
}

fn gravity(cx: &mut Ctxt, e: &Expr) -> Option<[Geometry; 3]> {
    let values = array(cx, e, "three values")?;
    if values.len() != 3 {
        cx.error(
            e.span(),
            format!(
                "gravity has {} values; give three in the base frame, e.g. `[0, 0, -9.81]`",
                values.len()
            ),
        );
        return None;
    }
    let g: Vec<Option<Geometry>> = values.iter().map(|v| value(cx, v)).collect();
    Some([g[0].clone()?, g[1].clone()?, g[2].clone()?])
}

fn drive(cx: &mut Ctxt, e: &Expr) -> Option<Drive> {
    let mut d = Drive::NONE;
    for term in array(cx, e, "drive terms `Ia`, `Fv`, `Fc`, `Fo`")? {
        let name = match term {
            Expr::Path(p) => p.path.get_ident().map(|i| i.to_string()),
            _ => None,
        };
        match name.as_deref().map(str::parse::<DriveTerm>) {
            Some(Ok(t)) => d.add(t),
            Some(Err(e)) => cx.error(term.span(), format!("unknown drive term; {}", e.expected)),
            None => cx.error(
                term.span(),
                "a drive term is a name: `Ia` (rotor inertia), `Fv` (viscous), `Fc` (Coulomb) or `Fo` (offset)",
            ),
        }
    }
    Some(d)
}

fn symbols(cx: &mut Ctxt, e: &Expr) -> Vec<(String, f64, Span)> {
    let mut out = Vec::new();
    for s in array(cx, e, "`NAME = value` pairs").unwrap_or_default() {
        let pair = match s {
            Expr::Assign(a) => match (&*a.left, number(&a.right)) {
                (Expr::Path(p), Some(Ok(x))) if p.path.get_ident().is_some() => {
                    Some((p.path.get_ident().map(|i| i.to_string()), x))
                }
                _ => None,
            },
            _ => None,
        };
        match pair {
            Some((Some(name), x)) if x.is_finite() => out.push((name, x, s.span())),
            _ => cx.error(
                s.span(),
                "expected `NAME = number` with a finite number, e.g. `L3 = 0.425`",
            ),
        }
    }
    out
}

/// A joint's values in the order `Spans::joints` keeps their spans: the four DH values
/// (positional), then Khalil and Kleinfinger's `gamma` and `b` (named, optional).
const JOINT_VALUES: [&str; 6] = ["alpha", "a", "d", "theta", "gamma", "b"];

/// The joint syntax, for messages.
const JOINT_SYNTAX: &str = "`revolute(alpha, a, d, theta)` or `prismatic(alpha, a, d, theta)`, \
     optionally followed by `gamma = ...` and `b = ...` (modified convention)";

fn joints(cx: &mut Ctxt, e: &Expr, spans: &mut Vec<[Span; 6]>) -> Option<Vec<Joint>> {
    let rows = array(cx, e, "joints `revolute(alpha, a, d, theta)`")?;
    if rows.is_empty() {
        cx.error(
            e.span(),
            "the robot has no joints; add one entry per DH row",
        );
        return None;
    }
    for r in &rows {
        spans.push(match r {
            Expr::Call(call) => {
                let Arguments {
                    positional, named, ..
                } = arguments(call);
                let mut s = [call.span(); 6];
                for (k, a) in positional.iter().take(4).enumerate() {
                    s[k] = a.span();
                }
                for (key, value) in named {
                    if let Some(k) = JOINT_VALUES[4..].iter().position(|n| key == n) {
                        s[4 + k] = value.span();
                    }
                }
                s
            }
            other => [other.span(); 6],
        });
    }
    let joints: Vec<Option<Joint>> = rows.into_iter().map(|r| joint(cx, r)).collect();
    joints.into_iter().collect()
}

/// The arguments of a joint's call.
struct Arguments<'a> {
    positional: Vec<&'a Expr>,
    /// `key = value`, in order.
    named: Vec<(&'a syn::Ident, &'a Expr)>,
    /// The first positional argument written after a named one.
    late: Option<&'a Expr>,
}

/// A joint call's positional arguments and its named ones (`key = value`), in order.
fn arguments(call: &syn::ExprCall) -> Arguments<'_> {
    let mut positional = Vec::new();
    let mut named = Vec::new();
    let mut late = None;
    for a in &call.args {
        let key = match a {
            Expr::Assign(assign) => match &*assign.left {
                Expr::Path(p) => p.path.get_ident().map(|key| (key, &*assign.right)),
                _ => None,
            },
            _ => None,
        };
        match key {
            Some(key) => named.push(key),
            None => {
                if !named.is_empty() && late.is_none() {
                    late = Some(a);
                }
                positional.push(a);
            }
        }
    }
    Arguments {
        positional,
        named,
        late,
    }
}

fn joint(cx: &mut Ctxt, e: &Expr) -> Option<Joint> {
    let Expr::Call(call) = e else {
        cx.error(e.span(), format!("expected a joint {JOINT_SYNTAX}"));
        return None;
    };
    let kind = match &*call.func {
        Expr::Path(p) if p.path.is_ident("revolute") => Some(JointKind::Revolute),
        Expr::Path(p) if p.path.is_ident("prismatic") => Some(JointKind::Prismatic),
        other => {
            cx.error(
                other.span(),
                "unknown joint type; write `revolute(...)` or `prismatic(...)`",
            );
            None
        }
    };
    let Arguments {
        positional,
        named,
        late,
    } = arguments(call);
    if let Some(late) = late {
        cx.error(
            late.span(),
            format!("the four DH values come first, then the named ones; write {JOINT_SYNTAX}"),
        );
        return None;
    }
    if positional.len() != 4 {
        cx.error(
            e.span(),
            format!(
                "a joint has 4 DH values (alpha, a, d, theta), found {}; write {JOINT_SYNTAX}",
                positional.len()
            ),
        );
        return None;
    }
    let mut extra: [Option<Geometry>; 2] = [None, None];
    let mut ok = true;
    for (key, value) in named {
        let Some(k) = JOINT_VALUES[4..].iter().position(|n| key == n) else {
            cx.error(
                key.span(),
                format!("unknown joint value `{key}`; after the four DH values a joint takes `gamma = ...` and `b = ...`"),
            );
            ok = false;
            continue;
        };
        if extra[k].is_some() {
            cx.error(key.span(), format!("`{key}` is given twice"));
            ok = false;
            continue;
        }
        match self::value(cx, value) {
            Some(v) => extra[k] = Some(v),
            None => ok = false,
        }
    }
    let v: Vec<Option<Geometry>> = positional.iter().map(|a| value(cx, a)).collect();
    let [alpha, a, d, theta] = [v[0].clone()?, v[1].clone()?, v[2].clone()?, v[3].clone()?];
    let joint = Joint::new(kind?, alpha, a, d, theta);
    if !ok {
        return None;
    }
    let [gamma, b] = extra;
    Some(match (gamma, b) {
        (None, None) => joint,
        (gamma, b) => joint.with_gamma_b(
            gamma.unwrap_or_else(Geometry::zero),
            b.unwrap_or_else(Geometry::zero),
        ),
    })
}

/// A number literal (possibly negated); `None` when `e` is not one.
fn number(e: &Expr) -> Option<syn::Result<f64>> {
    match e {
        Expr::Lit(ExprLit {
            lit: Lit::Float(f), ..
        }) => Some(f.base10_parse::<f64>()),
        Expr::Lit(ExprLit {
            lit: Lit::Int(i), ..
        }) => Some(i.base10_parse::<f64>()),
        Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => number(&u.expr).map(|r| r.map(|x| -x)),
        _ => None,
    }
}

/// A DH or gravity value: a finite number or a string expression (its
/// magnitude is checked with the robot, which knows its place).
fn value(cx: &mut Ctxt, e: &Expr) -> Option<Geometry> {
    if let Some(x) = number(e) {
        return match x.map(Geometry::number) {
            Ok(Ok(g)) => Some(g),
            Ok(Err(err)) => {
                cx.error(e.span(), err);
                None
            }
            Err(err) => {
                cx.errors.push(err);
                None
            }
        };
    }
    if let Some(s) = literal(e) {
        return match Geometry::text(&s.value()) {
            Ok(g) => Some(g),
            Err(err) => {
                cx.error(s.span(), err);
                None
            }
        };
    }
    let path = match e {
        Expr::Path(p) => p.path.segments.last().map(|s| s.ident.to_string()),
        _ => None,
    };
    match path.as_deref() {
        Some("NAN" | "INFINITY" | "NEG_INFINITY") => cx.error(
            e.span(),
            "not a finite number; DH values and gravity must be finite numbers, exact angles such as \"pi/2\" or symbols such as \"L3\"",
        ),
        _ => cx.error(
            e.span(),
            "expected a number or a string such as \"pi/2\" or \"-L3\"",
        ),
    }
    None
}
