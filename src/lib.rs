//! fringe: exact tracing of linearly polarized rays and a verification harness for light
//! interference in scenes of optically isotropic transparent objects.
pub mod fresnel;
pub mod geometry;
pub mod interaction;
pub mod material;
pub mod path;
pub mod ray;
pub mod scene;
pub mod source;
pub mod accumulate;
pub mod fidelity;
pub mod trace;
pub mod colour;
pub mod analytic;
