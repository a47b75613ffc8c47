//! Sparse multivariate polynomials with exact rational coefficients, the
//! canonical form used for expansion, exact integration and Horner factoring.
//!
//! Two flavours: [`Poly`] has rational coefficients (full expansion in every
//! symbol); [`Arena::expand_in`] expands only in chosen variables and keeps
//! the coefficients as shared DAG expressions, so expanding a strain in `x`
//! and `z` leaves products of the unknowns' sub-expressions factored.

use std::collections::{BTreeMap, HashMap};
use std::fmt;

use crate::expr::{Arena, ExprId, Node, Sym, SymError};
use crate::rational::{Overflow, Rational};

/// A monomial: symbols with positive exponents, sorted by symbol.
pub type Mono = Vec<(Sym, u32)>;

fn mono_mul(a: &Mono, b: &Mono) -> Result<Mono, Overflow> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        if j >= b.len() || (i < a.len() && a[i].0 < b[j].0) {
            out.push(a[i]);
            i += 1;
        } else if i >= a.len() || b[j].0 < a[i].0 {
            out.push(b[j]);
            j += 1;
        } else {
            let e = a[i]
                .1
                .checked_add(b[j].1)
                .ok_or(Overflow { op: "exponent" })?;
            out.push((a[i].0, e));
            i += 1;
            j += 1;
        }
    }
    Ok(out)
}

/// The exponent of `s` in a monomial.
pub fn mono_degree(m: &Mono, s: Sym) -> u32 {
    m.iter().find(|(t, _)| *t == s).map_or(0, |(_, e)| *e)
}

/// The monomial without `s`.
pub fn mono_without(m: &Mono, s: Sym) -> Mono {
    m.iter().copied().filter(|(t, _)| *t != s).collect()
}

/// A polynomial with rational coefficients; no zero coefficients are stored.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Poly {
    terms: BTreeMap<Mono, Rational>,
}

impl Poly {
    /// The zero polynomial.
    pub fn zero() -> Poly {
        Poly::default()
    }

    /// A constant.
    pub fn constant(r: Rational) -> Poly {
        let mut p = Poly::zero();
        if !r.is_zero() {
            p.terms.insert(Vec::new(), r);
        }
        p
    }

    /// A single symbol.
    pub fn var(s: Sym) -> Poly {
        let mut p = Poly::zero();
        p.terms.insert(vec![(s, 1)], Rational::ONE);
        p
    }

    /// The terms, in monomial order.
    pub fn terms(&self) -> impl Iterator<Item = (&Mono, Rational)> {
        self.terms.iter().map(|(m, c)| (m, *c))
    }

    /// Number of terms.
    pub fn len(&self) -> usize {
        self.terms.len()
    }

    /// True for the zero polynomial (no terms).
    pub fn is_empty(&self) -> bool {
        self.terms.is_empty()
    }

    /// True for the zero polynomial.
    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    fn insert_add(&mut self, m: Mono, c: Rational) -> Result<(), Overflow> {
        if c.is_zero() {
            return Ok(());
        }
        let v = match self.terms.get(&m) {
            Some(&old) => old.add(c)?,
            None => c,
        };
        if v.is_zero() {
            self.terms.remove(&m);
        } else {
            self.terms.insert(m, v);
        }
        Ok(())
    }

    /// `self + other`.
    pub fn add(&self, other: &Poly) -> Result<Poly, Overflow> {
        let mut out = self.clone();
        for (m, c) in &other.terms {
            out.insert_add(m.clone(), *c)?;
        }
        Ok(out)
    }

    /// `self - other`.
    pub fn sub(&self, other: &Poly) -> Result<Poly, Overflow> {
        self.add(&other.scale(Rational::int(-1))?)
    }

    /// `c * self`.
    pub fn scale(&self, c: Rational) -> Result<Poly, Overflow> {
        let mut out = Poly::zero();
        for (m, k) in &self.terms {
            out.insert_add(m.clone(), k.mul(c)?)?;
        }
        Ok(out)
    }

    /// `self * other`.
    pub fn mul(&self, other: &Poly) -> Result<Poly, Overflow> {
        let mut out = Poly::zero();
        for (ma, ca) in &self.terms {
            for (mb, cb) in &other.terms {
                out.insert_add(mono_mul(ma, mb)?, ca.mul(*cb)?)?;
            }
        }
        Ok(out)
    }

