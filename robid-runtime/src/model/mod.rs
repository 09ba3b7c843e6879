//! The slice-based model trait the identification pipeline works with.
//!
//! Implemented by the code `robot_model!` emits (compiled, fixed size) and by the
//! interpreter of a derived program (any description file, at run time). All
//! matrices are row-major slices.
//!
//! One contract for every implementation: a slice of the wrong length is a
//! [`LengthError`] naming the argument, returned before any output is written; a
//! method never panics and never writes a partial result.

use core::fmt;

// The vocabulary this trait is written in lives in robid-core, which the symbolic engine
// shares without depending on the runtime.
pub use robid_core::{
    Argument, BaseName, DriveTerm, Inertial, PROGRAMS, ParameterId, ParameterKind, ParseNameError,
    ProgramInfo, ProgramKind, Size, Sizes,
};

/// A slice given to a [`Model`] method does not have the length the model needs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LengthError {
    /// The argument, as the method names it (`q`, `qd`, `qdd`, `base`, `standard`, `out`, `tau`).
    pub argument: &'static str,
    /// The length the model needs.
    pub expected: usize,
    /// The length given.
    pub found: usize,
}

impl fmt::Display for LengthError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "`{}` has {} but the model needs {}; pass one entry per {}",
            self.argument,
            crate::Count(self.found, "entry"),
            self.expected,
            match self.argument {
                "q" | "qd" | "qdd" | "tau" => "joint",
                "base" => "base parameter",
                "standard" => "standard parameter",
                "phi" => "parameter of the estimate",
                "inputs" => "input of the program (see robid_runtime::model::PROGRAMS)",
                _ => "output value",
            }
        )
    }
}

impl core::error::Error for LengthError {}

/// Checks that `slice` has `expected` entries.
pub fn check_length(
    argument: &'static str,
    slice: &[f64],
    expected: usize,
) -> Result<(), LengthError> {
    if slice.len() == expected {
        Ok(())
    } else {
        Err(LengthError {
            argument,
            expected,
            found: slice.len(),
        })
    }
}

/// `slice` as a fixed-size array (the inputs of generated code).
pub fn fixed<'a, const N: usize>(
    argument: &'static str,
    slice: &'a [f64],
) -> Result<&'a [f64; N], LengthError> {
    slice.try_into().map_err(|_| LengthError {
        argument,
        expected: N,
        found: slice.len(),
    })
}

/// `slice` as a mutable fixed-size array (the outputs of generated code).
pub fn fixed_mut<'a, const N: usize>(
    argument: &'static str,
    slice: &'a mut [f64],
) -> Result<&'a mut [f64; N], LengthError> {
    let found = slice.len();
    slice.try_into().map_err(|_| LengthError {
        argument,
        expected: N,
        found,
    })
}

/// A robot's dynamic model in base parameters, as the runtime sees it.
///
/// Conventions: `q`, `qd`, `qdd` and `tau` have `dof()` entries; `base` has
/// `base_parameter_count()` entries, in the order of `base_parameter_name`;
/// `standard` has `standard_parameter_count()` entries. Geometric symbols (lengths
/// kept symbolic in the description) are part of the implementing value, set when it
/// is constructed.
///
/// An implementation provides [`run`](Model::run), which computes any program of the
/// table [`PROGRAMS`]; the named methods (`inverse_dynamics_into`, ...) call it. Every
/// computation checks the number of inputs and the length of every slice first: on a
/// mismatch it returns the [`LengthError`] of the first wrong argument and leaves the
/// output as it was; otherwise it overwrites the output completely.
///
/// ```
/// use robid_runtime::model::{LengthError, Model};
/// fn torques(m: &dyn Model, q: &[f64], base: &[f64]) -> Result<Vec<f64>, LengthError> {
///     let zero = vec![0.0; m.dof()];
///     let mut tau = vec![0.0; m.dof()];
///     m.inverse_dynamics_into(q, &zero, &zero, base, &mut tau)?;
///     Ok(tau)
/// }
/// ```
pub trait Model {
    /// Name of the robot, as in its description.
    fn name(&self) -> &str;
    /// Number of joints.
    fn dof(&self) -> usize;
    /// Number of standard parameters (10 per link plus the enabled drive terms).
    fn standard_parameter_count(&self) -> usize;
    /// Name of standard parameter `index` (e.g. `XX1`, `MZ3`, `Fv2`); `None` past the end.
    fn standard_parameter_name(&self, index: usize) -> Option<&str>;
    /// Number of base parameters.
    fn base_parameter_count(&self) -> usize;
    /// Name of base parameter `index` (e.g. `ZZR1`, `MXR2`); `None` past the end.
    fn base_parameter_name(&self, index: usize) -> Option<&str>;

