//! The energy-spec language: a mechanician's description of what to
//! integrate and differentiate, parsed into expressions.
//!
//! ```text
//! # comments run to the end of the line
//! unknowns a1, a3, b1, c2;               # the per-element unknowns, in order
//! let u = a1*x + a3*x^3;                 # definitions, inlined where used
//! let ex = d(u, x) + 1/2*d(w, x)^2;      # d(e, v[, n]) differentiates, at(e, v, value) substitutes
//! integral linear(x0, x1, q11) = 1/2*q11*ex^2 over x in [x0, x1], z in [z0, z1];
//! point end(L) { Xe = at(x + u, x, L); eta = atan2(..., ...); }
//! model Ccm;                             # the generated model's name
//! scaled a1, a3*L^2;                     # the solver's unknowns: each unknown times a factor
//! local b1;                              # unknowns that couple only within their element
//! across b1;                             # unknowns of the strain across the width
//! straighten a3 by 2/3*c2^2;             # Newton solves for a3 + 2/3 c2^2 instead of a3
//! law psi(s);                            # a `let` of one variable: value and two derivatives
//! energy = linear - kp*gas;              # how the integrals combine; `kp` a runtime scalar
//! ```
//!
//! An `integral` is a box integral of a polynomial density; its parameters
//! are the runtime inputs (bounds, widths, material constants) and every
//! other free symbol must be an unknown or an integration variable. A
//! `point` kernel is a set of named outputs in the unknowns and its
//! parameters. Errors give line, column and what was expected.

use crate::expr::{Arena, ExprId, Sym};
use crate::parse::{ParseError, Parser, Tok};
use crate::rational::Rational;

/// A box integral to generate kernels for.
#[derive(Debug, Clone)]
pub struct IntegralDef {
    /// Kernel name (a Rust identifier).
    pub name: String,
    /// Runtime parameters, in the order the moments function takes them.
    pub params: Vec<Sym>,
    /// The density.
    pub integrand: ExprId,
    /// Integration variables with their bounds (`v in [lo, hi]`).
    pub ranges: Vec<(Sym, ExprId, ExprId)>,
    /// Line of the statement.
    pub line: usize,
}

/// Named outputs in the unknowns and some parameters.
#[derive(Debug, Clone)]
pub struct PointDef {
    /// Kernel name.
    pub name: String,
    /// Runtime parameters.
    pub params: Vec<Sym>,
    /// Outputs in order.
    pub outputs: Vec<(String, ExprId)>,
    /// Line of the statement.
    pub line: usize,
}

/// A material law: a `let` of one variable, emitted with its first two
/// derivatives in that variable.
#[derive(Debug, Clone)]
pub struct LawDef {
    /// The `let` name (also the generated function's name).
    pub name: String,
    /// The variable.
    pub var: Sym,
    /// The law's expression.
    pub expr: ExprId,
    /// Its other free symbols, in order of first appearance: runtime parameters.
    pub params: Vec<Sym>,
    /// Line of the statement.
    pub line: usize,
}

/// How the integrals combine into one energy: `sum_i coefficient_i * integral_i`.
#[derive(Debug, Clone)]
pub struct EnergyDef {
    /// (integral name, coefficient), in the order of the spec's integrals;
    /// each coefficient is an expression in the scalars only.
    pub terms: Vec<(String, ExprId)>,
    /// The runtime scalars of the coefficients, in order of first appearance.
    pub scalars: Vec<Sym>,
    /// Line of the statement.
    pub line: usize,
}

/// `straighten t by c*s^2;`: Newton solves for `t + c s^2` in place of
/// the unknown `t` (raw units), which makes a parabolic valley of the
/// energy (`t` following `-c s^2` at equilibrium) a straight one.
#[derive(Debug, Clone, PartialEq)]
pub struct StraightenDef {
    /// The unknown replaced.
    pub target: Sym,
    /// The unknown whose square shifts it.
    pub source: Sym,
    /// The coefficient `c`.
    pub coefficient: Rational,
    /// Line of the statement.
    pub line: usize,
}

/// The unknowns the solver works with: `scaled_i = unknown_i * factor_i`.
#[derive(Debug, Clone)]
pub struct ScaledDef {
    /// One factor per unknown, free of unknowns.
    pub factors: Vec<ExprId>,
    /// The factors' free symbols, in order of first appearance.
    pub params: Vec<Sym>,
    /// Line of the statement.
    pub line: usize,
}

