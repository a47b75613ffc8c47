//! Kernel generation: a pure function from spec text to Rust tokens.
//!
//! **Integral kernels** are split in two so one generated kernel serves
//! every block (lamina, channel void, rib) and every element:
//!
//! 1. The density is expanded in the integration variables and the
//!    parameters only; the coefficients stay factored expressions of the
//!    unknowns. Their distinct factors are the kernel's *atoms* (for the
//!    CCM: `a1`, `3*a3 + 2*c2^2`, `c2`, `b1`), and each distinct product of
//!    atoms is a *slot*.
//! 2. Integrating term by term gives `energy = sum_s m_s * slot_s(atoms)`,
//!    where the moment `m_s` is a polynomial in the parameters and the
//!    exact 1-D moments `(hi^(j+1) - lo^(j+1))/(j+1)`. Energy is linear in
//!    the moments, so blocks add: `NAME_moments` accumulates one block's
//!    moments into an array once per scene, and `NAME_value`,
//!    `NAME_gradient` and `NAME_hessian` evaluate the sum for given unknowns.
//!
//! Derivatives are taken with respect to the atoms (as polynomials, exact)
//! and chained to the unknowns with the atoms' symbolic Jacobian and
//! Hessian, which keeps the straight-line code short. Polynomials are
//! emitted in Horner form; shared sub-expressions are bound once.
//!
//! **Point kernels** (end kinematics) are differentiated directly on the DAG.
//! On request ([`point_polynomial`]), a point kernel's outputs are also
//! expanded as polynomials in one parameter and their coefficients emitted.

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::quote;

use crate::emit::OpCount;
use crate::expr::{Arena, Sym, SymError};
use crate::parse::ParseError;
use crate::spec::{parse_spec, Spec};

mod energy;
mod integral;
mod moments;
mod point;
mod polynomial;
mod scalar;

use energy::energy_fns;
use integral::integral_kernel;
use point::point_kernel;
use scalar::{law_fn, unscale_fn};

pub use polynomial::{point_polynomial, PolynomialKernel};

/// Why generation failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GenError {
    /// The spec did not parse.
    #[error("energy spec: {0}")]
    Parse(#[from] ParseError),
    /// Algebra failed (overflow, non-polynomial density).
    #[error("energy spec, kernel `{kernel}` (line {line}): {source}")]
    Algebra {
        /// kernel name
        kernel: String,
        /// its statement's line
        line: usize,
        /// the failure
        source: SymError,
    },
    /// A kernel or parameter asked for is not in the spec.
    #[error("energy spec has no {what}")]
    Missing {
        /// what was asked for
        what: String,
    },
    /// The generated tokens did not form a Rust file (a generator bug).
    #[error("generated code does not parse as Rust: {0}")]
    Syntax(String),
}

/// Operation counts of one generated function.
#[derive(Debug, Clone, PartialEq)]
pub struct FunctionReport {
    /// Rust function name.
    pub function: String,
    /// Operations if every sub-expression were recomputed at each use.
    pub ops_before_cse: OpCount,
    /// Operations in the emitted straight-line code.
    pub ops_after_cse: OpCount,
}

/// The generated module and its per-function report.
#[derive(Debug, Clone)]
pub struct Generated {
    /// The module's items.
    pub tokens: TokenStream,
    /// One entry per generated function.
    pub report: Vec<FunctionReport>,
}

/// Where the parameter structs of the generated functions live, and
/// whether to emit lane-generic kernels.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// A Rust path (e.g. `super::params`) holding the parameter structs
    /// ([`param_structs`]) that several generated modules share; `None`
    /// emits them into the module itself.
    pub shared_params: Option<TokenStream>,
    /// A Rust path holding the traits `Lane` and `LaneScalar` (the fpc
    /// crate's `lanes` module): with it, every integral kernel's value,
    /// gradient and Hessian and the energy's are emitted a second time as
    /// `*_value_lanes`, `*_gradient_lanes` and `*_hessian_lanes`,
    /// generic over a lane type holding one number per element (the same
    /// statements in the same order, so each lane is bit for bit the scalar
    /// kernel's result), with a `MomentLanes` struct of moments side by
    /// side, and the derivatives of the point kernels named in
    /// [`lane_points`](Self::lane_points) as `*_derivatives_lanes`. `None`
    /// emits none.
    pub lanes: Option<TokenStream>,
    /// The point kernels whose derivatives are emitted on lanes too (with
    /// [`lanes`](Self::lanes)): the ones a caller evaluates for several
    /// elements at once.
    pub lane_points: Vec<String>,
}

/// A named parameter struct of a generated function: integral kernels take
/// their parameters as one (`LinearParams` for `integral linear(...)`), a
/// law its constants (`PsiParams`), the energy its scalars (`EnergyScalars`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ParamStruct {
    /// Rust type name.
    pub name: String,
    /// What it parametrises.
    pub doc: String,
    /// Field names, in the spec's order.
    pub fields: Vec<String>,
}

