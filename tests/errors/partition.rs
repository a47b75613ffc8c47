//! Partition errors.

use super::*;

// ------------------------------------------------------------- partition

#[test]
fn partition_lengths_must_be_finite() {
    // (n = 0, too many, short, negative or NaN lengths and a wrong sum are in
    // tests/actuator_validation.rs)
    names(
        &Partition::equal(f64::NAN, 8).unwrap_err(),
        "partition.lx",
        f64::NAN,
        "must be finite",
    );
    names(
        &Partition::equal(0.0, 8).unwrap_err(),
        "partition.lx",
        0.0,
        "must be positive",
    );
    names(
        &Partition::equal(110.0, usize::MAX).unwrap_err(),
        "partition.n",
        usize::MAX as f64,
        "must lie in [1, 1000]",
    );
    names(
        &Partition::custom(vec![55.0, f64::INFINITY], 110.0).unwrap_err(),
        "partition.lengths[1]",
        f64::INFINITY,
        "must be finite",
    );
    // each length is finite, their sum is not
    names(
        &Partition::custom(vec![f64::MAX, f64::MAX], 110.0).unwrap_err(),
        "partition.lengths (sum)",
        f64::INFINITY,
        "must be finite",
    );
    names(
        &Partition::custom(vec![110.0], f64::INFINITY).unwrap_err(),
        "partition.lx",
        f64::INFINITY,
        "must be finite",
    );
}
