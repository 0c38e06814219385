//! What a case's gate can see: a known error is injected into one traced path and the smallest
//! one that makes the primary reference fail its `vector` tolerance is the case's *detection
//! floor* (issue "truth across every valid scene", item 6). A case whose floor is far above its
//! tolerance could not tell a wrong tracer from a right one: it is decoration, and `check`
//! fails it (floor > [`FLOOR_FACTOR`] × tolerance).
//!
//! The fault is applied to the arrival after the first at every probe point and wavelength (the
//! second beam of a two-beam scene, the first internal reflection of a plate): a phase offset
//! of ε rad, or an amplitude factor 1 + ε. Tracing is done once; only the accumulation is
//! repeated while ε is bisected on a log scale, over at most `MAX_POINTS` probe points spread
//! evenly (fewer points can only miss an error, so the floor is never optimistic).

use super::build;
use super::load::{Case, CaseError};
use super::reference::MetricKind;
use super::run::{CaseResult, Traced, trace_point};
use crate::accumulate::fidelity::Fidelity;
use crate::accumulate::{Accumulator, Contribution};
use crate::optics::double_double::DoubleDouble;
use crate::optics::ray::field_of;
use crate::trace::Arrival;
use glam::DVec3;
use num_complex::Complex64;
use rayon::prelude::*;

/// Probe points the floor is measured on, at most.
pub(crate) const MAX_POINTS: usize = 48;
/// A floor above this multiple of the tolerance fails the case.
pub const FLOOR_FACTOR: f64 = 10.0;

/// The smallest injected errors the primary reference's `vector` gate catches (`None`: not
/// caught even at ε = 1).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DetectionFloors {
    /// Phase offset on one path (rad).
    pub phase_rad: Floor,
    /// Relative amplitude error on one path.
    pub amplitude: Floor,
    /// The primary reference's `vector` tolerance.
    pub tolerance: f64,
}

/// The detection floor of one kind of error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Floor {
    /// The smallest error that fails the gate.
    Caught(f64),
    /// Not caught even at ε = 1: the case cannot see this error.
    Blind,
    /// The error does not change the observable, by physics (a phase where nothing
    /// interferes, anything where the reference vanishes everywhere).
    NotApplicable(&'static str),
}

/// An error injected into one path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Fault {
    /// Phase offset (rad).
    Phase(f64),
    /// Amplitude factor 1 + ε.
    Amplitude(f64),
}

/// The arrivals of one probe point at every spectral sample: (weight × observable factor,
/// what a fault touches of the arrivals, [`fault_rays`]).
pub(crate) type PointArrivals = Vec<(f64, Vec<FaultRay>)>;

/// The probe points (indices, ascending) the floors are measured on: at most [`MAX_POINTS`],
/// spread evenly over `n` points.
pub(crate) fn sampled_points(n: usize) -> Vec<usize> {
    let stride = n.div_ceil(MAX_POINTS).max(1);
    (0..n).step_by(stride).collect()
}

/// The floors of a case's primary reference, for intensity references with a `vector`
/// tolerance (`None` for spacing, retardance and visibility references: one path's phase or
/// amplitude does not enter them the same way), tracing the points `sampled_points` names
/// again; a case run measures them on its own arrivals (`floors_of_traced`).
pub fn detection_floors(
    case: &Case,
    result: &CaseResult,
) -> Result<Option<DetectionFloors>, CaseError> {
    let points = build::probe_points(&case.spec.probe);
    let traced: Vec<PointArrivals> = sampled_points(points.len())
        .par_iter()
        .map(|&i| {
            let mut per_lambda = Vec::new();
            trace_point(case, &points[i], &mut Traced::default(), |_, _, sample| {
                per_lambda.push((sample.weight * sample.factor, fault_rays(sample.arrivals)));
                Ok(())
            })?;
            Ok(per_lambda)
        })
        .collect::<Result<_, CaseError>>()?;
    Ok(floors_of_traced(result, traced))
}

