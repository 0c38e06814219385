//! Fresnel coefficients and ray directions at a plane interface between two
//! isotropic, lossless media.
//!
//! # Conventions (docs/PHYSICS.md §1, fixed once for the whole crate)
//!
//! * Time dependence `e^{-iωt}`; a wave that travelled optical path `s` carries `e^{+i 2π s/λ0}`.
//! * At an interface with unit normal `N` (either orientation) and incident direction `d_i`:
//!   `s = normalize(d_i × N)`, and for every ray `d ∈ {d_i, d_r, d_t}`: `p = d × s`, so that
//!   `(s, p, d)` is right-handed. A field is `E = a_s s + a_p p`.
//! * `n1` is the index on the incident side, `n2` on the other side; `cos θt` follows from Snell.
//! * The amplitude coefficients are the cosine forms (B&W §1.5.2), which stay finite at normal
//!   incidence and for `n1 = n2`:
//!
//! ```text
//! r_s = (n1 cos θi − n2 cos θt)/(n1 cos θi + n2 cos θt)      (P1)
//! r_p = (n2 cos θi − n1 cos θt)/(n2 cos θi + n1 cos θt)      (P2)
//! t_s = 2 n1 cos θi/(n1 cos θi + n2 cos θt)                  (P3)
//! t_p = 2 n1 cos θi/(n2 cos θi + n1 cos θt)                  (P4)
//! ```
//!
//! * Total internal reflection (`n1 sin θi > n2`): `cos θt = +i·sqrt((n1/n2)² sin²θi − 1)`
//!   (the evanescent wave decays for `e^{-iωt}`); (P1), (P2) then have unit modulus with
//!   `arg r_s = −2 atan(sqrt(sin²θi − n21²)/cos θi)` (P5) and
//!   `arg r_p = −2 atan(sqrt(sin²θi − n21²)/(n21² cos θi))` (P6), `n21 = n2/n1`.
//!
//! Every function here is a pure kernel on scalars and unit vectors; angles are radians.

use crate::optics::double_double::DoubleDouble;
use glam::DVec3;
use num_complex::Complex64;

/// Complex Fresnel amplitude coefficients for one incidence, in the frame of the module docs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FresnelCoefficients {
    /// Reflection coefficient for the s (⊥) component, (P1) or (P5) under TIR.
    pub r_s: Complex64,
    /// Reflection coefficient for the p (∥) component, (P2) or (P6) under TIR.
    pub r_p: Complex64,
    /// Transmission coefficient for s, (P3); under TIR the evanescent amplitude.
    pub t_s: Complex64,
    /// Transmission coefficient for p, (P4); under TIR the evanescent amplitude.
    pub t_p: Complex64,
    /// cos θt: real in [0, 1] outside TIR, `+i·κ` (κ ≥ 0) under TIR.
    pub cos_theta_t: Complex64,
    /// True when `n1 sin θi > n2` (no propagating transmitted wave).
    pub total_internal_reflection: bool,
}

/// Power reflectance and transmittance for s and p: R = |r|², T = Re(n2 cos θt)/(n1 cos θi)·|t|².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FresnelPower {
    /// Power reflectance for s, R_s = |r_s|² (dimensionless, in [0, 1]).
    pub r_s: f64,
    /// Power reflectance for p, R_p = |r_p|².
    pub r_p: f64,
    /// Power transmittance for s, T_s = Re(n2 cos θt)/(n1 cos θi)·|t_s|² (0 under TIR).
    pub t_s: f64,
    /// Power transmittance for p, T_p = Re(n2 cos θt)/(n1 cos θi)·|t_p|² (0 under TIR).
    pub t_p: f64,
}

/// `cos² θt` from Snell's law, in whichever of its two forms rounds less here:
/// `((n2 − n1)(n2 + n1) + n1² cos²θi)/n2²` (exact for nearly equal indices, also at grazing
/// incidence; its rounding is u·max(|n2² − n1²|, n1² cos²θi)/n2²) or `1 − (n1/n2)² sin²θi`
/// with sin²θi = (1 − cos θi)(1 + cos θi) (rounding u·max(1, (n1/n2)² sin²θi)). Into a much
/// thinner medium near normal incidence the first cancels to ~u (n1/n2)²: 3.7e-10 for
/// n = 3 → 0.001 at normal incidence, where cos²θt is exactly 1 (`fringe fuzz --family
/// coherence_gaussian --seed 1`, scene 239, test `precision_classes::cos_theta_t_into_a_much_thinner_medium_is_exact_at_normal_incidence`).
/// Negative values mean total internal reflection.
pub fn cos2_theta_t(n1: f64, n2: f64, cos_theta_i: f64) -> f64 {
    let c = cos_theta_i;
    let sin2 = (1.0 - c) * (1.0 + c);
    let ratio2 = (n1 / n2) * (n1 / n2);
    let rounding_sum = ((n2 - n1) * (n2 + n1)).abs().max(n1 * n1 * c * c) / (n2 * n2);
    let rounding_sine = (ratio2 * sin2).max(1.0);
    if rounding_sine < rounding_sum {
        1.0 - ratio2 * sin2
    } else {
        ((n2 - n1) * (n2 + n1) + n1 * n1 * c * c) / (n2 * n2)
    }
}

