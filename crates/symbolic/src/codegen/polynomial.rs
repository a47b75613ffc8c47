//! A point kernel's outputs as polynomials in one of its parameters: the
//! coefficients as straight-line code of the unknowns (and of the kernel's
//! other parameters), so a runtime can treat the outputs as exact curves.

use proc_macro2::{Ident, Literal, TokenStream};
use quote::quote;

use super::{ident, FunctionReport, GenError};
use crate::emit::{tree_ops, Emitter};
use crate::expr::{Arena, ExprId, SymError};
use crate::poly::mono_degree;
use crate::spec::Spec;

/// The coefficient kernel of [`point_polynomial`].
#[derive(Debug, Clone)]
pub struct PolynomialKernel {
    /// `pub fn NAME_polynomial(k, other parameters) -> [[f64; outputs]; degree + 1]`.
    pub tokens: TokenStream,
    /// Its operation counts.
    pub report: FunctionReport,
    /// The highest power of the variable over every output (0 for outputs
    /// that do not depend on it).
    pub degree: usize,
    /// The generated function's name.
    pub function: String,
}

/// Expands every output of `point NAME(...)` as a polynomial in its
/// parameter `var` and emits `NAME_polynomial`, whose entry `[j][o]` is
/// the coefficient of `var^j` in output `o` (the spec's output order); the
/// kernel's other parameters stay arguments. Fails with
/// [`SymError::NotPolynomial`] (naming `var` and the offending
/// sub-expression) when an output is not a polynomial in `var`.
pub fn point_polynomial(
    spec: &mut Spec,
    point: &str,
    var: &str,
) -> Result<PolynomialKernel, GenError> {
    let def = spec
        .points
        .iter()
        .find(|p| p.name == point)
        .cloned()
        .ok_or_else(|| GenError::Missing {
            what: format!("`point {point}`"),
        })?;
    let Some(v) = def
        .params
        .iter()
        .copied()
        .find(|&p| spec.arena.name(p) == var)
    else {
        return Err(GenError::Missing {
            what: format!("parameter `{var}` of `point {point}`"),
        });
    };
    let wrap = |source: SymError| GenError::Algebra {
        kernel: point.to_string(),
        line: def.line,
        source,
    };
    let arena = &mut spec.arena;
    let mut expanded = Vec::with_capacity(def.outputs.len());
    for (_, e) in &def.outputs {
        let m = arena.expand_in(*e, &|s| s == v).map_err(|e| match e {
            SymError::NotPolynomial { what, .. } => wrap(SymError::NotPolynomial {
                var: var.to_string(),
                what,
            }),
            other => wrap(other),
        })?;
        expanded.push(m);
    }
    let degree = expanded
        .iter()
        .flat_map(|m| m.keys().map(|mono| mono_degree(mono, v)))
        .max()
        .unwrap_or(0) as usize;
    // roots[j * outputs + o]: the coefficient of var^j in output o
    let mut roots: Vec<ExprId> = Vec::with_capacity((degree + 1) * def.outputs.len());
    for j in 0..=degree {
        for m in &expanded {
            let c = match m
                .iter()
                .find(|(mono, _)| mono_degree(mono, v) as usize == j)
            {
                Some((_, lc)) => lc.to_expr(arena).map_err(wrap)?,
                None => arena.int(0),
            };
            roots.push(c);
        }
    }
    let arena_ro: &Arena = arena;
    let mut em = Emitter::new(arena_ro, &roots, "tmp");
    let mut pre = Vec::new();
    let mut uses_k = false;
    for (i, &u) in spec.unknowns.iter().enumerate() {
        if roots.iter().any(|&r| arena_ro.free_symbols(r).contains(&u)) {
            let id = ident(arena_ro.name(u));
            let idx = Literal::usize_unsuffixed(i);
            pre.push(quote! { let #id = k[#idx]; });
            em.bind_symbol(u, quote! { #id });
            uses_k = true;
        }
    }
    let outs: Vec<TokenStream> = roots.iter().map(|&r| em.expr(r)).collect();
    pre.extend(em.take_statements());
    let no = def.outputs.len();
    let rows: Vec<TokenStream> = outs
        .chunks(no.max(1))
        .map(|row| quote! { [#(#row),*] })
        .collect();
    let others: Vec<Ident> = def
        .params
        .iter()
        .filter(|&&p| p != v)
        .map(|&p| ident(arena_ro.name(p)))
        .collect();
    let k_arg = if uses_k { ident("k") } else { ident("_k") };
    let nu = Literal::usize_unsuffixed(spec.unknowns.len());
    let nout = Literal::usize_unsuffixed(no);
    let ncoef = Literal::usize_unsuffixed(degree + 1);
    let names: Vec<String> = def.outputs.iter().map(|(o, _)| format!("`{o}`")).collect();
    let doc = format!(
        "Point kernel `{point}` as polynomials in `{var}` of degree {degree}: entry \
         `[j][o]` is the coefficient of `{var}^j` in output `o` ({}).",
        names.join(", ")
    );
    let function = format!("{point}_polynomial");
    let name = ident(&function);
    let report = FunctionReport {
        function: function.clone(),
        ops_before_cse: tree_ops(arena_ro, &roots),
        ops_after_cse: em.ops(),
    };
    let tokens = quote! {
        #[doc = #doc]
        pub fn #name(#k_arg: &[f64; #nu], #(#others: f64),*) -> [[f64; #nout]; #ncoef] {
            #(#pre)*
            [#(#rows),*]
        }
    };
    Ok(PolynomialKernel {
        tokens,
        report,
        degree,
        function,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::parse_spec;

    const SPEC: &str = "unknowns a, b;\n\
                        let u = a*x + b*x^3;\n\
                        point mid(x) { X = x + u; Z = (a + b*x)^2; }\n\
                        point bad(x) { X = sqrt(x); }\n\
                        point free(x) { X = a*b; }\n";

    #[test]
    fn coefficients_in_ascending_powers() {
        let mut spec = parse_spec(SPEC).unwrap();
        let k = point_polynomial(&mut spec, "mid", "x").unwrap();
        assert_eq!(k.degree, 3);
        assert_eq!(k.function, "mid_polynomial");
        let text = super::super::format_file(&k.tokens).unwrap();
        assert!(text.contains("-> [[f64; 2]; 4]"), "{text}");
    }

    #[test]
    fn not_polynomial_names_the_variable() {
        let mut spec = parse_spec(SPEC).unwrap();
        let e = point_polynomial(&mut spec, "bad", "x").unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains("not a polynomial in x"), "{msg}");
        assert!(msg.contains("sqrt(x)"), "{msg}");
    }

    #[test]
    fn constant_outputs_have_degree_zero() {
        let mut spec = parse_spec(SPEC).unwrap();
        let k = point_polynomial(&mut spec, "free", "x").unwrap();
        assert_eq!(k.degree, 0);
    }

    #[test]
    fn missing_point_or_parameter() {
        let mut spec = parse_spec(SPEC).unwrap();
        assert!(matches!(
            point_polynomial(&mut spec, "nope", "x"),
            Err(GenError::Missing { .. })
        ));
        assert!(matches!(
            point_polynomial(&mut spec, "mid", "y"),
            Err(GenError::Missing { .. })
        ));
    }
}
