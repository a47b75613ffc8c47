//! A small layer over plotters' SVG backend: a [`Panel`] is a 2-D chart
//! described as data (series, reference lines, shaded bands, filled areas)
//! and drawn into one cell of a figure. Text is written as SVG `<text>`
//! elements; no font files are read.

use plotters::coord::Shift;
use plotters::prelude::*;

/// The drawing area of one figure cell.
pub type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// Colours for up to six series (colour-blind-safe order).
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
];

/// A grey for reference lines.
pub const GREY: RGBColor = RGBColor(110, 110, 110);

/// How a series is drawn.
#[derive(Clone, Copy, PartialEq)]
pub enum Style {
    /// A solid line.
    Line,
    /// A dashed line (dash length in pixels).
    Dashed(u32),
    /// A solid line with a filled dot at every point.
    LineDots,
    /// Filled dots only.
    Dots,
    /// Small filled dots only (dense scatter).
    SmallDots,
    /// Hollow circles only.
    Rings,
    /// Crosses only.
    Crosses,
}

/// One data series.
pub struct Series {
    pub label: Option<String>,
    pub color: RGBColor,
    pub style: Style,
    pub points: Vec<(f64, f64)>,
}

impl Series {
    pub fn new(color: RGBColor, style: Style, points: Vec<(f64, f64)>) -> Series {
        Series {
            label: None,
            color,
            style,
            points: points
                .into_iter()
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .collect(),
        }
    }

    pub fn label(mut self, l: impl Into<String>) -> Series {
        self.label = Some(l.into());
        self
    }
}

/// An area between a curve and y = 0.
pub struct FilledArea {
    pub points: Vec<(f64, f64)>,
    pub color: RGBColor,
    pub label: Option<String>,
}

/// One chart.
pub struct Panel {
    pub title: String,
    pub x_desc: String,
    pub y_desc: String,
    pub series: Vec<Series>,
    /// Horizontal reference lines: (y, label).
    pub hlines: Vec<(f64, String)>,
    /// Vertical reference lines: (x, label).
    pub vlines: Vec<(f64, String)>,
    /// Shaded x ranges spanning the whole height: (from, to, colour).
    pub bands: Vec<(f64, f64, RGBColor)>,
    /// Legend entry of the bands.
    pub band_label: Option<String>,
    /// Areas filled down to y = 0.
    pub areas: Vec<FilledArea>,
    /// Fixed ranges (else fitted to the data with a margin).
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
    /// Include y = 0 (x = 0) in a fitted range.
    pub y_zero: bool,
    pub x_zero: bool,
    /// Same scale on both axes (shapes).
    pub equal_aspect: bool,
    /// Lines of text written in the top-left corner of the plot.
    pub notes: Vec<String>,
    pub legend: SeriesLabelPosition,
}

impl Panel {
    pub fn new(title: impl Into<String>, x_desc: &str, y_desc: &str) -> Panel {
        Panel {
            title: title.into(),
            x_desc: x_desc.into(),
            y_desc: y_desc.into(),
            series: Vec::new(),
            hlines: Vec::new(),
            vlines: Vec::new(),
            bands: Vec::new(),
            band_label: None,
            areas: Vec::new(),
            x_range: None,
            y_range: None,
            y_zero: false,
            x_zero: false,
            equal_aspect: false,
            notes: Vec::new(),
            legend: SeriesLabelPosition::UpperRight,
        }
    }

