//! Integral kernels: the density expanded over atoms and slots, and the
//! moments, value, gradient and Hessian functions built from it.

use std::collections::{BTreeMap, HashMap};

use proc_macro2::{Ident, Literal, TokenStream};
use quote::quote;

use super::moments::moments_jacobian;
use super::{camel, fresh_symbol, ident, upper_pairs, FunctionReport};
use crate::emit::{literal, tree_ops, Emitter, OpCount};
use crate::expr::{Arena, ExprId, Node, Sym, SymError};
use crate::poly::Poly;
use crate::rational::Rational;
use crate::spec::{IntegralDef, Spec};

/// A distinct product of atoms and its moment.
pub(super) struct Slot {
    /// exponent per atom
    pub(super) exps: Vec<u32>,
    /// moment as a polynomial in parameters and 1-D moment symbols
    pub(super) moment: Poly,
}

pub(super) fn integral_kernel(
    spec: &mut Spec,
    def: &IntegralDef,
    prefix: &TokenStream,
    lanes: Option<&TokenStream>,
) -> Result<(TokenStream, Vec<FunctionReport>), SymError> {
    let arena = &mut spec.arena;
    let unknowns = spec.unknowns.clone();
    let range_vars: Vec<Sym> = def.ranges.iter().map(|r| r.0).collect();
    let params = def.params.clone();
    let in_xp = |s: Sym| range_vars.contains(&s) || params.contains(&s);
    let expanded = arena.expand_in(def.integrand, &in_xp)?;

    // 1-D moment symbols: (variable index, power) -> symbol and definition
    let mut moment_syms: BTreeMap<(usize, u32), Sym> = BTreeMap::new();
    let mut moment_defs: Vec<(Sym, ExprId, String)> = Vec::new();
    // slot body -> poly
    let mut slot_of: HashMap<ExprId, Poly> = HashMap::new();
    let mut body_order: Vec<ExprId> = Vec::new();
    for (mono, coef) in &expanded {
        // split the monomial into integration-variable powers and a parameter monomial
        let mut pmono = Poly::constant(Rational::ONE);
        let mut powers = vec![0u32; range_vars.len()];
        for &(s, e) in mono {
            match range_vars.iter().position(|&v| v == s) {
                Some(i) => powers[i] = e,
                None => pmono = pmono.mul(&Poly::var(s).pow(e)?)?,
            }
        }
        for (i, &j) in powers.iter().enumerate() {
            let sym = match moment_syms.get(&(i, j)) {
                Some(&s) => s,
                None => {
                    let vname = arena.name(range_vars[i]).to_string();
                    let s = fresh_symbol(arena, &format!("__mom_{vname}{j}"));
                    let (_, lo, hi) = def.ranges[i];
                    let hi_p = arena.pow(hi, j as i32 + 1)?;
                    let lo_p = arena.pow(lo, j as i32 + 1)?;
                    let diff = arena.sub(hi_p, lo_p)?;
                    let k = arena.num(Rational::new(1, j as i128 + 1)?);
                    let d = arena.mul2(k, diff)?;
                    moment_syms.insert((i, j), s);
                    moment_defs.push((s, d, format!("mom_{vname}{j}")));
                    s
                }
            };
            pmono = pmono.mul(&Poly::var(sym))?;
        }
        // the coefficient is already rational * (products of atoms)
        for &(body, r) in &coef.terms {
            let add = pmono.scale(r)?;
            match slot_of.get_mut(&body) {
                Some(p) => *p = p.add(&add)?,
                None => {
                    body_order.push(body);
                    slot_of.insert(body, add);
                }
            }
        }
    }

    // atoms: the distinct bases of the slot bodies
    let mut atoms: Vec<ExprId> = Vec::new();
    let mut body_factors: Vec<Vec<(ExprId, u32)>> = Vec::new();
    for &body in &body_order {
        let factors = match arena.node(body) {
            Node::Num(_) => vec![],
            Node::Mul(fs) => fs.clone(),
            _ => vec![body],
        };
        let mut fx = Vec::new();
        for f in factors {
            let (b, e) = match arena.node(f) {
                Node::Pow(b, e) => (*b, *e),
                _ => (f, 1),
            };
            if e < 0 {
                return Err(SymError::NotPolynomial {
                    var: "the unknowns".into(),
                    what: arena.show(body).to_string(),
                });
            }
            if !atoms.contains(&b) {
                atoms.push(b);
            }
            fx.push((b, e as u32));
        }
        body_factors.push(fx);
    }
    atoms.sort();
    let mut slots: Vec<Slot> = body_order
        .iter()
        .zip(&body_factors)
        .map(|(b, fx)| {
            let mut exps = vec![0u32; atoms.len()];
            for (base, e) in fx {
                let i = atoms.iter().position(|a| a == base).unwrap_or(0);
                exps[i] = *e;
            }
            Slot {
                exps,
                moment: slot_of[b].clone(),
            }
        })
        .filter(|s| !s.moment.is_zero())
        .collect();
    // graded order: constant first, then by total degree and exponents
    slots.sort_by_key(|s| {
        (
            s.exps.iter().sum::<u32>(),
            std::cmp::Reverse(s.exps.clone()),
        )
    });

    let tau: Vec<Sym> = (0..atoms.len())
        .map(|i| fresh_symbol(arena, &format!("__atom{i}")))
        .collect();
    let msym: Vec<Sym> = (0..slots.len())
        .map(|i| fresh_symbol(arena, &format!("__slot{i}")))
        .collect();

    // energy as a polynomial in atoms and moments
    let mut energy = Poly::zero();
    for (s, slot) in slots.iter().enumerate() {
        let mut t = Poly::var(msym[s]);
        for (a, &e) in slot.exps.iter().enumerate() {
            t = t.mul(&Poly::var(tau[a]).pow(e)?)?;
        }
        energy = energy.add(&t)?;
    }
    let na = atoms.len();
    let grad_tau: Vec<Poly> = tau
        .iter()
        .map(|&t| energy.diff(t))
        .collect::<Result<_, _>>()?;
    let mut hess_tau = vec![vec![Poly::zero(); na]; na];
    for a in 0..na {
        for b in a..na {
            let h = grad_tau[a].diff(tau[b])?;
            hess_tau[a][b] = h.clone();
            hess_tau[b][a] = h;
        }
    }
    let value_e = arena.horner(&energy, &msym)?;
    let grad_e: Vec<ExprId> = grad_tau
        .iter()
        .map(|g| arena.horner(g, &msym))
        .collect::<Result<_, _>>()?;
    let mut hess_e = vec![vec![arena.int(0); na]; na];
    for a in 0..na {
        for b in a..na {
            let h = arena.horner(&hess_tau[a][b], &msym)?;
            hess_e[a][b] = h;
            hess_e[b][a] = h;
        }
    }
    // atom Jacobian and second derivatives w.r.t. the unknowns
    let n = unknowns.len();
    let mut jac = vec![vec![arena.int(0); n]; na];
    let mut jac2 = vec![vec![vec![arena.int(0); n]; n]; na];
    for a in 0..na {
        for k in 0..n {
            jac[a][k] = arena.diff(atoms[a], unknowns[k])?;
            for l in 0..n {
                jac2[a][k][l] = arena.diff(jac[a][k], unknowns[l])?;
            }
        }
    }
    let mut grad_u = Vec::with_capacity(n);
    for k in 0..n {
        let mut terms = Vec::new();
        for (ge, ja) in grad_e.iter().zip(&jac) {
            terms.push(arena.mul2(*ge, ja[k])?);
        }
        grad_u.push(arena.add(&terms)?);
    }
    // (H J)_{a,l} shared between rows
    let mut hj = vec![vec![arena.int(0); n]; na];
    for a in 0..na {
        for l in 0..n {
            let mut terms = Vec::new();
            for b in 0..na {
                terms.push(arena.mul2(hess_e[a][b], jac[b][l])?);
            }
            hj[a][l] = arena.add(&terms)?;
        }
    }
    let mut hess_u = Vec::new();
    for (k, l) in upper_pairs(n) {
        let mut terms = Vec::new();
        for a in 0..na {
            terms.push(arena.mul2(jac[a][k], hj[a][l])?);
            terms.push(arena.mul2(grad_e[a], jac2[a][k][l])?);
        }
        hess_u.push(arena.add(&terms)?);
    }

    // ---- emission ----
    let name = &def.name;
    let upper = name.to_uppercase();
    let count_ident = ident(&format!("{upper}_MOMENTS"));
    let nslots = Literal::usize_unsuffixed(slots.len());
    let nu = Literal::usize_unsuffixed(n);
    let nh = Literal::usize_unsuffixed(n * (n + 1) / 2);
    let mut reports = Vec::new();
    let arena_ro: &Arena = arena;

    // docs
    let atom_docs: Vec<String> = atoms
        .iter()
        .enumerate()
        .map(|(i, &a)| format!("- `atom{i} = {}`", arena_ro.show(a)))
        .collect();
    let slot_docs: Vec<String> = slots
        .iter()
        .enumerate()
        .map(|(s, slot)| {
            let mono: Vec<String> = slot
                .exps
                .iter()
                .enumerate()
                .filter(|(_, &e)| e > 0)
                .map(|(a, &e)| {
                    if e == 1 {
                        format!("atom{a}")
                    } else {
                        format!("atom{a}^{e}")
                    }
                })
                .collect();
            let mono = if mono.is_empty() {
                "1".to_string()
            } else {
                mono.join("*")
            };
            format!("- `m[{s}]` multiplies `{mono}`")
        })
        .collect();
    let ranges: Vec<String> = def
        .ranges
        .iter()
        .map(|(v, lo, hi)| {
            format!(
                "{} in [{}, {}]",
                arena_ro.name(*v),
                arena_ro.show(*lo),
                arena_ro.show(*hi)
            )
        })
        .collect();
    let head_doc = format!(
        "Kernel `{name}`: the integral of `{}` over {}.",
        arena_ro.show(def.integrand),
        ranges.join(", ")
    );
    let atoms_doc = format!(
        "Atoms (functions of the unknowns):\n{}",
        atom_docs.join("\n")
    );
    let slots_doc = format!("Moment slots:\n{}", slot_docs.join("\n"));

    // moments function
    let param_idents: Vec<Ident> = params.iter().map(|&p| ident(arena_ro.name(p))).collect();
    let mut moment_roots: Vec<ExprId> = Vec::new();
    let mut moment_polys_e = Vec::new();
    {
        // need &mut arena for horner: rebind
    }
    let _ = arena_ro;
    let mom_syms_all: Vec<Sym> = moment_defs.iter().map(|d| d.0).collect();
    for slot in &slots {
        let e = arena.horner(&slot.moment, &[])?;
        moment_polys_e.push(e);
    }
    for (_, d, _) in &moment_defs {
        moment_roots.push(*d);
    }
    moment_roots.extend(moment_polys_e.iter().copied());
    // on a copy of the arena: the expressions of the kernels generated
    // after this one (ordered by their ids) stay exactly as they were
    let mut jacobian_arena = arena.clone();
    let jacobian = moments_jacobian(&mut jacobian_arena, &params, &slots, &moment_defs)?;
    let arena_ro: &Arena = arena;
    let mut em = Emitter::new(arena_ro, &moment_roots, "tmp");
    let mut before = OpCount::default();
    for (s, d, label) in &moment_defs {
        if moment_polys_e
            .iter()
            .any(|&e| arena_ro.free_symbols(e).contains(s))
        {
            let t = em.let_named(label, *d);
            em.bind_symbol(*s, t);
            before += tree_ops(arena_ro, &[*d]);
        }
    }
    let mut adds = Vec::new();
    for (s, &e) in moment_polys_e.iter().enumerate() {
        let v = em.expr(e);
        let idx = Literal::usize_unsuffixed(s);
        adds.extend(em.take_statements());
        adds.push(quote! { m[#idx] += #v; });
    }
    before += tree_ops(arena_ro, &moment_polys_e);
    before.add += slots.len() as u64;
    let mut after = em.ops();
    after.add += slots.len() as u64;
    let prelude = em.take_statements();
    let _ = &mom_syms_all;
    let fn_moments = ident(&format!("{name}_moments_at"));
    let fn_moments_named = ident(&format!("{name}_moments"));
    let params_struct = ident(&format!("{}Params", camel(name)));
    reports.push(FunctionReport {
        function: fn_moments.to_string(),
        ops_before_cse: before,
        ops_after_cse: after,
    });
    let mom_doc = format!(
        "Adds one block's moments to `m` (call once per block per scene; blocks with \
         a negative width are subtracted). Parameters: `{}`.",
        param_idents
            .iter()
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );

    // evaluation functions
    let used_unknowns: Vec<(usize, Sym)> = unknowns
        .iter()
        .copied()
        .enumerate()
        .filter(|(_, u)| atoms.iter().any(|&a| arena_ro.free_symbols(a).contains(u)))
        .collect();
    let make_eval = |outputs: &[ExprId]| -> (Vec<TokenStream>, Vec<TokenStream>, OpCount, OpCount) {
        let mut roots: Vec<ExprId> = atoms.clone();
        roots.extend_from_slice(outputs);
        let mut em = Emitter::new(arena_ro, &roots, "tmp");
        let mut pre = Vec::new();
        for (i, u) in &used_unknowns {
            let id = ident(arena_ro.name(*u));
            let idx = Literal::usize_unsuffixed(*i);
            pre.push(quote! { let #id = k[#idx]; });
            em.bind_symbol(*u, quote! { #id });
        }
        for (s, _) in slots.iter().enumerate() {
            let idx = Literal::usize_unsuffixed(s);
            em.bind_symbol(msym[s], quote! { m[#idx] });
        }
        let mut before = tree_ops(arena_ro, &atoms);
        for (a, &atom) in atoms.iter().enumerate() {
            let t = em.let_named(&format!("atom{a}"), atom);
            em.bind_symbol(tau[a], t);
        }
        let outs: Vec<TokenStream> = outputs.iter().map(|&o| em.expr(o)).collect();
        before += tree_ops(arena_ro, outputs);
        let mut stmts = pre;
        stmts.extend(em.take_statements());
        (outs, stmts, before, em.ops())
    };

    let fn_value = ident(&format!("{name}_value"));
    let fn_grad = ident(&format!("{name}_gradient"));
    let fn_hess = ident(&format!("{name}_hessian"));
    let (v_outs, v_stmts, b, a) = make_eval(&[value_e]);
    let v_out = &v_outs[0];
    reports.push(FunctionReport {
        function: fn_value.to_string(),
        ops_before_cse: b,
        ops_after_cse: a,
    });
    let mut gouts = vec![value_e];
    gouts.extend(grad_u.iter().copied());
    let (g_out, g_stmts, b, a) = make_eval(&gouts);
    reports.push(FunctionReport {
        function: fn_grad.to_string(),
        ops_before_cse: b,
        ops_after_cse: a,
    });
    let mut houts = gouts.clone();
    houts.extend(hess_u.iter().copied());
    let (h_all, h_stmts, b, a) = make_eval(&houts);
    reports.push(FunctionReport {
        function: fn_hess.to_string(),
        ops_before_cse: b,
        ops_after_cse: a,
    });
    let (jacobian_tokens, jacobian_report) = jacobian.emit(
        &jacobian_arena,
        name,
        &params,
        &param_idents,
        &count_ident,
        &params_struct,
        prefix,
    );
    reports.push(jacobian_report);
    // split the hessian tuple tokens into value, gradient and hessian parts
    let h_parts = h_all;
    let hv = &h_parts[0];
    let hg = &h_parts[1..=n];
    let hh = &h_parts[n + 1..];
    let g_parts = g_out;
    let gv = &g_parts[0];
    let gg = &g_parts[1..];
    let _ = literal;
    let hess_lanes = lanes.map(|path| {
        // a constant output is an f64: splat it into the lanes
        let lane_outs = |parts: &[TokenStream], exprs: &[ExprId]| -> Vec<TokenStream> {
            parts
                .iter()
                .zip(exprs)
                .map(|(t, &e)| match arena_ro.as_num(e) {
                    Some(_) => quote! { L::splat(#t) },
                    None => t.clone(),
                })
                .collect()
        };
        let doc = "On lanes: each lane of `k` and `m` holds one element's unknowns and moments, and each lane of the result is bit for bit that element's scalar result (the same statements in the same order).";
        let fn_value_lanes = ident(&format!("{name}_value_lanes"));
        let fn_grad_lanes = ident(&format!("{name}_gradient_lanes"));
        let fn_hess_lanes = ident(&format!("{name}_hessian_lanes"));
        let v = lane_outs(std::slice::from_ref(v_out), &[value_e]);
        let lv0 = &v[0];
        let g = lane_outs(&g_parts, &gouts);
        let (gv, gg) = (&g[0], &g[1..]);
        let h = lane_outs(&h_parts, &houts);
        let (lv, lg, lh) = (&h[0], &h[1..=n], &h[n + 1..]);
        quote! {
            #[doc = #head_doc]
            #[doc = ""]
            #[doc = "The value kernel."]
            #[doc = #doc]
            #[inline(always)]
            pub fn #fn_value_lanes<L: #path::Lane>(k: &[L; #nu], m: &[L; #count_ident]) -> L
            where
                f64: #path::LaneScalar<L>,
            {
                #(#v_stmts)*
                #lv0
            }

            #[doc = #head_doc]
            #[doc = ""]
            #[doc = "The gradient kernel."]
            #[doc = #doc]
            #[inline(always)]
            pub fn #fn_grad_lanes<L: #path::Lane>(k: &[L; #nu], m: &[L; #count_ident]) -> (L, [L; #nu])
            where
                f64: #path::LaneScalar<L>,
            {
                #(#g_stmts)*
                (#gv, [#(#gg),*])
            }

            #[doc = #head_doc]
            #[doc = ""]
            #[doc = "The Hessian kernel."]
            #[doc = #doc]
            #[inline(always)]
            pub fn #fn_hess_lanes<L: #path::Lane>(k: &[L; #nu], m: &[L; #count_ident]) -> (L, [L; #nu], [L; #nh])
            where
                f64: #path::LaneScalar<L>,
            {
                #(#h_stmts)*
                (#lv, [#(#lg),*], [#(#lh),*])
            }
        }
    });

    let tokens = quote! {
        #[doc = #head_doc]
        #[doc = ""]
        #[doc = "Number of moment slots of this kernel."]
        pub const #count_ident: usize = #nslots;

        #[doc = #head_doc]
        #[doc = ""]
        #[doc = #mom_doc]
        #[doc = ""]
        #[doc = #slots_doc]
        fn #fn_moments(m: &mut [f64; #count_ident], #(#param_idents: f64),*) {
            #(#prelude)*
            #(#adds)*
        }

        #[doc = #head_doc]
        #[doc = ""]
        #[doc = "Adds one block's moments to `m`, the parameters passed by name."]
        #[inline]
        pub fn #fn_moments_named(m: &mut [f64; #count_ident], p: &#prefix #params_struct) {
            #fn_moments(m, #(p.#param_idents),*)
        }

        #[doc = #head_doc]
        #[doc = ""]
        #[doc = "Value of the summed blocks whose moments are `m`, at unknowns `k`."]
        #[doc = ""]
        #[doc = #atoms_doc]
        pub fn #fn_value(k: &[f64; #nu], m: &[f64; #count_ident]) -> f64 {
            #(#v_stmts)*
            #v_out
        }

        #[doc = #head_doc]
        #[doc = ""]
        #[doc = "Value and gradient with respect to the unknowns (for line searches)."]
        pub fn #fn_grad(k: &[f64; #nu], m: &[f64; #count_ident]) -> (f64, [f64; #nu]) {
            #(#g_stmts)*
            (#gv, [#(#gg),*])
        }

        #[doc = #head_doc]
        #[doc = ""]
        #[doc = "Value, gradient and the upper triangle of the Hessian (row by row)."]
        pub fn #fn_hess(k: &[f64; #nu], m: &[f64; #count_ident]) -> (f64, [f64; #nu], [f64; #nh]) {
            #(#h_stmts)*
            (#hv, [#(#hg),*], [#(#hh),*])
        }

        #hess_lanes

        #jacobian_tokens
    };
    Ok((tokens, reports))
}