/// Critical angle θc = asin(n2/n1) in radians, `None` when `n1 ≤ n2` (no TIR possible).
pub fn critical_angle(n1: f64, n2: f64) -> Option<f64> {
    (n1 > n2).then(|| (n2 / n1).asin())
}

/// Brewster angle θB = atan(n2/n1) in radians (docs/PHYSICS.md §2, paper eq. 9).
pub fn brewster_angle(n1: f64, n2: f64) -> f64 {
    n2.atan2(n1)
}

/// Complex Fresnel coefficients (P1)–(P6) for incidence from index `n1` onto index `n2`.
///
/// `cos_theta_i` is |d_i·N| in [0, 1]; indices must be finite and positive (lossless media).
pub fn fresnel(n1: f64, n2: f64, cos_theta_i: f64) -> FresnelCoefficients {
    debug_assert!(n1 > 0.0 && n2 > 0.0, "indices must be positive");
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    if n1 == n2 {
        // No interface: the limit of (P1)–(P4) for n2 → n1 at every angle, including exactly
        // grazing incidence where the cosine forms are 0/0.
        return FresnelCoefficients {
            r_s: Complex64::from(0.0),
            r_p: Complex64::from(0.0),
            t_s: Complex64::from(1.0),
            t_p: Complex64::from(1.0),
            cos_theta_t: Complex64::from(cos_i),
            total_internal_reflection: false,
        };
    }
    fresnel_with_cos2_t(n1, n2, cos_i, cos2_theta_t(n1, n2, cos_i))
}

/// [`fresnel`] with cos²θt given (negative under total internal reflection): for a caller that
/// knows it better than [`cos2_theta_t`] can form it from an f64 cos θi (the tracer's normal
/// wavevector carried in double-double between parallel faces, docs/PHYSICS.md §8).
pub fn fresnel_with_cos2_t(n1: f64, n2: f64, cos_i: f64, c2t: f64) -> FresnelCoefficients {
    let total_internal_reflection = c2t < 0.0;
    // Evanescent branch: cos θt = +i sqrt(-cos²θt) for the e^{-iωt} convention.
    let cos_t = if total_internal_reflection {
        Complex64::new(0.0, (-c2t).sqrt())
    } else {
        Complex64::new(c2t.sqrt(), 0.0)
    };
    let n1ci = Complex64::from(n1 * cos_i);
    let n2ci = Complex64::from(n2 * cos_i);
    let n2ct = cos_t * n2;
    let n1ct = cos_t * n1;
    let den_s = n1ci + n2ct;
    let den_p = n2ci + n1ct;
    FresnelCoefficients {
        r_s: (n1ci - n2ct) / den_s,
        r_p: (n2ci - n1ct) / den_p,
        t_s: 2.0 * n1ci / den_s,
        t_p: 2.0 * n1ci / den_p,
        cos_theta_t: cos_t,
        total_internal_reflection,
    }
}

/// The real parts of [`fresnel_with_cos2_t`]'s (r_s, r_p, t_s, t_p) for cos²θt ≥ 0 (no total
/// internal reflection, where every coefficient is real), formed without complex arithmetic but
/// bit for bit as it forms them: num-complex divides by a real-valued denominator d + 0i as
/// (a·d + 0·0)/(d·d + 0·0), so each quotient here is (a·d)/(d·d) rather than a/d
/// (`tests/suite/stack_kernel.rs`, `real_fresnel_is_the_complex_one_bit_for_bit`).
/// For the per-pixel kernels, which vouch only for pixels away from every critical angle.
pub fn fresnel_real_with_cos2_t(n1: f64, n2: f64, cos_i: f64, c2t: f64) -> [f64; 4] {
    let [r_s, r_p] = fresnel_real_pair_with_cos2_t(n1, n2, cos_i, c2t, true);
    let [t_s, t_p] = fresnel_real_pair_with_cos2_t(n1, n2, cos_i, c2t, false);
    [r_s, r_p, t_s, t_p]
}

