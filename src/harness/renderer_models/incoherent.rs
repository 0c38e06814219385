//! The incoherent thin plate: multiple reflections inside the layer summed in **power**, with
//! no phase, as pbrt-v4 and Mitsuba 3 ship it for thin dielectric sheets.
//!
//! Summing the powers of the reflected orders of a layer n1 | n2 | n3 (B&W §7.6.1 with the
//! cross terms dropped) gives the geometric series
//!
//! ```text
//! R' = R12 + T12 R23 T21 Σ_k (R21 R23)^k = R12 + T12² R23/(1 − R12 R23)        (I1)
//! ```
//!
//! with R21 = R12 and T21 = T12 = 1 − R12 (lossless interface, reciprocity). For a free-standing
//! sheet (n3 = n1, so R23 = R12 = R) this is pbrt-v4's `ThinDielectricBxDF`
//! (M. Pharr, W. Jakob, G. Humphreys, *Physically Based Rendering*, 4th ed., §9.5.1 "Thin
//! Dielectric BSDF": `R += Sqr(T) * R / (1 - Sqr(R))`) and Mitsuba 3's `thindielectric` plugin
//! (`src/bsdfs/thindielectric.cpp`: `r += t * t * r / (1 - r * r)`), both applied to the
//! polarization-**averaged** Fresnel reflectance R = ½(R_s + R_p) of P1/P2. On a substrate
//! (n3 ≠ n1) neither renderer ships a model; (I1) with both interfaces' averaged reflectances
//! is the direct generalization and is what [`averaged`] evaluates.
//!
//! [`per_polarization`] applies (I1) to s and p separately and then averages: the physically
//! right incoherent limit (orders of one polarization add in power, and s and p do not mix in a
//! plane-parallel layer), so the difference between the two isolates the cost of averaging
//! before summing, and the difference to the exact Airy sum the cost of dropping the phase.
//! Neither depends on the wavelength or the thickness (constant indices).

use super::Film;
use crate::optics::fresnel::{cos2_theta_t, fresnel};

/// The power reflectances (R12, R23) for s and p at incidence cos θ1 on the stack: R12 from
/// n1 → n2, R23 from n2 → n3 at the refraction angle in the film (P1, P2; R23 = 1 under total
/// internal reflection at the back face). Returns `None` when the wave cannot enter the film
/// (total internal reflection at the front face).
fn interface_reflectances(film: &Film, cos_theta_1: f64) -> Option<([f64; 2], [f64; 2])> {
    let c2 = cos2_theta_t(film.n1, film.n2, cos_theta_1);
    if c2 < 0.0 {
        return None;
    }
    let f12 = fresnel(film.n1, film.n2, cos_theta_1).power(film.n1, film.n2, cos_theta_1);
    let cos_theta_2 = c2.sqrt();
    let f23 = fresnel(film.n2, film.n3, cos_theta_2);
    Some(([f12.r_s, f12.r_p], [f23.r_s.norm_sqr(), f23.r_p.norm_sqr()]))
}

/// (I1): the incoherent sum of all orders for interface reflectances R12, R23 (each in [0, 1]).
/// R12 = 1 or R23 = 1 reflect everything: R' = 1 (the limit of (I1)).
pub fn incoherent_sum(r12: f64, r23: f64) -> f64 {
    if r12 >= 1.0 || r23 >= 1.0 {
        return 1.0;
    }
    let t12 = 1.0 - r12;
    r12 + t12 * t12 * r23 / (1.0 - r12 * r23)
}

/// pbrt-v4 `ThinDielectricBxDF` / Mitsuba 3 `thindielectric`: (I1) on the polarization-averaged
/// reflectances, R' for unpolarized light (dimensionless; 1 under TIR at the front face).
pub fn averaged(film: &Film, cos_theta_1: f64) -> f64 {
    let Some((r12, r23)) = interface_reflectances(film, cos_theta_1) else {
        return 1.0;
    };
    incoherent_sum(0.5 * (r12[0] + r12[1]), 0.5 * (r23[0] + r23[1]))
}

/// (I1) for s and for p, then averaged: the incoherent plate per polarization (dimensionless).
pub fn per_polarization(film: &Film, cos_theta_1: f64) -> f64 {
    let Some((r12, r23)) = interface_reflectances(film, cos_theta_1) else {
        return 1.0;
    };
    0.5 * (incoherent_sum(r12[0], r23[0]) + incoherent_sum(r12[1], r23[1]))
}
