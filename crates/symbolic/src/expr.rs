//! The expression DAG: hash-consed nodes in one flat arena.
//!
//! Children are always created before their parents, so a node's id is
//! larger than its children's ids and the arena order is a topological order.
//! Constructors canonicalise (flatten, fold numbers, merge like terms and
//! equal bases, sort children), and identical nodes are stored once, so
//! common sub-expressions are shared from the moment they are built.

use std::collections::HashMap;
use std::fmt;

use crate::rational::{Overflow, Rational};

/// Index of a node in an [`Arena`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ExprId(pub(crate) u32);

impl ExprId {
    /// Position in the arena (creation order).
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// An interned symbol.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Sym(pub(crate) u32);

/// Elementary functions the spec language knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Func {
    /// sine
    Sin,
    /// cosine
    Cos,
    /// non-negative square root
    Sqrt,
    /// two-argument arc tangent `atan2(y, x)`
    Atan2,
}

impl Func {
    /// The name used in the text form and in emitted Rust.
    pub fn name(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Sqrt => "sqrt",
            Func::Atan2 => "atan2",
        }
    }

    /// Number of arguments.
    pub fn arity(self) -> usize {
        match self {
            Func::Atan2 => 2,
            _ => 1,
        }
    }

    /// Looks a function up by name.
    pub fn from_name(name: &str) -> Option<Func> {
        Some(match name {
            "sin" => Func::Sin,
            "cos" => Func::Cos,
            "sqrt" => Func::Sqrt,
            "atan2" => Func::Atan2,
            _ => return None,
        })
    }
}

/// One node of the DAG.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Node {
    /// An exact rational constant.
    Num(Rational),
    /// A symbol.
    Sym(Sym),
    /// A sum of at least two terms (sorted, no numbers but an optional first one).
    Add(Vec<ExprId>),
    /// A product of at least two factors (sorted; a numeric factor comes first).
    Mul(Vec<ExprId>),
    /// An integer power `base ^ exp` with `exp` not 0 or 1.
    Pow(ExprId, i32),
    /// A function application.
    Fun(Func, Vec<ExprId>),
}

/// Errors of symbolic operations.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SymError {
    /// Exact arithmetic overflowed.
    #[error(transparent)]
    Overflow(#[from] Overflow),
    /// Division by an expression that is identically zero.
    #[error("division by zero")]
    DivisionByZero,
    /// An operation needed a polynomial and got something else.
    #[error("not a polynomial in {var}: {what}")]
    NotPolynomial {
        /// the variable(s) the polynomial was wanted in
        var: String,
        /// the offending sub-expression, in text form
        what: String,
    },
}

/// The arena holding every node and symbol name.
#[derive(Debug, Clone, Default)]
pub struct Arena {
    nodes: Vec<Node>,
    lookup: HashMap<Node, ExprId>,
    names: Vec<String>,
    sym_lookup: HashMap<String, Sym>,
}

impl Arena {
    /// An empty arena.
    pub fn new() -> Arena {
        Arena::default()
    }

    /// Number of stored nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// True when no node is stored.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node behind an id.
    pub fn node(&self, id: ExprId) -> &Node {
        &self.nodes[id.index()]
    }

    /// Interns a symbol name.
    pub fn symbol(&mut self, name: &str) -> Sym {
        if let Some(&s) = self.sym_lookup.get(name) {
            return s;
        }
        let s = Sym(self.names.len() as u32);
        self.names.push(name.to_string());
        self.sym_lookup.insert(name.to_string(), s);
        s
    }

    /// Looks a symbol up without interning it.
    pub fn find_symbol(&self, name: &str) -> Option<Sym> {
        self.sym_lookup.get(name).copied()
    }

    /// The name of a symbol.
    pub fn name(&self, s: Sym) -> &str {
        &self.names[s.0 as usize]
    }

    fn intern(&mut self, node: Node) -> ExprId {
        if let Some(&id) = self.lookup.get(&node) {
            return id;
        }
        let id = ExprId(self.nodes.len() as u32);
        self.nodes.push(node.clone());
        self.lookup.insert(node, id);
        id
    }

