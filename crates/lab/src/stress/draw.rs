//! Drawing a case: the per-case random stream, one draw of every input,
//! and redrawing until validation accepts.

use std::panic::{catch_unwind, AssertUnwindSafe};

use fpc::actuator::{Channel, Geometry};
use fpc::{Actuator, InputError, ModelId};

use super::inputs::{force_scale, StressInputs};
use super::{AUTO_FRACTION, ELEMENT_WEIGHTS, MAX_DRAWS, STRESS_ELEMENT_COUNTS};

/// Relative thicknesses of the default stack: CL, regular EMC, fluidic
/// layer, prestressed EMC (mm).
const STACK: [f64; 4] = [0.4, 1.9, 4.0, 1.9];

/// Why a case has no actuator to solve.
pub(super) enum NoFinger {
    Rejected(String),
    Panicked(String),
}

/// Draws until validation accepts (at most [`MAX_DRAWS`] times).
pub(super) fn draw_case(
    seed: u64,
    index: usize,
    max_elements: usize,
) -> (StressInputs, Vec<String>, Result<Actuator, NoFinger>) {
    let mut rng = CaseRng::for_case(seed, index);
    let mut rejected = Vec::new();
    loop {
        let (mut inputs, angle) = draw(&mut rng, max_elements);
        let validated = catch_unwind(AssertUnwindSafe(|| {
            let act = inputs.actuator()?;
            inputs.partition()?;
            let scale = force_scale(&act);
            Ok::<_, InputError>((act, scale))
        }));
        match validated {
            Err(p) => {
                let m = format!("while validating: {}", fpc::cancel::panic_text(&*p));
                return (inputs, rejected, Err(NoFinger::Panicked(m)));
            }
            Ok(Ok((act, scale))) => {
                // an undefined scale (not seen) leaves the scene unloaded
                let scale = if scale.is_finite() && scale > 0.0 {
                    scale
                } else {
                    0.0
                };
                inputs.force_scale = scale;
                let f = inputs.relative_load * scale;
                inputs.fx = f * angle.cos();
                inputs.fz = f * angle.sin();
                return (inputs, rejected, Ok(act));
            }
            Ok(Err(e)) => {
                if rejected.len() + 1 >= MAX_DRAWS {
                    return (inputs, rejected, Err(NoFinger::Rejected(e.to_string())));
                }
                rejected.push(e.field().to_string());
            }
        }
    }
}

/// The random stream of one case: fastrand's generator, seeded from the
/// run's seed and the case index, so a case does not depend on the cases
/// before it (an early stop does not change later cases).
#[derive(Debug, Clone)]
struct CaseRng(fastrand::Rng);

impl CaseRng {
    fn for_case(seed: u64, index: usize) -> CaseRng {
        // the index picks a stream; fastrand mixes the seed itself
        let stream = fastrand::Rng::with_seed(index as u64).u64(..);
        CaseRng(fastrand::Rng::with_seed(seed ^ stream))
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        self.0.f64()
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    fn log_range(&mut self, lo: f64, hi: f64) -> f64 {
        self.range(lo.ln(), hi.ln()).exp()
    }

    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    fn below(&mut self, n: usize) -> usize {
        self.0.usize(..n.max(1))
    }
}

/// One draw of every input (module docs) and the tip load's direction
/// (rad from +X); validation and the load in newtons are the caller's.
fn draw(rng: &mut CaseRng, max_elements: usize) -> (StressInputs, f64) {
    use std::f64::consts::{FRAC_PI_2, PI};
    let model = ModelId::ALL[rng.below(ModelId::ALL.len())];
    let eps0 = rng.range(0.01, 0.6);
    let pressure_kpa = if rng.chance(0.2) {
        0.0
    } else {
        rng.range(0.0, 600.0)
    };
    let (relative_load, angle) = if rng.chance(0.3) {
        (0.0, 0.0)
    } else {
        let f = rng.log_range(1e-3, 30.0);
        let u = rng.unit();
        let sign = if rng.chance(0.5) { 1.0 } else { -1.0 };
        let angle = if u < 1.0 / 7.0 {
            if sign > 0.0 {
                0.0
            } else {
                PI
            }
        } else if u < 2.0 / 7.0 {
            sign * FRAC_PI_2
        } else {
            rng.range(-PI, PI)
        };
        (f, angle)
    };
    // the partition: automatic, or a weighted, capped element count
    let auto_partition = rng.chance(AUTO_FRACTION);
    let max_elements = max_elements.max(1);
    let allowed: Vec<(usize, f64)> = STRESS_ELEMENT_COUNTS
        .iter()
        .zip(ELEMENT_WEIGHTS)
        .filter(|(&n, _)| n <= max_elements)
        .map(|(&n, w)| (n, w))
        .collect();
    let total: f64 = allowed.iter().map(|(_, w)| w).sum();
    let mut pick = rng.unit() * total;
    let mut elements = allowed.last().map_or(1, |a| a.0);
    for &(n, w) in &allowed {
        if pick < w {
            elements = n;
            break;
        }
        pick -= w;
    }
    let lx = Geometry::default().lx;
    let lengths = if elements == 1 || rng.chance(0.3) {
        vec![lx / elements as f64; elements]
    } else {
        let ratio = rng.log_range(1.0, 100.0);
        let mut u: Vec<f64> = (0..elements).map(|_| rng.unit()).collect();
        let lo = rng.below(elements);
        let mut hi = rng.below(elements - 1);
        if hi >= lo {
            hi += 1;
        }
        u[lo] = 0.0;
        u[hi] = 1.0;
        let raw: Vec<f64> = u.iter().map(|&u| ratio.powf(u)).collect();
        let sum: f64 = raw.iter().sum();
        raw.iter().map(|r| r * lx / sum).collect()
    };
    let (lengths, elements, length_ratio) = if auto_partition {
        (Vec::new(), 0, 1.0)
    } else {
        let (lmin, lmax) = lengths
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &l| (a.min(l), b.max(l)));
        (lengths, elements, lmax / lmin)
    };
    // the layer stack
    let thickness_scale = rng.log_range(0.3, 3.0);
    let jittered = rng.chance(0.35);
    let mut lamina_factors = [1.0; 4];
    if jittered {
        for f in &mut lamina_factors {
            *f = rng.log_range(0.5, 2.0);
        }
    }
    let t: Vec<f64> = STACK
        .iter()
        .zip(lamina_factors)
        .map(|(t, f)| t * f * thickness_scale)
        .collect();
    let h = t.iter().sum::<f64>();
    let h1 = h / 2.0 - t[0];
    let h2 = h1 - t[1];
    let h3 = t[2] - h2;
    let d = Geometry::default();
    let dc = Channel::default();
    let (fa, fb) = if jittered {
        (rng.range(0.15, 0.95), rng.range(0.15, 0.95))
    } else {
        (dc.h3a / d.h2, dc.h3b / d.h3)
    };
    let geometry = Geometry { h, h1, h2, h3, ..d };
    let channel = Channel {
        h3a: fa * h2,
        h3b: fb * h3,
        ..dc
    };
    let ribs = rng.chance(0.5);
    (
        StressInputs {
            model,
            eps0,
            pressure_kpa,
            fx: 0.0,
            fz: 0.0,
            relative_load,
            force_scale: 0.0,
            auto_partition,
            elements,
            lengths,
            length_ratio,
            thickness_scale,
            jittered,
            lamina_factors,
            geometry,
            channel,
            ribs,
        },
        angle,
    )
}
