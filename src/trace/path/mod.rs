//! The exact point-to-point path solver and the enumeration of surface sequences.
//!
//! A path is a source, a sequence of surface events (reflect / refract at surface k) and an
//! end: a screen point P, or a direction (far field: observation at infinity through an ideal
//! lens). The launch of the ray is described by two parameters (launch direction for point and
//! line sources, launch position for plane waves); the solver finds them by damped Newton
//! iteration on the landing residual with a central-difference Jacobian, starting from the
//! image-method guess (reflections unfolded exactly, refractions ignored). It stops when the
//! landing error is below `landing_tolerance × scene scale` and fails loudly otherwise: a
//! missing path (TIR on a refraction event, a surface missed or outside its extent, P behind
//! the ray, a blocking shield or an unlisted surface on the way) is an error with a reason.
//!
//! A plane wave into the far field needs no solve (every launch is equivalent): [`solve`] traces
//! it from the wave's reference point, and [`FarFieldPaths`] does the same one event at a time,
//! so sequences that share a beginning trace it once.
//!
//! Geometric spreading (optional): the ray-tube cross-section at P per unit launch measure is
//! |det J|·|d_f·d_ref| from the same Jacobian, so the field amplitude factor is
//! `S² = (n_src/n_P)·Π_refractions(n2 cos θt/(n1 cos θi))·(launch measure)/(dA⊥)`; for a point
//! source in a homogeneous medium this is exactly 1/r².

use crate::optics::double_double::{DoubleDouble, projection, segment_length};
use crate::optics::interaction::{SurfaceOptics, indices_for};
use crate::optics::trail::Trail;
use crate::scene::geometry::{Extent, Plane};
use crate::scene::source::Emitter;
use crate::scene::{Scene, SceneOptics, SurfaceKind};
use crate::trace::sequence_tree::{SequenceTree, TreeBuilder};
use crate::{optics::fresnel, optics::interaction};
use glam::DVec3;

mod enumerate;
mod far_field;
mod reach;
mod stack;

pub use enumerate::{EnumerationLimits, discover_sequences};
pub use far_field::FarFieldPaths;
use far_field::*;
pub(crate) use reach::distance_to_line;
use reach::*;
pub use reach::{cannot_reach, crossing};
use stack::*;

/// Reflect, refract or tunnel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EventKind {
    /// Reflected at the surface.
    Reflect,
    /// Refracted (transmitted) through it.
    Refract,
    /// Tunnelled through the layer behind it (frustrated total reflection, docs/PHYSICS.md §5):
    /// the surface is lit beyond its critical angle, and the evanescent field in the layer
    /// behind it (`crate::scene::Scene::layer_behind`) launches a wave from the layer's far face
    /// into the medium beyond. The event's point is the hit point on the lit face; the next
    /// segment starts at the foot of the normal through it on the far face (`tunnel_exit`),
    /// with no optical path in between (all of the layer's phase is in its t_layer).
    Tunnel,
}

impl EventKind {
    /// The [`interaction::Child`] a path with this event follows.
    pub fn child(self) -> interaction::Child {
        match self {
            EventKind::Reflect => interaction::Child::Reflected,
            EventKind::Refract => interaction::Child::Refracted,
            EventKind::Tunnel => interaction::Child::Tunnelled,
        }
    }
}

/// Where a wave tunnelled at surface `surface` (hit at `x`, arriving along `d`) leaves the layer
/// behind it: the foot of the normal through `x` on the layer's far face (its partner,
/// [`crate::optics::interaction::Layer`]), with that partner's index; `None` without a layer.
/// The path solver and the carried rays both call this, so they start the tunnelled segment
/// at the same point, bit for bit.
pub(crate) fn tunnel_exit(
    scene: &Scene,
    optics: &SceneOptics,
    surface: usize,
    x: DVec3,
    d: DVec3,
) -> Option<(DVec3, usize)> {
    let normal = scene.surfaces[surface].plane.normal;
    let layer = optics.layers[surface][usize::from(d.dot(normal) >= 0.0)]?;
    Some((
        scene.surfaces[layer.partner].plane.project(x),
        layer.partner,
    ))
}

/// One surface event of a sequence.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Event {
    /// The surface's index in the scene.
    pub surface: usize,
    /// Reflect or refract.
    pub kind: EventKind,
}

/// A surface sequence, in order from the source.
pub type Sequence = Vec<Event>;

/// Compact text for a sequence, e.g. `R0 T1 R2` (R: reflect, T: refract, number: surface).
pub fn sequence_label<'a>(seq: impl IntoIterator<Item = &'a Event>) -> String {
    let labels: Vec<String> = seq
        .into_iter()
        .map(|e| match e.kind {
            EventKind::Reflect => format!("R{}", e.surface),
            EventKind::Refract => format!("T{}", e.surface),
            EventKind::Tunnel => format!("U{}", e.surface),
        })
        .collect();
    if labels.is_empty() {
        return "direct".into();
    }
    labels.join(" ")
}

