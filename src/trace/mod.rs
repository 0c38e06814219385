//! Exact tracing at a point: every source channel along every surface sequence that reaches
//! the target, each ray carried through the real interactions (with its ledger), then turned
//! into accumulation-core contributions at any rung of the fidelity ladder.
//!
//! The sequences of a source are a tree of shared beginnings ([`SequenceTree`]). A plane wave
//! observed in the far field walks it depth first (`far_field_walk`): each beginning is traced
//! and its rays propagated once, so a plate's m internal reflections cost O(m), not O(m²); every
//! other source and target solves each sequence on its own.

pub mod beats;
pub mod dispersive_sweep;
pub mod forward;
pub(crate) mod parallel_phase;
pub mod path;
pub mod round_trips;
pub mod sequence_tree;
pub mod tail;

use crate::accumulate::fidelity::{Fidelity, SceneNeeds};
use crate::accumulate::{Accumulator, Contribution};
use crate::optics::double_double::{DoubleDouble, projection};
use crate::optics::interaction::{
    CoefficientModel, InterfaceHit, JonesFrame, interact_along, interact_along_in_place,
    interact_along_shared,
};
use crate::optics::ray::{INCOHERENT, LedgerEntry, Ray};
use crate::optics::trail::Trail;
use crate::scene::source::{Channel, ChannelField, Emitter, Source, field_reference};
use crate::scene::{Scene, SceneOptics};
use crate::trace::path::{
    EnumerationLimits, Event, EventKind, PathError, Sequence, SolveOptions, SolvedPath, Target,
};
use crate::trace::sequence_tree::SequenceTree;
use glam::DVec3;
use num_complex::Complex64;
use std::sync::Arc;

/// Tracing settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceSettings {
    /// Which surface sequences are enumerated (events, internal reflections).
    pub limits: EnumerationLimits,
    /// How each path is solved.
    pub solve: SolveOptions,
    /// Trace the sequences of a plane wave into the far field that share a beginning once
    /// ([`path::FarFieldPaths`]: O(m) for a plate's m internal reflections). `false` traces
    /// every sequence from the source (O(m²)); both give the same arrivals bit for bit.
    pub share_beginnings: bool,
}

impl Default for TraceSettings {
    fn default() -> Self {
        TraceSettings {
            limits: EnumerationLimits::default(),
            solve: SolveOptions::default(),
            share_beginnings: true,
        }
    }
}

/// The candidate surface sequences of every source, discovered once per scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    /// One tree of sequences per source, in the scene's order.
    pub sequences: Vec<SequenceTree>,
}

impl Plan {
    /// A plan of given sequence lists, one per source (their order is not kept: a plan walks
    /// sequences in sorted order).
    pub fn from_sequences(per_source: Vec<Vec<Sequence>>) -> Plan {
        Plan {
            sequences: per_source
                .into_iter()
                .map(SequenceTree::from_sequences)
                .collect(),
        }
    }
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
                if let Some(t) = surf.plane.intersect(a, (img - a).normalize())
                    && t > 0.0
                {
                    targets.push(a + t * (img - a).normalize());
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
    /// The source's index in the scene.
    pub source: usize,
    /// The source's polarization channel the ray carries.
    pub channel: Channel,
    /// The solved path (shared by the source's channels along it).
    pub path: Arc<SolvedPath>,
    /// The ray propagated with complex Fresnel coefficients.
    pub vector: Ray,
    /// The ray propagated with the paper's rules (`None` when traced without them, see
    /// [`arrivals_with`]).
    pub paper: Option<Ray>,
    /// `Some` for the arrival that stands for every order of a plane wave between two parallel
    /// faces beyond the last one traced ([`tail::close`]): its rays are that order's, and its
    /// contribution is the closed sum of the further orders (docs/PHYSICS.md §5a).
    pub tail: Option<Arc<tail::TailClosure>>,
}

impl Arrival {
    /// The same arrival at vacuum wavelength `lambda_m`. Tracing uses the wavelength only
    /// through the scene's indices (`SceneOptics`) and stores it in the rays: where every index
    /// and the target are unchanged (non-dispersive media), this is bit for bit the arrival a
    /// new trace at `lambda_m` gives, so a spectrum is traced once.
    pub fn at_wavelength(&self, lambda_m: f64) -> Arrival {
        let mut a = self.clone();
        a.set_wavelength(lambda_m);
        a
    }

    /// The reflections of the arrival's path inside a medium other than the ambient one
    /// (index `ambient_index`): what [`path::EnumerationLimits::max_internal_reflections`]
    /// bounds (an event's medium is the index of the segment before it).
    pub fn internal_reflections(&self, ambient_index: f64) -> usize {
        self.path
            .sequence
            .iter()
            .zip(self.path.indices.iter())
            .filter(|(e, n)| e.kind == path::EventKind::Reflect && **n != ambient_index)
            .count()
    }

