//! The SVG writer of every [`Figure`] (the studies', `fpc solve`'s shape,
//! `fpc design`'s, the accuracy study's): plotters' SVG backend, text as
//! SVG `<text>` elements (no font files are read), and a fixed palette
//! keyed by the series' colour keys, so that one prestrain, mounting angle
//! or overlap has one colour in every panel of every figure.

use fpc::report::{
    Corner, Figure, Panel, PlotAxis, Series, SeriesKind, BENT_BACKWARDS, INVALID_GRASP, NEUTRAL,
};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::html::escape;

/// The drawing area of one panel.
type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// A grey for reference lines.
pub const GREY: RGBColor = RGBColor(110, 110, 110);

/// The colours of the keys the studies use: the paper's prestrains, then
/// its mounting angles (Okabe-Ito), its overlaps, and the quantities drawn
/// alone. A key not listed gets one of [`SPARE`] by a hash of its text.
const KEYED: [(&str, RGBColor); 29] = [
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
    (INVALID_GRASP, RGBColor(204, 51, 17)),
    (NEUTRAL, RGBColor(60, 60, 60)),
    // the parts of a finger or gripper drawing
    ("finger", RGBColor(31, 95, 191)),
    ("mirror", RGBColor(160, 185, 230)),
    ("rest", RGBColor(120, 120, 120)),
    ("palm", RGBColor(51, 51, 51)),
    ("object", RGBColor(176, 106, 0)),
    ("tip", RGBColor(192, 57, 43)),
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
    /// Checks the options (positive and finite): rejected input otherwise.
    pub fn validate(&self) -> anyhow::Result<()> {
        for (name, v) in [("--width-in", self.width_in), ("--font-pt", self.font_pt)] {
            if let Some(v) = v {
                if !(v.is_finite() && v > 0.0 && v <= 1000.0) {
                    return Err(crate::status::rejected(format!(
                        "{name} = {v}: must be a positive number of at most 1000"
                    )));
                }
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

/// The data ranges of a panel's plotting area and its size in pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Frame {
    x: (f64, f64),
    y: (f64, f64),
    /// Width and height of the plotting area in pixels.
    px: (f64, f64),
}

impl Frame {
    /// A data point in pixels from the plotting area's top-left corner.
    fn pixel(&self, (x, y): (f64, f64)) -> (f64, f64) {
        (
            (x - self.x.0) / (self.x.1 - self.x.0) * self.px.0,
            (self.y.1 - y) / (self.y.1 - self.y.0) * self.px.1,
        )
    }

    /// Stretches the range that is too short for an equal scale on both
    /// axes.
    fn equal_aspect(mut self) -> Frame {
        let (w, h) = self.px;
        let (x, y) = (self.x, self.y);
        let (sx, sy) = ((x.1 - x.0) / w, (y.1 - y.0) / h);
        if sx > sy {
            let extra = 0.5 * (sx * h - (y.1 - y.0));
            self.y = (y.0 - extra, y.1 + extra);
        } else {
            let extra = 0.5 * (sy * w - (x.1 - x.0));
            self.x = (x.0 - extra, x.1 + extra);
        }
        self
    }
}

/// The panel's frame: ranges fixed, or fitted to everything it draws
/// (stretched for an equal aspect on `px` pixels). Under a clipped axis
/// top (`top`), values above it count as the top and the range ends there.
fn frame(p: &Panel, px: (f64, f64), top: Option<f64>) -> Frame {
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    let cap = |y: f64| top.map_or(y, |t| y.min(t));
    for s in &p.series {
        for (x, y) in finite(&s.points) {
            xs.push(x);
            ys.push(cap(y));
        }
        if s.kind == SeriesKind::Area {
            ys.push(0.0);
        }
    }
    xs.extend(p.vlines.iter().map(|v| v.at));
    ys.extend(p.hlines.iter().map(|h| h.at).filter(|&y| y <= cap(y)));
    for b in &p.bands {
        xs.extend([b.from, b.to]);
    }
    let x = range(&p.x, xs);
    let mut y = range(&p.y, ys);
    if let Some(t) = top.filter(|&t| t > y.0) {
        y.1 = t;
    }
    let f = Frame { x, y, px };
    if p.equal_aspect {
        f.equal_aspect()
    } else {
        f
    }
}

fn position(c: Corner) -> SeriesLabelPosition {
    match c {
        Corner::UpperLeft => SeriesLabelPosition::UpperLeft,
        Corner::UpperRight => SeriesLabelPosition::UpperRight,
        Corner::LowerLeft => SeriesLabelPosition::LowerLeft,
        Corner::LowerRight => SeriesLabelPosition::LowerRight,
    }
}

/// Tick labels per axis, as plotters is asked for.
const TICKS: usize = 7;

/// Colour of the text that says an axis is clipped.
const CLIP_NOTE: RGBColor = RGBColor(150, 60, 0);

/// Where a series is drawn: areas first, so that every line and marker
/// stays visible, and the bent-backwards circles last, over every curve
/// (their legend entry after the curves').
fn layer(kind: SeriesKind) -> u8 {
    match kind {
        SeriesKind::Area | SeriesKind::Outline => 0,
        SeriesKind::BentBackwards | SeriesKind::Invalid => 2,
        _ => 1,
    }
}

/// The indices of a panel's series in drawing order ([`layer`]).
fn drawing_order(p: &Panel) -> Vec<usize> {
    let mut order: Vec<usize> = (0..p.series.len()).collect();
    order.sort_by_key(|&i| layer(p.series[i].kind));
    order
}

/// The legend entries of a panel, in the order they are drawn.
fn legend_entries(p: &Panel, top: Option<f64>) -> Vec<String> {
    let mut entries: Vec<String> = Vec::new();
    if !p.bands.is_empty() {
        entries.extend(p.band_label.clone());
    }
    let hlines = p.hlines.iter().filter(|l| top.is_none_or(|t| l.at <= t));
    for l in hlines.chain(&p.vlines) {
        if !l.label.is_empty() {
            entries.push(l.label.clone());
        }
    }
    let order = drawing_order(p).into_iter().map(|i| &p.series[i]);
    for l in order.filter_map(|s| s.label.as_deref()) {
        if !entries.iter().any(|e| e == l) {
            entries.push(l.to_string());
        }
    }
    entries
}

/// Draws one panel into `area`.
fn draw(p: &Panel, area: &Area, k: f64) -> anyhow::Result<()> {
    // label areas grow with the fonts they hold
    let grown = |px: f64| (px * k.max(0.5)).round() as u32;
    let (x_labels, y_labels) = (grown(42.0), grown(62.0));
    const MARGIN: u32 = 12;
    // an axis cut short above outliers (never a log axis)
    let (top, clip_note) = match (p.clipped(), p.clip_note()) {
        (Some(c), Some(n)) => (Some(c.at), Some(n)),
        _ => (None, None),
    };
    // a log axis is drawn as log10 of the data on a linear axis, a downward
    // one as the negated data
    let drawn;
    let p = if p.x.log || p.y.log || p.y.down {
        drawn = upside_down(&on_log_axes(p));
        &drawn
    } else {
        p
    };
    // the title, then the clip note, then the chart, then the caption
    let inner = area.margin(MARGIN, MARGIN, MARGIN, MARGIN);
    let inner = draw_caption(p, inner, k)?;
    let body = if p.title.is_empty() {
        inner
    } else {
        inner.titled(&p.title, ("sans-serif", 17.0 * k))?
    };
    let (bw, bh) = body.dim_in_pixel();
    let plot_w = bw.saturating_sub(y_labels).max(10);
    let note_font = ("sans-serif", 12.0 * k).into_font().color(&CLIP_NOTE);
    let note = match &clip_note {
        Some(n) => {
            let mut text = MultiLineText::<_, String>::new((0, 0), &note_font);
            for line in wrap(n, &note_font.font, f64::from(plot_w))? {
                text.push_line(line);
            }
            Some(text)
        }
        None => None,
    };
    let note_h = match &note {
        Some(t) => t.estimate_dimension().map_err(font_error)?.1.max(0) as u32 + 12,
        None => 0,
    };
    let plot_h = bh.saturating_sub(x_labels + note_h).max(10);
    let mut fr = frame(p, (f64::from(plot_w), f64::from(plot_h)), top);

    // what the legend should not cover, and where it goes
    let shown: Vec<Shown> = p.series.iter().map(|s| Shown::of(s, top)).collect();
    let font = ("sans-serif", LABEL_FONT * k).into_font();
    let step = 17.0 * k;
    let mut cover = Cover::default();
    for (s, sh) in p.series.iter().zip(&shown) {
        if s.kind == SeriesKind::Area {
            cover.areas.extend(sh.runs.iter().cloned());
        }
        cover.lines.extend(sh.runs.iter().map(|r| (r.clone(), 1.0)));
        cover.points.extend(sh.marks.iter().map(|&m| (m, 1.0)));
        if let Some(t) = top {
            cover.points.extend(sh.off.iter().map(|&x| ((x, t), 1.0)));
        }
    }
    cover.hlines = p
        .hlines
        .iter()
        .map(|l| l.at)
        .filter(|&y| top.is_none_or(|t| y <= t))
        .collect();
    cover.vlines = p.vlines.iter().map(|l| l.at).collect();
    for (i, n) in p.notes.iter().enumerate() {
        let (tw, th) = font.box_size(n).map_err(font_error)?;
        let y = 8.0 + (step * i as f64).floor();
        cover
            .boxes
            .push([8.0, y, 8.0 + f64::from(tw), y + f64::from(th)]);
    }
    let entries = legend_entries(p, top);
    let legend_font: TextStyle = ("sans-serif", 12.0 * k).into();
    let spot = if entries.is_empty() {
        None
    } else {
        let mut text = MultiLineText::<_, &str>::new((0, 0), &legend_font);
        for e in &entries {
            text.push_line(e.as_str());
        }
        let (tw, th) = text.estimate_dimension().map_err(font_error)?;
        // plotters' legend box: a 30 px mark column and 10 px margins
        let size = (f64::from(tw + 30 + 20), f64::from(th + 20));
        let room = Room {
            top: top.is_none() && p.y.range.is_none(),
            bottom: p.y.range.is_none(),
            equal_aspect: p.equal_aspect,
        };
        let (spot, placed) = cover.place(p.legend, size, fr, room);
        fr = placed;
        Some(spot)
    };

    let Frame {
        x: (x0, x1),
        y: (y0, y1),
        ..
    } = fr;
    let mut chart = ChartBuilder::on(&body)
        .margin_top(note_h)
        .x_label_area_size(x_labels)
        .y_label_area_size(y_labels)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    if let Some(mut text) = note {
        let (tw, th) = text.estimate_dimension().map_err(font_error)?;
        let left = y_labels as i32 + (plot_w as i32 - tw) / 2;
        text.relocate((left.max(0), note_h as i32 - th - 10));
        body.draw(&text)?;
    }
    // tick labels that share their decimals along an axis
    let flip = if p.y.down { -1.0 } else { 1.0 };
    let y_keys: Vec<f64> = RangedCoordf64::from(y0..y1).key_points(TICKS);
    let (x_ticks, y_ticks) = (
        tick_format(&RangedCoordf64::from(x0..x1).key_points(TICKS)),
        tick_format(&y_keys.iter().map(|v| flip * v).collect::<Vec<_>>()),
    );
    let x_label = move |v: &f64| tick_label(*v, x_ticks);
    let y_label = move |v: &f64| tick_label(flip * *v, y_ticks);
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(p.x.text())
        .y_desc(p.y.text())
        .label_style(("sans-serif", LABEL_FONT * k))
        .axis_desc_style(("sans-serif", 14.0 * k))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .x_labels(TICKS)
        .y_labels(TICKS)
        .x_label_formatter(&x_label)
        .y_label_formatter(&y_label);
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
    let mut legend: Vec<&str> = Vec::new();
    for (i, b) in p.bands.iter().enumerate() {
        let color = color_of(&b.color);
        let (a, z) = (b.from.max(x0), b.to.min(x1));
        if z > a {
            let anno = chart.draw_series(std::iter::once(Rectangle::new(
                [(a, y0), (z, y1)],
                color.mix(0.18).filled(),
            )))?;
            if let (0, Some(l)) = (i, &p.band_label) {
                anno.label(l.as_str()).legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 18, y + 5)], color.mix(0.3).filled())
                });
            }
        }
    }
    for line in p.hlines.iter().filter(|l| top.is_none_or(|t| l.at <= t)) {
        let anno = chart.draw_series(DashedLineSeries::new(
            [(x0, line.at), (x1, line.at)],
            6,
            4,
            GREY.stroke_width(1),
        ))?;
        if !line.label.is_empty() {
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
            anno.label(line.label.as_str()).legend(|(x, y)| {
                PathElement::new(vec![(x + 9, y - 6), (x + 9, y + 6)], GREY.stroke_width(1))
            });
        }
    }
    let order: Vec<(&Series, &Shown)> = drawing_order(p)
        .into_iter()
        .map(|i| (&p.series[i], &shown[i]))
        .collect();
    for &(s, sh) in &order {
        let anno = draw_series(&mut chart, s, sh)?;
        // one legend entry per label (the bent-backwards markers of
        // several curves share one)
        if let Some(l) = s.label.as_deref().filter(|l| !legend.contains(l)) {
            legend.push(l);
            let (c, kind) = (color_of(&s.color), s.kind);
            anno.label(l)
                .legend(move |(x, y)| legend_mark(x, y, c, kind));
        }
    }
    // where a curve leaves a clipped axis, and points above it: a triangle
    // on the top edge
    if let Some(t) = top {
        for &(s, sh) in &order {
            let c = color_of(&s.color);
            let style = match s.kind {
                SeriesKind::Hollow | SeriesKind::BentBackwards | SeriesKind::Invalid => {
                    c.stroke_width(2)
                }
                _ => c.filled(),
            };
            chart.draw_series(
                sh.off
                    .iter()
                    .map(|&x| TriangleMarker::new((x, t), 6, style)),
            )?;
        }
    }
    if !p.notes.is_empty() {
        let style = font.color(&BLACK);
        chart.draw_series(p.notes.iter().enumerate().map(|(i, n)| {
            EmptyElement::at((x0, y1))
                + Text::new(n.clone(), (8, 8 + (step * i as f64) as i32), style.clone())
        }))?;
    }
    if let Some(spot) = spot {
        chart
            .configure_series_labels()
            .position(spot)
            .label_font(legend_font)
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(190, 190, 190))
            .draw()?;
    }
    Ok(())
}

