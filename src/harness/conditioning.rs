//! What the arithmetic allows: a bound on the rounding error of a traced intensity, derived
//! from the conditioning of the coherent sum at the probe (docs/PHYSICS.md §8, "Derived
//! tolerances").
//!
//! A scene is given in f64: every wavelength, index, thickness, coordinate and direction is
//! known to a relative u = 2⁻⁵³ only, so the traced value is at best the exact value of a scene
//! within a few u of the one written (backward error). The forward error this allows follows
//! from the conditioning of I = Σ_g |Σ_k E_k e^{2πi φ_k}|² (docs/PHYSICS.md §3, paper eq. 6) in
//! each arrival's phase and amplitude:
//!
//! * phase: a path difference ΔS_k = S_k − S_ref known to C·u relative moves φ_k by
//!   δφ_k = 2π C u (|ΔS_k|/λ + 1) rad (the 1: the phase reduced to a fraction of a cycle);
//! * amplitude: each of the m_k events multiplies by a Fresnel coefficient of a few u relative
//!   error, δa_k = C u (m_k + 1) |E_k|; a spreading factor from the path solver's
//!   finite-difference Jacobian (step h = 1e-6 of the launch parameters, residuals of f64
//!   coordinates of size X at distance ℓ, each rounded by u X) adds u X/(h ℓ) of |E_k| (half
//!   the relative error of S² = 1/det J, whose entries are differences of two residuals);
//! * the sum: adding n_g fields rounds by u n_g Σ_k |E_k|.
//!
//! With δE_g = Σ_k |E_k| δφ_k + δa_k + u n_g Σ_k |E_k|, |δI_g| ≤ 2|E_g| δE_g + δE_g², and the
//! bound is Σ_g of that (plus u I for the final sum). C = 8 covers the handful of roundings
//! each quantity passes through. The bound uses |E_g| itself (not Σ|E_k|), so at a dark fringe
//! it is as small as the arithmetic makes the error there.

use crate::accumulate::fidelity::Fidelity;
use crate::accumulate::phasor_from_cycles;
use crate::optics::double_double::DoubleDouble;
use crate::optics::ray::INCOHERENT;
use crate::trace::{self, Arrival};
use num_complex::Complex64;
use std::collections::BTreeMap;

/// Unit roundoff of f64, u = 2⁻⁵³.
pub const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;

/// Roundings per quantity the bound allows (module docs).
pub const ROUNDINGS: f64 = 8.0;

/// The path solver's finite-difference step of the launch parameters (`path::LaunchModel`'s
/// step for point sources, radians).
const SPREADING_STEP: f64 = 1e-6;

/// The bound (module docs) on the rounding error of the `vector` intensity of `arrivals` at
/// vacuum wavelength `lambda_m`, phases referred to the optical path `reference` (the first
/// arrival's, as the traced value refers them), in the units of the traced |E|².
pub fn intensity_rounding(arrivals: &[Arrival], reference: DoubleDouble, lambda_m: f64) -> f64 {
    let cu = ROUNDINGS * UNIT_ROUNDOFF;
    // Per coherence group: (Σ E_k e^{iφ}, Σ|E_k|, Σ|E_k|(δφ_k + δa_k), n).
    let mut groups: BTreeMap<u64, ([Complex64; 3], f64, f64, usize)> = BTreeMap::new();
    let mut singles = Vec::new();
    for a in arrivals {
        let c = trace::contribution_from(a, Fidelity::Vector, reference);
        let e = c.field.iter().map(|x| x.norm_sqr()).sum::<f64>().sqrt();
        let ds = (a.vector.optical_path - reference).to_f64().abs();
        let dphi = std::f64::consts::TAU * cu * (ds / lambda_m + 1.0);
        let mut da = cu * (a.path.sequence.len() as f64 + 1.0);
        if a.path.spreading != 1.0 {
            let x = a
                .path
                .points
                .iter()
                .fold(0.0f64, |m, p| m.max(p.abs().max_element()));
            let ell: f64 = a
                .path
                .points
                .iter()
                .zip(a.path.points.iter().skip(1))
                .map(|(p, q)| (*q - *p).length())
                .sum::<f64>()
                .max(f64::MIN_POSITIVE);
            let end = a.vector.origin.abs().max_element();
            da += UNIT_ROUNDOFF * x.max(end) / (SPREADING_STEP * ell);
        }
        // A closed Airy tail (docs/PHYSICS.md §5a): the sum q/(1 − q) of the further orders is
        // 1/|1 − q| more sensitive to the round trip's phase and amplitude than one order.
        if let Some(t) = &a.tail {
            da += t.field(&a.vector.field(), Fidelity::Vector, lambda_m).1;
        }
        let term = e * (dphi + da);
        if c.coherence_id == INCOHERENT {
            singles.push((e, term));
            continue;
        }
        let g = groups
            .entry(c.coherence_id)
            .or_insert(([Complex64::default(); 3], 0.0, 0.0, 0));
        let ph = phasor_from_cycles(c.phase_cycles);
        for (s, f) in g.0.iter_mut().zip(c.field) {
            *s += f * ph;
        }
        g.1 += e;
        g.2 += term;
        g.3 += 1;
    }
    let bound = |e_g: f64, de: f64| 2.0 * e_g * de + de * de;
    let mut total = 0.0;
    let mut intensity = 0.0;
    for (field, sum_abs, terms, n) in groups.values() {
        let e_g = field.iter().map(|x| x.norm_sqr()).sum::<f64>().sqrt();
        let de = terms + UNIT_ROUNDOFF * *n as f64 * sum_abs;
        total += bound(e_g, de);
        intensity += e_g * e_g;
    }
    for (e, term) in singles {
        total += bound(e, term + UNIT_ROUNDOFF * e);
        intensity += e * e;
    }
    total + UNIT_ROUNDOFF * intensity
}

/// The derived tolerance of an intensity profile: the largest per-point bound relative to the
/// profile's scale (the largest |reference|, as [`crate::harness::case::run::MetricResult::deviations`]
/// divides), never below `floor`.
pub fn relative_tolerance(rounding: &[f64], analytic: &[f64], floor: f64) -> f64 {
    let scale = analytic.iter().fold(1e-15f64, |m, a| m.max(a.abs()));
    rounding.iter().fold(floor, |m, r| m.max(r / scale))
}
