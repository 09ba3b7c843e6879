use super::*;
use crate::Robot;
use crate::program::RobotPrograms;
use robid_core::ProgramKind;

/// Seven tasks on which the two rules differ (worked out by hand):
///
/// ```text
/// 0 Y(3) -> 3 U(1) -> 5 V(2) -> 6 S(1)
/// 1 X(1) -> 2 Z(5) -> 4 W(2)
/// ```
///
/// Priority list (level, then decreasing cost): Y X | Z U | W V | S. On two processors
/// both rules place Y on 0 at [0,3], X on 1 at [0,1], Z on 1 at [1,6], U on 0 at [3,4].
/// W is ready at 6 with both processors free: first fit takes processor 0 (idle since 4),
/// best fit processor 1 (free at 6, no idle time). V is ready at 4: under first fit no
/// processor is free (0 until 8, 1 until 6), so it waits for processor 1, [6,8], and S runs
/// at [8,9]: makespan 9. Under best fit processor 0 is free: V at [4,6], S at [6,7], and W
/// ends at 8: makespan 8, the critical path X Z W.
fn hand_built() -> TaskGraph {
    TaskGraph::new(
        vec![3, 1, 5, 1, 2, 2, 1],
        vec![vec![], vec![], vec![1], vec![0], vec![2], vec![3], vec![5]],
    )
    .unwrap()
}

fn at(processor: usize, start: u64, finish: u64) -> Placement {
    Placement {
        processor,
        start,
        finish,
    }
}

#[test]
fn zomaya_schedule_hand_built_graph_ffd_and_bfd() {
    let g = hand_built();
    assert_eq!(g.total(), 15);
    assert_eq!(g.levels(), vec![0, 0, 1, 1, 2, 2, 3]);
    assert_eq!(priority_list(&g), vec![0, 1, 2, 3, 4, 5, 6]);
    // levels cost 3 + 5 + 2 + 1
    assert_eq!(g.level_estimate(), 11);
    assert_eq!(
        g.critical_path(),
        CriticalPath {
            length: 8,
            tasks: vec![1, 2, 4]
        }
    );
    let ff = schedule(&g, 2, Rule::FirstFit).unwrap();
    assert_eq!(ff.makespan, 9);
    assert_eq!(
        ff.placements,
        vec![
            at(0, 0, 3),
            at(1, 0, 1),
            at(1, 1, 6),
            at(0, 3, 4),
            at(0, 6, 8),
            at(1, 6, 8),
            at(0, 8, 9)
        ]
    );
    assert_eq!(ff.tasks_on(0), vec![0, 3, 4, 6]);
    assert_eq!((ff.load(0), ff.load(1)), (7, 8));
    let bf = schedule(&g, 2, Rule::BestFit).unwrap();
    assert_eq!(bf.makespan, 8);
    assert_eq!(bf.placements[4], at(1, 6, 8));
    assert_eq!(bf.placements[5], at(0, 4, 6));
    assert_eq!(bf.placements[6], at(0, 6, 7));
    assert_eq!(bf.speed_up(), 15.0 / 8.0);
    assert_eq!(bf.efficiency(), 15.0 / 16.0);
    for rule in [Rule::FirstFit, Rule::BestFit] {
        // one processor: the serial time; three or more: the critical path
        assert_eq!(schedule(&g, 1, rule).unwrap().makespan, 15);
        assert_eq!(schedule(&g, 3, rule).unwrap().makespan, 8);
    }
}

