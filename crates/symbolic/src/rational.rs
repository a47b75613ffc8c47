//! Exact rational numbers on `i128` with checked arithmetic.
//!
//! Every operation that could overflow returns [`Overflow`] instead of
//! wrapping: a symbolic expansion that outgrows 128-bit integers is a bug in
//! the spec (or a sign that it needs a different basis), never a silent
//! wrong coefficient in generated code.

use std::cmp::Ordering;
use std::fmt;

/// The error of an exact-arithmetic operation whose result does not fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("rational arithmetic overflowed 128-bit integers in {op}")]
pub struct Overflow {
    /// The operation that overflowed (`"add"`, `"mul"`, `"pow"`, ...).
    pub op: &'static str,
}

/// A reduced fraction `num / den` with `den > 0`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Rational {
    num: i128,
    den: i128,
}

/// The gcd of `|a|` and `|b|`, in `u128`: `i128::MIN.abs()` overflows, and
/// gcd(i128::MIN, 0 or i128::MIN) = 2^127 does not fit in `i128`.
fn gcd(a: i128, b: i128) -> u128 {
    let (mut a, mut b) = (a.unsigned_abs(), b.unsigned_abs());
    while b != 0 {
        let t = a % b;
        a = b;
        b = t;
    }
    a
}

// The arithmetic methods are checked (they return `Result`), so they are
// deliberately not the operator traits.
#[allow(clippy::should_implement_trait)]
impl Rational {
    /// Zero.
    pub const ZERO: Rational = Rational { num: 0, den: 1 };
    /// One.
    pub const ONE: Rational = Rational { num: 1, den: 1 };

    /// An integer.
    pub const fn int(n: i128) -> Rational {
        Rational { num: n, den: 1 }
    }

    /// `num / den`, reduced. Fails on a zero denominator (reported as an
    /// overflow of `div`) or when negating `i128::MIN`.
    pub fn new(num: i128, den: i128) -> Result<Rational, Overflow> {
        if den == 0 {
            return Err(Overflow { op: "div" });
        }
        let g = match i128::try_from(gcd(num, den)) {
            Ok(g) => g.max(1),
            // 2^127: both are i128::MIN, or num is 0
            Err(_) => {
                return Ok(if num == 0 {
                    Rational::ZERO
                } else {
                    Rational::ONE
                })
            }
        };
        let (mut n, mut d) = (num / g, den / g);
        if d < 0 {
            n = n.checked_neg().ok_or(Overflow { op: "neg" })?;
            d = d.checked_neg().ok_or(Overflow { op: "neg" })?;
        }
        Ok(Rational { num: n, den: d })
    }

    /// The numerator (sign carrier).
    pub fn numer(self) -> i128 {
        self.num
    }

    /// The denominator (always positive).
    pub fn denom(self) -> i128 {
        self.den
    }

    /// True for 0.
    pub fn is_zero(self) -> bool {
        self.num == 0
    }

    /// True for 1.
    pub fn is_one(self) -> bool {
        self.num == 1 && self.den == 1
    }

    /// True for an integer value.
    pub fn is_integer(self) -> bool {
        self.den == 1
    }

    /// True for a negative value.
    pub fn is_negative(self) -> bool {
        self.num < 0
    }

    /// `self + rhs`.
    pub fn add(self, rhs: Rational) -> Result<Rational, Overflow> {
        let o = Overflow { op: "add" };
        // denominators are positive, so their gcd fits
        let g = gcd(self.den, rhs.den) as i128;
        let l = self.den / g;
        let r = rhs.den / g;
        let num = self
            .num
            .checked_mul(r)
            .and_then(|a| rhs.num.checked_mul(l).and_then(|b| a.checked_add(b)))
            .ok_or(o)?;
        let den = l.checked_mul(rhs.den).ok_or(o)?;
        Rational::new(num, den)
    }

    /// `self - rhs`.
    pub fn sub(self, rhs: Rational) -> Result<Rational, Overflow> {
        self.add(rhs.neg()?)
    }

    /// `-self`.
    pub fn neg(self) -> Result<Rational, Overflow> {
        Ok(Rational {
            num: self.num.checked_neg().ok_or(Overflow { op: "neg" })?,
            den: self.den,
        })
    }

    /// `self * rhs`.
    pub fn mul(self, rhs: Rational) -> Result<Rational, Overflow> {
        let o = Overflow { op: "mul" };
        // each gcd divides a positive denominator, so it fits
        let g1 = (gcd(self.num, rhs.den) as i128).max(1);
        let g2 = (gcd(rhs.num, self.den) as i128).max(1);
        let num = (self.num / g1).checked_mul(rhs.num / g2).ok_or(o)?;
        let den = (self.den / g2).checked_mul(rhs.den / g1).ok_or(o)?;
        Rational::new(num, den)
    }

    /// `1 / self`; fails for zero.
    pub fn recip(self) -> Result<Rational, Overflow> {
        Rational::new(self.den, self.num)
    }

