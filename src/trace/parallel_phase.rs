//! The far-field optical path of a plane wave whose every event lies on planes with one line
//! of normals (a film, a plate, a stack of parallel plates), formed from Snell's invariant
//! instead of summed along the traced segments (docs/PHYSICS.md §8).
//!
//! Every wave of such a path is a plane wave with the same tangential wavevector k_t (Snell's
//! law conserves it), so its phase at the far-field wavefront through `r_t` is
//!
//! Φ = k_t·(r_t − r_pw) + κ_0 h_0(r_pw) + Σ_e κ_{e+1} (h_{e+1} − h_e) − κ_m h_{m−1}(r_t),
//!
//! with κ_i = n_i d̂_i·N̂ = ±√q²_i the normal wavevector of segment i ((n cos θ)², from the
//! launch's q²_0 and the indices in double-double as the tracer carries it), h_e(r) = N̂·(x_e − r)
//! the height of event e's plane (its anchor and height, not the rounded point) and r_pw the
//! plane wave's reference point: the tangential parts of all segments telescope to the first
//! term exactly. Summed along the segments instead, each tangential part is the rounded f64
//! direction times a lateral run that near grazing incidence reaches metres, and the far-field
//! projection is along the *target's* f64 direction: both first-order errors, ~1e-16 rad times
//! the run, that grow linearly with the order. A film 1e-10° below the critical angle of its
//! top face (n = 1 in n = 3, 1 µm, 200 nm; `fuzz_airy_s1_203`) runs 0.64 m sideways per round
//! trip, and its orders' phases were 8e-17 m of path per round trip off (2.5e-9 rad, ninth
//! order), which its closed tail (|1 − q| ~ 2e-4) turned into 7e-9 of the reflectance.
//!
//! Used where the Airy tail is closed (`tail::close`), on the few orders traced below it; the
//! far-field walk itself still sums along the segments (this costs O(m) per order).

use crate::optics::double_double::{DoubleDouble, difference};
use crate::optics::interaction::normal_wavevector_squares;
use crate::scene::Scene;
use crate::scene::source::Emitter;
use crate::trace::path::{EventKind, SolvedPath, Target};
use glam::DVec3;

/// The exact far-field optical path Φ (m, module docs) of `path`, traced from the plane-wave
/// source `emitter` into `target`, relative to the wavefront through the wave's reference
/// point as the traced paths are; `None` (the traced sum stands) unless the source is a plane
/// wave, the target a far-field direction, the path has at least one event, no event tunnels,
/// and every event's plane normal is the first one's (bitwise ±, the tracer's own test for
/// carrying q² between faces), with a propagating wave on every segment.
pub(crate) fn far_field_path(
    scene: &Scene,
    emitter: Emitter,
    path: &SolvedPath,
    target: &Target,
) -> Option<DoubleDouble> {
    let Emitter::PlaneWave {
        reference_point, ..
    } = emitter
    else {
        return None;
    };
    let Target::Direction { reference, .. } = *target else {
        return None;
    };
    let first = path.sequence.first()?;
    let normal = scene.surfaces[first.surface].plane.normal;
    let mut sign_of = Vec::with_capacity(2);
    for ev in path.sequence.iter() {
        let n = scene.surfaces[ev.surface].plane.normal;
        if ev.kind == EventKind::Tunnel || (n != normal && n != -normal) {
            return None;
        }
        if !sign_of.iter().any(|&(s, _)| s == ev.surface) {
            sign_of.push((ev.surface, if n == normal { 1.0 } else { -1.0 }));
        }
    }
    let d0 = *path.dirs.first()?;
    let n0 = *path.indices.first()?;
    // (n0 cos θ0)² about N, as the tracer forms it at the first face.
    let (q2_0, _) = normal_wavevector_squares(d0, normal, (n0, n0), None);
    // κ per distinct index and side (a few per path), √q² in double-double.
    let mut kappas: Vec<(f64, bool, DoubleDouble)> = Vec::with_capacity(4);
    let mut kappa = |n: f64, d: DVec3| -> Option<DoubleDouble> {
        let up = d.dot(normal) >= 0.0;
        if let Some(&(_, _, k)) = kappas.iter().find(|&&(m, u, _)| m == n && u == up) {
            return Some(k);
        }
        let q2 = if n == n0 {
            q2_0
        } else {
            q2_0 + crate::optics::double_double::two_prod(n, n)
                - crate::optics::double_double::two_prod(n0, n0)
        };
        if q2.hi < 0.0 {
            return None;
        }
        let k = if up { q2.sqrt() } else { -q2.sqrt() };
        kappas.push((n, up, k));
        Some(k)
    };
    // h_e(r) = N̂·(x_e − r) of event e's plane: −σ_e times r's signed distance from it.
    let height = |surface: usize, r: DVec3| -> DoubleDouble {
        let sigma = sign_of.iter().find(|&&(s, _)| s == surface).unwrap().1;
        let sd = scene.surfaces[surface].plane.signed_distance_dd(r);
        if sigma > 0.0 { -sd } else { sd }
    };
    // Segments between events, counted per (from, to, κ) so that m round trips cost m integer
    // steps and a handful of double-double products.
    let mut runs: Vec<(usize, usize, DoubleDouble, f64)> = Vec::with_capacity(4);
    let mut events = path.sequence.iter();
    let mut prev = events.next()?.surface;
    for ((ev, &d), &n) in events
        .zip(path.dirs.iter().skip(1))
        .zip(path.indices.iter().skip(1))
    {
        let k = kappa(n, d)?;
        match runs
            .iter_mut()
            .find(|r| r.0 == prev && r.1 == ev.surface && r.2 == k)
        {
            Some(r) => r.3 += 1.0,
            None => runs.push((prev, ev.surface, k, 1.0)),
        }
        prev = ev.surface;
    }
    let last = prev;
    let m = path.sequence.len();
    let k_first = kappa(n0, d0)?;
    let k_exit = kappa(*path.indices.get(m)?, *path.dirs.get(m)?)?;
    let mut phi = k_first * height(first.surface, reference_point);
    for (a, b, k, count) in runs {
        let dh = height(b, reference_point) - height(a, reference_point);
        phi += (k * dh).mul_f64(count);
    }
    phi -= k_exit * height(last, reference);
    // k_t·(r_t − r_pw) = n0 [d̂0·v − (d̂0·N̂)(N̂·v)]: the same for every path into the target.
    if reference != reference_point {
        let v = difference(reference_point, reference);
        let dot = |a: DVec3| v[0].mul_f64(a.x) + v[1].mul_f64(a.y) + v[2].mul_f64(a.z);
        let (dd, nn) = (DoubleDouble::dot(d0, d0), DoubleDouble::dot(normal, normal));
        let along = DoubleDouble::dot(d0, normal) * dot(normal) / nn;
        phi += (dot(d0) - along).mul_f64(n0) / dd.sqrt();
    }
    Some(phi)
}