    fn fitted_ranges(&self, plot_px: (f64, f64)) -> ((f64, f64), (f64, f64)) {
        let mut xs: Vec<f64> = Vec::new();
        let mut ys: Vec<f64> = Vec::new();
        for s in &self.series {
            xs.extend(s.points.iter().map(|p| p.0));
            ys.extend(s.points.iter().map(|p| p.1));
        }
        for a in &self.areas {
            xs.extend(a.points.iter().map(|p| p.0));
            ys.extend(a.points.iter().map(|p| p.1));
            ys.push(0.0);
        }
        xs.extend(self.vlines.iter().map(|v| v.0));
        ys.extend(self.hlines.iter().map(|h| h.0));
        for b in &self.bands {
            xs.extend([b.0, b.1]);
        }
        if self.x_zero {
            xs.push(0.0);
        }
        if self.y_zero {
            ys.push(0.0);
        }
        let mut x = self.x_range.unwrap_or_else(|| padded(&xs));
        let mut y = self.y_range.unwrap_or_else(|| padded(&ys));
        if self.equal_aspect {
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

    /// Draws the panel into `area`.
    pub fn draw(&self, area: &Area) -> anyhow::Result<()> {
        const X_LABELS: u32 = 42;
        const Y_LABELS: u32 = 62;
        const CAPTION: u32 = 26;
        const MARGIN: u32 = 12;
        let (w, h) = area.dim_in_pixel();
        let plot_px = (
            f64::from(w.saturating_sub(Y_LABELS + 2 * MARGIN).max(10)),
            f64::from(h.saturating_sub(X_LABELS + CAPTION + 2 * MARGIN).max(10)),
        );
        let ((x0, x1), (y0, y1)) = self.fitted_ranges(plot_px);
        let mut builder = ChartBuilder::on(area);
        if !self.title.is_empty() {
            builder.caption(&self.title, ("sans-serif", 17));
        }
        let mut chart = builder
            .margin(MARGIN)
            .x_label_area_size(X_LABELS)
            .y_label_area_size(Y_LABELS)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        chart
            .configure_mesh()
            .x_desc(self.x_desc.as_str())
            .y_desc(self.y_desc.as_str())
            .label_style(("sans-serif", 13))
            .axis_desc_style(("sans-serif", 14))
            .light_line_style(RGBColor(238, 238, 238))
            .bold_line_style(RGBColor(215, 215, 215))
            .x_labels(7)
            .y_labels(7)
            .draw()?;
        let mut labelled = false;
        for (k, &(a, b, color)) in self.bands.iter().enumerate() {
            let (a, b) = (a.max(x0), b.min(x1));
            if b > a {
                let anno = chart.draw_series(std::iter::once(Rectangle::new(
                    [(a, y0), (b, y1)],
                    color.mix(0.18).filled(),
                )))?;
                if let (0, Some(l)) = (k, &self.band_label) {
                    labelled = true;
                    anno.label(l.as_str()).legend(move |(x, y)| {
                        Rectangle::new([(x, y - 5), (x + 18, y + 5)], color.mix(0.3).filled())
                    });
                }
            }
        }
        for FilledArea {
            points,
            color,
            label,
        } in &self.areas
        {
            let color = *color;
            let pts: Vec<(f64, f64)> = points
                .iter()
                .copied()
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .collect();
            let anno = chart.draw_series(
                AreaSeries::new(pts, 0.0, color.mix(0.25)).border_style(color.stroke_width(2)),
            )?;
            if let Some(l) = label {
                labelled = true;
                anno.label(l.as_str()).legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 18, y + 5)], color.mix(0.4).filled())
                });
            }
        }
        for &(y, ref label) in &self.hlines {
            let anno = chart.draw_series(DashedLineSeries::new(
                [(x0, y), (x1, y)],
                6,
                4,
                GREY.stroke_width(1),
            ))?;
            if !label.is_empty() {
                labelled = true;
                anno.label(label.as_str())
                    .legend(|(x, y)| legend_mark(x, y, GREY, Style::Dashed(4)));
            }
        }
        for &(x, ref label) in &self.vlines {
            let anno = chart.draw_series(DashedLineSeries::new(
                [(x, y0), (x, y1)],
                3,
                3,
                GREY.stroke_width(1),
            ))?;
            if !label.is_empty() {
                labelled = true;
                anno.label(label.as_str()).legend(|(x, y)| {
                    PathElement::new(vec![(x + 9, y - 6), (x + 9, y + 6)], GREY.stroke_width(1))
                });
            }
        }
        for s in &self.series {
            let c = s.color;
            let pts = s.points.clone();
            let anno = match s.style {
                Style::Line => chart.draw_series(LineSeries::new(pts, c.stroke_width(2)))?,
                Style::Dashed(d) => chart.draw_series(DashedLineSeries::new(
                    pts,
                    d,
                    d.div_ceil(2) + 2,
                    c.stroke_width(2),
                ))?,
                Style::LineDots => {
                    chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))?;
                    chart.draw_series(LineSeries::new(pts, c.stroke_width(2)))?
                }
                Style::Dots => {
                    chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))?
                }
                Style::SmallDots => chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 2, c.mix(0.55).filled())))?,
                Style::Rings => {
                    chart.draw_series(pts.iter().map(|&p| Circle::new(p, 4, c.stroke_width(1))))?
                }
                Style::Crosses => {
                    chart.draw_series(pts.iter().map(|&p| Cross::new(p, 4, c.stroke_width(2))))?
                }
            };
            if let Some(l) = &s.label {
                labelled = true;
                let style = s.style;
                anno.label(l.as_str())
                    .legend(move |(x, y)| legend_mark(x, y, c, style));
            }
        }
        if !self.notes.is_empty() {
            let style = ("sans-serif", 13).into_font().color(&BLACK);
            chart.draw_series(self.notes.iter().enumerate().map(|(i, n)| {
                EmptyElement::at((x0, y1))
                    + Text::new(n.clone(), (8, 8 + 17 * i as i32), style.clone())
            }))?;
        }
        if labelled {
            chart
                .configure_series_labels()
                .position(self.legend.clone())
                .label_font(("sans-serif", 12))
                .background_style(WHITE.mix(0.85))
                .border_style(RGBColor(190, 190, 190))
                .draw()?;
        }
        Ok(())
    }
}

fn legend_mark<DB: DrawingBackend>(
    x: i32,
    y: i32,
    c: RGBColor,
    style: Style,
) -> DynElement<'static, DB, (i32, i32)> {
    match style {
        Style::Line | Style::LineDots => {
            PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)).into_dyn()
        }
        Style::Dashed(d) => {
            // long or short dashes, like the plotted line
            let d = d.clamp(2, 8);
            plotters::element::DashedPathElement::new(
                vec![(x, y), (x + 18, y)],
                d,
                d.div_ceil(2) + 1,
                c.stroke_width(2),
            )
            .into_dyn()
        }
        Style::Dots | Style::SmallDots => Circle::new((x + 9, y), 3, c.filled()).into_dyn(),
        Style::Rings => Circle::new((x + 9, y), 4, c.stroke_width(1)).into_dyn(),
        Style::Crosses => Cross::new((x + 9, y), 4, c.stroke_width(2)).into_dyn(),
    }
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

/// Renders a figure of `size` pixels titled `title`: `draw` receives the
/// area under the title.
pub fn figure(
    size: (u32, u32),
    title: &str,
    draw: impl FnOnce(&Area) -> anyhow::Result<()>,
) -> anyhow::Result<String> {
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, size).into_drawing_area();
        root.fill(&WHITE)?;
        let body = root.titled(title, ("sans-serif", 21))?;
        draw(&body)?;
        root.present()?;
    }
    Ok(buf)
}

/// A figure that only states why there is nothing to plot.
pub fn placeholder(title: &str, message: &str) -> String {
    use super::files::escape;
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
