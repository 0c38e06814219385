//! Running a case: trace every probe point at every fidelity level, evaluate the closed forms,
//! and compare. Probe points run in parallel (rayon); results are deterministic.

use super::build::{self, Built, Overrides, ProbePoint};
use super::load::{Case, CaseError};
use super::reference::{self, MetricKind};
use super::spec::{FarSide, Light, Observer, Probe, ReferenceModel};
use crate::accumulate::Accumulator;
use crate::accumulate::fidelity::{self, Fidelity, SceneNeeds};
use crate::optics::observable::{Observable, Returns, check_match};
use crate::scene::source::Emitter;
use crate::trace::path::{EnumerationLimits, EventKind, PathError, SolveOptions, Target};
use crate::trace::{self, Arrival, TraceSettings};
use glam::DVec3;
use num_complex::Complex64;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::time::Instant;

/// The smallest scale an intensity profile's deviations are divided by: a profile that vanishes
/// everywhere (p light at Brewster's angle) is judged on an absolute scale of 1e-15 of a unit
/// source, not relative to its own rounding noise (the gate and the golden comparison).
pub const VANISHING_SCALE: f64 = 1e-15;

/// Traced and closed-form values of one reference over the probe.
#[derive(Clone, Debug)]
pub struct MetricResult {
    /// Index of the reference in the case file.
    pub index: usize,
    /// The metric's name (the reference's label, else its model's key).
    pub name: String,
    /// The closed form.
    pub model: ReferenceModel,
    /// What the values are.
    pub kind: MetricKind,
    /// The probe coordinate of each value.
    pub coordinates: Vec<f64>,
    /// The closed form's value at each coordinate.
    pub analytic: Vec<f64>,
    /// Traced values per fidelity level (levels where the metric is undefined are absent).
    pub traced: BTreeMap<Fidelity, Vec<f64>>,
    /// Relative tolerance per level (levels without one are information only).
    pub tolerances: BTreeMap<Fidelity, f64>,
    /// Why a tolerance looser than 1e-9 is physically forced.
    pub tolerance_note: Option<String>,
}

/// Deviation statistics of one level against one reference.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelStats {
    /// Largest deviation ([`MetricResult::deviations`]).
    pub max_abs_dev: f64,
    /// Root-mean-square deviation.
    pub rms_dev: f64,
    /// Where the largest deviation occurs (probe coordinate).
    pub at: f64,
}

impl MetricResult {
    /// The scale deviations are divided by: the largest |reference| of an intensity profile,
    /// and |reference| pointwise for the other kinds.
    pub fn deviations(&self, level: Fidelity) -> Option<Vec<f64>> {
        let t = self.traced.get(&level)?;
        let scale = self
            .analytic
            .iter()
            .fold(VANISHING_SCALE, |m, a| m.max(a.abs()));
        Some(
            t.iter()
                .zip(&self.analytic)
                .map(|(t, a)| {
                    // A retardance is a phase: judged in radians (relative to 1 rad), since
                    // near the critical angle it goes to 0 and a relative error would not be
                    // one the tracer makes.
                    let s = match self.kind {
                        MetricKind::Intensity => scale,
                        MetricKind::Retardance => 1.0,
                        _ => a.abs(),
                    };
                    if s > 0.0 {
                        (t - a).abs() / s
                    } else {
                        (t - a).abs()
                    }
                })
                .collect(),
        )
    }

    /// The quantity compared, with its unit: the probe's observable for intensity references.
    pub fn quantity(&self, observable: Observable) -> &'static str {
        match self.kind {
            MetricKind::Intensity => observable.label(),
            MetricKind::FringeSpacing => "fringe spacing (m)",
            MetricKind::Retardance => "retardance arg E_p − arg E_s (rad)",
            MetricKind::Visibility => "fringe visibility",
        }
    }

    /// The tolerance the arithmetic allows this metric at `vector` (docs/PHYSICS.md §8): the
    /// largest per-point rounding bound `rounding` ([`CaseResult::rounding`]) relative to the
    /// profile's scale, at least `floor`; `None` for metrics other than intensity profiles.
    pub fn derived_tolerance(&self, rounding: &[f64], floor: f64) -> Option<f64> {
        (self.kind == MetricKind::Intensity && rounding.len() == self.analytic.len()).then(|| {
            crate::harness::conditioning::relative_tolerance(rounding, &self.analytic, floor)
        })
    }

    /// The deviation statistics of `level` (`None` where the metric is undefined there).
    pub fn stats(&self, level: Fidelity) -> Option<LevelStats> {
        let d = self.deviations(level)?;
        let (mut max, mut at) = (0.0f64, self.coordinates.first().copied().unwrap_or(0.0));
        for (k, x) in d.iter().enumerate() {
            if *x > max || x.is_nan() {
                max = *x;
                at = self.coordinates[k];
            }
        }
        let rms = (d.iter().map(|x| x * x).sum::<f64>() / d.len().max(1) as f64).sqrt();
        Some(LevelStats {
            max_abs_dev: max,
            rms_dev: rms,
            at,
        })
    }
}

/// Error of the traced Airy sum against the closed form for a given number of reflected orders.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvergenceRow {
    /// Reflected orders summed.
    pub orders: usize,
    /// Internal reflections traced.
    pub internal_reflections: usize,
    /// Largest relative deviation from the closed form over the probe.
    pub max_abs_dev: f64,
    /// The geometric-tail bound on |R_N − R| (2|r|τ + τ², τ the amplitude tail bound), maximised
    /// over the probe.
    pub bound: f64,
}

/// Everything a case run produced.
#[derive(Clone, Debug)]
pub struct CaseResult {
    /// The case's name.
    pub name: String,
    /// What it shows.
    pub description: String,
    /// The formula its reference evaluates.
    pub formula: String,
    /// The fidelity levels run.
    pub levels: Vec<Fidelity>,
    /// One per reference.
    pub metrics: Vec<MetricResult>,
    /// The cheapest exact level for the scene, and why.
    pub auto: fidelity::AutoChoice,
    /// Wall time of the exact tracing, s.
    pub trace_seconds: f64,
    /// Wall time of each level's accumulation, s.
    pub level_seconds: BTreeMap<Fidelity, f64>,
    /// Airy cases: the error against the number of reflected orders.
    pub convergence: Vec<ConvergenceRow>,
    /// Internal reflections used per probe point (max over points).
    pub internal_reflections: usize,
    /// Probe points that no light reached.
    pub dark_points: usize,
    /// What the probe measures (intensity references compare this observable).
    pub observable: Observable,
    /// The smallest errors the primary reference's gate catches (full runs only).
    pub detection: Option<super::detection::DetectionFloors>,
    /// Per probe point, the bound on the rounding error of the traced `vector` intensity that
    /// the arithmetic allows ([`crate::harness::conditioning::intensity_rounding`], same units).
    pub rounding: Vec<f64>,
}

