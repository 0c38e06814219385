//! Exact tracing at a point: every source channel along every surface sequence that reaches
//! the target, each ray carried through the real interactions (with its ledger), then turned
//! into accumulation-core contributions at any rung of the fidelity ladder.

use crate::accumulate::{Accumulator, Contribution};
use crate::fidelity::{Fidelity, SceneNeeds};
use crate::interaction::{
    CoefficientModel, InterfaceHit, JonesFrame, interact_along, interact_along_shared,
};
use crate::path::{
    self, EnumerationLimits, EventKind, PathError, Sequence, SolveOptions, SolvedPath, Target,
};
use crate::ray::{INCOHERENT, LedgerEntry, Ray};
use crate::scene::{Scene, SceneOptics};
use crate::source::{Channel, field_reference};
use glam::DVec3;
use num_complex::Complex64;
use std::sync::Arc;

/// Tracing settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceSettings {
    pub limits: EnumerationLimits,
    pub solve: SolveOptions,
}

impl Default for TraceSettings {
    fn default() -> Self {
        TraceSettings {
            limits: EnumerationLimits::default(),
            solve: SolveOptions::default(),
        }
    }
}

/// The candidate surface sequences of every source, discovered once per scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub sequences: Vec<Vec<Sequence>>,
}

/// Discover the sequences of every source with probe rays toward `probe_targets` (typically the
/// detector's corners and centre) and toward every surface and its mirror images.
pub fn plan(
    scene: &Scene,
    optics: &SceneOptics,
    probe_targets: &[DVec3],
    limits: &EnumerationLimits,
) -> Plan {
    let mut targets: Vec<DVec3> = probe_targets.to_vec();
    for surf in &scene.surfaces {
        targets.push(surf.plane.point);
        for &p in probe_targets {
            // The specular point of p on this plane, seen from each source.
            for src in &scene.sources {
                let a = src.anchor();
                let img = surf.plane.mirror_point(p);
                if let Some(t) = surf.plane.intersect(a, (img - a).normalize()) {
                    if t > 0.0 {
                        targets.push(a + t * (img - a).normalize());
                    }
                }
            }
        }
    }
    Plan {
        sequences: scene
            .sources
            .iter()
            .map(|s| path::discover_sequences(scene, optics, s.emitter, &targets, limits))
            .collect(),
    }
}

/// One ray arriving at a target, with its exact path and its state under both polarized models.
#[derive(Clone, Debug)]
pub struct Arrival {
    pub source: usize,
    pub channel: Channel,
    /// The solved path (shared by the source's channels along it).
    pub path: Arc<SolvedPath>,
    /// The ray propagated with complex Fresnel coefficients.
    pub vector: Ray,
    /// The ray propagated with the paper's rules (`None` when traced without them, see
    /// [`arrivals_with`]).
    pub paper: Option<Ray>,
}

/// A sequence that did not give a path, and why (for reports).
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    pub source: usize,
    pub sequence: Sequence,
    pub error: PathError,
}

/// A channel's ray at the launch point of a solved path (no ledger entries yet), given the
/// launch direction normalized, `unit = path.dirs[0].normalize()`, and the channel's field
/// reference `e_ref = field_reference(channel.reference, path.dirs[0])`.
fn launch_ray_with(
    optics: &SceneOptics,
    channel: &Channel,
    coherence_length_m: f64,
    path: &SolvedPath,
    unit: DVec3,
    e_ref: DVec3,
) -> Ray {
    let d0 = path.dirs[0];
    let mut ray = Ray::linear_unit(
        path.points[0],
        unit,
        channel.field_direction_from(e_ref, d0),
        (channel.intensity * path.spreading).sqrt(),
        optics.lambda_m,
        optics.ambient_index,
    );
    ray.coherence_id = channel.coherence_id;
    ray.coherence_length_m = coherence_length_m;
    ray
}

/// A channel's ray at the launch point of a solved path (no ledger entries yet).
fn launch_ray(
    optics: &SceneOptics,
    channel: &Channel,
    coherence_length_m: f64,
    path: &SolvedPath,
) -> Ray {
    let d0 = path.dirs[0];
    let e_ref = field_reference(channel.reference, d0);
    launch_ray_with(
        optics,
        channel,
        coherence_length_m,
        path,
        d0.normalize(),
        e_ref,
    )
}

