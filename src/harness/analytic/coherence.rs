//! Temporal coherence (docs/PHYSICS.md §3): visibility of two-beam fringes against the optical path
//! difference Δs, under the paper's rule (P9) and for a Gaussian spectrum.

/// |γ(Δs)| for a spectrum Gaussian in wavenumber with FWHM Δλ around λ0 (docs/PHYSICS.md §3):
/// exp(−(π Δs Δλ/λ0²)²/(4 ln 2)).
pub fn gaussian_visibility(delta_s_m: f64, lambda0_m: f64, fwhm_m: f64) -> f64 {
    let x = std::f64::consts::PI * delta_s_m * fwhm_m / (lambda0_m * lambda0_m);
    (-(x * x) / (4.0 * std::f64::consts::LN_2)).exp()
}

/// Coherence length commonly associated with the bandwidth, λ0²/Δλ (m).
pub fn coherence_length(lambda0_m: f64, fwhm_m: f64) -> f64 {
    lambda0_m * lambda0_m / fwhm_m
}

/// Two-beam intensity with partial coherence: I1 + I2 + 2√(I1 I2)|γ| cos δ (P10 generalised).
pub fn two_beam(i1: f64, i2: f64, gamma: f64, delta: f64) -> f64 {
    i1 + i2 + 2.0 * (i1 * i2).sqrt() * gamma * delta.cos()
}

/// sin(2π f) in double-double for a fraction of a cycle `f` (|f| ≤ ½ after the whole cycles are
/// removed): the Taylor series of sin x at x = 2π f (2π in double-double), summed until a term
/// falls below 2⁻¹⁴⁰ ≈ 7e-43 of the sum (at most 60 terms, whose truncation is below 1e-40 for
/// |x| ≤ π). The series alternates with decreasing terms from the third on, so what is left out
/// is below the last term taken: ~2⁻³⁴ of one unit in the last place of the double-double sum,
/// after ~27 terms at |x| = π and fewer for smaller |x| (the closed form of `coherence_length`
/// evaluates it at every probe point and wavelength). Accurate to ~1e-31 absolute.
pub(crate) fn sin_cycles_dd(f: twofloat::TwoFloat) -> twofloat::TwoFloat {
    use twofloat::TwoFloat;
    // 2π = TAU + 2.4492935982947064e-16 (the low part of 2π in double-double).
    let tau = TwoFloat::new_add(std::f64::consts::TAU, 2.449_293_598_294_706_4e-16);
    let x = f * tau;
    let x2 = x * x;
    let mut term = x;
    let mut sum = x;
    // 2⁻¹⁴⁰: the relative size of a term that no longer matters to the double-double sum.
    const NEGLIGIBLE: f64 = 7.174_648_137_343_064e-43;
    for k in 1..60 {
        let d = ((2 * k) * (2 * k + 1)) as f64;
        term = -super::precise::div(term * x2, d.into());
        sum += term;
        if k >= 2 && term.hi().abs() <= NEGLIGIBLE * sum.hi().abs() {
            break;
        }
    }
    sum
}

/// One spectral sample of the two-beam reflectance of a plate at normal incidence (docs/PHYSICS.md
/// §3, the `coherence_gaussian` reference): beams a1 = r12 and a2 = t12 r23 t21 (real at normal
/// incidence, `n1` above, `n2` the plate, `n3` below) with the phase δ = 4π n2 d/λ, as
/// (a1 + a2)² − 4 a1 a2 sin²(δ/2), everything in double-double: the optical thickness `n2_d`
/// (m, as held), the Fresnel coefficients, sin(δ/2) (`sin_cycles_dd`) and the difference.
/// Near a dark fringe the two terms cancel to ~1e-5 of each (a plate between a dense ambient
/// and a rare substrate): in f64 that cancellation cost 1e-11 of the value, more than the
/// tracer's own error (`fringe fuzz --family coherence_gaussian`, checked at 50 digits).
pub fn two_beam_normal_reflectance(
    n1: f64,
    n2: f64,
    n3: f64,
    n2_d: twofloat::TwoFloat,
    lambda_m: f64,
) -> f64 {
    TwoBeamNormal::new(n1, n2, n3).reflectance(n2_d, lambda_m)
}

/// The two beams of [`two_beam_normal_reflectance`] for one set of indices: a1 = r12 and
/// a2 = t12 r23 t21 in double-double. Formed once and reused across the wavelengths of a
/// spectrum where the indices do not change (non-dispersive media): the same numbers, so the
/// same reflectance to the bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoBeamNormal {
    /// Indices above, inside and below the plate.
    pub indices: [f64; 3],
    a1: twofloat::TwoFloat,
    a2: twofloat::TwoFloat,
}

impl TwoBeamNormal {
    /// The beams' amplitudes for the indices `n1` (above), `n2` (the plate), `n3` (below).
    pub fn new(n1: f64, n2: f64, n3: f64) -> Self {
        use super::precise::div;
        use twofloat::TwoFloat;
        let (t1, t2, t3) = (TwoFloat::from(n1), TwoFloat::from(n2), TwoFloat::from(n3));
        let s12 = t1 + t2;
        let a1 = div(t1 - t2, s12);
        // t12 r23 t21 = (2 n1/(n1+n2)) ((n2−n3)/(n2+n3)) (2 n2/(n1+n2)).
        let a2 = div(t1 * t2 * 4.0 * (t2 - t3), s12 * s12 * (t2 + t3));
        TwoBeamNormal {
            indices: [n1, n2, n3],
            a1,
            a2,
        }
    }

    /// (a1 + a2)² − 4 a1 a2 sin²(δ/2) at vacuum wavelength `lambda_m` for the optical thickness
    /// `n2_d` (m, as held), δ = 4π n2 d/λ ([`two_beam_normal_reflectance`]).
    pub fn reflectance(&self, n2_d: twofloat::TwoFloat, lambda_m: f64) -> f64 {
        let (a1, a2) = (self.a1, self.a2);
        let cycles = super::precise::div(n2_d, lambda_m.into());
        let frac = cycles - cycles.hi().round();
        let s = sin_cycles_dd(frac);
        let sum = a1 + a2;
        f64::from(sum * sum - a1 * a2 * s * s * 4.0)
    }
}
