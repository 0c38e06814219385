//! Temporal coherence (docs/PHYSICS.md §3): visibility of two-beam fringes against the optical path
//! difference Δs, under the paper's rule (P9) and for a Gaussian spectrum.

/// |γ(Δs)| for a spectrum Gaussian in wavenumber with FWHM Δλ around λ0 (docs/PHYSICS.md §3):
/// exp(−(π Δs Δλ/λ0²)²/(4 ln 2)).
pub fn gaussian_visibility(delta_s_m: f64, lambda0_m: f64, fwhm_m: f64) -> f64 {
    let x = std::f64::consts::PI * delta_s_m * fwhm_m / (lambda0_m * lambda0_m);
    (-(x * x) / (4.0 * std::f64::consts::LN_2)).exp()
}

/// Coherence length commonly associated with the bandwidth, λ0²/Δλ (m).
pub fn coherence_length(lambda0_m: f64, fwhm_m: f64) -> f64 {
    lambda0_m * lambda0_m / fwhm_m
}

/// Two-beam intensity with partial coherence: I1 + I2 + 2√(I1 I2)|γ| cos δ (P10 generalised).
pub fn two_beam(i1: f64, i2: f64, gamma: f64, delta: f64) -> f64 {
    i1 + i2 + 2.0 * (i1 * i2).sqrt() * gamma * delta.cos()
}