/// The interface met at event `k` of a solved path.
fn hit_at(scene: &Scene, optics: &SceneOptics, path: &SolvedPath, k: usize) -> InterfaceHit {
    let ev = path.sequence[k];
    let surf = &scene.surfaces[ev.surface];
    InterfaceHit {
        surface: ev.surface,
        point: path.points[k + 1],
        normal: surf.plane.normal,
        optics: optics.surfaces[ev.surface].expect("solved paths only meet non-opaque surfaces"),
        coherence: surf.coherence(),
    }
}

/// The last leg of a ray after its last event: to the target point, or to the far-field
/// wavefront; then the paper's coherence-length rule.
fn end_ray(ray: &mut Ray, target: &Target, coherence_length_m: f64) {
    match target {
        Target::Point(p) => ray.advance_to(*p),
        Target::Direction { reference, .. } => {
            // Projection onto the far-field wavefront through `reference`.
            let proj = -ray.dir.dot(ray.origin - *reference);
            ray.optical_path_m += ray.index * proj;
            ray.ledger.entries.push(LedgerEntry::Path {
                index: ray.index,
                length_m: proj,
            });
        }
    }
    // The paper's coherence-length rule (P9): a ray whose own path exceeds the source's
    // coherence length loses coherence.
    if ray.optical_path_m > coherence_length_m && ray.coherence_id != INCOHERENT {
        ray.coherence_id = INCOHERENT;
        ray.ledger
            .entries
            .push(LedgerEntry::CoherenceLost { surface: None });
    }
}

/// Per event a path, an interaction and perhaps a coherence loss; then the last path and
/// perhaps the coherence-length loss.
fn ledger_capacity(path: &SolvedPath) -> usize {
    3 * path.sequence.len() + 2
}

/// Carry a channel's ray along a solved path through the real interactions.
pub fn propagate(
    scene: &Scene,
    optics: &SceneOptics,
    channel: &Channel,
    coherence_length_m: f64,
    path: &SolvedPath,
    target: &Target,
    model: CoefficientModel,
) -> Ray {
    let mut ray = launch_ray(optics, channel, coherence_length_m, path);
    ray.ledger.entries.reserve(ledger_capacity(path));
    for (k, ev) in path.sequence.iter().enumerate() {
        let hit = hit_at(scene, optics, path, k);
        ray = interact_along(ray, &hit, model, ev.kind == EventKind::Reflect)
            .expect("solved paths only refract where a refracted ray exists");
    }
    end_ray(&mut ray, target, coherence_length_m);
    ray
}

/// The most channels [`propagate_channels`] carries in one pass (a source has one or two).
const SHARED_CHANNELS: usize = 4;