    /// A rational constant.
    pub fn num(&mut self, r: Rational) -> ExprId {
        self.intern(Node::Num(r))
    }

    /// An integer constant.
    pub fn int(&mut self, n: i128) -> ExprId {
        self.num(Rational::int(n))
    }

    /// A symbol as an expression (interning the name).
    pub fn var(&mut self, name: &str) -> ExprId {
        let s = self.symbol(name);
        self.sym(s)
    }

    /// A symbol as an expression.
    pub fn sym(&mut self, s: Sym) -> ExprId {
        self.intern(Node::Sym(s))
    }

    /// The constant value of a node, if it is a number.
    pub fn as_num(&self, id: ExprId) -> Option<Rational> {
        match self.node(id) {
            Node::Num(r) => Some(*r),
            _ => None,
        }
    }

    /// The symbol of a node, if it is one.
    pub fn as_sym(&self, id: ExprId) -> Option<Sym> {
        match self.node(id) {
            Node::Sym(s) => Some(*s),
            _ => None,
        }
    }

    /// Splits a term into its numeric coefficient and the rest
    /// (`3*x*y` gives `(3, x*y)`; `x` gives `(1, x)`; `5` gives `(5, 1)`).
    pub fn split_coeff(&mut self, id: ExprId) -> (Rational, ExprId) {
        match self.node(id).clone() {
            Node::Num(r) => (r, self.int(1)),
            Node::Mul(fs) => match self.as_num(fs[0]) {
                Some(r) => {
                    let rest = fs[1..].to_vec();
                    let body = if rest.len() == 1 {
                        rest[0]
                    } else {
                        self.intern(Node::Mul(rest))
                    };
                    (r, body)
                }
                None => (Rational::ONE, id),
            },
            _ => (Rational::ONE, id),
        }
    }

    /// `coeff * body` without re-canonicalising `body` (which must already be
    /// canonical and not a number unless it is 1).
    fn scaled(&mut self, c: Rational, body: ExprId) -> ExprId {
        if c.is_zero() {
            return self.int(0);
        }
        if let Some(b) = self.as_num(body) {
            // body is 1 by construction
            let v = b.mul(c).unwrap_or(c);
            return self.num(v);
        }
        if c.is_one() {
            return body;
        }
        let k = self.num(c);
        let mut fs = vec![k];
        match self.node(body).clone() {
            Node::Mul(inner) => fs.extend(inner),
            _ => fs.push(body),
        }
        self.intern(Node::Mul(fs))
    }

    /// A canonical sum.
    pub fn add(&mut self, terms: &[ExprId]) -> Result<ExprId, SymError> {
        let mut flat = Vec::with_capacity(terms.len());
        for &t in terms {
            match self.node(t) {
                Node::Add(inner) => flat.extend(inner.iter().copied()),
                _ => flat.push(t),
            }
        }
        let mut constant = Rational::ZERO;
        // body -> coefficient, in first-seen order of bodies sorted afterwards
        let mut coeffs: Vec<(ExprId, Rational)> = Vec::new();
        let mut index: HashMap<ExprId, usize> = HashMap::new();
        for t in flat {
            if let Some(r) = self.as_num(t) {
                constant = constant.add(r)?;
                continue;
            }
            let (c, body) = self.split_coeff(t);
            match index.get(&body) {
                Some(&i) => coeffs[i].1 = coeffs[i].1.add(c)?,
                None => {
                    index.insert(body, coeffs.len());
                    coeffs.push((body, c));
                }
            }
        }
        coeffs.sort_by_key(|(b, _)| *b);
        let mut out = Vec::with_capacity(coeffs.len() + 1);
        if !constant.is_zero() {
            out.push(self.num(constant));
        }
        for (body, c) in coeffs {
            if !c.is_zero() {
                out.push(self.scaled(c, body));
            }
        }
        if out.iter().any(|&t| matches!(self.node(t), Node::Add(_))) {
            // multiples of a sum added up to coefficient 1 (`2*(x + y) - (x + y)`):
            // flatten that sum into this one. Its terms are children of the
            // sum, so repeating this terminates.
            return self.add(&out);
        }
        Ok(match out.len() {
            0 => self.int(0),
            1 => out[0],
            _ => self.intern(Node::Add(out)),
        })
    }

