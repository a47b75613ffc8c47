//! The laminate and its validated [`Actuator`]: dimensions, channel and
//! ribs, the layers' materials (`material.rs`), with the paper's defaults
//! (the table of laminae is in the module docs of [`crate::actuator`]).

use crate::error::{finite, positive, require, InputError, Warning};
use crate::field::{
    ChannelKey, ClRibKey, Field, GeometryKey, Lamina, LaminateKey, PaperRibKey, PemcKey, RibKey,
    ShearLayer,
};

use super::material::{
    modulus, Isotropic, Material, Orthotropic, PlaneStress, Prestressed, TransverseShear,
    MODULUS_RANGE_MPA,
};

/// Strain range of the uniaxial test the prestressed law was fitted to;
/// a prestrain outside it is accepted with a [`Warning`].
pub const EPS0_FIT_RANGE: (f64, f64) = (0.0, 0.6);

/// Upper bound on the number of ribs a [`RibLayout::Paper`] may generate
/// (guards against a tiny pitch allocating without bound).
pub const MAX_GENERATED_RIBS: usize = 10_000;

/// Upper bound on the number of ribs a [`RibLayout::Explicit`] may list
/// (as many as a paper layout may generate), checked before the ribs are.
pub const MAX_LISTED_RIBS: usize = MAX_GENERATED_RIBS;

/// Upper bound on the number of ribs on the constraining layer
/// ([`ActuatorParams::cl_ribs`]).
pub const MAX_CL_RIBS: usize = 10_000;

/// The range of the prestrain `eps0`: above -1 (a strain of -1 shrinks the
/// layer to nothing) and at most 10 (no elastomer stretches to eleven
/// times its length). Inside it, values outside [`EPS0_FIT_RANGE`] are
/// accepted with a warning.
pub const EPS0_RANGE: (f64, f64) = (-1.0, 10.0);

/// Dimensions of the strip (mm); z values are measured from the mid-plane.
/// A scene's `[actuator.geometry]` holds its keys
/// ([`GeometrySection`](crate::scene::GeometrySection)).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Geometry {
    /// Modelled length, root (clamp exit) to tip.
    pub lx: f64,
    /// Width.
    pub ly: f64,
    /// Clamped length: informational only, not modelled.
    pub lc: f64,
    /// Total thickness H.
    pub h: f64,
    /// Bottom of the constraining layer (top of the regular EMC).
    pub h1: f64,
    /// Bottom of the regular EMC (top of the fluidic layer).
    pub h2: f64,
    /// The fluidic layer's bottom is at z = -h3.
    pub h3: f64,
}

impl Default for Geometry {
    fn default() -> Self {
        Geometry {
            lx: 110.0,
            ly: 31.75,
            lc: 20.0,
            h: 8.2,
            h1: 3.7,
            h2: 1.8,
            h3: 2.2,
        }
    }
}

/// The channel: X_ref in [0, cx], z in [-h3b, h3a], width cy (mm). A
/// scene's `[actuator.channel]` holds its keys
/// ([`ChannelSection`](crate::scene::ChannelSection)).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Channel {
    pub cx: f64,
    pub cy: f64,
    pub h3a: f64,
    pub h3b: f64,
}

impl Default for Channel {
    fn default() -> Self {
        Channel {
            cx: 105.0,
            cy: 26.0,
            h3a: 0.8,
            h3b: 1.2,
        }
    }
}

/// A rib inside the channel: X_ref in [x0, x1], total width `width`
/// across Y, filling the channel's height. Only its X range and total
/// width matter, since the energy density does not depend on y.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rib {
    pub x0: f64,
    pub x1: f64,
    pub width: f64,
}

/// A rib on the constraining layer (docs/model.md section 4.10): a box of
/// the constraining layer's material on its top surface, X_ref in
/// [x0, x1], total width `width` across Y and `height` above the
/// laminate's top z = H/2 (so z in [H/2, H/2 + height]). All in mm. Its
/// strain energy enters the laminate; it holds no gas.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClRib {
    pub x0: f64,
    pub x1: f64,
    pub width: f64,
    pub height: f64,
}

