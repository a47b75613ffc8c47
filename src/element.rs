//! One element of a finger: its integration blocks (docs/model.md section
//! 4.4) folded into the model's moments.
//!
//! The moments depend only on the scene (geometry, materials, prestrain),
//! so they are accumulated once; each Newton iteration then costs one call
//! of the model's energy, whatever the number of laminae, ribs and voids.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use crate::lanes::{CacheLine, Lane, LaneScalar, Lanes, OnLines, Width};
use crate::model::{
    upper_index, Energy, EnergyScalars, GasParams, Kinematics, LinearParams, ModelCore,
    PrestressedParams, Vector,
};

/// The blocks of one element, each in the parameter struct of the model's
/// integral family it feeds (a negative width subtracts a box: the channel
/// from the fluidic layer, a rib from the gas volume). Two elements with
/// equal `ElementBlocks` (compared exactly) have the same energy function.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementBlocks {
    /// Undeformed length L_i.
    pub length: f64,
    /// Plane strain: the model's unknowns across the width are held at
    /// zero (docs/model.md section 4.9).
    pub plane_strain: bool,
    /// CL, regular EMC, whole fluidic layer, then the channel (negative
    /// width), then the ribs (fluidic material) if enabled.
    pub linear: Vec<LinearParams>,
    /// The prestressed layer.
    pub prestressed: Vec<PrestressedParams>,
    /// The channel (positive width), then the ribs (negative width) if
    /// enabled. Empty where the element has no channel.
    pub gas: Vec<GasParams>,
}

/// For each element, the index of the first element with identical
/// blocks (itself if none before it matches). Elements that map to the
/// same index have the same energy and, without tip loads, the same
/// equilibrium, so they can be solved once.
pub(crate) fn distinct_elements(blocks: &[ElementBlocks]) -> Vec<usize> {
    let mut first = Vec::with_capacity(blocks.len());
    for (i, b) in blocks.iter().enumerate() {
        let j = (0..i)
            .find(|&j| first[j] == j && blocks[j] == *b)
            .unwrap_or(i);
        first.push(j);
    }
    first
}

/// An element ready for evaluation with model `M`.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Element<M: ModelCore> {
    length: f64,
    moments: M::Moments,
    /// Plane strain: the stiffness that holds each of the model's unknowns
    /// across the width ([`crate::model::Across`]) at zero, in that order;
    /// empty in plane stress.
    pin: Vec<f64>,
}

impl<M: ModelCore> Element<M> {
    /// Undeformed length `L_i`.
    pub fn length(&self) -> f64 {
        self.length
    }
}

impl<M: Energy> Element<M> {
    /// Folds an element's blocks into moments.
    pub fn from_blocks(b: &ElementBlocks) -> Element<M> {
        let mut moments = M::zero_moments();
        for p in &b.linear {
            M::add_linear(&mut moments, p);
        }
        for p in &b.prestressed {
            M::add_prestressed(&mut moments, p);
        }
        for p in &b.gas {
            M::add_gas(&mut moments, p);
        }
        // plane strain replaces each held unknown's equation by `c k = 0`,
        // with c its own stiffness at rest (the scale of its neighbours,
        // for the solver; 1 if it has none)
        let pin = if b.plane_strain {
            let n = M::Coeffs::LEN;
            let (_, _, h) = M::hessian(&moments, &M::Coeffs::zero(), &EnergyScalars { kp: 0.0 });
            M::ACROSS
                .iter()
                .map(|&i| {
                    let c = h[upper_index(n, i, i)].abs();
                    if c.is_finite() && c > 0.0 {
                        c
                    } else {
                        1.0
                    }
                })
                .collect()
        } else {
            Vec::new()
        };
        Element {
            length: b.length,
            moments,
            pin,
        }
    }

    /// `k` with the unknowns plane strain holds set to zero: the model's
    /// energy sees no strain across the width.
    #[inline]
    fn held(&self, k: &M::Coeffs) -> M::Coeffs {
        let mut k = *k;
        for &i in M::ACROSS {
            k[i] = 0.0;
        }
        k
    }

    /// `sum 1/2 c k_i^2` over the held unknowns (zero at an equilibrium).
    fn pin_energy(&self, k: &M::Coeffs) -> f64 {
        M::ACROSS
            .iter()
            .zip(&self.pin)
            .map(|(&i, &c)| 0.5 * c * k[i] * k[i])
            .sum()
    }

