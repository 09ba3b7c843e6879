//! The AVX2 + FMA path of [`super::sin_cos`]: four angles per vector (the algorithm is
//! described in the parent module).

use core::arch::x86_64::{
    __m256d, _CMP_EQ_OQ, _CMP_NLE_UQ, _mm256_add_epi64, _mm256_add_pd, _mm256_and_pd,
    _mm256_and_si256, _mm256_blendv_pd, _mm256_castpd_si256, _mm256_castsi256_pd, _mm256_cmp_pd,
    _mm256_fmadd_pd, _mm256_fmsub_pd, _mm256_fnmadd_pd, _mm256_loadu_pd, _mm256_movemask_pd,
    _mm256_mul_pd, _mm256_set1_epi64x, _mm256_set1_pd, _mm256_setzero_pd, _mm256_slli_epi64,
    _mm256_storeu_pd, _mm256_sub_pd, _mm256_xor_pd,
};

use super::VECTOR_LIMIT as LIMIT;

/// 2/pi rounded to a double.
const TWO_OVER_PI: f64 = 0.6366197723675814;
/// 1.5 * 2^52: added to a number of magnitude below 2^51, rounds it to an integer held in
/// the low bits of the mantissa.
const ROUND: f64 = 6755399441055744.0;
/// pi/2 = P1 + P2 + P3 + (about 5.6e-50): each the double nearest to what is left.
const P1: f64 = 1.5707963267948966;
const P2: f64 = 6.123233995736766e-17;
const P3: f64 = -1.4973849048591698e-33;

// fdlibm's __kernel_sin and __kernel_cos coefficients (as in musl and the libm crate).
const S1: f64 = -1.66666666666666324348e-01;
const S2: f64 = 8.33333333332248946124e-03;
const S3: f64 = -1.98412698298579493134e-04;
const S4: f64 = 2.75573137070700676789e-06;
const S5: f64 = -2.50507602534068634195e-08;
const S6: f64 = 1.58969099521155010221e-10;
const C1: f64 = 4.16666666666666019037e-02;
const C2: f64 = -1.38888888888741095749e-03;
const C3: f64 = 2.48015872894767294178e-05;
const C4: f64 = -2.75573143513906633035e-07;
const C5: f64 = 2.08757232129817482790e-09;
const C6: f64 = -1.13596475577881948265e-11;

/// Sines and cosines of `N` angles, four at a time (the last vector padded with zeros).
///
/// # Safety
///
/// The CPU must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(super) unsafe fn sin_cos<const N: usize>(x: [f64; N]) -> ([f64; N], [f64; N]) {
    let mut s = [0.0; N];
    let mut c = [0.0; N];
    let mut i = 0;
    while i < N {
        let n = (N - i).min(4);
        let mut lanes = [0.0; 4];
        lanes[..n].copy_from_slice(&x[i..i + n]);
        let (mut ls, mut lc) = ([0.0; 4], [0.0; 4]);
        // SAFETY: the caller guarantees AVX2 and FMA; the loads and stores are
        // unaligned ones from and to arrays of four doubles.
        unsafe {
            let (vs, vc) = sin_cos4(_mm256_loadu_pd(lanes.as_ptr()));
            _mm256_storeu_pd(ls.as_mut_ptr(), vs);
            _mm256_storeu_pd(lc.as_mut_ptr(), vc);
            let outside = _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_NLE_UQ>(
                abs(_mm256_loadu_pd(lanes.as_ptr())),
                _mm256_set1_pd(LIMIT),
            ));
            if outside != 0 {
                for (l, &x) in lanes.iter().enumerate() {
                    if outside & (1 << l) != 0 {
                        (ls[l], lc[l]) = libm::sincos(x);
                    }
                }
            }
        }
        s[i..i + n].copy_from_slice(&ls[..n]);
        c[i..i + n].copy_from_slice(&lc[..n]);
        i += n;
    }
    (s, c)
}

/// `|x|`.
#[inline]
#[target_feature(enable = "avx2,fma")]
unsafe fn abs(x: __m256d) -> __m256d {
    // SAFETY: the caller guarantees AVX2 (these are AVX instructions). The block is
    // needed before Rust 1.87, which made these intrinsics safe in AVX2 functions.
    #[allow(unused_unsafe)]
    unsafe {
        _mm256_and_pd(x, _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX)))
    }
}