    /// `a + b`.
    pub fn add2(&mut self, a: ExprId, b: ExprId) -> Result<ExprId, SymError> {
        self.add(&[a, b])
    }

    /// `a - b`.
    pub fn sub(&mut self, a: ExprId, b: ExprId) -> Result<ExprId, SymError> {
        let nb = self.neg(b)?;
        self.add(&[a, nb])
    }

    /// `-a`.
    pub fn neg(&mut self, a: ExprId) -> Result<ExprId, SymError> {
        let m = self.int(-1);
        self.mul(&[m, a])
    }

    /// A canonical product.
    pub fn mul(&mut self, factors: &[ExprId]) -> Result<ExprId, SymError> {
        let mut flat = Vec::with_capacity(factors.len());
        for &f in factors {
            match self.node(f) {
                Node::Mul(inner) => flat.extend(inner.iter().copied()),
                _ => flat.push(f),
            }
        }
        let mut coeff = Rational::ONE;
        let mut bases: Vec<(ExprId, i32)> = Vec::new();
        let mut index: HashMap<ExprId, usize> = HashMap::new();
        for f in flat {
            if let Some(r) = self.as_num(f) {
                coeff = coeff.mul(r)?;
                continue;
            }
            let (base, e) = match self.node(f) {
                Node::Pow(b, e) => (*b, *e),
                _ => (f, 1),
            };
            match index.get(&base) {
                Some(&i) => {
                    bases[i].1 = bases[i]
                        .1
                        .checked_add(e)
                        .ok_or(Overflow { op: "exponent" })?
                }
                None => {
                    index.insert(base, bases.len());
                    bases.push((base, e));
                }
            }
        }
        if coeff.is_zero() {
            return Ok(self.int(0));
        }
        bases.sort_by_key(|(b, _)| *b);
        let mut out = Vec::with_capacity(bases.len() + 1);
        for (b, e) in bases {
            if e != 0 {
                out.push(self.pow_raw(b, e));
            }
        }
        if out.is_empty() {
            return Ok(self.num(coeff));
        }
        if !coeff.is_one() {
            out.insert(0, self.num(coeff));
        }
        Ok(if out.len() == 1 {
            out[0]
        } else {
            self.intern(Node::Mul(out))
        })
    }

    /// `a * b`.
    pub fn mul2(&mut self, a: ExprId, b: ExprId) -> Result<ExprId, SymError> {
        self.mul(&[a, b])
    }

    /// `a / b`.
    pub fn div(&mut self, a: ExprId, b: ExprId) -> Result<ExprId, SymError> {
        let inv = self.pow(b, -1)?;
        self.mul(&[a, inv])
    }

    fn pow_raw(&mut self, base: ExprId, e: i32) -> ExprId {
        if e == 1 {
            base
        } else {
            self.intern(Node::Pow(base, e))
        }
    }

    /// `base ^ e` for an integer exponent.
    pub fn pow(&mut self, base: ExprId, e: i32) -> Result<ExprId, SymError> {
        if e == 0 {
            return Ok(self.int(1));
        }
        if e == 1 {
            return Ok(base);
        }
        match self.node(base).clone() {
            Node::Num(r) => {
                if r.is_zero() && e < 0 {
                    return Err(SymError::DivisionByZero);
                }
                let v = r.pow(e)?;
                Ok(self.num(v))
            }
            Node::Pow(b, k) => {
                let ke = k.checked_mul(e).ok_or(Overflow { op: "exponent" })?;
                self.pow(b, ke)
            }
            Node::Mul(fs) => {
                let mut parts = Vec::with_capacity(fs.len());
                for f in fs {
                    parts.push(self.pow(f, e)?);
                }
                self.mul(&parts)
            }
            _ => Ok(self.pow_raw(base, e)),
        }
    }