/// A parsed spec.
#[derive(Debug, Clone)]
pub struct Spec {
    /// All expressions live here.
    pub arena: Arena,
    /// The model's name (`model NAME;`), if declared.
    pub model: Option<String>,
    /// The unknowns, in kernel-argument order.
    pub unknowns: Vec<Sym>,
    /// The solver's scaling of the unknowns (`scaled ...;`), if declared.
    pub scaled: Option<ScaledDef>,
    /// Unknowns declared local to their element (`local ...;`).
    pub local: Vec<Sym>,
    /// Unknowns of the strain across the width (`across ...;`): what a
    /// runtime holds at zero for plane strain.
    pub across: Vec<Sym>,
    /// Changes of Newton's unknowns (`straighten ...;`), in order.
    pub straighten: Vec<StraightenDef>,
    /// Box integrals.
    pub integrals: Vec<IntegralDef>,
    /// Point kernels.
    pub points: Vec<PointDef>,
    /// Material laws.
    pub laws: Vec<LawDef>,
    /// The energy combination (`energy = ...;`), if declared.
    pub energy: Option<EnergyDef>,
}

const KEYWORDS: [&str; 14] = [
    "unknowns",
    "let",
    "integral",
    "point",
    "over",
    "in",
    "model",
    "scaled",
    "local",
    "across",
    "straighten",
    "by",
    "law",
    "energy",
];

/// Free symbols of several expressions, in order of first appearance.
fn symbols_in_order(arena: &Arena, es: &[ExprId]) -> Vec<Sym> {
    let mut out = Vec::new();
    for &e in es {
        for s in arena.free_symbols(e) {
            if !out.contains(&s) {
                out.push(s);
            }
        }
    }
    out
}

