//! One model's module, `model_NAME.rs`: its kernels from the symbolic
//! crate and the glue that implements `fpc`'s `ElementModel` on them.

use fpc_symbolic::codegen::{format_file, generate_with, report_table, Options};
use fpc_symbolic::emit::Emitter;
use fpc_symbolic::spec::Spec;
use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::quote;

use crate::contract::{point, Checked, FAMILIES, LAW, POINT_ROLES};
use crate::{ModelGenError, SpecFile};

/// The runtime's names for the role parameters.
pub(crate) fn runtime_arg(param: &str) -> TokenStream {
    match param {
        "L" => quote! { length },
        "x" => quote! { x },
        _ => quote! { z },
    }
}

pub(crate) fn ident(s: &str) -> Ident {
    Ident::new(s, Span::call_site())
}

/// The spec's leading comment block, without the `#` marks.
pub(crate) fn header_comment(text: &str) -> String {
    let mut out = Vec::new();
    for line in text.lines() {
        let t = line.trim();
        match t.strip_prefix('#') {
            Some(rest) => out.push(rest.strip_prefix(' ').unwrap_or(rest).to_string()),
            None if t.is_empty() && out.is_empty() => continue,
            None => break,
        }
    }
    out.join("\n")
}

/// The call of a point kernel's function with the runtime's arguments in
/// the spec's parameter order, and the output reordering to the runtime's.
fn role_call(spec: &Spec, role: &str, suffix: &str) -> (TokenStream, Vec<usize>) {
    let (_, _, outputs) = POINT_ROLES
        .iter()
        .find(|r| r.0 == role)
        .copied()
        .unwrap_or(POINT_ROLES[0]);
    let def = point(spec, role).expect("checked");
    let f = ident(&format!("{role}_{suffix}"));
    let args: Vec<TokenStream> = def
        .params
        .iter()
        .map(|&p| runtime_arg(spec.arena.name(p)))
        .collect();
    let order = outputs
        .iter()
        .map(|o| def.outputs.iter().position(|d| d.0 == *o).expect("checked"))
        .collect();
    (quote! { #f(k, #(#args),*) }, order)
}

fn reorder(value: TokenStream, order: &[usize]) -> TokenStream {
    if order.iter().enumerate().all(|(i, &j)| i == j) && order.len() > 1 {
        return value;
    }
    let idx: Vec<Literal> = order
        .iter()
        .map(|&j| Literal::usize_unsuffixed(j))
        .collect();
    quote! { { let o = #value; [#(o[#idx]),*] } }
}

pub(crate) fn model_file(file: &SpecFile, c: &Checked) -> Result<(String, String), ModelGenError> {
    let fail = |message: String| ModelGenError {
        spec: file.path.clone(),
        message,
    };
    let options = Options {
        shared_params: Some(quote! { super }),
        lanes: Some(quote! { super }),
        // the chain's assembly takes the end's derivatives in groups
        lane_points: vec!["end".into()],
    };
    let mut generated = generate_with(&file.text, &options).map_err(|e| fail(e.to_string()))?;
    let midplane_kernel = &c.midplane.tokens;
    generated.report.push(c.midplane.report.clone());
    let kernels = generated.tokens;
    let spec = &c.spec;
    let n = spec.unknowns.len();
    let nu = Literal::usize_unsuffixed(n);
    let nh = Literal::usize_unsuffixed(n * (n + 1) / 2);
    let model = ident(&c.model);
    let name = &c.module;
    let path = &file.path;
    let description = header_comment(&file.text);
    let unknowns: Vec<&str> = spec.unknowns.iter().map(|&s| spec.arena.name(s)).collect();
    let families: Vec<Ident> = FAMILIES.iter().map(|f| ident(f)).collect();
    let family_names = FAMILIES;
    let add_fns: Vec<Ident> = FAMILIES
        .iter()
        .map(|f| ident(&format!("add_{f}")))
        .collect();
    let moments_fns: Vec<Ident> = FAMILIES
        .iter()
        .map(|f| ident(&format!("{f}_moments")))
        .collect();
    let params_types: Vec<Ident> = FAMILIES
        .iter()
        .map(|f| {
            let mut s = f.to_string();
            s[..1].make_ascii_uppercase();
            ident(&format!("{s}Params"))
        })
        .collect();
    let tangent_add_fns: Vec<Ident> = FAMILIES
        .iter()
        .map(|f| ident(&format!("add_{f}_tangents")))
        .collect();
    let tangent_fns: Vec<Ident> = FAMILIES
        .iter()
        .map(|f| ident(&format!("{f}_dmoments")))
        .collect();
    let grad_fns: Vec<Ident> = FAMILIES
        .iter()
        .map(|f| ident(&format!("{f}_gradient")))
        .collect();
    // each family's coefficient in the energy (0 if the energy leaves it out)
    let energy = spec.energy.as_ref().expect("checked");
    let coefficients: Vec<TokenStream> = FAMILIES
        .iter()
        .map(|f| match energy.terms.iter().find(|t| t.0 == *f) {
            None => quote! { 0.0 },
            Some((_, coef)) => {
                let mut em = Emitter::new(&spec.arena, &[*coef], "c");
                for &sc in &energy.scalars {
                    let id = ident(spec.arena.name(sc));
                    em.bind_symbol(sc, quote! { s.#id });
                }
                let e = em.expr(*coef);
                let stmts = em.take_statements();
                quote! { { #(#stmts)* #e } }
            }
        })
        .collect();
    let hess_fns: Vec<Ident> = FAMILIES
        .iter()
        .map(|f| ident(&format!("{f}_hessian")))
        .collect();
    let fam_idx: Vec<Literal> = (0..FAMILIES.len()).map(Literal::usize_unsuffixed).collect();
    let scaled_params: Vec<TokenStream> = spec
        .scaled
        .as_ref()
        .map(|s| {
            s.params
                .iter()
                .map(|&p| runtime_arg(spec.arena.name(p)))
                .collect()
        })
        .unwrap_or_default();
    let (end_v, end_o) = role_call(spec, "end", "value");
    let (end_g, _) = role_call(spec, "end", "gradient");
    let (end_h, _) = role_call(spec, "end", "hessian");
    let (end_d, _) = role_call(spec, "end", "derivatives");
    let (end_d_lanes, _) = role_call(spec, "end", "derivatives_lanes");
    let (frame_v, frame_o) = role_call(spec, "frame", "value");
    let (mid_v, mid_o) = role_call(spec, "midplane", "value");
    let mid_poly = ident(&c.midplane.function);
    let mid_degree = Literal::usize_unsuffixed(c.midplane.degree);
    let mid_poly_idx: Vec<Literal> = mid_o
        .iter()
        .map(|&j| Literal::usize_unsuffixed(j))
        .collect();
    let (tan_v, tan_o) = role_call(spec, "tangent", "value");
    let (strain_v, strain_o) = role_call(spec, "strain", "value");
    let (curv_v, curv_o) = role_call(spec, "curvature", "value");
    let end_value = reorder(end_v, &end_o);
    let idx3: Vec<Literal> = end_o
        .iter()
        .map(|&j| Literal::usize_unsuffixed(j))
        .collect();
    let frame_value = reorder(frame_v, &frame_o);
    let mid_value = reorder(mid_v, &mid_o);
    let tan_value = reorder(tan_v, &tan_o);
    let s_idx = Literal::usize_unsuffixed(strain_o[0]);
    let c_idx = Literal::usize_unsuffixed(curv_o[0]);
    let law = ident(LAW.0);
    let model_doc = format!(
        "The element model of `{path}` ({n} unknowns: `{}`).\n\n{description}",
        unknowns.join(", ")
    );
    let tokens = quote! {
        #kernels

        #midplane_kernel

        #[doc = #model_doc]
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
        pub struct #model;

        impl super::ModelCore for #model {
            type Coeffs = [f64; #nu];
            type Upper = [f64; #nh];
            type Moments = Moments;

            const NAME: &'static str = #name;
            const SPEC_PATH: &'static str = #path;
            const DESCRIPTION: &'static str = #description;
            const UNKNOWNS: &'static [&'static str] = &[#(#unknowns),*];
            const LOCAL: &'static [usize] = LOCAL;
            const FAMILIES: &'static [&'static str] = &[#(#family_names),*];
            const MIDPLANE_DEGREE: usize = #mid_degree;

            #[inline]
            fn unscale(length: f64) -> [f64; #nu] {
                unscale(#(#scaled_params),*)
            }
        }

        #[doc = "Lane `l` holds `k[l]` (lanes past the end repeat its last entry); `None` for no unknowns."]
        #[inline(always)]
        fn gather<L: super::Lane>(k: &[[f64; #nu]]) -> Option<[L; #nu]> {
            let last = k.len().checked_sub(1)?;
            Some(std::array::from_fn(|j| L::from_fn(|l| k[l.min(last)][j])))
        }

        impl super::Energy for #model {
            fn zero_moments() -> Moments {
                Moments::ZERO
            }

            #(
                fn #add_fns(m: &mut Moments, p: &super::#params_types) {
                    #moments_fns(&mut m.#families, p);
                }
            )*

            #[inline]
            fn energy(m: &Moments, k: &[f64; #nu], s: &super::EnergyScalars) -> f64 {
                energy_value(k, m, s)
            }

            #[inline]
            fn gradient(m: &Moments, k: &[f64; #nu], s: &super::EnergyScalars) -> (f64, [f64; #nu]) {
                energy_gradient(k, m, s)
            }

            #[inline]
            fn hessian(m: &Moments, k: &[f64; #nu], s: &super::EnergyScalars) -> (f64, [f64; #nu], [f64; #nh]) {
                energy_hessian(k, m, s)
            }

            type MomentLanes<L: super::Lane> = MomentLanes<L>;

            fn moment_lanes<L: super::Lane>(m: &[&Moments]) -> MomentLanes<L> {
                MomentLanes::gather(m)
            }

            #[inline(always)]
            fn energy_lanes<L: super::Lane>(
                m: &MomentLanes<L>,
                k: &[[f64; #nu]],
                s: &super::EnergyScalars,
                out: &mut [f64],
            ) where
                f64: super::LaneScalar<L>,
            {
                let Some(kl) = gather(k) else {
                    return;
                };
                let v = std::hint::black_box(energy_value_lanes(&kl, m, s));
                for (l, o) in out.iter_mut().enumerate().take(L::WIDTH) {
                    *o = v.lane(l);
                }
            }

            #[inline(always)]
            fn gradient_lanes<L: super::Lane>(
                m: &MomentLanes<L>,
                k: &[[f64; #nu]],
                s: &super::EnergyScalars,
                out: &mut [(f64, [f64; #nu])],
            ) where
                f64: super::LaneScalar<L>,
            {
                let Some(kl) = gather(k) else {
                    return;
                };
                let r = energy_gradient_lanes(&kl, m, s);
                let (v, g) = std::hint::black_box(&r);
                for (l, o) in out.iter_mut().enumerate().take(L::WIDTH) {
                    *o = (v.lane(l), std::array::from_fn(|j| g[j].lane(l)));
                }
            }

            #[inline(always)]
            fn hessian_lane_major<L: super::Lane>(
                m: &MomentLanes<L>,
                k: &[[f64; #nu]],
                s: &super::EnergyScalars,
                put: impl FnOnce(&L, &[L], &[L]),
            ) -> bool
            where
                f64: super::LaneScalar<L>,
            {
                let Some(kl) = gather(k) else {
                    return false;
                };
                let r = energy_hessian_lanes(&kl, m, s);
                // the kernel's lanes kept whole: read lane by lane at once,
                // the compiler splits the kernel into one scalar chain per
                // lane and the vector instructions are lost (measured:
                // slower than the scalar kernels at eight lanes); an opaque
                // reference, not an opaque copy, so the result is not moved
                let (v, g, h) = std::hint::black_box(&r);
                put(v, g, h);
                true
            }

            fn family_hessian(m: &Moments, family: usize, k: &[f64; #nu]) -> Option<(f64, [f64; #nu], [f64; #nh])> {
                match family {
                    #(#fam_idx => Some(#hess_fns(k, &m.#families)),)*
                    _ => None,
                }
            }

            #[inline]
            fn psi(s: f64, p: &super::PsiParams) -> [f64; 3] {
                #law(s, p)
            }
        }

        impl super::Kinematics for #model {
            #[inline]
            fn end(k: &[f64; #nu], length: f64) -> [f64; 3] {
                #end_value
            }

            #[inline]
            fn end_gradient(k: &[f64; #nu], length: f64) -> ([f64; 3], [[f64; #nu]; 3]) {
                let (v, g) = #end_g;
                ([#(v[#idx3]),*], [#(g[#idx3]),*])
            }

            #[inline]
            fn end_hessian(k: &[f64; #nu], length: f64) -> ([f64; 3], [[f64; #nu]; 3], [[f64; #nh]; 3]) {
                let (v, g, h) = #end_h;
                ([#(v[#idx3]),*], [#(g[#idx3]),*], [#(h[#idx3]),*])
            }

            #[inline]
            fn end_derivatives(k: &[f64; #nu], length: f64) -> ([[f64; #nu]; 3], [[f64; #nh]; 3]) {
                let (g, h) = #end_d;
                ([#(g[#idx3]),*], [#(h[#idx3]),*])
            }

            #[inline(always)]
            fn end_derivatives_lanes<L: super::Lane>(k: &[L], length: L, g: &mut [L], h: &mut [L])
            where
                f64: super::LaneScalar<L>,
            {
                let k: &[L; #nu] = &std::array::from_fn(|j| k[j]);
                let (dg, dh) = #end_d_lanes;
                for (c, o) in [#(#idx3),*].into_iter().enumerate() {
                    g[c * #nu..(c + 1) * #nu].copy_from_slice(&dg[o]);
                    h[c * #nh..(c + 1) * #nh].copy_from_slice(&dh[o]);
                }
            }

            #[inline]
            fn frame(k: &[f64; #nu], length: f64) -> [f64; 4] {
                #frame_value
            }

            #[inline]
            fn midplane(k: &[f64; #nu], x: f64) -> [f64; 2] {
                #mid_value
            }

            #[inline]
            fn midplane_coefficients(k: &[f64; #nu], out: &mut [[f64; 2]]) {
                for (o, c) in out.iter_mut().zip(#mid_poly(k)) {
                    *o = [#(c[#mid_poly_idx]),*];
                }
            }

            #[inline]
            fn tangent(k: &[f64; #nu], x: f64) -> [f64; 2] {
                #tan_value
            }

            #[inline]
            fn strain(k: &[f64; #nu], x: f64, z: f64) -> f64 {
                #strain_v[#s_idx]
            }

            #[inline]
            fn curvature(k: &[f64; #nu], x: f64) -> f64 {
                #curv_v[#c_idx]
            }
        }

        impl super::Tangents for #model {

            #(
                fn #tangent_add_fns(m: &mut [Moments], p: &super::#params_types, dp: &[super::#params_types]) {
                    let jacobian = #tangent_fns(p);
                    for (m, dp) in m.iter_mut().zip(dp) {
                        for (column, dpj) in jacobian.iter().zip(dp.to_values()) {
                            if dpj != 0.0 {
                                for (mi, c) in m.#families.iter_mut().zip(column) {
                                    *mi += c * dpj;
                                }
                            }
                        }
                    }
                }
            )*

            fn family_gradient(m: &Moments, family: usize, k: &[f64; #nu]) -> Option<(f64, [f64; #nu])> {
                match family {
                    #(#fam_idx => Some(#grad_fns(k, &m.#families)),)*
                    _ => None,
                }
            }

            fn family_coefficient(family: usize, s: &super::EnergyScalars) -> f64 {
                let _ = s;
                match family {
                    #(#fam_idx => #coefficients,)*
                    _ => 0.0,
                }
            }

            #[inline]
            fn scalars_tangent(m: &Moments, k: &[f64; #nu], s: &super::EnergyScalars, ds: &super::EnergyScalars) -> (f64, [f64; #nu]) {
                energy_scalars_tangent(k, m, s, ds)
            }
        }
    };
    let body = format_file(&tokens).map_err(|e| fail(e.to_string()))?;
    let text = format!(
        "// @generated by build.rs from {path} with fpc-modelgen and fpc-symbolic.\n\
         // Do not edit: change the spec or the generator. A reviewed copy lives in\n\
         // energy-spec/golden/ and tests/golden.rs compares the two.\n\n{body}"
    );
    Ok((text, report_table(&generated.report)))
}
