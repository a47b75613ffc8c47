//! Test fixtures shared by the scene's tests: the example scenes and
//! helpers that expect an error.

use super::{Scene, SceneError, SceneFile, SceneReadError};
use crate::error::InputError;

pub(crate) const SCENES: &[(&str, &str)] = &[
    ("default.toml", include_str!("../../scenes/default.toml")),
    (
        "pressurised.toml",
        include_str!("../../scenes/pressurised.toml"),
    ),
    ("tip_load.toml", include_str!("../../scenes/tip_load.toml")),
    (
        "no_ribs_custom.toml",
        include_str!("../../scenes/no_ribs_custom.toml"),
    ),
    (
        "cuboid_grasp.toml",
        include_str!("../../scenes/cuboid_grasp.toml"),
    ),
    (
        "sphere_grasp.toml",
        include_str!("../../scenes/sphere_grasp.toml"),
    ),
];

pub(crate) fn input_err(text: &str) -> InputError {
    match Scene::from_toml(text) {
        Err(SceneReadError::Input(e)) => e,
        other => panic!("expected an input error for {text:?}, got {other:?}"),
    }
}

pub(crate) fn syntax_err(text: &str) -> SceneError {
    match SceneFile::parse(text) {
        Err(e) => e,
        Ok(f) => panic!("expected a syntax error for {text:?}, got {f:?}"),
    }
}
