//! The field an error names, typed: one variant per field of the
//! library's input ([`Field`]), with the actuator's keys, the laminae and
//! their elastic constants it is made of. A front end (the scene, the
//! CLI, Python) maps a field to the name the user wrote by a `match`.
//! This module depends on nothing else of the crate.

use std::borrow::Cow;
use std::fmt;

/// Defines an enum of leaf names with `ALL` and `name()` (the key as
/// written in a scene file).
macro_rules! names {
    ($(#[$meta:meta])* $vis:vis $name:ident { $($(#[$vmeta:meta])* $variant:ident => $text:literal),+ $(,)? }) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        $vis enum $name {
            $($(#[$vmeta])* $variant),+
        }

        impl $name {
            /// Every variant, in schema order.
            #[allow(dead_code)] // some are only walked by the tests
            $vis const ALL: &'static [$name] = &[$($name::$variant),+];

            /// The key as written in a scene file.
            $vis fn name(self) -> &'static str {
                match self {
                    $($name::$variant => $text),+
                }
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}
pub(crate) use names;

names!(
    /// `actuator.geometry.<key>`.
    pub GeometryKey { Lx => "lx", Ly => "ly", Lc => "lc", H => "h", H1 => "h1", H2 => "h2", H3 => "h3" }
);
names!(
    /// `actuator.channel.<key>`.
    pub ChannelKey { Cx => "cx", Cy => "cy", H3a => "h3a", H3b => "h3b" }
);
names!(
    /// `actuator.ribs.<key>` of the paper's rib layout.
    pub PaperRibKey { W1 => "w1", W2 => "w2", T => "t" }
);
names!(
    /// A key of one explicit rib.
    pub RibKey { X0 => "x0", X1 => "x1", Width => "width" }
);
names!(
    /// A linear lamina with its own material table (`actuator.<layer>`),
    /// top to bottom.
    pub Lamina {
        /// The constraining layer, `actuator.cl`.
        Cl => "cl",
        /// The regular EMC, `actuator.emc`.
        Emc => "emc",
        /// The fluidic layer (and the ribs), `actuator.fluidic`.
        Fluidic => "fluidic",
    }
);
names!(
    /// An elastic constant of a lamina's material: `e`, `nu` of an
    /// isotropic material, `e1`, `e2`, `nu12` of an orthotropic one.
    pub Elastic {
        /// Young's modulus of an isotropic material (MPa).
        E => "e",
        /// Poisson's ratio of an isotropic material.
        Nu => "nu",
        /// Young's modulus along X of an orthotropic material (MPa).
        E1 => "e1",
        /// Young's modulus along Y of an orthotropic material (MPa).
        E2 => "e2",
        /// Major Poisson's ratio of an orthotropic material.
        Nu12 => "nu12",
    }
);
names!(
    /// `actuator.pemc.<key>`: the prestrain, the Y modulus, the psi law's
    /// coefficients.
    pub PemcKey { Eps0 => "eps0", E2 => "e2", P1 => "p1", P2 => "p2", P3 => "p3", P4 => "p4" }
);

names!(
    /// `refinement.<key>`: a refinement plan's.
    pub RefinementKey { Start => "start", Levels => "levels", Extrapolate => "extrapolate" }
);

/// A field of the library's input, as errors name it. Displays as the
/// library writes it (`actuator.geometry.h1`, `partition.lengths[2]`,
/// `load.pressure` in MPa, `grasp.beta` in rad).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Field {
    Geometry(GeometryKey),
    Channel(ChannelKey),
    PaperRib(PaperRibKey),
    /// `actuator.ribs[i].<key>`: an explicit rib.
    Rib(usize, RibKey),
    /// `actuator.ribs`: the ribs together.
    Ribs,
    Material(Lamina, Elastic),
    /// `actuator.pemc.eps0`, `actuator.pemc.e2`, `actuator.pemc.law.p1..p4`.
    Pemc(PemcKey),
    /// `partition.n`: the number of equal elements.
    PartitionN,
    PartitionLx,
    PartitionLengths,
    /// `partition.lengths (sum)`.
    PartitionLengthsSum,
    /// `partition.lengths[i]`.
    PartitionLength(usize),
    /// `partition.max_length` (the material and automatic partitions).
    PartitionMaxLength,
    TipTolMm,
    Refinement(RefinementKey),
    /// `samples_per_element` (of a solution's curve).
    SamplesPerElement,
    /// `load.pressure` (MPa).
    LoadPressure,
    LoadKappa,
    LoadFx,
    LoadFz,
    /// `solve`: the Newton settings together.
    Solve,
    SolveRtol,
    SolveMaxIter,
    SolveSamplesPerElement,
    SolveMaxStep,
    /// `gripper.mounting_angle` (rad).
    GripperMountingAngle,
    GripperMu,
    GripperFingers,
    /// `gripper.finger`: a finger without elements.
    GripperFinger,
    GripperOverlap,
    GripperPalm,
    GraspPressureKpa,
    GraspSize,
    /// `grasp.beta` (rad).
    GraspBeta,
    GraspFriction,
    GraspForce,
    SphereRadius,
    /// `sphere.beta` (rad).
    SphereBeta,
    SphereLift,
    SphereSamples,
    /// `guess`: a solve's starting coefficients.
    Guess,
    /// `coefficients`: a solution's coefficients.
    Coefficients,
    /// A name written out: a front end's (a scene key, a command-line
    /// flag, a Python argument), or a library argument no front end
    /// renames (`affine.angle`, `design.step`, `target.value`).
    Key(Cow<'static, str>),
}

impl Field {
    /// A field named by `name`.
    pub const fn key(name: &'static str) -> Field {
        Field::Key(Cow::Borrowed(name))
    }
}

impl From<&'static str> for Field {
    fn from(name: &'static str) -> Field {
        Field::key(name)
    }
}

impl From<String> for Field {
    fn from(name: String) -> Field {
        Field::Key(Cow::Owned(name))
    }
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let text = match self {
            Field::Geometry(k) => return write!(f, "actuator.geometry.{k}"),
            Field::Channel(k) => return write!(f, "actuator.channel.{k}"),
            Field::PaperRib(k) => return write!(f, "actuator.ribs.{k}"),
            Field::Rib(i, k) => return write!(f, "actuator.ribs[{i}].{k}"),
            Field::Material(l, k) => return write!(f, "actuator.{l}.{k}"),
            Field::Pemc(k @ (PemcKey::Eps0 | PemcKey::E2)) => {
                return write!(f, "actuator.pemc.{k}")
            }
            Field::Pemc(k) => return write!(f, "actuator.pemc.law.{k}"),
            Field::PartitionLength(i) => return write!(f, "partition.lengths[{i}]"),
            Field::Refinement(k) => return write!(f, "refinement.{k}"),
            Field::Key(name) => name,
            Field::Ribs => "actuator.ribs",
            Field::PartitionN => "partition.n",
            Field::PartitionLx => "partition.lx",
            Field::PartitionLengths => "partition.lengths",
            Field::PartitionLengthsSum => "partition.lengths (sum)",
            Field::PartitionMaxLength => "partition.max_length",
            Field::TipTolMm => "tip_tol_mm",
            Field::SamplesPerElement => "samples_per_element",
            Field::LoadPressure => "load.pressure",
            Field::LoadKappa => "load.kappa",
            Field::LoadFx => "load.fx",
            Field::LoadFz => "load.fz",
            Field::Solve => "solve",
            Field::SolveRtol => "solve.rtol",
            Field::SolveMaxIter => "solve.max_iter",
            Field::SolveSamplesPerElement => "solve.samples_per_element",
            Field::SolveMaxStep => "solve.max_step",
            Field::GripperMountingAngle => "gripper.mounting_angle",
            Field::GripperMu => "gripper.mu",
            Field::GripperFingers => "gripper.fingers",
            Field::GripperFinger => "gripper.finger",
            Field::GripperOverlap => "gripper.overlap",
            Field::GripperPalm => "gripper.palm",
            Field::GraspPressureKpa => "grasp.pressure_kpa",
            Field::GraspSize => "grasp.size",
            Field::GraspBeta => "grasp.beta",
            Field::GraspFriction => "grasp.friction",
            Field::GraspForce => "grasp.force",
            Field::SphereRadius => "sphere.radius",
            Field::SphereBeta => "sphere.beta",
            Field::SphereLift => "sphere.lift",
            Field::SphereSamples => "sphere.samples",
            Field::Guess => "guess",
            Field::Coefficients => "coefficients",
        };
        f.write_str(text)
    }
}

/// A field equals the name it displays as (for tests and front ends that
/// compare with a name the user wrote).
impl PartialEq<str> for Field {
    fn eq(&self, name: &str) -> bool {
        self.to_string().as_str() == name
    }
}