/// The two coefficients of [`fresnel_real_with_cos2_t`] one event uses, (r_s, r_p) when
/// `reflect`, else (t_s, t_p), bit for bit, without forming the other two.
#[inline]
pub fn fresnel_real_pair_with_cos2_t(
    n1: f64,
    n2: f64,
    cos_i: f64,
    c2t: f64,
    reflect: bool,
) -> [f64; 2] {
    debug_assert!(
        c2t >= 0.0,
        "total internal reflection has complex coefficients"
    );
    fresnel_real_pair_with_cos_t(n1, n2, cos_i, c2t.sqrt(), reflect)
}

/// [`fresnel_real_pair_with_cos2_t`] from cos θt itself (cos θt ≥ 0, the square root of cos²θt
/// taken by the caller, e.g. once for the events that share it): the same operations, bit for
/// bit.
#[inline]
pub fn fresnel_real_pair_with_cos_t(
    n1: f64,
    n2: f64,
    cos_i: f64,
    cos_t: f64,
    reflect: bool,
) -> [f64; 2] {
    let n1ci = n1 * cos_i;
    let n2ci = n2 * cos_i;
    let n2ct = cos_t * n2;
    let n1ct = cos_t * n1;
    let den_s = n1ci + n2ct;
    let den_p = n2ci + n1ct;
    let (a_s, a_p) = if reflect {
        (n1ci - n2ct, n2ci - n1ct)
    } else {
        (2.0 * n1ci, 2.0 * n1ci)
    };
    [
        (a_s * den_s) / (den_s * den_s),
        (a_p * den_p) / (den_p * den_p),
    ]
}

/// The coefficients of a layer of index n2 and thickness d between n1 and n3, lit from n1
/// beyond the critical angle of its top face (frustrated total reflection, docs/PHYSICS.md §5):
/// the Airy sum with the imaginary cos θ2, per s and p.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrustratedLayer {
    /// r_layer − r12 for s and p: what the evanescent coupling adds to the face's total
    /// reflection r12 (P5, P6). Exactly 0 where e^{−2κd} underflows.
    pub dr: [Complex64; 2],
    /// t_layer for s and p: the field leaving the far face into n3 over the field arriving at the
    /// top face, both at the same tangential coordinates (all phase in it; 0 when n3 too is
    /// beyond its critical angle, where no wave leaves).
    pub t: [Complex64; 2],
    /// κ = (2π/λ) sqrt(−(n2 cos θ2)²), 1/m: the evanescent field decays as e^{−κz} in the layer.
    pub kappa_per_m: f64,
}

/// [`FrustratedLayer`] from the squared normal wavevector components (n_k cos θk)², k = 1, 2, 3
/// (in units of the vacuum wavenumber, double-double, the second negative: the tracer's
/// `interaction::normal_wavevector_squares`), the indices, the thickness d (m) and the vacuum
/// wavelength λ (m).
///
/// With the admittances a_k = n_k cos θk (s) or cos θk/n_k (p) (a2 = i|a2|, a3 imaginary when
/// n3 is beyond its critical angle too) and E − 1 = expm1(−2κd) (no cancellation for a thin
/// layer), the Airy sum of docs/PHYSICS.md §5 gives, with
/// D = 2 a2 (a1 + a3) + (a1 − a2)(a2 − a3)(E − 1),
///
/// ```text
/// r − r12 = 4 a1 a2 (a2 − a3) e^{−2κd} / ((a1 + a2) D)
/// t       = 4 a1 a2 e^{−κd} / D        (× n1/n3 for p)
/// ```
///
/// (r − r12 is the exact difference of the two closed forms, without subtracting them), so the
/// reflected wave r12 + (r − r12) reduces bit for bit to the total reflection r12 where the
/// coupling is below half an ulp of it.
pub fn frustrated_layer(
    (n1, n2, n3): (f64, f64, f64),
    (q2_1, q2_2, q2_3): (DoubleDouble, DoubleDouble, DoubleDouble),
    thickness_m: f64,
    lambda_m: f64,
) -> FrustratedLayer {
    let q1 = q2_1.sqrt().to_f64();
    let q2 = (-q2_2).sqrt().to_f64();
    let (q3, q3_imaginary) = if q2_3.hi >= 0.0 {
        (q2_3.sqrt().to_f64(), false)
    } else {
        ((-q2_3).sqrt().to_f64(), true)
    };
    let kappa = std::f64::consts::TAU * q2 / lambda_m;
    let decay = 2.0 * kappa * thickness_m;
    let (e, em1, half) = ((-decay).exp(), (-decay).exp_m1(), (-0.5 * decay).exp());
    let mut out = FrustratedLayer {
        dr: [Complex64::from(0.0); 2],
        t: [Complex64::from(0.0); 2],
        kappa_per_m: kappa,
    };
    // s: a_k = q_k; p: a_k = q_k/n_k².
    let weights = [(1.0, 1.0, 1.0), (n1 * n1, n2 * n2, n3 * n3)];
    for (k, (w1, w2, w3)) in weights.into_iter().enumerate() {
        let a1 = Complex64::from(q1 / w1);
        let a2 = Complex64::new(0.0, q2 / w2);
        let a3 = if q3_imaginary {
            Complex64::new(0.0, q3 / w3)
        } else {
            Complex64::from(q3 / w3)
        };
        let den = a2 * (a1 + a3) * 2.0 + (a1 - a2) * (a2 - a3) * em1;
        out.dr[k] = a1 * a2 * (a2 - a3) * (4.0 * e) / ((a1 + a2) * den);
        out.t[k] = if q3_imaginary {
            Complex64::from(0.0)
        } else {
            let t = a1 * a2 * (4.0 * half) / den;
            if k == 0 { t } else { t * (n1 / n3) }
        };
    }
    out
}

