//! Tick labels: as few decimals as tell the ticks apart.

use super::*;

/// How the tick labels of one linear axis are written: chosen from the
/// whole set of its ticks, so that they share their decimals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum TickFormat {
    /// Plain decimals, this many after the point.
    Plain(usize),
    /// A mantissa with `decimals` decimals times `10^exponent`, the
    /// exponent of the largest tick.
    Power { decimals: usize, exponent: i32 },
}

/// The fewest decimals (at most 12) that write every value of `vs`
/// exactly, to a millionth of the last digit.
pub(super) fn decimals_for(vs: &[f64]) -> usize {
    (0..=12)
        .find(|&d| {
            let s = 10f64.powi(d as i32);
            vs.iter().all(|v| ((v * s) - (v * s).round()).abs() < 1e-6)
        })
        .unwrap_or(12)
}

/// The format of a set of ticks: plain decimals when the largest tick is
/// from 0.001 to below a million (0, 20, 40; 0.0, 0.5, 1.0; 0.25, 0.50),
/// else a power of ten shared by every tick (0.5×10⁻⁴, 1.0×10⁻⁴; 2×10⁶).
pub(super) fn tick_format(ticks: &[f64]) -> TickFormat {
    let ticks: Vec<f64> = ticks.iter().copied().filter(|t| t.is_finite()).collect();
    let largest = ticks.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    if largest == 0.0 || (1e-3..1e6).contains(&largest) {
        return TickFormat::Plain(decimals_for(&ticks));
    }
    let exponent = largest.log10().floor() as i32;
    let scale = 10f64.powi(exponent);
    let mantissas: Vec<f64> = ticks.iter().map(|t| t / scale).collect();
    TickFormat::Power {
        decimals: decimals_for(&mantissas),
        exponent,
    }
}

/// The label of a tick at `v`: `0` for a value that rounds to zero, else
/// as `f` says.
pub(super) fn tick_label(v: f64, f: TickFormat) -> String {
    if !v.is_finite() {
        return String::new();
    }
    let (mantissa, decimals, exponent) = match f {
        TickFormat::Plain(d) => (v, d, None),
        TickFormat::Power { decimals, exponent } => {
            (v / 10f64.powi(exponent), decimals, Some(exponent))
        }
    };
    let text = format!("{mantissa:.decimals$}");
    if text.chars().all(|c| matches!(c, '0' | '.' | '-')) {
        return "0".into();
    }
    match exponent {
        Some(e) => format!("{text}×10{}", superscript(i64::from(e))),
        None => text,
    }
}
