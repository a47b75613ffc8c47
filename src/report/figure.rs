//! A figure as data: rows of panels, each with its axes, series (their
//! colour keys and how they are drawn), reference lines and bands, notes,
//! a caption, where its legend goes and how its vertical axis may be cut
//! short above outliers.

use serde::Serialize;

/// A figure: a title and rows of panels (each row split evenly across the
/// width, the rows evenly down the height).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Figure {
    /// Title over the whole figure.
    pub title: String,
    /// Width and height in pixels.
    pub size: [u32; 2],
    /// Rows of panels, top to bottom.
    pub rows: Vec<Vec<Panel>>,
}

impl Figure {
    /// A figure of one row of panels.
    pub fn row(title: impl Into<String>, size: [u32; 2], panels: Vec<Panel>) -> Figure {
        Figure {
            title: title.into(),
            size,
            rows: vec![panels],
        }
    }

    /// Every panel, row by row.
    pub fn panels(&self) -> impl Iterator<Item = &Panel> {
        self.rows.iter().flatten()
    }

    /// The clip notes of its panels ([`Panel::clip_note`]) with their
    /// panels' titles: what a caption says about axes cut short.
    pub fn clip_notes(&self) -> Vec<(String, String)> {
        self.panels()
            .filter_map(|p| Some((p.title.clone(), p.clip_note()?)))
            .collect()
    }
}

/// One axis of a panel.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlotAxis {
    /// What is plotted, e.g. `grasping size d`.
    pub label: String,
    /// Its unit, e.g. `mm` (empty: a pure number).
    pub unit: String,
    /// A fixed range (else fitted to the data).
    pub range: Option<[f64; 2]>,
    /// Include 0 in a fitted range.
    pub include_zero: bool,
    /// A logarithmic axis: positive values only, ticks at powers of ten.
    pub log: bool,
    /// A vertical axis whose values grow downwards (a frame whose axis
    /// points down, as the gripper's Zg): drawn upside down, its ticks
    /// showing the values.
    pub down: bool,
}

impl PlotAxis {
    /// An axis with a fitted range.
    pub fn new(label: &str, unit: &str) -> PlotAxis {
        PlotAxis {
            label: label.into(),
            unit: unit.into(),
            range: None,
            include_zero: false,
            log: false,
            down: false,
        }
    }

    /// A logarithmic axis (a renderer skips values that are not positive).
    pub fn log(mut self) -> Self {
        self.log = true;
        self
    }

    /// The label with its unit, `label (unit)`.
    pub fn text(&self) -> String {
        if self.unit.is_empty() {
            self.label.clone()
        } else {
            format!("{} ({})", self.label, self.unit)
        }
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SeriesKind {
    /// A solid line.
    Line,
    /// A dashed line.
    Dashed,
    /// A line with a marker at every point.
    LinePoints,
    /// Filled markers.
    Points,
    /// Small translucent markers (dense scatter).
    Scatter,
    /// Hollow markers.
    Hollow,
    /// Crosses.
    Cross,
    /// The area between the curve and y = 0.
    Area,
    /// Points whose grasp bends an element backwards (`curvature_reversal`):
    /// hollow markers over the curve they belong to, one legend entry per
    /// panel.
    BentBackwards,
    /// Points whose grasp is not valid (the one verdict): crosses over the
    /// curve they belong to, one legend entry per panel.
    Invalid,
    /// A closed outline, filled translucent (an object's section).
    Outline,
    /// A shaded band between two curves, the points its closed outline
    /// (the upper curve forwards, the lower one back): a curve's 1-sigma
    /// band ([`Series::spread`]). No line, no markers.
    Spread,
}

/// The legend entry and colour key of every [`SeriesKind::BentBackwards`]
/// series.
pub const BENT_BACKWARDS: &str = "bent backwards";

/// The legend entry and colour key of every [`SeriesKind::Invalid`] series.
pub const INVALID_GRASP: &str = "invalid grasp";

/// The colour key of what is no variable's value: a legend entry that
/// explains a line style or marker drawn in several colours.
pub const NEUTRAL: &str = "neutral";

/// One data series. `color` is a key naming the variable and its value
/// (`eps0=0.25`, `a=pi/3`, `g=10mm`) or the quantity (`normal force`), so
/// a renderer can give every key one colour across panels and studies.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Series {
    /// Legend entry (`None`: not in the legend).
    pub label: Option<String>,
    /// Colour key.
    pub color: String,
    /// How it is drawn.
    pub kind: SeriesKind,
    /// The points (x, y); non-finite ones are skipped when drawn.
    pub points: Vec<[f64; 2]>,
}

impl Series {
    /// A series without a legend entry.
    pub fn new(color: impl Into<String>, kind: SeriesKind, points: Vec<[f64; 2]>) -> Series {
        Series {
            label: None,
            color: color.into(),
            kind,
            points,
        }
    }