/// [`propagate`] for every channel of a source along one path, in one pass: the channels differ
/// only in polarization, so each interaction's geometry, coefficients and ledger entry are
/// computed once ([`interact_along_shared`]). `emit(k, ray)` receives channel k's ray, in
/// order; each is bitwise the ray [`propagate`] gives that channel.
#[allow(clippy::too_many_arguments)]
pub fn propagate_channels(
    scene: &Scene,
    optics: &SceneOptics,
    channels: &[Channel],
    coherence_length_m: f64,
    path: &SolvedPath,
    target: &Target,
    model: CoefficientModel,
    mut emit: impl FnMut(usize, Ray),
) {
    // The last channel's ray is carried in full; the others' frames ride along.
    let Some((last, rest)) = channels.split_last() else {
        return;
    };
    // The rays share their coherence id's fate only if all start coherent or all incoherent.
    let incoherent = last.coherence_id == INCOHERENT;
    if channels.len() > SHARED_CHANNELS
        || rest
            .iter()
            .any(|c| (c.coherence_id == INCOHERENT) != incoherent)
    {
        for (k, ch) in channels.iter().enumerate() {
            emit(
                k,
                propagate(scene, optics, ch, coherence_length_m, path, target, model),
            );
        }
        return;
    }
    // The launch direction and the field reference are shared too (bit for bit: one
    // reference gives one projection).
    let d0 = path.dirs[0];
    let unit = d0.normalize();
    let e_ref = field_reference(last.reference, d0);
    let launch = |ch: &Channel| {
        let same = ch.reference.to_array().map(f64::to_bits)
            == last.reference.to_array().map(f64::to_bits);
        let e = if same {
            e_ref
        } else {
            field_reference(ch.reference, d0)
        };
        launch_ray_with(optics, ch, coherence_length_m, path, unit, e)
    };
    let mut lead = launch(last);
    lead.ledger.entries.reserve(ledger_capacity(path));
    let mut frames = [JonesFrame::default(); SHARED_CHANNELS - 1];
    let others = &mut frames[..rest.len()];
    for (f, ch) in others.iter_mut().zip(rest) {
        *f = JonesFrame::of(&launch(ch));
    }
    for (k, ev) in path.sequence.iter().enumerate() {
        let hit = hit_at(scene, optics, path, k);
        let ok = interact_along_shared(
            &mut lead,
            others,
            &hit,
            model,
            ev.kind == EventKind::Reflect,
        );
        assert!(ok, "solved paths only refract where a refracted ray exists");
    }
    end_ray(&mut lead, target, coherence_length_m);
    // The others differ from the lead only in frame and coherence id.
    let lost = lead.coherence_id == INCOHERENT;
    for (k, (f, ch)) in others.iter().zip(rest).enumerate() {
        let mut ray = lead.clone();
        f.apply_to(&mut ray);
        ray.coherence_id = if lost { INCOHERENT } else { ch.coherence_id };
        emit(k, ray);
    }
    emit(rest.len(), lead);
}

/// Every ray reaching `target`, and every candidate sequence that did not.
pub fn arrivals(
    scene: &Scene,
    optics: &SceneOptics,
    plan: &Plan,
    target: &Target,
    settings: &TraceSettings,
) -> (Vec<Arrival>, Vec<Failure>) {
    let mut failed = Vec::new();
    let found = arrivals_with(
        scene,
        optics,
        plan,
        target,
        settings,
        true,
        Some(&mut failed),
    );
    (found, failed)
}

/// Every ray reaching `target` ([`arrivals`]), propagated under the paper's rules too only
/// when `paper_rules` (a render that shows no `paper_rules` picture skips that half of the
/// work), with the failed sequences pushed to `failed` when given. Without a failure list,
/// sequences that [`path::cannot_reach`] rules out are not solved at all (the arrivals are the
/// same; only the reasons would be missing). The channels of a source are carried along each
/// path together ([`propagate_channels`]).
pub fn arrivals_with(
    scene: &Scene,
    optics: &SceneOptics,
    plan: &Plan,
    target: &Target,
    settings: &TraceSettings,
    paper_rules: bool,
    mut failed: Option<&mut Vec<Failure>>,
) -> Vec<Arrival> {
    let mut found = Vec::new();
    for (si, src) in scene.sources.iter().enumerate() {
        let channels = src.channels();
        for seq in &plan.sequences[si] {
            // Without a failure list the reason is not needed: skip what surely fails.
            if failed.is_none() && path::cannot_reach(scene, src.emitter, seq, target) {
                continue;
            }
            let p = match path::solve(scene, optics, src.emitter, seq, *target, &settings.solve) {
                Ok(p) => Arc::new(p),
                Err(error) => {
                    if let Some(f) = failed.as_deref_mut() {
                        f.push(Failure {
                            source: si,
                            sequence: seq.clone(),
                            error,
                        });
                    }
                    continue;
                }
            };
            let first = found.len();
            let along = |model, emit: &mut dyn FnMut(usize, Ray)| {
                let coherence_length_m = src.coherence_length_m;
                propagate_channels(
                    scene,
                    optics,
                    &channels,
                    coherence_length_m,
                    &p,
                    target,
                    model,
                    emit,
                )
            };
            along(CoefficientModel::Vector, &mut |k, vector| {
                found.push(Arrival {
                    source: si,
                    channel: channels[k],
                    path: Arc::clone(&p),
                    vector,
                    paper: None,
                })
            });
            if paper_rules {
                along(CoefficientModel::PaperRules, &mut |k, ray| {
                    found[first + k].paper = Some(ray)
                });
            }
        }
    }
    found
}

