//! The reflected or transmitted orders of a plane wave between two parallel faces, observed in
//! the far field, traced by round trips: the first orders are traced by the general far-field
//! walk, and every further order is the deepest traced one after one more round trip, applied
//! exactly (docs/PHYSICS.md §5a, the round trip of eq. T1; §1 for the optical path).
//!
//! Between two parallel faces X and Y, every further round trip of a plane wave has the same
//! direction, the same Fresnel coefficients and the same optical path: order N + 1 leaves the
//! film with order N's exit field after the transformation
//!
//! E_{N+1} = Σ_σ A_σ (E_N·σ̂) σ̂,  A_σ = r_σ(X) r_σ(Y),  σ ∈ {s, p} of the exit direction,
//!
//! and an optical path to the far-field wavefront longer by ΔS = 2 d n cos θ (d the faces'
//! distance, n cos θ inside from the carried (n cos θ)², both in double-double, as
//! [`super::tail`] forms it). A_σ are the coefficients the tracer itself applied on the deepest
//! traced order's last round trip (its ledger). Each further order is one such step from the
//! previous one: a record per order, as the walk gives, not the closed sum of [`super::tail`].
//! The per-order work is one complex multiplication per σ and one double-double addition,
//! instead of the walk's three events (solve, extents, blockers, Fresnel, ledger, allocation).
//!
//! Where it applies (anything else is refused with the reason; the caller then runs the general
//! walk): far-field targets (a direction); plane-wave sources of infinite coherence length;
//! scenes of exactly two unbounded dielectric interfaces whose normals are the same line
//! (bitwise ±), no traced order tunnelling through a layer; the deepest traced order of each
//! source ending in a round trip between the faces followed only by refractions. Only the
//! `vector` model.
//!
//! [`spectrum`] gives the intensity spectrum of one far-field direction: for non-dispersive
//! media one trace and [`Beats::intensities`]; for dispersive media (Sellmeier, Cauchy, …) one
//! trace by round trips and a [`Sweep`] of the indices, coefficients and round trip over the
//! wavelengths where its structure holds ([`super::dispersive_sweep`]), a trace at every other
//! wavelength, each by round trips where they apply.

use super::beats::{Beats, SpectralContribution};
use super::dispersive_sweep::Sweep;
use super::tail::{film_thickness, last_two_reflections, one_film};
use super::{Arrival, TraceSettings, arrivals_with, phase_cycles, plan};
use crate::accumulate::Accumulator;
use crate::optics::double_double::DoubleDouble;
use crate::optics::material::{Dispersion, IndexError, Medium};
use crate::optics::ray::Field3;
use crate::scene::source::Emitter;
use crate::scene::{Scene, SceneOptics, SurfaceKind};
use crate::trace::path::{EnumerationLimits, EventKind, Target};
use glam::DVec3;
use num_complex::Complex64;

/// Internal reflections traced by the general walk before the round trips take over: reflected
/// orders 0, 1, 2 (0, 1, 3 internal reflections) and transmitted orders 0, 1, 2 (0, 2, 4), so
/// that every order family has its first round trip traced.
pub const TRACED_INTERNAL_REFLECTIONS: usize = 4;

/// Why the round trips do not apply (the general walk runs instead).
#[derive(Clone, Debug, PartialEq)]
pub struct NotApplicable(pub String);

impl std::fmt::Display for NotApplicable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

fn refuse<T>(msg: impl Into<String>) -> Result<T, NotApplicable> {
    Err(NotApplicable(msg.into()))
}

/// One ray arriving in the far field under the `vector` model: what a spectrum needs of an
/// [`Arrival`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FarFieldRay {
    /// Coherence id; 0 adds intensity only.
    pub coherence_id: u64,
    /// Optical path to the far-field wavefront (m), double-double ([`crate::optics::ray::Ray::optical_path`]).
    pub optical_path: DoubleDouble,
    /// Complex 3D field amplitude, path phase excluded ([`crate::optics::ray::Ray::field`]).
    pub field: Field3,
}

