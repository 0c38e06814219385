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
//!   cosine: each event's Fresnel coefficient moves by up to its change over θ ± C u X/ℓ,
//!   relative ([`tilt_change`]; ≈ κ_e C u X/ℓ, κ_e = |∂coef/∂cos θ| / |coef| of
//!   [`fresnel_sensitivity`], away from critical angles). A 1 µm Lloyd source 100 m from the
//!   origin, 1 cm from its screen, has u X/ℓ = 1.1e-12 (the tracer's incidence cosine was
//!   6.7e-12 off, `fringe fuzz --family lloyd --seed 1`, scene 218): no f64 hit point does
//!   better, and a scene near the origin has X ≤ ℓ.
//!
//! With δE_g = Σ_k |E_k| δφ_k + δa_k + u n_g Σ_k |E_k|, |δI_g| ≤ 2|E_g| δE_g + δE_g², and the
//! bound is Σ_g of that (plus u I for the final sum). C = 8 covers the handful of roundings
//! each quantity passes through. The bound uses |E_g| itself (not Σ|E_k|), so at a dark fringe
//! it is as small as the arithmetic makes the error there.
//!
//! [`direction_sensitivity`] is a different quantity, kept apart: not a rounding of the tracer
//! but how far the exact observable moves when the scene's plane-wave direction turns by the
//! rounding an f64 scene holds it to (docs/PHYSICS.md §8, "Representation sensitivity").

use crate::accumulate::fidelity::Fidelity;
use crate::accumulate::{Contribution, phasor_from_cycles};
use crate::optics::double_double::{DoubleDouble, two_prod};
use crate::optics::fresnel;
use crate::optics::interaction::{Layer, SurfaceOptics, indices_for};
use crate::optics::ray::INCOHERENT;
use crate::scene::{Scene, SceneOptics};
use crate::trace::Arrival;
use crate::trace::path::EventKind;
use glam::DVec3;
use num_complex::Complex64;
use std::collections::{BTreeMap, HashMap};

/// Unit roundoff of f64, u = 2⁻⁵³.
pub(crate) const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;

/// Roundings per quantity the bound allows (module docs).
pub(crate) const ROUNDINGS: f64 = 8.0;

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
        let q2_i = two_prod(n1 * c, n1 * c);
        let q2_t = q2_i + two_prod(n2, n2) - two_prod(n1, n1);
        let q2_3 = layer.map(|l| q2_i + two_prod(l.n_beyond, l.n_beyond) - two_prod(n1, n1));
        event_coefficients(kind, layer, (n1, n2), c, (q2_i, q2_t, q2_3))
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

/// The coefficients (s, p) event `kind` applies between indices (n1, n2) at incidence cosine
/// `c`, with the normal wavevector squares (q_i², q_t², q_3²) = (n cos θ)² in the incident,
/// transmitted and beyond-the-layer media: r or t, or beyond the critical angle with `layer`
/// behind the face the frustrated layer's r_layer or t_layer ([`fresnel::frustrated_layer`],
/// docs/PHYSICS.md §5; q_3² is `Some` whenever `layer` is).
fn event_coefficients(
    kind: EventKind,
    layer: Option<Layer>,
    (n1, n2): (f64, f64),
    c: f64,
    (q2_i, q2_t, q2_3): (DoubleDouble, DoubleDouble, Option<DoubleDouble>),
) -> [Complex64; 2] {
    let f = fresnel::fresnel_with_cos2_t(n1, n2, c, q2_t.to_f64() / (n2 * n2));
    match (kind, layer, q2_3) {
        (EventKind::Reflect | EventKind::Tunnel, Some(l), Some(q2_3))
            if f.total_internal_reflection =>
        {
            let fl = fresnel::frustrated_layer(
                (n1, n2, l.n_beyond),
                (q2_i, q2_t, q2_3),
                l.thickness_m,
                l.lambda_m,
            );
            if kind == EventKind::Tunnel {
                fl.t
            } else {
                [f.r_s + fl.dr[0], f.r_p + fl.dr[1]]
            }
        }
        (EventKind::Tunnel, ..) => [Complex64::from(0.0); 2],
        (EventKind::Reflect, ..) => [f.r_s, f.r_p],
        (EventKind::Refract, ..) => [f.t_s, f.t_p],
    }
}

