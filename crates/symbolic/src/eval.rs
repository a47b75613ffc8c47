//! Numeric evaluation of expressions, used by tests to check algebra against
//! plain floating-point arithmetic.

use crate::expr::{Arena, ExprId, Func, Node, Sym};

/// A symbol had no value during evaluation.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("no value for symbol `{0}`")]
pub struct Unbound(pub String);

impl Arena {
    /// Evaluates `e`, asking `value` for each symbol.
    pub fn eval(&self, e: ExprId, value: &dyn Fn(Sym) -> Option<f64>) -> Result<f64, Unbound> {
        // The arena is topologically ordered, so one pass over ids <= e works;
        // only nodes reachable from e are computed.
        let mut need = vec![false; e.index() + 1];
        need[e.index()] = true;
        for i in (0..=e.index()).rev() {
            if need[i] {
                for c in self.children(ExprId(i as u32)) {
                    need[c.index()] = true;
                }
            }
        }
        let mut vals = vec![0.0f64; e.index() + 1];
        for i in 0..=e.index() {
            if !need[i] {
                continue;
            }
            let v = match self.node(ExprId(i as u32)) {
                Node::Num(r) => r.to_f64(),
                Node::Sym(s) => value(*s).ok_or_else(|| Unbound(self.name(*s).to_string()))?,
                Node::Add(ts) => ts.iter().map(|t| vals[t.index()]).sum(),
                Node::Mul(fs) => fs.iter().map(|f| vals[f.index()]).product(),
                Node::Pow(b, k) => vals[b.index()].powi(*k),
                Node::Fun(f, args) => {
                    let a = vals[args[0].index()];
                    match f {
                        Func::Sin => a.sin(),
                        Func::Cos => a.cos(),
                        Func::Sqrt => a.sqrt(),
                        Func::Atan2 => a.atan2(vals[args[1].index()]),
                    }
                }
            };
            vals[i] = v;
        }
        Ok(vals[e.index()])
    }

    /// Evaluates with values given by symbol name.
    pub fn eval_named(&self, e: ExprId, values: &[(&str, f64)]) -> Result<f64, Unbound> {
        self.eval(e, &|s| {
            let n = self.name(s);
            values.iter().find(|(k, _)| *k == n).map(|(_, v)| *v)
        })
    }
}
