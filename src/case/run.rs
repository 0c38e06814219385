//! Running a case: trace every probe point at every fidelity level, evaluate the closed forms,
//! and compare. Probe points run in parallel (rayon); results are deterministic.

use super::build::{self, Built, Overrides, ProbePoint};
use super::load::{Case, CaseError};
use super::reference::{self, MetricKind};
use super::spec::{FarSide, Light, Observer, Probe, ReferenceModel};
use crate::accumulate::Accumulator;
use crate::fidelity::{self, Fidelity, SceneNeeds};
use crate::observable::{Observable, Returns, check_match};
use crate::path::{EnumerationLimits, SolveOptions, Target};
use crate::source::Emitter;
use crate::trace::{self, Arrival, TraceSettings};
use glam::DVec3;
use num_complex::Complex64;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::time::Instant;

/// Traced and closed-form values of one reference over the probe.
#[derive(Clone, Debug)]
pub struct MetricResult {
    /// Index of the reference in the case file.
    pub index: usize,
    pub name: String,
    pub model: ReferenceModel,
    pub kind: MetricKind,
    pub coordinates: Vec<f64>,
    pub analytic: Vec<f64>,
    /// Traced values per fidelity level (levels where the metric is undefined are absent).
    pub traced: BTreeMap<Fidelity, Vec<f64>>,
    pub tolerances: BTreeMap<Fidelity, f64>,
    pub tolerance_note: Option<String>,
}

/// Deviation statistics of one level against one reference.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelStats {
    pub max_abs_dev: f64,
    pub rms_dev: f64,
    /// Where the largest deviation occurs (probe coordinate).
    pub at: f64,
}

