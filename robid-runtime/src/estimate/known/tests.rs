//! Known parameters against independent computations: the count against the numeric rank
//! of the unknowns' regressor, values against `K theta`, deviations against the reduced
//! system's and by their definition.

use nalgebra::{DMatrix, DVector};

use super::KnownParameters;
use crate::estimate::{Observation, ols, wls};
use crate::model::{LengthError, Model, ProgramKind, check_arguments};
use crate::rng::Rng;

/// A model that is only its map `base = K standard` (row-major `nb x ns`).
struct Map {
    k: DMatrix<f64>,
    standard: Vec<String>,
    base: Vec<String>,
}

impl Map {
    fn new(k: DMatrix<f64>) -> Self {
        let standard = (1..=k.ncols()).map(|i| format!("s{i}")).collect();
        let base = (1..=k.nrows()).map(|i| format!("b{i}")).collect();
        Self { k, standard, base }
    }
}

impl Model for Map {
    fn name(&self) -> &str {
        "map"
    }
    fn dof(&self) -> usize {
        1
    }
    fn standard_parameter_count(&self) -> usize {
        self.standard.len()
    }
    fn standard_parameter_name(&self, index: usize) -> Option<&str> {
        self.standard.get(index).map(String::as_str)
    }
    fn base_parameter_count(&self) -> usize {
        self.base.len()
    }
    fn base_parameter_name(&self, index: usize) -> Option<&str> {
        self.base.get(index).map(String::as_str)
    }
    fn run(
        &self,
        program: ProgramKind,
        inputs: &[&[f64]],
        output: &mut [f64],
    ) -> Result<(), LengthError> {
        check_arguments(program, self.sizes(), inputs, output)?;
        match (program, inputs) {
            (ProgramKind::BaseFromStandard, [s]) => {
                let b = &self.k * DVector::from_column_slice(s);
                output.copy_from_slice(b.as_slice());
            }
            _ => output.fill(0.0),
        }
        Ok(())
    }
}

/// A random full-rank base regressor (`rows x nb`, one joint) and its observation.
fn observation(w: DMatrix<f64>, y: DVector<f64>, extra: usize) -> Observation {
    let nb = w.ncols() - extra;
    let names = (1..=nb)
        .map(|i| format!("b{i}"))
        .chain((1..=extra).map(|i| format!("e{i}")))
        .collect();
    let rows = w.nrows();
    Observation::new(
        w,
        y,
        std::iter::once(0..rows).collect(),
        (0..rows).collect(),
        names,
    )
    .unwrap()
}

fn random(rng: &mut Rng, rows: usize, cols: usize) -> DMatrix<f64> {
    DMatrix::from_fn(rows, cols, |_, _| rng.uniform(-1.0, 1.0))
}

/// b1 = s1 + s2 (a parent's mass with its child's), b2 = s3 + 0.4 s2 (a first moment with
/// the child's mass at 0.4 m), b3 = s4 + 0.16 s2 + 2 s3, b4 = 2 s1 + 2 s2 + s5.
fn arm() -> Map {
    Map::new(DMatrix::from_row_slice(
        4,
        5,
        &[
            1.0, 1.0, 0.0, 0.0, 0.0, //
            0.0, 0.4, 1.0, 0.0, 0.0, //
            0.0, 0.16, 2.0, 1.0, 0.0, //
            2.0, 2.0, 0.0, 0.0, 1.0,
        ],
    ))
}

#[test]
fn zomaya_known_parameters_fix_and_fold_base_rows() {
    let model = arm();
    // s1 and s2 known: b1 is fixed, b2..b4 keep one unknown each
    let k = KnownParameters::new(&model, &[(0, 3.0), (1, 2.0)]).unwrap();
    assert_eq!(k.known_names(), ["b1"]);
    assert_eq!(k.kept_names(), ["b2", "b3", "b4"]);
    assert_eq!(k.offset(), [5.0, 0.8, 0.32, 10.0]);
    // s3 and s5 known: b2 = s2 + .. and b4 = 2 (s1 + s2) + .. are multiples of b1's unknowns
    let k = KnownParameters::new(&model, &[(2, 1.0), (4, 0.5)]).unwrap();
    assert!(k.known_names().is_empty());
    assert_eq!(k.kept_names(), ["b1", "b2", "b3"]);
    assert!((k.map[(3, 0)] - 2.0).abs() < 1e-15, "{}", k.map);
    // s3 enters only as s1, s2 and s4 can (its column is -2.5 K_s1 + 2.5 K_s2 + 1.6 K_s4):
    // its value moves no estimate; s5 fixes b4's share
    assert_eq!(k.without_effect(), [2]);
    // s2 alone: s1, s3, s4 and s5 span every base row; with s1 known too, both fix b1
    let k = KnownParameters::new(&model, &[(1, 2.0)]).unwrap();
    assert_eq!(k.without_effect(), [1]);
    let k = KnownParameters::new(&model, &[(0, 3.0), (1, 2.0)]).unwrap();
    assert!(k.without_effect().is_empty());
    // nothing known: the model's own base parameters, unchanged
    let k = KnownParameters::new(&model, &[]).unwrap();
    assert_eq!(k.kept_names(), ["b1", "b2", "b3", "b4"]);
    assert_eq!(k.map, DMatrix::identity(4, 4));
    // a known index outside the model is refused
    let e = KnownParameters::new(&model, &[(5, 1.0)]).unwrap_err();
    assert!(e.to_string().contains("5 standard parameters"), "{e}");
    // an index given twice is refused (the last value won)
    let e = KnownParameters::new(&model, &[(1, 1.0), (1, 2.0)])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("standard parameter 1") && e.contains("given twice"),
        "{e}"
    );
}

