//! Ribs on the constraining layer (`actuator.cl_ribs`, docs/model.md
//! section 4.10), for every element model, in plane stress and plane
//! strain:
//!
//! - without them every result is main's, bit for bit;
//! - a rib over the whole finger is a thicker constraining layer: the same
//!   energy at every state and the same equilibrium as the geometry with H
//!   grown by the rib's height, once the shift of the mid-plane is carried
//!   into the axial strain (a1' = a1 - 2 delta c2, delta = height / 2);
//! - an element's energy grows by the rib box's energy, integrated here by
//!   Gauss-Legendre quadrature of the densities (M2, M4, M33), and at a
//!   pure curvature by the closed form Q11 kappa^2 b l (z1^3 - z0^3) / 6;
//! - taller ribs curl the finger less;
//! - bad input is a typed error naming the key, in the library and in a
//!   scene.

use fpc::actuator::{ClRib, ClRibKey, MAX_CL_RIBS};
use fpc::{
    Actuator, ActuatorParams, Coefficients, Field, Finger, Load, ModelId, Partition, Scene,
    SolveOptions,
};

fn params(plane_strain: bool, ribs: Vec<ClRib>) -> ActuatorParams {
    ActuatorParams {
        plane_strain,
        cl_ribs: ribs,
        ..ActuatorParams::default()
    }
}

fn rib(x0: f64, x1: f64, width: f64, height: f64) -> ClRib {
    ClRib {
        x0,
        x1,
        width,
        height,
    }
}

fn fnv(h: &mut u64, x: f64) {
    for b in x.to_bits().to_le_bytes() {
        *h ^= u64::from(b);
        *h = h.wrapping_mul(0x100000001b3);
    }
}

/// Main's potential without the ribs on the constraining layer (recorded
/// at commit 98461c9, the last before them, by this computation; the
/// `shear` model's recorded again when its end angle took the shear angle
/// at the element's end, docs/model.md section 4.8): a hash
/// of the bits of the energy, gradient and Hessian of the default finger
/// (N = 8) at 40 kPa with a tip force (0.3, -0.5) N, at three fixed
/// states, per model and plane strain. These do not depend on the solver's
/// path (an earlier version hashed solved equilibria, whose last bits move
/// with any change to Newton). Bit patterns of the kernels' arithmetic are
/// this platform's, so the check runs on x86_64 Linux only.
#[test]
fn without_ribs_the_potential_is_mains_bit_for_bit() {
    let main: [(&str, bool, u64); 6] = [
        ("ccm", false, 0x8aa7718c78f0654d),
        ("ccm", true, 0x7752c41f3a6e19b2),
        ("quad", false, 0x51661c52c35634e7),
        ("quad", true, 0xc0df7572be803561),
        ("shear", false, 0x107a3e3e2a5ecd5b),
        ("shear", true, 0xea356afb621d9479),
    ];
    let load = Load::unloaded()
        .with_pressure_kpa(40.0)
        .with_tip_force(0.3, -0.5);
    let part = Partition::equal(110.0, 8).unwrap();
    for (name, plane_strain, want) in main {
        let model = ModelId::from_name(name).unwrap();
        let act = Actuator::new(params(plane_strain, Vec::new())).unwrap();
        let f = Finger::with_model(model, &act, &part, true);
        let n = f.unknowns_per_element();
        let mut h = 0xcbf29ce484222325u64;
        for state in 0..3 {
            let values: Vec<f64> = (0..8 * n)
                .map(|i| 1e-3 * ((i * 7 + state * 13) % 11) as f64 - 5e-3)
                .collect();
            let k = Coefficients::new(n, values).unwrap();
            let (e, g, hess) = f.hessian(&load, &k).unwrap();
            fnv(&mut h, e);
            for x in g.iter().chain(hess.iter()) {
                fnv(&mut h, *x);
            }
        }
        if cfg!(all(target_arch = "x86_64", target_os = "linux")) {
            assert_eq!(h, want, "{name}, plane strain {plane_strain}");
        }
    }
}