/// Where a path ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// A screen point (m).
    Point(DVec3),
    /// A far-field direction (unit); the phase is referred to the wavefront plane through
    /// `reference` perpendicular to the direction (equal optical path to the lens focus).
    Direction {
        /// Unit direction of the far field.
        dir: DVec3,
        /// A point of the reference wavefront, m.
        reference: DVec3,
    },
}

/// Why a path does not exist.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PathError {
    /// Total internal reflection where the sequence refracts.
    #[error("total internal reflection at a refraction event (event {event})")]
    TotalInternalReflection {
        /// The event's position in the sequence.
        event: usize,
    },
    /// The ray never meets the event's plane.
    #[error("the ray misses the plane of event {event}")]
    Missed {
        /// The event's position in the sequence.
        event: usize,
    },
    /// The event point is outside the surface's extent.
    #[error("event {event} lies outside the extent of surface {surface}")]
    OutOfExtent {
        /// The event's position in the sequence.
        event: usize,
        /// The surface's index in the scene.
        surface: usize,
    },
    /// The ray reaches the event from the wrong side's medium.
    #[error("the ray arrives at event {event} from a medium it is not in")]
    MediumMismatch {
        /// The event's position in the sequence.
        event: usize,
    },
    /// Another surface stops a segment.
    #[error("segment {segment} is blocked by surface {surface}")]
    Blocked {
        /// The segment's position in the path (0: from the launch point).
        segment: usize,
        /// The blocking surface's index in the scene.
        surface: usize,
    },
    /// The end point is behind the last segment's start.
    #[error("the end point lies behind the last segment")]
    Behind,
    /// A tunnel event where no tunnelled wave exists: the face is not lit beyond its critical
    /// angle, has no layer behind it, or the medium beyond the layer is beyond its own critical
    /// angle too.
    #[error("no tunnelled wave at event {event}")]
    NoTunnel {
        /// The event's position in the sequence.
        event: usize,
    },
    /// A tunnel event on a path other than a plane wave into the far field: the point-to-point
    /// solver does not yet solve through a layer's jump (docs/PHYSICS.md §5).
    #[error("a tunnelled wave (event {event}) is traced only for a plane wave into the far field")]
    TunnelNotSolved {
        /// The event's position in the sequence.
        event: usize,
    },
    /// The exit direction is not the far-field direction asked for.
    #[error("the exit direction does not match the far-field direction")]
    DirectionMismatch,
    /// The solver did not land on the target within the tolerance.
    #[error("no convergence: landing error {landing_error_m:e} m after {iterations} iterations")]
    NotConverged {
        /// The last landing error, m.
        landing_error_m: f64,
        /// Iterations spent.
        iterations: usize,
    },
    /// An opaque surface named as an event.
    #[error("surface {surface} is opaque and cannot be an event")]
    OpaqueEvent {
        /// The surface's index in the scene.
        surface: usize,
    },
    /// The solved path refracts at event `event` at the critical angle to within rounding, and
    /// the ray carried along it, a rounding away, is totally reflected there: the refracted
    /// wave would graze the surface, and which side of the critical angle the path lies on is
    /// decided by rounding. The sequence is reported as not arriving (`trace::carry`).
    #[error(
        "refraction at the critical angle to within rounding at event {event}: the ray is totally reflected there a rounding away from the solved path"
    )]
    CriticalAngle {
        /// The event's position in the sequence.
        event: usize,
    },
}

/// Solver settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions {
    /// Accepted landing error relative to the scene scale (default 1e-12).
    pub landing_tolerance: f64,
    /// Newton iterations before giving up ([`PathError::NotConverged`]).
    pub max_iterations: usize,
    /// Compute the geometric spreading factor.
    pub spreading: bool,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            landing_tolerance: 1e-12,
            max_iterations: 80,
            spreading: false,
        }
    }
}

/// A solved path: the polyline from the launch point through every event to the end.
///
/// The records are [`Trail`]s: a path solved on its own owns them; the reflected orders of a
/// plane wave into the far field share their common beginning (`trace`'s far-field walk).
#[derive(Clone, Debug, PartialEq)]
pub struct SolvedPath {
    /// The surface events, in order from the source.
    pub sequence: Trail<Event>,
    /// Launch point, every event point, and the end point (for the far field: the last event
    /// point, or the launch point for a direct path).
    pub points: Trail<DVec3>,
    /// Unit direction of each segment (`points.len() - 1` entries, plus the exit direction for
    /// the far field: always `points.len()` entries, the last being the final direction).
    pub dirs: Trail<DVec3>,
    /// Refractive index along each segment (same length as `dirs`).
    pub indices: Trail<f64>,
    /// Σ n_i L_i from the launch to the end (far field: to the reference wavefront) (m), in
    /// double-double: each length from exact coordinate differences, the far-field projection
    /// with exact differences and products ([`crate::optics::double_double`]).
    pub optical_path: DoubleDouble,
    /// The optical path already travelled at the launch point `points[0]` (m): 0, except for a
    /// plane wave into the far field launched off its reference wavefront
    /// ([`plane_wave_launch`]), where it is n·d·(launch − reference); for a plane wave toward a
    /// point it also holds the (negative) kink of the last segment drawn to the target
    /// (−|v⊥|²/(|v| + v·d), [`solve`]). Included in `optical_path`; rays start with it.
    pub start_optical_path: DoubleDouble,
    /// Distance between the landing point and the target (m); for the far field the sine of the
    /// angle between the exit and target directions.
    pub landing_error: f64,
    /// Solver iterations spent.
    pub iterations: usize,
    /// Number of reflections from the optically denser side (n1 < n2, or a mirror): the π
    /// jumps of `scalar_jump` (docs/PHYSICS.md §4).
    pub denser_reflections: usize,
    /// Whether any reflection event was total internal reflection.
    pub has_tir: bool,
    /// S², the intensity factor of geometric spreading (1 when spreading is off).
    pub spreading: f64,
    /// The launch's Snell invariant about the first event's plane normal, with that normal
    /// ([`crate::optics::ray::Ray::normal_q2`]), where the launch came from Snell's invariant of
    /// a parallel stack (`stack::parallel_stack_launch`; held as the (n cos θ)² of the medium
    /// the beam grazes in): rays start with it, so a beam grazing inside a plate (cos θt ~
    /// 1e-12) keeps its angle, which the f64 launch direction rounds away, and its amplitude,
    /// which an invariant re-formed in the ambient first rounds (docs/PHYSICS.md §8). `None`
    /// otherwise.
    pub launch_normal_q2: Option<(DVec3, interaction::SnellInvariant)>,
}

