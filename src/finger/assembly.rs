//! The chain's Hessian assembled a group of elements at a time.
//!
//! After the element pass every element's block of the chain's Hessian
//! takes the tip load's terms (the module docs of src/finger/chain.rs),
//! the scales of the unknowns and, where Newton's unknowns are
//! straightened, their change of variables (src/finger/straighten.rs).
//! That is the same arithmetic for every element, so it runs on lanes of
//! [`GROUP`] elements ([`Group`]): the element pass leaves its Hessians in
//! such groups ([`HessianGroups`]), the end kinematics' derivatives are
//! computed in them (the generator's `end_derivatives_lanes`), and the
//! blocks and coupling vectors go into fpc-newton's [`Semiseparable`],
//! which stores the same groups side by side, with no transposition
//! ([`Semiseparable::set_group`]). The scales and lengths are packed in
//! groups once per finger; only Newton's state, the elements' unknowns and
//! the frames are read element by element, and the gradient is written
//! so.
//!
//! Each lane is statement for statement its element's arithmetic (nothing
//! fused or reordered), so the matrix and the gradient are bit for bit
//! those of an assembly element by element. The lanes are compiled for
//! AVX-512 or AVX2 where the element pass runs with them ([`Width`],
//! chosen at run time), and for the baseline instruction set otherwise.

use fpc_newton::{Semiseparable, GROUP};

use crate::element::packed::{Group, HessianGroups};
use crate::lanes::{Lane, Lanes, OnLines, Width};
use crate::model::{upper_index, ElementModel, Vector};

use super::straighten;

/// What the assembly reads besides Newton's unknowns.
pub(crate) struct Terms<'a, M: ElementModel> {
    /// The element pass.
    pub groups: &'a HessianGroups,
    /// The elements' raw unknowns.
    pub k: &'a [M::Coeffs],
    /// The unknowns' scales (raw = scale times scaled) and the elements'
    /// lengths, in groups (`FingerCore::unscale_groups`, `length_groups`).
    pub unscale: &'a [Group],
    pub lengths: &'a [Group],
    /// The tip load's terms; `None` without a tip load (no coupling).
    pub load: Option<LoadTerms<'a>>,
    /// Newton's unknowns are straightened.
    pub straight: bool,
}

/// The tip load and each element's frame.
pub(crate) struct LoadTerms<'a> {
    /// The tip force `(Fx, Fz)`.
    pub force: [f64; 2],
    /// `(cos, sin)` of the element frame's angle.
    pub rot: &'a [[f64; 2]],
    /// The vector from the element's end to the tip.
    pub q: &'a [[f64; 2]],
}

/// Adds the tip load's terms to the element gradients, scales them and
/// carries them to Newton's unknowns at `y` into `g`, and fills `h` with
/// the blocks and coupling vectors (the coupling is left alone without a
/// tip load: the caller clears it). `width` is the element pass's.
pub(crate) fn assemble<M: ElementModel>(
    terms: &Terms<M>,
    y: &[f64],
    g: &mut [f64],
    h: &mut Semiseparable,
    width: Width,
    work: &mut Work,
) {
    match width {
        #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
        // SAFETY: the element pass runs at a width only where the
        // processor has its instructions (`Width::or_narrower`)
        Width::EightAvx512 => unsafe { assemble_avx512(terms, y, g, h, work) },
        #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
        // SAFETY: as above
        Width::FourAvx2 => unsafe { assemble_avx2(terms, y, g, h, work) },
        _ => assemble_in(terms, y, g, h, work),
    }
}

#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
#[target_feature(enable = "avx512f,avx2,fma")]
fn assemble_avx512<M: ElementModel>(
    terms: &Terms<M>,
    y: &[f64],
    g: &mut [f64],
    h: &mut Semiseparable,
    work: &mut Work,
) {
    assemble_in(terms, y, g, h, work)
}

#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
#[target_feature(enable = "avx2,fma")]
fn assemble_avx2<M: ElementModel>(
    terms: &Terms<M>,
    y: &[f64],
    g: &mut [f64],
    h: &mut Semiseparable,
    work: &mut Work,
) {
    assemble_in(terms, y, g, h, work)
}

/// Lane `l` of `out[e]` is entry `e` of `row(at[l])`, for every entry `e`
/// of `out`.
#[inline(always)]
fn gather<'v>(out: &mut [Group], at: &[usize; GROUP], row: impl Fn(usize) -> &'v [f64]) {
    let mut rows: [&[f64]; GROUP] = [&[]; GROUP];
    for l in 0..GROUP {
        rows[l] = row(at[l]);
    }
    for (e, o) in out.iter_mut().enumerate() {
        let mut v = [0.0; GROUP];
        for l in 0..GROUP {
            v[l] = rows[l][e];
        }
        *o = Lanes(v);
    }
}

/// `dst` from the start of `src`, lane vector by lane vector (a call of
/// `memmove` otherwise).
#[inline(always)]
fn copy(dst: &mut [Group], src: &[Group]) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d = *s;
    }
}

