//! A figure in the formats asked for with `--format svg,png,pdf`: the one
//! SVG text the renderer draws, written as is, rasterised to PNG (resvg)
//! or converted to PDF (svg2pdf), in process.
//!
//! Text is laid out with the font bundled in the crate (DejaVu Sans,
//! `assets/fonts/`), never with system fonts: the font database holds
//! that one face, and every generic family the figures name
//! (`sans-serif` from plotters, and the others for safety) maps to it. A
//! fresh clone renders the same PNG and PDF on any machine.

use std::fmt;
use std::path::Path;
use std::sync::{Arc, OnceLock};

use resvg::tiny_skia;
use resvg::usvg;

/// The bundled font, embedded in the binary.
const FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
/// Its family name, as its name table gives it.
pub const FONT_FAMILY: &str = "DejaVu Sans";

/// PNG pixels per SVG pixel (CSS pixel, 1/96 in): 2, so a figure of
/// 1200 x 520 px becomes a PNG of 2400 x 1040, and one sized in inches
/// is rasterised at 192 pixels per inch.
pub const PNG_SCALE: f32 = 2.0;

/// The largest PNG side in pixels: a figure sized larger (a huge
/// `--width-in`) is scaled down to fit, not allocated whole.
pub const PNG_MAX_SIDE: f32 = 16384.0;

/// One output format of a figure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, clap::ValueEnum)]
pub enum Format {
    /// The SVG as drawn.
    Svg,
    /// A raster image, 2 pixels per SVG pixel.
    Png,
    /// A one-page vector PDF, the bundled font embedded.
    Pdf,
}

impl Format {
    /// The file extension (without the dot).
    pub fn extension(self) -> &'static str {
        match self {
            Format::Svg => "svg",
            Format::Png => "png",
            Format::Pdf => "pdf",
        }
    }
}

/// Removes the files `stem.<ext>` of `dir` in every format but `keep`'s
/// (none there is no error): an earlier run's figure that this run does
/// not draw, or draws in other formats.
pub fn remove_figure(dir: &Path, stem: &str, keep: &[Format]) -> anyhow::Result<()> {
    for f in [Format::Svg, Format::Png, Format::Pdf] {
        if keep.contains(&f) {
            continue;
        }
        let path = dir.join(format!("{stem}.{}", f.extension()));
        match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                anyhow::bail!("cannot remove the stale figure {}: {e}", path.display())
            }
            _ => {}
        }
    }
    Ok(())
}

/// The `--format` flag, flattened into every command that writes figures.
#[derive(clap::Args, Debug, Clone)]
pub struct FormatArgs {
    /// Figure formats, a comma-separated list of svg, png and pdf (e.g.
    /// `--format svg,png`). All are rendered in process from the same SVG
    /// with the bundled DejaVu Sans font (no system fonts are used). PNG
    /// has 2 pixels per SVG pixel (192 dpi for figures sized in inches);
    /// PDF is vector, one page the size of the figure, the font embedded.
    #[arg(
        long = "format",
        value_name = "FORMATS",
        value_delimiter = ',',
        default_value = "svg",
        num_args = 1
    )]
    pub formats: Vec<Format>,
}

impl Default for FormatArgs {
    fn default() -> Self {
        FormatArgs {
            formats: vec![Format::Svg],
        }
    }
}

impl FormatArgs {
    /// The formats asked for, each once, in the order svg, png, pdf.
    pub fn list(&self) -> Vec<Format> {
        let mut v = self.formats.clone();
        v.sort_unstable();
        v.dedup();
        if v.is_empty() {
            v.push(Format::Svg);
        }
        v
    }

    /// The same formats with svg added: for a command whose other output
    /// (an HTML page) links the SVG.
    pub fn with_svg(&self) -> FormatArgs {
        let mut formats = self.list();
        formats.push(Format::Svg);
        FormatArgs { formats }
    }

    /// The file names `stem` is written as.
    pub fn names(&self, stem: &str) -> Vec<String> {
        self.list()
            .into_iter()
            .map(|f| format!("{stem}.{}", f.extension()))
            .collect()
    }