impl ParamStruct {
    /// The struct's definition (`Debug, Clone, Copy, PartialEq`, `f64` fields).
    pub fn tokens(&self) -> TokenStream {
        let name = ident(&self.name);
        let doc = &self.doc;
        let fields: Vec<Ident> = self.fields.iter().map(|f| ident(f)).collect();
        let names = &self.fields;
        let count = Literal::usize_unsuffixed(self.fields.len());
        let idx: Vec<Literal> = (0..self.fields.len())
            .map(Literal::usize_unsuffixed)
            .collect();
        quote! {
            #[doc = #doc]
            #[derive(Debug, Clone, Copy, PartialEq)]
            pub struct #name {
                #(#[doc = "Parameter of the spec."] pub #fields: f64,)*
            }

            impl #name {
                #[doc = "The field names, in the spec's order."]
                pub const FIELDS: &'static [&'static str] = &[#(#names),*];

                #[doc = "The fields' values, in the spec's order."]
                pub fn to_values(&self) -> [f64; #count] {
                    [#(self.#fields),*]
                }

                #[doc = "The struct of values in the spec's order."]
                pub fn from_values(v: [f64; #count]) -> Self {
                    Self { #(#fields: v[#idx],)* }
                }
            }
        }
    }
}

/// `linear` -> `Linear`, `end_kin` -> `EndKin`.
fn camel(name: &str) -> String {
    name.split('_')
        .filter(|p| !p.is_empty())
        .map(|p| {
            let mut c = p.chars();
            c.next()
                .map(|f| f.to_ascii_uppercase().to_string() + c.as_str())
                .unwrap_or_default()
        })
        .collect()
}

/// The parameter structs a spec's generated functions take.
pub fn param_structs(spec: &Spec) -> Vec<ParamStruct> {
    let names = |syms: &[Sym]| -> Vec<String> {
        syms.iter()
            .map(|&s| spec.arena.name(s).to_string())
            .collect()
    };
    let mut out: Vec<ParamStruct> = spec
        .integrals
        .iter()
        .map(|d| ParamStruct {
            name: format!("{}Params", camel(&d.name)),
            doc: format!(
                "Parameters of one `{}` box (integral kernel `{}` of the spec).",
                d.name, d.name
            ),
            fields: names(&d.params),
        })
        .collect();
    out.extend(spec.laws.iter().map(|l| ParamStruct {
        name: format!("{}Params", camel(&l.name)),
        doc: format!("Constants of the law `{}`.", l.name),
        fields: names(&l.params),
    }));
    if let Some(e) = &spec.energy {
        out.push(ParamStruct {
            name: "EnergyScalars".into(),
            doc: "The runtime scalars of the energy's coefficients.".into(),
            fields: names(&e.scalars),
        });
    }
    out
}

/// Generates kernels from spec text, with the parameter structs in the module.
pub fn generate(src: &str) -> Result<Generated, GenError> {
    generate_with(src, &Options::default())
}

/// Generates kernels from spec text.
pub fn generate_with(src: &str, options: &Options) -> Result<Generated, GenError> {
    let mut spec = parse_spec(src)?;
    let mut items = Vec::new();
    let mut report = Vec::new();
    let n = spec.unknowns.len();
    let nu = Literal::usize_unsuffixed(n);
    let nh = Literal::usize_unsuffixed(n * (n + 1) / 2);
    let names: Vec<String> = spec
        .unknowns
        .iter()
        .map(|&s| spec.arena.name(s).to_string())
        .collect();
    let unknown_doc = format!("Unknowns, in order: `{}`.", names.join(", "));
    items.push(quote! {
        #[doc = "Number of unknowns per element."]
        #[doc = #unknown_doc]
        pub const UNKNOWNS: usize = #nu;
        #[doc = "Number of unique Hessian entries: the upper triangle, row by row \
                 (`(0,0), (0,1), ..., (0,n-1), (1,1), ...`)."]
        pub const HESSIAN_ENTRIES: usize = #nh;
    });
    let structs = param_structs(&spec);
    let prefix = match &options.shared_params {
        Some(path) => quote! { #path:: },
        None => {
            items.extend(structs.iter().map(ParamStruct::tokens));
            TokenStream::new()
        }
    };
    if let Some(def) = spec.scaled.clone() {
        let wrap = |e: SymError| GenError::Algebra {
            kernel: "scaled".into(),
            line: def.line,
            source: e,
        };
        items.push(unscale_fn(&mut spec, &def).map_err(wrap)?);
    }
    if !spec.local.is_empty() || spec.scaled.is_some() {
        let idx: Vec<Literal> = spec
            .local
            .iter()
            .map(|s| {
                Literal::usize_unsuffixed(spec.unknowns.iter().position(|u| u == s).unwrap_or(0))
            })
            .collect();
        let names: Vec<&str> = spec.local.iter().map(|&s| spec.arena.name(s)).collect();
        let doc = format!(
            "Positions of the unknowns local to their element (`{}`): they couple \
             only within the element and can be condensed out of a coupled system.",
            names.join(", ")
        );
        items.push(quote! {
            #[doc = #doc]
            pub const LOCAL: &[usize] = &[#(#idx),*];
        });
    }
    let integrals = spec.integrals.clone();
    for def in &integrals {
        let wrap = |e: SymError| GenError::Algebra {
            kernel: def.name.clone(),
            line: def.line,
            source: e,
        };
        let (tokens, rep) =
            integral_kernel(&mut spec, def, &prefix, options.lanes.as_ref()).map_err(wrap)?;
        items.push(tokens);
        report.extend(rep);
    }
    if let Some(def) = spec.energy.clone() {
        let wrap = |e: SymError| GenError::Algebra {
            kernel: "energy".into(),
            line: def.line,
            source: e,
        };
        items.push(energy_fns(&mut spec, &def, &prefix, options.lanes.as_ref()).map_err(wrap)?);
    }
    let laws = spec.laws.clone();
    for def in &laws {
        let wrap = |e: SymError| GenError::Algebra {
            kernel: def.name.clone(),
            line: def.line,
            source: e,
        };
        let (tokens, rep) = law_fn(&mut spec, def, &prefix).map_err(wrap)?;
        items.push(tokens);
        report.push(rep);
    }
    let points = spec.points.clone();
    let lanes_for = |name: &String| {
        options
            .lanes
            .as_ref()
            .filter(|_| options.lane_points.contains(name))
    };
    for def in &points {
        let wrap = |e: SymError| GenError::Algebra {
            kernel: def.name.clone(),
            line: def.line,
            source: e,
        };
        let (tokens, rep) = point_kernel(&mut spec, def, lanes_for(&def.name)).map_err(wrap)?;
        items.push(tokens);
        report.extend(rep);
    }
    let _ = nh;
    Ok(Generated {
        tokens: quote! { #(#items)* },
        report,
    })
}

/// Formats generated tokens as a Rust file with prettyplease.
pub fn format_file(tokens: &TokenStream) -> Result<String, GenError> {
    let file: syn::File =
        syn::parse2(tokens.clone()).map_err(|e| GenError::Syntax(e.to_string()))?;
    Ok(prettyplease::unparse(&file))
}

fn ident(s: &str) -> Ident {
    Ident::new(s, Span::call_site())
}

/// A name not used by any symbol of the arena.
fn fresh_symbol(arena: &mut Arena, base: &str) -> Sym {
    let mut name = base.to_string();
    while arena.find_symbol(&name).is_some() {
        name.insert(0, '_');
    }
    arena.symbol(&name)
}

/// Index pairs of the upper triangle, row by row.
fn upper_pairs(n: usize) -> Vec<(usize, usize)> {
    (0..n).flat_map(|i| (i..n).map(move |j| (i, j))).collect()
}

/// A plain-text table of operation counts per generated function.
pub fn report_table(report: &[FunctionReport]) -> String {
    let mut s = String::from(
        "function                  ops before CSE   ops after CSE   (add / mul / div / fn after)\n",
    );
    for r in report {
        let a = r.ops_after_cse;
        s.push_str(&format!(
            "{:<25} {:>14} {:>15}   ({} / {} / {} / {})\n",
            r.function,
            r.ops_before_cse.total(),
            a.total(),
            a.add,
            a.mul,
            a.div,
            a.func
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_kernels_go_on_lanes_only_where_named() {
        let src = "unknowns a, b;\n\
                   let u = a*x + b*x^3;\n\
                   point end(L) { X = at(x + u, x, L); }\n\
                   point mid(x) { X = x + u; }\n";
        let names = |options: &Options| {
            let tokens = generate_with(src, options).unwrap().tokens;
            let text = format_file(&tokens).unwrap();
            ["end", "mid"].map(|p| text.contains(&format!("fn {p}_derivatives_lanes")))
        };
        let lanes = Some(quote! { super });
        let none = Options::default();
        assert_eq!(names(&none), [false, false]);
        let all_off = Options {
            lanes: lanes.clone(),
            ..Options::default()
        };
        assert_eq!(names(&all_off), [false, false]);
        let end = Options {
            lanes: lanes.clone(),
            lane_points: vec!["end".into()],
            ..Options::default()
        };
        assert_eq!(names(&end), [true, false]);
        // naming a point without `lanes` emits nothing on lanes
        let no_path = Options {
            lane_points: vec!["end".into(), "mid".into()],
            ..Options::default()
        };
        assert_eq!(names(&no_path), [false, false]);
    }
}
