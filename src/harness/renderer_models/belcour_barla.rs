//! Belcour & Barla 2017: the thin-film model behind glTF `KHR_materials_iridescence`, OpenPBR
//! `thin_film_*` and several production renderers.
//!
//! L. Belcour, P. Barla, "A Practical Extension to Microfacet Theory for the Modeling of Varying
//! Iridescence", ACM Trans. Graph. 36(4), 65 (SIGGRAPH 2017), §4 and its supplemental code; the
//! glTF 2.0 extension `KHR_materials_iridescence`, sections "Iridescence Fresnel" and "Analytic
//! Spectral Integration" (the reference implementation `evalIridescence`/`evalSensitivity`).
//!
//! **The Airy sum as a Fourier series.** For one polarization, with power reflectances
//! R12 = |r12|², R23 = |r23|², T121 = 1 − R12, and the phases φ21 = arg r21 = π − φ12,
//! φ23 = arg r23 (0 or π outside TIR, P5/P6 under TIR), the exact reflectance of the layer is
//!
//! ```text
//! R(λ) = C0 + 2 Σ_{m≥1} C_m cos(m ψ),   ψ = 2π OPD/λ + φ2,   OPD = 2 n2 d cos θ2,  φ2 = φ21 + φ23
//! C0 = R12 + R_s,   R_s = T121² R23/(1 − R12 R23),   C_m = (R_s − T121) (R12 R23)^{m/2}   (BB1)
//! ```
//!
//! (Belcour & Barla eqs. 6–9; ψ is the phase of r21 r23 e^{iβ} of docs/PHYSICS.md §5, β = 2π OPD/λ,
//! so the full series equals |r|² of the Airy sum: [`reflectance`] with many orders is a check
//! of the exact closed form.) The model keeps `ORDERS` = 3 orders (the paper's code; the glTF
//! sample code keeps 2).
//!
//! **Spectral integration with fitted sensitivities.** Instead of integrating R(λ) against the
//! colour-matching functions, each cosine term is integrated in closed form against Gaussian
//! fits of x̄, ȳ, z̄ over wavenumber ([`sensitivity`], the glTF `evalSensitivity` constants,
//! normalised so that S(0) ≈ (1, 1, 1), the equal-energy white). As in the glTF reference, the
//! constant term C0 is added as an RGB grey (white = linear sRGB (1, 1, 1), the D65 white) and
//! the oscillating terms, whose sensitivities are fitted for the equal-energy illuminant, as
//! XYZ → linear sRGB; negative RGB is clamped to 0. `colour_xyz`
//! returns that colour back in XYZ (D65 white, Y = 1 for a perfect reflector) to compare with the
//! exact colour. Both polarizations are evaluated with the exact Fresnel amplitudes and averaged
//! (the paper's code; the glTF sample code uses Schlick's approximation of the averaged R
//! instead, which is not modelled here).

use super::Film;
use crate::colour::XYZ_TO_LINEAR_SRGB;
use crate::optics::fresnel::{cos2_theta_t, fresnel};
use std::f64::consts::PI;

/// Fourier orders m the model keeps (Belcour & Barla's supplemental code: m = 1..3).
pub(crate) const ORDERS: usize = 3;

/// The coefficients of (BB1) for one polarization.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FourierTerms {
    /// C0 = R12 + R_s: the mean of R(λ) over a fringe period (dimensionless).
    pub c0: f64,
    /// C_m/ρ^m = R_s − T121: the amplitude of the first harmonic before the decay ρ^m.
    pub c_scale: f64,
    /// ρ = √(R12 R23) = |r21 r23|: the decay of the harmonics.
    pub rho: f64,
    /// φ2 = φ21 + φ23 (rad): the phase the interfaces add to each round trip.
    pub phi2: f64,
    /// OPD = 2 n2 d cos θ2 (m): the optical path of one round trip.
    pub opd_m: f64,
}

impl FourierTerms {
    /// C_m = (R_s − T121) ρ^m for m ≥ 1.
    pub fn c(&self, m: usize) -> f64 {
        self.c_scale * self.rho.powi(m as i32)
    }
}

/// (BB1) for s (`[0]`) and p (`[1]`) at incidence cos θ1; `None` under total internal
/// reflection at the front face (the glTF reference then returns R = 1).
pub fn terms(film: &Film, cos_theta_1: f64) -> Option<[FourierTerms; 2]> {
    let c2 = cos2_theta_t(film.n1, film.n2, cos_theta_1);
    if c2 < 0.0 {
        return None;
    }
    let cos_theta_2 = c2.sqrt();
    let f12 = fresnel(film.n1, film.n2, cos_theta_1);
    let f21 = fresnel(film.n2, film.n1, cos_theta_2);
    let f23 = fresnel(film.n2, film.n3, cos_theta_2);
    let opd_m = 2.0 * film.n2 * film.thickness_m * cos_theta_2;
    let one =
        |r12: num_complex::Complex64, r21: num_complex::Complex64, r23: num_complex::Complex64| {
            let r12_pow = r12.norm_sqr();
            let r23_pow = r23.norm_sqr();
            let t121 = 1.0 - r12_pow;
            let r_s = if r23_pow >= 1.0 {
                t121
            } else {
                t121 * t121 * r23_pow / (1.0 - r12_pow * r23_pow)
            };
            // arg of an exactly zero coefficient is 0, as the paper's sign test gives.
            let phase = |r: num_complex::Complex64| if r == 0.0.into() { 0.0 } else { r.arg() };
            FourierTerms {
                c0: r12_pow + r_s,
                c_scale: r_s - t121,
                rho: (r12_pow * r23_pow).sqrt(),
                phi2: phase(r21) + phase(r23),
                opd_m,
            }
        };
    Some([
        one(f12.r_s, f21.r_s, f23.r_s),
        one(f12.r_p, f21.r_p, f23.r_p),
    ])
}

