//! Several argument sets through one generated function: [`Lanes`], a [`Real`] whose
//! every operation acts on `W` values side by side.
//!
//! A generated function is straight-line code with no branch on its values, so running it
//! with `T = Lanes<W>` computes `W` independent sets (samples of a trajectory, candidate
//! trajectories of an excitation) with one instruction stream: the compiler turns each
//! lane-wise operation into vector instructions (two lanes per SSE2 instruction, four per
//! AVX2 one). Every lane's result is the `f64` function's, to the bit: each lane-wise
//! operation is the same IEEE operation, and the sines and cosines of a lane are those
//! [`Real::sin_cos_array`] gives `f64` for the same angles (a NaN's payload aside). The
//! lane-major slices of [`Model::run_lanes`](crate::Model::run_lanes) do not go through
//! it: transposing them into lanes and back costs what the lanes save
//! (docs/performance.md, "Several states per call").

use crate::Real;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// `W` values of `f64` computed side by side: each operation acts lane by lane.
///
/// ```
/// use robid_runtime::Real;
/// use robid_runtime::lanes::Lanes;
/// let x = Lanes([0.5, -1.0]);
/// let y = x * x + Lanes::from_f64(1.0);
/// assert_eq!(y, Lanes([1.25, 2.0]));
/// assert_eq!(y.sign(), Lanes([1.0, 1.0]));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(transparent)]
pub struct Lanes<const W: usize>(pub [f64; W]);

impl<const W: usize> Lanes<W> {
    /// Applies `f` to every lane.
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        Self(self.0.map(f))
    }

    /// Applies `f` to the lanes of `self` and `other` pairwise.
    #[inline(always)]
    fn zip(self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        Self(core::array::from_fn(|l| f(self.0[l], other.0[l])))
    }
}

macro_rules! lane_wise {
    ($trait:ident, $method:ident, $op:tt) => {
        impl<const W: usize> $trait for Lanes<W> {
            type Output = Self;
            #[inline(always)]
            fn $method(self, other: Self) -> Self {
                self.zip(other, |a, b| a $op b)
            }
        }
    };
}

lane_wise!(Add, add, +);
lane_wise!(Sub, sub, -);
lane_wise!(Mul, mul, *);
lane_wise!(Div, div, /);

impl<const W: usize> Neg for Lanes<W> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.map(|a| -a)
    }
}

impl<const W: usize> Real for Lanes<W> {
    const ZERO: Self = Self([0.0; W]);
    const ONE: Self = Self([1.0; W]);
    #[inline(always)]
    fn from_f64(value: f64) -> Self {
        Self([value; W])
    }
    #[inline(always)]
    fn sin(self) -> Self {
        self.map(Real::sin)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        self.map(Real::cos)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.map(Real::sqrt)
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        let ([s], [c]) = Self::sin_cos_array([self]);
        (s, c)
    }
    /// Lane by lane, `f64`'s [`Real::sin_cos_array`] of that lane's `N` angles, so that
    /// each lane's values are those of the `f64` function to the bit (the vector path
    /// takes angles four at a time, the same in either case).
    #[inline(always)]
    fn sin_cos_array<const N: usize>(x: [Self; N]) -> ([Self; N], [Self; N]) {
        let mut s = [Self::ZERO; N];
        let mut c = [Self::ZERO; N];
        for l in 0..W {
            let (ls, lc) = f64::sin_cos_array(x.map(|a| a.0[l]));
            for i in 0..N {
                s[i].0[l] = ls[i];
                c[i].0[l] = lc[i];
            }
        }
        (s, c)
    }
    #[inline(always)]
    fn sign(self) -> Self {
        self.map(Real::sign)
    }
    #[inline(always)]
    fn mul_add(self, a: Self, b: Self) -> Self {
        Self(core::array::from_fn(|l| {
            Real::mul_add(self.0[l], a.0[l], b.0[l])
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::Lanes;
    use crate::Real;

    /// Each operation of a lane equals the `f64` operation on that lane's values.
    #[test]
    fn every_operation_is_the_f64_one_lane_by_lane() {
        let a = [0.3, -1.7, -0.0, 2.5e3];
        let b = [1.1, 0.4, -0.5, -7.0];
        let (x, y) = (Lanes(a), Lanes(b));
        for l in 0..4 {
            assert_eq!((x + y).0[l], a[l] + b[l]);
            assert_eq!((x - y).0[l], a[l] - b[l]);
            assert_eq!((x * y).0[l], a[l] * b[l]);
            assert_eq!((x / y).0[l].to_bits(), (a[l] / b[l]).to_bits());
            assert_eq!((-x).0[l].to_bits(), (-a[l]).to_bits());
            assert_eq!(x.sign().0[l], Real::sign(a[l]));
            let fused = Real::mul_add(x, y, x).0[l];
            assert_eq!(fused.to_bits(), Real::mul_add(a[l], b[l], a[l]).to_bits());
            let root = Lanes(b.map(f64::abs)).sqrt().0[l];
            assert_eq!(root.to_bits(), Real::sqrt(b[l].abs()).to_bits());
            assert_eq!(x.sin().0[l], Real::sin(a[l]));
            assert_eq!(x.cos().0[l], Real::cos(a[l]));
            assert_eq!(x.sin_cos().0.0[l], Real::sin_cos(a[l]).0);
        }
        assert_eq!(Lanes::<4>::from_f64(2.0), Lanes([2.0; 4]));
        assert_eq!(
            (Lanes::<3>::ZERO, Lanes::<3>::ONE),
            (Lanes([0.0; 3]), Lanes([1.0; 3]))
        );
    }

    /// The sines and cosines of several angles are those `f64` gives each lane's angles
    /// (the vector path when the build has AVX2, libm otherwise), to the bit.
    #[test]
    fn sines_and_cosines_are_each_lanes_own() {
        let angles: [[f64; 4]; 5] =
            core::array::from_fn(|i| core::array::from_fn(|l| 0.7 * i as f64 - 1.3 * l as f64));
        let (s, c) = Lanes::<4>::sin_cos_array(angles.map(Lanes));
        for l in 0..4 {
            let (fs, fc) = f64::sin_cos_array(angles.map(|a| a[l]));
            for i in 0..5 {
                assert_eq!(s[i].0[l].to_bits(), fs[i].to_bits());
                assert_eq!(c[i].0[l].to_bits(), fc[i].to_bits());
            }
        }
    }
}
