//! Young's two-slit experiment (paper §4.1, eq. 4; docs/PHYSICS.md §5 "Young").
//!
//! Two coherent line sources (slits) parallel to the z axis at (0, ±d/2); screen at x = l.
//! The exact distances are the perpendicular distances to the slit axes,
//! `r_{1,2} = sqrt(l² + (y ∓ d/2)²)` (cylindrical waves, spreading off as in the paper).

use glam::DVec3;

/// Exact intensity for two unit-intensity coherent line sources along unit `axis` through
/// `s1`, `s2`, at the point `p`, wavelength `lambda_m`, for an unpolarized source whose channel
/// reference is the slit axis: the channel polarized along the axis has parallel fields,
/// `I = 2 + 2 cos δ`; the in-plane channel has fields at the angle α between the two rays,
/// `I = 2 + 2 cos α cos δ`. Unpolarized: `I = 2 + (1 + cos α) cos δ`, δ = 2π(r1 − r2)/λ (P10).
/// `axis_fraction` is the intensity fraction in the axis-polarized channel (1 for linear
/// polarization along the axis, 1/2 for unpolarized).
pub fn exact_line_sources(
    s1: DVec3,
    s2: DVec3,
    axis: DVec3,
    p: DVec3,
    lambda_m: f64,
    axis_fraction: f64,
) -> f64 {
    let a = axis.normalize();
    let perp = |s: DVec3| {
        let v = p - s;
        v - v.dot(a) * a
    };
    let (v1, v2) = (perp(s1), perp(s2));
    let (r1, r2) = (v1.length(), v2.length());
    let cos_delta = super::path_phasor(r1 - r2, lambda_m).re;
    let cos_alpha = v1.dot(v2) / (r1 * r2);
    axis_fraction * (2.0 + 2.0 * cos_delta)
        + (1.0 - axis_fraction) * (2.0 + 2.0 * cos_alpha * cos_delta)
}

/// Paraxial Young intensity `2(1 + cos(2π d y/(λ l)))` (paper eq. 4 with δ ≈ 2π d y/(λ l)).
pub fn paraxial(d_m: f64, l_m: f64, y_m: f64, lambda_m: f64) -> f64 {
    2.0 * (1.0 + (std::f64::consts::TAU * d_m * y_m / (lambda_m * l_m)).cos())
}

/// Paraxial fringe spacing λ l/d (m).
pub fn fringe_spacing_paraxial(d_m: f64, l_m: f64, lambda_m: f64) -> f64 {
    lambda_m * l_m / d_m
}

/// Exact local fringe spacing on the axis (y = 0): 2π/|dδ/dy| = λ sqrt(l² + d²/4)/d.
pub fn fringe_spacing_exact_on_axis(d_m: f64, l_m: f64, lambda_m: f64) -> f64 {
    lambda_m * (l_m * l_m + 0.25 * d_m * d_m).sqrt() / d_m
}
