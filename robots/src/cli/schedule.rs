//! `robid model ROBOT.toml --schedule P`: the parallel computation of one derived program
//! in the form of Zomaya's Tables 2-4 (docs/performance.md#parallel-schedule).

use super::Error;
use robid_runtime::model::ProgramKind;
use robid_symbolic::program::schedule::{Rule, Schedule, TaskGraph, Weights, schedule};
use robid_symbolic::program::{Instr, RobotPrograms};
use serde::Serialize;

/// One processor of a schedule (the paper's Tables 2 and 3 count operations per task; here
/// per processor).
#[derive(Serialize)]
pub(crate) struct Processor {
    tasks: usize,
    mul: usize,
    add: usize,
    other: usize,
    load: u64,
}

/// One rule's schedule.
#[derive(Serialize)]
pub(crate) struct RuleReport {
    rule: &'static str,
    makespan: u64,
    speed_up: f64,
    efficiency: f64,
    processors: Vec<Processor>,
}

/// Makespans and speed-ups for one number of processors.
#[derive(Serialize)]
pub(crate) struct Scaling {
    processors: usize,
    ffd_makespan: u64,
    ffd_speed_up: f64,
    bfd_makespan: u64,
    bfd_speed_up: f64,
}

/// The analysis printed by `--schedule`.
#[derive(Serialize)]
pub(crate) struct Report {
    program: &'static str,
    processors: usize,
    tasks: usize,
    edges: usize,
    levels: usize,
    serial: u64,
    critical_path: u64,
    level_estimate: u64,
    rules: Vec<RuleReport>,
    scaling: Vec<Scaling>,
}

/// The program called `name`, or an error listing the names.
pub(crate) fn program_kind(name: &str) -> Result<ProgramKind, Error> {
    ProgramKind::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = ProgramKind::ALL.iter().map(|k| k.info().name).collect();
        format!(
            "--schedule-program {}: no such program; use one of {}",
            robid_runtime::names::short(name),
            names.join(", ")
        )
        .into()
    })
}

/// The numbers of processors of the scaling table: 1 to `p`, or powers of two and `p`
/// beyond 16.
fn counts(p: usize) -> Vec<usize> {
    if p <= 16 {
        return (1..=p).collect();
    }
    let mut c: Vec<usize> = (0..).map(|k| 1 << k).take_while(|&n| n < p).collect();
    c.push(p);
    c
}

/// Schedules program `kind` of `programs` on `p` processors by both rules, one unit of
/// time per operation.
pub(crate) fn analyse(
    programs: &RobotPrograms,
    kind: ProgramKind,
    p: usize,
) -> Result<Report, Error> {
    let program = &programs[kind];
    let graph = TaskGraph::from_program(program, &Weights::default())?;
    // no task: no makespan to divide by (a speed-up of 1 and an efficiency of 1 / p were
    // printed for 0 / 0)
    if graph.is_empty() {
        return Err(format!(
            "--schedule-program {}: the program has no operations for this robot (its outputs \
             are inputs or constants as they are): nothing to schedule; choose another \
             program",
            kind.info().name
        )
        .into());
    }
    let one = |rule: Rule| -> Result<RuleReport, Error> {
        let s = schedule(&graph, p, rule)?;
        Ok(RuleReport {
            rule: rule.name(),
            makespan: s.makespan,
            speed_up: s.speed_up(),
            efficiency: s.efficiency(),
            processors: (0..p).map(|q| processor(program, &s, q)).collect(),
        })
    };
    let rules = vec![one(Rule::FirstFit)?, one(Rule::BestFit)?];
    let mut scaling = Vec::new();
    for n in counts(p) {
        let ffd = schedule(&graph, n, Rule::FirstFit)?;
        let bfd = schedule(&graph, n, Rule::BestFit)?;
        scaling.push(Scaling {
            processors: n,
            ffd_makespan: ffd.makespan,
            ffd_speed_up: ffd.speed_up(),
            bfd_makespan: bfd.makespan,
            bfd_speed_up: bfd.speed_up(),
        });
    }
    Ok(Report {
        program: kind.info().name,
        processors: p,
        tasks: graph.len(),
        edges: graph.edges(),
        levels: graph.levels().iter().max().map_or(0, |l| l + 1),
        serial: graph.total(),
        critical_path: graph.critical_path().length,
        level_estimate: graph.level_estimate(),
        rules,
        scaling,
    })
}

fn processor(program: &robid_symbolic::program::Program, s: &Schedule, q: usize) -> Processor {
    let tasks = s.tasks_on(q);
    let (mut mul, mut add, mut other) = (0, 0, 0);
    for &t in &tasks {
        match program.instrs[t] {
            Instr::Mul(..) => mul += 1,
            Instr::Add(..) | Instr::Sub(..) => add += 1,
            _ => other += 1,
        }
    }
    Processor {
        tasks: tasks.len(),
        mul,
        add,
        other,
        load: s.load(q),
    }
}

/// The report as text, in the form of the paper's Tables 2-4.
pub(crate) fn text(r: &Report) -> String {
    use std::fmt::Write;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "\nparallel schedule of {} (Zomaya 1994, section 6.1; one time unit per operation, \
         no communication cost):",
        r.program
    );
    let _ = writeln!(
        out,
        "  task graph: {} tasks, {} edges, {} levels; serial time {}, critical path {}, \
         level estimate (eqs. 32-33) {}",
        r.tasks, r.edges, r.levels, r.serial, r.critical_path, r.level_estimate
    );
    let _ = writeln!(
        out,
        "\n  per processor, on {} (tasks, multiplications, additions, other operations, \
         busy time):",
        robid_runtime::Count(r.processors, "processor")
    );
    let mut head = String::from("      ");
    let mut cols = String::from("  proc");
    for x in &r.rules {
        let _ = write!(head, "  {:-^34}", format!(" {} ", x.rule));
        let _ = write!(
            cols,
            "  {:>6} {:>6} {:>6} {:>6} {:>6}",
            "tasks", "mul", "add", "other", "load"
        );
    }
    let _ = writeln!(out, "{head}\n{cols}");
    for q in 0..r.processors {
        let mut line = format!("  {:>4}", q + 1);
        for x in &r.rules {
            let p = &x.processors[q];
            let _ = write!(
                line,
                "  {:>6} {:>6} {:>6} {:>6} {:>6}",
                p.tasks, p.mul, p.add, p.other, p.load
            );
        }
        let _ = writeln!(out, "{line}");
    }
    let _ = writeln!(
        out,
        "\n  {:<5} {:>9} {:>9} {:>11}",
        "rule", "makespan", "speed-up", "efficiency"
    );
    for x in &r.rules {
        let _ = writeln!(
            out,
            "  {:<5} {:>9} {:>9.2} {:>10.1}%",
            x.rule,
            x.makespan,
            x.speed_up,
            100.0 * x.efficiency
        );
    }
    let _ = writeln!(
        out,
        "\n  {:>4} {:>13} {:>9} {:>13} {:>9}",
        "P", "FFD makespan", "speed-up", "BFD makespan", "speed-up"
    );
    for s in &r.scaling {
        let _ = writeln!(
            out,
            "  {:>4} {:>13} {:>9.2} {:>13} {:>9.2}",
            s.processors, s.ffd_makespan, s.ffd_speed_up, s.bfd_makespan, s.bfd_speed_up
        );
    }
    out
}
