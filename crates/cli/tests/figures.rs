//! `--format svg,png,pdf`: every figure the CLI writes (the paper's
//! studies, `fpc design`'s, `fpc solve`'s shape of a finger and of a
//! gripper) as a PNG that is not blank and has its text drawn, and as a
//! one-page PDF that embeds the bundled font; a bad format is rejected
//! before any work.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use fpc_cli::render::formats;
use resvg::tiny_skia::Pixmap;
use tempfile::TempDir;

fn fpc() -> Command {
    Command::new(env!("CARGO_BIN_EXE_fpc"))
}

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

fn tmp(name: &str) -> TempDir {
    common::tmp("figures", name)
}

fn run_ok(cmd: &mut Command) -> Output {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "status {:?}\nstderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// What the checks of one figure measured.
struct Measured {
    size: (u32, u32),
    /// Fraction of pixels that are not white.
    inked: f64,
    /// Fraction of the title band's pixels that are dark (text).
    title_ink: f64,
}

/// Checks `dir/stem.png` and `dir/stem.pdf` against `dir/stem.svg`.
fn check_figure(dir: &Path, stem: &str) -> Measured {
    let svg = std::fs::read_to_string(dir.join(format!("{stem}.svg"))).unwrap();
    // every text element is laid out with the bundled font
    let tree = formats::parse(&svg).unwrap();
    let texts = svg.matches("<text").count();
    assert!(texts > 3, "{stem}: {texts} texts");
    assert_eq!(laid_out(tree.root()), texts, "{stem}: texts without glyphs");

    let png = std::fs::read(dir.join(format!("{stem}.png"))).unwrap();
    let p = Pixmap::decode_png(&png).unwrap_or_else(|e| panic!("{stem}.png: {e}"));
    // twice the SVG's size
    let (w, h) = (tree.size().width(), tree.size().height());
    assert_eq!(
        (p.width(), p.height()),
        ((2.0 * w).ceil() as u32, (2.0 * h).ceil() as u32),
        "{stem}.png"
    );
    let rgb = |x: u32, y: u32| {
        let c = p.pixel(x, y).unwrap();
        (c.red(), c.green(), c.blue())
    };
    let all = f64::from(p.width()) * f64::from(p.height());
    let inked = (0..p.height())
        .flat_map(|y| (0..p.width()).map(move |x| (x, y)))
        .filter(|&(x, y)| rgb(x, y) != (255, 255, 255))
        .count() as f64
        / all;
    assert!(inked > 0.02 && inked < 0.6, "{stem}.png: inked {inked}");
    // the figure's title is the only thing in its top band: text drawn
    let band = 2 * 30;
    let title_ink = (0..band)
        .flat_map(|y| (0..p.width()).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let (r, g, b) = rgb(x, y);
            r.max(g).max(b) < 100
        })
        .count() as f64
        / (f64::from(band) * f64::from(p.width()));
    assert!(title_ink > 0.003, "{stem}.png: title band {title_ink}");

    let pdf = std::fs::read(dir.join(format!("{stem}.pdf"))).unwrap();
    assert!(pdf.starts_with(b"%PDF-"), "{stem}.pdf");
    let text = String::from_utf8_lossy(&pdf);
    assert!(text.contains("/Count 1"), "{stem}.pdf: not one page");
    assert!(text.contains("/FontFile2"), "{stem}.pdf: no embedded font");
    assert!(
        text.contains("DejaVuSans"),
        "{stem}.pdf: not the bundled font"
    );
    assert!(text.trim_end().ends_with("%%EOF"), "{stem}.pdf: truncated");
    Measured {
        size: (p.width(), p.height()),
        inked,
        title_ink,
    }
}

/// The text nodes of a tree with glyphs laid out.
fn laid_out(g: &resvg::usvg::Group) -> usize {
    g.children()
        .iter()
        .map(|n| match n {
            resvg::usvg::Node::Group(g) => laid_out(g),
            resvg::usvg::Node::Text(t) => usize::from(!t.flattened().children().is_empty()),
            _ => 0,
        })
        .sum()
}

