//! One renderer for every study's [`Figure`]: plotters' SVG backend, text
//! as SVG `<text>` elements (no font files are read), and a fixed palette
//! keyed by the series' colour keys, so that one prestrain, mounting angle
//! or overlap has one colour in every panel of every study.

use fpc::studies::{Corner, Figure, Panel, PlotAxis, Series, SeriesKind, BENT_BACKWARDS};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::files::escape;

/// The drawing area of one panel.
type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// A grey for reference lines.
pub const GREY: RGBColor = RGBColor(110, 110, 110);

/// The colours of the keys the studies use: the paper's prestrains, then
/// its mounting angles (Okabe-Ito), its overlaps, and the quantities drawn
/// alone. A key not listed gets one of [`SPARE`] by a hash of its text.
const KEYED: [(&str, RGBColor); 21] = [
    ("eps0=0.4", RGBColor(0, 114, 178)),
    ("eps0=0.25", RGBColor(213, 94, 0)),
    ("eps0=0.15", RGBColor(0, 158, 115)),
    ("a=pi/2", RGBColor(204, 121, 167)),
    ("a=pi/2.5", RGBColor(230, 159, 0)),
    ("a=pi/3", RGBColor(86, 180, 233)),
    ("g=0mm", RGBColor(51, 34, 136)),
    ("g=10mm", RGBColor(153, 153, 51)),
    ("g=20mm", RGBColor(136, 34, 85)),
    ("region", RGBColor(68, 170, 153)),
    ("cuboid", RGBColor(204, 102, 119)),
    ("normal force", RGBColor(17, 119, 51)),
    ("height", RGBColor(170, 68, 153)),
    ("slips", RGBColor(204, 102, 119)),
    ("grasps", RGBColor(68, 170, 153)),
    ("envelope", RGBColor(17, 119, 51)),
    ("peak", RGBColor(204, 102, 119)),
    ("viable", RGBColor(17, 119, 51)),
    ("not viable", RGBColor(204, 102, 119)),
    ("reference", GREY),
    (BENT_BACKWARDS, BLACK),
];

/// Colours for keys not in [`KEYED`].
const SPARE: [RGBColor; 6] = [
    RGBColor(51, 102, 170),
    RGBColor(187, 85, 51),
    RGBColor(34, 136, 85),
    RGBColor(119, 51, 153),
    RGBColor(170, 136, 0),
    RGBColor(85, 85, 85),
];

/// The colour of a colour key: a pure function of the key.
pub fn color_of(key: &str) -> RGBColor {
    if let Some((_, c)) = KEYED.iter().find(|(k, _)| *k == key) {
        return *c;
    }
    // FNV-1a: stable across runs and platforms
    let h = key.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
    });
    SPARE[(h % SPARE.len() as u64) as usize]
}

/// A colour as SVG writes it (`#0072B2`).
#[cfg(test)]
pub fn hex(c: RGBColor) -> String {
    format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
}

/// Print sizing of a figure: the width it is shown at on paper and the
/// size of its tick labels there. The drawing keeps its pixel layout; the
/// SVG's `width` and `height` become inches and every text (titles, axis
/// names, legends, notes) scales with the tick labels.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Style {
    /// Printed width in inches (`None`: the pixel size, at 96 px per inch).
    pub width_in: Option<f64>,
    /// Printed size of the tick labels in points (`None`: as drawn, 13 px
    /// in plotters' units).
    pub font_pt: Option<f64>,
}

/// Default tick-label size in plotters' units; the SVG's font-size is
/// 1/1.24 of it.
const LABEL_FONT: f64 = 13.0;

impl Style {
    /// Checks the options (positive and finite).
    pub fn validate(&self) -> anyhow::Result<()> {
        for (name, v) in [("--width-in", self.width_in), ("--font-pt", self.font_pt)] {
            if let Some(v) = v {
                anyhow::ensure!(
                    v.is_finite() && v > 0.0 && v <= 1000.0,
                    "{name} = {v}: must be a positive number of at most 1000"
                );
            }
        }
        Ok(())
    }

    /// Printed points per SVG pixel of a figure `width_px` wide.
    fn pt_per_px(&self, width_px: u32) -> f64 {
        match self.width_in {
            Some(w) => 72.0 * w / f64::from(width_px.max(1)),
            None => 0.75,
        }
    }