struct PointOut {
    intensity: BTreeMap<Fidelity, f64>,
    /// [`crate::harness::conditioning::intensity_rounding`] summed over the spectrum like the intensity.
    rounding: f64,
    analytic: Vec<f64>,
    /// Retardance / visibility per reference and level.
    special: Vec<BTreeMap<Fidelity, f64>>,
    needs: SceneNeeds,
    arrivals: usize,
    /// No wave propagates toward the probe at the centre wavelength (a transmitted far-field
    /// probe beyond the critical angle): dark by physics, T = 0.
    evanescent: bool,
    internal: usize,
}

fn case_err(case: &Case, path: &str, msg: impl Into<String>) -> CaseError {
    CaseError {
        file: case.file.clone(),
        json_path: path.into(),
        message: msg.into(),
    }
}

/// Gaussian light parameters (centre, FWHM) in metres, if any.
fn gaussian(light: &Light) -> Option<(f64, f64)> {
    match light {
        Light::Gaussian {
            center_nm, fwhm_nm, ..
        } => Some((center_nm * 1e-9, fwhm_nm * 1e-9)),
        Light::Monochrome { .. } => None,
    }
}

/// Reflected orders traced explicitly where the Airy tail is closed instead of refused
/// ([`Budget::closed`]): the closure (docs/PHYSICS.md §5a) needs two consecutive traced orders
/// with at least one round trip; a few more keep the traced part what it is below the cap.
pub const CLOSED_TAIL_ORDERS: usize = 8;

/// The internal-reflection budget at a probe point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Budget {
    /// Internal reflections traced per path.
    internal: usize,
    /// The Airy tail beyond them is closed exactly ([`trace::tail::close`]) instead of bounded:
    /// the tail bound needs more internal reflections than the cap.
    closed: bool,
}

/// The internal-reflection budget at a probe point.
fn internal_reflections(case: &Case, built: &Built, lambda_m: f64) -> Result<usize, CaseError> {
    budget(case, built, lambda_m).map(|b| b.internal)
}

/// The budget at a probe point: `max_internal_reflections`, or the Airy tail rule: enough
/// reflected orders that the tail bound is below `airy_tail_epsilon`; where that needs more
/// internal reflections than the cap (near grazing incidence), [`CLOSED_TAIL_ORDERS`] orders
/// with the tail beyond them closed exactly.
fn budget(case: &Case, built: &Built, lambda_m: f64) -> Result<Budget, CaseError> {
    let spec = &case.spec;
    let Some(eps) = spec.trace.airy_tail_epsilon else {
        return Ok(Budget {
            internal: spec.trace.max_internal_reflections,
            closed: false,
        });
    };
    let film = spec
        .references
        .iter()
        .find_map(|r| match &r.model {
            ReferenceModel::Airy { film, .. } => Some(film.clone()),
            _ => None,
        })
        .ok_or_else(|| {
            case_err(
                case,
                "$.trace.airy_tail_epsilon",
                "needs an `airy` reference naming the film",
            )
        })?;
    let (f, cos1) = reference::airy_film(built, &film, lambda_m)
        .map_err(|e| case_err(case, "$.references", e))?;
    let pols = [
        crate::harness::analytic::plate::Pol::S,
        crate::harness::analytic::plate::Pol::P,
    ];
    // The most orders the cap allows (2 N + 1 internal reflections); the bound decreases with
    // N, so the bound needs more than the cap exactly when it is not met at N.
    let cap = super::load::limits::MAX_INTERNAL_REFLECTIONS;
    let most = (cap - 1) / 2;
    if pols
        .into_iter()
        .any(|p| f.r_tail_bound(cos1, lambda_m, p, most) > eps)
    {
        return Ok(Budget {
            internal: 2 * CLOSED_TAIL_ORDERS + 1,
            closed: true,
        });
    }
    let orders = pols
        .into_iter()
        .map(|p| f.orders_for_bound(cos1, lambda_m, p, eps))
        .max()
        .unwrap_or(1);
    // The bound holds only if every order it asks for is traced: never cap silently.
    Ok(Budget {
        internal: 2 * orders + 1,
        closed: false,
    })
}

/// Work units (see [`preflight`]) a case may use before it is refused: about five minutes of
/// tracing on the busy 2-core machine of this project, about one when it is idle (see
/// [`SECONDS_PER_WORK_UNIT`]). The Airy plate with 2000 internal reflections at 2000 angles
/// (2.3e8 units) is accepted; three plates stacked in air under a point source (1.7e8 units,
/// 110 s measured) too; four (2.8e9) are refused.
pub const MAX_PATH_EVENTS: f64 = 5.0e8;

/// Measured seconds of tracing per work unit: 4.4e-7 to 1.05e-6 (stacked plates and a 41-order
/// plate under a point source, the Airy plate walk at m = 2000) on the 2-core AMD EPYC VM of
/// this project at a load of about 12 (six developers building); README "Limits" gives the
/// runs and the command. Used only to state the estimate in time.
pub const SECONDS_PER_WORK_UNIT: f64 = 6.0e-7;

/// Work units of tracing one node of the sequence tree in the far-field walk (both polarized
/// models, extents and blockers: about 20 discovery visits, measured with the Airy plate at
/// m = 2000 against stacked plates).
const WALKED_NODE_UNITS: f64 = 20.0;

