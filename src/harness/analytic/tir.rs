//! Total internal reflection: the Fresnel rhomb (docs/PHYSICS.md §5) and a TIR beam interfering with
//! a beam of another path.
//!
//! Under TIR |r_s| = |r_p| = 1 with arg r_s (P5) and arg r_p (P6); the relative phase
//! Δ = arg r_p − arg r_s obeys tan(|Δ|/2) = cos θ sqrt(sin²θ − n21²)/sin²θ.

use super::precise::div;
use twofloat::TwoFloat;

/// arg r_s under TIR (P5), radians: −2 atan(sqrt(sin²θ − n21²)/cos θ).
pub(crate) fn phase_s(n1: f64, n2: f64, theta: f64) -> f64 {
    let n21 = n2 / n1;
    -2.0 * ((theta.sin().powi(2) - n21 * n21).sqrt() / theta.cos()).atan()
}

/// arg r_p under TIR (P6), radians: −2 atan(sqrt(sin²θ − n21²)/(n21² cos θ)).
pub(crate) fn phase_p(n1: f64, n2: f64, theta: f64) -> f64 {
    let n21 = n2 / n1;
    -2.0 * ((theta.sin().powi(2) - n21 * n21).sqrt() / (n21 * n21 * theta.cos())).atan()
}

/// The convention-free retardance of one TIR: |Δ| = 2 atan(cos θ sqrt(sin²θ − n21²)/sin²θ).
pub(crate) fn retardance_magnitude(n1: f64, n2: f64, theta: f64) -> f64 {
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

/// The retardance of `k` identical TIRs, arg(p) − arg(s) of the output (radians, e^{-iωt}: the
/// k (P6 − P5) of [`rhomb_retardance`], docs/PHYSICS.md §5), from the direction of the wave
/// inside the glass and the TIR face's normal (any lengths, either orientation) instead of
/// from θ. Near the critical angle the retardance goes as √(sin²θ − n21²): θ = acos(u·n) in
/// f64 is off by ~1e-16/sin θ, which at θ − θc = 1e-12 rad moved the retardance by up to
/// 1e-4 rad, far more than the tracer's own error (the fuzz's 50-digit check,
/// `tools/rhomb_mpmath.py`). Here sin²θ = |û × n̂|², n21 = n_out/n_glass and
/// sin²θ − n21² = (sin θ − n21)(sin θ + n21) are formed in double-double from the given
/// vectors, so the closed form's own error stays ~1e-16 rad down to θ − θc ~ 1e-30. `None`
/// when the wave is not beyond the critical angle (n_glass sin θ ≤ n_out: no TIR).
pub fn rhomb_retardance_from_vectors(
    n_glass: f64,
    n_out: f64,
    direction: glam::DVec3,
    normal: glam::DVec3,
    k: usize,
) -> Option<f64> {
    let TirAngle {
        sin: _,
        cos,
        n21,
        gap,
    } = TirAngle::of(n_glass, n_out, direction, normal)?;
    let root = gap.sqrt();
    // tan(−P5/2) = √(sin²θ − n21²)/cos θ, tan(−P6/2) = √(sin²θ − n21²)/(n21² cos θ).
    let ts = f64::from(div(root, cos));
    let tp = f64::from(div(root, n21 * n21 * cos));
    Some(k as f64 * 2.0 * (ts.atan() - tp.atan()))
}

/// A wave's angle at a TIR face from the given vectors, in double-double (the shared part of
/// [`rhomb_retardance_from_vectors`] and [`rhomb_retardance_representation`]): sin θ = |û × n̂|,
/// cos θ = |û·n̂|, n21 = n_out/n_glass and gap = sin²θ − n21² = (sin θ − n21)(sin θ + n21).
struct TirAngle {
    sin: TwoFloat,
    cos: TwoFloat,
    n21: TwoFloat,
    gap: TwoFloat,
}

impl TirAngle {
    /// `None` when the wave is not beyond the critical angle (gap ≤ 0) or grazes (cos θ = 0).
    fn of(n_glass: f64, n_out: f64, direction: glam::DVec3, normal: glam::DVec3) -> Option<Self> {
        use super::precise::{dot2, unit};
        let u = unit(direction);
        let n = unit(normal);
        let cross = [
            u[1] * n[2] - u[2] * n[1],
            u[2] * n[0] - u[0] * n[2],
            u[0] * n[1] - u[1] * n[0],
        ];
        let sin = dot2(&cross, &cross).sqrt();
        let cos = dot2(&u, &n).abs();
        let n21 = div(n_out.into(), n_glass.into());
        let gap = (sin - n21) * (sin + n21);
        (gap.hi() > 0.0 && cos.hi() > 0.0).then_some(TirAngle { sin, cos, n21, gap })
    }
}

/// The *representation term* of [`rhomb_retardance_from_vectors`] (docs/PHYSICS.md §8,
/// "Representation sensitivity"), radians: how far the retardance of `k` identical TIRs moves
/// when the wave's direction inside the glass and the TIR face's normal are each held one f64
/// rounding off the ones written, |∂Δ/∂θ| δθ. Every f64 tracer holds them so (the direction
/// inside the glass is the f64 output of a refraction, the normal one normalization): not a
/// rounding error of the tracer but of the scene it can hold.
///
/// ∂Δ/∂θ = 2k (sin θ/R) [1 − n21²(1 − n21²)/(n21⁴ cos²θ + R²)], R = √(sin²θ − n21²), from
/// Δ = 2k [atan(R/cos θ) − atan(R/(n21² cos θ))] with R dR/dθ = sin θ cos θ: a square-root
/// singularity at the critical angle (R → 0). δθ = δ(sin θ)/cos θ with δ(sin θ) the rounding of
/// |û × n̂| from one rounding of each component of û and of n̂: 2u Σ_{i≠j} |û_i n̂_j| (u = 2⁻⁵³).
/// In a frame where û and n̂ lie in a coordinate plane that is u sin θ; in a rotated frame it is
/// ~u, which near the critical angle moves Δ by 1e-9 … 1e-6 rad (`fringe fuzz --family
/// rhomb_retardance --seed 1`, scenes 2773, 4425, 4569, 7597). `None` without TIR.
pub fn rhomb_retardance_representation(
    n_glass: f64,
    n_out: f64,
    direction: glam::DVec3,
    normal: glam::DVec3,
    k: usize,
) -> Option<f64> {
    let TirAngle { sin, cos, n21, gap } = TirAngle::of(n_glass, n_out, direction, normal)?;
    let cos = f64::from(cos);
    let r = f64::from(gap.sqrt());
    let (sin, n21) = (f64::from(sin), f64::from(n21));
    let n2 = n21 * n21;
    let slope =
        2.0 * k as f64 * (sin / r) * (1.0 - n2 * (1.0 - n2) / (n2 * n2 * cos * cos + r * r));
    let (uf, nf) = (direction.normalize(), normal.normalize());
    let products: f64 = (0..3)
        .flat_map(|i| (0..3).filter(move |j| *j != i).map(move |j| (i, j)))
        .map(|(i, j)| (uf[i] * nf[j]).abs())
        .sum();
    let d_sin = 2.0 * (f64::EPSILON / 2.0) * products;
    Some(slope.abs() * d_sin / cos)
}

/// One planar face a plane wave meets: a point of it, its normal (any length, either
/// orientation), the indices before and after it, and whether the wave reflects there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// A point of the face, m.
    pub point: glam::DVec3,
    /// Its normal (any length, either orientation).
    pub normal: glam::DVec3,
    /// Index on the side the wave comes from.
    pub n_before: f64,
    /// Index on the other side.
    pub n_after: f64,
    /// Whether the wave reflects there (else it refracts).
    pub reflect: bool,
}