/// Draws the panel's caption at the bottom of `area`, wrapped to its
/// width, and returns the area above it.
fn draw_caption<'a>(p: &Panel, area: Area<'a>, k: f64) -> anyhow::Result<Area<'a>> {
    if p.caption.is_empty() {
        return Ok(area);
    }
    let font = ("sans-serif", LABEL_FONT * k).into_font().color(&BLACK);
    let (w, h) = area.dim_in_pixel();
    let mut lines = Vec::new();
    for c in &p.caption {
        lines.extend(wrap(c, &font.font, f64::from(w))?);
    }
    let step = (17.0 * k).round() as u32;
    let caption_h = (step * lines.len() as u32 + 8).min(h / 2);
    let (upper, foot) = area.split_vertically(h - caption_h);
    for (i, line) in lines.iter().enumerate() {
        let y = 8 + (step * i as u32) as i32;
        foot.draw(&Text::new(line.as_str(), (0, y), font.clone()))?;
    }
    Ok(upper)
}

/// A copy of `p` with a downward vertical axis turned upright: its data,
/// reference lines and fixed range negated (the tick labels negate back).
fn upside_down(p: &Panel) -> Panel {
    let mut q = p.clone();
    if p.y.down {
        for pt in q.series.iter_mut().flat_map(|s| &mut s.points) {
            pt[1] = -pt[1];
        }
        for l in &mut q.hlines {
            l.at = -l.at;
        }
        q.y.range = p.y.range.map(|[a, b]| [-b, -a]);
    }
    q
}

