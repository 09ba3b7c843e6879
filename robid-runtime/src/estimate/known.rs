//! Identification with standard parameters known beforehand (Zomaya 1994 takes the link
//! masses as known and identifies the rest; docs/identification.md#known-parameters).
//!
//! The base parameters are `b = K theta` (the model's `base_from_standard`, a linear map).
//! Split the standard parameters into the known `theta_k` and the unknown `theta_u`:
//! `b = K_k theta_k + K_u theta_u = b0 + K_u theta_u`. The torques the unknowns can explain
//! span `W K_u`, whose rank is `rank(K_u)` because the base regressor `W` has full column
//! rank: the regrouping of the rest keeps `r = rank(K_u)` base parameters, the first rows of
//! `K_u` (in the model's order) that are independent of the earlier kept ones, and writes
//! every row as a combination of them, `K_u = L K_kept`. The reduced system is
//! `(W L) beta = y - W b0`, minimal by construction; after solving, every base parameter is
//! `b = b0 + L beta`: the kept ones are estimated (their known part added back), the others
//! follow, and those with no unknown term at all are known.
//!
//! ## Reference
//! A. Y. Zomaya, "Extraction and computation of identifiable parameters in robot dynamic
//! models: theory and application", IEE Proceedings - Control Theory and Applications
//! 141(1), 1994 (the masses known: 9N unknowns).

use nalgebra::{DMatrix, DVector};

use crate::Model;
use crate::error::{Error, Result};
use crate::estimate::lstsq::solve;
use crate::estimate::quality::{effects, reassess_uncertain, relative_column_norms};
use crate::estimate::{Estimate, Observation};

/// Relative size below which a row of `K_u` counts as dependent on the kept rows (or as
/// zero): the entries are exact geometric products, so a dependent row leaves a residual
/// at the level of rounding (1e-16), an independent one of order 1.
const DEPENDENT: f64 = 1e-9;

/// The base parameters of a model with some standard parameters known.
#[derive(Debug, Clone)]
pub struct KnownParameters {
    /// The model's base parameter names.
    names: Vec<String>,
    /// `b0 = K_k theta_k`: the known part of every base parameter.
    offset: DVector<f64>,
    /// `L` (base x kept): every base parameter's unknown part in the kept ones.
    map: DMatrix<f64>,
    /// The base parameters estimated (indices into `names`).
    kept: Vec<usize>,
    /// The base parameters with no unknown term: fixed by the known values.
    known: Vec<usize>,
    /// The known standard parameters that fix nothing: each enters the base parameters
    /// only as the unknown ones can (its column of K in the span of theirs), so its value
    /// moves no estimate.
    idle: Vec<usize>,
}

