//! Input errors and non-fatal warnings.
//!
//! Every error names the offending field by its path in the input (for
//! example `actuator.geometry.h1` or `partition.lengths[2]`), the value
//! where there is one (written by [`Num`]: `1e308`, not 309 digits), and
//! the rule it breaks, on one line.

use std::fmt;

use crate::field::Field;
use crate::num::Num;

/// A rejected input: one field, its value where it has one, and the rule.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InputError {
    /// The value is NaN or infinite.
    #[error("{field} = {}: must be finite", Num(*.value))]
    NotFinite { field: Field, value: f64 },
    /// The value must be strictly positive.
    #[error("{field} = {}: must be positive", Num(*.value))]
    NotPositive { field: Field, value: f64 },
    /// The value lies outside its admissible range; `rule` states the range.
    #[error("{field} = {}: {rule}", Num(*.value))]
    OutOfRange {
        field: Field,
        value: f64,
        rule: String,
    },
    /// Several fields together are inconsistent (the layer stack, a
    /// channel outside its layer, overlapping ribs); `rule` says how.
    #[error("{field}: {rule}")]
    Inconsistent { field: Field, rule: String },
    /// A name that is not one of the choices (a model, a kind).
    #[error("{field} = `{value}`: {rule}")]
    Unrecognised {
        field: Field,
        value: String,
        rule: String,
    },
}

impl InputError {
    /// The same error about the same field under another name (a scene
    /// key, a command-line flag), its value converted to that name's unit
    /// by `value` (for example MPa to kPa).
    pub fn renamed(self, field: impl Into<Field>, value: impl Fn(f64) -> f64) -> InputError {
        let field = field.into();
        match self {
            InputError::NotFinite { value: v, .. } => InputError::NotFinite {
                field,
                value: value(v),
            },
            InputError::NotPositive { value: v, .. } => InputError::NotPositive {
                field,
                value: value(v),
            },
            InputError::OutOfRange { value: v, rule, .. } => InputError::OutOfRange {
                field,
                value: value(v),
                rule,
            },
            InputError::Inconsistent { rule, .. } => InputError::Inconsistent { field, rule },
            InputError::Unrecognised { value: v, rule, .. } => InputError::Unrecognised {
                field,
                value: v,
                rule,
            },
        }
    }

    /// The offending field.
    pub fn field(&self) -> &Field {
        match self {
            InputError::NotFinite { field, .. }
            | InputError::NotPositive { field, .. }
            | InputError::OutOfRange { field, .. }
            | InputError::Inconsistent { field, .. }
            | InputError::Unrecognised { field, .. } => field,
        }
    }
}

/// Fails with [`InputError::NotFinite`] unless `value` is finite.
pub(crate) fn finite(field: Field, value: f64) -> Result<f64, InputError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(InputError::NotFinite { field, value })
    }
}

/// Fails unless `value` is finite and strictly positive.
pub(crate) fn positive(field: Field, value: f64) -> Result<f64, InputError> {
    if !value.is_finite() {
        Err(InputError::NotFinite { field, value })
    } else if value > 0.0 {
        Ok(value)
    } else {
        Err(InputError::NotPositive { field, value })
    }
}

/// Fails with [`InputError::OutOfRange`] unless `ok`.
pub(crate) fn require(
    ok: bool,
    field: Field,
    value: f64,
    rule: impl FnOnce() -> String,
) -> Result<(), InputError> {
    if ok {
        Ok(())
    } else {
        Err(InputError::OutOfRange {
            field,
            value,
            rule: rule(),
        })
    }
}

/// Which in-plane dimension of the strip a [`Warning::ThicknessRatio`]
/// compares the thickness with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StripDimension {
    /// The modelled length Lx (`actuator.geometry.lx`).
    Length,
    /// The width Ly (`actuator.geometry.ly`).
    Width,
}

impl StripDimension {
    /// `length` or `width`.
    pub fn name(self) -> &'static str {
        match self {
            StripDimension::Length => "length",
            StripDimension::Width => "width",
        }
    }

    /// The field's path in the input.
    pub fn field(self) -> &'static str {
        match self {
            StripDimension::Length => "actuator.geometry.lx",
            StripDimension::Width => "actuator.geometry.ly",
        }
    }

    /// `lx` or `ly`.
    pub fn symbol(self) -> &'static str {
        match self {
            StripDimension::Length => "lx",
            StripDimension::Width => "ly",
        }
    }
}