/// `text` broken into lines at most `width` pixels wide in `font`, at
/// spaces (a word wider than that stays whole on its line).
fn wrap(text: &str, font: &FontDesc, width: f64) -> anyhow::Result<Vec<String>> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let longer = if line.is_empty() {
            word.to_string()
        } else {
            format!("{line} {word}")
        };
        let (w, _) = font.box_size(&longer).map_err(font_error)?;
        if f64::from(w) <= width || line.is_empty() {
            line = longer;
        } else {
            lines.push(std::mem::replace(&mut line, word.to_string()));
        }
    }
    if !line.is_empty() {
        lines.push(line);
    }
    Ok(lines)
}

fn font_error(e: impl std::fmt::Debug) -> anyhow::Error {
    anyhow::anyhow!("cannot measure a text: {e:?}")
}

// ------------------------------------------------------------ tick labels

/// How the tick labels of one linear axis are written: chosen from the
/// whole set of its ticks, so that they share their decimals.
#[derive(Debug, Clone, Copy, PartialEq)]
enum TickFormat {
    /// Plain decimals, this many after the point.
    Plain(usize),
    /// A mantissa with `decimals` decimals times `10^exponent`, the
    /// exponent of the largest tick.
    Power { decimals: usize, exponent: i32 },
}

/// The fewest decimals (at most 12) that write every value of `vs`
/// exactly, to a millionth of the last digit.
fn decimals_for(vs: &[f64]) -> usize {
    (0..=12)
        .find(|&d| {
            let s = 10f64.powi(d as i32);
            vs.iter().all(|v| ((v * s) - (v * s).round()).abs() < 1e-6)
        })
        .unwrap_or(12)
}

