//! The scalar of the copies of generated functions compiled for AVX2 and FMA, which
//! [`Model::run`](crate::Model::run) calls on a processor that has both.
//!
//! A default x86-64 build targets every x86-64 processor: its generated code rounds each
//! product and each sum on its own and takes sines and cosines from libm one angle at a
//! time. Built with `-C target-cpu=native` on a recent processor, the same code writes a
//! product used only by a sum as one fused multiply-add and computes the joint angles'
//! sines and cosines four at a time ([`trig`](crate::trig)): the UR5e's inverse dynamics
//! then costs about 1.2 times six sines and cosines instead of 1.8
//! (docs/performance.md, "Fused multiply-adds").
//!
//! So that the default build gets the same, `robot_model!` emits for x86-64 a second
//! instance of each generated function, compiled with
//! `#[target_feature(enable = "avx2,fma")]` and with [`Fused`] as its scalar, whose
//! [`Real::mul_add`] is the `vfmadd` instruction and whose
//! [`Real::sin_cos_array`] is the vector path inlined. `Model::run` calls it when
//! [`dispatch`] says so: on x86-64 with the `std` feature, when the processor executes
//! AVX2 and FMA (asked once) and the build does not target them already (then the plain
//! `f64` code is the same). The generic functions (`Ur5e::inverse_dynamics::<f64>`, ...)
//! never dispatch.
//!
//! The two instances agree to rounding (a fused operation rounds once where the plain
//! code rounds twice; the vector sines and cosines are within 1 ulp of libm's), not to the
//! bit; [`set_enabled`]`(false)` makes `Model::run` take the plain instance everywhere,
//! for results equal to the bit on every x86-64 processor or to time both in one run.

use crate::Real;
use core::ops::{Add, Div, Mul, Neg, Sub};
use core::sync::atomic::{AtomicBool, Ordering};

/// An `f64` whose [`Real::mul_add`] rounds once (with the `std` feature) and whose
/// [`Real::sin_cos_array`] is [`trig::sin_cos`](crate::trig::sin_cos), vectorised when the
/// processor has AVX2 and FMA: the scalar of the generated functions' AVX2 instances.
///
/// In code compiled without the `fma` target feature a fused multiply-add is a call to a
/// slow software routine, so this type is for functions compiled with it, which is what
/// `robot_model!` emits it in.
///
/// ```
/// use robid_runtime::{Real, fused::Fused};
/// let x = Fused(1.0 + f64::EPSILON);
/// // x * x = 1 + 2 eps + eps^2: the eps^2 survives a single rounding
/// let r = Real::mul_add(x, x, Fused(-(1.0 + 2.0 * f64::EPSILON)));
/// assert_eq!(r, Fused(f64::EPSILON * f64::EPSILON));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, PartialOrd)]
#[repr(transparent)]
pub struct Fused(pub f64);

macro_rules! binary {
    ($trait:ident, $method:ident, $op:tt) => {
        impl $trait for Fused {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: Self) -> Self {
                Self(self.0 $op other.0)
            }
        }
    };
}

binary!(Add, add, +);
binary!(Sub, sub, -);
binary!(Mul, mul, *);
binary!(Div, div, /);

impl Neg for Fused {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Self(-self.0)
    }
}

impl Real for Fused {
    const ZERO: Self = Self(0.0);
    const ONE: Self = Self(1.0);
    #[inline(always)]
    fn from_f64(value: f64) -> Self {
        Self(value)
    }
    #[inline(always)]
    fn sin(self) -> Self {
        Self(libm::sin(self.0))
    }
    #[inline(always)]
    fn cos(self) -> Self {
        Self(libm::cos(self.0))
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        Self(libm::sqrt(self.0))
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = libm::sincos(self.0);
        (Self(s), Self(c))
    }
    #[inline(always)]
    fn sin_cos_array<const N: usize>(x: [Self; N]) -> ([Self; N], [Self; N]) {
        // the run-time choice of `trig::sin_cos` (an atomic load) keeps this safe for a
        // `Fused` used anywhere; in the AVX2 instances the vector path inlines
        let (s, c) = crate::trig::sin_cos_inlined(into_array(x));
        (from_array(s), from_array(c))
    }
    #[inline(always)]
    fn sign(self) -> Self {
        Self(self.0.sign())
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        #[cfg(feature = "std")]
        {
            Self(self.0.mul_add(a.0, b.0))
        }
        #[cfg(not(feature = "std"))]
        {
            self * a + b
        }
    }
}