#[test]
fn an_empty_list_is_no_ribs_and_the_scene_echo_is_unchanged() {
    let none = Scene::from_toml("[load]\npressure_kpa = 40\n").unwrap();
    let empty =
        Scene::from_toml("[load]\npressure_kpa = 40\n[actuator.cl_ribs]\nlist = []\n").unwrap();
    assert_eq!(none.actuator, empty.actuator);
    assert_eq!(none.actuator, Actuator::default());
    let (a, b) = (none.solve().unwrap(), empty.solve().unwrap());
    assert_eq!(a.solution().coefficients, b.solution().coefficients);
    assert_eq!(a.solution().tip, b.solution().tip);
    // a scene without the table writes none back (its output files stay)
    let echo = none.file().to_toml().unwrap();
    assert!(!echo.contains("cl_ribs"), "{echo}");
    assert!(empty.file().to_toml().unwrap().contains("cl_ribs"));
    // the material partition gets no new cuts
    let cut = |a: &Actuator| Partition::material(a, true, 110.0 / 8.0).unwrap();
    assert_eq!(cut(&none.actuator), cut(&Actuator::default()));
}

/// The geometry whose constraining layer is `hr` thicker: the laminate
/// grows by hr at the top, so about its new mid-plane every old height z
/// is z - hr / 2 (the rib's top H/2 + hr is the new H'/2).
fn thicker(plane_strain: bool, hr: f64) -> Actuator {
    let mut p = params(plane_strain, Vec::new());
    let d = hr / 2.0;
    let g = &mut p.geometry;
    (g.h, g.h1, g.h2, g.h3) = (g.h + hr, g.h1 - d, g.h2 - d, g.h3 + d);
    p.channel.h3a -= d;
    p.channel.h3b += d;
    Actuator::new(p).unwrap()
}

/// The unknowns of `model` named.
fn slot(model: ModelId, name: &str) -> Option<usize> {
    model.info().unknowns.iter().position(|u| *u == name)
}

/// K in the thicker geometry's variables: the strain at the same material
/// point is the same when a1' = a1 - 2 delta c2 (z = z' + delta).
fn shifted(model: ModelId, k: &Coefficients, delta: f64) -> Coefficients {
    let (a1, c2) = (slot(model, "a1").unwrap(), slot(model, "c2").unwrap());
    let n = k.per_element();
    let mut v = k.as_slice().to_vec();
    for e in v.chunks_mut(n) {
        e[a1] -= 2.0 * delta * e[c2];
    }
    Coefficients::new(n, v).unwrap()
}

fn random_state(model: ModelId, elements: usize, rng: &mut fastrand::Rng) -> Coefficients {
    let n = model.info().unknowns.len();
    let scale = |name: &str| match name {
        "a1" | "b1" | "g0" => 0.05,
        "a2" => 0.002,
        "a3" => 1e-5,
        "c2" => 2e-3,
        _ => 0.0,
    };
    let mut v = Vec::new();
    for _ in 0..elements {
        for name in model.info().unknowns {
            v.push(scale(name) * (2.0 * rng.f64() - 1.0));
        }
    }
    Coefficients::new(n, v).unwrap()
}

#[test]
fn a_rib_over_the_whole_finger_is_a_thicker_constraining_layer() {
    let hr = 0.5;
    let part = Partition::equal(110.0, 8).unwrap();
    let load = Load::unloaded().with_pressure_kpa(30.0);
    let mut rng = fastrand::Rng::with_seed(25);
    for &model in ModelId::ALL {
        for plane_strain in [false, true] {
            let ribbed =
                Actuator::new(params(plane_strain, vec![rib(0.0, 110.0, 31.75, hr)])).unwrap();
            let a = Finger::with_model(model, &ribbed, &part, true);
            let b = Finger::with_model(model, &thicker(plane_strain, hr), &part, true);
            let what = format!("{}, plane strain {plane_strain}", model.name());
            // the same energy at any state
            for _ in 0..5 {
                let k = random_state(model, 8, &mut rng);
                let (ea, eb) = (
                    a.energy(&load, &k).unwrap(),
                    b.energy(&load, &shifted(model, &k, hr / 2.0)).unwrap(),
                );
                assert!(
                    (ea - eb).abs() <= 1e-12 * ea.abs().max(1.0),
                    "{what}: {ea} against {eb}"
                );
            }
            // the same equilibrium, solved through the ordinary path
            let opts = SolveOptions::default();
            let (sa, sb) = (
                a.solve(&load, &opts).unwrap(),
                b.solve(&load, &opts).unwrap(),
            );
            let mapped = shifted(model, &sa.coefficients, hr / 2.0);
            for (x, y) in mapped.as_slice().iter().zip(sb.coefficients.as_slice()) {
                assert!(
                    (x - y).abs() <= 1e-10 * (1.0 + y.abs()),
                    "{what}: {x} against {y}"
                );
            }
            assert!(
                (sa.energy - sb.energy).abs() <= 1e-10 * sa.energy.abs(),
                "{what}"
            );
        }
    }
}