/// How the ribs inside the channel are laid out.
#[derive(Debug, Clone, PartialEq)]
pub enum RibLayout {
    /// The default layout of docs/model.md decision D5: one longitudinal rib of
    /// width `t` over the whole channel, and transverse ribs `t` long in X,
    /// centred at X_ref = k w1 (k = 1, 2, ... while k w1 + t/2 <= cx),
    /// each of total width 2 w2 beside the longitudinal rib.
    Paper { w1: f64, w2: f64, t: f64 },
    /// An explicit list of ribs.
    Explicit(Vec<Rib>),
    /// No ribs.
    None,
}

impl Default for RibLayout {
    /// D5 with w1 = 8, w2 = 6, t = 2 (13 transverse ribs in the default channel).
    fn default() -> Self {
        RibLayout::Paper {
            w1: 8.0,
            w2: 6.0,
            t: 2.0,
        }
    }
}

/// Everything that describes one finger, as plain editable data.
/// `Default` gives the paper's actuator with eps0 = 0.25.
#[derive(Debug, Clone, PartialEq)]
pub struct ActuatorParams {
    pub geometry: Geometry,
    pub channel: Channel,
    pub ribs: RibLayout,
    /// Constraining layer, z in [h1, H/2].
    pub cl: Material,
    /// Regular EMC, z in [h2, h1].
    pub emc: Material,
    /// Fluidic layer and ribs, z in [-h3, h2].
    pub fluidic: Material,
    /// Prestressed EMC, z in [-H/2, -h3].
    pub pemc: Prestressed,
    /// Transverse shear data (shear-deformable models only).
    pub shear: TransverseShear,
    /// Plane strain across the width: the strain across the width is held
    /// at zero (a strip much wider than its curl's reach, or clamped along
    /// its sides); `false`, the default, is plane stress, the width free
    /// to contract (docs/model.md section 4.9).
    pub plane_strain: bool,
    /// Ribs on the constraining layer, of its material (docs/model.md
    /// section 4.10); none by default (the paper's model). At most
    /// [`MAX_CL_RIBS`].
    pub cl_ribs: Vec<ClRib>,
}

impl Default for ActuatorParams {
    fn default() -> Self {
        ActuatorParams {
            geometry: Geometry::default(),
            channel: Channel::default(),
            ribs: RibLayout::default(),
            cl: Isotropic { e: 305.0, nu: 0.43 }.into(),
            emc: Orthotropic {
                e1: 1.5,
                e2: 250.0,
                nu12: 0.0,
            }
            .into(),
            fluidic: Isotropic { e: 1.2, nu: 0.48 }.into(),
            pemc: Prestressed::default(),
            shear: TransverseShear::default(),
            plane_strain: false,
            cl_ribs: Vec::new(),
        }
    }
}

/// A linear lamina of the validated stack.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layer {
    pub name: &'static str,
    pub z0: f64,
    pub z1: f64,
    pub q: PlaneStress,
    /// Transverse shear modulus G13 (MPa).
    pub g13: f64,
}

/// A validated actuator. Its content cannot change after
/// [`Actuator::new`]; to vary a parameter, edit [`Actuator::params`]'s
/// clone and validate again (or use [`Actuator::with_eps0`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Actuator {
    params: ActuatorParams,
    ribs: Vec<Rib>,
    warnings: Vec<Warning>,
}

impl Default for Actuator {
    /// The paper's actuator with eps0 = 0.25.
    fn default() -> Self {
        Actuator::new(ActuatorParams::default()).expect("the paper's defaults are valid")
    }
}

/// The largest length, width or thickness of an actuator (mm).
pub const MAX_DIMENSION_MM: f64 = 1e5;

/// Why [`Actuator::new`] refused its input: the error, and the fields the
/// failed rule compares its field with, with their values (none for a
/// rule on one field). A front end that knows which fields its user gave
/// names the one given ([`crate::scene`]: a rule between a key the scene
/// wrote and a default names the key written).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Refusal {
    pub error: InputError,
    pub against: Vec<(Field, f64)>,
}

impl From<InputError> for Refusal {
    fn from(error: InputError) -> Refusal {
        Refusal {
            error,
            against: Vec::new(),
        }
    }
}

/// A rule's result with the fields it compared against.
trait Against {
    fn against<const N: usize>(self, fields: [(Field, f64); N]) -> Result<(), Refusal>;
}

impl Against for Result<(), InputError> {
    fn against<const N: usize>(self, fields: [(Field, f64); N]) -> Result<(), Refusal> {
        self.map_err(|error| Refusal {
            error,
            against: fields.into(),
        })
    }
}

