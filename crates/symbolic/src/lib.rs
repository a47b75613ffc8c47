//! A small computer algebra system for generating energy kernels.
//!
//! It does, at build time, what the FPC paper did with MATLAB's symbolic
//! toolbox: expand polynomial energy densities, integrate them exactly over
//! boxes with symbolic bounds, differentiate, and emit straight-line Rust.
//! It knows nothing about fingers; the physics lives in the energy spec.
//!
//! - [`Arena`]: the hash-consed expression DAG (sharing on insert) with exact
//!   [`Rational`] coefficients, canonicalising constructors,
//!   differentiation, substitution and numeric evaluation.
//! - [`Poly`]: canonical polynomial form, exact definite integration,
//!   Horner factoring; [`Arena::expand_in`] expands in chosen variables only.
//! - [`emit`]: power lowering, common-subexpression binding, operation
//!   counts and Rust emission with `proc-macro2`/`quote`.
//! - [`spec`] and [`codegen`]: the energy-spec language and the kernel
//!   generator (a pure function from spec text to a token stream).
//! - [`Expr`]: an owned expression with `FromStr`/`Display`, so algebra
//!   tests read as formulas.

mod calculus;
pub mod codegen;
pub mod emit;
mod eval;
mod expr;
mod parse;
mod poly;
mod rational;
pub mod spec;

pub use eval::Unbound;
pub use expr::{Arena, ExprId, Func, Node, Show, Sym, SymError};
pub use parse::ParseError;
pub use poly::{mono_degree, LinComb, Mono, Poly};
pub use rational::{Overflow, Rational};

use std::fmt;
use std::str::FromStr;

/// An expression that owns its arena: convenient for tests and examples.
///
/// ```
/// use fpc_symbolic::Expr;
/// let e: Expr = "(x + 1)^2".parse().unwrap();
/// assert_eq!(e.expand().unwrap().to_string(), "1 + 2*x + x^2");
/// assert_eq!(e.diff("x").unwrap().to_string(), "2*(1 + x)");
/// ```
#[derive(Debug, Clone)]
pub struct Expr {
    arena: Arena,
    root: ExprId,
}

impl Expr {
    /// The arena and root.
    pub fn parts(&self) -> (&Arena, ExprId) {
        (&self.arena, self.root)
    }

    fn with(
        &self,
        f: impl FnOnce(&mut Arena, ExprId) -> Result<ExprId, SymError>,
    ) -> Result<Expr, SymError> {
        let mut arena = self.arena.clone();
        let root = f(&mut arena, self.root)?;
        Ok(Expr { arena, root })
    }

    /// The derivative with respect to the named symbol.
    pub fn diff(&self, var: &str) -> Result<Expr, SymError> {
        self.with(|a, r| {
            let s = a.symbol(var);
            a.diff(r, s)
        })
    }

    /// The full polynomial expansion, as an expression.
    pub fn expand(&self) -> Result<Expr, SymError> {
        self.with(|a, r| {
            let p = a.expand(r)?;
            a.from_poly(&p)
        })
    }

    /// The definite integral over `var` between two expressions in text form.
    pub fn integrate(
        &self,
        var: &str,
        lo: &str,
        hi: &str,
    ) -> Result<Expr, Box<dyn std::error::Error>> {
        let mut arena = self.arena.clone();
        let s = arena.symbol(var);
        let lo = arena.parse(lo)?;
        let hi = arena.parse(hi)?;
        let p = arena.expand(self.root)?;
        let (plo, phi) = (arena.expand(lo)?, arena.expand(hi)?);
        let i = p.integrate(s, &plo, &phi)?;
        let root = arena.from_poly(&i)?;
        Ok(Expr { arena, root })
    }

    /// Simultaneous substitution of named symbols by expressions in text form.
    pub fn subst(&self, pairs: &[(&str, &str)]) -> Result<Expr, Box<dyn std::error::Error>> {
        let mut arena = self.arena.clone();
        let mut map = std::collections::HashMap::new();
        for (name, by) in pairs {
            let s = arena.symbol(name);
            let e = arena.parse(by)?;
            map.insert(s, e);
        }
        let root = arena.subst(self.root, &map)?;
        Ok(Expr { arena, root })
    }

    /// Numeric value with symbol values given by name.
    pub fn eval(&self, values: &[(&str, f64)]) -> Result<f64, Unbound> {
        self.arena.eval_named(self.root, values)
    }
}

impl FromStr for Expr {
    type Err = ParseError;
    fn from_str(s: &str) -> Result<Expr, ParseError> {
        let mut arena = Arena::new();
        let root = arena.parse(s)?;
        Ok(Expr { arena, root })
    }
}

impl fmt::Display for Expr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.arena.show(self.root))
    }
}
