//! The SVG writer's tests.

use super::*;
use fpc::report::RefLine;

#[test]
fn powers_of_ten_are_labelled_with_superscripts() {
    assert_eq!(power_of_ten(&-2.0), "10⁻²");
    assert_eq!(power_of_ten(&0.0), "10⁰");
    assert_eq!(power_of_ten(&13.0), "10¹³");
    assert_eq!(power_of_ten(&0.5), "3.16");
    assert_eq!(decade_labels(-4.2, 1.3), 6);
    assert_eq!(decade_labels(0.2, 0.8), 7);
}

#[test]
fn a_log_log_panel_skips_values_that_are_not_positive() {
    let mut p = Panel::new(
        "t",
        PlotAxis::new("x", "").log(),
        PlotAxis::new("y", "mm").log(),
    );
    p.series.push(
        Series::new(
            "a",
            SeriesKind::LinePoints,
            vec![
                [1.0, 1e-3],
                [0.0, 1.0],
                [10.0, -1.0],
                [100.0, 1e-1],
                [1e3, f64::NAN],
            ],
        )
        .label("a"),
    );
    p.hlines.push(RefLine {
        at: 0.0,
        label: "zero".into(),
    });
    p.hlines.push(RefLine {
        at: 1e-2,
        label: "tol".into(),
    });
    let q = on_log_axes(&p);
    assert_eq!(q.hlines.len(), 1);
    assert_eq!(finite(&q.series[0].points), [(0.0, -3.0), (2.0, -1.0)]);
    let fig = Figure::row("log", [600, 400], vec![p]);
    let s = svg(&fig).unwrap();
    assert!(!s.contains("NaN") && !s.contains("inf"), "{s}");
    assert!(s.contains("10⁻²") && s.contains("10¹"), "{s}");
}

/// Values near f64's largest (an error bar of 1e308 mm from a measured
/// standard deviation): the axis span overflowed to inf and the tick
/// placement never ended. The axis now stops at its limit, and values
/// beyond it are drawn at its edge, in finite numbers.
#[test]
fn values_near_the_largest_float_draw_on_finite_axes() {
    let (lo, hi) = padded(&[39.0, 1e308, -1e308, f64::INFINITY]);
    assert!(lo.is_finite() && hi.is_finite() && (hi - lo).is_finite());
    assert!(lo < -1e299 && hi > 1e299, "{lo:e} {hi:e}");
    let mut p = Panel::new("t", PlotAxis::new("x", "kPa"), PlotAxis::new("y", "mm"));
    p.series.push(
        Series::new(
            "a",
            SeriesKind::LinePoints,
            // (values past the axis limit are drawn at its edge)
            vec![[0.0, 39.0], [25.0, 1e308], [50.0, -1e308], [1e308, 0.0]],
        )
        .label("a"),
    );
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(svg(&Figure::row("huge", [600, 400], vec![p])));
    });
    let s = rx
        .recv_timeout(std::time::Duration::from_secs(30))
        .expect("drawing values near f64::MAX hung")
        .unwrap();
    assert!(!s.contains("NaN") && !s.contains("inf"), "{s}");
}

#[test]
fn print_sizing_sets_inches_and_the_printed_font_size() {
    let mut p = Panel::new("t", PlotAxis::new("x", "mm"), PlotAxis::new("y", "N"));
    p.series
        .push(Series::new("a", SeriesKind::Line, vec![[0.0, 0.0], [1.0, 2.0]]).label("a"));
    let fig = Figure::row("print", [1200, 600], vec![p]);
    let style = Style {
        width_in: Some(6.0),
        font_pt: Some(9.0),
    };
    let s = svg_styled(&fig, &style).unwrap();
    assert!(s.starts_with("<svg width=\"6.000in\" height=\"3.000in\" viewBox=\"0 0 1200 600\""));
    // 6 in over 1200 px: 0.36 pt per px, so 9 pt tick labels are 25 px
    // in the SVG; the tick labels are its most common font size
    let mut counts = std::collections::BTreeMap::<String, usize>::new();
    for part in s.split("font-size=\"").skip(1) {
        let v = part.split('"').next().unwrap().to_string();
        *counts.entry(v).or_default() += 1;
    }
    let (common, _) = counts.iter().max_by_key(|(_, n)| **n).unwrap();
    let px: f64 = common.parse().unwrap();
    assert!((px * 72.0 * 6.0 / 1200.0 - 9.0).abs() < 1e-6, "{counts:?}");
    // the default keeps the pixel size
    assert!(svg(&fig)
        .unwrap()
        .starts_with("<svg width=\"1200\" height=\"600\""));
    assert!(Style {
        width_in: Some(-1.0),
        font_pt: None
    }
    .validate()
    .is_err());
}

