//! The lifting-force curve that studies 1 to 3 share: a gripper at grasping
//! angle 0 with full friction `f = mu F`, its grasping size swept from
//! `max(0, l - 2 l0)` to `d_max`; and the table rows, figure series and
//! summary rows built from one.

use serde::Serialize;

use super::bands::{BandColumn, BandParams, BAND_LABEL};
use super::options::SweepStop;
use super::output::{
    columns, max_of, pts, stop_entry, Assembly, Cell, Column, Panel, Series, SeriesKind, StopAt,
    StopEntry, GRASP_TAIL,
};
use super::sweep::size_sweep;
use crate::actuator::Actuator;
use crate::error::Warning;
use crate::gripper::{Grasp, Gripper, Invalid, Object};
use crate::sensitivity::{GraspKind, GraspSensitivity, GripperParam, Param};

/// One point of a lifting-force curve (grasping angle 0, `f = mu F`).
#[derive(Debug, Clone, PartialEq)]
pub struct LiftPoint {
    /// Grasping size `d` (mm).
    pub size: f64,
    /// Gap between the tips (mm).
    pub tip_gap: f64,
    /// Normal force `F` (N).
    pub normal: f64,
    /// Max lifting force `f_v = mu F` (N).
    pub lift: f64,
    /// Finger height `h` (mm).
    pub height: f64,
    /// An element is bent backwards (dropped in strict mode).
    pub reversed: bool,
    /// Why the grasp is not valid, the first reason of its verdict
    /// (`None`: valid; [`crate::gripper::Verdict`]).
    pub invalid: Option<Invalid>,
    /// The grasp's validity findings.
    pub warnings: Vec<Warning>,
    /// With a covariance (studies 1 and 2 from `fpc paper --scene`): the
    /// 1-sigma of the grasp's outputs at its size; `None` without one, or
    /// when its sensitivities failed (`sd_note` says why).
    pub sd: Option<LiftSd>,
    /// Why a point of a study with a covariance has no `sd`.
    pub sd_note: Option<String>,
}

/// 1-sigma of a lift point from a covariance, by first-order propagation
/// through the grasp's exact sensitivities at its (fixed) grasping size
/// ([`crate::Gripper::grasp_sensitivities`], a size grasp).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiftSd {
    /// Of the normal force F (N).
    pub normal: f64,
    /// Of the max lifting force f_v (N).
    pub lift: f64,
    /// Of the finger height h (mm).
    pub height: f64,
}

/// Max lifting force versus grasping size for one gripper.
#[derive(Debug, Clone, PartialEq)]
pub struct LiftCurve {
    /// Prestrain.
    pub eps0: f64,
    /// Mounting angle (rad).
    pub mounting_angle: f64,
    /// Overlap `g` (mm).
    pub overlap: f64,
    /// Palm diameter `l` (mm).
    pub palm: f64,
    /// Inward reach `l0` (mm).
    pub l0: f64,
    /// `d_max = l + 2 Lx cos a` (mm).
    pub d_max: f64,
    /// The unloaded finger's mid-plane in the gripper frame (mm).
    pub rest_shape: Vec<[f64; 2]>,
    /// The sweep from `max(0, l - 2 l0)` to `d_max` (in strict mode
    /// without the grasps that bend an element backwards).
    pub points: Vec<LiftPoint>,
    /// Grasps left out in strict mode.
    pub dropped: usize,
    /// Set when the sweep stopped before `d_max`.
    pub stopped: Option<SweepStop>,
    /// The gripper's design warnings.
    pub warnings: Vec<Warning>,
    /// With a covariance: d_max's 1-sigma (mm); `None` without one, or
    /// when the gripper's sensitivities do not cover its rest shape
    /// (`sd_note` says why, and its points have none either).
    pub d_max_sd: Option<f64>,
    /// Why a curve of a study with a covariance has no `d_max_sd`.
    pub sd_note: Option<String>,
}