    /// [`Arrival::at_wavelength`] in place: the rays' vacuum wavelength set to `lambda_m`.
    pub fn set_wavelength(&mut self, lambda_m: f64) {
        self.vector.wavelength_m = lambda_m;
        if let Some(p) = &mut self.paper {
            p.wavelength_m = lambda_m;
        }
    }
}

/// A sequence that did not give a path, and why (for reports).
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// The source's index in the scene.
    pub source: usize,
    /// The surface sequence that was tried.
    pub sequence: Trail<Event>,
    /// Why it gave no path.
    pub error: PathError,
}

/// A channel's ray at the launch point `p0` in direction `d0` (no ledger entries yet), given
/// `unit = d0.normalize()` and the channel's launch `(e, amplitude)` along `d0`
/// ([`channel_launch`]); `spreading` is the path's S² and `ledger` the (empty) record the ray
/// starts with.
#[allow(clippy::too_many_arguments)]
#[inline]
fn launch_ray_with(
    optics: &SceneOptics,
    channel: &Channel,
    coherence_length_m: f64,
    (p0, _d0, spreading): (DVec3, DVec3, f64),
    unit: DVec3,
    (e, amplitude): (DVec3, f64),
    ledger: Trail<LedgerEntry>,
) -> Ray {
    let mut ray = Ray::linear_unit(
        p0,
        unit,
        e,
        amplitude * (channel.intensity * spreading).sqrt(),
        optics.lambda_m,
        optics.ambient_index,
    );
    ray.coherence_id = channel.coherence_id;
    ray.coherence_length_m = coherence_length_m;
    ray.ledger.entries = ledger;
    ray
}

/// A channel's unit launch field and amplitude factor along `d0` (docs/PHYSICS.md §3): a
/// linear channel's field from `e_ref = field_reference(reference, d0)` with factor 1 (`e_ref`
/// is shared by channels with one reference), a dipole's projected axis and its length.
#[inline]
fn channel_launch(channel: &Channel, e_ref: Option<DVec3>, d0: DVec3) -> (DVec3, f64) {
    match (channel.field, e_ref) {
        (ChannelField::Linear { reference, .. }, e_ref) => {
            let e_ref = e_ref.unwrap_or_else(|| field_reference(reference, d0));
            (channel.field_direction_from(e_ref, d0), 1.0)
        }
        (ChannelField::Dipole { .. }, _) => channel.launch(d0.normalize()),
    }
}

/// Give a just-launched `ray` the optical path `start` already travelled at its launch point
/// (a plane wave launched off its reference wavefront, [`path::plane_wave_launch`]), with a
/// ledger entry for it; nothing for a start of 0.
#[inline]
fn start_at(ray: &mut Ray, start: DoubleDouble) {
    if start != DoubleDouble::ZERO {
        ray.optical_path = start;
        ray.ledger.entries.push(LedgerEntry::Path {
            index: ray.index,
            length_m: start.to_f64() / ray.index,
        });
    }
}

/// Where a solved path starts: its launch point, launch direction and spreading S².
fn launch_of(path: &SolvedPath) -> (DVec3, DVec3, f64) {
    (path.points[0], path.dirs[0], path.spreading)
}

/// A channel's ray at the launch point of a solved path (no ledger entries yet).
fn launch_ray(
    optics: &SceneOptics,
    channel: &Channel,
    coherence_length_m: f64,
    path: &SolvedPath,
) -> Ray {
    let d0 = path.dirs[0];
    let mut ray = launch_ray_with(
        optics,
        channel,
        coherence_length_m,
        launch_of(path),
        d0.normalize(),
        channel_launch(channel, None, d0),
        Trail::with_capacity(ledger_capacity(path)),
    );
    start_at(&mut ray, path.start_optical_path);
    ray.normal_q2 = path.launch_normal_q2;
    ray
}

/// Give `ray`, just through the event at `point` on surface `surface` (it arrived in index
/// `n_in` along `u_in`), the first-order optical path of moving `point` back onto the plane as
/// held ([`crate::scene::geometry::Plane::off_plane_path_correction`]): an f64 hit point on a tilted
/// plane far from the origin is ~1 ulp off it, a first-order path error the path solver's
/// points carry too. Nothing (bit for bit) for a point on its plane.
#[inline]
fn onto_plane(
    scene: &Scene,
    surface: usize,
    point: DVec3,
    (n_in, u_in): (f64, DVec3),
    ray: &mut Ray,
) {
    let c = scene.surfaces[surface].plane.off_plane_path_correction(
        point,
        (n_in, u_in),
        (ray.index, ray.dir),
    );
    if c != 0.0 {
        ray.optical_path += DoubleDouble::from(c);
    }
}