/// The panic message of asking for `paper_rules` of an arrival traced without them.
pub const PAPER_MISSING: &str =
    "paper_rules asked of an arrival traced without the paper's rules (trace::arrivals_with)";

/// The accumulation-core contribution of an arrival at a rung of the ladder, with its path
/// phase measured from the optical path `reference_m` (m): path differences are formed in
/// metres before dividing by λ, so metre-long paths keep their phase differences to ~1e-17 m.
pub fn contribution_from(a: &Arrival, level: Fidelity, reference_m: f64) -> Contribution {
    let v = &a.vector;
    let cycles = |r: &Ray| (r.optical_path_m - reference_m) / r.wavelength_m;
    let scalar = |extra_cycles: f64| Contribution {
        coherence_id: v.coherence_id,
        phase_cycles: cycles(v) + extra_cycles,
        field: [
            Complex64::from(v.intensity().sqrt()),
            Complex64::default(),
            Complex64::default(),
        ],
    };
    match level {
        Fidelity::Incoherent => Contribution {
            coherence_id: INCOHERENT,
            ..scalar(0.0)
        },
        Fidelity::Scalar => scalar(0.0),
        Fidelity::ScalarJump => scalar(0.5 * a.path.denser_reflections as f64),
        Fidelity::PaperRules => {
            let paper = a.paper.as_ref().expect(PAPER_MISSING);
            Contribution {
                coherence_id: paper.coherence_id,
                phase_cycles: cycles(paper),
                field: paper.field(),
            }
        }
        Fidelity::Vector => Contribution {
            coherence_id: v.coherence_id,
            phase_cycles: cycles(v),
            field: v.field(),
        },
    }
}

/// [`contribution_from`] with the absolute optical path (phase referred to the source).
pub fn contribution(a: &Arrival, level: Fidelity) -> Contribution {
    contribution_from(a, level, 0.0)
}

/// The contributions of all arrivals at one point, phases referred to the first arrival's
/// optical path (a common phase does not change any intensity).
pub fn contributions(arrivals: &[Arrival], level: Fidelity) -> Vec<Contribution> {
    let reference_m = arrivals.first().map_or(0.0, |a| a.vector.optical_path_m);
    arrivals
        .iter()
        .map(|a| contribution_from(a, level, reference_m))
        .collect()
}

/// Intensity of a set of arrivals at a rung of the ladder.
pub fn intensity(arrivals: &[Arrival], level: Fidelity) -> f64 {
    let mut acc = Accumulator::new();
    acc.extend(&contributions(arrivals, level));
    acc.intensity()
}

/// What the arrivals at one point need from the ladder (merge points with [`merge_needs`]).
pub fn needs(arrivals: &[Arrival]) -> SceneNeeds {
    let mut n = SceneNeeds {
        parallel_fields: true,
        ..Default::default()
    };
    for (i, a) in arrivals.iter().enumerate() {
        n.interfaces |= !a.path.sequence.is_empty();
        n.tir |= a.path.has_tir;
        let id = a.vector.coherence_id;
        if id == INCOHERENT {
            continue;
        }
        for b in &arrivals[..i] {
            if b.vector.coherence_id != id {
                continue;
            }
            n.interference = true;
            // Parallel, real-proportional fields: |E_a·E_b*| = |E_a||E_b|.
            let (ea, eb) = (a.vector.field(), b.vector.field());
            let dot: Complex64 = (0..3).map(|k| ea[k] * eb[k].conj()).sum();
            let na = a.vector.intensity().sqrt();
            let nb = b.vector.intensity().sqrt();
            if (dot.norm() - na * nb).abs() > 1e-12 * na * nb || dot.im.abs() > 1e-12 * na * nb {
                n.parallel_fields = false;
            }
        }
    }
    n
}

/// Combine the needs of several points.
pub fn merge_needs(a: SceneNeeds, b: SceneNeeds) -> SceneNeeds {
    SceneNeeds {
        interference: a.interference || b.interference,
        interfaces: a.interfaces || b.interfaces,
        parallel_fields: a.parallel_fields && b.parallel_fields,
        tir: a.tir || b.tir,
        polarization_state: a.polarization_state || b.polarization_state,
    }
}
