//! Numbers as text: compact at every magnitude.
//!
//! Rust writes an `f64` with `{}` in full decimal notation, so `1e300` is
//! 301 digits and `1e-300` is 300 zeros and a one; fixed decimals
//! (`{:.4}`) turn a small nonzero value into `0.0000`. [`Num`] writes
//! ordinary values exactly as `{}` and `{:.N}` do, and switches to the
//! exponent form only where those break. Error messages, summaries and
//! CSV files use it, so an extreme value reads the same everywhere.

use std::fmt;

/// Below this magnitude a value without a precision is written with an
/// exponent.
const SMALL: f64 = 1e-9;
/// From this magnitude on a value is written with an exponent.
const LARGE: f64 = 1e16;

/// A value as text: as Rust writes it, except at extreme magnitudes.
///
/// - `{}`: the shortest text that reads back to the same `f64` (Rust's
///   `{}`) for a magnitude from 1e-9 to below 1e16, and otherwise the
///   shortest exponent form (`{:e}`: `1e300`, `1.5e-12`), which reads back
///   exactly too. Zero is `0`.
/// - `{:.N}`: `N` decimals (`{:.N}`) for a magnitude from 10^-N to below
///   1e16, so every such value keeps at least one significant digit;
///   otherwise the exponent form with `N` digits after the mantissa's
///   point, trailing zeros dropped (`{:.4}` of `1.5e-7` is `1.5e-7`, not
///   `0.0000`). Zero is `0.0000`.
/// - NaN and the infinities are written as Rust writes them (`NaN`,
///   `inf`, `-inf`).
///
/// Width, alignment (right by default) and `+` apply as for numbers:
/// `{:>10.3}`, `{:+}`.
///
/// ```
/// use fpc::num::Num;
///
/// assert_eq!(Num(0.5).to_string(), "0.5");
/// assert_eq!(Num(1e300).to_string(), "1e300");
/// assert_eq!(Num(-2.5e-12).to_string(), "-2.5e-12");
/// assert_eq!(format!("{:.4}", Num(12.345678)), "12.3457");
/// assert_eq!(format!("{:.4}", Num(1.5e-7)), "1.5e-7");
/// assert_eq!(format!("{:.3}", Num(1e300)), "1e300");
/// assert_eq!(format!("{:>8.2}", Num(3.14159)), "    3.14");
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Num(pub f64);

impl Num {
    /// The text without width, alignment or sign flag.
    fn text(self, precision: Option<usize>) -> String {
        let v = self.0;
        let a = v.abs();
        match precision {
            None if v.is_finite() && a != 0.0 && !(SMALL..LARGE).contains(&a) => format!("{v:e}"),
            None => format!("{v}"),
            Some(p) if v.is_finite() && a != 0.0 && !(small_fixed(p)..LARGE).contains(&a) => {
                let s = format!("{v:.p$e}");
                match s.split_once('e') {
                    Some((mantissa, exp)) if mantissa.contains('.') => {
                        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
                        format!("{mantissa}e{exp}")
                    }
                    _ => s,
                }
            }
            Some(p) => format!("{v:.p$}"),
        }
    }
}

/// The smallest magnitude written with `p` fixed decimals: 10^-p (below
/// it the decimals show no significant digit).
fn small_fixed(p: usize) -> f64 {
    10f64.powi(-(p.min(300) as i32))
}

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut s = self.text(f.precision());
        if f.sign_plus() && !s.starts_with('-') {
            s.insert(0, '+');
        }
        let width = f.width().unwrap_or(0);
        let pad = width.saturating_sub(s.chars().count());
        if pad == 0 {
            return f.write_str(&s);
        }
        let fill = f.fill().to_string();
        let (left, right) = match f.align() {
            Some(fmt::Alignment::Left) => (0, pad),
            Some(fmt::Alignment::Center) => (pad / 2, pad - pad / 2),
            Some(fmt::Alignment::Right) | None => (pad, 0),
        };
        write!(f, "{}{s}{}", fill.repeat(left), fill.repeat(right))
    }
}

#[cfg(test)]
mod tests {
    use super::Num;

    #[test]
    fn ordinary_values_as_rust_writes_them() {
        for v in [
            0.0,
            -0.0,
            0.5,
            120.0,
            0.939782,
            -21.25,
            1e-9,
            123456789.5,
            9.9e15,
        ] {
            assert_eq!(Num(v).to_string(), format!("{v}"));
            for p in [0, 2, 4, 10] {
                if v == 0.0 || v.abs() >= 10f64.powi(-p) {
                    let p = p as usize;
                    assert_eq!(format!("{:.p$}", Num(v)), format!("{v:.p$}"));
                }
            }
        }
        assert_eq!(format!("{:>14.8}", Num(1.5)), format!("{:>14.8}", 1.5));
        assert_eq!(format!("{:<6.1}|", Num(1.5)), "1.5   |");
        assert_eq!(format!("{:+.4}", Num(0.25)), "+0.2500");
        assert_eq!(format!("{:+.4}", Num(-0.25)), "-0.2500");
    }

    #[test]
    fn extreme_values_with_an_exponent() {
        assert_eq!(Num(1e300).to_string(), "1e300");
        assert_eq!(Num(-1e-300).to_string(), "-1e-300");
        assert_eq!(Num(1e16).to_string(), "1e16");
        assert_eq!(
            Num(f64::MIN_POSITIVE / 4.0).to_string(),
            "5.562684646268003e-309"
        );
        assert_eq!(format!("{:.4}", Num(1e-300)), "1e-300");
        assert_eq!(format!("{:.4}", Num(-1.23456789e-7)), "-1.2346e-7");
        assert_eq!(format!("{:.3}", Num(1e300)), "1e300");
        assert_eq!(format!("{:.10}", Num(3e-12)), "3e-12");
        assert_eq!(format!("{:.0}", Num(0.4)), "4e-1");
        assert_eq!(format!("{:>8.2}", Num(1e-9)), "    1e-9");
        // exact: the text reads back to the same value
        for v in [1e300, 1e-300, 1.2345678901234567e-200, f64::MAX, 5e-324] {
            assert_eq!(Num(v).to_string().parse::<f64>().unwrap(), v);
        }
    }

    #[test]
    fn non_finite_as_rust_writes_them() {
        assert_eq!(Num(f64::NAN).to_string(), "NaN");
        assert_eq!(Num(f64::INFINITY).to_string(), "inf");
        assert_eq!(format!("{:.2}", Num(f64::NEG_INFINITY)), "-inf");
    }
}