#[inline(always)]
fn assemble_in<M: ElementModel>(
    terms: &Terms<M>,
    y: &[f64],
    g: &mut [f64],
    h: &mut Semiseparable,
    work: &mut Work,
) {
    let n = M::Coeffs::LEN;
    let nh = M::Upper::LEN;
    let count_all = terms.k.len();
    let straight = terms.straight;
    let [yl, gl, kl, u, w, eg, blk, eh, full] = work.split(Work::runs(n));
    for group in 0..count_all.div_ceil(GROUP) {
        let first = group * GROUP;
        let count = GROUP.min(count_all - first);
        // lane l is element first + l; the lanes past the last element
        // repeat it (their results are not stored)
        let mut at = [0; GROUP];
        for (l, a) in at.iter_mut().enumerate() {
            *a = first + l.min(count - 1);
        }
        let s = &terms.unscale[group * n..(group + 1) * n];
        gather(yl, &at, |j| &y[n * j..n * j + n]);
        copy(gl, &terms.groups.g[group * n..]);
        copy(blk, &terms.groups.h[group * nh..]);
        if let Some(load) = &terms.load {
            let [fx, fz] = load.force;
            gather(kl, &at, |j| terms.k[j].as_ref());
            let length = terms.lengths[group];
            M::end_derivatives_lanes::<Group>(kl, length, eg, eh);
            let (eg0, eg1, eg2) = (&eg[..n], &eg[n..2 * n], &eg[2 * n..]);
            let (eh0, eh1, eh2) = (&eh[..nh], &eh[nh..2 * nh], &eh[2 * nh..]);
            let pair = |f: &dyn Fn(usize) -> [f64; 2]| {
                let (mut a, mut b) = ([0.0; GROUP], [0.0; GROUP]);
                for l in 0..GROUP {
                    [a[l], b[l]] = f(at[l]);
                }
                (Lanes(a), Lanes(b))
            };
            let (cs, sn) = pair(&|j| load.rot[j]);
            let (q0, q1) = pair(&|j| load.q[j]);
            let fr = [cs * fx + sn * fz, -sn * fx + cs * fz];
            let fjq = -fx * q1 + fz * q0; // F . J Q_j
            let fq = fx * q0 + fz * q1; // F . Q_j
            for a in 0..n {
                gl[a] = gl[a] - (fr[0] * eg0[a] + fr[1] * eg1[a] + fjq * eg2[a]);
                for b in a..n {
                    let ab = upper_index(n, a, b);
                    blk[ab] = blk[ab]
                        - (fr[0] * eh0[ab] + fr[1] * eh1[ab] + fjq * eh2[ab]
                            - fq * eg2[a] * eg2[b]);
                }
            }
            // scaled coupling vectors: u_j = grad eta_j, and
            // w_j = (J^T Fr_j) . De_j - (F . Q_j) grad eta_j, J^T Fr = (Fr_z, -Fr_x)
            for a in 0..n {
                u[a] = eg2[a] * s[a];
                w[a] = (fr[1] * eg0[a] - fr[0] * eg1[a] - fq * eg2[a]) * s[a];
            }
        }
        for a in 0..n {
            gl[a] = gl[a] * s[a];
        }
        straighten::newton_block::<M, Group>(blk, s, yl, gl, straight, full);
        if terms.load.is_some() && straight {
            straighten::pull_back::<M, Group>(yl, u);
            straighten::pull_back::<M, Group>(yl, w);
        }
        let coupling = terms.load.is_some().then_some((&u[..], &w[..]));
        h.set_group(group, full, coupling);
        if straight {
            straighten::pull_back::<M, Group>(yl, gl);
        }
        for l in 0..count {
            for (a, gla) in gl.iter().enumerate() {
                g[n * (first + l) + a] = gla.0[l];
            }
        }
    }
}

/// The assembly's lanes, kept between evaluations (nothing to initialise
/// per evaluation).
#[derive(Debug, Clone)]
pub(crate) struct Work(OnLines<Group>);

impl Work {
    /// The assembly's runs of lanes for elements of `n` unknowns: the
    /// state, gradient, unknowns and the two coupling vectors (`n` each),
    /// the end's gradients (`3 n`), the block's upper triangle, the end's
    /// Hessians (three upper triangles) and the full block (`n^2`).
    #[inline(always)]
    fn runs(n: usize) -> [usize; 9] {
        let nh = n * (n + 1) / 2;
        [n, n, n, n, n, 3 * n, nh, 3 * nh, n * n]
    }

    /// Lanes for elements of `n` unknowns.
    pub fn new(n: usize) -> Work {
        let len = Work::runs(n).iter().sum();
        Work(OnLines::from_elem(Group::splat(0.0), len))
    }

    /// The lanes cut into runs of the lengths `lens` (in all at most the
    /// lanes [`Work::new`] made).
    #[inline(always)]
    fn split<const K: usize>(&mut self, lens: [usize; K]) -> [&mut [Group]; K] {
        let mut rest = &mut *self.0;
        lens.map(|len| {
            let (run, tail) = std::mem::take(&mut rest).split_at_mut(len);
            rest = tail;
            run
        })
    }
}