impl FresnelCoefficients {
    /// Power coefficients for this incidence. At exactly grazing incidence (cos θi = 0) no
    /// power crosses the interface: T = 0, R = 1.
    pub fn power(&self, n1: f64, n2: f64, cos_theta_i: f64) -> FresnelPower {
        let ratio = if cos_theta_i > 0.0 {
            n2 * self.cos_theta_t.re / (n1 * cos_theta_i)
        } else {
            0.0
        };
        FresnelPower {
            r_s: self.r_s.norm_sqr(),
            r_p: self.r_p.norm_sqr(),
            t_s: ratio * self.t_s.norm_sqr(),
            t_p: ratio * self.t_p.norm_sqr(),
        }
    }
}

/// The paper's rules (docs/PHYSICS.md §2, P7/P8, paper eqs. 8–9, and the paper's TIR phases),
/// expressed in this crate's frame so they can be compared with [`fresnel`] term by term.
///
/// Outside TIR: |r|, |t| from (P1)–(P4), with a π jump on E⊥ when n1 < n2 (P7) and on E∥ when
/// (n1 < n2 ∧ θi < θB) ∨ (n1 > n2 ∧ θi > θB) (P8), measured in the continuing frame
/// p'_r = −p_r. Refraction is co-phased. Under TIR the paper writes δ⊥ = +2 atan(…) and
/// δ∥ = 2 atan(…) − π (continuing frame); converted here to p_r they are the complex
/// conjugates of (P5), (P6): the opposite time convention.
pub fn paper_rules(n1: f64, n2: f64, cos_theta_i: f64) -> FresnelCoefficients {
    let exact = fresnel(n1, n2, cos_theta_i);
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    if exact.total_internal_reflection {
        // Paper: E⊥ gains +2atan(..) = −arg(P5); E∥ in p' gains 2atan(..) − π, i.e. in p_r
        // (one more sign) 2atan(..) = −arg(P6).
        return FresnelCoefficients {
            r_s: exact.r_s.conj(),
            r_p: exact.r_p.conj(),
            ..exact
        };
    }
    let sign = |jump: bool| if jump { -1.0 } else { 1.0 };
    let theta_i = cos_i.acos();
    let theta_b = brewster_angle(n1, n2);
    let jump_perp = n1 < n2;
    let jump_par = (n1 < n2 && theta_i < theta_b) || (n1 > n2 && theta_i > theta_b);
    // In the continuing frame p' = −p_r the paper's E∥ amplitude is ±|r_p|; in p_r it is ∓|r_p|.
    FresnelCoefficients {
        r_s: Complex64::from(sign(jump_perp) * exact.r_s.norm()),
        r_p: Complex64::from(-sign(jump_par) * exact.r_p.norm()),
        t_s: Complex64::from(exact.t_s.norm()),
        t_p: Complex64::from(exact.t_p.norm()),
        ..exact
    }
}

