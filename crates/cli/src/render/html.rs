//! The HTML writer: a page of headings, paragraphs, figures, overview
//! tables and link lists under one style sheet. Every text handed in as
//! text is escaped; only [`Page::html`] and [`link`] take markup.

use fpc::report::Overview;

const STYLE: &str = "body { font-family: sans-serif; max-width: 1400px; margin: 2em auto; padding: 0 1em; color: #222; }
section { border-top: 1px solid #ccc; padding-top: 1em; margin-top: 2em; }
img { max-width: 100%; height: auto; border: 1px solid #eee; }
table { border-collapse: collapse; margin: 0.8em 0; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: left; }
th { background: #f3f3f3; }
.failed { color: #b00000; font-weight: bold; }
.note { color: #8a5a00; }
.small { color: #666; font-size: 0.9em; }
";

/// A page being written.
pub struct Page {
    out: String,
    in_section: bool,
}

impl Page {
    /// A page with this title (in the head) and the shared style sheet.
    pub fn new(title: &str) -> Page {
        Page {
            out: format!(
                "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
                 <title>{}</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n",
                escape(title)
            ),
            in_section: false,
        }
    }

    /// Markup as it is (the caller escapes what it holds).
    pub fn html(&mut self, markup: &str) -> &mut Self {
        self.out.push_str(markup);
        self
    }

    /// A heading of `level` (1 to 6).
    pub fn heading(&mut self, level: u8, text: &str) -> &mut Self {
        self.html(&format!("<h{level}>{}</h{level}>\n", escape(text)))
    }

    /// A paragraph of text, of a class (`""`: none).
    pub fn para(&mut self, class: &str, text: &str) -> &mut Self {
        self.para_html(class, &escape(text))
    }

    /// A paragraph of markup, of a class (`""`: none).
    pub fn para_html(&mut self, class: &str, markup: &str) -> &mut Self {
        let class = if class.is_empty() {
            String::new()
        } else {
            format!(" class=\"{}\"", escape(class))
        };
        self.html(&format!("<p{class}>{markup}</p>\n"))
    }

    /// A list of text items, each of a class.
    pub fn list(&mut self, class: &str, items: &[String]) -> &mut Self {
        self.html("<ul>\n");
        for i in items {
            self.html(&format!(
                "<li class=\"{}\">{}</li>\n",
                escape(class),
                escape(i)
            ));
        }
        self.html("</ul>\n")
    }

    /// An image.
    pub fn image(&mut self, src: &str, alt: &str) -> &mut Self {
        self.html(&format!(
            "<img src=\"{}\" alt=\"{}\">\n",
            escape(src),
            escape(alt)
        ))
    }

    /// A table of text (nothing when it has no header).
    pub fn table(&mut self, t: &Overview) -> &mut Self {
        if t.header.is_empty() {
            return self;
        }
        let row = |cells: &[String], tag: &str| {
            let cells: String = cells
                .iter()
                .map(|c| format!("<{tag}>{}</{tag}>", escape(c)))
                .collect();
            format!("<tr>{cells}</tr>\n")
        };
        self.html("<table>\n");
        self.html(&row(&t.header, "th"));
        for r in &t.rows {
            self.html(&row(r, "td"));
        }
        self.html("</table>\n")
    }

    /// Starts a section (ending the one open) with this anchor.
    pub fn section(&mut self, id: &str) -> &mut Self {
        self.end_section();
        self.in_section = true;
        self.html(&format!("<section id=\"{}\">\n", escape(id)))
    }

    fn end_section(&mut self) {
        if std::mem::take(&mut self.in_section) {
            self.out.push_str("</section>\n");
        }
    }

    /// The page, with a footer of markup.
    pub fn finish(mut self, footer: &str) -> String {
        self.end_section();
        self.html(&format!(
            "<footer class=\"small\">{footer}</footer>\n</body>\n</html>\n"
        ));
        self.out
    }
}

/// A link to `href` reading `text`.
pub fn link(href: &str, text: &str) -> String {
    format!("<a href=\"{}\">{}</a>", escape(href), escape(text))
}

/// Escapes text for HTML and SVG (`&`, `<`, `>`, both quotes).
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escaping_covers_quotes() {
        assert_eq!(
            escape(r#"<a href="x">'&'</a>"#),
            "&lt;a href=&quot;x&quot;&gt;&#39;&amp;&#39;&lt;/a&gt;"
        );
    }
}