    /// Zeroes the entries of the unknowns plane strain holds (in plane
    /// stress nothing): a right-hand side of the sensitivities, since the
    /// held unknowns do not move with any parameter.
    pub fn hold(&self, g: &mut M::Coeffs) {
        if !self.pin.is_empty() {
            for &i in M::ACROSS {
                g[i] = 0.0;
            }
        }
    }

    /// The element's moments, summed over its blocks.
    pub fn moments(&self) -> &M::Moments {
        &self.moments
    }

    /// The element's potential for the load scalars `s`.
    #[inline]
    pub fn energy(&self, k: &M::Coeffs, s: &EnergyScalars) -> f64 {
        self.finish_energy(k, M::energy(&self.moments, &self.seen(k), s))
    }

    /// The element's potential at `k` from the model's at
    /// [`Element::seen`]`(k)`.
    #[inline]
    fn finish_energy(&self, k: &M::Coeffs, v: f64) -> f64 {
        if self.pin.is_empty() {
            return v;
        }
        v + self.pin_energy(k)
    }

    /// Potential and gradient.
    #[inline]
    pub fn gradient(&self, k: &M::Coeffs, s: &EnergyScalars) -> (f64, M::Coeffs) {
        self.finish_gradient(k, M::gradient(&self.moments, &self.seen(k), s))
    }

    /// The element's potential and gradient at `k` from the model's at
    /// [`Element::seen`]`(k)`.
    #[inline]
    fn finish_gradient(&self, k: &M::Coeffs, (v, mut g): (f64, M::Coeffs)) -> (f64, M::Coeffs) {
        if self.pin.is_empty() {
            return (v, g);
        }
        for (&i, &c) in M::ACROSS.iter().zip(&self.pin) {
            g[i] = c * k[i];
        }
        (v + self.pin_energy(k), g)
    }

    /// Potential, gradient and Hessian (upper triangle).
    #[inline]
    pub fn hessian(&self, k: &M::Coeffs, s: &EnergyScalars) -> (f64, M::Coeffs, M::Upper) {
        self.finish_hessian(k, M::hessian(&self.moments, &self.seen(k), s))
    }

    /// The unknowns the model's energy sees: `k`, with the unknowns plane
    /// strain holds set to zero.
    #[inline]
    fn seen(&self, k: &M::Coeffs) -> M::Coeffs {
        if self.pin.is_empty() {
            *k
        } else {
            self.held(k)
        }
    }

    /// The element's potential, gradient and Hessian at `k` from the
    /// model's at [`Element::seen`]`(k)`: the held unknowns' pins added.
    #[inline]
    fn finish_hessian(
        &self,
        k: &M::Coeffs,
        (v, mut g, mut h): (f64, M::Coeffs, M::Upper),
    ) -> (f64, M::Coeffs, M::Upper) {
        if self.pin.is_empty() {
            return (v, g, h);
        }
        let n = M::Coeffs::LEN;
        for (&i, &c) in M::ACROSS.iter().zip(&self.pin) {
            g[i] = c * k[i];
            for j in 0..n {
                h[upper_index(n, i, j)] = 0.0;
            }
            h[upper_index(n, i, i)] = c;
        }
        (v + self.pin_energy(k), g, h)
    }

    /// One integral family alone.
    pub fn family_hessian(
        &self,
        family: usize,
        k: &M::Coeffs,
    ) -> Option<(f64, M::Coeffs, M::Upper)> {
        if self.pin.is_empty() {
            return M::family_hessian(&self.moments, family, k);
        }
        // the family alone, with the width held: no entries for the held
        // unknowns
        let (v, mut g, mut h) = M::family_hessian(&self.moments, family, &self.held(k))?;
        let n = M::Coeffs::LEN;
        for &i in M::ACROSS {
            g[i] = 0.0;
            for j in 0..n {
                h[upper_index(n, i, j)] = 0.0;
            }
        }
        Some((v, g, h))
    }
}

impl<M: Kinematics> Element<M> {
    /// End point and slope `[Xe, Ze, eta]` in the element frame.
    #[inline]
    pub fn end(&self, k: &M::Coeffs) -> [f64; 3] {
        M::end(k, self.length)
    }

    /// End point and slope with their gradients.
    #[inline]
    pub fn end_gradient(&self, k: &M::Coeffs) -> ([f64; 3], [M::Coeffs; 3]) {
        M::end_gradient(k, self.length)
    }