/// The interface met by event `ev` at `point`.
#[inline]
fn hit_at(scene: &Scene, optics: &SceneOptics, ev: Event, point: DVec3) -> InterfaceHit {
    let surf = &scene.surfaces[ev.surface];
    InterfaceHit {
        surface: ev.surface,
        point,
        normal: surf.plane.normal,
        optics: optics.surfaces[ev.surface].expect("solved paths only meet non-opaque surfaces"),
        coherence: surf.coherence(),
        layers: optics.layers[ev.surface],
    }
}

/// After a tunnel event at `point` (the ray arrived along `u_in`): the ray leaves from the foot
/// of the normal on the layer's far face (`path::tunnel_exit`, the point the path solver
/// starts the next segment from), with no optical path for the jump (all of the layer's phase
/// is in its t_layer, docs/PHYSICS.md §5). Nothing for any other event.
#[inline]
fn tunnel_jump(
    scene: &Scene,
    optics: &SceneOptics,
    ev: Event,
    point: DVec3,
    u_in: DVec3,
    ray: &mut Ray,
) {
    if ev.kind == EventKind::Tunnel {
        let (exit, _) = path::tunnel_exit(scene, optics, ev.surface, point, u_in)
            .expect("a traced tunnel event has a layer behind its face");
        ray.origin = exit;
    }
}

/// The events of a solved path with the points where they happen.
#[inline]
fn events_of(path: &SolvedPath) -> impl Iterator<Item = (Event, DVec3)> + '_ {
    path.sequence
        .iter()
        .copied()
        .zip(path.points.iter().skip(1).copied())
}

/// The last leg of a ray after its last event: to the target point, or to the far-field
/// wavefront; then the paper's coherence-length rule.
#[inline]
fn end_ray(ray: &mut Ray, target: &Target, coherence_length_m: f64) {
    match target {
        Target::Point(p) => ray.advance_to(*p),
        Target::Direction { reference, dir } => {
            // Projection onto the far-field wavefront through `reference` perpendicular to the
            // target direction, −d·(x − reference), in double-double (a reference 100 m away
            // keeps the path's digits; `path::to_far_wavefront` says why the target's d).
            let proj = -projection(dir.normalize(), ray.origin, *reference);
            ray.optical_path += proj.mul_f64(ray.index);
            ray.ledger.entries.push(LedgerEntry::Path {
                index: ray.index,
                length_m: proj.to_f64(),
            });
        }
    }
    // The paper's coherence-length rule (P9): a ray whose own path exceeds the source's
    // coherence length loses coherence.
    if ray.optical_path_m() > coherence_length_m && ray.coherence_id != INCOHERENT {
        ray.coherence_id = INCOHERENT;
        ray.ledger
            .entries
            .push(LedgerEntry::CoherenceLost { surface: None });
    }
}

/// Per event a path, an interaction and perhaps a coherence loss; then the last path and
/// perhaps the coherence-length loss; and perhaps the start of a plane wave launched off its
/// reference wavefront.
fn ledger_capacity(path: &SolvedPath) -> usize {
    3 * path.sequence.len() + 3
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
    for (ev, point) in events_of(path) {
        let hit = hit_at(scene, optics, ev, point);
        let before = (ray.index, ray.dir);
        ray = interact_along(ray, &hit, model, ev.kind.child())
            .expect("solved paths only refract where a refracted ray exists");
        onto_plane(scene, ev.surface, point, before, &mut ray);
        tunnel_jump(scene, optics, ev, point, before.1, &mut ray);
    }
    end_ray(&mut ray, target, coherence_length_m);
    ray
}

/// The most channels carried together (a source has one, two or three,
/// [`crate::scene::source::CHANNELS_PER_GROUP`]; the rays are moved by value, so room for more would
/// cost every path).
const SHARED_CHANNELS: usize = 3;

/// The rays of a source's channels along a path. The channels differ only in polarization, so
/// they travel together: the last channel's ray in full and the others' polarizations riding
/// along, each interaction's geometry, coefficients and ledger entry computed once
/// ([`interact_along_shared`]). Channels whose coherence ids could part (some start incoherent,
/// some not), or more than [`SHARED_CHANNELS`], travel apart, each as [`propagate`] carries it.
// `Together` is large (a ray and a frame) and moved by value; boxing it would cost an
// allocation per path in every render.
#[allow(clippy::large_enum_variant)]
#[derive(Clone)]
enum ChannelRays {
    Together {
        lead: Ray,
        frames: [JonesFrame; SHARED_CHANNELS - 1],
    },
    Apart(Vec<Ray>),
}

