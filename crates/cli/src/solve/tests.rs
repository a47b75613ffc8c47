//! Unit tests of `fpc solve`'s outputs: the JSON keys, the figure's
//! geometry and its text.

use super::figure::*;
use super::render::*;
use super::report::*;
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
        let json = serde_json::to_string(&solution_file("t", &file, &s)).unwrap();
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

#[test]
fn equal_aspect_gives_one_scale() {
    for (lo, hi, px) in [
        ([0.0, -80.0], [110.0, 5.0], (734, 600)),
        ([-60.0, -150.0], [60.0, 5.0], (734, 760)),
        ([0.0, 0.0], [10.0, 1000.0], (300, 220)),
        ([-1.0, -1.0], [1.0, 1.0], (2, 2)),
    ] {
        let (x, y) = equal_aspect(lo, hi, px);
        let sx = (x.1 - x.0) / f64::from(px.0 - 1);
        let sy = (y.1 - y.0) / f64::from(px.1 - 1);
        assert!((sx - sy).abs() <= 1e-12 * sx, "{sx} {sy}");
        assert!(x.0 <= lo[0] && x.1 >= hi[0] && y.0 <= lo[1] && y.1 >= hi[1]);
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
    for (y_down, wide) in [(false, 300.0), (true, 20.0), (false, 5.0)] {
        let mut p = Plot::new("t".into(), "X (mm)", "Z (mm)", y_down);
        p.add(
            Look::Object,
            "square",
            [[0.0, 0.0], [40.0, 0.0], [40.0, 40.0], [0.0, 40.0]],
        );
        p.add(Look::Finger, "line", [[-wide, 0.0], [wide, 10.0]]);
        let corners = polygon_px(&render(&p).unwrap());
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
    let SceneSolution::Finger { solution, .. } = &mut s else {
        panic!()
    };
    solution.tip = [f64::NAN, f64::INFINITY];
    solution.end_angle = f64::NAN;
    solution.points[3] = [f64::NAN, 1.0];
    solution.points[4] = [1e300, -1e300];
    let svg = shape_svg("t", &s).unwrap();
    assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
    assert!(svg.contains("tip X = n/a mm"));
    // nothing drawable at all still gives axes around the origin
    let mut p = Plot::new("t".into(), "X (mm)", "Z (mm)", false);
    p.add(Look::Finger, "f", [[f64::NAN, 0.0], [f64::INFINITY, 1.0]]);
    p.add(Look::Tip, "tip", [[f64::NAN, f64::NAN]]);
    assert!(p.items.is_empty());
    let svg = render(&p).unwrap();
    assert!(svg.contains("X (mm)") && !svg.contains("NaN"));
}

#[test]
fn ticks_and_text() {
    assert_eq!(tick(-0.0), "0");
    assert_eq!(tick(-1e-9), "0");
    assert_eq!(tick(20.000000000004), "20");
    assert_eq!(tick(-12.5), "-12.5");
    assert_eq!(nice_step(16.0), 20.0);
    assert_eq!(nice_step(20.0), 20.0);
    assert_eq!(nice_step(0.3), 0.5);
    assert_eq!(nice_step(7.0), 10.0);
    assert_eq!(multiples((-5.0, 105.0), 20.0), 6);
    assert_eq!(num(f64::NAN, 2), "n/a");
    assert_eq!(num(1.23456, 2), "1.23");
    let text = "outside the model: element_slope at element 1: element 1 turns 64.9 degrees";
    let lines = wrap(text, 30);
    assert!(lines.len() > 1);
    assert!(lines.iter().all(|l| l.chars().count() <= 30), "{lines:?}");
    assert_eq!(lines.join(" "), text);
    assert_eq!(wrap("", 10), [""]);
    assert_eq!(wrap(&"x".repeat(50), 10), ["x".repeat(50)]);
}