    /// A function application, folding exact special values (`sin 0`, `sqrt 1`...).
    pub fn func(&mut self, f: Func, args: &[ExprId]) -> Result<ExprId, SymError> {
        assert_eq!(
            args.len(),
            f.arity(),
            "{} takes {} argument(s)",
            f.name(),
            f.arity()
        );
        let zero = Some(Rational::ZERO);
        match f {
            Func::Sin if self.as_num(args[0]) == zero => return Ok(self.int(0)),
            Func::Cos if self.as_num(args[0]) == zero => return Ok(self.int(1)),
            Func::Sqrt => {
                if let Some(r) = self.as_num(args[0]) {
                    if r.is_zero() || r.is_one() {
                        return Ok(args[0]);
                    }
                }
            }
            Func::Atan2 if self.as_num(args[0]) == zero => {
                if let Some(x) = self.as_num(args[1]) {
                    if !x.is_negative() && !x.is_zero() {
                        return Ok(self.int(0));
                    }
                }
            }
            _ => {}
        }
        Ok(self.intern(Node::Fun(f, args.to_vec())))
    }

    /// The children of a node.
    pub fn children(&self, id: ExprId) -> Vec<ExprId> {
        match self.node(id) {
            Node::Num(_) | Node::Sym(_) => vec![],
            Node::Add(c) | Node::Mul(c) | Node::Fun(_, c) => c.clone(),
            Node::Pow(b, _) => vec![*b],
        }
    }

    /// True when `id` contains any symbol for which `pred` holds.
    pub fn depends_on(&self, id: ExprId, pred: &dyn Fn(Sym) -> bool) -> bool {
        let mut memo = HashMap::new();
        self.depends_memo(id, pred, &mut memo)
    }

    fn depends_memo(
        &self,
        id: ExprId,
        pred: &dyn Fn(Sym) -> bool,
        memo: &mut HashMap<ExprId, bool>,
    ) -> bool {
        if let Some(&v) = memo.get(&id) {
            return v;
        }
        let v = match self.node(id) {
            Node::Num(_) => false,
            Node::Sym(s) => pred(*s),
            _ => self
                .children(id)
                .into_iter()
                .any(|c| self.depends_memo(c, pred, memo)),
        };
        memo.insert(id, v);
        v
    }

    /// The symbols an expression contains, in first-seen order.
    pub fn free_symbols(&self, id: ExprId) -> Vec<Sym> {
        let mut seen = std::collections::HashSet::new();
        let mut out = Vec::new();
        let mut stack = vec![id];
        let mut visited = std::collections::HashSet::new();
        while let Some(n) = stack.pop() {
            if !visited.insert(n) {
                continue;
            }
            if let Node::Sym(s) = self.node(n) {
                if seen.insert(*s) {
                    out.push(*s);
                }
            }
            let mut ch = self.children(n);
            ch.reverse();
            stack.extend(ch);
        }
        out
    }