impl KnownParameters {
    /// The regrouping of `model`'s parameters with `known` standard parameters (index into
    /// the model's standard parameters, value) fixed.
    ///
    /// # Errors
    ///
    /// [`Error::Setting`] for an index outside the model, a value that is not finite, or
    /// an index given twice; [`Error::NonFiniteResult`] when the known values overflow the
    /// model's map.
    ///
    /// ```
    /// use robid_runtime::Model;
    /// use robid_runtime::estimate::KnownParameters;
    ///
    /// /// The base parameters left to estimate when the masses `M1`.. are known.
    /// fn unknown_with_masses(model: &dyn Model, masses: &[f64]) -> robid_runtime::Result<Vec<String>> {
    ///     let known: Vec<(usize, f64)> = (0..model.standard_parameter_count())
    ///         .filter(|&i| model.standard_parameter_name(i).is_some_and(|n| n.starts_with('M') && n[1..].parse::<usize>().is_ok()))
    ///         .zip(masses.iter().copied())
    ///         .collect();
    ///     let regrouped = KnownParameters::new(model, &known)?;
    ///     Ok(regrouped.kept_names().into_iter().map(String::from).collect())
    /// }
    /// ```
    pub fn new(model: &dyn Model, known: &[(usize, f64)]) -> Result<Self> {
        let (ns, nb) = (
            model.standard_parameter_count(),
            model.base_parameter_count(),
        );
        let names = crate::model::base_parameter_names(model);
        let mut theta = vec![0.0; ns];
        let mut is_known = vec![false; ns];
        for &(i, v) in known {
            if i >= ns || !v.is_finite() {
                return Err(Error::setting(
                    "KnownParameters",
                    "known",
                    format!(
                        "({i}, {v}) is not a finite value of one of the {ns} standard parameters"
                    ),
                ));
            }
            // a repeated index took its last value without a word: which one was meant?
            if is_known[i] {
                let name = model.standard_parameter_name(i).unwrap_or_default();
                return Err(Error::setting(
                    "KnownParameters",
                    "known",
                    format!(
                        "standard parameter {i} (`{name}`) is given twice ({} and {v}); give each known parameter once",
                        theta[i]
                    ),
                ));
            }
            theta[i] = v;
            is_known[i] = true;
        }
        let mut offset = DVector::zeros(nb);
        model.base_from_standard_into(&theta, offset.as_mut_slice())?;
        // the columns of K for the unknown standard parameters
        let unknown: Vec<usize> = (0..ns).filter(|&i| !is_known[i]).collect();
        let k = crate::model::base_map(model)?;
        let k_u = k.select_columns(&unknown);
        if let Some(i) = offset.iter().chain(k_u.iter()).position(|v| !v.is_finite()) {
            return Err(Error::NonFiniteResult {
                what: format!("the base parameters of the known values (entry {i})"),
                cause: "the known values are too large for the model's map; give them in SI units"
                    .into(),
            });
        }
        let (kept, known_rows) = independent_rows(&k_u);
        let map = combination(&k_u, &kept)?;
        // a known parameter fixes something only where its column of K leaves the span of
        // the unknown ones' (the orthonormal basis of that span: K_u's left singular
        // vectors of the nonzero singular values)
        let svd = k_u.clone().svd(true, false);
        let top = svd.singular_values.iter().fold(0.0f64, |a, s| a.max(*s));
        let span: Vec<DVector<f64>> = svd.u.as_ref().map_or_else(Vec::new, |u| {
            svd.singular_values
                .iter()
                .enumerate()
                .filter(|(_, s)| **s > DEPENDENT * top)
                .map(|(c, _)| u.column(c).into_owned())
                .collect()
        });
        let mut idle = Vec::new();
        for &(i, _) in known {
            let mut rest = k.column(i).into_owned();
            let size = rest.norm();
            for u in &span {
                let along = u.dot(&rest);
                rest.axpy(-along, u, 1.0);
            }
            if rest.norm() <= DEPENDENT * size.max(f64::MIN_POSITIVE) {
                idle.push(i);
            }
        }
        Ok(Self {
            names,
            offset,
            map,
            kept,
            known: known_rows,
            idle,
        })
    }

    /// The known standard parameters (indices into the model's) that fix nothing: each
    /// enters the base parameters only alongside unknown ones that can stand for it
    /// (`M2` of a two-link arm, in `ZZR1 = ZZ1 + YY2 + 0.16 M2` with `ZZ1` unknown), or
    /// not at all, so its value changes no estimate.
    pub fn without_effect(&self) -> &[usize] {
        &self.idle
    }

    /// The base parameters that are estimated, in the model's order.
    pub fn kept_names(&self) -> Vec<&str> {
        self.kept.iter().map(|&i| self.names[i].as_str()).collect()
    }

    /// The base parameters fixed by the known values alone.
    pub fn known_names(&self) -> Vec<&str> {
        self.known.iter().map(|&i| self.names[i].as_str()).collect()
    }

    /// The known part `b0` of every base parameter.
    pub fn offset(&self) -> &[f64] {
        self.offset.as_slice()
    }

