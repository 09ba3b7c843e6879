//! The extraction problem: the linear map K (base = K standard), the parameter
//! layout, and the identified base parameters with their uncertainty.

use nalgebra::{DMatrix, DVector};

use super::layout::Layout;
use super::prior::LinkShape;
use crate::limits::MAX_PARAMETER;
use crate::{Error, Model, Result};

/// Identified base parameters to reproduce, and the map from standard parameters.
#[derive(Debug, Clone)]
pub struct Problem {
    /// Standard parameter names (columns of K).
    pub standard_names: Vec<String>,
    /// Base parameter names (rows of K).
    pub base_names: Vec<String>,
    /// K, `base x standard`: base = K * standard.
    pub k: DMatrix<f64>,
    /// Where each link's parameters and each drive term are.
    pub layout: Layout,
    /// Identified base values beta.
    pub target: DVector<f64>,
    /// Standard deviations of beta (square roots of the covariance diagonal).
    pub std: DVector<f64>,
    /// Whitening L^-1 (covariance = L L'): z = L^-1 (K p - beta) has unit covariance.
    pub whitening: DMatrix<f64>,
    /// Each link's extent, when the geometry is known: the default prior is then a solid
    /// of that size (see the module `feasible`); else the centre of the bounds.
    pub shapes: Option<Vec<LinkShape>>,
}

impl Problem {
    /// A problem from names and K; the target starts at zero with unit deviations.
    pub fn new(
        standard_names: Vec<String>,
        base_names: Vec<String>,
        k: DMatrix<f64>,
    ) -> Result<Problem> {
        if k.nrows() != base_names.len() {
            return Err(dims(
                "rows of K (base parameters)",
                base_names.len(),
                k.nrows(),
            ));
        }
        if k.ncols() != standard_names.len() {
            return Err(dims(
                "columns of K (standard parameters)",
                standard_names.len(),
                k.ncols(),
            ));
        }
        if let Some(i) = k.iter().position(|v| !(v.abs() <= MAX_PARAMETER)) {
            return Err(Error::setting(
                "Problem::new",
                "k",
                format!(
                    "K[{}][{}] (base parameter `{}`, standard parameter `{}`) is {}; the geometry must give finite coefficients of magnitude at most {MAX_PARAMETER:e}",
                    i % k.nrows(),
                    i / k.nrows(),
                    base_names[i % k.nrows()],
                    standard_names[i / k.nrows()],
                    crate::error::num(k[(i % k.nrows(), i / k.nrows())])
                ),
            ));
        }
        let layout = Layout::from_names(&standard_names)?;
        let nb = base_names.len();
        Ok(Problem {
            standard_names,
            base_names,
            k,
            layout,
            target: DVector::zeros(nb),
            std: DVector::from_element(nb, 1.0),
            whitening: DMatrix::identity(nb, nb),
            shapes: None,
        })
    }

    /// Sets each link's extent (one shape per link), for the default prior.
    pub fn with_shapes(mut self, shapes: Vec<LinkShape>) -> Result<Problem> {
        if shapes.len() != self.layout.links.len() {
            return Err(dims("link shapes", self.layout.links.len(), shapes.len()));
        }
        if shapes
            .iter()
            .flat_map(|s| s.from.iter().chain(&s.to))
            .any(|v| !(v.abs() <= MAX_PARAMETER))
        {
            return Err(Error::setting(
                "Problem::with_shapes",
                "shapes",
                "a link end is not a finite length of at most 1e6 m",
            ));
        }
        self.shapes = Some(shapes);
        Ok(self)
    }

    /// A problem from names and K given row by row (`rows[b][s]`).
    pub fn from_rows(
        standard_names: Vec<String>,
        base_names: Vec<String>,
        rows: &[Vec<f64>],
    ) -> Result<Problem> {
        let ns = standard_names.len();
        if let Some(r) = rows.iter().find(|r| r.len() != ns) {
            return Err(dims("entries of a row of K", ns, r.len()));
        }
        let k = DMatrix::from_fn(rows.len(), ns, |b, s| rows[b][s]);
        Problem::new(standard_names, base_names, k)
    }