    /// The gradients and Hessians of the end point and slope (no values).
    #[inline]
    #[allow(clippy::type_complexity)]
    pub fn end_derivatives(&self, k: &M::Coeffs) -> ([M::Coeffs; 3], [M::Upper; 3]) {
        M::end_derivatives(k, self.length)
    }

    /// End point and the end tangent's direction `[Xe, Ze, cos eta, sin eta]`
    /// without trigonometric calls.
    #[inline]
    pub fn frame(&self, k: &M::Coeffs) -> [f64; 4] {
        let [xe, ze, dx, dz] = M::frame(k, self.length);
        // the tangent is of order 1: no overflow for hypot to guard against
        // (selects, not branches: the validity scan runs this in lanes)
        let r = (dx * dx + dz * dz).sqrt();
        let inv = 1.0 / r;
        let some = r > 0.0;
        [
            xe,
            ze,
            if some { dx * inv } else { 1.0 },
            if some { dz * inv } else { 0.0 },
        ]
    }
}

/// Element `i`'s raw unknowns from the flat unknowns `k` of a finger.
#[inline]
pub(crate) fn coeffs<M: ModelCore>(k: &[f64], i: usize) -> M::Coeffs {
    let n = M::Coeffs::LEN;
    M::Coeffs::from_fn(|j| k[n * i + j])
}

/// Each element's frame at its root: its position and (cos, sin) of its
/// angle, for the raw unknowns `k` of the chain of `elements` ([`walk`]).
pub(crate) fn frames<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
) -> Vec<([f64; 2], [f64; 2])> {
    let mut out = Vec::with_capacity(elements.len());
    walk(
        elements,
        |i| coeffs::<M>(k, i),
        |_, root, rot, _| out.push((root, rot)),
    );
    out
}

/// The chain of `elements` from the clamp to the tip, element `i` at its
/// unknowns `k(i)` (raw): calls `visit(i, root, rotation, end)` with the
/// element's root point, its root frame's `[cos, sin]` and its end point
/// (finger frame), and returns the tip. Chained by rotation, without
/// trigonometric calls.
#[inline(always)]
pub(crate) fn walk<M: Kinematics>(
    elements: &[Element<M>],
    k: impl Fn(usize) -> M::Coeffs,
    mut visit: impl FnMut(usize, [f64; 2], [f64; 2], [f64; 2]),
) -> [f64; 2] {
    let mut w = Walk::new();
    for (i, e) in elements.iter().enumerate() {
        let (root, rot) = (w.tip, w.rot);
        w.step(e.frame(&k(i)));
        visit(i, root, rot, w.tip);
    }
    w.tip
}

/// A walk along a chain of elements from the clamp: the point and the
/// rotation `[cos, sin]` reached so far, chained element by element from
/// each element's [`Element::frame`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct Walk {
    /// The point reached (finger frame): the next element's root.
    pub tip: [f64; 2],
    /// The next element's root frame.
    pub rot: [f64; 2],
}

impl Walk {
    /// At the clamp.
    pub fn new() -> Walk {
        Walk {
            tip: [0.0, 0.0],
            rot: [1.0, 0.0],
        }
    }

    /// Past one element of frame `[Xe, Ze, cos eta, sin eta]`.
    #[inline(always)]
    pub fn step(&mut self, [xe, ze, ce, se]: [f64; 4]) {
        let [c, s] = self.rot;
        self.tip[0] += c * xe - s * ze;
        self.tip[1] += s * xe + c * ze;
        self.rot = [c * ce - s * se, s * ce + c * se];
    }

    /// The angle (rad) of the tangent at the walk's end, given the sum of
    /// the elements' [`approx_atan2`] of their turns: the one `atan2` of
    /// the chained rotation, on the branch nearest that sum; NaN if a turn
    /// was NaN. It is the sum of the elements' exact `atan2` within the
    /// rounding of the rotations, at the cost of one `atan2` per finger
    /// instead of one per element.
    pub fn end_angle(&self, approx: f64) -> f64 {
        let [c, s] = self.rot;
        let a = s.atan2(c);
        a + TAU * ((approx - a) / TAU).round()
    }
}

/// How far (rad) a sum of `n` [`approx_atan2`] may lie from the sum of
/// the exact ones (the rounding of the sum included).
pub(crate) fn approx_slack(n: usize) -> f64 {
    n as f64 * APPROX_ATAN2_ERROR * 1.01
}