impl FarFieldRay {
    fn of(a: &Arrival) -> Self {
        FarFieldRay {
            coherence_id: a.vector.coherence_id,
            optical_path: a.vector.optical_path,
            field: a.vector.field(),
        }
    }
}

/// The `vector` rays of `arrivals` ([`FarFieldRay`]), in order.
pub fn far_field_rays(arrivals: &[Arrival]) -> Vec<FarFieldRay> {
    arrivals.iter().map(FarFieldRay::of).collect()
}

/// The rays as spectral contributions for any wavelength of a non-dispersive scene (as
/// [`super::beats::vector_rays`]): Δs is each optical path minus the first ray's, formed in
/// double-double and rounded once.
pub fn spectral_contributions(rays: &[FarFieldRay]) -> Vec<SpectralContribution> {
    let Some(first) = rays.first() else {
        return Vec::new();
    };
    rays.iter()
        .map(|r| SpectralContribution {
            coherence_id: r.coherence_id,
            delta_s_m: (r.optical_path - first.optical_path).to_f64(),
            extra_cycles: 0.0,
            field: r.field,
        })
        .collect()
}

/// The intensity |E|² of the rays at vacuum wavelength `lambda_m` (eqs. 5–6, compensated
/// sums), each phase measured from the first ray's optical path in double-double and reduced
/// to its fraction of a cycle before rounding ([`phase_cycles`]), as [`super::intensity`].
pub fn intensity(rays: &[FarFieldRay], lambda_m: f64, acc: &mut Accumulator) -> f64 {
    acc.clear();
    let Some(first) = rays.first() else {
        return acc.intensity();
    };
    for r in rays {
        acc.add_parts(
            r.coherence_id,
            phase_cycles(r.optical_path, first.optical_path, lambda_m),
            &r.field,
        );
    }
    acc.intensity()
}

/// The normal of the two faces if the scene and target admit round trips (module docs).
pub(super) fn check_scene(scene: &Scene, target: &Target) -> Result<DVec3, NotApplicable> {
    if !matches!(target, Target::Direction { .. }) {
        return refuse("round trips are traced only into the far field (the target is a point)");
    }
    for src in &scene.sources {
        if !matches!(src.emitter, Emitter::PlaneWave { .. }) {
            return refuse(format!(
                "round trips need plane-wave sources; {:?} is not one",
                src.name
            ));
        }
        if src.coherence_length_m.is_finite() {
            return refuse(
                "round trips need an infinite coherence length (far orders lose coherence by \
                 the paper's rule)",
            );
        }
    }
    one_film(scene, "round trips are traced").map_err(NotApplicable)
}

/// One source's deepest traced order (per channel) and the round trip that makes the next one.
pub(super) struct Extension {
    /// The deepest order's rays, one per channel (indices into the traced arrivals).
    pub(super) deepest: Vec<usize>,
    /// Per channel A_σ (σ = s, p).
    a: Vec<[Complex64; 2]>,
    /// s and p = d × s of the exit direction.
    s: DVec3,
    p: DVec3,
    /// ΔS = 2 d n cos θ (m).
    round_trip_path: DoubleDouble,
    /// How many further orders the limits allow.
    pub(super) further: usize,
}