    /// With a legend entry.
    pub fn label(mut self, label: impl Into<String>) -> Series {
        self.label = Some(label.into());
        self
    }

    /// The shaded band `y - sd` to `y + sd` around the points `(x, y)`
    /// with standard deviations `sd` (points where either is not finite
    /// are left out), each of `y - sd` and `y + sd` held in `clamp`;
    /// `None` when fewer than two points are left.
    pub fn spread(
        color: impl Into<String>,
        points: &[[f64; 2]],
        sd: &[f64],
        clamp: [f64; 2],
    ) -> Option<Series> {
        let kept: Vec<([f64; 2], f64)> = points
            .iter()
            .zip(sd)
            .filter(|(p, s)| p[0].is_finite() && p[1].is_finite() && s.is_finite())
            .map(|(p, s)| (*p, *s))
            .collect();
        if kept.len() < 2 {
            return None;
        }
        let at = |y: f64| y.clamp(clamp[0], clamp[1]);
        let upper = kept.iter().map(|(p, s)| [p[0], at(p[1] + s)]);
        let lower = kept.iter().rev().map(|(p, s)| [p[0], at(p[1] - s)]);
        Some(Series::new(
            color,
            SeriesKind::Spread,
            upper.chain(lower).collect(),
        ))
    }

    /// The markers of the points that are bent backwards (colour key and
    /// legend entry [`BENT_BACKWARDS`]); `None` when there is none.
    pub fn bent_backwards(points: Vec<[f64; 2]>) -> Option<Series> {
        (!points.is_empty()).then(|| {
            Series::new(BENT_BACKWARDS, SeriesKind::BentBackwards, points).label(BENT_BACKWARDS)
        })
    }

    /// The markers of the points whose grasp is not valid (colour key and
    /// legend entry [`INVALID_GRASP`]); `None` when there is none.
    pub fn invalid(points: Vec<[f64; 2]>) -> Option<Series> {
        (!points.is_empty())
            .then(|| Series::new(INVALID_GRASP, SeriesKind::Invalid, points).label(INVALID_GRASP))
    }
}

/// A dashed grey reference line at a constant x or y.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RefLine {
    /// Where.
    pub at: f64,
    /// Legend entry (empty: none).
    pub label: String,
}

/// A shaded x range spanning the panel's height.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Band {
    /// From x.
    pub from: f64,
    /// To x.
    pub to: f64,
    /// Colour key.
    pub color: String,
}

/// A corner of a panel (where its legend goes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Corner {
    /// Top left.
    UpperLeft,
    /// Top right.
    UpperRight,
    /// Bottom left.
    LowerLeft,
    /// Bottom right.
    LowerRight,
}

/// One chart.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Panel {
    /// Title (may be empty).
    pub title: String,
    /// Horizontal axis.
    pub x: PlotAxis,
    /// Vertical axis.
    pub y: PlotAxis,
    /// Data series, drawn in order.
    pub series: Vec<Series>,
    /// Horizontal reference lines.
    pub hlines: Vec<RefLine>,
    /// Vertical reference lines.
    pub vlines: Vec<RefLine>,
    /// Shaded x ranges.
    pub bands: Vec<Band>,
    /// The bands' legend entry.
    pub band_label: Option<String>,
    /// Lines of text in the top-left corner.
    pub notes: Vec<String>,
    /// Same scale on both axes (shapes).
    pub equal_aspect: bool,
    /// Where the legend should go: a renderer keeps it there unless it
    /// would cover data there and less of it elsewhere (another corner or
    /// the middle of an edge).
    pub legend: Corner,
    /// Cut the vertical axis short above outliers ([`Panel::clipped`]).
    pub y_clip: Option<Clip>,
    /// Lines of text under the chart (wrapped to its width when drawn).
    pub caption: Vec<String>,
}