/// The largest error (rad) of [`approx_atan2`], with a margin of at least
/// 10 over the largest error seen on a dense sweep (tested below).
pub(crate) const APPROX_ATAN2_ERROR: f64 = 1e-6;

/// `atan2(y, x)` to within [`APPROX_ATAN2_ERROR`], on the same branch
/// (`(-pi, pi]`, the sign from `y`'s sign bit as `atan2` takes it), NaN
/// for NaN; a polynomial in the ratio of the smaller component to the
/// larger (Abramowitz and Stegun 4.4.49, error 2e-8 on `[0, 1]`).
#[inline(always)]
pub(crate) fn approx_atan2(y: f64, x: f64) -> f64 {
    // (selects, not branches: the scan runs this in vector lanes)
    let (ax, ay) = (x.abs(), y.abs());
    let steep = ay > ax;
    let (num, den) = if steep { (ax, ay) } else { (ay, ax) };
    // atan2(+-0, +-0) is +-0 or +-pi: the ratio taken as 0
    let t = if den == 0.0 { 0.0 } else { num / den };
    let t2 = t * t;
    let p = [
        -0.333_331_452_8,
        0.199_935_508_5,
        -0.142_088_994_4,
        0.106_562_639_3,
        -0.075_289_640_0,
        0.042_909_613_8,
        -0.016_165_736_7,
        0.002_866_225_7,
    ];
    let a = t + t * t2 * p.iter().rev().fold(0.0, |acc, &c| acc * t2 + c);
    let a = if steep { FRAC_PI_2 - a } else { a };
    let a = if x.is_sign_negative() { PI - a } else { a };
    if y.is_sign_negative() {
        -a
    } else {
        a
    }
}

/// The tip and the end tangent's angle (rad) of the chain of `elements`
/// at raw unknowns `k` ([`Walk`]).
pub(crate) fn tip_and_end_angle<M: Kinematics>(
    elements: &[Element<M>],
    k: &[f64],
) -> ([f64; 2], f64) {
    let mut w = Walk::new();
    let mut approx = 0.0;
    for (i, e) in elements.iter().enumerate() {
        let f = e.frame(&coeffs::<M>(k, i));
        approx += approx_atan2(f[3], f[2]);
        w.step(f);
    }
    (w.tip, w.end_angle(approx))
}

/// What an element pass evaluates ([`Value`], [`Gradient`]; the Hessians
/// go by [`ElementLanes::hessian_groups`]):
/// the scalar path, the lanes, and what the held unknowns of plane strain
/// add to the model's result.
pub(crate) trait Pass<M: Energy> {
    /// One element's result.
    type Out: Copy;
    /// The model's result at `k` (the unknowns it sees), lane by lane.
    fn lanes<L: Lane>(
        m: &M::MomentLanes<L>,
        k: &[M::Coeffs],
        s: &EnergyScalars,
        out: &mut [Self::Out],
    ) where
        f64: LaneScalar<L>;
    /// One element's result, the scalar way.
    fn element(e: &Element<M>, k: &M::Coeffs, s: &EnergyScalars) -> Self::Out;
    /// The element's result at `k` from the model's.
    fn finish(e: &Element<M>, k: &M::Coeffs, out: Self::Out) -> Self::Out;
}

/// The element potentials ([`Element::energy`]).
pub(crate) struct Value;
/// The potentials and gradients ([`Element::gradient`]).
pub(crate) struct Gradient;

/// `pass!(Pass, its output, lane method, element method, finishing method)`.
macro_rules! pass {
    ($pass:ident, $out:ty, $lanes:ident, $element:ident, $finish:ident) => {
        impl<M: Energy> Pass<M> for $pass {
            type Out = $out;
            #[inline(always)]
            fn lanes<L: Lane>(
                m: &M::MomentLanes<L>,
                k: &[M::Coeffs],
                s: &EnergyScalars,
                out: &mut [Self::Out],
            ) where
                f64: LaneScalar<L>,
            {
                M::$lanes(m, k, s, out)
            }
            #[inline(always)]
            fn element(e: &Element<M>, k: &M::Coeffs, s: &EnergyScalars) -> Self::Out {
                e.$element(k, s)
            }
            #[inline(always)]
            fn finish(e: &Element<M>, k: &M::Coeffs, out: Self::Out) -> Self::Out {
                e.$finish(k, out)
            }
        }
    };
}