    /// The problem of a model: K is read column by column from `base_from_standard`.
    pub fn from_model(model: &dyn Model) -> Result<Problem> {
        let k = crate::model::base_map(model)?;
        let standard = crate::model::standard_parameter_names(model);
        let base = crate::model::base_parameter_names(model);
        Problem::new(standard, base, k)
    }

    /// Adds free terms that are identified alongside the base parameters but are not part of
    /// the model (the extra columns of an identification config, e.g. a coupled wrist's
    /// `Iam6`, `fvm6`). Each becomes both a standard and a base parameter with K = 1 there
    /// and zero elsewhere, of any sign and under no physical constraint. Call this before
    /// setting the target; a name that is already a parameter is an error.
    pub fn with_extra_columns(mut self, names: &[String]) -> Result<Problem> {
        for (i, n) in names.iter().enumerate() {
            if self.standard_names.contains(n)
                || self.base_names.contains(n)
                || names[..i].contains(n)
            {
                return Err(Error::setting(
                    "Problem::with_extra_columns",
                    "names",
                    format!(
                        "`{n}` is the name of a parameter already present; rename the extra column"
                    ),
                ));
            }
        }
        let (nb, ns, ne) = (self.k.nrows(), self.k.ncols(), names.len());
        let mut k = DMatrix::zeros(nb + ne, ns + ne);
        k.view_mut((0, 0), (nb, ns)).copy_from(&self.k);
        for e in 0..ne {
            k[(nb + e, ns + e)] = 1.0;
            self.layout.extra.push(ns + e);
        }
        self.k = k;
        self.standard_names.extend(names.iter().cloned());
        self.base_names.extend(names.iter().cloned());
        self.target = DVector::zeros(nb + ne);
        self.std = DVector::from_element(nb + ne, 1.0);
        self.whitening = DMatrix::identity(nb + ne, nb + ne);
        Ok(self)
    }

    /// Sets the identified values and their standard deviations, matched by name
    /// (`names` may be in any order but must hold every base parameter once).
    pub fn with_identified(self, names: &[String], values: &[f64], std: &[f64]) -> Result<Problem> {
        if names.len() != values.len() || names.len() != std.len() {
            return Err(dims(
                "identified values and deviations",
                names.len(),
                values.len().min(std.len()),
            ));
        }
        // drive terms that differ (identify run with other --drive): say which to give. The
        // result holds base parameters, so its names are compared with the base names
        let drive = || crate::model::drive_terms_mismatch("it", names, &self.base_names);
        let mut v = Vec::with_capacity(self.base_names.len());
        let mut s = Vec::with_capacity(self.base_names.len());
        for b in &self.base_names {
            let i = names.iter().position(|n| n == b).ok_or_else(|| {
                Error::setting(
                    "Problem::with_identified",
                    "names",
                    match drive() {
                        Some(fix) => format!("base parameter `{b}` is missing from the identified result: {fix}"),
                        None => format!("base parameter `{b}` is missing from the identified result; identify with the same robot description"),
                    },
                )
            })?;
            v.push(values[i]);
            s.push(std[i]);
        }
        if names.len() != self.base_names.len() {
            let extra = names.iter().find(|n| !self.base_names.contains(n));
            return Err(Error::setting(
                "Problem::with_identified",
                "names",
                format!(
                    "the identified result has {} parameters (e.g. `{}`), the model {} base parameters{}",
                    names.len(),
                    extra.cloned().unwrap_or_default(),
                    self.base_names.len(),
                    drive().map_or_else(
                        || "; identify with the same robot description".to_owned(),
                        |fix| format!(": {fix}")
                    )
                ),
            ));
        }
        self.with_target(&v, &s)
    }

    /// Sets the identified values and their standard deviations, in base order. A
    /// deviation of 0 is a parameter known exactly (`robid identify`'s `[known]`
    /// parameters): it keeps the floor of [`with_covariance`](Problem::with_covariance).
    pub fn with_target(self, values: &[f64], std: &[f64]) -> Result<Problem> {
        let nb = self.base_names.len();
        let mut cov = DMatrix::zeros(nb, nb);
        if std.len() != nb {
            return Err(dims("standard deviations", nb, std.len()));
        }
        for (i, &s) in std.iter().enumerate() {
            if !(0.0..=MAX_PARAMETER).contains(&s) {
                return Err(Error::setting(
                    "Problem::with_target",
                    "std",
                    format!(
                        "the standard deviation of `{}` is {}; it must be at least 0 (0 for a parameter known exactly) and at most {MAX_PARAMETER:e}",
                        self.base_names[i],
                        crate::error::num(s)
                    ),
                ));
            }
            cov[(i, i)] = s * s;
        }
        self.floored(values, cov)
    }

