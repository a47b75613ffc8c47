//! The parameters of a sensitivity ([`Param`]): the actuator's
//! ([`ActuatorParam`], src/actuator/param.rs), the load's and the target's,
//! each named by its scene key.

use std::fmt;

use crate::actuator::{Actuator, ActuatorParam};
use crate::finger::{Load, TargetProblem};

/// A parameter of a sensitivity: of the actuator, of the load, or the
/// target of a target solve. Named by its scene key ([`Param::name`]);
/// derivatives are per unit of that key (the pressure per kPa).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Param {
    /// An actuator parameter.
    Actuator(ActuatorParam),
    /// `load.pressure_kpa`: the channel pressure, per kPa.
    Pressure,
    /// `load.kappa`: the pressure factor.
    Kappa,
    /// `load.fx` (N): the tip force along X (for a target solve, the fixed
    /// part of the load, `base.fx`).
    Fx,
    /// `load.fz` (N): the tip force along Z (`base.fz` for a target solve).
    Fz,
    /// `target.value` (mm): the target of a target solve.
    Target,
}

impl Param {
    /// The load's parameters.
    pub const LOAD: [Param; 4] = [Param::Pressure, Param::Kappa, Param::Fx, Param::Fz];

    /// Every parameter `actuator` and a load have (actuator parameters,
    /// then the load's; not [`Param::Target`]).
    pub fn all(actuator: &Actuator) -> Vec<Param> {
        let mut v: Vec<Param> = ActuatorParam::for_actuator(actuator)
            .into_iter()
            .map(Param::Actuator)
            .collect();
        v.extend(Param::LOAD);
        v
    }

    /// The scene key (`actuator.pemc.eps0`, `load.pressure_kpa`, ...;
    /// `target.value` for the target).
    pub fn name(self) -> String {
        match self {
            Param::Actuator(a) => a.name(),
            Param::Pressure => "load.pressure_kpa".into(),
            Param::Kappa => "load.kappa".into(),
            Param::Fx => "load.fx".into(),
            Param::Fz => "load.fz".into(),
            Param::Target => "target.value".into(),
        }
    }

    /// The parameter of a name ([`Param::name`]).
    pub fn from_name(name: &str) -> Option<Param> {
        ActuatorParam::from_name(name)
            .map(Param::Actuator)
            .or_else(|| {
                Param::LOAD
                    .into_iter()
                    .chain([Param::Target])
                    .find(|p| p.name() == name)
            })
    }

    /// The parameter's value (in its key's unit) for an actuator and a load
    /// (and, for [`Param::Target`], a target problem).
    pub fn value(
        self,
        actuator: &Actuator,
        load: &Load,
        target: Option<&TargetProblem>,
    ) -> Option<f64> {
        match self {
            Param::Actuator(a) => a.value(actuator),
            Param::Pressure => Some(load.pressure * 1e3),
            Param::Kappa => Some(load.kappa),
            Param::Fx => Some(load.fx),
            Param::Fz => Some(load.fz),
            Param::Target => target.map(|t| t.target),
        }
    }

    /// `load` with this load parameter set to `value` (`None` for an
    /// actuator parameter or the target).
    pub fn load_with(self, load: &Load, value: f64) -> Option<Load> {
        let mut l = *load;
        match self {
            Param::Pressure => l.pressure = value * 1e-3,
            Param::Kappa => l.kappa = value,
            Param::Fx => l.fx = value,
            Param::Fz => l.fz = value,
            Param::Actuator(_) | Param::Target => return None,
        }
        Some(l)
    }
}

impl fmt::Display for Param {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

impl serde::Serialize for Param {
    /// The scene key.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.name())
    }
}
