//! The feasible-parameter extraction problem of a description, as `robid feasible` sets it
//! up (docs/experiments.md#the-extraction-problem).

use robid_runtime::feasible::{LinkShape, Problem};
use robid_symbolic::{Derivation, Robot};

/// The extraction problem of `robot`: K (base parameters from standard ones) evaluated at
/// the description's geometric values, and the links' segments of the chain as the shapes
/// of the default prior's solids. Fails, naming the symbol, when a geometric symbol has no
/// value.
///
/// ```
/// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/descriptions/ur5e.toml")).unwrap();
/// let robot = robid_symbolic::Robot::from_toml(&text, "ur5e.toml").unwrap();
/// let problem = robots::extraction::problem(&robot).unwrap();
/// assert_eq!(problem.layout.links.len(), 6);
/// ```
pub fn problem(robot: &Robot) -> Result<Problem, Box<dyn std::error::Error>> {
    let mut derivation = Derivation::new(robot);
    let base = derivation.base_parameters()?;
    let mut pairs = Vec::new();
    for (name, value) in robot.symbols() {
        let v = value.ok_or_else(|| {
            format!("geometric symbol `{name}` has no value; give it one in the description")
        })?;
        pairs.push((name.as_str(), v));
    }
    let values = derivation.arena.values(&pairs);
    let mut k = vec![vec![0.0; base.standard.len()]; base.base.len()];
    for (b, bp) in base.base.iter().enumerate() {
        for &(s, c) in &bp.terms {
            k[b][s] = derivation
                .arena
                .eval(&[c], &values)
                .map_err(|e| format!("{e:?}"))?[0];
        }
    }
    let standard = base.standard.iter().map(|p| p.to_string()).collect();
    let names = base.base.iter().map(|b| b.name.to_string()).collect();
    let shapes = robot
        .link_segments()
        .map_err(|e| e.to_string())?
        .into_iter()
        .map(|[from, to]| LinkShape { from, to })
        .collect();
    Ok(Problem::from_rows(standard, names, &k)?.with_shapes(shapes)?)
}
