//! The shear-deformable element (`energy-spec/shear.spec`, docs/model.md
//! section 4.8) against closed forms, through the public finger API:
//!
//! - a homogeneous strip clamped at the root and loaded at the tip against
//!   Timoshenko's cantilever, bending plus shear deflection
//!   `P L^3 / (3 E I) + P L / (ks G A)`, with the default shear modulus
//!   and with a soft one (shear then a third of the deflection);
//! - a three-layer strip (stiff faces, soft core) against the sandwich
//!   beam's cantilever deflection `P L^3 / (3 D) + P L / S`, with
//!   `D = Ef b t^3 / 6 + Ef b t d^2 / 2 + Ec b c^3 / 12` and the core's
//!   shear stiffness `S = Gc b d^2 / c` (Allen; d the distance between the
//!   faces' centres, c the core's thickness);
//! - the limit of infinite shear stiffness: the paper's finger under
//!   pressure and a tip force converges to the CCM's solution as the shear
//!   correction factor grows, like its inverse, and is the CCM's to the
//!   solver's tolerance at the end.
//!
//! The strips are the actuator's four layers given one material (the
//! prestressed layer linear: eps0 = 0, psi = p1 s^2 / 2), nu = 0, the
//! channel filled by one rib of the fluidic material, so the section is
//! solid. The loads are small (tip deflection about 1e-4 of the length),
//! so the von Karman terms are negligible; the CCM's constant-curvature
//! elements converge at second order in the element length, so the
//! deflection is extrapolated from N and 2N elements (Richardson) and the
//! error is checked against that of the raw value.

use fpc::actuator::{
    Channel, Geometry, Isotropic, Prestressed, PsiLaw, Rib, RibLayout, TransverseShear,
};
use fpc::{Actuator, ActuatorParams, Finger, Load, ModelId, Partition, SolveOptions};

fn shear_model() -> ModelId {
    ModelId::from_name("shear").expect("the shear-deformable model is generated")
}

/// A strip of length `lx`, width `b`: faces of thickness `t` and modulus
/// `ef` (the constraining layer on top, the prestressed layer below), the
/// core (regular EMC and fluidic layer, channel filled) of thickness `c`
/// and modulus `ec`; nu = 0 everywhere. `shear` sets the shear data.
fn strip(lx: f64, b: f64, t: f64, c: f64, ef: f64, ec: f64, shear: TransverseShear) -> Actuator {
    let h = c + 2.0 * t;
    let half = h / 2.0;
    let (h1, h3) = (half - t, half - t);
    let h2 = h1 - 0.4 * c;
    let channel = Channel {
        cx: lx,
        cy: 0.5 * b,
        h3a: 0.5 * h2,
        h3b: 0.5 * h3,
    };
    let params = ActuatorParams {
        geometry: Geometry {
            lx,
            ly: b,
            lc: 0.0,
            h,
            h1,
            h2,
            h3,
        },
        channel,
        ribs: RibLayout::Explicit(vec![Rib {
            x0: 0.0,
            x1: lx,
            width: channel.cy,
        }]),
        cl: Isotropic { e: ef, nu: 0.0 }.into(),
        emc: Isotropic { e: ec, nu: 0.0 }.into(),
        fluidic: Isotropic { e: ec, nu: 0.0 }.into(),
        pemc: Prestressed {
            e2: ef,
            law: PsiLaw {
                p1: ef,
                p2: 0.0,
                p3: 0.0,
                p4: 0.0,
            },
            eps0: 0.0,
        },
        shear,
        plane_strain: false,
        cl_ribs: Vec::new(),
    };
    Actuator::new(params).expect("a valid strip")
}

/// The tip's deflection under the tip force `p` (along -Z) with `n` equal
/// elements.
fn tip_deflection(model: ModelId, act: &Actuator, n: usize, p: f64) -> f64 {
    let part = Partition::equal(act.geometry().lx, n).unwrap();
    let finger = Finger::with_model(model, act, &part, true);
    let at_rest = finger
        .solve(&Load::unloaded(), &SolveOptions::default())
        .unwrap();
    let sol = finger
        .solve(
            &Load::unloaded().with_tip_force(0.0, -p),
            &SolveOptions::default(),
        )
        .unwrap();
    at_rest.tip[1] - sol.tip[1]
}

/// The deflection with `n` and `2 n` elements, extrapolated to zero
/// element length (second order), and the raw value with `2 n`.
fn extrapolated(model: ModelId, act: &Actuator, n: usize, p: f64) -> (f64, f64) {
    let (a, b) = (
        tip_deflection(model, act, n, p),
        tip_deflection(model, act, 2 * n, p),
    );
    ((4.0 * b - a) / 3.0, b)
}