    /// Runs `program` on `inputs` (one slice per input of its table entry, in order)
    /// and writes its result to `output`.
    fn run(
        &self,
        program: ProgramKind,
        inputs: &[&[f64]],
        output: &mut [f64],
    ) -> Result<(), LengthError>;

    /// Runs `program` on `lanes` argument sets at once. Every input and the output are
    /// lane-major: element `i` of set `l` is at `i * lanes + l`, so each slice is `lanes`
    /// times as long as for [`run`](Model::run). Each set's result equals that of `run`
    /// on it. The default runs the sets one by one (it allocates one buffer per input and
    /// one for the output per call); an interpreter overrides it to dispatch each operation
    /// once for all sets.
    ///
    /// ```
    /// use robid_runtime::model::{LengthError, Model, ProgramKind};
    /// /// Gravity torques at two positions `qa`, `qb` in one call.
    /// fn two(m: &dyn Model, qa: &[f64], qb: &[f64], base: &[f64]) -> Result<Vec<f64>, LengthError> {
    ///     let q: Vec<f64> = qa.iter().zip(qb).flat_map(|(a, b)| [*a, *b]).collect();
    ///     let base2: Vec<f64> = base.iter().flat_map(|b| [*b, *b]).collect();
    ///     let mut tau = vec![0.0; 2 * m.dof()];
    ///     m.run_lanes(ProgramKind::Gravity, 2, &[&q, &base2], &mut tau)?;
    ///     Ok(tau) // tau[2 i] is joint i at qa, tau[2 i + 1] at qb
    /// }
    /// ```
    ///
    /// # Errors
    /// The [`LengthError`] of the first wrong argument, with `lanes` times the length
    /// `run` expects; `lanes` = 0 is an error on the argument `lanes`.
    #[cfg(feature = "std")]
    fn run_lanes(
        &self,
        program: ProgramKind,
        lanes: usize,
        inputs: &[&[f64]],
        output: &mut [f64],
    ) -> Result<(), LengthError> {
        check_lanes(program, self.sizes(), lanes, inputs, output)?;
        let mut sets: Vec<Vec<f64>> = inputs.iter().map(|s| vec![0.0; s.len() / lanes]).collect();
        let mut one = vec![0.0; output.len() / lanes];
        for l in 0..lanes {
            for (set, s) in sets.iter_mut().zip(inputs) {
                set.iter_mut()
                    .zip(s.iter().skip(l).step_by(lanes))
                    .for_each(|(x, &v)| *x = v);
            }
            let views: Vec<&[f64]> = sets.iter().map(Vec::as_slice).collect();
            self.run(program, &views, &mut one)?;
            output
                .iter_mut()
                .skip(l)
                .step_by(lanes)
                .zip(&one)
                .for_each(|(o, &v)| *o = v);
        }
        Ok(())
    }

    /// The sizes the table's shapes are measured in.
    fn sizes(&self) -> Sizes {
        Sizes {
            joints: self.dof(),
            base: self.base_parameter_count(),
            standard: self.standard_parameter_count(),
        }
    }

    /// Base regressor Y_b(q, qd, qdd): `out` is `dof x base_parameter_count`, row-major,
    /// so that tau = Y_b * base.
    fn base_regressor_into(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [f64],
    ) -> Result<(), LengthError> {
        self.run(ProgramKind::BaseRegressor, &[q, qd, qdd], out)
    }
    /// Standard regressor Y(q, qd, qdd): `out` is `dof x standard_parameter_count`, row-major.
    fn standard_regressor_into(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [f64],
    ) -> Result<(), LengthError> {
        self.run(ProgramKind::StandardRegressor, &[q, qd, qdd], out)
    }
    /// Inverse dynamics with base parameters, friction and offsets included: `tau` has `dof` entries.
    fn inverse_dynamics_into(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        base: &[f64],
        tau: &mut [f64],
    ) -> Result<(), LengthError> {
        self.run(ProgramKind::InverseDynamics, &[q, qd, qdd, base], tau)
    }
    /// Joint-space inertia matrix M(q) (rotor inertias included): `out` is `dof x dof`, row-major.
    fn mass_matrix_into(
        &self,
        q: &[f64],
        base: &[f64],
        out: &mut [f64],
    ) -> Result<(), LengthError> {
        self.run(ProgramKind::MassMatrix, &[q, base], out)
    }
    /// Gravity torques g(q): `out` has `dof` entries.
    fn gravity_into(&self, q: &[f64], base: &[f64], out: &mut [f64]) -> Result<(), LengthError> {
        self.run(ProgramKind::Gravity, &[q, base], out)
    }
    /// Coriolis and centripetal torques c(q, qd) (no gravity, no friction): `out` has `dof` entries.
    fn coriolis_into(
        &self,
        q: &[f64],
        qd: &[f64],
        base: &[f64],
        out: &mut [f64],
    ) -> Result<(), LengthError> {
        self.run(ProgramKind::Coriolis, &[q, qd, base], out)
    }
    /// Maps standard parameters to base parameters (base = K * standard).
    fn base_from_standard_into(
        &self,
        standard: &[f64],
        base: &mut [f64],
    ) -> Result<(), LengthError> {
        self.run(ProgramKind::BaseFromStandard, &[standard], base)
    }
}

