//! Running a case: trace every probe point at every fidelity level, evaluate the closed forms,
//! and compare. Probe points run in parallel (rayon); results are deterministic.
//!
//! Work is shared where it gives the same values bit for bit, never traced again: every rung
//! takes its contributions from one trace of a sample; a sample's arrivals are relabelled to
//! the next sample's wavelength where a new trace would give the same ones (`Traced`: a
//! spectrum, or a wavelength sweep over one scene, through non-dispersive media), with the
//! wavelength-free parts of the conditioning terms formed once per trace
//! ([`conditioning::RoundingTerms`], [`conditioning::direction_offsets`]) and a
//! non-dispersive scene's optics formed once per point ([`relabelled_optics`]); the detection
//! floors and the convergence report read the arrivals the run traced
//! ([`orders_within`]: a rung within a point's budget is its traced orders, cut; a rung
//! beyond it is cut from one trace of the report's deepest rung).

use super::build::{self, Built, Overrides, ProbePoint};
use super::load::{Case, CaseError};
use super::reference::{self, MetricKind};
use super::spec::{FarSide, Light, Observer, Probe, ReferenceModel};
use crate::accumulate::Accumulator;
use crate::accumulate::fidelity::{self, Fidelity, SceneNeeds};
use crate::harness::conditioning;
use crate::optics::observable::{Observable, Returns, check_match};
use crate::scene::source::Emitter;
use crate::trace::path::{EnumerationLimits, EventKind, PathError, SolveOptions, Target};
use crate::trace::{self, Arrival, TraceSettings};
use glam::DVec3;
use num_complex::Complex64;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::time::Instant;

mod arrivals;
mod budget;
mod convergence;
mod metrics;
mod wiring;

pub use arrivals::trace_settings;
use arrivals::*;
use budget::*;
pub use budget::{
    CLOSED_TAIL_ORDERS, DEPTH_SQUARE_UNITS, MAX_PATH_EVENTS, MOVED_TRACE, NEWTON_EVENT_UNITS,
    NODE_UNITS, PointKind, SAMPLE_UNITS, SECONDS_PER_WORK_UNIT, SURFACE_DEPTH_SQUARE_UNITS,
    TAIL_RULE_UNITS, TRACE_UNITS, VISIT_UNITS, WALKED_EVENT_UNITS, WorkCounts, WorkEstimate,
    preflight, work_estimate,
};
use convergence::*;
pub use convergence::{convergence_traced, orders_within};
use metrics::*;
use wiring::*;

/// The smallest scale an intensity profile's deviations are divided by: a profile that vanishes
/// everywhere (p light at Brewster's angle) is judged on an absolute scale of 1e-15 of a unit
/// source, not relative to its own rounding noise (the gate and the golden comparison).
pub(crate) const VANISHING_SCALE: f64 = 1e-15;

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
    /// Per probe point, how far the exact `vector` intensity moves when the scene's plane-wave
    /// direction turns by the rounding its f64 representation allows
    /// ([`crate::harness::conditioning::direction_sensitivity`], same units; docs/PHYSICS.md §8).
    pub representation: Vec<f64>,
    /// Per probe point, the same for a primary reference that measures a phase (the rhomb's
    /// retardance, rad): how far the exact value moves when the directions it depends on are
    /// held one rounding off ([`crate::harness::analytic::tir::rhomb_retardance_representation`]);
    /// 0 for other references.
    pub phase_representation: Vec<f64>,
}

impl CaseResult {
    /// The primary reference's representation term in the units its deviations are measured in
    /// (docs/PHYSICS.md §8): relative to the profile's scale for an intensity profile
    /// ([`CaseResult::representation`]), in radians for a retardance
    /// ([`CaseResult::phase_representation`]), 0 otherwise.
    pub fn representation_tolerance(&self) -> f64 {
        let Some(primary) = self.metrics.first() else {
            return 0.0;
        };
        match primary.kind {
            MetricKind::Intensity => primary
                .derived_tolerance(&self.representation, 0.0)
                .unwrap_or(0.0),
            MetricKind::Retardance => self
                .phase_representation
                .iter()
                .fold(0.0f64, |m, x| m.max(*x)),
            _ => 0.0,
        }
    }
}

