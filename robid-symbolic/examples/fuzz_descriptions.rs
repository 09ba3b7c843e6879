//! A seeded mutation fuzzer for robot descriptions:
//!
//! ```sh
//! cargo run --release -p robid-symbolic --example fuzz_descriptions -- CASES [SEED] [DERIVE_SECONDS]
//! ```
//!
//! Each case mutates one of the reference descriptions or a general one with
//! Khalil-Kleinfinger `gamma` and `b`, a `[base]` and a `[tool]` (byte flips,
//! deletions, duplications, splices from another description, numbers
//! replaced by extremes such as 1e308, NaN, -0 or 1e-320, values replaced by
//! deeply nested or long expressions, keys and names replaced) and reads it
//! with `Robot::from_toml`. Robots that read are derived
//! (`RobotPrograms::derive`, each distinct robot once, while the derivation
//! time stays within DERIVE_SECONDS, default 60) and emitted. A finding is a
//! panic, a case slower than its budget, or a non-finite number in a base
//! parameter's expression, a program constant or a program's outputs at a
//! sample input; a watchdog ends the process (exit status 2) with the input
//! on stderr when one case runs for more than `HANG_SECONDS`. The summary
//! says how many cases were read, derived and emitted, and what was found
//! (exit status 1 when anything was). The test `fuzz_descriptions_quick`
//! runs a few thousand cases through the same code.

#![allow(dead_code)]

use robid_core::rng::Rng;
use robid_symbolic::Robot;
use robid_symbolic::emit::emit_programs;
use robid_symbolic::program::{Program, RobotPrograms};
use std::collections::HashSet;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// A general description: Khalil-Kleinfinger `gamma` and `b`, a `[base]` and a `[tool]`
/// (docs/conventions.md#khalil-kleinfinger-general-frames).
const GENERAL: &str = r#"name = "general"
convention = "modified"
gravity = [0, 0, -9.81]
drive = ["Ia", "Fv"]

[base]
xyz = [0.1, 0, 1.2]
rpy = ["pi/2", 0, 0.3]

[tool]
xyz = [0, 0, "L_tool"]
rpy = [0, "-pi/2", 0]

[symbols]
L_tool = 0.1

[[joints]]
alpha = 0
a = 0
d = 0.2

[[joints]]
gamma = "pi/2"
b = 0.05
alpha = "-pi/2"
a = 0.1
d = 0
theta = 0

[[joints]]
type = "prismatic"
gamma = 0.4
b = -0.1
alpha = "pi/2"
a = 0.3
d = 0.1
theta = "pi/2"
"#;

/// The descriptions the mutations start from: the reference robots and [`GENERAL`].
const SEEDS: [&str; 8] = [
    GENERAL,
    include_str!("../../robots/descriptions/ur5e.toml"),
    include_str!("../../robots/descriptions/puma560.toml"),
    include_str!("../../robots/descriptions/rx90.toml"),
    include_str!("../../robots/descriptions/tx40.toml"),
    include_str!("../../robots/descriptions/lwr4.toml"),
    include_str!("../../robots/descriptions/panda.toml"),
    include_str!("../../robots/descriptions/stanford.toml"),
];

/// A case that runs longer than this is a hang: the watchdog ends the process.
const HANG_SECONDS: u64 = 120;

/// Reading one description must take less than this.
const READ_BUDGET: Duration = Duration::from_secs(1);

/// Deriving and emitting one robot must take less than this (a 32-joint
/// chain with every drive term takes a few seconds).
const DERIVE_BUDGET: Duration = Duration::from_secs(60);

/// What a run is asked to do.
#[derive(Clone, Debug)]
pub(crate) struct Config {
    /// Number of cases (description reads).
    pub(crate) cases: u64,
    /// Seed of the mutations.
    pub(crate) seed: u64,
    /// Derivations stop once they have taken this long in total.
    pub(crate) derive_time: Duration,
}