/// Random maps with random known subsets: the kept count equals the numeric rank of the
/// unknowns' own regressor `W K_u` (an SVD, independent of the row selection), and
/// noise-free data give back `K theta` for every base parameter and the extra column.
#[test]
fn zomaya_known_parameters_keep_the_rank_of_the_unknowns_and_recover_the_truth() {
    let mut rng = Rng::new(7);
    for case in 0..40 {
        let (nb, ns) = (2 + rng.below(6), 8 + rng.below(6));
        // K of rank nb with integer-ish entries, as geometric products are
        let mut k = DMatrix::from_fn(nb, ns, |_, _| match rng.below(3) {
            0 => 0.0,
            _ => (rng.below(5) as f64 - 2.0) * 0.5,
        });
        for i in 0..nb {
            k[(i, i)] = 1.0;
        }
        let model = Map::new(k.clone());
        let theta: Vec<f64> = (0..ns).map(|_| rng.uniform(-2.0, 2.0)).collect();
        let known: Vec<(usize, f64)> = (0..ns)
            .filter(|_| rng.below(2) == 0)
            .map(|i| (i, theta[i]))
            .collect();
        let regrouped = KnownParameters::new(&model, &known).unwrap();
        let w = random(&mut rng, 60, nb + 1);
        let unknown: Vec<usize> = (0..ns)
            .filter(|i| known.iter().all(|(j, _)| j != i))
            .collect();
        let k_u = DMatrix::from_fn(nb, unknown.len(), |r, c| k[(r, unknown[c])]);
        let rank = (w.columns(0, nb) * &k_u)
            .singular_values()
            .iter()
            .filter(|s| **s > 1e-9)
            .count();
        assert_eq!(regrouped.kept_names().len(), rank, "case {case}");
        let base = &k * DVector::from_vec(theta.clone());
        let mut truth: Vec<f64> = base.iter().copied().collect();
        truth.push(0.7); // the extra column
        let y = &w * DVector::from_column_slice(&truth);
        let obs = observation(w, y, 1);
        let reduced = regrouped.reduce(&obs).unwrap();
        assert_eq!(reduced.cols(), rank + 1);
        let e = regrouped
            .expand(&ols(&reduced, 1e-10).unwrap(), &obs, &reduced, 1e-10)
            .unwrap();
        for (i, (v, t)) in e.values.iter().zip(&truth).enumerate() {
            assert!(
                (v - t).abs() < 1e-10,
                "case {case} {}: {v} vs {t}",
                e.names[i]
            );
        }
        assert_eq!(e.names[nb], "e1");
        for n in &e.known {
            let i = e.names.iter().position(|m| m == n).unwrap();
            assert_eq!(e.std[i], 0.0);
        }
    }
}

/// Deviations: a kept parameter keeps its estimator's deviation, which equals the full
/// system's when nothing is known; a folded one is its multiple (b4 = 2 b1 + known), with
/// OLS and with WLS (whose weights are carried over).
#[test]
fn zomaya_known_parameters_carry_their_deviations() {
    let mut rng = Rng::new(3);
    let model = arm();
    let theta = [1.0, 0.5, 0.3, 0.2, 0.9];
    let base = arm().k * DVector::from_column_slice(&theta);
    let w = random(&mut rng, 200, 4);
    let noise = DVector::from_fn(200, |_, _| 0.05 * rng.normal());
    let y = &w * &base + noise;
    let obs = observation(w.clone(), y.clone(), 0);
    let full = ols(&obs, 1e-10).unwrap();
    let none = KnownParameters::new(&model, &[]).unwrap();
    let reduced = none.reduce(&obs).unwrap();
    let same = none
        .expand(&ols(&reduced, 1e-10).unwrap(), &obs, &reduced, 1e-10)
        .unwrap();
    for i in 0..4 {
        assert!((same.values[i] - full.values[i]).abs() < 1e-12);
        assert!((same.std[i] - full.std[i]).abs() < 1e-12 * full.std[i]);
    }
    // s3 and s5 known: b4 = 2 b1's unknown part + 2 * 0 ... its deviation is twice b1's
    let k = KnownParameters::new(&model, &[(2, theta[2]), (4, theta[4])]).unwrap();
    let reduced = k.reduce(&obs).unwrap();
    for estimate in [ols(&reduced, 1e-10).unwrap(), wls(&reduced, 1e-10).unwrap()] {
        let e = k.expand(&estimate, &obs, &reduced, 1e-10).unwrap();
        // the reduced system's robust deviations are of its own parameters, fewer and in
        // another order: the expanded estimate carries none (they were paired with the
        // wrong names)
        assert!(estimate.robust.is_some() && e.robust.is_none());
        assert!(
            (e.std[3] - 2.0 * e.std[0]).abs() < 1e-12 * e.std[0],
            "{:?}",
            e.std
        );
        for i in 0..4 {
            // within 4 sigma of the truth
            assert!((e.values[i] - base[i]).abs() < 4.0 * e.std[i], "{i}: {e:?}");
        }
    }
}

