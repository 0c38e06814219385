//! Outputs: reports (CSV, JSON, HTML, plots), pictures of a case, spectral colour (CIE →
//! sRGB, docs/PHYSICS.md §6), the paper's figures, and the memory budget of a render.

pub mod colour;
#[doc(hidden)]
pub mod figures;
pub(crate) mod memory;
pub mod render;
#[doc(hidden)]
pub mod report;