    /// The factor on every font size (and on the label areas that hold
    /// them) for a figure `width_px` wide.
    fn font_scale(&self, width_px: u32) -> f64 {
        match self.font_pt {
            Some(pt) => pt / (LABEL_FONT / 1.24 * self.pt_per_px(width_px)),
            None => 1.0,
        }
    }
}

/// Renders a figure as an SVG document, at its pixel size.
pub fn svg(fig: &Figure) -> anyhow::Result<String> {
    svg_styled(fig, &Style::default())
}

/// Renders a figure as an SVG document sized for print by `style`.
pub fn svg_styled(fig: &Figure, style: &Style) -> anyhow::Result<String> {
    anyhow::ensure!(
        fig.rows.iter().all(|r| !r.is_empty()) && !fig.rows.is_empty(),
        "the figure has no panels"
    );
    let k = style.font_scale(fig.size[0]);
    let mut buf = String::new();
    {
        let root =
            SVGBackend::with_string(&mut buf, (fig.size[0], fig.size[1])).into_drawing_area();
        root.fill(&WHITE)?;
        let body = root.titled(&fig.title, ("sans-serif", 21.0 * k))?;
        let rows = body.split_evenly((fig.rows.len(), 1));
        for (row, area) in fig.rows.iter().zip(&rows) {
            let cells = area.split_evenly((1, row.len()));
            for (p, cell) in row.iter().zip(&cells) {
                draw(p, cell, k)?;
            }
        }
        root.present()?;
    }
    if let Some(w) = style.width_in {
        let h = w * f64::from(fig.size[1]) / f64::from(fig.size[0].max(1));
        let from = format!("<svg width=\"{}\" height=\"{}\"", fig.size[0], fig.size[1]);
        anyhow::ensure!(
            buf.starts_with(&from),
            "unexpected SVG header from plotters"
        );
        buf = format!(
            "<svg width=\"{w:.3}in\" height=\"{h:.3}in\"{}",
            &buf[from.len()..]
        );
    }
    Ok(buf)
}

/// The finite points of a series.
fn finite(points: &[[f64; 2]]) -> Vec<(f64, f64)> {
    points
        .iter()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .map(|p| (p[0], p[1]))
        .collect()
}

/// A data range with 5 % margins (a unit range around a single value,
/// `0..1` without data).
fn padded(v: &[f64]) -> (f64, f64) {
    let (lo, hi) = v
        .iter()
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    if span <= 1e-12 * (1.0 + lo.abs()) {
        let d = 0.5 * (1.0 + lo.abs() * 0.1);
        return (lo - d, hi + d);
    }
    (lo - 0.05 * span, hi + 0.05 * span)
}

fn range(axis: &PlotAxis, mut data: Vec<f64>) -> (f64, f64) {
    if let Some([a, b]) = axis.range {
        return (a, b);
    }
    if axis.include_zero {
        data.push(0.0);
    }
    padded(&data)
}

/// The panel's ranges: fixed, or fitted to everything it draws (stretched
/// for an equal aspect on `plot_px` pixels).
fn ranges(p: &Panel, plot_px: (f64, f64)) -> ((f64, f64), (f64, f64)) {
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for s in &p.series {
        for (x, y) in finite(&s.points) {
            xs.push(x);
            ys.push(y);
        }
        if s.kind == SeriesKind::Area {
            ys.push(0.0);
        }
    }
    xs.extend(p.vlines.iter().map(|v| v.at));
    ys.extend(p.hlines.iter().map(|h| h.at));
    for b in &p.bands {
        xs.extend([b.from, b.to]);
    }
    let mut x = range(&p.x, xs);
    let mut y = range(&p.y, ys);
    if p.equal_aspect {
        // stretch the range that is too short for the pixel aspect
        let (w, h) = plot_px;
        let (sx, sy) = ((x.1 - x.0) / w, (y.1 - y.0) / h);
        if sx > sy {
            let extra = 0.5 * (sx * h - (y.1 - y.0));
            y = (y.0 - extra, y.1 + extra);
        } else {
            let extra = 0.5 * (sy * w - (x.1 - x.0));
            x = (x.0 - extra, x.1 + extra);
        }
    }
    (x, y)
}

fn position(c: Corner) -> SeriesLabelPosition {
    match c {
        Corner::UpperLeft => SeriesLabelPosition::UpperLeft,
        Corner::UpperRight => SeriesLabelPosition::UpperRight,
        Corner::LowerLeft => SeriesLabelPosition::LowerLeft,
        Corner::LowerRight => SeriesLabelPosition::LowerRight,
    }
}

