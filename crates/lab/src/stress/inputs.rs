//! The inputs of one case, their envelope classification
//! ([`inside_envelope`]) and the force scale of a stack.

use std::fmt;

use fpc::actuator::{Channel, Geometry};
use fpc::{Actuator, ActuatorParams, InputError, Load, ModelId, Partition};

use super::envelope;

/// True when a case's inputs lie inside the validity envelope, where the
/// solutions are expected to converge and to satisfy every validity limit
/// (docs/stress.md gives the evidence):
///
/// - the default stack's proportions, uniformly scaled (no per-lamina
///   jitter: that moves the neutral axis and the prestress moment in ways
///   the thickness alone does not capture);
/// - `eps0 <= 0.5` and `P <= 400 kPa` (the strain limits);
/// - the curl estimate `|eps0 - P / 1000 kPa| lx / H <= 6.5` (self contact
///   of the curled, or reversed, finger; it bounds the thickness from
///   below for a given prestrain and pressure);
/// - the load strain `|F| lx H / D <= 0.15 eps0`, with `D = F_ref lx^2`
///   ([`force_scale`]): `relative_load * H / lx` (folding loads compress the
///   prestressed layer below zero strain);
/// - the automatic partition, or a drawn one whose longest element is at
///   most `lx / 12` (the slope limit).
pub fn inside_envelope(i: &StressInputs) -> bool {
    use envelope::*;
    let partition_ok = i.auto_partition
        || i.lengths.iter().fold(0.0f64, |m, &l| m.max(l))
            <= MAX_ELEMENT_FRACTION * i.geometry.lx * (1.0 + 1e-12);
    !i.jittered
        && i.eps0 <= MAX_EPS0
        && i.pressure_kpa <= MAX_PRESSURE_KPA
        && i.curl().abs() <= MAX_CURL
        && i.load_strain() <= MAX_LOAD_STRAIN_OVER_EPS0 * i.eps0
        && i.geometry.h <= fpc::validity::THICKNESS_TO_LENGTH_LIMIT * i.geometry.lx
        && i.geometry.h <= fpc::validity::THICKNESS_TO_WIDTH_LIMIT * i.geometry.ly
        && partition_ok
}

/// The inputs of one case.
#[derive(Debug, Clone, PartialEq)]
pub struct StressInputs {
    /// Element model.
    pub model: ModelId,
    /// Prestrain.
    pub eps0: f64,
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// Tip force along X (N).
    pub fx: f64,
    /// Tip force along Z (N).
    pub fz: f64,
    /// Tip load magnitude over the force scale (0: no tip load).
    pub relative_load: f64,
    /// The force scale `F_ref` (N) of the stack ([`force_scale`]; 0 when
    /// no draw was accepted).
    pub force_scale: f64,
    /// Solved on the automatic partition ([`fpc::Plan::Auto`]).
    pub auto_partition: bool,
    /// Element count N drawn (0 for the automatic partition).
    pub elements: usize,
    /// Element lengths, root to tip (mm; empty for the automatic partition).
    pub lengths: Vec<f64>,
    /// Longest over shortest element (1 for the automatic partition).
    pub length_ratio: f64,
    /// Scale of the whole layer stack (1: the default thicknesses).
    pub thickness_scale: f64,
    /// Per-lamina factors and channel heights redrawn.
    pub jittered: bool,
    /// Extra per-lamina factors (CL, regular EMC, fluidic layer, PEMC).
    pub lamina_factors: [f64; 4],
    /// The geometry handed to [`Actuator::new`].
    pub geometry: Geometry,
    /// The channel handed to [`Actuator::new`].
    pub channel: Channel,
    /// Ribs modelled.
    pub ribs: bool,
}

impl StressInputs {
    /// The scene's load.
    pub fn load(&self) -> Load {
        Load::unloaded()
            .with_pressure_kpa(self.pressure_kpa)
            .with_tip_force(self.fx, self.fz)
    }

    /// Validates the inputs into an actuator.
    pub fn actuator(&self) -> Result<Actuator, InputError> {
        let mut params = ActuatorParams {
            geometry: self.geometry,
            channel: self.channel,
            ..ActuatorParams::default()
        };
        params.pemc.eps0 = self.eps0;
        Actuator::new(params)
    }

