//! Clipping: a panel's points beyond its axis limits, marked and noted.

use super::*;

/// What of a series is drawn under a clipped axis top: the polylines
/// (each cut where it leaves the chart; an area is capped at the top
/// instead), the markers kept, and the x of every place where it leaves
/// or comes back (a line) or of every point above (markers).
pub(super) struct Shown {
    pub(super) runs: Vec<Vec<(f64, f64)>>,
    pub(super) marks: Vec<(f64, f64)>,
    pub(super) off: Vec<f64>,
}

impl Shown {
    pub(super) fn of(s: &Series, top: Option<f64>) -> Shown {
        let pts = finite(&s.points);
        let lines = matches!(
            s.kind,
            SeriesKind::Line
                | SeriesKind::Dashed
                | SeriesKind::LinePoints
                | SeriesKind::Area
                | SeriesKind::Outline
                | SeriesKind::Spread
        );
        let Some(top) = top else {
            return Shown {
                runs: if lines { vec![pts.clone()] } else { Vec::new() },
                marks: if lines && s.kind != SeriesKind::LinePoints {
                    Vec::new()
                } else {
                    pts
                },
                off: Vec::new(),
            };
        };
        let above = |p: &(f64, f64)| p.1 > top;
        let marks = if lines && s.kind != SeriesKind::LinePoints {
            Vec::new()
        } else {
            pts.iter().filter(|p| !above(p)).copied().collect()
        };
        if !lines {
            let off = pts.iter().filter(|p| above(p)).map(|p| p.0).collect();
            return Shown {
                runs: Vec::new(),
                marks,
                off,
            };
        }
        let area = s.kind == SeriesKind::Area;
        let (mut runs, mut run, mut off) = (Vec::new(), Vec::new(), Vec::new());
        for (i, &q) in pts.iter().enumerate() {
            if i > 0 {
                let p = pts[i - 1];
                if above(&p) != above(&q) {
                    // where the segment crosses the top
                    let x = p.0 + (q.0 - p.0) * (top - p.1) / (q.1 - p.1);
                    run.push((x, top));
                    off.push(x);
                    if above(&q) && !area {
                        runs.push(std::mem::take(&mut run));
                    }
                }
            }
            if !above(&q) {
                run.push(q);
            } else if area {
                run.push((q.0, top));
            }
        }
        if !run.is_empty() {
            runs.push(run);
        }
        if off.is_empty() {
            // wholly above: one mark where it starts
            off.extend(pts.first().filter(|p| above(p)).map(|p| p.0));
        }
        Shown { runs, marks, off }
    }
}