impl ChannelRays {
    /// The channels' rays at the launch `(p0, d0, spreading)`, each ledger starting as
    /// `ledger()` gives it (empty: owned with room reserved, or shared).
    #[inline]
    fn launch(
        optics: &SceneOptics,
        channels: &[Channel],
        coherence_length_m: f64,
        start: (DVec3, DVec3, f64),
        start_path: DoubleDouble,
        ledger: impl Fn() -> Trail<LedgerEntry>,
    ) -> ChannelRays {
        let d0 = start.1;
        let unit = d0.normalize();
        let Some((last, rest)) = channels.split_last() else {
            return ChannelRays::Apart(Vec::new());
        };
        // The rays share their coherence id's fate only if all start coherent or all incoherent.
        let incoherent = last.coherence_id == INCOHERENT;
        if channels.len() > SHARED_CHANNELS
            || rest
                .iter()
                .any(|c| (c.coherence_id == INCOHERENT) != incoherent)
        {
            let alone = |ch: &Channel| {
                let e = channel_launch(ch, None, d0);
                let mut ray =
                    launch_ray_with(optics, ch, coherence_length_m, start, unit, e, ledger());
                start_at(&mut ray, start_path);
                ray
            };
            return ChannelRays::Apart(channels.iter().map(alone).collect());
        }
        // A linear field reference is shared too (bit for bit: one reference gives one
        // projection).
        let lead_reference = last.linear_reference();
        let e_ref = lead_reference.map(|r| field_reference(r, d0));
        // Only the lead's ledger is kept (the others' frames ride along without one).
        let launch = |ch: &Channel, ledger| {
            let bits = |r: Option<DVec3>| r.map(|r| r.to_array().map(f64::to_bits));
            let same = bits(ch.linear_reference()) == bits(lead_reference);
            let e = channel_launch(ch, if same { e_ref } else { None }, d0);
            launch_ray_with(optics, ch, coherence_length_m, start, unit, e, ledger)
        };
        let mut frames = [JonesFrame::default(); SHARED_CHANNELS - 1];
        for (f, ch) in frames.iter_mut().zip(rest) {
            *f = JonesFrame::of(&launch(ch, Trail::new()));
        }
        let mut lead = launch(last, ledger());
        start_at(&mut lead, start_path);
        ChannelRays::Together { lead, frames }
    }

    /// Give every ray the launch's Snell invariant about the first face
    /// ([`SolvedPath::launch_normal_q2`]).
    #[inline]
    fn carry_launch_q2(&mut self, q2: Option<(DVec3, crate::optics::interaction::SnellInvariant)>) {
        match self {
            ChannelRays::Together { lead, .. } => lead.normal_q2 = q2,
            ChannelRays::Apart(rays) => rays.iter_mut().for_each(|r| r.normal_q2 = q2),
        }
    }

    /// Through the interaction at `hit` along the followed branch (`reflect`: the reflected
    /// one); `others` is the number of channels besides the lead. False, with the rays partly
    /// updated, where the branch does not exist ([`interact_along`] gives `None`).
    /// Each ray's optical path is then moved onto the event's plane ([`onto_plane`]).
    #[inline]
    fn interact(
        &mut self,
        (scene, optics): (&Scene, &SceneOptics),
        (ev, hit): (Event, &InterfaceHit),
        model: CoefficientModel,
        others: usize,
    ) -> bool {
        let which = ev.kind.child();
        match self {
            ChannelRays::Together { lead, frames } => {
                let before = (lead.index, lead.dir);
                let ok = interact_along_shared(lead, &mut frames[..others], hit, model, which);
                if ok {
                    onto_plane(scene, ev.surface, hit.point, before, lead);
                    tunnel_jump(scene, optics, ev, hit.point, before.1, lead);
                }
                ok
            }
            ChannelRays::Apart(rays) => rays.iter_mut().all(|ray| {
                let before = (ray.index, ray.dir);
                let ok = interact_along_in_place(ray, hit, model, which);
                if ok {
                    onto_plane(scene, ev.surface, hit.point, before, ray);
                    tunnel_jump(scene, optics, ev, hit.point, before.1, ray);
                }
                ok
            }),
        }
    }

    /// The last leg to `target` ([`end_ray`]); `emit(k, ray)` receives channel k's ray, in order.
    #[inline]
    fn emit(
        self,
        channels: &[Channel],
        target: &Target,
        coherence_length_m: f64,
        mut emit: impl FnMut(usize, Ray),
    ) {
        match self {
            ChannelRays::Apart(rays) => {
                for (k, mut ray) in rays.into_iter().enumerate() {
                    end_ray(&mut ray, target, coherence_length_m);
                    emit(k, ray);
                }
            }
            ChannelRays::Together { mut lead, frames } => {
                let rest = &channels[..channels.len() - 1];
                end_ray(&mut lead, target, coherence_length_m);
                // The others differ from the lead only in frame and coherence id.
                let lost = lead.coherence_id == INCOHERENT;
                for (k, (f, ch)) in frames.iter().zip(rest).enumerate() {
                    let mut ray = lead.clone();
                    f.apply_to(&mut ray);
                    ray.coherence_id = if lost { INCOHERENT } else { ch.coherence_id };
                    emit(k, ray);
                }
                emit(rest.len(), lead);
            }
        }
    }
}