/// A non-fatal note about an accepted input (the model runs, but the
/// result may be outside what the model was fitted or meant for), or a
/// finding that an answer lies outside the model's assumptions
/// ([`Warning::is_validity`], docs/model.md section 8).
#[derive(Debug, Clone, PartialEq)]
pub enum Warning {
    /// The prestrain lies outside [`lo`, `hi`], the strain range of the
    /// uniaxial test the prestressed law was fitted to (the paper's
    /// samples use 0.15 to 0.4). A negative value means a precompressed
    /// layer.
    Eps0OutsideFit { eps0: f64, lo: f64, hi: f64 },
    /// The prestressed law's tangent modulus psi''(eps0) is not positive:
    /// the unloaded layer softens and equilibria may be unstable. `tangent`
    /// (MPa) is `None` where the law overflows (a huge `eps0`).
    SofteningPrestressLaw { eps0: f64, tangent: Option<f64> },
    /// The gripper's mounting angle (rad) lies outside the design space
    /// [`lo`, `hi`] = [arccot mu, pi/2]: fingers pressed flat cannot hold
    /// the object by friction (docs/model.md section 5).
    MountingAngleOutsideDesignSpace { angle: f64, lo: f64, hi: f64 },
    /// The palm diameter exceeds twice the fingers' inward reach
    /// (`palm > 2 l0`, a negative overlap): the fingers leave a gap at rest,
    /// and objects smaller than `palm - 2 l0` cannot be grasped.
    PalmGapAtRest { palm: f64, reach: f64 },
    /// A grasp on a scene's fixed partition of `elements` elements turns
    /// an element beyond the slope limit. `clears_with`: the fewest
    /// elements (the partition halved once or twice) at which the same
    /// grasp has no `element_slope` finding; `None` when `tried` elements
    /// still have one. A note.
    PartitionAdvice {
        elements: usize,
        clears_with: Option<usize>,
        tried: usize,
    },
    /// The automatic partition stopped at a fold: after its last split,
    /// half `element` of an element that turned `parent` degrees still
    /// turns `degrees`, at least `limit` of its parent's turn. The turn
    /// gathers in one element however short it is, so more elements do
    /// not clear its `element_slope` finding. A note.
    PartitionFold {
        element: usize,
        degrees: f64,
        parent: f64,
        limit: f64,
    },
    /// The automatic partition stopped because a split partition of
    /// `elements` elements did not solve (`reason`, from its parent's state
    /// and from rest): the answer is the last partition that solved, of
    /// `kept` elements, with the `element_slope` findings that asked for
    /// the split. A note.
    PartitionSplitFailed {
        elements: usize,
        kept: usize,
        reason: String,
    },
    /// An element's mid-plane turns further than the CCM's small-slope
    /// limit from the element's root tangent (`degrees`, limit `limit`).
    ElementSlope {
        element: usize,
        degrees: f64,
        limit: f64,
    },
    /// An element's mid-plane axial strain exceeds the small-strain limit
    /// in magnitude.
    MidplaneStrain {
        element: usize,
        strain: f64,
        limit: f64,
    },
    /// The prestressed layer's own strain `s = eps0 + eps_x` leaves the
    /// range its law was fitted to.
    PrestressedStrain {
        element: usize,
        strain: f64,
        range: (f64, f64),
    },
    /// The finger's surfaces meet: the mid-plane of element `element`
    /// comes within the laminate's thickness H (`thickness`, mm) of the
    /// mid-plane of element `other`, an earlier part at least pi H / 2
    /// away along the finger (`distance` in mm, 0 where the mid-plane
    /// crosses itself; docs/model.md section 8).
    SelfContact {
        element: usize,
        other: usize,
        distance: f64,
        thickness: f64,
    },
    /// The laminate is too thick for classical laminate theory against the
    /// strip's length or width: `thickness / extent` (H over Lx or Ly)
    /// exceeds `limit`. A finding about the actuator, carried by every
    /// solution built from it.
    ThicknessRatio {
        dimension: StripDimension,
        thickness: f64,
        extent: f64,
        limit: f64,
    },
    /// A grasp bends an element backwards (its curvature, in 1/mm, has the
    /// opposite sign to the unloaded finger's), which the paper's grasp
    /// analysis assumes away.
    CurvatureReversal { element: usize, curvature: f64 },
    /// A grasp's size exceeds `d_max`: the fingers are pressed past flat.
    BeyondFlat { size: f64, d_max: f64 },
}

