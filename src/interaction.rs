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

/// The parent ray at the hit point, split into s and p, with the coefficients of `model`.
struct Split {
    d_i: DVec3,
    /// The s unit vector (PHYSICS.md §1).
    s: DVec3,
    /// The parent's field components along s and p_i.
    a_s: Complex64,
    a_p: Complex64,
    n1: f64,
    n2: f64,
    cos_theta_i: f64,
    coefficients: FresnelCoefficients,
}

/// Advances `parent` to the hit point and splits its field.
fn split(parent: &mut Ray, hit: &InterfaceHit, model: CoefficientModel) -> Split {
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
    Split {
        d_i,
        s,
        a_s,
        a_p,
        n1,
        n2,
        cos_theta_i,
        coefficients,
    }
}

/// A child of the split parent: direction `dir`, frame (s, dir × s), Jones (c_s a_s, c_p a_p).
fn child(
    mut ray: Ray,
    sp: &Split,
    dir: DVec3,
    c: [Complex64; 2],
    index: f64,
    keep: bool,
    entry: LedgerEntry,
) -> Ray {
    ray.dir = dir;
    ray.x = sp.s;
    ray.y = dir.cross(sp.s);
    ray.jones = [c[0] * sp.a_s, c[1] * sp.a_p];
    ray.index = index;
    if !keep && ray.coherence_id != INCOHERENT {
        ray.coherence_id = INCOHERENT;
        ray.ledger
            .entries
            .push(LedgerEntry::CoherenceLost { surface: None });
    }
    ray.ledger.entries.push(entry);
    ray
}

/// Step 3: the reflected child.
fn reflected(ray: Ray, sp: &Split, hit: &InterfaceHit) -> Ray {
    let c = &sp.coefficients;
    let entry = LedgerEntry::Reflection {
        surface: hit.surface,
        r_s: c.r_s,
        r_p: c.r_p,
        tir: c.total_internal_reflection,
    };
    let d_r = fresnel::reflect(sp.d_i, hit.normal);
    let keep = hit.coherence.reflected_keeps;
    child(ray, sp, d_r, [c.r_s, c.r_p], sp.n1, keep, entry)
}

/// Step 4: the refracted child, unless TIR or a mirror.
fn refracted(ray: Ray, sp: &Split, hit: &InterfaceHit) -> Option<Ray> {
    if matches!(hit.optics, SurfaceOptics::IdealMirror) {
        return None;
    }
    let d_t = fresnel::refract(sp.d_i, hit.normal, sp.n1, sp.n2)?;
    let c = &sp.coefficients;
    let entry = LedgerEntry::Refraction {
        surface: hit.surface,
        t_s: c.t_s,
        t_p: c.t_p,
    };
    let keep = hit.coherence.refracted_keeps;
    Some(child(ray, sp, d_t, [c.t_s, c.t_p], sp.n2, keep, entry))
}

/// Split `ray` at `hit` into its reflected and refracted children using `model`.
pub fn interact(ray: &Ray, hit: &InterfaceHit, model: CoefficientModel) -> Children {
    let mut parent = ray.clone();
    let sp = split(&mut parent, hit, model);
    Children {
        refracted: refracted(parent.clone(), &sp, hit),
        reflected: reflected(parent, &sp, hit),
        coefficients: sp.coefficients,
        cos_theta_i: sp.cos_theta_i,
        n1: sp.n1,
        n2: sp.n2,
    }
}

/// The one child of `ray` at `hit` that a path follows (`reflect`: the reflected one, else the
/// refracted one, `None` under TIR or at a mirror): the same ray [`interact`] returns, without
/// building the other child.
pub fn interact_along(
    mut ray: Ray,
    hit: &InterfaceHit,
    model: CoefficientModel,
    reflect: bool,
) -> Option<Ray> {
    let sp = split(&mut ray, hit, model);
    if reflect {
        Some(reflected(ray, &sp, hit))
    } else {
        refracted(ray, &sp, hit)
    }
}
