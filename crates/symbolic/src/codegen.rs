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

use std::collections::{BTreeMap, HashMap};

use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;

use crate::emit::{literal, tree_ops, Emitter, OpCount};
use crate::expr::{Arena, ExprId, Node, Sym, SymError};
use crate::parse::ParseError;
use crate::poly::Poly;
use crate::rational::Rational;
use crate::spec::{parse_spec, EnergyDef, IntegralDef, LawDef, PointDef, ScaledDef, Spec};

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

/// Where the parameter structs of the generated functions live.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// A Rust path (e.g. `super::params`) holding the parameter structs
    /// ([`param_structs`]) that several generated modules share; `None`
    /// emits them into the module itself.
    pub shared_params: Option<TokenStream>,
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
        let (tokens, rep) = integral_kernel(&mut spec, def, &prefix).map_err(wrap)?;
        items.push(tokens);
        report.extend(rep);
    }
    if let Some(def) = spec.energy.clone() {
        let wrap = |e: SymError| GenError::Algebra {
            kernel: "energy".into(),
            line: def.line,
            source: e,
        };
        items.push(energy_fns(&mut spec, &def, &prefix).map_err(wrap)?);
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
    for def in &points {
        let wrap = |e: SymError| GenError::Algebra {
            kernel: def.name.clone(),
            line: def.line,
            source: e,
        };
        let (tokens, rep) = point_kernel(&mut spec, def).map_err(wrap)?;
        items.push(tokens);
        report.extend(rep);
    }
    let _ = nh;
    Ok(Generated {
        tokens: quote! { #(#items)* },
        report,
    })
}

use proc_macro2::Literal;

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

struct Slot {
    /// exponent per atom
    exps: Vec<u32>,
    /// moment as a polynomial in parameters and 1-D moment symbols
    moment: Poly,
}

fn integral_kernel(
    spec: &mut Spec,
    def: &IntegralDef,
    prefix: &TokenStream,
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

        #jacobian_tokens
    };
    Ok((tokens, reports))
}

/// The Jacobian of an integral's moments with respect to its parameters:
/// `dm_s/dp_j = dP_s/dp_j + sum_mu dP_s/dmu dmu/dp_j`, where `P_s` is slot
/// `s`'s moment as a polynomial in the parameters and the 1-D moments `mu`
/// (the chain rule through the range bounds). The `dP_s/dmu` are shared by
/// every column.
struct MomentsJacobian {
    /// The 1-D moments (as in the moments kernel).
    moments: Vec<(Sym, ExprId, String)>,
    /// `columns[j][s] = dm_s/dp_j`.
    columns: Vec<Vec<ExprId>>,
}

fn moments_jacobian(
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
    fn emit(
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

fn point_kernel(
    spec: &mut Spec,
    def: &PointDef,
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
    let hv = &h_outs[..no];
    let hg: Vec<TokenStream> = (0..no)
        .map(|o| {
            let row = &h_outs[no + o * n..no + (o + 1) * n];
            quote! { [#(#row),*] }
        })
        .collect();
    let nhu = n * (n + 1) / 2;
    let hh: Vec<TokenStream> = (0..no)
        .map(|o| {
            let start = no + no * n + o * nhu;
            let row = &h_outs[start..start + nhu];
            quote! { [#(#row),*] }
        })
        .collect();
    let tokens = quote! {
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

/// `pub fn unscale(params) -> [f64; n]`: the raw unknown per unit of the
/// solver's scaled unknown, `1 / factor_i`.
fn unscale_fn(spec: &mut Spec, def: &ScaledDef) -> Result<TokenStream, SymError> {
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
fn law_fn(
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

/// The `Moments` struct (one array per integral of the energy) and
/// `energy_value`, `energy_gradient`, `energy_hessian`: the integrals
/// combined with their coefficients. A term whose coefficient is not a
/// constant is skipped when the coefficient is zero (no gas kernel at zero
/// pressure, say).
fn energy_fns(
    spec: &mut Spec,
    def: &EnergyDef,
    prefix: &TokenStream,
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
        if i == 0 && first_is_one {
            value.push(quote! { let mut v = #f_value(k, &m.#field); });
            grad.push(quote! { let (mut v, mut g) = #f_grad(k, &m.#field); });
            hess.push(quote! { let (mut v, mut g, mut h) = #f_hess(k, &m.#field); });
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
    }
    let (init_v, init_g, init_h) = if first_is_one {
        (TokenStream::new(), TokenStream::new(), TokenStream::new())
    } else {
        (
            quote! { let mut v = 0.0; },
            quote! { let mut v = 0.0; let mut g = [0.0; #nu]; },
            quote! { let mut v = 0.0; let mut g = [0.0; #nu]; let mut h = [0.0; #nh]; },
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
    Ok(quote! {
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
