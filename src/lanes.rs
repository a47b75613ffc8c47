//! Several elements at once: the lane type the generated `*_lanes` kernels
//! are written for, and the width this machine runs them at.
//!
//! The generator emits every integral kernel's value, gradient and
//! Hessian, and the energy's, a second time (`*_lanes`), generic over a
//! [`Lane`]: the same statements, in the same order, on a
//! value that holds one number per element. [`Lanes<W>`] holds `W`
//! elements' numbers; its operations act lane by lane, so each lane of a
//! result is bit for bit the scalar kernel's result for that element (no
//! operation is fused or reordered). The compiler turns the lane
//! operations into vector instructions: inside a function compiled for
//! AVX-512 ([`Width::EightAvx512`]) or AVX2 ([`Width::FourAvx2`]) when the
//! processor has them (checked at run time), and with the baseline
//! instruction set otherwise ([`Width::Four`]). The element code that packs
//! the moments and calls the kernels is `crate::element`'s.

use std::ops::{Add, AddAssign, Div, Mul, Neg, Sub};
use std::sync::OnceLock;

/// A number per lane: the type the generated `*_lanes` kernels compute on.
pub trait Lane:
    Copy
    + std::fmt::Debug
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + Add<f64, Output = Self>
    + Sub<f64, Output = Self>
    + Mul<f64, Output = Self>
    + Div<f64, Output = Self>
{
    /// Number of lanes.
    const WIDTH: usize;
    /// Every lane `x`.
    fn splat(x: f64) -> Self;
    /// Lane `i` is `f(i)`.
    fn from_fn(f: impl FnMut(usize) -> f64) -> Self;
    /// Lane `i` (`i < WIDTH`).
    fn lane(&self, i: usize) -> f64;
    /// The square root of every lane (correctly rounded, as `f64::sqrt`).
    fn sqrt(self) -> Self;
}

/// `f64` on the left of a lane operation (`2.0 * x`): the generated
/// kernels require `f64: LaneScalar<L>`.
pub trait LaneScalar<L>:
    Add<L, Output = L> + Sub<L, Output = L> + Mul<L, Output = L> + Div<L, Output = L>
{
}

impl<L> LaneScalar<L> for f64 where
    f64: Add<L, Output = L> + Sub<L, Output = L> + Mul<L, Output = L> + Div<L, Output = L>
{
}

/// A value on a 64-byte boundary, a cache line: the lanes in it are read
/// with vector loads that never straddle two lines (the heap aligns to 16
/// bytes only; docs/performance.md, "Code and lanes on cache lines").
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(crate) struct CacheLine<T>(pub T);

/// Values of one cache line each (lanes of eight numbers), every one on a
/// 64-byte boundary: a `Vec` of them would sit where the heap put it, so
/// three vector loads and stores in four would straddle two lines.
#[derive(Debug)]
pub(crate) struct OnLines<T>(Vec<CacheLine<T>>);

impl<T> Default for OnLines<T> {
    fn default() -> OnLines<T> {
        OnLines(Vec::new())
    }
}

impl<T: Copy> OnLines<T> {
    /// A `T` fills its line exactly: the slices of `Deref` rely on it, and
    /// for a type that does not, they fail to compile.
    const FITS: () = assert!(size_of::<CacheLine<T>>() == size_of::<T>());

    /// `len` copies of `x`.
    pub fn from_elem(x: T, len: usize) -> OnLines<T> {
        OnLines(vec![CacheLine(x); len])
    }

    /// The values of `values`, in order.
    pub fn from_values(values: impl IntoIterator<Item = T>) -> OnLines<T> {
        OnLines(values.into_iter().map(CacheLine).collect())
    }
}

impl<T: Copy> std::ops::Deref for OnLines<T> {
    type Target = [T];
    #[inline(always)]
    fn deref(&self) -> &[T] {
        let () = Self::FITS;
        // SAFETY: `CacheLine` is `repr(C)` around one `T` and, by `FITS`
        // (checked when this is compiled), as large as it: no padding
        unsafe { std::slice::from_raw_parts(self.0.as_ptr().cast::<T>(), self.0.len()) }
    }
}

impl<T: Copy> std::ops::DerefMut for OnLines<T> {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut [T] {
        let () = Self::FITS;
        let (ptr, len) = (self.0.as_mut_ptr(), self.0.len());
        // SAFETY: as in `deref`
        unsafe { std::slice::from_raw_parts_mut(ptr.cast::<T>(), len) }
    }
}