    /// Renders `svg` in every format asked for and writes each file as
    /// `stem.<ext>` in `dir` (atomically, [`crate::output::write_atomic`]).
    /// Every file is rendered before any is written; then the formats not
    /// asked for are removed ([`remove_figure`]), so that no figure of an
    /// earlier run stands beside this one's. Returns the names written.
    pub fn write(&self, dir: &Path, stem: &str, svg: &str) -> anyhow::Result<Vec<String>> {
        let files = self.render(stem, svg)?;
        for (name, bytes) in &files {
            crate::output::write_atomic(dir, name, bytes)?;
        }
        remove_figure(dir, stem, &self.list())?;
        Ok(files.into_iter().map(|(n, _)| n).collect())
    }

    /// Every file of `stem` as (name, bytes), rendered from `svg`.
    pub fn render(&self, stem: &str, svg: &str) -> Result<Vec<(String, Vec<u8>)>, RenderError> {
        let mut tree = None;
        let mut files = Vec::new();
        for format in self.list() {
            let name = format!("{stem}.{}", format.extension());
            let bytes = match format {
                Format::Svg => svg.as_bytes().to_vec(),
                Format::Png | Format::Pdf => {
                    let t = match tree {
                        Some(ref t) => t,
                        None => {
                            tree.insert(parse(svg).map_err(|why| RenderError::new(&name, why))?)
                        }
                    };
                    let out = if format == Format::Png {
                        png(t)
                    } else {
                        pdf(t)
                    };
                    out.map_err(|why| RenderError::new(&name, why))?
                }
            };
            files.push((name, bytes));
        }
        Ok(files)
    }
}

/// A figure that could not be rendered: the file it was for, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RenderError {
    /// The file name (`study1.png`).
    pub file: String,
    /// What went wrong.
    pub why: String,
}

impl RenderError {
    fn new(file: &str, why: String) -> RenderError {
        RenderError {
            file: file.to_string(),
            why,
        }
    }
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "cannot render {}: {}", self.file, self.why)
    }
}

impl std::error::Error for RenderError {}

/// The font database: the bundled face alone, the generic families
/// mapped to it. Built once.
pub fn fonts() -> Arc<usvg::fontdb::Database> {
    static DB: OnceLock<Arc<usvg::fontdb::Database>> = OnceLock::new();
    DB.get_or_init(|| {
        let mut db = usvg::fontdb::Database::new();
        db.load_font_data(FONT.to_vec());
        db.set_sans_serif_family(FONT_FAMILY);
        db.set_serif_family(FONT_FAMILY);
        db.set_monospace_family(FONT_FAMILY);
        db.set_cursive_family(FONT_FAMILY);
        db.set_fantasy_family(FONT_FAMILY);
        Arc::new(db)
    })
    .clone()
}

/// The SVG parsed and its text laid out with the bundled font.
pub fn parse(svg: &str) -> Result<usvg::Tree, String> {
    let opt = usvg::Options {
        font_family: FONT_FAMILY.to_string(),
        fontdb: fonts(),
        ..usvg::Options::default()
    };
    usvg::Tree::from_str(svg, &opt).map_err(|e| format!("the SVG does not parse: {e}"))
}

/// The PNG of a parsed figure, at [`PNG_SCALE`] (less for a figure
/// larger than [`PNG_MAX_SIDE`]), on white.
pub fn png(tree: &usvg::Tree) -> Result<Vec<u8>, String> {
    let size = tree.size();
    let scale = PNG_SCALE.min(PNG_MAX_SIDE / size.width().max(size.height()));
    let (w, h) = (
        (size.width() * scale).ceil().max(1.0) as u32,
        (size.height() * scale).ceil().max(1.0) as u32,
    );
    let mut pixmap = tiny_skia::Pixmap::new(w, h)
        .ok_or_else(|| format!("cannot allocate a {w} x {h} pixel image"))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        tree,
        tiny_skia::Transform::from_scale(scale, scale),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| format!("cannot encode the PNG: {e}"))
}

/// The PDF of a parsed figure: one page of the figure's size (an SVG
/// pixel is 1/96 in), text as text in the embedded font.
pub fn pdf(tree: &usvg::Tree) -> Result<Vec<u8>, String> {
    svg2pdf::to_pdf(
        tree,
        svg2pdf::ConversionOptions::default(),
        svg2pdf::PageOptions { dpi: 96.0 },
    )
    .map_err(|e| format!("cannot convert to PDF: {e}"))
}

#[cfg(test)]
mod tests;
