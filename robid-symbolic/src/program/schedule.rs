//! The parallel computation of a program, as an analysis
//! (docs/performance.md#parallel-schedule): its task graph, the critical path, and list
//! schedules on `P` identical processors by Zomaya's first-fit decreasing and best-fit
//! decreasing rules, with the speed-up they give.
//!
//! Each instruction of a [`Program`] is a task whose cost is its [`Weights`]; it depends on
//! the instructions whose temporaries it reads. Reading inputs and constants and writing
//! outputs cost nothing, and communication between processors is not modelled (shared
//! memory), so the figures are an upper bound on what a real machine achieves.
//!
//! ## Reference
//! A. Y. Zomaya, "Extraction and computation of identifiable parameters in robot dynamic
//! models: theory and application", IEE Proceedings - Control Theory and Applications
//! 141(1), 1994 (section 6.1: the task graph of the Newton-Euler algorithm, its levels,
//! eqs. 32-33, and the FFD/BFD scheduling heuristic).

use super::{Instr, Program, Value};

/// The cost of each kind of instruction, in arbitrary time units.
///
/// The default counts one unit per instruction, as the operation count (`count.rs`) does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Weights {
    /// Additions and subtractions.
    pub add: u64,
    /// Multiplications.
    pub mul: u64,
    /// Negations.
    pub neg: u64,
    /// Divisions.
    pub div: u64,
    /// Sines, cosines, signs and square roots.
    pub function: u64,
}

impl Default for Weights {
    fn default() -> Weights {
        Weights {
            add: 1,
            mul: 1,
            neg: 1,
            div: 1,
            function: 1,
        }
    }
}

impl Weights {
    /// The cost of one instruction.
    pub fn of(&self, instr: &Instr) -> u64 {
        match instr {
            Instr::Add(..) | Instr::Sub(..) => self.add,
            Instr::Mul(..) => self.mul,
            Instr::Neg(_) => self.neg,
            Instr::Div(..) => self.div,
            Instr::Sin(_) | Instr::Cos(_) | Instr::Sign(_) | Instr::Sqrt(_) => self.function,
        }
    }
}

/// The most processors a schedule may use.
pub const MAX_PROCESSORS: usize = 4096;

/// A task graph or a schedule request that cannot be used.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ScheduleError {
    /// The number of processors is 0 or above [`MAX_PROCESSORS`].
    #[error("{0} processors: a schedule needs 1 to {MAX_PROCESSORS}")]
    Processors(usize),
    /// A task depends on itself or on a later task (tasks must be in topological order).
    #[error(
        "task {task} depends on task {predecessor}: tasks must be numbered so that every \
         predecessor comes first"
    )]
    Order {
        /// The task.
        task: usize,
        /// The predecessor that is not earlier.
        predecessor: usize,
    },
    /// The cost and predecessor lists have different lengths.
    #[error("{costs} costs but {predecessors} predecessor lists; give one of each per task")]
    Sizes {
        /// Number of costs.
        costs: usize,
        /// Number of predecessor lists.
        predecessors: usize,
    },
    /// The total cost does not fit in 64 bits.
    #[error("the total cost of the tasks overflows 64 bits; use smaller weights")]
    Overflow,
}

/// A directed acyclic graph of tasks with costs, in topological order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TaskGraph {
    cost: Vec<u64>,
    preds: Vec<Vec<usize>>,
}

/// The longest path through a task graph, weighted by cost.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CriticalPath {
    /// Its length: no schedule finishes earlier.
    pub length: u64,
    /// Its tasks, first to last.
    pub tasks: Vec<usize>,
}

impl TaskGraph {
    /// A graph from each task's cost and predecessors; every predecessor must be an
    /// earlier task (which also rules out cycles).
    ///
    /// ```
    /// use robid_symbolic::program::schedule::TaskGraph;
    /// // 0 and 1 independent, 2 needs both
    /// let g = TaskGraph::new(vec![3, 1, 2], vec![vec![], vec![], vec![0, 1]]).unwrap();
    /// assert_eq!(g.total(), 6);
    /// assert_eq!(g.critical_path().length, 5);
    /// assert!(TaskGraph::new(vec![1, 1], vec![vec![1], vec![]]).is_err());
    /// ```
    pub fn new(cost: Vec<u64>, preds: Vec<Vec<usize>>) -> Result<TaskGraph, ScheduleError> {
        if cost.len() != preds.len() {
            return Err(ScheduleError::Sizes {
                costs: cost.len(),
                predecessors: preds.len(),
            });
        }
        for (task, ps) in preds.iter().enumerate() {
            if let Some(&predecessor) = ps.iter().find(|&&p| p >= task) {
                return Err(ScheduleError::Order { task, predecessor });
            }
        }
        cost.iter()
            .try_fold(0u64, |a, &c| a.checked_add(c))
            .ok_or(ScheduleError::Overflow)?;
        Ok(TaskGraph { cost, preds })
    }

