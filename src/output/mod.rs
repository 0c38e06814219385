//! Outputs: reports (CSV, JSON, HTML, plots), pictures of a case, the paper's figures, and the
//! memory budget of a render.

#[doc(hidden)]
pub mod figures;
pub mod memory;
pub(crate) mod beat_table;
pub mod render;
pub mod stack_kernel;
#[doc(hidden)]
pub mod report;