    /// Sets the identified values and their full covariance (symmetric positive
    /// semidefinite, singular only where a parameter is known exactly).
    ///
    /// A parameter whose variance, row and column are all 0 is known exactly (`robid
    /// identify`'s `[known]` parameters) and keeps just the floor below. Otherwise a
    /// negative variance, an asymmetric matrix and a singular coupling of the other
    /// parameters (a zero variance with nonzero covariances, exactly tied parameters) are
    /// refused as given; then each variance gets a floor at the solvers' precision,
    /// (1e-5 |beta_i| + 1e-8 max |beta| + 1e-12)^2: values from noise-free data (std at rounding level) would otherwise make
    /// the whitened problem too ill-conditioned to solve, and a misfit below that precision
    /// meaningless. Values must be finite with magnitude at most
    /// [`MAX_PARAMETER`](crate::limits::MAX_PARAMETER) (a larger identified value is not a
    /// physical parameter: check the identification and its warnings).
    pub fn with_covariance(self, values: &[f64], covariance: &DMatrix<f64>) -> Result<Problem> {
        let nb = self.base_names.len();
        if covariance.shape() != (nb, nb) {
            return Err(dims("covariance entries", nb * nb, covariance.len()));
        }
        if covariance
            .iter()
            .any(|v| !(v.abs() <= MAX_PARAMETER * MAX_PARAMETER))
        {
            return Err(singular());
        }
        // The floor makes any covariance factorable, so what it would hide is refused first,
        // on the covariance as given: a negative variance, two triangles that differ (the
        // factor reads one), and a combination of parameters known exactly though they are
        // not (a zero variance with covariances, tied parameters), decided on the
        // correlations so that units do not matter. A zero row and column is a parameter
        // known exactly, which the floor is right for.
        let name = |i: usize| &self.base_names[i];
        let setting =
            |problem: String| Error::setting("Problem::with_covariance", "covariance", problem);
        if let Some(i) = (0..nb).find(|&i| !(covariance[(i, i)] >= 0.0)) {
            return Err(setting(format!(
                "the variance of `{}` is {}; a variance is at least 0 (0 for a parameter known exactly)",
                name(i),
                crate::error::num(covariance[(i, i)])
            )));
        }
        let known =
            |i: usize| (0..nb).all(|k| covariance[(i, k)] == 0.0 && covariance[(k, i)] == 0.0);
        let free: Vec<usize> = (0..nb).filter(|&i| !known(i)).collect();
        if let Some(&i) = free.iter().find(|&&i| covariance[(i, i)] == 0.0) {
            let k = (0..nb)
                .find(|&k| covariance[(i, k)] != 0.0 || covariance[(k, i)] != 0.0)
                .unwrap_or(i);
            let c = if covariance[(i, k)] != 0.0 {
                covariance[(i, k)]
            } else {
                covariance[(k, i)]
            };
            return Err(setting(format!(
                "the variance of `{}` is 0 but its covariance with `{}` is {}; a parameter known exactly has no covariance (its row and column are 0), else its variance is positive",
                name(i),
                name(k),
                crate::error::num(c)
            )));
        }
        let spread = covariance.diagonal().map(f64::sqrt);
        let n = free.len();
        let correlation = DMatrix::from_fn(n, n, |a, b| {
            let (i, k) = (free[a], free[b]);
            covariance[(i, k)] / (spread[i] * spread[k])
        });
        for a in 0..n {
            for b in 0..a {
                if (correlation[(a, b)] - correlation[(b, a)]).abs() > 1e-9 {
                    let (i, k) = (free[a], free[b]);
                    return Err(setting(format!(
                        "not symmetric: ({}, {}) is {}, ({}, {}) {}; give the covariance matrix itself",
                        name(k),
                        name(i),
                        crate::error::num(covariance[(k, i)]),
                        name(i),
                        name(k),
                        crate::error::num(covariance[(i, k)])
                    )));
                }
            }
        }
        if let Some(a) = first_tied(&correlation) {
            return Err(Error::Singular {
                what: format!(
                    "the covariance of the identified base parameters (`{}` and the ones \
                     before it have a combination of variance 0 or less)",
                    name(free[a])
                ),
                hint: "apart from parameters known exactly (variance, row and column 0) it \
                       must be positive definite: no combination of the parameters can be \
                       known exactly; check how the covariance was computed",
            });
        }
        self.floored(values, covariance.clone())
    }