/// The relative change of the coefficients of event `kind` (as [`layer_sensitivity`]: s and p,
/// the larger, over the larger |coef|) when the incident direction `d_in` turns by `tilt` rad
/// within its plane of incidence, either way: max over ± of |coef(θ ± tilt) − coef(θ)|. The
/// secant over the turn itself, not `tilt` times a derivative taken over a fixed step: within
/// a few 1e-7 of a critical angle the coefficients go as sqrt(cos²θt) (docs/PHYSICS.md §5), a
/// ±1e-6 difference of cos θi averages that singularity away, and the tilt of the event points
/// of a scene translated 10 m moved the tracer's intensity 15× further than tilt × the
/// difference quotient (fuzz `two_beam_plate` seed 1 scene 4441: 1.4 over 0.001 at 2.6e-7 below
/// the top face's critical angle, tilt 2e-11 rad, 1.8e-5 of I;
/// `tests/suite/truth_point_sources.rs`). sin θ and cos θ are turned separately and
/// cos²θt = (n2² − n1² sin²θ)/n2² is formed from sin θ with exact squares, so near normal
/// incidence (cos θi = 1 − 2.5e-7 there) the turn is resolved. 0 where [`layer_sensitivity`]
/// is (mirrors, splitters, equal indices) and for `tilt` = 0.
pub fn tilt_change(
    optics: SurfaceOptics,
    kind: EventKind,
    normal: DVec3,
    d_in: DVec3,
    n_in: f64,
    layer: Option<Layer>,
    tilt: f64,
) -> f64 {
    let SurfaceOptics::Dielectric { .. } = optics else {
        return 0.0;
    };
    let (n1, n2) = indices_for(optics, normal, d_in, n_in);
    if n1 == n2 || tilt <= 0.0 {
        return 0.0;
    }
    // Coefficients at (cos θi, sin θi), both in [0, 1].
    let coefficients = |c: f64, s: f64| {
        let q2_i = two_prod(n1 * c, n1 * c);
        let n1s = n1 * s;
        let q2_t = two_prod(n2, n2) - two_prod(n1s, n1s);
        let q2_3 = layer.map(|l| two_prod(l.n_beyond, l.n_beyond) - two_prod(n1s, n1s));
        event_coefficients(kind, layer, (n1, n2), c, (q2_i, q2_t, q2_3))
    };
    let len = d_in.length() * normal.length();
    let c = (d_in.dot(normal).abs() / len).min(1.0);
    let s = (d_in.cross(normal).length() / len).min(1.0);
    let here = coefficients(c, s);
    let size = here.iter().fold(0.0f64, |m, z| m.max(z.norm()));
    if size == 0.0 {
        return 0.0;
    }
    let (ct, st) = (tilt.cos(), tilt.sin());
    let turned = |sign: f64| {
        // θ ± tilt, clamped to [0, π/2].
        let s2 = (s * ct + sign * c * st).clamp(0.0, 1.0);
        let c2 = (c * ct - sign * s * st).clamp(0.0, 1.0);
        let there = coefficients(c2, s2);
        here.iter()
            .zip(there)
            .fold(0.0f64, |m, (a, b)| m.max((b - a).norm()))
    };
    turned(1.0).max(turned(-1.0)) / size
}

/// Whether arrival `a` comes from a plane-wave source of `scene`.
fn from_plane_wave(scene: &Scene, a: &Arrival) -> bool {
    matches!(
        scene.sources.get(a.source).map(|s| &s.emitter),
        Some(crate::scene::source::Emitter::PlaneWave { .. })
    )
}