    /// `self ^ k`.
    pub fn pow(&self, k: u32) -> Result<Poly, Overflow> {
        let mut acc = Poly::constant(Rational::ONE);
        for _ in 0..k {
            acc = acc.mul(self)?;
        }
        Ok(acc)
    }

    /// The partial derivative with respect to `s`.
    pub fn diff(&self, s: Sym) -> Result<Poly, Overflow> {
        let mut out = Poly::zero();
        for (m, c) in &self.terms {
            let e = mono_degree(m, s);
            if e == 0 {
                continue;
            }
            let mut nm = mono_without(m, s);
            if e > 1 {
                nm.push((s, e - 1));
                nm.sort();
            }
            out.insert_add(nm, c.mul(Rational::int(e as i128))?)?;
        }
        Ok(out)
    }

    /// The exact definite integral over `s` from `lo` to `hi`, bounds being
    /// polynomials themselves (they must not contain `s`).
    pub fn integrate(&self, s: Sym, lo: &Poly, hi: &Poly) -> Result<Poly, Overflow> {
        // group by the power of s: integral of s^k = (hi^(k+1) - lo^(k+1)) / (k+1)
        let mut by_power: BTreeMap<u32, Poly> = BTreeMap::new();
        for (m, c) in &self.terms {
            let e = mono_degree(m, s);
            by_power
                .entry(e)
                .or_default()
                .insert_add(mono_without(m, s), *c)?;
        }
        let mut out = Poly::zero();
        for (k, rest) in by_power {
            let anti = hi
                .pow(k + 1)?
                .sub(&lo.pow(k + 1)?)?
                .scale(Rational::new(1, k as i128 + 1)?)?;
            out = out.add(&rest.mul(&anti)?)?;
        }
        Ok(out)
    }

    /// The highest exponent of `s`.
    pub fn degree_in(&self, s: Sym) -> u32 {
        self.terms
            .keys()
            .map(|m| mono_degree(m, s))
            .max()
            .unwrap_or(0)
    }

    /// Evaluates with a value per symbol.
    pub fn eval(&self, value: &dyn Fn(Sym) -> f64) -> f64 {
        self.terms
            .iter()
            .map(|(m, c)| {
                m.iter()
                    .fold(c.to_f64(), |acc, (s, e)| acc * value(*s).powi(*e as i32))
            })
            .sum()
    }

    /// A displayable view with the arena's symbol names.
    pub fn show<'a>(&'a self, arena: &'a Arena) -> ShowPoly<'a> {
        ShowPoly { poly: self, arena }
    }
}

/// Display adaptor for [`Poly::show`].
pub struct ShowPoly<'a> {
    poly: &'a Poly,
    arena: &'a Arena,
}

impl fmt::Display for ShowPoly<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.poly.is_zero() {
            return write!(f, "0");
        }
        for (i, (m, c)) in self.poly.terms.iter().enumerate() {
            let neg = c.is_negative();
            let abs = if neg { c.neg().unwrap_or(*c) } else { *c };
            match (i, neg) {
                (0, true) => write!(f, "-")?,
                (0, false) => {}
                (_, true) => write!(f, " - ")?,
                (_, false) => write!(f, " + ")?,
            }
            let mut parts = Vec::new();
            if !abs.is_one() || m.is_empty() {
                parts.push(abs.to_string());
            }
            for (s, e) in m {
                let n = self.arena.name(*s);
                parts.push(if *e == 1 {
                    n.to_string()
                } else {
                    format!("{n}^{e}")
                });
            }
            write!(f, "{}", parts.join("*"))?;
        }
        Ok(())
    }
}

impl Arena {
    /// Fully expands `e` into a polynomial in all its symbols.
    ///
    /// Fails with [`SymError::NotPolynomial`] on functions of symbols or
    /// negative powers of non-constants.
    pub fn expand(&mut self, e: ExprId) -> Result<Poly, SymError> {
        let mut memo: HashMap<ExprId, Poly> = HashMap::new();
        self.expand_memo(e, &mut memo)
    }

