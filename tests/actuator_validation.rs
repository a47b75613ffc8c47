//! The actuator's defaults and validation rules and the partition, checked
//! against values computed here by hand. (The integration blocks are
//! crate-private; their checks live in `src/actuator/blocks.rs`'s test module.)

use fpc::actuator::{Isotropic, Material, Orthotropic, Rib, RibLayout, MAX_LISTED_RIBS};
use fpc::model::ccm::Ccm;
use fpc::model::Energy;
use fpc::model::PsiParams;
use fpc::{Actuator, ActuatorParams, Finger, InputError, Partition, Warning};

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
}

/// Validation of the default parameters after `edit` must fail.
fn rejected(edit: impl FnOnce(&mut ActuatorParams)) -> InputError {
    let mut p = ActuatorParams::default();
    edit(&mut p);
    match Actuator::new(p) {
        Ok(_) => panic!("accepted invalid input"),
        Err(e) => e,
    }
}

/// The error names `field`, and its message names the field and `value`.
fn names(e: &InputError, field: &str, value: &str) {
    let msg = e.to_string();
    assert_eq!(e.field(), field, "{msg}");
    assert!(msg.starts_with(&format!("{field} = {value}:")), "{msg}");
    assert!(!msg.contains('\n'), "{msg}");
}

/// An edit of the default parameters, the field its error names and the
/// value as written.
type Rejection = (fn(&mut ActuatorParams), &'static str, &'static str);

/// Every edit is rejected with an error naming its field and value.
fn all_rejected(cases: &[Rejection]) {
    for &(edit, field, value) in cases {
        names(&rejected(edit), field, value);
    }
}

// ---------------------------------------------------------------- defaults

#[test]
fn default_ribs_follow_d5() {
    let act = Actuator::default();
    let ribs = act.ribs();
    assert_eq!(
        ribs[0],
        Rib {
            x0: 0.0,
            x1: 105.0,
            width: 2.0
        }
    );
    let transverse = &ribs[1..];
    assert_eq!(transverse.len(), 13);
    for (i, r) in transverse.iter().enumerate() {
        let centre = 8.0 * (i + 1) as f64;
        assert_eq!(r.x0, centre - 1.0);
        assert_eq!(r.x1, centre + 1.0);
        assert_eq!(r.width, 12.0);
    }
    assert_eq!(
        transverse[12].x1, 105.0,
        "the last rib touches the channel's end"
    );
}

#[test]
fn default_stiffnesses_by_hand() {
    let act = Actuator::default();
    let [cl, emc, fl] = act.linear_layers();
    let d = 1.0 - 0.43 * 0.43;
    assert!(close(cl.q.q11, 305.0 / d, 1e-14));
    assert!(close(cl.q.q22, 305.0 / d, 1e-14));
    assert!(close(cl.q.q12, 0.43 * 305.0 / d, 1e-14));
    assert_eq!((emc.q.q11, emc.q.q12, emc.q.q22), (1.5, 0.0, 250.0));
    let d = 1.0 - 0.48 * 0.48;
    assert!(close(fl.q.q11, 1.2 / d, 1e-14));
    assert!(close(fl.q.q12, 0.48 * 1.2 / d, 1e-14));
    assert_eq!(act.fluidic_q(), fl.q);
    assert_eq!(act.pemc().q22(), 250.0);
    assert_eq!(act.eps0(), 0.25);
    assert!(act.warnings().is_empty());
}

#[test]
fn orthotropic_with_poisson_coupling() {
    let m = Orthotropic {
        e1: 10.0,
        e2: 5.0,
        nu12: 0.3,
    };
    // nu21 = 0.3 * 5 / 10 = 0.15, D = 1 - 0.045.
    let d = 0.955;
    let q = m.q();
    assert!(close(m.nu21(), 0.15, 1e-15));
    assert!(close(q.q11, 10.0 / d, 1e-14));
    assert!(close(q.q22, 5.0 / d, 1e-14));
    assert!(close(q.q12, 1.5 / d, 1e-14));
    // Reciprocity: Q12 = nu21 Q11 as well.
    assert!(close(q.q12, m.nu21() * q.q11, 1e-14));
}

