//! The values a requirements file may hold ([`Requirements::validate`]),
//! and where a value error lies in the file ([`RequirementsError::position`]).
//!
//! Every value of a requirements file is checked when the file is read,
//! before any work, and an error names the key as written
//! (`object[1].lift_n`); [`RequirementsError::position`] finds the line
//! and column where the file writes it, as a syntax error has them. The
//! bounds are physically generous, there to keep every normalised margin
//! and its sensitivities finite (a margin divides by the size, the lift,
//! the normal force or the opening it is measured against) and every run
//! bounded:
//!
//! - lengths (`size_mm`, `radius_mm`, `open.size_mm`) within
//!   [`LENGTH_RANGE_MM`], a micrometre to ten metres;
//! - forces (`lift_n`, `max_normal_n`) within [`FORCE_RANGE_N`], a
//!   micronewton to ten kilonewtons;
//! - `mu` within [`MU_RANGE`]; `open.pressure_kpa` within [0, 1000] kPa;
//! - the design variables' bounds within [0, 0.6] (eps0), [1, 179] degrees
//!   and [-200, 200] mm;
//! - at most [`MAX_OBJECTS`] `[[object]]` tables: each one's margins are
//!   solved at every design the search tries, so the run time grows with
//!   their number (module docs of [`crate::design`]);
//! - `fingers` within [2, 12] ([`MAX_FINGERS`]), `elements` within [1, 256].
//!
//! A scene's `[gripper]` takes a single finger (`gripper.fingers = 1`: its
//! shape at rest, or a finger pressed on an object by something else), but
//! a requirement is a grasp: the object is held between fingers facing
//! each other, the model solving one of them and mirroring it (docs/model.md
//! Sec. 5.2), so a gripper that must hold something has at least two. The
//! upper bound is a scene's, 12, a generous count: the Sec. 5 palm holds 3
//! to 6 fingers of the paper's width, and twelve need a palm of at least
//! 3.9 finger widths (docs/model.md Sec. 5.4).

use crate::error::{finite, positive, require, InputError};
use crate::field::Field;
use crate::gripper::MAX_FINGERS;
use crate::scene::locate;

use super::requirements::{ObjectRequirement, Requirements, RequirementsError, DEFAULT_DESIGN};

/// The most `[[object]]` tables of a requirements file. Each object's
/// margins are solved at every design the search evaluates, so a run's
/// time grows with their number: with the default search, 32 objects,
/// half of them spheres, take about 15 s on two cores on the paper's
/// finger (more starts: [`MAX_RANDOM_STARTS`](super::MAX_RANDOM_STARTS)).
pub const MAX_OBJECTS: usize = 32;

/// The lengths of a requirements file, `[smallest, largest]` (mm): object
/// widths and radii and the opening to reach. A margin is normalised by
/// them, so the floor keeps it finite; the ceiling is far beyond any
/// gripper the model describes.
pub const LENGTH_RANGE_MM: [f64; 2] = [1e-3, 1e4];

/// The forces of a requirements file, `[smallest, largest]` (N): the lift
/// per finger and the largest normal force. A margin is normalised by
/// them, so the floor keeps it finite.
pub const FORCE_RANGE_N: [f64; 2] = [1e-6, 1e4];

/// The friction coefficient `mu`, `[smallest, largest]`.
pub const MU_RANGE: [f64; 2] = [1e-3, 10.0];

/// Fails unless `value` is finite, positive and within `[lo, hi]` (`unit`
/// after the range in the message).
fn within(field: Field, value: f64, [lo, hi]: [f64; 2], unit: &str) -> Result<(), InputError> {
    positive(field.clone(), value)?;
    require((lo..=hi).contains(&value), field, value, || {
        format!("must lie in [{lo}, {hi}]{unit}")
    })
}

