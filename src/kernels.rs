//! Element kernels generated at build time from `energy-spec/ccm.spec`.
//!
//! Each integral kernel comes as four functions: `*_moments` accumulates a
//! block's parameter moments (once per scene), and `*_value`,
//! `*_gradient`, `*_hessian` evaluate the summed blocks at the unknowns
//! `k = [a1, a3, b1, c2]`. Hessians are the upper triangle, row by row.
//! `end_value` / `end_hessian` give the element end `(Xe, Ze, eta)` and its
//! derivatives. [`SOURCE`] is the generated text and [`REPORT`] the
//! operation counts before and after common-subexpression binding.
#![allow(
    non_snake_case,
    clippy::too_many_arguments,
    clippy::excessive_precision,
    clippy::unreadable_literal,
    clippy::neg_multiply,
    clippy::double_parens,
    clippy::let_and_return,
    clippy::redundant_locals,
    clippy::needless_return
)]

include!(concat!(env!("OUT_DIR"), "/kernels.rs"));

/// The generated Rust source, as compiled.
pub const SOURCE: &str = include_str!(concat!(env!("OUT_DIR"), "/kernels.rs"));

/// Operation counts of every generated function, before and after CSE.
pub const REPORT: &str = include_str!(concat!(env!("OUT_DIR"), "/kernels_report.txt"));

/// Index of Hessian entry `(i, j)` in the upper-triangle layout for `n` unknowns.
pub const fn upper_index(i: usize, j: usize) -> usize {
    let (i, j) = if i <= j { (i, j) } else { (j, i) };
    i * UNKNOWNS - i * (i + 1) / 2 + j
}
