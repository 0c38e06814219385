//! fringe: exact tracing of linearly polarized rays and a verification harness for light
//! interference in scenes of optically isotropic transparent objects.
pub mod accumulate;
pub mod analytic;
pub mod beats;
pub mod case;
pub mod check;
pub mod colour;
pub mod fidelity;
pub mod figures;
pub mod forward;
pub mod forward_study;
pub mod fresnel;
pub mod geometry;
pub mod interaction;
pub mod material;
pub mod memory;
pub mod path;
pub mod ray;
pub mod render;
pub mod report;
pub mod scene;
pub mod sequence_tree;
pub mod source;
pub mod stability;
pub mod trace;
pub mod tradeoff;
pub mod trail;
