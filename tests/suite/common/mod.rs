//! Shared proptest strategies and independent reference helpers for the integration tests.
//!
//! Nothing here calls into `fringe`'s physics: the reference Fresnel formulas below are written
//! out again from Born & Wolf §1.5 (the cosine forms, P1–P4 of docs/PHYSICS.md) so that the tests
//! compare the crate against an independent evaluation, never against itself.
#![allow(dead_code)]

use glam::DVec3;
use num_complex::Complex64;
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// The proptest configuration of these tests: `cases` cases, no regression files written into
/// the source tree (a failure prints its minimal input; re-run with PROPTEST_RNG_SEED to replay).
pub fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// Machine epsilon, used to state rounding-error budgets explicitly.
pub const EPS: f64 = f64::EPSILON;

/// A refractive index in [1, 3].
pub fn index() -> impl Strategy<Value = f64> {
    1.0..=3.0f64
}

/// A pair of indices (n1, n2) in [1, 3]², with exactly equal pairs and the end points
/// appearing deliberately (they are the degenerate cases of the formulas).
pub fn index_pair() -> impl Strategy<Value = (f64, f64)> {
    prop_oneof![
        6 => (index(), index()),
        1 => index().prop_map(|n| (n, n)),
        1 => (Just(1.0), index()),
        1 => (index(), Just(1.0)),
        1 => (Just(3.0), index()),
    ]
}

/// A pair of indices with |n1 − n2| ≥ 0.01 (a well-defined Brewster angle).
pub fn distinct_index_pair() -> impl Strategy<Value = (f64, f64)> {
    (index(), index()).prop_filter("indices must differ by at least 0.01", |(a, b)| {
        (a - b).abs() >= 0.01
    })
}

/// An angle of incidence in [0, π/2], with both ends included explicitly.
pub fn angle() -> impl Strategy<Value = f64> {
    prop_oneof![
        8 => 0.0..=FRAC_PI_2,
        1 => Just(0.0),
        1 => Just(FRAC_PI_2),
    ]
}

/// cos θ, returning exactly 0 at θ = π/2 (f64 `cos(π/2)` is 6e-17, which would never test
/// exactly grazing incidence).
pub fn cos_of(theta: f64) -> f64 {
    if theta == FRAC_PI_2 { 0.0 } else { theta.cos() }
}

/// A unit vector distributed uniformly on the sphere (z uniform in [−1, 1], azimuth uniform).
pub fn unit_vector() -> impl Strategy<Value = DVec3> {
    (-1.0..=1.0f64, 0.0..TAU).prop_map(|(z, phi): (f64, f64)| {
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z).normalize()
    })
}

/// An incidence on a plane: a surface normal with random orientation (it may point to either
/// side), an angle θ in [0, π/2] and an azimuth; `d_i` makes the angle θ with the normal that
/// faces the incident side.
#[derive(Clone, Copy, Debug)]
pub struct Incidence {
    /// The normal as handed to the code (random orientation).
    pub normal: DVec3,
    /// The unit normal facing the incident side (d_i·n_o = −cos θ).
    pub n_o: DVec3,
    pub d_i: DVec3,
    pub theta: f64,
    pub cos_i: f64,
}

pub fn incidence() -> impl Strategy<Value = Incidence> {
    (unit_vector(), angle(), 0.0..TAU, any::<bool>()).prop_map(|(normal, theta, az, flip)| {
        let n_o = if flip { -normal } else { normal };
        let (t1, t2) = tangent_basis(n_o);
        let t = az.cos() * t1 + az.sin() * t2;
        let c = cos_of(theta);
        let d_i = (-c * n_o + theta.sin() * t).normalize();
        Incidence {
            normal,
            n_o,
            d_i,
            theta,
            cos_i: c,
        }
    })
}

/// Two unit vectors spanning the plane perpendicular to unit `n` (built by hand, not with glam's
/// helper, so tests do not share the crate's choices).
pub fn tangent_basis(n: DVec3) -> (DVec3, DVec3) {
    let a = if n.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
    let t1 = (a - a.dot(n) * n).normalize();
    (t1, n.cross(t1))
}

/// A random complex number with modulus in [0.1, 2].
pub fn complex_amplitude() -> impl Strategy<Value = Complex64> {
    (0.1..=2.0f64, -PI..PI).prop_map(|(m, a)| Complex64::from_polar(m, a))
}

/// Reference Fresnel coefficients written out independently from B&W §1.5 (P1–P4, cosine
/// forms), with cos θt = sqrt(1 − (n1/n2)² sin²θi), or +i·sqrt(..) under TIR (docs/PHYSICS.md §1).
#[derive(Clone, Copy, Debug)]
pub struct RefFresnel {
    pub r_s: Complex64,
    pub r_p: Complex64,
    pub t_s: Complex64,
    pub t_p: Complex64,
    pub cos_t: Complex64,
}

pub fn ref_fresnel(n1: f64, n2: f64, cos_i: f64) -> RefFresnel {
    // cos²θt = 1 − (n1/n2)² sin²θi, rearranged as (n2² − n1² + n1² cos²θi)/n2² so that it keeps
    // its digits when n1 ≈ n2 near grazing incidence (the plain form loses them to 1 − sin²).
    let c2 = ((n2 - n1) * (n2 + n1) + (n1 * cos_i).powi(2)) / (n2 * n2);
    let cos_t = if c2 >= 0.0 {
        Complex64::new(c2.sqrt(), 0.0)
    } else {
        Complex64::new(0.0, (-c2).sqrt())
    };
    let a_s = Complex64::from(n1 * cos_i);
    let b_s = cos_t * n2;
    let a_p = Complex64::from(n2 * cos_i);
    let b_p = cos_t * n1;
    RefFresnel {
        r_s: (a_s - b_s) / (a_s + b_s),
        r_p: (a_p - b_p) / (a_p + b_p),
        t_s: 2.0 * a_s / (a_s + b_s),
        t_p: Complex64::from(2.0 * n1 * cos_i) / (a_p + b_p),
        cos_t,
    }
}

/// Wrap an angle difference into (−π, π].
pub fn wrap(a: f64) -> f64 {
    let mut x = a % TAU;
    if x <= -PI {
        x += TAU;
    } else if x > PI {
        x -= TAU;
    }
    x
}

/// |a − b| for complex numbers.
pub fn cdist(a: Complex64, b: Complex64) -> f64 {
    (a - b).norm()
}

/// Distance between two complex 3D fields.
pub fn field_dist(a: &[Complex64; 3], b: &[Complex64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).norm_sqr()).sum::<f64>().sqrt()
}

/// Norm of a complex 3D field.
pub fn field_norm(a: &[Complex64; 3]) -> f64 {
    a.iter().map(|c| c.norm_sqr()).sum::<f64>().sqrt()
}