/// The derived deviations of torques near 1e-170 (the test above scaled): sigma^2 underflows
/// to 0 there, and b4's deviation, derived from the solved ones, read 0 (exact) beside
/// b1's right one.
#[test]
fn zomaya_known_parameters_carry_the_deviations_of_tiny_torques() {
    let mut rng = Rng::new(3);
    let model = arm();
    let scale = 1e-170;
    let theta = [1.0, 0.5, 0.3, 0.2, 0.9].map(|v| v * scale);
    let base = arm().k * DVector::from_column_slice(&theta);
    let w = random(&mut rng, 200, 4);
    let noise = DVector::from_fn(200, |_, _| 0.05 * scale * rng.normal());
    let obs = observation(w.clone(), &w * &base + noise, 0);
    let k = KnownParameters::new(&model, &[(2, theta[2]), (4, theta[4])]).unwrap();
    let reduced = k.reduce(&obs).unwrap();
    let e = k
        .expand(&ols(&reduced, 1e-10).unwrap(), &obs, &reduced, 1e-10)
        .unwrap();
    assert!(e.std[0] > 0.0, "{:?}", e.std);
    assert!(
        (e.std[3] - 2.0 * e.std[0]).abs() < 1e-12 * e.std[0],
        "{:?}",
        e.std
    );
}

#[test]
fn zomaya_known_parameters_check_the_columns_they_reduce() {
    let model = arm();
    let k = KnownParameters::new(&model, &[(0, 1.0)]).unwrap();
    let w = DMatrix::from_element(5, 3, 1.0);
    let obs = observation(w, DVector::zeros(5), 0);
    let e = k.reduce(&obs).unwrap_err();
    assert!(e.to_string().contains("4 base parameters"), "{e}");
}

/// The warning about parameters uncertain by more than their size judges the base
/// parameters the table gives, not what is left of them once the known values are taken
/// out: `b1 = s1 + s2` with `s2 = 1` known and `s1 = 1e-4` is known to about 0.4 % of its
/// value, though its unknown part `s1` is uncertain by thousands of percent (the warning
/// named `b1` with its remainder's deviation beside a table giving it 0.4 %).
#[test]
fn the_uncertainty_warning_judges_the_expanded_values() {
    use crate::estimate::QualityWarning;
    let mut rng = Rng::new(5);
    let model = arm();
    let theta = [1e-4, 1.0, 0.3, 0.2, 0.9];
    let base = arm().k * DVector::from_column_slice(&theta);
    let w = random(&mut rng, 200, 4);
    let noise = DVector::from_fn(200, |_, _| 0.05 * rng.normal());
    let obs = observation(w.clone(), &w * &base + noise, 0);
    let k = KnownParameters::new(&model, &[(1, theta[1])]).unwrap();
    let reduced = k.reduce(&obs).unwrap();
    let estimate = ols(&reduced, 1e-10).unwrap();
    let uncertain = |warnings: &[QualityWarning]| {
        warnings
            .iter()
            .filter_map(|w| match w {
                QualityWarning::Uncertain { parameters, .. } => Some(parameters.clone()),
                _ => None,
            })
            .flatten()
            .collect::<Vec<_>>()
    };
    // the reduced system's own estimate: b1's remainder s1 is uncertain
    assert!(uncertain(&estimate.warnings).contains(&"b1".to_string()));
    let e = k.expand(&estimate, &obs, &reduced, 1e-10).unwrap();
    assert!(e.rel_std_percent[0] < 5.0, "{:?}", e.rel_std_percent);
    assert!(uncertain(&e.warnings).is_empty(), "{:?}", e.warnings);
    // a base parameter the expansion leaves uncertain is still named, with its own figure
    let mut far = estimate.clone();
    far.std = far.std.iter().map(|s| s * 1e4).collect();
    let e = k.expand(&far, &obs, &reduced, 1e-10).unwrap();
    let named = uncertain(&e.warnings);
    for (i, n) in e.names.iter().enumerate() {
        assert_eq!(
            named.contains(n),
            e.rel_std_percent[i] > 100.0,
            "{n}: {} %, {named:?}",
            e.rel_std_percent[i]
        );
    }
}
