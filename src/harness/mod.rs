//! The verification harness: case files and their validation, the closed forms they are
//! compared with, the gate (`fringe check`), the stability sweep, fuzzing, grading of another
//! tracer's values, and the cost studies (docs/PHYSICS.md §5, §8, §9).

pub mod analytic;
pub mod case;
#[doc(hidden)]
pub mod check;
pub mod conditioning;
#[doc(hidden)]
pub mod forward_study;
#[doc(hidden)]
pub mod fuzz;
#[doc(hidden)]
pub mod grade;
#[doc(hidden)]
pub mod renderer_models;
#[doc(hidden)]
pub mod stability;
#[doc(hidden)]
pub mod tradeoff;
#[doc(hidden)]
pub mod verdict;
