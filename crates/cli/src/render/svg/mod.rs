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

mod clip;
mod fine;
mod legend;
mod log_axes;
#[cfg(test)]
mod tests;
mod ticks;

use clip::*;
use fine::SUB;
use legend::*;
use log_axes::*;
use ticks::*;

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

/// The printed width a figure may be given, in inches: from a column's
/// sliver to a poster's; the SVG writes it to 3 decimals.
pub const WIDTH_IN_RANGE: (f64, f64) = (0.5, 1000.0);

/// The printed tick-label size, in points: from the smallest that prints
/// legibly to labels an inch and a half high; a smaller size wrote
/// font-size 0.
pub const FONT_PT_RANGE: (f64, f64) = (1.0, 100.0);

impl Style {
    /// Checks the options (finite, within [`WIDTH_IN_RANGE`] and
    /// [`FONT_PT_RANGE`]): rejected input otherwise.
    pub fn validate(&self) -> anyhow::Result<()> {
        for (name, v, (lo, hi)) in [
            ("--width-in", self.width_in, WIDTH_IN_RANGE),
            ("--font-pt", self.font_pt, FONT_PT_RANGE),
        ] {
            if let Some(v) = v {
                if !(v.is_finite() && (lo..=hi).contains(&v)) {
                    // (the library's error writes 1e-300 with an exponent)
                    return Err(fpc::InputError::OutOfRange {
                        field: fpc::Field::key(name),
                        value: v,
                        rule: format!("must lie in [{lo}, {hi}]"),
                    }
                    .into());
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
    // each panel's data, drawn finer than the layout (fine.rs)
    let mut layers = Vec::new();
    {
        let root =
            SVGBackend::with_string(&mut buf, (fig.size[0], fig.size[1])).into_drawing_area();
        root.fill(&WHITE)?;
        let body = root.titled(&fig.title, ("sans-serif", 21.0 * k))?;
        let rows = body.split_evenly((fig.rows.len(), 1));
        for (row, area) in fig.rows.iter().zip(&rows) {
            let cells = area.split_evenly((1, row.len()));
            for (p, cell) in row.iter().zip(&cells) {
                draw(p, cell, k, &mut layers)?;
            }
        }
        root.present()?;
    }
    buf = fine::put_layers(&buf, &layers)?;
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

/// The finite points of a series, each coordinate within
/// [`AXIS_LIMIT`] (a point beyond it is drawn at the axis' edge: plotters
/// maps points to integer pixels, which overflow far past the axis).
fn finite(points: &[[f64; 2]]) -> Vec<(f64, f64)> {
    let edge = |v: f64| v.clamp(-AXIS_LIMIT, AXIS_LIMIT);
    points
        .iter()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .map(|p| (edge(p[0]), edge(p[1])))
        .collect()
}

/// The largest magnitude an axis reaches: data beyond it are drawn at the
/// edge. Its span (twice it) and the padding stay finite, which the tick
/// placement needs (an infinite span never ended).
const AXIS_LIMIT: f64 = 1e300;

/// A data range with 5 % margins (a unit range around a single value,
/// `0..1` without data), within [`AXIS_LIMIT`].
fn padded(v: &[f64]) -> (f64, f64) {
    let (lo, hi) = v
        .iter()
        .filter(|x| x.is_finite())
        .map(|x| x.clamp(-AXIS_LIMIT, AXIS_LIMIT))
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
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
        SeriesKind::Area | SeriesKind::Outline | SeriesKind::Spread => 0,
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

/// Draws one panel into `area`; its data goes to a layer of its own,
/// pushed onto `layers` ([`fine`]).
fn draw(p: &Panel, area: &Area, k: f64, layers: &mut Vec<String>) -> anyhow::Result<()> {
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
    // the data, SUB times finer than the layout, over the same plotting
    // area; the legend entries stay on the layout's chart
    let (px, py) = chart.plotting_area().get_pixel_range();
    let whole = |v: i32| u32::try_from(v).unwrap_or(0);
    let mut layer = String::new();
    {
        let fine_root =
            SVGBackend::with_string(&mut layer, (SUB * whole(px.end), SUB * whole(py.end)))
                .into_drawing_area();
        let mut fine = ChartBuilder::on(&fine_root)
            .margin_left(SUB * whole(px.start))
            .margin_top(SUB * whole(py.start))
            .margin_right(SUB - 1)
            .margin_bottom(SUB - 1)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        draw_data(&mut fine, &mut chart, p, &shown, top, (x0, x1, y0, y1))?;
        fine_root.present()?;
    }
    layers.push(fine::layer_body(&layer)?);
    body.draw(&Text::new(
        fine::marker(layers.len() - 1),
        (0, 0),
        ("sans-serif", 1.0).into_font(),
    ))?;
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

/// A legend entry on the layout's chart for data drawn elsewhere: an
/// empty series to label.
fn entry<'a, 'b, 'c>(
    chart: &'c mut Chart<'a, 'b>,
) -> anyhow::Result<&'c mut plotters::chart::SeriesAnno<'a, SVGBackend<'b>>> {
    Ok(chart.draw_series(std::iter::empty::<EmptyElement<(f64, f64), SVGBackend<'b>>>())?)
}

/// Draws a panel's data (bands, reference lines, series, clip markers)
/// into `fine`, a chart [`SUB`] times finer than the layout's `chart`,
/// and their legend entries into `chart`.
fn draw_data<'a, 'b: 'a>(
    fine: &mut Chart,
    chart: &mut Chart<'a, 'b>,
    p: &Panel,
    shown: &[Shown],
    top: Option<f64>,
    (x0, x1, y0, y1): (f64, f64, f64, f64),
) -> anyhow::Result<()> {
    let sub = SUB as i32;
    let mut legend: Vec<&str> = Vec::new();
    for (i, b) in p.bands.iter().enumerate() {
        let color = color_of(&b.color);
        let (a, z) = (b.from.max(x0), b.to.min(x1));
        if z > a {
            fine.draw_series(std::iter::once(Rectangle::new(
                [(a, y0), (z, y1)],
                color.mix(0.18).filled(),
            )))?;
            if let (0, Some(l)) = (i, &p.band_label) {
                entry(chart)?.label(l.as_str()).legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 18, y + 5)], color.mix(0.3).filled())
                });
            }
        }
    }
    let thin = GREY.stroke_width(SUB);
    for line in p.hlines.iter().filter(|l| top.is_none_or(|t| l.at <= t)) {
        fine.draw_series(DashedLineSeries::new(
            [(x0, line.at), (x1, line.at)],
            6 * SUB,
            4 * SUB,
            thin,
        ))?;
        if !line.label.is_empty() {
            entry(chart)?
                .label(line.label.as_str())
                .legend(|(x, y)| legend_mark(x, y, GREY, SeriesKind::Dashed));
        }
    }
    for line in &p.vlines {
        fine.draw_series(DashedLineSeries::new(
            [(line.at, y0), (line.at, y1)],
            3 * SUB,
            3 * SUB,
            thin,
        ))?;
        if !line.label.is_empty() {
            entry(chart)?.label(line.label.as_str()).legend(|(x, y)| {
                PathElement::new(vec![(x + 9, y - 6), (x + 9, y + 6)], GREY.stroke_width(1))
            });
        }
    }
    let order: Vec<(&Series, &Shown)> = drawing_order(p)
        .into_iter()
        .map(|i| (&p.series[i], &shown[i]))
        .collect();
    for &(s, sh) in &order {
        draw_series(fine, s, sh)?;
        // one legend entry per label (the bent-backwards markers of
        // several curves share one)
        if let Some(l) = s.label.as_deref().filter(|l| !legend.contains(l)) {
            legend.push(l);
            let (c, kind) = (color_of(&s.color), s.kind);
            entry(chart)?
                .label(l)
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
                    c.stroke_width(2 * SUB)
                }
                _ => c.filled(),
            };
            fine.draw_series(
                sh.off
                    .iter()
                    .map(|&x| TriangleMarker::new((x, t), 6 * sub, style)),
            )?;
        }
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

type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

fn draw_series<'a, 'b, 'c>(
    chart: &'c mut Chart<'a, 'b>,
    s: &Series,
    shown: &Shown,
) -> anyhow::Result<&'c mut plotters::chart::SeriesAnno<'a, SVGBackend<'b>>> {
    let c = color_of(&s.color);
    // pens and markers in the fine layer's units
    let (w1, w2, r) = (SUB, 2 * SUB, |px: u32| px * SUB);
    let runs = shown.runs.iter().filter(|r| !r.is_empty()).cloned();
    let marks = shown.marks.iter().copied();
    Ok(match s.kind {
        SeriesKind::Line => {
            chart.draw_series(runs.map(|r| PathElement::new(r, c.stroke_width(w2))))?
        }
        SeriesKind::Dashed => chart.draw_series(runs.map(|r| {
            plotters::element::DashedPathElement::new(r, 5 * SUB, 5 * SUB, c.stroke_width(w2))
        }))?,
        SeriesKind::LinePoints => {
            chart.draw_series(marks.map(|p| Circle::new(p, r(3), c.filled())))?;
            chart.draw_series(runs.map(|r| PathElement::new(r, c.stroke_width(w2))))?
        }
        SeriesKind::Points => chart.draw_series(marks.map(|p| Circle::new(p, r(3), c.filled())))?,
        SeriesKind::Scatter => {
            chart.draw_series(marks.map(|p| Circle::new(p, r(2), c.mix(0.55).filled())))?
        }
        SeriesKind::Hollow => {
            chart.draw_series(marks.map(|p| Circle::new(p, r(4), c.stroke_width(w1))))?
        }
        SeriesKind::Cross => {
            chart.draw_series(marks.map(|p| Cross::new(p, r(4), c.stroke_width(w2))))?
        }
        SeriesKind::Area => chart.draw_series(
            AreaSeries::new(runs.flatten().collect::<Vec<_>>(), 0.0, c.mix(0.25))
                .border_style(c.stroke_width(w2)),
        )?,
        SeriesKind::BentBackwards => {
            chart.draw_series(marks.map(|p| Circle::new(p, r(6), c.stroke_width(w2))))?
        }
        SeriesKind::Invalid => {
            chart.draw_series(marks.map(|p| Cross::new(p, r(5), c.stroke_width(w2))))?
        }
        SeriesKind::Spread => {
            chart.draw_series(runs.map(|r| Polygon::new(r, c.mix(0.18).filled())))?
        }
        SeriesKind::Outline => {
            let fill = runs.clone().map(|r| Polygon::new(r, c.mix(0.22).filled()));
            chart.draw_series(fill)?;
            chart.draw_series(runs.map(|r| PathElement::new(r, c.stroke_width(w1))))?
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
        SeriesKind::Area | SeriesKind::Outline | SeriesKind::Spread => {
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