impl<T: Copy> Clone for OnLines<T> {
    fn clone(&self) -> OnLines<T> {
        OnLines(self.0.clone())
    }

    /// Reuses `self`'s allocation where it is large enough.
    fn clone_from(&mut self, source: &OnLines<T>) {
        self.0.clone_from(&source.0);
    }
}

impl<T: Copy + PartialEq> PartialEq for OnLines<T> {
    fn eq(&self, other: &OnLines<T>) -> bool {
        **self == **other
    }
}

/// `W` numbers side by side, one per element.
#[derive(Debug, Clone, Copy, PartialEq)]
#[repr(transparent)]
pub struct Lanes<const W: usize>(pub [f64; W]);

macro_rules! lane_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<const W: usize> $tr for Lanes<W> {
            type Output = Lanes<W>;
            #[inline(always)]
            fn $f(self, b: Lanes<W>) -> Lanes<W> {
                Lanes(std::array::from_fn(|i| self.0[i] $op b.0[i]))
            }
        }
        impl<const W: usize> $tr<f64> for Lanes<W> {
            type Output = Lanes<W>;
            #[inline(always)]
            fn $f(self, b: f64) -> Lanes<W> {
                Lanes(self.0.map(|a| a $op b))
            }
        }
        impl<const W: usize> $tr<Lanes<W>> for f64 {
            type Output = Lanes<W>;
            #[inline(always)]
            fn $f(self, b: Lanes<W>) -> Lanes<W> {
                Lanes(b.0.map(|x| self $op x))
            }
        }
    };
}

lane_op!(Add, add, +);
lane_op!(Sub, sub, -);
lane_op!(Mul, mul, *);
lane_op!(Div, div, /);

impl<const W: usize> Neg for Lanes<W> {
    type Output = Lanes<W>;
    #[inline(always)]
    fn neg(self) -> Lanes<W> {
        Lanes(self.0.map(|a| -a))
    }
}

impl<const W: usize> AddAssign for Lanes<W> {
    #[inline(always)]
    fn add_assign(&mut self, b: Lanes<W>) {
        *self = *self + b;
    }
}

impl<const W: usize> Lane for Lanes<W> {
    const WIDTH: usize = W;
    #[inline(always)]
    fn splat(x: f64) -> Lanes<W> {
        Lanes([x; W])
    }
    #[inline(always)]
    fn from_fn(f: impl FnMut(usize) -> f64) -> Lanes<W> {
        Lanes(std::array::from_fn(f))
    }
    #[inline(always)]
    fn lane(&self, i: usize) -> f64 {
        self.0[i]
    }
    #[inline(always)]
    fn sqrt(self) -> Lanes<W> {
        Lanes(self.0.map(f64::sqrt))
    }
}

impl<const W: usize> AsRef<[f64]> for Lanes<W> {
    #[inline(always)]
    fn as_ref(&self) -> &[f64] {
        &self.0
    }
}

impl<const W: usize> AsRef<[f64; W]> for Lanes<W> {
    #[inline(always)]
    fn as_ref(&self) -> &[f64; W] {
        &self.0
    }
}

/// One number is one lane: code written for a [`Lane`] runs on plain
/// `f64` too, statement for statement the same arithmetic.
impl Lane for f64 {
    const WIDTH: usize = 1;
    #[inline(always)]
    fn splat(x: f64) -> f64 {
        x
    }
    #[inline(always)]
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> f64 {
        f(0)
    }
    #[inline(always)]
    fn lane(&self, i: usize) -> f64 {
        debug_assert_eq!(i, 0);
        *self
    }
    #[inline(always)]
    fn sqrt(self) -> f64 {
        f64::sqrt(self)
    }
}

/// How many elements an evaluation takes at once, and with which
/// instructions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Width {
    /// One element at a time: the scalar kernels.
    One,
    /// Four elements, baseline instructions (two-wide SSE2 on x86-64).
    Four,
    /// Four elements in 256-bit AVX2 registers.
    FourAvx2,
    /// Eight elements in 512-bit AVX-512 registers.
    EightAvx512,
}

impl Width {
    /// Every width, narrowest first.
    pub const ALL: [Width; 4] = [Width::One, Width::Four, Width::FourAvx2, Width::EightAvx512];

