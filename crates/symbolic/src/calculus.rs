//! Differentiation and substitution on the DAG, memoised per call so shared
//! sub-expressions are processed once.

use std::collections::HashMap;

use crate::expr::{Arena, ExprId, Func, Node, Sym, SymError};

impl Arena {
    /// The derivative of `e` with respect to symbol `s`.
    pub fn diff(&mut self, e: ExprId, s: Sym) -> Result<ExprId, SymError> {
        let mut memo = HashMap::new();
        self.diff_memo(e, s, &mut memo)
    }

    /// The `n`-th derivative of `e` with respect to `s`.
    pub fn diff_n(&mut self, mut e: ExprId, s: Sym, n: u32) -> Result<ExprId, SymError> {
        for _ in 0..n {
            e = self.diff(e, s)?;
        }
        Ok(e)
    }

    fn diff_memo(
        &mut self,
        e: ExprId,
        s: Sym,
        memo: &mut HashMap<ExprId, ExprId>,
    ) -> Result<ExprId, SymError> {
        if let Some(&d) = memo.get(&e) {
            return Ok(d);
        }
        let d = match self.node(e).clone() {
            Node::Num(_) => self.int(0),
            Node::Sym(t) => self.int(if t == s { 1 } else { 0 }),
            Node::Add(ts) => {
                let mut ds = Vec::with_capacity(ts.len());
                for t in ts {
                    ds.push(self.diff_memo(t, s, memo)?);
                }
                self.add(&ds)?
            }
            Node::Mul(fs) => {
                // product rule: sum_i f_i' * prod_{j != i} f_j
                let mut terms = Vec::with_capacity(fs.len());
                for i in 0..fs.len() {
                    let di = self.diff_memo(fs[i], s, memo)?;
                    if self.as_num(di).is_some_and(|r| r.is_zero()) {
                        continue;
                    }
                    let mut parts: Vec<ExprId> = fs
                        .iter()
                        .enumerate()
                        .filter(|&(j, _)| j != i)
                        .map(|(_, &f)| f)
                        .collect();
                    parts.push(di);
                    terms.push(self.mul(&parts)?);
                }
                self.add(&terms)?
            }
            Node::Pow(b, k) => {
                let db = self.diff_memo(b, s, memo)?;
                let kk = self.int(k as i128);
                let k1 = k.checked_sub(1).ok_or(crate::Overflow { op: "exponent" })?;
                let bk = self.pow(b, k1)?;
                self.mul(&[kk, bk, db])?
            }
            Node::Fun(f, args) => {
                let a = args[0];
                let da = self.diff_memo(a, s, memo)?;
                match f {
                    Func::Sin => {
                        let c = self.func(Func::Cos, &[a])?;
                        self.mul2(c, da)?
                    }
                    Func::Cos => {
                        let sn = self.func(Func::Sin, &[a])?;
                        let m = self.int(-1);
                        self.mul(&[m, sn, da])?
                    }
                    Func::Sqrt => {
                        // (sqrt a)' = a' / (2 sqrt a)
                        let half = self.num(crate::Rational::new(1, 2)?);
                        let inv = self.pow(e, -1)?;
                        self.mul(&[half, inv, da])?
                    }
                    Func::Atan2 => {
                        // atan2(y, x)' = (x y' - y x') / (x^2 + y^2)
                        let (y, x) = (args[0], args[1]);
                        let dy = da;
                        let dx = self.diff_memo(x, s, memo)?;
                        let xdy = self.mul2(x, dy)?;
                        let ydx = self.mul2(y, dx)?;
                        let num = self.sub(xdy, ydx)?;
                        let x2 = self.pow(x, 2)?;
                        let y2 = self.pow(y, 2)?;
                        let den = self.add2(x2, y2)?;
                        self.div(num, den)?
                    }
                }
            }
        };
        memo.insert(e, d);
        Ok(d)
    }

    /// Replaces symbols by expressions everywhere in `e` (simultaneously).
    pub fn subst(&mut self, e: ExprId, map: &HashMap<Sym, ExprId>) -> Result<ExprId, SymError> {
        let mut memo = HashMap::new();
        self.subst_memo(e, map, &mut memo)
    }

    /// Replaces one symbol by an expression.
    pub fn subst1(&mut self, e: ExprId, s: Sym, by: ExprId) -> Result<ExprId, SymError> {
        let map = HashMap::from([(s, by)]);
        self.subst(e, &map)
    }

    fn subst_memo(
        &mut self,
        e: ExprId,
        map: &HashMap<Sym, ExprId>,
        memo: &mut HashMap<ExprId, ExprId>,
    ) -> Result<ExprId, SymError> {
        if let Some(&r) = memo.get(&e) {
            return Ok(r);
        }
        let r = match self.node(e).clone() {
            Node::Num(_) => e,
            Node::Sym(s) => map.get(&s).copied().unwrap_or(e),
            Node::Add(ts) => {
                let v = self.subst_all(&ts, map, memo)?;
                self.add(&v)?
            }
            Node::Mul(fs) => {
                let v = self.subst_all(&fs, map, memo)?;
                self.mul(&v)?
            }
            Node::Pow(b, k) => {
                let nb = self.subst_memo(b, map, memo)?;
                self.pow(nb, k)?
            }
            Node::Fun(f, args) => {
                let v = self.subst_all(&args, map, memo)?;
                self.func(f, &v)?
            }
        };
        memo.insert(e, r);
        Ok(r)
    }

    fn subst_all(
        &mut self,
        ids: &[ExprId],
        map: &HashMap<Sym, ExprId>,
        memo: &mut HashMap<ExprId, ExprId>,
    ) -> Result<Vec<ExprId>, SymError> {
        ids.iter().map(|&i| self.subst_memo(i, map, memo)).collect()
    }
}

#[cfg(test)]
mod tests {
    use crate::Expr;

    fn d(src: &str, var: &str) -> String {
        let e: Expr = src.parse().unwrap();
        e.diff(var).unwrap().to_string()
    }

    #[test]
    fn rules() {
        assert_eq!(d("x^3", "x"), "3*x^2");
        assert_eq!(d("x*y", "x"), "y");
        assert_eq!(d("sin(x)", "x"), "cos(x)");
        assert_eq!(d("cos(2*x)", "x"), "-2*sin(2*x)");
        assert_eq!(d("1/x", "x"), "-x^(-2)");
        assert_eq!(d("y^2 + 7", "x"), "0");
    }

    #[test]
    fn subst_is_simultaneous() {
        let e: Expr = "x + 2*y".parse().unwrap();
        let s = e.subst(&[("x", "y"), ("y", "x")]).unwrap();
        assert_eq!(s.to_string(), "2*x + y");
        let v = s.eval(&[("x", 3.0), ("y", 5.0)]).unwrap();
        assert_eq!(v, 5.0 + 2.0 * 3.0);
    }
}