pass!(Value, f64, energy_lanes, energy, finish_energy);
pass!(
    Gradient,
    (f64, M::Coeffs),
    gradient_lanes,
    gradient,
    finish_gradient
);

/// The elements' moments packed side by side for one [`Width`]: the
/// potentials, gradients and Hessians of a whole finger, several elements
/// per instruction ([`crate::lanes`]). Built once with the finger.
#[derive(Debug, Clone)]
pub(crate) enum ElementLanes<M: Energy> {
    /// One element at a time.
    One,
    /// Four at a time; `true` with AVX2.
    Four(Vec<CacheLine<M::MomentLanes<Lanes<4>>>>, bool),
    /// Eight at a time, with AVX-512.
    Eight(Vec<CacheLine<M::MomentLanes<Lanes<8>>>>),
}

/// Up to this many elements per lane evaluation.
const MAX_LANES: usize = 8;

impl<M: Energy> ElementLanes<M> {
    /// The moments of `elements` packed for `width`, or for the widest
    /// width below it this processor runs.
    pub fn new(elements: &[Element<M>], width: Width) -> ElementLanes<M> {
        fn pack<M: Energy, L: Lane>(elements: &[Element<M>]) -> Vec<CacheLine<M::MomentLanes<L>>> {
            elements
                .chunks(L::WIDTH)
                .map(|c| {
                    let m: Vec<&M::Moments> = c.iter().map(|e| &e.moments).collect();
                    CacheLine(M::moment_lanes::<L>(&m))
                })
                .collect()
        }
        match width.or_narrower() {
            Width::One => ElementLanes::One,
            Width::Four => ElementLanes::Four(pack::<M, Lanes<4>>(elements), false),
            Width::FourAvx2 => ElementLanes::Four(pack::<M, Lanes<4>>(elements), true),
            Width::EightAvx512 => ElementLanes::Eight(pack::<M, Lanes<8>>(elements)),
        }
    }

    /// The width the moments are packed for.
    pub fn width(&self) -> Width {
        match self {
            ElementLanes::One => Width::One,
            ElementLanes::Four(_, false) => Width::Four,
            ElementLanes::Four(_, true) => Width::FourAvx2,
            ElementLanes::Eight(_) => Width::EightAvx512,
        }
    }

    /// Pass `P` ([`Value`], [`Gradient`]) of every element of
    /// `elements` (the ones packed) at `k[i]` into `out[i]`, bit for bit
    /// the scalar [`Element::energy`] or [`Element::gradient`].
    pub fn eval<P: Pass<M>>(
        &self,
        elements: &[Element<M>],
        k: &[M::Coeffs],
        s: &EnergyScalars,
        out: &mut [P::Out],
    ) {
        match self {
            ElementLanes::One => {
                for ((o, e), k) in out.iter_mut().zip(elements).zip(k) {
                    *o = P::element(e, k, s);
                }
            }
            #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
            // SAFETY: packed with AVX2 only where the processor has it
            // (`Width::is_supported`)
            ElementLanes::Four(p, true) => unsafe { eval_avx2::<M, P>(p, elements, k, s, out) },
            ElementLanes::Four(p, _) => eval_in::<M, P, Lanes<4>>(p, elements, k, s, out),
            #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
            // SAFETY: packed for AVX-512 only where the processor has it
            ElementLanes::Eight(p) => unsafe { eval_avx512::<M, P>(p, elements, k, s, out) },
            #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
            ElementLanes::Eight(p) => eval_in::<M, P, Lanes<8>>(p, elements, k, s, out),
        }
    }
}

/// Pass `P` of every element, `L::WIDTH` at a time (inlined into the
/// functions compiled for a width's instructions).
#[inline(always)]
fn eval_in<M: Energy, P: Pass<M>, L: Lane>(
    packed: &[CacheLine<M::MomentLanes<L>>],
    elements: &[Element<M>],
    k: &[M::Coeffs],
    s: &EnergyScalars,
    out: &mut [P::Out],
) where
    f64: LaneScalar<L>,
{
    let mut seen = [M::Coeffs::zero(); MAX_LANES];
    for (((m, e), k), o) in packed
        .iter()
        .zip(elements.chunks(L::WIDTH))
        .zip(k.chunks(L::WIDTH))
        .zip(out.chunks_mut(L::WIDTH))
    {
        for ((sk, e), k) in seen.iter_mut().zip(e).zip(k) {
            *sk = e.seen(k);
        }
        P::lanes::<L>(&m.0, &seen[..k.len()], s, o);
        for ((o, e), k) in o.iter_mut().zip(e).zip(k) {
            *o = P::finish(e, k, *o);
        }
    }
}