/// The tick labels of a set of ticks.
fn labels(ticks: &[f64]) -> Vec<String> {
    let f = tick_format(ticks);
    ticks.iter().map(|&t| tick_label(t, f)).collect()
}

#[test]
fn tick_labels_drop_needless_decimals() {
    assert_eq!(labels(&[0.0, 20.0, 40.0, 60.0]), ["0", "20", "40", "60"]);
    assert_eq!(
        labels(&[-100.0, -50.0, 0.0, 50.0]),
        ["-100", "-50", "0", "50"]
    );
    // half steps: one decimal on every tick but zero
    assert_eq!(
        labels(&[0.0, 0.5, 1.0, 1.5, 2.0]),
        ["0", "0.5", "1.0", "1.5", "2.0"]
    );
    assert_eq!(
        labels(&[98.5, 99.0, 99.5, 100.0]),
        ["98.5", "99.0", "99.5", "100.0"]
    );
    assert_eq!(
        labels(&[0.25, 0.5, 0.75, 1.0]),
        ["0.25", "0.50", "0.75", "1.00"]
    );
    assert_eq!(
        labels(&[-0.01, 0.0, 0.01, 0.02]),
        ["-0.01", "0", "0.01", "0.02"]
    );
    assert_eq!(labels(&[0.001, 0.002, 0.003]), ["0.001", "0.002", "0.003"]);
    assert_eq!(labels(&[200000.0, 400000.0]), ["200000", "400000"]);
    // rounding noise and a negative zero
    assert_eq!(
        labels(&[-0.2, 5.551115123125783e-17, 0.2, 0.1 + 0.2, -0.0]),
        ["-0.2", "0", "0.2", "0.3", "0"]
    );
    // small and large magnitudes: the largest tick's power of ten
    assert_eq!(
        labels(&[0.0, 2e-5, 4e-5, 6e-5]),
        ["0", "2×10⁻⁵", "4×10⁻⁵", "6×10⁻⁵"]
    );
    assert_eq!(
        labels(&[0.0, 5e-5, 1e-4, 1.5e-4]),
        ["0", "0.5×10⁻⁴", "1.0×10⁻⁴", "1.5×10⁻⁴"]
    );
    assert_eq!(
        labels(&[0.0, 1e6, 2e6, 3e6]),
        ["0", "1×10⁶", "2×10⁶", "3×10⁶"]
    );
    assert_eq!(
        labels(&[0.0, 2.5e6, 5e6, 7.5e6]),
        ["0", "2.5×10⁶", "5.0×10⁶", "7.5×10⁶"]
    );
    assert_eq!(labels(&[0.0]), ["0"]);
    assert_eq!(tick_label(f64::NAN, TickFormat::Plain(1)), "");
    // log axes between powers of ten: three significant digits
    assert_eq!(three_digits(2.0), "2");
    assert_eq!(three_digits(1.5849), "1.58");
    assert_eq!(three_digits(251.19), "251");
    assert_eq!(three_digits(1.5849e-4), "1.58×10⁻⁴");
    assert_eq!(three_digits(1234567.0), "1.23×10⁶");
}

