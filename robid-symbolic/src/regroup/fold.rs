//! The coefficients with which each dependency found by the rank analysis
//! is folded into the kept parameters.
//!
//! Without geometric symbols a coefficient is a number: exact where it is
//! (see `exact.rs`), a float otherwise. With symbols, the coefficient of a
//! dependency is a function of them, and the base parameters must hold for
//! every value, since the symbols are inputs of the generated code. The
//! dependent column and the columns it depends on are sampled again at other
//! values of the symbols (each sample: a fresh value of every symbol, in
//! [`SYMBOL_SAMPLES`], or over a whole turn for a symbol that enters the
//! columns only through sines and cosines; the columns at random states; the
//! coefficients by least squares on the columns the dependency involves),
//! and each coefficient is fitted by a polynomial in the atoms of those
//! columns (`atoms.rs`), of the lowest degree that reproduces it: degree 0 is
//! a constant. A fit of `m` monomials uses `m + 3` samples and is checked on
//! 2 more; a coefficient that no polynomial up to [`exact::MAX_DEGREE`]
//! (within [`exact::MAX_MONOMIALS`]) reproduces is an error that names the
//! symbols it varies with.
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
use super::{Candidate, RegroupError};
use crate::dynamics::Derivation;
use crate::expr::{Id, Node, Symbol, Values};
use crate::robot::bounds::SYMBOL_SAMPLES;
use robid_core::rng::Rng;

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

/// A coefficient whose term is below this fraction of the dependent column
/// at every sample is zero (rounding in the first solve).
const NEGLIGIBLE: f64 = 1e-12;

/// The fit of one dependency's coefficients.
struct Fit {
    /// Positions among the kept candidates of the columns it involves.
    support: Vec<usize>,
    /// The atoms of the involved columns.
    atoms: Vec<Atom>,
    /// `values[k][s]`: coefficient on `support[k]` at sample `s`.
    values: Vec<Vec<f64>>,
    /// Largest size, over the samples, of the term of `support[k]`
    /// relative to the dependent column.
    largest_term: Vec<f64>,
    /// `atom_values[s][a]`: atom `a` at sample `s`.
    atom_values: Vec<Vec<f64>>,
    /// The expression of each coefficient, once fitted.
    result: Vec<Option<Id>>,
    /// No higher degree can be tried (too many monomials).
    exhausted: bool,
    /// The highest degree tried.
    tried: usize,
}

impl Fit {
    fn done(&self) -> bool {
        self.result.iter().all(Option::is_some)
    }
}

/// What the fits are about.
struct Context<'a> {
    dependencies: &'a [Dependency],
    kept: &'a [usize],
    candidates: &'a [Candidate],
    /// The geometric symbols, as expressions.
    geometry: &'a [Id],
}

impl Context<'_> {
    fn name(&self, candidate: usize) -> String {
        self.candidates[candidate].id.to_string()
    }

    /// The candidates fit `f` involves: the dependent one, then its support.
    fn involved<'a>(&'a self, f: usize, fit: &'a Fit) -> impl Iterator<Item = usize> + 'a {
        std::iter::once(self.dependencies[f].candidate)
            .chain(fit.support.iter().map(|&k| self.kept[k]))
    }
}

/// Samples of the geometric symbols shared by every fit: the values, and the
/// same bound in the arena, for evaluating atoms and fitted expressions.
struct Points {
    values: Vec<Vec<f64>>,
    bound: Vec<Values>,
    /// The interval each symbol is sampled in.
    ranges: Vec<[f64; 2]>,
}

