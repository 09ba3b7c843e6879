//! The AVX2 + FMA path of [`super::sin_cos`]: four angles per vector (the algorithm is
//! described in the parent module).

use core::arch::x86_64::{
    _CMP_EQ_OQ, _CMP_LT_OQ, _CMP_NEQ_OQ, _CMP_NLE_UQ, _mm256_add_epi64, _mm256_add_pd,
    _mm256_and_pd, _mm256_and_si256, _mm256_blendv_pd, _mm256_castpd_si256, _mm256_castsi256_pd,
    _mm256_cmp_pd, _mm256_fmadd_pd, _mm256_fnmadd_pd, _mm256_loadu_pd, _mm256_movemask_pd,
    _mm256_mul_pd, _mm256_or_pd, _mm256_set1_epi64x, _mm256_set1_pd, _mm256_setzero_pd,
    _mm256_slli_epi64, _mm256_storeu_pd, _mm256_sub_pd, _mm256_xor_pd,
};

use super::VECTOR_LIMIT as LIMIT;

/// 2/pi rounded to a double.
const TWO_OVER_PI: f64 = core::f64::consts::FRAC_2_PI;
/// 1.5 * 2^52: added to a number of magnitude below 2^51, rounds it to an integer held in
/// the low bits of the mantissa.
const ROUND: f64 = 6755399441055744.0;
/// pi/2 = P1 + P2 + P3 + (about 5.6e-50): each the double nearest to what is left.
const P1: f64 = core::f64::consts::FRAC_PI_2;
const P2: f64 = 6.123233995736766e-17;
const P3: f64 = -1.4973849048591698e-33;

// fdlibm's __kernel_sin and __kernel_cos coefficients (as in musl and the libm crate),
// written as fdlibm publishes them.
#[allow(clippy::excessive_precision)]
const S1: f64 = -1.66666666666666324348e-01;
#[allow(clippy::excessive_precision)]
const S2: f64 = 8.33333333332248946124e-03;
#[allow(clippy::excessive_precision)]
const S3: f64 = -1.98412698298579493134e-04;
#[allow(clippy::excessive_precision)]
const S4: f64 = 2.75573137070700676789e-06;
#[allow(clippy::excessive_precision)]
const S5: f64 = -2.50507602534068634195e-08;
#[allow(clippy::excessive_precision)]
const S6: f64 = 1.58969099521155010221e-10;
#[allow(clippy::excessive_precision)]
const C1: f64 = 4.16666666666666019037e-02;
#[allow(clippy::excessive_precision)]
const C2: f64 = -1.38888888888741095749e-03;
#[allow(clippy::excessive_precision)]
const C3: f64 = 2.48015872894767294178e-05;
#[allow(clippy::excessive_precision)]
const C4: f64 = -2.75573143513906633035e-07;
#[allow(clippy::excessive_precision)]
const C5: f64 = 2.08757232129817482790e-09;
#[allow(clippy::excessive_precision)]
const C6: f64 = -1.13596475577881948265e-11;

/// Sines and cosines of `N` angles, four at a time (the last vector padded with zeros).
///
/// # Safety
///
/// The CPU must support AVX2 and FMA.
#[inline]
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn sin_cos<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    // SAFETY: the caller guarantees AVX2 and FMA.
    unsafe { sin_cos_inlined(x) }
}

/// [`sin_cos`] without its target features, always inlined: in a function compiled with
/// AVX2 and FMA (the models' AVX2 instances, `crate::fused`) the whole vector path inlines,
/// as Rust allows no `#[inline(always)]` on a function with target features. Elsewhere its
/// intrinsics stay calls, slow but right.
///
/// # Safety
///
/// The CPU must support AVX2 and FMA.
#[inline(always)]
pub(super) unsafe fn sin_cos_inlined<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    let mut s = [0.0; N];
    let mut c = [0.0; N];
    let mut to_libm = false;
    let mut i = 0;
    while i < N {
        let n = (N - i).min(4);
        let mut lanes = [0.0; 4];
        lanes[..n].copy_from_slice(&x[i..i + n]);
        let (mut ls, mut lc) = ([0.0; 4], [0.0; 4]);
        // SAFETY: the caller guarantees AVX2 and FMA.
        let outside = unsafe { sin_cos4(&lanes, &mut ls, &mut lc) };
        to_libm |= outside != 0;
        s[i..i + n].copy_from_slice(&ls[..n]);
        c[i..i + n].copy_from_slice(&lc[..n]);
        i += n;
    }
    if to_libm {
        redo_outside(&x, &mut s, &mut c);
    }
    (s, c)
}

/// Rare: redoes through libm the angles the vector path does not take (libm's results are
/// within its accuracy anyway, so all of them). Out of line, so that its calls do not make
/// the inlining caller keep its values on the stack.
#[cold]
#[inline(never)]
fn redo_outside<const N: usize>(x: &[f64; N], s: &mut [f64; N], c: &mut [f64; N]) {
    for i in 0..N {
        if !in_range(x[i]) {
            (s[i], c[i]) = libm::sincos(x[i]);
        }
    }
}

/// Whether the vector path computes the sine and cosine of `x`: `|x| <= LIMIT`, and `x`
/// is not within `2^-36` of a nonzero multiple of `P1` (the scalar twin of the mask
/// [`sin_cos4`] returns).
fn in_range(x: f64) -> bool {
    let t = libm::fma(x, TWO_OVER_PI, ROUND);
    let k = t - ROUND;
    let r1 = libm::fma(-k, P1, x);
    libm::fabs(x) <= LIMIT && !(k != 0.0 && libm::fabs(r1) < TINY)
}

/// Below this, a reduced argument `x - k P1` with `k != 0` goes to libm (see [`sin_cos4`]).
const TINY: f64 = 1.4551915228366852e-11; // 2^-36