/// A rule that cuts a panel's vertical axis short when a few values are
/// far above the rest, so that the bulk of the curves is not squashed
/// flat: the axis ends at `base + factor * (q - base)`, rounded up to a
/// round number, where `q` is the `quantile` of the plotted values and
/// `base` the axis' lower end (the smallest value, or 0 when the axis
/// includes 0). It cuts only when the largest value is above that end.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Clip {
    /// The quantile of the plotted values the bound is taken from, in
    /// (0, 1].
    pub quantile: f64,
    /// The factor on that quantile's height above the base, at least 1.
    pub factor: f64,
}

impl Clip {
    /// The studies' rule: twice the 90 % quantile's height above the base.
    pub const OUTLIERS: Clip = Clip {
        quantile: 0.9,
        factor: 2.0,
    };
}

/// Where a panel's vertical axis is cut ([`Panel::clipped`]) and what lies
/// above it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Clipped {
    /// The axis' upper end (a round number).
    pub at: f64,
    /// How many plotted points lie above it.
    pub above: usize,
    /// The point with the largest value, (x, y).
    pub largest: [f64; 2],
}

/// Fewest plotted values for which a panel is ever clipped: below it a
/// quantile says little about what the bulk is.
const CLIP_MIN_POINTS: usize = 10;

/// The smallest multiple of 1, 2, 2.5 or 5 times a power of ten that is at
/// least a tenth of `span`: a step to round an axis end to.
fn round_step(span: f64) -> f64 {
    let want = span / 10.0;
    let p = 10f64.powf(want.log10().floor());
    [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * p)
        .find(|s| *s >= want * (1.0 - 1e-12))
        .unwrap_or(10.0 * p)
}

