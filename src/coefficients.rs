//! The unknowns of a finger's elements, flat and element by element: what
//! a solve returns, what a guess gives, and what a failed solve carries
//! ([`crate::SolveError`]).

use crate::error::InputError;
use crate::field::Field;

/// The unknowns of every element, element by element (`per_element` values
/// each, in the model's order: `a1, a3, b1, c2` for the paper's element).
#[derive(Debug, Clone, PartialEq)]
pub struct Coefficients {
    per_element: usize,
    values: Vec<f64>,
}

impl Coefficients {
    /// Coefficients from their values, `per_element` per element.
    pub fn new(per_element: usize, values: Vec<f64>) -> Result<Coefficients, InputError> {
        if per_element == 0 || values.is_empty() || !values.len().is_multiple_of(per_element) {
            return Err(InputError::Inconsistent {
                field: Field::Coefficients,
                rule: format!(
                    "{} values do not split into elements of {per_element} unknowns",
                    values.len()
                ),
            });
        }
        Ok(Coefficients {
            per_element,
            values,
        })
    }

    /// Coefficients from values known to split into elements of
    /// `per_element` (no check).
    pub(crate) fn from_parts(per_element: usize, values: Vec<f64>) -> Coefficients {
        Coefficients {
            per_element,
            values,
        }
    }

    /// Zeros: the straight, unstrained finger.
    pub fn zeros(elements: usize, per_element: usize) -> Coefficients {
        Coefficients {
            per_element,
            values: vec![0.0; elements * per_element],
        }
    }

    /// Number of elements.
    pub fn elements(&self) -> usize {
        self.values.len() / self.per_element
    }

    /// Unknowns per element.
    pub fn per_element(&self) -> usize {
        self.per_element
    }

    /// Element `i`'s unknowns.
    pub fn element(&self, i: usize) -> &[f64] {
        &self.values[i * self.per_element..(i + 1) * self.per_element]
    }

    /// Element by element.
    pub fn iter(&self) -> std::slice::ChunksExact<'_, f64> {
        self.values.chunks_exact(self.per_element)
    }

    /// Every value, element by element.
    pub fn as_slice(&self) -> &[f64] {
        &self.values
    }

    /// A start for [`crate::Partition::split`] with the same `split`: each
    /// half of a split element starts from its parent's raw coefficients
    /// (exact for the first half, whose local frame is the parent's).
    pub(crate) fn split(&self, split: &[bool]) -> Coefficients {
        let halves = split.iter().filter(|&&s| s).count();
        let mut values = Vec::with_capacity(self.values.len() + halves * self.per_element);
        for (i, e) in self.iter().enumerate() {
            values.extend_from_slice(e);
            if split.get(i).copied().unwrap_or(false) {
                values.extend_from_slice(e);
            }
        }
        Coefficients::from_parts(self.per_element, values)
    }

    /// Every value, element by element, to change in place.
    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        &mut self.values
    }
}

impl serde::Serialize for Coefficients {
    /// One array of unknowns per element.
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeSeq;
        let mut seq = serializer.serialize_seq(Some(self.elements()))?;
        for e in self.iter() {
            seq.serialize_element(e)?;
        }
        seq.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A split element's coefficients appear twice, where
    /// `Partition::split` puts its halves; the others once.
    #[test]
    fn a_split_repeats_each_split_element_in_place() {
        let k = Coefficients::new(2, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]).unwrap();
        let s = k.split(&[false, true, false]);
        assert_eq!(s.elements(), 4);
        assert_eq!(s.as_slice(), [1.0, 2.0, 3.0, 4.0, 3.0, 4.0, 5.0, 6.0]);
        let all = k.split(&[true; 3]);
        assert_eq!(all.as_slice()[..4], [1.0, 2.0, 1.0, 2.0]);
        assert_eq!(all.elements(), 6);
    }
}
