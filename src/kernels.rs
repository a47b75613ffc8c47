//! Generated kernels (placeholder).