/// The work of one probe point at one wavelength, counted on the sequence tree the tracer
/// itself discovers there (`trace::plan`): every probe ray of discovery visits at most every
/// node of the tree (one unit each), and the solver then traces every candidate sequence event
/// by event (one unit per event), or, for a plane wave observed in the far field, every node
/// of the tree once (the walk of shared beginnings, [`WALKED_NODE_UNITS`] per node). Returns (work, measured): `measured` is false when the tree grew so fast with
/// the allowed depth that the work was extrapolated (polynomially from the last doubling of the
/// depth, which under-counts an exponential growth) instead of enumerated, because it already
/// exceeds `cap`.
fn point_work(
    case: &Case,
    pt: &ProbePoint,
    internal: usize,
    cap: f64,
) -> Result<(f64, bool), CaseError> {
    let spec = &case.spec;
    let built =
        build::build_scene(&spec.scene, &pt.overrides).map_err(|e| case_err(case, "$.scene", e))?;
    let spectrum = build::spectrum(&spec.light, &pt.overrides);
    let lambda = spectrum[spectrum.len() / 2].0;
    let optics = built
        .scene
        .optics(lambda)
        .map_err(|e| case_err(case, "$.light", e.to_string()))?;
    let Some(target) = build::propagating_target(&pt.observer, &built, lambda)
        .map_err(|e| case_err(case, "$.probe", e))?
    else {
        return Ok((0.0, true)); // no transmitted wave: nothing is traced
    };
    let walked = !matches!(pt.observer, Observer::Point { .. })
        && built
            .scene
            .sources
            .iter()
            .all(|s| matches!(s.emitter, Emitter::PlaneWave { .. }));
    let probe = probe_targets(&target);
    // trace::plan's probe rays per source: the probe points, each surface's plane point and the
    // specular points of the probe on each plane.
    let rays = (probe.len()
        + built.scene.surfaces.len() * (1 + probe.len() * built.scene.sources.len()))
        as f64;
    let full = settings(case, &built, internal).limits;
    let mut depth = full.max_events.min(8);
    let mut previous: Option<f64> = None;
    loop {
        let limits = EnumerationLimits {
            max_events: depth,
            ..full
        };
        let plan = trace::plan(&built.scene, &optics, &probe, &limits);
        let (mut nodes, mut events) = (0.0, 0.0);
        for tree in &plan.sequences {
            nodes += tree.nodes().len() as f64;
            events += tree
                .nodes()
                .iter()
                .filter(|n| n.candidate)
                .map(|n| n.depth as f64)
                .sum::<f64>();
        }
        let work = rays * nodes
            + if walked {
                WALKED_NODE_UNITS * nodes
            } else {
                events
            };
        if depth == full.max_events {
            return Ok((work, true));
        }
        if let Some(w0) = previous {
            let p = (work / w0).log2().max(0.0);
            let predicted = work * (full.max_events as f64 / depth as f64).powf(p);
            if predicted > cap {
                return Ok((predicted, false));
            }
        }
        previous = Some(work);
        depth = (2 * depth).min(full.max_events);
    }
}

/// The tracing work of a case, checked before anything runs, in work units (one unit: a probe
/// ray of sequence discovery visiting one node of the sequence tree, or the solver tracing one
/// surface event; about [`SECONDS_PER_WORK_UNIT`] each). The tree is enumerated as the tracer enumerates it, at the probe point with
/// the largest internal-reflection budget (the Airy tail rule may raise it near grazing
/// incidence up to the cap; beyond it the budget is [`CLOSED_TAIL_ORDERS`] orders and the
/// closed tail, one arrival of O(1) work per channel, docs/PHYSICS.md §5a), so the count follows the surfaces: reflections between separate surfaces in
/// the ambient medium are not internal reflections, and stacked plates multiply the sequences
/// (the tree is enumerated with doubling depth and refused as soon as it outgrows the cap).
/// Every other point costs the same, scaled by its own budget m as the tracer scales
/// ((m + 2) for the walk of a plane wave in the far field, (m + 2)² otherwise), times its
/// spectral samples; the bounce-convergence report of monochrome Airy cases adds twelve budgets
/// of at most 24 points. A case over [`MAX_PATH_EVENTS`] is refused with the estimate (units
/// and seconds) and the key that drives it.
pub fn preflight(case: &Case) -> Result<f64, CaseError> {
    let spec = &case.spec;
    let points = build::probe_points(&spec.probe);
    let mut budgets = Vec::with_capacity(points.len());
    for pt in &points {
        let built = build::build_scene(&spec.scene, &pt.overrides)
            .map_err(|e| case_err(case, "$.scene", e))?;
        let spectrum = build::spectrum(&spec.light, &pt.overrides);
        let internal = internal_reflections(case, &built, spectrum[spectrum.len() / 2].0)?;
        let walked = !matches!(pt.observer, Observer::Point { .. })
            && built
                .scene
                .sources
                .iter()
                .all(|s| matches!(s.emitter, Emitter::PlaneWave { .. }));
        budgets.push((internal, walked, spectrum.len() as f64));
    }
    // The representative point: the largest budget, the centre among equals.
    let centre = points.len() / 2;
    let worst = budgets.iter().map(|b| b.0).max().unwrap_or(0);
    let rep = if budgets[centre].0 == worst {
        centre
    } else {
        budgets.iter().position(|b| b.0 == worst).unwrap_or(centre)
    };
    // Each point relative to the representative one.
    let scale = |&(m, walked, samples): &(usize, bool, f64)| {
        let r = (m as f64 + 2.0) / (worst as f64 + 2.0);
        samples * if walked { r } else { r * r }
    };
    let mut weight: f64 = budgets.iter().map(scale).sum();
    let convergence_report = matches!(spec.light, Light::Monochrome { .. })
        && spec.references.iter().any(|r| {
            matches!(
                r.model,
                ReferenceModel::Airy {
                    index_override: None,
                    ..
                }
            )
        });
    if convergence_report {
        weight += 12.0 * points.len().min(24) as f64;
    }
    let (per_point, measured) = point_work(case, &points[rep], worst, MAX_PATH_EVENTS / weight)?;
    let work = per_point * weight;
    if work > MAX_PATH_EVENTS {
        let key = if spec.trace.airy_tail_epsilon.is_some() {
            "$.trace.airy_tail_epsilon"
        } else {
            "$.trace.max_internal_reflections"
        };
        return Err(case_err(
            case,
            key,
            format!(
                "this case would take {} {work:.2e} work units (≈ {:.0} s on the 2-core \
                 machine of this project), more than the work cap of {MAX_PATH_EVENTS:.0e}: \
                 {} surface(s) with up to {worst} internal reflections give {per_point:.2e} \
                 units per probe point and wavelength (sequence discovery and solving; \
                 reflections between separate surfaces in the ambient medium multiply the \
                 sequences), times {} probe point(s) and their spectral samples: use fewer \
                 surfaces, internal reflections, probe points or spectral samples",
                if measured { "about" } else { "at least" },
                work * SECONDS_PER_WORK_UNIT,
                spec.scene.surfaces.len(),
                points.len()
            ),
        ));
    }
    Ok(work)
}

/// The tracer settings of a case at a probe point: its internal-reflection budget (or the Airy
/// tail rule at `lambda_m`), spreading as configured.
pub fn trace_settings(
    case: &Case,
    built: &Built,
    lambda_m: f64,
) -> Result<TraceSettings, CaseError> {
    let b = budget(case, built, lambda_m)?;
    if b.closed {
        // Only the case runner closes the tail (trace::tail::close): a caller of these settings
        // would trace a cut sum.
        return Err(case_err(
            case,
            "$.trace.airy_tail_epsilon",
            format!(
                "the Airy tail bound {:e} needs more internal reflections than the cap of {} \
                 here (near grazing incidence); `fringe check` closes that tail exactly, this \
                 command does not: loosen airy_tail_epsilon or move away from grazing",
                case.spec.trace.airy_tail_epsilon.unwrap_or(0.0),
                super::load::limits::MAX_INTERNAL_REFLECTIONS
            ),
        ));
    }
    Ok(settings(case, built, b.internal))
}

