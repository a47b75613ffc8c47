//! The layers' materials: linear laminae (isotropic or orthotropic) and
//! their plane-stress Q's, the prestressed layer with its axial law, the
//! transverse shear data, and the range every modulus must lie in.

use crate::error::{finite, positive, require, InputError};
use crate::field::{Elastic, Field, Lamina, PemcKey};
use crate::model::PsiParams;

/// The range of every modulus (MPa: Young's moduli and the prestressed
/// law's constants in magnitude; a transverse shear modulus has the
/// ceiling only): from 1 Pa, far below the softest elastomer, to 10 TPa,
/// beyond diamond's 1.2 TPa. Outside it the solver's stiffness scale
/// under- or overflows.
pub const MODULUS_RANGE_MPA: (f64, f64) = (1e-6, 1e7);

/// Fails unless `value` is a modulus in [`MODULUS_RANGE_MPA`].
pub(super) fn modulus(field: Field, value: f64) -> Result<(), InputError> {
    positive(field.clone(), value)?;
    let (lo, hi) = MODULUS_RANGE_MPA;
    require((lo..=hi).contains(&value), field, value, || {
        format!("must lie in [{lo:e}, {hi:e}] MPa (1 Pa to 10 TPa)")
    })
}

/// Plane-stress reduced stiffnesses (MPa) of a lamina, with X = 1, Y = 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneStress {
    pub q11: f64,
    pub q12: f64,
    pub q22: f64,
}

/// An isotropic linear-elastic material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Isotropic {
    /// Young's modulus (MPa).
    pub e: f64,
    /// Poisson's ratio, in [0, 0.5).
    pub nu: f64,
}

impl Isotropic {
    /// Q11 = Q22 = E/(1-nu^2), Q12 = nu E/(1-nu^2): the orthotropic
    /// formulas with E1 = E2.
    pub fn q(&self) -> PlaneStress {
        Orthotropic {
            e1: self.e,
            e2: self.e,
            nu12: self.nu,
        }
        .q()
    }

    pub(super) fn validate(&self, l: Lamina) -> Result<(), InputError> {
        modulus(Field::Material(l, Elastic::E), self.e)?;
        let field = Field::Material(l, Elastic::Nu);
        finite(field.clone(), self.nu)?;
        require((0.0..0.5).contains(&self.nu), field, self.nu, || {
            "must lie in [0, 0.5)".into()
        })
    }
}

/// An orthotropic linear-elastic lamina with axes X (1) and Y (2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Orthotropic {
    /// Young's modulus along X (MPa).
    pub e1: f64,
    /// Young's modulus along Y (MPa).
    pub e2: f64,
    /// Major Poisson's ratio (strain in Y from stress in X).
    pub nu12: f64,
}

impl Orthotropic {
    /// Minor Poisson's ratio nu21 = nu12 E2 / E1.
    pub fn nu21(&self) -> f64 {
        self.nu12 * self.e2 / self.e1
    }

    /// Q11 = E1/D, Q22 = E2/D, Q12 = nu12 E2/D with D = 1 - nu12 nu21.
    pub fn q(&self) -> PlaneStress {
        let d = 1.0 - self.nu12 * self.nu21();
        PlaneStress {
            q11: self.e1 / d,
            q12: self.nu12 * self.e2 / d,
            q22: self.e2 / d,
        }
    }

    pub(super) fn validate(&self, l: Lamina) -> Result<(), InputError> {
        modulus(Field::Material(l, Elastic::E1), self.e1)?;
        modulus(Field::Material(l, Elastic::E2), self.e2)?;
        let field = Field::Material(l, Elastic::Nu12);
        finite(field.clone(), self.nu12)?;
        let d = 1.0 - self.nu12 * self.nu21();
        require(d > 0.0, field, self.nu12, || {
            format!(
                "1 - nu12 nu21 = {d} must be positive (nu21 = nu12 E2/E1 = {})",
                self.nu21()
            )
        })
    }
}

/// The material of a linear lamina.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    Isotropic(Isotropic),
    Orthotropic(Orthotropic),
}

impl Material {
    /// The plane-stress reduced stiffnesses.
    pub fn q(&self) -> PlaneStress {
        match self {
            Material::Isotropic(m) => m.q(),
            Material::Orthotropic(m) => m.q(),
        }
    }