/// Checks `inputs` and `output` against `program`'s table entry for a model of `sizes`:
/// the number of inputs (argument `inputs`), then each slice's length in order.
pub fn check_arguments(
    program: ProgramKind,
    sizes: Sizes,
    inputs: &[&[f64]],
    output: &[f64],
) -> Result<(), LengthError> {
    check_lanes(program, sizes, 1, inputs, output)
}

/// [`check_arguments`] for `lanes` argument sets in one lane-major slice each
/// ([`Model::run_lanes`]): every length `lanes` times the table's; `lanes` = 0 is an error
/// on the argument `lanes`.
pub fn check_lanes(
    program: ProgramKind,
    sizes: Sizes,
    lanes: usize,
    inputs: &[&[f64]],
    output: &[f64],
) -> Result<(), LengthError> {
    if lanes == 0 {
        return Err(LengthError {
            argument: "lanes",
            expected: 1,
            found: 0,
        });
    }
    let info = program.info();
    if inputs.len() != info.inputs.len() {
        return Err(LengthError {
            argument: "inputs",
            expected: info.inputs.len(),
            found: inputs.len(),
        });
    }
    for (slice, argument) in inputs.iter().zip(info.inputs) {
        check_length(argument.name, slice, argument.size.len(sizes) * lanes)?;
    }
    check_length(
        info.output.name,
        output,
        info.output.size.len(sizes) * lanes,
    )
}

/// The base parameter names of `model`, in order.
#[cfg(feature = "std")]
pub fn base_parameter_names<M: Model + ?Sized>(model: &M) -> Vec<String> {
    (0..model.base_parameter_count())
        .filter_map(|i| model.base_parameter_name(i).map(str::to_owned))
        .collect()
}

/// `model`'s map from standard to base parameters as a matrix K (`base = K standard`,
/// base x standard), read column by column from
/// [`base_from_standard_into`](Model::base_from_standard_into).
///
/// # Errors
/// The model's map refuses the lengths it states itself (a model in error).
#[cfg(feature = "std")]
pub fn base_map<M: Model + ?Sized>(model: &M) -> Result<nalgebra::DMatrix<f64>, LengthError> {
    let (ns, nb) = (
        model.standard_parameter_count(),
        model.base_parameter_count(),
    );
    let mut k = nalgebra::DMatrix::zeros(nb, ns);
    let mut unit = vec![0.0; ns];
    for s in 0..ns {
        unit[s] = 1.0;
        model.base_from_standard_into(&unit, k.column_mut(s).as_mut_slice())?;
        unit[s] = 0.0;
    }
    Ok(k)
}

/// The standard parameter names of `model`, in order.
#[cfg(feature = "std")]
pub fn standard_parameter_names<M: Model + ?Sized>(model: &M) -> Vec<String> {
    (0..model.standard_parameter_count())
        .filter_map(|i| model.standard_parameter_name(i).map(str::to_owned))
        .collect()
}