#[test]
fn plotters_ticks_get_labels_that_read_back_exactly() {
    // the ticks plotters puts on a few ranges: integer steps are
    // written without a point, and every label reads back as its tick
    for (lo, hi, integer) in [
        (-10.0, 210.0, true),
        (0.0, 33.4, true),
        (-95.0, 45.0, true),
        (-0.08, 1.7, false),
        (98.3, 101.0, false),
        (-0.015, 0.046, false),
    ] {
        let ticks = RangedCoordf64::from(lo..hi).key_points(TICKS);
        let f = tick_format(&ticks);
        assert!(ticks.len() >= 3, "{ticks:?}");
        for t in ticks {
            let l = tick_label(t, f);
            // zero is `0` on every axis
            let plain = !l.contains('.');
            assert!(plain == integer || l == "0", "{lo}..{hi}: {t} -> {l}");
            let back: f64 = l.parse().unwrap();
            assert!((back - t).abs() < 1e-9 * (hi - lo), "{t} -> {l}");
        }
    }
}

#[test]
fn a_line_is_cut_where_it_leaves_a_clipped_axis() {
    let pts = vec![[0.0, 0.0], [1.0, 10.0], [2.0, 30.0], [3.0, 5.0]];
    // it leaves between (1, 10) and (2, 30) at x = 1 + 10/20 = 1.5 and
    // comes back between (2, 30) and (3, 5) at x = 2 + 10/25 = 2.4
    let line = Shown::of(&Series::new("k", SeriesKind::Line, pts.clone()), Some(20.0));
    assert_eq!(
        line.runs,
        [
            vec![(0.0, 0.0), (1.0, 10.0), (1.5, 20.0)],
            vec![(2.4, 20.0), (3.0, 5.0)]
        ]
    );
    assert_eq!(line.off, [1.5, 2.4]);
    assert!(line.marks.is_empty());
    // an area is capped instead
    let area = Shown::of(&Series::new("k", SeriesKind::Area, pts.clone()), Some(20.0));
    assert_eq!(
        area.runs,
        [vec![
            (0.0, 0.0),
            (1.0, 10.0),
            (1.5, 20.0),
            (2.0, 20.0),
            (2.4, 20.0),
            (3.0, 5.0)
        ]]
    );
    // markers above are dropped and marked at their x
    let dots = Shown::of(
        &Series::new("k", SeriesKind::Points, pts.clone()),
        Some(20.0),
    );
    assert!(dots.runs.is_empty());
    assert_eq!(dots.marks, [(0.0, 0.0), (1.0, 10.0), (3.0, 5.0)]);
    assert_eq!(dots.off, [2.0]);
    let lp = Shown::of(
        &Series::new("k", SeriesKind::LinePoints, pts.clone()),
        Some(20.0),
    );
    assert_eq!(lp.marks, dots.marks);
    assert_eq!(lp.runs, line.runs);
    // wholly above: one mark where it starts
    let high = Series::new("k", SeriesKind::Line, vec![[4.0, 30.0], [5.0, 40.0]]);
    let h = Shown::of(&high, Some(20.0));
    assert!(h.runs.is_empty());
    assert_eq!(h.off, [4.0]);
    // no clip: everything, nothing off
    let all = Shown::of(&Series::new("k", SeriesKind::Line, pts), None);
    assert_eq!(all.runs[0].len(), 4);
    assert!(all.off.is_empty());
}

/// The text of every `<text>` element of an SVG.
fn texts(svg: &str) -> Vec<String> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let body = t.split_once('>')?.1;
            Some(body.split("</text>").next()?.trim().to_string())
        })
        .collect()
}