    /// A displayable view of an expression in the text form.
    pub fn show(&self, id: ExprId) -> Show<'_> {
        Show { arena: self, id }
    }

    fn write(&self, id: ExprId, prec: u8, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // precedence: 0 sum, 1 product, 2 unary minus, 3 power base
        match self.node(id) {
            Node::Num(r) => {
                let needs = prec >= 1 && (r.is_negative() || !r.is_integer());
                if needs {
                    write!(f, "({r})")
                } else {
                    write!(f, "{r}")
                }
            }
            Node::Sym(s) => write!(f, "{}", self.name(*s)),
            Node::Add(ts) => {
                if prec > 0 {
                    write!(f, "(")?;
                }
                for (i, &t) in ts.iter().enumerate() {
                    let (neg, body) = self.negated_view(t);
                    if i == 0 {
                        if neg {
                            write!(f, "-")?;
                        }
                    } else if neg {
                        write!(f, " - ")?;
                    } else {
                        write!(f, " + ")?;
                    }
                    match body {
                        Some((c, rest)) => self.write_scaled(c, &rest, f)?,
                        None => self.write(t, 1, f)?,
                    }
                }
                if prec > 0 {
                    write!(f, ")")?;
                }
                Ok(())
            }
            Node::Mul(_) => {
                let (neg, body) = self.negated_view(id);
                let paren = prec > 1 || (neg && prec >= 1);
                if paren {
                    write!(f, "(")?;
                }
                if neg {
                    write!(f, "-")?;
                }
                match body {
                    Some((c, rest)) => self.write_scaled(c, &rest, f)?,
                    None => unreachable!("a product always has a view"),
                }
                if paren {
                    write!(f, ")")?;
                }
                Ok(())
            }
            Node::Pow(b, e) => {
                self.write(*b, 3, f)?;
                if *e < 0 {
                    write!(f, "^({e})")
                } else {
                    write!(f, "^{e}")
                }
            }
            Node::Fun(func, args) => {
                write!(f, "{}(", func.name())?;
                for (i, &a) in args.iter().enumerate() {
                    if i > 0 {
                        write!(f, ", ")?;
                    }
                    self.write(a, 0, f)?;
                }
                write!(f, ")")
            }
        }
    }

    /// For a product or negative number: (is negative, |coefficient|, other factors).
    #[allow(clippy::type_complexity)]
    fn negated_view(&self, id: ExprId) -> (bool, Option<(Rational, Vec<ExprId>)>) {
        match self.node(id) {
            Node::Mul(fs) => {
                let (c, rest) = match self.as_num(fs[0]) {
                    Some(c) => (c, fs[1..].to_vec()),
                    None => (Rational::ONE, fs.clone()),
                };
                let neg = c.is_negative();
                let abs = if neg { c.neg().unwrap_or(c) } else { c };
                (neg, Some((abs, rest)))
            }
            Node::Num(r) if r.is_negative() => (true, Some((r.neg().unwrap_or(*r), Vec::new()))),
            _ => (false, None),
        }
    }

    fn write_scaled(
        &self,
        c: Rational,
        rest: &[ExprId],
        f: &mut fmt::Formatter<'_>,
    ) -> fmt::Result {
        let mut first = true;
        if !c.is_one() || rest.is_empty() {
            if c.is_integer() {
                write!(f, "{c}")?;
            } else {
                write!(f, "{}/{}", c.numer(), c.denom())?;
            }
            first = false;
        }
        for &r in rest {
            if !first {
                write!(f, "*")?;
            }
            self.write(r, 2, f)?;
            first = false;
        }
        Ok(())
    }
}

/// Display adaptor returned by [`Arena::show`].
pub struct Show<'a> {
    arena: &'a Arena,
    id: ExprId,
}

impl fmt::Display for Show<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.arena.write(self.id, 0, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_subexpressions_are_stored_once() {
        let mut a = Arena::new();
        let x = a.var("x");
        let y = a.var("y");
        let s1 = a.add2(x, y).unwrap();
        let s2 = a.add2(y, x).unwrap();
        assert_eq!(s1, s2);
        let n = a.len();
        let p1 = a.mul2(s1, x).unwrap();
        let p2 = a.mul2(x, s2).unwrap();
        assert_eq!(p1, p2);
        assert_eq!(a.len(), n + 1);
    }

    #[test]
    fn canonical_forms() {
        let mut a = Arena::new();
        let x = a.var("x");
        let two = a.int(2);
        let xx = a.add(&[x, x]).unwrap();
        let tx = a.mul2(two, x).unwrap();
        assert_eq!(xx, tx);
        let x2 = a.mul2(x, x).unwrap();
        assert_eq!(x2, a.pow(x, 2).unwrap());
        let zero = a.sub(x, x).unwrap();
        assert_eq!(a.as_num(zero), Some(Rational::ZERO));
        let one = a.div(x, x).unwrap();
        assert_eq!(a.as_num(one), Some(Rational::ONE));
        assert_eq!(a.show(tx).to_string(), "2*x");
    }

    #[test]
    fn children_precede_parents() {
        let mut a = Arena::new();
        let x = a.var("x");
        let y = a.var("y");
        let s = a.add2(x, y).unwrap();
        let p = a.pow(s, 3).unwrap();
        for id in [s, p] {
            for c in a.children(id) {
                assert!(c < id);
            }
        }
    }
}