impl Actuator {
    /// Validates `params`. Non-fatal findings (a prestrain outside the
    /// fitted range, a laminate too thick for laminate theory, ...) do not
    /// fail; they are kept and returned by [`Actuator::warnings`].
    pub fn new(params: ActuatorParams) -> Result<Actuator, InputError> {
        Actuator::checked(params).map_err(|r| r.error)
    }

    /// [`Actuator::new`], saying which fields a failed rule between
    /// fields compared.
    pub(crate) fn checked(params: ActuatorParams) -> Result<Actuator, Refusal> {
        let g = &params.geometry;
        for (key, v) in [
            (GeometryKey::Lx, g.lx),
            (GeometryKey::Ly, g.ly),
            (GeometryKey::H, g.h),
        ] {
            let field = Field::Geometry(key);
            positive(field.clone(), v)?;
            require(v <= MAX_DIMENSION_MM, field, v, || {
                format!("must be at most {MAX_DIMENSION_MM} mm (beyond it the solver's scales overflow; no FPC actuator is 100 m long)")
            })?;
        }
        finite(Field::Geometry(GeometryKey::Lc), g.lc)?;
        require(g.lc >= 0.0, Field::Geometry(GeometryKey::Lc), g.lc, || {
            "must not be negative".into()
        })?;
        positive(Field::Geometry(GeometryKey::H1), g.h1)?;
        positive(Field::Geometry(GeometryKey::H2), g.h2)?;
        positive(Field::Geometry(GeometryKey::H3), g.h3)?;
        let half = g.h / 2.0;
        let h = [(Field::Geometry(GeometryKey::H), g.h)];
        require(g.h1 < half, Field::Geometry(GeometryKey::H1), g.h1, || {
            format!("must be below H/2 = {half} (the constraining layer [h1, H/2] needs a positive thickness)")
        })
        .against(h.clone())?;
        require(g.h2 < g.h1, Field::Geometry(GeometryKey::H2), g.h2, || {
            format!(
                "must be below h1 = {} (the regular EMC [h2, h1] needs a positive thickness)",
                g.h1
            )
        })
        .against([(Field::Geometry(GeometryKey::H1), g.h1)])?;
        require(g.h3 < half, Field::Geometry(GeometryKey::H3), g.h3, || {
            format!("must be below H/2 = {half} (the prestressed EMC [-H/2, -h3] needs a positive thickness)")
        })
        .against(h)?;

        let c = &params.channel;
        positive(Field::Channel(ChannelKey::Cx), c.cx)?;
        require(c.cx <= g.lx, Field::Channel(ChannelKey::Cx), c.cx, || {
            format!("must not exceed the length lx = {}", g.lx)
        })
        .against([(Field::Geometry(GeometryKey::Lx), g.lx)])?;
        positive(Field::Channel(ChannelKey::Cy), c.cy)?;
        require(c.cy < g.ly, Field::Channel(ChannelKey::Cy), c.cy, || {
            format!("must be below the width ly = {}", g.ly)
        })
        .against([(Field::Geometry(GeometryKey::Ly), g.ly)])?;
        positive(Field::Channel(ChannelKey::H3a), c.h3a)?;
        require(c.h3a < g.h2, Field::Channel(ChannelKey::H3a), c.h3a, || {
            format!(
                "must be below h2 = {} (the channel lies inside the fluidic layer)",
                g.h2
            )
        })
        .against([(Field::Geometry(GeometryKey::H2), g.h2)])?;
        positive(Field::Channel(ChannelKey::H3b), c.h3b)?;
        require(c.h3b < g.h3, Field::Channel(ChannelKey::H3b), c.h3b, || {
            format!(
                "must be below h3 = {} (the channel lies inside the fluidic layer)",
                g.h3
            )
        })
        .against([(Field::Geometry(GeometryKey::H3), g.h3)])?;

        let ribs = resolve_ribs(&params.ribs, c)?;
        check_rib_overlap(&ribs, c.cy, Field::Ribs, "channel width cy")
            .against([(Field::Channel(ChannelKey::Cy), c.cy)])?;
        check_cl_ribs(&params.cl_ribs, g)?;

        params.cl.validate(Lamina::Cl)?;
        params.emc.validate(Lamina::Emc)?;
        params.fluidic.validate(Lamina::Fluidic)?;

        let pemc = &params.pemc;
        modulus(Field::Pemc(PemcKey::E2), pemc.e2)?;
        pemc.law.validate()?;
        finite(Field::Pemc(PemcKey::Eps0), pemc.eps0)?;
        let (lo, hi) = EPS0_RANGE;
        require(
            pemc.eps0 > lo && pemc.eps0 <= hi,
            Field::Pemc(PemcKey::Eps0),
            pemc.eps0,
            || {
                format!("must lie in ({lo}, {hi}] (a strain of {lo} shrinks the layer to nothing; no elastomer stretches past {hi})")
            },
        )?;

        let shear = &params.shear;
        positive(
            Field::Laminate(LaminateKey::ShearCorrection),
            shear.correction,
        )?;
        for (&layer, g) in ShearLayer::ALL.iter().zip(shear.g13) {
            if let Some(g) = g {
                // (no floor: a face nearly free in shear is the sandwich
                // beam's limit, tests/shear.rs; the ceiling as for any
                // modulus)
                positive(Field::ShearModulus(layer), g)?;
                let hi = MODULUS_RANGE_MPA.1;
                require(g <= hi, Field::ShearModulus(layer), g, || {
                    format!("must be at most {hi:e} MPa (10 TPa)")
                })?;
            }
        }

        let mut warnings = Vec::new();
        let (lo, hi) = EPS0_FIT_RANGE;
        if !(lo..=hi).contains(&pemc.eps0) {
            warnings.push(Warning::Eps0OutsideFit {
                eps0: pemc.eps0,
                lo,
                hi,
            });
        }
        // a validity finding, not an error: the strip may still be solved;
        // the section is as thick as its tallest rib on the constraining
        // layer makes it (none: H itself)
        let tallest = params.cl_ribs.iter().fold(0.0_f64, |m, r| m.max(r.height));
        warnings.extend(crate::validity::thickness(g.h + tallest, g.lx, g.ly));
        Ok(Actuator {
            params,
            ribs,
            warnings,
        })
    }

