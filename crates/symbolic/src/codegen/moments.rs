//! The moment-Jacobian generator: the derivatives of an integral's moments
//! with respect to its parameters, through the range bounds.

use proc_macro2::{Ident, Literal, TokenStream};
use quote::quote;

use super::integral::Slot;
use super::{ident, FunctionReport};
use crate::emit::{tree_ops, Emitter, OpCount};
use crate::expr::{Arena, ExprId, Sym, SymError};
use crate::rational::Rational;

/// The Jacobian of an integral's moments with respect to its parameters:
/// `dm_s/dp_j = dP_s/dp_j + sum_mu dP_s/dmu dmu/dp_j`, where `P_s` is slot
/// `s`'s moment as a polynomial in the parameters and the 1-D moments `mu`
/// (the chain rule through the range bounds). The `dP_s/dmu` are shared by
/// every column.
pub(super) struct MomentsJacobian {
    /// The 1-D moments (as in the moments kernel).
    moments: Vec<(Sym, ExprId, String)>,
    /// `columns[j][s] = dm_s/dp_j`.
    columns: Vec<Vec<ExprId>>,
}

pub(super) fn moments_jacobian(
    arena: &mut Arena,
    params: &[Sym],
    slots: &[Slot],
    moment_defs: &[(Sym, ExprId, String)],
) -> Result<MomentsJacobian, SymError> {
    // dmu/dp_j per 1-D moment and parameter
    let mut dmu = Vec::with_capacity(moment_defs.len());
    for (_, d, _) in moment_defs {
        let row: Vec<ExprId> = params
            .iter()
            .map(|&p| arena.diff(*d, p))
            .collect::<Result<_, _>>()?;
        dmu.push(row);
    }
    // dP_s/dmu, shared by the columns
    let mut dpdmu = Vec::with_capacity(slots.len());
    for slot in slots {
        let mut row = Vec::with_capacity(moment_defs.len());
        for (ms, _, _) in moment_defs {
            let d = slot.moment.diff(*ms)?;
            row.push(if d.is_zero() {
                None
            } else {
                Some(arena.horner(&d, &[])?)
            });
        }
        dpdmu.push(row);
    }
    let mut columns = Vec::with_capacity(params.len());
    for (j, &p) in params.iter().enumerate() {
        let mut col = Vec::with_capacity(slots.len());
        for (s, slot) in slots.iter().enumerate() {
            let mut terms = Vec::new();
            let direct = slot.moment.diff(p)?;
            if !direct.is_zero() {
                terms.push(arena.horner(&direct, &[])?);
            }
            for (mu, dp) in dpdmu[s].iter().enumerate() {
                if let Some(dp) = *dp {
                    let inner = dmu[mu][j];
                    if arena.as_num(inner) != Some(Rational::ZERO) {
                        terms.push(arena.mul2(dp, inner)?);
                    }
                }
            }
            col.push(arena.add(&terms)?);
        }
        columns.push(col);
    }
    Ok(MomentsJacobian {
        moments: moment_defs.to_vec(),
        columns,
    })
}

impl MomentsJacobian {
    /// `NAME_dmoments_at` (straight-line, positional) and `NAME_dmoments`
    /// (the parameters by name).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn emit(
        &self,
        arena: &Arena,
        name: &str,
        params: &[Sym],
        param_idents: &[Ident],
        count_ident: &Ident,
        params_struct: &Ident,
        prefix: &TokenStream,
    ) -> (TokenStream, FunctionReport) {
        let entries: Vec<ExprId> = self.columns.iter().flatten().copied().collect();
        let mut roots: Vec<ExprId> = self.moments.iter().map(|d| d.1).collect();
        roots.extend(entries.iter().copied());
        let mut em = Emitter::new(arena, &roots, "tmp");
        let used = |s: Sym| entries.iter().any(|&e| arena.free_symbols(e).contains(&s));
        let mut before = OpCount::default();
        let mut emitted: Vec<ExprId> = Vec::new();
        for (s, d, label) in &self.moments {
            if used(*s) {
                let t = em.let_named(label, *d);
                em.bind_symbol(*s, t);
                before += tree_ops(arena, &[*d]);
                emitted.push(*d);
            }
        }
        let cols: Vec<TokenStream> = self
            .columns
            .iter()
            .map(|col| {
                let vals: Vec<TokenStream> = col.iter().map(|&e| em.expr(e)).collect();
                quote! { [#(#vals),*] }
            })
            .collect();
        before += tree_ops(arena, &entries);
        let after = em.ops();
        let stmts = em.take_statements();
        emitted.extend(entries.iter().copied());
        let free: std::collections::HashSet<Sym> = emitted
            .iter()
            .flat_map(|&e| arena.free_symbols(e))
            .collect();
        // an argument nothing depends on is named `_...` (no unused warning)
        let args: Vec<Ident> = params
            .iter()
            .zip(param_idents)
            .map(|(&s, id)| {
                if free.contains(&s) {
                    id.clone()
                } else {
                    ident(&format!("_{id}"))
                }
            })
            .collect();
        let np = Literal::usize_unsuffixed(params.len());
        let fn_at = ident(&format!("{name}_dmoments_at"));
        let fn_named = ident(&format!("{name}_dmoments"));
        let head_doc = format!(
            "Kernel `{name}`: the Jacobian of one block's moments with respect to its \
             parameters, one column per parameter (`[j][s]` = d `m[s]` / d `p_j`). The \
             moments of an element add over its blocks, and so do their derivatives; \
             the energy is linear in the moments, so the gradient kernels evaluated at \
             a column give the gradient's derivative."
        );
        let at_doc = format!(
            "Parameters (and columns, in this order): `{}`.",
            param_idents
                .iter()
                .map(|i| i.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
        let tokens = quote! {
            #[doc = #head_doc]
            #[doc = ""]
            #[doc = #at_doc]
            fn #fn_at(#(#args: f64),*) -> [[f64; #count_ident]; #np] {
                #(#stmts)*
                [#(#cols),*]
            }

            #[doc = #head_doc]
            #[doc = ""]
            #[doc = "The parameters passed by name."]
            #[inline]
            pub fn #fn_named(p: &#prefix #params_struct) -> [[f64; #count_ident]; #np] {
                #fn_at(#(p.#param_idents),*)
            }
        };
        (
            tokens,
            FunctionReport {
                function: fn_at.to_string(),
                ops_before_cse: before,
                ops_after_cse: after,
            },
        )
    }
}
