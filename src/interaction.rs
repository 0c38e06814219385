//! A ray meets an interface: the reflected and refracted children (paper §3.3–3.5).
//!
//! The parent is advanced to the hit point (adding n·L to its optical path), its 3D field is
//! split into s and p in the frame of PHYSICS.md §1, each component is multiplied by its Fresnel
//! coefficient, and each child carries the frame (X, Y) = (s, p_child), so (X, Y, dir) stays
//! right-handed. Children inherit or lose the coherence id according to the surface's
//! [`CoherenceRules`].

use crate::fresnel::{self, FresnelCoefficients};
use crate::material::CoherenceRules;
use crate::ray::{Field3, INCOHERENT, LedgerEntry, Ray};
use glam::DVec3;
use num_complex::Complex64;

/// Which amplitude coefficients an interaction applies (the two polarized rungs of the
/// fidelity ladder, PHYSICS.md §4).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoefficientModel {
    /// Complex Fresnel (P1)–(P6).
    Vector,
    /// The paper's |r|, |t| with π-jump rules (P7, P8) and its TIR phases.
    PaperRules,
}

/// What is on the two sides of the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceOptics {
    /// An interface between two lossless media; `n_front` on the side the normal points to.
    Dielectric { n_front: f64, n_back: f64 },
    /// A perfectly conducting mirror (reflects from either side, transmits nothing).
    IdealMirror,
    /// An ideal thin beam splitter of power reflectance R in a uniform medium of index `n`.
    Splitter { reflectance: f64, n: f64 },
}

/// The local description of one ray–surface encounter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterfaceHit {
    /// Index of the surface in its scene (for the ledger).
    pub surface: usize,
    /// Where the ray meets the surface (m).
    pub point: DVec3,
    /// Unit normal of the surface, pointing to its front side.
    pub normal: DVec3,
    pub optics: SurfaceOptics,
    pub coherence: CoherenceRules,
}

/// The result of an interaction.
#[derive(Clone, Debug)]
pub struct Children {
    pub reflected: Ray,
    /// `None` under total internal reflection and for mirrors.
    pub refracted: Option<Ray>,
    /// The coefficients that were applied.
    pub coefficients: FresnelCoefficients,
    /// |d_i·N|.
    pub cos_theta_i: f64,
    /// Indices on the incident and the far side.
    pub n1: f64,
    pub n2: f64,
}

fn dot(e: &Field3, v: DVec3) -> Complex64 {
    e[0] * v.x + e[1] * v.y + e[2] * v.z
}

/// The (incident-side, far-side) indices for a ray travelling along `dir` in a medium of index
/// `current` (a mirror has the ray's medium on both sides as far as the ray is concerned).
pub fn indices_for(optics: SurfaceOptics, normal: DVec3, dir: DVec3, current: f64) -> (f64, f64) {
    match optics {
        SurfaceOptics::Dielectric { n_front, n_back } => {
            if dir.dot(normal) < 0.0 {
                (n_front, n_back)
            } else {
                (n_back, n_front)
            }
        }
        SurfaceOptics::IdealMirror => (current, current),
        SurfaceOptics::Splitter { n, .. } => (n, n),
    }
}

fn child(parent: &Ray, dir: DVec3, s: DVec3, jones: [Complex64; 2], index: f64, keep: bool) -> Ray {
    let mut ray = parent.clone();
    ray.dir = dir;
    ray.x = s;
    ray.y = dir.cross(s);
    ray.jones = jones;
    ray.index = index;
    if !keep && ray.coherence_id != INCOHERENT {
        ray.coherence_id = INCOHERENT;
        ray.ledger
            .entries
            .push(LedgerEntry::CoherenceLost { surface: None });
    }
    ray
}

/// Split `ray` at `hit` into its reflected and refracted children using `model`.
pub fn interact(ray: &Ray, hit: &InterfaceHit, model: CoefficientModel) -> Children {
    let mut parent = ray.clone();
    parent.advance_to(hit.point);
    let d_i = parent.dir;
    let cos_theta_i = d_i.dot(hit.normal).abs().min(1.0);

    // Step 1: the s/p frame of the incident ray.
    let s = fresnel::s_direction(d_i, hit.normal, parent.x);
    let p_i = d_i.cross(s);
    let e = parent.field();
    let (a_s, a_p) = (dot(&e, s), dot(&e, p_i));

    // Step 2: the coefficients.
    let (n1, n2) = indices_for(hit.optics, hit.normal, d_i, parent.index);
    let coefficients = match (hit.optics, model) {
        (SurfaceOptics::IdealMirror, _) => fresnel::ideal_mirror(),
        (SurfaceOptics::Splitter { reflectance, .. }, _) => {
            fresnel::ideal_splitter(reflectance, d_i.dot(hit.normal) < 0.0)
        }
        (SurfaceOptics::Dielectric { .. }, CoefficientModel::Vector) => {
            fresnel::fresnel(n1, n2, cos_theta_i)
        }
        (SurfaceOptics::Dielectric { .. }, CoefficientModel::PaperRules) => {
            fresnel::paper_rules(n1, n2, cos_theta_i)
        }
    };
    let c = coefficients;

    // Step 3: the reflected child.
    let d_r = fresnel::reflect(d_i, hit.normal);
    let mut reflected = child(
        &parent,
        d_r,
        s,
        [c.r_s * a_s, c.r_p * a_p],
        n1,
        hit.coherence.reflected_keeps,
    );
    reflected.ledger.entries.push(LedgerEntry::Reflection {
        surface: hit.surface,
        phase_s: c.r_s.arg(),
        phase_p: c.r_p.arg(),
        tir: c.total_internal_reflection,
    });

    // Step 4: the refracted child, unless TIR or a mirror.
    let refracted = match hit.optics {
        SurfaceOptics::IdealMirror => None,
        SurfaceOptics::Dielectric { .. } | SurfaceOptics::Splitter { .. } => {
            fresnel::refract(d_i, hit.normal, n1, n2).map(|d_t| {
                let mut t = child(
                    &parent,
                    d_t,
                    s,
                    [c.t_s * a_s, c.t_p * a_p],
                    n2,
                    hit.coherence.refracted_keeps,
                );
                t.ledger.entries.push(LedgerEntry::Refraction {
                    surface: hit.surface,
                    phase_s: c.t_s.arg(),
                    phase_p: c.t_p.arg(),
                });
                t
            })
        }
    };
    Children {
        reflected,
        refracted,
        coefficients,
        cos_theta_i,
        n1,
        n2,
    }
}
