//! The Fizeau wedge (docs/PHYSICS.md §5 "Wedge"): a plane wave at normal incidence on a wedge of
//! index n and angle α. The beam reflected at the top face goes straight back; the beam
//! reflected at the tilted bottom face leaves at ψ, sin ψ = n sin 2α, so on any screen plane
//! parallel to the top face the fringe spacing is exactly λ/(n sin 2α) ≈ λ/(2nα).

use super::precise;
use crate::optics::fresnel::{FresnelCoefficients, fresnel, fresnel_with_cos2_t};
use glam::DVec3;
use num_complex::Complex64;
use twofloat::TwoFloat;

/// Exact wedge fringe spacing for plane-wave illumination, λ/(n sin 2α) (m).
pub(crate) fn fringe_spacing_exact(lambda_m: f64, n: f64, alpha_rad: f64) -> f64 {
    lambda_m / (n * (2.0 * alpha_rad).sin())
}

/// The textbook small-angle spacing λ/(2nα) (m).
pub(crate) fn fringe_spacing_small_angle(lambda_m: f64, n: f64, alpha_rad: f64) -> f64 {
    lambda_m / (2.0 * n * alpha_rad)
}

/// The wedge scene as the scene gives it: the top face through `top_point` with normal
/// `top_normal` (pointing up, into the medium `n1` the light comes from), the bottom face through
/// `bottom_point` with normal `bottom_normal` (either orientation; neither normal needs unit
/// length), the wedge of index `n` between them, the medium `n3` below. A plane wave travels
/// along −top_normal; screen points lie above the wedge. s-polarized (field along the hinge,
/// top_normal × bottom_normal).
///
/// Everything is evaluated in double-double ([`super::precise`]) from exact coordinate
/// differences and exact products of the normals' components: the angle α from the cross and
/// dot products of the two normals, the lateral coordinate x and height h_obs of the screen
/// point, and the depth of the bottom face below the top point, so the closed form's own error
/// is ~1e-16 of the intensity for any size, position and orientation of the scene (plain f64
/// lost ~1e-8 in rotated and translated scenes: `tests/suite/closed_form_precision.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wedge {
    /// Index above the wedge (incidence side).
    pub n1: f64,
    /// The wedge's index.
    pub n: f64,
    /// Index below the wedge.
    pub n3: f64,
    /// A point of the top face, m.
    pub top_point: DVec3,
    /// The top face's normal.
    pub top_normal: DVec3,
    /// A point of the bottom face, m.
    pub bottom_point: DVec3,
    /// The bottom face's normal.
    pub bottom_normal: DVec3,
}

/// The wedge's geometry in its own frame, double-double.
struct Frame {
    /// sin α, cos α.
    sin_a: TwoFloat,
    cos_a: TwoFloat,
    /// Depth of the bottom face below the top point, along the top normal (m).
    depth0: TwoFloat,
    /// Screen point: lateral coordinate across the hinge (m, the wedge thickens with x) and
    /// height above the top face (m).
    x: TwoFloat,
    h_obs: TwoFloat,
}

fn dd3(v: DVec3) -> [TwoFloat; 3] {
    [v.x.into(), v.y.into(), v.z.into()]
}

fn exact_dot(a: DVec3, b: DVec3) -> TwoFloat {
    TwoFloat::new_mul(a.x, b.x) + TwoFloat::new_mul(a.y, b.y) + TwoFloat::new_mul(a.z, b.z)
}

/// The Fresnel coefficients from index `n_i` into `n_t` at the angle of incidence whose cosine
/// and sine are `cos_i`, `sin_i` (double-double): cos²θt = 1 − (n_i sin θi/n_t)² from the sine,
/// not from 1 − cos²θi of a rounded cosine. At the wedge's small angles 1 − cos²α is a
/// difference of nearly equal numbers: from the f64 cosine it lost 7e-9 of sin²α, and into a
/// much thinner medium (3 → 0.001, cos²θt = 1 − 9e6 sin²α) it moved r23 by 8e-13 and the
/// intensity by 1.7e-12 of the profile (`fringe fuzz --family wedge --seed 1`, scene 9953,
/// `tests/suite/truth_found_edges.rs`; the tracer carries the normal wavevector in
/// double-double and equals 50 digits there).
fn oblique(n_i: f64, n_t: f64, cos_i: TwoFloat, sin_i: TwoFloat) -> FresnelCoefficients {
    if n_i == n_t {
        return fresnel(n_i, n_t, f64::from(cos_i));
    }
    let s = precise::div(sin_i * n_i, TwoFloat::from(n_t));
    let c2t = TwoFloat::from(1.0) - s * s;
    fresnel_with_cos2_t(n_i, n_t, f64::from(cos_i), f64::from(c2t))
}

