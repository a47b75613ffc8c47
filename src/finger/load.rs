//! The loads on a finger: channel pressure, pressure factor and tip force.

use crate::error::{finite, positive, InputError};
use crate::model::EnergyScalars;

/// Pressure and tip loads of a scene.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Load {
    /// Channel pressure (MPa; 1 kPa = 0.001 MPa).
    pub pressure: f64,
    /// Pressure factor `kappa = 1/(gamma - 1)` (2.5 by default; 1 is plain
    /// `P dV` work; at most [`MAX_KAPPA`]).
    pub kappa: f64,
    /// Tip force along the finger's X axis (N).
    pub fx: f64,
    /// Tip force along the finger's Z axis (N).
    pub fz: f64,
}

impl Default for Load {
    fn default() -> Load {
        Load {
            pressure: 0.0,
            kappa: 2.5,
            fx: 0.0,
            fz: 0.0,
        }
    }
}

/// Largest pressure factor ([`Load::kappa`]): kappa = 1/(gamma - 1) for a
/// gas whose ratio of specific heats gamma is at least 1.01 (air's 1.4
/// gives the default 2.5).
pub const MAX_KAPPA: f64 = 100.0;

/// Absolute vacuum relative to the atmosphere (MPa): a channel pressure
/// (gauge) below it is not physical.
pub const VACUUM_GAUGE_MPA: f64 = -0.101_325;

impl Load {
    /// No pressure, no tip load.
    pub fn unloaded() -> Load {
        Load::default()
    }

    /// The same load with a pressure given in kPa.
    pub fn with_pressure_kpa(mut self, kpa: f64) -> Load {
        self.pressure = kpa * 1e-3;
        self
    }

    /// The same load with a tip force (N, finger frame).
    pub fn with_tip_force(mut self, fx: f64, fz: f64) -> Load {
        self.fx = fx;
        self.fz = fz;
        self
    }

    /// True when a tip force acts.
    pub fn has_tip_load(&self) -> bool {
        self.fx != 0.0 || self.fz != 0.0
    }

    /// Checks that every value is finite, kappa in (0, [`MAX_KAPPA`]] and the pressure
    /// (gauge) not below absolute vacuum.
    pub fn validate(&self) -> Result<(), InputError> {
        finite(crate::Field::LoadPressure, self.pressure)?;
        if self.pressure < VACUUM_GAUGE_MPA {
            return Err(InputError::OutOfRange {
                field: crate::Field::LoadPressure,
                value: self.pressure,
                rule: format!(
                    "is below absolute vacuum ({} kPa gauge)",
                    VACUUM_GAUGE_MPA * 1e3
                ),
            });
        }
        positive(crate::Field::LoadKappa, self.kappa)?;
        crate::error::require(
            self.kappa <= MAX_KAPPA,
            crate::Field::LoadKappa,
            self.kappa,
            || {
                format!(
                    "must be at most {MAX_KAPPA} (kappa = 1/(gamma - 1) for a ratio of specific heats gamma of at least 1.01)"
                )
            },
        )?;
        finite(crate::Field::LoadFx, self.fx)?;
        finite(crate::Field::LoadFz, self.fz)?;
        Ok(())
    }

    /// The energy's runtime scalars.
    pub(crate) fn scalars(&self) -> EnergyScalars {
        EnergyScalars {
            kp: self.kappa * self.pressure,
        }
    }
}
