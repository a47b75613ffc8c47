//! Tests of the PNG and PDF writers: the bundled font is the only one and
//! is used, a figure renders to a picture that is not blank, and a PDF
//! embeds its font.

use super::*;
use crate::render::svg::svg;
use fpc::report::{Figure, Panel, PlotAxis, Series, SeriesKind};

fn figure() -> String {
    let mut p = Panel::new(
        "Lift against size",
        PlotAxis::new("size", "mm"),
        PlotAxis::new("lift", "N"),
    );
    p.series.push(
        Series::new(
            "eps0=0.4",
            SeriesKind::LinePoints,
            vec![[0.0, 0.0], [1.0, 2.0], [2.0, 1.5]],
        )
        .label("curve"),
    );
    svg(&Figure::row("A figure", [600, 400], vec![p])).unwrap()
}

/// The SVG with every `<text>` element removed.
fn without_text(svg: &str) -> String {
    let mut out = String::new();
    let mut rest = svg;
    while let Some(i) = rest.find("<text") {
        out.push_str(&rest[..i]);
        let end = rest[i..].find("</text>").expect("a closed text") + i;
        rest = &rest[end + "</text>".len()..];
    }
    out.push_str(rest);
    out
}

/// The decoded pixels (premultiplied RGBA) of a PNG.
fn pixels(png: &[u8]) -> tiny_skia::Pixmap {
    tiny_skia::Pixmap::decode_png(png).expect("a PNG")
}

/// The fraction of pixels that are not white.
fn inked(p: &tiny_skia::Pixmap) -> f64 {
    let ink = p
        .pixels()
        .iter()
        .filter(|c| (c.red(), c.green(), c.blue()) != (255, 255, 255))
        .count();
    ink as f64 / p.pixels().len() as f64
}

#[test]
fn the_bundled_font_is_the_only_one_and_every_generic_family_maps_to_it() {
    let db = fonts();
    assert_eq!(db.len(), 1);
    let face = db.faces().next().unwrap();
    assert_eq!(face.families[0].0, FONT_FAMILY);
    use usvg::fontdb::{Family, Query};
    for family in [Family::SansSerif, Family::Serif, Family::Monospace] {
        let q = Query {
            families: &[family],
            ..Query::default()
        };
        assert_eq!(db.query(&q), Some(face.id));
    }
}

#[test]
fn a_figure_renders_to_a_png_at_twice_its_size_with_its_text() {
    let svg = figure();
    let png = png(&parse(&svg).unwrap()).unwrap();
    let p = pixels(&png);
    assert_eq!((p.width(), p.height()), (1200, 800));
    let ink = inked(&p);
    assert!(ink > 0.02 && ink < 0.5, "inked fraction {ink}");
    // the text is drawn: without it, markedly fewer pixels are inked
    let bare = pixels(&super::png(&parse(&without_text(&svg)).unwrap()).unwrap());
    let differ = p
        .pixels()
        .iter()
        .zip(bare.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ > 5000, "only {differ} pixels are text");
    // and every text element became text the font could lay out
    let texts = svg.matches("<text").count();
    let laid_out = count_text(parse(&svg).unwrap().root());
    assert_eq!(laid_out, texts, "texts laid out of {texts}");
}

/// The text nodes of a tree that have glyphs laid out.
fn count_text(g: &usvg::Group) -> usize {
    g.children()
        .iter()
        .map(|n| match n {
            usvg::Node::Group(g) => count_text(g),
            usvg::Node::Text(t) => usize::from(!t.flattened().children().is_empty()),
            _ => 0,
        })
        .sum()
}

#[test]
fn a_figure_becomes_a_one_page_pdf_with_the_font_embedded() {
    let pdf = pdf(&parse(&figure()).unwrap()).unwrap();
    assert!(pdf.starts_with(b"%PDF-"));
    let text = String::from_utf8_lossy(&pdf);
    assert_eq!(
        text.matches("/Type /Page\n").count()
            + text.matches("/Type /Page ").count()
            + text.matches("/Type /Page/").count(),
        1,
        "one page"
    );
    assert!(text.contains("/FontFile2"), "no embedded TrueType font");
    assert!(
        text.contains("DejaVuSans"),
        "the font is not the bundled one"
    );
    // 600 x 400 px at 96 px per inch: 450 x 300 pt
    assert!(text.contains("/MediaBox [0 0 450 300]"), "media box");
}

#[test]
fn the_formats_are_written_once_each_in_a_fixed_order() {
    let f = FormatArgs {
        formats: vec![Format::Pdf, Format::Svg, Format::Pdf],
    };
    assert_eq!(f.names("x"), ["x.svg", "x.pdf"]);
    let files = f.render("x", &figure()).unwrap();
    assert_eq!(files.len(), 2);
    assert!(files[0].1.starts_with(b"<svg"));
    assert!(files[1].1.starts_with(b"%PDF-"));
    assert_eq!(
        FormatArgs {
            formats: vec![Format::Png]
        }
        .with_svg()
        .names("a"),
        ["a.svg", "a.png"]
    );
}

#[test]
fn a_figure_that_does_not_parse_is_an_error_naming_its_file() {
    let f = FormatArgs {
        formats: vec![Format::Png],
    };
    let e = f.render("study3", "<svg").unwrap_err();
    assert_eq!(e.file, "study3.png");
    assert!(
        e.to_string().starts_with("cannot render study3.png: "),
        "{e}"
    );
    // svg alone needs no parsing
    assert!(FormatArgs::default().render("s", "<svg").is_ok());
}