impl Warning {
    /// A short, stable name of the warning's kind (`element_slope`,
    /// `strain_range`, `self_contact`, `thickness_ratio`, `beyond_flat` for
    /// the model's validity; `curvature_reversal` for the paper's grasp
    /// assumption, a rule only in strict mode; `eps0_outside_fit`,
    /// `softening_prestress_law`, `mounting_angle_outside_design_space`,
    /// `palm_gap_at_rest` for notes on the input; `partition_advice`,
    /// `partition_fold` and `partition_split_failed` for notes on the
    /// partition).
    pub fn kind(&self) -> &'static str {
        match self {
            Warning::Eps0OutsideFit { .. } => "eps0_outside_fit",
            Warning::SofteningPrestressLaw { .. } => "softening_prestress_law",
            Warning::MountingAngleOutsideDesignSpace { .. } => {
                "mounting_angle_outside_design_space"
            }
            Warning::PalmGapAtRest { .. } => "palm_gap_at_rest",
            Warning::PartitionAdvice { .. } => "partition_advice",
            Warning::PartitionFold { .. } => "partition_fold",
            Warning::PartitionSplitFailed { .. } => "partition_split_failed",
            Warning::ElementSlope { .. } => "element_slope",
            Warning::MidplaneStrain { .. } | Warning::PrestressedStrain { .. } => "strain_range",
            Warning::SelfContact { .. } => "self_contact",
            Warning::ThicknessRatio { .. } => "thickness_ratio",
            Warning::CurvatureReversal { .. } => "curvature_reversal",
            Warning::BeyondFlat { .. } => "beyond_flat",
        }
    }

    /// True for a finding that the answer lies outside the model's
    /// assumptions (as opposed to a note on the input, or a reversal: the
    /// CCM models a finger bent backwards; the paper's grasp analysis
    /// assumes it away, which strict mode makes a rule).
    pub fn is_validity(&self) -> bool {
        matches!(
            self,
            Warning::ElementSlope { .. }
                | Warning::MidplaneStrain { .. }
                | Warning::PrestressedStrain { .. }
                | Warning::SelfContact { .. }
                | Warning::ThicknessRatio { .. }
                | Warning::BeyondFlat { .. }
        )
    }

    /// The element concerned (0 = at the root), if one is.
    pub fn element(&self) -> Option<usize> {
        match self {
            Warning::ElementSlope { element, .. }
            | Warning::PartitionFold { element, .. }
            | Warning::MidplaneStrain { element, .. }
            | Warning::PrestressedStrain { element, .. }
            | Warning::SelfContact { element, .. }
            | Warning::CurvatureReversal { element, .. } => Some(*element),
            _ => None,
        }
    }

    /// The offending value (in the unit of [`Warning::limit`]).
    pub fn value(&self) -> Option<f64> {
        match *self {
            Warning::Eps0OutsideFit { eps0, .. } | Warning::SofteningPrestressLaw { eps0, .. } => {
                Some(eps0)
            }
            Warning::MountingAngleOutsideDesignSpace { angle, .. } => Some(angle),
            Warning::PalmGapAtRest { palm, .. } => Some(palm),
            Warning::PartitionAdvice { elements, .. } => Some(elements as f64),
            Warning::PartitionFold {
                degrees, parent, ..
            } => Some(degrees / parent),
            Warning::PartitionSplitFailed { elements, .. } => Some(elements as f64),
            Warning::ElementSlope { degrees, .. } => Some(degrees),
            Warning::MidplaneStrain { strain, .. } | Warning::PrestressedStrain { strain, .. } => {
                Some(strain)
            }
            Warning::SelfContact { distance, .. } => Some(distance),
            Warning::ThicknessRatio {
                thickness, extent, ..
            } => Some(thickness / extent),
            Warning::CurvatureReversal { curvature, .. } => Some(curvature),
            Warning::BeyondFlat { size, .. } => Some(size),
        }
    }

    /// The limit the value passes (for a range, the bound it passes).
    pub fn limit(&self) -> Option<f64> {
        match *self {
            Warning::Eps0OutsideFit { eps0, lo, hi } => Some(if eps0 < lo { lo } else { hi }),
            Warning::SofteningPrestressLaw { .. } => Some(0.0),
            Warning::MountingAngleOutsideDesignSpace { angle, lo, hi } => {
                Some(if angle < lo { lo } else { hi })
            }
            Warning::PalmGapAtRest { reach, .. } => Some(2.0 * reach),
            Warning::PartitionAdvice {
                clears_with, tried, ..
            } => Some(clears_with.unwrap_or(tried) as f64),
            Warning::ElementSlope { limit, .. } | Warning::PartitionFold { limit, .. } => {
                Some(limit)
            }
            Warning::PartitionSplitFailed { kept, .. } => Some(kept as f64),
            Warning::MidplaneStrain { strain, limit, .. } => {
                Some(if strain < 0.0 { -limit } else { limit })
            }
            Warning::PrestressedStrain { strain, range, .. } => {
                Some(if strain < range.0 { range.0 } else { range.1 })
            }
            Warning::SelfContact { thickness, .. } => Some(thickness),
            Warning::ThicknessRatio { limit, .. } => Some(limit),
            Warning::CurvatureReversal { .. } => Some(0.0),
            Warning::BeyondFlat { d_max, .. } => Some(d_max),
        }
    }
}