/// The bound (module docs) on the rounding error of the `vector` intensity of `arrivals` at
/// vacuum wavelength `lambda_m`, phases referred to the optical path `reference` (the first
/// arrival's, as the traced value refers them), in the units of the traced |E|². `scene` and
/// `optics` are the ones traced (the surfaces the events name); `vector` holds the arrivals'
/// `vector` contributions in order (`trace::contribution_from(a, Fidelity::Vector, reference)`,
/// which the caller has formed already).
pub fn intensity_rounding(
    arrivals: &[Arrival],
    reference: DoubleDouble,
    vector: &[Contribution],
    lambda_m: f64,
    scene: &Scene,
    optics: &SceneOptics,
) -> f64 {
    let cu = ROUNDINGS * UNIT_ROUNDOFF;
    debug_assert_eq!(arrivals.len(), vector.len());
    let terms = arrivals.iter().zip(vector).map(|(a, c)| {
        let (ds, mut da, x, ell) = path_rounding(a, reference);
        // A closed Airy tail (docs/PHYSICS.md §5a): the sum q/(1 − q) of the further orders is
        // 1/|1 − q| more sensitive to the round trip's phase and amplitude than one order.
        if let Some(t) = &a.tail {
            da += t.field(&a.vector.field(), Fidelity::Vector, lambda_m).1;
        }
        // The event points' rounding tilts every incidence cosine by up to C u X/ℓ where the
        // directions are solved through the points (point and line sources); a plane wave's
        // directions follow from its own direction and Snell's law, whatever the points.
        let plane_wave = from_plane_wave(scene, a);
        let tilt = if plane_wave { 0.0 } else { cu * x / ell };
        let events = (tilt > 0.0).then(|| {
            a.path
                .sequence
                .iter()
                .zip(a.path.dirs.iter())
                .zip(a.path.indices.iter())
        });
        for ((ev, d_in), &n_in) in events.into_iter().flatten() {
            let Some(so) = optics.surfaces.get(ev.surface).copied().flatten() else {
                continue;
            };
            let normal = scene.surfaces[ev.surface].plane.normal;
            let layer = optics.layers[ev.surface][usize::from(d_in.dot(normal) >= 0.0)];
            da += tilt_change(so, ev.kind, normal, *d_in, n_in, layer, tilt);
        }
        (c, ds, da)
    });
    rounding_sum(terms, lambda_m)
}

/// The wavelength-free part of an arrival's rounding terms ([`intensity_rounding`]): |ΔS|,
/// its optical path from `reference` (m); δa before a closed tail's and the tilts' shares; X,
/// the largest coordinate of its event points; ℓ, its length.
fn path_rounding(a: &Arrival, reference: DoubleDouble) -> (f64, f64, f64, f64) {
    let cu = ROUNDINGS * UNIT_ROUNDOFF;
    let ds = (a.vector.optical_path - reference).to_f64().abs();
    let mut da = cu * (a.path.sequence.len() as f64 + 1.0);
    // X and ℓ in one walk over the points (a shared trail is walked from its end,
    // [`crate::optics::trail::Trail::iter`]).
    let mut x = 0.0f64;
    let mut previous: Option<DVec3> = None;
    let ell: f64 = a
        .path
        .points
        .iter()
        .filter_map(|q| {
            x = x.max(q.abs().max_element());
            previous.replace(*q).map(|p| (*q - p).length())
        })
        .sum::<f64>()
        .max(f64::MIN_POSITIVE);
    if a.path.spreading != 1.0 {
        let end = a.vector.origin.abs().max_element();
        da += UNIT_ROUNDOFF * x.max(end) / (SPREADING_STEP * ell);
    }
    (ds, da, x, ell)
}

