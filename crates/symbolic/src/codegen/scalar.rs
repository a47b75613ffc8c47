//! Single-expression functions of the parameters: the unscale factors of
//! the scaled unknowns and the material laws with their derivatives.

use proc_macro2::{Ident, Literal, TokenStream};
use quote::quote;

use super::{camel, ident, FunctionReport};
use crate::emit::{tree_ops, Emitter};
use crate::expr::{Arena, ExprId, SymError};
use crate::spec::{LawDef, ScaledDef, Spec};

/// `pub fn unscale(params) -> [f64; n]`: the raw unknown per unit of the
/// solver's scaled unknown, `1 / factor_i`.
pub(super) fn unscale_fn(spec: &mut Spec, def: &ScaledDef) -> Result<TokenStream, SymError> {
    let arena = &mut spec.arena;
    let one = arena.int(1);
    let inv: Vec<ExprId> = def
        .factors
        .iter()
        .map(|&f| arena.div(one, f))
        .collect::<Result<_, _>>()?;
    let arena_ro: &Arena = arena;
    let params: Vec<Ident> = def
        .params
        .iter()
        .map(|&p| ident(arena_ro.name(p)))
        .collect();
    let mut em = Emitter::new(arena_ro, &inv, "tmp");
    let outs: Vec<TokenStream> = inv.iter().map(|&e| em.expr(e)).collect();
    let stmts = em.take_statements();
    let n = Literal::usize_unsuffixed(spec.unknowns.len());
    let scaled: Vec<String> = spec
        .unknowns
        .iter()
        .zip(&def.factors)
        .map(|(&u, &f)| format!("`{} * ({})`", arena_ro.name(u), arena_ro.show(f)))
        .collect();
    let doc = format!(
        "The solver's unknowns are {}; this gives, per unknown, the raw value of one \
         scaled unit (`raw = scaled * unscale`).",
        scaled.join(", ")
    );
    Ok(quote! {
        #[doc = #doc]
        pub fn unscale(#(#params: f64),*) -> [f64; #n] {
            #(#stmts)*
            [#(#outs),*]
        }
    })
}

/// `pub fn NAME(var, &Params) -> [f64; 3]`: a law with its first two derivatives.
pub(super) fn law_fn(
    spec: &mut Spec,
    def: &LawDef,
    prefix: &TokenStream,
) -> Result<(TokenStream, FunctionReport), SymError> {
    let arena = &mut spec.arena;
    let d1 = arena.diff(def.expr, def.var)?;
    let d2 = arena.diff(d1, def.var)?;
    let roots = [def.expr, d1, d2];
    let arena_ro: &Arena = arena;
    let mut em = Emitter::new(arena_ro, &roots, "tmp");
    let var = ident(arena_ro.name(def.var));
    em.bind_symbol(def.var, quote! { #var });
    let mut pre = Vec::new();
    for &p in &def.params {
        let id = ident(arena_ro.name(p));
        pre.push(quote! { let #id = p.#id; });
        em.bind_symbol(p, quote! { #id });
    }
    let outs: Vec<TokenStream> = roots.iter().map(|&r| em.expr(r)).collect();
    pre.extend(em.take_statements());
    let name = ident(&def.name);
    let st = ident(&format!("{}Params", camel(&def.name)));
    let doc = format!(
        "Law `{}({})` = `{}`: value, first and second derivative in `{}`.",
        def.name,
        arena_ro.name(def.var),
        arena_ro.show(def.expr),
        arena_ro.name(def.var)
    );
    let report = FunctionReport {
        function: def.name.clone(),
        ops_before_cse: tree_ops(arena_ro, &roots),
        ops_after_cse: em.ops(),
    };
    Ok((
        quote! {
            #[doc = #doc]
            pub fn #name(#var: f64, p: &#prefix #st) -> [f64; 3] {
                #(#pre)*
                [#(#outs),*]
            }
        },
        report,
    ))
}
