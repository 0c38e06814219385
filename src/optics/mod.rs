//! Optics kernels: the Fresnel coefficients, media and dispersion, the linearly polarized
//! ray and its ledger, a ray meeting an interface, the observables, and double-double optical
//! paths (docs/PHYSICS.md §1–§3a). Pure functions of their inputs; nothing here knows a scene.

pub mod double_double;
pub mod fresnel;
pub mod interaction;
pub mod material;
pub mod observable;
pub mod ray;
pub mod trail;