    fn expand_memo(
        &mut self,
        e: ExprId,
        memo: &mut HashMap<ExprId, Poly>,
    ) -> Result<Poly, SymError> {
        if let Some(p) = memo.get(&e) {
            return Ok(p.clone());
        }
        let p = match self.node(e).clone() {
            Node::Num(r) => Poly::constant(r),
            Node::Sym(s) => Poly::var(s),
            Node::Add(ts) => {
                let mut acc = Poly::zero();
                for t in ts {
                    acc = acc.add(&self.expand_memo(t, memo)?)?;
                }
                acc
            }
            Node::Mul(fs) => {
                let mut acc = Poly::constant(Rational::ONE);
                for f in fs {
                    acc = acc.mul(&self.expand_memo(f, memo)?)?;
                }
                acc
            }
            Node::Pow(b, k) if k > 0 => self.expand_memo(b, memo)?.pow(k as u32)?,
            _ => {
                return Err(SymError::NotPolynomial {
                    var: "its symbols".into(),
                    what: self.show(e).to_string(),
                })
            }
        };
        memo.insert(e, p.clone());
        Ok(p)
    }

    /// Converts a polynomial back into an expression (a plain sum of terms).
    pub fn from_poly(&mut self, p: &Poly) -> Result<ExprId, SymError> {
        let mut terms = Vec::with_capacity(p.len());
        for (m, c) in p.terms() {
            let mut fs = vec![self.num(c)];
            for &(s, e) in m {
                let v = self.sym(s);
                fs.push(self.pow(v, e as i32)?);
            }
            terms.push(self.mul(&fs)?);
        }
        self.add(&terms)
    }

    /// Converts a polynomial into a nested Horner form, factoring out at each
    /// level the symbol that occurs in most terms (ties broken by the order
    /// of `priority`, then by symbol). Symbols in `last` are factored only
    /// after all others, so they end up as innermost coefficients.
    pub fn horner(&mut self, p: &Poly, last: &[Sym]) -> Result<ExprId, SymError> {
        let terms: Vec<(Mono, Rational)> = p.terms().map(|(m, c)| (m.clone(), c)).collect();
        self.horner_terms(terms, last)
    }

    fn horner_terms(
        &mut self,
        terms: Vec<(Mono, Rational)>,
        last: &[Sym],
    ) -> Result<ExprId, SymError> {
        if terms.is_empty() {
            return Ok(self.int(0));
        }
        // choose the variable occurring in most terms, preferring non-`last`
        let mut count: BTreeMap<(bool, Sym), usize> = BTreeMap::new();
        for (m, _) in &terms {
            for (s, _) in m {
                *count.entry((last.contains(s), *s)).or_default() += 1;
            }
        }
        let pick = count
            .iter()
            .min_by_key(|((is_last, s), n)| (*is_last, std::cmp::Reverse(**n), *s))
            .map(|((_, s), _)| *s);
        let Some(v) = pick else {
            // all constants
            let mut acc = Rational::ZERO;
            for (_, c) in terms {
                acc = acc.add(c)?;
            }
            return Ok(self.num(acc));
        };
        if terms.len() == 1 {
            let (m, c) = &terms[0];
            let mut fs = vec![self.num(*c)];
            for &(s, e) in m {
                let x = self.sym(s);
                fs.push(self.pow(x, e as i32)?);
            }
            return self.mul(&fs);
        }
        // p = sum_k v^k p_k ; Horner over the powers present
        let mut by_power: BTreeMap<u32, Vec<(Mono, Rational)>> = BTreeMap::new();
        for (m, c) in terms {
            by_power
                .entry(mono_degree(&m, v))
                .or_default()
                .push((mono_without(&m, v), c));
        }
        let powers: Vec<u32> = by_power.keys().copied().collect();
        let x = self.sym(v);
        let mut acc: Option<ExprId> = None;
        for (i, &k) in powers.iter().enumerate().rev() {
            let coeff_terms = by_power.remove(&k).unwrap_or_default();
            let ck = self.horner_terms(coeff_terms, last)?;
            let cur = match acc {
                None => ck,
                Some(inner) => {
                    let gap = powers[i + 1] - k;
                    let xg = self.pow(x, gap as i32)?;
                    let t = self.mul2(xg, inner)?;
                    self.add2(ck, t)?
                }
            };
            acc = Some(cur);
        }
        let lowest = powers[0];
        let inner = acc.unwrap_or_else(|| self.int(0));
        if lowest == 0 {
            Ok(inner)
        } else {
            let xl = self.pow(x, lowest as i32)?;
            self.mul2(xl, inner)
        }
    }