/// The coefficients of some fits at one point of the symbols: for each fit,
/// the coefficients on its support and the relative size of their terms.
type AtPoint = Vec<(Vec<f64>, Vec<f64>)>;

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
        let cx = Context {
            dependencies,
            kept,
            candidates,
            geometry,
        };
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
                largest_term: vec![0.0; support.len()],
                support,
                atoms,
                atom_values: Vec::new(),
                result,
                exhausted: false,
                tried: 0,
            });
        }
        // Angles (symbols only inside sines and cosines) are sampled over a
        // whole turn, where their sines and cosines are well apart from the
        // constant; any other symbol in [0.2, 1], where the description's
        // values were checked.
        let all_atoms: Vec<Atom> = fits.iter().flat_map(|f| f.atoms.iter().copied()).collect();
        let angles = atoms::angle_symbols(&self.arena, &all_atoms);
        let mut points = Points {
            values: Vec::new(),
            bound: Vec::new(),
            ranges: geometry
                .iter()
                .map(|&g| match self.arena.node(g) {
                    Node::Sym(s) if angles.contains(s) => {
                        [-std::f64::consts::PI, std::f64::consts::PI]
                    }
                    _ => SYMBOL_SAMPLES,
                })
                .collect(),
        };
        for degree in 0..=exact::MAX_DEGREE {
            let mut needs = vec![0; fits.len()];
            for (f, need) in fits.iter_mut().zip(&mut needs) {
                if f.done() || f.exhausted {
                    continue;
                }
                let monomials = exact::monomials(&f.atoms, degree).len();
                if !exact::within_limit(monomials) {
                    f.exhausted = true;
                } else {
                    *need = monomials + MARGIN + CHECKS;
                    f.tried = degree;
                }
            }
            if needs.iter().all(|&n| n == 0) {
                break;
            }
            self.sample_fits(&cx, &mut fits, &needs, &mut points, rng)?;
            for (f, &need) in fits.iter_mut().zip(&needs) {
                if need == 0 {
                    continue;
                }
                for k in 0..f.support.len() {
                    if f.result[k].is_some() {
                        continue;
                    }
                    if f.largest_term[k] <= NEGLIGIBLE {
                        f.result[k] = Some(self.arena.zero());
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
        let mut out = Vec::with_capacity(fits.len());
        for (f, fit) in fits.iter().enumerate() {
            let mut coefficients = Vec::with_capacity(fit.support.len());
            for (position, (&k, result)) in fit.support.iter().zip(&fit.result).enumerate() {
                let Some(c) = *result else {
                    let symbols = self.varying_symbols(&cx, &fits, f, position, &points, rng)?;
                    return Err(RegroupError::NotExpressible {
                        parameter: cx.name(dependencies[f].candidate),
                        on: cx.name(kept[k]),
                        symbols,
                        degree: fit.tried,
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
    /// the fits that need sample `s` in one evaluation of their columns.
    fn sample_fits(
        &mut self,
        cx: &Context<'_>,
        fits: &mut [Fit],
        needs: &[usize],
        points: &mut Points,
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
                let values: Vec<f64> = points
                    .ranges
                    .iter()
                    .map(|r| rng.uniform(r[0], r[1]))
                    .collect();
                points.bound.push(self.bind(cx.geometry, &values));
                points.values.push(values);
            }
            let at = self.coefficients_at(cx, fits, &which, &points.values[s], rng)?;
            for (&f, (c, terms)) in which.iter().zip(at) {
                let fit = &mut fits[f];
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
                for (largest, t) in fit.largest_term.iter_mut().zip(terms) {
                    *largest = largest.max(t);
                }
                fit.atom_values.push(atom_values);
            }
        }
        Ok(())
    }

    /// Arena values binding the geometric symbols to `values`.
    fn bind(&mut self, geometry: &[Id], values: &[f64]) -> Values {
        let pairs: Vec<(String, f64)> = geometry
            .iter()
            .zip(values)
            .map(|(&g, &v)| (self.arena.display(g), v))
            .collect();
        let refs: Vec<(&str, f64)> = pairs.iter().map(|(n, v)| (n.as_str(), *v)).collect();
        self.arena.values(&refs)
    }

    /// The coefficients of the fits `which` with the geometric symbols at
    /// `point`: their columns sampled at random states in one evaluation,
    /// each dependent column solved on its support, which must reproduce it.
    fn coefficients_at(
        &mut self,
        cx: &Context<'_>,
        fits: &[Fit],
        which: &[usize],
        point: &[f64],
        rng: &mut Rng,
    ) -> Result<AtPoint, RegroupError> {
        // The union of the columns involved, each once.
        let mut involved: Vec<usize> = Vec::new();
        for &f in which {
            for c in cx.involved(f, &fits[f]) {
                if !involved.contains(&c) {
                    involved.push(c);
                }
            }
        }
        let columns: Vec<&[Id]> = involved
            .iter()
            .map(|&c| cx.candidates[c].column.as_slice())
            .collect();
        let sampled = self.sample(&columns, cx.geometry, point, rng);
        let at = |c: usize| {
            let position = involved.iter().position(|&x| x == c).unwrap_or(0);
            &sampled[position]
        };
        let mut out = Vec::with_capacity(which.len());
        for &f in which {
            let d = &cx.dependencies[f];
            let dependent = at(d.candidate);
            let on: Vec<&Vec<f64>> = fits[f].support.iter().map(|&k| at(cx.kept[k])).collect();
            let Some(at) = holds(&on, dependent).ok_or_else(not_finite)? else {
                let atom_ids: Vec<Id> = fits[f].atoms.iter().map(|a| a.id).collect();
                let symbols: Vec<String> = self
                    .arena
                    .free_symbols(&atom_ids)
                    .into_iter()
                    .map(|s| self.arena.symbol_name(s).to_owned())
                    .collect();
                return Err(RegroupError::Numeric(format!(
                    "the dependency of `{}` found at one value of the geometric symbols {} does not hold at another value in [{}, {}], where robid samples them; a value whose size changes by many orders of magnitude over that interval (a high power of a symbol) leaves part of the model below rounding",
                    cx.name(d.candidate),
                    super::quoted(&symbols),
                    SYMBOL_SAMPLES[0],
                    SYMBOL_SAMPLES[1]
                )));
            };
            out.push(at);
        }
        Ok(out)
    }

    /// The geometric symbols that coefficient `position` of fit `f` varies
    /// with: each symbol of its atoms changed alone from the first sample.
    fn varying_symbols(
        &mut self,
        cx: &Context<'_>,
        fits: &[Fit],
        f: usize,
        position: usize,
        points: &Points,
        rng: &mut Rng,
    ) -> Result<Vec<String>, RegroupError> {
        let atom_ids: Vec<Id> = fits[f].atoms.iter().map(|a| a.id).collect();
        let of_atoms = self.arena.free_symbols(&atom_ids);
        let (Some(first), Some(&reference)) = (
            points.values.first(),
            fits[f].values.get(position).and_then(|v| v.first()),
        ) else {
            return Ok(Vec::new());
        };
        let mut out = Vec::new();
        for (g, &expression) in cx.geometry.iter().enumerate() {
            let Node::Sym(symbol) = *self.arena.node(expression) else {
                continue;
            };
            if !of_atoms.contains(&symbol) {
                continue;
            }
            let mut point = first.clone();
            let range = points.ranges[g];
            point[g] = rng.uniform(range[0], range[1]);
            let at = self.coefficients_at(cx, fits, &[f], &point, rng)?;
            let value = at.first().map_or(reference, |(c, _)| c[position]);
            if varies(value, reference) {
                out.push(self.arena.symbol_name(symbol).to_owned());
            }
        }
        Ok(out)
    }
}

fn not_finite() -> RegroupError {
    RegroupError::Numeric("a sampled regressor value is not finite".to_owned())
}

/// The coefficients of `dependent` on the columns `on` (least squares) and each term's
/// size relative to the dependent column's (`|c_k| |on_k| / |dependent|`, 0 for a zero
/// column), when the dependency holds: its remainder within [`DEPENDENT`] of the
/// column's size. `Some(None)`: it does not hold; `None`: a value is not finite.
fn holds(on: &[&Vec<f64>], dependent: &[f64]) -> Option<Option<(Vec<f64>, Vec<f64>)>> {
    let c = rank::coefficients(on, dependent)?;
    let size = rank::norm(dependent);
    let remainder: Vec<f64> = (0..dependent.len())
        .map(|r| dependent[r] - on.iter().zip(&c).map(|(col, ck)| col[r] * ck).sum::<f64>())
        .collect();
    let off = rank::norm(&remainder);
    if !off.is_finite() {
        return None;
    }
    if off > DEPENDENT * size {
        return Some(None);
    }
    let terms = on
        .iter()
        .zip(&c)
        .map(|(col, ck)| {
            if size > 0.0 {
                ck.abs() * rank::norm(col) / size
            } else {
                0.0
            }
        })
        .collect();
    Some(Some((c, terms)))
}

/// Whether a coefficient's `value` at another point differs from its `reference` by
/// more than the fit's tolerance, relative to the larger of the two.
fn varies(value: f64, reference: f64) -> bool {
    let size = value.abs().max(reference.abs());
    (value - reference).abs() > exact::FIT_TOLERANCE * size
}

#[cfg(test)]
mod tests {
    use super::{holds, varies};

    fn column(f: impl Fn(f64) -> f64) -> Vec<f64> {
        (0..8).map(|r| f(r as f64 + 1.0)).collect()
    }

    /// A column in the span of others gives its coefficients and the sizes of its terms
    /// relative to it; one that leaves a remainder beyond the threshold does not hold,
    /// however large or small the column; a zero column holds with zero terms; a value
    /// past the floats' range is not finite.
    #[test]
    fn a_dependency_holds_only_within_the_threshold() {
        let (a, b) = (column(|x| x), column(|x| x * x));
        let dependent: Vec<f64> = a.iter().zip(&b).map(|(x, y)| 2.0 * x - 0.5 * y).collect();
        let (c, terms) = holds(&[&a, &b], &dependent).unwrap().unwrap();
        let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!(
            (c[0] - 2.0).abs() < 1e-12 && (c[1] + 0.5).abs() < 1e-12,
            "{c:?}"
        );
        for (t, expected) in terms.iter().zip([
            2.0 * norm(&a) / norm(&dependent),
            0.5 * norm(&b) / norm(&dependent),
        ]) {
            assert!((t - expected).abs() < 1e-12 * expected, "{terms:?}");
        }
        // a remainder of 1e-10 of the column's size, at sizes 1e-3 and 1e3: not a dependency
        let wiggle = column(|x| (3.0 * x).sin());
        for scale in [1e-3, 1e3] {
            let off: Vec<f64> = a
                .iter()
                .zip(&wiggle)
                .map(|(x, w)| x + 1e-10 * 5.0 * w)
                .collect();
            let scaled: Vec<f64> = off.iter().map(|v| v * scale).collect();
            assert_eq!(holds(&[&a], &scaled), Some(None), "scale {scale}");
            // and 1e-13 of it (rounding) holds
            let near: Vec<f64> = a
                .iter()
                .zip(&wiggle)
                .map(|(x, w)| scale * (x + 1e-13 * w))
                .collect();
            assert!(holds(&[&a], &near).unwrap().is_some(), "scale {scale}");
        }
        let zero = vec![0.0; a.len()];
        assert_eq!(holds(&[&a], &zero), Some(Some((vec![0.0], vec![0.0]))));
        let huge: Vec<f64> = a.iter().map(|x| x * 1e300).collect();
        assert_eq!(holds(&[&a], &huge), None);
    }

    /// A coefficient varies when it moves by more than the fit's tolerance relative to
    /// the larger value, at any magnitude; equal values, zeros included, do not.
    #[test]
    fn a_coefficient_varies_beyond_the_tolerance() {
        for size in [1e-6, 1.0, 1e6] {
            assert!(varies(size * (1.0 + 1e-7), size), "{size}");
            assert!(!varies(size * (1.0 + 1e-9), size), "{size}");
            assert!(!varies(size, size));
        }
        assert!(!varies(0.0, 0.0));
        assert!(varies(1e-300, 0.0));
    }
}
