//! Rendering a figure to SVG with plotters: layout, axes at an equal
//! aspect, ticks, legend and wrapped caption.

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::figure::{Item, Look, Plot, ORANGE};

/// Width of the SVG (px).
const WIDTH: u32 = 820;
/// Margin around the plot and the caption (px).
const MARGIN: u32 = 14;
/// Heights of the title strip and of one caption line (px).
const TITLE_H: u32 = 34;
const LINE_H: u32 = 19;
/// Room for the tick labels and the axis names (px).
const X_LABEL_AREA: u32 = 46;
const Y_LABEL_AREA: u32 = 66;
/// Bounds of the plotting area's height (px).
const PLOT_H: (f64, f64) = (220.0, 760.0);
/// Text size (plotters' units; the SVG's font-size is 1/1.24 of it) and
/// the average width of one character of it (px).
const TEXT: u32 = 16;
const CHAR_PX: f64 = 7.0;

type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// Renders a plot: title, the plot with axes at an equal aspect, the
/// legend and the caption.
pub(super) fn render(plot: &Plot) -> anyhow::Result<String> {
    let (lo, hi) = plot.extent();
    let plot_w = f64::from(WIDTH - Y_LABEL_AREA - 2 * MARGIN);
    let plot_h = (plot_w * (hi[1] - lo[1]) / (hi[0] - lo[0])).clamp(PLOT_H.0, PLOT_H.1);
    let chart_h = plot_h as u32 + X_LABEL_AREA + 2 * MARGIN;
    let text_w = WIDTH - 2 * MARGIN;
    let legend = legend(&plot.items, text_w);
    let rows = legend.last().map_or(0, |e| e.row + 1);
    let chars = (f64::from(text_w) / CHAR_PX) as usize;
    // continued lines are indented
    let caption: Vec<(bool, String)> = plot
        .caption
        .iter()
        .flat_map(|c| wrap(c, chars).into_iter().enumerate())
        .map(|(k, line)| (k > 0, line))
        .collect();
    let caption_h = LINE_H * (rows + caption.len() as u32 + 1);
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (WIDTH, TITLE_H + chart_h + caption_h))
            .into_drawing_area();
        root.fill(&WHITE)?;
        let (head, rest) = root.split_vertically(TITLE_H);
        let (body, foot) = rest.split_vertically(chart_h);
        let title = ("sans-serif", 19).into_font().color(&BLACK);
        head.draw(&Text::new(plot.title.as_str(), (MARGIN as i32, 12), title))?;
        draw_chart(plot, &body, lo, hi)?;
        draw_caption(&foot, &legend, &caption)?;
        root.present()?;
    }
    Ok(buf)
}

/// Builds the chart on `area` over the given ranges.
fn chart_on<'a, 'b>(
    area: &'a Area<'b>,
    x: (f64, f64),
    y: (f64, f64),
) -> anyhow::Result<Chart<'a, 'b>> {
    Ok(ChartBuilder::on(area)
        .margin(MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)?)
}

type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws the axes and the items: the ranges cover `lo..hi`, stretched to
/// one scale on both axes of the plotting area.
fn draw_chart(plot: &Plot, area: &Area, lo: [f64; 2], hi: [f64; 2]) -> anyhow::Result<()> {
    // building draws nothing: a first chart measures the plotting area
    let px = chart_on(area, (0.0, 1.0), (0.0, 1.0))?
        .plotting_area()
        .dim_in_pixel();
    let (x, y) = equal_aspect(lo, hi, px);
    let mut chart = chart_on(area, x, y)?;
    let flip = if plot.y_down { -1.0 } else { 1.0 };
    let x_tick = |v: &f64| tick(*v);
    let y_tick = |v: &f64| tick(flip * v);
    // one tick step on both axes, about every TICK_PX pixels
    let step = nice_step(TICK_PX * (x.1 - x.0) / f64::from(px.0.max(2) - 1));
    chart
        .configure_mesh()
        .x_desc(plot.x_desc)
        .y_desc(plot.y_desc)
        .x_label_formatter(&x_tick)
        .y_label_formatter(&y_tick)
        .x_labels(multiples(x, step))
        .y_labels(multiples(y, step))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(RGBColor(242, 242, 242))
        .bold_line_style(RGBColor(222, 222, 222))
        .draw()?;
    for item in &plot.items {
        draw_item(&mut chart, item)?;
    }
    Ok(())
}

/// The least distance between tick labels (px).
const TICK_PX: f64 = 80.0;

/// The smallest of 1, 2 or 5 times a power of ten that is at least `min`
/// (> 0).
pub(super) fn nice_step(min: f64) -> f64 {
    let p = 10f64.powf(min.log10().floor());
    [1.0, 2.0, 5.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= min * (1.0 - 1e-9))
        .unwrap_or(10.0 * p)
}

/// How many multiples of `step` lie in `range`: as plotters' largest
/// number of labels, it makes plotters choose `step` itself.
pub(super) fn multiples(range: (f64, f64), step: f64) -> usize {
    ((range.1 / step).floor() - (range.0 / step).ceil() + 1.0).max(1.0) as usize
}

/// A tick label: the value to 1e-6 mm, no `-0`.
pub(super) fn tick(v: f64) -> String {
    let r = (v * 1e6).round() / 1e6 + 0.0;
    format!("{r}")
}