fn settings(case: &Case, built: &Built, internal: usize) -> TraceSettings {
    TraceSettings {
        limits: EnumerationLimits {
            max_internal_reflections: internal,
            max_events: 2 * internal + 2 * built.scene.surfaces.len() + 4,
        },
        solve: SolveOptions {
            spreading: case.spec.trace.spreading,
            ..SolveOptions::default()
        },
        ..TraceSettings::default()
    }
}

fn probe_targets(target: &Target) -> Vec<DVec3> {
    match target {
        Target::Point(p) => vec![*p],
        Target::Direction { reference, .. } => vec![*reference],
    }
}

/// The paths a case's references model that exist in every scene the reference accepts, so a
/// solver that does not land one has lost a beam: for `two_beam_plate`, the top reflection and
/// the beam through the plate (Snell's invariant has its root at any lateral distance; over a
/// plate thinner than its ambient, beyond the top face's critical angle, the beam enters below
/// it nearer the source and runs grazing inside: docs/PHYSICS.md §5).
fn required_paths(case: &Case, built: &Built) -> Vec<Vec<crate::trace::path::Event>> {
    use crate::trace::path::Event;
    let mut out = Vec::new();
    for r in &case.spec.references {
        if let ReferenceModel::TwoBeamPlate { plate } = &r.model
            && let (Ok(top), Ok(bottom)) = (
                built.surface(&format!("{plate}.top")),
                built.surface(&format!("{plate}.bottom")),
            )
        {
            let ev = |surface, kind| Event { surface, kind };
            out.push(vec![ev(top, EventKind::Reflect)]);
            out.push(vec![
                ev(top, EventKind::Refract),
                ev(bottom, EventKind::Reflect),
                ev(top, EventKind::Refract),
            ]);
        }
    }
    out
}

/// All arrivals at a target that the observer records, or why a path that exists could not be
/// traced: a path of [`required_paths`] whose solver fails for any reason but an obstruction
/// (`Blocked`, `OutOfExtent`: a scene that shields a beam) is a beam the tracer failed to find, and dropping it would lose
/// it silently (a two-beam plate lost its second beam so and was 0.25 off,
/// `tests/suite/truth_plates.rs`); the case is refused with that reason instead. (Other
/// sequences that do not converge are, as before, taken as paths that do not exist.)
fn arrivals_at(
    built: &Built,
    optics: &crate::scene::SceneOptics,
    target: &Target,
    observer: &Observer,
    st: &TraceSettings,
    required: &[Vec<crate::trace::path::Event>],
) -> Result<Vec<Arrival>, String> {
    let plan = trace::plan(&built.scene, optics, &probe_targets(target), &st.limits);
    let (mut arr, failed) = trace::arrivals(&built.scene, optics, &plan, target, st);
    if let Some(f) = failed.iter().find(|f| {
        !matches!(
            f.error,
            PathError::Blocked { .. } | PathError::OutOfExtent { .. }
        ) && required.iter().any(|q| f.sequence.iter().eq(q.iter()))
    }) {
        return Err(format!(
            "the path solver could not land the path {} on a probe point ({}): f64 ray \
             directions cannot resolve it to 1e-12 of the scene (an extreme index contrast or \
             grazing incidence; README \"fuzz\")",
            crate::trace::path::sequence_label(f.sequence.iter()),
            f.error
        ));
    }
    arr.retain(|a| build::records(observer, a.vector.dir));
    Ok(arr)
}

/// Group-summed field of the arrivals at one level (for retardance).
fn summed_field(arr: &[Arrival], level: Fidelity) -> Option<[num_complex::Complex64; 3]> {
    let mut acc = Accumulator::new();
    for c in trace::contributions(arr, level) {
        acc.add(&c);
    }
    acc.groups().first().map(|(_, e)| *e)
}

fn special_value(
    model: &ReferenceModel,
    built: &Built,
    arr: &[Arrival],
    level: Fidelity,
) -> Option<f64> {
    match model {
        ReferenceModel::RhombRetardance { tir_surface, .. } => {
            if !matches!(level, Fidelity::Vector | Fidelity::PaperRules) {
                return None;
            }
            let e = summed_field(arr, level)?;
            let (d_in, _) = build::plane_wave(&built.scene)?;
            let n = built.scene.surfaces[built.surface(tir_surface).ok()?]
                .plane
                .normal;
            let s = d_in.cross(n).normalize();
            let d_out = arr.first()?.vector.dir;
            let p = d_out.cross(s);
            let dot = |v: DVec3| e[0] * v.x + e[1] * v.y + e[2] * v.z;
            // The retardance is what the TIRs add: the output's relative phase of p and s minus
            // the input's (0 or π for linear light: a field at −45° starts at π).
            let src = built.scene.sources.first()?;
            let e_in = src.channels().first()?.field_direction(d_in);
            let phase_in =
                Complex64::from(e_in.dot(d_in.cross(s))).arg() - Complex64::from(e_in.dot(s)).arg();
            Some(reference::wrap(dot(p).arg() - dot(s).arg() - phase_in))
        }
        ReferenceModel::LloydVisibility {} => {
            if level != Fidelity::Vector {
                return None;
            }
            let id = arr.first()?.vector.coherence_id;
            let i: Vec<f64> = arr
                .iter()
                .filter(|a| a.vector.coherence_id == id)
                .map(|a| a.vector.intensity())
                .collect();
            if i.len() != 2 {
                return None;
            }
            Some(2.0 * (i[0] * i[1]).sqrt() / (i[0] + i[1]))
        }
        _ => None,
    }
}

/// One spectral sample of a probe point as traced.
pub(super) struct Sample {
    /// Index in the spectrum, vacuum wavelength (m) and spectral weight.
    pub index: usize,
    pub lambda_m: f64,
    pub weight: f64,
    /// `None` where no wave propagates toward the probe (a transmitted far-field probe beyond
    /// the critical angle, [`build::propagating_target`]): no arrivals, observable 0.
    pub target: Option<Target>,
    /// The factor from |E|² to the probe's observable ([`reference::observable_factor`]).
    pub factor: f64,
    pub arrivals: Vec<Arrival>,
}

