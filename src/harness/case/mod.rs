//! The case library: file format ([`spec`]), loading and validation ([`load`]), building tracer
//! objects ([`build`]), closed-form references ([`reference`](mod@reference)) and running a case ([`run`]).
pub mod build;
pub mod detection;
pub mod load;
pub mod reference;
pub mod run;
pub mod schema;
pub mod spec;
