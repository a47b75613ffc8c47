//! The one set of writers for the library's report model
//! ([`fpc::report`]): every figure as SVG ([`svg`], plotters), and from
//! that SVG as PNG or PDF ([`formats`], `--format`), every table as CSV
//! ([`csv`]), pages as HTML ([`html`]). `fpc paper`, `fpc solve`, `fpc
//! design` and the accuracy study all draw and write through them.

pub mod csv;
pub mod formats;
pub mod html;
pub mod svg;
