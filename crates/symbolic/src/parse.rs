//! The text form of expressions and the energy-spec language.
//!
//! Expressions: numbers (decimal literals are exact rationals), symbols,
//! `+ - * / ^` (integer exponents), parentheses, `sin cos sqrt atan2`, and
//! two operators evaluated while parsing: `d(e, x)` / `d(e, x, n)`
//! (derivative) and `at(e, x, v)` (substitute `v` for `x`).
//!
//! Spec files add statements (see [`crate::spec`]); every error carries the
//! line and column and says what was expected.

use std::collections::HashMap;
use std::fmt;

use crate::expr::{Arena, ExprId, Func, SymError};
use crate::rational::Rational;

/// A parse error with its position (1-based line and column).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub struct ParseError {
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub col: usize,
    /// What the parser expected there.
    pub expected: String,
    /// What it found instead.
    pub found: String,
}

impl fmt::Display for ParseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "line {}, column {}: expected {}, found {}",
            self.line, self.col, self.expected, self.found
        )
    }
}

/// A lexical token.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Tok {
    Num(String),
    Ident(String),
    Punct(char),
    Eof,
}

impl fmt::Display for Tok {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Tok::Num(n) => write!(f, "number `{n}`"),
            Tok::Ident(s) => write!(f, "`{s}`"),
            Tok::Punct(c) => write!(f, "`{c}`"),
            Tok::Eof => write!(f, "end of input"),
        }
    }
}

#[derive(Debug, Clone)]
pub(crate) struct Token {
    pub tok: Tok,
    pub line: usize,
    pub col: usize,
}

pub(crate) fn lex(src: &str) -> Result<Vec<Token>, ParseError> {
    let mut out = Vec::new();
    let chars: Vec<char> = src.chars().collect();
    let (mut i, mut line, mut col) = (0usize, 1usize, 1usize);
    while i < chars.len() {
        let c = chars[i];
        let (l0, c0) = (line, col);
        if c == '\n' {
            i += 1;
            line += 1;
            col = 1;
            continue;
        }
        if c.is_whitespace() {
            i += 1;
            col += 1;
            continue;
        }
        if c == '#' {
            while i < chars.len() && chars[i] != '\n' {
                i += 1;
            }
            continue;
        }
        if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
        {
            let start = i;
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '-' || chars[j] == '+') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    i = j;
                    while i < chars.len() && chars[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let text: String = chars[start..i].iter().collect();
            col += i - start;
            out.push(Token {
                tok: Tok::Num(text),
                line: l0,
                col: c0,
            });
            continue;
        }
        if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            let text: String = chars[start..i].iter().collect();
            col += i - start;
            out.push(Token {
                tok: Tok::Ident(text),
                line: l0,
                col: c0,
            });
            continue;
        }
        if "+-*/^(),;=[]{}:".contains(c) {
            out.push(Token {
                tok: Tok::Punct(c),
                line: l0,
                col: c0,
            });
            i += 1;
            col += 1;
            continue;
        }
        return Err(ParseError {
            line: l0,
            col: c0,
            expected: "a number, a name, an operator or punctuation".into(),
            found: format!("character `{c}`"),
        });
    }
    out.push(Token {
        tok: Tok::Eof,
        line,
        col,
    });
    Ok(out)
}

/// A recursive-descent parser over tokens that builds straight into an arena.
pub(crate) struct Parser<'a> {
    pub toks: Vec<Token>,
    pub pos: usize,
    pub arena: &'a mut Arena,
    /// `let` definitions visible to expressions.
    pub lets: HashMap<String, ExprId>,
}