    /// The identified values and a checked covariance (a full one, the squares of
    /// deviations: 0 for a parameter known exactly, or a tiny one's underflow, or one mapped
    /// from a floored covariance), each variance with its floor, and the whitening.
    pub(crate) fn floored(
        mut self,
        values: &[f64],
        mut covariance: DMatrix<f64>,
    ) -> Result<Problem> {
        let nb = self.base_names.len();
        if values.len() != nb {
            return Err(dims("identified base values", nb, values.len()));
        }
        if let Some(i) = values.iter().position(|v| !(v.abs() <= MAX_PARAMETER)) {
            return Err(Error::setting(
                "Problem::with_covariance",
                "values",
                format!(
                    "the identified value of `{}` is {}, beyond +-{MAX_PARAMETER:e}: not a physical parameter; check the identification (its condition number and relative deviations)",
                    self.base_names[i],
                    crate::error::num(values[i])
                ),
            ));
        }
        let largest = values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (i, v) in values.iter().enumerate() {
            covariance[(i, i)] += (1e-5 * v.abs() + 1e-8 * largest + 1e-12).powi(2);
        }
        let chol = covariance.clone().cholesky().ok_or_else(singular)?;
        let l = chol.l();
        let whitening = l
            .solve_lower_triangular(&DMatrix::identity(nb, nb))
            .filter(|w| w.iter().all(|v| v.is_finite()))
            .ok_or_else(singular)?;
        self.std = covariance.diagonal().map(f64::sqrt);
        self.target = DVector::from_column_slice(values);
        self.whitening = whitening;
        Ok(self)
    }

    /// Base parameters K p of a standard vector.
    ///
    /// # Panics
    /// When `standard` does not hold one value per standard parameter (`K`'s columns): a
    /// size the caller controls (the problem's own model), checked with a message naming
    /// both rather than nalgebra's; returning a `Result` would burden every caller, whose
    /// vectors come from the same model, for a programmer error.
    pub fn base_of(&self, standard: &[f64]) -> DVector<f64> {
        assert_eq!(
            standard.len(),
            self.k.ncols(),
            "Problem::base_of: give one value per standard parameter of the problem's model"
        );
        &self.k * DVector::from_column_slice(standard)
    }

    /// The whitened misfit z = L^-1 (K p - beta).
    ///
    /// # Panics
    /// As [`Problem::base_of`].
    pub fn normalized_residual(&self, standard: &[f64]) -> DVector<f64> {
        &self.whitening * (self.base_of(standard) - &self.target)
    }

    /// Indices of the standard parameters with no effect on any base parameter.
    pub fn no_effect(&self) -> Vec<usize> {
        (0..self.k.ncols())
            .filter(|&s| self.k.column(s).iter().all(|v| v.abs() < 1e-12))
            .collect()
    }
}

/// The first row of a correlation matrix that the rows before it determine: a
/// combination of variance 0 leaves the last of its rows a Cholesky pivot of 0, or of
/// rounding size (1e-8) when computed; a pivot below 1e-6 (a correlation of 1 - 5e-13
/// with the rows before) is taken for 0, and so is a negative one's (not positive
/// semidefinite).
fn first_tied(correlation: &DMatrix<f64>) -> Option<usize> {
    let n = correlation.nrows();
    let mut l = DMatrix::<f64>::zeros(n, n);
    for j in 0..n {
        let pivot = correlation[(j, j)] - l.row(j).columns(0, j).norm_squared();
        if !(pivot >= 1e-12) {
            return Some(j);
        }
        l[(j, j)] = pivot.sqrt();
        for i in j + 1..n {
            let dot = l.row(i).columns(0, j).dot(&l.row(j).columns(0, j));
            l[(i, j)] = (correlation[(i, j)] - dot) / l[(j, j)];
        }
    }
    None
}