#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
#[target_feature(enable = "avx2,fma")]
fn eval_avx2<M: Energy, P: Pass<M>>(
    packed: &[CacheLine<M::MomentLanes<Lanes<4>>>],
    elements: &[Element<M>],
    k: &[M::Coeffs],
    s: &EnergyScalars,
    out: &mut [P::Out],
) {
    eval_in::<M, P, Lanes<4>>(packed, elements, k, s, out)
}

#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
#[target_feature(enable = "avx512f,avx2,fma")]
fn eval_avx512<M: Energy, P: Pass<M>>(
    packed: &[CacheLine<M::MomentLanes<Lanes<8>>>],
    elements: &[Element<M>],
    k: &[M::Coeffs],
    s: &EnergyScalars,
    out: &mut [P::Out],
) {
    eval_in::<M, P, Lanes<8>>(packed, elements, k, s, out)
}

/// One number per element of a group of [`fpc_newton::GROUP`] elements:
/// the lane type of the chain's Hessian assembly (the group the chain's
/// matrix stores side by side).
pub(crate) type Group = Lanes<{ fpc_newton::GROUP }>;

/// Per-element numbers in groups: entry `e` of `row(i)` for element `i =
/// GROUP j + l` is lane `l` of `out[per j + e]` (`per` entries a group),
/// the lanes past the last of `count` elements repeating it. For what does
/// not change between evaluations (the scales, the lengths), packed once.
pub(crate) fn pack<'v>(
    count: usize,
    per: usize,
    row: impl Fn(usize) -> &'v [f64],
) -> OnLines<Group> {
    let w = fpc_newton::GROUP;
    OnLines::from_values((0..count.div_ceil(w)).flat_map(|j| {
        let row = &row;
        (0..per).map(move |e| Group::from_fn(|l| row((w * j + l).min(count - 1))[e]))
    }))
}

/// The element Hessians of a finger in groups of [`Group`] lanes, element
/// `GROUP j + l` in lane `l` of group `j`: its potential, its gradient
/// (`LEN` lanes a group) and its Hessian's upper triangle (`LEN (LEN + 1)
/// / 2` lanes a group). The lanes past the last element repeat it.
#[derive(Debug, Default, PartialEq)]
pub(crate) struct HessianGroups {
    pub v: OnLines<Group>,
    pub g: OnLines<Group>,
    pub h: OnLines<Group>,
}

impl Clone for HessianGroups {
    fn clone(&self) -> HessianGroups {
        HessianGroups {
            v: self.v.clone(),
            g: self.g.clone(),
            h: self.h.clone(),
        }
    }

    /// Reuses `self`'s allocations (the start memo's copies).
    fn clone_from(&mut self, source: &HessianGroups) {
        self.v.clone_from(&source.v);
        self.g.clone_from(&source.g);
        self.h.clone_from(&source.h);
    }
}

impl HessianGroups {
    /// Room for `elements` elements of model `M`.
    pub fn new<M: ModelCore>(elements: usize) -> HessianGroups {
        let (n, groups) = (M::Coeffs::LEN, elements.div_ceil(fpc_newton::GROUP));
        let zero = Group::splat(0.0);
        HessianGroups {
            v: OnLines::from_elem(zero, groups),
            g: OnLines::from_elem(zero, groups * n),
            h: OnLines::from_elem(zero, groups * n * (n + 1) / 2),
        }
    }
}