/// Sine and cosine of four angles into `s` and `c`, and the mask (bit `l` for lane `l`) of
/// the lanes whose results are not valid and must come from libm: `|x| > LIMIT`, NaN, and
/// angles within `2^-36` of a nonzero multiple of pi/2. Arrays, not vector registers, in
/// and out: a function without target features cannot pass `__m256d` by value.
///
/// # Safety
///
/// The CPU must support AVX2 and FMA.
#[inline(always)]
unsafe fn sin_cos4(x: &[f64; 4], s: &mut [f64; 4], c: &mut [f64; 4]) -> i32 {
    // SAFETY: AVX2/FMA arithmetic, which the caller guarantees the CPU has; unaligned
    // loads and stores from and to arrays of four doubles.
    unsafe {
        let x = _mm256_loadu_pd(x.as_ptr());
        let splat = |v: f64| _mm256_set1_pd(v);
        let abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX));
        // 1. k = round(x * 2/pi), its bits in the low mantissa of `t`.
        let t = _mm256_fmadd_pd(x, splat(TWO_OVER_PI), splat(ROUND));
        let k = _mm256_sub_pd(t, splat(ROUND));
        // 2. r_hi + r_lo = x - k pi/2: r1 is exact, r_hi one rounding away from
        //    r1 - k P2, and r_lo that rounding error (r1 - r_hi is exact by Sterbenz's
        //    lemma, |k P2| <= |r1| / 2 where the lane is valid) minus k P3.
        let r1 = _mm256_fnmadd_pd(k, splat(P1), x);
        let rh = _mm256_fnmadd_pd(k, splat(P2), r1);
        let rl = _mm256_fnmadd_pd(
            k,
            splat(P3),
            _mm256_fnmadd_pd(k, splat(P2), _mm256_sub_pd(r1, rh)),
        );
        let outside = _mm256_or_pd(
            _mm256_cmp_pd::<_CMP_NLE_UQ>(_mm256_and_pd(x, abs_mask), splat(LIMIT)),
            _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_and_pd(r1, abs_mask), splat(TINY)),
                _mm256_cmp_pd::<_CMP_NEQ_OQ>(k, _mm256_setzero_pd()),
            ),
        );
        // 3. The kernels: fdlibm's polynomials, evaluated by Estrin's scheme.
        let z = _mm256_mul_pd(rh, rh);
        let w = _mm256_mul_pd(z, z);
        let half = splat(0.5);
        let one = splat(1.0);
        // sin = x + (v (S1 + z r) + y (1 - z/2)), v = z x,
        //       r = S2 + z S3 + z^2 S4 + z^3 S5 + z^4 S6 (fdlibm's terms regrouped).
        let f1 = _mm256_fmadd_pd(z, splat(S3), splat(S2));
        let f2 = _mm256_fmadd_pd(z, splat(S5), splat(S4));
        let rs = _mm256_fmadd_pd(_mm256_mul_pd(w, w), splat(S6), _mm256_fmadd_pd(w, f2, f1));
        let v = _mm256_mul_pd(z, rh);
        let ys = _mm256_mul_pd(rl, _mm256_fnmadd_pd(half, z, one));
        let ps = _mm256_fmadd_pd(z, rs, splat(S1));
        let sin = _mm256_add_pd(rh, _mm256_fmadd_pd(v, ps, ys));
        // cos = (1 - z/2) + (z^2 P + (((1 - (1 - z/2)) - z/2) - x y)),
        //       P = C1 + z C2 + z^2 C3 + z^3 C4 + z^4 C5 + z^5 C6.
        let e1 = _mm256_fmadd_pd(z, splat(C2), splat(C1));
        let e2 = _mm256_fmadd_pd(z, splat(C4), splat(C3));
        let e3 = _mm256_fmadd_pd(z, splat(C6), splat(C5));
        let pc = _mm256_fmadd_pd(_mm256_mul_pd(w, w), e3, _mm256_fmadd_pd(w, e2, e1));
        let hz = _mm256_mul_pd(half, z);
        let w1 = _mm256_sub_pd(one, hz);
        let c0 = _mm256_fnmadd_pd(rh, rl, _mm256_sub_pd(_mm256_sub_pd(one, w1), hz));
        let cos = _mm256_add_pd(w1, _mm256_fmadd_pd(w, pc, c0));
        // 4. Quadrant: swap for odd k, then the signs of bit 1 of k (sine) and of k + 1
        //    (cosine).
        let bits = _mm256_castpd_si256(t);
        let odd = _mm256_castsi256_pd(_mm256_slli_epi64::<63>(bits));
        let sign = _mm256_set1_epi64x(i64::MIN);
        let sin_sign = _mm256_and_si256(_mm256_slli_epi64::<62>(bits), sign);
        let cos_sign = _mm256_and_si256(
            _mm256_slli_epi64::<62>(_mm256_add_epi64(bits, _mm256_set1_epi64x(1))),
            sign,
        );
        let sin_q = _mm256_xor_pd(
            _mm256_blendv_pd(sin, cos, odd),
            _mm256_castsi256_pd(sin_sign),
        );
        let cos_q = _mm256_xor_pd(
            _mm256_blendv_pd(cos, sin, odd),
            _mm256_castsi256_pd(cos_sign),
        );
        // sin(±0) = ±0 (x + (+0) would be +0 for -0).
        let zero = _mm256_cmp_pd::<_CMP_EQ_OQ>(x, _mm256_setzero_pd());
        _mm256_storeu_pd(s.as_mut_ptr(), _mm256_blendv_pd(sin_q, x, zero));
        _mm256_storeu_pd(c.as_mut_ptr(), cos_q);
        _mm256_movemask_pd(outside)
    }
}
