//! Kinematics and dynamics of a robot, derived symbolically.
//!
//! [`Derivation`] holds the arena, the robot, the joint symbols and the
//! kinematics; from it come the Newton-Euler torques and regressor, and the
//! Lagrange-Euler model and energy regressor.

pub mod kinematics;
pub mod lagrange;
pub mod link;
pub mod newton_euler;
pub mod vector;

pub use kinematics::{JointInputs, Kinematics};
pub use lagrange::Lagrange;
pub use link::LinkParameters;

use crate::expr::{Arena, Id};
use crate::robot::{ParameterId, Robot};

/// A regressor: one torque column per standard parameter, tau = sum_p column_p * p.
#[derive(Clone, Debug)]
pub struct Regressor {
    /// The parameters, in column order.
    pub parameters: Vec<ParameterId>,
    /// `columns[p][j]`: joint j's torque per unit of parameter p.
    pub columns: Vec<Vec<Id>>,
}

impl Regressor {
    /// All entries, column by column (for evaluation and programs).
    pub fn entries(&self) -> Vec<Id> {
        self.columns.iter().flatten().copied().collect()
    }
}

/// A robot's symbolic derivation context.
#[derive(Clone, Debug)]
pub struct Derivation {
    /// The arena every expression lives in.
    pub arena: Arena,
    /// The robot.
    pub robot: Robot,
    /// Joint symbols q, qd, qdd and gravity.
    pub inputs: JointInputs,
    /// Kinematics for those inputs.
    pub kinematics: Kinematics,
    /// The standard parameters, in column order.
    parameters: Vec<ParameterId>,
    /// Modified-DH to user link frames (standard DH only).
    frames: Vec<Option<(Id, Id)>>,
}

impl Derivation {
    /// Starts a derivation: joint symbols and kinematics.
    pub fn new(robot: &Robot) -> Derivation {
        let mut arena = Arena::new();
        let inputs = JointInputs::symbols(&mut arena, robot);
        let kinematics = Kinematics::new(&mut arena, robot, &inputs);
        let frames = link::user_frames(&mut arena, robot);
        let parameters = robot.standard_parameters();
        Derivation {
            arena,
            robot: robot.clone(),
            inputs,
            kinematics,
            parameters,
            frames,
        }
    }

    /// Link parameters (modified-DH frames) from standard-parameter values.
    pub fn link_parameters(&mut self, values: &[Id]) -> Vec<LinkParameters> {
        link::link_parameters(&mut self.arena, &self.parameters, &self.frames, values)
    }

    /// The standard parameters as symbols (`XX1`, ...).
    pub fn parameter_symbols(&mut self) -> Vec<Id> {
        self.parameters
            .iter()
            .map(|p| self.arena.var(&p.to_string()))
            .collect()
    }

    /// The standard parameters, in column order.
    pub fn standard_parameters(&self) -> &[ParameterId] {
        &self.parameters
    }

    /// Newton-Euler torques for the given standard-parameter values.
    pub fn inverse_dynamics(&mut self, values: &[Id]) -> Vec<Id> {
        let params = self.link_parameters(values);
        newton_euler::inverse_dynamics(
            &mut self.arena,
            &self.kinematics,
            &self.inputs.qd,
            &self.inputs.qdd,
            &params,
        )
    }

    /// Lagrange-Euler model for the given standard-parameter values.
    pub fn lagrange(&mut self, values: &[Id]) -> Lagrange {
        let params = self.link_parameters(values);
        lagrange::lagrange(&mut self.arena, &self.kinematics, &self.inputs, &params)
    }

    /// The Newton-Euler regressor: column p is the torque with parameter p at
    /// 1 and the others at 0 (the forward kinematics are shared by all).
    pub fn regressor(&mut self) -> Regressor {
        self.regressor_by(|d, values| d.inverse_dynamics(values))
    }

    /// The Lagrange-Euler regressor, built the same way from the energies.
    pub fn lagrange_regressor(&mut self) -> Regressor {
        self.regressor_by(|d, values| d.lagrange(values).torques)
    }

    fn regressor_by(
        &mut self,
        mut torques: impl FnMut(&mut Derivation, &[Id]) -> Vec<Id>,
    ) -> Regressor {
        let parameters = self.parameters.clone();
        let zero = self.arena.zero();
        let one = self.arena.one();
        let columns = (0..parameters.len())
            .map(|p| {
                let mut values = vec![zero; parameters.len()];
                values[p] = one;
                torques(self, &values)
            })
            .collect();
        Regressor {
            parameters,
            columns,
        }
    }
}
