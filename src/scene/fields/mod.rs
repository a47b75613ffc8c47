//! Scene keys in messages.
//!
//! [`SceneKey`] names every key of the file format by its place in the
//! schema; the resolution validates through it, so its own errors name
//! scene keys directly. The library's validating constructors name their
//! fields in the library's terms ([`Field`]: `load.pressure` in MPa,
//! `grasp.beta` in rad, ...): [`scene_key`] says which scene key a field
//! the scene can trigger is, and [`scene_value`] converts its value to the
//! key's unit. [`warning_text`] writes warnings the same way.

use crate::error::{self, InputError, Warning};
pub(crate) use crate::field::{Elastic, Field, GeometryKey, Lamina, PaperRibKey};
use crate::solve_error::SolveError;

mod keys;
pub use keys::{
    edit_distance, GraspKey, GripperKey, LoadKey, ModelKey, PartitionKey, SceneKey, SolveKey,
    ValueKind,
};

// ------------------------------------------------------------ checks in scene keys

/// Fails with `NotFinite` unless `value` is finite.
pub(super) fn finite(key: impl Into<SceneKey>, value: f64) -> Result<f64, InputError> {
    error::finite(key.into().to_string().into(), value)
}

/// Fails unless `value` is finite and strictly positive.
pub(super) fn positive(key: impl Into<SceneKey>, value: f64) -> Result<f64, InputError> {
    error::positive(key.into().to_string().into(), value)
}

/// Fails with `OutOfRange` unless `ok`.
pub(super) fn require(
    ok: bool,
    key: impl Into<SceneKey>,
    value: f64,
    rule: impl Into<String>,
) -> Result<(), InputError> {
    if ok {
        Ok(())
    } else {
        Err(InputError::OutOfRange {
            field: key.into().to_string().into(),
            value,
            rule: rule.into(),
        })
    }
}

/// An `Inconsistent` error at `key`.
pub(super) fn inconsistent(key: impl Into<SceneKey>, rule: impl Into<String>) -> InputError {
    InputError::Inconsistent {
        field: key.into().to_string().into(),
        rule: rule.into(),
    }
}

/// Fails for the first key of `keys` that is set.
pub(super) fn forbid(keys: &[(SceneKey, bool)], rule: &str) -> Result<(), InputError> {
    match keys.iter().find(|(_, set)| *set) {
        Some(&(k, _)) => Err(inconsistent(k, rule)),
        None => Ok(()),
    }
}

// ------------------------------------------------------------ library fields

/// The scene key a library field is given by (`None`: a field the scene
/// cannot set, or a name already written out).
pub(crate) fn scene_key(f: &Field) -> Option<SceneKey> {
    Some(match *f {
        Field::Geometry(k) => SceneKey::Geometry(k),
        Field::Channel(k) => SceneKey::Channel(k),
        Field::PaperRib(k) => SceneKey::PaperRib(k),
        Field::Rib(i, k) => SceneKey::RibEntry(i, k),
        Field::Ribs => SceneKey::Ribs,
        Field::ClRib(i, k) => SceneKey::ClRibEntry(i, k),
        Field::ClRibs => SceneKey::ClRibs,
        Field::Material(l, k) => SceneKey::Material(l, k),
        Field::Pemc(k) => SceneKey::Pemc(k),
        Field::ShearModulus(l) => SceneKey::ShearModulus(l),
        Field::Laminate(k) => SceneKey::Laminate(k),
        // the element count; the automatic partition's pieces; a finger
        // without elements
        Field::PartitionN | Field::PartitionMaxLength | Field::GripperFinger => {
            SceneKey::Partition(PartitionKey::Elements)
        }
        Field::PartitionLx => SceneKey::Geometry(GeometryKey::Lx),
        Field::PartitionLengths | Field::PartitionLengthsSum => {
            SceneKey::Partition(PartitionKey::Lengths)
        }
        Field::PartitionLength(i) => SceneKey::PartitionLength(i),
        Field::TipTolMm => SceneKey::Partition(PartitionKey::TipTolMm),
        Field::LoadPressure => SceneKey::Load(LoadKey::PressureKpa),
        Field::LoadKappa => SceneKey::Load(LoadKey::Kappa),
        Field::LoadFx => SceneKey::Load(LoadKey::Fx),
        Field::LoadFz => SceneKey::Load(LoadKey::Fz),
        Field::Solve => SceneKey::SolveTable,
        Field::SolveRtol => SceneKey::Solve(SolveKey::Rtol),
        Field::SolveMaxIter => SceneKey::Solve(SolveKey::MaxIter),
        Field::SolveSamplesPerElement => SceneKey::Solve(SolveKey::SamplesPerElement),
        Field::SolveMaxStep => SceneKey::Solve(SolveKey::MaxStep),
        Field::GripperMountingAngle => SceneKey::Gripper(GripperKey::MountingAngleDeg),
        Field::GripperMu => SceneKey::Gripper(GripperKey::Mu),
        Field::GripperFingers => SceneKey::Gripper(GripperKey::Fingers),
        Field::GripperOverlap => SceneKey::Gripper(GripperKey::OverlapMm),
        Field::GripperPalm => SceneKey::Gripper(GripperKey::PalmMm),
        Field::GraspPressureKpa => SceneKey::Grasp(GraspKey::PressureKpa),
        Field::GraspSize => SceneKey::Grasp(GraspKey::DMm),
        Field::GraspBeta | Field::SphereBeta => SceneKey::Grasp(GraspKey::BetaDeg),
        Field::GraspFriction => SceneKey::Grasp(GraspKey::FrictionN),
        Field::SphereRadius => SceneKey::Grasp(GraspKey::RMm),
        Field::SphereLift => SceneKey::Grasp(GraspKey::LiftN),
        Field::Refinement(_)
        | Field::SamplesPerElement
        | Field::GraspForce
        | Field::SphereSamples
        | Field::Guess
        | Field::Coefficients
        | Field::Key(_) => return None,
    })
}