#[test]
fn layers_stack_up_to_h() {
    let act = Actuator::default();
    let [cl, emc, fl] = act.linear_layers();
    let (p0, p1) = act.pemc_z();
    assert_eq!(p0, -4.1);
    assert_eq!(p1, fl.z0);
    assert_eq!(fl.z1, emc.z0);
    assert_eq!(emc.z1, cl.z0);
    assert_eq!(cl.z1, 4.1);
    let thick = [cl.z1 - cl.z0, emc.z1 - emc.z0, fl.z1 - fl.z0, p1 - p0];
    for (t, want) in thick.iter().zip([0.4, 1.9, 4.0, 1.9]) {
        assert!(close(*t, want, 1e-14), "{t} != {want}");
    }
    assert!(close(thick.iter().sum::<f64>(), 8.2, 1e-14));
}

#[test]
fn psi_law_stress_is_the_energy_derivative() {
    let law = Actuator::default().pemc().law;
    assert_eq!(law.to_array(), [1.598, 2.306, 2.29, 0.698]);
    assert_eq!(law, PsiParams::default());
    // the law is generated from the spec: [psi, psi', psi''] at s
    let energy = |s: f64| Ccm::psi(s, &law)[0];
    let stress = |s: f64| Ccm::psi(s, &law)[1];
    let tangent = |s: f64| Ccm::psi(s, &law)[2];
    let s = 0.3_f64;
    let by_hand = 1.598 / 2.0 * s.powi(2) - 2.306 / 3.0 * s.powi(3) + 2.29 / 4.0 * s.powi(4)
        - 0.698 / 5.0 * s.powi(5);
    assert!(close(energy(s), by_hand, 1e-14));
    for s in [-0.2, 0.0, 0.15, 0.4, 0.6] {
        let h = 1e-6;
        let fd = (energy(s + h) - energy(s - h)) / (2.0 * h);
        assert!(close(stress(s), fd, 1e-8), "stress at {s}");
        let fd = (stress(s + h) - stress(s - h)) / (2.0 * h);
        assert!(close(tangent(s), fd, 1e-8), "tangent at {s}");
    }
    assert_eq!(tangent(0.0), 1.598);
}

#[test]
fn paper_and_with_eps0() {
    let a = Actuator::paper(0.4).unwrap();
    assert_eq!(a.eps0(), 0.4);
    let b = Actuator::default().with_eps0(0.4).unwrap();
    assert_eq!(a, b);
    names(
        &Actuator::paper(f64::NAN).unwrap_err(),
        "actuator.pemc.eps0",
        "NaN",
    );
}

// ------------------------------------------------------------ validation

#[test]
fn geometry_rules() {
    let e = rejected(|p| p.geometry.h1 = -3.0);
    names(&e, "actuator.geometry.h1", "-3");
    assert_eq!(e.to_string(), "actuator.geometry.h1 = -3: must be positive");
    assert!(matches!(e, InputError::NotPositive { .. }));

    let e = rejected(|p| p.geometry.lx = f64::NAN);
    names(&e, "actuator.geometry.lx", "NaN");
    assert!(matches!(e, InputError::NotFinite { .. }));
    all_rejected(&[
        (|p| p.geometry.lx = -110.0, "actuator.geometry.lx", "-110"),
        (|p| p.geometry.ly = 0.0, "actuator.geometry.ly", "0"),
        (|p| p.geometry.lc = -1.0, "actuator.geometry.lc", "-1"),
        (
            |p| p.geometry.lc = f64::INFINITY,
            "actuator.geometry.lc",
            "inf",
        ),
        (|p| p.geometry.h = 0.0, "actuator.geometry.h", "0"),
        (|p| p.geometry.h2 = -1.0, "actuator.geometry.h2", "-1"),
        (|p| p.geometry.h3 = 0.0, "actuator.geometry.h3", "0"),
    ]);
}

