//! A grasp-size sweep carried past failed solves along the load path.

use crate::gripper::{Grasp, Gripper, Object, SizeTail};

use super::options::SweepStop;

/// Sweeps the grasping size over `n + 1` points from `from` to `to`
/// (grasping angle `beta`, `f = mu F`), each solve warm-started from the
/// previous. Where a target solve fails, the load path from the last grasp
/// is followed ([`Gripper::size_tail`]): the sweep goes on if it reaches
/// the size, and otherwise ends at the path's natural end (or, if the path
/// cannot be continued, at a numerical stop).
#[allow(clippy::too_many_arguments)]
pub(crate) fn size_sweep(
    g: &Gripper,
    pressure_kpa: f64,
    beta: f64,
    object: Object,
    from: f64,
    to: f64,
    n: usize,
    mut visit: impl FnMut(&Grasp),
) -> Option<SweepStop> {
    let mut warm: Option<Grasp> = None;
    for i in 0..=n {
        let d = from + (to - from) * i as f64 / n as f64;
        let gr = match g.size_grasp(pressure_kpa, d, beta, object, warm.as_ref(), false) {
            Ok(gr) => gr,
            Err(e) => {
                // from the last grasp, or the finger without contact force
                let start = match &warm {
                    Some(w) => Ok(w.clone()),
                    None => g.sweep_start(pressure_kpa, beta, object),
                };
                let last = match start {
                    Ok(l) => l,
                    Err(e2) => {
                        return Some(SweepStop::failed(
                            d,
                            format!("{e}; and the start of the load path: {e2}"),
                        ))
                    }
                };
                match g.size_tail(&last, d) {
                    Ok(SizeTail::Reached(gr)) => *gr,
                    Ok(SizeTail::End(end)) => {
                        return Some(SweepStop {
                            at: d,
                            reason: end.to_string(),
                            end: Some(end),
                        })
                    }
                    Err(e2) => {
                        return Some(SweepStop::failed(
                            d,
                            format!("{e}; following the load path: {e2}"),
                        ))
                    }
                }
            }
        };
        visit(&gr);
        warm = Some(gr);
    }
    None
}