impl Requirements {
    /// Checks every value.
    pub fn validate(&self) -> Result<(), InputError> {
        require(
            (2..=MAX_FINGERS).contains(&self.fingers),
            Field::key("fingers"),
            self.fingers as f64,
            || {
                format!("must lie in [2, {MAX_FINGERS}]: an object is held between fingers facing each other")
            },
        )?;
        within(Field::key("mu"), self.mu, MU_RANGE, "")?;
        require(
            (1..=256).contains(&self.elements),
            Field::key("elements"),
            self.elements as f64,
            || "must lie in [1, 256]".into(),
        )?;
        require(
            !self.objects.is_empty() || self.open.is_some(),
            Field::key("object"),
            0.0,
            || "at least one [[object]] (or an [open] requirement) is needed".into(),
        )?;
        require(
            self.objects.len() <= MAX_OBJECTS,
            Field::key("object"),
            self.objects.len() as f64,
            || {
                format!(
                "at most {MAX_OBJECTS} [[object]] tables (each one's margins are solved at every design the search tries)"
            )
            },
        )?;
        for (i, o) in self.objects.iter().enumerate() {
            let field = |k: &str| Field::from(format!("object[{i}].{k}"));
            let (range, range_key, lift, max_normal) = match o {
                ObjectRequirement::Cuboid {
                    size_mm,
                    lift_n,
                    max_normal_n,
                } => (size_mm, "size_mm", lift_n, max_normal_n),
                ObjectRequirement::Sphere {
                    radius_mm,
                    lift_n,
                    max_normal_n,
                } => (radius_mm, "radius_mm", lift_n, max_normal_n),
            };
            for (k, &v) in range.iter().enumerate() {
                within(
                    field(&format!("{range_key}[{k}]")),
                    v,
                    LENGTH_RANGE_MM,
                    " mm",
                )?;
            }
            require(range[0] <= range[1], field(range_key), range[1], || {
                "must be [smallest, largest]".into()
            })?;
            within(field("lift_n"), *lift, FORCE_RANGE_N, " N")?;
            if let Some(m) = max_normal {
                within(field("max_normal_n"), *m, FORCE_RANGE_N, " N")?;
            }
        }
        if let Some(o) = &self.open {
            within(
                Field::key("open.size_mm"),
                o.size_mm,
                LENGTH_RANGE_MM,
                " mm",
            )?;
            finite(Field::key("open.pressure_kpa"), o.pressure_kpa)?;
            require(
                (0.0..=1000.0).contains(&o.pressure_kpa),
                Field::key("open.pressure_kpa"),
                o.pressure_kpa,
                || "must lie in [0, 1000] kPa".into(),
            )?;
        }
        let bound = |key: &str, b: Option<[f64; 2]>, lo: f64, hi: f64| -> Result<(), InputError> {
            if let Some([a, z]) = b {
                finite(format!("vary.{key}[0]").into(), a)?;
                finite(format!("vary.{key}[1]").into(), z)?;
                require(a <= z, format!("vary.{key}").into(), z, || {
                    "must be [low, high]".into()
                })?;
                require(
                    a >= lo && z <= hi,
                    format!("vary.{key}").into(),
                    if a < lo { a } else { z },
                    || format!("must lie within [{lo}, {hi}]"),
                )?;
            }
            Ok(())
        };
        bound("eps0", self.vary.eps0, 0.0, 0.6)?;
        bound(
            "mounting_angle_deg",
            self.vary.mounting_angle_deg,
            1.0,
            179.0,
        )?;
        bound("overlap_mm", self.vary.overlap_mm, -200.0, 200.0)?;
        if !self.vary.allow_outside_design_space {
            let [lo, hi] = self.design_space_deg();
            let given = self
                .vary
                .mounting_angle_deg
                .unwrap_or([DEFAULT_DESIGN[1]; 2]);
            let (field, value) = match self.vary.mounting_angle_deg {
                Some(_) => ("vary.mounting_angle_deg", given[1]),
                // fixed at the paper's value, outside this mu's design space
                None => ("mu", self.mu),
            };
            require(
                given[1] >= lo && given[0] <= hi,
                Field::key(field),
                value,
                || {
                    format!(
                    "leaves no mounting angle in the design space [{lo:.3}, {hi}] deg (arccot mu to 90 deg); set vary.allow_outside_design_space = true to search outside it"
                )
                },
            )?;
        }
        require(
            self.vary.eps0.is_some()
                || self.vary.mounting_angle_deg.is_some()
                || self.vary.overlap_mm.is_some(),
            Field::key("vary"),
            0.0,
            || "must give at least one design variable".into(),
        )?;
        Ok(())
    }
}