    /// The paper's actuator with prestrain `eps0` (fails only if `eps0` is
    /// not finite).
    pub fn paper(eps0: f64) -> Result<Actuator, InputError> {
        let mut params = ActuatorParams::default();
        params.pemc.eps0 = eps0;
        Actuator::new(params)
    }

    /// This actuator with another prestrain, validated again.
    pub fn with_eps0(&self, eps0: f64) -> Result<Actuator, InputError> {
        let mut params = self.params.clone();
        params.pemc.eps0 = eps0;
        Actuator::new(params)
    }

    /// The validated input.
    pub fn params(&self) -> &ActuatorParams {
        &self.params
    }

    pub fn geometry(&self) -> &Geometry {
        &self.params.geometry
    }

    pub fn channel(&self) -> &Channel {
        &self.params.channel
    }

    /// The ribs resolved from the layout, in X_ref (empty for
    /// [`RibLayout::None`]). For [`RibLayout::Paper`] the longitudinal rib
    /// comes first, then the transverse ribs by increasing X.
    pub fn ribs(&self) -> &[Rib] {
        &self.ribs
    }

    /// The ribs on the constraining layer ([`ActuatorParams::cl_ribs`]).
    pub fn cl_ribs(&self) -> &[ClRib] {
        &self.params.cl_ribs
    }

    /// The prestressed layer.
    pub fn pemc(&self) -> &Prestressed {
        &self.params.pemc
    }

    pub fn eps0(&self) -> f64 {
        self.params.pemc.eps0
    }

    /// The fluidic layer's stiffnesses (also the ribs' material).
    pub fn fluidic_q(&self) -> PlaneStress {
        self.params.fluidic.q()
    }

    /// The linear laminae, top to bottom: CL, regular EMC, fluidic layer
    /// (whole, without the channel).
    pub fn linear_layers(&self) -> [Layer; 3] {
        let g = &self.params.geometry;
        [
            Layer {
                name: "cl",
                z0: g.h1,
                z1: g.h / 2.0,
                q: self.params.cl.q(),
                g13: self.g13(ShearLayer::Cl),
            },
            Layer {
                name: "emc",
                z0: g.h2,
                z1: g.h1,
                q: self.params.emc.q(),
                g13: self.g13(ShearLayer::Emc),
            },
            Layer {
                name: "fluidic",
                z0: -g.h3,
                z1: g.h2,
                q: self.params.fluidic.q(),
                g13: self.g13(ShearLayer::Fluidic),
            },
        ]
    }

