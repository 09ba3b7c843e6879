//! The scalar trait that generated models are generic over.

use core::fmt::Debug;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// A real scalar for generated straight-line code: `f64`, `f32`, and
/// [`Lanes`](crate::lanes::Lanes) of `f64` (several argument sets at once).
///
/// Only what the emitted code needs: arithmetic, the trigonometric functions of
/// joint angles, `sign` for Coulomb friction and `sqrt`. In `no_std` builds the
/// functions come from `libm`, so the same code runs on a microcontroller.
pub trait Real:
    Copy
    + Debug
    + PartialEq
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Zero.
    const ZERO: Self;
    /// One.
    const ONE: Self;
    /// Converts a literal from the generated code (rounded to the nearest value for `f32`).
    fn from_f64(value: f64) -> Self;
    /// Sine.
    fn sin(self) -> Self;
    /// Cosine.
    fn cos(self) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Sine and cosine of the same angle, `(sin, cos)`; implementations may
    /// share the work (one argument reduction).
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        (self.sin(), self.cos())
    }
    /// Sines and cosines of `N` angles, `([sin x0, ...], [cos x0, ...])`: what generated
    /// code calls once, at its start, for the joint angles it needs.
    ///
    /// By default each angle goes through [`sin_cos`](Real::sin_cos) (libm); for `f64`,
    /// [`trig::sin_cos_static`](crate::trig::sin_cos_static): vectorised when the build
    /// enables AVX2 and FMA on x86-64, libm otherwise.
    ///
    /// ```
    /// use robid_runtime::Real;
    /// let ([s0, s1], [c0, c1]) = f64::sin_cos_array([0.0, 1.0]);
    /// assert_eq!((s0, c0), (0.0, 1.0));
    /// assert!((s1 - 1.0_f64.sin()).abs() < 1e-15 && (c1 - 1.0_f64.cos()).abs() < 1e-15);
    /// let (s, c) = f32::sin_cos_array([0.5_f32; 3]);
    /// assert_eq!((s[2], c[2]), 0.5_f32.sin_cos());
    /// ```
    #[inline(always)]
    fn sin_cos_array<const N: usize>(x: [Self; N]) -> ([Self; N], [Self; N]) {
        let mut s = [Self::ZERO; N];
        let mut c = [Self::ZERO; N];
        for i in 0..N {
            (s[i], c[i]) = x[i].sin_cos();
        }
        (s, c)
    }
    /// Sign for Coulomb friction: -1, 0 or 1 (0 at exactly zero, unlike `f64::signum`).
    fn sign(self) -> Self;
    /// `self * a + b`: what generated code writes for a product used only by a sum.
    ///
    /// For `f64` and `f32`, rounded once (a fused multiply-add instruction) when
    /// [`FUSED_MUL_ADD`] says the build targets one, so one instruction replaces two;
    /// otherwise the product and the sum, each rounded, the same values to the bit as
    /// `self * a + b`. Rust never fuses operations by itself.
    ///
    /// ```
    /// use robid_runtime::{FUSED_MUL_ADD, Real};
    /// let x = 1.0 + f64::EPSILON;
    /// // x * x = 1 + 2 eps + eps^2: the eps^2 survives only a single rounding
    /// let r = Real::mul_add(x, x, -(1.0 + 2.0 * f64::EPSILON));
    /// assert_eq!(r, if FUSED_MUL_ADD { f64::EPSILON * f64::EPSILON } else { 0.0 });
    /// ```
    fn mul_add(self, a: Self, b: Self) -> Self;
}

/// Whether [`Real::mul_add`] of `f64` and `f32` rounds once: in `std` builds for
/// x86-64 (or x86) with the `fma` target feature (`-C target-cpu=native` on a CPU that
/// has it, `-C target-feature=+fma`), and for AArch64, where the instruction is always
/// there. Elsewhere a fused multiply-add would be a slow software routine, so the product
/// and the sum are rounded each; `no_std` builds always are (`core` has no `mul_add`).
pub const FUSED_MUL_ADD: bool = cfg!(all(
    feature = "std",
    any(
        target_arch = "aarch64",
        all(
            any(target_arch = "x86_64", target_arch = "x86"),
            target_feature = "fma"
        )
    )
));

macro_rules! impl_real {
    ($t:ty, $sin:path, $cos:path, $sincos:path, $sqrt:path $(, $array:path)?) => {
        impl Real for $t {
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            #[inline(always)]
            fn from_f64(value: f64) -> Self {
                value as $t
            }
            #[inline(always)]
            fn sin(self) -> Self {
                $sin(self)
            }
            #[inline(always)]
            fn cos(self) -> Self {
                $cos(self)
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                $sqrt(self)
            }
            #[inline(always)]
            fn sin_cos(self) -> (Self, Self) {
                $sincos(self)
            }
            $(
                #[inline(always)]
                fn sin_cos_array<const N: usize>(x: [Self; N]) -> ([Self; N], [Self; N]) {
                    $array(x)
                }
            )?
            #[inline(always)]
            fn mul_add(self, a: Self, b: Self) -> Self {
                #[cfg(feature = "std")]
                if FUSED_MUL_ADD {
                    return <$t>::mul_add(self, a, b);
                }
                self * a + b
            }
            #[inline(always)]
            fn sign(self) -> Self {
                if self > 0.0 {
                    1.0
                } else if self < 0.0 {
                    -1.0
                } else {
                    0.0
                }
            }
        }
    };
}

impl_real!(
    f64,
    libm::sin,
    libm::cos,
    libm::sincos,
    libm::sqrt,
    crate::trig::sin_cos_static
);
impl_real!(f32, libm::sinf, libm::cosf, libm::sincosf, libm::sqrtf);

#[cfg(test)]
mod tests {
    use super::Real;

    #[test]
    fn sign_is_zero_at_zero() {
        assert_eq!(Real::sign(0.0_f64), 0.0);
        assert_eq!(Real::sign(-2.0_f32), -1.0);
        assert_eq!(Real::sign(3.0_f64), 1.0);
    }

    #[test]
    fn trig_matches_std() {
        for x in [-3.0_f64, -0.5, 0.0, 1.2, 7.0] {
            assert!((Real::sin(x) - x.sin()).abs() < 1e-15);
            assert!((Real::cos(x) - x.cos()).abs() < 1e-15);
            let (s, c) = Real::sin_cos(x);
            assert!((s - x.sin()).abs() < 1e-15 && (c - x.cos()).abs() < 1e-15);
            let (s, c) = Real::sin_cos(x as f32);
            assert!((s - (x as f32).sin()).abs() < 1e-6 && (c - (x as f32).cos()).abs() < 1e-6);
        }
    }
}