/// Everything a valid schedule satisfies, whatever the heuristic.
fn check(g: &TaskGraph, s: &Schedule) {
    let p = s.processors as u64;
    let cp = g.critical_path().length;
    assert!(
        s.makespan >= cp,
        "{} below the critical path {cp}",
        s.makespan
    );
    assert!(
        s.makespan * p >= g.total(),
        "{} below total / P",
        s.makespan
    );
    assert!(s.makespan <= g.total());
    assert_eq!(s.serial, g.total());
    for (t, x) in s.placements.iter().enumerate() {
        assert!(x.processor < s.processors);
        assert_eq!(x.finish - x.start, g.cost(t), "task {t}");
        assert!(x.finish <= s.makespan);
        for &q in g.predecessors(t) {
            assert!(
                x.start >= s.placements[q].finish,
                "task {t} before {q} ends"
            );
        }
    }
    let mut load = 0;
    for q in 0..s.processors {
        let tasks = s.tasks_on(q);
        for pair in tasks.windows(2) {
            let (a, b) = (s.placements[pair[0]], s.placements[pair[1]]);
            assert!(
                b.start >= a.finish,
                "tasks {pair:?} overlap on processor {q}"
            );
        }
        load += s.load(q);
    }
    // each task on exactly one processor
    assert_eq!(load, g.total());
}

#[test]
fn zomaya_schedule_of_the_ur5e_inverse_dynamics_is_valid() {
    let ur5e = include_str!("../../../../robots/descriptions/ur5e.toml");
    let robot = Robot::from_toml(ur5e, "ur5e.toml").unwrap();
    let programs = RobotPrograms::derive(&robot).unwrap();
    let program = &programs[ProgramKind::InverseDynamics];
    let weights = Weights {
        mul: 3,
        function: 20,
        ..Weights::default()
    };
    let g = TaskGraph::from_program(program, &weights).unwrap();
    assert_eq!(g.len(), program.instrs.len());
    let ops = program.operations();
    let functions = (ops.sin + ops.cos + ops.sign + ops.sqrt) as u64;
    assert_eq!(
        g.total(),
        3 * ops.mul as u64 + (ops.add + ops.neg + ops.div) as u64 + 20 * functions
    );
    let cp = g.critical_path();
    // a chain: each task reads the previous one, and its costs add up to the length
    for pair in cp.tasks.windows(2) {
        assert!(g.predecessors(pair[1]).contains(&pair[0]));
    }
    assert!(g.predecessors(cp.tasks[0]).is_empty());
    assert_eq!(cp.tasks.iter().map(|&t| g.cost(t)).sum::<u64>(), cp.length);
    assert!(g.level_estimate() >= cp.length);
    let mut speed_ups = Vec::new();
    for p in [1, 2, 3, 4, 8, 64] {
        for rule in [Rule::FirstFit, Rule::BestFit] {
            let s = schedule(&g, p, rule).unwrap();
            check(&g, &s);
            if p == 1 {
                assert_eq!(s.makespan, g.total());
            }
            speed_ups.push((p, rule.name(), s.speed_up()));
        }
    }
    eprintln!(
        "total {} critical path {} {speed_ups:?}",
        g.total(),
        cp.length
    );
}

#[test]
fn zomaya_schedule_refuses_bad_requests() {
    let g = hand_built();
    assert_eq!(
        schedule(&g, 0, Rule::FirstFit),
        Err(ScheduleError::Processors(0))
    );
    assert!(schedule(&g, MAX_PROCESSORS + 1, Rule::BestFit).is_err());
    assert!(schedule(&g, MAX_PROCESSORS, Rule::BestFit).is_ok());
    assert_eq!(
        TaskGraph::new(vec![1, 1], vec![vec![], vec![1]]),
        Err(ScheduleError::Order {
            task: 1,
            predecessor: 1
        })
    );
    assert!(matches!(
        TaskGraph::new(vec![1], vec![]),
        Err(ScheduleError::Sizes { .. })
    ));
    assert_eq!(
        TaskGraph::new(vec![u64::MAX, 1], vec![vec![], vec![]]),
        Err(ScheduleError::Overflow)
    );
    let empty = TaskGraph::new(vec![], vec![]).unwrap();
    let s = schedule(&empty, 2, Rule::FirstFit).unwrap();
    assert_eq!((s.makespan, s.speed_up()), (0, 1.0));
    assert_eq!(empty.critical_path().length, 0);
}
