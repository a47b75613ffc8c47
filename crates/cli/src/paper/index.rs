//! `index.html`: every study's figure, overview table, notes and links to
//! its CSV files, on one page of the HTML writer.

use super::Output;
use crate::render::html::{escape, link, Page};

/// The page for everything `out` recorded.
pub fn html(out: &Output) -> String {
    let mut h = Page::new("fpc: the paper's studies");
    h.heading(
        1,
        &format!(
            "Fluidic prestressed composite grippers: the paper's {} studies",
            out.sections.len()
        ),
    );
    let mode = |on: bool, text: &'static str| if on { text } else { "" };
    h.para_html(
        "small",
        &format!(
            "{}. Key numbers: {}.",
            escape(&format!(
                "fpc {}, {} actuator, model {}, N = {} elements, μ = {}{}{}",
                env!("CARGO_PKG_VERSION"),
                out.source,
                out.opts.model.name(),
                out.opts.elements,
                fpc::num::Num(out.opts.mu),
                mode(out.coarse, ", coarse sweeps (preview)"),
                mode(
                    out.opts.strict,
                    ", strict mode (grasps that bend an element backwards are dropped)"
                ),
            )),
            link("summary.json", "summary.json")
        ),
    );
    let failed = out.failed_studies();
    if !failed.is_empty() {
        let links: Vec<String> = failed
            .iter()
            .map(|n| link(&format!("#study{n}"), &format!("study {n}")))
            .collect();
        h.para_html(
            "failed",
            &format!(
                "{} of {} studies failed: {}.",
                failed.len(),
                out.sections.len(),
                links.join(", ")
            ),
        );
    }
    if !out.warnings.is_empty() {
        h.para("note", "Design warnings:")
            .list("note", &out.warnings);
    }
    for sec in &out.sections {
        let n = sec.info.number;
        h.section(&sec.info.stem())
            .heading(2, &format!("Study {n}: {}", sec.info.title))
            .para("", sec.info.description);
        if !sec.ok {
            h.para("failed", "This study failed; no results.");
        } else {
            for (_, e) in out.failed.iter().filter(|f| f.0 == n) {
                h.para("failed", &format!("{e:#}"));
            }
        }
        for note in &sec.notes {
            h.para(if sec.ok { "note" } else { "failed" }, note);
        }
        h.image(
            &format!("{}.svg", sec.info.stem()),
            &format!("Figure of study {n}: {}", sec.info.title),
        );
        for (panel, note) in &sec.figure_notes {
            let panel = if panel.is_empty() {
                "In the figure".to_string()
            } else {
                format!("Panel “{panel}”")
            };
            h.para("small", &format!("{panel}: {note}."));
        }
        h.table(&sec.overview);
        if sec.ok && sec.points > 0 {
            let raised: Vec<String> = sec
                .warnings_by_kind
                .iter()
                .filter(|(_, &c)| c > 0)
                .map(|(k, c)| format!("{k}: {c}"))
                .collect();
            let strict = if out.opts.strict {
                format!("; strict mode ruled out {} grasps", sec.strict_dropped)
            } else {
                String::new()
            };
            h.para(
                "small",
                &format!(
                    "Validity over {} points (grasps and finger states): {}{strict}.",
                    sec.points,
                    if raised.is_empty() {
                        "all within the model's limits".to_string()
                    } else {
                        raised.join(", ")
                    },
                ),
            );
        }
        let csvs: Vec<String> = sec.csvs.iter().map(|c| link(c, c)).collect();
        h.para_html(
            "small",
            &format!(
                "Data: {} · computed in {:.2} s",
                csvs.join(", "),
                sec.seconds
            ),
        );
    }
    h.finish(&escape(&format!(
        "Actuator: {} · model {} · N = {} · {}",
        out.source,
        out.opts.model.name(),
        out.opts.elements,
        out.provenance.line()
    )))
}