/// The rays of every channel of a source carried along a solved path ([`ChannelRays`]), up to
/// the last event; [`PathError::CriticalAngle`] where the rays cannot follow one of its
/// refractions (the path refracts at the critical angle to within rounding).
#[inline]
fn carry(
    scene: &Scene,
    optics: &SceneOptics,
    channels: &[Channel],
    coherence_length_m: f64,
    path: &SolvedPath,
    model: CoefficientModel,
) -> Result<ChannelRays, PathError> {
    let capacity = ledger_capacity(path);
    let mut rays = ChannelRays::launch(
        optics,
        channels,
        coherence_length_m,
        launch_of(path),
        path.start_optical_path,
        || Trail::with_capacity(capacity),
    );
    rays.carry_launch_q2(path.launch_normal_q2);
    let others = channels.len().saturating_sub(1);
    for (event, (ev, point)) in events_of(path).enumerate() {
        let hit = hit_at(scene, optics, ev, point);
        if !rays.interact((scene, optics), (ev, &hit), model, others) {
            return Err(PathError::CriticalAngle { event });
        }
    }
    Ok(rays)
}

/// The panic message of a solved path whose refraction the ray cannot follow.
const NO_REFRACTED_RAY: &str = "solved paths only refract where a refracted ray exists";

/// [`propagate`] for every channel of a source along one path, in one pass (`ChannelRays`).
/// `emit(k, ray)` receives channel k's ray, in order; each is bitwise the ray [`propagate`]
/// gives that channel.
///
/// # Panics
///
/// Where the rays cannot follow one of the path's refractions ([`PathError::CriticalAngle`];
/// [`arrivals`] reports such a sequence as failed instead).
#[allow(clippy::too_many_arguments)]
pub fn propagate_channels(
    scene: &Scene,
    optics: &SceneOptics,
    channels: &[Channel],
    coherence_length_m: f64,
    path: &SolvedPath,
    target: &Target,
    model: CoefficientModel,
    emit: impl FnMut(usize, Ray),
) {
    carry(scene, optics, channels, coherence_length_m, path, model)
        .expect(NO_REFRACTED_RAY)
        .emit(channels, target, coherence_length_m, emit);
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
/// path together (`ChannelRays`); a plane wave's far-field sequences are walked as a tree
/// (`far_field_walk`) unless `settings.share_beginnings` is off.
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
        let mut out = Recorder {
            source: si,
            channels: &channels,
            target,
            coherence_length_m: src.coherence_length_m,
            found: &mut found,
            failed: failed.as_deref_mut(),
            exact: parallel_phase::PlaneWavePhase::new(scene, src.emitter, target),
        };
        let tree = &plan.sequences[si];
        if let (true, Emitter::PlaneWave { .. }, Target::Direction { .. }) =
            (settings.share_beginnings, src.emitter, target)
        {
            far_field_walk(scene, optics, src, tree, paper_rules, &mut out);
            continue;
        }
        tree.for_each(|seq| {
            // Without a failure list the reason is not needed: skip what surely fails.
            if out.failed.is_none() && path::cannot_reach(scene, src.emitter, seq, target) {
                return;
            }
            let carried = path::solve(scene, optics, src.emitter, seq, *target, &settings.solve)
                .and_then(|p| {
                    let along =
                        |model| carry(scene, optics, &channels, src.coherence_length_m, &p, model);
                    let vector = along(CoefficientModel::Vector)?;
                    let paper = paper_rules
                        .then(|| along(CoefficientModel::PaperRules))
                        .transpose()?;
                    Ok((p, vector, paper))
                });
            match carried {
                Ok((p, vector, paper)) => {
                    let exact = out.exact.as_ref().and_then(|x| x.of_path(&p));
                    out.arrive(Arc::new(p), vector, paper, exact)
                }
                Err(error) => out.fail(Trail::from(seq.to_vec()), error),
            }
        });
    }
    found
}

/// Where the arrivals and failures of one source go.
struct Recorder<'a, 'f> {
    source: usize,
    channels: &'a [Channel],
    target: &'a Target,
    coherence_length_m: f64,
    found: &'a mut Vec<Arrival>,
    failed: Option<&'f mut Vec<Failure>>,
    /// A plane wave into the far field: the exact optical paths of its paths between parallel
    /// planes ([`parallel_phase`]).
    exact: Option<parallel_phase::PlaneWavePhase<'a>>,
}