#[test]
fn layer_stack_rules() {
    // CL with no thickness: h1 = H/2.
    let e = rejected(|p| p.geometry.h1 = 4.1);
    names(&e, "actuator.geometry.h1", "4.1");
    assert!(e.to_string().contains("H/2"));
    // Regular EMC upside down.
    let e = rejected(|p| p.geometry.h2 = 3.8);
    names(&e, "actuator.geometry.h2", "3.8");
    assert!(e.to_string().contains("h1 = 3.7"));
    // PEMC with negative thickness.
    let e = rejected(|p| p.geometry.h3 = 4.5);
    names(&e, "actuator.geometry.h3", "4.5");
    // A thinner laminate that still stacks up is fine.
    let mut p = ActuatorParams::default();
    p.geometry.h = 7.6;
    assert!(Actuator::new(p).is_ok());
}

#[test]
fn channel_rules() {
    names(
        &rejected(|p| p.channel.cx = 0.0),
        "actuator.channel.cx",
        "0",
    );
    let e = rejected(|p| p.channel.cx = 111.0);
    names(&e, "actuator.channel.cx", "111");
    assert!(e.to_string().contains("lx = 110"));
    let e = rejected(|p| p.channel.cy = 31.75);
    names(&e, "actuator.channel.cy", "31.75");
    names(
        &rejected(|p| p.channel.cy = -1.0),
        "actuator.channel.cy",
        "-1",
    );
    names(
        &rejected(|p| p.channel.h3a = -0.1),
        "actuator.channel.h3a",
        "-0.1",
    );
    let e = rejected(|p| p.channel.h3a = 1.8);
    names(&e, "actuator.channel.h3a", "1.8");
    assert!(e.to_string().contains("fluidic layer"));
    let e = rejected(|p| p.channel.h3b = 2.2);
    names(&e, "actuator.channel.h3b", "2.2");
    // A channel the whole length of the finger is allowed.
    let mut p = ActuatorParams::default();
    p.channel.cx = 110.0;
    p.ribs = RibLayout::None;
    assert!(Actuator::new(p).is_ok());
}

fn explicit(ribs: Vec<Rib>) -> impl FnOnce(&mut ActuatorParams) {
    move |p| p.ribs = RibLayout::Explicit(ribs)
}

fn rib(x0: f64, x1: f64, width: f64) -> Rib {
    Rib { x0, x1, width }
}

#[test]
fn explicit_rib_rules() {
    let ok = rib(10.0, 20.0, 5.0);
    names(
        &rejected(explicit(vec![ok, rib(-1.0, 2.0, 1.0)])),
        "actuator.ribs.list[1].x0",
        "-1",
    );
    names(
        &rejected(explicit(vec![rib(5.0, 5.0, 1.0)])),
        "actuator.ribs.list[0].x1",
        "5",
    );
    let e = rejected(explicit(vec![rib(100.0, 106.0, 1.0)]));
    names(&e, "actuator.ribs.list[0].x1", "106");
    assert!(e.to_string().contains("cx = 105"));
    names(
        &rejected(explicit(vec![rib(1.0, 2.0, 0.0)])),
        "actuator.ribs.list[0].width",
        "0",
    );
    names(
        &rejected(explicit(vec![rib(1.0, 2.0, 27.0)])),
        "actuator.ribs.list[0].width",
        "27",
    );
    names(
        &rejected(explicit(vec![rib(f64::NAN, 2.0, 1.0)])),
        "actuator.ribs.list[0].x0",
        "NaN",
    );
    // a listed layout is bounded as a generated one is, by its length
    // before any rib is looked at
    let many = vec![rib(1.0, 2.0, 1.0); MAX_LISTED_RIBS + 1];
    let e = rejected(explicit(many));
    names(&e, "actuator.ribs", "10001");
    assert!(e.to_string().contains("more than 10000"), "{e}");
    let mut p = ActuatorParams::default();
    // as many as the bound, side by side along the channel
    let ribs = (0..MAX_LISTED_RIBS)
        .map(|k| rib(k as f64 * 0.01, k as f64 * 0.01 + 0.005, 1.0))
        .collect();
    p.ribs = RibLayout::Explicit(ribs);
    if let Err(e) = Actuator::new(p) {
        panic!("{e}");
    }
}