/// What a run did and found.
#[derive(Debug, Default)]
pub(crate) struct Report {
    /// Cases read.
    pub(crate) cases: u64,
    /// Cases that read as a robot.
    pub(crate) robots: u64,
    /// Distinct robots derived.
    pub(crate) derived: u64,
    /// Derivations that returned an error (not a finding).
    pub(crate) derive_errors: u64,
    /// The first few of those errors, with their input.
    pub(crate) derive_error_examples: Vec<String>,
    /// Robots emitted as Rust.
    pub(crate) emitted: u64,
    /// Problems, each with the case's input (shortened).
    pub(crate) findings: Vec<String>,
    /// Time taken.
    pub(crate) elapsed: Duration,
}

/// The case running now, for the watchdog: its number and start.
struct Current {
    started: Instant,
    case: AtomicU64,
    since: AtomicU64,
    input: Mutex<String>,
}

/// Runs the fuzzer.
pub(crate) fn run(config: &Config) -> Report {
    let start = Instant::now();
    let current = Arc::new(Current {
        started: Instant::now(),
        case: AtomicU64::new(0),
        since: AtomicU64::new(0),
        input: Mutex::new(String::new()),
    });
    watchdog(Arc::clone(&current));
    let previous_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let mut rng = Rng::from_state(config.seed);
    let mut report = Report::default();
    let mut seen: HashSet<String> = HashSet::new();
    let mut derive_time = Duration::ZERO;
    for case in 0..config.cases {
        let text = mutate(&mut rng);
        current.case.store(case, Ordering::Relaxed);
        current.since.store(
            current.started.elapsed().as_millis() as u64,
            Ordering::Relaxed,
        );
        if let Ok(mut input) = current.input.lock() {
            input.clone_from(&text);
        }
        report.cases += 1;
        if case > 0 && case % 100_000 == 0 {
            eprintln!(
                "{case} cases, {} robots, {} derived, {} findings, {:.0} s",
                report.robots,
                report.derived,
                report.findings.len(),
                start.elapsed().as_secs_f64()
            );
        }
        let t = Instant::now();
        let read = std::panic::catch_unwind(|| Robot::from_toml(&text, "fuzz.toml"));
        let elapsed = t.elapsed();
        let find = |report: &mut Report, what: String| {
            report
                .findings
                .push(format!("case {case}: {what}\n{}", shorten(&text)));
        };
        if elapsed > READ_BUDGET {
            find(&mut report, format!("reading took {elapsed:?}"));
        }
        let robot = match read {
            Err(panic) => {
                find(
                    &mut report,
                    format!("reading panicked: {}", message(&panic)),
                );
                continue;
            }
            Ok(Err(e)) => {
                if e.to_string().contains("NaN") && !text.to_lowercase().contains("nan") {
                    find(&mut report, format!("error mentions NaN: {e}"));
                }
                continue;
            }
            Ok(Ok(robot)) => robot,
        };
        report.robots += 1;
        if derive_time >= config.derive_time || !seen.insert(format!("{robot:?}")) {
            continue;
        }
        let t = Instant::now();
        let derived = std::panic::catch_unwind(|| derive_and_check(&robot));
        let elapsed = t.elapsed();
        derive_time += elapsed;
        if elapsed > DERIVE_BUDGET {
            find(&mut report, format!("deriving took {elapsed:?}"));
        }
        match derived {
            Err(panic) => find(
                &mut report,
                format!("deriving panicked: {}", message(&panic)),
            ),
            Ok(Outcome::DeriveError(e)) => {
                report.derived += 1;
                report.derive_errors += 1;
                if report.derive_error_examples.len() < 5 {
                    report
                        .derive_error_examples
                        .push(format!("case {case}: {e}\n{}", shorten(&text)));
                }
            }
            Ok(Outcome::Emitted) => {
                report.derived += 1;
                report.emitted += 1;
            }
            Ok(Outcome::Finding(what)) => {
                report.derived += 1;
                find(&mut report, what);
            }
        }
    }
    std::panic::set_hook(previous_hook);
    current.case.store(u64::MAX, Ordering::Relaxed);
    report.elapsed = start.elapsed();
    report
}

enum Outcome {
    DeriveError(String),
    Emitted,
    Finding(String),
}

