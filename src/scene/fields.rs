//! Scene keys in messages: library field names mapped to the scene's
//! keys, and warnings in the scene's terms.

use crate::error::{InputError, SolveError, Warning};

/// A warning in the scene's terms (its keys and units).
pub fn warning_text(w: &Warning) -> String {
    match *w {
        Warning::MountingAngleOutsideDesignSpace { angle, lo, hi } => format!(
            "gripper.mounting_angle_deg = {}: outside the design space [{}, {}] deg (arccot mu to 90 deg)",
            degrees(angle),
            degrees(lo),
            degrees(hi)
        ),
        Warning::PalmGapAtRest { palm, reach } => format!(
            "gripper: the palm diameter {palm:.4} mm is wider than twice the finger's inward reach l0 = {reach:.4} mm (negative overlap): the fingers leave a gap at rest"
        ),
        _ => w.to_string(),
    }
}

/// Radians in degrees, rounded to 1e-9 deg (so 60 deg prints as 60).
fn degrees(rad: f64) -> f64 {
    (rad.to_degrees() * 1e9).round() / 1e9
}

/// The scene key of a field the library names in its own terms.
fn toml_path(field: &str) -> String {
    if let Some(rest) = field.strip_prefix("actuator.pemc.law.") {
        return format!("actuator.pemc.{rest}");
    }
    if let Some(rest) = field.strip_prefix("actuator.ribs[") {
        return format!("actuator.ribs.list[{rest}");
    }
    let renamed = match field {
        "partition.n" => "partition.elements",
        "partition.lx" => "actuator.geometry.lx",
        "partition.lengths (sum)" => "partition.lengths",
        "tip_tol_mm" => "partition.tip_tol_mm",
        "load.pressure" => "load.pressure_kpa",
        "gripper.mounting_angle" => "gripper.mounting_angle_deg",
        "gripper.overlap" => "gripper.overlap_mm",
        "gripper.palm" => "gripper.palm_mm",
        "grasp.pressure_kpa" => "gripper.grasp.pressure_kpa",
        "grasp.size" => "gripper.grasp.d_mm",
        "grasp.beta" | "sphere.beta" => "gripper.grasp.beta_deg",
        "grasp.friction" => "gripper.grasp.friction_n",
        "sphere.radius" => "gripper.grasp.r_mm",
        "sphere.lift" => "gripper.grasp.lift_n",
        other => other,
    };
    renamed.to_string()
}

/// The same error naming the field by its scene key.
pub(super) fn rename(e: InputError) -> InputError {
    match e {
        InputError::NotFinite { field, value } => InputError::NotFinite {
            field: toml_path(&field),
            value,
        },
        InputError::NotPositive { field, value } => InputError::NotPositive {
            field: toml_path(&field),
            value,
        },
        InputError::OutOfRange { field, value, rule } => InputError::OutOfRange {
            field: toml_path(&field),
            value,
            rule,
        },
        InputError::Inconsistent { field, rule } => InputError::Inconsistent {
            field: toml_path(&field),
            rule,
        },
    }
}

pub(super) fn rename_solve(e: SolveError) -> SolveError {
    match e {
        SolveError::Input(i) => SolveError::Input(rename(i)),
        other => other,
    }
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    #[test]
    fn toml_paths_of_library_fields() {
        assert_eq!(toml_path("actuator.pemc.law.p1"), "actuator.pemc.p1");
        assert_eq!(toml_path("actuator.pemc.law.p4"), "actuator.pemc.p4");
        assert_eq!(
            toml_path("actuator.ribs[2].width"),
            "actuator.ribs.list[2].width"
        );
        assert_eq!(toml_path("actuator.ribs.w1"), "actuator.ribs.w1");
        assert_eq!(toml_path("actuator.ribs"), "actuator.ribs");
        assert_eq!(toml_path("load.pressure"), "load.pressure_kpa");
    }

    #[test]
    fn warnings_use_scene_keys() {
        let s = Scene::from_toml("[gripper]\nmounting_angle_deg = 30\n").unwrap();
        let sol = s.solve().unwrap();
        let texts: Vec<String> = sol.warnings().iter().map(warning_text).collect();
        assert!(
            texts
                .iter()
                .any(|t| t.starts_with("gripper.mounting_angle_deg = 30")),
            "{texts:?}"
        );
        let s = Scene::from_toml("[actuator.pemc]\neps0 = 0.8\n").unwrap();
        let texts: Vec<String> = s.warnings().iter().map(warning_text).collect();
        assert!(
            texts[0].starts_with("actuator.pemc.eps0 = 0.8"),
            "{texts:?}"
        );
    }
}
