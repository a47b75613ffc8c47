//! Legend placement: the corner that covers the least of the data.

use super::*;

/// How much covering a reference line counts against a legend spot,
/// against 1 for data.
pub(super) const REFERENCE_WEIGHT: f64 = 0.2;

/// How much covering a filled area counts, per sample every 6 pixels.
pub(super) const AREA_WEIGHT: f64 = 0.05;

/// Room of the vertical axis: whether its range may grow at the top or
/// the bottom to make space for the legend (a fitted axis, and at the top
/// one that is not clipped), and whether the panel keeps an equal aspect.
#[derive(Debug, Clone, Copy)]
pub(super) struct Room {
    pub(super) top: bool,
    pub(super) bottom: bool,
    pub(super) equal_aspect: bool,
}

/// What a legend should not cover: the lines and markers as drawn (in
/// data units), reference lines, and text boxes (pixels from the plotting
/// area's top-left corner) that it must not cover at all.
#[derive(Debug, Default)]
pub(super) struct Cover {
    /// Polylines and their weight.
    pub(super) lines: Vec<(Vec<(f64, f64)>, f64)>,
    /// Markers and their weight.
    pub(super) points: Vec<((f64, f64), f64)>,
    /// The tops of filled areas (down to y = 0).
    pub(super) areas: Vec<Vec<(f64, f64)>>,
    /// Horizontal reference lines (y).
    pub(super) hlines: Vec<f64>,
    /// Vertical reference lines (x).
    pub(super) vlines: Vec<f64>,
    /// [x0, y0, x1, y1] in pixels.
    pub(super) boxes: Vec<[f64; 4]>,
}

/// The legend spots in the order they are preferred after the panel's own
/// corner.
pub(super) const SPOTS: [SeriesLabelPosition; 8] = [
    SeriesLabelPosition::UpperRight,
    SeriesLabelPosition::UpperLeft,
    SeriesLabelPosition::LowerRight,
    SeriesLabelPosition::LowerLeft,
    SeriesLabelPosition::UpperMiddle,
    SeriesLabelPosition::LowerMiddle,
    SeriesLabelPosition::MiddleRight,
    SeriesLabelPosition::MiddleLeft,
];

/// The pixel box [x0, y0, x1, y1] of a legend of `size` at `spot` in a
/// plotting area of `px`, laid out as plotters does (5 pixels from the
/// edges).
pub(super) fn spot_box(spot: &SeriesLabelPosition, size: (f64, f64), px: (f64, f64)) -> [f64; 4] {
    use SeriesLabelPosition as P;
    let x = match spot {
        P::UpperLeft | P::MiddleLeft | P::LowerLeft => 5.0,
        P::UpperMiddle | P::MiddleMiddle | P::LowerMiddle => ((px.0 - size.0) / 2.0).floor(),
        _ => px.0 - size.0 - 5.0,
    };
    let y = match spot {
        P::UpperLeft | P::UpperMiddle | P::UpperRight => 5.0,
        P::MiddleLeft | P::MiddleMiddle | P::MiddleRight => ((px.1 - size.1) / 2.0).floor(),
        _ => px.1 - size.1 - 5.0,
    };
    [x, y, x + size.0, y + size.1]
}

