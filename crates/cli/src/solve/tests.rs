//! Unit tests of `fpc solve`'s outputs: the JSON keys, the figure's
//! geometry and its text.

use super::figure::*;
use super::report::*;
use crate::render::svg::svg;
use fpc::report::{Figure, Panel, PlotAxis, Series, SeriesKind};
use fpc::scene::SceneSolution;

fn solved(text: &str) -> SceneSolution {
    fpc::Scene::from_toml(text).unwrap().solve().unwrap()
}

/// The keys of a JSON object in the order written, repeats kept.
struct Keys(Vec<String>);

impl<'de> serde::Deserialize<'de> for Keys {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Keys, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = Keys;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an object")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut m: A) -> Result<Keys, A::Error> {
                let mut keys = Vec::new();
                while let Some((k, _)) = m.next_entry::<String, serde::de::IgnoredAny>()? {
                    keys.push(k);
                }
                Ok(Keys(keys))
            }
        }
        d.deserialize_map(Visitor)
    }
}

#[test]
fn solution_json_has_no_key_twice() {
    for text in [
        "",
        "[gripper]\n",
        "[gripper]\n[gripper.grasp]\nkind = \"sphere\"\n",
    ] {
        let s = solved(text);
        let file = fpc::Scene::from_toml(text).unwrap().file().clone();
        let json = serde_json::to_string(&solution_file("t", &file, &s, None)).unwrap();
        let Keys(mut top) = serde_json::from_str(&json).unwrap();
        let written = top.len();
        top.sort();
        top.dedup();
        assert_eq!(top.len(), written, "{text:?}: a key twice in {json}");
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        if let Some(g) = v.get("gripper") {
            let Keys(mut inner) = serde_json::from_value(g.clone()).unwrap();
            let written = inner.len();
            inner.sort();
            inner.dedup();
            assert_eq!(inner.len(), written, "{text:?}: gripper");
        }
        assert_eq!(v["warnings"], serde_json::json!([]), "{text:?}");
        assert_eq!(v["validity"], true, "{text:?}");
    }
}

/// The corners (px) of the first `<polygon>` of an SVG.
fn polygon_px(svg: &str) -> Vec<(f64, f64)> {
    let tag = &svg[svg.find("<polygon").unwrap()..];
    let start = tag.find("points=\"").unwrap() + "points=\"".len();
    let end = start + tag[start..].find('"').unwrap();
    tag[start..end]
        .split_whitespace()
        .map(|p| {
            let (x, y) = p.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

#[test]
fn a_square_is_drawn_square() {
    for (down, wide) in [(false, 300.0), (true, 20.0), (false, 5.0)] {
        let mut p = Panel::new("", PlotAxis::new("X", "mm"), PlotAxis::new("Z", "mm"));
        p.equal_aspect = true;
        p.y.down = down;
        let square = vec![
            [0.0, 0.0],
            [40.0, 0.0],
            [40.0, 40.0],
            [0.0, 40.0],
            [0.0, 0.0],
        ];
        p.series
            .push(Series::new("object", SeriesKind::Outline, square).label("square"));
        p.series.push(Series::new(
            "finger",
            SeriesKind::Line,
            vec![[-wide, 0.0], [wide, 10.0]],
        ));
        p.caption.push("a caption under the chart".into());
        let corners = polygon_px(&svg(&Figure::row("t", [820, 600], vec![p])).unwrap());
        let span = |f: fn(&(f64, f64)) -> f64| {
            let v: Vec<f64> = corners.iter().map(f).collect();
            v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
        };
        let (w, h) = (span(|c| c.0), span(|c| c.1));
        assert!(w > 10.0 && (w - h).abs() <= 1.0, "{w} x {h} px");
    }
}

#[test]
fn non_finite_values_draw_nothing_and_print_no_nan() {
    let mut s = solved("");
    let SceneSolution::Finger(solved) = &mut s else {
        panic!()
    };
    let solution = &mut solved.solution;
    solution.tip = [f64::NAN, f64::INFINITY];
    solution.end_angle = f64::NAN;
    solution.points[3] = [f64::NAN, 1.0];
    solution.points[4] = [1e300, -1e300];
    let svg = svg(&shape_figure("t", &s)).unwrap();
    assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
    assert!(svg.contains("tip X = n/a mm"));
    assert!(drawable([[f64::NAN, 0.0], [f64::INFINITY, 1.0], [1e300, 0.0]]).is_empty());
}

#[test]
fn numbers_in_the_caption() {
    assert_eq!(num(f64::NAN, 2), "n/a");
    assert_eq!(num(1.23456, 2), "1.23");
}

/// Downward axes show the frame's values: a gripper's tip below the palm
/// (Zg > 0) has positive Zg ticks, and the palm line sits at the top.
#[test]
fn the_gripper_frame_points_down() {
    let s = solved("[gripper]\n");
    let f = shape_figure("g", &s);
    let p = &f.rows[0][0];
    assert!(p.y.down && p.equal_aspect);
    let text = svg(&f).unwrap();
    for part in [
        "Xg (mm)",
        "Zg (mm, pointing down)",
        "gripper axis (Xg = 0)",
        "fingers at rest",
    ] {
        assert!(text.contains(part), "{part}");
    }
    let ticks: Vec<f64> = text
        .split("<text")
        .filter_map(|t| {
            t.split_once('>')?
                .1
                .split("</text>")
                .next()?
                .trim()
                .parse()
                .ok()
        })
        .collect();
    assert!(ticks.iter().any(|&t| t >= 40.0), "{ticks:?}");
}