impl LiftCurve {
    /// The largest grasping size the sweep reached (mm).
    pub fn reached(&self) -> f64 {
        self.points.last().map_or(0.0, |p| p.size)
    }

    /// The max lifting force at grasping size `d`, interpolated linearly
    /// between the two sweep points around it when both are valid grasps
    /// (`None` outside the swept range, or next to an invalid grasp: only
    /// valid grasps count).
    pub fn max_lift(&self, d: f64) -> Option<f64> {
        let pts = &self.points;
        if pts.is_empty() || !d.is_finite() {
            return None;
        }
        if pts.len() == 1 {
            return (d == pts[0].size && pts[0].invalid.is_none()).then_some(pts[0].lift);
        }
        let i = pts
            .windows(2)
            .position(|w| d >= w[0].size && d <= w[1].size)?;
        let (p, q) = (&pts[i], &pts[i + 1]);
        if p.invalid.is_some() || q.invalid.is_some() {
            return None;
        }
        let t = if q.size > p.size {
            (d - p.size) / (q.size - p.size)
        } else {
            0.0
        };
        Some(p.lift + t * (q.lift - p.lift))
    }

    /// The largest lifting force of the sweep's valid grasps.
    pub(crate) fn peak_lift(&self) -> Option<f64> {
        max_of(
            self.points
                .iter()
                .filter(|p| p.invalid.is_none())
                .map(|p| p.lift),
        )
    }
}

/// The lifting-force curve of `g` on `n + 1` grasping sizes (`n` at least
/// 1): studies 1 to 3's sweep at grasping angle 0 and zero pressure, from
/// `d_min` to `d_max`; `eps0` is the curve's label only.
pub fn lift_curve(g: &Gripper, eps0: f64, n: usize) -> LiftCurve {
    lift_curve_with(g, eps0, n, None)
}

/// [`lift_curve`], and with `bands` (the gripper finger's actuator and
/// the covariance's propagated parameters) d_max's and every point's
/// 1-sigma by first-order propagation through exact sensitivities.
pub(crate) fn lift_curve_with(
    g: &Gripper,
    eps0: f64,
    n: usize,
    bands: Option<(&Actuator, &BandParams)>,
) -> LiftCurve {
    let params: Vec<GripperParam> = bands.map_or_else(Vec::new, |(_, b)| {
        b.params()
            .into_iter()
            .filter_map(|p| match p {
                Param::Actuator(a) => Some(GripperParam::Actuator(a)),
                _ => None,
            })
            .collect()
    });
    // d_max's; when the gripper's chaining does not cover its rest shape,
    // neither it nor any point has a band
    let (d_max_sd, sd_note) = match bands {
        Some((act, b)) => match g.geometry_sensitivities(act, &params) {
            Ok(rows) => (
                Some(b.sigma(&rows.iter().map(|r| r.d_max).collect::<Vec<_>>())),
                None,
            ),
            Err(e) => (None, Some(format!("no error bars: {e}"))),
        },
        None => (None, None),
    };
    let point_sd = |gr: &Grasp| -> (Option<LiftSd>, Option<String>) {
        let Some((act, b)) = bands else {
            return (None, None);
        };
        if sd_note.is_some() {
            return (None, sd_note.clone());
        }
        match g.grasp_sensitivities(act, gr, GraspKind::Size { d: gr.size }, &params) {
            Ok(s) => {
                let sig = |f: fn(&GraspSensitivity) -> f64| {
                    b.sigma(&s.rows.iter().map(f).collect::<Vec<_>>())
                };
                let sd = LiftSd {
                    normal: sig(|r| r.normal),
                    lift: sig(|r| r.lift),
                    height: sig(|r| r.height),
                };
                (Some(sd), None)
            }
            Err(e) => (None, Some(format!("no error bars: {e}"))),
        }
    };
    let mut points = Vec::with_capacity(n + 1);
    let mut dropped = 0;
    let stopped = size_sweep(g, 0.0, 0.0, Object::Face, g.d_min(), g.d_max(), n, |gr| {
        if matches!(gr.invalid(), Some(Invalid::CurvatureReversal { .. })) {
            dropped += 1;
            return;
        }
        let (sd, note) = point_sd(gr);
        points.push(LiftPoint {
            size: gr.size,
            tip_gap: gr.tip_gap,
            normal: gr.normal,
            lift: gr.lift,
            height: gr.height,
            reversed: gr.is_reversed(),
            invalid: gr.invalid(),
            warnings: gr.warnings.clone(),
            sd,
            sd_note: note,
        })
    });
    LiftCurve {
        eps0,
        mounting_angle: g.mounting_angle(),
        overlap: g.overlap(),
        palm: g.palm(),
        l0: g.l0(),
        d_max: g.d_max(),
        rest_shape: g.rest_shape(),
        points,
        dropped,
        stopped,
        warnings: g.warnings().to_vec(),
        d_max_sd,
        sd_note,
    }
}