impl Recorder<'_, '_> {
    /// The channels' arrivals along `path`, from their rays after its last event under the
    /// vector model and, when traced, the paper's rules; with the optical path `exact` (m)
    /// instead of the traced sum where given (a plane wave between parallel planes,
    /// [`parallel_phase`]: the sum's rounding grows with the lateral run, docs/PHYSICS.md §8).
    #[inline]
    fn arrive(
        &mut self,
        path: Arc<SolvedPath>,
        vector: ChannelRays,
        paper: Option<ChannelRays>,
        exact: Option<DoubleDouble>,
    ) {
        let first = self.found.len();
        let (found, channels, si) = (&mut *self.found, self.channels, self.source);
        let with_exact = |mut ray: Ray| {
            if let Some(phi) = exact {
                ray.optical_path = phi;
            }
            ray
        };
        vector.emit(channels, self.target, self.coherence_length_m, |k, ray| {
            found.push(Arrival {
                source: si,
                channel: channels[k],
                path: Arc::clone(&path),
                vector: with_exact(ray),
                paper: None,
                tail: None,
            })
        });
        if let Some(paper) = paper {
            paper.emit(channels, self.target, self.coherence_length_m, |k, ray| {
                found[first + k].paper = Some(with_exact(ray))
            });
        }
    }

    /// A sequence without a path (kept only when failures are asked for).
    fn fail(&mut self, sequence: Trail<Event>, error: PathError) {
        if let Some(f) = self.failed.as_deref_mut() {
            f.push(Failure {
                source: self.source,
                sequence,
                error,
            });
        }
    }
}

/// The arrivals of a plane wave into the far field along every sequence of `tree`, walked depth
/// first with [`path::FarFieldPaths`]: each beginning is traced once, and the channels' rays
/// are carried through each of its events once (lazily, when a sequence through it arrives).
/// The arrivals and failures are those of the one-by-one trace, bit for bit and in the same
/// order; the cost is O(1) per tree node instead of O(sequence length) per sequence.
fn far_field_walk(
    scene: &Scene,
    optics: &SceneOptics,
    src: &Source,
    tree: &SequenceTree,
    paper_rules: bool,
    out: &mut Recorder,
) {
    let Emitter::PlaneWave {
        direction,
        reference_point,
    } = src.emitter
    else {
        unreachable!("far_field_walk is only called for plane waves");
    };
    let mut paths = path::FarFieldPaths::new(scene, optics, direction, reference_point);
    let models: &[CoefficientModel] = if paper_rules {
        &[CoefficientModel::Vector, CoefficientModel::PaperRules]
    } else {
        &[CoefficientModel::Vector]
    };
    // Per model, `rays[m][k]`: the channels' rays after k events of the current beginning;
    // entries from `valid` on belong to an earlier beginning. All start as the launched rays.
    let launched = ChannelRays::launch(
        optics,
        out.channels,
        out.coherence_length_m,
        paths.launch(),
        paths.start_optical_path(),
        Trail::shared,
    );
    let mut rays = vec![vec![launched]; models.len()];
    // The exact optical path after k events of the current beginning (`parallel_phase`), kept
    // like `rays` (index 0: none yet).
    let mut phases: Vec<Option<parallel_phase::Partial>> = vec![None];
    let mut valid = 1;
    let others = out.channels.len().saturating_sub(1);
    let nodes = tree.nodes();
    let mut i = 0;
    while i < nodes.len() {
        let node = nodes[i];
        if let Some(ev) = node.event {
            paths.truncate(node.depth - 1);
            valid = valid.min(node.depth);
            if let Err(error) = paths.advance(ev) {
                // Every sequence beginning here fails the same way.
                if out.failed.is_some() {
                    let mut seqs = vec![paths.sequence()];
                    for n in &nodes[i..node.subtree_end] {
                        seqs.truncate(n.depth - node.depth + 1);
                        let mut seq = seqs.last().unwrap().clone();
                        seq.push(n.event.expect("only the root has no event"));
                        if n.candidate {
                            out.fail(seq.clone(), error.clone());
                        }
                        seqs.push(seq);
                    }
                }
                i = node.subtree_end;
                continue;
            }
        }
        if node.candidate {
            match paths.path(out.target) {
                Ok(p) => {
                    // Carry the rays through the events they have not met yet; where they
                    // cannot follow a refraction (the critical angle to within rounding), the
                    // stack keeps what was carried and the sequence fails as `carry` fails it.
                    let mut stopped = None;
                    for (stack, &model) in rays.iter_mut().zip(models) {
                        stack.truncate(valid);
                        for k in valid..=node.depth {
                            let (ev, point) = paths.event(k - 1);
                            let mut next = stack[k - 1].clone();
                            let hit = hit_at(scene, optics, ev, point);
                            if !next.interact((scene, optics), (ev, &hit), model, others) {
                                stopped = Some(k - 1);
                                break;
                            }
                            stack.push(next);
                        }
                        if stopped.is_some() {
                            break;
                        }
                    }
                    if let Some(event) = stopped {
                        out.fail(paths.sequence(), PathError::CriticalAngle { event });
                    } else {
                        let exact = out.exact.as_ref().and_then(|x| {
                            // One term per event not met yet: O(1) per order, as the rays.
                            phases.truncate(valid);
                            for k in valid..=node.depth {
                                let (ev, _) = paths.event(k - 1);
                                let (d, n) = paths.segment(k - 1);
                                let next = if k == 1 {
                                    x.first(ev, d, n)
                                } else {
                                    x.step(phases[k - 1], ev, d, n)
                                };
                                phases.push(next);
                            }
                            let (d, n) = paths.segment(node.depth);
                            x.finish(phases[node.depth], d, n)
                        });
                        valid = node.depth + 1;
                        let mut at_end = rays.iter().map(|stack| stack[node.depth].clone());
                        let vector = at_end.next().unwrap();
                        out.arrive(Arc::new(p), vector, at_end.next(), exact);
                    }
                }
                Err(error) => out.fail(paths.sequence(), error),
            }
        }
        i += 1;
    }
}