/// The bound of [`intensity_rounding`] from each arrival's contribution, |ΔS| and δa.
fn rounding_sum<'c>(
    terms: impl Iterator<Item = (&'c Contribution, f64, f64)>,
    lambda_m: f64,
) -> f64 {
    let cu = ROUNDINGS * UNIT_ROUNDOFF;
    // Per coherence group: (Σ E_k e^{iφ}, Σ|E_k|, Σ|E_k|(δφ_k + δa_k), n).
    let mut groups: BTreeMap<u64, ([Complex64; 3], f64, f64, usize)> = BTreeMap::new();
    let mut singles = Vec::new();
    for (c, ds, da) in terms {
        let e = c.field.iter().map(|x| x.norm_sqr()).sum::<f64>().sqrt();
        let dphi = std::f64::consts::TAU * cu * (ds / lambda_m + 1.0);
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

/// The wavelength-free part of [`intensity_rounding`] for arrivals that all come from plane
/// waves (no tilt terms, which read the optics): per arrival |ΔS| and δa before a closed tail's
/// share. `None` where an arrival comes from another source. Valid for the same arrivals at
/// any wavelength ([`crate::trace::Arrival::set_wavelength`]).
#[derive(Clone, Debug, PartialEq)]
pub struct RoundingTerms {
    paths: Vec<(f64, f64)>,
}

impl RoundingTerms {
    /// The terms of `arrivals`, phases referred to `reference`, in `scene`.
    pub fn of(arrivals: &[Arrival], reference: DoubleDouble, scene: &Scene) -> Option<Self> {
        arrivals
            .iter()
            .all(|a| from_plane_wave(scene, a))
            .then(|| RoundingTerms {
                paths: arrivals
                    .iter()
                    .map(|a| {
                        let (ds, da, _, _) = path_rounding(a, reference);
                        (ds, da)
                    })
                    .collect(),
            })
    }

    /// [`intensity_rounding`] of the arrivals these terms were formed of, at `lambda_m`: the
    /// same value, bit for bit, with the paths read once.
    pub fn intensity_rounding(
        &self,
        arrivals: &[Arrival],
        vector: &[Contribution],
        lambda_m: f64,
    ) -> f64 {
        debug_assert_eq!(arrivals.len(), self.paths.len());
        let terms = arrivals
            .iter()
            .zip(vector)
            .zip(&self.paths)
            .map(|((a, c), &(ds, mut da))| {
                if let Some(t) = &a.tail {
                    da += t.field(&a.vector.field(), Fidelity::Vector, lambda_m).1;
                }
                (c, ds, da)
            });
        rounding_sum(terms, lambda_m)
    }
}

/// The derived tolerance of an intensity profile: the largest per-point bound relative to the
/// profile's scale (the largest |reference|, as [`crate::harness::case::run::MetricResult::deviations`]
/// divides), never below `floor`.
pub(crate) fn relative_tolerance(rounding: &[f64], analytic: &[f64], floor: f64) -> f64 {
    let scale = analytic.iter().fold(1e-15f64, |m, a| m.max(a.abs()));
    rounding.iter().fold(floor, |m, r| m.max(r / scale))
}

/// The turn (rad) by which a plane wave's direction, or a surface normal, is held off the one
/// written: one f64 normalization of each (the scene's `normalize`, `Plane::new`), u for the
/// direction and u for the normal it meets (docs/PHYSICS.md §8, "Representation sensitivity").
pub const DIRECTION_ROUNDING: f64 = 2.0 * UNIT_ROUNDOFF;

/// The *representation sensitivity* of the `vector` intensity of `arrivals` (docs/PHYSICS.md
/// §8): how far the exact intensity moves when the incident plane wave's direction turns by
/// [`DIRECTION_ROUNDING`], the rounding with which an f64 scene holds a direction it was given
/// in any frame but the axes. Not a rounding error of the tracer: the scene the tracer holds is
/// that far from the one written, and every f64 tracer holds it so.
///
/// First order and signed, so tight: by Hamilton's mixed characteristic an arrival whose
/// entry and exit points lie Δx_in, Δx_out from the reference arrival's (the first) changes its
/// optical path difference by δΔS_k = n_in (Δx_in·e_in) δθ − n_out (Δx_out·e_out) δθ_out when
/// the incident direction turns by δθ toward e_in (⊥ d_in) and the exit direction by δθ_out
/// toward e_out (the in-plane axis of the orders' walk); δθ_out = δθ n_in cos θ_in /
/// (n_out cos θ_out) through Snell's law at the first and last face (1 for a reflection). Then
/// δI = Σ_g 2 Re(E_g* · Σ_k i 2π δΔS_k/λ E_k e^{iφ_k}). 0 for point and line sources (the
/// gate judges the scene as held: a line source's closed form reads the same f64 point and
/// axis as the tracer, so a rounding of them moves both sides alike, docs/PHYSICS.md §8;
/// `tests/suite/truth_found_edges.rs`) and for a single arrival. A closed Airy tail counts
/// at the offsets of the order it starts from (its further orders carry at most the tail
/// bound's share of the field). `vector`: the arrivals' `vector` contributions, as for
/// [`intensity_rounding`].
pub fn direction_sensitivity(
    arrivals: &[Arrival],
    vector: &[Contribution],
    lambda_m: f64,
    scene: &Scene,
) -> f64 {
    match direction_offsets(arrivals, scene) {
        Some(offsets) => direction_sensitivity_of(&offsets, vector, lambda_m),
        None => 0.0,
    }
}

/// The wavelength-free part of [`direction_sensitivity`]: per arrival, n_in (Δx_in·e_in) −
/// n_out (Δx_out·e_out) δθ_out/δθ (m per rad); `None` where the sensitivity is 0 whatever the
/// wavelength (fewer than two arrivals, a source other than a plane wave). Valid for the same
/// arrivals at any wavelength ([`crate::trace::Arrival::set_wavelength`]).
pub fn direction_offsets(arrivals: &[Arrival], scene: &Scene) -> Option<Vec<f64>> {
    let first = arrivals.first()?;
    let plane_wave = |a: &Arrival| from_plane_wave(scene, a);
    if arrivals.len() < 2 || !arrivals.iter().all(plane_wave) {
        return None;
    }
    // Each arrival's entry and exit: points, unit directions and indices (read once: the
    // first element of a shared trail is a walk from its end).
    let ends_of = |a: &Arrival| {
        let p = &a.path;
        let (x0, x1) = (p.points[0], *p.points.last().unwrap());
        let (d0, d1) = (p.dirs[0].normalize(), p.dirs.last().unwrap().normalize());
        let (n0, n1) = (p.indices[0], *p.indices.last().unwrap());
        (x0, x1, d0, d1, n0, n1)
    };
    let all_ends: Vec<_> = arrivals.iter().map(ends_of).collect();
    let ends = |k: usize| all_ends[k];
    let (r_in, r_out, _, _, _, _) = ends(0);
    // The walk's in-plane axis at exit (and at entry): the largest offset from the first
    // arrival, perpendicular to the ray.
    let axis = |pick: &dyn Fn(usize) -> (DVec3, DVec3)| {
        (0..arrivals.len())
            .map(|k| {
                let (x, d) = pick(k);
                x - x.dot(d) * d
            })
            .max_by(|a, b| a.length().total_cmp(&b.length()))
            .filter(|v| v.length() > 0.0)
            .map(|v| v.normalize())
    };
    let e_out = axis(&|k| {
        let (_, x1, _, d1, _, _) = ends(k);
        (x1 - r_out, d1)
    });
    let e_in = axis(&|k| {
        let (x0, _, d0, _, _, _) = ends(k);
        (x0 - r_in, d0)
    });
    // δθ_out per δθ through the first and last face (Snell: n cos θ dθ is conserved).
    let turn_out = {
        let p = &first.path;
        match (p.sequence.first(), p.sequence.last()) {
            (Some(a), Some(b)) => {
                let (na, nb) = (
                    scene.surfaces[a.surface].plane.normal,
                    scene.surfaces[b.surface].plane.normal,
                );
                let (_, _, d0, d1, n0, n1) = ends(0);
                let (c0, c1) = (d0.dot(na).abs(), d1.dot(nb).abs());
                if c1 > 0.0 { (n0 * c0) / (n1 * c1) } else { 0.0 }
            }
            _ => 1.0,
        }
    };
    Some(
        all_ends
            .iter()
            .map(|&(x0, x1, _, _, n0, n1)| {
                let ds_in = e_in.map_or(0.0, |e| n0 * (x0 - r_in).dot(e));
                let ds_out = e_out.map_or(0.0, |e| n1 * (x1 - r_out).dot(e) * turn_out);
                ds_in - ds_out
            })
            .collect(),
    )
}

/// [`direction_sensitivity`] from its [`direction_offsets`] and the arrivals' `vector`
/// contributions at `lambda_m`: the same value, bit for bit.
pub fn direction_sensitivity_of(offsets: &[f64], vector: &[Contribution], lambda_m: f64) -> f64 {
    let mut groups: BTreeMap<u64, ([Complex64; 3], [Complex64; 3])> = BTreeMap::new();
    let mut total = 0.0;
    debug_assert_eq!(offsets.len(), vector.len());
    for (&offset, c) in offsets.iter().zip(vector) {
        if c.coherence_id == INCOHERENT {
            continue;
        }
        let dphi = std::f64::consts::TAU * offset * DIRECTION_ROUNDING / lambda_m;
        let ph = phasor_from_cycles(c.phase_cycles);
        let g = groups
            .entry(c.coherence_id)
            .or_insert(([Complex64::default(); 3], [Complex64::default(); 3]));
        for ((s, ds), f) in g.0.iter_mut().zip(g.1.iter_mut()).zip(c.field) {
            *s += f * ph;
            *ds += f * ph * Complex64::new(0.0, dphi);
        }
    }
    for (e, de) in groups.values() {
        total += e
            .iter()
            .zip(de)
            .map(|(x, dx)| 2.0 * (x.conj() * dx).re)
            .sum::<f64>();
    }
    total.abs()
}

/// The rounding of an incidence cosine |d̂·N̂| when the direction `d` and the normal `normal`
/// are each held one rounding off the ones written (docs/PHYSICS.md §8, "Representation
/// sensitivity"): one rounding of each component of each unit vector moves the dot product by
/// up to 2u Σ_i |d̂_i N̂_i|. In a frame where N is an axis that is 2u cos θ (relative 2u); in a
/// rotated frame it is ~u whatever θ, so near grazing (cos θ = 1.7e-9 at 89.9999999°) it is
/// u/cos θ of the cosine.
pub fn cosine_rounding(d: DVec3, normal: DVec3) -> f64 {
    let (d, n) = (d.normalize(), normal.normalize());
    DIRECTION_ROUNDING * (d * n).abs().element_sum()
}

/// The *amplitude* part of the representation sensitivity of the `vector` intensity of
/// `arrivals` (docs/PHYSICS.md §8; [`direction_sensitivity`] is the phase part): how far the
/// exact intensity moves through the Fresnel coefficients when the plane wave's incidence cosine
/// c1 on the first face moves by [`cosine_rounding`]. Between parallel faces Snell's invariant
/// carries that to every event, q_e² = q1² + n_e² − n1² (q = n cos θ), so dc_e = n1² c1
/// dc1/(n_e q_e), and each event's coefficient moves by κ_e |dc_e| of itself
/// ([`layer_sensitivity`], κ = |∂coef/∂cos θ|/|coef|). With ρ_k = Σ_e κ_e |dc_e| for arrival k,
/// δI ≤ Σ_g 2 |E_g| Σ_k ρ_k |E_k| (first order, unsigned). 0 for point and line sources, for
/// scenes whose faces are not all parallel to the first, and at normal incidence (a turn moves
/// the cosine only to second order there). In units of the traced |E|². `vector`: the
/// arrivals' `vector` contributions, as for [`intensity_rounding`].
pub fn amplitude_sensitivity(
    arrivals: &[Arrival],
    vector: &[Contribution],
    scene: &Scene,
    optics: &SceneOptics,
) -> f64 {
    let Some(first) = arrivals.first() else {
        return 0.0;
    };
    let plane_wave = |a: &Arrival| from_plane_wave(scene, a);
    let (Some(ev0), Some(d0), Some(&n1)) = (
        first.path.sequence.first(),
        first.path.dirs.first(),
        first.path.indices.first(),
    ) else {
        return 0.0;
    };
    let n0 = scene.surfaces[ev0.surface].plane.normal.normalize();
    let parallel = |a: &Arrival| {
        a.path.sequence.iter().all(|e| {
            let m = scene.surfaces[e.surface].plane.normal.normalize();
            (m - n0).length() < 1e-12 || (m + n0).length() < 1e-12
        })
    };
    // At normal incidence (and grazing) the term is 0 whatever the arrivals: decided before
    // the scan of every event below.
    let c1 = d0.normalize().dot(n0).abs();
    if c1 == 0.0 || c1 >= 1.0 {
        return 0.0;
    }
    if !arrivals.iter().all(|a| plane_wave(a) && parallel(a)) {
        return 0.0;
    }
    let dc1 = cosine_rounding(*d0, n0);
    let q1 = n1 * c1;
    // Between parallel faces every event at one surface, of one kind, from one side, in one
    // index meets the same angle (Snell's invariant), so its share κ_e |dc_e| is computed once:
    // the orders of an Airy sum repeat a few events hundreds of times.
    let mut shares: HashMap<(usize, EventKind, bool, u64), f64> = HashMap::new();
    let mut groups: BTreeMap<u64, ([Complex64; 3], f64)> = BTreeMap::new();
    let mut total = 0.0;
    debug_assert_eq!(arrivals.len(), vector.len());
    for (a, c) in arrivals.iter().zip(vector) {
        let e = c.field.iter().map(|x| x.norm_sqr()).sum::<f64>().sqrt();
        let mut rho = 0.0;
        // Zipped, not indexed: the far-field walk's paths are shared trails, where `get(i)` walks
        // back from the end (O(len) per event, O(m³) over an Airy sum's orders).
        let events = a
            .path
            .sequence
            .iter()
            .zip(a.path.dirs.iter())
            .zip(a.path.indices.iter());
        for ((ev, d_in), &n_in) in events {
            let Some(so) = optics.surfaces.get(ev.surface).copied().flatten() else {
                continue;
            };
            let normal = scene.surfaces[ev.surface].plane.normal;
            let side = d_in.dot(normal) >= 0.0;
            rho += *shares
                .entry((ev.surface, ev.kind, side, n_in.to_bits()))
                .or_insert_with(|| {
                    let layer = optics.layers[ev.surface][usize::from(side)];
                    let kappa = layer_sensitivity(so, ev.kind, normal, *d_in, n_in, layer);
                    let q_e = (q1 * q1 + (n_in - n1) * (n_in + n1)).abs().sqrt();
                    if q_e > 0.0 && kappa > 0.0 {
                        kappa * n1 * q1 / (n_in * q_e) * dc1
                    } else {
                        0.0
                    }
                });
        }
        if c.coherence_id == INCOHERENT {
            total += 2.0 * e * e * rho;
            continue;
        }
        let g = groups
            .entry(c.coherence_id)
            .or_insert(([Complex64::default(); 3], 0.0));
        let ph = phasor_from_cycles(c.phase_cycles);
        for (s, f) in g.0.iter_mut().zip(c.field) {
            *s += f * ph;
        }
        g.1 += e * rho;
    }
    for (field, de) in groups.values() {
        let e_g = field.iter().map(|x| x.norm_sqr()).sum::<f64>().sqrt();
        total += 2.0 * e_g * de + de * de;
    }
    total
}

/// The relative representation sensitivity of the far-field power factor
/// (n_out cos θ_out)/(n_in cos θ_in) that turns a transmitted |E|² into T (docs/PHYSICS.md §3a,
/// §8): with q = n cos θ and q_out² = q_in² + n_out² − n_in², d ln(q_out/q_in)/dc1 =
/// n_in q_in/q_out² − 1/c1 (signed), times [`cosine_rounding`]. Near grazing T ∝ cos θ_in and this
/// is ≈ dc1/c1. 0 where no transmitted wave propagates.
pub fn power_factor_sensitivity(d: DVec3, normal: DVec3, n_in: f64, n_out: f64) -> f64 {
    let c1 = d.normalize().dot(normal.normalize()).abs();
    let q1 = n_in * c1;
    let q2_out = q1 * q1 + (n_out - n_in) * (n_out + n_in);
    if c1 == 0.0 || q2_out <= 0.0 {
        return 0.0;
    }
    (n_in * q1 / q2_out - 1.0 / c1).abs() * cosine_rounding(d, normal)
}