/// [`detection_floors`] on arrivals already traced: `traced` holds, for the points
/// [`sampled_points`] names and in that order, every spectral sample's weight × observable
/// factor and [`fault_rays`] of its arrivals, as `run::trace_point` gives them.
pub(crate) fn floors_of_traced(
    result: &CaseResult,
    traced: Vec<PointArrivals>,
) -> Option<DetectionFloors> {
    let primary = result.metrics.first()?;
    let &tolerance = primary.tolerances.get(&Fidelity::Vector)?;
    if primary.kind != MetricKind::Intensity || !primary.traced.contains_key(&Fidelity::Vector) {
        return None;
    }
    let scale = primary
        .analytic
        .iter()
        .fold(1e-15f64, |m, a| m.max(a.abs()));
    let sampled = sampled_points(primary.analytic.len());
    assert_eq!(
        traced.len(),
        sampled.len(),
        "one traced point per sampled point"
    );
    let coherent = traced.iter().flatten().any(|(_, rays)| interfere(rays));
    // What a fault touches, taken from the arrivals once, as they were traced (the bisection
    // evaluates the deviation ~80 times).
    let faultable = traced;
    let analytic: Vec<f64> = sampled.iter().map(|&i| primary.analytic[i]).collect();
    // Whether `fault` fails the gate at sampled point `k`: it deviates by more than the
    // tolerance (a NaN deviation does not).
    let caught_at =
        |k: usize, fault: Fault, acc: &mut Accumulator, scratch: &mut Vec<Contribution>| {
            let value: f64 = faultable[k]
                .iter()
                .map(|(w, rays)| w * faulted_intensity(rays, fault, acc, scratch))
                .sum();
            (value - analytic[k]).abs() / scale > tolerance
        };
    // The point that caught the last fault: it is tried first, alone (a fault a little smaller
    // or larger is most often caught there again, and then the other points need no work).
    // Whether a fault is caught does not depend on the order the points are tried in.
    let last_catcher = std::cell::Cell::new(None::<usize>);
    // Whether `fault` fails the gate: some sampled point deviates by more than the tolerance
    // (the largest deviation exceeds it). The search stops at the first such point.
    let caught_by = |fault: Fault| -> bool {
        if let Some(k) = last_catcher.get()
            && caught_at(k, fault, &mut Accumulator::new(), &mut Vec::new())
        {
            return true;
        }
        let catcher = (0..faultable.len())
            .into_par_iter()
            .map_init(
                || (Accumulator::new(), Vec::new()),
                |(acc, scratch), k| caught_at(k, fault, acc, scratch).then_some(k),
            )
            .find_any(|caught| caught.is_some())
            .flatten();
        if catcher.is_some() {
            last_catcher.set(catcher);
        }
        catcher.is_some()
    };
    let floor = |make: fn(f64) -> Fault| -> Floor {
        // Log-bisection for the smallest ε in [1e-16, 1] that is caught.
        let caught = |e: f64| caught_by(make(e));
        if !caught(1.0) {
            return Floor::Blind;
        }
        let (mut lo, mut hi) = (-16.0f64, 0.0f64);
        if caught(10f64.powf(lo)) {
            return Floor::Caught(10f64.powf(lo));
        }
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if caught(10f64.powf(mid)) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        Floor::Caught(10f64.powf(hi))
    };
    if scale <= 1e-12 {
        let why = "the closed form vanishes everywhere (an extinction case)";
        return Some(DetectionFloors {
            phase_rad: Floor::NotApplicable(why),
            amplitude: Floor::NotApplicable(why),
            tolerance,
        });
    }
    Some(DetectionFloors {
        phase_rad: if coherent {
            floor(Fault::Phase)
        } else {
            Floor::NotApplicable("no two arrivals interfere: phases do not enter")
        },
        amplitude: floor(Fault::Amplitude),
        tolerance,
    })
}

/// The chosen path of a fault: the path carrying the second-largest intensity (the weaker of
/// two beams, the first internal reflection of a plate), or the only one.
fn chosen_path(arrivals: &[Arrival]) -> Option<*const crate::trace::path::SolvedPath> {
    let mut paths: Vec<(*const crate::trace::path::SolvedPath, f64)> = Vec::new();
    for a in arrivals {
        let key = std::sync::Arc::as_ptr(&a.path);
        match paths.iter_mut().find(|(k, _)| *k == key) {
            Some((_, i)) => *i += a.vector.intensity(),
            None => paths.push((key, a.vector.intensity())),
        }
    }
    paths.sort_by(|a, b| b.1.total_cmp(&a.1));
    paths.get(1).or(paths.first()).map(|&(k, _)| k)
}