/// The panic message of asking for `paper_rules` of an arrival traced without them.
pub(crate) const PAPER_MISSING: &str =
    "paper_rules asked of an arrival traced without the paper's rules (trace::arrivals_with)";

/// The phase in cycles of the optical path `path` measured from `reference` at vacuum
/// wavelength `lambda_m`, reduced to its fraction of a cycle in double-double before it is
/// rounded: the cycles of a path difference of 10 m at 200 nm (5e7) rounded to f64 are 7e-9 off,
/// more than the phase a thick plate's reference resolves (docs/PHYSICS.md §8).
pub fn phase_cycles(path: DoubleDouble, reference: DoubleDouble, lambda_m: f64) -> f64 {
    let c = (path - reference) / DoubleDouble::from(lambda_m);
    (c - DoubleDouble::from(c.hi.round())).to_f64()
}

/// The path phases of one arrival in cycles ([`phase_cycles`]), measured from one reference
/// optical path: its `vector` ray's and, where traced, its `paper_rules` ray's. Every rung of
/// the ladder (docs/PHYSICS.md §4) starts from the same exact path, so the rungs share these
/// two numbers: the double-double reduction is done once per arrival, not once per rung.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArrivalCycles {
    /// The `vector` ray's phase (cycles); also the phase of the scalar rungs.
    pub vector: f64,
    /// The `paper_rules` ray's phase (cycles); `None` where the arrival was traced without
    /// the paper's rules or the rung is not asked for.
    pub paper: Option<f64>,
}

impl ArrivalCycles {
    /// The phases of `a` from `reference` (m, double-double); the paper ray's only when
    /// `with_paper` (it is the `vector` one, bit for bit, where the two rays carry the same
    /// optical path and wavelength).
    pub fn of(a: &Arrival, reference: DoubleDouble, with_paper: bool) -> Self {
        let v = &a.vector;
        let vector = phase_cycles(v.optical_path, reference, v.wavelength_m);
        let paper = a.paper.as_ref().filter(|_| with_paper).map(|p| {
            if p.optical_path == v.optical_path && p.wavelength_m == v.wavelength_m {
                vector
            } else {
                phase_cycles(p.optical_path, reference, p.wavelength_m)
            }
        });
        ArrivalCycles { vector, paper }
    }

    /// The paper ray's phase; panics where it was not reduced (`with_paper` false).
    fn paper(&self) -> f64 {
        self.paper
            .expect("paper_rules asked of ArrivalCycles reduced without the paper ray's phase")
    }
}

/// The accumulation-core contribution of an arrival at a rung of the ladder, with its path
/// phase measured from the optical path `reference` (m, double-double): the difference is
/// formed in double-double and only then rounded and divided by λ, so a path of any length
/// keeps its phase relative to the reference to ~1e-16 of the difference (docs/PHYSICS.md §1).
pub fn contribution_from(a: &Arrival, level: Fidelity, reference: DoubleDouble) -> Contribution {
    let cycles = ArrivalCycles::of(a, reference, level == Fidelity::PaperRules);
    contribution_with(a, level, &cycles)
}

/// [`contribution_from`] with the arrival's phases already reduced ([`ArrivalCycles::of`],
/// with the paper ray's phase for `paper_rules`): what a loop over the rungs calls, the same
/// contribution bit for bit.
pub fn contribution_with(a: &Arrival, level: Fidelity, cycles: &ArrivalCycles) -> Contribution {
    if let Some(t) = &a.tail {
        return tail_contribution(a, t, level, cycles);
    }
    let v = &a.vector;
    let scalar = |extra_cycles: f64| Contribution {
        coherence_id: v.coherence_id,
        phase_cycles: cycles.vector + extra_cycles,
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
                phase_cycles: cycles.paper(),
                field: paper.field(),
            }
        }
        Fidelity::Vector => Contribution {
            coherence_id: v.coherence_id,
            phase_cycles: cycles.vector,
            field: v.field(),
        },
    }
}