/// An ideal (perfectly conducting) mirror: the n2 → ∞ limit of (P1), (P2):
/// r_s = −1, r_p = +1 in this crate's frame (so at normal incidence E_r = −E_i), no transmission.
pub fn ideal_mirror() -> FresnelCoefficients {
    FresnelCoefficients {
        r_s: Complex64::from(-1.0),
        r_p: Complex64::from(1.0),
        t_s: Complex64::from(0.0),
        t_p: Complex64::from(0.0),
        cos_theta_t: Complex64::from(0.0),
        total_internal_reflection: false,
    }
}

/// An ideal thin lossless beam splitter of power reflectance `reflectance` (zero thickness,
/// no deviation): seen from the front (the side the normal points to) it reflects like an
/// attenuated perfect mirror, r_s = −√R, r_p = +√R; from the back with the opposite signs
/// (Stokes: r' = −r); t_s = t_p = √(1−R), so t t' − r r' = 1 and R + T = 1.
pub(crate) fn ideal_splitter(reflectance: f64, from_front: bool) -> FresnelCoefficients {
    let r = reflectance.sqrt() * if from_front { 1.0 } else { -1.0 };
    let t = Complex64::from((1.0 - reflectance).sqrt());
    FresnelCoefficients {
        r_s: Complex64::from(-r),
        r_p: Complex64::from(r),
        t_s: t,
        t_p: t,
        cos_theta_t: Complex64::from(1.0),
        total_internal_reflection: false,
    }
}

/// Mirror direction `d_r = d_i − 2 (d_i·N) N` (any orientation of N).
pub fn reflect(d_i: DVec3, normal: DVec3) -> DVec3 {
    d_i - 2.0 * d_i.dot(normal) * normal
}

/// Refracted direction by Snell's law (vector form, B&W §1.5.1), or `None` under total
/// internal reflection. `eta = n1/n2`; `normal` may have either orientation.
///
/// `d_t = η d_i + (η cos θi − cos θt) N_o` with `N_o` the normal facing the incident side.
/// Unlike `glam::DVec3::refract`, TIR is reported explicitly rather than as a zero vector.
pub fn refract(d_i: DVec3, normal: DVec3, n1: f64, n2: f64) -> Option<DVec3> {
    let n_o = if d_i.dot(normal) < 0.0 {
        normal
    } else {
        -normal
    };
    let cos_i = -d_i.dot(n_o);
    let c2t = cos2_theta_t(n1, n2, cos_i);
    if c2t < 0.0 {
        return None;
    }
    let eta = n1 / n2;
    Some((eta * d_i + (eta * cos_i - c2t.sqrt()) * n_o).normalize())
}

/// The s unit vector of docs/PHYSICS.md §1: `normalize(d_i × N)`, oriented so that it does not
/// depend on the orientation of N (`N` is first turned to face against `d_i`). At normal
/// incidence (|d_i × N| below 1e-12) the plane of incidence is undefined and `fallback`
/// (projected perpendicular to `d_i`) is used; any choice gives the same 3D fields.
pub fn s_direction(d_i: DVec3, normal: DVec3, fallback: DVec3) -> DVec3 {
    s_of_plane_of_incidence(d_i, normal).unwrap_or_else(|| s_at_normal_incidence(d_i, fallback))
}

/// The s vector of [`s_direction`] when the plane of incidence is defined (|d_i × N| > 1e-12,
/// tested on the square: no square root for the verdict), `None` at normal incidence, where
/// only the fallback decides: what every ray of direction `d_i` shares at this interface,
/// whatever its polarization frame.
#[inline]
pub(crate) fn s_of_plane_of_incidence(d_i: DVec3, normal: DVec3) -> Option<DVec3> {
    let n_o = if d_i.dot(normal) < 0.0 {
        normal
    } else {
        -normal
    };
    let c = d_i.cross(n_o);
    // Near normal incidence d_i × N has relative error ε/|d_i × N|: project out N again so s
    // stays ⟂ N and d_i to rounding (a no-op in exact arithmetic; tests/suite/interaction_props.rs).
    (c.length_squared() > 1e-24).then(|| (c - c.dot(n_o) * n_o).normalize())
}

/// The s vector of [`s_direction`] at normal incidence: `fallback` projected perpendicular to
/// `d_i` (any perpendicular if it is nearly parallel to `d_i`).
pub(crate) fn s_at_normal_incidence(d_i: DVec3, fallback: DVec3) -> DVec3 {
    let f = fallback - fallback.dot(d_i) * d_i;
    if f.length() > 1e-6 {
        f.normalize()
    } else {
        d_i.any_orthonormal_vector()
    }
}