impl SolvedPath {
    /// The optical path rounded to f64 (m).
    pub fn optical_path_m(&self) -> f64 {
        self.optical_path.to_f64()
    }
}

/// The geometric ray state during a trace.
struct Geometry {
    points: Vec<DVec3>,
    dirs: Vec<DVec3>,
    indices: Vec<f64>,
    denser_reflections: usize,
    has_tir: bool,
    /// Π over refractions of n2 cos θt/(n1 cos θi).
    refraction_factor: f64,
}

/// The surface's optics or an error if it is opaque.
fn surface_optics(
    optics: &SceneOptics,
    event: usize,
    surface: usize,
) -> Result<SurfaceOptics, PathError> {
    let _ = event;
    optics.surfaces[surface].ok_or(PathError::OpaqueEvent { surface })
}

impl Geometry {
    /// No points yet (allocates nothing).
    fn empty() -> Self {
        Geometry {
            points: Vec::new(),
            dirs: Vec::new(),
            indices: Vec::new(),
            denser_reflections: 0,
            has_tir: false,
            refraction_factor: 1.0,
        }
    }

    /// Forget the last trace, keeping the allocations.
    fn clear(&mut self) {
        self.points.clear();
        self.dirs.clear();
        self.indices.clear();
        self.denser_reflections = 0;
        self.has_tir = false;
        self.refraction_factor = 1.0;
    }

    /// The launch point, direction and index of a trace through `events` events (with room for
    /// the end point that point targets add).
    fn start(&mut self, origin: DVec3, dir: DVec3, index: f64, events: usize) {
        self.points.reserve(events + 2);
        self.dirs.reserve(events + 2);
        self.indices.reserve(events + 1);
        self.points.push(origin);
        self.dirs.push(dir);
        self.indices.push(index);
    }
}

/// Image-method initial guess: the target mirrored through every reflection, in reverse order.
fn unfolded_target(scene: &Scene, seq: &[Event], p: DVec3) -> DVec3 {
    seq.iter().rev().fold(p, |x, ev| match ev.kind {
        EventKind::Reflect => scene.surfaces[ev.surface].plane.mirror_point(x),
        EventKind::Refract | EventKind::Tunnel => x,
    })
}

fn residual(g: &Geometry, target: &Target, frame: (DVec3, DVec3, DVec3)) -> Option<[f64; 2]> {
    let (o, d) = (*g.points.last()?, *g.dirs.last()?);
    let (dref, f1, f2) = frame;
    match target {
        Target::Point(p) => {
            let denom = d.dot(dref);
            if denom <= 0.0 {
                return None;
            }
            // o − p first: both are absolute coordinates (up to ~1000 m) and their difference
            // is exact when they are near each other, so the residual keeps its digits at the
            // scale of the path, not of the coordinates (the Jacobian's finite differences
            // divide it by the launch step: 1/r² spreading 500 m from the origin was 1.8e-5 off).
            let t = (*p - o).dot(dref) / denom;
            let x = (o - *p) + t * d;
            Some([x.dot(f1), x.dot(f2)])
        }
        Target::Direction { .. } => Some([d.dot(f1), d.dot(f2)]),
    }
}

fn norm2(r: [f64; 2]) -> f64 {
    r[0].hypot(r[1])
}

/// Solve the 2×2 system J x = b (Cramer's rule); `None` if singular.
fn solve2(j: [[f64; 2]; 2], b: [f64; 2]) -> Option<[f64; 2]> {
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    Some([
        (b[0] * j[1][1] - j[0][1] * b[1]) / det,
        (j[0][0] * b[1] - b[0] * j[1][0]) / det,
    ])
}