fn is_rust_ident(s: &str) -> bool {
    let mut cs = s.chars();
    cs.next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && cs.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Parses a spec.
pub fn parse_spec(src: &str) -> Result<Spec, ParseError> {
    let mut arena = Arena::new();
    let mut unknowns = Vec::new();
    let mut integrals = Vec::new();
    let mut points: Vec<PointDef> = Vec::new();
    let mut model = None;
    let mut scaled = None;
    let mut local = Vec::new();
    let mut across = Vec::new();
    let mut straighten: Vec<StraightenDef> = Vec::new();
    let mut laws: Vec<LawDef> = Vec::new();
    let mut energy = None;
    {
        let mut p = Parser::new(src, &mut arena)?;
        let mut names_used: Vec<String> = Vec::new();
        loop {
            let t = p.peek().clone();
            match &t.tok {
                Tok::Eof => break,
                Tok::Ident(w) if w == "unknowns" => {
                    p.next();
                    if !unknowns.is_empty() {
                        return Err(p.error_at(&t, "a single `unknowns` statement"));
                    }
                    let list = ident_list(&mut p, ';', "an unknown's name")?;
                    for (name, tok) in list {
                        let s = p.arena.symbol(&name);
                        if unknowns.contains(&s) {
                            return Err(p.error_at(&tok, "distinct unknowns"));
                        }
                        unknowns.push(s);
                    }
                }
                Tok::Ident(w) if w == "let" => {
                    p.next();
                    let (name, tok) = definable_name(&mut p, "a name to define")?;
                    if p.lets.contains_key(&name) {
                        return Err(
                            p.error_at(&tok, &format!("a new name (`{name}` is already defined)"))
                        );
                    }
                    p.expect_punct('=')?;
                    let e = p.expr()?;
                    p.expect_punct(';')?;
                    p.lets.insert(name, e);
                }
                Tok::Ident(w) if w == "integral" => {
                    p.next();
                    let (name, tok) = kernel_name(&mut p, &mut names_used)?;
                    p.expect_punct('(')?;
                    let params = param_list(&mut p)?;
                    p.expect_punct('=')?;
                    let integrand = p.expr()?;
                    if !p.is_ident("over") {
                        return Err(p.error("`over` and the integration ranges"));
                    }
                    p.next();
                    let mut ranges = Vec::new();
                    loop {
                        let (v, vt) = definable_name(&mut p, "an integration variable")?;
                        let vs = p.arena.symbol(&v);
                        if ranges.iter().any(|(s, _, _)| *s == vs)
                            || params.contains(&vs)
                            || unknowns.contains(&vs)
                        {
                            return Err(p.error_at(&vt, "an integration variable that is not a parameter, an unknown or repeated"));
                        }
                        if !p.is_ident("in") {
                            return Err(p.error("`in`"));
                        }
                        p.next();
                        p.expect_punct('[')?;
                        let lo = p.expr()?;
                        p.expect_punct(',')?;
                        let hi = p.expr()?;
                        p.expect_punct(']')?;
                        for b in [lo, hi] {
                            for s in p.arena.free_symbols(b) {
                                if !params.contains(&s) {
                                    let n = p.arena.name(s).to_string();
                                    return Err(p.error_at(
                                        &vt,
                                        &format!(
                                            "bounds in the kernel's parameters (`{n}` is not one)"
                                        ),
                                    ));
                                }
                            }
                        }
                        ranges.push((vs, lo, hi));
                        if p.is_punct(',') {
                            p.next();
                            continue;
                        }
                        p.expect_punct(';')?;
                        break;
                    }
                    for s in p.arena.free_symbols(integrand) {
                        let known = params.contains(&s)
                            || unknowns.contains(&s)
                            || ranges.iter().any(|(v, _, _)| *v == s);
                        if !known {
                            let n = p.arena.name(s).to_string();
                            return Err(p.error_at(&tok, &format!(
                                "every symbol of the density to be an unknown, a parameter or an integration variable (`{n}` is none)"
                            )));
                        }
                    }
                    integrals.push(IntegralDef {
                        name,
                        params,
                        integrand,
                        ranges,
                        line: t.line,
                    });
                }
                Tok::Ident(w) if w == "point" => {
                    p.next();
                    let (name, tok) = kernel_name(&mut p, &mut names_used)?;
                    p.expect_punct('(')?;
                    let params = param_list(&mut p)?;
                    p.expect_punct('{')?;
                    let mut outputs: Vec<(String, ExprId)> = Vec::new();
                    while !p.is_punct('}') {
                        let (o, ot) = definable_name(&mut p, "an output name or `}`")?;
                        if outputs.iter().any(|(n, _)| *n == o) {
                            return Err(p.error_at(&ot, "distinct output names"));
                        }
                        p.expect_punct('=')?;
                        let e = p.expr()?;
                        p.expect_punct(';')?;
                        for s in p.arena.free_symbols(e) {
                            if !params.contains(&s) && !unknowns.contains(&s) {
                                let n = p.arena.name(s).to_string();
                                return Err(p.error_at(
                                    &ot,
                                    &format!(
                                        "outputs in the unknowns and parameters (`{n}` is neither)"
                                    ),
                                ));
                            }
                        }
                        outputs.push((o, e));
                    }
                    p.next();
                    if outputs.is_empty() {
                        return Err(p.error_at(&tok, "at least one output"));
                    }
                    points.push(PointDef {
                        name,
                        params,
                        outputs,
                        line: t.line,
                    });
                }
                Tok::Ident(w) if w == "model" => {
                    p.next();
                    if model.is_some() {
                        return Err(p.error_at(&t, "a single `model` statement"));
                    }
                    let (name, tok) = definable_name(&mut p, "the model's name")?;
                    if !name.starts_with(|c: char| c.is_ascii_uppercase()) {
                        return Err(p.error_at(&tok, "a model name that starts with a capital letter (it names a Rust type)"));
                    }
                    p.expect_punct(';')?;
                    model = Some(name);
                }
                Tok::Ident(w) if w == "scaled" => {
                    p.next();
                    if scaled.is_some() {
                        return Err(p.error_at(&t, "a single `scaled` statement"));
                    }
                    if unknowns.is_empty() {
                        return Err(p.error_at(&t, "the `unknowns` statement before `scaled`"));
                    }
                    let mut factors = Vec::new();
                    loop {
                        let et = p.peek().clone();
                        let e = p.expr()?;
                        let i = factors.len();
                        let Some(&u) = unknowns.get(i) else {
                            return Err(p.error_at(&et, &format!("one scaled unknown per unknown ({})", unknowns.len())));
                        };
                        let ue = p.arena.sym(u);
                        let factor = p.arena.div(e, ue).map_err(|err| p.error_at(&et, &format!("a scaling that can be built ({err})")))?;
                        let fine = !p.arena.free_symbols(factor).iter().any(|s| unknowns.contains(s))
                            && p.arena.as_num(factor).is_none_or(|r| !r.is_zero());
                        if !fine {
                            let n = p.arena.name(u).to_string();
                            return Err(p.error_at(&et, &format!("`{n}` times a nonzero factor free of unknowns (entry {} scales `{n}`)", i + 1)));
                        }
                        factors.push(factor);
                        if p.is_punct(',') {
                            p.next();
                            continue;
                        }
                        p.expect_punct(';')?;
                        break;
                    }
                    if factors.len() != unknowns.len() {
                        return Err(p.error_at(&t, &format!("one scaled unknown per unknown ({}, found {})", unknowns.len(), factors.len())));
                    }
                    let params = symbols_in_order(p.arena, &factors);
                    scaled = Some(ScaledDef { factors, params, line: t.line });
                }
                Tok::Ident(w) if w == "local" => {
                    unknown_subset(&mut p, &unknowns, &mut local, "distinct local unknowns")?;
                }
                Tok::Ident(w) if w == "across" => {
                    unknown_subset(&mut p, &unknowns, &mut across, "distinct unknowns across the width")?;
                }
                Tok::Ident(w) if w == "straighten" => {
                    p.next();
                    let (name, tok) = p.expect_ident("the unknown Newton replaces")?;
                    let target = p.arena.symbol(&name);
                    if !unknowns.contains(&target) {
                        return Err(p.error_at(&tok, &format!("an unknown (`{name}` is not one)")));
                    }
                    let by = p.peek().clone();
                    if !p.is_ident("by") {
                        return Err(p.error_at(&by, "`by` and the shift, a number times an unknown squared"));
                    }
                    p.next();
                    let et = p.peek().clone();
                    let e = p.expr()?;
                    p.expect_punct(';')?;
                    let free = p.arena.free_symbols(e);
                    let shift = match free[..] {
                        [source] if unknowns.contains(&source) && source != target => {
                            let se = p.arena.sym(source);
                            let sq = p.arena.pow(se, 2).and_then(|sq| p.arena.div(e, sq)).ok();
                            sq.and_then(|c| p.arena.as_num(c)).filter(|c| !c.is_zero()).map(|c| (source, c))
                        }
                        _ => None,
                    };
                    let Some((source, coefficient)) = shift else {
                        return Err(p.error_at(&et, "a nonzero number times the square of another unknown"));
                    };
                    let used = |u: Sym| straighten.iter().any(|d| d.target == u || d.source == u);
                    if used(target) || used(source) {
                        return Err(p.error_at(&tok, "unknowns that no other `straighten` statement names"));
                    }
                    straighten.push(StraightenDef { target, source, coefficient, line: t.line });
                }
                Tok::Ident(w) if w == "law" => {
                    p.next();
                    let (name, tok) = p.expect_ident("the name of a `let` to emit as a law")?;
                    let Some(&expr) = p.lets.get(&name) else {
                        return Err(p.error_at(&tok, &format!("the name of a `let` (`{name}` is not one)")));
                    };
                    if laws.iter().any(|l| l.name == name) || names_used.contains(&name) {
                        return Err(p.error_at(&tok, &format!("a new function name (`{name}` is taken)")));
                    }
                    names_used.push(name.clone());
                    p.expect_punct('(')?;
                    let (v, vt) = p.expect_ident("the law's variable")?;
                    p.expect_punct(')')?;
                    p.expect_punct(';')?;
                    let var = p.arena.symbol(&v);
                    let free = p.arena.free_symbols(expr);
                    if !free.contains(&var) {
                        return Err(p.error_at(&vt, &format!("a variable of `{name}` (`{v}` does not appear in it)")));
                    }
                    if let Some(u) = free.iter().find(|s| unknowns.contains(s)) {
                        let n = p.arena.name(*u).to_string();
                        return Err(p.error_at(&tok, &format!("a law free of unknowns (`{name}` uses `{n}`)")));
                    }
                    let params = symbols_in_order(p.arena, &[expr]).into_iter().filter(|&s| s != var).collect();
                    laws.push(LawDef { name, var, expr, params, line: t.line });
                }
                Tok::Ident(w) if w == "energy" => {
                    p.next();
                    if energy.is_some() {
                        return Err(p.error_at(&t, "a single `energy` statement"));
                    }
                    p.expect_punct('=')?;
                    let et = p.peek().clone();
                    let e = p.expr()?;
                    p.expect_punct(';')?;
                    let names: Vec<Sym> = integrals.iter().map(|d: &IntegralDef| p.arena.symbol(&d.name)).collect();
                    let is_integral = |s: Sym| names.contains(&s);
                    let expanded = p.arena.expand_in(e, &is_integral).map_err(|err| p.error_at(&et, &format!("an energy that can be expanded ({err})")))?;
                    let mut coefs: Vec<Option<ExprId>> = vec![None; integrals.len()];
                    for (mono, coef) in &expanded {
                        let which = match mono.as_slice() {
                            [(s, 1)] => names.iter().position(|n| n == s),
                            _ => None,
                        };
                        let Some(i) = which else {
                            return Err(p.error_at(&et, "a sum of integrals, each times a coefficient free of integrals (the energy must be linear in them)"));
                        };
                        let c = coef.to_expr(p.arena).map_err(|err| p.error_at(&et, &format!("an energy that can be built ({err})")))?;
                        coefs[i] = Some(c);
                    }
                    let terms: Vec<(String, ExprId)> = integrals.iter().zip(&coefs).filter_map(|(d, c)| c.map(|c| (d.name.clone(), c))).collect();
                    if terms.is_empty() {
                        return Err(p.error_at(&et, "at least one integral in the energy"));
                    }
                    let coef_es: Vec<ExprId> = terms.iter().map(|t| t.1).collect();
                    let scalars = symbols_in_order(p.arena, &coef_es);
                    for &sc in &scalars {
                        if unknowns.contains(&sc) {
                            let n = p.arena.name(sc).to_string();
                            return Err(p.error_at(&et, &format!("coefficients free of unknowns (`{n}` is one)")));
                        }
                        let n = p.arena.name(sc).to_string();
                        if !is_rust_ident(&n) || RUST_AND_GENERATED.contains(&n.as_str()) {
                            return Err(p.error_at(&et, &format!("scalar names usable in Rust (`{n}` is not)")));
                        }
                    }
                    energy = Some(EnergyDef { terms, scalars, line: t.line });
                }
                _ => return Err(p.error(
                    "a statement (`model`, `unknowns`, `scaled`, `local`, `across`, `straighten`, `let`, `law`, `integral`, `energy` or `point`)",
                )),
            }
        }
        if unknowns.is_empty() && (!integrals.is_empty() || !points.is_empty()) {
            let t = p.peek().clone();
            return Err(p.error_at(&t, "an `unknowns` statement before the end"));
        }
    }
    Ok(Spec {
        arena,
        model,
        unknowns,
        scaled,
        local,
        across,
        straighten,
        integrals,
        points,
        laws,
        energy,
    })
}

/// Rust keywords, and the argument names of generated kernels (`k`, `m`).
const RUST_AND_GENERATED: [&str; 38] = [
    "as", "break", "const", "continue", "crate", "else", "enum", "extern", "false", "fn", "for",
    "if", "impl", "loop", "match", "mod", "move", "mut", "pub", "ref", "return", "self", "Self",
    "static", "struct", "super", "trait", "true", "type", "unsafe", "use", "where", "while",
    "async", "await", "dyn", "k", "m",
];

/// Names the generator uses for its own locals: `tmp0`, `atom3`, `mom_x2`.
fn is_generated_name(name: &str) -> bool {
    let numbered = |prefix: &str| {
        name.strip_prefix(prefix)
            .is_some_and(|rest| !rest.is_empty() && rest.chars().all(|c| c.is_ascii_digit()))
    };
    numbered("tmp") || numbered("atom") || name.starts_with("mom_")
}

fn definable_name(
    p: &mut Parser<'_>,
    what: &str,
) -> Result<(String, crate::parse::Token), ParseError> {
    let (name, tok) = p.expect_ident(what)?;
    if KEYWORDS.contains(&name.as_str())
        || ["d", "at", "sin", "cos", "sqrt", "atan2"].contains(&name.as_str())
        || RUST_AND_GENERATED.contains(&name.as_str())
        || is_generated_name(&name)
    {
        return Err(p.error_at(&tok, &format!("{what} (`{name}` is reserved)")));
    }
    if !is_rust_ident(&name) {
        return Err(p.error_at(
            &tok,
            &format!("{what} made of ASCII letters, digits and `_`"),
        ));
    }
    Ok((name, tok))
}

fn kernel_name(
    p: &mut Parser<'_>,
    used: &mut Vec<String>,
) -> Result<(String, crate::parse::Token), ParseError> {
    let (name, tok) = definable_name(p, "a kernel name")?;
    if used.contains(&name) {
        return Err(p.error_at(&tok, &format!("a new kernel name (`{name}` is taken)")));
    }
    used.push(name.clone());
    Ok((name, tok))
}

/// The list of a `local` or `across` statement (its keyword is next):
/// unknowns, each named once over all such statements (`twice`: what a
/// repeat is told it should be), added to `into`.
fn unknown_subset(
    p: &mut Parser<'_>,
    unknowns: &[Sym],
    into: &mut Vec<Sym>,
    twice: &str,
) -> Result<(), ParseError> {
    p.next();
    for (name, tok) in ident_list(p, ';', "an unknown's name")? {
        let s = p.arena.symbol(&name);
        if !unknowns.contains(&s) {
            return Err(p.error_at(&tok, &format!("an unknown (`{name}` is not one)")));
        }
        if into.contains(&s) {
            return Err(p.error_at(&tok, twice));
        }
        into.push(s);
    }
    Ok(())
}

fn ident_list(
    p: &mut Parser<'_>,
    end: char,
    what: &str,
) -> Result<Vec<(String, crate::parse::Token)>, ParseError> {
    let mut out = vec![definable_name(p, what)?];
    while p.is_punct(',') {
        p.next();
        out.push(definable_name(p, what)?);
    }
    p.expect_punct(end)?;
    Ok(out)
}

fn param_list(p: &mut Parser<'_>) -> Result<Vec<Sym>, ParseError> {
    if p.is_punct(')') {
        p.next();
        return Ok(Vec::new());
    }
    let list = ident_list(p, ')', "a parameter name")?;
    let mut out = Vec::new();
    for (name, tok) in list {
        if p.lets.contains_key(&name) {
            return Err(p.error_at(
                &tok,
                &format!("a parameter name that is not a `let` (`{name}` is one)"),
            ));
        }
        let s = p.arena.symbol(&name);
        if out.contains(&s) {
            return Err(p.error_at(&tok, "distinct parameter names"));
        }
        out.push(s);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: &str = "
        unknowns a, b;
        let e = a + b*x;
        integral spring(ks, l) = 1/2*ks*e^2 over x in [0, l];
        point tip(l) { y = at(e, x, l); }
    ";

    #[test]
    fn parses_statements() {
        let s = parse_spec(SMALL).unwrap();
        assert_eq!(s.unknowns.len(), 2);
        assert_eq!(s.integrals[0].name, "spring");
        assert_eq!(s.integrals[0].params.len(), 2);
        assert_eq!(s.points[0].outputs[0].0, "y");
        assert_eq!(
            s.arena.show(s.points[0].outputs[0].1).to_string(),
            "a + b*l"
        );
    }

    fn err(src: &str) -> ParseError {
        parse_spec(src).unwrap_err()
    }

    #[test]
    fn errors_say_where_and_what() {
        let e = err("unknowns a;\nintegral f(ks) = ks*a*q over x in [0, 1];");
        assert_eq!(e.line, 2);
        assert!(e.expected.contains("`q` is none"), "{e}");
        let e = err("unknowns a;\nlet x = ;");
        assert_eq!((e.line, e.col), (2, 9));
        let e = err("unknowns a;\nintegral f(ks) = a over x in [0, mm];");
        assert!(e.expected.contains("`mm` is not one"), "{e}");
        let e = err("unknowns a;\nintegral f(ks) = a;");
        assert!(e.expected.contains("`over`"), "{e}");
        let e = err("bogus");
        assert!(e.expected.contains("a statement"), "{e}");
        let e = err("unknowns a;\nlet let = 1;");
        assert!(e.expected.contains("reserved"), "{e}");
        let e = err("unknowns as, b;");
        assert!(e.expected.contains("reserved"), "{e}");
        let e = err("unknowns a, tmp3;");
        assert!(e.expected.contains("reserved"), "{e}");
        let e = err("unknowns a;\npoint p(l) { }");
        assert!(e.expected.contains("at least one output"), "{e}");
        let e = err(
            "unknowns a;\nintegral f(ks) = a over x in [0, ks];\nintegral f(ks) = a over x in [0, ks];",
        );
        assert_eq!(e.line, 3);
    }
}