/// Unpolarized R(λ) of (BB1) truncated after `orders` harmonics (dimensionless); with the
/// spectral integration bypassed this is the model's Airy sum at one vacuum wavelength `lambda_m`
/// (m). R = 1 under total internal reflection at the front face.
pub fn reflectance(film: &Film, cos_theta_1: f64, lambda_m: f64, orders: usize) -> f64 {
    let Some(t) = terms(film, cos_theta_1) else {
        return 1.0;
    };
    let one = |t: &FourierTerms| {
        let psi = 2.0 * PI * t.opd_m / lambda_m + t.phi2;
        t.c0 + (1..=orders)
            .map(|m| 2.0 * t.c(m) * (m as f64 * psi).cos())
            .sum::<f64>()
    };
    0.5 * (one(&t[0]) + one(&t[1]))
}

/// The fitted sensitivity S(OPD, shift) of glTF `evalSensitivity` (XYZ, equal-energy white
/// S(0, 0) ≈ (1, 1, 1)): Gaussians in wavenumber ν (1/m) with amplitude `val`, centre `pos`
/// and variance `var`, integrated in closed form against cos(2π OPD ν + shift), fitted so that
/// S ≈ ∫ x̄(λ) cos(2π OPD/λ + shift) dλ / ∫ ȳ dλ (and likewise ȳ, z̄): the colour of a cosine
/// spectrum under the equal-energy illuminant. `opd_m` in metres (the glTF code takes nanometres and multiplies by 1e-9), `shift`
/// in radians.
pub fn sensitivity(opd_m: f64, shift: f64) -> [f64; 3] {
    const VAL: [f64; 3] = [5.4856e-13, 4.4201e-13, 5.2481e-13];
    const POS: [f64; 3] = [1.6810e+06, 1.7953e+06, 2.2084e+06];
    const VAR: [f64; 3] = [4.3278e+09, 9.3046e+09, 6.6121e+09];
    const NORM: f64 = 1.0685e-7;
    let phase = 2.0 * PI * opd_m;
    let gauss = |val: f64, pos: f64, var: f64| {
        val * (2.0 * PI * var).sqrt() * (pos * phase + shift).cos() * (-phase * phase * var).exp()
    };
    let mut xyz: [f64; 3] = std::array::from_fn(|c| gauss(VAL[c], POS[c], VAR[c]));
    xyz[0] += gauss(9.7470e-14, 2.2399e+06, 4.5282e+09);
    xyz.map(|v| v / NORM)
}

fn mat_vec(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
}

/// Inverse of a 3×3 matrix by cofactors.
fn inverse(m: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let c = |r: usize, k: usize| {
        let (r1, r2) = ((r + 1) % 3, (r + 2) % 3);
        let (k1, k2) = ((k + 1) % 3, (k + 2) % 3);
        m[r1][k1] * m[r2][k2] - m[r1][k2] * m[r2][k1]
    };
    let det = m[0][0] * c(0, 0) + m[0][1] * c(0, 1) + m[0][2] * c(0, 2);
    std::array::from_fn(|r| std::array::from_fn(|k| c(k, r) / det))
}

/// The model's colour of the layer: linear sRGB I = C0·(1, 1, 1) + Σ_{m=1}^{orders} 2 C_m M·S(m
/// OPD, m φ2), averaged over s and p, clamped at 0 (glTF `evalIridescence`), returned as XYZ
/// with the D65 white of the sRGB matrix M (Y = 1 for a perfect reflector). Under total
/// internal reflection at the front face: the white (R = 1).
pub(crate) fn colour_xyz(film: &Film, cos_theta_1: f64, orders: usize) -> [f64; 3] {
    let to_xyz = inverse(&XYZ_TO_LINEAR_SRGB);
    let Some(t) = terms(film, cos_theta_1) else {
        return mat_vec(&to_xyz, [1.0; 3]);
    };
    let mut rgb = [0.0; 3];
    for pol in &t {
        let mut xyz = [0.0; 3];
        for m in 1..=orders {
            let s = sensitivity(m as f64 * pol.opd_m, m as f64 * pol.phi2);
            for c in 0..3 {
                xyz[c] += 2.0 * pol.c(m) * s[c];
            }
        }
        let osc = mat_vec(&XYZ_TO_LINEAR_SRGB, xyz);
        for c in 0..3 {
            rgb[c] += 0.5 * (pol.c0 + osc[c]);
        }
    }
    mat_vec(&to_xyz, rgb.map(|v| v.max(0.0)))
}