/// Derives, checks every number the derivation produced, and emits.
fn derive_and_check(robot: &Robot) -> Outcome {
    let programs = match RobotPrograms::derive(robot) {
        Ok(p) => p,
        Err(e) => return Outcome::DeriveError(e.to_string()),
    };
    // Symbols cannot be named inf or nan: such a word is a number.
    for b in &programs.base {
        let words = b.expression.split(|c: char| !c.is_ascii_alphanumeric());
        if words
            .map(str::to_lowercase)
            .any(|w| w == "inf" || w == "nan")
        {
            return Outcome::Finding(format!("base parameter {} = {}", b.name, b.expression));
        }
    }
    for (info, program) in programs.iter() {
        let name = info.name;
        if let Some(c) = program.constants.iter().find(|c| !c.is_finite()) {
            return Outcome::Finding(format!("{name} has the constant {c}"));
        }
        if let Some(what) = outputs_not_finite(program) {
            return Outcome::Finding(format!("{name}: {what}"));
        }
    }
    match emit_programs(&programs) {
        Ok(_) => Outcome::Emitted,
        Err(e) => Outcome::Finding(format!("emission failed: {e}")),
    }
}

/// Runs `program` at a moderate input (every element 0.5, symbols at their
/// values); a non-finite output is reported.
fn outputs_not_finite(program: &Program) -> Option<String> {
    let inputs: Vec<Vec<f64>> = program.inputs.iter().map(|g| vec![0.5; g.len()]).collect();
    let refs: Vec<&[f64]> = inputs.iter().map(Vec::as_slice).collect();
    match program.eval(&refs) {
        Err(e) => Some(format!("cannot run: {e}")),
        Ok(outs) => outs
            .iter()
            .flatten()
            .find(|v| !v.is_finite())
            .map(|v| format!("an output is {v} at input 0.5")),
    }
}

/// Ends the process when a case runs longer than [`HANG_SECONDS`].
fn watchdog(current: Arc<Current>) {
    std::thread::spawn(move || {
        loop {
            std::thread::sleep(Duration::from_millis(500));
            let case = current.case.load(Ordering::Relaxed);
            if case == u64::MAX {
                return;
            }
            let since = current.since.load(Ordering::Relaxed);
            let now = current.started.elapsed().as_millis() as u64;
            if now.saturating_sub(since) > HANG_SECONDS * 1000
                && current.case.load(Ordering::Relaxed) == case
            {
                let input = current.input.lock().map(|s| s.clone()).unwrap_or_default();
                eprintln!("case {case} runs for more than {HANG_SECONDS} s (a hang):\n{input}");
                std::process::exit(2);
            }
        }
    });
}

fn message(panic: &Box<dyn std::any::Any + Send>) -> String {
    panic
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
        .unwrap_or_else(|| "(no message)".to_owned())
}

fn shorten(text: &str) -> String {
    match text.char_indices().nth(2000) {
        Some((i, _)) => format!("{}... ({} bytes)", &text[..i], text.len()),
        None => text.to_owned(),
    }
}

/// Numbers at and past the ends of every range, special floats and integers.
const NUMBERS: [&str; 40] = [
    "1e308",
    "-1e308",
    "1.8e308",
    "1e-320",
    "-1e-320",
    "-0",
    "0",
    "-0.0",
    "nan",
    "-nan",
    "inf",
    "-inf",
    "1e200",
    "-1e200",
    "1e-7",
    "1e-6",
    "-1e-6",
    "1e3",
    "-1e3",
    "1000.0001",
    "1e4",
    "1e-3",
    "-1e-3",
    "9.99e-4",
    "6.283185307179586",
    "6.2832",
    "1.5707963",
    "1.5707963267948966",
    "1.57081",
    "3.1415926",
    "90",
    "-9.81",
    "-9810",
    "9999999999999999999999",
    "0x7fffffffffffffff",
    "-9223372036854775808",
    "1_000",
    "+1",
    "0.1625",
    "1e-5",
];