// ------------------------------------------------------------ outputs

/// The columns of a lift-curve table after its two leading ones, before
/// [`GRASP_TAIL`].
const LIFT_COLUMNS: [Column; 8] = [
    Column::new("palm_mm", "mm"),
    Column::new("l0_mm", "mm"),
    Column::new("dmax_mm", "mm"),
    Column::new("d_mm", "mm"),
    Column::new("tip_gap_mm", "mm"),
    Column::new("F_n", "N"),
    Column::new("fv_n", "N"),
    Column::new("h_mm", "mm"),
];

/// The 1-sigma columns of a lift-curve table, with a covariance.
pub(crate) const LIFT_SD_COLUMNS: [Column; 4] = [
    Column::new("dmax_mm_sd", "mm"),
    Column::new("F_n_sd", "N"),
    Column::new("fv_n_sd", "N"),
    Column::new("h_mm_sd", "mm"),
];

/// Two leading columns, then [`LIFT_COLUMNS`] (and with `with_sd`
/// [`LIFT_SD_COLUMNS`]) and [`GRASP_TAIL`].
pub(crate) fn lift_columns(lead: [Column; 2], with_sd: bool) -> Vec<Column> {
    let mut c = columns(&lead, &LIFT_COLUMNS);
    if with_sd {
        c.extend(LIFT_SD_COLUMNS);
    }
    columns(&c, &GRASP_TAIL)
}

/// The methods of [`LIFT_SD_COLUMNS`] (`bands`).
pub(crate) fn lift_bands() -> Vec<BandColumn> {
    super::bands::exact_bands(&LIFT_SD_COLUMNS)
}

/// Writes why point `p` has no band into the note cell of table 0's last
/// row (nothing when it has one).
pub(crate) fn sd_note(a: &mut Assembly, p: &LiftPoint) {
    if let (Some(n), Some(r)) = (&p.sd_note, a.tables[0].rows.last_mut()) {
        let at = r.len() - 1;
        r[at] = n.clone().into();
    }
}

/// Appends to table 0 one row per point of `c` (the first two cells
/// `lead`, e.g. eps0 and the angle), then the stop of sweep `case` if it
/// stopped; counts what strict mode dropped and the gripper's design
/// warnings.
pub(crate) fn lift_rows(
    a: &mut Assembly,
    c: &LiftCurve,
    lead: [Cell; 2],
    case: &str,
    with_sd: bool,
) {
    for p in &c.points {
        let mut row = lead.to_vec();
        row.extend(
            [
                c.palm, c.l0, c.d_max, p.size, p.tip_gap, p.normal, p.lift, p.height,
            ]
            .map(Cell::from),
        );
        if with_sd {
            row.extend([
                c.d_max_sd.into(),
                p.sd.map(|s| s.normal).into(),
                p.sd.map(|s| s.lift).into(),
                p.sd.map(|s| s.height).into(),
            ]);
        }
        a.grasp(0, row, p.reversed, p.invalid.as_ref(), &p.warnings);
        if with_sd {
            sd_note(a, p);
        }
    }
    if let Some(s) = &c.stopped {
        let [x, y] = lead;
        let t = &a.tables[0];
        let (first, second) = (t.columns[0].name, t.columns[1].name);
        let named = vec![
            (first, x),
            (second, y),
            ("palm_mm", c.palm.into()),
            ("l0_mm", c.l0.into()),
            ("dmax_mm", c.d_max.into()),
        ];
        a.stop(0, named, "d_mm", case, StopAt::Mm, s, true);
    }
    a.strict_dropped += c.dropped;
    a.design(&c.warnings);
}