/// 4-point Gauss-Legendre on [a, b]: exact for the quartic in x and the
/// quadratic in z of the densities.
fn gauss(a: f64, b: f64, f: impl Fn(f64) -> f64) -> f64 {
    let s = (30.0_f64).sqrt();
    let x = [
        ((3.0 - 2.0 * (6.0 / 5.0_f64).sqrt()) / 7.0).sqrt(),
        ((3.0 + 2.0 * (6.0 / 5.0_f64).sqrt()) / 7.0).sqrt(),
    ];
    let w = [(18.0 + s) / 36.0, (18.0 - s) / 36.0];
    let (m, h) = ((a + b) / 2.0, (b - a) / 2.0);
    let mut sum = 0.0;
    for i in 0..2 {
        sum += w[i] * (f(m - h * x[i]) + f(m + h * x[i]));
    }
    h * sum
}

/// The rib box's energy at one element's state `k` (the element's own x
/// in [x0, x1]), from the densities written out: the axial strain of (M2)
/// and (M32), u' = a1 + 2 a2 x + 3 a3 x^2, w' = 2 c2 x + g0, the bending
/// strain -2 c2 z, the plane-stress density (M4) of polypropylene
/// (E = 305, nu = 0.43) and the shear energy of (M33) with G13 =
/// E / (2 (1 + nu)), ks = 5/6.
fn rib_box_energy(model: ModelId, k: &[f64], r: &ClRib, z0: f64, plane_strain: bool) -> f64 {
    let get = |name: &str| slot(model, name).map_or(0.0, |i| k[i]);
    let (a1, a2, a3, b1, c2, g0) = (
        get("a1"),
        get("a2"),
        get("a3"),
        get("b1"),
        get("c2"),
        get("g0"),
    );
    let (e, nu) = (305.0, 0.43);
    let q11 = e / (1.0 - nu * nu);
    let (q12, q22) = (nu * q11, q11);
    let g13 = e / (2.0 * (1.0 + nu));
    let ey = if plane_strain { 0.0 } else { b1 };
    let density = |x: f64, z: f64| {
        let wp = 2.0 * c2 * x + g0;
        let ex = a1 + 2.0 * a2 * x + 3.0 * a3 * x * x + 0.5 * wp * wp - 2.0 * c2 * z;
        0.5 * q11 * ex * ex
            + q12 * ex * ey
            + 0.5 * q22 * ey * ey
            + 0.5 * (5.0 / 6.0) * g13 * g0 * g0
    };
    r.width * gauss(r.x0, r.x1, |x| gauss(z0, z0 + r.height, |z| density(x, z)))
}

#[test]
fn an_element_stores_the_rib_box_energy() {
    let part = Partition::equal(110.0, 1).unwrap();
    let top = 8.2 / 2.0;
    let box_ = rib(20.0, 50.0, 10.0, 0.7);
    let mut rng = fastrand::Rng::with_seed(3);
    for &model in ModelId::ALL {
        for plane_strain in [false, true] {
            let with = Actuator::new(params(plane_strain, vec![box_])).unwrap();
            let without = Actuator::new(params(plane_strain, Vec::new())).unwrap();
            let fw = Finger::with_model(model, &with, &part, true);
            let fo = Finger::with_model(model, &without, &part, true);
            let what = format!("{}, plane strain {plane_strain}", model.name());
            for load in [Load::unloaded(), Load::unloaded().with_pressure_kpa(20.0)] {
                for _ in 0..4 {
                    let mut k = random_state(model, 1, &mut rng);
                    if plane_strain {
                        // a state of plane strain: the width strain held
                        // (the runtime's pin on b1, 1/2 c b1^2 with c the
                        // element's own stiffness, is no energy of the rib)
                        k.as_mut_slice()[slot(model, "b1").unwrap()] = 0.0;
                    }
                    let added = fw.energy(&load, &k).unwrap() - fo.energy(&load, &k).unwrap();
                    let want = rib_box_energy(model, k.element(0), &box_, top, plane_strain);
                    assert!(
                        (added - want).abs() <= 1e-9 * want.abs(),
                        "{what}: {added} against {want}"
                    );
                }
            }
            // a pure curvature kappa = 2 c2 (the membrane's x^2 term
            // cancelled by a3 = -2 c2^2 / 3): E b l (z1^3 - z0^3) kappa^2 / 6
            // with E the plane-stress Q11 (the width strain is zero here)
            let c2 = 1e-3;
            let mut v = vec![0.0; model.info().unknowns.len()];
            v[slot(model, "c2").unwrap()] = c2;
            v[slot(model, "a3").unwrap()] = -2.0 * c2 * c2 / 3.0;
            let k = Coefficients::new(v.len(), v).unwrap();
            let load = Load::unloaded();
            let added = fw.energy(&load, &k).unwrap() - fo.energy(&load, &k).unwrap();
            let q11 = 305.0 / (1.0 - 0.43 * 0.43);
            let (z0, z1) = (top, top + box_.height);
            let kappa = 2.0 * c2;
            let closed = q11 * box_.width * 30.0 * (z1.powi(3) - z0.powi(3)) * kappa * kappa / 6.0;
            assert!(
                (added - closed).abs() <= 1e-9 * closed,
                "{what}: {added} against {closed}"
            );
        }
    }
}