/// Expressions for string values: extremes of each limit and known traps.
fn expression(rng: &mut Rng) -> String {
    let depth = [1, 10, 63, 64, 65, 100, 1000, 20_000][rng.below(8)];
    match rng.below(22) {
        0 => format!("{}L1{}", "(".repeat(depth), ")".repeat(depth)),
        1 => format!("{}L1", "-".repeat(depth)),
        2 => format!("{}0.5{}", "sin(".repeat(depth), ")".repeat(depth)),
        3 => format!("{}x{}", "-(".repeat(depth), ")".repeat(depth)),
        4 => "2^1024".to_owned(),
        5 => "x^99999999".to_owned(),
        6 => "L1/(L2 - L2)".to_owned(),
        7 => format!("L{}", "x".repeat([10, 1000, 5000][rng.below(3)])),
        8 => [
            "self", "q1", "XX2", "pi", "sin(x)", "sqrt(L)", "sign(L)", "_",
        ][rng.below(8)]
        .to_owned(),
        9 => "1e300*1e300".to_owned(),
        10 => "pi/2 + 1e-7".to_owned(),
        11 => format!("L1^{}", rng.below(140) as i64 - 70),
        12 => format!("(L1 + L2)^{}", rng.below(140) as i64 - 70),
        13 => vec!["L1"; [10, 1000, 3000][rng.below(3)]].join("*"),
        14 => (0..[10, 500, 2000][rng.below(3)])
            .map(|i| format!("x{i}"))
            .collect::<Vec<_>>()
            .join("+"),
        15 => "1e5*L".to_owned(),
        16 => format!("{}*L1", NUMBERS[rng.below(NUMBERS.len())]),
        17 => "L1 - L1".to_owned(),
        18 => "pi/".to_owned(),
        19 => "-pi/2".to_owned(),
        20 => format!(
            "{} + {}",
            NUMBERS[rng.below(NUMBERS.len())],
            NUMBERS[rng.below(NUMBERS.len())]
        ),
        _ => String::new(),
    }
}

/// Lines that can be added anywhere.
fn line(rng: &mut Rng) -> String {
    let key = [
        "name",
        "convention",
        "gravity",
        "drive",
        "alpha",
        "a",
        "d",
        "theta",
        "type",
        "limits",
        "L1",
        "l1",
        "D3",
        "colour",
        "gamma",
        "b",
        "xyz",
        "rpy",
        "base",
        "tool",
    ][rng.below(20)];
    let value = match rng.below(8) {
        0 => NUMBERS[rng.below(NUMBERS.len())].to_owned(),
        1 => format!("\"{}\"", expression(rng)),
        2 => format!(
            "[{}, {}, {}]",
            NUMBERS[rng.below(NUMBERS.len())],
            NUMBERS[rng.below(NUMBERS.len())],
            NUMBERS[rng.below(NUMBERS.len())]
        ),
        3 => "{ position = [1, 2, 3], velocity = -1 }".to_owned(),
        4 => [
            "\"self\"",
            "\"fn\"",
            "\"Self\"",
            "\"my arm\"",
            "\"crate\"",
            "\"standard\"",
            "\"prismatic\"",
            "[\"Ia\", \"Fv\", \"Fc\", \"Fo\"]",
        ][rng.below(8)]
        .to_owned(),
        5 => format!("\"{}\"", "a".repeat([1, 100, 100_000][rng.below(3)])),
        6 => "[]".to_owned(),
        _ => "{ }".to_owned(),
    };
    match rng.below(8) {
        0 => format!("\n[symbols]\n{key} = {value}\n"),
        1 => format!("\n[[joints]]\n{key} = {value}\n"),
        2 => format!("\n[base]\n{key} = {value}\n"),
        3 => format!("\n[tool]\n{key} = {value}\n"),
        _ => format!("\n{key} = {value}\n"),
    }
}

/// One case: a reference description with one to four mutations.
pub(crate) fn mutate(rng: &mut Rng) -> String {
    let mut text: Vec<u8> = SEEDS[rng.below(SEEDS.len())].as_bytes().to_vec();
    for _ in 0..1 + rng.below(4) {
        mutate_once(rng, &mut text);
    }
    String::from_utf8_lossy(&text).into_owned()
}