/// Draws one panel into `area`.
fn draw(p: &Panel, area: &Area, k: f64) -> anyhow::Result<()> {
    // label areas grow with the fonts they hold
    let grown = |px: f64| (px * k.max(0.5)).round() as u32;
    let (x_labels, y_labels, caption) = (grown(42.0), grown(62.0), grown(26.0));
    const MARGIN: u32 = 12;
    // a log axis is drawn as log10 of the data on a linear axis
    let logged;
    let p = if p.x.log || p.y.log {
        logged = on_log_axes(p);
        &logged
    } else {
        p
    };
    let (w, h) = area.dim_in_pixel();
    let plot_px = (
        f64::from(w.saturating_sub(y_labels + 2 * MARGIN).max(10)),
        f64::from(h.saturating_sub(x_labels + caption + 2 * MARGIN).max(10)),
    );
    let ((x0, x1), (y0, y1)) = ranges(p, plot_px);
    let mut builder = ChartBuilder::on(area);
    if !p.title.is_empty() {
        builder.caption(&p.title, ("sans-serif", 17.0 * k));
    }
    let mut chart = builder
        .margin(MARGIN)
        .x_label_area_size(x_labels)
        .y_label_area_size(y_labels)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(p.x.text())
        .y_desc(p.y.text())
        .label_style(("sans-serif", LABEL_FONT * k))
        .axis_desc_style(("sans-serif", 14.0 * k))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .x_labels(7)
        .y_labels(7);
    if p.x.log {
        mesh.x_labels(decade_labels(x0, x1))
            .x_max_light_lines(1)
            .x_label_formatter(&power_of_ten);
    }
    if p.y.log {
        mesh.y_labels(decade_labels(y0, y1))
            .y_max_light_lines(1)
            .y_label_formatter(&power_of_ten);
    }
    mesh.draw()?;
    draw_log_minor_lines(&mut chart, p, (x0, x1), (y0, y1))?;
    let mut labelled = false;
    for (k, b) in p.bands.iter().enumerate() {
        let color = color_of(&b.color);
        let (a, z) = (b.from.max(x0), b.to.min(x1));
        if z > a {
            let anno = chart.draw_series(std::iter::once(Rectangle::new(
                [(a, y0), (z, y1)],
                color.mix(0.18).filled(),
            )))?;
            if let (0, Some(l)) = (k, &p.band_label) {
                labelled = true;
                anno.label(l.as_str()).legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 18, y + 5)], color.mix(0.3).filled())
                });
            }
        }
    }
    for line in &p.hlines {
        let anno = chart.draw_series(DashedLineSeries::new(
            [(x0, line.at), (x1, line.at)],
            6,
            4,
            GREY.stroke_width(1),
        ))?;
        if !line.label.is_empty() {
            labelled = true;
            anno.label(line.label.as_str())
                .legend(|(x, y)| legend_mark(x, y, GREY, SeriesKind::Dashed));
        }
    }
    for line in &p.vlines {
        let anno = chart.draw_series(DashedLineSeries::new(
            [(line.at, y0), (line.at, y1)],
            3,
            3,
            GREY.stroke_width(1),
        ))?;
        if !line.label.is_empty() {
            labelled = true;
            anno.label(line.label.as_str()).legend(|(x, y)| {
                PathElement::new(vec![(x + 9, y - 6), (x + 9, y + 6)], GREY.stroke_width(1))
            });
        }
    }
    // areas first, so that every line and marker stays visible
    let order = p
        .series
        .iter()
        .filter(|s| s.kind == SeriesKind::Area)
        .chain(p.series.iter().filter(|s| s.kind != SeriesKind::Area));
    let mut legend: Vec<&str> = Vec::new();
    for s in order {
        let anno = draw_series(&mut chart, s)?;
        // one legend entry per label (the bent-backwards markers of
        // several curves share one)
        if let Some(l) = s.label.as_deref().filter(|l| !legend.contains(l)) {
            legend.push(l);
            labelled = true;
            let (c, kind) = (color_of(&s.color), s.kind);
            anno.label(l)
                .legend(move |(x, y)| legend_mark(x, y, c, kind));
        }
    }
    if !p.notes.is_empty() {
        let style = ("sans-serif", LABEL_FONT * k).into_font().color(&BLACK);
        chart.draw_series(p.notes.iter().enumerate().map(|(i, n)| {
            EmptyElement::at((x0, y1))
                + Text::new(
                    n.clone(),
                    (8, 8 + (17.0 * k * i as f64) as i32),
                    style.clone(),
                )
        }))?;
    }
    if labelled {
        chart
            .configure_series_labels()
            .position(position(p.legend))
            .label_font(("sans-serif", 12.0 * k))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(190, 190, 190))
            .draw()?;
    }
    Ok(())
}

