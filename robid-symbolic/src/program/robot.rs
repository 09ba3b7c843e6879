//! The programs of one robot (docs/dynamics.md#inverse-dynamics-with-base-parameters,
//! docs/dynamics.md#programs-and-generated-code): standard and base regressors,
//! inverse dynamics with base parameters as a customised Newton-Euler, mass
//! matrix (the composite-rigid-body algorithm on the same values,
//! docs/dynamics.md#composite-rigid-body-mass-matrix), gravity and Coriolis vectors,
//! and the standard -> base map.
//!
//! Every base parameter is built on one link parameter slot in modified-DH
//! frames (its name says which: `MXR2` is MX of link 2), and its base
//! regressor column is the Newton-Euler torque with that slot at 1. So the
//! customised Newton-Euler, run with each base parameter in its slot and every
//! other slot at zero, equals Y_b * beta exactly, with the constant zeros
//! folded away. Should a name not map to a slot, that parameter's part falls
//! back to its column times the parameter.

use super::customised::{Choices, RunInputs, frame_exprs};
use super::lower::Lowering;
use super::{Group, Program, ProgramError, Value};
use crate::dynamics::{Derivation, JointInputs, LinkParameters};
use crate::expr::{Arena, Id};
use crate::regroup::{BaseParameters, RegroupError};
use crate::robot::{DriveTerm, ParameterKind, Robot};
use robid_core::BaseName;
use robid_core::{PROGRAMS, ProgramInfo, ProgramKind, Sizes};
use std::ops::{Index, IndexMut};

/// A base parameter as the generated code describes it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BaseParameter {
    /// Name (`ZZR1`, `XY2`): the standard parameter it is built on.
    pub name: BaseName,
    /// Its expression in the standard parameters, as text.
    pub expression: String,
}

/// Every program of a robot, with the names the generated code needs.
#[derive(Clone, Debug)]
pub struct RobotPrograms {
    /// The robot.
    pub robot: Robot,
    /// Names of the standard parameters, in column order.
    pub standard: Vec<String>,
    /// The base parameters.
    pub base: Vec<BaseParameter>,
    /// Geometric symbols (inputs of every program, group `geometry`) and default values.
    pub geometry: Vec<(String, Option<f64>)>,
    /// The programs, in the order of the table
    /// ([`robid_core::PROGRAMS`]); index with a [`ProgramKind`].
    pub programs: [Program; PROGRAMS.len()],
}

impl RobotPrograms {
    /// Each program with its table entry, in table order.
    pub fn iter(&self) -> impl Iterator<Item = (&'static ProgramInfo, &Program)> {
        PROGRAMS.iter().zip(&self.programs)
    }
}

impl Index<ProgramKind> for RobotPrograms {
    type Output = Program;
    fn index(&self, kind: ProgramKind) -> &Program {
        &self.programs[kind as usize]
    }
}

impl IndexMut<ProgramKind> for RobotPrograms {
    fn index_mut(&mut self, kind: ProgramKind) -> &mut Program {
        &mut self.programs[kind as usize]
    }
}