/// The points of the polylines of an SVG drawn in `colour`, one list
/// per polyline.
fn polylines(svg: &str, colour: &str) -> Vec<Vec<(f64, f64)>> {
    svg.split("<polyline")
        .skip(1)
        .filter(|t| t.contains(&format!("stroke=\"{colour}\"")))
        .map(|t| {
            let pts = t
                .split("points=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap();
            pts.split_whitespace()
                .map(|xy| {
                    let (x, y) = xy.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect()
        })
        .collect()
}

#[test]
fn an_outlier_is_clipped_marked_and_explained() {
    // 0..19 at x = 0..19 and 100 at x = 20: the 90 % quantile (nearest
    // rank 19 of 21) is 18, the bound 2 * 18 = 36, rounded up to a
    // multiple of 5 (a tenth of 36 is 3.6): the axis ends at 40 N
    let mut ys: Vec<[f64; 2]> = (0..20).map(|i| [f64::from(i), f64::from(i)]).collect();
    ys.push([20.0, 100.0]);
    let mut p = Panel::new(
        "lift",
        PlotAxis::new("size d", "mm"),
        PlotAxis::new("f", "N"),
    );
    p.y.include_zero = true;
    p.y_clip = Some(fpc::report::Clip::OUTLIERS);
    p.series
        .push(Series::new("a=pi/3", SeriesKind::Line, ys).label("curve"));
    let svg = svg(&Figure::row("clip", [600, 500], vec![p.clone()])).unwrap();
    let text = texts(&svg).join("\n");
    assert!(
        text.contains("axis clipped at 40 N (▲: off the chart)"),
        "{text}"
    );
    assert!(text.contains("100 N at size d = 20 mm"), "{text}");
    // the y ticks end at the clip: none above 40
    let numbers: Vec<f64> = texts(&svg).iter().filter_map(|t| t.parse().ok()).collect();
    assert!(numbers.contains(&40.0), "{numbers:?}");
    assert!(numbers.iter().all(|&v| v <= 40.0), "{numbers:?}");
    // one triangle, in the curve's colour, where it leaves the chart
    // (x = 19 + (40 - 19) / 81): its centre is 6 px below its apex,
    // on the top edge, and the curve ends there (plotters would clamp
    // the outlier onto the edge and run the line along it)
    let colour = hex(color_of("a=pi/3"));
    let tri: Vec<&str> = svg
        .split("<polygon")
        .skip(1)
        .filter(|t| t.contains(&format!("fill=\"{colour}\"")))
        .collect();
    assert_eq!(tri.len(), 1, "{svg}");
    let apex: Vec<f64> = tri[0]
        .split("points=\"")
        .nth(1)
        .unwrap()
        .split([',', ' '])
        .take(2)
        .map(|v| v.parse().unwrap())
        .collect();
    let (ax, edge) = (apex[0], apex[1] + 6.0);
    // the curve: the polyline of more than the legend mark's 2 points
    let curves: Vec<Vec<(f64, f64)>> = polylines(&svg, &colour)
        .into_iter()
        .filter(|l| l.len() > 2)
        .collect();
    assert_eq!(curves.len(), 1, "{curves:?}");
    let curve = &curves[0];
    assert_eq!(curve.len(), 21, "20 points and the crossing");
    let end = curve[20];
    assert!(
        (end.0 - ax).abs() <= 1.0 && (end.1 - edge).abs() <= 1.0,
        "{end:?} vs {apex:?}"
    );
    assert!(curve[..20].iter().all(|p| p.1 > edge + 1.0), "{curve:?}");

    // without the rule the axis reaches 100 and nothing is said
    p.y_clip = None;
    let svg = super::svg(&Figure::row("clip", [600, 500], vec![p])).unwrap();
    assert!(!svg.contains("clipped"));
    assert!(!svg.contains("<polygon"));
    let numbers: Vec<f64> = texts(&svg).iter().filter_map(|t| t.parse().ok()).collect();
    assert!(numbers.iter().any(|&v| v >= 100.0), "{numbers:?}");
}

fn frame10() -> Frame {
    Frame {
        x: (0.0, 10.0),
        y: (0.0, 10.0),
        px: (400.0, 300.0),
    }
}

const FREE: Room = Room {
    top: true,
    bottom: true,
    equal_aspect: false,
};

#[test]
fn the_legend_moves_off_the_data() {
    use SeriesLabelPosition as P;
    // a diagonal from (0, 0) to (10, 10) is y = 300 - 0.75 x in
    // pixels: a 100 x 50 box at the upper right (x 295..395, y 5..55)
    // covers it, the upper left (x 5..105, y 5..55) does not
    let mut c = Cover::default();
    c.lines.push((vec![(0.0, 0.0), (10.0, 10.0)], 1.0));
    let (spot, f) = c.place(Corner::UpperRight, (100.0, 50.0), frame10(), FREE);
    assert_eq!((spot, f), (P::UpperLeft, frame10()));
    // nothing in the way: the panel's own corner
    let (spot, _) = Cover::default().place(Corner::LowerLeft, (100.0, 50.0), frame10(), FREE);
    assert_eq!(spot, P::LowerLeft);
    // a note in the upper left is never covered
    let mut c = Cover::default();
    c.boxes.push([8.0, 8.0, 200.0, 22.0]);
    let (spot, _) = c.place(Corner::UpperLeft, (100.0, 50.0), frame10(), FREE);
    assert_eq!(spot, P::UpperRight);
}

#[test]
fn the_range_grows_when_every_spot_is_covered() {
    use SeriesLabelPosition as P;
    // lines across at y = 9.5, 5 and 0.5 (pixels 15, 150, 285) cover
    // every corner and edge middle of a 100 x 50 legend
    let mut c = Cover::default();
    for y in [9.5, 5.0, 0.5] {
        c.lines.push((vec![(0.0, y), (10.0, y)], 1.0));
    }
    // growing the top by (50 + 10) px: span 10 * 300 / 240 = 12.5, and
    // y = 9.5 moves to pixel 3 / 12.5 * 300 = 72, below the box (5..55
    // and 4 px of room); a quarter, half or three quarters of that
    // leave it at 29, 44 and 58 px, still covered
    let (spot, f) = c.place(Corner::UpperRight, (100.0, 50.0), frame10(), FREE);
    assert_eq!(spot, P::UpperRight);
    assert!(
        (f.y.0 - 0.0).abs() < 1e-12 && (f.y.1 - 12.5).abs() < 1e-9,
        "{f:?}"
    );
    assert_eq!(f.x, (0.0, 10.0));
    // a clipped top may not grow: the bottom does, for a lower spot
    let room = Room { top: false, ..FREE };
    let (spot, f) = c.place(Corner::UpperRight, (100.0, 50.0), frame10(), room);
    assert_eq!(spot, P::LowerRight);
    assert!((f.y.0 + 2.5).abs() < 1e-9 && f.y.1 == 10.0, "{f:?}");
    // a fixed range does not grow: the spot that covers least
    let fixed = Room {
        top: false,
        bottom: false,
        ..FREE
    };
    let (_, f) = c.place(Corner::UpperRight, (100.0, 50.0), frame10(), fixed);
    assert_eq!(f, frame10());
    // an equal aspect keeps one scale: x widens with y
    let square = Frame {
        px: (300.0, 300.0),
        ..frame10()
    };
    let room = Room {
        equal_aspect: true,
        ..FREE
    };
    let (_, f) = c.place(Corner::UpperRight, (100.0, 50.0), square, room);
    let (sx, sy) = ((f.x.1 - f.x.0) / f.px.0, (f.y.1 - f.y.0) / f.px.1);
    assert!(f.y.1 > 10.0 && (sx - sy).abs() < 1e-12, "{f:?}");
}

#[test]
fn a_spread_is_a_filled_band_in_its_colour() {
    let panel = |spread: bool| {
        let mut p = Panel::new("t", PlotAxis::new("x", "kPa"), PlotAxis::new("y", "mm"));
        let pts = [[0.0, 1.0], [1.0, 2.0], [2.0, 2.5]];
        if spread {
            p.series.extend(
                Series::spread("eps0=0.25", &pts, &[0.1, 0.2, 0.3], [0.0, 10.0])
                    .map(|s| s.label("band")),
            );
        }
        p.series
            .push(Series::new("eps0=0.25", SeriesKind::Line, pts.to_vec()).label("curve"));
        svg(&Figure::row("spread", [600, 400], vec![p])).unwrap()
    };
    let c = hex(color_of("eps0=0.25"));
    let with = panel(true);
    let polygons: Vec<&str> = with.split("<polygon").skip(1).collect();
    assert!(
        polygons
            .iter()
            .any(|p| p[..p.find('>').unwrap()].contains(&c)),
        "{with}"
    );
    assert!(with.contains("band") && with.contains("curve"));
    assert!(!panel(false).contains("<polygon"));
}