struct PointOut {
    intensity: BTreeMap<Fidelity, f64>,
    /// [`crate::harness::conditioning::intensity_rounding`] summed over the spectrum like the intensity.
    rounding: f64,
    /// [`crate::harness::conditioning::direction_sensitivity`] summed like the intensity.
    representation: f64,
    /// [`CaseResult::phase_representation`] of this point.
    phase_representation: f64,
    analytic: Vec<f64>,
    /// Retardance / visibility per reference and level.
    special: Vec<BTreeMap<Fidelity, f64>>,
    needs: SceneNeeds,
    arrivals: usize,
    /// No wave propagates toward the probe at the centre wavelength (a transmitted far-field
    /// probe beyond the critical angle): dark by physics, T = 0.
    evanescent: bool,
    internal: usize,
    /// Kept for the detection floors (`keep`): every spectral sample's weight × observable
    /// factor and what a fault touches of its arrivals (`detection::floors_of_traced`).
    kept: super::detection::PointArrivals,
    /// Kept for the convergence report (`keep_orders`): the internal reflections traced and
    /// the arrivals of a monochrome point (`convergence::convergence`, [`orders_within`]).
    orders: Option<(usize, Vec<Arrival>)>,
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

/// One spectral sample of a probe point as traced.
pub(super) struct Sample<'a> {
    /// Index in the spectrum, vacuum wavelength (m) and spectral weight.
    pub index: usize,
    pub lambda_m: f64,
    pub weight: f64,
    /// `None` where no wave propagates toward the probe (a transmitted far-field probe beyond
    /// the critical angle, [`build::propagating_target`]): no arrivals, observable 0.
    pub target: Option<Target>,
    /// The factor from |E|² to the probe's observable ([`reference::observable_factor`]).
    pub factor: f64,
    /// The sample's arrivals, lent: a visitor that keeps them copies them (they are the
    /// arrivals the next sample of a non-dispersive spectrum starts from, [`Traced`]).
    pub arrivals: &'a [Arrival],
    /// Whether `arrivals` were traced for this sample (`false`: the previous sample's, or a
    /// previous point's, at this sample's wavelength, [`Traced`]); what a visitor derives from
    /// the arrivals' paths alone stays valid while this is `false`.
    pub retraced: bool,
    /// The scene's optics at `lambda_m` (formed once per sample, or relabelled from the previous
    /// sample's for a [`dispersionless`] scene; for the tracer and the
    /// conditioning terms alike).
    pub optics: &'a crate::scene::SceneOptics,
}

/// What a traced sample's arrivals depend on besides the wavelength they carry: the scene,
/// the observer, the internal-reflection budget, the indices at the sample's wavelength and
/// the target.
#[derive(Clone, Debug, PartialEq)]
struct TraceKey {
    scene: crate::scene::Scene,
    observer: Observer,
    budget: (usize, bool),
    ambient_index: f64,
    surfaces: Vec<Option<crate::optics::interaction::SurfaceOptics>>,
    target: Target,
}

/// The arrivals last traced, and what they were traced for ([`TraceKey`]). A sample with the
/// same key has the same arrivals at its own wavelength ([`Arrival::at_wavelength`]: tracing
/// uses the wavelength only through the indices and stores it in the rays), so a spectrum
/// through non-dispersive media, and a wavelength sweep over one scene, is traced once and its
/// arrivals are set to each sample's wavelength in place: the same arrivals, bit for bit, as a
/// trace at that wavelength. Not across a total internal reflection or a tunnelling (a
/// frustrated layer's coupling depends on the wavelength through its thickness,
/// docs/PHYSICS.md §5): such arrivals are traced at every sample.
#[derive(Default)]
pub(super) struct Traced {
    key: Option<TraceKey>,
    arrivals: Vec<Arrival>,
}

impl Traced {
    /// Whether arrivals traced at one wavelength are, at another with the same indices, the
    /// same arrivals with that wavelength ([`Traced`]).
    fn wavelength_free(arrivals: &[Arrival]) -> bool {
        arrivals
            .iter()
            .all(|a| !a.path.has_tir && a.path.sequence.iter().all(|e| e.kind != EventKind::Tunnel))
    }
}

/// Whether no index of `scene` depends on the wavelength (every medium, the ambient and each
/// surface's, has a constant index): its optics at one wavelength are then its optics at any
/// other with the wavelength relabelled ([`relabelled_optics`]).
pub fn dispersionless(scene: &crate::scene::Scene) -> bool {
    use crate::optics::material::{Dispersion, Medium};
    use crate::scene::SurfaceKind;
    let constant = |m: &Medium| matches!(m.dispersion, Dispersion::Constant { .. });
    constant(&scene.ambient)
        && scene.surfaces.iter().all(|s| match &s.kind {
            SurfaceKind::Interface { front, back, .. } => constant(front) && constant(back),
            SurfaceKind::Splitter { medium, .. } => constant(medium),
            SurfaceKind::IdealMirror { .. } | SurfaceKind::Opaque { .. } => true,
        })
}