/// The scene scale used for tolerances: the distance from the source anchor to the target
/// (or to the farthest event plane point), never below 1 µm.
fn scene_scale(scene: &Scene, anchor: DVec3, target: &Target) -> f64 {
    let mut s = match target {
        Target::Point(p) => (*p - anchor).length(),
        Target::Direction { reference, .. } => (*reference - anchor).length(),
    };
    for surf in &scene.surfaces {
        s = s.max((surf.plane.point - anchor).length());
    }
    s.max(1e-6)
}

/// The landing error below which a point target counts as met whatever the path's length:
/// [`COORDINATE_ULPS`] roundings of the largest coordinate of the target and the traced points
/// (m). The residual is formed from f64 points of that size, so Newton's method stalls at about
/// one rounding of them; accepting it costs nothing the tracer keeps, because the last segment
/// ends exactly at the target and an optical path is stationary in its event points (Fermat):
/// a landing error δ changes it by O(δ²/L).
fn coordinate_floor(target: DVec3, points: &[DVec3]) -> f64 {
    let largest = points.iter().fold(target.abs().max_element(), |m, p| {
        m.max(p.abs().max_element())
    });
    COORDINATE_ULPS * f64::EPSILON * largest
}

/// The smallest finite-difference step of the solver's Jacobian, relative to the launch
/// model's step (`LaunchModel::step`): 1e-6 of the scene scale shrunk by at most 1e-9.
const JACOBIAN_STEP_FLOOR: f64 = 1e-9;

/// How often a plane wave's launch line toward a point target is halved toward the target's own
/// line before that line itself is tried (`solve`): 2^-24 of the image method's offset, ~6e-8.
const SLIDE_STEPS: i32 = 24;

/// Roundings of the largest coordinate a landing error may carry ([`coordinate_floor`]).
const COORDINATE_ULPS: f64 = 32.0;

/// Where the rays of a plane wave along unit `direction` (phase 0 on the wavefront through
/// `reference`) observed in the far field start, and the distance along `direction` from that
/// wavefront to the start: (launch point, d·(launch − reference) in double-double; the optical
/// path there is the ambient index times it).
///
/// Every launch is equivalent for the far field, but the *size of the coordinates* of the hit
/// points is not: a hit point rounded by ε along its plane costs ε²/L on a segment of length L
/// (second order, by Fermat), and a reference point 100 m away puts the hit points ~100 m (at
/// oblique incidence up to ~1000 m) from the origin, ε ~ 1e-13 m, which a 1 nm film (L ~ 1 nm)
/// does feel. So when every surface is an unbounded, non-opaque plane parallel to the others (a
/// film stack: the planes met and their order do not depend on the launch line) and the
/// reference lies more than 1 mm before the first plane the wave meets, the rays start 1 mm
/// before that plane on the line through its point (a local anchor of the scene), carrying the
/// exact path from the reference's wavefront. Otherwise they start at `reference` (path 0), and
/// the reference point also fixes the launch line through bounded surfaces.
pub fn plane_wave_launch(
    scene: &Scene,
    direction: DVec3,
    reference: DVec3,
) -> (DVec3, DoubleDouble) {
    stack_launch(scene, direction, reference).unwrap_or((reference, DoubleDouble::ZERO))
}

/// [`plane_wave_launch`]'s launch 1 mm (or more) before a film stack, `None` where the rays
/// start at the reference point.
pub(crate) fn stack_launch(
    scene: &Scene,
    direction: DVec3,
    reference: DVec3,
) -> Option<(DVec3, DoubleDouble)> {
    let first = scene.surfaces.first()?;
    let nu = first.plane.normal;
    let stack = scene.surfaces.iter().all(|s| {
        matches!(s.extent, Extent::Unbounded)
            && !matches!(s.kind, SurfaceKind::Opaque { .. })
            && (s.plane.normal == nu || s.plane.normal.cross(nu).length_squared() <= 1e-30)
    });
    if !stack {
        return None;
    }
    // The first plane met: the nearest ahead of the reference along the direction.
    let nearest = scene
        .surfaces
        .iter()
        .filter_map(|s| s.plane.intersect(reference, direction).map(|t| (t, s)))
        .fold(
            None::<(f64, &crate::scene::Surface)>,
            |best, (t, s)| match best {
                Some((bt, _)) if bt <= t => best,
                _ => Some((t, s)),
            },
        );
    // Every plane must lie ahead (the reference before the whole stack), the first by more
    // than the standoff.
    let all_ahead = scene.surfaces.iter().all(|s| {
        s.plane
            .intersect(reference, direction)
            .is_some_and(|t| t > 0.0)
    });
    let (t, surf) = nearest?;
    let standoff = launch_standoff(surf.plane.point, direction.dot(nu).abs());
    (all_ahead && t > standoff).then(|| {
        let launch = surf.plane.point - standoff * direction;
        (launch, projection(direction, launch, reference))
    })
}

