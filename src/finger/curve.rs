//! The mid-plane as exact curves: one polynomial curve per element
//! (docs/model.md M14), and the affine maps between frames (M10, M15).
//!
//! The generator checks that every model's mid-plane is a polynomial in the
//! element's local `x` (`Kinematics::midplane_coefficients`), so each
//! element's piece of the finger is `q(x) = sum_j c_j x^j` for `x` in
//! `[0, L]`, with `c_j` points of the plane. Rotating and translating a
//! polynomial curve keeps it one: the map applies to the coefficients.

use crate::error::{finite, positive, InputError};

/// An affine map of the plane, `q -> matrix q + offset` (`matrix` given
/// row by row): the chain's element frames (a rotation by the chain angle
/// and a translation to the element's root, M10) and the finger-to-gripper
/// map (M15) are such maps.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Affine2 {
    matrix: [[f64; 2]; 2],
    offset: [f64; 2],
}

impl Affine2 {
    /// The identity.
    pub const IDENTITY: Affine2 = Affine2 {
        matrix: [[1.0, 0.0], [0.0, 1.0]],
        offset: [0.0, 0.0],
    };

    /// The map `q -> matrix q + offset`; every entry must be finite.
    pub fn new(matrix: [[f64; 2]; 2], offset: [f64; 2]) -> Result<Affine2, InputError> {
        for (i, row) in matrix.iter().enumerate() {
            for (j, &v) in row.iter().enumerate() {
                finite(format!("affine.matrix[{i}][{j}]").into(), v)?;
            }
        }
        finite(crate::Field::key("affine.offset[0]"), offset[0])?;
        finite(crate::Field::key("affine.offset[1]"), offset[1])?;
        Ok(Affine2 { matrix, offset })
    }

    /// A rotation by `angle` (rad, counter-clockwise from X towards Z)
    /// followed by a translation by `offset`.
    pub fn rotation(angle: f64, offset: [f64; 2]) -> Result<Affine2, InputError> {
        finite(crate::Field::key("affine.angle"), angle)?;
        let (s, c) = angle.sin_cos();
        Affine2::new([[c, -s], [s, c]], offset)
    }

    /// The rotation `[[c, -s], [s, c]]` (c, s finite: the chain's frames).
    pub(crate) fn rotation_cs(c: f64, s: f64, offset: [f64; 2]) -> Affine2 {
        Affine2 {
            matrix: [[c, -s], [s, c]],
            offset,
        }
    }

    /// The matrix, row by row.
    pub fn matrix(&self) -> [[f64; 2]; 2] {
        self.matrix
    }

    /// The offset.
    pub fn offset(&self) -> [f64; 2] {
        self.offset
    }

    /// The image of a point.
    #[inline]
    pub fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        let v = self.apply_vector(p);
        [v[0] + self.offset[0], v[1] + self.offset[1]]
    }

    /// The image of a displacement (the matrix alone).
    #[inline]
    pub fn apply_vector(&self, v: [f64; 2]) -> [f64; 2] {
        let m = &self.matrix;
        [
            m[0][0] * v[0] + m[0][1] * v[1],
            m[1][0] * v[0] + m[1][1] * v[1],
        ]
    }

    /// `self` after `inner`: the map `q -> self(inner(q))`.
    pub fn after(&self, inner: &Affine2) -> Affine2 {
        let a = &self.matrix;
        let b = &inner.matrix;
        let matrix = [
            [
                a[0][0] * b[0][0] + a[0][1] * b[1][0],
                a[0][0] * b[0][1] + a[0][1] * b[1][1],
            ],
            [
                a[1][0] * b[0][0] + a[1][1] * b[1][0],
                a[1][0] * b[0][1] + a[1][1] * b[1][1],
            ],
        ];
        Affine2 {
            matrix,
            offset: self.apply(inner.offset),
        }
    }
}

/// A polynomial curve `q(x) = sum_j c_j x^j` of the plane for `x` in
/// `[0, L]`: one element's piece of the mid-plane
/// ([`Finger::midplane_curves`](crate::Finger::midplane_curves)), `x`
/// being the element's local coordinate.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PolyCurve {
    /// `[X_j, Z_j]`, the coefficient of `x^j`, in ascending powers.
    coefficients: Vec<[f64; 2]>,
    /// The parameter range's end `L` (mm).
    #[serde(rename = "length_mm")]
    length: f64,
}

impl PolyCurve {
    /// The curve with coefficients `[X_j, Z_j]` in ascending powers of `x`
    /// over `[0, length]`: at least one coefficient, all finite, and a
    /// positive, finite length.
    pub fn new(coefficients: Vec<[f64; 2]>, length: f64) -> Result<PolyCurve, InputError> {
        positive(crate::Field::key("curve.length"), length)?;
        if coefficients.is_empty() {
            return Err(InputError::Inconsistent {
                field: crate::Field::key("curve.coefficients"),
                rule: "a curve needs at least one coefficient".into(),
            });
        }
        for (j, c) in coefficients.iter().enumerate() {
            finite(format!("curve.coefficients[{j}][0]").into(), c[0])?;
            finite(format!("curve.coefficients[{j}][1]").into(), c[1])?;
        }
        Ok(PolyCurve {
            coefficients,
            length,
        })
    }

    /// A curve from parts the caller knows to be valid.
    pub(crate) fn from_parts(coefficients: Vec<[f64; 2]>, length: f64) -> PolyCurve {
        debug_assert!(!coefficients.is_empty() && length > 0.0);
        PolyCurve {
            coefficients,
            length,
        }
    }