    /// The reduced system of `obs`, whose first columns are the model's base parameters (in
    /// order) and the rest extra columns, kept as they are: `W L` for the base columns and
    /// `y - W b0` on the right-hand side.
    pub fn reduce(&self, obs: &Observation) -> Result<Observation> {
        let nb = self.names.len();
        if obs.cols() < nb || obs.names[..nb] != self.names[..] {
            return Err(Error::setting(
                "KnownParameters",
                "reduce",
                format!(
                    "the observation's first columns must be the model's {nb} base parameters in \
                     order; found {}",
                    obs.names.join(", ")
                ),
            ));
        }
        let extra = obs.cols() - nb;
        let base = obs.w.columns(0, nb);
        let mut w = DMatrix::zeros(obs.rows(), self.kept.len() + extra);
        w.columns_mut(0, self.kept.len())
            .copy_from(&(base * &self.map));
        w.columns_mut(self.kept.len(), extra)
            .copy_from(&obs.w.columns(nb, extra));
        let y = &obs.y - base * &self.offset;
        let names = self
            .kept
            .iter()
            .map(|&i| self.names[i].clone())
            .chain(obs.names[nb..].iter().cloned())
            .collect();
        Observation::new(
            w,
            y,
            obs.joint_rows.clone(),
            obs.sample_of_row.clone(),
            names,
        )
    }

    /// Every base parameter (then the extra columns) from the estimate of the reduced system
    /// `reduced` (unweighted; the estimate's WLS weights are applied here): values `b0 + L
    /// beta`; the estimated ones keep their standard deviations, the others get
    /// `sqrt(diag(L C L'))` with `C = sigma^2 (W'W)^-1` of the solved system, and the known
    /// ones 0 (listed in [`Estimate::known`]). The parameters uncertain by more than their
    /// size are judged again on these values, against the columns of `system`, the system
    /// before [`KnownParameters::reduce`] (the reduced estimate's warning named a base
    /// parameter with the relative deviation of what is left of it once the known values are
    /// taken out: `MXR1 (118 %)` beside a table giving it 0.00 %).
    pub fn expand(
        &self,
        estimate: &Estimate,
        system: &Observation,
        reduced: &Observation,
        tolerance: f64,
    ) -> Result<Estimate> {
        let (nb, r) = (self.names.len(), self.kept.len());
        let extra = estimate.values.len().saturating_sub(r);
        if estimate.values.len() != reduced.cols() {
            return Err(Error::DimensionMismatch {
                what: "estimate of the reduced system".into(),
                expected: reduced.cols(),
                found: estimate.values.len(),
            });
        }
        let mut solved = reduced.clone();
        if let Some(weights) = &estimate.weights {
            for (rows, wj) in reduced.joint_rows.iter().zip(weights) {
                solved.w.rows_mut(rows.start, rows.len()).scale_mut(*wj);
            }
        }
        let solution = solve(&solved.w, &solved.y, &solved.names, tolerance)?;
        // L extended by the identity on the extra columns
        let mut l = DMatrix::zeros(nb + extra, r + extra);
        l.view_mut((0, 0), (nb, r)).copy_from(&self.map);
        for e in 0..extra {
            l[(nb + e, r + e)] = 1.0;
        }
        let beta = DVector::from_column_slice(&estimate.values);
        let mut values = &l * &beta;
        for i in 0..nb {
            values[i] += self.offset[i];
        }
        // sqrt(diag(L C L')) with C = sigma^2 (W'W)^-1, each from the scaled factors (the
        // product of the matrices underflowed to 0 for a column near 1e200)
        // sigma as the estimate's own deviations have it (std_k = sigma sqrt((W'W)^-1_kk)),
        // not sqrt(sigma2): that underflows to 0 for torques near 1e-170, where the
        // deviations stay right (the derived ones read 0, exact)
        let sigma = solution
            .inverse
            .root_diagonal()
            .iter()
            .zip(&estimate.std)
            .filter(|(root, _)| **root > 0.0)
            .max_by(|a, b| a.0.total_cmp(b.0))
            .map_or(estimate.sigma2.sqrt(), |(root, std)| std / root);
        let mut std: Vec<f64> = (0..nb + extra)
            .map(|i| {
                let row: Vec<f64> = l.row(i).iter().copied().collect();
                sigma * solution.root_quadratic(&row)
            })
            .collect();
        for (k, &i) in self.kept.iter().enumerate() {
            std[i] = estimate.std[k];
        }
        std[nb..].copy_from_slice(&estimate.std[r..]);
        for &i in &self.known {
            std[i] = 0.0;
        }
        let rel_std_percent: Vec<f64> = std
            .iter()
            .zip(values.iter())
            .map(|(s, v)| {
                if *v == 0.0 {
                    if *s == 0.0 { 0.0 } else { f64::INFINITY }
                } else {
                    100.0 * s / v.abs()
                }
            })
            .collect();
        let names: Vec<String> = self
            .names
            .iter()
            .chain(&estimate.names[r..])
            .cloned()
            .collect();
        if let Some(i) = values.iter().chain(&std).position(|v| !v.is_finite()) {
            return Err(Error::NonFiniteResult {
                what: format!("the base parameter `{}`", names[i % names.len()]),
                cause: "the known values or the estimate overflowed: check their units".into(),
            });
        }
        let effect = effects(&std, &relative_column_norms(&system.w, &system.y));
        let warnings =
            reassess_uncertain(&estimate.warnings, &names, &rel_std_percent, &effect, false);
        Ok(Estimate {
            names,
            values: values.iter().copied().collect(),
            std,
            rel_std_percent,
            warnings,
            known: self.known.iter().map(|&i| self.names[i].clone()).collect(),
            // the reduced system's, in its own order and count: none for the expanded
            // estimate (as documented)
            robust: None,
            ..estimate.clone()
        })
    }
}

