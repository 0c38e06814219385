//! Total internal reflection: the Fresnel rhomb (docs/PHYSICS.md §5) and a TIR beam interfering with
//! a beam of another path.
//!
//! Under TIR |r_s| = |r_p| = 1 with arg r_s (P5) and arg r_p (P6); the relative phase
//! Δ = arg r_p − arg r_s obeys tan(|Δ|/2) = cos θ sqrt(sin²θ − n21²)/sin²θ.

use crate::fresnel::fresnel;

/// arg r_s under TIR (P5), radians: −2 atan(sqrt(sin²θ − n21²)/cos θ).
pub fn phase_s(n1: f64, n2: f64, theta: f64) -> f64 {
    let n21 = n2 / n1;
    -2.0 * ((theta.sin().powi(2) - n21 * n21).sqrt() / theta.cos()).atan()
}

/// arg r_p under TIR (P6), radians: −2 atan(sqrt(sin²θ − n21²)/(n21² cos θ)).
pub fn phase_p(n1: f64, n2: f64, theta: f64) -> f64 {
    let n21 = n2 / n1;
    -2.0 * ((theta.sin().powi(2) - n21 * n21).sqrt() / (n21 * n21 * theta.cos())).atan()
}

/// The convention-free retardance of one TIR: |Δ| = 2 atan(cos θ sqrt(sin²θ − n21²)/sin²θ).
pub fn retardance_magnitude(n1: f64, n2: f64, theta: f64) -> f64 {
    let n21 = n2 / n1;
    let s2 = theta.sin().powi(2);
    2.0 * (theta.cos() * (s2 - n21 * n21).sqrt() / s2).atan()
}

/// Retardance of `k` identical TIRs in one plane of incidence, glass of index `n_glass` against
/// a medium of index `n_out` < n_glass sin θ, arg(p) − arg(s) of the output (radians,
/// e^{-iωt}): k (P6 − P5). Normal-incidence entry and exit faces add no retardance (t_s = t_p
/// there).
pub fn rhomb_retardance(n_glass: f64, n_out: f64, theta: f64, k: usize) -> f64 {
    k as f64 * (phase_p(n_glass, n_out, theta) - phase_s(n_glass, n_out, theta))
}

/// Output of a rhomb in air (n = 1) for 45° linear input (equal s and p): the normalised
/// Stokes V/I = sin(retardance) (±1: circular).
pub fn rhomb_circularity(n_glass: f64, theta: f64, k: usize) -> f64 {
    rhomb_retardance(n_glass, 1.0, theta, k).sin()
}

/// Amplitude factors (s, p) through a TIR prism: normal-incidence entry (t12), one TIR at θ,
/// normal-incidence exit (t21). Complex, in the crate's frame.
pub fn prism_amplitudes(
    n_glass: f64,
    theta: f64,
) -> (num_complex::Complex64, num_complex::Complex64) {
    let t_in = fresnel(1.0, n_glass, 1.0);
    let tir = fresnel(n_glass, 1.0, theta.cos());
    let t_out = fresnel(n_glass, 1.0, 1.0);
    (
        t_in.t_s * tir.r_s * t_out.t_s,
        t_in.t_p * tir.r_p * t_out.t_p,
    )
}
