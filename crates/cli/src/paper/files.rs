//! Output plumbing of `fpc paper`: atomic file writes, CSV tables, finite
//! JSON numbers, HTML escaping.

use serde_json::Value;

pub use crate::output::write_atomic;

/// A JSON number, or `null` when `x` is not finite.
pub fn num(x: f64) -> Value {
    if x.is_finite() {
        Value::from(x)
    } else {
        Value::Null
    }
}

/// A JSON number, or `null` when absent or not finite.
pub fn opt(x: Option<f64>) -> Value {
    x.map_or(Value::Null, num)
}

/// One CSV cell.
#[derive(Clone)]
pub enum Cell {
    /// A number (empty when not finite).
    Num(f64),
    /// A number that may be missing (empty).
    Opt(Option<f64>),
    /// Text (quoted when needed).
    Text(String),
    /// `true` / `false`.
    Bool(bool),
    /// Nothing.
    Empty,
}

impl From<f64> for Cell {
    fn from(x: f64) -> Cell {
        Cell::Num(x)
    }
}

impl From<Option<f64>> for Cell {
    fn from(x: Option<f64>) -> Cell {
        Cell::Opt(x)
    }
}

impl From<bool> for Cell {
    fn from(b: bool) -> Cell {
        Cell::Bool(b)
    }
}

impl From<&str> for Cell {
    fn from(s: &str) -> Cell {
        Cell::Text(s.to_string())
    }
}

impl From<String> for Cell {
    fn from(s: String) -> Cell {
        Cell::Text(s)
    }
}

/// A CSV table with a fixed header. Every table of `fpc paper` ends with
/// the columns `status` (`ok`, `stopped`, `failed`, ...) and `note`.
pub struct Csv {
    header: &'static [&'static str],
    text: String,
}

impl Csv {
    /// An empty table with `header` (column names with units).
    pub fn new(header: &'static [&'static str]) -> Csv {
        let mut text = header.join(",");
        text.push('\n');
        Csv { header, text }
    }

    /// Appends a row; panics (a programming error) when the cell count
    /// does not match the header.
    pub fn row(&mut self, cells: Vec<Cell>) {
        assert_eq!(cells.len(), self.header.len(), "CSV row width");
        let cells: Vec<String> = cells.into_iter().map(cell_text).collect();
        self.text.push_str(&cells.join(","));
        self.text.push('\n');
    }

    /// Appends a row whose only filled cells are those named in `cells`
    /// (by column name); the others stay empty.
    pub fn sparse_row(&mut self, cells: Vec<(&str, Cell)>) {
        let mut row: Vec<Cell> = self.header.iter().map(|_| Cell::Empty).collect();
        for (name, cell) in cells {
            let i = self
                .header
                .iter()
                .position(|h| *h == name)
                .unwrap_or_else(|| panic!("no CSV column {name}"));
            row[i] = cell;
        }
        self.row(row);
    }

    /// The table's text.
    pub fn into_string(self) -> String {
        self.text
    }
}

fn cell_text(c: Cell) -> String {
    match c {
        Cell::Num(x) | Cell::Opt(Some(x)) if x.is_finite() => format!("{x}"),
        Cell::Num(_) | Cell::Opt(_) | Cell::Empty => String::new(),
        Cell::Bool(b) => b.to_string(),
        Cell::Text(s) => {
            if s.contains([',', '"', '\n', '\r']) {
                format!("\"{}\"", s.replace('"', "\"\"").replace(['\n', '\r'], " "))
            } else {
                s
            }
        }
    }
}

/// Escapes text for HTML and SVG.
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
    fn csv_quotes_and_blanks() {
        let mut t = Csv::new(&["d_mm", "status", "note"]);
        t.row(vec![f64::NAN.into(), "ok".into(), "a, \"b\"".into()]);
        t.sparse_row(vec![("status", "stopped".into())]);
        assert_eq!(
            t.into_string(),
            "d_mm,status,note\n,ok,\"a, \"\"b\"\"\"\n,stopped,\n"
        );
    }

    #[test]
    fn json_numbers_are_finite() {
        assert_eq!(num(f64::INFINITY), Value::Null);
        assert_eq!(opt(None), Value::Null);
        assert_eq!(num(1.5), Value::from(1.5));
    }
}