/// The least distance (m) along a plane wave's direction from its stack launch to the point
/// `point` of the first plane: [`STANDOFF_M`], or more where that leaves the launch too close to
/// the plane to be told from it. The launch's height above the plane is the standoff times
/// `cos_theta` = |d·N|, and its f64 coordinates are rounded by ~u of the plane point's largest
/// coordinate X: at 89.999999999999° (cos θ = 1.7e-14) 1 mm is 1.7e-17 m above the plane, below
/// one rounding of X = 3 m (4e-16 m), and the launch fell on the plane or behind it — the wave
/// met no face and no light reached the probe (`fringe fuzz --family airy --seed 1`, scenes
/// 8206 and 9450; `plane_wave_beams` scene 1294). The height is therefore at least
/// [`LAUNCH_HEIGHT_ULPS`] roundings of the coordinates the launch is formed from (X and the
/// standoff itself): s·cos θ ≥ K u (X + s), s = K u X/(cos θ − K u), where cos θ > 2 K u; for a
/// wave more grazing still the standoff stays 1 mm (no launch off that plane resolves it: the
/// reference is used if it is nearer). The hit point's rounding grows with the standoff, u s
/// along the plane (second order, Fermat) and across it (moved back onto the plane and its
/// first-order path added, [`crate::scene::geometry::Plane::off_plane_path_correction`]).
fn launch_standoff(point: DVec3, cos_theta: f64) -> f64 {
    let ku = LAUNCH_HEIGHT_ULPS * f64::EPSILON / 2.0;
    let x = point.abs().max_element();
    if cos_theta > 2.0 * ku {
        STANDOFF_M.max(ku * x / (cos_theta - ku))
    } else {
        STANDOFF_M
    }
}

/// The distance (m) along a plane wave's direction from its stack launch to the first plane
/// where that is resolved ([`launch_standoff`]).
const STANDOFF_M: f64 = 1e-3;

/// Roundings of its coordinates by which a stack launch must lie above the first plane
/// ([`launch_standoff`]).
const LAUNCH_HEIGHT_ULPS: f64 = 16.0;