#[test]
fn overlapping_ribs_must_fit_in_the_channel() {
    let e = rejected(explicit(vec![rib(0.0, 10.0, 20.0), rib(5.0, 15.0, 10.0)]));
    assert_eq!(e.field(), "actuator.ribs");
    assert!(matches!(e, InputError::Inconsistent { .. }));
    assert!(e.to_string().contains("cy = 26"), "{e}");
    // Ribs that only touch do not overlap; side by side they may fill cy.
    let p = ActuatorParams {
        ribs: RibLayout::Explicit(vec![
            rib(0.0, 5.0, 20.0),
            rib(5.0, 10.0, 20.0),
            rib(5.0, 10.0, 6.0),
        ]),
        ..Default::default()
    };
    assert_eq!(Actuator::new(p).unwrap().ribs().len(), 3);
}

#[test]
fn paper_rib_rules() {
    let layout = |w1, w2, t| move |p: &mut ActuatorParams| p.ribs = RibLayout::Paper { w1, w2, t };
    names(&rejected(layout(0.0, 6.0, 2.0)), "actuator.ribs.w1", "0");
    names(&rejected(layout(8.0, -6.0, 2.0)), "actuator.ribs.w2", "-6");
    names(
        &rejected(layout(8.0, 6.0, f64::NAN)),
        "actuator.ribs.t",
        "NaN",
    );
    // Longitudinal plus transverse wider than the channel.
    let e = rejected(layout(8.0, 13.0, 2.0));
    names(&e, "actuator.ribs.w2", "13");
    assert!(e.to_string().contains("cy = 26"));
    // Transverse ribs overlapping each other.
    names(&rejected(layout(1.5, 6.0, 2.0)), "actuator.ribs.w1", "1.5");
    // Too many ribs.
    let e = rejected(layout(0.001, 6.0, 0.001));
    names(&e, "actuator.ribs.w1", "0.001");
    // A pitch too long for any transverse rib leaves the longitudinal one.
    let p = ActuatorParams {
        ribs: RibLayout::Paper {
            w1: 200.0,
            w2: 6.0,
            t: 2.0,
        },
        ..Default::default()
    };
    assert_eq!(Actuator::new(p).unwrap().ribs().len(), 1);
}

#[test]
fn material_rules() {
    names(
        &rejected(|p| p.cl = Isotropic { e: -1.0, nu: 0.3 }.into()),
        "actuator.cl.e",
        "-1",
    );
    let e = rejected(|p| p.cl = Isotropic { e: 305.0, nu: 0.5 }.into());
    names(&e, "actuator.cl.nu", "0.5");
    assert!(e.to_string().contains("[0, 0.5)"));
    names(
        &rejected(|p| p.fluidic = Isotropic { e: 1.2, nu: -0.1 }.into()),
        "actuator.fluidic.nu",
        "-0.1",
    );
    names(
        &rejected(|p| {
            p.fluidic = Isotropic {
                e: 1.2,
                nu: f64::NAN,
            }
            .into()
        }),
        "actuator.fluidic.nu",
        "NaN",
    );
    names(
        &rejected(|p| {
            p.emc = Orthotropic {
                e1: 0.0,
                e2: 250.0,
                nu12: 0.0,
            }
            .into()
        }),
        "actuator.emc.e1",
        "0",
    );
    // nu21 = 0.1 * 250 / 1.5 = 16.7: 1 - nu12 nu21 < 0.
    let e = rejected(|p| {
        p.emc = Orthotropic {
            e1: 1.5,
            e2: 250.0,
            nu12: 0.1,
        }
        .into()
    });
    names(&e, "actuator.emc.nu12", "0.1");
    assert!(e.to_string().contains("1 - nu12 nu21"));
    // Any material kind may go in any linear layer.
    let p = ActuatorParams {
        cl: Material::Orthotropic(Orthotropic {
            e1: 305.0,
            e2: 305.0,
            nu12: 0.43,
        }),
        ..Default::default()
    };
    let a = Actuator::new(p).unwrap();
    let b = Actuator::default();
    let (qa, qb) = (a.linear_layers()[0].q, b.linear_layers()[0].q);
    assert!(close(qa.q11, qb.q11, 1e-14) && close(qa.q12, qb.q12, 1e-14));
}

