//! One element of a finger: its integration blocks (docs/model.md section
//! 4.4) folded into the model's moments.
//!
//! The moments depend only on the scene (geometry, materials, prestrain),
//! so they are accumulated once; each Newton iteration then costs one call
//! of the model's energy, whatever the number of laminae, ribs and voids.
//!
//! Here: the blocks and the element (its energy, gradient and Hessian one
//! element at a time, its end kinematics). The elements chained from the
//! clamp (tip, frames, end angle) are in `walk`; the elements' moments
//! packed side by side for the passes in vector lanes in `packed`.

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

pub(crate) mod packed;
pub(crate) mod walk;
