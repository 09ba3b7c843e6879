//! The search's data term, whitened K p - beta with the drive terms and extra columns
//! solved for, evaluated into reusable buffers (the search runs millions of evaluations).
//! Two ways: [`Data::evaluate_exact`] with the roundings the search always had, for the
//! annealing and Nelder-Mead, whose random walk and comparisons follow every rounding
//! (so their paths, and the results, stay as they were); and [`Data::evaluate`] with K
//! split by link, for the Levenberg-Marquardt polish, whose forward differences change one
//! link at a time ([`Data::step_link`] re-evaluates only that link's columns: the
//! differences were most of the search's time, each a full evaluation).

use nalgebra::{DMatrix, DVector};

use super::parametrise::{PER_LINK, link_of};
use crate::feasible::layout::Layout;

/// Whitened K split into the links' columns and the linearly solved ones.
pub(super) struct Data {
    /// Whitened K (base x standard).
    pub(super) a: DMatrix<f64>,
    /// The whitened target.
    pub(super) b: DVector<f64>,
    /// The links' columns of `a`, link by link in the order of [`Layout::links`], so that
    /// a link's ten columns are contiguous.
    links: DMatrix<f64>,
    /// The linearly solved columns (drive terms, then extra columns): index in the
    /// standard vector and whether the value must be non-negative.
    pub(super) linear: Vec<(usize, bool)>,
    /// Their columns of `a` (base x linear).
    columns: DMatrix<f64>,
    /// Pseudo-inverse of `columns` (linear x base).
    pinv: DMatrix<f64>,
    /// `pinv` times `links`: how the linear terms follow a link's values.
    pinv_links: DMatrix<f64>,
    /// `links - columns pinv_links`: how the misfit follows a link's values while no
    /// linear term meets its clamp.
    net_links: DMatrix<f64>,
}

/// The buffers of one evaluation: the state at a point of the search.
#[derive(Clone)]
pub(super) struct Scratch {
    /// The full variable vector (lifted).
    pub(super) x: Vec<f64>,
    /// The standard values of the links, link by link.
    links: Vec<f64>,
    /// The standard vector, linear terms solved.
    pub(super) p: Vec<f64>,
    /// `links' columns x links - b`: the misfit before the linear terms.
    fit: Vec<f64>,
    /// `pinv fit`: minus the linear terms before the clamp at zero.
    raw: Vec<f64>,
    /// The linear terms' values.
    d: Vec<f64>,
    /// The whitened misfit.
    pub(super) r: Vec<f64>,
    /// The change of the whitened misfit in [`Data::step_link`].
    pub(super) delta: Vec<f64>,
    /// The change of `raw` in [`Data::step_link`].
    raw_change: Vec<f64>,
    /// The residual rows, for their norm as nalgebra sums it.
    pub(super) rows: Vec<f64>,
}

impl Data {
    /// The data term of whitened K `a` and target `b` under `layout`, the columns `linear`
    /// solved for.
    pub(super) fn new(
        a: DMatrix<f64>,
        b: DVector<f64>,
        layout: &Layout,
        linear: Vec<(usize, bool)>,
    ) -> Data {
        let link_columns: Vec<usize> = layout.links.iter().flatten().copied().collect();
        let links = a.select_columns(&link_columns);
        let linear_columns: Vec<usize> = linear.iter().map(|&(i, _)| i).collect();
        let columns = a.select_columns(&linear_columns);
        let pinv = if linear.is_empty() {
            DMatrix::zeros(0, a.nrows())
        } else {
            // a capped SVD: the iteration cannot loop whatever the matrix holds
            columns
                .clone()
                .try_svd(true, true, f64::EPSILON, crate::limits::SVD_ITERATIONS)
                .and_then(|s| s.pseudo_inverse(1e-10).ok())
                .unwrap_or_else(|| DMatrix::zeros(linear.len(), a.nrows()))
        };
        let pinv_links = &pinv * &links;
        let net_links = &links - &columns * &pinv_links;
        Data {
            a,
            b,
            links,
            linear,
            columns,
            pinv,
            pinv_links,
            net_links,
        }
    }

