//! Plane strain across the width (`actuator.laminate.plane_strain`,
//! docs/model.md section 4.9) against closed forms, for every model:
//!
//! - a strip (nu = 0.4 in its linear layers) pulled along its axis and
//!   bent by a tip force, against the section's stiffness integrated by
//!   hand in (e0, kappa, eps_y): under plane stress the width strain is
//!   free (its resultant zero), under plane strain it is held at zero;
//!   the tip moves by e0 L when pulled and by P L^3 / 3 times the bending
//!   compliance when bent (+ P L / (ks G A) for the shear model);
//! - the transverse strain of a plane-strain solution is exactly zero, and
//!   plane strain is stiffer than plane stress on the paper's finger.

use fpc::actuator::{
    Channel, Geometry, Isotropic, Prestressed, PsiLaw, Rib, RibLayout, TransverseShear,
};
use fpc::{Actuator, ActuatorParams, Finger, Load, ModelId, Partition, SolveOptions};

/// A homogeneous strip: every layer isotropic (e, nu), the prestressed one
/// linear (eps0 = 0, psi = e s^2 / 2, its E2 = e: no Poisson coupling,
/// which the paper's law does not have), the channel filled by a rib.
fn strip(e: f64, nu: f64, plane_strain: bool) -> Actuator {
    let (lx, b, h) = (40.0, 10.0, 4.0);
    let params = ActuatorParams {
        geometry: Geometry {
            lx,
            ly: b,
            lc: 0.0,
            h,
            h1: 1.5,
            h2: 0.5,
            h3: 1.5,
        },
        channel: Channel {
            cx: lx,
            cy: 5.0,
            h3a: 0.25,
            h3b: 0.75,
        },
        ribs: RibLayout::Explicit(vec![Rib {
            x0: 0.0,
            x1: lx,
            width: 5.0,
        }]),
        cl: Isotropic { e, nu }.into(),
        emc: Isotropic { e, nu }.into(),
        fluidic: Isotropic { e, nu }.into(),
        pemc: Prestressed {
            e2: e,
            law: PsiLaw {
                p1: e,
                p2: 0.0,
                p3: 0.0,
                p4: 0.0,
            },
            eps0: 0.0,
        },
        shear: TransverseShear::default(),
        plane_strain,
        cl_ribs: Vec::new(),
    };
    Actuator::new(params).expect("a valid strip")
}

/// The tip's displacement under the tip force (fx, fz), from rest.
fn tip_move(model: ModelId, act: &Actuator, n: usize, fx: f64, fz: f64) -> [f64; 2] {
    let part = Partition::equal(act.geometry().lx, n).unwrap();
    let finger = Finger::with_model(model, act, &part, true);
    let opts = SolveOptions::default();
    let rest = finger.solve(&Load::unloaded(), &opts).unwrap();
    let sol = finger
        .solve(&Load::unloaded().with_tip_force(fx, fz), &opts)
        .unwrap();
    [sol.tip[0] - rest.tip[0], sol.tip[1] - rest.tip[1]]
}

/// The strip's section stiffness per unit length in (e0, kappa, eps_y),
/// eps_x = e0 - z kappa, integrated by hand over its layers: the linear
/// layers over z in [-1.5, 2] (Q11 = Q22 = E / (1 - nu^2), Q12 = nu Q11),
/// the prestressed one over [-2, -1.5] (modulus e along X, E2 = e across,
/// no coupling); width 10.
fn section(e: f64, nu: f64) -> [[f64; 3]; 3] {
    let b = 10.0;
    let q11 = e / (1.0 - nu * nu);
    let q12 = nu * q11;
    let m = |k: i32, z0: f64, z1: f64| (z1.powi(k + 1) - z0.powi(k + 1)) / f64::from(k + 1);
    let (lin, pre) = ((-1.5, 2.0), (-2.0, -1.5));
    let a = b * (q11 * m(0, lin.0, lin.1) + e * m(0, pre.0, pre.1));
    let bb = b * (q11 * m(1, lin.0, lin.1) + e * m(1, pre.0, pre.1));
    let d = b * (q11 * m(2, lin.0, lin.1) + e * m(2, pre.0, pre.1));
    let a12 = b * q12 * m(0, lin.0, lin.1);
    let b12 = b * q12 * m(1, lin.0, lin.1);
    let a22 = b * (q11 * m(0, lin.0, lin.1) + e * m(0, pre.0, pre.1));
    [[a, -bb, a12], [-bb, d, -b12], [a12, -b12, a22]]
}