#[test]
fn homogeneous_strip_matches_timoshenkos_cantilever() {
    let (lx, b, t, c, e): (f64, f64, f64, f64, f64) = (40.0, 10.0, 1.5, 5.0, 10.0);
    let h = c + 2.0 * t;
    let ei = e * b * h.powi(3) / 12.0;
    let p = 1e-3;
    for (label, g13) in [("default G = E/2", None), ("soft G = E/40", Some(e / 40.0))] {
        let shear = TransverseShear {
            g13: [g13; 4],
            ..TransverseShear::default()
        };
        let ks = shear.correction;
        let g = g13.unwrap_or(e / 2.0);
        let act = strip(lx, b, t, c, e, e, shear);
        let bending = p * lx.powi(3) / (3.0 * ei);
        let shearing = p * lx / (ks * g * b * h);
        let want = bending + shearing;
        let (got, raw) = extrapolated(shear_model(), &act, 16, p);
        let err = (got - want).abs() / want;
        let raw_err = (raw - want).abs() / want;
        println!(
            "Timoshenko cantilever, {label}: {got:.9e} mm vs {want:.9e} (bending {bending:.4e}, \
             shear {shearing:.4e}): relative error {err:.1e} (32 elements raw {raw_err:.1e})"
        );
        assert!(err < 2e-5, "{label}: {got} vs {want}");
        // the shear term is resolved: far more than the error
        assert!(shearing / want > 100.0 * err, "{label}");
        // the CCM misses exactly the shear term
        let (ccm, _) = extrapolated(ModelId::Ccm, &act, 16, p);
        let ccm_err = (ccm - bending).abs() / bending;
        assert!(ccm_err < 2e-5, "{label}: CCM {ccm} vs {bending}");
    }
}

#[test]
fn three_layer_strip_matches_the_sandwich_beam() {
    // stiff faces, soft core: shear is most of the deflection
    let (lx, b, t, c, ef, ec): (f64, f64, f64, f64, f64, f64) = (60.0, 10.0, 0.5, 6.0, 1000.0, 1.0);
    let d = c + t;
    let gc = ec / 2.0;
    // the sandwich's core alone carries the shear, with the faces' distance:
    // in first-order shear deformation, faces that do not shear and ks =
    // d^2 / c^2 over the core's thickness
    let ks = d * d / (c * c);
    let shear = TransverseShear {
        correction: ks,
        g13: [Some(1e-9 * gc), None, None, Some(1e-9 * gc)],
    };
    let act = strip(lx, b, t, c, ef, ec, shear);
    let dd = ef * b * t.powi(3) / 6.0 + ef * b * t * d * d / 2.0 + ec * b * c.powi(3) / 12.0;
    let s = gc * b * d * d / c;
    let p = 1e-3;
    let (bending, shearing) = (p * lx.powi(3) / (3.0 * dd), p * lx / s);
    let want = bending + shearing;
    let (got, raw) = extrapolated(shear_model(), &act, 16, p);
    let err = (got - want).abs() / want;
    let raw_err = (raw - want).abs() / want;
    println!(
        "sandwich cantilever: {got:.9e} mm vs {want:.9e} (bending {bending:.4e}, shear \
         {shearing:.4e}): relative error {err:.1e} (32 elements raw {raw_err:.1e})"
    );
    assert!(shearing > bending, "the case is shear-dominated");
    assert!(err < 2e-5, "{got} vs {want}");
}