/// Find the exact path from `emitter` through `seq` to `target`.
pub fn solve(
    scene: &Scene,
    optics: &SceneOptics,
    emitter: Emitter,
    seq: &[Event],
    target: Target,
    opts: &SolveOptions,
) -> Result<SolvedPath, PathError> {
    let anchor = match emitter {
        Emitter::Point { position } => position,
        Emitter::Line { point, .. } => point,
        Emitter::PlaneWave {
            reference_point, ..
        } => reference_point,
    };
    // A tunnelled wave: only a plane wave into the far field (one event at a time, as the
    // far-field walk traces it).
    if let Some(event) = seq.iter().position(|e| e.kind == EventKind::Tunnel) {
        let (
            Emitter::PlaneWave {
                direction,
                reference_point,
            },
            Target::Direction { .. },
        ) = (emitter, target)
        else {
            return Err(PathError::TunnelNotSolved { event });
        };
        let mut paths = FarFieldPaths::new(scene, optics, direction, reference_point);
        for ev in seq {
            paths.advance(*ev)?;
        }
        return paths.path(&target);
    }
    // Plane wave into the far field: every launch is equivalent; trace from the reference point.
    if let (
        Emitter::PlaneWave {
            direction,
            reference_point,
        },
        Target::Direction { dir, .. },
    ) = (emitter, target)
    {
        let mut g = Geometry::empty();
        let d = direction.normalize();
        let (launch, ahead) = plane_wave_launch(scene, d, reference_point);
        trace_planes(scene, optics, launch, d, seq, &mut g)?;
        let exit_normal = seq.last().map(|e| scene.surfaces[e.surface].plane.normal);
        let err = far_field_landing(*g.dirs.last().unwrap(), dir, exit_normal)?;
        let start = ahead.mul_f64(optics.ambient_index);
        return finish(scene, g, seq, &target, (err, 0, 1.0), start);
    }

    // Initial guess by the image method.
    let (guess_dir, guess_origin) = match target {
        Target::Point(p) => {
            let img = unfolded_target(scene, seq, p);
            (img - anchor, img)
        }
        Target::Direction { dir, .. } => {
            // Unfold the direction: mirror it through every reflection plane in reverse order.
            let d = seq.iter().rev().fold(dir, |d, ev| match ev.kind {
                EventKind::Reflect => fresnel::reflect(d, scene.surfaces[ev.surface].plane.normal),
                EventKind::Refract | EventKind::Tunnel => d,
            });
            (d, anchor)
        }
    };
    // The image method ignores refraction: where that guess is totally reflected (e.g. a source
    // inside glass looking out at a shallow angle), steepen it toward the first event's
    // normal, halving the tangential part until the sequence can be traced.
    let mut guess_dir = guess_dir;
    // The first trace (the guess) and, when steepening finds it, its launch model.
    let mut g0 = Geometry::empty();
    let mut start = None;
    // A point source and a point through parallel planes: Snell's invariant gives the launch
    // direction directly (Newton then only confirms it).
    let stack = match (emitter, target) {
        (Emitter::Point { position }, Target::Point(p)) => {
            parallel_stack_launch(scene, optics, seq, position, p)
        }
        _ => None,
    };
    let launch_p2 = stack.map(|(_, carried)| carried);
    if let Some((d, _)) = stack {
        guess_dir = d;
    } else if let (Some(first), Emitter::Point { .. } | Emitter::Line { .. }) =
        (seq.first(), emitter)
    {
        let n = scene.surfaces[first.surface].plane.normal;
        let (gn, gt) = (guess_dir.dot(n) * n, guess_dir - guess_dir.dot(n) * n);
        let mut shrink = 1.0;
        for _ in 0..64 {
            let g = gn + shrink * gt;
            shrink *= 0.5;
            let m = LaunchModel::new(emitter, g, guess_origin);
            let (o, d) = m.launch([0.0, 0.0]);
            match trace_planes(scene, optics, o, d, seq, &mut g0) {
                // Steepening keeps the side of the first plane the ray heads for: these
                // failures cannot go away.
                Err(
                    e @ (PathError::Missed { event: 0 }
                    | PathError::MediumMismatch { event: 0 }
                    | PathError::OpaqueEvent { .. }),
                ) => return Err(e),
                Err(_) => continue,
                Ok(()) => {
                    // This launch is the start below: keep its model and trace.
                    guess_dir = g;
                    start = Some(m);
                    break;
                }
            }
        }
    }
    // A plane wave toward a point: the image method's launch line ignores refraction too, and
    // through a thin wedge it can start where the sequence cannot be followed (beyond the
    // hinge, the bottom face lies above the top one: `Missed`). Slide the launch line from the
    // image's toward the target's own (the path of a wave that is not deviated at all) until
    // the sequence traces.
    if let (None, Some(_), Emitter::PlaneWave { .. }, Target::Point(p)) =
        (&start, seq.first(), emitter, target)
    {
        let offset = guess_origin - p;
        // The image's line first, then halfway to the target's, ..., then the target's.
        for k in 0..=SLIDE_STEPS {
            let towards = if k == SLIDE_STEPS {
                0.0
            } else {
                0.5f64.powi(k)
            };
            let m = LaunchModel::new(emitter, guess_dir, p + towards * offset);
            let (o, d) = m.launch([0.0, 0.0]);
            match trace_planes(scene, optics, o, d, seq, &mut g0) {
                Ok(()) => {
                    start = Some(m);
                    break;
                }
                // Wrong side of the first plane, or an opaque event: no launch line helps.
                Err(PathError::MediumMismatch { event: 0 } | PathError::OpaqueEvent { .. }) => {
                    break;
                }
                Err(_) => {}
            }
        }
    }
    let model = match start {
        Some(m) => m,
        None => {
            let m = LaunchModel::new(emitter, guess_dir, guess_origin);
            let (o, d) = m.launch([0.0, 0.0]);
            trace_planes_carrying(scene, optics, (o, d, launch_p2), seq, &mut g0)?;
            m
        }
    };
    // The stack launch (x = 0) carries its invariant; Newton's other launches their own.
    let trace = |p: [f64; 2], g: &mut Geometry| {
        let (o, d) = model.launch(p);
        let carried = if p == [0.0, 0.0] { launch_p2 } else { None };
        trace_planes_carrying(scene, optics, (o, d, carried), seq, g)
    };
    let mut x = [0.0, 0.0];
    let dref = match target {
        Target::Point(_) => *g0.dirs.last().unwrap(),
        Target::Direction { dir, .. } => dir.normalize(),
    };
    let f1 = dref.any_orthonormal_vector();
    let frame = (dref, f1, dref.cross(f1));
    // Newton's trial launches reuse one scratch trace.
    let mut scratch = Geometry::empty();
    let res = |p: [f64; 2], g: &mut Geometry| {
        trace(p, g).ok()?;
        residual(g, &target, frame)
    };
    let scale = scene_scale(scene, anchor, &target);
    let tol = match target {
        Target::Point(_) => opts.landing_tolerance * scale,
        Target::Direction { .. } => 1e-13,
    };
    let h = model.step(scale);
    // Central differences; where a step leaves the region the sequence can be traced in (a
    // wedge's hinge 60 nm from a plane wave's path, a bounded surface's edge, TIR), the step
    // shrinks by 16 until both sides trace: the scene scale (up to the distance of a plane
    // wave's reference point) says nothing about how far the path's features are.
    let jacobian = |p: [f64; 2], g: &mut Geometry| -> Option<[[f64; 2]; 2]> {
        let mut j = [[0.0; 2]; 2];
        for k in 0..2 {
            let mut hk = h[k];
            let (rp, rm) = loop {
                let (mut pp, mut pm) = (p, p);
                pp[k] += hk;
                pm[k] -= hk;
                if let (Some(rp), Some(rm)) = (res(pp, g), res(pm, g)) {
                    break (rp, rm);
                }
                hk /= 16.0;
                if hk < JACOBIAN_STEP_FLOOR * h[k] {
                    return None;
                }
            };
            for i in 0..2 {
                j[i][k] = (rp[i] - rm[i]) / (2.0 * hk);
            }
        }
        Some(j)
    };

    let mut r = residual(&g0, &target, frame).ok_or(PathError::Behind)?;
    let mut r_norm = norm2(r);
    let mut iterations = 0;
    while r_norm > tol && iterations < opts.max_iterations {
        iterations += 1;
        let Some(j) = jacobian(x, &mut scratch) else {
            break;
        };
        let Some(delta) = solve2(j, [-r[0], -r[1]]) else {
            break;
        };
        // Damped step: halve until the residual decreases.
        let mut lambda = 1.0;
        let mut improved = false;
        while lambda > 1e-12 {
            let xn = [x[0] + lambda * delta[0], x[1] + lambda * delta[1]];
            if let Some(rn) = res(xn, &mut scratch) {
                let rn_norm = norm2(rn);
                if rn_norm < r_norm {
                    x = xn;
                    r = rn;
                    r_norm = rn_norm;
                    improved = true;
                    break;
                }
            }
            lambda *= 0.5;
        }
        if !improved {
            break;
        }
    }
    let landing_error = r_norm;
    // A point target is met to within the rounding of the coordinates the residual is formed
    // from, never better: a path 0.1 mm long 25 m from the origin lands ~1e-15 m off its
    // target at best, above 1e-12 of its length (a Young slit or a Michelson arm was lost
    // so, `tests/suite/truth_geometry.rs`).
    let floor = match target {
        Target::Point(p) => coordinate_floor(p, &g0.points),
        Target::Direction { .. } => 0.0,
    };
    if landing_error > tol.max(opts.landing_tolerance * scale).max(floor)
        && !(stack.is_some() && stack_landing_harmless(&trace, x, &mut scratch, target))
    {
        return Err(PathError::NotConverged {
            landing_error_m: landing_error,
            iterations,
        });
    }
    let mut g = g0;
    if iterations > 0 {
        trace(x, &mut g)?;
    }
    let spreading = if let (true, true, Emitter::Point { position }, Target::Point(p)) =
        (opts.spreading, seq.is_empty(), emitter, target)
    {
        // The direct path of a point source: S² = 1/r² exactly (module docs), which the
        // finite-difference Jacobian below only reaches to ~1e-10 (`fringe fuzz --family
        // incoherent_sum --seed 1`, scene 333: 1.4e-10 in a medium of n = 10).
        1.0 / (p - position).length_squared()
    } else if opts.spreading {
        let j = jacobian(x, &mut scratch).ok_or(PathError::NotConverged {
            landing_error_m: landing_error,
            iterations,
        })?;
        let det = (j[0][0] * j[1][1] - j[0][1] * j[1][0]).abs();
        let d_f = *g.dirs.last().unwrap();
        let area = det * d_f.dot(frame.0).abs();
        let n_src = optics.ambient_index;
        let n_end = *g.indices.last().unwrap();
        (n_src / n_end) * g.refraction_factor * model.measure(x) / area
    } else {
        1.0
    };
    if let Target::Point(p) = target {
        // Land exactly on P: the last segment ends at the target point.
        let last = *g.points.last().unwrap();
        if (p - last).dot(*g.dirs.last().unwrap()) <= 0.0 {
            return Err(PathError::Behind);
        }
        g.points.push(p);
    }
    // A line source's direct ray leaves the line itself perpendicular to it, toward the target:
    // from the f64 launch point (off the line by a rounding of its coordinates) the direction,
    // and with it the launch field, would turn by up to that rounding over the path's length
    // (`scene::source::line_launch_direction`). Only without events: a path with events was
    // landed from the launch point, and its first event's incidence angle must stay consistent
    // with the directions after it (from the line's own foot the first segment of a Lloyd
    // mirror's reflected path turned by that rounding over the first segment alone, and 44 of
    // `fringe fuzz --family lloyd --count 2000 --seed 1` failed).
    if let (Emitter::Line { point, axis }, [_, first]) = (emitter, &g.points[..])
        && let Some(d) =
            crate::scene::source::line_launch_direction(point, axis.normalize(), *first)
    {
        g.dirs[0] = d;
    }
    // A plane wave's launch point is meant to lie on its reference plane, but it is formed in
    // f64 (base + p·e1 + p·e2) and sits off that plane by a rounding of its distance from the
    // reference point: the wave's phase there, n (o − r0)·d, is not 0 but ~1e-16 m per metre,
    // 1e-8 rad at 200 nm for a reference 1 m away (found by `fringe fuzz --family wedge`
    // against a 50-digit ray trace). Start the optical path at that phase, in double-double.
    let start = match emitter {
        Emitter::PlaneWave {
            direction,
            reference_point,
        } => {
            let mut start = projection(direction.normalize(), g.points[0], reference_point)
                .mul_f64(optics.ambient_index);
            // The last segment is drawn from the last event point X to the target P (above),
            // a kink for a landing error m: |P − X| exceeds the wave's own path to P's
            // wavefront, (P − X)·d, by m²/(2L). Between plane faces a plane wave stays plane, so
            // (P − X)·d is exact; the difference, −|v⊥|²/(|v| + v·d) with v = P − X, is
            // subtracted here (a small-angle wedge seen 1e-4 m above its face was accepted
            // 1.5e-11 m off its target, 1.1e-18 m of path, 1e-11 of I: `fringe fuzz --family
            // wedge --seed 1` scene 538, `tests/suite/truth_small_deviations.rs`).
            if let (Target::Point(p), [.., x, _]) = (target, &g.points[..]) {
                let d = g.dirs.last().unwrap().normalize();
                let v = p - *x;
                let along = v.dot(d);
                let perp = (v - along * d).length_squared();
                let kink = -perp / (v.length() + along);
                if kink.is_finite() {
                    start += DoubleDouble::from(kink * g.indices.last().unwrap());
                }
            }
            start
        }
        // A line source's launch point is an f64 point near the line, off it by up to ~ulp of its
        // coordinates (2.8e-14 m at 183 m): measured from there the first segment would carry that
        // as a first-order path error. The wave's phase at the first point is n times its
        // perpendicular distance to the line itself (docs/PHYSICS.md §5 "Young"), formed from exact
        // differences to the source's own point; the start corrects the first segment to it.
        Emitter::Line { point, axis } if g.points.len() > 1 => {
            let n0 = g.indices[0];
            // The first segment as `finish` measures it (along the ray when it ends on an event).
            let first = if seq.is_empty() {
                segment_length(g.points[0], g.points[1])
            } else {
                event_segment_length(g.points[0], g.points[1], g.dirs[0])
            };
            (distance_to_line(point, axis.normalize(), g.points[1]) - first).mul_f64(n0)
        }
        _ => DoubleDouble::ZERO,
    };
    let mut path = finish(
        scene,
        g,
        seq,
        &target,
        (landing_error, iterations, spreading),
        start,
    )?;
    if x == [0.0, 0.0] {
        path.launch_normal_q2 = launch_p2;
    }
    Ok(path)
}

