//! Lloyd's mirror (docs/PHYSICS.md §5): a line source parallel to a dielectric mirror, polarized
//! along its axis (pure s at every reflection), interfering with its reflection. With (P1)
//! the reflected wave is r_s(θ) < 0 times the image source's wave, so the fringe at the mirror
//! plane is dark as θ → 90°; visibility V = 2|r_s|/(1 + |r_s|²).
//!
//! The geometry is evaluated from the scene's own coordinates in double-double
//! ([`super::precise`]): heights above the mirror and the distances to the source and to its
//! image come from exact coordinate differences, the image is formed with the mirror normal
//! normalized in double-double, and the path difference is reduced to a fraction of a cycle
//! before it is rounded, so the closed form's own error is ~1e-16 of the intensity whatever the
//! scene's size, position or orientation (plain f64 lost up to ~1e-7 on a 10 m screen:
//! `tests/suite/closed_form_precision.rs`).

use super::precise;
use crate::optics::fresnel::fresnel;
use glam::DVec3;
use twofloat::TwoFloat;

/// A Lloyd scene: line source through `source` along `axis`, mirror plane through
/// `mirror_point` with normal `normal` (either orientation; neither needs unit length), the
/// source's side of index `n1`, the mirror's bulk of index `n2`. The axis must be parallel to
/// the mirror (it is s polarization at every reflection).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lloyd {
    /// Index on the source's side.
    pub n1: f64,
    /// Index of the mirror's bulk.
    pub n2: f64,
    /// A point of the line source, m.
    pub source: DVec3,
    /// The line source's direction (parallel to the mirror).
    pub axis: DVec3,
    /// A point of the mirror plane, m.
    pub mirror_point: DVec3,
    /// The mirror's normal (either orientation, any length).
    pub normal: DVec3,
}

/// The quantities of one screen point, in double-double where digits matter.
struct Rays {
    /// Image path minus direct path (geometric, m).
    image_minus_direct: TwoFloat,
    /// cos θ of the reflected ray at the mirror (θ from the normal).
    cos_theta: f64,
}

impl Lloyd {
    /// Heights of the source and of `p` above the mirror (m, positive on the source's side),
    /// and the unit normal on the source's side (double-double components).
    fn rays(&self, p: DVec3) -> Rays {
        let nn = precise::dot(
            &[
                TwoFloat::from(self.normal.x),
                TwoFloat::from(self.normal.y),
                TwoFloat::from(self.normal.z),
            ],
            self.normal,
        );
        let norm = nn.sqrt();
        let mut h_s = precise::div(
            precise::dot(&precise::diff(self.source, self.mirror_point), self.normal),
            norm,
        );
        let mut h_p = precise::div(
            precise::dot(&precise::diff(p, self.mirror_point), self.normal),
            norm,
        );
        let sign = if h_s.hi() < 0.0 { -1.0 } else { 1.0 };
        h_s *= sign;
        h_p *= sign;
        // Direct ray p − s and image ray p − s', s' = s − 2 h_s n̂, both perpendicular to the
        // axis (their along-axis parts are equal and drop out of the perpendicular lengths).
        let v = precise::diff(p, self.source);
        let two_h = precise::div(h_s * (2.0 * sign), norm);
        let w = [
            v[0] + two_h * self.normal.x,
            v[1] + two_h * self.normal.y,
            v[2] + two_h * self.normal.z,
        ];
        let r_d = perpendicular_length(&v, self.axis);
        let r_i = perpendicular_length(&w, self.axis);
        Rays {
            image_minus_direct: r_i - r_d,
            cos_theta: f64::from(precise::div(h_s + h_p, r_i)),
        }
    }

    /// Angle of incidence at the mirror (rad) of the reflected ray reaching `p`.
    pub fn theta(&self, p: DVec3) -> f64 {
        self.rays(p).cos_theta.clamp(-1.0, 1.0).acos()
    }

    /// I = |e^{iφ_d} + r_s e^{iφ_r}|² at `p` for a unit-intensity s-polarized line source at
    /// vacuum wavelength `lambda_m`, spreading off (docs/PHYSICS.md §5 "Lloyd", P1, P10):
    /// φ_r − φ_d = 2π n1 (r_image − r_direct)/λ.
    pub fn intensity(&self, p: DVec3, lambda_m: f64) -> f64 {
        let rays = self.rays(p);
        let rs = fresnel(self.n1, self.n2, rays.cos_theta).r_s;
        (precise::path_phasor(rays.image_minus_direct * self.n1, lambda_m) * rs + 1.0).norm_sqr()
    }

    /// Fringe visibility 2|r_s|/(1 + |r_s|²) at `p`.
    pub fn visibility(&self, p: DVec3) -> f64 {
        let r = fresnel(self.n1, self.n2, self.rays(p).cos_theta).r_s.norm();
        2.0 * r / (1.0 + r * r)
    }
}

/// The length of the part of `v` perpendicular to `axis` (any length):
/// sqrt(|v|² − (v·a)²/|a|²), in double-double.
fn perpendicular_length(v: &[TwoFloat; 3], axis: DVec3) -> TwoFloat {
    let va = precise::dot(v, axis);
    let aa = TwoFloat::new_mul(axis.x, axis.x)
        + TwoFloat::new_mul(axis.y, axis.y)
        + TwoFloat::new_mul(axis.z, axis.z);
    let vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    (vv - precise::div(va * va, aa)).sqrt()
}
