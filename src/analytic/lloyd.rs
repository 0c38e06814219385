//! Lloyd's mirror (docs/PHYSICS.md §5): a line source parallel to a dielectric mirror, polarized
//! along its axis (pure s at every reflection), interfering with its reflection. With (P1)
//! the reflected wave is r_s(θ) < 0 times the image source's wave, so the fringe at the mirror
//! plane is dark as θ → 90°; visibility V = 2|r_s|/(1 + |r_s|²).

use super::path_phasor;
use crate::fresnel::fresnel;

/// Geometry in the plane perpendicular to the source axis: source at height `h` above the
/// mirror, screen at horizontal distance `l`; point at height `y` on the screen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lloyd {
    pub n1: f64,
    pub n2: f64,
    pub h_m: f64,
    pub l_m: f64,
}

impl Lloyd {
    /// Angle of incidence at the mirror for the reflected ray to height y (image method).
    pub fn theta(&self, y_m: f64) -> f64 {
        self.l_m.atan2(self.h_m + y_m)
    }

    /// I = |e^{iφ_d} + r_s e^{iφ_r}|² for a unit-intensity s-polarized line source, spreading off.
    pub fn intensity(&self, y_m: f64, lambda_m: f64) -> f64 {
        let r_direct = self.n1 * self.l_m.hypot(y_m - self.h_m);
        let r_image = self.n1 * self.l_m.hypot(y_m + self.h_m);
        let rs = fresnel(self.n1, self.n2, self.theta(y_m).cos()).r_s;
        (path_phasor(r_direct - r_image, lambda_m) + rs).norm_sqr()
    }

    /// Fringe visibility 2|r_s|/(1 + |r_s|²) at height y.
    pub fn visibility(&self, y_m: f64) -> f64 {
        let r = fresnel(self.n1, self.n2, self.theta(y_m).cos()).r_s.norm();
        2.0 * r / (1.0 + r * r)
    }
}