#[test]
fn infinite_shear_stiffness_is_the_ccm() {
    let load = Load::unloaded()
        .with_pressure_kpa(40.0)
        .with_tip_force(0.3, -0.5);
    let options = SolveOptions {
        rtol: 1e-13,
        ..SolveOptions::default()
    };
    let n = 8;
    let act = Actuator::paper(0.25).unwrap();
    let part = Partition::equal(act.geometry().lx, n).unwrap();
    let ccm = Finger::with_model(ModelId::Ccm, &act, &part, true)
        .solve(&load, &options)
        .unwrap();
    let scale = ccm.tip[0].hypot(ccm.tip[1]);
    let mut gaps = Vec::new();
    let mut tips = Vec::new();
    for ks in [1e1, 1e2, 1e3, 1e4] {
        let mut params = act.params().clone();
        params.shear.correction = ks;
        let stiff = Actuator::new(params).unwrap();
        let sol = Finger::with_model(shear_model(), &stiff, &part, true)
            .solve(&load, &options)
            .unwrap();
        let gap = (sol.tip[0] - ccm.tip[0]).hypot(sol.tip[1] - ccm.tip[1]) / scale;
        // the CCM's unknowns, element by element (the shear model's fifth
        // is its shear strain)
        let (k, kc) = (sol.coefficients.as_slice(), ccm.coefficients.as_slice());
        let mut coefficient_gap: f64 = 0.0;
        let mut strain: f64 = 0.0;
        for i in 0..n {
            for j in 0..4 {
                let (a, c) = (k[5 * i + j], kc[4 * i + j]);
                coefficient_gap = coefficient_gap.max((a - c).abs() / c.abs().max(1e-3));
            }
            strain = strain.max(k[5 * i + 4].abs());
        }
        println!(
            "ks = {ks:.0e}: tip {:?} vs CCM {:?}, relative gap {gap:.2e}, unknowns {coefficient_gap:.1e}, \
             largest shear strain {strain:.1e}",
            sol.tip, ccm.tip
        );
        gaps.push((ks, gap, coefficient_gap));
        tips.push(sol.tip);
    }
    // the shear compliance, and with it the gap, falls like 1/ks ...
    for w in gaps.windows(2) {
        let ratio = w[1].1 / w[0].1;
        assert!(
            (0.07..0.14).contains(&ratio),
            "ks {} -> {}: gap {} -> {} (ratio {ratio})",
            w[0].0,
            w[1].0,
            w[0].1,
            w[1].1
        );
    }
    // ... to the solver's tolerance: at ks = 1e4 the shear model is the CCM
    // to 1e-8 of the tip's distance (the solver's rtol on the tip is 1e-8
    // by default); stiffer still, the shear direction's stiffness swamps
    // the others in the solver's scaling and the comparison measures the
    // conditioning, not the model
    let (_, gap, unknowns) = gaps[gaps.len() - 1];
    assert!(gap < 2e-8, "{gap}");
    assert!(unknowns < 5e-8, "{unknowns}");
    // the limit itself, extrapolated in 1/ks from the last two: the CCM's
    // tip to the solver's tolerance
    let [a, b] = [tips[tips.len() - 2], tips[tips.len() - 1]];
    let limit = [(10.0 * b[0] - a[0]) / 9.0, (10.0 * b[1] - a[1]) / 9.0];
    let gap = (limit[0] - ccm.tip[0]).hypot(limit[1] - ccm.tip[1]) / scale;
    println!("ks -> infinity (extrapolated): tip {limit:?}, relative gap to the CCM {gap:.1e}");
    assert!(gap < 1e-9, "{gap}");
}

#[test]
fn the_paper_finger_shears_a_little() {
    // the default shear data on the paper's finger: a tip force bends it
    // a little more than the CCM says, and pressure alone (no shear force)
    // about as much
    let act = Actuator::paper(0.25).unwrap();
    let part = Partition::equal(act.geometry().lx, 8).unwrap();
    let options = SolveOptions::default();
    let solve = |model, load: &Load| {
        Finger::with_model(model, &act, &part, true)
            .solve(load, &options)
            .unwrap()
    };
    let pressure = Load::unloaded().with_pressure_kpa(40.0);
    let (a, b) = (
        solve(ModelId::Ccm, &pressure),
        solve(shear_model(), &pressure),
    );
    let gap = (a.tip[0] - b.tip[0]).hypot(a.tip[1] - b.tip[1]);
    println!(
        "40 kPa: CCM tip {:?}, shear tip {:?}, gap {gap:.2e} mm",
        a.tip, b.tip
    );
    assert!(gap < 1e-3, "{gap}");
    // a tip force across the finger at rest: the difference of the
    // deflections is the shear's, of the order of P L / (ks G A)
    let rest = Load::unloaded();
    let push = Load::unloaded().with_tip_force(0.0, -0.2);
    let deflection = |model| {
        let (r, s) = (solve(model, &rest), solve(model, &push));
        (s.tip[0] - r.tip[0]).hypot(s.tip[1] - r.tip[1])
    };
    let (ccm, shear) = (deflection(ModelId::Ccm), deflection(shear_model()));
    println!("0.2 N at the tip: CCM moves it {ccm:.4} mm, the shear model {shear:.4} mm");
    assert!(shear > ccm, "{shear} vs {ccm}");
    assert!(shear < 1.2 * ccm, "{shear} vs {ccm}");
}
