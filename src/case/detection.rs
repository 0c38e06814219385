//! What a case's gate can see: a known error is injected into one traced path and the smallest
//! one that makes the primary reference fail its `vector` tolerance is the case's *detection
//! floor* (issue "truth across every valid scene", item 6). A case whose floor is far above its
//! tolerance could not tell a wrong tracer from a right one: it is decoration, and `check`
//! fails it (floor > [`FLOOR_FACTOR`] × tolerance).
//!
//! The fault is applied to the arrival after the first at every probe point and wavelength (the
//! second beam of a two-beam scene, the first internal reflection of a plate): a phase offset
//! of ε rad, or an amplitude factor 1 + ε. Tracing is done once; only the accumulation is
//! repeated while ε is bisected on a log scale, over at most [`MAX_POINTS`] probe points spread
//! evenly (fewer points can only miss an error, so the floor is never optimistic).

use super::build;
use super::load::{Case, CaseError};
use super::reference::MetricKind;
use super::run::{CaseResult, trace_point};
use crate::fidelity::Fidelity;
use crate::trace::{self, Arrival};

/// Probe points the floor is measured on, at most.
pub const MAX_POINTS: usize = 48;
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
pub enum Fault {
    /// Phase offset (rad).
    Phase(f64),
    /// Amplitude factor 1 + ε.
    Amplitude(f64),
}

/// The arrivals of one probe point at every spectral sample: (weight × observable factor,
/// arrivals).
type PointArrivals = Vec<(f64, Vec<Arrival>)>;

/// The floors of a case's primary reference, for intensity references with a `vector`
/// tolerance (`None` for spacing, retardance and visibility references: one path's phase or
/// amplitude does not enter them the same way).
pub fn detection_floors(
    case: &Case,
    result: &CaseResult,
) -> Result<Option<DetectionFloors>, CaseError> {
    let Some(primary) = result.metrics.first() else {
        return Ok(None);
    };
    let Some(&tolerance) = primary.tolerances.get(&Fidelity::Vector) else {
        return Ok(None);
    };
    if primary.kind != MetricKind::Intensity || !primary.traced.contains_key(&Fidelity::Vector) {
        return Ok(None);
    }
    let scale = primary
        .analytic
        .iter()
        .fold(1e-15f64, |m, a| m.max(a.abs()));
    let points = build::probe_points(&case.spec.probe);
    let stride = points.len().div_ceil(MAX_POINTS).max(1);
    let sampled: Vec<usize> = (0..points.len()).step_by(stride).collect();
    let mut traced: Vec<PointArrivals> = Vec::with_capacity(sampled.len());
    for &i in &sampled {
        let mut per_lambda = Vec::new();
        trace_point(case, &points[i], |_, _, sample| {
            per_lambda.push((sample.weight * sample.factor, sample.arrivals));
            Ok(())
        })?;
        traced.push(per_lambda);
    }
    let analytic: Vec<f64> = sampled.iter().map(|&i| primary.analytic[i]).collect();
    let deviation = |fault: Fault| -> f64 {
        traced
            .iter()
            .zip(&analytic)
            .map(|(per_lambda, a)| {
                let value: f64 = per_lambda
                    .iter()
                    .map(|(w, arr)| w * trace::intensity(&faulted(arr, fault), Fidelity::Vector))
                    .sum();
                (value - a).abs() / scale
            })
            .fold(0.0, f64::max)
    };
    let floor = |make: fn(f64) -> Fault| -> Floor {
        // Log-bisection for the smallest ε in [1e-16, 1] that is caught.
        let caught = |e: f64| deviation(make(e)) > tolerance;
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
        return Ok(Some(DetectionFloors {
            phase_rad: Floor::NotApplicable(why),
            amplitude: Floor::NotApplicable(why),
            tolerance,
        }));
    }
    let coherent = traced.iter().flatten().any(|(_, arr)| interfere(arr));
    Ok(Some(DetectionFloors {
        phase_rad: if coherent {
            floor(Fault::Phase)
        } else {
            Floor::NotApplicable("no two arrivals interfere: phases do not enter")
        },
        amplitude: floor(Fault::Amplitude),
        tolerance,
    }))
}

/// The arrivals with `fault` applied to every channel of one path: the path carrying the
/// second-largest intensity (the weaker of two beams, the first internal reflection of a
/// plate), or the only one.
fn faulted(arrivals: &[Arrival], fault: Fault) -> Vec<Arrival> {
    let mut paths: Vec<(*const crate::path::SolvedPath, f64)> = Vec::new();
    for a in arrivals {
        let key = std::sync::Arc::as_ptr(&a.path);
        match paths.iter_mut().find(|(k, _)| *k == key) {
            Some((_, i)) => *i += a.vector.intensity(),
            None => paths.push((key, a.vector.intensity())),
        }
    }
    paths.sort_by(|a, b| b.1.total_cmp(&a.1));
    let Some(&(chosen, _)) = paths.get(1).or(paths.first()) else {
        return Vec::new();
    };
    let mut out = arrivals.to_vec();
    for a in out
        .iter_mut()
        .filter(|a| std::sync::Arc::as_ptr(&a.path) == chosen)
    {
        let ray = &mut a.vector;
        match fault {
            Fault::Phase(e) => {
                ray.optical_path += (e / std::f64::consts::TAU * ray.wavelength_m).into();
            }
            Fault::Amplitude(e) => ray.scale(1.0 + e),
        }
    }
    out
}

/// Whether two arrivals of one point are mutually coherent (share a non-zero coherence id):
/// only then can a phase error show.
fn interfere(arrivals: &[Arrival]) -> bool {
    arrivals.iter().enumerate().any(|(i, a)| {
        a.vector.coherence_id != crate::ray::INCOHERENT
            && arrivals[i + 1..]
                .iter()
                .any(|b| b.vector.coherence_id == a.vector.coherence_id)
    })
}
