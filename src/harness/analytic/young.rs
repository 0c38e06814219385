//! Young's two-slit experiment (paper §4.1, eq. 4; docs/PHYSICS.md §5 "Young").
//!
//! Two coherent line sources (slits) parallel to the z axis at (0, ±d/2); screen at x = l.
//! The exact distances are the perpendicular distances to the slit axes,
//! `r_{1,2} = sqrt(l² + (y ∓ d/2)²)` (cylindrical waves, spreading off as in the paper).

use super::precise;
use glam::DVec3;
use twofloat::TwoFloat;

/// Exact intensity for two unit-intensity coherent line sources along unit `axis` through
/// `s1`, `s2`, at the point `p`, vacuum wavelength `lambda_m`, in a medium of index `n`, for an
/// unpolarized source whose channel reference is the slit axis: the channel polarized along the
/// axis has parallel fields, `I = 2 + 2 cos δ`; the in-plane channel has fields at the angle α
/// between the two rays, `I = 2 + 2 cos α cos δ`. Unpolarized: `I = 2 + (1 + cos α) cos δ`,
/// δ = 2π n (r1 − r2)/λ (P10). `axis_fraction` is the intensity fraction in the
/// axis-polarized channel (1 for linear polarization along the axis, 1/2 for unpolarized).
///
/// The distances come from exact coordinate differences in double-double and δ is reduced to a
/// fraction of a cycle before rounding ([`super::precise`]), so the closed form's own phase
/// error is ~1e-16 rad whatever the distances (the tracer forms r1 − r2 from f64 lengths).
/// The intensity is evaluated as `2(1 + cos δ) − 2(1 − f)(1 − cos α) cos δ` with both
/// differences formed without cancellation (`Terms`): `2 + …` in f64 rounds by 2.2e-16
/// absolute, which at a dark fringe of I = 7.4e-7 was 3e-10 of the profile (`fringe fuzz
/// --family young_exact --seed 2`, scene 2559, `tests/suite/truth_found_edges.rs`), while the
/// tracer's |E1 + E2|² keeps its relative digits there.
pub fn exact_line_sources(
    s1: DVec3,
    s2: DVec3,
    axis: DVec3,
    p: DVec3,
    lambda_m: f64,
    n: f64,
    axis_fraction: f64,
) -> f64 {
    let t = Terms::at(s1, s2, axis, p, lambda_m, n);
    2.0 * t.one_plus_cos_delta - 2.0 * (1.0 - axis_fraction) * t.one_minus_cos_alpha * t.cos_delta
}

/// [`exact_line_sources`] for basis-free unpolarized light (three incoherent dipoles of weight
/// 1/2, docs/PHYSICS.md §3): the coherent term is tr[(I − k1k1ᵀ)(I − k2k2ᵀ)]/2 = (1 + cos²α)/2
/// of the parallel-field one, α the angle between the rays (both perpendicular to the axis),
/// so `I = 2 + (1 + cos²α) cos δ` (the two-channel model's `1 + cos α` differs by α²/2),
/// evaluated as `2(1 + cos δ) − sin²α cos δ` (`Terms`).
pub fn exact_line_sources_basis_free(
    s1: DVec3,
    s2: DVec3,
    axis: DVec3,
    p: DVec3,
    lambda_m: f64,
    n: f64,
) -> f64 {
    let t = Terms::at(s1, s2, axis, p, lambda_m, n);
    2.0 * t.one_plus_cos_delta - t.sin2_alpha * t.cos_delta
}

/// The phase and angle terms of [`exact_line_sources`] at one screen point, each rounded once
/// from double-double, and the two that vanish at a dark fringe and between parallel rays
/// (1 + cos δ, 1 − cos α) formed as such rather than as differences of rounded cosines, so
/// each keeps its relative digits.
struct Terms {
    /// cos δ, δ = 2π n (r1 − r2)/λ.
    cos_delta: f64,
    /// 1 + cos δ = 2 sin²(π q), q the distance of n (r1 − r2)/λ from the nearest half cycle
    /// ([`super::precise::half_cycle_distance`]).
    one_plus_cos_delta: f64,
    /// 1 − cos α, α the angle between the rays v1 = p − s1, v2 = p − s2 (both perpendicular to
    /// the axis): |v1 × v2|²/(r1 r2 (r1 r2 + v1·v2)) while v1·v2 ≥ 0, 1 − v1·v2/(r1 r2)
    /// otherwise (no cancellation either way).
    one_minus_cos_alpha: f64,
    /// sin²α = |v1 × v2|²/(r1 r2)².
    sin2_alpha: f64,
}

impl Terms {
    /// The terms at `p` (double-double distances from exact coordinate differences).
    fn at(s1: DVec3, s2: DVec3, axis: DVec3, p: DVec3, lambda_m: f64, n: f64) -> Terms {
        let a = axis.normalize();
        let v1 = precise::reject(&precise::diff(p, s1), a);
        let v2 = precise::reject(&precise::diff(p, s2), a);
        let (r1, r2) = (precise::length(&v1), precise::length(&v2));
        let q = precise::half_cycle_distance((r1 - r2) * n, lambda_m);
        let sin_half = (std::f64::consts::PI * q).sin();
        let one_plus_cos_delta = 2.0 * sin_half * sin_half;
        let dot12 = precise::dot2(&v1, &v2);
        let cross = [
            v1[1] * v2[2] - v1[2] * v2[1],
            v1[2] * v2[0] - v1[0] * v2[2],
            v1[0] * v2[1] - v1[1] * v2[0],
        ];
        let cross2 = precise::dot2(&cross, &cross);
        let r12 = r1 * r2;
        let one_minus_cos_alpha = if dot12.hi() >= 0.0 {
            precise::div(cross2, r12 * (r12 + dot12))
        } else {
            TwoFloat::from(1.0) - precise::div(dot12, r12)
        };
        Terms {
            cos_delta: one_plus_cos_delta - 1.0,
            one_plus_cos_delta,
            one_minus_cos_alpha: f64::from(one_minus_cos_alpha),
            sin2_alpha: f64::from(precise::div(cross2, r12 * r12)),
        }
    }
}

/// Paraxial Young intensity `2(1 + cos(2π n d y/(λ l)))` in a medium of index `n` (paper eq. 4
/// with δ ≈ 2π n d y/(λ l)).
pub fn paraxial(d_m: f64, l_m: f64, y_m: f64, lambda_m: f64, n: f64) -> f64 {
    2.0 * (1.0 + (std::f64::consts::TAU * n * d_m * y_m / (lambda_m * l_m)).cos())
}

/// Paraxial fringe spacing λ l/(n d) (m) in a medium of index `n`.
pub(crate) fn fringe_spacing_paraxial(d_m: f64, l_m: f64, lambda_m: f64, n: f64) -> f64 {
    lambda_m * l_m / (n * d_m)
}

/// Exact local fringe spacing on the axis (y = 0) in a medium of index `n`:
/// 2π/|dδ/dy| = λ sqrt(l² + d²/4)/(n d).
pub(crate) fn fringe_spacing_exact_on_axis(d_m: f64, l_m: f64, lambda_m: f64, n: f64) -> f64 {
    lambda_m * (l_m * l_m + 0.25 * d_m * d_m).sqrt() / (n * d_m)
}
