//! The Fizeau wedge (docs/PHYSICS.md §5 "Wedge"): a plane wave at normal incidence on a wedge of
//! index n and angle α. The beam reflected at the top face goes straight back; the beam
//! reflected at the tilted bottom face leaves at ψ, sin ψ = n sin 2α, so on any screen plane
//! parallel to the top face the fringe spacing is exactly λ/(n sin 2α) ≈ λ/(2nα).

use super::path_phasor;
use crate::fresnel::fresnel;

/// Exact wedge fringe spacing for plane-wave illumination, λ/(n sin 2α) (m).
pub fn fringe_spacing_exact(lambda_m: f64, n: f64, alpha_rad: f64) -> f64 {
    lambda_m / (n * (2.0 * alpha_rad).sin())
}

/// The textbook small-angle spacing λ/(2nα) (m).
pub fn fringe_spacing_small_angle(lambda_m: f64, n: f64, alpha_rad: f64) -> f64 {
    lambda_m / (2.0 * n * alpha_rad)
}

/// The wedge scene of the case library: top face z = 0 (index n above = 1), bottom face through
/// (0, 0, −t0) with normal (sin α, 0, cos α), same ambient index 1 below; plane wave along −z
/// with phase 0 at z = h_src; screen points (x, y, h_obs). s-polarized (field along y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wedge {
    pub n: f64,
    pub alpha_rad: f64,
    pub t0_m: f64,
    pub h_src_m: f64,
    pub h_obs_m: f64,
}

impl Wedge {
    /// Optical path and s amplitude of the top reflection at screen x: h_src + h_obs, r12(0).
    fn top(&self) -> (f64, f64) {
        let f = fresnel(1.0, self.n, 1.0);
        (self.h_src_m + self.h_obs_m, f.r_s.re)
    }

    /// Optical path and s amplitude of the bottom reflection arriving at screen x.
    /// Inside, the ray reflected at the bottom face travels at 2α; it leaves the top face at
    /// ψ (sin ψ = n sin 2α). Exit point x_e = x − h tan ψ; entry point
    /// x_i = (x_e − t0 tan 2α)/(1 + tan α tan 2α); depth D = t0 + x_i tan α; inside length
    /// D/cos 2α. Op = h + n D + n D/cos 2α + h/cos ψ.
    fn bottom(&self, x_m: f64) -> (f64, f64) {
        let (a, n) = (self.alpha_rad, self.n);
        let psi = (n * (2.0 * a).sin()).asin();
        let x_e = x_m - self.h_obs_m * psi.tan();
        let x_i = (x_e - self.t0_m * (2.0 * a).tan()) / (1.0 + a.tan() * (2.0 * a).tan());
        let depth = self.t0_m + x_i * a.tan();
        let op = self.h_src_m + n * depth + n * depth / (2.0 * a).cos() + self.h_obs_m / psi.cos();
        let t12 = fresnel(1.0, n, 1.0).t_s.re;
        let r23 = fresnel(n, 1.0, a.cos()).r_s.re;
        let t21 = fresnel(n, 1.0, (2.0 * a).cos()).t_s.re;
        (op, t12 * r23 * t21)
    }

    /// Two-beam intensity at screen x for unit incident intensity, s polarization (fields
    /// parallel along y): |a1 e^{iφ1} + a2 e^{iφ2}|².
    pub fn intensity_s(&self, x_m: f64, lambda_m: f64) -> f64 {
        let ((op1, a1), (op2, a2)) = (self.top(), self.bottom(x_m));
        (a1 * path_phasor(op1 - op2, lambda_m) + a2).norm_sqr()
    }
}