impl Wedge {
    fn frame(&self, p: DVec3) -> Frame {
        let nt = self.top_normal;
        let mut nb = self.bottom_normal;
        if exact_dot(nt, nb).hi() < 0.0 {
            nb = -nb;
        }
        let (tt, bb, tb) = (exact_dot(nt, nt), exact_dot(nb, nb), exact_dot(nt, nb));
        let cross = [
            TwoFloat::new_mul(nt.y, nb.z) - TwoFloat::new_mul(nt.z, nb.y),
            TwoFloat::new_mul(nt.z, nb.x) - TwoFloat::new_mul(nt.x, nb.z),
            TwoFloat::new_mul(nt.x, nb.y) - TwoFloat::new_mul(nt.y, nb.x),
        ];
        let cross_len = precise::length(&cross);
        let (t_len, b_len) = (tt.sqrt(), bb.sqrt());
        let sin_a = precise::div(cross_len, t_len * b_len);
        let cos_a = precise::div(tb, t_len * b_len);
        // x̂ = (n_t × n_b) × n_t/|…| = (n_b |n_t|² − n_t (n_t·n_b))/(|n_t × n_b| |n_t|); its
        // product with n̂_b is sin α.
        let x_dir = [0, 1, 2].map(|k| dd3(nb)[k] * tt - dd3(nt)[k] * tb);
        let x_len = cross_len * t_len;
        let rel = precise::diff(p, self.top_point);
        let x = if x_len.hi() > 0.0 {
            precise::div(
                rel[0] * x_dir[0] + rel[1] * x_dir[1] + rel[2] * x_dir[2],
                x_len,
            )
        } else {
            TwoFloat::from(0.0)
        };
        let h_obs = precise::div(precise::dot(&rel, nt), t_len);
        let depth0 = precise::div(
            precise::dot(&precise::diff(self.top_point, self.bottom_point), nb),
            b_len * cos_a,
        );
        Frame {
            sin_a,
            cos_a,
            depth0,
            x,
            h_obs,
        }
    }

    /// The wedge angle α (rad).
    pub fn alpha(&self) -> f64 {
        let f = self.frame(self.top_point);
        f.sin_a.hi().atan2(f.cos_a.hi())
    }

    /// The s amplitude of the top reflection, r12(0).
    fn top(&self) -> Complex64 {
        fresnel(self.n1, self.n, 1.0).r_s
    }

    /// The optical path of the bottom reflection arriving at screen point `p` *minus* that of
    /// the top reflection (m, double-double), and its s amplitude t12 r23 t21 (complex when the
    /// bottom face totally reflects). Inside, the ray reflected at the bottom face travels at
    /// 2α; it leaves the top face at ψ (n1 sin ψ = n sin 2α). Exit point x_e = x − h_obs tan ψ;
    /// entry point x_i = (x_e − D0 tan 2α)/(1 + tan α tan 2α); depth D = D0 + x_i tan α;
    /// inside length D/cos 2α. Op_bottom − Op_top = n D (1 + 1/cos 2α) + n1 h_obs (1/cos ψ − 1),
    /// the last factor written as sin²ψ/(cos ψ (1 + cos ψ)) so that no digits cancel. `None`
    /// when the beam cannot leave the top face (n sin 2α ≥ n1).
    fn bottom(&self, p: DVec3) -> Option<(TwoFloat, Complex64)> {
        let (n, n1) = (self.n, self.n1);
        let f = self.frame(p);
        let one = TwoFloat::from(1.0);
        let sin_2a = f.sin_a * f.cos_a * 2.0;
        let cos_2a = f.cos_a * f.cos_a - f.sin_a * f.sin_a;
        let sin_psi = precise::div(sin_2a * n, TwoFloat::from(n1));
        if sin_psi.hi() >= 1.0 {
            return None;
        }
        let cos_psi = (one - sin_psi * sin_psi).sqrt();
        let tan_a = precise::div(f.sin_a, f.cos_a);
        let tan_2a = precise::div(sin_2a, cos_2a);
        let x_e = f.x - f.h_obs * precise::div(sin_psi, cos_psi);
        let x_i = precise::div(x_e - f.depth0 * tan_2a, one + tan_a * tan_2a);
        let depth = f.depth0 + x_i * tan_a;
        let tilt = precise::div(sin_psi * sin_psi, cos_psi * (one + cos_psi));
        let delta = depth * n * (one + precise::div(one, cos_2a)) + f.h_obs * tilt * n1;
        let t12 = fresnel(n1, n, 1.0).t_s;
        let r23 = oblique(n, self.n3, f.cos_a, f.sin_a).r_s;
        let t21 = oblique(n, n1, cos_2a, sin_2a).t_s;
        Some((delta, t12 * r23 * t21))
    }

    /// Two-beam intensity at screen point `p` for unit incident intensity, s polarization
    /// (fields parallel along the hinge): |a1 + a2 e^{iδ}|², δ = 2π (Op_bottom − Op_top)/λ (P10).
    pub fn intensity_s(&self, p: DVec3, lambda_m: f64) -> f64 {
        let a1 = self.top();
        match self.bottom(p) {
            Some((delta, a2)) => (a1 + a2 * precise::path_phasor(delta, lambda_m)).norm_sqr(),
            None => a1.norm_sqr(),
        }
    }
}