    /// `self / rhs`; fails for a zero divisor.
    pub fn div(self, rhs: Rational) -> Result<Rational, Overflow> {
        self.mul(rhs.recip()?)
    }

    /// `self ^ e` for any integer exponent (negative inverts).
    pub fn pow(self, e: i32) -> Result<Rational, Overflow> {
        let base = if e < 0 { self.recip()? } else { self };
        let mut acc = Rational::ONE;
        let mut sq = base;
        let mut k = e.unsigned_abs();
        while k > 0 {
            if k & 1 == 1 {
                acc = acc.mul(sq).map_err(|_| Overflow { op: "pow" })?;
            }
            k >>= 1;
            if k > 0 {
                sq = sq.mul(sq).map_err(|_| Overflow { op: "pow" })?;
            }
        }
        Ok(acc)
    }

    /// The nearest `f64` (exact when numerator and denominator are below 2^53,
    /// where a single correctly rounded division gives the nearest double).
    pub fn to_f64(self) -> f64 {
        self.num as f64 / self.den as f64
    }

    /// Parses a decimal literal such as `1.598`, `250` or `2.5e-3` exactly.
    pub fn from_decimal(text: &str) -> Option<Rational> {
        let (mantissa, exp) = match text.find(['e', 'E']) {
            Some(i) => (&text[..i], text[i + 1..].parse::<i32>().ok()?),
            None => (text, 0),
        };
        let (int_part, frac_part) = match mantissa.find('.') {
            Some(i) => (&mantissa[..i], &mantissa[i + 1..]),
            None => (mantissa, ""),
        };
        if int_part.is_empty() && frac_part.is_empty() {
            return None;
        }
        if !int_part
            .chars()
            .chain(frac_part.chars())
            .all(|c| c.is_ascii_digit())
        {
            return None;
        }
        let digits = format!("{int_part}{frac_part}");
        let n: i128 = digits.parse().ok()?;
        let scale = exp.checked_sub(i32::try_from(frac_part.len()).ok()?)?;
        Rational::int(n)
            .mul(Rational::int(10).pow(scale).ok()?)
            .ok()
    }
}

impl PartialOrd for Rational {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Rational {
    fn cmp(&self, other: &Self) -> Ordering {
        // Compare a/b with c/d via a*d vs c*b, falling back to f64 on overflow.
        match (
            self.num.checked_mul(other.den),
            other.num.checked_mul(self.den),
        ) {
            (Some(l), Some(r)) => l.cmp(&r),
            _ => self
                .to_f64()
                .partial_cmp(&other.to_f64())
                .unwrap_or(Ordering::Equal),
        }
    }
}

impl fmt::Display for Rational {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.den == 1 {
            write!(f, "{}", self.num)
        } else {
            write!(f, "{}/{}", self.num, self.den)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(n: i128, d: i128) -> Rational {
        Rational::new(n, d).unwrap()
    }

    #[test]
    fn reduces_and_normalises_sign() {
        assert_eq!(r(6, -4), r(-3, 2));
        assert_eq!(r(-6, -4).to_string(), "3/2");
        assert_eq!(r(0, -5), Rational::ZERO);
    }

    #[test]
    fn field_operations() {
        assert_eq!(r(1, 2).add(r(1, 3)).unwrap(), r(5, 6));
        assert_eq!(r(1, 2).sub(r(1, 3)).unwrap(), r(1, 6));
        assert_eq!(r(2, 3).mul(r(9, 4)).unwrap(), r(3, 2));
        assert_eq!(r(2, 3).div(r(4, 9)).unwrap(), r(3, 2));
        assert_eq!(r(2, 3).pow(-3).unwrap(), r(27, 8));
        assert_eq!(r(-2, 1).pow(5).unwrap(), Rational::int(-32));
    }

    #[test]
    fn overflow_is_an_error() {
        let big = Rational::int(i128::MAX / 2 + 1);
        assert!(big.add(big).is_err());
        assert!(big.mul(Rational::int(3)).is_err());
        assert!(Rational::int(10).pow(40).is_err());
        assert!(Rational::ZERO.recip().is_err());
    }

    #[test]
    fn decimal_literals_are_exact() {
        assert_eq!(Rational::from_decimal("1.598").unwrap(), r(1598, 1000));
        assert_eq!(Rational::from_decimal("250").unwrap(), Rational::int(250));
        assert_eq!(Rational::from_decimal("2.5e-3").unwrap(), r(1, 400));
        assert_eq!(Rational::from_decimal(".5").unwrap(), r(1, 2));
        assert!(Rational::from_decimal("1.2.3").is_none());
        assert!(Rational::from_decimal("e5").is_none());
    }

    #[test]
    fn ordering() {
        assert!(r(1, 3) < r(1, 2));
        assert!(r(-1, 2) < Rational::ZERO);
    }
}