    /// Expands `e` as a polynomial in the symbols selected by `is_var` only.
    ///
    /// Each monomial's coefficient is a [`LinComb`]: rational multiples of
    /// *bodies*, products of factors free of the variables. Products do not
    /// distribute over a completed sum: when a sum is multiplied, each of its
    /// multi-term coefficients is frozen into one opaque factor (an atom), so
    /// `(a + (b + c) x)^2` keeps `(b + c)` whole and shared.
    pub fn expand_in(
        &mut self,
        e: ExprId,
        is_var: &dyn Fn(Sym) -> bool,
    ) -> Result<BTreeMap<Mono, LinComb>, SymError> {
        let mut memo = HashMap::new();
        self.expand_in_memo(e, is_var, &mut memo)
    }

    fn expand_in_memo(
        &mut self,
        e: ExprId,
        is_var: &dyn Fn(Sym) -> bool,
        memo: &mut HashMap<ExprId, BTreeMap<Mono, LinComb>>,
    ) -> Result<BTreeMap<Mono, LinComb>, SymError> {
        if let Some(p) = memo.get(&e) {
            return Ok(p.clone());
        }
        let out = if !self.depends_on(e, is_var) {
            let (r, body) = self.split_coeff(e);
            let mut lc = LinComb::default();
            lc.push(body, r)?;
            let mut m = BTreeMap::new();
            if !lc.is_zero() {
                m.insert(Vec::new(), lc);
            }
            m
        } else {
            match self.node(e).clone() {
                Node::Sym(s) => BTreeMap::from([(vec![(s, 1)], LinComb::one(self))]),
                Node::Add(ts) => {
                    let mut acc = BTreeMap::new();
                    for t in ts {
                        let pt = self.expand_in_memo(t, is_var, memo)?;
                        map_add(&mut acc, pt)?;
                    }
                    acc
                }
                Node::Mul(fs) => {
                    let mut acc = BTreeMap::from([(Vec::new(), LinComb::one(self))]);
                    for f in fs {
                        let pf = self.expand_in_memo(f, is_var, memo)?;
                        let pf = self.freeze(pf)?;
                        acc = self.map_mul(&acc, &pf)?;
                    }
                    acc
                }
                Node::Pow(b, k) if k > 0 => {
                    let pb = self.expand_in_memo(b, is_var, memo)?;
                    let pb = self.freeze(pb)?;
                    let mut acc = BTreeMap::from([(Vec::new(), LinComb::one(self))]);
                    for _ in 0..k {
                        acc = self.map_mul(&acc, &pb)?;
                    }
                    acc
                }
                _ => {
                    return Err(SymError::NotPolynomial {
                        var: "the integration variables".into(),
                        what: self.show(e).to_string(),
                    })
                }
            }
        };
        memo.insert(e, out.clone());
        Ok(out)
    }

    /// Turns every multi-term coefficient into a single opaque factor.
    fn freeze(&mut self, m: BTreeMap<Mono, LinComb>) -> Result<BTreeMap<Mono, LinComb>, SymError> {
        let mut out = BTreeMap::new();
        for (mono, lc) in m {
            if lc.terms.len() <= 1 {
                out.insert(mono, lc);
                continue;
            }
            let atom = lc.to_expr(self)?;
            let (r, body) = self.split_coeff(atom);
            let mut f = LinComb::default();
            f.push(body, r)?;
            out.insert(mono, f);
        }
        Ok(out)
    }

    fn map_mul(
        &mut self,
        a: &BTreeMap<Mono, LinComb>,
        b: &BTreeMap<Mono, LinComb>,
    ) -> Result<BTreeMap<Mono, LinComb>, SymError> {
        let mut acc: BTreeMap<Mono, LinComb> = BTreeMap::new();
        for (ma, ca) in a {
            for (mb, cb) in b {
                let prod = ca.mul(cb, self)?;
                let slot = acc.entry(mono_mul(ma, mb)?).or_default();
                slot.add(&prod)?;
            }
        }
        acc.retain(|_, lc| !lc.is_zero());
        Ok(acc)
    }
}

fn map_add(
    acc: &mut BTreeMap<Mono, LinComb>,
    other: BTreeMap<Mono, LinComb>,
) -> Result<(), SymError> {
    for (m, lc) in other {
        acc.entry(m).or_default().add(&lc)?;
    }
    acc.retain(|_, lc| !lc.is_zero());
    Ok(())
}

