//! Helpers shared by several test modules (and, through `#[path]`, by `benches/airy.rs`).

pub mod airy_plate;
pub mod library;
pub mod schema;