#[test]
fn every_figure_renders_to_a_png_that_is_not_blank_and_a_pdf() {
    let scratch = tmp("all");
    let base = scratch.path();
    let mut measured = Vec::new();

    // the paper's eight studies (coarse): png and pdf asked for, the svg
    // written all the same for index.html
    let paper = base.join("paper");
    run_ok(
        fpc()
            .args(["paper", "--coarse", "--format", "png,pdf", "--out"])
            .arg(&paper),
    );
    let html = std::fs::read_to_string(paper.join("index.html")).unwrap();
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(paper.join("summary.json")).unwrap())
            .unwrap();
    for n in 1..=8 {
        let stem = format!("study{n}");
        assert!(html.contains(&format!("<img src=\"{stem}.svg\"")), "{stem}");
        assert_eq!(
            summary["studies"][n - 1]["figures"],
            serde_json::json!([
                format!("{stem}.svg"),
                format!("{stem}.png"),
                format!("{stem}.pdf")
            ])
        );
        measured.push((stem.clone(), check_figure(&paper, &stem)));
    }

    // fpc design on one small object
    let req = base.join("req.toml");
    std::fs::write(
        &req,
        "[[object]]\nkind = \"cuboid\"\nsize_mm = [80.0, 100.0]\nlift_n = 0.3\n[vary]\nmounting_angle_deg = [60.0, 80.0]\n",
    )
    .unwrap();
    let design = base.join("design");
    let o = run_ok(
        fpc()
            .arg("design")
            .arg(&req)
            .args(["--starts", "0", "--format", "svg,png,pdf", "--out"])
            .arg(&design),
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("design.svg, design.png, design.pdf"),
        "{stdout}"
    );
    measured.push(("design".into(), check_figure(&design, "design")));

    // fpc solve: a finger alone and a gripper's grasp
    for scene in ["tip_load", "sphere_grasp"] {
        let out = base.join(scene);
        let o = run_ok(
            fpc()
                .arg("solve")
                .arg(repo(&format!("scenes/{scene}.toml")))
                .args(["--format", "pdf,svg,png", "--out"])
                .arg(&out),
        );
        let stdout = String::from_utf8_lossy(&o.stdout);
        assert!(stdout.contains("shape.png"), "{stdout}");
        measured.push((scene.into(), check_figure(&out, "shape")));
    }
    for (name, m) in &measured {
        eprintln!(
            "{name}: {} x {} px, {:.3} inked, {:.4} of the title band",
            m.size.0, m.size.1, m.inked, m.title_ink
        );
    }
}

#[test]
fn png_alone_writes_no_svg_outside_the_paper() {
    let scratch = tmp("png-only");
    // not there yet: the run makes it
    let out = scratch.path().join("out");
    run_ok(
        fpc()
            .arg("solve")
            .arg(repo("scenes/tip_load.toml"))
            .args(["--format", "png", "--out"])
            .arg(&out),
    );
    assert!(out.join("shape.png").is_file());
    assert!(!out.join("shape.svg").exists());
    assert!(!out.join("shape.pdf").exists());
    // again into the same directory as SVG: the PNG of the run before is
    // not left beside it (a figure there is always this run's)
    run_ok(
        fpc()
            .arg("solve")
            .arg(repo("scenes/tip_load.toml"))
            .arg("--out")
            .arg(&out),
    );
    assert!(out.join("shape.svg").is_file());
    assert!(!out.join("shape.png").exists());
}

#[test]
fn an_unknown_format_is_rejected_before_any_work() {
    for (cmd, extra) in [
        ("solve", Some(repo("scenes/tip_load.toml"))),
        ("design", Some(repo("scenes/design/paper_sec5.toml"))),
        ("paper", None),
    ] {
        let scratch = tmp(&format!("bad-{cmd}"));
        let out = scratch.path().join("out");
        let mut c = fpc();
        c.arg(cmd);
        if let Some(file) = extra {
            c.arg(file);
        }
        let o = c
            .args(["--format", "svg,jpeg", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{cmd}: {err}");
        assert!(
            err.contains("--format") && err.contains("'jpeg'"),
            "{cmd}: {err}"
        );
        assert!(err.contains("svg, png, pdf"), "{cmd}: {err}");
        assert!(!out.exists(), "{cmd}: the output directory was made");
    }
}
