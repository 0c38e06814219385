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
//! * the sum: adding n_g fields rounds by u n_g Σ_k |E_k|;
//! * the event points: every hit point is an f64 point, off the exact path along its plane by a
//!   rounding of its coordinates, u X (X the largest coordinate of the path). The optical path
//!   does not feel it to first order (Fermat; the offset across the plane is corrected,
//!   `Plane::off_plane_path_correction`), but the launch that lands the path on its target
//!   from such a point tilts by up to u X/ℓ (ℓ the path's length), and with it every incidence
//!   cosine: each event's Fresnel coefficient moves by κ_e C u X/ℓ relative, κ_e = |∂coef/∂cos θ|
//!   / |coef| of that event ([`fresnel_sensitivity`]). A 1 µm Lloyd source 100 m from the
//!   origin, 1 cm from its screen, has u X/ℓ = 1.1e-12 (the tracer's incidence cosine was
//!   6.7e-12 off, `fringe fuzz --family lloyd --seed 1`, scene 218): no f64 hit point does
//!   better, and a scene near the origin has X ≤ ℓ.
//!
//! With δE_g = Σ_k |E_k| δφ_k + δa_k + u n_g Σ_k |E_k|, |δI_g| ≤ 2|E_g| δE_g + δE_g², and the
//! bound is Σ_g of that (plus u I for the final sum). C = 8 covers the handful of roundings
//! each quantity passes through. The bound uses |E_g| itself (not Σ|E_k|), so at a dark fringe
//! it is as small as the arithmetic makes the error there.

use crate::accumulate::fidelity::Fidelity;
use crate::accumulate::phasor_from_cycles;
use crate::optics::double_double::{DoubleDouble, two_prod};
use crate::optics::fresnel;
use crate::optics::interaction::{Layer, SurfaceOptics, indices_for};
use crate::optics::ray::INCOHERENT;
use crate::scene::{Scene, SceneOptics};
use crate::trace::path::EventKind;
use crate::trace::{self, Arrival};
use glam::DVec3;
use num_complex::Complex64;
use std::collections::BTreeMap;

/// Unit roundoff of f64, u = 2⁻⁵³.
pub const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;

/// Roundings per quantity the bound allows (module docs).
pub const ROUNDINGS: f64 = 8.0;

/// The path solver's finite-difference step of the launch parameters (`path::LaunchModel`'s
/// step for point sources, radians).
const SPREADING_STEP: f64 = 1e-6;

/// κ = |∂coef/∂cos θi| / |coef| of the Fresnel coefficients (s and p, the larger of each) that
/// event `kind` at a surface of `optics` with unit `normal` applies to a ray along `d_in` in
/// index `n_in` (module docs, "the event points"): a central difference of ±1e-6 in cos θi
/// (one-sided at 0 and 1), so at a critical angle it is large but finite. 0 for an ideal mirror
/// or splitter, whose coefficients do not depend on the angle, and between equal indices.
pub fn fresnel_sensitivity(
    optics: SurfaceOptics,
    kind: EventKind,
    normal: DVec3,
    d_in: DVec3,
    n_in: f64,
) -> f64 {
    layer_sensitivity(optics, kind, normal, d_in, n_in, None)
}

/// [`fresnel_sensitivity`] of an event at a face with the layer `layer` behind it on the
/// incident ray's far side ([`crate::scene::SceneOptics::layers`]): beyond the critical angle
/// its reflection is the layer's frustrated one ([`fresnel::frustrated_layer`],
/// docs/PHYSICS.md §5), whose e^{−2κd} makes it more sensitive to the angle than r12.
pub fn layer_sensitivity(
    optics: SurfaceOptics,
    kind: EventKind,
    normal: DVec3,
    d_in: DVec3,
    n_in: f64,
    layer: Option<Layer>,
) -> f64 {
    let SurfaceOptics::Dielectric { .. } = optics else {
        return 0.0;
    };
    let (n1, n2) = indices_for(optics, normal, d_in, n_in);
    if n1 == n2 {
        return 0.0;
    }
    let coefficients = |c: f64| {
        let f = fresnel::fresnel(n1, n2, c);
        match (kind, layer) {
            (EventKind::Reflect, Some(l)) if f.total_internal_reflection => {
                let q2_i = two_prod(n1 * c, n1 * c);
                let q2_t = q2_i + two_prod(n2, n2) - two_prod(n1, n1);
                let q2_3 = q2_i + two_prod(l.n_beyond, l.n_beyond) - two_prod(n1, n1);
                let fl = fresnel::frustrated_layer(
                    (n1, n2, l.n_beyond),
                    (q2_i, q2_t, q2_3),
                    l.thickness_m,
                    l.lambda_m,
                );
                [f.r_s + fl.dr[0], f.r_p + fl.dr[1]]
            }
            (EventKind::Reflect, _) => [f.r_s, f.r_p],
            (EventKind::Refract, _) => [f.t_s, f.t_p],
        }
    };
    let c = (d_in.dot(normal).abs() / d_in.length()).min(1.0);
    const STEP: f64 = 1e-6;
    let (lo, hi) = ((c - STEP).max(0.0), (c + STEP).min(1.0));
    let size = coefficients(c).iter().fold(0.0f64, |m, z| m.max(z.norm()));
    if size == 0.0 || hi <= lo {
        return 0.0;
    }
    let (a, b) = (coefficients(lo), coefficients(hi));
    let slope = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((y - x).norm()));
    slope / (hi - lo) / size
}

/// The bound (module docs) on the rounding error of the `vector` intensity of `arrivals` at
/// vacuum wavelength `lambda_m`, phases referred to the optical path `reference` (the first
/// arrival's, as the traced value refers them), in the units of the traced |E|². `scene` and
/// `optics` are the ones traced (the surfaces the events name).
pub fn intensity_rounding(
    arrivals: &[Arrival],
    reference: DoubleDouble,
    lambda_m: f64,
    scene: &Scene,
    optics: &SceneOptics,
) -> f64 {
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
        if a.path.spreading != 1.0 {
            let end = a.vector.origin.abs().max_element();
            da += UNIT_ROUNDOFF * x.max(end) / (SPREADING_STEP * ell);
        }
        // A closed Airy tail (docs/PHYSICS.md §5a): the sum q/(1 − q) of the further orders is
        // 1/|1 − q| more sensitive to the round trip's phase and amplitude than one order.
        if let Some(t) = &a.tail {
            da += t.field(&a.vector.field(), Fidelity::Vector, lambda_m).1;
        }
        // The event points' rounding tilts every incidence cosine by up to C u X/ℓ where the
        // directions are solved through the points (point and line sources); a plane wave's
        // directions follow from its own direction and Snell's law, whatever the points.
        let plane_wave = matches!(
            scene.sources.get(a.source).map(|s| &s.emitter),
            Some(crate::scene::source::Emitter::PlaneWave { .. })
        );
        let tilt = if plane_wave { 0.0 } else { cu * x / ell };
        for (i, ev) in a.path.sequence.iter().enumerate().filter(|_| tilt > 0.0) {
            let (Some(so), Some(d_in), Some(&n_in)) = (
                optics.surfaces.get(ev.surface).copied().flatten(),
                a.path.dirs.get(i),
                a.path.indices.get(i),
            ) else {
                continue;
            };
            let normal = scene.surfaces[ev.surface].plane.normal;
            let layer = optics.layers[ev.surface][usize::from(d_in.dot(normal) >= 0.0)];
            da += tilt * layer_sensitivity(so, ev.kind, normal, *d_in, n_in, layer);
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