    /// The task graph of a program: one task per instruction, an edge from each
    /// instruction whose temporary it reads.
    pub fn from_program(program: &Program, weights: &Weights) -> Result<TaskGraph, ScheduleError> {
        let cost = program.instrs.iter().map(|i| weights.of(i)).collect();
        let preds = program
            .instrs
            .iter()
            .map(|i| {
                let mut ps: Vec<usize> = i
                    .operands()
                    .into_iter()
                    .filter_map(|v| match v {
                        Value::Temp(t) => Some(t as usize),
                        _ => None,
                    })
                    .collect();
                ps.dedup();
                ps
            })
            .collect();
        TaskGraph::new(cost, preds)
    }

    /// Number of tasks.
    pub fn len(&self) -> usize {
        self.cost.len()
    }

    /// True without tasks.
    pub fn is_empty(&self) -> bool {
        self.cost.is_empty()
    }

    /// Cost of task `task`.
    pub fn cost(&self, task: usize) -> u64 {
        self.cost[task]
    }

    /// Predecessors of task `task`.
    pub fn predecessors(&self, task: usize) -> &[usize] {
        &self.preds[task]
    }

    /// Number of edges.
    pub fn edges(&self) -> usize {
        self.preds.iter().map(Vec::len).sum()
    }

    /// The serial time: the sum of the costs (checked not to overflow on construction).
    pub fn total(&self) -> u64 {
        self.cost.iter().sum()
    }

    /// Each task's level (Zomaya's Fig. 3): 0 without predecessors, otherwise one more
    /// than its highest predecessor. Tasks of one level are independent.
    pub fn levels(&self) -> Vec<usize> {
        let mut level = vec![0; self.len()];
        for t in 0..self.len() {
            level[t] = self.preds[t]
                .iter()
                .map(|&p| level[p] + 1)
                .max()
                .unwrap_or(0);
        }
        level
    }

    /// Zomaya's estimate of the parallel time (eqs. 32-33): the sum over the levels of
    /// the costliest task of each level, as if each level ran at once with a barrier
    /// between levels. It is at least the critical path.
    pub fn level_estimate(&self) -> u64 {
        let level = self.levels();
        let depth = level.iter().max().map_or(0, |d| d + 1);
        let mut costliest = vec![0u64; depth];
        for (t, &l) in level.iter().enumerate() {
            costliest[l] = costliest[l].max(self.cost[t]);
        }
        costliest.iter().sum()
    }

    /// The longest path weighted by cost (ties go to the first predecessor listed and the
    /// lowest-numbered last task).
    pub fn critical_path(&self) -> CriticalPath {
        let mut finish = vec![0u64; self.len()];
        let mut via = vec![None; self.len()];
        for t in 0..self.len() {
            let mut start = 0;
            for &p in &self.preds[t] {
                if finish[p] > start || via[t].is_none() && finish[p] == start {
                    start = finish[p];
                    via[t] = Some(p);
                }
            }
            finish[t] = start + self.cost[t];
        }
        let Some(last) = (0..self.len()).max_by_key(|&t| (finish[t], core::cmp::Reverse(t))) else {
            return CriticalPath {
                length: 0,
                tasks: Vec::new(),
            };
        };
        let mut tasks = vec![last];
        let mut current = last;
        while let Some(p) = via[current] {
            tasks.push(p);
            current = p;
        }
        tasks.reverse();
        CriticalPath {
            length: finish[last],
            tasks,
        }
    }
}

/// How a task picks its processor among those free when it becomes ready.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Rule {
    /// First fit: the lowest-numbered processor free when the task is ready.
    FirstFit,
    /// Best fit: the free processor that stays idle the shortest before the task (the
    /// one that became free last); ties go to the lowest number.
    BestFit,
}

impl Rule {
    /// The paper's abbreviation, with the decreasing order of the list: `FFD` or `BFD`.
    pub fn name(self) -> &'static str {
        match self {
            Rule::FirstFit => "FFD",
            Rule::BestFit => "BFD",
        }
    }
}

