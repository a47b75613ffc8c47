//! An element's integration blocks (`fpc::actuator::element_blocks`, the
//! library's own, docs/model.md sections 4.3 and 4.4) folded into a
//! model's moments, for the benchmarks that time one element's kernels.

#![allow(dead_code)] // each bench uses part of this

use fpc::actuator::ElementBlocks;
use fpc::model::ElementModel;

/// The element's blocks folded into model `M`'s moments.
pub fn moments<M: ElementModel>(b: &ElementBlocks) -> M::Moments {
    let mut m = M::zero_moments();
    for p in &b.linear {
        M::add_linear(&mut m, p);
    }
    for p in &b.prestressed {
        M::add_prestressed(&mut m, p);
    }
    for p in &b.gas {
        M::add_gas(&mut m, p);
    }
    m
}
