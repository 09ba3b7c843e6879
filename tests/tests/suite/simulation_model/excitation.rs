//! Shared by the excitation acceptance tests: a Fourier design of a reference robot weighted by
//! the expected torque noise, a validation trajectory, and the comparison with random
//! trajectories of the same family.

use robid_runtime::excite::{FourierDesign, JointLimits, PointDesign, assess};
use robid_runtime::simulate::{Noise, Trajectory};
use robid_symbolic::Drive;
use robid_symbolic::robot::DriveTerm;

use super::{Interpreted, expected_error, mean_outcome, reference, validation_records};

/// Duration of every trajectory (s).
pub(crate) const DURATION: f64 = 30.0;
/// Sample rate (Hz).
pub(crate) const RATE: f64 = 100.0;

/// A designed experiment on a reference robot.
pub(crate) struct Setup {
    /// The model (rigid body + chosen drive terms).
    pub(crate) model: Interpreted,
    /// True base parameters.
    pub(crate) truth: Vec<f64>,
    /// Published joint limits.
    pub(crate) limits: Vec<JointLimits>,
    /// Torque noise per joint.
    pub(crate) sigma: Vec<f64>,
    /// The design settings (reduced budget).
    pub(crate) design: FourierDesign,
    /// The optimised trajectory.
    pub(crate) optimal: Trajectory,
    /// Another (random) trajectory for validation.
    pub(crate) validation: Trajectory,
}

impl Setup {
    /// Designs for `robot` with `drive` terms (values from `drive_value`), weighting the
    /// regressor rows by 1 / `sigma`.
    pub(crate) fn new(
        robot: &str,
        drive: Drive,
        drive_value: impl Fn(DriveTerm, usize) -> f64,
        sigma: &[f64],
        seed: u64,
    ) -> Self {
        let (model, truth, limits) = reference(robot, drive, drive_value);
        let design = FourierDesign {
            restarts: 2,
            evaluations: 800,
            points: 60,
            seed,
            weights: Some(sigma.iter().map(|s| 1.0 / s).collect()),
            ..FourierDesign::default()
        };
        let start = std::time::Instant::now();
        let result = design.optimize(&model, &limits, None).expect("design");
        println!(
            "{robot} Fourier design: cost {:.1} on the grid, {} evaluations in {:?}",
            result.cost,
            result.evaluations,
            start.elapsed()
        );
        let optimal = result.fourier.sample(DURATION, RATE).expect("sampling");
        let validation = FourierDesign {
            seed: 99,
            ..design.clone()
        }
        .random(&limits)
        .expect("random")
        .sample(DURATION, RATE)
        .expect("sampling");
        Self {
            model,
            truth,
            limits,
            sigma: sigma.to_vec(),
            design,
            optimal,
            validation,
        }
    }

    /// The simulated noise: `sigma` on the torques, encoder noise and quantization.
    pub(crate) fn noise(&self) -> Noise {
        Noise {
            torque: self.sigma.clone(),
            position: 1e-5,
            quantization: std::f64::consts::TAU / (1 << 20) as f64,
            ..Noise::default()
        }
    }

    /// Checks condition number <= `max_condition` (when given), every limit, rest at both ends;
    /// returns the condition number.
    pub(crate) fn check_design(&self, max_condition: Option<f64>) -> f64 {
        let a = assess(
            &self.model,
            &self.optimal,
            &self.limits,
            Some(&self.truth),
            1,
        )
        .unwrap();
        println!(
            "{} Fourier: cond {:.1} over {} samples",
            self.model.programs().robot.name(),
            a.condition_number,
            a.samples
        );
        if let Some(max) = max_condition {
            assert!(
                a.condition_number <= max,
                "condition number {}",
                a.condition_number
            );
        }
        assert!(a.within_limits(), "{:?}", a.margins);
        for (j, q) in self.optimal.q.joints().enumerate() {
            assert!(self.optimal.qd[j][0].abs() < 1e-12 && self.optimal.qdd[j][0].abs() < 1e-9);
            assert!((q[0] - q[q.len() - 1]).abs() < 1e-9);
        }
        a.condition_number
    }

    /// Identifies (WLS, two noise seeds) on the design and on random trajectories of the same
    /// family (`random_seeds`): the design has a lower condition number and a lower parameter
    /// error, empirical and expected, than every random trajectory. The validation error is
    /// printed, not asserted: it is the noise floor to within 0.5 % for the design and for
    /// random trajectories alike (UR5e: 0.03195 and 0.03191 against a floor of 0.03185), so it
    /// cannot tell a good design from a poor one.
    pub(crate) fn check_identification(&self, random_seeds: &[u64]) {
        let noise = self.noise();
        let validation = validation_records(&self.model, &self.truth, &self.validation, &noise, 2);
        let run = |tr: &Trajectory| {
            let o = mean_outcome(&self.model, &self.truth, tr, &validation, &noise, "wls");
            (o, expected_error(&self.model, &self.truth, tr, &self.sigma))
        };
        let (opt, opt_expected) = run(&self.optimal);
        println!(
            "optimised: parameter error {:.5} (expected {opt_expected:.5}), model error {:.5}, validation {:.5}, floor {:.5}",
            opt[0], opt[1], opt[2], opt[3]
        );
        let opt_cond = assess(&self.model, &self.optimal, &self.limits, None, 1)
            .unwrap()
            .condition_number;
        for &seed in random_seeds {
            let random = FourierDesign {
                seed,
                ..self.design.clone()
            }
            .random(&self.limits)
            .expect("random")
            .sample(DURATION, RATE)
            .expect("sampling");
            let a = assess(&self.model, &random, &self.limits, None, 1).unwrap();
            assert!(a.within_limits());
            let (rnd, rnd_expected) = run(&random);
            println!(
                "random {seed} (cond {:.1}): parameter error {:.5} (expected {rnd_expected:.5}), model error {:.5}, validation {:.5}",
                a.condition_number, rnd[0], rnd[1], rnd[2]
            );
            assert!(
                opt_cond < a.condition_number,
                "condition number {opt_cond} vs random {}",
                a.condition_number
            );
            assert!(opt[0] < rnd[0], "{} vs random {}", opt[0], rnd[0]);
            assert!(
                opt_expected < rnd_expected,
                "{opt_expected} vs random {rnd_expected}"
            );
        }
    }

    /// A point design (reduced budget): the criterion decreases and every limit holds;
    /// returns the condition number of the sampled trajectory.
    pub(crate) fn check_point_design(&self, seed: u64) -> f64 {
        let design = PointDesign {
            duration: DURATION,
            restarts: 1,
            sweeps: 2,
            evaluations: 80,
            seed,
            weights: self.design.weights.clone(),
            ..PointDesign::default()
        };
        let start = std::time::Instant::now();
        let r = design
            .optimize(&self.model, &self.limits, None)
            .expect("point design");
        let tr = r.points.sample(RATE).expect("sampling");
        let a = assess(&self.model, &tr, &self.limits, Some(&self.truth), 1).unwrap();
        println!(
            "{} points: extended-regressor cost {:.1} (from {:.1}), cond {:.1} over {} samples, {} evaluations in {:?}",
            self.model.programs().robot.name(),
            r.cost,
            r.initial_cost,
            a.condition_number,
            a.samples,
            r.evaluations,
            start.elapsed()
        );
        assert!(r.cost < r.initial_cost);
        assert!(a.within_limits(), "{:?}", a.margins);
        a.condition_number
    }
}