impl MetricResult {
    /// The scale deviations are divided by: the largest |reference| of an intensity profile,
    /// and |reference| pointwise for the other kinds.
    pub fn deviations(&self, level: Fidelity) -> Option<Vec<f64>> {
        let t = self.traced.get(&level)?;
        // Floor: profiles that vanish everywhere (e.g. p light at Brewster's angle) are judged
        // on an absolute scale of 1e-15 of a unit source.
        let scale = self.analytic.iter().fold(1e-15f64, |m, a| m.max(a.abs()));
        Some(
            t.iter()
                .zip(&self.analytic)
                .map(|(t, a)| {
                    let s = match self.kind {
                        MetricKind::Intensity => scale,
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
    pub orders: usize,
    pub internal_reflections: usize,
    pub max_abs_dev: f64,
    /// The geometric-tail bound on |R_N − R| (2|r|τ + τ², τ the amplitude tail bound), maximised
    /// over the probe.
    pub bound: f64,
}

/// Everything a case run produced.
#[derive(Clone, Debug)]
pub struct CaseResult {
    pub name: String,
    pub description: String,
    pub formula: String,
    pub levels: Vec<Fidelity>,
    pub metrics: Vec<MetricResult>,
    pub auto: fidelity::AutoChoice,
    pub trace_seconds: f64,
    pub level_seconds: BTreeMap<Fidelity, f64>,
    pub convergence: Vec<ConvergenceRow>,
    /// Internal reflections used per probe point (max over points).
    pub internal_reflections: usize,
    /// Probe points that no light reached.
    pub dark_points: usize,
    /// What the probe measures (intensity references compare this observable).
    pub observable: Observable,
}

struct PointOut {
    intensity: BTreeMap<Fidelity, f64>,
    analytic: Vec<f64>,
    /// Retardance / visibility per reference and level.
    special: Vec<BTreeMap<Fidelity, f64>>,
    needs: SceneNeeds,
    arrivals: usize,
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

/// The internal-reflection budget at a probe point.
fn internal_reflections(case: &Case, built: &Built, lambda_m: f64) -> Result<usize, CaseError> {
    let spec = &case.spec;
    let Some(eps) = spec.trace.airy_tail_epsilon else {
        return Ok(spec.trace.max_internal_reflections);
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
    let orders = [
        crate::analytic::plate::Pol::S,
        crate::analytic::plate::Pol::P,
    ]
    .into_iter()
    .map(|p| f.orders_for_bound(cos1, lambda_m, p, eps))
    .max()
    .unwrap_or(1);
    // The bound holds only if every order it asks for is traced: never cap silently.
    let internal = 2 * orders + 1;
    let cap = super::load::limits::MAX_INTERNAL_REFLECTIONS;
    if internal > cap {
        return Err(case_err(
            case,
            "$.trace.airy_tail_epsilon",
            format!(
                "the Airy tail bound {eps:e} needs {orders} reflected orders ({internal} internal \
                 reflections) at {:.1} nm and θ1 = {:.4}°, more than the cap of {cap}: the plate \
                 reflects too well there (|r21 r23| → 1 near grazing incidence); loosen \
                 airy_tail_epsilon or move the probe away from grazing",
                lambda_m * 1e9,
                cos1.clamp(-1.0, 1.0).acos().to_degrees()
            ),
        ));
    }
    Ok(internal)
}

/// Path events a case may trace before it is refused (see [`preflight`]).
pub const MAX_PATH_EVENTS: f64 = 1.0e9;

/// The tracing work of a case, checked before anything runs: Σ over probe points of (spectral
/// samples) × (path events per point), m the internal-reflection budget at the point (the Airy
/// tail rule may raise it near grazing incidence), and tracing time is proportional to the
/// events. Plane waves observed in the far field are walked as a tree of shared beginnings
/// (`trace`'s far-field walk: each internal reflection adds a reflected and a transmitted
/// branch), 2(m + 2) events; any other point traces every sequence from its source, and
/// (m + 2)² bounds the events of all sequences of a plane-parallel plate with up to m internal
/// reflections (about m/2 orders of up to m + 2 events each). A case over [`MAX_PATH_EVENTS`] is
/// refused with an error naming the key that drives it; so is a tail bound that needs more
/// internal reflections than the cap.
pub fn preflight(case: &Case) -> Result<f64, CaseError> {
    let spec = &case.spec;
    let mut events = 0.0;
    let mut worst = 0;
    for pt in build::probe_points(&spec.probe) {
        let built = build::build_scene(&spec.scene, &pt.overrides)
            .map_err(|e| case_err(case, "$.scene", e))?;
        let spectrum = build::spectrum(&spec.light, &pt.overrides);
        let internal = internal_reflections(case, &built, spectrum[spectrum.len() / 2].0)?;
        worst = worst.max(internal);
        let walked = !matches!(pt.observer, Observer::Point { .. })
            && built
                .scene
                .sources
                .iter()
                .all(|s| matches!(s.emitter, Emitter::PlaneWave { .. }));
        let m = (internal + 2) as f64;
        events += spectrum.len() as f64 * if walked { 2.0 * m } else { m * m };
    }
    if events > MAX_PATH_EVENTS {
        let key = if spec.trace.airy_tail_epsilon.is_some() {
            "$.trace.airy_tail_epsilon"
        } else {
            "$.trace.max_internal_reflections"
        };
        return Err(case_err(
            case,
            key,
            format!(
                "this case would trace about {events:.2e} path events (probe points × spectral \
                 samples × path events per point: (internal reflections + 2)², or twice \
                 (internal reflections + 2) for plane waves in the far field; up to {worst} \
                 internal reflections), more than the work cap of {MAX_PATH_EVENTS:.0e}: use \
                 fewer probe points or spectral samples, or fewer internal reflections"
            ),
        ));
    }
    Ok(events)
}

/// The tracer settings of a case at a probe point: its internal-reflection budget (or the Airy
/// tail rule at `lambda_m`), spreading as configured.
pub fn trace_settings(
    case: &Case,
    built: &Built,
    lambda_m: f64,
) -> Result<TraceSettings, CaseError> {
    Ok(settings(
        case,
        built,
        internal_reflections(case, built, lambda_m)?,
    ))
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

/// All arrivals at a target that the observer records.
fn arrivals_at(
    built: &Built,
    optics: &crate::scene::SceneOptics,
    target: &Target,
    observer: &Observer,
    st: &TraceSettings,
) -> Vec<Arrival> {
    let plan = trace::plan(&built.scene, optics, &probe_targets(target), &st.limits);
    let mut arr = trace::arrivals(&built.scene, optics, &plan, target, st).0;
    arr.retain(|a| build::records(observer, a.vector.dir));
    arr
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

fn run_point(case: &Case, pt: &ProbePoint, levels: &[Fidelity]) -> Result<PointOut, CaseError> {
    let spec = &case.spec;
    let built =
        build::build_scene(&spec.scene, &pt.overrides).map_err(|e| case_err(case, "$.scene", e))?;
    let spectrum = build::spectrum(&spec.light, &pt.overrides);
    let center = spectrum[spectrum.len() / 2].0;
    let internal = internal_reflections(case, &built, center)?;
    let st = settings(case, &built, internal);
    let mut out = PointOut {
        intensity: levels.iter().map(|l| (*l, 0.0)).collect(),
        analytic: vec![0.0; spec.references.len()],
        special: vec![BTreeMap::new(); spec.references.len()],
        needs: SceneNeeds::default(),
        arrivals: 0,
        internal,
    };
    let mut center_arrivals = Vec::new();
    let mut center_target = None;
    for (k, &(lambda, w)) in spectrum.iter().enumerate() {
        let optics = built
            .scene
            .optics(lambda)
            .map_err(|e| case_err(case, "$.light", e.to_string()))?;
        let target = build::target(&pt.observer, &built, lambda)
            .map_err(|e| case_err(case, "$.probe", e))?;
        let arr = arrivals_at(&built, &optics, &target, &pt.observer, &st);
        // |E|² → the observable the probe measures (R or T of a plane wave in the far field).
        let factor = reference::observable_factor(&pt.observer, &built, &target, lambda)
            .map_err(|e| case_err(case, "$.probe", e))?;
        for l in levels {
            *out.intensity.get_mut(l).unwrap() += w * factor * trace::intensity(&arr, *l);
        }
        for (ri, r) in spec.references.iter().enumerate() {
            if reference::kind(&r.model) == MetricKind::Intensity
                && !matches!(
                    r.model,
                    ReferenceModel::CoherenceGaussian { .. } | ReferenceModel::CoherenceP9 { .. }
                )
            {
                let v = reference::value(&r.model, &built, &target, lambda, spec.trace.spreading)
                    .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
                let v = match reference::returns(&r.model) {
                    Some(Returns::AsProbe) => v * factor,
                    _ => v,
                };
                out.analytic[ri] += w * v;
            }
        }
        if k == spectrum.len() / 2 {
            out.arrivals = arr.len();
            out.needs = trace::needs(&arr);
            center_arrivals = arr;
            center_target = Some(target);
        }
    }
    let target = center_target.expect("the spectrum has at least one sample");
    for (ri, r) in spec.references.iter().enumerate() {
        match reference::kind(&r.model) {
            MetricKind::Retardance | MetricKind::Visibility => {
                out.analytic[ri] =
                    reference::value(&r.model, &built, &target, center, spec.trace.spreading)
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
                out.analytic[ri] =
                    reference::coherence(&r.model, &built, &target, &spectrum, c, g.map(|g| g.1))
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
    let mut arr = arrivals_at(built, &optics, &Target::Point(p0), &observer, &st);
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
                    crate::source::Emitter::Line { point, axis } => Some((point, axis)),
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
                crate::analytic::young::fringe_spacing_paraxial(d, l, lambda, n)
            } else {
                crate::analytic::young::fringe_spacing_exact_on_axis(d, l, lambda, n)
            })
        }
        ReferenceModel::WedgeSpacing { wedge, small_angle } => {
            let top = &built.scene.surfaces[built.surface(&format!("{wedge}.top"))?];
            let bottom = &built.scene.surfaces[built.surface(&format!("{wedge}.bottom"))?];
            let crate::scene::SurfaceKind::Interface { back: glass, .. } = &top.kind else {
                return Err("wedge faces must be interfaces".into());
            };
            let n = glass.index(lambda).map_err(|e| e.to_string())?;
            let alpha = crate::geometry::angle_between(top.plane.normal, bottom.plane.normal);
            Ok(if *small_angle {
                crate::analytic::wedge::fringe_spacing_small_angle(lambda, n, alpha)
            } else {
                crate::analytic::wedge::fringe_spacing_exact(lambda, n, alpha)
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
    let dark_points = outs.iter().filter(|o| o.arrivals == 0).count();
    if dark_points == points.len() {
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
    };
    if convergence_report {
        result.convergence = convergence(case, &points)?;
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
            && let Some(crate::case::spec::SurfaceSpec::Plate { normal, .. }) =
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
    for orders in [1usize, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64] {
        let internal = 2 * orders - 1;
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
                let target = build::target(&pt.observer, &built, lambda)
                    .map_err(|e| case_err(case, "$.probe", e))?;
                let st = settings(case, &built, internal);
                let factor = reference::observable_factor(&pt.observer, &built, &target, lambda)
                    .map_err(|e| case_err(case, "$.probe", e))?;
                let traced = factor
                    * trace::intensity(
                        &arrivals_at(&built, &optics, &target, &pt.observer, &st),
                        Fidelity::Vector,
                    );
                let exact =
                    reference::value(&spec.references[ri].model, &built, &target, lambda, false)
                        .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
                let (f, cos1) = reference::airy_film(&built, &film, lambda)
                    .map_err(|e| case_err(case, "$.references", e))?;
                let tau = [
                    crate::analytic::plate::Pol::S,
                    crate::analytic::plate::Pol::P,
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