/// Sine and cosine of four angles of magnitude at most [`LIMIT`] (other lanes give
/// garbage, which the caller replaces).
///
/// # Safety
///
/// The CPU must support AVX2 and FMA.
#[inline]
#[target_feature(enable = "avx2,fma")]
unsafe fn sin_cos4(x: __m256d) -> (__m256d, __m256d) {
    // SAFETY: register-only AVX2/FMA arithmetic; the caller guarantees the CPU has it.
    // (The block is needed before Rust 1.87, which made these intrinsics safe here.)
    #[allow(unused_unsafe)]
    unsafe {
        let splat = |v: f64| _mm256_set1_pd(v);
        // 1. k = round(x * 2/pi), its bits in the low mantissa of `t`.
        let t = _mm256_fmadd_pd(x, splat(TWO_OVER_PI), splat(ROUND));
        let k = _mm256_sub_pd(t, splat(ROUND));
        // 2. r_hi + r_lo = x - k pi/2.
        let r1 = _mm256_fnmadd_pd(k, splat(P1), x);
        let p_hi = _mm256_mul_pd(k, splat(P2));
        let p_lo = _mm256_fmsub_pd(k, splat(P2), p_hi);
        let s = _mm256_sub_pd(r1, p_hi);
        let b = _mm256_sub_pd(s, r1);
        let e = _mm256_sub_pd(
            _mm256_sub_pd(r1, _mm256_sub_pd(s, b)),
            _mm256_add_pd(p_hi, b),
        );
        let lo = _mm256_fnmadd_pd(k, splat(P3), _mm256_sub_pd(e, p_lo));
        let rh = _mm256_add_pd(s, lo);
        let rl = _mm256_sub_pd(lo, _mm256_sub_pd(rh, s));
        // 3. The kernels (fdlibm's evaluation order, with fused multiply-adds).
        let z = _mm256_mul_pd(rh, rh);
        let w = _mm256_mul_pd(z, z);
        let half = splat(0.5);
        // sin: r = S2 + z (S3 + z S4) + z w (S5 + z S6);
        //      sin = x - ((z (y/2 - v r) - y) - v S1), v = z x.
        let a = _mm256_fmadd_pd(z, _mm256_fmadd_pd(z, splat(S4), splat(S3)), splat(S2));
        let bs = _mm256_fmadd_pd(z, splat(S6), splat(S5));
        let rs = _mm256_fmadd_pd(_mm256_mul_pd(z, w), bs, a);
        let v = _mm256_mul_pd(z, rh);
        let inner = _mm256_fnmadd_pd(v, rs, _mm256_mul_pd(half, rl));
        let tail = _mm256_fnmadd_pd(v, splat(S1), _mm256_fmsub_pd(z, inner, rl));
        let sin = _mm256_sub_pd(rh, tail);
        // cos: r = z (C1 + z (C2 + z C3)) + w^2 (C4 + z (C5 + z C6));
        //      cos = (1 - z/2) + (((1 - (1 - z/2)) - z/2) + (z r - x y)).
        let ac = _mm256_fmadd_pd(z, _mm256_fmadd_pd(z, splat(C3), splat(C2)), splat(C1));
        let bc = _mm256_fmadd_pd(z, _mm256_fmadd_pd(z, splat(C6), splat(C5)), splat(C4));
        let rc = _mm256_fmadd_pd(_mm256_mul_pd(w, w), bc, _mm256_mul_pd(z, ac));
        let hz = _mm256_mul_pd(half, z);
        let one = splat(1.0);
        let w1 = _mm256_sub_pd(one, hz);
        let corr = _mm256_fnmadd_pd(rh, rl, _mm256_mul_pd(z, rc));
        let cos = _mm256_add_pd(
            w1,
            _mm256_add_pd(_mm256_sub_pd(_mm256_sub_pd(one, w1), hz), corr),
        );
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
        // sin(±0) = ±0 (the reduction above returns +0 for -0).
        let zero = _mm256_cmp_pd::<_CMP_EQ_OQ>(x, _mm256_setzero_pd());
        (_mm256_blendv_pd(sin_q, x, zero), cos_q)
    }
}