/// `x` as `Fused` values, the same bits (what the AVX2 instances take).
#[inline(always)]
pub fn from_array<const N: usize>(x: [f64; N]) -> [Fused; N] {
    // SAFETY: `Fused` is a `repr(transparent)` `f64`: the same size, alignment and valid
    // bit patterns, so the arrays are too.
    unsafe { core::mem::transmute_copy(&x) }
}

/// `x` as `f64` values, the same bits (what the AVX2 instances return).
#[inline(always)]
pub fn into_array<const N: usize>(x: [Fused; N]) -> [f64; N] {
    // SAFETY: as in `from_array`.
    unsafe { core::mem::transmute_copy(&x) }
}

/// `x` seen as `Fused` values, without a copy.
#[inline(always)]
pub fn as_array<const N: usize>(x: &[f64; N]) -> &[Fused; N] {
    // SAFETY: as in `from_array`; the reference keeps the borrow of `x`.
    unsafe { &*core::ptr::from_ref(x).cast::<[Fused; N]>() }
}

/// `x` seen as `Fused` values to write, without a copy (the AVX2 instances write their
/// results straight into the caller's array).
#[inline(always)]
pub fn as_array_mut<const N: usize>(x: &mut [f64; N]) -> &mut [Fused; N] {
    // SAFETY: as in `from_array`; the reference keeps the mutable borrow of `x`.
    unsafe { &mut *core::ptr::from_mut(x).cast::<[Fused; N]>() }
}

/// Whether the AVX2 instances may be called: cleared by [`set_enabled`]`(false)`.
static ENABLED: AtomicBool = AtomicBool::new(true);

/// Makes [`Model::run`](crate::Model::run) of generated models call their AVX2 instances
/// where the processor allows (`true`, the default) or always their plain `f64` code
/// (`false`: the same results to the bit on every x86-64 processor, as on one without
/// AVX2). For the whole process.
///
/// ```
/// robid_runtime::fused::set_enabled(false);
/// assert!(!robid_runtime::fused::dispatch());
/// robid_runtime::fused::set_enabled(true);
/// ```
pub fn set_enabled(enabled: bool) {
    ENABLED.store(enabled, Ordering::Relaxed);
}

/// Whether [`Model::run`](crate::Model::run) of generated models calls their AVX2
/// instances: on x86-64 with the `std` feature, when the processor executes AVX2 and FMA
/// (asked once), the build does not target both already, and [`set_enabled`] has not
/// turned it off. `false` everywhere else.
///
/// ```
/// let avx2 = robid_runtime::fused::dispatch();
/// if avx2 {
///     assert!(robid_runtime::trig::vector_available());
/// }
/// ```
#[inline]
pub fn dispatch() -> bool {
    #[cfg(all(
        target_arch = "x86_64",
        feature = "std",
        not(all(target_feature = "avx2", target_feature = "fma"))
    ))]
    {
        ENABLED.load(Ordering::Relaxed) && crate::trig::vector_available()
    }
    #[cfg(not(all(
        target_arch = "x86_64",
        feature = "std",
        not(all(target_feature = "avx2", target_feature = "fma"))
    )))]
    {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::{Fused, from_array, into_array};
    use crate::Real;
    use crate::rng::Rng;

    /// The instances' sines and cosines are `trig::sin_cos`'s to the bit: the vector path
    /// where the processor has it (which differs from libm in some last bits), libm else.
    #[test]
    fn sines_and_cosines_are_those_of_trig_sin_cos() {
        let mut rng = Rng::from_state(3);
        for _ in 0..300 {
            let x: [f64; 5] = core::array::from_fn(|_| rng.uniform(-10.0, 10.0));
            let (s, c) = Fused::sin_cos_array(from_array(x));
            let (ts, tc) = crate::trig::sin_cos(x);
            assert_eq!(into_array(s).map(f64::to_bits), ts.map(f64::to_bits));
            assert_eq!(into_array(c).map(f64::to_bits), tc.map(f64::to_bits));
        }
        // one angle: libm's
        let ([s], [c]) = Fused::sin_cos_array([Fused(0.7)]);
        assert_eq!((s.0, c.0), libm::sincos(0.7));
    }

    #[test]
    fn arithmetic_is_that_of_f64() {
        let (a, b) = (Fused(1.5), Fused(-0.25));
        assert_eq!(
            (a + b, a - b, a * b, a / b, -a),
            (
                Fused(1.25),
                Fused(1.75),
                Fused(-0.375),
                Fused(-6.0),
                Fused(-1.5)
            )
        );
        assert_eq!(
            (Fused(-2.0).sign(), Fused(0.0).sign()),
            (Fused(-1.0), Fused(0.0))
        );
        assert_eq!(Fused(4.0).sqrt(), Fused(2.0));
    }
}
