//! A design's claim checked through the ordinary path: every object's
//! scene file ([`Designed::scenes`]) is parsed and solved as `fpc solve`
//! would, and its grasp must be valid and give the claimed lifting and
//! normal forces to [`REPRODUCE_RTOL`] before the design is reported as
//! meeting its requirements.

use serde::Serialize;

use super::evaluate::{notes, Evaluation};
use super::requirements::Requirements;
use crate::scene::{Scene, SceneSolution};

/// The relative agreement a re-solved scene must show with the claim.
pub const REPRODUCE_RTOL: f64 = 1e-6;

/// One object's scene, solved again.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reproduction {
    /// The scene file's name (`object0_cuboid.toml`, ...).
    pub file: String,
    /// The scene file's text.
    #[serde(skip)]
    pub text: String,
    /// The margin it reproduces: the object's hardest lift margin; when
    /// no lift was claimed, the object's hardest margin of any kind (what
    /// kept it from a claim, `object[0] cuboid d = 150.0 mm: fits`).
    pub requirement: String,
    /// The claimed lifting force (N); `None` when no valid grasp was claimed.
    pub claimed_lift_n: Option<f64>,
    /// The claimed normal force (N).
    pub claimed_normal_n: Option<f64>,
    /// The scene's lifting force (N), when it solved.
    pub solved_lift_n: Option<f64>,
    /// The scene's normal force (N), when it solved.
    pub solved_normal_n: Option<f64>,
    /// The scene's grasp is valid (the one verdict).
    pub valid: bool,
    /// The scene confirms the claim: the same verdict, with the claimed
    /// forces to [`REPRODUCE_RTOL`]; or, where no grasp was claimed, no
    /// valid grasp either.
    pub reproduced: bool,
    /// What the scene gave, in words.
    pub detail: String,
    /// The notes of the scene's grasp that do not make it invalid (a
    /// reversed element outside strict mode, the actuator's notes), in
    /// words: a claim is reported with them, never without.
    pub notes: Vec<String>,
}

fn agrees(claimed: f64, solved: f64) -> bool {
    (claimed - solved).abs() <= REPRODUCE_RTOL * claimed.abs().max(solved.abs()).max(1e-9)
}

/// Solves every scene of the design `best` ([`Evaluation::scenes`])
/// through the ordinary scene path and compares it with the claim.
pub fn reproduce(best: &Evaluation, req: &Requirements) -> Vec<Reproduction> {
    best.scenes(req)
        .into_iter()
        .enumerate()
        .map(|(i, (file, text))| {
            let claim = best.hardest_lift(i);
            // no lift claimed: the object's hardest margin says why
            let requirement = claim
                .or_else(|| best.hardest(i))
                .map(|m| m.requirement.clone())
                .unwrap_or_default();
            let claimed_lift_n = claim.and_then(|m| m.value);
            let claimed_normal_n = claim.and_then(|m| m.normal_n);
            let claimed_valid = claim.and_then(|m| m.valid);
            let solved = Scene::from_toml(&text)
                .map_err(|e| e.to_string())
                .and_then(|s| s.solve().map_err(|e| e.to_string()));
            let grasp = match &solved {
                Ok(SceneSolution::Gripper { grasp: Some(g), .. }) => Some(g),
                _ => None,
            };
            let valid = grasp.is_some_and(|g| g.is_valid());
            let detail = match (&solved, grasp) {
                (_, Some(g)) => match g.invalid() {
                    None => "valid".to_string(),
                    Some(inv) => format!("invalid: {inv}"),
                },
                (Ok(_), None) => "no grasp in the scene".into(),
                (Err(e), _) => format!("does not solve: {e}"),
            };
            let notes = grasp.map(|g| notes(&g.grasp.warnings)).unwrap_or_default();
            let (solved_lift_n, solved_normal_n) = match grasp {
                Some(g) => (Some(g.grasp.lift), Some(g.grasp.normal)),
                None => (None, None),
            };
            let reproduced = match (claimed_lift_n, claimed_normal_n, claimed_valid) {
                (Some(l), Some(n), Some(v)) => {
                    valid == v
                        && solved_lift_n.is_some_and(|s| agrees(l, s))
                        && solved_normal_n.is_some_and(|s| agrees(n, s))
                }
                // nothing claimed: the scene must not find a valid grasp
                _ => !valid,
            };
            Reproduction {
                file,
                text,
                requirement,
                claimed_lift_n,
                claimed_normal_n,
                solved_lift_n,
                solved_normal_n,
                valid,
                reproduced,
                detail,
                notes,
            }
        })
        .collect()
}
