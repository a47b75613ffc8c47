//! `index.html`: every study's figure, overview table, notes and links to
//! its CSV files, on one page. Every piece of text is escaped.

use super::files::escape;
use super::Output;

/// The page for everything `out` recorded.
pub fn html(out: &Output) -> String {
    let mut h = String::new();
    h.push_str(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <title>fpc: the paper&#39;s studies</title>\n<style>\n\
         body { font-family: sans-serif; max-width: 1400px; margin: 2em auto; padding: 0 1em; color: #222; }\n\
         section { border-top: 1px solid #ccc; padding-top: 1em; margin-top: 2em; }\n\
         img { max-width: 100%; height: auto; border: 1px solid #eee; }\n\
         table { border-collapse: collapse; margin: 0.8em 0; font-size: 0.92em; }\n\
         th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; }\n\
         th { background: #f3f3f3; }\n\
         .failed { color: #b00000; font-weight: bold; }\n\
         .note { color: #8a5a00; }\n\
         .small { color: #666; font-size: 0.9em; }\n\
         </style>\n</head>\n<body>\n",
    );
    h.push_str(&format!(
        "<h1>Fluidic prestressed composite grippers: the paper&#39;s {} studies</h1>\n",
        out.sections.len()
    ));
    h.push_str(&format!(
        "<p class=\"small\">fpc {}, {} actuator, model {}, N = {} elements, μ = {}{}{}. \
         Key numbers: <a href=\"summary.json\">summary.json</a>.</p>\n",
        escape(env!("CARGO_PKG_VERSION")),
        escape(&out.source),
        escape(out.opts.model.name()),
        out.opts.elements,
        out.opts.mu,
        if out.coarse {
            ", coarse sweeps (preview)"
        } else {
            ""
        },
        if out.opts.strict {
            ", strict mode (grasps that bend an element backwards are dropped)"
        } else {
            ""
        }
    ));
    let failed = out.failed_studies();
    if !failed.is_empty() {
        h.push_str(&format!(
            "<p class=\"failed\">{} of {} studies failed: {}.</p>\n",
            failed.len(),
            out.sections.len(),
            failed
                .iter()
                .map(|n| format!("<a href=\"#study{n}\">study {n}</a>"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    if !out.warnings.is_empty() {
        h.push_str("<p class=\"note\">Design warnings:</p>\n<ul>\n");
        for w in &out.warnings {
            h.push_str(&format!("<li class=\"note\">{}</li>\n", escape(w)));
        }
        h.push_str("</ul>\n");
    }
    for sec in &out.sections {
        let n = sec.info.number;
        let stem = escape(&sec.info.stem());
        h.push_str(&format!(
            "<section id=\"{stem}\">\n<h2>Study {n}: {}</h2>\n<p>{}</p>\n",
            escape(sec.info.title),
            escape(sec.info.description)
        ));
        if !sec.ok {
            h.push_str("<p class=\"failed\">This study failed; no results.</p>\n");
        } else {
            for (_, e) in out.failed.iter().filter(|f| f.0 == n) {
                h.push_str(&format!(
                    "<p class=\"failed\">{}</p>\n",
                    escape(&format!("{e:#}"))
                ));
            }
        }
        for note in &sec.notes {
            let class = if sec.ok { "note" } else { "failed" };
            h.push_str(&format!("<p class=\"{class}\">{}</p>\n", escape(note)));
        }
        h.push_str(&format!(
            "<img src=\"{stem}.svg\" alt=\"Figure of study {n}: {}\">\n",
            escape(sec.info.title)
        ));
        let ov = &sec.overview;
        if !ov.header.is_empty() {
            h.push_str("<table>\n<tr>");
            for c in &ov.header {
                h.push_str(&format!("<th>{}</th>", escape(c)));
            }
            h.push_str("</tr>\n");
            for r in &ov.rows {
                h.push_str("<tr>");
                for c in r {
                    h.push_str(&format!("<td>{}</td>", escape(c)));
                }
                h.push_str("</tr>\n");
            }
            h.push_str("</table>\n");
        }
        if sec.ok && sec.points > 0 {
            let raised: Vec<String> = sec
                .warnings_by_kind
                .iter()
                .filter(|(_, &c)| c > 0)
                .map(|(k, c)| format!("{}: {c}", escape(k)))
                .collect();
            h.push_str(&format!(
                "<p class=\"small\">Validity over {} points (grasps and finger states): {}{}.</p>\n",
                sec.points,
                if raised.is_empty() {
                    "all within the model&#39;s limits".to_string()
                } else {
                    raised.join(", ")
                },
                if out.opts.strict {
                    format!("; strict mode ruled out {} grasps", sec.strict_dropped)
                } else {
                    String::new()
                }
            ));
        }
        h.push_str(&format!(
            "<p class=\"small\">Data: {} · computed in {:.2} s</p>\n</section>\n",
            sec.csvs
                .iter()
                .map(|c| format!("<a href=\"{0}\">{0}</a>", escape(c)))
                .collect::<Vec<_>>()
                .join(", "),
            sec.seconds
        ));
    }
    h.push_str(&format!(
        "<footer class=\"small\">Actuator: {} · model {} · N = {} · {}</footer>\n",
        escape(&out.source),
        escape(out.opts.model.name()),
        out.opts.elements,
        escape(&out.provenance.line())
    ));
    h.push_str("</body>\n</html>\n");
    h
}
