//! The data model of every figure and table the project writes: a
//! [`Table`] of typed [`Cell`]s under named [`Column`]s, a small text
//! [`Overview`], and a [`Figure`] of [`Panel`]s (its own module). Plain
//! data with serde: nothing here draws or writes a file; the `fpc` command
//! has the one set of writers (SVG, CSV, HTML) for all of it.

mod figure;

pub use figure::{
    Band, Clip, Clipped, Corner, Figure, Panel, PlotAxis, RefLine, Series, SeriesKind,
    BENT_BACKWARDS, INVALID_GRASP, NEUTRAL,
};

use serde::Serialize;

/// A column: its name as written in a CSV header (unit last, as in `d_mm`,
/// `F_n`, `pressure_kpa`) and that unit on its own (`None`: a pure number,
/// a flag or text).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Column {
    /// Header name, e.g. `d_mm`.
    pub name: &'static str,
    /// Unit, e.g. `mm`.
    pub unit: Option<&'static str>,
}

impl Column {
    /// A column with a unit (`""`: none).
    pub const fn new(name: &'static str, unit: &'static str) -> Column {
        Column {
            name,
            unit: if unit.is_empty() { None } else { Some(unit) },
        }
    }
}

/// One cell of a table.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Cell {
    /// A number (written empty when not finite).
    Num(f64),
    /// Text.
    Text(String),
    /// A flag.
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
        x.map_or(Cell::Empty, Cell::Num)
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

/// A named table: `name` is the file stem (`study1`, `study1_shapes`).
/// Every row has one cell per column; every table of the studies ends with
/// the columns `status` and `note`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table {
    /// File stem.
    pub name: String,
    /// The columns.
    pub columns: Vec<Column>,
    /// The rows, each as wide as `columns`.
    pub rows: Vec<Vec<Cell>>,
}

impl Table {
    /// An empty table.
    pub fn new(name: impl Into<String>, columns: &[Column]) -> Table {
        Table {
            name: name.into(),
            columns: columns.to_vec(),
            rows: Vec::new(),
        }
    }

    /// The index of the column called `name`.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c.name == name)
    }

    /// The cell of row `row` in column `name`.
    pub fn cell(&self, row: usize, name: &str) -> Option<&Cell> {
        self.rows.get(row)?.get(self.column(name)?)
    }

    /// Appends a row; panics (a programming error) when it is not as wide
    /// as the table.
    pub fn push(&mut self, row: Vec<Cell>) {
        assert_eq!(
            row.len(),
            self.columns.len(),
            "row width of table {}",
            self.name
        );
        self.rows.push(row);
    }

    /// Appends a row whose only filled cells are the named ones; panics on
    /// an unknown column name.
    pub fn push_named(&mut self, cells: Vec<(&str, Cell)>) {
        let mut row = vec![Cell::Empty; self.columns.len()];
        for (name, cell) in cells {
            let i = self
                .column(name)
                .unwrap_or_else(|| panic!("table {} has no column {name}", self.name));
            row[i] = cell;
        }
        self.rows.push(row);
    }
}

/// The small table a report shows for a study: a header and rows of text.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Overview {
    /// Column titles.
    pub header: Vec<String>,
    /// Rows, each as wide as the header.
    pub rows: Vec<Vec<String>>,
}

impl Overview {
    /// An empty overview with this header.
    pub fn new(header: &[&str]) -> Overview {
        Overview {
            header: header.iter().map(|h| h.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row.
    pub fn push(&mut self, row: Vec<String>) {
        self.rows.push(row);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_check_their_width() {
        let status = Column::new("status", "");
        let mut t = Table::new(
            "t",
            &[Column::new("d_mm", "mm"), status, Column::new("note", "")],
        );
        assert_eq!(t.columns[0].unit, Some("mm"));
        assert_eq!(t.columns[1].unit, None);
        t.push(vec![1.0.into(), "ok".into(), Cell::Empty]);
        t.push_named(vec![("status", "stopped".into())]);
        assert_eq!(t.rows[1], [Cell::Empty, "stopped".into(), Cell::Empty]);
        assert_eq!(t.cell(0, "d_mm"), Some(&Cell::Num(1.0)));
        let wide = std::panic::catch_unwind(move || t.push(vec![Cell::Empty]));
        assert!(wide.is_err(), "a short row is a programming error");
    }
}