impl<M: Energy> ElementLanes<M> {
    /// The Hessian pass ([`Element::hessian`]) of every element in groups
    /// ([`HessianGroups`]), bit for bit the scalar results, computed at
    /// this packing's width.
    pub fn hessian_groups(
        &self,
        elements: &[Element<M>],
        k: &[M::Coeffs],
        s: &EnergyScalars,
        out: &mut HessianGroups,
    ) {
        match self {
            ElementLanes::One => {
                let (n, nh) = (M::Coeffs::LEN, M::Upper::LEN);
                for (i, (e, k)) in elements.iter().zip(k).enumerate() {
                    let (j, l) = (i / fpc_newton::GROUP, i % fpc_newton::GROUP);
                    let (v, g, h) = e.hessian(k, s);
                    out.v[j].0[l] = v;
                    for (o, x) in out.g[j * n..].iter_mut().zip(g.as_ref()) {
                        o.0[l] = *x;
                    }
                    for (o, x) in out.h[j * nh..].iter_mut().zip(h.as_ref()) {
                        o.0[l] = *x;
                    }
                }
                pad_groups::<M>(elements.len(), out);
            }
            #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
            // SAFETY: packed with AVX2 only where the processor has it
            ElementLanes::Four(p, true) => unsafe { groups_avx2(p, elements, k, s, out) },
            ElementLanes::Four(p, _) => groups_in::<M, Lanes<4>>(p, elements, k, s, out),
            #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
            // SAFETY: packed for AVX-512 only where the processor has it
            ElementLanes::Eight(p) => unsafe { groups_avx512(p, elements, k, s, out) },
            #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
            ElementLanes::Eight(p) => groups_in::<M, Lanes<8>>(p, elements, k, s, out),
        }
    }
}

/// The lanes past the last element repeat it (the scalar path fills
/// element by element).
fn pad_groups<M: ModelCore>(elements: usize, out: &mut HessianGroups) {
    let (n, nh, w) = (M::Coeffs::LEN, M::Upper::LEN, fpc_newton::GROUP);
    let Some(last) = elements.checked_sub(1) else {
        return;
    };
    let (j, from) = (last / w, last % w);
    let fill = |x: &mut Group| {
        for l in from + 1..w {
            x.0[l] = x.0[from];
        }
    };
    fill(&mut out.v[j]);
    out.g[j * n..(j + 1) * n].iter_mut().for_each(fill);
    out.h[j * nh..(j + 1) * nh].iter_mut().for_each(fill);
}

/// [`ElementLanes::hessian_groups`] `L::WIDTH` elements at a time (a
/// divisor of the group), inlined into the functions compiled for a
/// width's instructions.
#[inline(always)]
fn groups_in<M: Energy, L: Lane + AsRef<[f64]>>(
    packed: &[CacheLine<M::MomentLanes<L>>],
    elements: &[Element<M>],
    k: &[M::Coeffs],
    s: &EnergyScalars,
    out: &mut HessianGroups,
) where
    f64: LaneScalar<L>,
{
    let (n, nh, w) = (M::Coeffs::LEN, M::Upper::LEN, L::WIDTH);
    let per = fpc_newton::GROUP / w;
    let mut seen = [M::Coeffs::zero(); MAX_LANES];
    for (c, ((m, e), k)) in packed
        .iter()
        .zip(elements.chunks(w))
        .zip(k.chunks(w))
        .enumerate()
    {
        for ((sk, e), k) in seen.iter_mut().zip(e).zip(k) {
            *sk = e.seen(k);
        }
        let (j, at) = (c / per, (c % per) * w);
        let put = |o: &mut Group, x: &L| {
            for (o, x) in o.0[at..at + w].iter_mut().zip(x.as_ref()) {
                *o = *x;
            }
        };
        let taken = M::hessian_lane_major::<L>(&m.0, &seen[..k.len()], s, |v, g, h| {
            put(&mut out.v[j], v);
            out.g[j * n..]
                .iter_mut()
                .zip(g)
                .for_each(|(o, x)| put(o, x));
            out.h[j * nh..]
                .iter_mut()
                .zip(h)
                .for_each(|(o, x)| put(o, x));
        });
        if !taken {
            continue;
        }
        // the held unknowns of plane strain, element by element
        for (l, (e, k)) in e.iter().zip(k).enumerate() {
            if !e.pin.is_empty() {
                pin_lane(e, k, at + l, j, out);
            }
        }
    }
    pad_groups::<M>(elements.len(), out);
}

/// [`Element::finish_hessian`] on element `e`'s lane `l` of group `j`.
fn pin_lane<M: Energy>(e: &Element<M>, k: &M::Coeffs, l: usize, j: usize, out: &mut HessianGroups) {
    let (n, nh) = (M::Coeffs::LEN, M::Upper::LEN);
    let (g, h) = (
        &mut out.g[j * n..(j + 1) * n],
        &mut out.h[j * nh..(j + 1) * nh],
    );
    let model = (
        out.v[j].0[l],
        M::Coeffs::from_fn(|a| g[a].0[l]),
        M::Upper::from_fn(|a| h[a].0[l]),
    );
    let (v, gk, hk) = e.finish_hessian(k, model);
    out.v[j].0[l] = v;
    g.iter_mut().zip(gk.as_ref()).for_each(|(o, x)| o.0[l] = *x);
    h.iter_mut().zip(hk.as_ref()).for_each(|(o, x)| o.0[l] = *x);
}