fn mutate_once(rng: &mut Rng, text: &mut Vec<u8>) {
    let len = text.len().max(1);
    let at = rng.below(len).min(text.len());
    let span = |rng: &mut Rng, text: &Vec<u8>, at: usize| {
        let n = 1 + rng.below(64);
        at..(at + n).min(text.len())
    };
    match rng.below(10) {
        0 => {
            if let Some(b) = text.get_mut(at) {
                *b ^= 1 << rng.below(8);
            }
        }
        1 => {
            const BYTES: &[u8] = b"\"[]{}=,.-+*/^()\n#'\\eE0123456789pi_ ";
            if let Some(b) = text.get_mut(at) {
                *b = BYTES[rng.below(BYTES.len())];
            }
        }
        2 => {
            let r = span(rng, text, at);
            text.drain(r);
        }
        3 => {
            let r = span(rng, text, at);
            let copy: Vec<u8> = text[r].to_vec();
            let to = rng.below(text.len() + 1);
            for _ in 0..1 + rng.below(3) {
                text.splice(to..to, copy.iter().copied());
            }
        }
        4 => {
            // Whole joint tables, repeated (joint counts up to and past the limit).
            let s = String::from_utf8_lossy(text).into_owned();
            if let Some(i) = s.find("[[joints]]") {
                let block: String = s[i..].split("\n\n").next().unwrap_or("").to_owned();
                let times = [1, 5, 26, 30][rng.below(4)];
                let mut out = s.clone();
                for _ in 0..times {
                    out.push_str("\n\n");
                    out.push_str(&block);
                }
                *text = out.into_bytes();
            }
        }
        5 => {
            let other = SEEDS[rng.below(SEEDS.len())].as_bytes();
            let from = rng.below(other.len());
            let r = from..(from + 1 + rng.below(200)).min(other.len());
            text.splice(at..at, other[r].iter().copied());
        }
        6 | 7 => {
            // A number token replaced by an extreme.
            let s = String::from_utf8_lossy(text).into_owned();
            let starts: Vec<usize> = s
                .char_indices()
                .filter(|&(i, c)| {
                    (c.is_ascii_digit() || c == '-')
                        && (i == 0 || !s.as_bytes()[i - 1].is_ascii_alphanumeric())
                })
                .map(|(i, _)| i)
                .collect();
            if starts.is_empty() {
                return;
            }
            let start = starts[rng.below(starts.len())];
            let end = s[start..]
                .find(|c: char| !(c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '+' | '_')))
                .map_or(s.len(), |k| start + k);
            let with = if rng.below(3) == 0 {
                format!("\"{}\"", expression(rng))
            } else {
                NUMBERS[rng.below(NUMBERS.len())].to_owned()
            };
            let mut out = s[..start].to_owned();
            out.push_str(&with);
            out.push_str(&s[end..]);
            *text = out.into_bytes();
        }
        8 => {
            // A quoted value replaced.
            let s = String::from_utf8_lossy(text).into_owned();
            let quotes: Vec<usize> = s.match_indices('"').map(|(i, _)| i).collect();
            if quotes.len() < 2 {
                return;
            }
            let k = rng.below(quotes.len() / 2) * 2;
            let (open, close) = (quotes[k], quotes[k + 1]);
            let mut out = s[..=open].to_owned();
            out.push_str(&expression(rng));
            out.push_str(&s[close..]);
            *text = out.into_bytes();
        }
        _ => {
            let l = line(rng);
            text.splice(at..at, l.bytes());
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let number = |i: usize, default: u64| -> u64 {
        match args.get(i).map(|a| a.parse::<u64>()) {
            None => default,
            Some(Ok(n)) => n,
            Some(Err(_)) => {
                eprintln!(
                    "usage: fuzz_descriptions CASES [SEED] [DERIVE_SECONDS] (whole numbers); got `{}`",
                    args[i]
                );
                std::process::exit(2);
            }
        }
    };
    let config = Config {
        cases: number(0, 10_000),
        seed: number(1, 1),
        derive_time: Duration::from_secs(number(2, 60)),
    };
    let report = run(&config);
    println!(
        "{} cases in {:.1} s (seed {}): {} read as robots, {} distinct robots derived ({} derivation errors), {} emitted; {} findings",
        report.cases,
        report.elapsed.as_secs_f64(),
        config.seed,
        report.robots,
        report.derived,
        report.derive_errors,
        report.emitted,
        report.findings.len()
    );
    for f in report.findings.iter().take(20) {
        println!("\n{f}");
    }
    for e in &report.derive_error_examples {
        println!("\nderivation error (returned, not a finding): {e}");
    }
    if !report.findings.is_empty() {
        std::process::exit(1);
    }
}