// ------------------------------------------------------------ log axes

/// `log10(v)`, or `None` for a value a log axis cannot show.
fn log10_of(v: f64) -> Option<f64> {
    (v > 0.0 && v.is_finite()).then(|| v.log10())
}

/// A copy of `p` with the data of its log axes replaced by their log10
/// (values that are not positive become NaN points, which are skipped, or
/// are dropped), a fixed range likewise, `include_zero` ignored, and areas
/// on a log y axis drawn as lines (their base, y = 0, is not on it).
fn on_log_axes(p: &Panel) -> Panel {
    let mut q = p.clone();
    let map = |log: bool, v: f64| {
        if log {
            log10_of(v).unwrap_or(f64::NAN)
        } else {
            v
        }
    };
    for s in &mut q.series {
        for pt in &mut s.points {
            *pt = [map(p.x.log, pt[0]), map(p.y.log, pt[1])];
        }
        if p.y.log && s.kind == SeriesKind::Area {
            s.kind = SeriesKind::Line;
        }
    }
    for (lines, log) in [(&mut q.hlines, p.y.log), (&mut q.vlines, p.x.log)] {
        lines.retain_mut(|l| {
            l.at = map(log, l.at);
            l.at.is_finite()
        });
    }
    if p.x.log {
        q.bands.retain_mut(|b| match log10_of(b.to) {
            Some(to) => {
                b.from = log10_of(b.from).unwrap_or(f64::NEG_INFINITY);
                b.to = to;
                true
            }
            None => false,
        });
    }
    for axis in [&mut q.x, &mut q.y] {
        if axis.log {
            axis.include_zero = false;
            axis.range = axis.range.and_then(|[a, b]| {
                let (a, b) = (log10_of(a)?, log10_of(b)?);
                (b > a).then_some([a, b])
            });
        }
    }
    q
}

/// The integer powers in `[lo, hi]` (log10 units): asked for as many
/// labels, plotters puts its ticks on them (its steps are 1, 2 or 5 times a
/// power of ten, and step 1/2 would give too many). Fewer than two: the
/// default count, ticks between powers.
fn decade_labels(lo: f64, hi: f64) -> usize {
    let n = (hi.floor() - lo.ceil() + 1.0).max(0.0);
    if n >= 2.0 {
        (n as usize).min(16)
    } else {
        7
    }
}

/// Superscript digits of an integer exponent (`-2` -> `⁻²`).
fn superscript(k: i64) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::new();
    if k < 0 {
        s.push('⁻');
    }
    for c in k.unsigned_abs().to_string().chars() {
        s.push(c.to_digit(10).map_or(c, |d| DIGITS[d as usize]));
    }
    s
}

/// The label of a tick at `v` on a log axis: `10⁻²` at a power of ten,
/// else the value with three significant digits.
fn power_of_ten(v: &f64) -> String {
    let k = v.round();
    if (v - k).abs() < 1e-6 && k.abs() < 1e6 {
        format!("10{}", superscript(k as i64))
    } else {
        format!("{:.2e}", 10f64.powf(*v))
    }
}