/// A probe point's scene, spectrum and internal-reflection budget; `visit` gets every
/// spectral sample traced, one at a time (a point's arrivals over a long spectrum are never
/// held together).
pub(super) fn trace_point(
    case: &Case,
    pt: &ProbePoint,
    mut visit: impl FnMut(&Built, &[(f64, f64)], Sample) -> Result<(), CaseError>,
) -> Result<(Built, usize), CaseError> {
    let spec = &case.spec;
    let built =
        build::build_scene(&spec.scene, &pt.overrides).map_err(|e| case_err(case, "$.scene", e))?;
    let spectrum = build::spectrum(&spec.light, &pt.overrides);
    let b = budget(case, &built, spectrum[spectrum.len() / 2].0)?;
    let internal = b.internal;
    let st = settings(case, &built, internal);
    // The last traced sample's indices, target and arrivals: a sample with the same indices
    // and target (non-dispersive media) has the same arrivals at its own wavelength
    // ([`Arrival::at_wavelength`]), so a spectrum through such a scene is traced once.
    let mut last: Option<(crate::scene::SceneOptics, Target, Vec<Arrival>)> = None;
    for (index, &(lambda_m, weight)) in spectrum.iter().enumerate() {
        let optics = built
            .scene
            .optics(lambda_m)
            .map_err(|e| case_err(case, "$.light", e.to_string()))?;
        let Some(target) = build::propagating_target(&pt.observer, &built, lambda_m)
            .map_err(|e| case_err(case, "$.probe", e))?
        else {
            // No transmitted wave propagates (beyond the critical angle): nothing arrives.
            let sample = Sample {
                index,
                lambda_m,
                weight,
                target: None,
                factor: 0.0,
                arrivals: Vec::new(),
            };
            visit(&built, &spectrum, sample)?;
            continue;
        };
        let arrivals = match &last {
            Some((o, t, arr))
                if *t == target
                    && o.ambient_index == optics.ambient_index
                    && o.surfaces == optics.surfaces =>
            {
                arr.iter().map(|a| a.at_wavelength(lambda_m)).collect()
            }
            _ => {
                let mut arr = arrivals_at(
                    &built,
                    &optics,
                    &target,
                    &pt.observer,
                    &st,
                    &required_paths(case, &built),
                )
                .map_err(|e| {
                    // A reference that refuses this point itself (frustrated total reflection,
                    // an unresolvable grazing entry) names the scene's own limit: its reason wins.
                    let refused = spec.references.iter().enumerate().find_map(|(ri, r)| {
                        matches!(r.model, ReferenceModel::TwoBeamPlate { .. })
                            .then(|| {
                                reference::value(
                                    &r.model,
                                    &built,
                                    &target,
                                    lambda_m,
                                    spec.trace.spreading,
                                )
                                .err()
                            })
                            .flatten()
                            .map(|m| case_err(case, &format!("$.references[{ri}].model"), m))
                    });
                    refused.unwrap_or_else(|| case_err(case, "$.probe", e))
                })?;
                // Beyond the cap: the orders past the traced ones, closed exactly.
                if b.closed {
                    trace::tail::close(&built.scene, &optics, &mut arr).map_err(|e| {
                        case_err(
                            case,
                            "$.trace.airy_tail_epsilon",
                            format!(
                                "the Airy tail bound needs more internal reflections than the \
                                 cap of {} here (near grazing incidence), and the tail cannot \
                                 be closed exactly: {e}; loosen airy_tail_epsilon or move the \
                                 probe away from grazing",
                                super::load::limits::MAX_INTERNAL_REFLECTIONS
                            ),
                        )
                    })?;
                }
                last = Some((optics, target, arr.clone()));
                arr
            }
        };
        // |E|² → the observable the probe measures (R or T of a plane wave in the far field).
        let factor = reference::observable_factor(&pt.observer, &built, &target, lambda_m)
            .map_err(|e| case_err(case, "$.probe", e))?;
        let sample = Sample {
            index,
            lambda_m,
            weight,
            target: Some(target),
            factor,
            arrivals,
        };
        visit(&built, &spectrum, sample)?;
    }
    Ok((built, internal))
}

fn run_point(case: &Case, pt: &ProbePoint, levels: &[Fidelity]) -> Result<PointOut, CaseError> {
    let spec = &case.spec;
    let mut out = PointOut {
        intensity: levels.iter().map(|l| (*l, 0.0)).collect(),
        rounding: 0.0,
        analytic: vec![0.0; spec.references.len()],
        special: vec![BTreeMap::new(); spec.references.len()],
        needs: SceneNeeds::default(),
        arrivals: 0,
        evanescent: false,
        internal: 0,
    };
    let mut center_arrivals = Vec::new();
    let mut center_target = None;
    let mut center = 0.0;
    let mut acc = Accumulator::new();
    let mut contributions = Vec::new();
    let (built, internal) = trace_point(case, pt, |built, spectrum, sample| {
        let Sample {
            index: k,
            lambda_m: lambda,
            weight: w,
            target,
            factor,
            arrivals: arr,
        } = sample;
        // `trace::intensity` of each level, with the accumulator and contributions reused
        // (the same sums: a cleared accumulator is a new one).
        let reference = arr.first().map(|a| a.vector.optical_path);
        for l in levels {
            contributions.clear();
            if let Some(r) = reference {
                contributions.extend(arr.iter().map(|a| trace::contribution_from(a, *l, r)));
            }
            acc.clear();
            acc.extend(&contributions);
            *out.intensity.get_mut(l).unwrap() += w * factor * acc.intensity();
        }
        if let (Some(r), Ok(optics)) = (reference, built.scene.optics(lambda)) {
            out.rounding += w
                * factor
                * crate::harness::conditioning::intensity_rounding(
                    &arr,
                    r,
                    lambda,
                    &built.scene,
                    &optics,
                );
        }
        for (ri, r) in spec.references.iter().enumerate() {
            if reference::kind(&r.model) == MetricKind::Intensity
                && !matches!(
                    r.model,
                    ReferenceModel::CoherenceGaussian { .. } | ReferenceModel::CoherenceP9 { .. }
                )
            {
                // Beyond the critical angle no transmitted wave exists: T = 0 exactly.
                let Some(target) = &target else { continue };
                let v = reference::value(&r.model, built, target, lambda, spec.trace.spreading)
                    .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
                let v = match reference::returns(&r.model) {
                    Some(Returns::AsProbe) => v * factor,
                    _ => v,
                };
                out.analytic[ri] += w * v;
            }
        }
        for (ri, r) in spec.references.iter().enumerate() {
            if let ReferenceModel::Michelson { splitter, mirrors } = &r.model {
                let modeled = reference::michelson_sequences(built, splitter, mirrors)
                    .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
                if let Some(a) = arr
                    .iter()
                    .find(|a| !modeled.iter().any(|m| a.path.sequence.iter().eq(m.iter())))
                {
                    let names: Vec<String> = a
                        .path
                        .sequence
                        .iter()
                        .map(|e| {
                            let verb = match e.kind {
                                EventKind::Reflect => "reflected by",
                                EventKind::Refract => "through",
                            };
                            format!("{verb} {:?}", built.scene.surfaces[e.surface].name)
                        })
                        .collect();
                    return Err(case_err(
                        case,
                        &format!("$.references[{ri}].model"),
                        format!(
                            "light reaches the probe along a path the two-arm michelson \
                             closed form does not model (source, {}, probe): the scene is not a \
                             Michelson interferometer there; shield that path (a pinhole, \
                             smaller mirrors) or move the probe (at {:?})",
                            names.join(", "),
                            target
                        ),
                    ));
                }
            }
        }
        if k == spectrum.len() / 2 {
            out.arrivals = arr.len();
            out.needs = trace::needs(&arr);
            center_arrivals = arr;
            // Dark by physics: no transmitted wave, or a film beyond its top face's critical
            // angle whose transmittance is negligible (frustrated total reflection).
            out.evanescent = target.is_none()
                || spec
                    .references
                    .iter()
                    .any(|r| reference::frustrated(&r.model, built, lambda));
            center_target = target;
            center = lambda;
        }
        Ok(())
    })?;
    out.internal = internal;
    let spectrum = build::spectrum(&spec.light, &pt.overrides);
    // The centre sample's target: the metrics below need a propagating wave there.
    let centre_target = || {
        center_target.as_ref().ok_or_else(|| {
            case_err(
                case,
                "$.probe",
                "no transmitted wave: total internal reflection",
            )
        })
    };
    for (ri, r) in spec.references.iter().enumerate() {
        match reference::kind(&r.model) {
            MetricKind::Retardance | MetricKind::Visibility => {
                out.analytic[ri] = reference::value(
                    &r.model,
                    &built,
                    centre_target()?,
                    center,
                    spec.trace.spreading,
                )
                .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
                for l in levels {
                    if let Some(v) = special_value(&r.model, &built, &center_arrivals, *l) {
                        out.special[ri].insert(*l, v);
                    }
                }
            }
            MetricKind::Intensity
                if matches!(
                    r.model,
                    ReferenceModel::CoherenceGaussian { .. } | ReferenceModel::CoherenceP9 { .. }
                ) =>
            {
                let g = gaussian(&spec.light);
                let c = g.map(|g| g.0).unwrap_or(center);
                out.analytic[ri] = reference::coherence(
                    &r.model,
                    &built,
                    centre_target()?,
                    &spectrum,
                    c,
                    g.map(|g| g.1),
                )
                .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
            }
            _ => {}
        }
    }
    Ok(out)
}

