//! The elements of one finger, for one element model: energy, tip, shape
//! and the raw-coefficient derivatives, and what a
//! [`Finger`](super::Finger) asks of them for its model.
//!
//! Unknowns are scaled per element by the model (`scaled` in the spec), so
//! the Newton system sees dimensionless strains; `unscale[i]` holds, per
//! element, the raw value of one scaled unit of each unknown.

use crate::actuator::element_blocks;
use crate::actuator::Actuator;
use crate::element::packed::{ElementLanes, Group};
use crate::element::{self, distinct_elements, Element};
use crate::error::Warning;
use crate::lanes::{OnLines, Width};
use crate::model::{upper_index, ElementModel, ModelId, Vector};
use crate::partition::Partition;

use super::curve::{Affine2, PolyCurve};
use super::load::Load;
use crate::coefficients::Coefficients;

/// The elements of a finger for model `M`.
#[derive(Debug, Clone)]
pub(crate) struct FingerCore<M: ElementModel> {
    pub elements: Vec<Element<M>>,
    /// The elements' moments packed for the widest lanes this processor
    /// runs (the chain's element pass).
    pub lanes: ElementLanes<M>,
    /// For each element, the first element with identical blocks.
    pub distinct: Vec<usize>,
    /// Raw value of one scaled unit, per element.
    pub unscale: Vec<M::Coeffs>,
    pub lengths: Vec<f64>,
    /// `unscale` and `lengths` in groups of elements ([`element::packed::pack`]),
    /// as the chain's assembly reads them.
    pub unscale_groups: OnLines<Group>,
    pub length_groups: OnLines<Group>,
    /// The largest scaled Hessian diagonal of the unstrained finger (N mm).
    pub stiffness: f64,
    /// The prestressed layer's z range and prestrain (validity checks).
    pub pemc_z: (f64, f64),
    pub eps0: f64,
    /// The laminate's total thickness H (self contact).
    pub thickness: f64,
    /// The strip's width Ly (mm).
    pub width: f64,
}

impl<M: ElementModel> FingerCore<M> {
    pub fn new(actuator: &Actuator, partition: &Partition, ribs: bool) -> FingerCore<M> {
        let blocks = element_blocks(actuator, partition, ribs);
        let distinct = distinct_elements(&blocks);
        let elements: Vec<Element<M>> = blocks.iter().map(Element::from_blocks).collect();
        let lengths: Vec<f64> = elements.iter().map(Element::length).collect();
        let unscale: Vec<M::Coeffs> = lengths.iter().map(|&l| M::unscale(l)).collect();
        // stiffness scale: the largest scaled Hessian diagonal of the
        // unstrained strain energy (about E*A*L of the stiffest element)
        let n = M::Coeffs::LEN;
        let unloaded = Load::unloaded().scalars();
        let mut stiffness: f64 = 0.0;
        for (e, s) in elements.iter().zip(&unscale) {
            let (_, _, h) = e.hessian(&M::Coeffs::zero(), &unloaded);
            for i in 0..n {
                stiffness = stiffness.max((h[upper_index(n, i, i)] * s[i] * s[i]).abs());
            }
        }
        let count = elements.len();
        let unscale_groups = element::packed::pack(count, n, |i| unscale[i].as_ref());
        let length_groups = element::packed::pack(count, 1, |i| std::slice::from_ref(&lengths[i]));
        FingerCore {
            lanes: ElementLanes::new(&elements, Width::detect()),
            elements,
            distinct,
            unscale_groups,
            length_groups,
            unscale,
            lengths,
            stiffness: stiffness.max(f64::MIN_POSITIVE),
            pemc_z: actuator.pemc_z(),
            eps0: actuator.eps0(),
            thickness: actuator.geometry().h,
            width: actuator.geometry().ly,
        }
    }

    pub fn len(&self) -> usize {
        self.elements.len()
    }

    /// The cross-section the validity checks read.
    pub fn laminate(&self) -> crate::validity::Laminate {
        crate::validity::Laminate {
            pemc_z: self.pemc_z,
            eps0: self.eps0,
            thickness: self.thickness,
        }
    }

    /// Element `i`'s raw unknowns from a flat slice.
    #[inline]
    pub fn element_coeffs(k: &[f64], i: usize) -> M::Coeffs {
        crate::element::coeffs::<M>(k, i)
    }

    /// Tip position at raw coefficients, chaining element frames by
    /// rotation (no trigonometric calls).
    pub fn tip_position(&self, k: &[f64]) -> [f64; 2] {
        crate::element::walk::walk(
            &self.elements,
            |i| Self::element_coeffs(k, i),
            |_, _, _, _| {},
        )
    }

    /// Total potential at raw coefficients.
    pub fn energy_raw(&self, load: &Load, k: &[f64]) -> f64 {
        let s = load.scalars();
        let mut v: f64 = self
            .elements
            .iter()
            .enumerate()
            .map(|(i, e)| e.energy(&Self::element_coeffs(k, i), &s))
            .sum();
        if load.has_tip_load() {
            let tip = self.tip_position(k);
            v -= load.fx * tip[0] + load.fz * tip[1];
        }
        v
    }