/// Ribs over the channel's transverse ribs (centres 8k mm, 2 mm long)
/// across the whole width, of the given height.
fn transverse(height: f64) -> Vec<ClRib> {
    (1..=13)
        .map(|k| {
            let c = 8.0 * f64::from(k);
            rib(c - 1.0, c + 1.0, 31.75, height)
        })
        .collect()
}

#[test]
fn taller_ribs_curl_the_finger_less() {
    for &model in ModelId::ALL {
        for plane_strain in [false, true] {
            let mut last = [0.0; 2];
            for height in [0.0, 0.2, 0.5, 1.0, 2.0] {
                let ribs = if height > 0.0 {
                    transverse(height)
                } else {
                    Vec::new()
                };
                let mut p = params(plane_strain, ribs);
                p.pemc.eps0 = 0.15;
                let act = Actuator::new(p).unwrap();
                let part = Partition::material(&act, true, 110.0 / 8.0).unwrap();
                let finger = Finger::with_model(model, &act, &part, true);
                for (i, kpa) in [0.0, 100.0].into_iter().enumerate() {
                    let sol = finger
                        .solve(
                            &Load::unloaded().with_pressure_kpa(kpa),
                            &SolveOptions::default(),
                        )
                        .unwrap();
                    let r = sol.radius.expect("curled");
                    assert!(
                        r > last[i],
                        "{}, plane strain {plane_strain}, {kpa} kPa: height {height} gives R {r}, not above {}",
                        model.name(),
                        last[i]
                    );
                    last[i] = r;
                }
            }
        }
    }
}

#[test]
fn the_rib_ends_cut_the_material_partition() {
    let act = Actuator::new(params(false, vec![rib(3.3, 4.1, 5.0, 1.0)])).unwrap();
    // without the channel's ribs: the channel's end and the rib's ends
    let part = Partition::material(&act, false, 200.0).unwrap();
    let mut ends = vec![0.0];
    for l in part.lengths() {
        ends.push(ends.last().unwrap() + l);
    }
    for x in [3.3, 4.1, 105.0, 110.0] {
        assert!(
            ends.iter().any(|e| (e - x).abs() < 1e-12),
            "{x} is no element end: {ends:?}"
        );
    }
    assert_eq!(part.len(), 4);
}

#[test]
fn the_thickness_finding_counts_the_tallest_rib() {
    // H = 8.2 against lx = 110: within the length limit 0.1 until a rib
    // makes the section thicker than 11 mm
    let thick = |ribs: Vec<ClRib>| {
        Actuator::new(params(false, ribs))
            .unwrap()
            .warnings()
            .iter()
            .any(|w| matches!(w, fpc::Warning::ThicknessRatio { .. }))
    };
    assert!(!thick(Vec::new()));
    assert!(!thick(vec![rib(10.0, 12.0, 5.0, 2.5)]));
    assert!(thick(vec![
        rib(10.0, 12.0, 5.0, 2.5),
        rib(20.0, 22.0, 5.0, 3.0)
    ]));
}

fn library_error(r: ClRib) -> String {
    let e = Actuator::new(params(false, vec![rib(60.0, 62.0, 1.0, 0.3), r])).unwrap_err();
    e.field().to_string()
}