/// Fringe spacing at the probe centre from the two strongest mutually coherent arrivals. The
/// gradient of a ray's optical path with respect to its end point is n·d (the eikonal
/// equation), so the traced phase-difference gradient along the probe line t̂ is
/// (2π/λ)·n (d_a − d_b)·t̂ and the local spacing λ/|n (d_a − d_b)·t̂|, free of finite differences.
fn traced_spacing(case: &Case, built: &Built) -> Result<(f64, f64), CaseError> {
    let Probe::Line {
        from_m,
        to_m,
        looks_toward,
        ..
    } = &case.spec.probe
    else {
        return Err(case_err(
            case,
            "$.probe",
            "spacing references need a line probe",
        ));
    };
    let (a, b) = (DVec3::from_array(*from_m), DVec3::from_array(*to_m));
    let dir = (b - a).normalize();
    let p0 = a.lerp(b, 0.5);
    let spectrum = build::spectrum(&case.spec.light, &Overrides::default());
    let lambda = spectrum[spectrum.len() / 2].0;
    let optics = built
        .scene
        .optics(lambda)
        .map_err(|e| case_err(case, "$.light", e.to_string()))?;
    let st = settings(case, built, case.spec.trace.max_internal_reflections);
    let observer = Observer::Point {
        position_m: p0.to_array(),
        looks_toward: *looks_toward,
    };
    let required = required_paths(case, built);
    let mut arr = arrivals_at(
        built,
        &optics,
        &Target::Point(p0),
        &observer,
        &st,
        &required,
    )
    .map_err(|e| case_err(case, "$.probe", e))?;
    let id = arr.first().map(|x| x.vector.coherence_id);
    arr.retain(|x| Some(x.vector.coherence_id) == id);
    arr.sort_by(|x, y| y.vector.intensity().total_cmp(&x.vector.intensity()));
    match (arr.first(), arr.get(1)) {
        (Some(x), Some(y)) => {
            let g = x.vector.index * x.vector.dir - y.vector.index * y.vector.dir;
            Ok((lambda / g.dot(dir).abs(), lambda))
        }
        _ => Err(case_err(
            case,
            "$.probe",
            "fewer than two coherent beams reach the probe centre",
        )),
    }
}

fn analytic_spacing(
    case: &Case,
    built: &Built,
    model: &ReferenceModel,
    lambda: f64,
) -> Result<f64, String> {
    match model {
        ReferenceModel::YoungSpacing { paraxial } => {
            let srcs: Vec<(DVec3, DVec3)> = built
                .scene
                .sources
                .iter()
                .filter_map(|s| match s.emitter {
                    crate::scene::source::Emitter::Line { point, axis } => Some((point, axis)),
                    _ => None,
                })
                .collect();
            if srcs.len() != 2 {
                return Err("young_spacing needs two line sources".into());
            }
            let Probe::Line { from_m, to_m, .. } = &case.spec.probe else {
                return Err("needs a line probe".into());
            };
            let p0 = DVec3::from_array(*from_m).lerp(DVec3::from_array(*to_m), 0.5);
            let sep = srcs[0].0 - srcs[1].0;
            let d = sep.length();
            let forward = srcs[0].1.cross(sep / d).normalize();
            let l = (p0 - 0.5 * (srcs[0].0 + srcs[1].0)).dot(forward).abs();
            let n = reference::ambient_index(built, lambda)?;
            Ok(if *paraxial {
                crate::harness::analytic::young::fringe_spacing_paraxial(d, l, lambda, n)
            } else {
                crate::harness::analytic::young::fringe_spacing_exact_on_axis(d, l, lambda, n)
            })
        }
        ReferenceModel::WedgeSpacing { wedge, small_angle } => {
            let top = &built.scene.surfaces[built.surface(&format!("{wedge}.top"))?];
            let bottom = &built.scene.surfaces[built.surface(&format!("{wedge}.bottom"))?];
            let crate::scene::SurfaceKind::Interface { back: glass, .. } = &top.kind else {
                return Err("wedge faces must be interfaces".into());
            };
            let n = glass.index(lambda).map_err(|e| e.to_string())?;
            let alpha =
                crate::scene::geometry::angle_between(top.plane.normal, bottom.plane.normal);
            Ok(if *small_angle {
                crate::harness::analytic::wedge::fringe_spacing_small_angle(lambda, n, alpha)
            } else {
                crate::harness::analytic::wedge::fringe_spacing_exact(lambda, n, alpha)
            })
        }
        _ => unreachable!(),
    }
}