/// Where and when a task runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Placement {
    /// The processor, from 0.
    pub processor: usize,
    /// Start time.
    pub start: u64,
    /// Finish time (start + cost).
    pub finish: u64,
}

/// A schedule of a task graph on identical processors.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Schedule {
    /// The rule used.
    pub rule: Rule,
    /// Number of processors.
    pub processors: usize,
    /// Where each task runs, by task number.
    pub placements: Vec<Placement>,
    /// When the last task finishes.
    pub makespan: u64,
    /// The serial time (sum of the costs).
    pub serial: u64,
}

impl Schedule {
    /// Serial time over makespan (1 for an empty graph).
    pub fn speed_up(&self) -> f64 {
        if self.makespan == 0 {
            1.0
        } else {
            self.serial as f64 / self.makespan as f64
        }
    }

    /// Speed-up over the number of processors.
    pub fn efficiency(&self) -> f64 {
        self.speed_up() / self.processors as f64
    }

    /// The tasks on processor `p`, in start order.
    pub fn tasks_on(&self, p: usize) -> Vec<usize> {
        let mut tasks: Vec<usize> = (0..self.placements.len())
            .filter(|&t| self.placements[t].processor == p)
            .collect();
        tasks.sort_by_key(|&t| self.placements[t].start);
        tasks
    }

    /// The busy time of processor `p`.
    pub fn load(&self, p: usize) -> u64 {
        self.placements
            .iter()
            .filter(|x| x.processor == p)
            .map(|x| x.finish - x.start)
            .sum()
    }
}

/// The priority list: by level (Zomaya's Fig. 3), within a level by decreasing cost (the
/// "decreasing" of FFD and BFD), then by task number. Predecessors come first.
pub fn priority_list(graph: &TaskGraph) -> Vec<usize> {
    let level = graph.levels();
    let mut list: Vec<usize> = (0..graph.len()).collect();
    list.sort_by_key(|&t| (level[t], core::cmp::Reverse(graph.cost[t]), t));
    list
}

/// List scheduling on `processors` identical processors: the tasks of
/// [`priority_list`] are placed in turn, each on a processor chosen by `rule` among those
/// free when its predecessors have finished, or (when none is) on the one free first, and
/// never moved afterwards. A processor runs one task at a time, from start to finish.
///
/// ```
/// use robid_symbolic::program::schedule::{Rule, TaskGraph, schedule};
/// let g = TaskGraph::new(vec![2, 2, 1], vec![vec![], vec![], vec![0, 1]]).unwrap();
/// let s = schedule(&g, 2, Rule::FirstFit).unwrap();
/// assert_eq!(s.makespan, 3);
/// assert_eq!(s.speed_up(), 5.0 / 3.0);
/// ```
pub fn schedule(
    graph: &TaskGraph,
    processors: usize,
    rule: Rule,
) -> Result<Schedule, ScheduleError> {
    if !(1..=MAX_PROCESSORS).contains(&processors) {
        return Err(ScheduleError::Processors(processors));
    }
    let mut free = vec![0u64; processors];
    let unplaced = Placement {
        processor: 0,
        start: 0,
        finish: 0,
    };
    let mut placements = vec![unplaced; graph.len()];
    for t in priority_list(graph) {
        let ready = graph.preds[t]
            .iter()
            .map(|&p| placements[p].finish)
            .max()
            .unwrap_or(0);
        let available = (0..processors).filter(|&p| free[p] <= ready);
        let chosen = match rule {
            Rule::FirstFit => available.min(),
            // the latest free time is the shortest idle gap; max_by_key keeps the last
            // maximum, so reverse the order to keep the lowest number on ties
            Rule::BestFit => available.rev().max_by_key(|&p| free[p]),
        };
        // none free: the one free first (min_by_key keeps the first, lowest-numbered, minimum)
        let processor =
            chosen.unwrap_or_else(|| (0..processors).min_by_key(|&p| free[p]).unwrap_or(0));
        let start = ready.max(free[processor]);
        let finish = start + graph.cost[t];
        free[processor] = finish;
        placements[t] = Placement {
            processor,
            start,
            finish,
        };
    }
    Ok(Schedule {
        rule,
        processors,
        makespan: free.iter().copied().max().unwrap_or(0),
        serial: graph.total(),
        placements,
    })
}

#[cfg(test)]
mod tests;
