//! How a finger's length is split into elements ([`Partition`];
//! docs/model.md section 4.3). The partition on the actuator's material
//! changes, [`Partition::material`], is built in src/actuator/blocks.rs,
//! next to the boxes it aligns the elements with.

use crate::error::{finite, positive, require, InputError};
use crate::field::Field;

/// Shortest element allowed, as a fraction of the finger's length.
pub const MIN_ELEMENT_FRACTION: f64 = 1e-3;

/// Relative tolerance on the sum of custom element lengths.
pub const LENGTH_SUM_TOLERANCE: f64 = 1e-9;

/// How the finger's length is split into elements.
#[derive(Debug, Clone, PartialEq)]
pub struct Partition {
    lengths: Vec<f64>,
    starts: Vec<f64>,
}

impl Partition {
    /// `n` equal elements of length `lx / n`; `n` at most
    /// 1 / [`MIN_ELEMENT_FRACTION`].
    pub fn equal(lx: f64, n: usize) -> Result<Partition, InputError> {
        positive(Field::PartitionLx, lx)?;
        let max = (1.0 / MIN_ELEMENT_FRACTION).round();
        require(
            n >= 1 && n as f64 <= max,
            Field::PartitionN,
            n as f64,
            || {
                format!(
                    "must lie in [1, {max}] (each element at least {MIN_ELEMENT_FRACTION} lx long)"
                )
            },
        )?;
        Ok(Partition::from_lengths(vec![lx / n as f64; n]))
    }

    /// Elements of the given lengths, in order from the root. Each must be
    /// finite and at least [`MIN_ELEMENT_FRACTION`] `lx` long, and they must
    /// add up to `lx` within [`LENGTH_SUM_TOLERANCE`] `lx`.
    pub fn custom(lengths: Vec<f64>, lx: f64) -> Result<Partition, InputError> {
        positive(Field::PartitionLx, lx)?;
        if lengths.is_empty() {
            return Err(InputError::Inconsistent {
                field: Field::PartitionLengths,
                rule: "needs at least one element".into(),
            });
        }
        let min = MIN_ELEMENT_FRACTION * lx;
        for (i, &l) in lengths.iter().enumerate() {
            positive(Field::PartitionLength(i), l)?;
            require(l >= min, Field::PartitionLength(i), l, || {
                format!("must be at least {MIN_ELEMENT_FRACTION} lx = {min}")
            })?;
        }
        let sum: f64 = lengths.iter().sum();
        finite(Field::PartitionLengthsSum, sum)?;
        if (sum - lx).abs() > LENGTH_SUM_TOLERANCE * lx {
            return Err(InputError::Inconsistent {
                field: Field::PartitionLengths,
                rule: format!("the lengths add up to {sum}, not to lx = {lx}"),
            });
        }
        Ok(Partition::from_lengths(lengths))
    }

    /// Every element halved (twice the elements, nested in this partition).
    pub fn halved(&self) -> Partition {
        self.split(&vec![true; self.len()])
    }

    /// Splits the elements whose index `split` marks into two halves.
    pub fn split(&self, split: &[bool]) -> Partition {
        let mut lengths = Vec::with_capacity(self.len() + split.len());
        for (i, &l) in self.lengths.iter().enumerate() {
            if split.get(i).copied().unwrap_or(false) {
                lengths.push(0.5 * l);
                lengths.push(0.5 * l);
            } else {
                lengths.push(l);
            }
        }
        Partition::from_lengths(lengths)
    }

    fn from_lengths(lengths: Vec<f64>) -> Partition {
        let mut starts = Vec::with_capacity(lengths.len());
        let mut s = 0.0;
        for &l in &lengths {
            starts.push(s);
            s += l;
        }
        Partition { lengths, starts }
    }

    /// Undeformed element lengths L_i, root to tip.
    pub fn lengths(&self) -> &[f64] {
        &self.lengths
    }

    /// X_ref of each element's root: S_i = L_1 + ... + L_{i-1}.
    pub fn starts(&self) -> &[f64] {
        &self.starts
    }

    /// Number of elements N.
    pub fn len(&self) -> usize {
        self.lengths.len()
    }

    /// Always false: a partition has at least one element.
    pub fn is_empty(&self) -> bool {
        self.lengths.is_empty()
    }
}