/// The extension of one source's traced arrivals `own` (indices into `arrivals`), or `None`
/// when the limits allow no further order.
pub(super) fn extension(
    scene: &Scene,
    optics: &SceneOptics,
    normal: DVec3,
    arrivals: &[Arrival],
    own: &[usize],
    limits: &EnumerationLimits,
) -> Result<Option<Extension>, NotApplicable> {
    let Some(&deep) = own.iter().max_by_key(|&&i| arrivals[i].path.sequence.len()) else {
        return Ok(None);
    };
    let deep_path = &arrivals[deep].path;
    let seq: Vec<_> = deep_path.sequence.iter().copied().collect();
    let len = seq.len();
    let same_seq = |i: usize, s: &[crate::trace::path::Event]| {
        arrivals[i].path.sequence.len() == s.len() && arrivals[i].path.sequence.iter().eq(s.iter())
    };
    let deepest: Vec<usize> = own.iter().copied().filter(|&i| same_seq(i, &seq)).collect();
    if own
        .iter()
        .any(|&i| arrivals[i].path.sequence.len() == len && !same_seq(i, &seq))
    {
        return refuse("two order families of the same depth reach the target");
    }
    // Internal reflections of the deepest order (as the enumeration counts them).
    let internal = seq
        .iter()
        .enumerate()
        .filter(|(k, e)| {
            e.kind == EventKind::Reflect && deep_path.indices[*k] != optics.ambient_index
        })
        .count();
    let further = (limits.max_internal_reflections.saturating_sub(internal) / 2)
        .min(limits.max_events.saturating_sub(len) / 2);
    if further == 0 {
        return Ok(None);
    }
    // The deepest order: refractions in, a run of reflections alternating between the faces,
    // refractions out; the order before it (one round trip fewer) traced too.
    let mut end = len;
    while end > 0 && seq[end - 1].kind == EventKind::Refract {
        end -= 1;
    }
    let mut start = end;
    while start > 0 && seq[start - 1].kind == EventKind::Reflect {
        start -= 1;
    }
    let run = &seq[start..end];
    if run.len() < 2
        || end == len
        || run.windows(2).any(|w| w[0].surface == w[1].surface)
        || seq[..start].iter().any(|e| e.kind != EventKind::Refract)
        || seq[end..].iter().any(|e| e.kind != EventKind::Refract)
    {
        return refuse(format!(
            "the deepest traced order ({len} events) does not end in a round trip between the \
             faces followed by refractions out"
        ));
    }
    let mut shorter = seq.clone();
    shorter.drain(start..start + 2);
    let previous: Vec<usize> = own
        .iter()
        .copied()
        .filter(|&i| same_seq(i, &shorter))
        .collect();
    if previous.len() != deepest.len() {
        return refuse("the order before the deepest one was not traced");
    }
    let n_in = deep_path.indices[start + 1];
    let lead = &arrivals[deepest[0]].vector;
    let Some((m, invariant)) = lead.normal_q2 else {
        return refuse("the exit ray carries no normal wavevector");
    };
    if m != normal && m != -normal {
        return refuse("the exit face is not parallel to the film");
    }
    let q2_in = invariant.q2_in(n_in);
    if q2_in.hi <= 0.0 {
        return refuse("no propagating wave inside the film");
    }
    let round_trip_path = film_thickness(scene) * q2_in.sqrt() * 2.0;
    let mut a = Vec::with_capacity(deepest.len());
    for (&d, &p) in deepest.iter().zip(&previous) {
        let v = &arrivals[d].vector;
        if v.coherence_id != arrivals[p].vector.coherence_id || v.dir != lead.dir {
            return refuse("the orders do not stay coherent with each other");
        }
        let Some([(sx, px), (sy, py)]) = last_two_reflections(v) else {
            return refuse("the ledger holds no round trip");
        };
        a.push([sx * sy, px * py]);
    }
    let dir = lead.dir;
    let s = crate::optics::fresnel::s_of_plane_of_incidence(dir, normal)
        .unwrap_or_else(|| dir.any_orthonormal_vector());
    Ok(Some(Extension {
        deepest,
        a,
        s,
        p: dir.cross(s),
        round_trip_path,
        further,
    }))
}

/// The short trace: the general far-field walk with at most
/// [`TRACED_INTERNAL_REFLECTIONS`] internal reflections (the `vector` model only).
pub(super) fn traced_orders(
    scene: &Scene,
    optics: &SceneOptics,
    probe_targets: &[DVec3],
    target: &Target,
    settings: &TraceSettings,
) -> Vec<Arrival> {
    let short = TraceSettings {
        limits: EnumerationLimits {
            max_internal_reflections: settings
                .limits
                .max_internal_reflections
                .min(TRACED_INTERNAL_REFLECTIONS),
            max_events: settings.limits.max_events,
        },
        ..*settings
    };
    let p = plan(scene, optics, probe_targets, &short.limits);
    arrivals_with(scene, optics, &p, target, &short, false, None)
}