/// Light grid lines at 2..9 times each power of ten of a log axis (the
/// mesh's own light lines are turned off there), when the axis spans at
/// most 12 decades.
fn draw_log_minor_lines(
    chart: &mut Chart<'_, '_>,
    p: &Panel,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> anyhow::Result<()> {
    let minor = |lo: f64, hi: f64| -> Vec<f64> {
        if !(hi - lo).is_finite() || hi - lo > 12.0 {
            return Vec::new();
        }
        let (first, last) = (lo.floor() as i64, hi.ceil() as i64);
        (first..=last)
            .flat_map(|k| (2..=9).map(move |m| k as f64 + f64::from(m).log10()))
            .filter(|v| (lo..=hi).contains(v))
            .collect()
    };
    let style = RGBColor(238, 238, 238).stroke_width(1);
    if p.x.log {
        chart.draw_series(
            minor(x0, x1)
                .into_iter()
                .map(|x| PathElement::new(vec![(x, y0), (x, y1)], style)),
        )?;
    }
    if p.y.log {
        chart.draw_series(
            minor(y0, y1)
                .into_iter()
                .map(|y| PathElement::new(vec![(x0, y), (x1, y)], style)),
        )?;
    }
    Ok(())
}

type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

fn draw_series<'a, 'b, 'c>(
    chart: &'c mut Chart<'a, 'b>,
    s: &Series,
) -> anyhow::Result<&'c mut plotters::chart::SeriesAnno<'a, SVGBackend<'b>>> {
    let c = color_of(&s.color);
    let pts = finite(&s.points);
    Ok(match s.kind {
        SeriesKind::Line => chart.draw_series(LineSeries::new(pts, c.stroke_width(2)))?,
        SeriesKind::Dashed => {
            chart.draw_series(DashedLineSeries::new(pts, 5, 5, c.stroke_width(2)))?
        }
        SeriesKind::LinePoints => {
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))?;
            chart.draw_series(LineSeries::new(pts, c.stroke_width(2)))?
        }
        SeriesKind::Points => {
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))?
        }
        SeriesKind::Scatter => {
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 2, c.mix(0.55).filled())))?
        }
        SeriesKind::Hollow => {
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 4, c.stroke_width(1))))?
        }
        SeriesKind::Cross => {
            chart.draw_series(pts.iter().map(|&p| Cross::new(p, 4, c.stroke_width(2))))?
        }
        SeriesKind::Area => chart
            .draw_series(AreaSeries::new(pts, 0.0, c.mix(0.25)).border_style(c.stroke_width(2)))?,
        SeriesKind::BentBackwards => {
            chart.draw_series(pts.iter().map(|&p| Circle::new(p, 6, c.stroke_width(2))))?
        }
    })
}

fn legend_mark<DB: DrawingBackend>(
    x: i32,
    y: i32,
    c: RGBColor,
    kind: SeriesKind,
) -> DynElement<'static, DB, (i32, i32)> {
    match kind {
        SeriesKind::Line | SeriesKind::LinePoints => {
            PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)).into_dyn()
        }
        SeriesKind::Dashed => plotters::element::DashedPathElement::new(
            vec![(x, y), (x + 18, y)],
            4,
            3,
            c.stroke_width(2),
        )
        .into_dyn(),
        SeriesKind::Points | SeriesKind::Scatter => {
            Circle::new((x + 9, y), 3, c.filled()).into_dyn()
        }
        SeriesKind::Hollow => Circle::new((x + 9, y), 4, c.stroke_width(1)).into_dyn(),
        SeriesKind::BentBackwards => Circle::new((x + 9, y), 6, c.stroke_width(2)).into_dyn(),
        SeriesKind::Cross => Cross::new((x + 9, y), 4, c.stroke_width(2)).into_dyn(),
        SeriesKind::Area => {
            Rectangle::new([(x, y - 5), (x + 18, y + 5)], c.mix(0.4).filled()).into_dyn()
        }
    }
}

/// A figure that only states why there is nothing to plot.
pub fn placeholder(title: &str, message: &str) -> String {
    format!(
        "<svg width=\"800\" height=\"160\" viewBox=\"0 0 800 160\" xmlns=\"http://www.w3.org/2000/svg\">\n\
         <rect x=\"0\" y=\"0\" width=\"800\" height=\"160\" fill=\"#FFFFFF\"/>\n\
         <text x=\"400\" y=\"50\" text-anchor=\"middle\" font-family=\"sans-serif\" font-size=\"20\">{}</text>\n\
         <text x=\"400\" y=\"95\" text-anchor=\"middle\" font-family=\"sans-serif\" font-size=\"14\" fill=\"#B00000\">{}</text>\n\
         </svg>\n",
        escape(title),
        escape(message)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use fpc::studies::RefLine;

    #[test]
    fn powers_of_ten_are_labelled_with_superscripts() {
        assert_eq!(power_of_ten(&-2.0), "10⁻²");
        assert_eq!(power_of_ten(&0.0), "10⁰");
        assert_eq!(power_of_ten(&13.0), "10¹³");
        assert_eq!(power_of_ten(&0.5), "3.16e0");
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
}