/// `v` with three significant digits, trailing zeros dropped (`31.8`,
/// `193`, `0.0125`, `15`).
fn short(v: f64) -> String {
    if !v.is_finite() {
        return "–".into();
    }
    if v == 0.0 {
        return "0".into();
    }
    let decimals = (2 - v.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// `value unit`, or the value alone without a unit.
fn with_unit(v: f64, unit: &str) -> String {
    if unit.is_empty() {
        short(v)
    } else {
        format!("{} {unit}", short(v))
    }
}

impl Panel {
    /// An empty panel.
    pub fn new(title: impl Into<String>, x: PlotAxis, y: PlotAxis) -> Panel {
        Panel {
            title: title.into(),
            x,
            y,
            series: Vec::new(),
            hlines: Vec::new(),
            vlines: Vec::new(),
            bands: Vec::new(),
            band_label: None,
            notes: Vec::new(),
            equal_aspect: false,
            legend: Corner::UpperRight,
            y_clip: None,
            caption: Vec::new(),
        }
    }

    /// Where [`Panel::y_clip`] cuts the vertical axis, or `None` when it
    /// does not: no rule, a log or fixed-range axis, an equal-aspect panel,
    /// fewer than 10 plotted values, or nothing above the rounded bound.
    /// The plotted values are the finite points of every series but the
    /// [`SeriesKind::BentBackwards`] markers (they circle points of other
    /// series).
    pub fn clipped(&self) -> Option<Clipped> {
        let rule = self.y_clip?;
        if self.y.log || self.y.range.is_some() || self.equal_aspect {
            return None;
        }
        if !(rule.quantile > 0.0 && rule.quantile <= 1.0 && rule.factor >= 1.0) {
            return None;
        }
        let points: Vec<[f64; 2]> = self
            .series
            .iter()
            .filter(|s| s.kind != SeriesKind::BentBackwards)
            .flat_map(|s| &s.points)
            .filter(|p| p[0].is_finite() && p[1].is_finite())
            .copied()
            .collect();
        if points.len() < CLIP_MIN_POINTS {
            return None;
        }
        let mut ys: Vec<f64> = points.iter().map(|p| p[1]).collect();
        ys.sort_by(f64::total_cmp);
        let mut base = ys[0];
        if self.y.include_zero {
            base = base.min(0.0);
        }
        // nearest rank: the smallest value with at least q of them at or below it
        let rank = (rule.quantile * ys.len() as f64).ceil() as usize;
        let q = ys[rank.clamp(1, ys.len()) - 1];
        let raw = base + rule.factor * (q - base);
        if !raw.is_finite() || raw <= base {
            return None;
        }
        let step = round_step(raw - base);
        let at = (raw / step).ceil() * step;
        let largest = points
            .iter()
            .copied()
            .reduce(|a, b| if b[1] > a[1] { b } else { a })?;
        (largest[1] > at).then(|| Clipped {
            at,
            above: points.iter().filter(|p| p[1] > at).count(),
            largest,
        })
    }

    /// The sentence that says where the panel's vertical axis is cut and
    /// what is off the chart (`None` when it is not cut).
    pub fn clip_note(&self) -> Option<String> {
        let c = self.clipped()?;
        let largest = format!(
            "{} at {} = {}",
            with_unit(c.largest[1], &self.y.unit),
            self.x.label,
            with_unit(c.largest[0], &self.x.unit)
        );
        let above = if c.above == 1 {
            format!("one point lies above it: {largest}")
        } else {
            format!("{} points lie above it, the largest {largest}", c.above)
        };
        Some(format!(
            "axis clipped at {} (▲: off the chart); {above}",
            with_unit(c.at, &self.y.unit)
        ))
    }

    /// Adds a series, and the markers of its points bent backwards.
    pub(crate) fn curve(&mut self, s: Series, bent: Vec<[f64; 2]>) {
        self.series.push(s);
        self.series.extend(Series::bent_backwards(bent));
    }

    /// Adds a series, the markers of its points bent backwards and those of
    /// its points that are not valid grasps.
    pub(crate) fn grasp_curve(&mut self, s: Series, bent: Vec<[f64; 2]>, invalid: Vec<[f64; 2]>) {
        self.curve(s, bent);
        self.series.extend(Series::invalid(invalid));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_spread_is_the_closed_band_of_its_finite_points() {
        let pts = [[0.0, 1.0], [1.0, 2.0], [2.0, f64::NAN], [3.0, 4.0]];
        let sd = [0.5, f64::NAN, 1.0, 3.0];
        let s = Series::spread("k", &pts, &sd, [0.0, 6.0]).unwrap();
        assert_eq!(s.kind, SeriesKind::Spread);
        // (0, 1 +- 0.5) and (3, 4 +- 3), the upper side clamped at 6;
        // the points without a finite value or sd are left out
        assert_eq!(s.points, [[0.0, 1.5], [3.0, 6.0], [3.0, 1.0], [0.0, 0.5]]);
        assert!(Series::spread("k", &pts[..2], &sd[..2], [0.0, 6.0]).is_none());
    }

    /// x = 0, 1, 2, ...
    fn lift_panel(ys: &[f64]) -> Panel {
        let mut p = Panel::new(
            "t",
            PlotAxis::new("grasping size d", "mm"),
            PlotAxis::new("f", "N"),
        );
        p.y.include_zero = true;
        p.y_clip = Some(Clip::OUTLIERS);
        let points = ys.iter().enumerate().map(|(i, y)| [i as f64, *y]).collect();
        p.series.push(Series::new("k", SeriesKind::Line, points));
        p
    }

    #[test]
    fn round_steps_and_short_numbers() {
        // a tenth of the span, rounded up to 1, 2, 2.5 or 5 times a power of ten
        assert_eq!(round_step(14.4), 2.0);
        assert_eq!(round_step(23.0), 2.5);
        assert_eq!(round_step(40.0), 5.0);
        assert_eq!(round_step(100.0), 10.0);
        assert!((round_step(0.5) - 0.05).abs() < 1e-15);
        assert_eq!(short(31.80247056), "31.8");
        assert_eq!(short(192.8985231), "193");
        assert_eq!(short(1234.6), "1235");
        assert_eq!(short(15.0), "15");
        assert_eq!(short(1.5), "1.5");
        assert_eq!(short(0.012345), "0.0123");
        assert_eq!(short(-2.3449), "-2.34");
        assert_eq!(short(0.0), "0");
    }

    #[test]
    fn an_outlier_clips_the_vertical_axis_at_a_round_number() {
        // 0..9 and 100 at x = 10: eleven values; the 90 % quantile by
        // nearest rank is the 10th smallest, 9; twice its height above the
        // base 0 is 18, a multiple of the step 2 (a tenth of 18 is 1.8)
        let mut ys: Vec<f64> = (0..10).map(f64::from).collect();
        ys.push(100.0);
        let p = lift_panel(&ys);
        assert_eq!(
            p.clipped(),
            Some(Clipped {
                at: 18.0,
                above: 1,
                largest: [10.0, 100.0]
            })
        );
        assert_eq!(
            p.clip_note().unwrap(),
            "axis clipped at 18 N (▲: off the chart); one point lies above it: \
             100 N at grasping size d = 10 mm"
        );
        let fig = Figure::row("f", [400, 300], vec![p.clone(), lift_panel(&[1.0; 12])]);
        let notes = fig.clip_notes();
        assert_eq!(notes.len(), 1);
        assert_eq!(notes[0].0, "t");
        assert!(notes[0].1.starts_with("axis clipped at 18 N"));

        // two above: counted, the largest named
        let mut two = ys.clone();
        two[9] = 40.0;
        two.push(0.5);
        // sorted: 0, 0.5, 1..8, 40, 100; rank ceil(0.9 * 12) = 11: 40, so
        // the bound 80 (step 10) keeps 40 and cuts 100
        assert_eq!(lift_panel(&two).clipped().unwrap().at, 80.0);
        let mut three = ys.clone();
        three.extend([40.0, 45.0, 50.0, 55.0]);
        // 15 values, rank ceil(13.5) = 14: 55 -> 110 -> 120 (step 20): none cut
        assert_eq!(lift_panel(&three).clipped(), None);

        // a base away from zero: 100..109 and 150, without zero: the
        // quantile 109 is 9 above the base 100, the bound 118 (step 2)
        let mut high: Vec<f64> = (100..110).map(f64::from).collect();
        high.push(150.0);
        let mut p = lift_panel(&high);
        p.y.include_zero = false;
        let c = p.clipped().unwrap();
        assert_eq!((c.at, c.above), (118.0, 1));
        // with zero on the axis the bound is 2 * 109 = 218 -> 225 (step
        // 25): nothing cut
        p.y.include_zero = true;
        assert_eq!(p.clipped(), None);
        // several points above: 0..19, 90 and 100; rank ceil(19.8) = 20:
        // 19 -> 38 -> 40 (step 5)
        let mut many: Vec<f64> = (0..20).map(f64::from).collect();
        many.extend([90.0, 100.0]);
        let p = lift_panel(&many);
        assert_eq!(p.clipped().map(|c| (c.at, c.above)), Some((40.0, 2)));
        assert!(p
            .clip_note()
            .unwrap()
            .ends_with("2 points lie above it, the largest 100 N at grasping size d = 21 mm"));
    }

    #[test]
    fn clipping_needs_a_rule_data_and_a_free_linear_axis() {
        let mut ys: Vec<f64> = (0..10).map(f64::from).collect();
        ys.push(100.0);
        let clipped = |f: &dyn Fn(&mut Panel)| {
            let mut p = lift_panel(&ys);
            f(&mut p);
            p.clipped()
        };
        assert!(clipped(&|_| {}).is_some());
        assert_eq!(clipped(&|p| p.y_clip = None), None);
        assert_eq!(clipped(&|p| p.y = p.y.clone().log()), None);
        assert_eq!(clipped(&|p| p.y.range = Some([0.0, 200.0])), None);
        assert_eq!(clipped(&|p| p.equal_aspect = true), None);
        assert_eq!(
            clipped(&|p| p.y_clip = Some(Clip {
                quantile: 0.0,
                factor: 2.0
            })),
            None
        );
        // fewer than ten values
        assert_eq!(
            clipped(&|p| p.series[0].points.drain(..2).for_each(drop)),
            None
        );
        // bent-backwards markers are not counted: an outlier only they
        // carry does not cut the axis
        assert_eq!(
            clipped(&|p| {
                p.series[0].points.pop();
                p.series[0].points.push([10.0, 9.0]);
                p.series.extend(Series::bent_backwards(vec![[10.0, 100.0]]));
            }),
            None
        );
        // non-finite points are skipped
        assert_eq!(
            clipped(&|p| p.series[0].points.push([f64::NAN, 1e9])),
            clipped(&|_| {})
        );
    }
}