/// The format of a set of ticks: plain decimals when the largest tick is
/// from 0.001 to below a million (0, 20, 40; 0.0, 0.5, 1.0; 0.25, 0.50),
/// else a power of ten shared by every tick (0.5×10⁻⁴, 1.0×10⁻⁴; 2×10⁶).
fn tick_format(ticks: &[f64]) -> TickFormat {
    let ticks: Vec<f64> = ticks.iter().copied().filter(|t| t.is_finite()).collect();
    let largest = ticks.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    if largest == 0.0 || (1e-3..1e6).contains(&largest) {
        return TickFormat::Plain(decimals_for(&ticks));
    }
    let exponent = largest.log10().floor() as i32;
    let scale = 10f64.powi(exponent);
    let mantissas: Vec<f64> = ticks.iter().map(|t| t / scale).collect();
    TickFormat::Power {
        decimals: decimals_for(&mantissas),
        exponent,
    }
}

/// The label of a tick at `v`: `0` for a value that rounds to zero, else
/// as `f` says.
fn tick_label(v: f64, f: TickFormat) -> String {
    if !v.is_finite() {
        return String::new();
    }
    let (mantissa, decimals, exponent) = match f {
        TickFormat::Plain(d) => (v, d, None),
        TickFormat::Power { decimals, exponent } => {
            (v / 10f64.powi(exponent), decimals, Some(exponent))
        }
    };
    let text = format!("{mantissa:.decimals$}");
    if text.chars().all(|c| matches!(c, '0' | '.' | '-')) {
        return "0".into();
    }
    match exponent {
        Some(e) => format!("{text}×10{}", superscript(i64::from(e))),
        None => text,
    }
}

