//! The CSV writer: a [`Table`] with a header of its column names, one line
//! per row, numbers to [`CSV_DIGITS`] significant digits (the `csv` crate
//! quotes what needs it).

use fpc::report::{Cell, Table};

/// Significant digits of a number in a CSV file: 10, well above what the
/// model's tolerances resolve and short enough to read.
pub const CSV_DIGITS: usize = 10;

/// A number with [`CSV_DIGITS`] significant digits, trailing zeros dropped:
/// plain decimals for magnitudes from 1e-5 to below 1e15, else
/// `1.234567891e-12`; `0` for zero, empty when not finite.
pub fn number(x: f64) -> String {
    if !x.is_finite() {
        return String::new();
    }
    if x == 0.0 {
        return "0".into();
    }
    let sci = format!("{:.*e}", CSV_DIGITS - 1, x);
    let (mantissa, exp) = sci.split_once('e').expect("`e` in exponent format");
    let exp: i32 = exp.parse().expect("integer exponent");
    if (-5..15).contains(&exp) {
        let decimals = (CSV_DIGITS as i32 - 1 - exp).max(0) as usize;
        trim_zeros(format!("{x:.decimals$}"))
    } else {
        format!("{}e{exp}", trim_zeros(mantissa.to_string()))
    }
}

fn trim_zeros(s: String) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The text of one cell: numbers by [`number`], flags as `true`/`false`,
/// text on one line (line breaks become spaces).
pub fn cell_text(c: &Cell) -> String {
    match c {
        Cell::Num(x) => number(*x),
        Cell::Bool(b) => b.to_string(),
        Cell::Text(s) => s.replace(['\n', '\r'], " "),
        Cell::Empty => String::new(),
    }
}

/// A table as CSV: a header of the column names, one line per row, fields
/// quoted where they need it.
pub fn csv(table: &Table) -> anyhow::Result<Vec<u8>> {
    let mut w = csv::WriterBuilder::new()
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    w.write_record(table.columns.iter().map(|c| c.name))?;
    for row in &table.rows {
        anyhow::ensure!(
            row.len() == table.columns.len(),
            "table {}: a row of {} cells under {} columns",
            table.name,
            row.len(),
            table.columns.len()
        );
        w.write_record(row.iter().map(cell_text))?;
    }
    Ok(w.into_inner().map_err(|e| e.into_error())?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use fpc::report::Column;

    #[test]
    fn numbers_have_ten_significant_digits() {
        assert_eq!(number(0.0), "0");
        assert_eq!(number(-0.0), "0");
        assert_eq!(number(10.0), "10");
        assert_eq!(number(5.5), "5.5");
        assert_eq!(number(-21.143866366825623), "-21.14386637");
        assert_eq!(number(std::f64::consts::FRAC_PI_2), "1.570796327");
        assert_eq!(number(143.93439916293065), "143.9343992");
        assert_eq!(number(99.99999999994014), "100");
        assert_eq!(number(0.00002842170943040401), "0.00002842170943");
        assert_eq!(number(2.842170943040401e-14), "2.842170943e-14");
        assert_eq!(number(-6.658668470837774e-17), "-6.658668471e-17");
        assert_eq!(number(1.0e20), "1e20");
        assert_eq!(number(123456789012.0), "123456789012");
        assert_eq!(number(f64::NAN), "");
        assert_eq!(number(f64::NEG_INFINITY), "");
        // the text reads back to within the precision
        for x in [0.1234567890123, -98765.4321012345, 3.3e-9] {
            let y: f64 = number(x).parse().unwrap();
            assert!((x - y).abs() <= 1e-9 * x.abs(), "{x} -> {y}");
        }
    }

    #[test]
    fn csv_quotes_and_blanks() {
        let columns = ["d_mm", "status", "note"].map(|n| Column::new(n, ""));
        let mut t = Table::new("t", &columns);
        t.push(vec![f64::NAN.into(), "ok".into(), "a, \"b\"".into()]);
        t.push_named(vec![("status", "stopped".into())]);
        t.push(vec![Cell::Bool(true), Cell::Empty, "two\nlines".into()]);
        assert_eq!(
            String::from_utf8(csv(&t).unwrap()).unwrap(),
            "d_mm,status,note\n,ok,\"a, \"\"b\"\"\"\n,stopped,\ntrue,,two lines\n"
        );
    }
}