/// Run a validated case, including the bounce-convergence report of Airy cases.
pub fn run(case: &Case) -> Result<CaseResult, CaseError> {
    run_with(case, true)
}

/// Run a validated case; `convergence` adds the Airy error-vs-orders table (extra traces).
pub fn run_with(case: &Case, convergence_report: bool) -> Result<CaseResult, CaseError> {
    let spec = &case.spec;
    let levels: Vec<Fidelity> = spec
        .fidelities
        .clone()
        .unwrap_or_else(|| Fidelity::ALL.to_vec());
    let points = build::probe_points(&spec.probe);
    let measured = check_observables(case, &points)?;
    let t0 = Instant::now();
    let outs: Vec<PointOut> = points
        .par_iter()
        .map(|pt| run_point(case, pt, &levels))
        .collect::<Result<_, _>>()?;
    let trace_seconds = t0.elapsed().as_secs_f64();
    // A probe that no light reaches is refused as misplaced, unless every point is dark by
    // physics (beyond the critical angle, no transmitted wave: T = 0 is compared as such).
    let dark_points = outs.iter().filter(|o| o.arrivals == 0).count();
    if dark_points == points.len() && !outs.iter().all(|o| o.evanescent) {
        return Err(case_err(
            case,
            "$.probe",
            "no light reaches any probe point (is the probe behind an opaque surface?)",
        ));
    }
    let coordinates: Vec<f64> = points.iter().map(|p| p.coordinate).collect();
    let mut metrics = Vec::new();
    for (ri, r) in spec.references.iter().enumerate() {
        let kind = reference::kind(&r.model);
        let mut m = MetricResult {
            index: ri,
            name: r.label.clone().unwrap_or_else(|| reference::name(&r.model)),
            model: r.model.clone(),
            kind,
            coordinates: coordinates.clone(),
            analytic: outs.iter().map(|o| o.analytic[ri]).collect(),
            traced: BTreeMap::new(),
            tolerances: r.tolerances.clone(),
            tolerance_note: r.tolerance_note.clone(),
        };
        match kind {
            MetricKind::Intensity => {
                for l in &levels {
                    m.traced
                        .insert(*l, outs.iter().map(|o| o.intensity[l]).collect());
                }
            }
            MetricKind::Retardance | MetricKind::Visibility => {
                for l in &levels {
                    let v: Option<Vec<f64>> =
                        outs.iter().map(|o| o.special[ri].get(l).copied()).collect();
                    if let Some(v) = v {
                        m.traced.insert(*l, v);
                    }
                }
            }
            MetricKind::FringeSpacing => {
                let built = build::build_scene(&spec.scene, &Overrides::default())
                    .map_err(|e| case_err(case, "$.scene", e))?;
                let (t, lambda) = traced_spacing(case, &built)?;
                let a = analytic_spacing(case, &built, &r.model, lambda)
                    .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
                m.coordinates = vec![coordinates[coordinates.len() / 2]];
                m.analytic = vec![a];
                m.traced.insert(Fidelity::Vector, vec![t]);
            }
        }
        metrics.push(m);
    }
    // Accumulation cost per level (tracing is shared): time the core on the centre point.
    let mut level_seconds = BTreeMap::new();
    for l in &levels {
        level_seconds.insert(*l, trace_seconds / levels.len() as f64);
    }
    let needs = outs.iter().fold(
        SceneNeeds {
            parallel_fields: true,
            ..Default::default()
        },
        |a, o| trace::merge_needs(a, o.needs),
    );
    let needs = SceneNeeds {
        polarization_state: spec
            .references
            .iter()
            .any(|r| reference::kind(&r.model) == MetricKind::Retardance),
        ..needs
    };
    let auto = fidelity::auto_select(&needs);
    let mut result = CaseResult {
        name: spec.name.clone(),
        description: spec.description.clone(),
        formula: spec.formula.clone(),
        levels,
        metrics,
        auto,
        trace_seconds,
        level_seconds,
        convergence: Vec::new(),
        internal_reflections: outs.iter().map(|o| o.internal).max().unwrap_or(0),
        dark_points,
        observable: measured,
        detection: None,
        rounding: outs.iter().map(|o| o.rounding).collect(),
    };
    if convergence_report {
        result.convergence = convergence(case, &points)?;
        result.detection = super::detection::detection_floors(case, &result)?;
    }
    Ok(result)
}

/// What the probe measures, after checking that every intensity reference returns the same
/// observable (docs/PHYSICS.md §3a) and that the observer makes sense: a mismatch is bad input.
fn check_observables(case: &Case, points: &[ProbePoint]) -> Result<Observable, CaseError> {
    let spec = &case.spec;
    let observer = &points
        .first()
        .ok_or_else(|| case_err(case, "$.probe", "the probe has no points"))?
        .observer;
    if let Observer::FarField {
        side: FarSide::Reflected,
        exit_medium: Some(m),
        ..
    } = observer
        && *m != spec.scene.ambient
    {
        return Err(case_err(
            case,
            &format!("{}.exit_medium", observer_path(&spec.probe)),
            format!(
                "the reflected wave leaves into the ambient medium {:?}, not {m:?}: \
                 exit_medium is for the transmitted side (omit it here)",
                spec.scene.ambient
            ),
        ));
    }
    check_wiring(case, observer)?;
    let measured = reference::measured(observer);
    for (ri, r) in spec.references.iter().enumerate() {
        if let Some(returns) = reference::returns(&r.model) {
            check_match(&reference::name(&r.model), returns, measured)
                .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
        }
    }
    Ok(measured)
}