impl Cover {
    /// Weighted pixel samples of everything on `f`: a polyline every 3
    /// pixels or so, reference lines across the frame.
    pub(super) fn samples(&self, f: &Frame) -> Vec<(f64, f64, f64)> {
        let mut out = Vec::new();
        let mut line = |path: &[(f64, f64)], w: f64| {
            let px: Vec<(f64, f64)> = path.iter().map(|&p| f.pixel(p)).collect();
            if let [only] = px[..] {
                out.push((only.0, only.1, w));
            }
            for s in px.windows(2) {
                let (a, b) = (s[0], s[1]);
                let len = (b.0 - a.0).abs().max((b.1 - a.1).abs());
                let n = (len / 3.0).ceil().clamp(1.0, 1e5) as usize;
                for i in 0..=n {
                    let t = i as f64 / n as f64;
                    out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1), w));
                }
            }
        };
        for (path, w) in &self.lines {
            line(path, *w);
        }
        for &y in &self.hlines {
            line(&[(f.x.0, y), (f.x.1, y)], REFERENCE_WEIGHT);
        }
        for &x in &self.vlines {
            line(&[(x, f.y.0), (x, f.y.1)], REFERENCE_WEIGHT);
        }
        // a filled area: columns of samples down to its base
        let base = f.pixel((0.0, 0.0)).1.clamp(0.0, f.px.1);
        for top in &self.areas {
            let px: Vec<(f64, f64)> = top.iter().map(|&p| f.pixel(p)).collect();
            for s in px.windows(2) {
                let (a, b) = (s[0], s[1]);
                let n = ((b.0 - a.0).abs() / 6.0).ceil().clamp(1.0, 1e4) as usize;
                for i in 0..n {
                    let t = i as f64 / n as f64;
                    let (x, y) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
                    let (lo, hi) = (y.min(base).max(0.0), y.max(base).min(f.px.1));
                    let rows = ((hi - lo) / 6.0).ceil().min(1e4) as usize;
                    out.extend((0..rows).map(|j| (x, lo + 6.0 * j as f64, AREA_WEIGHT)));
                }
            }
        }
        for &(p, w) in &self.points {
            let (x, y) = f.pixel(p);
            out.push((x, y, w));
        }
        out
    }

    /// How much a legend box covers (4 pixels of room around it): the
    /// weights of the samples inside, 1000 for each text box it touches.
    pub(super) fn covered(&self, samples: &[(f64, f64, f64)], r: [f64; 4]) -> f64 {
        let pad = 4.0;
        let data: f64 = samples
            .iter()
            .filter(|p| {
                p.0 >= r[0] - pad && p.0 <= r[2] + pad && p.1 >= r[1] - pad && p.1 <= r[3] + pad
            })
            .map(|p| p.2)
            .sum();
        let text = self
            .boxes
            .iter()
            .filter(|b| b[0] <= r[2] && b[2] >= r[0] && b[1] <= r[3] && b[3] >= r[1])
            .count();
        data + 1000.0 * text as f64
    }

    /// The legend's spot and the frame to draw: the panel's corner when
    /// the legend covers nothing there; else the first other corner or
    /// edge middle where it covers nothing; else the least growth of the
    /// vertical range (at the top for an upper spot, at the bottom for a
    /// lower one, as `room` allows) that clears a corner or edge middle;
    /// else the spot that covers least.
    pub(super) fn place(
        &self,
        wish: Corner,
        size: (f64, f64),
        f: Frame,
        room: Room,
    ) -> (SeriesLabelPosition, Frame) {
        use SeriesLabelPosition as P;
        let spots: Vec<P> = std::iter::once(position(wish))
            .chain(SPOTS.iter().filter(|s| **s != position(wish)).cloned())
            .collect();
        let samples = self.samples(&f);
        let scores: Vec<f64> = spots
            .iter()
            .map(|s| self.covered(&samples, spot_box(s, size, f.px)))
            .collect();
        if let Some(i) = scores.iter().position(|&c| c == 0.0) {
            return (spots[i].clone(), f);
        }
        // grow the range by fractions of the legend's height
        let h = f.px.1;
        for frac in [0.25, 0.5, 0.75, 1.0, 1.25] {
            let extra = frac * (size.1 + 10.0);
            if extra > 0.5 * h {
                break;
            }
            for spot in &spots {
                let upper = matches!(spot, P::UpperLeft | P::UpperMiddle | P::UpperRight);
                let lower = matches!(spot, P::LowerLeft | P::LowerMiddle | P::LowerRight);
                if !(upper && room.top || lower && room.bottom) {
                    continue;
                }
                // the new span leaves `extra` pixels free on that side
                let span = f.y.1 - f.y.0;
                let more = span * h / (h - extra) - span;
                let mut g = f;
                if upper {
                    g.y.1 += more;
                } else {
                    g.y.0 -= more;
                }
                if room.equal_aspect {
                    g = g.equal_aspect();
                }
                let samples = self.samples(&g);
                if self.covered(&samples, spot_box(spot, size, g.px)) == 0.0 {
                    return (spot.clone(), g);
                }
            }
        }
        let best = (0..spots.len())
            .min_by(|&a, &b| scores[a].total_cmp(&scores[b]))
            .unwrap_or(0);
        (spots[best].clone(), f)
    }
}
