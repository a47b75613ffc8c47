//! The contract between a spec and the `fpc` runtime: the integrals, point
//! roles and law the runtime reads, and the check of a spec against them
//! (every rule named with the spec's path when it fails).

use fpc_symbolic::codegen::{point_polynomial, GenError, PolynomialKernel};
use fpc_symbolic::spec::{parse_spec, PointDef, Spec};

use crate::{ModelGenError, SpecFile};

/// The integrals the runtime builds blocks for.
pub const FAMILIES: [&str; 3] = ["linear", "prestressed", "gas"];

/// The point kernels the runtime reads: name, parameters (by name), outputs
/// in the runtime's order.
pub const POINT_ROLES: [(&str, &[&str], &[&str]); 6] = [
    ("end", &["L"], &["Xe", "Ze", "eta"]),
    ("frame", &["L"], &["Xe", "Ze", "dx", "dz"]),
    ("midplane", &["x"], &["X", "Z"]),
    ("tangent", &["x"], &["dx", "dz"]),
    ("strain", &["x", "z"], &["eps_x"]),
    ("curvature", &["x"], &["kappa"]),
];

/// The point kernel the runtime also reads as polynomials, and its variable.
pub const POLYNOMIAL_ROLE: (&str, &str) = ("midplane", "x");

/// The prestressed layer's law.
pub const LAW: (&str, &str) = ("psi", "s");

/// A spec that keeps the contract, parsed, with its names and the
/// mid-plane's polynomial kernel.
pub(crate) struct Checked {
    pub(crate) model: String,
    pub(crate) module: String,
    pub(crate) spec: Spec,
    /// The mid-plane's coefficient kernel.
    pub(crate) midplane: PolynomialKernel,
    /// The `straighten` statements in scaled unknowns: (target, source,
    /// c), Newton's unknown `y_target = scaled_target + c scaled_source^2`.
    pub(crate) straighten: Vec<(usize, usize, f64)>,
}