/// Every surface a reference names must be of the kind its closed form describes, and a
/// far-field observer of an Airy film must look along the film's normal: a reference wired to
/// the wrong thing is bad input, never a NaN row or a deviation of 1.
fn check_wiring(case: &Case, observer: &Observer) -> Result<(), CaseError> {
    let spec = &case.spec;
    let kind_of = |name: &str| {
        spec.scene
            .surfaces
            .iter()
            .find(|s| s.name() == name)
            .map(|s| s.kind())
    };
    for (ri, r) in spec.references.iter().enumerate() {
        let (key, named, wanted): (&str, Vec<&String>, &str) = match &r.model {
            ReferenceModel::Airy { film, .. } => ("film", vec![film], "plate"),
            ReferenceModel::TwoBeamPlate { plate }
            | ReferenceModel::CoherenceGaussian { plate, .. }
            | ReferenceModel::CoherenceP9 { plate } => ("plate", vec![plate], "plate"),
            ReferenceModel::Wedge { wedge } | ReferenceModel::WedgeSpacing { wedge, .. } => {
                ("wedge", vec![wedge], "wedge")
            }
            ReferenceModel::Michelson { splitter, .. } => ("splitter", vec![splitter], "splitter"),
            _ => continue,
        };
        let mut checks = vec![(key.to_string(), named, wanted)];
        if let ReferenceModel::Michelson { mirrors, .. } = &r.model {
            checks.push(("mirrors".into(), mirrors.iter().collect(), "mirror"));
        }
        for (key, names, wanted) in checks {
            for (k, name) in names.iter().enumerate() {
                let path = if key == "mirrors" {
                    format!("$.references[{ri}].model.michelson.mirrors[{k}]")
                } else {
                    format!(
                        "$.references[{ri}].model.{}.{key}",
                        reference::name(&r.model)
                    )
                };
                match kind_of(name) {
                    Some(found) if found == wanted => {}
                    Some(found) => {
                        return Err(case_err(
                            case,
                            &path,
                            format!(
                                "{name:?} is a {found}; {} describes a {wanted} here",
                                reference::name(&r.model)
                            ),
                        ));
                    }
                    None => {} // a missing name is reported by the loader
                }
            }
        }
        if let (ReferenceModel::Airy { film, .. }, Observer::FarField { surface_normal, .. }) =
            (&r.model, observer)
            && let Some(crate::harness::case::spec::SurfaceSpec::Plate { normal, .. }) =
                spec.scene.surfaces.iter().find(|s| s.name() == film)
        {
            let (a, b) = (
                DVec3::from_array(*surface_normal).normalize(),
                DVec3::from_array(*normal).normalize(),
            );
            if a.cross(b).length() > 1e-9 {
                return Err(case_err(
                    case,
                    &format!("{}.surface_normal", observer_path(&spec.probe)),
                    format!(
                        "the far field of the airy film {film:?} is observed about the film's \
                         normal {b:?}; this surface_normal {a:?} is not parallel to it"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The JSON path of a probe's observer (`$.probe.<kind>.observe.far_field`), for errors.
fn observer_path(probe: &Probe) -> String {
    match probe {
        Probe::Sweep { .. } => "$.probe.sweep.observe.far_field".into(),
        Probe::Single { .. } => "$.probe.single.observe.far_field".into(),
        _ => "$.probe".into(),
    }
}

/// For cases with an Airy reference: the traced error against the number of reflected orders,
/// with the geometric-tail bound.
fn convergence(case: &Case, points: &[ProbePoint]) -> Result<Vec<ConvergenceRow>, CaseError> {
    let spec = &case.spec;
    let Some((ri, film)) = spec
        .references
        .iter()
        .enumerate()
        .find_map(|(i, r)| match &r.model {
            ReferenceModel::Airy {
                film,
                index_override: None,
            } => Some((i, film.clone())),
            _ => None,
        })
    else {
        return Ok(Vec::new());
    };
    if !matches!(spec.light, Light::Monochrome { .. }) {
        return Ok(Vec::new());
    }
    // At most 24 probe points, evenly spread, keep the report cheap.
    let stride = points.len().div_ceil(24).max(1);
    let points: Vec<ProbePoint> = points.iter().step_by(stride).cloned().collect();
    let points = &points[..];
    let mut rows = Vec::new();
    // Never more internal reflections than the case's own budget (the preflight counted it).
    let budget = points
        .iter()
        .map(|pt| {
            let built = build::build_scene(&spec.scene, &pt.overrides)
                .map_err(|e| case_err(case, "$.scene", e))?;
            let lambda = build::spectrum(&spec.light, &pt.overrides)[0].0;
            internal_reflections(case, &built, lambda)
        })
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .max()
        .unwrap_or(0);
    for orders in [1usize, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64] {
        let internal = 2 * orders - 1;
        if internal > budget.max(1) {
            break;
        }
        let res: Vec<(f64, f64)> = points
            .par_iter()
            .map(|pt| -> Result<(f64, f64), CaseError> {
                let built = build::build_scene(&spec.scene, &pt.overrides)
                    .map_err(|e| case_err(case, "$.scene", e))?;
                let lambda = build::spectrum(&spec.light, &pt.overrides)[0].0;
                let optics = built
                    .scene
                    .optics(lambda)
                    .map_err(|e| case_err(case, "$.light", e.to_string()))?;
                let Some(target) = build::propagating_target(&pt.observer, &built, lambda)
                    .map_err(|e| case_err(case, "$.probe", e))?
                else {
                    return Ok((0.0, 0.0)); // no transmitted wave: T = 0 traced and exact
                };
                let st = settings(case, &built, internal);
                let factor = reference::observable_factor(&pt.observer, &built, &target, lambda)
                    .map_err(|e| case_err(case, "$.probe", e))?;
                let traced = factor
                    * trace::intensity(
                        &arrivals_at(
                            &built,
                            &optics,
                            &target,
                            &pt.observer,
                            &st,
                            &required_paths(case, &built),
                        )
                        .map_err(|e| case_err(case, "$.probe", e))?,
                        Fidelity::Vector,
                    );
                let exact =
                    reference::value(&spec.references[ri].model, &built, &target, lambda, false)
                        .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
                let (f, cos1) = reference::airy_film(&built, &film, lambda)
                    .map_err(|e| case_err(case, "$.references", e))?;
                let tau = [
                    crate::harness::analytic::plate::Pol::S,
                    crate::harness::analytic::plate::Pol::P,
                ]
                .into_iter()
                .map(|p| f.r_tail_bound(cos1, lambda, p, orders))
                .fold(0.0f64, f64::max);
                let bound = 2.0 * exact.sqrt() * tau + tau * tau;
                Ok(((traced - exact).abs(), bound))
            })
            .collect::<Result<_, _>>()?;
        rows.push(ConvergenceRow {
            orders,
            internal_reflections: internal,
            max_abs_dev: res.iter().map(|r| r.0).fold(0.0, f64::max),
            bound: res.iter().map(|r| r.1).fold(0.0, f64::max),
        });
        if internal > spec.trace.max_internal_reflections.max(8)
            && rows.last().is_some_and(|r| r.max_abs_dev < 1e-15)
        {
            break;
        }
    }
    Ok(rows)
}