/// Findings of one kind beyond this many are summed up by their worst
/// ([`Warning::by_kind`]): a finger past its limits has one finding per
/// element and kind.
pub const WARNINGS_PER_KIND: usize = 2;

/// The findings of one kind among a solution's warnings
/// ([`Warning::by_kind`]).
#[derive(Debug, Clone, PartialEq)]
pub struct KindSummary<'a> {
    /// The kind ([`Warning::kind`]).
    pub kind: &'static str,
    /// How many findings of the kind there are.
    pub count: usize,
    /// Every one of them when they are at most [`WARNINGS_PER_KIND`], else
    /// only the worst ([`Warning::excess`]).
    pub kept: Vec<&'a Warning>,
}

impl Warning {
    /// How far the value lies past its limit (0 without either): what
    /// makes one finding of a kind worse than another.
    pub fn excess(&self) -> f64 {
        match (self.value(), self.limit()) {
            (Some(v), Some(l)) => (v - l).abs(),
            _ => 0.0,
        }
    }

    /// `all` by kind, in the order the kinds first appear: how many of
    /// each, and every one where they are few, else the worst (the first
    /// of equals). What the CLI writes on stderr and the server answers
    /// for each point of a load path.
    pub fn by_kind<'a>(all: impl IntoIterator<Item = &'a Warning>) -> Vec<KindSummary<'a>> {
        let mut out: Vec<(KindSummary<'a>, Vec<&'a Warning>)> = Vec::new();
        for w in all {
            match out.iter_mut().find(|(s, _)| s.kind == w.kind()) {
                Some((_, of_kind)) => of_kind.push(w),
                None => out.push((
                    KindSummary {
                        kind: w.kind(),
                        count: 0,
                        kept: Vec::new(),
                    },
                    vec![w],
                )),
            }
        }
        out.into_iter()
            .map(|(mut s, of_kind)| {
                s.count = of_kind.len();
                s.kept = if of_kind.len() <= WARNINGS_PER_KIND {
                    of_kind
                } else {
                    of_kind
                        .into_iter()
                        .reduce(|a, b| if b.excess() > a.excess() { b } else { a })
                        .into_iter()
                        .collect()
                };
                s
            })
            .collect()
    }
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::Eps0OutsideFit { eps0, lo, hi } => write!(
                f,
                "actuator.pemc.eps0 = {eps0}: outside [{lo}, {hi}], the range the prestressed law was fitted to"
            ),
            Warning::SofteningPrestressLaw {
                eps0,
                tangent: Some(tangent),
            } => write!(
                f,
                "actuator.pemc.eps0 = {eps0}: the prestressed law's tangent modulus there is {tangent} MPa (not positive)"
            ),
            Warning::SofteningPrestressLaw {
                eps0,
                tangent: None,
            } => write!(
                f,
                "actuator.pemc.eps0 = {eps0}: the prestressed law's tangent modulus there is not a finite number (the law overflows)"
            ),
            Warning::MountingAngleOutsideDesignSpace { angle, lo, hi } => write!(
                f,
                "gripper.mounting_angle = {angle}: outside the design space [{lo}, {hi}] (arccot mu to pi/2)"
            ),
            Warning::PalmGapAtRest { palm, reach } => write!(
                f,
                "gripper.palm = {palm}: wider than twice the finger's inward reach l0 = {reach} mm, the fingers leave a gap at rest"
            ),
            Warning::PartitionAdvice {
                elements,
                clears_with: Some(n),
                ..
            } => write!(
                f,
                "partition.elements = {elements}: the grasp turns an element beyond the slope limit; with partition.elements = {n} it does not (set it to {n})"
            ),
            Warning::PartitionAdvice {
                elements,
                clears_with: None,
                tried,
            } => write!(
                f,
                "partition.elements = {elements}: the grasp turns an element beyond the slope limit, and still does with {tried} elements (the most tried): it needs a much finer partition, or bends beyond the model at any"
            ),
            Warning::ElementSlope {
                element,
                degrees,
                limit,
            } => write!(
                f,
                "element {element} turns {degrees:.1} degrees, beyond the CCM's small-slope limit of {limit} degrees per element: use more elements (--elements auto)"
            ),
            Warning::PartitionFold {
                element,
                degrees,
                parent,
                ..
            } => write!(
                f,
                "the automatic partition stopped at a fold: an element that turned {parent:.1} degrees was split in two, and its half, element {element}, turns {degrees:.1}; the turn gathers in one element however short it is, and more elements do not clear its slope finding"
            ),
            Warning::PartitionSplitFailed {
                elements,
                kept,
                reason,
            } => write!(
                f,
                "the automatic partition stopped at {kept} elements, the last partition that solved: their split into {elements} did not ({reason})"
            ),
            Warning::MidplaneStrain {
                element,
                strain,
                limit,
            } => write!(
                f,
                "element {element} has a mid-plane axial strain of {strain:.3}, beyond the small-strain limit of {limit}"
            ),
            Warning::PrestressedStrain {
                element,
                strain,
                range,
            } => write!(
                f,
                "element {element}: the prestressed layer's strain reaches {strain:.3}, outside [{}, {}] where its law was fitted",
                range.0, range.1
            ),
            Warning::SelfContact {
                element,
                other,
                distance,
                thickness,
            } => {
                if *distance == 0.0 {
                    write!(
                        f,
                        "the mid-plane crosses itself: element {element} passes through element {other} (the finger is H = {thickness} mm thick)"
                    )
                } else {
                    write!(
                        f,
                        "the finger's surfaces meet: element {element}'s mid-plane comes within {distance:.3} mm of element {other}'s, less than the thickness H = {thickness} mm"
                    )
                }
            }
            Warning::ThicknessRatio {
                dimension,
                thickness,
                extent,
                limit,
            } => write!(
                f,
                "actuator.geometry.h = {thickness} mm against the {} {} = {extent} mm: H / {} = {:.4} exceeds {limit}, too thick for classical laminate theory",
                dimension.name(),
                dimension.field(),
                dimension.symbol(),
                thickness / extent
            ),
            Warning::CurvatureReversal { element, curvature } => write!(
                f,
                "element {element} is bent backwards (curvature {curvature:.3e} 1/mm against the unloaded curl), which the grasp analysis assumes away"
            ),
            Warning::BeyondFlat { size, d_max } => write!(
                f,
                "grasp size {size:.2} mm exceeds d_max = {d_max:.2} mm: the fingers would be pressed past flat"
            ),
        }
    }
}

impl serde::Serialize for Warning {
    /// `{"kind", "message", "element"?, "value"?, "limit"?}`.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("kind", self.kind())?;
        m.serialize_entry("message", &self.to_string())?;
        if let Some(e) = self.element() {
            m.serialize_entry("element", &e)?;
        }
        if let Some(v) = self.value() {
            m.serialize_entry("value", &v)?;
        }
        if let Some(l) = self.limit() {
            m.serialize_entry("limit", &l)?;
        }
        m.end()
    }
}
