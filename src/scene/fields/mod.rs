//! Scene keys in messages.
//!
//! [`SceneKey`] names every key of the file format by its place in the
//! schema; the resolution validates through it, so its own errors name
//! scene keys directly. The library's validating constructors name their
//! fields in the library's terms (`load.pressure` in MPa, `grasp.beta` in
//! rad, ...): [`LibField`] has one variant per library field the scene can
//! trigger, and [`LibField::scene_key`] says which scene key it is, with
//! the value in the key's unit. [`warning_text`] writes warnings the same
//! way.

use std::fmt;

use crate::error::{self, InputError, Warning};
use crate::solve_error::SolveError;

/// Defines an enum of leaf names with `ALL` and `name()` (the key as
/// written in the file).
macro_rules! names {
    ($(#[$meta:meta])* $name:ident { $($variant:ident => $text:literal),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub(crate) enum $name {
            $($variant),+
        }

        impl $name {
            /// Every variant, in schema order.
            #[allow(dead_code)] // some are only walked by the tests
            pub(crate) const ALL: &'static [$name] = &[$($name::$variant),+];

            /// The key as written in a scene file.
            pub(crate) fn name(self) -> &'static str {
                match self {
                    $($name::$variant => $text),+
                }
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}

names!(
    /// `[model]`.
    ModelKey { Name => "name" }
);
names!(
    /// `[actuator.geometry]`.
    GeometryKey { Lx => "lx", Ly => "ly", Lc => "lc", H => "h", H1 => "h1", H2 => "h2", H3 => "h3" }
);
names!(
    /// `[actuator.channel]`.
    ChannelKey { Cx => "cx", Cy => "cy", H3a => "h3a", H3b => "h3b" }
);
names!(
    /// The keys of `[actuator.ribs]` with `kind = "paper"`.
    PaperRibKey { W1 => "w1", W2 => "w2", T => "t" }
);
names!(
    /// The keys of one entry of `actuator.ribs.list`.
    RibEntryKey { X0 => "x0", X1 => "x1", Width => "width" }
);
names!(
    /// The linear laminae with a `[actuator.<layer>]` material table.
    Layer { Cl => "cl", Emc => "emc", Fluidic => "fluidic" }
);
names!(
    /// The elastic constants of a material table.
    ElasticKey { E => "e", Nu => "nu", E1 => "e1", E2 => "e2", Nu12 => "nu12" }
);
names!(
    /// `[actuator.pemc]`.
    PemcKey { Eps0 => "eps0", E2 => "e2", P1 => "p1", P2 => "p2", P3 => "p3", P4 => "p4" }
);
names!(
    /// `[partition]`.
    PartitionKey { Elements => "elements", Lengths => "lengths", TipTolMm => "tip_tol_mm" }
);
names!(
    /// `[load]`.
    LoadKey { PressureKpa => "pressure_kpa", Kappa => "kappa", Fx => "fx", Fz => "fz" }
);
names!(
    /// `[solve]`.
    SolveKey {
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
    GripperKey {
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
    GraspKey {
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
    RibEntry(usize, RibEntryKey),
    /// `actuator.<layer>.kind` (checked by the parser).
    #[allow(dead_code)]
    MaterialKind(Layer),
    /// `actuator.<layer>.<key>`.
    Material(Layer, ElasticKey),
    Pemc(PemcKey),
    Partition(PartitionKey),
    /// `partition.lengths[i]`.
    PartitionLength(usize),
    Load(LoadKey),
    /// `solve` as a whole (settings that do not fit together).
    SolveTable,
    Solve(SolveKey),
    Gripper(GripperKey),
    Grasp(GraspKey),
}

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
            SceneKey::MaterialKind(l) => write!(f, "actuator.{l}.kind"),
            SceneKey::Material(l, k) => write!(f, "actuator.{l}.{k}"),
            SceneKey::Pemc(k) => write!(f, "actuator.pemc.{k}"),
            SceneKey::Partition(k) => write!(f, "partition.{k}"),
            SceneKey::PartitionLength(i) => write!(f, "partition.lengths[{i}]"),
            SceneKey::Load(k) => write!(f, "load.{k}"),
            SceneKey::SolveTable => f.write_str("solve"),
            SceneKey::Solve(k) => write!(f, "solve.{k}"),
            SceneKey::Gripper(k) => write!(f, "gripper.{k}"),
            SceneKey::Grasp(k) => write!(f, "gripper.grasp.{k}"),
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
        keys.extend(RibEntryKey::ALL.iter().map(|&k| SceneKey::RibEntry(0, k)));
        for &l in Layer::ALL {
            keys.push(SceneKey::MaterialKind(l));
            keys.extend(ElasticKey::ALL.iter().map(|&k| SceneKey::Material(l, k)));
        }
        keys.extend(PemcKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(PartitionKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.push(SceneKey::PartitionLength(0));
        keys.extend(LoadKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.push(SceneKey::SolveTable);
        keys.extend(SolveKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(GripperKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys.extend(GraspKey::ALL.iter().map(|&k| SceneKey::from(k)));
        keys
    }
}

// ------------------------------------------------------------ checks in scene keys

/// Fails with `NotFinite` unless `value` is finite.
pub(super) fn finite(key: impl Into<SceneKey>, value: f64) -> Result<f64, InputError> {
    error::finite(&key.into().to_string(), value)
}

/// Fails unless `value` is finite and strictly positive.
pub(super) fn positive(key: impl Into<SceneKey>, value: f64) -> Result<f64, InputError> {
    error::positive(&key.into().to_string(), value)
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
            field: key.into().to_string(),
            value,
            rule: rule.into(),
        })
    }
}

/// An `Inconsistent` error at `key`.
pub(super) fn inconsistent(key: impl Into<SceneKey>, rule: impl Into<String>) -> InputError {
    InputError::Inconsistent {
        field: key.into().to_string(),
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

/// A field the library names in its own terms, in an error the scene can
/// trigger: one variant per library field ([`LibField::name`] is the
/// library's spelling).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LibField {
    /// `actuator.geometry.<key>` ([`crate::Actuator::new`]).
    Geometry(GeometryKey),
    /// `actuator.channel.<key>`.
    Channel(ChannelKey),
    /// `actuator.ribs.w1`, `w2`, `t`.
    PaperRib(PaperRibKey),
    /// `actuator.ribs[i].<key>`: an explicit rib.
    Rib(usize, RibEntryKey),
    /// `actuator.ribs`: the ribs overlap.
    Ribs,
    /// `actuator.<layer>.<key>`.
    Material(Layer, ElasticKey),
    /// `actuator.pemc.eps0`, `actuator.pemc.e2`, `actuator.pemc.law.p1..p4`.
    Pemc(PemcKey),
    /// `partition.n` ([`crate::Partition::equal`], [`crate::Plan::TipTolerance`]).
    PartitionN,
    /// `partition.lx`.
    PartitionLx,
    /// `partition.lengths`.
    PartitionLengths,
    /// `partition.lengths (sum)`.
    PartitionLengthsSum,
    /// `partition.lengths[i]`.
    PartitionLength(usize),
    /// `partition.max_length` ([`crate::Partition::material`], the automatic partition).
    PartitionMaxLength,
    /// `tip_tol_mm` ([`crate::Plan::TipTolerance`]).
    TipTolMm,
    /// `load.pressure` (MPa).
    LoadPressure,
    /// `load.kappa`.
    LoadKappa,
    /// `load.fx`.
    LoadFx,
    /// `load.fz`.
    LoadFz,
    /// `solve` (the Newton settings together).
    Solve,
    /// `solve.rtol`.
    SolveRtol,
    /// `solve.max_iter`.
    SolveMaxIter,
    /// `solve.samples_per_element`.
    SolveSamplesPerElement,
    /// `solve.max_step`.
    SolveMaxStep,
    /// `gripper.mounting_angle` (rad; [`crate::Gripper::new`]).
    GripperMountingAngle,
    /// `gripper.mu`.
    GripperMu,
    /// `gripper.fingers`.
    GripperFingers,
    /// `gripper.finger` (a finger without elements).
    GripperFinger,
    /// `gripper.overlap`.
    GripperOverlap,
    /// `gripper.palm`.
    GripperPalm,
    /// `grasp.pressure_kpa` (the grasp solves).
    GraspPressureKpa,
    /// `grasp.size`.
    GraspSize,
    /// `grasp.beta` (rad).
    GraspBeta,
    /// `grasp.friction`.
    GraspFriction,
    /// `sphere.radius`.
    SphereRadius,
    /// `sphere.beta` (rad).
    SphereBeta,
    /// `sphere.lift`.
    SphereLift,
}

impl LibField {
    /// Every field whose name has no index.
    const FIXED: &'static [LibField] = &[
        LibField::Ribs,
        LibField::PartitionN,
        LibField::PartitionLx,
        LibField::PartitionLengths,
        LibField::PartitionLengthsSum,
        LibField::PartitionMaxLength,
        LibField::TipTolMm,
        LibField::LoadPressure,
        LibField::LoadKappa,
        LibField::LoadFx,
        LibField::LoadFz,
        LibField::Solve,
        LibField::SolveRtol,
        LibField::SolveMaxIter,
        LibField::SolveSamplesPerElement,
        LibField::SolveMaxStep,
        LibField::GripperMountingAngle,
        LibField::GripperMu,
        LibField::GripperFingers,
        LibField::GripperFinger,
        LibField::GripperOverlap,
        LibField::GripperPalm,
        LibField::GraspPressureKpa,
        LibField::GraspSize,
        LibField::GraspBeta,
        LibField::GraspFriction,
        LibField::SphereRadius,
        LibField::SphereBeta,
        LibField::SphereLift,
    ];

    /// Every field: the fixed ones, every actuator key, and the indexed
    /// ones at index `index`.
    pub(crate) fn all(index: usize) -> Vec<LibField> {
        let mut all = Vec::new();
        all.extend(GeometryKey::ALL.iter().map(|&k| LibField::Geometry(k)));
        all.extend(ChannelKey::ALL.iter().map(|&k| LibField::Channel(k)));
        all.extend(PaperRibKey::ALL.iter().map(|&k| LibField::PaperRib(k)));
        all.extend(RibEntryKey::ALL.iter().map(|&k| LibField::Rib(index, k)));
        for &l in Layer::ALL {
            all.extend(ElasticKey::ALL.iter().map(|&k| LibField::Material(l, k)));
        }
        all.extend(PemcKey::ALL.iter().map(|&k| LibField::Pemc(k)));
        all.push(LibField::PartitionLength(index));
        all.extend_from_slice(LibField::FIXED);
        all
    }

    /// The field's name as the library writes it.
    pub(crate) fn name(self) -> String {
        let fixed = match self {
            LibField::Geometry(k) => return format!("actuator.geometry.{k}"),
            LibField::Channel(k) => return format!("actuator.channel.{k}"),
            LibField::PaperRib(k) => return format!("actuator.ribs.{k}"),
            LibField::Rib(i, k) => return format!("actuator.ribs[{i}].{k}"),
            LibField::Material(l, k) => return format!("actuator.{l}.{k}"),
            LibField::Pemc(k @ (PemcKey::Eps0 | PemcKey::E2)) => {
                return format!("actuator.pemc.{k}")
            }
            LibField::Pemc(k) => return format!("actuator.pemc.law.{k}"),
            LibField::PartitionLength(i) => return format!("partition.lengths[{i}]"),
            LibField::Ribs => "actuator.ribs",
            LibField::PartitionN => "partition.n",
            LibField::PartitionLx => "partition.lx",
            LibField::PartitionLengths => "partition.lengths",
            LibField::PartitionLengthsSum => "partition.lengths (sum)",
            LibField::PartitionMaxLength => "partition.max_length",
            LibField::TipTolMm => "tip_tol_mm",
            LibField::LoadPressure => "load.pressure",
            LibField::LoadKappa => "load.kappa",
            LibField::LoadFx => "load.fx",
            LibField::LoadFz => "load.fz",
            LibField::Solve => "solve",
            LibField::SolveRtol => "solve.rtol",
            LibField::SolveMaxIter => "solve.max_iter",
            LibField::SolveSamplesPerElement => "solve.samples_per_element",
            LibField::SolveMaxStep => "solve.max_step",
            LibField::GripperMountingAngle => "gripper.mounting_angle",
            LibField::GripperMu => "gripper.mu",
            LibField::GripperFingers => "gripper.fingers",
            LibField::GripperFinger => "gripper.finger",
            LibField::GripperOverlap => "gripper.overlap",
            LibField::GripperPalm => "gripper.palm",
            LibField::GraspPressureKpa => "grasp.pressure_kpa",
            LibField::GraspSize => "grasp.size",
            LibField::GraspBeta => "grasp.beta",
            LibField::GraspFriction => "grasp.friction",
            LibField::SphereRadius => "sphere.radius",
            LibField::SphereBeta => "sphere.beta",
            LibField::SphereLift => "sphere.lift",
        };
        fixed.to_string()
    }

    /// The field of a library name (`None`: not a field the scene can
    /// trigger). Indexed names (`partition.lengths[2]`,
    /// `actuator.ribs[0].x1`) carry their index.
    pub(crate) fn from_name(name: &str) -> Option<LibField> {
        let index = match name.split_once('[') {
            None => None,
            Some((_, rest)) => {
                let (digits, _) = rest.split_once(']')?;
                if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
                    return None;
                }
                Some(digits.parse().ok()?)
            }
        };
        LibField::all(index.unwrap_or(0))
            .into_iter()
            .find(|f| f.name() == name)
    }

    /// The scene key the field is given by.
    pub(crate) fn scene_key(self) -> SceneKey {
        match self {
            LibField::Geometry(k) => SceneKey::Geometry(k),
            LibField::Channel(k) => SceneKey::Channel(k),
            LibField::PaperRib(k) => SceneKey::PaperRib(k),
            LibField::Rib(i, k) => SceneKey::RibEntry(i, k),
            LibField::Ribs => SceneKey::Ribs,
            LibField::Material(l, k) => SceneKey::Material(l, k),
            LibField::Pemc(k) => SceneKey::Pemc(k),
            // the element count; the automatic partition's pieces; a
            // finger without elements
            LibField::PartitionN | LibField::PartitionMaxLength | LibField::GripperFinger => {
                SceneKey::Partition(PartitionKey::Elements)
            }
            LibField::PartitionLx => SceneKey::Geometry(GeometryKey::Lx),
            LibField::PartitionLengths | LibField::PartitionLengthsSum => {
                SceneKey::Partition(PartitionKey::Lengths)
            }
            LibField::PartitionLength(i) => SceneKey::PartitionLength(i),
            LibField::TipTolMm => SceneKey::Partition(PartitionKey::TipTolMm),
            LibField::LoadPressure => SceneKey::Load(LoadKey::PressureKpa),
            LibField::LoadKappa => SceneKey::Load(LoadKey::Kappa),
            LibField::LoadFx => SceneKey::Load(LoadKey::Fx),
            LibField::LoadFz => SceneKey::Load(LoadKey::Fz),
            LibField::Solve => SceneKey::SolveTable,
            LibField::SolveRtol => SceneKey::Solve(SolveKey::Rtol),
            LibField::SolveMaxIter => SceneKey::Solve(SolveKey::MaxIter),
            LibField::SolveSamplesPerElement => SceneKey::Solve(SolveKey::SamplesPerElement),
            LibField::SolveMaxStep => SceneKey::Solve(SolveKey::MaxStep),
            LibField::GripperMountingAngle => SceneKey::Gripper(GripperKey::MountingAngleDeg),
            LibField::GripperMu => SceneKey::Gripper(GripperKey::Mu),
            LibField::GripperFingers => SceneKey::Gripper(GripperKey::Fingers),
            LibField::GripperOverlap => SceneKey::Gripper(GripperKey::OverlapMm),
            LibField::GripperPalm => SceneKey::Gripper(GripperKey::PalmMm),
            LibField::GraspPressureKpa => SceneKey::Grasp(GraspKey::PressureKpa),
            LibField::GraspSize => SceneKey::Grasp(GraspKey::DMm),
            LibField::GraspBeta | LibField::SphereBeta => SceneKey::Grasp(GraspKey::BetaDeg),
            LibField::GraspFriction => SceneKey::Grasp(GraspKey::FrictionN),
            LibField::SphereRadius => SceneKey::Grasp(GraspKey::RMm),
            LibField::SphereLift => SceneKey::Grasp(GraspKey::LiftN),
        }
    }

    /// A value of the field in the unit of its scene key (MPa to kPa, rad
    /// to degrees).
    pub(crate) fn scene_value(self, value: f64) -> f64 {
        match self {
            LibField::LoadPressure => value * 1e3,
            LibField::GripperMountingAngle | LibField::GraspBeta | LibField::SphereBeta => {
                degrees(value)
            }
            _ => value,
        }
    }
}

/// A library error in the scene's terms: the field named by its scene
/// key, the value in the key's unit. Errors on fields the scene cannot
/// trigger stay as they are.
pub fn scene_input(e: InputError) -> InputError {
    let Some(f) = LibField::from_name(e.field()) else {
        return e;
    };
    e.renamed(f.scene_key().to_string(), |v| f.scene_value(v))
}

/// A library solve error in the scene's terms: input errors as in
/// [`scene_input`], and the target of a target not reached. Front ends
/// whose own names follow the scene keys (the CLI's flags) start from it.
pub fn scene_solve(e: SolveError) -> SolveError {
    match e {
        SolveError::Input(i) => SolveError::Input(scene_input(i)),
        SolveError::TargetNotReached {
            target,
            value,
            reached,
            detail,
        } => match LibField::from_name(&target) {
            Some(f) => SolveError::TargetNotReached {
                target: f.scene_key().to_string(),
                value: f.scene_value(value),
                reached,
                detail,
            },
            None => SolveError::TargetNotReached {
                target,
                value,
                reached,
                detail,
            },
        },
        SolveError::NotOnPath {
            target,
            value,
            detail,
        } => match LibField::from_name(&target) {
            Some(f) => SolveError::NotOnPath {
                target: f.scene_key().to_string(),
                value: f.scene_value(value),
                detail,
            },
            None => SolveError::NotOnPath {
                target,
                value,
                detail,
            },
        },
        other => other,
    }
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