/// Every `vector` ray reaching the far-field `target` at the wavelength of `optics`, within
/// `settings.limits`, traced by round trips (module docs): the orders with up to
/// [`TRACED_INTERNAL_REFLECTIONS`] internal reflections by the general walk
/// ([`super::arrivals_with`], sequences discovered with `probe_targets` as [`super::plan`]),
/// every further order from the one before by one round trip. The rays are those of
/// `trace::arrivals` with the same plan settings, to the rounding of the round-trip steps (per
/// source: the traced orders in the walk's order, the further ones, order by order and channel
/// by channel, right after the deepest traced one; a sum over them differs from the walk's only
/// in its rounding); `NotApplicable` where the round trips do not hold.
pub fn rays(
    scene: &Scene,
    optics: &SceneOptics,
    probe_targets: &[DVec3],
    target: &Target,
    settings: &TraceSettings,
) -> Result<Vec<FarFieldRay>, NotApplicable> {
    let normal = check_scene(scene, target)?;
    let arrivals = traced_orders(scene, optics, probe_targets, target, settings);
    if arrivals
        .iter()
        .any(|a| a.path.sequence.iter().any(|e| e.kind == EventKind::Tunnel))
    {
        return refuse("an order tunnels through a layer (frustrated total reflection)");
    }
    let mut out = Vec::with_capacity(arrivals.len() + 64);
    for si in 0..scene.sources.len() {
        let own: Vec<usize> = (0..arrivals.len())
            .filter(|&i| arrivals[i].source == si)
            .collect();
        let Some(ext) = extension(scene, optics, normal, &arrivals, &own, &settings.limits)? else {
            out.extend(own.iter().map(|&i| FarFieldRay::of(&arrivals[i])));
            continue;
        };
        // The further orders follow the deepest traced one, where the walk's depth-first order
        // puts them (they descend from its beginning).
        let last = *ext.deepest.iter().max().expect("a deepest order");
        let split = own.partition_point(|&i| i <= last);
        out.extend(own[..split].iter().map(|&i| FarFieldRay::of(&arrivals[i])));
        // Per channel: its s and p amplitudes, its optical path, stepped one round trip at a time.
        let mut state: Vec<(u64, [Complex64; 2], DoubleDouble)> = ext
            .deepest
            .iter()
            .map(|&i| {
                let r = FarFieldRay::of(&arrivals[i]);
                let dot = |v: DVec3| r.field[0] * v.x + r.field[1] * v.y + r.field[2] * v.z;
                (r.coherence_id, [dot(ext.s), dot(ext.p)], r.optical_path)
            })
            .collect();
        for _ in 0..ext.further {
            for ((id, amp, path), a) in state.iter_mut().zip(&ext.a) {
                amp[0] *= a[0];
                amp[1] *= a[1];
                *path += ext.round_trip_path;
                let (es, ep) = (amp[0], amp[1]);
                out.push(FarFieldRay {
                    coherence_id: *id,
                    optical_path: *path,
                    field: [
                        es * ext.s.x + ep * ext.p.x,
                        es * ext.s.y + ep * ext.p.y,
                        es * ext.s.z + ep * ext.p.z,
                    ],
                });
            }
        }
        out.extend(own[split..].iter().map(|&i| FarFieldRay::of(&arrivals[i])));
    }
    Ok(out)
}

/// Which tracer gave a spectrum.
#[derive(Clone, Debug, PartialEq)]
pub enum Route {
    /// Round trips ([`rays`]) at every traced wavelength.
    RoundTrips,
    /// The general walk ([`super::arrivals_with`]), with the reason the round trips did not
    /// apply.
    GeneralWalk(NotApplicable),
}

