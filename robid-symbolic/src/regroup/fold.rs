//! The coefficients with which each dependency found by the rank analysis
//! is folded into the kept parameters.
//!
//! Without geometric symbols a coefficient is a number: exact where it is
//! (see `exact.rs`), a float otherwise. With symbols, the coefficient of a
//! dependency is a function of them, and the base parameters must hold for
//! every value, since the symbols are inputs of the generated code. The
//! dependent column and the columns it depends on are sampled again at other
//! values of the symbols (each sample: a fresh value of every symbol in
//! [`SYMBOL_SAMPLES`], the columns at random states, the coefficients by least
//! squares on the columns the dependency involves), and each coefficient is
//! fitted by a polynomial in the atoms of those columns (`atoms.rs`), of the
//! lowest degree that reproduces it: degree 0 is a constant. A fit of `m`
//! monomials uses `m + 3` samples and is checked on 2 more; a coefficient
//! that no polynomial up to [`exact::MAX_DEGREE`] (within
//! [`exact::MAX_MONOMIALS`]) reproduces is an error that names the symbols.
//!
//! A polynomial identity that holds at random points holds everywhere, so
//! the fitted coefficients, hence the base parameters and the base regressor,
//! are exact for every value of the symbols (at particular values some base
//! parameters may also become dependent: the set is then still correct,
//! though not minimal). A coefficient such as `1/g` or `tan(alpha)` has no
//! value at some values of the symbols; it is refused rather than written
//! with a division.

use super::atoms::{self, Atom};
use super::exact::{self, Samples};
use super::rank::{self, DEPENDENT};
use super::{Candidate, RegroupError, SLOT_NAMES};
use crate::dynamics::Derivation;
use crate::expr::{Id, Symbol, Values};
use crate::robot::bounds::SYMBOL_SAMPLES;
use crate::sample::Rng;

/// Extra samples of a fit beyond its monomials (least squares, so a wrong
/// degree leaves a residual).
const MARGIN: usize = 3;

/// Samples that check a fit without taking part in it.
const CHECKS: usize = 2;

/// A dependent candidate and its coefficients at the first sample.
pub(super) struct Dependency {
    /// Its index among the candidates.
    pub(super) candidate: usize,
    /// `(position among the kept candidates, coefficient)`, nonzero only.
    pub(super) numeric: Vec<(usize, f64)>,
}

/// The fit of one dependency's coefficients.
struct Fit {
    /// Positions among the kept candidates of the columns it involves.
    support: Vec<usize>,
    /// The atoms of the involved columns.
    atoms: Vec<Atom>,
    /// `values[k][s]`: coefficient on `support[k]` at sample `s`.
    values: Vec<Vec<f64>>,
    /// `atom_values[s][a]`: atom `a` at sample `s`.
    atom_values: Vec<Vec<f64>>,
    /// The expression of each coefficient, once fitted.
    result: Vec<Option<Id>>,
    /// No higher degree can be tried (too many monomials).
    exhausted: bool,
}

impl Fit {
    fn done(&self) -> bool {
        self.result.iter().all(Option::is_some)
    }
}

/// Samples of the geometric symbols shared by every fit: the values, and the
/// same as arena values for evaluating atoms and fitted expressions.
struct Points {
    values: Vec<Vec<f64>>,
    bound: Vec<Values>,
}

impl Derivation {
    /// The coefficients (kept position, expression) of each dependency.
    pub(super) fn dependency_coefficients(
        &mut self,
        dependencies: &[Dependency],
        kept: &[usize],
        candidates: &[Candidate],
        geometry: &[Id],
        rng: &mut Rng,
    ) -> Result<Vec<Vec<(usize, Id)>>, RegroupError> {
        let symbols: Vec<Symbol> = self.arena.free_symbols(geometry);
        let mut fits: Vec<Fit> = Vec::with_capacity(dependencies.len());
        for d in dependencies {
            let support: Vec<usize> = d.numeric.iter().map(|&(k, _)| k).collect();
            let atoms = if symbols.is_empty() {
                Vec::new()
            } else {
                let roots: Vec<Id> = std::iter::once(d.candidate)
                    .chain(support.iter().map(|&k| kept[k]))
                    .flat_map(|c| candidates[c].column.iter().copied())
                    .collect();
                atoms::find(&mut self.arena, &roots, &symbols)
            };
            // Columns free of the symbols: the coefficients are numbers.
            let result = if atoms.is_empty() {
                d.numeric
                    .iter()
                    .map(|&(_, c)| Some(self.arena.num(exact::constant(c))))
                    .collect()
            } else {
                vec![None; support.len()]
            };
            fits.push(Fit {
                values: vec![Vec::new(); support.len()],
                support,
                atoms,
                atom_values: Vec::new(),
                result,
                exhausted: false,
            });
        }
        let mut points = Points {
            values: Vec::new(),
            bound: Vec::new(),
        };
        for degree in 0..=exact::MAX_DEGREE {
            let mut needs = vec![0; fits.len()];
            for (f, need) in fits.iter_mut().zip(&mut needs) {
                if f.done() || f.exhausted {
                    continue;
                }
                let monomials = exact::monomials(&f.atoms, degree).len();
                if monomials > exact::MAX_MONOMIALS {
                    f.exhausted = true;
                } else {
                    *need = monomials + MARGIN + CHECKS;
                }
            }
            if needs.iter().all(|&n| n == 0) {
                break;
            }
            self.sample_fits(
                &mut fits,
                &needs,
                &mut points,
                dependencies,
                kept,
                candidates,
                geometry,
                rng,
            )?;
            for (f, &need) in fits.iter_mut().zip(&needs) {
                if need == 0 {
                    continue;
                }
                for k in 0..f.support.len() {
                    if f.result[k].is_some() {
                        continue;
                    }
                    let samples = Samples {
                        atoms: &f.atom_values[..need],
                        values: &f.values[k][..need],
                        geometry: &points.bound[..need],
                    };
                    f.result[k] = exact::fit_polynomial(
                        &mut self.arena,
                        &f.atoms,
                        degree,
                        &samples,
                        need - CHECKS,
                    );
                }
            }
        }
        let name = |c: usize| {
            let c = &candidates[c];
            format!("{}{}", SLOT_NAMES[c.slot], c.link + 1)
        };
        let mut out = Vec::with_capacity(fits.len());
        for (f, d) in fits.iter().zip(dependencies) {
            let mut coefficients = Vec::with_capacity(f.support.len());
            for (&k, result) in f.support.iter().zip(&f.result) {
                let Some(c) = *result else {
                    let atom_ids: Vec<Id> = f.atoms.iter().map(|a| a.id).collect();
                    let symbols = self
                        .arena
                        .free_symbols(&atom_ids)
                        .into_iter()
                        .map(|s| self.arena.symbol_name(s).to_owned())
                        .collect();
                    return Err(RegroupError::NotExpressible {
                        parameter: name(d.candidate),
                        on: name(kept[k]),
                        symbols,
                    });
                };
                if !self.arena.is_zero(c) {
                    coefficients.push((k, c));
                }
            }
            out.push(coefficients);
        }
        Ok(out)
    }