/// A covariance that cannot be factored.
fn singular() -> Error {
    Error::Singular {
        what: "the covariance of the identified base parameters".to_owned(),
        hint: "every variance and covariance must be finite, of magnitude at most 1e12 (a \
               deviation of at most 1e6)",
    }
}

fn dims(what: &str, expected: usize, found: usize) -> Error {
    Error::DimensionMismatch {
        what: what.to_owned(),
        expected,
        found,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feasible::LinkShape;
    use crate::feasible::fixture::{problem, problem_with};

    fn names() -> Vec<String> {
        problem(&[0.0; 11]).standard_names
    }

    /// K's shape must match the names, and a non-finite entry is named by its place.
    #[test]
    fn k_must_fit_the_names_and_be_finite() {
        let n = names();
        let e = Problem::new(n.clone(), n[..10].to_vec(), DMatrix::zeros(11, 11)).unwrap_err();
        assert!(
            matches!(
                e,
                Error::DimensionMismatch {
                    expected: 10,
                    found: 11,
                    ..
                }
            ),
            "{e}"
        );
        let e = Problem::new(n.clone(), n.clone(), DMatrix::zeros(11, 10)).unwrap_err();
        assert!(
            matches!(
                e,
                Error::DimensionMismatch {
                    expected: 11,
                    found: 10,
                    ..
                }
            ),
            "{e}"
        );
        let mut k = DMatrix::identity(11, 11);
        k[(2, 7)] = f64::NAN;
        let e = Problem::new(n.clone(), n.clone(), k.clone()).unwrap_err();
        assert!(
            e.to_string()
                .contains("K[2][7] (base parameter `XZ1`, standard parameter `MY1`)"),
            "{e}"
        );
        k[(2, 7)] = 2e6;
        assert!(Problem::new(n.clone(), n.clone(), k.clone()).is_err());
        k[(2, 7)] = 1e6;
        let p = Problem::new(n.clone(), n, k).unwrap();
        assert_eq!(p.target, DVector::zeros(11));
        assert_eq!(p.std, DVector::from_element(11, 1.0));
        assert_eq!(p.whitening, DMatrix::identity(11, 11));
    }

    #[test]
    fn rows_give_k_and_must_be_complete() {
        let n = names();
        let rows: Vec<Vec<f64>> = (0..2)
            .map(|b| (0..11).map(|s| (b * 11 + s) as f64).collect())
            .collect();
        let p = Problem::from_rows(n.clone(), vec!["A".into(), "B".into()], &rows).unwrap();
        assert_eq!(p.k[(1, 3)], 14.0);
        assert_eq!(p.k[(0, 10)], 10.0);
        let short = vec![vec![0.0; 11], vec![0.0; 10]];
        let e = Problem::from_rows(n, vec!["A".into(), "B".into()], &short).unwrap_err();
        assert!(
            matches!(
                e,
                Error::DimensionMismatch {
                    expected: 11,
                    found: 10,
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn shapes_are_one_finite_segment_per_link() {
        let shape = LinkShape {
            from: [0.0; 3],
            to: [0.0, 0.0, 0.3],
        };
        assert!(
            problem(&[0.0; 11])
                .with_shapes(vec![shape])
                .unwrap()
                .shapes
                .is_some()
        );
        assert!(problem(&[0.0; 11]).with_shapes(vec![shape; 2]).is_err());
        for bad in [f64::NAN, 2e6] {
            let far = LinkShape {
                to: [0.0, bad, 0.0],
                ..shape
            };
            assert!(problem(&[0.0; 11]).with_shapes(vec![far]).is_err(), "{bad}");
        }
        let far = LinkShape {
            to: [0.0, 1e6, 0.0],
            ..shape
        };
        assert!(problem(&[0.0; 11]).with_shapes(vec![far]).is_ok());
    }

    /// Extra columns are their own base parameters, free of sign; names must be new.
    #[test]
    fn extra_columns_extend_k_by_an_identity_block() {
        let n = names();
        // three base rows and two extras: no sum of the sizes is also their product
        let mut k = DMatrix::zeros(3, 11);
        k[(0, 0)] = 2.0;
        k[(1, 9)] = 3.0;
        k[(2, 4)] = 4.0;
        let p = Problem::new(n, vec!["A".into(), "B".into(), "C".into()], k).unwrap();
        let e = p
            .with_extra_columns(&["Iam6".into(), "fvm6".into()])
            .unwrap();
        assert_eq!(e.k.shape(), (5, 13));
        assert_eq!(
            (
                e.k[(0, 0)],
                e.k[(1, 9)],
                e.k[(2, 4)],
                e.k[(3, 11)],
                e.k[(4, 12)]
            ),
            (2.0, 3.0, 4.0, 1.0, 1.0)
        );
        assert_eq!(e.k.sum(), 11.0);
        assert_eq!(e.layout.extra, vec![11, 12]);
        assert_eq!(e.standard_names[12], "fvm6");
        assert_eq!(e.base_names[3..], ["Iam6".to_string(), "fvm6".into()]);
        assert_eq!(e.target, DVector::zeros(5));
        assert_eq!(e.std, DVector::from_element(5, 1.0));
        assert_eq!(e.whitening, DMatrix::identity(5, 5));
        let p = problem(&[0.0; 11]);
        assert!(p.clone().with_extra_columns(&["M1".into()]).is_err());
        assert!(
            p.clone()
                .with_extra_columns(&["x".into(), "x".into()])
                .is_err()
        );
        let two =
            Problem::new(names(), vec!["A".into(), "B".into()], DMatrix::zeros(2, 11)).unwrap();
        assert!(two.with_extra_columns(&["B".into()]).is_err());
    }

    /// Identified values are matched to the base parameters by name, in any order.
    #[test]
    fn identified_values_are_matched_by_name() {
        let base = vec!["A".to_string(), "B".into()];
        let p = Problem::new(names(), base, DMatrix::zeros(2, 11)).unwrap();
        let got = p
            .clone()
            .with_identified(&["B".into(), "A".into()], &[2.0, 1.0], &[0.2, 0.1])
            .unwrap();
        assert_eq!(got.target.as_slice(), [1.0, 2.0]);
        // with the floor (1e-5 |beta_i| + 1e-8 max |beta| + 1e-12)^2 added to the variance
        let floored = |s: f64, v: f64| (s * s + (1e-5 * v + 2e-8 + 1e-12).powi(2)).sqrt();
        assert_eq!(got.std.as_slice(), [floored(0.1, 1.0), floored(0.2, 2.0)]);
        // missing, one too many, and lengths that disagree
        assert!(
            p.clone()
                .with_identified(&["A".into(), "C".into()], &[1.0, 2.0], &[0.1; 2])
                .is_err()
        );
        let e = p
            .clone()
            .with_identified(&["A".into(), "B".into(), "C".into()], &[1.0; 3], &[0.1; 3])
            .unwrap_err();
        assert!(e.to_string().contains("`C`"), "{e}");
        assert!(
            p.clone()
                .with_identified(&["A".into(), "B".into()], &[1.0; 2], &[0.1])
                .is_err()
        );
        assert!(
            p.with_identified(&["A".into(), "B".into()], &[1.0], &[0.1; 2])
                .is_err()
        );
    }

    /// A result identified with other drive terms (identify given `--drive Fv,Fc`,
    /// feasible not) names the terms and the `--drive` to give; it said "identify with the
    /// same robot description", which would not have helped.
    #[test]
    fn other_drive_terms_name_the_drive_to_give() {
        let n = names();
        let p = Problem::new(n.clone(), n.clone(), DMatrix::identity(11, 11)).unwrap();
        let mut more = n.clone();
        more.extend(["Fv1".to_string(), "Fc1".into()]);
        let e = p
            .clone()
            .with_identified(&more, &[1.0; 13], &[0.1; 13])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(
                "the model 11 base parameters: it has the drive terms Ia, Fv, Fc (`Ia1`, \
                 `Fv1`, `Fc1`, ...), while the robot models Ia: give `--drive Ia,Fv,Fc`"
            ),
            "{e}"
        );
        assert!(!e.contains("same robot description"), "{e}");
        // fewer: identified without Ia
        let e = p
            .with_identified(&n[..10], &[1.0; 10], &[0.1; 10])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(
                "base parameter `Ia1` is missing from the identified result: it has no drive \
                 terms, while the robot models Ia: give no --drive, and no `drive` key in the description"
            ),
            "{e}"
        );
    }

    /// Deviations must be finite, positive or 0 (known exactly); the variance gets the
    /// solvers' floor (1e-5 |beta_i| + 1e-8 max |beta| + 1e-12)^2 and the whitening is the
    /// inverse factor.
    #[test]
    fn the_covariance_gets_its_floor_and_whitens() {
        let p = problem(&[0.0; 11]);
        for bad in [-1.0, f64::NAN, 2e6] {
            assert!(
                p.clone().with_target(&[0.0; 11], &[bad; 11]).is_err(),
                "{bad}"
            );
        }
        assert!(p.clone().with_target(&[0.0; 11], &[1e-3; 10]).is_err());
        assert!(p.clone().with_target(&[0.0; 10], &[1e-3; 11]).is_err());
        assert!(p.clone().with_target(&[2e6; 11], &[1e-3; 11]).is_err());
        let mut values = [0.0; 11];
        values[0] = 4.0;
        values[1] = -2.0;
        let mut cov = DMatrix::identity(11, 11) * 1e-4;
        cov[(0, 1)] = 5e-5;
        cov[(1, 0)] = 5e-5;
        let got = p.clone().with_covariance(&values, &cov).unwrap();
        let floor = |v: f64| (1e-5 * v + 1e-8 * 4.0 + 1e-12).powi(2);
        assert_eq!(got.std[0], (1e-4 + floor(4.0)).sqrt());
        assert_eq!(got.std[1], (1e-4 + floor(2.0)).sqrt());
        assert_eq!(got.std[5], (1e-4 + floor(0.0)).sqrt());
        // whitened covariance is the identity: W (C + floor) W' = I
        let mut floored = cov.clone();
        for i in 0..11 {
            floored[(i, i)] += floor(values[i].abs());
        }
        let white = &got.whitening * floored * got.whitening.transpose();
        assert!((white - DMatrix::identity(11, 11)).amax() < 1e-12);
        let mut singular = cov.clone();
        singular[(0, 1)] = 1.0;
        singular[(1, 0)] = 1.0;
        assert!(matches!(
            p.clone().with_covariance(&values, &singular),
            Err(Error::Singular { .. })
        ));
        singular[(0, 1)] = f64::INFINITY;
        assert!(matches!(
            p.clone().with_covariance(&values, &singular),
            Err(Error::Singular { .. })
        ));
        assert!(matches!(
            p.clone()
                .with_covariance(&values, &DMatrix::identity(10, 10)),
            Err(Error::DimensionMismatch {
                expected: 121,
                found: 100,
                ..
            })
        ));
        // the floor would make these factorable, so they are refused as given: a negative
        // variance, a zero variance with a covariance (an exact value that is not known
        // exactly), two parameters exactly tied (correlation 1), and a matrix whose two
        // triangles differ (the factor would read one of them)
        let mut negative = cov.clone();
        negative[(5, 5)] = -1e-4;
        let e = p.clone().with_covariance(&values, &negative).unwrap_err();
        assert!(
            e.to_string()
                .contains("the variance of `ZZ1` is -0.0001; a variance is at least 0"),
            "{e}"
        );
        let mut coupled = cov.clone();
        coupled[(5, 5)] = 0.0;
        coupled[(5, 6)] = 1e-6;
        coupled[(6, 5)] = 1e-6;
        let e = p.clone().with_covariance(&values, &coupled).unwrap_err();
        assert!(
            e.to_string()
                .contains("the variance of `ZZ1` is 0 but its covariance with `MX1` is 1e-6"),
            "{e}"
        );
        // a combination known exactly with no variance 0 nor correlation 1: XZ1 = XX1 - XY1
        // (correlations 1/sqrt 2 and -1/sqrt 2), its pivot 0 but for rounding
        let mut combination = cov.clone();
        combination[(2, 2)] = 2e-4;
        combination[(0, 1)] = 0.0;
        combination[(1, 0)] = 0.0;
        combination[(0, 2)] = 1e-4;
        combination[(2, 0)] = 1e-4;
        combination[(1, 2)] = -1e-4;
        combination[(2, 1)] = -1e-4;
        let e = p
            .clone()
            .with_covariance(&values, &combination)
            .unwrap_err();
        assert!(matches!(e, Error::Singular { .. }), "{e}");
        assert!(
            e.to_string().contains("`XZ1` and the ones before it"),
            "{e}"
        );
        // a zero variance, row and column is a parameter known exactly (`robid identify`'s
        // [known]): the floor is its deviation, here 4e-8, and the others are whitened
        // as before
        let mut known = cov.clone();
        known[(5, 5)] = 0.0;
        let got = p.clone().with_covariance(&values, &known).unwrap();
        assert_eq!(got.std[5], floor(0.0).sqrt());
        assert_eq!(got.std[0], (1e-4 + floor(4.0)).sqrt());
        let mut floored = known.clone();
        for i in 0..11 {
            floored[(i, i)] += floor(values[i].abs());
        }
        let white = &got.whitening * floored * got.whitening.transpose();
        assert!((white - DMatrix::identity(11, 11)).amax() < 1e-9);
        let mut std = [1e-2; 11];
        std[5] = 0.0;
        let got = p.clone().with_target(&values, &std).unwrap();
        assert_eq!(got.std[5], floor(0.0).sqrt());
        let mut tied = cov.clone();
        tied[(0, 1)] = 1e-4;
        tied[(1, 0)] = 1e-4;
        assert!(matches!(
            p.clone().with_covariance(&values, &tied),
            Err(Error::Singular { .. })
        ));
        let mut lopsided = cov.clone();
        lopsided[(1, 0)] = 0.0;
        let e = p.clone().with_covariance(&values, &lopsided).unwrap_err();
        assert!(e.to_string().contains("not symmetric: (XX1, XY1)"), "{e}");
        // a deviation of 1e-300 is positive, though its square underflows to 0: the floor
        // takes it (4e-8 here)
        let tiny = p.clone().with_target(&values, &[1e-300; 11]).unwrap();
        assert_eq!(tiny.std[5], floor(0.0).sqrt());
        // nearly tied is a covariance (correlation 1 - 1e-9)
        let mut close = cov.clone();
        close[(0, 1)] = 1e-4 * (1.0 - 1e-9);
        close[(1, 0)] = close[(0, 1)];
        assert!(p.clone().with_covariance(&values, &close).is_ok());
        // variances up to MAX_PARAMETER^2 (a deviation of 1e6), not beyond
        let wide = DMatrix::identity(11, 11) * 1e11;
        assert!(p.clone().with_covariance(&values, &wide).is_ok());
        let wider = DMatrix::identity(11, 11) * 2e12;
        assert!(matches!(
            p.with_covariance(&values, &wider),
            Err(Error::Singular { .. })
        ));
    }

    /// K p, the whitened misfit, and the parameters K does not see.
    #[test]
    fn base_misfit_and_blind_parameters() {
        let mut k = DMatrix::zeros(2, 11);
        k[(0, 0)] = 2.0;
        k[(0, 3)] = -1.0;
        k[(1, 9)] = 1.0;
        k[(1, 4)] = 1e-13;
        let p = Problem::new(names(), vec!["A".into(), "B".into()], k)
            .unwrap()
            .with_target(&[1.0, 3.0], &[0.5, 2.0])
            .unwrap();
        let mut standard = vec![0.0; 11];
        standard[0] = 1.0;
        standard[3] = 0.5;
        standard[9] = 4.0;
        assert_eq!(p.base_of(&standard).as_slice(), [1.5, 4.0]);
        let z = p.normalized_residual(&standard);
        assert!((z[0] - 0.5 / p.std[0]).abs() < 1e-12 && (z[1] - 1.0 / p.std[1]).abs() < 1e-12);
        assert_eq!(p.no_effect(), vec![1, 2, 4, 5, 6, 7, 8, 10]);
        let all = problem_with(&[0.0; 11], &["Fv"]);
        assert!(all.no_effect().is_empty());
    }

    /// A standard vector of the wrong length panicked inside nalgebra's Gemv; the
    /// documented panic names the fix.
    #[test]
    #[should_panic(expected = "give one value per standard parameter")]
    fn base_of_names_a_standard_vector_of_the_wrong_length() {
        let p = Problem::new(names(), vec!["A".into()], DMatrix::zeros(1, 11)).unwrap();
        p.base_of(&[1.0]);
    }
}
