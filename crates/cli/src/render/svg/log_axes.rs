//! Log axes: decades, superscript labels and minor lines.

use super::*;

/// `log10(v)`, or `None` for a value a log axis cannot show.
pub(super) fn log10_of(v: f64) -> Option<f64> {
    (v > 0.0 && v.is_finite()).then(|| v.log10())
}

/// A copy of `p` with the data of its log axes replaced by their log10
/// (values that are not positive become NaN points, which are skipped, or
/// are dropped), a fixed range likewise, `include_zero` ignored, and areas
/// on a log y axis drawn as lines (their base, y = 0, is not on it).
pub(super) fn on_log_axes(p: &Panel) -> Panel {
    let mut q = p.clone();
    let map = |log: bool, v: f64| {
        if log {
            log10_of(v).unwrap_or(f64::NAN)
        } else {
            v
        }
    };
    for s in &mut q.series {
        for pt in &mut s.points {
            *pt = [map(p.x.log, pt[0]), map(p.y.log, pt[1])];
        }
        if p.y.log && s.kind == SeriesKind::Area {
            s.kind = SeriesKind::Line;
        }
    }
    for (lines, log) in [(&mut q.hlines, p.y.log), (&mut q.vlines, p.x.log)] {
        lines.retain_mut(|l| {
            l.at = map(log, l.at);
            l.at.is_finite()
        });
    }
    if p.x.log {
        q.bands.retain_mut(|b| match log10_of(b.to) {
            Some(to) => {
                b.from = log10_of(b.from).unwrap_or(f64::NEG_INFINITY);
                b.to = to;
                true
            }
            None => false,
        });
    }
    for axis in [&mut q.x, &mut q.y] {
        if axis.log {
            axis.include_zero = false;
            axis.range = axis.range.and_then(|[a, b]| {
                let (a, b) = (log10_of(a)?, log10_of(b)?);
                (b > a).then_some([a, b])
            });
        }
    }
    q
}

/// The integer powers in `[lo, hi]` (log10 units): asked for as many
/// labels, plotters puts its ticks on them (its steps are 1, 2 or 5 times a
/// power of ten, and step 1/2 would give too many). Fewer than two: the
/// default count, ticks between powers.
pub(super) fn decade_labels(lo: f64, hi: f64) -> usize {
    let n = (hi.floor() - lo.ceil() + 1.0).max(0.0);
    if n >= 2.0 {
        (n as usize).min(16)
    } else {
        7
    }
}

/// Superscript digits of an integer exponent (`-2` -> `⁻²`).
pub(super) fn superscript(k: i64) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::new();
    if k < 0 {
        s.push('⁻');
    }
    for c in k.unsigned_abs().to_string().chars() {
        s.push(c.to_digit(10).map_or(c, |d| DIGITS[d as usize]));
    }
    s
}

/// The label of a tick at `v` on a log axis: `10⁻²` at a power of ten,
/// else the value with three significant digits (`3.16`, `1.58×10⁻⁴`).
pub(super) fn power_of_ten(v: &f64) -> String {
    let k = v.round();
    if (v - k).abs() < 1e-6 && k.abs() < 1e6 {
        format!("10{}", superscript(k as i64))
    } else {
        three_digits(10f64.powf(*v))
    }
}

/// A positive value with three significant digits, trailing zeros
/// dropped: plain from 0.001 to below a million, else times a power of
/// ten.
pub(super) fn three_digits(x: f64) -> String {
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    if !(x.is_finite() && x > 0.0) {
        return String::new();
    }
    let e = x.log10().floor() as i32;
    if (-3..6).contains(&e) {
        let d = (2 - e).max(0) as usize;
        trim(format!("{x:.d$}"))
    } else {
        let m = x / 10f64.powi(e);
        format!(
            "{}×10{}",
            trim(format!("{m:.2}")),
            superscript(i64::from(e))
        )
    }
}

/// Light grid lines at 2..9 times each power of ten of a log axis (the
/// mesh's own light lines are turned off there), when the axis spans at
/// most 12 decades.
pub(super) fn draw_log_minor_lines(
    chart: &mut Chart<'_, '_>,
    p: &Panel,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
) -> anyhow::Result<()> {
    let minor = |lo: f64, hi: f64| -> Vec<f64> {
        if !(hi - lo).is_finite() || hi - lo > 12.0 {
            return Vec::new();
        }
        let (first, last) = (lo.floor() as i64, hi.ceil() as i64);
        (first..=last)
            .flat_map(|k| (2..=9).map(move |m| k as f64 + f64::from(m).log10()))
            .filter(|v| (lo..=hi).contains(v))
            .collect()
    };
    let style = RGBColor(238, 238, 238).stroke_width(1);
    if p.x.log {
        chart.draw_series(
            minor(x0, x1)
                .into_iter()
                .map(|x| PathElement::new(vec![(x, y0), (x, y1)], style)),
        )?;
    }
    if p.y.log {
        chart.draw_series(
            minor(y0, y1)
                .into_iter()
                .map(|y| PathElement::new(vec![(x0, y), (x1, y)], style)),
        )?;
    }
    Ok(())
}
