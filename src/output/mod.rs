//! Outputs: reports (CSV, JSON, HTML, plots), pictures of a case, the paper's figures, and the
//! memory budget of a render.

pub(crate) mod beat_table;
#[doc(hidden)]
pub mod figures;
pub(crate) mod free_kernel;
pub mod memory;
pub mod render;
#[doc(hidden)]
pub mod report;
pub mod stack_kernel;