/// A rational linear combination of bodies (products of opaque factors),
/// the coefficient type of [`Arena::expand_in`].
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LinComb {
    /// (body, multiplier), sorted by body, no zero multipliers.
    pub terms: Vec<(ExprId, Rational)>,
}

impl LinComb {
    fn one(arena: &mut Arena) -> LinComb {
        LinComb {
            terms: vec![(arena.int(1), Rational::ONE)],
        }
    }

    /// True when empty.
    pub fn is_zero(&self) -> bool {
        self.terms.is_empty()
    }

    fn push(&mut self, body: ExprId, r: Rational) -> Result<(), Overflow> {
        match self.terms.binary_search_by_key(&body, |t| t.0) {
            Ok(i) => {
                let v = self.terms[i].1.add(r)?;
                if v.is_zero() {
                    self.terms.remove(i);
                } else {
                    self.terms[i].1 = v;
                }
            }
            Err(i) => {
                if !r.is_zero() {
                    self.terms.insert(i, (body, r));
                }
            }
        }
        Ok(())
    }

    fn add(&mut self, other: &LinComb) -> Result<(), Overflow> {
        for &(b, r) in &other.terms {
            self.push(b, r)?;
        }
        Ok(())
    }

    fn mul(&self, other: &LinComb, arena: &mut Arena) -> Result<LinComb, SymError> {
        let mut out = LinComb::default();
        for &(ba, ra) in &self.terms {
            for &(bb, rb) in &other.terms {
                let p = arena.mul2(ba, bb)?;
                let (r, body) = arena.split_coeff(p);
                out.push(body, r.mul(ra)?.mul(rb)?)?;
            }
        }
        Ok(out)
    }

    /// The combination as one expression.
    pub fn to_expr(&self, arena: &mut Arena) -> Result<ExprId, SymError> {
        let mut ts = Vec::with_capacity(self.terms.len());
        for &(b, r) in &self.terms {
            let k = arena.num(r);
            ts.push(arena.mul2(k, b)?);
        }
        arena.add(&ts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expand_binomial() {
        let mut a = Arena::new();
        let e = a.parse("(x + 2*y)^3").unwrap();
        let p = a.expand(e).unwrap();
        // canonical order: monomials sorted by (symbol, exponent) lists
        assert_eq!(p.show(&a).to_string(), "12*x*y^2 + 6*x^2*y + x^3 + 8*y^3");
    }

    #[test]
    fn integrate_with_symbolic_bounds() {
        let mut a = Arena::new();
        let e = a.parse("3*x^2 + y").unwrap();
        let p = a.expand(e).unwrap();
        let x = a.symbol("x");
        let lo = Poly::var(a.symbol("u"));
        let hi = Poly::constant(Rational::int(2));
        let i = p.integrate(x, &lo, &hi).unwrap();
        // [x^3 + x y] from u to 2 = 8 + 2y - u^3 - u y
        let want_e = a.parse("8 + 2*y - u^3 - u*y").unwrap();
        let want = a.expand(want_e).unwrap();
        assert_eq!(i, want);
    }

    #[test]
    fn horner_round_trips() {
        let mut a = Arena::new();
        let e = a.parse("1 + 2*x + 3*x^2*y + x^4 - y^2").unwrap();
        let p = a.expand(e).unwrap();
        let h = a.horner(&p, &[]).unwrap();
        assert_eq!(a.expand(h).unwrap(), p);
    }

    #[test]
    fn expand_in_keeps_coefficients_factored() {
        let mut a = Arena::new();
        let e = a.parse("(b + c*x)^2").unwrap();
        let x = a.symbol("x");
        let m = a.expand_in(e, &|s| s == x).unwrap();
        let mut shown = Vec::new();
        for lc in m.values() {
            let c = lc.to_expr(&mut a).unwrap();
            shown.push(a.show(c).to_string());
        }
        assert_eq!(shown, vec!["b^2", "2*b*c", "c^2"]);
        // a completed sum stays one factor when squared
        let e = a.parse("(1 + (b + c)*x)^2").unwrap();
        let m = a.expand_in(e, &|s| s == x).unwrap();
        let top = m.values().last().unwrap().to_expr(&mut a).unwrap();
        assert_eq!(a.show(top).to_string(), "(b + c)^2");
    }
}