/// A scene's optics ([`crate::scene::Scene::optics`]) at `lambda_m` from its optics at another
/// wavelength, for a [`dispersionless`] scene: the same indices and layers, with the wavelength
/// they are taken at set to `lambda_m` (what `Scene::optics(lambda_m)` gives, field for field,
/// without forming the layers again).
pub fn relabelled_optics(
    optics: &crate::scene::SceneOptics,
    lambda_m: f64,
) -> crate::scene::SceneOptics {
    let mut o = optics.clone();
    relabel_optics(&mut o, lambda_m);
    o
}

/// [`relabelled_optics`] in place: the wavelength the optics are taken at set to `lambda_m`.
fn relabel_optics(optics: &mut crate::scene::SceneOptics, lambda_m: f64) {
    optics.lambda_m = lambda_m;
    for layer in optics.layers.iter_mut().flatten().flatten() {
        layer.lambda_m = lambda_m;
    }
}

/// A probe point's scene built, its optics at `lambda_m` and its propagating target, with the
/// errors at the keys that drive them (`$.scene`, `$.light`, `$.probe`); `None` where no wave
/// is transmitted to the observer (nothing is traced there). What the preflight's tree count
/// and the convergence report form at one wavelength of a point.
pub(super) fn point_at(
    case: &Case,
    pt: &ProbePoint,
    lambda_m: f64,
) -> Result<Option<(Built, crate::scene::SceneOptics, Target)>, CaseError> {
    let built = build::build_scene(&case.spec.scene, &pt.overrides)
        .map_err(|e| case_err(case, "$.scene", e))?;
    let optics = built
        .scene
        .optics(lambda_m)
        .map_err(|e| case_err(case, "$.light", e.to_string()))?;
    let target = build::propagating_target(&pt.observer, &built, lambda_m)
        .map_err(|e| case_err(case, "$.probe", e))?;
    Ok(target.map(|t| (built, optics, t)))
}

