//! Straight-line Rust emission with common-subexpression binding.
//!
//! The arena already stores each distinct sub-expression once; emission
//! binds every node used more than once to a `let` and inlines the rest.
//! Integer powers become multiplications through a per-base power cache
//! (`x^5 = x^4 * x`, `x^4 = x^2 * x^2`), negative powers become divisions;
//! a base that divides in several places is inverted once (`r = 1 / x`) and
//! its negative powers become multiplications by powers of `r`.
//! The output has no loops and no allocation.

use std::collections::HashMap;
use std::ops::AddAssign;

use proc_macro2::{Ident, Literal, Span, TokenStream};
use quote::quote;

use crate::expr::{Arena, ExprId, Func, Node, Sym};
use crate::rational::Rational;

/// Floating-point operation counts of some code.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OpCount {
    /// additions and subtractions
    pub add: u64,
    /// multiplications (including those that replace integer powers)
    pub mul: u64,
    /// divisions
    pub div: u64,
    /// elementary function calls
    pub func: u64,
}

impl OpCount {
    /// All operations.
    pub fn total(&self) -> u64 {
        self.add + self.mul + self.div + self.func
    }
}

impl AddAssign for OpCount {
    fn add_assign(&mut self, o: OpCount) {
        self.add += o.add;
        self.mul += o.mul;
        self.div += o.div;
        self.func += o.func;
    }
}

/// Multiplications used by plain repeated squaring for `x^n`, as counted
/// before sharing powers.
fn naive_pow_muls(n: u32) -> u64 {
    u64::from(n.saturating_sub(1))
}

/// Operation count as if every use of a sub-expression recomputed it
/// (the expression trees written out, before common-subexpression binding).
pub fn tree_ops(arena: &Arena, roots: &[ExprId]) -> OpCount {
    let mut memo: HashMap<ExprId, OpCount> = HashMap::new();
    let mut total = OpCount::default();
    for &r in roots {
        total += tree_ops_memo(arena, r, &mut memo);
    }
    total
}

fn tree_ops_memo(arena: &Arena, id: ExprId, memo: &mut HashMap<ExprId, OpCount>) -> OpCount {
    if let Some(c) = memo.get(&id) {
        return *c;
    }
    let mut c = OpCount::default();
    match arena.node(id) {
        Node::Num(_) | Node::Sym(_) => {}
        Node::Add(ts) => c.add += ts.len() as u64 - 1,
        Node::Mul(fs) => c.mul += fs.len() as u64 - 1,
        Node::Pow(_, k) => {
            c.mul += naive_pow_muls(k.unsigned_abs());
            if *k < 0 {
                c.div += 1;
            }
        }
        Node::Fun(..) => c.func += 1,
    }
    for ch in arena.children(id) {
        let cc = tree_ops_memo(arena, ch, memo);
        c += cc;
    }
    memo.insert(id, c);
    c
}

/// Operator precedence of a rendered piece, to place parentheses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Prec {
    Sum,
    Product,
    Atom,
}

#[derive(Clone)]
struct Piece {
    tokens: TokenStream,
    prec: Prec,
}