/// When the parameter names of a file (`file`: a parameter file's keys, the names of an
/// identified result) and of a model (`model`: its standard or base parameter names)
/// differ in drive terms, what differs and the fix: e.g. "it has the drive terms Fv, Fc
/// (`Fv1`, ...), while the robot models none: give `--drive Fv,Fc` ...". `what` names the file
/// ("the identified result"). `None` when both have the same kinds of drive terms, or
/// when `file` has a name that is neither a drive term nor one of `model`'s (a file of
/// another robot or description: other drive terms are not what is wrong).
///
/// The kinds are compared, not the joints: `--drive` and a description's `drive` key give
/// every joint the same terms (a term regrouped into a link's parameter, such as joint
/// 1's `Ia1`, has no name of its own, and the other joints name it).
#[cfg(feature = "std")]
pub fn drive_terms_mismatch<S: AsRef<str>, T: AsRef<str>>(
    what: &str,
    file: &[S],
    model: &[T],
) -> Option<String> {
    use std::collections::BTreeSet;
    let kinds = |names: &mut dyn Iterator<Item = &str>| -> (BTreeSet<DriveTerm>, Vec<String>) {
        let mut kinds = BTreeSet::new();
        let mut examples = Vec::new();
        for name in names {
            if let Ok(ParameterId {
                kind: ParameterKind::Drive(term),
                ..
            }) = name.parse::<ParameterId>()
                && kinds.insert(term)
            {
                examples.push(name.to_owned());
            }
        }
        (kinds, examples)
    };
    let (in_file, examples) = kinds(&mut file.iter().map(AsRef::as_ref));
    let (in_model, _) = kinds(&mut model.iter().map(AsRef::as_ref));
    if in_file == in_model {
        return None;
    }
    // the file's other names are the model's: else it is of another robot (or description)
    let drive = |name: &str| {
        matches!(
            name.parse::<ParameterId>(),
            Ok(ParameterId {
                kind: ParameterKind::Drive(_),
                ..
            })
        )
    };
    if file
        .iter()
        .map(AsRef::as_ref)
        .any(|n| !drive(n) && !model.iter().any(|m| m.as_ref() == n))
    {
        return None;
    }
    let list = |set: &BTreeSet<DriveTerm>| -> String {
        if set.is_empty() {
            "none".to_owned()
        } else {
            set.iter().map(|t| t.stem()).collect::<Vec<_>>().join(", ")
        }
    };
    let had = if in_file.is_empty() {
        format!("{what} has no drive terms")
    } else {
        format!(
            "{what} has the drive terms {} (`{}`, ...)",
            list(&in_file),
            examples.join("`, `")
        )
    };
    let fix = if in_file.is_empty() {
        "give no --drive, and no `drive` key in the description".to_owned()
    } else {
        format!(
            "give `--drive {}` to model them (or a `drive` key with them in the description)",
            in_file
                .iter()
                .map(|t| t.stem())
                .collect::<Vec<_>>()
                .join(",")
        )
    };
    Some(format!(
        "{had}, while the robot models {}: {fix}",
        if in_model.is_empty() {
            "none (no --drive, no `drive` key)".to_owned()
        } else {
            list(&in_model)
        }
    ))
}

#[cfg(feature = "std")]
impl From<LengthError> for crate::Error {
    fn from(e: LengthError) -> Self {
        crate::Error::DimensionMismatch {
            what: format!("model argument `{}`", e.argument),
            expected: e.expected,
            found: e.found,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Drive terms that differ are named with the `--drive` to give; a file with names of
    /// another robot is not told about drive terms.
    #[test]
    fn drive_terms_that_differ_name_the_drive_to_give() {
        let model = ["ZZR1", "MX2", "Fv1", "Fv2"];
        let file = ["ZZR1", "MX2", "Fv1", "Fc1", "Fv2", "Fc2"];
        assert_eq!(
            drive_terms_mismatch("it", &file, &model).as_deref(),
            Some(
                "it has the drive terms Fv, Fc (`Fv1`, `Fc1`, ...), while the robot models Fv: give \
                 `--drive Fv,Fc` to model them (or a `drive` key with them in the description)"
            )
        );
        assert_eq!(
            drive_terms_mismatch("it", &["ZZR1", "MX2"], &model).as_deref(),
            Some(
                "it has no drive terms, while the robot models Fv: give no --drive, and no `drive` key in \
                 the description"
            )
        );
        assert_eq!(drive_terms_mismatch("it", &model, &model), None);
        // another robot's names
        assert_eq!(drive_terms_mismatch("it", &["XXR3", "Fc1"], &model), None);
    }

    #[test]
    fn fixed_checks_the_length() {
        let v = [1.0, 2.0, 3.0];
        let a: &[f64; 3] = fixed("q", &v).unwrap();
        assert_eq!(a, &v);
        let e = fixed::<2>("qd", &v).unwrap_err();
        assert_eq!(
            e,
            LengthError {
                argument: "qd",
                expected: 2,
                found: 3
            }
        );
        let mut out = [0.0; 2];
        assert!(fixed_mut::<3>("out", &mut out).is_err());
        *fixed_mut::<2>("out", &mut out).unwrap() = [4.0, 5.0];
        assert_eq!(out, [4.0, 5.0]);
        assert!(check_length("base", &v, 3).is_ok());
        assert!(check_length("base", &v, 4).is_err());
    }
}
