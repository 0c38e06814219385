//! Double-double arithmetic for the closed forms (≈ 106-bit significands, [`TwoFloat`]): the
//! references must be better conditioned than the tracer they judge, so lengths whose
//! difference sets a phase are formed from exact coordinate differences and summed without
//! rounding, and the phase is reduced to a fraction of a cycle before it is rounded to f64.
//!
//! The closed forms use the `twofloat` crate on purpose, not the tracer's own
//! [`crate::optics::double_double`]: a reference that shared the tracer's arithmetic could share its
//! bugs, and the gate would not see them.

use glam::DVec3;
use num_complex::Complex64;
use twofloat::TwoFloat;

/// The vector `a − b` with each component exact (a double-double difference of two f64).
pub fn diff(a: DVec3, b: DVec3) -> [TwoFloat; 3] {
    [
        TwoFloat::new_sub(a.x, b.x),
        TwoFloat::new_sub(a.y, b.y),
        TwoFloat::new_sub(a.z, b.z),
    ]
}

/// `a / b` to double-double accuracy. (`twofloat`'s own `TwoFloat / TwoFloat` forms
/// 1 − b·(1/b) without a fused multiply-add and is only as accurate as f64: found by the
/// 50-digit two-beam test, where it cost 1e-13 of the intensity of a 1 mm plate.) One Newton
/// step on the reciprocal, with the residual 1 − b·x0 formed exactly.
pub(crate) fn div(a: TwoFloat, b: TwoFloat) -> TwoFloat {
    let x0 = 1.0 / b.hi();
    let residual = TwoFloat::from(1.0) - b * x0;
    a * (TwoFloat::from(x0) + residual * x0)
}

/// The dot product of a double-double vector with an f64 vector.
pub fn dot(v: &[TwoFloat; 3], u: DVec3) -> TwoFloat {
    v[0] * u.x + v[1] * u.y + v[2] * u.z
}

/// `v − (v·u) u` for a unit f64 vector `u`: the part of `v` perpendicular to `u`.
pub fn reject(v: &[TwoFloat; 3], u: DVec3) -> [TwoFloat; 3] {
    let k = dot(v, u);
    [v[0] - k * u.x, v[1] - k * u.y, v[2] - k * u.z]
}

/// The Euclidean length of a double-double vector.
pub fn length(v: &[TwoFloat; 3]) -> TwoFloat {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The distance |a − b| from exact coordinate differences.
pub fn distance(a: DVec3, b: DVec3) -> TwoFloat {
    length(&diff(a, b))
}

/// The phasor e^{i 2π s/λ} of an optical path `s` (m) in double-double at vacuum wavelength
/// `lambda_m` (docs/PHYSICS.md §1): the whole cycles are removed in double-double, so the rounded
/// fraction keeps its digits for paths of any length.
pub fn path_phasor(s_m: TwoFloat, lambda_m: f64) -> Complex64 {
    crate::accumulate::phasor_from_cycles(f64::from(cycle_fraction(s_m, lambda_m)))
}

/// The cycles s/λ of an optical path `s_m` (m) at vacuum wavelength `lambda_m` less the nearest
/// whole number, in double-double (in [−1/2, 1/2]).
fn cycle_fraction(s_m: TwoFloat, lambda_m: f64) -> TwoFloat {
    let cycles = s_m / lambda_m;
    cycles - cycles.hi().round()
}

/// The distance q ∈ [0, 1/2] of `s_m`/`lambda_m` (cycles of an optical path `s_m`, m, at vacuum
/// wavelength `lambda_m`) from the nearest half-integer, formed in double-double and rounded
/// once: a two-beam dark fringe is q = 0, and 1 + cos(2π s/λ) = 2 sin²(π q) keeps its relative
/// digits there, where 1 + cos of a rounded phase keeps only 2.2e-16 absolute.
pub fn half_cycle_distance(s_m: TwoFloat, lambda_m: f64) -> f64 {
    let frac = cycle_fraction(s_m, lambda_m);
    let frac = if frac.hi() < 0.0 { -frac } else { frac };
    f64::from(TwoFloat::from(0.5) - frac).clamp(0.0, 0.5)
}

/// A unit vector in double-double: `v/|v|` (any nonzero length).
pub fn unit(v: DVec3) -> [TwoFloat; 3] {
    let len =
        (TwoFloat::new_mul(v.x, v.x) + TwoFloat::new_mul(v.y, v.y) + TwoFloat::new_mul(v.z, v.z))
            .sqrt();
    [
        div(v.x.into(), len),
        div(v.y.into(), len),
        div(v.z.into(), len),
    ]
}

/// The dot product of two double-double vectors.
pub(crate) fn dot2(a: &[TwoFloat; 3], b: &[TwoFloat; 3]) -> TwoFloat {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The direction reflected at a plane of unit normal `n` (either orientation):
/// u − 2 (u·n) n (docs/PHYSICS.md §1), in double-double.
pub fn reflect(u: &[TwoFloat; 3], n: &[TwoFloat; 3]) -> [TwoFloat; 3] {
    let k = dot2(u, n) * 2.0;
    [u[0] - k * n[0], u[1] - k * n[1], u[2] - k * n[2]]
}

/// The direction refracted from index `n1` into `n2` at a plane of unit normal `n` (either
/// orientation) by Snell's law in vector form, η u + (η cos θi − cos θt) N_o with N_o facing the
/// incident side and η = n1/n2, in double-double; `None` under total internal reflection.
pub fn refract(u: &[TwoFloat; 3], n: &[TwoFloat; 3], n1: f64, n2: f64) -> Option<[TwoFloat; 3]> {
    let un = dot2(u, n);
    let n_o = if un.hi() < 0.0 {
        *n
    } else {
        [-n[0], -n[1], -n[2]]
    };
    let cos_i = -dot2(u, &n_o);
    let eta = div(n1.into(), n2.into());
    let one = TwoFloat::from(1.0);
    let c2t = one - eta * eta * (one - cos_i * cos_i);
    if c2t.hi() < 0.0 {
        return None;
    }
    let k = eta * cos_i - c2t.sqrt();
    Some([0, 1, 2].map(|i| eta * u[i] + k * n_o[i]))
}
