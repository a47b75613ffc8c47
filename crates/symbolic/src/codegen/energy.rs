//! The total energy: the `Moments` struct and the functions combining the
//! integral kernels with their coefficients.

use proc_macro2::{Ident, Literal, TokenStream};
use quote::quote;

use super::{fresh_symbol, ident};
use crate::emit::Emitter;
use crate::expr::{Arena, Sym, SymError};
use crate::rational::Rational;
use crate::spec::{EnergyDef, Spec};

/// The `Moments` struct (one array per integral of the energy) and
/// `energy_value`, `energy_gradient`, `energy_hessian`: the integrals
/// combined with their coefficients. A term whose coefficient is not a
/// constant is skipped when the coefficient is zero (no gas kernel at zero
/// pressure, say).
pub(super) fn energy_fns(
    spec: &mut Spec,
    def: &EnergyDef,
    prefix: &TokenStream,
    lanes: Option<&TokenStream>,
) -> Result<TokenStream, SymError> {
    let n = spec.unknowns.len();
    let nu = Literal::usize_unsuffixed(n);
    let nh = Literal::usize_unsuffixed(n * (n + 1) / 2);
    // each coefficient's change along a change `ds` of the scalars (on a
    // copy of the arena, which leaves the later kernels as they were)
    let mut tangent_arena = spec.arena.clone();
    let dscalars: Vec<Sym> = def
        .scalars
        .iter()
        .map(|&sc| {
            let base = format!("__d{}", tangent_arena.name(sc));
            fresh_symbol(&mut tangent_arena, &base)
        })
        .collect();
    let mut dcoefs = Vec::with_capacity(def.terms.len());
    for (_, coef) in &def.terms {
        let arena = &mut tangent_arena;
        let mut terms = Vec::new();
        for (&sc, &ds) in def.scalars.iter().zip(&dscalars) {
            let d = arena.diff(*coef, sc)?;
            if arena.as_num(d) != Some(Rational::ZERO) {
                let v = arena.sym(ds);
                terms.push(arena.mul2(d, v)?);
            }
        }
        dcoefs.push(arena.add(&terms)?);
    }
    let fields: Vec<Ident> = def.terms.iter().map(|(t, _)| ident(t)).collect();
    let counts: Vec<Ident> = def
        .terms
        .iter()
        .map(|(t, _)| ident(&format!("{}_MOMENTS", t.to_uppercase())))
        .collect();
    let arena_ro: &Arena = &spec.arena;
    let scalars: Vec<Ident> = def
        .scalars
        .iter()
        .map(|&s| ident(arena_ro.name(s)))
        .collect();
    let mut value = Vec::new();
    let mut grad = Vec::new();
    let mut hess = Vec::new();
    let mut value_lanes = Vec::new();
    let mut grad_lanes = Vec::new();
    let mut hess_lanes = Vec::new();
    // a first term with coefficient 1 initialises the sums (no adds to zero)
    let first_is_one = def
        .terms
        .first()
        .is_some_and(|(_, c)| arena_ro.as_num(*c) == Some(Rational::ONE));
    for (i, ((name, coef), field)) in def.terms.iter().zip(&fields).enumerate() {
        let mut em = Emitter::new(arena_ro, &[*coef], "coef");
        for &sc in &def.scalars {
            let id = ident(arena_ro.name(sc));
            em.bind_symbol(sc, quote! { s.#id });
        }
        let c = em.expr(*coef);
        let pre = em.take_statements();
        let constant = arena_ro.as_num(*coef);
        let one = constant == Some(Rational::ONE);
        let ci = ident(&format!("c{i}"));
        let f_value = ident(&format!("{name}_value"));
        let f_grad = ident(&format!("{name}_gradient"));
        let f_hess = ident(&format!("{name}_hessian"));
        let f_hess_lanes = ident(&format!("{name}_hessian_lanes"));
        let f_value_lanes = ident(&format!("{name}_value_lanes"));
        let f_grad_lanes = ident(&format!("{name}_gradient_lanes"));
        if i == 0 && first_is_one {
            value_lanes.push(quote! { let mut v = #f_value_lanes(k, &m.#field); });
            grad_lanes.push(quote! { let (mut v, mut g) = #f_grad_lanes(k, &m.#field); });
            value.push(quote! { let mut v = #f_value(k, &m.#field); });
            grad.push(quote! { let (mut v, mut g) = #f_grad(k, &m.#field); });
            hess.push(quote! { let (mut v, mut g, mut h) = #f_hess(k, &m.#field); });
            hess_lanes.push(quote! { let (mut v, mut g, mut h) = #f_hess_lanes(k, &m.#field); });
            continue;
        }
        let times = |t: TokenStream| {
            if one {
                t
            } else {
                quote! { #ci * #t }
            }
        };
        let tv = times(quote! { tv });
        let gi: Vec<TokenStream> = (0..n)
            .map(|j| {
                let j = Literal::usize_unsuffixed(j);
                let t = times(quote! { tg[#j] });
                quote! { g[#j] += #t; }
            })
            .collect();
        let hi: Vec<TokenStream> = (0..n * (n + 1) / 2)
            .map(|j| {
                let j = Literal::usize_unsuffixed(j);
                let t = times(quote! { th[#j] });
                quote! { h[#j] += #t; }
            })
            .collect();
        let v_lanes_body = quote! { let tv = #f_value_lanes(k, &m.#field); v += #tv; };
        let g_lanes_body = quote! {
            let (tv, tg) = #f_grad_lanes(k, &m.#field);
            v += #tv;
            #(#gi)*
        };
        let h_lanes_body = quote! {
            let (tv, tg, th) = #f_hess_lanes(k, &m.#field);
            v += #tv;
            #(#gi)*
            #(#hi)*
        };
        let (v_body, g_body, h_body) = (
            quote! { let tv = #f_value(k, &m.#field); v += #tv; },
            quote! {
                let (tv, tg) = #f_grad(k, &m.#field);
                v += #tv;
                #(#gi)*
            },
            quote! {
                let (tv, tg, th) = #f_hess(k, &m.#field);
                v += #tv;
                #(#gi)*
                #(#hi)*
            },
        );
        let guard = |body: TokenStream| match (one, constant) {
            (true, _) => quote! { { #body } },
            (false, Some(_)) => quote! { { #(#pre)* let #ci: f64 = #c; #body } },
            (false, None) => quote! { { #(#pre)* let #ci: f64 = #c; if #ci != 0.0 { #body } } },
        };
        value.push(guard(v_body));
        grad.push(guard(g_body));
        hess.push(guard(h_body));
        value_lanes.push(guard(v_lanes_body));
        grad_lanes.push(guard(g_lanes_body));
        hess_lanes.push(guard(h_lanes_body));
    }
    let (init_v, init_g, init_h, init_v_lanes) = if first_is_one {
        Default::default()
    } else {
        (
            quote! { let mut v = 0.0; },
            quote! { let mut v = 0.0; let mut g = [0.0; #nu]; },
            quote! { let mut v = 0.0; let mut g = [0.0; #nu]; let mut h = [0.0; #nh]; },
            quote! { let mut v = L::splat(0.0); },
        )
    };
    let (init_g_lanes, init_h_lanes) = if first_is_one {
        Default::default()
    } else {
        (
            quote! { #init_v_lanes let mut g = [L::splat(0.0); #nu]; },
            quote! { #init_v_lanes let mut g = [L::splat(0.0); #nu]; let mut h = [L::splat(0.0); #nh]; },
        )
    };
    let combo: Vec<String> = def
        .terms
        .iter()
        .map(|(t, c)| format!("({}) * {t}", arena_ro.show(*c)))
        .collect();
    let doc = format!("The element energy: {}.", combo.join(" + "));
    let scalar_doc = format!(
        "`s` holds the runtime scalars (`{}`); a term whose coefficient is zero is skipped.",
        scalars
            .iter()
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let used = if scalars.is_empty() {
        quote! { let _ = s; }
    } else {
        TokenStream::new()
    };
    // the scalar tangent: only terms whose coefficient moves with the scalars
    let mut tangent = Vec::new();
    let mut tangent_uses_s = false;
    let ta: &Arena = &tangent_arena;
    for (i, (((name, _), field), &dc)) in def.terms.iter().zip(&fields).zip(&dcoefs).enumerate() {
        if ta.as_num(dc) == Some(Rational::ZERO) {
            continue;
        }
        let mut em = Emitter::new(ta, &[dc], "dcoef");
        for &sc in &def.scalars {
            let id = ident(ta.name(sc));
            em.bind_symbol(sc, quote! { s.#id });
        }
        for (&sc, &ds) in def.scalars.iter().zip(&dscalars) {
            let id = ident(ta.name(sc));
            em.bind_symbol(ds, quote! { ds.#id });
        }
        tangent_uses_s |= ta.free_symbols(dc).iter().any(|s| def.scalars.contains(s));
        let c = em.expr(dc);
        let pre = em.take_statements();
        let ci = ident(&format!("dc{i}"));
        let f_grad = ident(&format!("{name}_gradient"));
        let gi: Vec<TokenStream> = (0..n)
            .map(|j| {
                let j = Literal::usize_unsuffixed(j);
                quote! { g[#j] += #ci * tg[#j]; }
            })
            .collect();
        tangent.push(quote! {
            {
                #(#pre)*
                let #ci: f64 = #c;
                if #ci != 0.0 {
                    let (tv, tg) = #f_grad(k, &m.#field);
                    v += #ci * tv;
                    #(#gi)*
                }
            }
        });
    }
    let tangent_unused = match (tangent.is_empty(), tangent_uses_s) {
        (true, _) => quote! { let _ = (k, m, s, ds); },
        (false, false) => quote! { let _ = s; },
        (false, true) => TokenStream::new(),
    };
    let tangent_doc = format!(
        "The derivative of the element energy and of its gradient along a change `ds` \
         of the runtime scalars (`{}`): each integral enters linearly through its \
         coefficient, so this is each integral's value and gradient times the \
         coefficient's change.",
        scalars
            .iter()
            .map(|s| s.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let lane_items = lanes.map(|path| {
        quote! {
            #[doc = "The moments of several elements side by side: lane `l` of each entry holds element `l`'s (the input of `energy_hessian_lanes`)."]
            #[derive(Debug, Clone, PartialEq)]
            pub struct MomentLanes<L> {
                #(#[doc = "Moments of this integral."] pub #fields: [L; #counts],)*
            }

            impl<L: #path::Lane> MomentLanes<L> {
                #[doc = "Lane `l` holds `m[l]`'s moments; lanes past the end of `m` repeat its last element (their results are not used). `m` must not be empty."]
                pub fn gather(m: &[&Moments]) -> MomentLanes<L> {
                    let last = m.len() - 1;
                    MomentLanes {
                        #(#fields: std::array::from_fn(|j| L::from_fn(|l| m[l.min(last)].#fields[j])),)*
                    }
                }
            }

            #[doc = #doc]
            #[doc = ""]
            #[doc = "The value on lanes, one element per lane, each lane bit for bit `energy_value`'s result for that element."]
            #[inline(always)]
            pub fn energy_value_lanes<L: #path::Lane>(k: &[L; #nu], m: &MomentLanes<L>, s: &#prefix EnergyScalars) -> L
            where
                f64: #path::LaneScalar<L>,
            {
                #used
                #init_v_lanes
                #(#value_lanes)*
                v
            }

            #[doc = #doc]
            #[doc = ""]
            #[doc = "Value and gradient on lanes, one element per lane, each lane bit for bit `energy_gradient`'s result for that element."]
            #[inline(always)]
            pub fn energy_gradient_lanes<L: #path::Lane>(k: &[L; #nu], m: &MomentLanes<L>, s: &#prefix EnergyScalars) -> (L, [L; #nu])
            where
                f64: #path::LaneScalar<L>,
            {
                #used
                #init_g_lanes
                #(#grad_lanes)*
                (v, g)
            }

            #[doc = #doc]
            #[doc = ""]
            #[doc = "Value, gradient and Hessian on lanes, one element per lane, each lane bit for bit `energy_hessian`'s result for that element."]
            #[inline(always)]
            pub fn energy_hessian_lanes<L: #path::Lane>(k: &[L; #nu], m: &MomentLanes<L>, s: &#prefix EnergyScalars) -> (L, [L; #nu], [L; #nh])
            where
                f64: #path::LaneScalar<L>,
            {
                #used
                #init_h_lanes
                #(#hess_lanes)*
                (v, g, h)
            }
        }
    });
    Ok(quote! {
        #lane_items

        #[doc = "The moments of every integral of the energy, accumulated block by block."]
        #[derive(Debug, Clone, PartialEq)]
        pub struct Moments {
            #(#[doc = "Moments of this integral."] pub #fields: [f64; #counts],)*
        }

        impl Moments {
            #[doc = "No blocks yet."]
            pub const ZERO: Moments = Moments { #(#fields: [0.0; #counts],)* };
        }

        #[doc = #doc]
        #[doc = ""]
        #[doc = #scalar_doc]
        pub fn energy_value(k: &[f64; #nu], m: &Moments, s: &#prefix EnergyScalars) -> f64 {
            #used
            #init_v
            #(#value)*
            v
        }

        #[doc = #doc]
        #[doc = ""]
        #[doc = "Value and gradient with respect to the unknowns."]
        pub fn energy_gradient(k: &[f64; #nu], m: &Moments, s: &#prefix EnergyScalars) -> (f64, [f64; #nu]) {
            #used
            #init_g
            #(#grad)*
            (v, g)
        }

        #[doc = #doc]
        #[doc = ""]
        #[doc = "Value, gradient and the upper triangle of the Hessian (row by row)."]
        pub fn energy_hessian(k: &[f64; #nu], m: &Moments, s: &#prefix EnergyScalars) -> (f64, [f64; #nu], [f64; #nh]) {
            #used
            #init_h
            #(#hess)*
            (v, g, h)
        }

        #[doc = #doc]
        #[doc = ""]
        #[doc = #tangent_doc]
        pub fn energy_scalars_tangent(k: &[f64; #nu], m: &Moments, s: &#prefix EnergyScalars, ds: &#prefix EnergyScalars) -> (f64, [f64; #nu]) {
            #tangent_unused
            let mut v = 0.0;
            let mut g = [0.0; #nu];
            #(#tangent)*
            (v, g)
        }
    })
}