// ------------------------------------------------------------ clipping

/// What of a series is drawn under a clipped axis top: the polylines
/// (each cut where it leaves the chart; an area is capped at the top
/// instead), the markers kept, and the x of every place where it leaves
/// or comes back (a line) or of every point above (markers).
struct Shown {
    runs: Vec<Vec<(f64, f64)>>,
    marks: Vec<(f64, f64)>,
    off: Vec<f64>,
}

impl Shown {
    fn of(s: &Series, top: Option<f64>) -> Shown {
        let pts = finite(&s.points);
        let lines = matches!(
            s.kind,
            SeriesKind::Line
                | SeriesKind::Dashed
                | SeriesKind::LinePoints
                | SeriesKind::Area
                | SeriesKind::Outline
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

// ------------------------------------------------------------ legend

/// How much covering a reference line counts against a legend spot,
/// against 1 for data.
const REFERENCE_WEIGHT: f64 = 0.2;

/// How much covering a filled area counts, per sample every 6 pixels.
const AREA_WEIGHT: f64 = 0.05;

/// Room of the vertical axis: whether its range may grow at the top or
/// the bottom to make space for the legend (a fitted axis, and at the top
/// one that is not clipped), and whether the panel keeps an equal aspect.
#[derive(Debug, Clone, Copy)]
struct Room {
    top: bool,
    bottom: bool,
    equal_aspect: bool,
}

/// What a legend should not cover: the lines and markers as drawn (in
/// data units), reference lines, and text boxes (pixels from the plotting
/// area's top-left corner) that it must not cover at all.
#[derive(Debug, Default)]
struct Cover {
    /// Polylines and their weight.
    lines: Vec<(Vec<(f64, f64)>, f64)>,
    /// Markers and their weight.
    points: Vec<((f64, f64), f64)>,
    /// The tops of filled areas (down to y = 0).
    areas: Vec<Vec<(f64, f64)>>,
    /// Horizontal reference lines (y).
    hlines: Vec<f64>,
    /// Vertical reference lines (x).
    vlines: Vec<f64>,
    /// [x0, y0, x1, y1] in pixels.
    boxes: Vec<[f64; 4]>,
}

/// The legend spots in the order they are preferred after the panel's own
/// corner.
const SPOTS: [SeriesLabelPosition; 8] = [
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
fn spot_box(spot: &SeriesLabelPosition, size: (f64, f64), px: (f64, f64)) -> [f64; 4] {
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
    fn samples(&self, f: &Frame) -> Vec<(f64, f64, f64)> {
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
    fn covered(&self, samples: &[(f64, f64, f64)], r: [f64; 4]) -> f64 {
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
    fn place(
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
/// else the value with three significant digits (`3.16`, `1.58×10⁻⁴`).
fn power_of_ten(v: &f64) -> String {
    let k = v.round();
    if (v - k).abs() < 1e-6 && k.abs() < 1e6 {
        format!("10{}", superscript(k as i64))
    } else {
        three_digits(10f64.powf(*v))
    }
}

/// A positive value with three significant digits, trailing zeros
/// dropped: plain from 0.001 to below a million, else times a power of
/// ten.
fn three_digits(x: f64) -> String {
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if !(x.is_finite() && x > 0.0) {
        return String::new();
    }
    let e = x.log10().floor() as i32;
    if (-3..6).contains(&e) {
        let d = (2 - e).max(0) as usize;
        trim(format!("{x:.d$}"))
    } else {
        let m = x / 10f64.powi(e);
        format!(
            "{}×10{}",
            trim(format!("{m:.2}")),
            superscript(i64::from(e))
        )
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

/// Draws a series as `shown` keeps it (one annotation for the legend).
fn draw_series<'a, 'b, 'c>(
    chart: &'c mut Chart<'a, 'b>,
    s: &Series,
    shown: &Shown,
) -> anyhow::Result<&'c mut plotters::chart::SeriesAnno<'a, SVGBackend<'b>>> {
    let c = color_of(&s.color);
    let runs = shown.runs.iter().filter(|r| !r.is_empty()).cloned();
    let marks = shown.marks.iter().copied();
    Ok(match s.kind {
        SeriesKind::Line => {
            chart.draw_series(runs.map(|r| PathElement::new(r, c.stroke_width(2))))?
        }
        SeriesKind::Dashed => chart.draw_series(
            runs.map(|r| plotters::element::DashedPathElement::new(r, 5, 5, c.stroke_width(2))),
        )?,
        SeriesKind::LinePoints => {
            chart.draw_series(marks.map(|p| Circle::new(p, 3, c.filled())))?;
            chart.draw_series(runs.map(|r| PathElement::new(r, c.stroke_width(2))))?
        }
        SeriesKind::Points => chart.draw_series(marks.map(|p| Circle::new(p, 3, c.filled())))?,
        SeriesKind::Scatter => {
            chart.draw_series(marks.map(|p| Circle::new(p, 2, c.mix(0.55).filled())))?
        }
        SeriesKind::Hollow => {
            chart.draw_series(marks.map(|p| Circle::new(p, 4, c.stroke_width(1))))?
        }
        SeriesKind::Cross => {
            chart.draw_series(marks.map(|p| Cross::new(p, 4, c.stroke_width(2))))?
        }
        SeriesKind::Area => chart.draw_series(
            AreaSeries::new(runs.flatten().collect::<Vec<_>>(), 0.0, c.mix(0.25))
                .border_style(c.stroke_width(2)),
        )?,
        SeriesKind::BentBackwards => {
            chart.draw_series(marks.map(|p| Circle::new(p, 6, c.stroke_width(2))))?
        }
        SeriesKind::Invalid => {
            chart.draw_series(marks.map(|p| Cross::new(p, 5, c.stroke_width(2))))?
        }
        SeriesKind::Outline => {
            let fill = runs.clone().map(|r| Polygon::new(r, c.mix(0.22).filled()));
            chart.draw_series(fill)?;
            chart.draw_series(runs.map(|r| PathElement::new(r, c.stroke_width(1))))?
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
        SeriesKind::Invalid => Cross::new((x + 9, y), 5, c.stroke_width(2)).into_dyn(),
        SeriesKind::Cross => Cross::new((x + 9, y), 4, c.stroke_width(2)).into_dyn(),
        SeriesKind::Area | SeriesKind::Outline => {
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
}