#[test]
fn prestressed_rules() {
    names(&rejected(|p| p.pemc.e2 = 0.0), "actuator.pemc.e2", "0");
    names(
        &rejected(|p| p.pemc.law.p1 = 0.0),
        "actuator.pemc.law.p1",
        "0",
    );
    names(
        &rejected(|p| p.pemc.law.p3 = f64::INFINITY),
        "actuator.pemc.law.p3",
        "inf",
    );
    names(
        &rejected(|p| p.pemc.eps0 = f64::NEG_INFINITY),
        "actuator.pemc.eps0",
        "-inf",
    );
}

/// Finite values that under- or overflow the solver's scales are refused
/// by name, the value written short: a modulus outside 1 Pa to 10 TPa, a
/// law constant past 10 TPa in magnitude, a prestrain at -1 or past 10.
#[test]
fn moduli_and_prestrain_are_bounded() {
    all_rejected(&[
        (|p| p.pemc.e2 = 1e308, "actuator.pemc.e2", "1e308"),
        (
            |p| p.pemc.law.p2 = -2e7,
            "actuator.pemc.law.p2",
            "-20000000",
        ),
        (|p| p.pemc.law.p1 = 1e-320, "actuator.pemc.law.p1", "1e-320"),
    ]);
    let tiny = rejected(|p| {
        p.cl = Orthotropic {
            e1: 1e-320,
            e2: 305.0,
            nu12: 0.3,
        }
        .into()
    });
    // the modulus, not the Poisson ratio its nu21 overflows
    names(&tiny, "actuator.cl.e1", "1e-320");
    assert!(tiny.to_string().contains("MPa"), "{tiny}");
    all_rejected(&[
        (
            |p| p.fluidic = Isotropic { e: 2e7, nu: 0.3 }.into(),
            "actuator.fluidic.e",
            "20000000",
        ),
        (|p| p.pemc.eps0 = -1.0, "actuator.pemc.eps0", "-1"),
        (|p| p.pemc.eps0 = 1e6, "actuator.pemc.eps0", "1000000"),
    ]);
    // the ends inside are accepted
    for edit in [
        |p: &mut ActuatorParams| p.pemc.e2 = 1e7,
        |p: &mut ActuatorParams| p.pemc.law.p4 = -1e7,
        |p: &mut ActuatorParams| p.fluidic = Isotropic { e: 1e-6, nu: 0.3 }.into(),
        |p: &mut ActuatorParams| p.pemc.eps0 = 10.0,
    ] {
        let mut p = ActuatorParams::default();
        edit(&mut p);
        assert!(Actuator::new(p).is_ok());
    }
}