/// [`contribution_with`] of an arrival standing for a closed tail (docs/PHYSICS.md §5a): the
/// sum of the orders beyond the traced one it carries, under the level's own model.
fn tail_contribution(
    a: &Arrival,
    t: &tail::TailClosure,
    level: Fidelity,
    cycles: &ArrivalCycles,
) -> Contribution {
    let v = &a.vector;
    let e = v.field();
    let scalar = |jump: bool, extra_cycles: f64| {
        let f = t.scalar_factor(&e, jump, v.wavelength_m) * v.intensity().sqrt();
        Contribution {
            coherence_id: v.coherence_id,
            phase_cycles: cycles.vector + extra_cycles,
            field: [f, Complex64::default(), Complex64::default()],
        }
    };
    match level {
        Fidelity::Incoherent => Contribution {
            coherence_id: INCOHERENT,
            phase_cycles: cycles.vector,
            field: [
                Complex64::from(t.incoherent_intensity(&e).sqrt()),
                Complex64::default(),
                Complex64::default(),
            ],
        },
        Fidelity::Scalar => scalar(false, 0.0),
        Fidelity::ScalarJump => scalar(true, 0.5 * a.path.denser_reflections as f64),
        Fidelity::PaperRules => {
            let paper = a.paper.as_ref().expect(PAPER_MISSING);
            Contribution {
                coherence_id: paper.coherence_id,
                phase_cycles: cycles.paper(),
                field: t.field(&paper.field(), level, paper.wavelength_m).0,
            }
        }
        Fidelity::Vector => Contribution {
            coherence_id: v.coherence_id,
            phase_cycles: cycles.vector,
            field: t.field(&e, level, v.wavelength_m).0,
        },
    }
}

/// The contributions of all arrivals at one point, phases referred to the first arrival's
/// optical path (a common phase does not change any intensity).
pub fn contributions(arrivals: &[Arrival], level: Fidelity) -> Vec<Contribution> {
    let reference = arrivals
        .first()
        .map_or(DoubleDouble::ZERO, |a| a.vector.optical_path);
    arrivals
        .iter()
        .map(|a| contribution_from(a, level, reference))
        .collect()
}

/// Intensity of a set of arrivals at a rung of the ladder.
pub fn intensity(arrivals: &[Arrival], level: Fidelity) -> f64 {
    let mut acc = Accumulator::new();
    acc.extend(&contributions(arrivals, level));
    acc.intensity()
}

/// What the arrivals at one point need from the ladder (merge points with `merge_needs`).
pub fn needs(arrivals: &[Arrival]) -> SceneNeeds {
    let mut n = SceneNeeds {
        parallel_fields: true,
        ..Default::default()
    };
    // Each arrival's field, formed once (a closed tail's is a sum), not once per pair.
    let fields: Vec<crate::optics::ray::Field3> = arrivals.iter().map(vector_field).collect();
    for (i, a) in arrivals.iter().enumerate() {
        n.interfaces |= !a.path.sequence.is_empty();
        n.tir |= a.path.has_tir;
        let id = a.vector.coherence_id;
        if id == INCOHERENT {
            continue;
        }
        for (j, b) in arrivals[..i].iter().enumerate() {
            if b.vector.coherence_id != id {
                continue;
            }
            n.interference = true;
            // Parallel, real-proportional fields: |E_a·E_b*| = |E_a||E_b|.
            let (ea, eb) = (fields[i], fields[j]);
            let dot: Complex64 = (0..3).map(|k| ea[k] * eb[k].conj()).sum();
            let norm =
                |e: &crate::optics::ray::Field3| e.iter().map(|x| x.norm_sqr()).sum::<f64>().sqrt();
            let (na, nb) = (norm(&ea), norm(&eb));
            if (dot.norm() - na * nb).abs() > 1e-12 * na * nb || dot.im.abs() > 1e-12 * na * nb {
                n.parallel_fields = false;
            }
        }
    }
    n
}

/// An arrival's `vector` field (path phase excluded): its ray's, or for a closed tail the sum
/// of the orders it stands for.
fn vector_field(a: &Arrival) -> crate::optics::ray::Field3 {
    match &a.tail {
        Some(t) => {
            t.field(&a.vector.field(), Fidelity::Vector, a.vector.wavelength_m)
                .0
        }
        None => a.vector.field(),
    }
}

/// Combine the needs of several points.
pub(crate) fn merge_needs(a: SceneNeeds, b: SceneNeeds) -> SceneNeeds {
    SceneNeeds {
        interference: a.interference || b.interference,
        interfaces: a.interfaces || b.interfaces,
        parallel_fields: a.parallel_fields && b.parallel_fields,
        tir: a.tir || b.tir,
        polarization_state: a.polarization_state || b.polarization_state,
    }
}
