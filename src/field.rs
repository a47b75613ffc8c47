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
    /// A key of one rib on the constraining layer (`actuator.cl_ribs`).
    pub ClRibKey { X0 => "x0", X1 => "x1", Width => "width", Height => "height" }
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
    /// A layer with a transverse shear modulus, `actuator.<layer>.g13`:
    /// the three linear laminae and the prestressed EMC, top to bottom.
    pub ShearLayer { Cl => "cl", Emc => "emc", Fluidic => "fluidic", Pemc => "pemc" }
);
names!(
    /// `actuator.laminate.<key>`: options of the laminate as a whole.
    pub LaminateKey {
        /// The shear correction factor of shear-deformable models.
        ShearCorrection => "shear_correction",
        /// Plane strain across the width (default plane stress).
        PlaneStrain => "plane_strain",
    }
);

names!(
    /// `refinement.<key>`: a refinement plan's.
    pub RefinementKey { Start => "start", Levels => "levels", Extrapolate => "extrapolate" }
);

/// Defines [`Field`]: the variants with data, and the fixed ones with
/// their text ([`Field::FIXED`] lists them).
macro_rules! field {
    ($($variant:ident => $text:literal),+ $(,)?) => {
        /// A field of the library's input, as errors name it. Displays as
        /// the library writes it (`actuator.geometry.h1`,
        /// `partition.lengths[2]`, `partition.n` for the number of equal
        /// elements, `load.pressure` in MPa, `grasp.beta`, `sphere.beta` and
        /// `gripper.mounting_angle` in rad).
        #[derive(Debug, Clone, PartialEq, Eq, Hash)]
        pub enum Field {
            Geometry(GeometryKey),
            Channel(ChannelKey),
            PaperRib(PaperRibKey),
            /// `actuator.ribs.list[i].<key>`: an explicit rib (the scene key).
            Rib(usize, RibKey),
            /// `actuator.cl_ribs.list[i].<key>`: a rib on the constraining layer.
            ClRib(usize, ClRibKey),
            Material(Lamina, Elastic),
            /// `actuator.pemc.eps0`, `e2`, `actuator.pemc.law.p1..p4`.
            Pemc(PemcKey),
            /// `actuator.<layer>.g13`: a layer's transverse shear modulus.
            ShearModulus(ShearLayer),
            /// `actuator.laminate.<key>`.
            Laminate(LaminateKey),
            /// `partition.lengths[i]`.
            PartitionLength(usize),
            Refinement(RefinementKey),
            /// A name written out: a front end's (a scene key, a
            /// command-line flag, a Python argument), or a library
            /// argument no front end renames (`affine.angle`,
            /// `design.step`, `target.value`).
            Key(Cow<'static, str>),
            $(#[doc = concat!("`", $text, "`.")] $variant),+
        }

        impl Field {
            /// Every field without data.
            pub const FIXED: &'static [Field] = &[$(Field::$variant),+];

            fn fixed_name(&self) -> &'static str {
                match self {
                    $(Field::$variant => $text,)+
                    _ => "",
                }
            }
        }
    };
}

field! {
    Ribs => "actuator.ribs",
    ClRibs => "actuator.cl_ribs",
    PartitionN => "partition.n",
    PartitionLx => "partition.lx",
    PartitionLengths => "partition.lengths",
    PartitionLengthsSum => "partition.lengths (sum)",
    PartitionMaxLength => "partition.max_length",
    TipTolMm => "tip_tol_mm",
    SamplesPerElement => "samples_per_element",
    LoadPressure => "load.pressure",
    LoadKappa => "load.kappa",
    LoadFx => "load.fx",
    LoadFz => "load.fz",
    Solve => "solve",
    SolveRtol => "solve.rtol",
    SolveMaxIter => "solve.max_iter",
    SolveSamplesPerElement => "solve.samples_per_element",
    SolveMaxStep => "solve.max_step",
    GripperMountingAngle => "gripper.mounting_angle",
    GripperMu => "gripper.mu",
    GripperFingers => "gripper.fingers",
    GripperFinger => "gripper.finger",
    GripperOverlap => "gripper.overlap",
    GripperPalm => "gripper.palm",
    GraspPressureKpa => "grasp.pressure_kpa",
    GraspSize => "grasp.size",
    GraspBeta => "grasp.beta",
    GraspFriction => "grasp.friction",
    GraspForce => "grasp.force",
    SphereRadius => "sphere.radius",
    SphereBeta => "sphere.beta",
    SphereLift => "sphere.lift",
    SphereSamples => "sphere.samples",
    Guess => "guess",
    Coefficients => "coefficients",
}

impl Field {
    /// A field named by `name`.
    pub const fn key(name: &'static str) -> Field {
        Field::Key(Cow::Borrowed(name))
    }
}

impl From<String> for Field {
    fn from(name: String) -> Field {
        Field::Key(Cow::Owned(name))
    }
}

impl fmt::Display for Field {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Field::Geometry(k) => write!(f, "actuator.geometry.{k}"),
            Field::Channel(k) => write!(f, "actuator.channel.{k}"),
            Field::PaperRib(k) => write!(f, "actuator.ribs.{k}"),
            Field::Rib(i, k) => write!(f, "actuator.ribs.list[{i}].{k}"),
            Field::ClRib(i, k) => write!(f, "actuator.cl_ribs.list[{i}].{k}"),
            Field::Material(l, k) => write!(f, "actuator.{l}.{k}"),
            Field::Pemc(k @ (PemcKey::Eps0 | PemcKey::E2)) => write!(f, "actuator.pemc.{k}"),
            Field::Pemc(k) => write!(f, "actuator.pemc.law.{k}"),
            Field::ShearModulus(l) => write!(f, "actuator.{l}.g13"),
            Field::Laminate(k) => write!(f, "actuator.laminate.{k}"),
            Field::PartitionLength(i) => write!(f, "partition.lengths[{i}]"),
            Field::Refinement(k) => write!(f, "refinement.{k}"),
            Field::Key(name) => f.write_str(name),
            fixed => f.write_str(fixed.fixed_name()),
        }
    }
}

/// A field equals the name it displays as (for tests and front ends that
/// compare with a name the user wrote).
impl PartialEq<str> for Field {
    fn eq(&self, name: &str) -> bool {
        self.to_string().as_str() == name
    }
}
