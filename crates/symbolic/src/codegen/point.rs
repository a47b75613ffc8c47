//! Point kernels (end kinematics), differentiated directly on the DAG.

use proc_macro2::{Ident, Literal, TokenStream};
use quote::quote;

use super::{ident, upper_pairs, FunctionReport};
use crate::emit::{tree_ops, Emitter, OpCount};
use crate::expr::{Arena, ExprId, SymError};
use crate::spec::{PointDef, Spec};

pub(super) fn point_kernel(
    spec: &mut Spec,
    def: &PointDef,
    lanes: Option<&TokenStream>,
) -> Result<(TokenStream, Vec<FunctionReport>), SymError> {
    let arena = &mut spec.arena;
    let unknowns = spec.unknowns.clone();
    let n = unknowns.len();
    let no = def.outputs.len();
    let values: Vec<ExprId> = def.outputs.iter().map(|o| o.1).collect();
    let mut grads = Vec::new();
    let mut hess = Vec::new();
    for &v in &values {
        let g: Vec<ExprId> = unknowns
            .iter()
            .map(|&u| arena.diff(v, u))
            .collect::<Result<_, _>>()?;
        let mut h = Vec::new();
        for (k, l) in upper_pairs(n) {
            h.push(arena.diff(g[k], unknowns[l])?);
        }
        grads.push(g);
        hess.push(h);
    }
    let arena_ro: &Arena = arena;
    let name = &def.name;
    let params: Vec<Ident> = def
        .params
        .iter()
        .map(|&p| ident(arena_ro.name(p)))
        .collect();
    let nu = Literal::usize_unsuffixed(n);
    let nh = Literal::usize_unsuffixed(n * (n + 1) / 2);
    let nout = Literal::usize_unsuffixed(no);
    let nhu = n * (n + 1) / 2;
    let outs_doc: Vec<String> = def
        .outputs
        .iter()
        .enumerate()
        .map(|(i, (o, e))| format!("- `[{i}]` {o} = `{}`", arena_ro.show(*e)))
        .collect();
    let head_doc = format!("Point kernel `{name}`. Outputs:\n{}", outs_doc.join("\n"));

    let emit = |roots: &[ExprId]| -> (Vec<TokenStream>, Vec<TokenStream>, OpCount, OpCount) {
        let mut em = Emitter::new(arena_ro, roots, "tmp");
        let mut pre = Vec::new();
        for (i, &u) in unknowns.iter().enumerate() {
            if roots.iter().any(|&r| arena_ro.free_symbols(r).contains(&u)) {
                let id = ident(arena_ro.name(u));
                let idx = Literal::usize_unsuffixed(i);
                pre.push(quote! { let #id = k[#idx]; });
                em.bind_symbol(u, quote! { #id });
            }
        }
        let outs: Vec<TokenStream> = roots.iter().map(|&r| em.expr(r)).collect();
        pre.extend(em.take_statements());
        (pre, outs, tree_ops(arena_ro, roots), em.ops())
    };
    let fn_value = ident(&format!("{name}_value"));
    let fn_hess = ident(&format!("{name}_hessian"));
    let (v_stmts, v_outs, b, a) = emit(&values);
    let mut reports = vec![FunctionReport {
        function: fn_value.to_string(),
        ops_before_cse: b,
        ops_after_cse: a,
    }];
    let mut all = values.clone();
    for g in &grads {
        all.extend(g.iter().copied());
    }
    for h in &hess {
        all.extend(h.iter().copied());
    }
    let mut with_grads = values.clone();
    for g in &grads {
        with_grads.extend(g.iter().copied());
    }
    let (g_stmts, g_outs, b, a) = emit(&with_grads);
    let fn_grad = ident(&format!("{name}_gradient"));
    reports.push(FunctionReport {
        function: fn_grad.to_string(),
        ops_before_cse: b,
        ops_after_cse: a,
    });
    let gv = &g_outs[..no];
    let gg: Vec<TokenStream> = (0..no)
        .map(|o| {
            let row = &g_outs[no + o * n..no + (o + 1) * n];
            quote! { [#(#row),*] }
        })
        .collect();
    let (h_stmts, h_outs, b, a) = emit(&all);
    reports.push(FunctionReport {
        function: fn_hess.to_string(),
        ops_before_cse: b,
        ops_after_cse: a,
    });
    // derivatives only (no values: an atan2 value costs more than its derivatives)
    let mut derivs: Vec<ExprId> = Vec::new();
    for g in &grads {
        derivs.extend(g.iter().copied());
    }
    for h in &hess {
        derivs.extend(h.iter().copied());
    }
    let (d_stmts, d_outs, b, a) = emit(&derivs);
    // a kernel linear in the unknowns has constant derivatives
    let d_arg = if derivs.iter().any(|&r| {
        arena_ro
            .free_symbols(r)
            .iter()
            .any(|s| unknowns.contains(s))
    }) {
        ident("k")
    } else {
        ident("_k")
    };
    let fn_derivs = ident(&format!("{name}_derivatives"));
    reports.push(FunctionReport {
        function: fn_derivs.to_string(),
        ops_before_cse: b,
        ops_after_cse: a,
    });
    let dg: Vec<TokenStream> = (0..no)
        .map(|o| {
            let row = &d_outs[o * n..(o + 1) * n];
            quote! { [#(#row),*] }
        })
        .collect();
    let dh: Vec<TokenStream> = (0..no)
        .map(|o| {
            let start = no * n + o * (n * (n + 1) / 2);
            let row = &d_outs[start..start + n * (n + 1) / 2];
            quote! { [#(#row),*] }
        })
        .collect();
    // the derivatives on lanes (one element per lane): the same statements
    // on the lane type, a constant output splatted into the lanes
    let derivs_lanes = lanes.map(|path| {
        let outs: Vec<TokenStream> = d_outs
            .iter()
            .zip(&derivs)
            .map(|(t, &e)| match arena_ro.as_num(e) {
                Some(_) => quote! { T::splat(#t) },
                None => t.clone(),
            })
            .collect();
        let lg = (0..no).map(|o| {
            let row = &outs[o * n..(o + 1) * n];
            quote! { [#(#row),*] }
        });
        let lh = (0..no).map(|o| {
            let start = no * n + o * nhu;
            let row = &outs[start..start + nhu];
            quote! { [#(#row),*] }
        });
        let fn_lanes = ident(&format!("{name}_derivatives_lanes"));
        let doc = "On lanes: each lane of `k` and the parameters holds one element's, and each lane of the result is bit for bit that element's `derivatives` result (the same statements in the same order).";
        quote! {
            #[doc = #head_doc]
            #[doc = ""]
            #[doc = #doc]
            #[inline(always)]
            pub fn #fn_lanes<T: #path::Lane>(#d_arg: &[T; #nu], #(#params: T),*) -> ([[T; #nu]; #nout], [[T; #nh]; #nout])
            where
                f64: #path::LaneScalar<T>,
            {
                #(#d_stmts)*
                ([#(#lg),*], [#(#lh),*])
            }
        }
    });
    let hv = &h_outs[..no];
    let hg: Vec<TokenStream> = (0..no)
        .map(|o| {
            let row = &h_outs[no + o * n..no + (o + 1) * n];
            quote! { [#(#row),*] }
        })
        .collect();
    let hh: Vec<TokenStream> = (0..no)
        .map(|o| {
            let start = no + no * n + o * nhu;
            let row = &h_outs[start..start + nhu];
            quote! { [#(#row),*] }
        })
        .collect();
    let tokens = quote! {
        #derivs_lanes

        #[doc = #head_doc]
        pub fn #fn_value(k: &[f64; #nu], #(#params: f64),*) -> [f64; #nout] {
            #(#v_stmts)*
            [#(#v_outs),*]
        }

        #[doc = #head_doc]
        #[doc = ""]
        #[doc = "Values and gradients of each output."]
        pub fn #fn_grad(k: &[f64; #nu], #(#params: f64),*) -> ([f64; #nout], [[f64; #nu]; #nout]) {
            #(#g_stmts)*
            ([#(#gv),*], [#(#gg),*])
        }

        #[doc = #head_doc]
        #[doc = ""]
        #[doc = "Gradients and upper-triangle Hessians (row by row) of each output, without the values."]
        pub fn #fn_derivs(#d_arg: &[f64; #nu], #(#params: f64),*) -> ([[f64; #nu]; #nout], [[f64; #nh]; #nout]) {
            #(#d_stmts)*
            ([#(#dg),*], [#(#dh),*])
        }

        #[doc = #head_doc]
        #[doc = ""]
        #[doc = "Values, gradients and upper-triangle Hessians (row by row) of each output."]
        pub fn #fn_hess(k: &[f64; #nu], #(#params: f64),*) -> ([f64; #nout], [[f64; #nu]; #nout], [[f64; #nh]; #nout]) {
            #(#h_stmts)*
            ([#(#hv),*], [#(#hg),*], [#(#hh),*])
        }
    };
    Ok((tokens, reports))
}