impl RequirementsError {
    /// Where the error lies in `text`, the document that was parsed: line
    /// and column, both from 1. A syntax error's own; for a value error,
    /// the value of the key it names (`object[1].size_mm[0]` is the first
    /// number of the second `[[object]]`'s `size_mm`), or `None` where the
    /// file does not write that key (`object = 0`: no `[[object]]` table
    /// at all). Too many `[[object]]` tables: the first one past
    /// [`MAX_OBJECTS`].
    pub fn position(&self, text: &str) -> Option<(usize, usize)> {
        match self {
            RequirementsError::Syntax(s) => Some((s.line, s.col)),
            RequirementsError::Input(i) => {
                let field = i.field().to_string();
                let path = match i {
                    InputError::OutOfRange { value, .. }
                        if field == "object" && *value > MAX_OBJECTS as f64 =>
                    {
                        format!("object[{MAX_OBJECTS}]")
                    }
                    _ => field,
                };
                locate(text, &path)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::requirements::tests::PAPER;
    use super::super::requirements::RequirementsError;
    use super::*;

    /// The audit's values: sizes that overflow a sample, requirements so
    /// small that a margin normalised by them is infinite, friction that
    /// overflows a force. Each is refused on reading, naming its key; the
    /// bounds themselves are accepted.
    #[test]
    fn lengths_forces_and_friction_are_bounded_on_reading() {
        let sphere = PAPER.replace(
            "kind = \"cuboid\"\nsize_mm = [60.0, 120.0]",
            "kind = \"sphere\"\nradius_mm = [20.0, 30.0]",
        );
        let open = format!("{PAPER}[open]\nsize_mm = 100.0\npressure_kpa = 50.0\n");
        let fragile = PAPER.replace("lift_n = 0.3", "lift_n = 0.3\nmax_normal_n = 2.0");
        for (text, from, to, field) in [
            (
                PAPER,
                "[60.0, 120.0]",
                "[60.0, 1e308]",
                "object[0].size_mm[1]",
            ),
            (
                PAPER,
                "[60.0, 120.0]",
                "[1e-320, 120.0]",
                "object[0].size_mm[0]",
            ),
            (
                PAPER,
                "[60.0, 120.0]",
                "[60.0, 20000.0]",
                "object[0].size_mm[1]",
            ),
            (
                &sphere,
                "[20.0, 30.0]",
                "[1e-320, 30.0]",
                "object[0].radius_mm[0]",
            ),
            (
                &sphere,
                "[20.0, 30.0]",
                "[20.0, inf]",
                "object[0].radius_mm[1]",
            ),
            (PAPER, "lift_n = 0.3", "lift_n = 1e-320", "object[0].lift_n"),
            (PAPER, "lift_n = 0.3", "lift_n = 5e-7", "object[0].lift_n"),
            (PAPER, "lift_n = 0.3", "lift_n = 1e300", "object[0].lift_n"),
            (
                &fragile,
                "max_normal_n = 2.0",
                "max_normal_n = 1e-320",
                "object[0].max_normal_n",
            ),
            (
                &fragile,
                "max_normal_n = 2.0",
                "max_normal_n = 2e4",
                "object[0].max_normal_n",
            ),
            (&open, "size_mm = 100.0", "size_mm = 1e-320", "open.size_mm"),
            (&open, "size_mm = 100.0", "size_mm = 1e308", "open.size_mm"),
            (PAPER, "mu = 0.6", "mu = 1e300", "mu"),
            (PAPER, "mu = 0.6", "mu = 1e-9", "mu"),
        ] {
            let changed = text.replace(from, to);
            assert_ne!(changed, text, "{to}");
            let e = Requirements::parse(&changed).unwrap_err();
            let RequirementsError::Input(i) = e else {
                panic!("{to}: {e:?}")
            };
            assert_eq!(i.field(), field, "{to}: {i}");
        }
        // the bounds themselves pass
        let [short, long] = LENGTH_RANGE_MM;
        let [light, heavy] = FORCE_RANGE_N;
        let at_bounds = fragile
            .replace("[60.0, 120.0]", &format!("[{short:e}, {long:e}]"))
            .replace("lift_n = 0.3", &format!("lift_n = {light:e}"))
            .replace("max_normal_n = 2.0", &format!("max_normal_n = {heavy:e}"));
        Requirements::parse(&at_bounds).unwrap();
        let mu = PAPER.replace("mu = 0.6", &format!("mu = {:e}", MU_RANGE[1]));
        assert_eq!(Requirements::parse(&mu).unwrap().mu, 10.0);
    }

    /// `n` cuboid tables and a `[vary]` table.
    fn objects(n: usize) -> String {
        let table = "[[object]]\nkind = \"cuboid\"\nsize_mm = [60.0, 80.0]\nlift_n = 0.3\n";
        format!("{}[vary]\neps0 = [0.1, 0.5]\n", table.repeat(n))
    }

    #[test]
    fn the_number_of_objects_is_bounded_and_the_first_one_past_it_located() {
        assert_eq!(
            Requirements::parse(&objects(MAX_OBJECTS))
                .unwrap()
                .objects
                .len(),
            MAX_OBJECTS
        );
        for n in [MAX_OBJECTS + 1, 2000] {
            let text = objects(n);
            let e = Requirements::parse(&text).unwrap_err();
            let RequirementsError::Input(i) = &e else {
                panic!("{e:?}")
            };
            assert_eq!(i.field(), "object", "{i}");
            assert!(
                i.to_string().contains(&format!("at most {MAX_OBJECTS}")),
                "{i}"
            );
            // four lines per table: the header of the one past the limit
            assert_eq!(e.position(&text), Some((4 * MAX_OBJECTS + 1, 1)), "{i}");
        }
    }

    /// A value error is located at the value of the key it names, as the
    /// file writes it; a key the file does not write has no position.
    #[test]
    fn value_errors_are_located_at_their_key() {
        let text = "fingers = 3\n\n[[object]]\nkind = \"cuboid\"\nsize_mm = [60.0, 80.0]\nlift_n = 0.3\n\n[[object]]\nkind = \"sphere\"\nradius_mm = [30.0, 40.0]\nlift_n = 0.5\n\n[vary]\neps0 = [0.1, 0.5]\n";
        // (replace, with, field, line, column of the value)
        for (from, to, field, line, col) in [
            ("fingers = 3", "fingers = 1", "fingers", 1, 11),
            ("fingers = 3", "fingers =  40", "fingers", 1, 12),
            (
                "[30.0, 40.0]",
                "[30.0, 0.0]",
                "object[1].radius_mm[1]",
                10,
                20,
            ),
            (
                "[30.0, 40.0]",
                "[30.0, 20.0]",
                "object[1].radius_mm",
                10,
                13,
            ),
            ("lift_n = 0.5", "lift_n = -0.5", "object[1].lift_n", 11, 10),
            ("eps0 = [0.1, 0.5]", "eps0 = [0.5, 0.1]", "vary.eps0", 14, 8),
            ("eps0 = [0.1, 0.5]", "", "vary", 13, 1),
        ] {
            let changed = text.replace(from, to);
            let e = Requirements::parse(&changed).unwrap_err();
            let RequirementsError::Input(i) = &e else {
                panic!("{to}: {e:?}")
            };
            assert_eq!(i.field(), field, "{to}: {i}");
            assert_eq!(e.position(&changed), Some((line, col)), "{to}: {i}");
        }
        // one finger is refused, saying why
        let e = Requirements::parse(&text.replace("fingers = 3", "fingers = 1")).unwrap_err();
        assert!(e.to_string().contains("facing each other"), "{e}");
        // the paper's fixed mounting angle outside the design space of mu:
        // the error names mu, at its value
        let angle = "[[object]]\nkind = \"cuboid\"\nsize_mm = [60.0, 80.0]\nlift_n = 0.3\n[vary]\neps0 = [0.1, 0.5]\n";
        let e = Requirements::parse(&format!("mu = 0.1\n{angle}")).unwrap_err();
        assert_eq!(
            e.position(&format!("mu = 0.1\n{angle}")),
            Some((1, 6)),
            "{e}"
        );
        // no object: nothing the file writes to point at
        let e = Requirements::parse("[vary]\neps0 = [0.1, 0.5]\n").unwrap_err();
        assert!(e.to_string().starts_with("object = 0"), "{e}");
        assert_eq!(e.position("[vary]\neps0 = [0.1, 0.5]\n"), None, "{e}");
        // a syntax error keeps its own
        let e = Requirements::parse("fingers = 3\nfingerz = 2\n").unwrap_err();
        assert_eq!(
            e.position("fingers = 3\nfingerz = 2\n"),
            Some((2, 1)),
            "{e}"
        );
    }
}