    /// Buffers sized for this data term and `layout`.
    pub(super) fn scratch(&self, layout: &Layout) -> Scratch {
        Scratch {
            x: vec![0.0; layout.links.len() * PER_LINK],
            links: vec![0.0; self.links.ncols()],
            p: vec![0.0; layout.len()],
            fit: vec![0.0; self.a.nrows()],
            raw: vec![0.0; self.linear.len()],
            d: vec![0.0; self.linear.len()],
            r: vec![0.0; self.a.nrows()],
            delta: vec![0.0; self.a.nrows()],
            raw_change: vec![0.0; self.linear.len()],
            rows: Vec::new(),
        }
    }

    /// Evaluates the misfit at the full variables in `s.x`: the links' standard values,
    /// the linear terms and the misfit.
    pub(super) fn evaluate(&self, layout: &Layout, s: &mut Scratch) {
        for j in 0..layout.links.len() {
            set_link(layout, j, s);
        }
        mat_vec(&self.links, &s.links, &mut s.fit);
        for (f, b) in s.fit.iter_mut().zip(self.b.iter()) {
            *f -= b;
        }
        mat_vec(&self.pinv, &s.fit, &mut s.raw);
        self.solve_linear(s);
    }

    /// [`Data::evaluate`] with the search's old roundings, bit for bit: the products with
    /// the whole of K column by column in the standard order, the linear terms zero in the
    /// first (a zero entry of p adds nothing, so its column is skipped), solved in the
    /// second.
    pub(super) fn evaluate_exact(&self, layout: &Layout, s: &mut Scratch) {
        for j in 0..layout.links.len() {
            set_link(layout, j, s);
        }
        for &(index, _) in &self.linear {
            s.p[index] = 0.0;
        }
        s.fit.fill(0.0);
        mat_vec_add_nonzero(&self.a, &s.p, &mut s.fit);
        for (f, b) in s.fit.iter_mut().zip(self.b.iter()) {
            *f -= b;
        }
        if !self.linear.is_empty() {
            mat_vec(&self.pinv, &s.fit, &mut s.raw);
            self.clamp(s);
        }
        mat_vec(&self.a, &s.p, &mut s.r);
        for (r, b) in s.r.iter_mut().zip(self.b.iter()) {
            *r -= b;
        }
    }

    /// Re-evaluates `s`, evaluated before, after the variables of link `j` in `s.x`
    /// changed, but for its misfit (`fit` and `r` stay): `s.delta` is the misfit's change,
    /// formed from the link's change itself (only its columns enter), not as the difference
    /// of two misfits, whose rounding (1e-16 of the misfit) a forward difference divides by
    /// its step. The linear terms follow through `net_links`, corrected where one meets
    /// its clamp at zero.
    pub(super) fn step_link(&self, layout: &Layout, j: usize, s: &mut Scratch) {
        let at = j * PER_LINK;
        let before: [f64; PER_LINK] = std::array::from_fn(|k| s.links[at + k]);
        set_link(layout, j, s);
        let change: [f64; PER_LINK] = std::array::from_fn(|k| s.links[at + k] - before[k]);
        s.delta.fill(0.0);
        add_block(&self.net_links, at, &change, &mut s.delta);
        s.raw_change.fill(0.0);
        add_block(&self.pinv_links, at, &change, &mut s.raw_change);
        let rows = self.columns.nrows();
        for (k, &(index, non_negative)) in self.linear.iter().enumerate() {
            let (old, raw) = (-s.raw[k], -(s.raw[k] + s.raw_change[k]));
            s.raw[k] = -raw;
            let d = if non_negative { raw.max(0.0) } else { raw };
            (s.d[k], s.p[index]) = (d, d);
            if !(non_negative && (old < 0.0 || raw < 0.0)) {
                continue;
            }
            // net_links took the term as following unclamped (by -raw_change)
            let correction = (d - old.max(0.0)) + s.raw_change[k];
            let column = &self.columns.as_slice()[k * rows..(k + 1) * rows];
            for (delta, c) in s.delta.iter_mut().zip(column) {
                *delta += c * correction;
            }
        }
    }

    /// The linear terms from `s.raw` and the misfit with them.
    fn solve_linear(&self, s: &mut Scratch) {
        s.r.copy_from_slice(&s.fit);
        if self.linear.is_empty() {
            return;
        }
        self.clamp(s);
        mat_vec_add(&self.columns, &s.d, &mut s.r);
    }