    /// Samples every fit up to its need (`needs[f]` samples; 0: none), all
    /// fits that need sample `s` in one evaluation of their columns.
    #[allow(clippy::too_many_arguments)]
    fn sample_fits(
        &mut self,
        fits: &mut [Fit],
        needs: &[usize],
        points: &mut Points,
        dependencies: &[Dependency],
        kept: &[usize],
        candidates: &[Candidate],
        geometry: &[Id],
        rng: &mut Rng,
    ) -> Result<(), RegroupError> {
        let most = needs.iter().copied().max().unwrap_or(0);
        for s in 0..most {
            let which: Vec<usize> = (0..fits.len())
                .filter(|&f| needs[f] > s && fits[f].atom_values.len() == s)
                .collect();
            if which.is_empty() {
                continue;
            }
            while points.values.len() <= s {
                let values: Vec<f64> = geometry
                    .iter()
                    .map(|_| rng.uniform(SYMBOL_SAMPLES[0], SYMBOL_SAMPLES[1]))
                    .collect();
                let pairs: Vec<(String, f64)> = geometry
                    .iter()
                    .zip(&values)
                    .map(|(&g, &v)| (self.arena.display(g), v))
                    .collect();
                let refs: Vec<(&str, f64)> = pairs.iter().map(|(n, v)| (n.as_str(), *v)).collect();
                points.bound.push(self.arena.values(&refs));
                points.values.push(values);
            }
            // The union of the columns involved, each once.
            let mut involved: Vec<usize> = Vec::new();
            for &f in &which {
                let d = &dependencies[f];
                for c in
                    std::iter::once(d.candidate).chain(fits[f].support.iter().map(|&k| kept[k]))
                {
                    if !involved.contains(&c) {
                        involved.push(c);
                    }
                }
            }
            let columns: Vec<&[Id]> = involved
                .iter()
                .map(|&c| candidates[c].column.as_slice())
                .collect();
            let sampled = self.sample(&columns, geometry, &points.values[s], rng);
            let at = |c: usize| {
                let position = involved.iter().position(|&x| x == c).unwrap_or(0);
                &sampled[position]
            };
            for &f in &which {
                let d = &dependencies[f];
                let fit = &mut fits[f];
                let dependent = at(d.candidate);
                let on: Vec<&Vec<f64>> = fit.support.iter().map(|&k| at(kept[k])).collect();
                let not_finite =
                    || RegroupError::Numeric("a sampled regressor value is not finite".to_owned());
                let c = rank::coefficients(&on, dependent).ok_or_else(not_finite)?;
                // The dependency must hold here too.
                let residual = dependent
                    .iter()
                    .enumerate()
                    .map(|(r, &y)| {
                        let fitted: f64 = on.iter().zip(&c).map(|(col, ck)| col[r] * ck).sum();
                        (y - fitted).powi(2)
                    })
                    .sum::<f64>()
                    .sqrt();
                let size = dependent.iter().map(|y| y * y).sum::<f64>().sqrt();
                if !(residual <= DEPENDENT * size) {
                    let c = &candidates[d.candidate];
                    return Err(RegroupError::Numeric(format!(
                        "the dependency of `{}{}` found at one sample of the geometric symbols does not hold at another",
                        SLOT_NAMES[c.slot],
                        c.link + 1
                    )));
                }
                let atom_ids: Vec<Id> = fit.atoms.iter().map(|a| a.id).collect();
                let atom_values = self
                    .arena
                    .eval(&atom_ids, &points.bound[s])
                    .map_err(|e| RegroupError::Numeric(e.to_string()))?;
                if atom_values.iter().any(|v| !v.is_finite()) {
                    return Err(not_finite());
                }
                for (values, ck) in fit.values.iter_mut().zip(c) {
                    values.push(ck);
                }
                fit.atom_values.push(atom_values);
            }
        }
        Ok(())
    }
}