    /// The transverse shear modulus G13 (MPa) of a layer: the one given,
    /// or the default from its elastic constants ([`TransverseShear::g13`]).
    pub fn g13(&self, layer: ShearLayer) -> f64 {
        let p = &self.params;
        let given = p.shear.g13[layer as usize];
        given.unwrap_or_else(|| match layer {
            ShearLayer::Cl => p.cl.default_g13(),
            ShearLayer::Emc => p.emc.default_g13(),
            ShearLayer::Fluidic => p.fluidic.default_g13(),
            ShearLayer::Pemc => 0.5 * p.pemc.law.p1,
        })
    }

    /// Whether the width is held (plane strain) rather than free (plane
    /// stress).
    pub fn plane_strain(&self) -> bool {
        self.params.plane_strain
    }

    /// The shear correction factor ks.
    pub fn shear_correction(&self) -> f64 {
        self.params.shear.correction
    }

    /// The prestressed layer's z range [-H/2, -h3].
    pub fn pemc_z(&self) -> (f64, f64) {
        let g = &self.params.geometry;
        (-g.h / 2.0, -g.h3)
    }

    /// The channel's z range [-h3b, h3a].
    pub fn channel_z(&self) -> (f64, f64) {
        let c = &self.params.channel;
        (-c.h3b, c.h3a)
    }

    /// Non-fatal findings of validation: notes on the input
    /// (`eps0_outside_fit`) and the laminate's `thickness_ratio`, a
    /// validity finding ([`Warning::is_validity`]) that every finger,
    /// solution, grasp and gripper built from this actuator carries.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }
}

/// Checks the layout and lists its ribs in X_ref.
fn resolve_ribs(layout: &RibLayout, c: &Channel) -> Result<Vec<Rib>, Refusal> {
    match layout {
        RibLayout::None => Ok(Vec::new()),
        RibLayout::Explicit(ribs) => {
            require(
                ribs.len() <= MAX_LISTED_RIBS,
                Field::Ribs,
                ribs.len() as f64,
                || format!("lists {} ribs, more than {MAX_LISTED_RIBS}", ribs.len()),
            )?;
            for (k, r) in ribs.iter().enumerate() {
                let f = |key| Field::Rib(k, key);
                finite(f(RibKey::X0), r.x0)?;
                require(r.x0 >= 0.0, f(RibKey::X0), r.x0, || {
                    "must not be negative".into()
                })?;
                finite(f(RibKey::X1), r.x1)?;
                require(r.x1 > r.x0, f(RibKey::X1), r.x1, || {
                    format!("must exceed x0 = {}", r.x0)
                })
                .against([(f(RibKey::X0), r.x0)])?;
                require(r.x1 <= c.cx, f(RibKey::X1), r.x1, || {
                    format!(
                        "must not exceed the channel's end cx = {} (ribs lie inside the channel)",
                        c.cx
                    )
                })
                .against([(Field::Channel(ChannelKey::Cx), c.cx)])?;
                positive(f(RibKey::Width), r.width)?;
                require(r.width <= c.cy, f(RibKey::Width), r.width, || {
                    format!("must not exceed the channel width cy = {}", c.cy)
                })
                .against([(Field::Channel(ChannelKey::Cy), c.cy)])?;
            }
            Ok(ribs.clone())
        }
        &RibLayout::Paper { w1, w2, t } => {
            positive(Field::PaperRib(PaperRibKey::W1), w1)?;
            positive(Field::PaperRib(PaperRibKey::W2), w2)?;
            positive(Field::PaperRib(PaperRibKey::T), t)?;
            require(
                t + 2.0 * w2 <= c.cy,
                Field::PaperRib(PaperRibKey::W2),
                w2,
                || {
                    format!(
                        "t + 2 w2 = {} must not exceed the channel width cy = {}",
                        t + 2.0 * w2,
                        c.cy
                    )
                },
            )
            .against([
                (Field::PaperRib(PaperRibKey::T), t),
                (Field::Channel(ChannelKey::Cy), c.cy),
            ])?;
            require(w1 >= t, Field::PaperRib(PaperRibKey::W1), w1, || {
                format!("must be at least t = {t} (transverse ribs must not overlap)")
            })
            .against([(Field::PaperRib(PaperRibKey::T), t)])?;
            // Tolerance so that a rib meant to touch the channel's end is
            // kept despite rounding in k * w1.
            let end = c.cx + 1e-12 * c.cx;
            let count = ((end - t / 2.0) / w1).floor().max(0.0);
            require(
                count <= MAX_GENERATED_RIBS as f64,
                Field::PaperRib(PaperRibKey::W1),
                w1,
                || format!("gives {count} transverse ribs, more than {MAX_GENERATED_RIBS}"),
            )
            .against([
                (Field::Channel(ChannelKey::Cx), c.cx),
                (Field::PaperRib(PaperRibKey::T), t),
            ])?;
            let mut ribs = vec![Rib {
                x0: 0.0,
                x1: c.cx,
                width: t,
            }];
            let mut k = 1u32;
            loop {
                let centre = f64::from(k) * w1;
                if centre + t / 2.0 > end {
                    break;
                }
                ribs.push(Rib {
                    x0: centre - t / 2.0,
                    x1: (centre + t / 2.0).min(c.cx),
                    width: 2.0 * w2,
                });
                k += 1;
            }
            Ok(ribs)
        }
    }
}