/// The rows of `k` kept as independent (each independent of the earlier kept ones), and the
/// rows that are zero; by Gram-Schmidt on the rows, twice for accuracy.
fn independent_rows(k: &DMatrix<f64>) -> (Vec<usize>, Vec<usize>) {
    let mut basis: Vec<DVector<f64>> = Vec::new();
    let (mut kept, mut zero) = (Vec::new(), Vec::new());
    for i in 0..k.nrows() {
        let row: DVector<f64> = k.row(i).transpose();
        let size = row.norm();
        if size == 0.0 {
            zero.push(i);
            continue;
        }
        let mut rest = row.clone();
        for _ in 0..2 {
            for b in &basis {
                let along = b.dot(&rest);
                rest.axpy(-along, b, 1.0);
            }
        }
        let left = rest.norm();
        if left > DEPENDENT * size {
            basis.push(rest / left);
            kept.push(i);
        }
    }
    (kept, zero)
}

/// `L` with `k = L k[kept]`: each row's coefficients in the kept rows (least squares on the
/// kept rows, which are independent; exact for the dependent rows up to rounding).
fn combination(k: &DMatrix<f64>, kept: &[usize]) -> Result<DMatrix<f64>> {
    let r = kept.len();
    let mut l = DMatrix::zeros(k.nrows(), r);
    if r == 0 {
        return Ok(l);
    }
    let kept_rows = DMatrix::from_fn(r, k.ncols(), |a, c| k[(kept[a], c)]);
    // rows of k = L kept_rows  <=>  kept_rows' L' = k'
    let svd = kept_rows.transpose().svd(true, true);
    for i in 0..k.nrows() {
        let target: DVector<f64> = k.row(i).transpose();
        let c = svd.solve(&target, 0.0).map_err(|e| Error::Singular {
            what: format!("the known parameters' map ({e})"),
            hint: "the model's base_from_standard gave values too different in size",
        })?;
        l.row_mut(i).copy_from(&c.transpose());
    }
    for (a, &i) in kept.iter().enumerate() {
        l.row_mut(i).fill(0.0);
        l[(i, a)] = 1.0;
    }
    Ok(l)
}

#[cfg(test)]
mod tests;
