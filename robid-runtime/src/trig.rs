//! Sines and cosines of several angles in one call.
//!
//! Generated models need the sine and cosine of every joint angle before anything
//! else, and get them from one call of
//! [`Real::sin_cos_array`](crate::Real::sin_cos_array), which for `f64` is
//! [`sin_cos_static`].
//!
//! - [`sin_cos`]: on x86-64 with AVX2 and FMA, four angles at a time are reduced and
//!   evaluated in vector registers ([`vector_available`] says whether this path is
//!   taken). The CPU is asked once (with the `std` feature; the answer is cached in an
//!   atomic), or not at all when the code is compiled with
//!   `-C target-feature=+avx2,+fma`. Angles with `|x| <= 1e5` are within 1 ulp of
//!   libm's result, so within 2 ulp of the exact value (tested on 1.38e7 angles; under
//!   1 % of the results differ from libm's; against 200-bit values on 58 184 angles, the
//!   largest error was 0.74 ulp); any other angle (larger, infinite or NaN,
//!   or within `2^-36` of a nonzero multiple of pi/2) is passed to libm, so the results
//!   are libm's there. Everywhere else (other architectures, CPUs without AVX2, `no_std`
//!   builds for x86-64 without the target features) each angle goes through libm's
//!   `sincos` ([`sin_cos_libm`]).
//! - [`sin_cos_static`], what generated models use: the vector path only when the build
//!   enables AVX2 and FMA, so that it inlines; libm otherwise (see its documentation for
//!   why the run-time choice is not taken there).
//!
//! `f32` keeps the scalar libm path: its models are for microcontrollers, which have
//! no AVX2.
//!
//! # The vector algorithm
//!
//! For each angle `x`:
//!
//! 1. `k = round(x * 2/pi)`, as an integer in a double: `fma(x, 2/pi, 1.5 * 2^52)`
//!    rounds the exact product once, and the low mantissa bits of that sum are `k`'s
//!    two's complement bits (valid for `|k| < 2^51`).
//! 2. Cody-Waite reduction by `pi/2 = P1 + P2 + P3` (three doubles, 159 bits of
//!    `pi/2`), keeping the result as a double-double `r_hi + r_lo`:
//!    - `r1 = fma(-k, P1, x)` is exact: for `|x| >= pi/4` (otherwise `k = 0` and
//!      `r1 = x`), `x` and `k * P1` are whole multiples of `2^-53` (`P1` lies in
//!      `[1, 2)`, so its last bit weighs `2^-52`; `|x| >= 0.5` has no bit below
//!      `2^-53`), and their difference is below 1 in magnitude (`|x - k pi/2| <= pi/4`
//!      plus `|k| * 6.2e-17`), so it has at most 53 significant bits and the fused
//!      operation, which rounds the exact value once, does not round it.
//!    - `r_hi = fma(-k, P2, r1)`, one rounding of `r1 - k P2`.
//!    - `r_lo = fma(-k, P3, fma(-k, P2, r1 - r_hi))`: `r1 - r_hi` is exact (Sterbenz)
//!      when `|k P2| <= |r1| / 2`, which holds whenever `|r1| >= 2^-36` (`|k| <= 63663`
//!      for `|x| <= 1e5`, so `2 |k P2| < 7.8e-12 < 2^-36`); the inner fused operation
//!      then gives the rounding error of `r_hi` to 53 bits, and the outer one subtracts
//!      `k P3`. `r_hi + r_lo` is `x - k pi/2` to about `2^-104` relative (the neglected
//!      `k (pi/2 - P1 - P2 - P3)` is below `1e5 * 5.6e-50`). Lanes with `k != 0` and
//!      `|r1| < 2^-36` (angles within `2^-36` of a nonzero multiple of pi/2, `x = pi/2`
//!      typed as a double among them) go to libm instead.
//! 3. The sine and cosine of `r_hi + r_lo` on `[-pi/4, pi/4]` by the minimax
//!    polynomials of fdlibm's `__kernel_sin` and `__kernel_cos` (the ones musl and the
//!    Rust libm crate use, error below `2^-58` relative), evaluated by Estrin's scheme
//!    (shorter dependency chains than Horner's), with their first-order corrections for
//!    `r_lo`.
//! 4. The quadrant `k mod 4` swaps sine and cosine (`k` odd) and sets their signs:
//!    `sin x = [S, C, -S, -C][k mod 4]`, `cos x = [C, -S, -C, S][k mod 4]`.
//!
//! `±0` is returned unchanged as its own sine (`x + 0` would lose the sign of `-0`).

#[cfg(target_arch = "x86_64")]
mod avx2;

/// Angles from this many on use the vector path when it is available; below, libm.
///
/// One angle costs the same through either (one libm `sincos` is about as dear as a
/// call to the vector code, which cannot be inlined into code compiled without AVX2).
const VECTOR_FROM: usize = 2;

/// Angles up to this magnitude take the vector path; beyond (and NaN), libm.
#[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
const VECTOR_LIMIT: f64 = 1e5;