impl Piece {
    fn atom(tokens: TokenStream) -> Piece {
        Piece {
            tokens,
            prec: Prec::Atom,
        }
    }
    fn at_least(&self, p: Prec) -> TokenStream {
        let t = &self.tokens;
        if self.prec >= p {
            t.clone()
        } else {
            quote! { (#t) }
        }
    }
}

/// A float literal for an exact rational.
pub fn literal(r: Rational) -> TokenStream {
    let v = r.to_f64();
    let lit = Literal::f64_unsuffixed(v.abs());
    if v < 0.0 {
        quote! { -#lit }
    } else {
        quote! { #lit }
    }
}

/// Builds straight-line code for a set of expressions sharing one arena.
pub struct Emitter<'a> {
    arena: &'a Arena,
    uses: HashMap<ExprId, usize>,
    bound: HashMap<ExprId, Piece>,
    symbols: HashMap<Sym, TokenStream>,
    powers: HashMap<(ExprId, u32), Piece>,
    /// Bases that divide more than once: their reciprocal is computed once.
    inverted: std::collections::HashSet<ExprId>,
    /// `base^-n` for the inverted bases, through their reciprocal.
    reciprocals: HashMap<(ExprId, u32), Piece>,
    /// Expressions already bound to a `let` name.
    named: std::collections::HashSet<ExprId>,
    stmts: Vec<TokenStream>,
    next: usize,
    prefix: String,
    ops: OpCount,
}

impl<'a> Emitter<'a> {
    /// Prepares emission of `roots` (all expressions that will be requested).
    /// `prefix` names the temporaries (`{prefix}0`, `{prefix}1`, ...).
    pub fn new(arena: &'a Arena, roots: &[ExprId], prefix: &str) -> Emitter<'a> {
        let mut uses: HashMap<ExprId, usize> = HashMap::new();
        let mut seen = std::collections::HashSet::new();
        let mut stack: Vec<ExprId> = roots.to_vec();
        for &r in roots {
            *uses.entry(r).or_default() += 1;
        }
        while let Some(n) = stack.pop() {
            if !seen.insert(n) {
                continue;
            }
            for c in arena.children(n) {
                *uses.entry(c).or_default() += 1;
                stack.push(c);
            }
        }
        // a base whose negative powers are used twice or more (one power in
        // two places, or two powers) is inverted once
        let mut divides: HashMap<ExprId, usize> = HashMap::new();
        for &n in &seen {
            if let Node::Pow(b, k) = arena.node(n) {
                if *k < 0 {
                    *divides.entry(*b).or_default() += uses.get(&n).copied().unwrap_or(0);
                }
            }
        }
        let inverted = divides
            .into_iter()
            .filter(|&(_, count)| count > 1)
            .map(|(b, _)| b)
            .collect();
        Emitter {
            arena,
            uses,
            bound: HashMap::new(),
            symbols: HashMap::new(),
            powers: HashMap::new(),
            inverted,
            reciprocals: HashMap::new(),
            named: std::collections::HashSet::new(),
            stmts: Vec::new(),
            next: 0,
            prefix: prefix.to_string(),
            ops: OpCount::default(),
        }
    }

    /// Says how a symbol is written in the emitted code.
    pub fn bind_symbol(&mut self, s: Sym, tokens: TokenStream) {
        self.symbols.insert(s, tokens);
    }

    /// Operations in the statements and expressions emitted so far.
    pub fn ops(&self) -> OpCount {
        self.ops
    }

    /// The `let` statements emitted so far (drains them).
    pub fn take_statements(&mut self) -> Vec<TokenStream> {
        std::mem::take(&mut self.stmts)
    }

    fn fresh(&mut self) -> Ident {
        let id = Ident::new(&format!("{}{}", self.prefix, self.next), Span::call_site());
        self.next += 1;
        id
    }

    fn bind(&mut self, p: Piece) -> Piece {
        let id = self.fresh();
        let t = &p.tokens;
        self.stmts.push(quote! { let #id = #t; });
        Piece::atom(quote! { #id })
    }

    /// Emits what `e` needs and returns an expression for it.
    pub fn expr(&mut self, e: ExprId) -> TokenStream {
        self.piece(e).tokens
    }

    /// Emits `e` into a named `let` and returns the name's tokens.
    pub fn let_named(&mut self, name: &str, e: ExprId) -> TokenStream {
        let p = self.piece(e);
        let id = Ident::new(name, Span::call_site());
        let t = p.tokens;
        self.stmts.push(quote! { let #id = #t; });
        quote! { #id }
    }

    fn piece(&mut self, e: ExprId) -> Piece {
        if let Some(p) = self.bound.get(&e) {
            return p.clone();
        }
        let p = self.render(e);
        let shared = self.uses.get(&e).copied().unwrap_or(0) > 1;
        let p = if shared && self.costly(e, &p) {
            self.named.insert(e);
            self.bind(p)
        } else {
            p
        };
        self.bound.insert(e, p.clone());
        p
    }

    /// True when writing `p` (the rendering of `e`) twice would compute
    /// something twice: anything but a name or a literal (a function call is
    /// atomic in syntax but not free).
    fn costly(&self, e: ExprId, p: &Piece) -> bool {
        !self.named.contains(&e)
            && (p.prec != Prec::Atom || matches!(self.arena.node(e), Node::Fun(..)))
    }

    /// Makes sure `e` is available as a bound name (or a name or literal).
    fn force_bind(&mut self, e: ExprId) {
        let p = self.piece(e);
        if self.costly(e, &p) {
            let b = self.bind(p);
            self.named.insert(e);
            self.bound.insert(e, b);
        }
    }

    /// `base^n` for n >= 1 through the power cache.
    fn power(&mut self, base: ExprId, n: u32) -> Piece {
        if n == 1 {
            return self.piece(base);
        }
        if let Some(p) = self.powers.get(&(base, n)) {
            return p.clone();
        }
        // the base is multiplied by itself: write it as a name, not twice
        self.force_bind(base);
        let p = if n.is_multiple_of(2) {
            let h = self.power(base, n / 2).at_least(Prec::Atom);
            self.ops.mul += 1;
            self.bind(Piece {
                tokens: quote! { #h * #h },
                prec: Prec::Product,
            })
        } else {
            let a = self.power(base, n - 1).at_least(Prec::Atom);
            let b = self.piece(base).at_least(Prec::Atom);
            self.ops.mul += 1;
            self.bind(Piece {
                tokens: quote! { #a * #b },
                prec: Prec::Product,
            })
        };
        self.powers.insert((base, n), p.clone());
        p
    }

    /// `base^-n` for n >= 1 and an inverted base: `r = 1 / base` once, then
    /// powers of `r` through multiplications.
    fn reciprocal(&mut self, base: ExprId, n: u32) -> Piece {
        if let Some(p) = self.reciprocals.get(&(base, n)) {
            return p.clone();
        }
        let p = if n == 1 {
            let d = self.piece(base).at_least(Prec::Atom);
            self.ops.div += 1;
            self.bind(Piece {
                tokens: quote! { 1.0 / #d },
                prec: Prec::Product,
            })
        } else {
            let (a, b) = if n.is_multiple_of(2) {
                (n / 2, n / 2)
            } else {
                (n - 1, 1)
            };
            let a = self.reciprocal(base, a).at_least(Prec::Atom);
            let b = self.reciprocal(base, b).at_least(Prec::Atom);
            self.ops.mul += 1;
            self.bind(Piece {
                tokens: quote! { #a * #b },
                prec: Prec::Product,
            })
        };
        self.reciprocals.insert((base, n), p.clone());
        p
    }

    fn render(&mut self, e: ExprId) -> Piece {
        match self.arena.node(e).clone() {
            Node::Num(r) => {
                let t = literal(r);
                if r.is_negative() {
                    Piece {
                        tokens: t,
                        prec: Prec::Sum,
                    }
                } else {
                    Piece::atom(t)
                }
            }
            Node::Sym(s) => {
                let t = self.symbols.get(&s).cloned().unwrap_or_else(|| {
                    let id = Ident::new(self.arena.name(s), Span::call_site());
                    quote! { #id }
                });
                Piece::atom(t)
            }
            Node::Add(ts) => {
                let mut out = TokenStream::new();
                for (i, t) in ts.iter().enumerate() {
                    let shared = self.uses.get(t).copied().unwrap_or(0) > 1;
                    let (neg, body) = if shared {
                        (false, self.piece(*t))
                    } else {
                        self.term(*t)
                    };
                    let b = body.at_least(Prec::Product);
                    if i == 0 {
                        out = if neg {
                            quote! { -#b }
                        } else {
                            b
                        };
                    } else {
                        self.ops.add += 1;
                        out = if neg {
                            quote! { #out - #b }
                        } else {
                            quote! { #out + #b }
                        };
                    }
                }
                Piece {
                    tokens: out,
                    prec: Prec::Sum,
                }
            }
            Node::Mul(_) => {
                let (neg, body) = self.term(e);
                if neg {
                    let b = body.at_least(Prec::Atom);
                    Piece {
                        tokens: quote! { -#b },
                        prec: Prec::Sum,
                    }
                } else {
                    body
                }
            }
            Node::Pow(b, k) if k < 0 && self.inverted.contains(&b) => {
                self.reciprocal(b, k.unsigned_abs())
            }
            Node::Pow(b, k) => {
                let p = self.power(b, k.unsigned_abs());
                if k < 0 {
                    self.ops.div += 1;
                    let d = p.at_least(Prec::Atom);
                    Piece {
                        tokens: quote! { 1.0 / #d },
                        prec: Prec::Product,
                    }
                } else {
                    p
                }
            }
            Node::Fun(f, args) => {
                self.ops.func += 1;
                let a0 = self.piece(args[0]).at_least(Prec::Atom);
                let t = match f {
                    Func::Sin => quote! { #a0.sin() },
                    Func::Cos => quote! { #a0.cos() },
                    Func::Sqrt => quote! { #a0.sqrt() },
                    Func::Atan2 => {
                        let a1 = self.piece(args[1]).tokens;
                        quote! { #a0.atan2(#a1) }
                    }
                };
                Piece::atom(t)
            }
        }
    }

    /// A product term as (negative?, |term|), with negative powers as a divisor.
    fn term(&mut self, e: ExprId) -> (bool, Piece) {
        let factors = match self.arena.node(e) {
            Node::Mul(fs) => fs.clone(),
            Node::Num(r) if r.is_negative() => {
                let abs = r.neg().unwrap_or(*r);
                return (true, Piece::atom(literal(abs)));
            }
            _ => return (false, self.piece(e)),
        };
        let mut coeff = Rational::ONE;
        let mut num: Vec<Piece> = Vec::new();
        let mut den: Vec<Piece> = Vec::new();
        for f in factors {
            if let Some(r) = self.arena.as_num(f) {
                coeff = r;
                continue;
            }
            match self.arena.node(f).clone() {
                Node::Pow(b, k) if k < 0 && self.inverted.contains(&b) => {
                    num.push(self.reciprocal(b, k.unsigned_abs()))
                }
                Node::Pow(b, k) if k < 0 && !self.bound.contains_key(&f) => {
                    // a divisor shared by several terms is computed once
                    if self.uses.get(&f).copied().unwrap_or(0) > 1 {
                        self.force_bind(b);
                    }
                    den.push(self.power(b, k.unsigned_abs()))
                }
                _ => num.push(self.piece(f)),
            }
        }
        let neg = coeff.is_negative();
        let abs = if neg {
            coeff.neg().unwrap_or(coeff)
        } else {
            coeff
        };
        if !abs.is_one() || num.is_empty() {
            num.insert(0, Piece::atom(literal(abs)));
        }
        let mut out = num[0].at_least(Prec::Product);
        for p in &num[1..] {
            let t = p.at_least(Prec::Atom);
            self.ops.mul += 1;
            out = quote! { #out * #t };
        }
        if !den.is_empty() {
            let mut d = den[0].at_least(Prec::Atom);
            for p in &den[1..] {
                let t = p.at_least(Prec::Atom);
                self.ops.mul += 1;
                d = quote! { (#d * #t) };
            }
            self.ops.div += 1;
            out = quote! { #out / #d };
        }
        (
            neg,
            Piece {
                tokens: out,
                prec: Prec::Product,
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn emit_one(src: &str) -> (String, OpCount) {
        let mut a = Arena::new();
        let e = a.parse(src).unwrap();
        let mut em = Emitter::new(&a, &[e], "t");
        let out = em.expr(e);
        let stmts = em.take_statements();
        let code = quote! { #(#stmts)* #out }.to_string();
        (code, em.ops())
    }

    #[test]
    fn powers_become_shared_multiplications() {
        let (code, ops) = emit_one("x^5 + x^4");
        assert!(!code.contains("powi"), "{code}");
        // x^2, x^4 = x^2*x^2, x^5 = x^4*x, then one addition
        assert_eq!(
            ops,
            OpCount {
                add: 1,
                mul: 3,
                div: 0,
                func: 0
            }
        );
    }

    #[test]
    fn shared_subexpressions_are_bound_once() {
        let (code, ops) = emit_one("sin(x + y)*(x + y) + cos(x + y)");
        assert_eq!(code.matches("x + y").count(), 1, "{code}");
        assert_eq!(ops.func, 2);
    }

    #[test]
    fn shared_divisors_are_computed_once() {
        let (code, _) = emit_one("x/(1 + y^2) + z/(1 + y^2) + x*z/(1 + y^2)");
        assert_eq!(
            code.matches("1.0 +").count() + code.matches("+ 1.0").count(),
            1,
            "{code}"
        );
    }

    #[test]
    fn a_base_dividing_twice_is_inverted_once() {
        let (code, ops) = emit_one("x/(1 + y^2) + z/(1 + y^2)^2 + x*z/(1 + y^2)");
        assert_eq!(ops.div, 1, "{code}");
        assert_eq!(code.matches('/').count(), 1, "{code}");
    }

    #[test]
    fn negative_powers_divide() {
        let (code, _) = emit_one("3*x/y^2");
        assert!(code.contains('/'), "{code}");
    }
}