/// Solves the section's equations for the resultants (N, M) with eps_y
/// free (plane stress: its resultant is zero) or held at zero (plane
/// strain): (e0, kappa).
fn strains(k: [[f64; 3]; 3], n: f64, m: f64, plane_strain: bool) -> (f64, f64) {
    let (k11, k12, k22) = if plane_strain {
        (k[0][0], k[0][1], k[1][1])
    } else {
        // eps_y condensed out
        (
            k[0][0] - k[0][2] * k[0][2] / k[2][2],
            k[0][1] - k[0][2] * k[1][2] / k[2][2],
            k[1][1] - k[1][2] * k[1][2] / k[2][2],
        )
    };
    let det = k11 * k22 - k12 * k12;
    ((k22 * n - k12 * m) / det, (k11 * m - k12 * n) / det)
}

#[test]
fn a_pulled_strip_contracts_across_the_width_only_under_plane_stress() {
    let (e, nu, f, lx): (f64, f64, f64, f64) = (10.0, 0.4, 1e-3, 40.0);
    let k = section(e, nu);
    for &model in ModelId::ALL {
        let mut moves = Vec::new();
        for plane_strain in [false, true] {
            let act = strip(e, nu, plane_strain);
            // a force at the mid-plane: N = f, no moment about z = 0
            let (e0, _) = strains(k, f, 0.0, plane_strain);
            let want = e0 * lx;
            let got = tip_move(model, &act, 4, f, 0.0)[0];
            let err = (got - want).abs() / want;
            println!(
                "{model}, plane strain {plane_strain}: pulled tip moves {got:.9e} mm, closed form {want:.9e}: {err:.1e}"
            );
            assert!(
                err < 1e-5,
                "{model} plane strain {plane_strain}: {got} vs {want}"
            );
            moves.push(got);
        }
        assert!(
            moves[1] < moves[0],
            "{model}: holding the width stiffens the pull"
        );
    }
}

#[test]
fn a_bent_strip_matches_the_sections_bending_stiffness() {
    let (e, nu, p, lx): (f64, f64, f64, f64) = (10.0, 0.4, 1e-4, 40.0);
    let k = section(e, nu);
    for &model in ModelId::ALL {
        for plane_strain in [false, true] {
            let act = strip(e, nu, plane_strain);
            // the bending compliance with no axial force: kappa per unit moment
            let (_, per_moment) = strains(k, 0.0, 1.0, plane_strain);
            let mut want = p * lx.powi(3) / 3.0 * per_moment;
            if model.name() == "shear" {
                // default G13 = E / (2 (1 + nu)) for the linear layers, p1 / 2
                // for the prestressed one, ks = 5/6, width 10
                let ga = 10.0 * (e / (2.0 * (1.0 + nu)) * 3.5 + e / 2.0 * 0.5);
                want += p * lx / (5.0 / 6.0 * ga);
            }
            // second-order convergence in the element length: extrapolated
            let (a, c) = (
                tip_move(model, &act, 16, 0.0, -p)[1],
                tip_move(model, &act, 32, 0.0, -p)[1],
            );
            let got = -(4.0 * c - a) / 3.0;
            let err = (got - want).abs() / want;
            println!(
                "{model}, plane strain {plane_strain}: bent tip {got:.9e} mm, closed form {want:.9e}: {err:.1e}"
            );
            assert!(
                err < 1e-5,
                "{model} plane strain {plane_strain}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn plane_strain_holds_the_width_and_stiffens_the_paper_finger() {
    let load = Load::unloaded()
        .with_pressure_kpa(40.0)
        .with_tip_force(0.3, -0.5);
    for &model in ModelId::ALL {
        let solve_at = |plane_strain: bool, load: &Load| {
            let act = Actuator::new(ActuatorParams {
                plane_strain,
                ..ActuatorParams::default()
            })
            .unwrap();
            let part = Partition::equal(110.0, 8).unwrap();
            Finger::with_model(model, &act, &part, true)
                .solve(load, &SolveOptions::default())
                .unwrap()
        };
        let (stress, strain) = (solve_at(false, &load), solve_at(true, &load));
        let info = model.info();
        let n = info.unknowns.len();
        let b1 = info
            .unknowns
            .iter()
            .position(|u| *u == "b1")
            .expect("every model has b1");
        let k = strain.coefficients.as_slice();
        let ks = stress.coefficients.as_slice();
        for i in 0..8 {
            assert_eq!(k[n * i + b1], 0.0, "{model}: element {i}");
            assert!(ks[n * i + b1] != 0.0, "{model}: element {i}");
        }
        // the pressure and the force move the tip less when the width is held
        let rest = |plane_strain: bool| solve_at(plane_strain, &Load::unloaded()).tip;
        let moved = |tip: [f64; 2], from: [f64; 2]| (tip[0] - from[0]).hypot(tip[1] - from[1]);
        let (d_stress, d_strain) = (
            moved(stress.tip, rest(false)),
            moved(strain.tip, rest(true)),
        );
        println!("{model}: the load moves the tip {d_stress:.4} mm in plane stress, {d_strain:.4} mm in plane strain");
        assert!(d_strain < d_stress, "{model}");
    }
}