/// The ranges over `lo..hi` that give both axes one scale (mm per pixel)
/// on a plotting area of `px` pixels: the short range grows about its
/// centre. Plotters maps a range onto `px - 1` pixels.
pub(super) fn equal_aspect(lo: [f64; 2], hi: [f64; 2], px: (u32, u32)) -> ((f64, f64), (f64, f64)) {
    let span = |n: u32| f64::from(n.max(2) - 1);
    let (w, h) = (span(px.0), span(px.1));
    let per_px = ((hi[0] - lo[0]) / w).max((hi[1] - lo[1]) / h);
    let around = |k: usize, pixels: f64| {
        let c = 0.5 * (lo[k] + hi[k]);
        (c - 0.5 * per_px * pixels, c + 0.5 * per_px * pixels)
    };
    (around(0, w), around(1, h))
}

fn draw_item(chart: &mut Chart, item: &Item) -> anyhow::Result<()> {
    let style = item.look.style();
    let pts = item.points.iter().copied();
    match item.look {
        Look::Root | Look::Tip => {
            chart.draw_series(pts.map(|p| Circle::new(p, 4, style)))?;
        }
        Look::Object => {
            chart.draw_series(std::iter::once(Polygon::new(
                item.points.clone(),
                ORANGE.mix(0.22).filled(),
            )))?;
            chart.draw_series(LineSeries::new(pts, style))?;
        }
        look => match look.dashes() {
            Some((dash, gap)) => {
                chart.draw_series(DashedLineSeries::new(pts, dash, gap, style))?;
            }
            None => {
                chart.draw_series(LineSeries::new(pts, style))?;
            }
        },
    }
    Ok(())
}

/// A legend entry placed in the caption: its row and its left edge (px).
struct Entry {
    look: Look,
    label: &'static str,
    row: u32,
    x: i32,
}

/// Width of an entry's mark and the gaps after it and after its label (px).
const MARK_W: i32 = 26;
const MARK_GAP: i32 = 7;
const ENTRY_GAP: i32 = 20;

/// The legend: one entry per label, in the order of [`Look`], filled into
/// rows `width` pixels wide.
fn legend(items: &[Item], width: u32) -> Vec<Entry> {
    let mut labelled: Vec<(Look, &'static str)> = Vec::new();
    for i in items.iter().filter(|i| !i.label.is_empty()) {
        if !labelled.iter().any(|(_, l)| *l == i.label) {
            labelled.push((i.look, i.label));
        }
    }
    labelled.sort_by_key(|(look, _)| *look);
    let mut entries = Vec::new();
    let (mut row, mut x) = (0, 0);
    for (look, label) in labelled {
        let w = MARK_W + MARK_GAP + (label.chars().count() as f64 * CHAR_PX) as i32;
        if x > 0 && x + w > width as i32 {
            row += 1;
            x = 0;
        }
        entries.push(Entry {
            look,
            label,
            row,
            x,
        });
        x += w + ENTRY_GAP;
    }
    entries
}

/// Draws the legend, then the caption lines, into `area`.
fn draw_caption(area: &Area, legend: &[Entry], lines: &[(bool, String)]) -> anyhow::Result<()> {
    let text = ("sans-serif", TEXT)
        .into_font()
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let left = MARGIN as i32;
    let line_y = |row: u32| (LINE_H * row + LINE_H / 2) as i32;
    for e in legend {
        let (x, y) = (left + e.x, line_y(e.row));
        draw_mark(area, e.look, x, y)?;
        area.draw(&Text::new(
            e.label,
            (x + MARK_W + MARK_GAP, y),
            text.clone(),
        ))?;
    }
    let first = legend.last().map_or(0, |e| e.row + 1);
    for (k, (continued, line)) in lines.iter().enumerate() {
        let x = if *continued { left + INDENT_PX } else { left };
        let y = line_y(first + k as u32);
        area.draw(&Text::new(line.as_str(), (x, y), text.clone()))?;
    }
    Ok(())
}

/// A legend entry's mark, `MARK_W` wide from `x`, centred on `y`.
fn draw_mark(area: &Area, look: Look, x: i32, y: i32) -> anyhow::Result<()> {
    let style = look.style();
    let line = vec![(x, y), (x + MARK_W, y)];
    match look {
        Look::Root | Look::Tip => area.draw(&Circle::new((x + MARK_W / 2, y), 4, style))?,
        Look::Object => {
            let corners = [(x, y - 6), (x + MARK_W, y + 6)];
            area.draw(&Rectangle::new(corners, ORANGE.mix(0.22).filled()))?;
            area.draw(&Rectangle::new(corners, style))?;
        }
        look => match look.dashes() {
            Some((dash, gap)) => area.draw(&plotters::element::DashedPathElement::new(
                line, dash, gap, style,
            ))?,
            None => area.draw(&PathElement::new(line, style))?,
        },
    }
    Ok(())
}

/// The indent of a continued caption line (px).
const INDENT_PX: i32 = 24;

/// `text` broken at spaces into lines of at most `width` characters, the
/// continued ones `INDENT_PX` narrower (a longer word keeps a line of its
/// own).
pub(super) fn wrap(text: &str, width: usize) -> Vec<String> {
    let narrower = (f64::from(INDENT_PX) / CHAR_PX).ceil() as usize;
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let room = if lines.is_empty() {
            width
        } else {
            width.saturating_sub(narrower)
        };
        let len = line.chars().count();
        if len > 0 && len + 1 + word.chars().count() > room {
            lines.push(std::mem::take(&mut line));
        } else if len > 0 {
            line.push(' ');
        }
        line.push_str(word);
    }
    lines.push(line);
    lines
}
