//! Sub-pixel coordinates for the data of a panel.
//!
//! plotters' backend works in whole pixels: a curve drawn through it
//! snaps every vertex to the pixel grid, which shows as steps in a PNG
//! at twice the size, and in a PDF at any zoom. The layout (titles,
//! axes, ticks, labels, legends) keeps plotters' whole pixels; the data
//! of each panel (bands, reference lines, series, clip markers) is drawn
//! a second time into a backend [`SUB`] times finer over the same
//! plotting area, with every pen and marker size multiplied by [`SUB`].
//! That layer's attributes are divided back by [`SUB`] (exactly, as
//! decimals) and the layer is put, in drawing order, where the panel left
//! a marker. The picture keeps its layout; its data points are placed to
//! 1/[`SUB`] px instead of 1 px.

/// How much finer the data layer is than the layout: 1/20 px, written
/// with at most two decimals.
pub const SUB: u32 = 20;

/// The text of the marker that holds the place of data layer `i`.
pub fn marker(i: usize) -> String {
    format!("fpc-data-layer-{i}-of-this-figure")
}

/// The attributes whose numbers are lengths or coordinates in pixels.
const SCALED: [&str; 13] = [
    "x",
    "y",
    "x1",
    "y1",
    "x2",
    "y2",
    "cx",
    "cy",
    "r",
    "width",
    "height",
    "stroke-width",
    "points",
];

/// The elements of a fine layer (an SVG document from plotters' backend)
/// with their pixel attributes divided by [`SUB`].
pub fn layer_body(doc: &str) -> anyhow::Result<String> {
    let body = doc
        .split_once('\n')
        .map(|(head, rest)| {
            debug_assert!(head.starts_with("<svg"));
            rest
        })
        .unwrap_or("");
    let body = body.trim_end();
    let body = body.strip_suffix("</svg>").unwrap_or(body);
    let mut out = String::with_capacity(body.len());
    let mut rest = body;
    while let Some(eq) = rest.find("=\"") {
        let name_start = rest[..eq].rfind([' ', '<', '\n']).map_or(0, |i| i + 1);
        let name = &rest[name_start..eq];
        let value_start = eq + 2;
        let value_len = rest[value_start..]
            .find('"')
            .ok_or_else(|| anyhow::anyhow!("an unclosed attribute in plotters' SVG"))?;
        let value = &rest[value_start..value_start + value_len];
        out.push_str(&rest[..value_start]);
        if SCALED.contains(&name) {
            out.push_str(&divided(value)?);
        } else {
            out.push_str(value);
        }
        rest = &rest[value_start + value_len..];
    }
    out.push_str(rest);
    Ok(out)
}

/// Every whole number in `value` divided by [`SUB`].
fn divided(value: &str) -> anyhow::Result<String> {
    let mut out = String::with_capacity(value.len() + 8);
    let mut number = String::new();
    let flush = |number: &mut String, out: &mut String| -> anyhow::Result<()> {
        if !number.is_empty() {
            let n: i64 = number
                .parse()
                .map_err(|_| anyhow::anyhow!("not a whole number in plotters' SVG: {number}"))?;
            out.push_str(&hundredths(n * 100 / i64::from(SUB)));
            number.clear();
        }
        Ok(())
    };
    for c in value.chars() {
        match c {
            '0'..='9' => number.push(c),
            '-' if number.is_empty() => number.push(c),
            ',' | ' ' => {
                flush(&mut number, &mut out)?;
                out.push(c);
            }
            _ => anyhow::bail!("an unexpected pixel value in plotters' SVG: {value}"),
        }
    }
    flush(&mut number, &mut out)?;
    Ok(out)
}

/// `h` hundredths as a decimal without needless zeros (`1250` is `12.5`).
fn hundredths(h: i64) -> String {
    let sign = if h < 0 { "-" } else { "" };
    let (whole, frac) = (h.abs() / 100, h.abs() % 100);
    match frac {
        0 => format!("{sign}{whole}"),
        f if f % 10 == 0 => format!("{sign}{whole}.{}", f / 10),
        f => format!("{sign}{whole}.{f:02}"),
    }
}

/// `svg` with the text element of each [`marker`] replaced by its layer.
pub fn put_layers(svg: &str, layers: &[String]) -> anyhow::Result<String> {
    let mut out = svg.to_string();
    for (i, layer) in layers.iter().enumerate() {
        let missing = || anyhow::anyhow!("the place of data layer {i} is missing");
        let at = out.find(&marker(i)).ok_or_else(missing)?;
        let start = out[..at].rfind("<text").ok_or_else(missing)?;
        let close = out[at..].find("</text>").ok_or_else(missing)? + at;
        let mut end = close + "</text>".len();
        if out[end..].starts_with('\n') {
            end += 1;
        }
        out.replace_range(start..end, layer);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_attributes_are_divided_exactly() {
        assert_eq!(hundredths(1250), "12.5");
        assert_eq!(hundredths(-5), "-0.05");
        assert_eq!(hundredths(300), "3");
        let doc = "<svg width=\"2000\" height=\"2000\">\n<polyline fill=\"none\" opacity=\"1\" stroke=\"#0072B2\" stroke-width=\"40\" points=\"101,-3 250,400 \"/>\n<circle cx=\"61\" cy=\"62\" r=\"60\" opacity=\"0.55\" fill=\"#FFFFFF\"/>\n</svg>\n";
        let body = layer_body(doc).unwrap();
        assert_eq!(
            body,
            "<polyline fill=\"none\" opacity=\"1\" stroke=\"#0072B2\" stroke-width=\"2\" points=\"5.05,-0.15 12.5,20 \"/>\n<circle cx=\"3.05\" cy=\"3.1\" r=\"3\" opacity=\"0.55\" fill=\"#FFFFFF\"/>\n"
        );
        assert!(layer_body("<svg>\n<rect x=\"1.5\"/>\n</svg>").is_err());
    }

    #[test]
    fn a_layer_takes_the_place_of_its_marker() {
        let svg = format!(
            "<svg>\n<line/>\n<text x=\"0\" y=\"0\">{}\n</text>\n<rect/>\n</svg>\n",
            marker(0)
        );
        let out = put_layers(&svg, &["<circle/>\n".to_string()]).unwrap();
        assert_eq!(out, "<svg>\n<line/>\n<circle/>\n<rect/>\n</svg>\n");
        assert!(put_layers("<svg/>", &["x".into()]).is_err());
    }
}