    /// The drawn partition (`None` for the automatic partition).
    pub fn partition(&self) -> Result<Option<Partition>, InputError> {
        if self.auto_partition {
            Ok(None)
        } else {
            Partition::custom(self.lengths.clone(), self.geometry.lx).map(Some)
        }
    }

    /// The curl estimate `(eps0 - P / 1000 kPa) lx / H`: the rest curl's
    /// turning scales as `eps0 lx / H` (the prestress moment over the
    /// bending stiffness, times the length), and pressure unbends it
    /// ([`envelope::PRESSURE_PER_PRESTRAIN_KPA`]); negative for a
    /// reversed curl.
    pub fn curl(&self) -> f64 {
        (self.eps0 - self.pressure_kpa / envelope::PRESSURE_PER_PRESTRAIN_KPA) * self.geometry.lx
            / self.geometry.h
    }

    /// The tip load's bending strain scale `|F| lx H / D`, with
    /// `D = F_ref lx^2`: `relative_load * H / lx`.
    pub fn load_strain(&self) -> f64 {
        self.relative_load * self.geometry.h / self.geometry.lx
    }

    /// The partition's label: `auto` or N.
    pub fn partition_key(&self) -> PartitionKey {
        if self.auto_partition {
            PartitionKey::Auto
        } else {
            PartitionKey::Count(self.elements)
        }
    }
}

impl fmt::Display for StressInputs {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [a, b, c, d] = self.lamina_factors;
        write!(
            f,
            "model={} eps0={:.4} P={:.1}kPa F=({:.4e},{:.4e})N ({:.3e} F_ref, F_ref={:.4e}N) N={} ratio={:.1} stack={:.3}x[{:.2},{:.2},{:.2},{:.2}] H={:.3}mm h3a={:.3} h3b={:.3} ribs={}",
            self.model,
            self.eps0,
            self.pressure_kpa,
            self.fx,
            self.fz,
            self.relative_load,
            self.force_scale,
            self.partition_key(),
            self.length_ratio,
            self.thickness_scale,
            a,
            b,
            c,
            d,
            self.geometry.h,
            self.channel.h3a,
            self.channel.h3b,
            if self.ribs { "on" } else { "off" }
        )
    }
}

/// A partition class: a fixed element count, or the automatic partition.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PartitionKey {
    /// N drawn elements.
    Count(usize),
    /// [`fpc::Plan::Auto`].
    Auto,
}

impl fmt::Display for PartitionKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PartitionKey::Count(n) => write!(f, "{n}"),
            PartitionKey::Auto => f.write_str("auto"),
        }
    }
}

/// The force scale `F_ref = D / lx^2` (N) of an actuator: `D` (N mm^2) is
/// the laminate bending stiffness of the solid strip about its neutral
/// axis, `ly (sum Q11 z^2 dz - (sum Q11 z dz)^2 / sum Q11 dz)` over the
/// constraining layer, the regular EMC, the fluidic layer and the
/// prestressed layer at its law's small-strain modulus `p1` (the channel
/// and the ribs, both inside the compliant fluidic layer, are ignored).
/// It depends on the stack and the materials only, not on eps0, the model
/// or the partition. `F_ref` bends a cantilever of stiffness `D` by about
/// a radian at small deflections; the Euler load of the clamped-free
/// strip is `pi^2 / 4 F_ref`. The default stack's is 0.672 N.
pub fn force_scale(actuator: &Actuator) -> f64 {
    let g = actuator.geometry();
    let (pz0, pz1) = actuator.pemc_z();
    let mut boxes: Vec<(f64, f64, f64)> = actuator
        .linear_layers()
        .iter()
        .map(|l| (l.z0, l.z1, l.q.q11))
        .collect();
    boxes.push((pz0, pz1, actuator.pemc().law.p1));
    let (mut a, mut b, mut d) = (0.0, 0.0, 0.0);
    for (z0, z1, q) in boxes {
        a += q * (z1 - z0);
        b += q * (z1 * z1 - z0 * z0) / 2.0;
        d += q * (z1.powi(3) - z0.powi(3)) / 3.0;
    }
    let stiffness = g.ly * (d - b * b / a);
    stiffness / (g.lx * g.lx)
}