/// A probe point's scene, spectrum and internal-reflection budget; `visit` gets every
/// spectral sample traced, one at a time (a point's arrivals over a long spectrum are never
/// held together). `traced` holds the arrivals last traced (by this point or a previous one)
/// and is reused where they are the arrivals a new trace would give ([`Traced`]).
pub(super) fn trace_point(
    case: &Case,
    pt: &ProbePoint,
    traced: &mut Traced,
    mut visit: impl FnMut(&Built, &[(f64, f64)], Sample) -> Result<(), CaseError>,
) -> Result<(Built, usize), CaseError> {
    let spec = &case.spec;
    let built =
        build::build_scene(&spec.scene, &pt.overrides).map_err(|e| case_err(case, "$.scene", e))?;
    let spectrum = build::spectrum(&spec.light, &pt.overrides);
    let b = budget(case, &built, spectrum[spectrum.len() / 2].0)?;
    let internal = b.internal;
    let st = settings(case, &built, internal);
    // A previous point's arrivals serve only the same scene, observer and budget.
    if traced.key.as_ref().is_some_and(|k| {
        k.budget != (b.internal, b.closed) || k.observer != pt.observer || k.scene != built.scene
    }) {
        traced.key = None;
    }
    // The optics of a scene whose indices do not depend on the wavelength are formed once and
    // relabelled in place to each sample's wavelength (`relabelled_optics`: the same values).
    let constant_optics = dispersionless(&built.scene);
    let mut held: Option<crate::scene::SceneOptics> = None;
    for (index, &(lambda_m, weight)) in spectrum.iter().enumerate() {
        match &mut held {
            Some(o) if constant_optics => relabel_optics(o, lambda_m),
            _ => {
                held = Some(
                    built
                        .scene
                        .optics(lambda_m)
                        .map_err(|e| case_err(case, "$.light", e.to_string()))?,
                )
            }
        }
        let Some(optics) = held.as_ref() else {
            unreachable!("the optics are formed above")
        };
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
                arrivals: &[],
                retraced: true,
                optics,
            };
            visit(&built, &spectrum, sample)?;
            continue;
        };
        let reuse = traced.key.as_ref().is_some_and(|k| {
            k.target == target
                && k.ambient_index == optics.ambient_index
                && k.surfaces == optics.surfaces
        });
        if reuse {
            for a in &mut traced.arrivals {
                a.set_wavelength(lambda_m);
            }
        } else {
            traced.key = None;
            let mut arr =
                arrivals_at(case, &built, optics, &target, &pt.observer, &st).map_err(|e| {
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
                trace::tail::close(&built.scene, optics, &mut arr).map_err(|e| {
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
            if Traced::wavelength_free(&arr) {
                traced.key = Some(TraceKey {
                    scene: built.scene.clone(),
                    observer: pt.observer.clone(),
                    budget: (b.internal, b.closed),
                    ambient_index: optics.ambient_index,
                    surfaces: optics.surfaces.clone(),
                    target,
                });
            }
            traced.arrivals = arr;
        }
        // |E|² → the observable the probe measures (R or T of a plane wave in the far field).
        let factor = reference::observable_factor(&pt.observer, &built, &target, lambda_m)
            .map_err(|e| case_err(case, "$.probe", e))?;
        let sample = Sample {
            index,
            lambda_m,
            weight,
            target: Some(target),
            factor,
            arrivals: &traced.arrivals,
            retraced: !reuse,
            optics,
        };
        visit(&built, &spectrum, sample)?;
    }
    Ok((built, internal))
}

/// Trace one probe point at every level; `keep`: also hand back every sample's arrivals
/// ([`PointOut::kept`]).
fn run_point(
    case: &Case,
    pt: &ProbePoint,
    levels: &[Fidelity],
    (keep, keep_orders): (bool, bool),
    traced: &mut Traced,
) -> Result<PointOut, CaseError> {
    let spec = &case.spec;
    let mut out = PointOut {
        intensity: levels.iter().map(|l| (*l, 0.0)).collect(),
        rounding: 0.0,
        representation: 0.0,
        phase_representation: 0.0,
        analytic: vec![0.0; spec.references.len()],
        special: vec![BTreeMap::new(); spec.references.len()],
        needs: SceneNeeds::default(),
        arrivals: 0,
        evanescent: false,
        internal: 0,
        kept: Vec::new(),
        orders: None,
    };
    let mut kept = Vec::new();
    let mut center_target = None;
    let mut center = 0.0;
    let mut acc = Accumulator::new();
    let mut contributions = Vec::new();
    // The `vector` contributions of the sample, for the conditioning terms.
    let mut vector = Vec::new();
    let mut cycles = Vec::new();
    // The conditioning terms' wavelength-free parts of the arrivals last traced.
    type PathTerms = (Option<conditioning::RoundingTerms>, Option<Vec<f64>>);
    let mut path_terms: Option<PathTerms> = None;
    let (built, internal) = trace_point(case, pt, traced, |built, spectrum, sample| {
        let Sample {
            index: k,
            lambda_m: lambda,
            weight: w,
            target,
            factor,
            arrivals: arr,
            retraced,
            optics,
        } = sample;
        // `trace::intensity` of each level, with the accumulator and contributions reused
        // (the same sums: a cleared accumulator is a new one).
        let reference = arr.first().map(|a| a.vector.optical_path);
        // Every rung starts from the same paths: each arrival's phase is reduced once
        // (`trace::ArrivalCycles`), and the rungs take their contributions from it.
        cycles.clear();
        if let Some(r) = reference {
            let with_paper = levels.contains(&Fidelity::PaperRules);
            cycles.extend(
                arr.iter()
                    .map(|a| trace::ArrivalCycles::of(a, r, with_paper)),
            );
        }
        let mut vector_intensity = None;
        for l in levels {
            contributions.clear();
            contributions.extend(
                arr.iter()
                    .zip(&cycles)
                    .map(|(a, c)| trace::contribution_with(a, *l, c)),
            );
            acc.clear();
            acc.extend(&contributions);
            let i = acc.intensity();
            if *l == Fidelity::Vector {
                vector_intensity = Some(i);
                // Kept for the conditioning terms below (the same contributions).
                std::mem::swap(&mut vector, &mut contributions);
            }
            *out.intensity.get_mut(l).unwrap() += w * factor * i;
        }
        if vector_intensity.is_none() {
            vector.clear();
            vector.extend(
                arr.iter()
                    .zip(&cycles)
                    .map(|(a, c)| trace::contribution_with(a, Fidelity::Vector, c)),
            );
        }
        // A sum cut where the Airy tail bound falls below `airy_tail_epsilon` (not closed) is
        // off the full sum by what the case asked to leave out (budget::tail_truncation).
        if let (Some(eps), Some(i), false) = (
            spec.trace.airy_tail_epsilon,
            vector_intensity,
            arr.iter().any(|a| a.tail.is_some()),
        ) {
            let sources = built.scene.sources.iter().map(|s| s.intensity.sqrt()).sum();
            out.rounding += w * budget::tail_truncation(factor * i, eps, sources);
        }
        if retraced {
            path_terms = None;
        }
        if let Some(r) = reference {
            // What the rounding and direction terms read from the paths alone, formed once
            // for the arrivals of a spectrum traced once (`conditioning::RoundingTerms`,
            // `conditioning::direction_offsets`: the same values, bit for bit).
            let (rounding_terms, offsets) = path_terms.get_or_insert_with(|| {
                (
                    conditioning::RoundingTerms::of(arr, r, &built.scene),
                    conditioning::direction_offsets(arr, &built.scene),
                )
            });
            let rounding = match rounding_terms {
                Some(t) => t.intensity_rounding(arr, &vector, lambda),
                None => {
                    conditioning::intensity_rounding(arr, r, &vector, lambda, &built.scene, optics)
                }
            };
            out.rounding += w * factor * rounding;
            let direction = offsets.as_ref().map_or(0.0, |o| {
                conditioning::direction_sensitivity_of(o, &vector, lambda)
            });
            // The representation term: the phase (direction_sensitivity) and the amplitudes
            // (amplitude_sensitivity; the transmitted power factor's own, relative) of a scene
            // whose plane-wave direction and normals are held one rounding off.
            out.representation += w
                * factor
                * (direction
                    + crate::harness::conditioning::amplitude_sensitivity(
                        arr,
                        &vector,
                        &built.scene,
                        optics,
                    )
                    + vector_intensity.unwrap_or(0.0)
                        * reference::observable_factor_representation(&pt.observer, built, lambda));
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
                                EventKind::Tunnel => "tunnelled through the layer behind",
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
            out.needs = trace::needs(arr);
            // Retardance and visibility are measured on the centre sample's arrivals.
            for (ri, r) in spec.references.iter().enumerate() {
                if matches!(
                    reference::kind(&r.model),
                    MetricKind::Retardance | MetricKind::Visibility
                ) {
                    for l in levels {
                        if let Some(v) = special_value(&r.model, built, arr, *l) {
                            out.special[ri].insert(*l, v);
                        }
                    }
                }
            }
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
        if keep {
            kept.push((w * factor, super::detection::fault_rays(arr)));
        }
        if keep_orders && spectrum.len() == 1 {
            out.orders = Some((0, arr.to_vec()));
        }
        Ok(())
    })?;
    out.internal = internal;
    out.kept = kept;
    if let Some(o) = &mut out.orders {
        o.0 = internal;
    }
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
                if ri == 0 {
                    out.phase_representation =
                        reference::phase_representation(&r.model, &built, center);
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
    // Every point's result in probe order, then the first error by probe index: rayon's
    // `collect` into a Result returns whichever failing point finished first, so the reason a
    // case is refused would depend on thread scheduling.
    // The points the detection floors sample keep their arrivals: the floors are measured on
    // the very arrivals traced here, not on a second trace of them.
    let sampled = super::detection::sampled_points(points.len());
    // The points the convergence report sums over keep their arrivals too: its rungs are
    // the traced orders up to each budget (`convergence::convergence`).
    let orders_sampled = if convergence_report {
        convergence_points(case, points.len())
    } else {
        Vec::new()
    };
    // Each worker keeps the arrivals it traced last: a wavelength sweep over one
    // non-dispersive scene is traced once per worker ([`Traced`]; the same arrivals, bit for
    // bit, whichever points a worker runs).
    let outs: Vec<PointOut> = points
        .par_iter()
        .enumerate()
        .map_init(Traced::default, |traced, (i, pt)| {
            let keep = convergence_report && sampled.binary_search(&i).is_ok();
            let keep_orders = orders_sampled.binary_search(&i).is_ok();
            run_point(case, pt, &levels, (keep, keep_orders), traced)
        })
        .collect::<Vec<_>>()
        .into_iter()
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
        representation: outs.iter().map(|o| o.representation).collect(),
        phase_representation: outs.iter().map(|o| o.phase_representation).collect(),
    };
    if convergence_report {
        let mut outs = outs;
        let kept_orders: Vec<Option<(usize, Vec<Arrival>)>> = orders_sampled
            .iter()
            .map(|&i| outs[i].orders.take())
            .collect();
        result.convergence = convergence(case, &points, kept_orders)?;
        let traced = outs
            .into_iter()
            .enumerate()
            .filter(|(i, _)| sampled.binary_search(i).is_ok())
            .map(|(_, o)| o.kept)
            .collect();
        result.detection = super::detection::floors_of_traced(&result, traced);
    }
    Ok(result)
}