pub(crate) fn check(file: &SpecFile) -> Result<Checked, ModelGenError> {
    let fail = |message: String| ModelGenError {
        spec: file.path.clone(),
        message,
    };
    let mut spec = parse_spec(&file.text).map_err(|e| fail(e.to_string()))?;
    let model = spec.model.clone().ok_or_else(|| {
        fail("needs a `model NAME;` statement (the Rust type of the model)".into())
    })?;
    let module = model.to_lowercase();
    if spec.scaled.is_none() {
        return Err(fail(
            "needs a `scaled ...;` statement: the solver's dimensionless unknowns".into(),
        ));
    }
    let names: Vec<&str> = spec.integrals.iter().map(|d| d.name.as_str()).collect();
    for f in FAMILIES {
        if !names.contains(&f) {
            return Err(fail(format!(
                "needs `integral {f}(...)`: the runtime builds {} blocks from the actuator",
                FAMILIES.join(", ")
            )));
        }
    }
    if let Some(other) = names.iter().find(|n| !FAMILIES.contains(n)) {
        return Err(fail(format!(
            "`integral {other}` has no blocks: the runtime builds {} blocks only",
            FAMILIES.join(", ")
        )));
    }
    let energy = spec.energy.as_ref().ok_or_else(|| {
        fail("needs an `energy = ...;` statement (how the integrals combine)".into())
    })?;
    for t in &energy.terms {
        if !FAMILIES.contains(&t.0.as_str()) {
            return Err(fail(format!(
                "the energy uses `{}`, which has no blocks",
                t.0
            )));
        }
    }
    for (role, params, outputs) in POINT_ROLES {
        let def = point(&spec, role).ok_or_else(|| {
            fail(format!(
                "needs `point {role}({}) {{ {} }}`",
                params.join(", "),
                outputs
                    .iter()
                    .map(|o| format!("{o} = ...;"))
                    .collect::<Vec<_>>()
                    .join(" ")
            ))
        })?;
        let got: Vec<&str> = def.params.iter().map(|&s| spec.arena.name(s)).collect();
        let mut want = params.to_vec();
        let mut have = got.clone();
        want.sort_unstable();
        have.sort_unstable();
        if want != have {
            return Err(fail(format!(
                "`point {role}` takes ({}); the runtime passes ({})",
                got.join(", "),
                params.join(", ")
            )));
        }
        let outs: Vec<&str> = def.outputs.iter().map(|o| o.0.as_str()).collect();
        let mut o1 = outs.clone();
        let mut o2 = outputs.to_vec();
        o1.sort_unstable();
        o2.sort_unstable();
        if o1 != o2 {
            return Err(fail(format!(
                "`point {role}` has outputs {{{}}}; the runtime reads {{{}}}",
                outs.join(", "),
                outputs.join(", ")
            )));
        }
    }
    // local unknowns must not reach the chain
    for &l in &spec.local {
        for role in ["end", "frame"] {
            if let Some(def) = point(&spec, role) {
                if def
                    .outputs
                    .iter()
                    .any(|o| spec.arena.free_symbols(o.1).contains(&l))
                {
                    return Err(fail(format!(
                        "`{}` is declared local but `point {role}` depends on it: it couples elements through the chain",
                        spec.arena.name(l)
                    )));
                }
            }
        }
    }
    if spec.across.is_empty() {
        return Err(fail(
            "needs an `across ...;` statement: the unknowns of the strain across the width, \
             which plane strain holds at zero"
                .into(),
        ));
    }
    let law = spec.laws.iter().find(|l| l.name == LAW.0).ok_or_else(|| {
        fail(format!(
            "needs `law {}({});`: the prestressed layer's material law",
            LAW.0, LAW.1
        ))
    })?;
    if spec.arena.name(law.var) != LAW.1 {
        return Err(fail(format!(
            "`law {}` must be a law in `{}`",
            LAW.0, LAW.1
        )));
    }
    let straighten = straighten_scaled(&mut spec).map_err(fail)?;
    let (role, var) = POLYNOMIAL_ROLE;
    let midplane = point_polynomial(&mut spec, role, var).map_err(|e| {
        let why = match e {
            GenError::Algebra { source, line, .. } => format!("line {line}: {source}"),
            other => other.to_string(),
        };
        fail(format!(
            "`point {role}({var})` must be a polynomial in `{var}` (contacts are computed \
             on the exact mid-plane curve, from its coefficients): {why}"
        ))
    })?;
    Ok(Checked {
        model,
        module,
        spec,
        midplane,
        straighten,
    })
}

/// The `straighten` statements in the solver's scaled unknowns: with
/// `scaled_t = t f_t`, `t + c s^2` scales to `scaled_t + c (f_t / f_s^2)
/// scaled_s^2`, so `f_t / f_s^2` must be a number. Neither unknown may be
/// local (condensed out of the chain) or across the width (held at zero).
fn straighten_scaled(spec: &mut Spec) -> Result<Vec<(usize, usize, f64)>, String> {
    let mut out = Vec::new();
    for d in spec.straighten.clone() {
        let (target, source) = (
            spec.arena.name(d.target).to_string(),
            spec.arena.name(d.source).to_string(),
        );
        for (u, name) in [(d.target, &target), (d.source, &source)] {
            if spec.local.contains(&u) || spec.across.contains(&u) {
                return Err(format!(
                    "line {}: `straighten` names `{name}`, which is local or across the width",
                    d.line
                ));
            }
        }
        let index = |u| spec.unknowns.iter().position(|&v| v == u).expect("parsed");
        let (t, s) = (index(d.target), index(d.source));
        let ratio = match &spec.scaled {
            Some(sc) => {
                let (ft, fs) = (sc.factors[t], sc.factors[s]);
                let arena = &mut spec.arena;
                arena
                    .pow(fs, 2)
                    .and_then(|fs2| arena.div(ft, fs2))
                    .ok()
                    .and_then(|r| arena.as_num(r))
            }
            None => None,
        };
        let Some(ratio) = ratio else {
            return Err(format!(
                "line {}: `straighten {target} by ...` needs `{target}`'s scaling to be the square of `{source}`'s times a number",
                d.line
            ));
        };
        out.push((t, s, d.coefficient.to_f64() * ratio.to_f64()));
    }
    Ok(out)
}

pub(crate) fn point<'s>(spec: &'s Spec, name: &str) -> Option<&'s PointDef> {
    spec.points.iter().find(|p| p.name == name)
}