    /// The coefficients `[X_j, Z_j]` of `x^j`, in ascending powers.
    pub fn coefficients(&self) -> &[[f64; 2]] {
        &self.coefficients
    }

    /// The parameter range's end `L`: the curve is defined on `[0, L]`.
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The polynomial degree (the number of coefficients less one; the
    /// leading one may be zero).
    pub fn degree(&self) -> usize {
        self.coefficients.len() - 1
    }

    /// The point at `x` (Horner's rule; any `x`, not only `[0, L]`).
    #[inline]
    pub fn point(&self, x: f64) -> [f64; 2] {
        self.coefficients
            .iter()
            .rev()
            .fold([0.0, 0.0], |acc, c| [acc[0] * x + c[0], acc[1] * x + c[1]])
    }

    /// The derivative `dq/dx` at `x`.
    pub fn tangent(&self, x: f64) -> [f64; 2] {
        self.coefficients
            .iter()
            .enumerate()
            .skip(1)
            .rev()
            .fold([0.0, 0.0], |acc, (j, c)| {
                let j = j as f64;
                [acc[0] * x + j * c[0], acc[1] * x + j * c[1]]
            })
    }

    /// The point at `x = 0`.
    pub fn start(&self) -> [f64; 2] {
        self.coefficients[0]
    }

    /// The point at `x = L`.
    pub fn end(&self) -> [f64; 2] {
        self.point(self.length)
    }

    /// The same curve mapped by `m`: the constant coefficient goes through
    /// the whole map, the others through its matrix (so `map(m).point(x) ==
    /// m.apply(point(x))`, to rounding).
    pub fn map(&self, m: Affine2) -> PolyCurve {
        let coefficients = self
            .coefficients
            .iter()
            .enumerate()
            .map(|(j, &c)| {
                if j == 0 {
                    m.apply(c)
                } else {
                    m.apply_vector(c)
                }
            })
            .collect();
        PolyCurve {
            coefficients,
            length: self.length,
        }
    }

    /// True when every coefficient is finite (a map may overflow).
    pub fn is_finite(&self) -> bool {
        self.coefficients
            .iter()
            .all(|c| c[0].is_finite() && c[1].is_finite())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_commutes_with_evaluation() {
        let c = PolyCurve::new(
            vec![[1.0, -2.0], [0.5, 0.25], [0.0, -0.1], [0.01, 0.0]],
            7.0,
        )
        .unwrap();
        let m = Affine2::new([[0.3, -1.2], [0.7, 0.4]], [5.0, -3.0]).unwrap();
        let mc = c.map(m);
        for i in 0..=20 {
            let x = 7.0 * i as f64 / 20.0;
            let (a, b) = (mc.point(x), m.apply(c.point(x)));
            assert!((a[0] - b[0]).abs() < 1e-13 && (a[1] - b[1]).abs() < 1e-13);
            let (ta, tb) = (mc.tangent(x), m.apply_vector(c.tangent(x)));
            assert!((ta[0] - tb[0]).abs() < 1e-13 && (ta[1] - tb[1]).abs() < 1e-13);
        }
        assert_eq!(c.end(), c.point(7.0));
        assert_eq!(c.degree(), 3);
    }

    #[test]
    fn tangent_is_the_derivative() {
        let c = PolyCurve::new(
            vec![[1.0, -2.0], [0.5, 0.25], [0.3, -0.1], [0.01, 0.02]],
            3.0,
        )
        .unwrap();
        for x in [0.0, 0.7, 2.9] {
            let h = 1e-6;
            let (p, m) = (c.point(x + h), c.point(x - h));
            let t = c.tangent(x);
            for o in 0..2 {
                assert!(((p[o] - m[o]) / (2.0 * h) - t[o]).abs() < 1e-8);
            }
        }
    }

    #[test]
    fn composition_and_rotation() {
        let a = Affine2::rotation(0.4, [1.0, 2.0]).unwrap();
        let b = Affine2::new([[2.0, 0.5], [-1.0, 3.0]], [-0.5, 0.25]).unwrap();
        let ab = a.after(&b);
        let p = [0.3, -1.7];
        let (x, y) = (ab.apply(p), a.apply(b.apply(p)));
        assert!((x[0] - y[0]).abs() < 1e-14 && (x[1] - y[1]).abs() < 1e-14);
        assert_eq!(Affine2::IDENTITY.apply(p), p);
    }

    #[test]
    fn invalid_input_is_a_typed_error() {
        assert_eq!(
            PolyCurve::new(vec![], 1.0).unwrap_err().field(),
            "curve.coefficients"
        );
        assert_eq!(
            PolyCurve::new(vec![[0.0, f64::NAN]], 1.0)
                .unwrap_err()
                .field(),
            "curve.coefficients[0][1]"
        );
        assert_eq!(
            PolyCurve::new(vec![[0.0, 0.0]], 0.0).unwrap_err().field(),
            "curve.length"
        );
        assert_eq!(
            Affine2::new([[1.0, f64::INFINITY], [0.0, 1.0]], [0.0; 2])
                .unwrap_err()
                .field(),
            "affine.matrix[0][1]"
        );
        assert_eq!(
            Affine2::rotation(f64::NAN, [0.0; 2]).unwrap_err().field(),
            "affine.angle"
        );
    }
}