/// Checks the ribs on the constraining layer: finite, inside the length,
/// no wider than the strip, a positive height, at most [`MAX_CL_RIBS`] of
/// them, and side by side no wider than the strip at any X.
fn check_cl_ribs(ribs: &[ClRib], g: &Geometry) -> Result<(), Refusal> {
    require(
        ribs.len() <= MAX_CL_RIBS,
        Field::ClRibs,
        ribs.len() as f64,
        || format!("lists {} ribs, more than {MAX_CL_RIBS}", ribs.len()),
    )?;
    for (k, r) in ribs.iter().enumerate() {
        let f = |key| Field::ClRib(k, key);
        finite(f(ClRibKey::X0), r.x0)?;
        require(r.x0 >= 0.0, f(ClRibKey::X0), r.x0, || {
            "must not be negative".into()
        })?;
        finite(f(ClRibKey::X1), r.x1)?;
        require(r.x1 > r.x0, f(ClRibKey::X1), r.x1, || {
            format!("must exceed x0 = {}", r.x0)
        })
        .against([(f(ClRibKey::X0), r.x0)])?;
        require(r.x1 <= g.lx, f(ClRibKey::X1), r.x1, || {
            format!("must not exceed the length lx = {}", g.lx)
        })
        .against([(Field::Geometry(GeometryKey::Lx), g.lx)])?;
        positive(f(ClRibKey::Width), r.width)?;
        require(r.width <= g.ly, f(ClRibKey::Width), r.width, || {
            format!("must not exceed the width ly = {}", g.ly)
        })
        .against([(Field::Geometry(GeometryKey::Ly), g.ly)])?;
        positive(f(ClRibKey::Height), r.height)?;
        require(
            r.height <= MAX_DIMENSION_MM,
            f(ClRibKey::Height),
            r.height,
            || format!("must be at most {MAX_DIMENSION_MM} mm"),
        )?;
    }
    let boxes: Vec<Rib> = ribs
        .iter()
        .map(|r| Rib {
            x0: r.x0,
            x1: r.x1,
            width: r.width,
        })
        .collect();
    check_rib_overlap(&boxes, g.ly, Field::ClRibs, "width ly")
        .against([(Field::Geometry(GeometryKey::Ly), g.ly)])
}

/// The ribs' summed width at any X must fit in `limit` (the channel's
/// width for the channel's ribs, the strip's for those on the
/// constraining layer).
fn check_rib_overlap(
    ribs: &[Rib],
    limit: f64,
    field: Field,
    limit_name: &str,
) -> Result<(), InputError> {
    // Sweep over the rib ends; at equal X a rib ending is processed before
    // one starting, so ribs that only touch do not add up.
    let mut events: Vec<(f64, f64)> = ribs
        .iter()
        .flat_map(|r| [(r.x0, r.width), (r.x1, -r.width)])
        .collect();
    events.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut sum = 0.0;
    for (x, dw) in events {
        sum += dw;
        if sum > limit * (1.0 + 1e-12) {
            return Err(InputError::Inconsistent {
                field,
                rule: format!(
                    "the ribs at X_ref = {x} add up to width {sum}, more than the {limit_name} = {limit}"
                ),
            });
        }
    }
    Ok(())
}
