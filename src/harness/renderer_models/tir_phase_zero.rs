//! The Airy sum with the phase of total internal reflection dropped: a simplification seen in
//! production thin-film code, which takes the phase of a reflection as 0 or π from the sign of
//! the real Fresnel coefficient and, under total internal reflection at the film's back face,
//! keeps |r23| = 1 with no phase.
//!
//! The exact amplitude is the Airy sum of docs/PHYSICS.md §5,
//! r = r12 + t12 t21 r23 e^{iβ}/(1 − r21 r23 e^{iβ}), with r23 of (P5)/(P6) under TIR; this
//! variant replaces r23 by |r23| = 1 when the 2→3 face totally reflects and is exact otherwise.
//! Under TIR at the back face no power leaves through it, so |r| = 1 for any phase of r23: the
//! reflectance R is unchanged, and the dropped phase shows only in the phase of the reflected
//! wave and so in the retardance arg r_p − arg r_s (its polarization state), which
//! [`retardance`] returns.

use super::{Film, Pol};
use num_complex::Complex64;

/// Reflection amplitude of the variant for one polarization at vacuum wavelength `lambda_m`
/// (m), in the s/p frame of `src/optics/fresnel.rs`.
pub fn r(film: &Film, cos_theta_1: f64, lambda_m: f64, pol: Pol) -> Complex64 {
    let a = film.terms(cos_theta_1, lambda_m, pol);
    let c2 = crate::optics::fresnel::cos2_theta_t(film.n1, film.n2, cos_theta_1).max(0.0);
    let back_face_tir = crate::optics::fresnel::cos2_theta_t(film.n2, film.n3, c2.sqrt()) < 0.0;
    let r23 = if back_face_tir {
        Complex64::from(a.r23.norm())
    } else {
        a.r23
    };
    let e = Complex64::from_polar(1.0, a.beta);
    a.r12 + a.t12 * a.t21 * r23 * e / (1.0 - a.r21 * r23 * e)
}

/// Unpolarized reflectance ½(|r_s|² + |r_p|²) of the variant (dimensionless).
pub fn reflectance(film: &Film, cos_theta_1: f64, lambda_m: f64) -> f64 {
    0.5 * (r(film, cos_theta_1, lambda_m, Pol::S).norm_sqr()
        + r(film, cos_theta_1, lambda_m, Pol::P).norm_sqr())
}

/// Retardance arg r_p − arg r_s of the reflected wave, wrapped to (−π, π] (rad).
pub fn retardance(film: &Film, cos_theta_1: f64, lambda_m: f64) -> f64 {
    wrap(
        r(film, cos_theta_1, lambda_m, Pol::P).arg() - r(film, cos_theta_1, lambda_m, Pol::S).arg(),
    )
}

/// The exact retardance arg r_p − arg r_s of the Airy sum, wrapped to (−π, π] (rad).
pub fn exact_retardance(film: &Film, cos_theta_1: f64, lambda_m: f64) -> f64 {
    wrap(film.r(cos_theta_1, lambda_m, Pol::P).arg() - film.r(cos_theta_1, lambda_m, Pol::S).arg())
}

/// An angle wrapped to (−π, π].
pub fn wrap(x: f64) -> f64 {
    let y = x.rem_euclid(2.0 * std::f64::consts::PI);
    if y > std::f64::consts::PI {
        y - 2.0 * std::f64::consts::PI
    } else {
        y
    }
}