    /// Element `i`'s frame at the root: its position and (cos, sin) of
    /// its angle, for every element, from raw coefficients.
    pub fn frames(&self, k: &[f64]) -> Vec<([f64; 2], [f64; 2])> {
        crate::element::walk::frames(&self.elements, k)
    }

    /// Mid-plane samples from the root (included) to the tip.
    pub fn shape_raw(&self, k: &[f64], per_element: usize) -> Vec<[f64; 2]> {
        let per = per_element.max(1);
        let mut pts = Vec::with_capacity(1 + per * self.len());
        pts.push([0.0, 0.0]);
        for (i, (e, (p, [c, s]))) in self.elements.iter().zip(self.frames(k)).enumerate() {
            let ki = Self::element_coeffs(k, i);
            let l = e.length();
            for j in 1..=per {
                let x = l * j as f64 / per as f64;
                let [xl, zl] = M::midplane(&ki, x);
                pts.push([p[0] + c * xl - s * zl, p[1] + s * xl + c * zl]);
            }
        }
        pts
    }

    /// Scaled unknowns of raw coefficients.
    pub fn scaled(&self, k: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; k.len()];
        self.scale_into(k, &mut y);
        y
    }

    /// [`FingerCore::scaled`] into `y` (of `k`'s length).
    pub fn scale_into(&self, k: &[f64], y: &mut [f64]) {
        let n = M::Coeffs::LEN;
        for ((y, k), s) in y.chunks_mut(n).zip(k.chunks(n)).zip(&self.unscale) {
            for ((y, v), s) in y.iter_mut().zip(k).zip(s.as_ref()) {
                *y = v / s;
            }
        }
    }

    /// Raw coefficients of scaled unknowns.
    pub fn raw(&self, y: &[f64]) -> Coefficients {
        let n = M::Coeffs::LEN;
        let mut values = Vec::with_capacity(y.len());
        for (y, s) in y.chunks(n).zip(&self.unscale) {
            values.extend(y.iter().zip(s.as_ref()).map(|(v, s)| v * s));
        }
        Coefficients::from_parts(n, values)
    }
}

/// What a [`Finger`](super::Finger) asks of its core, for its model.
impl<M: ElementModel> FingerCore<M> {
    pub fn model(&self) -> ModelId {
        ModelId::from_name(M::NAME).unwrap_or_default()
    }

    pub fn unknowns(&self) -> usize {
        M::Coeffs::LEN
    }

    pub fn lengths(&self) -> &[f64] {
        &self.lengths
    }

    pub fn width(&self) -> f64 {
        self.width
    }

    pub fn stiffness(&self) -> f64 {
        self.stiffness
    }

    pub fn unscale(&self) -> Vec<f64> {
        self.unscale
            .iter()
            .flat_map(|s| s.as_ref().to_vec())
            .collect()
    }

    pub fn energy(&self, load: &Load, k: &Coefficients) -> f64 {
        self.energy_raw(load, k.as_slice())
    }

    pub fn tip(&self, k: &Coefficients) -> ([f64; 2], f64) {
        element::walk::tip_and_end_angle(&self.elements, k.as_slice())
    }

    pub fn shape(&self, k: &Coefficients, per_element: usize) -> Vec<[f64; 2]> {
        self.shape_raw(k.as_slice(), per_element)
    }

    pub fn midplane_curves(&self, k: &Coefficients) -> Vec<PolyCurve> {
        let k = k.as_slice();
        self.frames(k)
            .into_iter()
            .enumerate()
            .map(|(i, (p, [c, s]))| {
                let mut local = vec![[0.0; 2]; M::MIDPLANE_DEGREE + 1];
                M::midplane_coefficients(&Self::element_coeffs(k, i), &mut local);
                PolyCurve::from_parts(local, self.lengths[i]).map(Affine2::rotation_cs(c, s, p))
            })
            .collect()
    }

    pub fn element_hessian(
        &self,
        element: usize,
        family: Option<usize>,
        load: &Load,
        k: &[f64],
    ) -> Option<(f64, Vec<f64>, Vec<f64>)> {
        let e = self.elements.get(element)?;
        if k.len() != M::Coeffs::LEN {
            return None;
        }
        let ki = Self::element_coeffs(k, 0);
        let (v, g, h) = match family {
            Some(f) => e.family_hessian(f, &ki)?,
            None => e.hessian(&ki, &load.scalars()),
        };
        Some((v, g.as_ref().to_vec(), h.as_ref().to_vec()))
    }

    pub fn element_end(&self, element: usize, k: &[f64]) -> Option<[f64; 3]> {
        let e = self.elements.get(element)?;
        (k.len() == M::Coeffs::LEN).then(|| e.end(&Self::element_coeffs(k, 0)))
    }

    pub fn validity(&self, k: &Coefficients, samples: usize) -> Vec<Warning> {
        crate::validity::check(&self.elements, &self.laminate(), k.as_slice(), samples).0
    }

    pub fn curvatures(&self, k: &Coefficients, per_element: usize) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.len() * per_element);
        for (i, e) in self.elements.iter().enumerate() {
            let ki = Self::element_coeffs(k.as_slice(), i);
            for j in 0..per_element {
                let x = e.length() * (j as f64 + 0.5) / per_element as f64;
                out.push(M::curvature(&ki, x));
            }
        }
        out
    }
}