/// What the `vector` contribution of one arrival is made of, and whether the fault hits it.
pub(crate) struct FaultRay {
    coherence_id: u64,
    optical_path: DoubleDouble,
    wavelength_m: f64,
    jones: [Complex64; 2],
    x: DVec3,
    y: DVec3,
    chosen: bool,
    /// The unfaulted phase, cycles from the first ray's optical path ([`crate::trace::phase_cycles`]),
    /// and the unfaulted field: what every evaluation of the bisection reuses for the rays the
    /// fault does not touch.
    cycles: f64,
    field: crate::optics::ray::Field3,
}

/// The arrivals of one spectral sample as [`faulted_intensity`] needs them.
pub(crate) fn fault_rays(arrivals: &[Arrival]) -> Vec<FaultRay> {
    let chosen = chosen_path(arrivals);
    let reference = arrivals
        .first()
        .map_or(DoubleDouble::ZERO, |a| a.vector.optical_path);
    arrivals
        .iter()
        .map(|a| {
            // A closed Airy tail (docs/PHYSICS.md §5a): the Jones vector of the orders it
            // stands for, in its ray's frame.
            let jones = a.tail.as_ref().map_or(a.vector.jones, |t| {
                let (e, _) = t.field(&a.vector.field(), Fidelity::Vector, a.vector.wavelength_m);
                let dot = |v: DVec3| e[0] * v.x + e[1] * v.y + e[2] * v.z;
                [dot(a.vector.x), dot(a.vector.y)]
            });
            let v = &a.vector;
            FaultRay {
                coherence_id: v.coherence_id,
                optical_path: v.optical_path,
                wavelength_m: v.wavelength_m,
                jones,
                x: v.x,
                y: v.y,
                chosen: Some(std::sync::Arc::as_ptr(&a.path)) == chosen,
                cycles: crate::trace::phase_cycles(v.optical_path, reference, v.wavelength_m),
                field: field_of(jones, v.x, v.y),
            }
        })
        .collect()
}

/// The `vector` intensity of the arrivals with `fault` applied to every channel of the chosen
/// path ([`chosen_path`]): the same arithmetic as tracing rays with the fault (a phase offset
/// added to the optical path in double-double, an amplitude factor on the Jones vector) and
/// [`crate::trace::intensity`] of them, without copying the arrivals.
fn faulted_intensity(
    rays: &[FaultRay],
    fault: Fault,
    acc: &mut Accumulator,
    scratch: &mut Vec<Contribution>,
) -> f64 {
    let path = |r: &FaultRay| {
        let mut op = r.optical_path;
        if let (true, Fault::Phase(e)) = (r.chosen, fault) {
            op += (e / std::f64::consts::TAU * r.wavelength_m).into();
        }
        op
    };
    let reference = rays.first().map_or(DoubleDouble::ZERO, path);
    // A phase fault on the first ray moves the reference of every phase; otherwise only the
    // chosen rays' phases and fields differ from the unfaulted ones (`FaultRay::cycles`,
    // `FaultRay::field`, the same arithmetic).
    let moved_reference =
        matches!(fault, Fault::Phase(_)) && rays.first().is_some_and(|r| r.chosen);
    scratch.clear();
    scratch.extend(rays.iter().map(|r| {
        let field = match (r.chosen, fault) {
            (true, Fault::Amplitude(e)) => {
                field_of([r.jones[0] * (1.0 + e), r.jones[1] * (1.0 + e)], r.x, r.y)
            }
            _ => r.field,
        };
        let phase_cycles = match (r.chosen, fault) {
            (true, Fault::Phase(_)) => {
                crate::trace::phase_cycles(path(r), reference, r.wavelength_m)
            }
            _ if moved_reference => crate::trace::phase_cycles(path(r), reference, r.wavelength_m),
            _ => r.cycles,
        };
        Contribution {
            coherence_id: r.coherence_id,
            phase_cycles,
            field,
        }
    }));
    acc.clear();
    acc.extend(scratch);
    acc.intensity()
}

/// Whether two arrivals of one point are mutually coherent (share a non-zero coherence id):
/// only then can a phase error show.
fn interfere(rays: &[FaultRay]) -> bool {
    rays.iter().enumerate().any(|(i, a)| {
        a.coherence_id != crate::optics::ray::INCOHERENT
            && rays[i + 1..]
                .iter()
                .any(|b| b.coherence_id == a.coherence_id)
    })
}