/// Sines and cosines of `N` angles, `([sin x0, sin x1, ...], [cos x0, cos x1, ...])`.
///
/// Vectorised on x86-64 with AVX2 and FMA (see the [module documentation](self) for the
/// accuracy), libm's `sincos` for each angle elsewhere.
///
/// ```
/// let (s, c) = robid_runtime::trig::sin_cos([0.0, 0.5, -2.0]);
/// for (i, x) in [0.0_f64, 0.5, -2.0].into_iter().enumerate() {
///     assert!((s[i] - libm::sin(x)).abs() <= 2.0 * f64::EPSILON);
///     assert!((c[i] - libm::cos(x)).abs() <= 2.0 * f64::EPSILON);
/// }
/// ```
#[inline]
pub fn sin_cos<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    #[cfg(target_arch = "x86_64")]
    if N >= VECTOR_FROM && vector_available() {
        // SAFETY: `vector_available` has confirmed (or the build's target features
        // guarantee) that the CPU executes AVX2 and FMA instructions.
        return unsafe { avx2::sin_cos(x) };
    }
    sin_cos_libm(x)
}

/// [`sin_cos`] for code compiled with AVX2 and FMA, where the vector path inlines whole
/// (the models' AVX2 instances: [`Fused`](crate::fused::Fused)); the same choice and the
/// same results. Elsewhere it is slower than [`sin_cos`].
#[inline(always)]
pub(crate) fn sin_cos_inlined<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    if N < VECTOR_FROM {
        // one angle: libm's call is as cheap, and expected
        return sin_cos_libm(x);
    }
    #[cfg(target_arch = "x86_64")]
    if vector_available() {
        // SAFETY: `vector_available` has confirmed that the CPU executes AVX2 and FMA.
        return unsafe { avx2::sin_cos_inlined(x) };
    }
    sin_cos_libm_cold(x)
}

/// [`sin_cos_libm`] kept out of line: the path [`sin_cos_inlined`] does not expect, whose
/// calls would otherwise make the caller keep its values on the stack.
#[cold]
#[inline(never)]
fn sin_cos_libm_cold<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    sin_cos_libm(x)
}

/// What [`Real::sin_cos_array`](crate::Real::sin_cos_array) computes for `f64`: the
/// vector path when the build enables AVX2 and FMA (`-C target-cpu=native` or
/// `-C target-feature=+avx2,+fma`), where it inlines into the generated code; libm for
/// each angle otherwise.
///
/// The run-time choice of [`sin_cos`] is not taken here: its call cannot be inlined into
/// code compiled without AVX2, and for the five to seven angles of a model it measured
/// slower in the generated functions than libm's calls inlined there, whose independent
/// evaluations the processor overlaps with each other and with the arithmetic
/// (docs/performance.md, "Trigonometry").
///
/// ```
/// let x = [0.1, 1.2, -2.3, 4.0, 5.5];
/// let (s, c) = robid_runtime::trig::sin_cos_static(x);
/// let (ls, lc) = robid_runtime::trig::sin_cos_libm(x);
/// for i in 0..5 {
///     assert!((s[i] - ls[i]).abs() <= f64::EPSILON && (c[i] - lc[i]).abs() <= f64::EPSILON);
/// }
/// ```
#[inline(always)]
pub fn sin_cos_static<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    #[cfg(all(
        target_arch = "x86_64",
        target_feature = "avx2",
        target_feature = "fma"
    ))]
    if N >= VECTOR_FROM {
        // SAFETY: the build's target features guarantee AVX2 and FMA.
        return unsafe { avx2::sin_cos(x) };
    }
    sin_cos_libm(x)
}

/// Sines and cosines of `N` angles through libm's `sincos`, one angle at a time: the
/// path [`sin_cos`] takes without AVX2, and its reference.
///
/// ```
/// let (s, c) = robid_runtime::trig::sin_cos_libm([1.0, 2.0]);
/// assert_eq!((s[1], c[1]), libm::sincos(2.0));
/// ```
#[inline(always)]
pub fn sin_cos_libm<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    let mut s = [0.0; N];
    let mut c = [0.0; N];
    for i in 0..N {
        (s[i], c[i]) = libm::sincos(x[i]);
    }
    (s, c)
}

/// Whether [`sin_cos`] takes the vector path (AVX2 and FMA on x86-64) on this machine.
///
/// Known at compile time when the build enables both target features; otherwise, with the
/// `std` feature, the CPU is asked on the first call and the answer kept in an atomic.
/// Without `std` and without the target features, `false`.
///
/// ```
/// let vector = robid_runtime::trig::vector_available();
/// assert_eq!(vector, robid_runtime::trig::vector_available());
/// ```
#[inline]
pub fn vector_available() -> bool {
    #[cfg(all(
        target_arch = "x86_64",
        target_feature = "avx2",
        target_feature = "fma"
    ))]
    {
        true
    }
    #[cfg(all(
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma")),
        feature = "std"
    ))]
    {
        detected()
    }
    #[cfg(not(all(
        target_arch = "x86_64",
        any(all(target_feature = "avx2", target_feature = "fma"), feature = "std")
    )))]
    {
        false
    }
}

/// The run-time answer, asked once: 0 not yet asked, 1 no, 2 yes.
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma")),
    feature = "std"
))]
#[inline]
fn detected() -> bool {
    use core::sync::atomic::{AtomicU8, Ordering};
    static STATE: AtomicU8 = AtomicU8::new(0);
    match STATE.load(Ordering::Relaxed) {
        0 => ask(&STATE),
        state => state == 2,
    }
}

/// The first call's question to the CPU, out of line (once per process).
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma")),
    feature = "std"
))]
#[cold]
#[inline(never)]
fn ask(state: &core::sync::atomic::AtomicU8) -> bool {
    let yes = std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma");
    state.store(
        if yes { 2 } else { 1 },
        core::sync::atomic::Ordering::Relaxed,
    );
    yes
}

#[cfg(test)]
mod tests;