/// The optical path (m, double-double) of a plane wave along `direction` (any length) with phase
/// 0 on the plane through `reference_point`, in a medium of index `n0`, after the faces `faces`,
/// at the point `x` (or, with `far_field`, on the wavefront through `x`, which is the same
/// number): by wavefront continuity φ_k(x) = φ_{k−1}(Q_k) + n_k u_k·(x − Q_k) at each face through
/// Q_k (docs/PHYSICS.md §5 "TIR"), with the directions reflected and refracted in double-double
/// ([`super::precise`]) from the given vectors normalized exactly, and every difference of points
/// exact. Returns the path and the final direction (f64), or `None` when a refraction event
/// meets total internal reflection.
///
/// A direction rounded to f64 moves the phase by n δu·(x − Q), ~1e-11 rad at 550 nm for a point
/// a few cm from the face point; here it is ~1e-27 m (`tests/suite/closed_form_precision.rs`).
pub fn plane_wave_path(
    direction: glam::DVec3,
    reference_point: glam::DVec3,
    n0: f64,
    faces: &[Face],
    x: glam::DVec3,
) -> Option<(twofloat::TwoFloat, glam::DVec3)> {
    use super::precise;
    let mut u = precise::unit(direction);
    let mut q = reference_point;
    let mut n = n0;
    let mut op = twofloat::TwoFloat::from(0.0);
    for f in faces {
        op += precise::dot2(&precise::diff(f.point, q), &u) * n;
        q = f.point;
        let nd = precise::unit(f.normal);
        if f.reflect {
            u = precise::reflect(&u, &nd);
        } else {
            u = precise::refract(&u, &nd, f.n_before, f.n_after)?;
            n = f.n_after;
        }
    }
    op += precise::dot2(&precise::diff(x, q), &u) * n;
    let dir = glam::DVec3::new(u[0].into(), u[1].into(), u[2].into());
    Some((op, dir))
}