    pub(super) fn validate(&self, l: Lamina) -> Result<(), InputError> {
        match self {
            Material::Isotropic(m) => m.validate(l),
            Material::Orthotropic(m) => m.validate(l),
        }
    }

    /// The transverse shear modulus G13 (x-z) a lamina of this material
    /// takes when none is given: E / (2 (1 + nu)) of an isotropic
    /// material, and the same with E1 and nu12 for an orthotropic one
    /// (its shear across the thickness along X).
    pub fn default_g13(&self) -> f64 {
        match self {
            Material::Isotropic(m) => m.e / (2.0 * (1.0 + m.nu)),
            Material::Orthotropic(m) => m.e1 / (2.0 * (1.0 + m.nu12)),
        }
    }
}

impl From<Isotropic> for Material {
    fn from(m: Isotropic) -> Self {
        Material::Isotropic(m)
    }
}

impl From<Orthotropic> for Material {
    fn from(m: Orthotropic) -> Self {
        Material::Orthotropic(m)
    }
}

/// The prestressed layer's axial law: the constants of the spec's
/// `law psi(s)` (for the paper's element,
/// psi(s) = p1/2 s^2 - p2/3 s^3 + p3/4 s^4 - p4/5 s^5 in MPa, a fit of a
/// uniaxial test; psi'(s) is the axial stress). The law itself, and its
/// derivatives, are generated from the spec ([`crate::model::Energy::psi`]).
pub type PsiLaw = PsiParams;

impl Default for PsiParams {
    /// The paper's fit (printed in Pa as 1.598e6, ...).
    fn default() -> Self {
        PsiParams {
            p1: 1.598,
            p2: 2.306,
            p3: 2.29,
            p4: 0.698,
        }
    }
}

impl PsiParams {
    /// The constants, in order.
    pub fn to_array(&self) -> [f64; 4] {
        [self.p1, self.p2, self.p3, self.p4]
    }

    pub(super) fn validate(&self) -> Result<(), InputError> {
        let hi = MODULUS_RANGE_MPA.1;
        for (&k, pk) in PemcKey::ALL[2..].iter().zip(self.to_array()) {
            finite(Field::Pemc(k), pk)?;
            require(pk.abs() <= hi, Field::Pemc(k), pk, || {
                format!("must lie in [-{hi:e}, {hi:e}] MPa")
            })?;
        }
        modulus(Field::Pemc(PemcKey::P1), self.p1)
    }
}

/// The prestressed EMC: nonlinear along X (stretched by `eps0` before
/// bonding), linear along Y.
///
/// There is no Poisson coupling: the law only defines the X response, so
/// the layer stores W = psi(eps0 + eps_x) + 1/2 Q22 eps_y^2 with
/// Q22 = E2 (the paper's nu = 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prestressed {
    /// Young's modulus along Y (MPa).
    pub e2: f64,
    /// Axial law along X.
    pub law: PsiLaw,
    /// Prestrain along X.
    pub eps0: f64,
}

impl Prestressed {
    /// The Y stiffness of the 1/2 Q22 eps_y^2 term: E2 (no coupling).
    pub fn q22(&self) -> f64 {
        self.e2
    }
}

impl Default for Prestressed {
    /// E2 = 250 MPa, the paper's law, eps0 = 0.25.
    fn default() -> Self {
        Prestressed {
            e2: 250.0,
            law: PsiLaw::default(),
            eps0: 0.25,
        }
    }
}

/// The laminate's transverse shear data (docs/model.md section 4.6): read
/// only by shear-deformable element models (`energy-spec/shear.spec`);
/// the paper's element ignores them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TransverseShear {
    /// The shear correction factor ks of the section (default 5/6, a
    /// rectangular section's).
    pub correction: f64,
    /// G13 (MPa) of the constraining layer, the regular EMC, the fluidic
    /// layer (and the ribs) and the prestressed EMC, in
    /// [`ShearLayer::ALL`](crate::field::ShearLayer::ALL)'s order; `None` takes the default from the
    /// layer's E and nu ([`Material::default_g13`]; the prestressed
    /// layer's p1 / 2, its initial modulus with the paper's nu = 0).
    pub g13: [Option<f64>; 4],
}

impl Default for TransverseShear {
    fn default() -> Self {
        TransverseShear {
            correction: 5.0 / 6.0,
            g13: [None; 4],
        }
    }
}