#[test]
fn prestrain_warnings() {
    for eps0 in [0.0, 0.15, 0.4, 0.6] {
        assert!(
            Actuator::paper(eps0).unwrap().warnings().is_empty(),
            "{eps0}"
        );
    }
    for eps0 in [-0.1, 0.7] {
        let a = Actuator::paper(eps0).unwrap();
        assert_eq!(a.warnings().len(), 1, "{eps0}");
        assert!(matches!(a.warnings()[0], Warning::Eps0OutsideFit { .. }));
        let msg = a.warnings()[0].to_string();
        assert!(
            msg.contains("actuator.pemc.eps0") && msg.contains(&eps0.to_string()),
            "{msg}"
        );
    }
    // A law whose tangent is negative at eps0: 1 - 2 * 10 * 0.25 = -4. The
    // law is the model's, so the finger (not the actuator) warns.
    let mut p = ActuatorParams::default();
    p.pemc.law = PsiParams {
        p1: 1.0,
        p2: 10.0,
        p3: 0.0,
        p4: 0.0,
    };
    let a = Actuator::new(p).unwrap();
    assert!(a.warnings().is_empty(), "{:?}", a.warnings());
    let f = Finger::new(&a, &Partition::equal(110.0, 1).unwrap(), true);
    assert_eq!(
        f.warnings(),
        [Warning::SofteningPrestressLaw {
            eps0: 0.25,
            tangent: Some(-4.0)
        }]
    );
    // A prestrain so large that the paper's law overflowed there (it was
    // accepted with a warning whose tangent was not a number) is refused
    // by name: the largest accepted one keeps a finite tangent.
    let e = rejected(|p| p.pemc.eps0 = 1e308);
    assert_eq!(e.field(), "actuator.pemc.eps0", "{e}");
    let mut p = ActuatorParams::default();
    p.pemc.eps0 = fpc::actuator::EPS0_RANGE.1;
    let a = Actuator::new(p).unwrap();
    let f = Finger::new(&a, &Partition::equal(110.0, 1).unwrap(), true);
    for w in f.warnings() {
        if let Warning::SofteningPrestressLaw { tangent, .. } = w {
            assert!(tangent.is_some_and(f64::is_finite), "{w}");
        }
    }
}

// ------------------------------------------------------------- partition

#[test]
fn equal_partition() {
    for n in [1, 3, 8, 1000] {
        let part = Partition::equal(110.0, n).unwrap();
        assert_eq!(part.len(), n);
        assert!(close(part.lengths().iter().sum::<f64>(), 110.0, 1e-13));
        let last = part.len() - 1;
        assert!(close(
            part.starts()[last] + part.lengths()[last],
            110.0,
            1e-13
        ));
        assert_eq!(part.starts()[0], 0.0);
    }
    names(&Partition::equal(110.0, 0).unwrap_err(), "partition.n", "0");
    names(
        &Partition::equal(110.0, 1001).unwrap_err(),
        "partition.n",
        "1001",
    );
    names(
        &Partition::equal(-1.0, 8).unwrap_err(),
        "partition.lx",
        "-1",
    );
}

#[test]
fn custom_partition() {
    let part = Partition::custom(vec![10.0, 40.0, 60.0], 110.0).unwrap();
    assert_eq!(part.starts(), [0.0, 10.0, 50.0]);
    assert_eq!(part.lengths(), [10.0, 40.0, 60.0]);

    let e = Partition::custom(vec![], 110.0).unwrap_err();
    assert_eq!(e.field(), "partition.lengths");
    let e = Partition::custom(vec![10.0, 40.0, 50.0], 110.0).unwrap_err();
    assert_eq!(e.field(), "partition.lengths");
    assert!(e.to_string().contains("add up to 100"), "{e}");
    names(
        &Partition::custom(vec![120.0, -10.0], 110.0).unwrap_err(),
        "partition.lengths[1]",
        "-10",
    );
    names(
        &Partition::custom(vec![f64::NAN, 110.0], 110.0).unwrap_err(),
        "partition.lengths[0]",
        "NaN",
    );
    let e = Partition::custom(vec![0.01, 109.99], 110.0).unwrap_err();
    names(&e, "partition.lengths[0]", "0.01");
    assert!(e.to_string().contains("at least"));
    // Rounding within the tolerance is accepted.
    assert!(Partition::custom(vec![110.0 / 3.0; 3], 110.0).is_ok());
}

/// Lengths beyond any actuator overflow the solver's scales: rejected by
/// the actuator, naming the field, not later as an internal option.
#[test]
fn dimensions_beyond_any_actuator_are_rejected() {
    let e = rejected(|p| p.geometry.lx = 1e308);
    assert_eq!(e.field(), "actuator.geometry.lx", "{e}");
    assert!(e.to_string().contains("must be at most 100000 mm"), "{e}");
    let e = rejected(|p| p.geometry.ly = 2e5);
    assert_eq!(e.field(), "actuator.geometry.ly", "{e}");
    let e = rejected(|p| p.geometry.h = f64::MAX);
    assert_eq!(e.field(), "actuator.geometry.h", "{e}");
}
