//! The elements' moments packed side by side for one lane width, and the
//! element passes (potentials, gradients, Hessian groups) run on them,
//! several elements per instruction ([`crate::lanes`]), bit for bit the
//! scalar kernels.

use super::Element;
use crate::lanes::{CacheLine, Lane, LaneScalar, Lanes, OnLines, Width};
use crate::model::{Energy, EnergyScalars, ModelCore, Vector};

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