    /// The widest this processor runs (checked once per process).
    pub fn detect() -> Width {
        static DETECTED: OnceLock<Width> = OnceLock::new();
        *DETECTED.get_or_init(|| Width::EightAvx512.or_narrower())
    }

    /// This width when the processor runs it, else the widest it runs
    /// with at most as many lanes.
    pub fn or_narrower(self) -> Width {
        if self.is_supported() {
            return self;
        }
        Width::ALL
            .into_iter()
            .rev()
            .find(|w| w.lanes() <= self.lanes() && w.is_supported())
            .unwrap_or(Width::One)
    }

    /// True when this processor has the instructions of the width.
    pub fn is_supported(self) -> bool {
        match self {
            Width::One | Width::Four => true,
            #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
            Width::FourAvx2 => {
                std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
            }
            #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
            Width::EightAvx512 => {
                std::arch::is_x86_feature_detected!("avx512f")
                    && std::arch::is_x86_feature_detected!("avx2")
                    && std::arch::is_x86_feature_detected!("fma")
            }
            #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
            Width::FourAvx2 | Width::EightAvx512 => false,
        }
    }

    /// Elements per evaluation.
    pub fn lanes(self) -> usize {
        match self {
            Width::One => 1,
            Width::Four | Width::FourAvx2 => 4,
            Width::EightAvx512 => 8,
        }
    }

    /// A short name (`scalar`, `4`, `4-avx2`, `8-avx512`).
    pub fn name(self) -> &'static str {
        match self {
            Width::One => "scalar",
            Width::Four => "4",
            Width::FourAvx2 => "4-avx2",
            Width::EightAvx512 => "8-avx512",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_on_lines_sit_on_cache_lines_and_keep_their_values() {
        let values: Vec<Lanes<8>> = (0..37)
            .map(|i| Lanes::from_fn(|l| (8 * i + l) as f64))
            .collect();
        let mut lines = OnLines::from_values(values.iter().copied());
        let mut copy = OnLines::from_elem(Lanes::splat(-1.0), 3);
        copy.clone_from(&lines);
        for v in [&lines, &copy] {
            assert_eq!(**v, values[..]);
            for x in v.iter() {
                assert_eq!(std::ptr::from_ref(x).addr() % 64, 0);
            }
        }
        lines[5] = Lanes::splat(2.0);
        assert_eq!(lines[5], Lanes::splat(2.0));
        assert!(lines != copy);
    }

    #[test]
    fn lane_operations_act_lane_by_lane() {
        let a = Lanes([1.0, -2.0, 3.5, 0.25]);
        let b = Lanes([0.5, 4.0, -1.0, 8.0]);
        let mut s = a;
        s += b;
        for i in 0..4 {
            let (x, y) = (a.0[i], b.0[i]);
            assert_eq!((a + b).lane(i), x + y);
            assert_eq!((a - b).lane(i), x - y);
            assert_eq!((a * b).lane(i), x * y);
            assert_eq!((a / b).lane(i), x / y);
            assert_eq!((-a).lane(i), -x);
            assert_eq!(s.lane(i), x + y);
            assert_eq!((2.0 * a - b * 3.0 + 1.0).lane(i), 2.0 * x - y * 3.0 + 1.0);
            assert_eq!((1.5 / a / 2.0 - 0.5).lane(i), 1.5 / x / 2.0 - 0.5);
            assert_eq!((a * a + 0.5).sqrt().lane(i), (x * x + 0.5).sqrt());
        }
        assert_eq!(Lanes::<4>::splat(2.5), Lanes([2.5; 4]));
        assert_eq!(
            Lanes::<4>::from_fn(|i| i as f64 + 7.0),
            Lanes([7.0, 8.0, 9.0, 10.0])
        );
    }

    #[test]
    fn the_detected_width_is_supported_and_the_baseline_always_is() {
        assert!(Width::detect().is_supported());
        assert_eq!(Width::EightAvx512.or_narrower(), Width::detect());
        for w in Width::ALL {
            let n = w.or_narrower();
            assert!(n.is_supported() && n.lanes() <= w.lanes());
            assert_eq!(n == w, w.is_supported());
        }
        assert!(Width::One.is_supported() && Width::Four.is_supported());
        let lanes: Vec<usize> = Width::ALL.iter().map(|w| w.lanes()).collect();
        assert_eq!(lanes, [1, 4, 4, 8]);
    }
}