/// The length (m, double-double) of a segment from `a` that ends on an event point `b`, the
/// point where the ray from `a` along `d` meets the event's plane, rounded to f64: measured along
/// `d` as d·(b − a)/|d| ([`projection`]), not as |b − a|. A rounding δ of `b` moves the two
/// measures alike to first order (δ·d, which the next segment's −δ·d′ cancels along the plane,
/// and [`crate::scene::geometry::Plane::off_plane_path_correction`] across it), but |b − a| adds
/// the second-order |δ⊥|²/(2L), which is no longer small when the segment is as short as a film
/// is thin: a 0.1 nm film 100 m from the origin (δ ~ 7e-15 m, L ~ 1e-10 m) gained 5e-19 m per
/// round trip, 3.7e-9 of its R off 50 digits (`fringe fuzz --family airy --count 1000 --seed 1`,
/// scene 499; docs/PHYSICS.md §8).
#[inline]
pub(crate) fn event_segment_length(a: DVec3, b: DVec3, d: DVec3) -> DoubleDouble {
    projection(d, b, a)
}

/// Validate extents and blockers and assemble the [`SolvedPath`]; `start` is the optical path
/// at the launch point ([`SolvedPath::start_optical_path`]).
fn finish(
    scene: &Scene,
    g: Geometry,
    seq: &[Event],
    target: &Target,
    (landing_error, iterations, spreading): (f64, usize, f64),
    start: DoubleDouble,
) -> Result<SolvedPath, PathError> {
    // Each event point must lie on its surface.
    for (k, ev) in seq.iter().enumerate() {
        if let Some(e) = out_of_extent(scene, k, *ev, g.points[k + 1]) {
            return Err(e);
        }
    }
    // No segment may cross a blocker or an unlisted interacting surface.
    let far = matches!(target, Target::Direction { .. });
    let n_seg = if far {
        g.points.len()
    } else {
        g.points.len() - 1
    };
    // Σ n_i L_i over the finite segments in double-double, each length measured once from
    // exact coordinate differences, summed in order (as `FarFieldPaths` sums them).
    let mut optical_path = start;
    for i in 0..n_seg {
        let a = g.points[i];
        let len = if i + 1 < g.points.len() {
            let len = if i < seq.len() {
                event_segment_length(a, g.points[i + 1], g.dirs[i])
            } else {
                segment_length(a, g.points[i + 1])
            };
            optical_path += len.mul_f64(g.indices[i]);
            // Event i's point back onto its plane (first order; as `FarFieldPaths` adds it).
            if let Some(ev) = seq.get(i) {
                optical_path +=
                    DoubleDouble::from(scene.surfaces[ev.surface].plane.off_plane_path_correction(
                        g.points[i + 1],
                        (g.indices[i], g.dirs[i]),
                        (g.indices[i + 1], g.dirs[i + 1]),
                    ));
            }
            len.to_f64()
        } else {
            f64::INFINITY
        };
        let ends = [
            i.checked_sub(1).map(|e| seq[e].surface),
            seq.get(i).map(|e| e.surface),
        ];
        if let Some(e) = segment_blocked(scene, i, ends, a, g.dirs[i], len) {
            return Err(e);
        }
    }
    if let Target::Direction { reference, dir } = target {
        let (x, n) = (*g.points.last().unwrap(), *g.indices.last().unwrap());
        optical_path += to_far_wavefront(x, dir.normalize(), n, *reference);
    }
    Ok(SolvedPath {
        sequence: seq.to_vec().into(),
        optical_path,
        start_optical_path: start,
        landing_error,
        iterations,
        denser_reflections: g.denser_reflections,
        has_tir: g.has_tir,
        spreading,
        launch_normal_q2: None,
        points: g.points.into(),
        dirs: g.dirs.into(),
        indices: g.indices.into(),
    })
}
