//! Scene keys in messages.
//!
//! [`SceneKey`] names every key of the file format by its place in the
//! schema; the resolution validates through it, so its own errors name
//! scene keys directly. The library's validating constructors name their
//! fields in the library's terms ([`Field`]: `load.pressure` in MPa,
//! `grasp.beta` in rad, ...): [`scene_key`] says which scene key a field
//! the scene can trigger is, and [`scene_value`] converts its value to the
//! key's unit. [`warning_text`] writes warnings the same way.

use std::fmt;

use crate::error::{self, InputError, Warning};
pub(crate) use crate::field::{
    names, ChannelKey, ClRibKey, Elastic, Field, GeometryKey, Lamina, LaminateKey, PaperRibKey,
    PemcKey, RibKey, ShearLayer,
};
use crate::solve_error::SolveError;

names!(
    /// `[model]`.
    pub(crate) ModelKey { Name => "name" }
);
names!(
    /// `[partition]`.
    pub(crate) PartitionKey { Elements => "elements", Lengths => "lengths", TipTolMm => "tip_tol_mm" }
);
names!(
    /// `[load]`.
    pub(crate) LoadKey { PressureKpa => "pressure_kpa", Kappa => "kappa", Fx => "fx", Fz => "fz" }
);
names!(
    /// `[solve]`.
    pub(crate) SolveKey {
        Rtol => "rtol",
        MaxIter => "max_iter",
        Strategy => "strategy",
        SamplesPerElement => "samples_per_element",
        Shape => "shape",
        Stability => "stability",
        Continuation => "continuation",
        MaxStep => "max_step",
    }
);
names!(
    /// `[gripper]` (without its `grasp` table).
    pub(crate) GripperKey {
        MountingAngleDeg => "mounting_angle_deg",
        OverlapMm => "overlap_mm",
        PalmMm => "palm_mm",
        Fingers => "fingers",
        Mu => "mu",
        Strict => "strict",
    }
);
names!(
    /// `[gripper.grasp]`.
    pub(crate) GraspKey {
        Kind => "kind",
        PressureKpa => "pressure_kpa",
        DMm => "d_mm",
        BetaDeg => "beta_deg",
        FrictionN => "friction_n",
        RMm => "r_mm",
        LiftN => "lift_n",
    }
);

/// A key of a scene file, by its place in the schema. Displays as its
/// TOML path (`actuator.geometry.h1`, `partition.lengths[2]`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum SceneKey {
    Model(ModelKey),
    Geometry(GeometryKey),
    Channel(ChannelKey),
    /// `actuator.ribs` as a whole (ribs that together do not fit).
    Ribs,
    /// `actuator.ribs.kind` (checked by the parser, like every `kind`).
    #[allow(dead_code)]
    RibsKind,
    /// `actuator.ribs.list`.
    RibsList,
    /// `actuator.ribs.w1`, `w2`, `t`.
    PaperRib(PaperRibKey),
    /// `actuator.ribs.list[i].<key>`.
    RibEntry(usize, RibKey),
    /// `actuator.cl_ribs` as a whole (too many ribs, or ribs that
    /// together are wider than the strip).
    ClRibs,
    /// `actuator.cl_ribs.list`.
    #[allow(dead_code)] // the parser checks its type
    ClRibsList,
    /// `actuator.cl_ribs.list[i].<key>`.
    ClRibEntry(usize, ClRibKey),
    /// `actuator.<layer>.kind` (checked by the parser).
    #[allow(dead_code)]
    MaterialKind(Lamina),
    /// `actuator.<layer>.<key>`.
    Material(Lamina, Elastic),
    Pemc(PemcKey),
    /// `actuator.<layer>.g13`.
    ShearModulus(ShearLayer),
    /// `actuator.laminate.<key>`.
    Laminate(LaminateKey),
    Partition(PartitionKey),
    /// `partition.lengths[i]`.
    PartitionLength(usize),
    Load(LoadKey),
    /// `solve` as a whole (settings that do not fit together).
    SolveTable,
    Solve(SolveKey),
    Gripper(GripperKey),
    Grasp(GraspKey),
    /// `calibration.<key>` (a calibration's record; it changes nothing
    /// that is solved).
    Calibration(&'static str),
}