/// Whether no medium of the scene depends on the wavelength (then every wavelength has the
/// same paths, coefficients and orders, and a spectrum is traced once).
pub fn non_dispersive(scene: &Scene) -> bool {
    let constant = |m: &Medium| matches!(m.dispersion, Dispersion::Constant { .. });
    constant(&scene.ambient)
        && scene.surfaces.iter().all(|s| match &s.kind {
            SurfaceKind::Interface { front, back, .. } => constant(front) && constant(back),
            SurfaceKind::Splitter { medium, .. } => constant(medium),
            _ => true,
        })
}

/// The `vector` rays at the wavelength of `optics`: by round trips where they apply, else by
/// the general walk.
pub fn rays_or_walk(
    scene: &Scene,
    optics: &SceneOptics,
    probe_targets: &[DVec3],
    target: &Target,
    settings: &TraceSettings,
) -> (Vec<FarFieldRay>, Route) {
    match rays(scene, optics, probe_targets, target, settings) {
        Ok(r) => (r, Route::RoundTrips),
        Err(why) => {
            let p = plan(scene, optics, probe_targets, &settings.limits);
            let arr = arrivals_with(scene, optics, &p, target, settings, false, None);
            (far_field_rays(&arr), Route::GeneralWalk(why))
        }
    }
}

/// The traced intensity |E|² (`vector`) toward `target` at every vacuum wavelength of
/// `lambdas_m`, into `out`. Non-dispersive scenes ([`non_dispersive`]) are traced once at the
/// middle wavelength and evaluated at all wavelengths by [`Beats::intensities`] (`beats` is
/// scratch space). Dispersive ones are traced once by round trips at the middle wavelength
/// and evaluated at every wavelength where that structure holds by a [`Sweep`] (indices,
/// Fresnel coefficients and round trip formed again, no trace); at any other wavelength they
/// are traced ([`rays_or_walk`]) and summed with compensation ([`intensity`]), and where such
/// a trace goes by round trips after one by the general walk (or at the first one, if the
/// middle wavelength refused), the sweep is set up again there. The route of the last
/// wavelength is returned (a sweep's wavelengths count as [`Route::RoundTrips`]).
pub fn spectrum(
    scene: &Scene,
    probe_targets: &[DVec3],
    target: &Target,
    settings: &TraceSettings,
    lambdas_m: &[f64],
    beats: &mut Beats,
    out: &mut [f64],
) -> Result<Route, IndexError> {
    assert_eq!(lambdas_m.len(), out.len(), "one output per wavelength");
    if lambdas_m.is_empty() {
        return Ok(Route::RoundTrips);
    }
    if non_dispersive(scene) {
        let optics = scene.optics(lambdas_m[lambdas_m.len() / 2])?;
        let (r, route) = rays_or_walk(scene, &optics, probe_targets, target, settings);
        beats.set(&spectral_contributions(&r));
        beats.intensities(lambdas_m, out);
        return Ok(route);
    }
    let mut sweep = Sweep::new(
        scene,
        &scene.optics(lambdas_m[lambdas_m.len() / 2])?,
        probe_targets,
        target,
        settings,
    )
    .ok();
    // Set the sweep up again at the next wavelength traced by round trips.
    let mut set_up_again = sweep.is_none();
    let mut acc = Accumulator::new();
    let mut route = Route::RoundTrips;
    for (&l, o) in lambdas_m.iter().zip(out.iter_mut()) {
        if let Some(sw) = &sweep
            && let Some(i) = sw.intensity(scene, l)?
        {
            *o = i;
            route = Route::RoundTrips;
            continue;
        }
        let optics = scene.optics(l)?;
        let (r, rt) = rays_or_walk(scene, &optics, probe_targets, target, settings);
        *o = intensity(&r, l, &mut acc);
        if rt == Route::RoundTrips {
            if set_up_again {
                sweep = Sweep::new(scene, &optics, probe_targets, target, settings).ok();
                set_up_again = false;
            }
        } else {
            set_up_again = true;
        }
        route = rt;
    }
    Ok(route)
}