/// A value of a library field in the unit of its scene key (MPa to kPa,
/// rad to degrees).
pub(crate) fn scene_value(f: &Field, value: f64) -> f64 {
    match f {
        Field::LoadPressure => value * 1e3,
        Field::GripperMountingAngle | Field::GraspBeta | Field::SphereBeta => degrees(value),
        _ => value,
    }
}

/// A library error in the scene's terms: the field named by its scene
/// key, the value in the key's unit. Errors on fields the scene cannot
/// trigger stay as they are.
pub fn scene_input(e: InputError) -> InputError {
    let f = e.field().clone();
    match scene_key(&f) {
        Some(k) => e.renamed(k.to_string(), |v| scene_value(&f, v)),
        None => e,
    }
}

/// Whether the scene document `doc` (a [`SceneFile`](crate::scene::SceneFile)
/// as written, as a TOML table: absent keys are not in it) gives `key`.
pub(crate) fn written_in(doc: &toml::Table, key: SceneKey) -> bool {
    let mut table = doc;
    let steps = key.steps();
    for (i, (name, index)) in steps.iter().enumerate() {
        let Some(mut value) = table.get(name) else {
            return false;
        };
        if let Some(k) = index {
            match value.as_array().and_then(|list| list.get(*k)) {
                Some(entry) => value = entry,
                None => return false,
            }
        }
        if i + 1 == steps.len() {
            return true;
        }
        match value.as_table() {
            Some(t) => table = t,
            None => return false,
        }
    }
    false
}

/// A failed rule between keys in the terms of what the scene wrote. The
/// library's `error` names one field; `against` are the fields its rule
/// compares it with, with their values. When the scene does not write the
/// named key (it holds its default) but writes one of `against`, the
/// error names the first such key, with its value, and says which
/// default it conflicts with (`actuator.geometry.lx = 50: conflicts with
/// the default of a key the scene does not set (actuator.channel.cx =
/// 105: must not exceed the length lx = 50)`). Otherwise (a rule on one
/// key, the named key written, or no key of the rule written) it is
/// [`scene_input`]'s. Every rule between keys of the scene is named here.
pub(crate) fn name_written(
    error: InputError,
    against: &[(Field, f64)],
    written: impl Fn(SceneKey) -> bool,
) -> InputError {
    let named = scene_key(error.field());
    let error = scene_input(error);
    match named {
        Some(k) if !written(k) => {}
        _ => return error,
    }
    let given = against
        .iter()
        .filter_map(|(f, v)| Some((scene_key(f)?, scene_value(f, *v))))
        .find(|&(k, _)| written(k));
    match given {
        Some((key, value)) => InputError::OutOfRange {
            field: key.to_string().into(),
            value,
            rule: format!("conflicts with the default of a key not given ({error})"),
        },
        None => error,
    }
}

/// An input error of a solve that names a key the scene does not write:
/// the key holds its default, and something the scene does write made
/// that default fail (a shorter finger, and the default overlap exceeds
/// its reach). The rule says so, so the user is not sent to look for a
/// key they never wrote. Any other error is returned as it is.
pub(crate) fn say_default(error: SolveError, written: impl Fn(SceneKey) -> bool) -> SolveError {
    let SolveError::Input(e) = error else {
        return error;
    };
    let Some(key) = scene_key(e.field()).filter(|&k| !written(k)) else {
        return SolveError::Input(e);
    };
    let note = format!("; {key} holds its default (it is not given)");
    SolveError::Input(match e {
        InputError::OutOfRange { field, value, rule } => InputError::OutOfRange {
            field,
            value,
            rule: rule + &note,
        },
        InputError::Inconsistent { field, rule } => InputError::Inconsistent {
            field,
            rule: rule + &note,
        },
        e => e,
    })
}

/// A library solve error in the scene's terms: input errors as in
/// [`scene_input`], and the target of a target not reached. Front ends
/// whose own names follow the scene keys (the CLI's flags) start from it.
pub fn scene_solve(e: SolveError) -> SolveError {
    e.renamed(|f| scene_key(f).map(|k| k.to_string().into()), scene_value)
}

/// Radians in degrees, rounded to 1e-9 deg (60 deg prints as 60).
pub fn degrees(rad: f64) -> f64 {
    (rad.to_degrees() * 1e9).round() / 1e9
}

// ------------------------------------------------------------ warnings

/// A warning in the scene's terms (its keys and units).
pub fn warning_text(w: &Warning) -> String {
    match *w {
        Warning::MountingAngleOutsideDesignSpace { angle, lo, hi } => format!(
            "{} = {}: outside the design space [{}, {}] deg (arccot mu to 90 deg)",
            SceneKey::Gripper(GripperKey::MountingAngleDeg),
            degrees(angle),
            degrees(lo),
            degrees(hi)
        ),
        Warning::ElementSlope {
            element,
            degrees,
            limit,
        } => format!(
            "element {element} turns {degrees:.1} degrees, beyond the CCM's small-slope limit of {limit} degrees per element: use more elements ({} = \"auto\")",
            SceneKey::Partition(PartitionKey::Elements)
        ),
        Warning::PalmGapAtRest { palm, reach } => format!(
            "gripper: the palm diameter {palm:.4} mm is wider than twice the finger's inward reach l0 = {reach:.4} mm (negative overlap): the fingers leave a gap at rest"
        ),
        _ => w.to_string(),
    }
}

#[cfg(test)]
mod tests;