impl<'a> Parser<'a> {
    pub fn new(src: &str, arena: &'a mut Arena) -> Result<Parser<'a>, ParseError> {
        Ok(Parser {
            toks: lex(src)?,
            pos: 0,
            arena,
            lets: HashMap::new(),
        })
    }

    pub fn peek(&self) -> &Token {
        &self.toks[self.pos.min(self.toks.len() - 1)]
    }

    pub fn next(&mut self) -> Token {
        let t = self.peek().clone();
        if self.pos < self.toks.len() - 1 {
            self.pos += 1;
        }
        t
    }

    pub fn error_at(&self, t: &Token, expected: &str) -> ParseError {
        ParseError {
            line: t.line,
            col: t.col,
            expected: expected.into(),
            found: t.tok.to_string(),
        }
    }

    pub fn error(&self, expected: &str) -> ParseError {
        self.error_at(self.peek(), expected)
    }

    fn sym_err(&self, t: &Token, e: SymError) -> ParseError {
        ParseError {
            line: t.line,
            col: t.col,
            expected: "an expression that can be built".into(),
            found: format!("a failure: {e}"),
        }
    }

    pub fn is_punct(&self, c: char) -> bool {
        self.peek().tok == Tok::Punct(c)
    }

    pub fn expect_punct(&mut self, c: char) -> Result<(), ParseError> {
        if self.is_punct(c) {
            self.next();
            Ok(())
        } else {
            Err(self.error(&format!("`{c}`")))
        }
    }

    pub fn is_ident(&self, word: &str) -> bool {
        matches!(&self.peek().tok, Tok::Ident(s) if s == word)
    }

    pub fn expect_ident(&mut self, what: &str) -> Result<(String, Token), ParseError> {
        let t = self.peek().clone();
        match &t.tok {
            Tok::Ident(s) => {
                let s = s.clone();
                self.next();
                Ok((s, t))
            }
            _ => Err(self.error(what)),
        }
    }

    /// expr := term (('+' | '-') term)*
    pub fn expr(&mut self) -> Result<ExprId, ParseError> {
        let mut acc = self.term()?;
        loop {
            let t = self.peek().clone();
            let op = match t.tok {
                Tok::Punct('+') => '+',
                Tok::Punct('-') => '-',
                _ => return Ok(acc),
            };
            self.next();
            let rhs = self.term()?;
            acc = if op == '+' {
                self.arena.add2(acc, rhs)
            } else {
                self.arena.sub(acc, rhs)
            }
            .map_err(|e| self.sym_err(&t, e))?;
        }
    }

    /// term := unary (('*' | '/') unary)*
    fn term(&mut self) -> Result<ExprId, ParseError> {
        let mut acc = self.unary()?;
        loop {
            let t = self.peek().clone();
            let op = match t.tok {
                Tok::Punct('*') => '*',
                Tok::Punct('/') => '/',
                _ => return Ok(acc),
            };
            self.next();
            let rhs = self.unary()?;
            acc = if op == '*' {
                self.arena.mul2(acc, rhs)
            } else {
                self.arena.div(acc, rhs)
            }
            .map_err(|e| self.sym_err(&t, e))?;
        }
    }

    /// unary := '-' unary | power
    fn unary(&mut self) -> Result<ExprId, ParseError> {
        if self.is_punct('-') {
            let t = self.next();
            let v = self.unary()?;
            return self.arena.neg(v).map_err(|e| self.sym_err(&t, e));
        }
        self.power()
    }

    /// power := atom ('^' exponent)?   exponent := integer | '-' integer | '(' ['-'] integer ')'
    fn power(&mut self) -> Result<ExprId, ParseError> {
        let base = self.atom()?;
        if !self.is_punct('^') {
            return Ok(base);
        }
        let t = self.next();
        let paren = self.is_punct('(');
        if paren {
            self.next();
        }
        let neg = self.is_punct('-');
        if neg {
            self.next();
        }
        let nt = self.peek().clone();
        let k: i32 = match &nt.tok {
            Tok::Num(n) => n.parse().map_err(|_| self.error("an integer exponent"))?,
            _ => return Err(self.error("an integer exponent")),
        };
        self.next();
        if paren {
            self.expect_punct(')')?;
        }
        let k = if neg { -k } else { k };
        self.arena.pow(base, k).map_err(|e| self.sym_err(&t, e))
    }

    fn atom(&mut self) -> Result<ExprId, ParseError> {
        let t = self.peek().clone();
        match &t.tok {
            Tok::Num(n) => {
                let r = Rational::from_decimal(n)
                    .ok_or_else(|| self.error("a number that fits exactly"))?;
                self.next();
                Ok(self.arena.num(r))
            }
            Tok::Punct('(') => {
                self.next();
                let e = self.expr()?;
                self.expect_punct(')')?;
                Ok(e)
            }
            Tok::Ident(name) => {
                let name = name.clone();
                self.next();
                if self.is_punct('(') {
                    return self.call(&name, &t);
                }
                if let Some(&e) = self.lets.get(&name) {
                    return Ok(e);
                }
                Ok(self.arena.var(&name))
            }
            _ => Err(self.error("a number, a name or `(`")),
        }
    }

    fn args(&mut self) -> Result<Vec<ExprId>, ParseError> {
        self.expect_punct('(')?;
        let mut out = vec![self.expr()?];
        while self.is_punct(',') {
            self.next();
            out.push(self.expr()?);
        }
        self.expect_punct(')')?;
        Ok(out)
    }

    fn call(&mut self, name: &str, t: &Token) -> Result<ExprId, ParseError> {
        let args = self.args()?;
        let bad = |p: &Self, what: &str| p.error_at(t, what);
        match name {
            "d" => {
                if !(2..=3).contains(&args.len()) {
                    return Err(bad(
                        self,
                        "d(expression, variable) or d(expression, variable, order)",
                    ));
                }
                let s = self
                    .arena
                    .as_sym(args[1])
                    .ok_or_else(|| bad(self, "a variable name as the second argument of d"))?;
                let n = match args.get(2) {
                    None => 1,
                    Some(&k) => match self.arena.as_num(k) {
                        Some(r) if r.is_integer() && !r.is_negative() && r.numer() < 16 => {
                            r.numer() as u32
                        }
                        _ => return Err(bad(self, "a small non-negative integer order in d")),
                    },
                };
                self.arena
                    .diff_n(args[0], s, n)
                    .map_err(|e| self.sym_err(t, e))
            }
            "at" => {
                if args.len() != 3 {
                    return Err(bad(self, "at(expression, variable, value)"));
                }
                let s = self
                    .arena
                    .as_sym(args[1])
                    .ok_or_else(|| bad(self, "a variable name as the second argument of at"))?;
                self.arena
                    .subst1(args[0], s, args[2])
                    .map_err(|e| self.sym_err(t, e))
            }
            _ => {
                let f = Func::from_name(name)
                    .ok_or_else(|| bad(self, "a known function (sin, cos, sqrt, atan2, d, at)"))?;
                if args.len() != f.arity() {
                    return Err(bad(
                        self,
                        &format!("{} argument(s) for {}", f.arity(), f.name()),
                    ));
                }
                self.arena.func(f, &args).map_err(|e| self.sym_err(t, e))
            }
        }
    }
}

impl Arena {
    /// Parses an expression in the text form into this arena.
    pub fn parse(&mut self, src: &str) -> Result<ExprId, ParseError> {
        let mut p = Parser::new(src, self)?;
        let e = p.expr()?;
        if p.peek().tok != Tok::Eof {
            return Err(p.error("an operator or the end of the expression"));
        }
        Ok(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_text_form() {
        let mut a = Arena::new();
        for src in [
            "x + 2*y",
            "-x^3 + 1/2*x*y",
            "sin(x)*cos(y)",
            "atan2(y, 1 + x)",
            "x^(-2)",
        ] {
            let e = a.parse(src).unwrap();
            let shown = a.show(e).to_string();
            let again = a.parse(&shown).unwrap();
            assert_eq!(e, again, "{src} -> {shown}");
        }
    }

    #[test]
    fn errors_name_position_and_expectation() {
        let mut a = Arena::new();
        let err = a.parse("x +\n  * y").unwrap_err();
        assert_eq!((err.line, err.col), (2, 3));
        assert!(
            err.to_string().contains("expected a number, a name or `(`"),
            "{err}"
        );
        let err = a.parse("x^y").unwrap_err();
        assert!(err.expected.contains("integer exponent"));
        let err = a.parse("foo(x)").unwrap_err();
        assert!(err.expected.contains("known function"));
        let err = a.parse("x $ y").unwrap_err();
        assert_eq!(err.col, 3);
    }

    #[test]
    fn derivative_and_substitution_operators() {
        let mut a = Arena::new();
        let e = a.parse("d(x^3, x, 2)").unwrap();
        assert_eq!(a.show(e).to_string(), "6*x");
        let e = a.parse("at(x^2 + y, x, 3)").unwrap();
        assert_eq!(a.show(e).to_string(), "9 + y");
    }
}