/// The curve's max lifting force against the grasping size, drawn as
/// `kind`, with markers on the points bent backwards and on the grasps
/// that are not valid.
pub(crate) fn add_lift_curve(
    p: &mut Panel,
    c: &LiftCurve,
    kind: SeriesKind,
    color: String,
    label: String,
    with_sd: bool,
) {
    if with_sd {
        let sd: Vec<f64> = c
            .points
            .iter()
            .map(|q| q.sd.map_or(f64::NAN, |s| s.lift))
            .collect();
        p.series.extend(
            Series::spread(color.clone(), &lift_points(c), &sd, [f64::MIN, f64::MAX])
                .map(|s| s.label(BAND_LABEL)),
        );
    }
    let marked = |keep: &dyn Fn(&LiftPoint) -> bool| {
        pts(c
            .points
            .iter()
            .filter(|q| keep(q))
            .map(|q| (q.size, q.lift)))
    };
    p.grasp_curve(
        Series::new(color, kind, lift_points(c)).label(label),
        marked(&|q| q.reversed),
        marked(&|q| q.invalid.is_some()),
    );
}

/// The (d, f_v) points of a curve.
pub(crate) fn lift_points(c: &LiftCurve) -> Vec<[f64; 2]> {
    pts(c.points.iter().map(|p| (p.size, p.lift)))
}

/// The geometry and reach of one curve, for `dmax_mm` and
/// `overlap_dmax_mm` in the summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct CurveSummary {
    pub dmax_mm: f64,
    /// With a covariance: d_max's 1-sigma (null where none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dmax_mm_sd: Option<Option<f64>>,
    pub l0_mm: f64,
    pub palm_mm: f64,
    pub reached_mm: f64,
    pub max_fv_n: Option<f64>,
    pub stopped: Option<StopEntry>,
}