    /// The linear terms that fit best, `-s.raw`, with those that cannot be negative
    /// clamped at zero, into `s.d` and the standard vector.
    fn clamp(&self, s: &mut Scratch) {
        for ((d, raw), &(index, non_negative)) in s.d.iter_mut().zip(&s.raw).zip(&self.linear) {
            let v = -*raw;
            *d = if non_negative { v.max(0.0) } else { v };
            s.p[index] = *d;
        }
    }
}

impl Scratch {
    /// Copies the evaluation `from` into these buffers without allocating (the derived
    /// `clone_from` would allocate anew).
    pub(super) fn copy_from(&mut self, from: &Scratch) {
        self.x.copy_from_slice(&from.x);
        self.links.copy_from_slice(&from.links);
        self.p.copy_from_slice(&from.p);
        self.fit.copy_from_slice(&from.fit);
        self.raw.copy_from_slice(&from.raw);
        self.d.copy_from_slice(&from.d);
        self.r.copy_from_slice(&from.r);
    }
}

/// Sets link `j`'s standard values in `s` from its variables in `s.x`.
fn set_link(layout: &Layout, j: usize, s: &mut Scratch) {
    let at = j * PER_LINK;
    let standard = link_of(&s.x[at..at + PER_LINK]).to_standard();
    s.links[at..at + PER_LINK].copy_from_slice(&standard);
    for (&i, v) in layout.links[j].iter().zip(standard) {
        s.p[i] = v;
    }
}

/// `y = a x`, on contiguous columns, which vectorise (nalgebra's generic strided product
/// was 59 % of the search).
pub(super) fn mat_vec(a: &DMatrix<f64>, x: &[f64], y: &mut [f64]) {
    y.fill(0.0);
    mat_vec_add(a, x, y);
}

/// `y += a x` over the columns of `a` whose entry of `x` is not zero, in order: the sums of
/// [`mat_vec`] to the bit (adding a zero product leaves a sum as it is).
fn mat_vec_add_nonzero(a: &DMatrix<f64>, x: &[f64], y: &mut [f64]) {
    if a.nrows() == 0 {
        return;
    }
    let columns = a.as_slice().chunks_exact(a.nrows());
    accumulate(y, columns.zip(x.iter().copied()).filter(|t| t.1 != 0.0));
}

/// `y += a[:, at..at + 10] change`: a link's ten contiguous columns.
fn add_block(a: &DMatrix<f64>, at: usize, change: &[f64; PER_LINK], y: &mut [f64]) {
    let rows = a.nrows();
    if rows == 0 {
        return;
    }
    let block = &a.as_slice()[at * rows..(at + PER_LINK) * rows];
    accumulate(y, block.chunks_exact(rows).zip(change.iter().copied()));
}

/// `y += a x`, column by column.
fn mat_vec_add(a: &DMatrix<f64>, x: &[f64], y: &mut [f64]) {
    if a.nrows() == 0 {
        return;
    }
    accumulate(
        y,
        a.as_slice().chunks_exact(a.nrows()).zip(x.iter().copied()),
    );
}

/// `y += column * value` for each of `terms` in turn, four columns a pass: each entry of
/// `y` takes the same additions in the same order as one column a pass would give it (the
/// same roundings), but is loaded and stored once per four columns.
fn accumulate<'a>(y: &mut [f64], terms: impl Iterator<Item = (&'a [f64], f64)>) {
    let mut group: [(&[f64], f64); 4] = [(&[], 0.0); 4];
    let mut len = 0;
    for term in terms {
        group[len] = term;
        len += 1;
        if len == group.len() {
            add_four(y, &group);
            len = 0;
        }
    }
    for &(column, v) in &group[..len] {
        for (y, c) in y.iter_mut().zip(column) {
            *y += c * v;
        }
    }
}

/// `y += column * value` for the four terms, in order, entry by entry.
fn add_four(y: &mut [f64], group: &[(&[f64], f64); 4]) {
    let n = y.len();
    let [(c0, x0), (c1, x1), (c2, x2), (c3, x3)] = *group;
    let (c0, c1, c2, c3) = (&c0[..n], &c1[..n], &c2[..n], &c3[..n]);
    for ((((y, a), b), c), d) in y.iter_mut().zip(c0).zip(c1).zip(c2).zip(c3) {
        let mut v = *y;
        v += a * x0;
        v += b * x1;
        v += c * x2;
        v += d * x3;
        *y = v;
    }
}
