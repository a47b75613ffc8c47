//! One CCM element: its blocks folded into kernel moments, and its energy
//! `Pi_e = Psi_e - kappa * P * V_e` with gradient and Hessian.
//!
//! The moments depend only on the scene (geometry, materials, prestrain),
//! so they are accumulated once; each Newton iteration then costs one call
//! per kernel family, whatever the number of laminae, ribs and voids.

use crate::blocks::ElementBlocks;
use crate::kernels::{
    end_hessian, end_value, frame_value, gas_gradient, gas_hessian, gas_moments, gas_value,
    linear_gradient, linear_hessian, linear_moments, linear_value, prestressed_gradient,
    prestressed_hessian, prestressed_moments, prestressed_value, GAS_MOMENTS, HESSIAN_ENTRIES,
    LINEAR_MOMENTS, PRESTRESSED_MOMENTS, UNKNOWNS,
};

/// Element unknowns `[a1, a3, b1, c2]`.
pub type Coeffs = [f64; UNKNOWNS];
/// Upper triangle of a 4x4 symmetric matrix, row by row.
pub type UpperHessian = [f64; HESSIAN_ENTRIES];

/// An element ready for evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct Element {
    length: f64,
    linear: [f64; LINEAR_MOMENTS],
    prestressed: [f64; PRESTRESSED_MOMENTS],
    gas: [f64; GAS_MOMENTS],
}

impl Element {
    /// Folds an element's blocks into moments.
    pub fn from_blocks(b: &ElementBlocks) -> Element {
        let mut e = Element {
            length: b.length,
            linear: [0.0; LINEAR_MOMENTS],
            prestressed: [0.0; PRESTRESSED_MOMENTS],
            gas: [0.0; GAS_MOMENTS],
        };
        for l in &b.linear {
            linear_moments(
                &mut e.linear,
                l.x0,
                l.x1,
                l.width,
                l.z0,
                l.z1,
                l.q.q11,
                l.q.q12,
                l.q.q22,
            );
        }
        for p in &b.prestressed {
            prestressed_moments(
                &mut e.prestressed,
                p.x0,
                p.x1,
                p.width,
                p.z0,
                p.z1,
                p.eps0,
                p.p[0],
                p.p[1],
                p.p[2],
                p.p[3],
                p.q22,
            );
        }
        for g in &b.gas {
            gas_moments(&mut e.gas, g.x0, g.x1, g.width, g.z0, g.z1);
        }
        e
    }

    /// Undeformed length `L_i`.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// Strain energy `Psi_e` (N mm).
    pub fn strain_energy(&self, k: &Coeffs) -> f64 {
        linear_value(k, &self.linear) + prestressed_value(k, &self.prestressed)
    }

    /// Deformed gas volume `V_e` (mm^3).
    pub fn gas_volume(&self, k: &Coeffs) -> f64 {
        gas_value(k, &self.gas)
    }

    /// `Pi_e` for a pressure factor `kp = kappa * P` (MPa); `kp = 0` skips the gas kernel.
    pub fn energy(&self, k: &Coeffs, kp: f64) -> f64 {
        let mut v = self.strain_energy(k);
        if kp != 0.0 {
            v -= kp * gas_value(k, &self.gas);
        }
        v
    }

    /// `Pi_e` and its gradient.
    pub fn gradient(&self, k: &Coeffs, kp: f64) -> (f64, Coeffs) {
        let (v1, g1) = linear_gradient(k, &self.linear);
        let (v2, g2) = prestressed_gradient(k, &self.prestressed);
        let mut v = v1 + v2;
        let mut g = [0.0; UNKNOWNS];
        for i in 0..UNKNOWNS {
            g[i] = g1[i] + g2[i];
        }
        if kp != 0.0 {
            let (vg, gg) = gas_gradient(k, &self.gas);
            v -= kp * vg;
            for i in 0..UNKNOWNS {
                g[i] -= kp * gg[i];
            }
        }
        (v, g)
    }

    /// `Pi_e`, its gradient and Hessian (upper triangle).
    pub fn hessian(&self, k: &Coeffs, kp: f64) -> (f64, Coeffs, UpperHessian) {
        let (v1, g1, h1) = linear_hessian(k, &self.linear);
        let (v2, g2, h2) = prestressed_hessian(k, &self.prestressed);
        let mut v = v1 + v2;
        let mut g = [0.0; UNKNOWNS];
        let mut h = [0.0; HESSIAN_ENTRIES];
        for i in 0..UNKNOWNS {
            g[i] = g1[i] + g2[i];
        }
        for i in 0..HESSIAN_ENTRIES {
            h[i] = h1[i] + h2[i];
        }
        if kp != 0.0 {
            let (vg, gg, hg) = gas_hessian(k, &self.gas);
            v -= kp * vg;
            for i in 0..UNKNOWNS {
                g[i] -= kp * gg[i];
            }
            for i in 0..HESSIAN_ENTRIES {
                h[i] -= kp * hg[i];
            }
        }
        (v, g, h)
    }

    /// Gas volume with its gradient and Hessian.
    pub fn gas_hessian(&self, k: &Coeffs) -> (f64, Coeffs, UpperHessian) {
        gas_hessian(k, &self.gas)
    }

    /// End point and slope `(Xe, Ze, eta)` in the element frame.
    pub fn end(&self, k: &Coeffs) -> [f64; 3] {
        end_value(k, self.length)
    }

    /// End point and the end tangent's direction `[Xe, Ze, cos eta, sin eta]`
    /// without trigonometric calls.
    pub fn frame(&self, k: &Coeffs) -> [f64; 4] {
        let [xe, ze, dx, dz] = frame_value(k, self.length);
        let r = dx.hypot(dz);
        if r > 0.0 {
            [xe, ze, dx / r, dz / r]
        } else {
            [xe, ze, 1.0, 0.0]
        }
    }

    /// End point and slope with gradients and Hessians.
    #[allow(clippy::type_complexity)]
    pub fn end_hessian(&self, k: &Coeffs) -> ([f64; 3], [Coeffs; 3], [UpperHessian; 3]) {
        end_hessian(k, self.length)
    }
}