/// A robot's models could not be derived.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DeriveError {
    /// The regrouping failed.
    #[error(transparent)]
    Regroup(#[from] RegroupError),
    /// A program could not be built.
    #[error(transparent)]
    Program(#[from] ProgramError),
}

/// Group of symbols `prefix1..prefixn`.
fn joint_group(name: &str, n: usize) -> Group {
    Group::new(name, (1..=n).map(|j| format!("{name}{j}")).collect())
}

struct Context {
    d: Derivation,
    base: BaseParameters,
    beta: Vec<Id>,
    geometry: Option<Group>,
}

impl Context {
    /// The derivation and base parameters of `robot`, with a symbol for each base
    /// parameter.
    fn new(robot: &Robot) -> Result<Context, DeriveError> {
        let mut d = Derivation::new(robot);
        let base = d.base_parameters()?;
        let beta: Vec<Id> = base
            .base
            .iter()
            .map(|b| d.arena.var(&b.name.to_string()))
            .collect();
        let geometry = (!robot.symbols().is_empty()).then(|| {
            Group::new(
                "geometry",
                robot.symbols().iter().map(|(s, _)| s.clone()).collect(),
            )
        });
        Ok(Context {
            d,
            base,
            beta,
            geometry,
        })
    }

    fn inputs(&self, groups: &[&str]) -> Vec<Group> {
        let n = self.d.robot.dof();
        let mut out: Vec<Group> = groups
            .iter()
            .map(|&g| match g {
                "base" => Group::new(
                    "base",
                    self.base.base.iter().map(|b| b.name.to_string()).collect(),
                ),
                "standard" => Group::new(
                    "standard",
                    self.base.standard.iter().map(|p| p.to_string()).collect(),
                ),
                other => joint_group(other, n),
            })
            .collect();
        out.extend(self.geometry.clone());
        out
    }

    /// The link parameters with every base parameter in the slot of the standard
    /// parameter it is built on (drive terms Fv, Fc, Fo only with `friction`).
    fn slots(&mut self, friction: bool) -> Vec<LinkParameters> {
        let arena = &mut self.d.arena;
        let n = self.d.robot.dof();
        let mut links: Vec<LinkParameters> = (0..n).map(|_| LinkParameters::zero(arena)).collect();
        for (b, &beta) in self.base.base.iter().zip(&self.beta) {
            let on = b.name.on;
            let is_friction = matches!(on.kind, ParameterKind::Drive(t) if t != DriveTerm::Ia);
            if friction || !is_friction {
                *links[on.link].slot_mut(on.kind) = beta;
            }
        }
        links
    }

    /// A program running the customised Newton-Euler algorithm once per
    /// entry of `runs` (straight into program values, see `customised/`);
    /// `assemble` turns the torques of every run into the output elements.
    fn newton_euler_program(
        &mut self,
        groups: &[&str],
        name: &str,
        runs: &[JointInputs],
        friction: bool,
        assemble: impl Fn(&[Vec<Value>]) -> Vec<Value>,
    ) -> Result<Program, ProgramError> {
        // The last link's wrench in its own frame or in its parent's
        // (`Lowering::tip`), and for a single run the scaled accelerations reused or
        // not: whichever program is the cheapest, so no robot pays for either.
        // Reusing scaled accelerations saves a few multiplications but made the 7-run
        // Panda mass matrix ~3 % slower (compiled code, when the mass matrix was built
        // this way): single runs only. The other choices are taken always: left out,
        // none makes a reference robot's program cheaper (`every_other_choice_pays`).
        let reuses: &[bool] = match runs.len() {
            1 => &[true, false],
            _ => &[false],
        };
        let variants: Vec<Choices> = [false, true]
            .into_iter()
            .flat_map(|tip| {
                reuses.iter().map(move |&reuse| Choices {
                    tip,
                    reuse,
                    ..Choices::ALL
                })
            })
            .collect();
        self.newton_euler_variants(groups, name, runs, friction, assemble, &variants)
    }

    /// [`Context::newton_euler_program`] built with each of `variants`, the cheapest
    /// kept (the first of equals).
    fn newton_euler_variants(
        &mut self,
        groups: &[&str],
        name: &str,
        runs: &[JointInputs],
        friction: bool,
        assemble: impl Fn(&[Vec<Value>]) -> Vec<Value>,
        variants: &[Choices],
    ) -> Result<Program, ProgramError> {
        let links = self.slots(friction);
        let q = self.d.inputs.q.clone();
        let frames = frame_exprs(&mut self.d.arena, &self.d.robot, &q);
        let inputs = self.inputs(groups);
        let mut best: Option<Program> = None;
        for &choices in variants {
            let mut l = Lowering::new(&self.d.arena, &inputs);
            let mut torques = Vec::with_capacity(runs.len());
            for run in runs {
                let run_inputs = RunInputs {
                    qd: &run.qd,
                    qdd: &run.qdd,
                    gravity: run.gravity,
                };
                let tau = l.newton_euler(&frames, &run_inputs, &links, choices)?;
                let mut values = Vec::with_capacity(tau.len());
                for t in tau {
                    values.push(l.output(t));
                }
                torques.push(values);
            }
            let values = assemble(&torques);
            let group = Group::new(name, element_names(name, values.len()));
            let program = l.finish(inputs.clone(), vec![(group, values)]);
            if best
                .as_ref()
                .is_none_or(|b| program.operations().flops() < b.operations().flops())
            {
                best = Some(program);
            }
        }
        Ok(best.unwrap_or_default())
    }

    /// The mass matrix by the composite-rigid-body algorithm (`customised/crba.rs`,
    /// docs/dynamics.md#composite-rigid-body-mass-matrix): one pass from the tip for
    /// the composite bodies, each column's wrench moved to the joints before it.
    fn mass_matrix_program(
        &mut self,
        groups: &[&str],
        name: &str,
    ) -> Result<Program, ProgramError> {
        let links = self.slots(false);
        let q = self.d.inputs.q.clone();
        let frames = frame_exprs(&mut self.d.arena, &self.d.robot, &q);
        let inputs = self.inputs(groups);
        let mut l = Lowering::new(&self.d.arena, &inputs);
        let entries = l.mass_matrix(&frames, &links)?;
        // Each entry is output once, the symmetric one shares its value.
        let mut values = Vec::with_capacity(entries.len());
        let n = frames.len();
        for (e, entry) in entries.into_iter().enumerate() {
            let (i, k) = (e / n, e % n);
            let v = if i > k {
                values[k * n + i]
            } else {
                l.output_swapping(entry)
            };
            values.push(v);
        }
        let group = Group::new(name, element_names(name, values.len()));
        Ok(l.finish(inputs.clone(), vec![(group, values)]))
    }

    /// The mass matrix as the customised Newton-Euler algorithm gives it, column k
    /// with `qd = 0`, `qdd = e_k` and no gravity: the construction the
    /// composite-rigid-body program replaced, kept for the tests that compare the two.
    #[cfg(test)]
    pub(super) fn mass_matrix_by_columns(&mut self) -> Result<Program, ProgramError> {
        let n = self.d.robot.dof();
        let info = ProgramKind::MassMatrix.info();
        let inputs: Vec<&str> = info.inputs.iter().map(|a| a.name).collect();
        let columns: Vec<JointInputs> = (0..n)
            .map(|k| self.constant_inputs(false, Some(k), false))
            .collect();
        self.newton_euler_program(&inputs, info.output.name, &columns, false, |t| {
            (0..n * n)
                .map(|e| {
                    let (i, k) = (e / n, e % n);
                    if i >= k { t[k][i] } else { t[i][k] }
                })
                .collect()
        })
    }

    /// Y_b written straight into a program (`customised/columns.rs`): one forward
    /// recursion for all columns; column k is the wrench of link j with base
    /// parameter k's slot at 1 (a few entries of w, wd, vd and U), projected
    /// on the axis of every joint i <= j expressed in frame j (torque
    /// z_i . n + (z_i x P_(i, j)) . f), so no column is transformed back
    /// link by link; the drive terms add to joint j alone.
    fn base_regressor_program(&mut self) -> Result<Program, ProgramError> {
        let n = self.d.robot.dof();
        let one = self.d.arena.one();
        let zero_links: Vec<LinkParameters> = (0..n)
            .map(|_| LinkParameters::zero(&mut self.d.arena))
            .collect();
        let q = self.d.inputs.q.clone();
        let frames = frame_exprs(&mut self.d.arena, &self.d.robot, &q);
        let inputs = self.inputs(&["q", "qd", "qdd"]);
        let mut l = Lowering::new(&self.d.arena, &inputs);
        let sym = &self.d.inputs;
        let run_inputs = RunInputs {
            qd: &sym.qd,
            qdd: &sym.qdd,
            gravity: sym.gravity,
        };
        let kinematics = l.forward(&frames, &run_inputs)?;
        let axes = l.axes(&kinematics);
        let arms = l.arms(&kinematics, &axes);
        let mut columns: Vec<Vec<Value>> = Vec::with_capacity(self.base.base.len());
        for b in &self.base.base {
            let on = b.name.on;
            let mut params = zero_links[on.link];
            *params.slot_mut(on.kind) = one;
            let tau = l.link_column(&kinematics, &axes, &arms, on.link, &params)?;
            let column: Vec<Value> = tau.into_iter().map(|t| l.output(t)).collect();
            columns.push(column);
        }
        let values: Vec<Value> = (0..n)
            .flat_map(|j| columns.iter().map(move |c| c[j]))
            .collect();
        let group = Group::new("out", element_names("out", values.len()));
        Ok(l.finish(inputs.clone(), vec![(group, values)]))
    }

    /// The builder of each program of the table.
    fn build(&mut self, kind: ProgramKind) -> Result<Program, ProgramError> {
        let n = self.d.robot.dof();
        let info = kind.info();
        let inputs: Vec<&str> = info.inputs.iter().map(|a| a.name).collect();
        let output = info.output.name;
        let single = |t: &[Vec<Value>]| t[0].clone();
        match kind {
            ProgramKind::StandardRegressor => {
                let columns = self.d.regressor().columns;
                self.expressions(&inputs, output, row_major(&columns, n))
            }
            ProgramKind::BaseRegressor => self.base_regressor_program(),
            ProgramKind::InverseDynamics => {
                let symbolic = [self.d.inputs.clone()];
                self.newton_euler_program(&inputs, output, &symbolic, true, single)
            }
            ProgramKind::MassMatrix => self.mass_matrix_program(&inputs, output),
            ProgramKind::Gravity => {
                let runs = [self.constant_inputs(false, None, true)];
                self.newton_euler_program(&inputs, output, &runs, false, single)
            }
            ProgramKind::Coriolis => {
                let runs = [self.constant_inputs(true, None, false)];
                self.newton_euler_program(&inputs, output, &runs, false, single)
            }
            ProgramKind::BaseFromStandard => {
                let expressions: Vec<Id> = self.base.base.iter().map(|b| b.expression).collect();
                self.expressions(&inputs, output, expressions)
            }
        }
    }

    /// A program computing `ids` (expressions of the arena) into output group `name`.
    fn expressions(
        &self,
        inputs: &[&str],
        name: &str,
        ids: Vec<Id>,
    ) -> Result<Program, ProgramError> {
        let group = Group::new(name, element_names(name, ids.len()));
        Program::build(&self.d.arena, self.inputs(inputs), vec![(group, ids)])
    }

    fn constant_inputs(&mut self, qd: bool, qdd: Option<usize>, gravity: bool) -> JointInputs {
        let a = &mut self.d.arena;
        let zero = a.zero();
        let one = a.one();
        let sym = &self.d.inputs;
        let n = sym.q.len();
        JointInputs {
            q: sym.q.clone(),
            qd: if qd { sym.qd.clone() } else { vec![zero; n] },
            qdd: (0..n)
                .map(|j| if qdd == Some(j) { one } else { zero })
                .collect(),
            gravity: if gravity { sym.gravity } else { [zero; 3] },
        }
    }
}

fn row_major(columns: &[Vec<Id>], n: usize) -> Vec<Id> {
    (0..n)
        .flat_map(|j| columns.iter().map(move |c| c[j]))
        .collect()
}

fn element_names(prefix: &str, count: usize) -> Vec<String> {
    (0..count).map(|i| format!("{prefix}{i}")).collect()
}

impl RobotPrograms {
    /// The stages [`RobotPrograms::derive_reporting`] reports: the base parameters, then
    /// every program.
    pub const STAGES: usize = 1 + PROGRAMS.len();

    /// Derives the base parameters and every program of `robot`.
    pub fn derive(robot: &Robot) -> Result<RobotPrograms, DeriveError> {
        Self::derive_reporting(robot, &mut |_| {})
    }

    /// [`RobotPrograms::derive`], calling `done` after each of its
    /// [`RobotPrograms::STAGES`] stages with the stage's name: the kinematics and base
    /// parameters (`"base parameters"`), then each program in the order of
    /// [`ProgramKind::ALL`] (its name, `"inverse_dynamics"`). A front end shows its
    /// progress so: a chain of 32 joints with general twists takes tens of seconds.
    pub fn derive_reporting(
        robot: &Robot,
        done: &mut dyn FnMut(&str),
    ) -> Result<RobotPrograms, DeriveError> {
        Self::derive_showing(robot, done, &mut |_, _| {})
    }

    /// [`RobotPrograms::derive_reporting`], handing the base parameters, with the arena
    /// their expressions and coefficients live in, to `base` as soon as they are derived
    /// (before the programs): a front end that shows their terms (`robid model`) needs no
    /// derivation of its own, which cost a quarter of the time on long chains.
    pub fn derive_showing(
        robot: &Robot,
        done: &mut dyn FnMut(&str),
        base: &mut dyn FnMut(&Arena, &BaseParameters),
    ) -> Result<RobotPrograms, DeriveError> {
        let n = robot.dof();
        let mut cx = Context::new(robot)?;
        base(&cx.d.arena, &cx.base);
        done("base parameters");
        let mut built = Vec::with_capacity(PROGRAMS.len());
        for kind in ProgramKind::ALL {
            let program = cx.build(kind)?;
            done(kind.info().name);
            debug_assert_eq!(
                program.outputs[0].values.len(),
                kind.info().output.size.len(Sizes {
                    joints: n,
                    base: cx.base.base.len(),
                    standard: cx.base.standard.len(),
                }),
                "{kind:?}"
            );
            built.push(program);
        }
        let mut built = built.into_iter();
        let programs = std::array::from_fn(|_| built.next().unwrap_or_default());
        let arena: &Arena = &cx.d.arena;
        Ok(RobotPrograms {
            robot: robot.clone(),
            standard: cx.base.standard.iter().map(|p| p.to_string()).collect(),
            base: cx
                .base
                .base
                .iter()
                .map(|b| BaseParameter {
                    name: b.name,
                    expression: arena.display(b.expression),
                })
                .collect(),
            geometry: robot.symbols().to_vec(),
            programs,
        })
    }
}

#[cfg(test)]
mod tests;