#[test]
fn bad_ribs_are_typed_errors_naming_the_key() {
    let cases = [
        (
            rib(10.0, 12.0, 5.0, -0.1),
            "actuator.cl_ribs.list[1].height",
        ),
        (rib(10.0, 12.0, 5.0, 0.0), "actuator.cl_ribs.list[1].height"),
        (
            rib(10.0, 12.0, 5.0, f64::INFINITY),
            "actuator.cl_ribs.list[1].height",
        ),
        (rib(10.0, 12.0, 5.0, 2e5), "actuator.cl_ribs.list[1].height"),
        (rib(12.0, 12.0, 5.0, 1.0), "actuator.cl_ribs.list[1].x1"),
        (rib(12.0, 10.0, 5.0, 1.0), "actuator.cl_ribs.list[1].x1"),
        (rib(-1.0, 10.0, 5.0, 1.0), "actuator.cl_ribs.list[1].x0"),
        (rib(f64::NAN, 10.0, 5.0, 1.0), "actuator.cl_ribs.list[1].x0"),
        (rib(100.0, 111.0, 5.0, 1.0), "actuator.cl_ribs.list[1].x1"),
        (rib(10.0, 12.0, 32.0, 1.0), "actuator.cl_ribs.list[1].width"),
        (rib(10.0, 12.0, 0.0, 1.0), "actuator.cl_ribs.list[1].width"),
        (
            rib(10.0, 12.0, f64::NAN, 1.0),
            "actuator.cl_ribs.list[1].width",
        ),
        // beside the first one, wider than the strip together
        (rib(61.0, 63.0, 31.0, 1.0), "actuator.cl_ribs"),
    ];
    for (r, key) in cases {
        assert_eq!(library_error(r), key, "{r:?}");
    }
    let many = vec![rib(1.0, 2.0, 0.001, 0.1); MAX_CL_RIBS + 1];
    let e = Actuator::new(params(false, many)).unwrap_err();
    assert_eq!(*e.field(), Field::ClRibs);
    assert_eq!(
        Field::ClRib(2, ClRibKey::Height).to_string(),
        "actuator.cl_ribs.list[2].height"
    );
}

#[test]
fn bad_ribs_in_a_scene_name_the_scene_key() {
    let scene = |list: &str| {
        format!(
            "[actuator.cl_ribs]\nlist = [{{ x0 = 1, x1 = 3, width = 4, height = 1 }}, {list}]\n"
        )
    };
    for (entry, key) in [
        (
            "{ x0 = 5, x1 = 6, width = 4, height = -1 }",
            "actuator.cl_ribs.list[1].height",
        ),
        (
            "{ x0 = 7, x1 = 6, width = 4, height = 1 }",
            "actuator.cl_ribs.list[1].x1",
        ),
        (
            "{ x0 = 5, x1 = 200, width = 4, height = 1 }",
            "actuator.cl_ribs.list[1].x1",
        ),
        (
            "{ x0 = 5, x1 = 6, width = 40, height = 1 }",
            "actuator.cl_ribs.list[1].width",
        ),
        (
            "{ x0 = 2, x1 = 6, width = 30, height = 1 }",
            "actuator.cl_ribs",
        ),
    ] {
        match Scene::from_toml(&scene(entry)) {
            Err(fpc::scene::SceneReadError::Input(e)) => {
                assert_eq!(e.field().to_string(), key, "{entry}");
            }
            other => panic!("{entry}: expected an input error, got {other:?}"),
        }
    }
    // a missing or unknown key is a syntax error with its place
    for entry in [
        "{ x0 = 5, x1 = 6, width = 4 }",
        "{ x0 = 5, x1 = 6, width = 4, height = 1, depth = 2 }",
    ] {
        match Scene::from_toml(&scene(entry)) {
            Err(fpc::scene::SceneReadError::Syntax(e)) => assert_eq!(e.line, 2, "{e}"),
            other => panic!("{entry}: expected a syntax error, got {other:?}"),
        }
    }
    // a good scene solves with every model, in plane strain too
    for model in ModelId::names() {
        let text = format!(
            "[model]\nname = \"{model}\"\n[actuator.laminate]\nplane_strain = true\n[load]\npressure_kpa = 30\nfx = 0.2\n{}",
            scene("{ x0 = 50, x1 = 60, width = 20, height = 0.5 }")
        );
        let s = Scene::from_toml(&text).unwrap();
        assert_eq!(s.actuator.cl_ribs().len(), 2);
        let sol = s.solve().unwrap();
        assert!(sol.solution().tip.iter().all(|x| x.is_finite()), "{model}");
    }
}