/// The keys of `[calibration]` (a list's entries at index 0).
#[cfg(test)]
pub(crate) const CALIBRATION_KEYS: [&str; 5] = [
    "manifest",
    "parameters[0]",
    "standard_errors[0]",
    "covariance[0][0]",
    "chi_square_per_dof",
];

impl fmt::Display for SceneKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneKey::Model(k) => write!(f, "model.{k}"),
            SceneKey::Geometry(k) => write!(f, "actuator.geometry.{k}"),
            SceneKey::Channel(k) => write!(f, "actuator.channel.{k}"),
            SceneKey::Ribs => f.write_str("actuator.ribs"),
            SceneKey::RibsKind => f.write_str("actuator.ribs.kind"),
            SceneKey::RibsList => f.write_str("actuator.ribs.list"),
            SceneKey::PaperRib(k) => write!(f, "actuator.ribs.{k}"),
            SceneKey::RibEntry(i, k) => write!(f, "actuator.ribs.list[{i}].{k}"),
            SceneKey::ClRibs => f.write_str("actuator.cl_ribs"),
            SceneKey::ClRibsList => f.write_str("actuator.cl_ribs.list"),
            SceneKey::ClRibEntry(i, k) => write!(f, "actuator.cl_ribs.list[{i}].{k}"),
            SceneKey::MaterialKind(l) => write!(f, "actuator.{l}.kind"),
            SceneKey::Material(l, k) => write!(f, "actuator.{l}.{k}"),
            SceneKey::Pemc(k) => write!(f, "actuator.pemc.{k}"),
            SceneKey::ShearModulus(l) => write!(f, "actuator.{l}.g13"),
            SceneKey::Laminate(k) => write!(f, "actuator.laminate.{k}"),
            SceneKey::Partition(k) => write!(f, "partition.{k}"),
            SceneKey::PartitionLength(i) => write!(f, "partition.lengths[{i}]"),
            SceneKey::Load(k) => write!(f, "load.{k}"),
            SceneKey::SolveTable => f.write_str("solve"),
            SceneKey::Solve(k) => write!(f, "solve.{k}"),
            SceneKey::Gripper(k) => write!(f, "gripper.{k}"),
            SceneKey::Grasp(k) => write!(f, "gripper.grasp.{k}"),
            SceneKey::Calibration(k) => write!(f, "calibration.{k}"),
        }
    }
}

macro_rules! into_key {
    ($($leaf:ident => $variant:ident),+ $(,)?) => {
        $(impl From<$leaf> for SceneKey {
            fn from(k: $leaf) -> SceneKey {
                SceneKey::$variant(k)
            }
        })+
    };
}

into_key!(
    ModelKey => Model,
    GeometryKey => Geometry,
    ChannelKey => Channel,
    PaperRibKey => PaperRib,
    PemcKey => Pemc,
    PartitionKey => Partition,
    LoadKey => Load,
    SolveKey => Solve,
    GripperKey => Gripper,
    GraspKey => Grasp,
);

#[cfg(test)]
impl SceneKey {
    /// Every key (list entries at index 0).
    pub(crate) fn all() -> Vec<SceneKey> {
        let mut keys: Vec<SceneKey> = Vec::new();
        keys.extend(ModelKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(GeometryKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(ChannelKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend([SceneKey::Ribs, SceneKey::RibsKind, SceneKey::RibsList]);
        keys.extend(PaperRibKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(RibKey::ALL.iter().map(|&k| SceneKey::RibEntry(0, k)));
        keys.extend([SceneKey::ClRibs, SceneKey::ClRibsList]);
        keys.extend(ClRibKey::ALL.iter().map(|&k| SceneKey::ClRibEntry(0, k)));
        for &l in Lamina::ALL {
            keys.push(SceneKey::MaterialKind(l));
            keys.extend(Elastic::ALL.iter().map(|&k| SceneKey::Material(l, k)));
        }
        keys.extend(PemcKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(ShearLayer::ALL.iter().map(|&l| SceneKey::ShearModulus(l)));
        keys.extend(LaminateKey::ALL.iter().map(|&k| SceneKey::Laminate(k)));
        keys.extend(PartitionKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.push(SceneKey::PartitionLength(0));
        keys.extend(LoadKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.push(SceneKey::SolveTable);
        keys.extend(SolveKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(GripperKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(GraspKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(CALIBRATION_KEYS.iter().map(|&k| SceneKey::Calibration(k)));
        keys
    }
}

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
