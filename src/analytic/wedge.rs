//! The Fizeau wedge (docs/PHYSICS.md §5 "Wedge"): a plane wave at normal incidence on a wedge of
//! index n and angle α. The beam reflected at the top face goes straight back; the beam
//! reflected at the tilted bottom face leaves at ψ, sin ψ = n sin 2α, so on any screen plane
//! parallel to the top face the fringe spacing is exactly λ/(n sin 2α) ≈ λ/(2nα).

use super::path_phasor;
use crate::fresnel::fresnel;
use num_complex::Complex64;

/// Exact wedge fringe spacing for plane-wave illumination, λ/(n sin 2α) (m).
pub fn fringe_spacing_exact(lambda_m: f64, n: f64, alpha_rad: f64) -> f64 {
    lambda_m / (n * (2.0 * alpha_rad).sin())
}

/// The textbook small-angle spacing λ/(2nα) (m).
pub fn fringe_spacing_small_angle(lambda_m: f64, n: f64, alpha_rad: f64) -> f64 {
    lambda_m / (2.0 * n * alpha_rad)
}

/// The wedge scene: top face z = 0 between the medium above (index `n1`) and the wedge (`n`),
/// bottom face through (0, 0, −t0) with normal (sin α, 0, cos α) between the wedge and the
/// medium below (`n3`); plane wave along −z with phase 0 at z = h_src; screen points
/// (x, y, h_obs) above the wedge. s-polarized (field along y, the hinge).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wedge {
    pub n1: f64,
    pub n: f64,
    pub n3: f64,
    pub alpha_rad: f64,
    pub t0_m: f64,
    pub h_src_m: f64,
    pub h_obs_m: f64,
}

impl Wedge {
    /// The s amplitude of the top reflection, r12(0).
    fn top(&self) -> Complex64 {
        fresnel(self.n1, self.n, 1.0).r_s
    }

    /// The optical path of the bottom reflection arriving at screen x *minus* that of the top
    /// reflection, and its s amplitude t12 r23 t21 (complex when the bottom face totally
    /// reflects). Inside, the ray reflected at the bottom face travels at 2α; it leaves the top
    /// face at ψ (n1 sin ψ = n sin 2α). Exit point x_e = x − h_obs tan ψ; entry point
    /// x_i = (x_e − t0 tan 2α)/(1 + tan α tan 2α); depth D = t0 + x_i tan α; inside length
    /// D/cos 2α. Op_bottom − Op_top = n D (1 + 1/cos 2α) − n1 h_obs (1/cos ψ − 1), the last
    /// factor written as 2 sin²(ψ/2)/cos ψ so that no digits cancel. `None` when the beam
    /// cannot leave the top face (n sin 2α ≥ n1).
    fn bottom(&self, x_m: f64) -> Option<(f64, Complex64)> {
        let (a, n, n1) = (self.alpha_rad, self.n, self.n1);
        let sin_psi = n * (2.0 * a).sin() / n1;
        if sin_psi >= 1.0 {
            return None;
        }
        let psi = sin_psi.asin();
        let x_e = x_m - self.h_obs_m * psi.tan();
        let x_i = (x_e - self.t0_m * (2.0 * a).tan()) / (1.0 + a.tan() * (2.0 * a).tan());
        let depth = self.t0_m + x_i * a.tan();
        let tilt = 2.0 * (0.5 * psi).sin().powi(2) / psi.cos();
        let delta = n * depth * (1.0 + 1.0 / (2.0 * a).cos()) + n1 * self.h_obs_m * tilt;
        let t12 = fresnel(n1, n, 1.0).t_s;
        let r23 = fresnel(n, self.n3, a.cos()).r_s;
        let t21 = fresnel(n, n1, (2.0 * a).cos()).t_s;
        Some((delta, t12 * r23 * t21))
    }

    /// Two-beam intensity at screen x for unit incident intensity, s polarization (fields
    /// parallel along y): |a1 + a2 e^{iδ}|², δ = 2π (Op_bottom − Op_top)/λ (P10).
    pub fn intensity_s(&self, x_m: f64, lambda_m: f64) -> f64 {
        let a1 = self.top();
        match self.bottom(x_m) {
            Some((delta, a2)) => (a1 + a2 * path_phasor(delta, lambda_m)).norm_sqr(),
            None => a1.norm_sqr(),
        }
    }
}