#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
#[target_feature(enable = "avx2,fma")]
fn groups_avx2<M: Energy>(
    packed: &[CacheLine<M::MomentLanes<Lanes<4>>>],
    elements: &[Element<M>],
    k: &[M::Coeffs],
    s: &EnergyScalars,
    out: &mut HessianGroups,
) {
    groups_in::<M, Lanes<4>>(packed, elements, k, s, out)
}

#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
#[target_feature(enable = "avx512f,avx2,fma")]
fn groups_avx512<M: Energy>(
    packed: &[CacheLine<M::MomentLanes<Lanes<8>>>],
    elements: &[Element<M>],
    k: &[M::Coeffs],
    s: &EnergyScalars,
    out: &mut HessianGroups,
) {
    groups_in::<M, Lanes<8>>(packed, elements, k, s, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `approx_atan2` stays within a tenth of the bound it claims of the
    /// library's `atan2` on a dense sweep of directions and magnitudes,
    /// and on the axes and signed zeros it takes `atan2`'s branch (an
    /// answer 2 pi off would send the chain's angle to another branch).
    #[test]
    fn the_approximate_atan2_keeps_its_bound_and_branch() {
        let mut worst = 0.0f64;
        let n = 400_000;
        for j in 0..=n {
            let phi = -PI + 2.0 * PI * j as f64 / n as f64;
            for r in [1e-300, 1e-3, 1.0, 7.5, 1e200] {
                let (y, x) = (r * phi.sin(), r * phi.cos());
                worst = worst.max((approx_atan2(y, x) - y.atan2(x)).abs());
            }
        }
        assert!(worst <= APPROX_ATAN2_ERROR / 10.0, "{worst}");
        for (y, x) in [
            (0.0, 1.0),
            (-0.0, 1.0),
            (0.0, -1.0),
            (-0.0, -1.0),
            (1.0, 0.0),
            (-1.0, 0.0),
            (1.0, -0.0),
            (-1.0, -0.0),
            (1e-310, -3.0),
            (-1e-310, -3.0),
        ] {
            let (got, want) = (approx_atan2(y, x), f64::atan2(y, x));
            assert!((got - want).abs() <= 1e-5, "({y}, {x}): {got} vs {want}");
        }
        assert!(approx_atan2(f64::NAN, 1.0).is_nan() && approx_atan2(1.0, f64::NAN).is_nan());
    }

    /// The walk's end angle from one `atan2` is the sum of the turns'
    /// `atan2` within rounding, for random chains of 1 to 1000 turns of
    /// every size up to a half turn (sums far past one revolution), and
    /// the approximate sum keeps within its slack of it.
    #[test]
    fn the_walks_end_angle_is_the_sum_of_the_turns() {
        let mut rng = fastrand::Rng::with_seed(23);
        let mut beyond = 0;
        for case in 0..2000 {
            let n = 1 + rng.usize(0..1000) * (case % 2) + rng.usize(0..8);
            let size = [1e-6, 0.05, 0.5, 3.1, PI][case % 5];
            let bias = (rng.f64() - 0.5) * size;
            let mut walk = Walk::new();
            let (mut sum, mut approx) = (0.0, 0.0);
            for i in 0..n {
                let phi = (bias + (rng.f64() - 0.5) * size).clamp(-PI, PI);
                let (c, s) = (phi.cos(), phi.sin());
                sum += s.atan2(c);
                approx += approx_atan2(s, c);
                walk.step([1.0, 0.0, c, s]);
                assert!((approx - sum).abs() <= approx_slack(i + 1), "case {case}");
            }
            let got = walk.end_angle(approx);
            assert!(
                (got - sum).abs() <= 1e-13 * n as f64 * sum.abs().max(1.0),
                "case {case}: {got} vs {sum}"
            );
            beyond += usize::from(sum.abs() > 2.0 * PI);
        }
        assert!(beyond > 200, "{beyond}");
        assert_eq!(Walk::new().end_angle(0.0), 0.0);
        let mut nan = Walk::new();
        nan.step([1.0, 0.0, f64::NAN, 0.0]);
        assert!(nan.end_angle(approx_atan2(0.0, f64::NAN)).is_nan());
    }
}