impl CurveSummary {
    pub fn of(c: &LiftCurve, with_sd: bool) -> CurveSummary {
        CurveSummary {
            dmax_mm: c.d_max,
            dmax_mm_sd: with_sd.then_some(c.d_max_sd),
            l0_mm: c.l0,
            palm_mm: c.palm,
            reached_mm: c.reached(),
            max_fv_n: c.peak_lift(),
            stopped: stop_entry(&c.stopped, StopAt::Mm),
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::studies::output::{PlotAxis, BENT_BACKWARDS, INVALID_GRASP};
    use crate::studies::Cell;

    /// A curve of two points, the second bent backwards, stopped at 5.5 mm.
    pub fn curve() -> LiftCurve {
        let point = |size: f64, reversed: bool| LiftPoint {
            size,
            tip_gap: size,
            normal: 0.4 + size,
            lift: 0.24 + 0.6 * size,
            height: 78.0,
            reversed,
            invalid: (size <= 0.0).then_some(Invalid::NotOpen {
                size,
                tip_gap: size,
            }),
            warnings: if reversed {
                vec![Warning::CurvatureReversal {
                    element: 2,
                    curvature: -0.01,
                }]
            } else {
                Vec::new()
            },
            sd: None,
            sd_note: None,
        };
        LiftCurve {
            eps0: 0.25,
            mounting_angle: std::f64::consts::FRAC_PI_3,
            overlap: 20.0,
            palm: 66.4,
            l0: 53.2,
            d_max: 176.4,
            rest_shape: vec![[33.2, 0.0], [40.0, 20.0]],
            points: vec![point(0.0, false), point(2.0, true)],
            dropped: 0,
            stopped: Some(SweepStop::failed(
                5.5,
                "solve failed: line search, test".into(),
            )),
            warnings: Vec::new(),
            d_max_sd: None,
            sd_note: None,
        }
    }

    #[test]
    fn a_stopped_lift_sweep_is_a_row() {
        let c = curve();
        let cols = lift_columns(
            [Column::new("angle_rad", "rad"), Column::new("g_mm", "mm")],
            false,
        );
        let mut a = Assembly::new(&[("t", &cols)], &[]);
        lift_rows(
            &mut a,
            &c,
            [c.mounting_angle.into(), 20.0.into()],
            "case",
            false,
        );
        let out = a.finish(
            crate::report::Figure::row("", [1, 1], Vec::new()),
            &serde_json::json!({}),
        );
        let t = &out.tables[0];
        // the points computed before the stop, then the stop
        assert_eq!(t.rows.len(), 3);
        assert_eq!(t.cell(0, "status"), Some(&Cell::from("ok")));
        assert_eq!(t.cell(0, "valid"), Some(&Cell::Bool(false)));
        assert_eq!(t.cell(0, "warnings"), Some(&Cell::Empty));
        assert_eq!(t.cell(1, "reversed"), Some(&Cell::Bool(true)));
        assert_eq!(
            t.cell(1, "warnings"),
            Some(&Cell::from("curvature_reversal"))
        );
        assert_eq!(t.cell(2, "d_mm"), Some(&Cell::Num(5.5)));
        assert_eq!(t.cell(2, "g_mm"), Some(&Cell::Num(20.0)));
        assert_eq!(t.cell(2, "status"), Some(&Cell::from("stopped")));
        assert_eq!(
            t.cell(2, "note"),
            Some(&Cell::from("solve failed: line search, test"))
        );
        // a stopped row is no point: its findings are empty and not counted
        assert_eq!(t.cell(2, "reversed"), Some(&Cell::Empty));
        assert_eq!(out.points, 2);
        assert_eq!(out.warnings_by_kind["curvature_reversal"], 1);
        assert_eq!(
            out.notes,
            ["case: sweep stopped at d = 5.5 mm: solve failed: line search, test"]
        );
        assert_eq!(out.stops.len(), 1);
        let s = CurveSummary::of(&c, false);
        assert_eq!(s.reached_mm, 2.0);
        assert_eq!(
            serde_json::to_value(&s.stopped).unwrap()["at_mm"],
            serde_json::json!(5.5)
        );
    }

    #[test]
    fn bent_and_invalid_points_get_markers() {
        let c = curve();
        let mut p = Panel::new("", PlotAxis::new("d", "mm"), PlotAxis::new("f", "N"));
        add_lift_curve(
            &mut p,
            &c,
            SeriesKind::Line,
            "a=pi/3".into(),
            "a = π/3".into(),
            false,
        );
        // the line, the bent point (d = 2) and the invalid one (d = 0)
        assert_eq!(p.series.len(), 3);
        assert_eq!(p.series[2].kind, SeriesKind::Invalid);
        assert_eq!(p.series[2].points, vec![[0.0, 0.24]]);
        assert_eq!(p.series[2].label.as_deref(), Some(INVALID_GRASP));
        assert_eq!(p.series[1].kind, SeriesKind::BentBackwards);
        assert_eq!(p.series[0].color, "a=pi/3");
        assert_eq!(p.series[1].color, BENT_BACKWARDS);
        assert_eq!(p.series[1].points, vec![[2.0, 0.24 + 1.2]]);
        assert_eq!(p.series[1].label.as_deref(), Some(BENT_BACKWARDS));
    }
}
