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
