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
use crate::optics::interaction::{InterfaceHit, SurfaceOptics, indices_for};
use crate::optics::trail::Trail;
use crate::scene::geometry::{Extent, Plane};
use crate::scene::source::Emitter;
use crate::scene::{Scene, SceneOptics, SurfaceKind};
use crate::trace::sequence_tree::{SequenceTree, TreeBuilder};
use crate::{optics::fresnel, optics::interaction};
use glam::DVec3;

/// Reflect or refract.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum EventKind {
    /// Reflected at the surface.
    Reflect,
    /// Refracted (transmitted) through it.
    Refract,
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
    /// ([`plane_wave_launch`]), where it is n·d·(launch − reference). Included in
    /// `optical_path`; rays start with it.
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

/// One event of a trace on the unbounded planes (no extents, no blockers).
struct PlaneStep {
    /// The event point.
    x: DVec3,
    /// Direction and index after the event.
    d: DVec3,
    n: f64,
    /// A reflection from the denser side (π jump of `scalar_jump`).
    denser: bool,
    /// A totally internally reflected reflection.
    tir: bool,
    /// n2 cos θt/(n1 cos θi) for a refraction, 1 for a reflection.
    refraction_factor: f64,
    /// The normal and (n cos θ)² after the event, in double-double (`Ray::normal_q2`).
    q2: (DVec3, DoubleDouble),
}

/// Event `k` of a sequence, `ev`, met by the ray from `o` along `d` in index `n`, carrying
/// `carried` ([`crate::optics::ray::Ray::normal_q2`]): TIR verdicts, refracted directions and the
/// refraction factor from the double-double normal wavevectors the tracer uses
/// ([`interaction::normal_wavevector_squares`]).
#[inline(always)]
fn step_planes(
    scene: &Scene,
    optics: &SceneOptics,
    k: usize,
    ev: Event,
    (o, d, n): (DVec3, DVec3, f64),
    carried: Option<(DVec3, DoubleDouble)>,
) -> Result<PlaneStep, PathError> {
    let surf = &scene.surfaces[ev.surface];
    let so = surface_optics(optics, k, ev.surface)?;
    let t = surf
        .plane
        .intersect(o, d)
        .filter(|t| *t > 0.0)
        .ok_or(PathError::Missed { event: k })?;
    // The hit point on the plane itself: o + t·d rounds at the size of t (a launch 100 m away
    // leaves the point ~1e-14 m off the plane, a first-order error of every path through it);
    // moved back onto the plane it is off by the rounding of its distance to the plane's point
    // only. Along the plane the rounding is second order (Fermat).
    let x = surf.plane.project(o + t * d);
    let normal = surf.plane.normal;
    let (n1, n2) = indices_for(so, normal, d, n);
    let (q2_i, q2_t) = interaction::normal_wavevector_squares(d, normal, (n1, n2), carried);
    let mirror = matches!(so, SurfaceOptics::IdealMirror);
    let splitter = matches!(so, SurfaceOptics::Splitter { .. });
    if n1 != n {
        return Err(PathError::MediumMismatch { event: k });
    }
    Ok(match ev.kind {
        EventKind::Reflect => PlaneStep {
            x,
            d: fresnel::reflect(d, normal),
            n,
            denser: mirror || n1 < n2 || (splitter && d.dot(normal) < 0.0),
            tir: !mirror && !splitter && q2_t.hi < 0.0,
            refraction_factor: 1.0,
            q2: (normal, q2_i),
        },
        EventKind::Refract => {
            if mirror {
                return Err(PathError::TotalInternalReflection { event: k });
            }
            let d_t = if matches!(so, SurfaceOptics::Dielectric { .. }) && n1 != n2 {
                if q2_t.hi < 0.0 {
                    return Err(PathError::TotalInternalReflection { event: k });
                }
                interaction::snell_direction(d, normal, (n1, n2), q2_t.sqrt().to_f64() / n2)
            } else {
                fresnel::refract(d, normal, n1, n2)
                    .ok_or(PathError::TotalInternalReflection { event: k })?
            };
            PlaneStep {
                x,
                d: d_t,
                n: n2,
                denser: false,
                tir: false,
                refraction_factor: (q2_t.sqrt().to_f64() / q2_i.sqrt().to_f64()),
                q2: (normal, q2_t),
            }
        }
    })
}

/// Trace a ray through `seq` on the unbounded planes (no extents, no blockers) into `g`
/// (cleared first; nothing is allocated when the first event already fails).
fn trace_planes(
    scene: &Scene,
    optics: &SceneOptics,
    origin: DVec3,
    dir: DVec3,
    seq: &[Event],
    g: &mut Geometry,
) -> Result<(), PathError> {
    g.clear();
    if seq.is_empty() {
        g.start(origin, dir, optics.ambient_index, 0);
    }
    let mut ray = (origin, dir, optics.ambient_index);
    let mut carried = None;
    for (k, ev) in seq.iter().enumerate() {
        let step = step_planes(scene, optics, k, *ev, ray, carried)?;
        carried = Some(step.q2);
        g.denser_reflections += usize::from(step.denser);
        g.has_tir |= step.tir;
        g.refraction_factor *= step.refraction_factor;
        if k == 0 {
            g.start(origin, dir, optics.ambient_index, seq.len());
        }
        g.points.push(step.x);
        g.dirs.push(step.d);
        g.indices.push(step.n);
        ray = (step.x, step.d, step.n);
    }
    Ok(())
}

/// How the two launch parameters map to a launch ray.
struct LaunchModel {
    emitter: Emitter,
    /// Guess direction (point/line) or fixed direction (plane wave).
    g: DVec3,
    e1: DVec3,
    e2: DVec3,
    base: DVec3,
}

impl LaunchModel {
    fn new(emitter: Emitter, guess_dir: DVec3, guess_origin: DVec3) -> Self {
        match emitter {
            Emitter::Point { position } => {
                let g = guess_dir.normalize();
                let e1 = g.any_orthonormal_vector();
                LaunchModel {
                    emitter,
                    g,
                    e1,
                    e2: g.cross(e1),
                    base: position,
                }
            }
            Emitter::Line { point, axis } => {
                let a = axis.normalize();
                let gp = guess_dir - guess_dir.dot(a) * a;
                let g = if gp.length() > 1e-12 {
                    gp.normalize()
                } else {
                    a.any_orthonormal_vector()
                };
                // Origin nearest to the guess origin along the axis.
                let base = point + (guess_origin - point).dot(a) * a;
                LaunchModel {
                    emitter,
                    g,
                    e1: a,
                    e2: a.cross(g),
                    base,
                }
            }
            Emitter::PlaneWave {
                direction,
                reference_point,
            } => {
                let g = direction.normalize();
                let e1 = g.any_orthonormal_vector();
                // Start on the reference plane, on the line through the guess origin.
                let base = guess_origin - (guess_origin - reference_point).dot(g) * g;
                LaunchModel {
                    emitter,
                    g,
                    e1,
                    e2: g.cross(e1),
                    base,
                }
            }
        }
    }

    fn launch(&self, p: [f64; 2]) -> (DVec3, DVec3) {
        match self.emitter {
            Emitter::Point { .. } => (
                self.base,
                (self.g + p[0] * self.e1 + p[1] * self.e2).normalize(),
            ),
            Emitter::Line { .. } => (
                self.base + p[0] * self.e1,
                (self.g + p[1] * self.e2).normalize(),
            ),
            Emitter::PlaneWave { .. } => (self.base + p[0] * self.e1 + p[1] * self.e2, self.g),
        }
    }

    /// Launch measure per unit parameter area: solid angle (point, gnomonic Jacobian
    /// (1+a²+b²)^{-3/2}), length × angle (line), or area (plane wave).
    fn measure(&self, p: [f64; 2]) -> f64 {
        match self.emitter {
            Emitter::Point { .. } => (1.0 + p[0] * p[0] + p[1] * p[1]).powf(-1.5),
            Emitter::Line { .. } => 1.0 / (1.0 + p[1] * p[1]),
            Emitter::PlaneWave { .. } => 1.0,
        }
    }

    /// Finite-difference step per parameter.
    fn step(&self, scale: f64) -> [f64; 2] {
        match self.emitter {
            Emitter::Point { .. } => [1e-6, 1e-6],
            Emitter::Line { .. } => [1e-6 * scale, 1e-6],
            Emitter::PlaneWave { .. } => [1e-6 * scale, 1e-6 * scale],
        }
    }
}

/// The launch direction of the exact path from a point source at `source` to the point
/// `target` when every event plane of `seq` is parallel to the first (a plate, a film stack, a
/// mirror parallel to a plate), or `None` when the planes are not parallel or the sequence
/// cannot be followed in the plane of incidence (the general solver then decides).
///
/// All segments then lie in the plane of incidence through `source`, `target` and the common
/// normal ν, and Snell's law keeps the invariant p = n_k sin θ_k (θ_k: angle of segment k to
/// ν) the same on every segment, reflections included. Segment k of height h_k (its extent
/// along ν, from the plane heights) in index n_k runs h_k tan θ_k = h_k p/√(n_k² − p²)
/// sideways, so p solves the lateral-run equation
///
/// f(p) = Σ_k h_k p/√(n_k² − p²) − D = 0,  0 ≤ p < min n_k,
///
/// with D the lateral distance from source to target. f is increasing and convex, so Newton's
/// method safeguarded by bisection on the bracket converges from any start. The segment
/// indices depend only on the sequence, not on the launch angle.
fn parallel_stack_launch(
    scene: &Scene,
    optics: &SceneOptics,
    seq: &[Event],
    source: DVec3,
    target: DVec3,
) -> Option<DVec3> {
    use crate::optics::double_double::two_diff;
    let nu = scene.surfaces[seq.first()?.surface].plane.normal;
    // The target relative to the source from exact coordinate differences, split along ν and
    // across it in double-double: scenes far from the origin (a mirror at 100 m, a source 1 µm
    // above it) keep the heights and the lateral distance to their own size, where f64 dot
    // products of absolute coordinates round at ~1e-14 m (a 1 µm height 1.4e-8 off moved a
    // Lloyd fringe by 1e-11, `fringe fuzz --family lloyd --seed 1`, scene 218).
    let v = [
        two_diff(target.x, source.x),
        two_diff(target.y, source.y),
        two_diff(target.z, source.z),
    ];
    let target_along = v[0].mul_f64(nu.x) + v[1].mul_f64(nu.y) + v[2].mul_f64(nu.z);
    // Heights along ν relative to the source (k = 0), of event plane k (1..=len) and the
    // target: a plane's is minus the source's signed distance from it, in double-double from
    // the plane as held (anchor and height, `Plane::signed_distance_precise`).
    let z = |k: usize| match k {
        0 => 0.0,
        k if k <= seq.len() => {
            let plane = &scene.surfaces[seq[k - 1].surface].plane;
            let side = if plane.normal.dot(nu) > 0.0 {
                1.0
            } else {
                -1.0
            };
            -side * plane.signed_distance_precise(source)
        }
        _ => target_along.to_f64(),
    };
    // Walk the segments: the direction along ν (it flips at reflections only) and the index
    // (it changes at refractions only), exactly as `trace_planes` finds them for any launch;
    // anything it would reject is left to the general solver and its error.
    let n0 = optics.ambient_index;
    let first_up = (z(1) - z(0)).signum();
    let (mut up, mut n) = (first_up, n0);
    // Total height per index (one entry per medium; more media than this is left to Newton).
    let mut runs = [(0.0, 0.0); 4];
    let mut media = 0;
    for k in 0..=seq.len() {
        let dz = z(k + 1) - z(k);
        if dz == 0.0 || dz.signum() != up {
            return None;
        }
        match runs[..media].iter_mut().find(|r| r.1 == n) {
            Some(r) => r.0 += dz.abs(),
            None if media < 4 => {
                runs[media] = (dz.abs(), n);
                media += 1;
            }
            None => return None,
        }
        let Some(ev) = seq.get(k) else { break };
        let normal = scene.surfaces[ev.surface].plane.normal;
        if normal.cross(nu).length_squared() > 1e-30 {
            return None;
        }
        let so = optics.surfaces[ev.surface]?;
        let (n1, n2) = indices_for(so, normal, up * nu, n);
        if n1 != n {
            return None;
        }
        match (ev.kind, so) {
            (EventKind::Reflect, _) => up = -up,
            (EventKind::Refract, SurfaceOptics::IdealMirror) => return None,
            (EventKind::Refract, _) => n = n2,
        }
    }
    let runs = &runs[..media];
    let lateral = DVec3::new(
        (v[0] - target_along.mul_f64(nu.x)).to_f64(),
        (v[1] - target_along.mul_f64(nu.y)).to_f64(),
        (v[2] - target_along.mul_f64(nu.z)).to_f64(),
    );
    let d = lateral.length();
    // The invariant in double-double: near grazing, p is within a rounding of n0 (cos θ0 =
    // 8.7e-9 puts p at n0 (1 − 3.8e-17), below the ulp of 1), so an f64 p rounds to n0 and
    // the launch is parallel to the plate: the beam through a plate was lost (`Missed`) or,
    // one ulp off, cos θ0 and the landing carried a relative error of ~u/cos²θ0 (`fringe fuzz
    // --family two_beam_plate --seed 1`, scenes 106, 129, docs/PHYSICS.md §8). Newton's method
    // runs on p in double-double and cos θ0 = √((n0 − p)(n0 + p))/n0 is formed from it, so both
    // direction components keep their relative precision at any angle.
    let dd = DoubleDouble::from_f64;
    let p = if d == 0.0 {
        dd(0.0)
    } else {
        let p_max = runs.iter().map(|r| r.1).fold(f64::INFINITY, f64::min);
        let height: f64 = runs.iter().map(|r| r.0).sum();
        // f(p) in double-double and f'(p) in f64; f = +∞ where a segment's cosine vanishes.
        let f = |p: DoubleDouble| -> (DoubleDouble, f64) {
            runs.iter().fold((dd(-d), 0.0), |(f, df), &(h, n)| {
                let c2 = (dd(n) - p) * (dd(n) + p);
                if c2.hi <= 0.0 {
                    return (dd(f64::INFINITY), f64::INFINITY);
                }
                let c = c2.sqrt();
                let c2f = c2.to_f64();
                (f + (p * h) / c, df + h * n * n / (c2f * c.to_f64()))
            })
        };
        // Start where every segment had the lowest index (f ≤ 0 there).
        let (mut lo, mut hi) = (dd(0.0), dd(p_max));
        let mut p = dd(p_max * d / d.hypot(height));
        // Quadratic convergence: a few steps reach the double-double rounding of p_max.
        let ulps = 1e-31 * p_max;
        for _ in 0..256 {
            let (fp, dfp) = f(p);
            if fp.hi == 0.0 {
                break;
            }
            if fp.hi < 0.0 {
                lo = p
            } else {
                hi = p
            }
            let step = if dfp.is_finite() && dfp > 0.0 {
                fp.to_f64() / dfp
            } else {
                f64::NAN
            };
            let newton = p - dd(step);
            if step.abs() <= ulps {
                p = newton;
                break;
            }
            p = if (newton - lo).hi > 0.0 && (hi - newton).hi > 0.0 {
                newton
            } else {
                (lo + hi).mul_f64(0.5)
            };
            if (hi - lo).hi <= ulps {
                break;
            }
        }
        p
    };
    let sin0 = (p / dd(n0)).to_f64();
    let cos0 = (((dd(n0) - p) * (dd(n0) + p)).sqrt() / dd(n0)).to_f64();
    let u = if d == 0.0 { DVec3::ZERO } else { lateral / d };
    Some(sin0 * u + cos0 * first_up * nu)
}

/// Whether no path from a point `source` through `seq` to the point `target` can exist, decided
/// from the geometry alone without solving; `false` when in doubt. When it returns true,
/// [`solve`] fails too (with an error of its own, which this test does not name): callers that
/// only need the paths that exist skip the solve. Two cases are decided:
///
/// * the empty sequence: the straight segment crosses a surface that stops or deflects it
///   there ([`Surface::surely_stops`](crate::scene::Surface::surely_stops));
/// * a sequence whose event planes are all parallel (normal ν): every segment's direction along
///   ν is fixed by the sequence (reflections flip it, refractions keep it), so a segment that
///   must run against the order of its end heights is missed, and a segment that crosses an
///   unbounded interface parallel to the events (other than its own end surfaces) is blocked,
///   whatever the launch.
///
/// Heights and crossings must clear their limits by 1e-9 × (1 m + the scene size) — a thousand
/// times the solver's own margins (`finish`'s 1e-12 (1 + t)) and far above rounding and
/// landing errors — so a true here never depends on rounding.
pub fn cannot_reach(scene: &Scene, emitter: Emitter, seq: &[Event], target: &Target) -> bool {
    let (Emitter::Point { position: source }, Target::Point(p)) = (emitter, *target) else {
        return false;
    };
    match seq.first() {
        None => straight_segment_stopped(scene, source, p),
        Some(first) => stack_cannot_reach(scene, seq, source, p, first.surface),
    }
}

/// An upper bound of |v| without a square root (|v| ≤ √3 max |v_i|).
fn length_bound(v: DVec3) -> f64 {
    1.7320508075688772 * v.abs().max_element()
}

/// [`cannot_reach`] for the direct path from `a` to `b`.
fn straight_segment_stopped(scene: &Scene, a: DVec3, b: DVec3) -> bool {
    // The solved launch lands within 1e-12 × scene scale of b (`scene_scale`), so crossing
    // points move by at most that much: bound the scale from above.
    let scale = scene
        .surfaces
        .iter()
        .map(|s| length_bound(s.plane.point - a))
        .fold(length_bound(b - a), f64::max);
    let margin = 1e-9 * (1.0 + scale);
    let length = length_bound(b - a);
    scene.surfaces.iter().any(|surf| {
        let (sa, sb) = (surf.plane.signed_distance(a), surf.plane.signed_distance(b));
        // Both ends clearly on opposite sides (then the segment is longer than 2 × margin).
        if !((sa > margin && sb < -margin) || (sa < -margin && sb > margin)) {
            return false;
        }
        let x = a + (sa / (sa - sb)) * (b - a);
        // An end moved by δ moves the crossing by at most δ (1 + |b − a|/|sa − sb|).
        surf.surely_stops(x, margin * (1.0 + length / (sa - sb).abs()))
    })
}

/// [`cannot_reach`] for a sequence on parallel planes.
fn stack_cannot_reach(
    scene: &Scene,
    seq: &[Event],
    source: DVec3,
    target: DVec3,
    first: usize,
) -> bool {
    // Longer sequences are left to the solver.
    const MAX_HEIGHTS: usize = 16;
    if seq.len() + 2 > MAX_HEIGHTS {
        return false;
    }
    let nu = scene.surfaces[first].plane.normal;
    let parallel = |n: DVec3| n == nu || n.cross(nu).length_squared() <= 1e-30;
    // Heights along ν of the source (k = 0), event plane k (1..=len) and the target.
    let mut heights = [0.0; MAX_HEIGHTS];
    heights[0] = source.dot(nu);
    for (k, ev) in seq.iter().enumerate() {
        let plane = &scene.surfaces[ev.surface].plane;
        if !parallel(plane.normal) {
            return false;
        }
        heights[k + 1] = plane.point.dot(nu);
    }
    heights[seq.len() + 1] = target.dot(nu);
    let z = &heights[..seq.len() + 2];
    // Every segment runs at most its height plus the lateral distance (all segments run the
    // same way sideways in the plane of incidence): the scene size bounds their lengths.
    let size =
        length_bound(target - source) + z.windows(2).map(|w| (w[1] - w[0]).abs()).sum::<f64>();
    let margin = 1e-9 * (1.0 + size);
    // The first segment runs toward the first plane; any launch that reaches it does.
    let dz0 = z[1] - z[0];
    if dz0.abs() <= margin {
        return false;
    }
    // The unbounded interfaces parallel to the events (surface, height): a segment strictly
    // between two of its own ends' heights that crosses one is blocked.
    const MAX_PLANES: usize = 16;
    let mut planes = [(0, 0.0); MAX_PLANES];
    let mut n_planes = 0;
    for (j, surf) in scene.surfaces.iter().enumerate() {
        if matches!(surf.extent, Extent::Unbounded)
            && !matches!(surf.kind, SurfaceKind::Opaque { .. })
            && parallel(surf.plane.normal)
        {
            if n_planes == MAX_PLANES {
                break; // the rest are not looked at: fewer claims, never a wrong one
            }
            planes[n_planes] = (j, surf.plane.point.dot(nu));
            n_planes += 1;
        }
    }
    let planes = &planes[..n_planes];
    let mut up = dz0.signum();
    for k in 0..=seq.len() {
        let (za, zb) = (z[k], z[k + 1]);
        if (zb - za) * up < -margin {
            // Missed (or the target behind): this segment runs away from its end.
            return true;
        }
        let ends = |j: usize| {
            (k >= 1 && seq[k - 1].surface == j) || (k < seq.len() && seq[k].surface == j)
        };
        let (lo, hi) = (za.min(zb) + margin, za.max(zb) - margin);
        if planes.iter().any(|&(j, zj)| zj > lo && zj < hi && !ends(j)) {
            return true;
        }
        if seq.get(k).is_some_and(|ev| ev.kind == EventKind::Reflect) {
            up = -up;
        }
    }
    false
}

/// Image-method initial guess: the target mirrored through every reflection, in reverse order.
fn unfolded_target(scene: &Scene, seq: &[Event], p: DVec3) -> DVec3 {
    seq.iter().rev().fold(p, |x, ev| match ev.kind {
        EventKind::Reflect => scene.surfaces[ev.surface].plane.mirror_point(x),
        EventKind::Refract => x,
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

/// Whether the landing error of a path through parallel planes, launched from the Snell
/// invariant of [`parallel_stack_launch`] (the path exists: the invariant's equation has its
/// root) and refined by Newton as far as f64 directions allow, is harmless to what the tracer
/// reports. Directions are f64 unit vectors: leaving a plate whose index is up to 10^4 times the
/// ambient's near grazing, the refraction multiplies their rounding by the index ratio and by
/// 1/cos²θ on the way to the target, so the landing error stalls above 1e-12 of the scene
/// (5.8e-8 m at 125 m for ambient n = 0.001 over a plate n = 1 at 88.9°; `fringe fuzz --family
/// two_beam_plate --seed 7`, scene 5), and the path was dropped, silently losing a beam. The
/// last segment ends exactly at the target and the optical path is stationary in the event
/// points (Fermat), so a landing error δ changes the path by ~n δ²/(2 L) with L the last
/// segment's length: accepted while that is ≤ [`STACK_PATH_SECOND_ORDER_M`], the directions and
/// amplitudes then being those of the exact launch to rounding.
fn stack_landing_harmless(
    trace: &impl Fn([f64; 2], &mut Geometry) -> Result<(), PathError>,
    x: [f64; 2],
    g: &mut Geometry,
    target: Target,
) -> bool {
    let Target::Point(p) = target else {
        return false;
    };
    if trace(x, g).is_err() {
        return false;
    }
    let (Some(&last), Some(&d), Some(&n)) = (g.points.last(), g.dirs.last(), g.indices.last())
    else {
        return false;
    };
    let along = (p - last).dot(d);
    if along <= 0.0 {
        return false;
    }
    let miss = ((p - last) - along * d).length();
    n * miss * miss / (2.0 * along) <= STACK_PATH_SECOND_ORDER_M
}

/// The largest second-order optical-path change (m) a stalled landing may cost a path through
/// parallel planes ([`stack_landing_harmless`]): 1e-18 m is 5e-12 of a cycle (3e-11 rad) at
/// 200 nm, the shortest wavelength a case may use, so it moves a two-beam intensity by at most
/// ~6e-11 of its scale, 16 times below the library's tightest tolerance (1e-9 in `fringe fuzz`).
const STACK_PATH_SECOND_ORDER_M: f64 = 1e-18;

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
    let from_reference = (reference, DoubleDouble::ZERO);
    let Some(first) = scene.surfaces.first() else {
        return from_reference;
    };
    let nu = first.plane.normal;
    let stack = scene.surfaces.iter().all(|s| {
        matches!(s.extent, Extent::Unbounded)
            && !matches!(s.kind, SurfaceKind::Opaque { .. })
            && (s.plane.normal == nu || s.plane.normal.cross(nu).length_squared() <= 1e-30)
    });
    if !stack {
        return from_reference;
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
    // Every plane must lie ahead (the reference before the whole stack), the first by > 1 mm.
    const STANDOFF_M: f64 = 1e-3;
    let all_ahead = scene.surfaces.iter().all(|s| {
        s.plane
            .intersect(reference, direction)
            .is_some_and(|t| t > 0.0)
    });
    match nearest {
        Some((t, surf)) if all_ahead && t > STANDOFF_M => {
            let launch = surf.plane.point - STANDOFF_M * direction;
            (launch, projection(direction, launch, reference))
        }
        _ => from_reference,
    }
}

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
        let err = far_field_landing(*g.dirs.last().unwrap(), dir)?;
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
                EventKind::Refract => d,
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
    if let Some(d) = stack {
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
            trace_planes(scene, optics, o, d, seq, &mut g0)?;
            m
        }
    };
    let trace = |p: [f64; 2], g: &mut Geometry| {
        let (o, d) = model.launch(p);
        trace_planes(scene, optics, o, d, seq, g)
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
    // A plane wave's launch point is meant to lie on its reference plane, but it is formed in
    // f64 (base + p·e1 + p·e2) and sits off that plane by a rounding of its distance from the
    // reference point: the wave's phase there, n (o − r0)·d, is not 0 but ~1e-16 m per metre,
    // 1e-8 rad at 200 nm for a reference 1 m away (found by `fringe fuzz --family wedge`
    // against a 50-digit ray trace). Start the optical path at that phase, in double-double.
    let start = match emitter {
        Emitter::PlaneWave {
            direction,
            reference_point,
        } => projection(direction.normalize(), g.points[0], reference_point)
            .mul_f64(optics.ambient_index),
        // A line source's launch point is an f64 point near the line, off it by up to ~ulp of its
        // coordinates (2.8e-14 m at 183 m): measured from there the first segment would carry that
        // as a first-order path error. The wave's phase at the first point is n times its
        // perpendicular distance to the line itself (docs/PHYSICS.md §5 "Young"), formed from exact
        // differences to the source's own point; the start corrects the first segment to it.
        Emitter::Line { point, axis } if g.points.len() > 1 => {
            let n0 = g.indices[0];
            (distance_to_line(point, axis.normalize(), g.points[1])
                - segment_length(g.points[0], g.points[1]))
            .mul_f64(n0)
        }
        _ => DoubleDouble::ZERO,
    };
    finish(
        scene,
        g,
        seq,
        &target,
        (landing_error, iterations, spreading),
        start,
    )
}

/// The distance (m, double-double) from `x` to the line through `point` along the unit `axis`:
/// |v − (v·a) a| with v = x − point from exact coordinate differences.
fn distance_to_line(point: DVec3, axis: DVec3, x: DVec3) -> DoubleDouble {
    use crate::optics::double_double::two_diff;
    let v = [
        two_diff(x.x, point.x),
        two_diff(x.y, point.y),
        two_diff(x.z, point.z),
    ];
    let along = v[0] * axis.x + v[1] * axis.y + v[2] * axis.z;
    let w = [
        v[0] - along * axis.x,
        v[1] - along * axis.y,
        v[2] - along * axis.z,
    ];
    (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt()
}

/// Whether event `k` (`ev` at `x`) lies outside its surface's extent.
#[inline]
fn out_of_extent(scene: &Scene, k: usize, ev: Event, x: DVec3) -> Option<PathError> {
    (!scene.surfaces[ev.surface].interacts(x)).then_some(PathError::OutOfExtent {
        event: k,
        surface: ev.surface,
    })
}

/// Where the segment from `a` along unit `d` over `len` m (`f64::INFINITY`: a ray) crosses
/// `plane` strictly between its ends: the ray parameter and the point, or `None`.
///
/// Scale-free: an end counts as on the plane (no crossing there) only when its signed distance
/// is within the rounding of that distance itself, a few ulps of its distance from the plane's
/// point — no absolute length, so a plane 1 pm from an end is crossed (a film of 1 pm is a
/// film) while a plane through an end is not.
#[inline(always)]
pub fn crossing(plane: &Plane, a: DVec3, d: DVec3, len: f64) -> Option<(f64, DVec3)> {
    let rate = d.dot(plane.normal);
    if rate == 0.0 {
        return None;
    }
    let sa = plane.signed_distance(a);
    let t = -sa / rate;
    if t <= 0.0 || t >= len {
        return None;
    }
    // Rounding of the signed distances at the ends (8 ulps of the distance to the plane's
    // point, which bounds the dot product's rounding).
    let rounding = |x: DVec3| 8.0 * f64::EPSILON * (x - plane.point).abs().max_element();
    if sa.abs() <= rounding(a) {
        return None;
    }
    if len.is_finite() {
        let b = a + len * d;
        if (sa + rate * len).abs() <= rounding(b) {
            return None;
        }
    }
    Some((t, a + t * d))
}

/// Whether segment `i` (from `a` along `d` over `len` m; `f64::INFINITY` for the far field's
/// last) crosses a blocker or an interacting surface other than its end surfaces `ends` (the
/// events before and after it), strictly between its ends ([`crossing`]: no distance epsilon).
#[inline(always)]
fn segment_blocked(
    scene: &Scene,
    i: usize,
    ends: [Option<usize>; 2],
    a: DVec3,
    d: DVec3,
    len: f64,
) -> Option<PathError> {
    for (j, surf) in scene.surfaces.iter().enumerate() {
        if ends.contains(&Some(j)) {
            continue;
        }
        if let Some((_, x)) = crossing(&surf.plane, a, d, len)
            && (surf.blocks(x) || surf.interacts(x))
        {
            return Some(PathError::Blocked {
                segment: i,
                surface: j,
            });
        }
    }
    None
}

/// The optical path from the exit point `x` (index `n`) to the far-field wavefront through
/// `reference` perpendicular to the unit far-field direction `d`: −n·d·(x − reference), in
/// double-double ([`projection`]: a reference 100 m away keeps the digits of the path).
///
/// `d` is the *target's* direction, the same for every path into it, not each path's own exit
/// direction: those agree only to the rounding of their events (~1e-16 per event, more over
/// many reflected orders), and a direction error δ moves the projection of a point ℓ from the
/// reference by δ·ℓ — 1e-16 m at ℓ = 1 m, a 1e-9 rad phase error that grows with the
/// distance to the reference.
fn to_far_wavefront(x: DVec3, d: DVec3, n: f64, reference: DVec3) -> DoubleDouble {
    -projection(d, x, reference).mul_f64(n)
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
            let len = segment_length(a, g.points[i + 1]);
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
        points: g.points.into(),
        dirs: g.dirs.into(),
        indices: g.indices.into(),
    })
}

/// Whether a far-field path's exit direction `d_f` meets the target direction `dir`: the sine
/// of the angle between them (the landing error), or the mismatch.
fn far_field_landing(d_f: DVec3, dir: DVec3) -> Result<f64, PathError> {
    let err = d_f.cross(dir.normalize()).length();
    if err > 1e-9 || d_f.dot(dir) <= 0.0 {
        return Err(PathError::DirectionMismatch);
    }
    Ok(err)
}

/// A beginning of a sequence traced by [`FarFieldPaths`]: the records so far, and what the
/// checks of [`finish`] found on it.
#[derive(Clone)]
struct Beginning {
    sequence: Trail<Event>,
    points: Trail<DVec3>,
    dirs: Trail<DVec3>,
    indices: Trail<f64>,
    denser_reflections: usize,
    has_tir: bool,
    /// Σ n_i L_i over the finite segments so far (double-double, summed in order as
    /// [`finish`] sums them).
    optical_path: DoubleDouble,
    /// The first event outside its extent, if any.
    out_of_extent: Option<PathError>,
    /// The first blocked finite segment, if any.
    blocked: Option<PathError>,
    /// The normal and (n cos θ)² after the last event (`Ray::normal_q2`).
    q2: Option<(DVec3, DoubleDouble)>,
}

/// The exact paths of a plane wave into the far field, traced one event at a time so that
/// sequences sharing a beginning trace it once.
///
/// For a plane wave observed in the far field every launch is equivalent, so [`solve`] traces
/// from the wave's reference point along its direction, and event k of a sequence depends only
/// on the events before it. The beginnings of the current sequence are kept on a stack:
/// [`FarFieldPaths::advance`] adds an event (O(1): the records are shared [`Trail`]s, the
/// extent of the new event and the blockers of the new finite segment are checked once), and
/// [`FarFieldPaths::path`] completes the current beginning into the [`SolvedPath`] that
/// [`solve`] gives for the same sequence, bit for bit, with the same error when there is none.
/// Walking a [`SequenceTree`] depth first costs O(1) per node: O(m) for a plate's m internal
/// reflections instead of O(m²) when each order is traced from the source.
pub struct FarFieldPaths<'a> {
    scene: &'a Scene,
    optics: &'a SceneOptics,
    /// `stack[k]`: the beginning of k events.
    stack: Vec<Beginning>,
    /// The optical path at the launch point ([`plane_wave_launch`]).
    start: DoubleDouble,
}

impl<'a> FarFieldPaths<'a> {
    /// The empty beginning of the plane wave along `direction` through `reference_point`.
    pub fn new(
        scene: &'a Scene,
        optics: &'a SceneOptics,
        direction: DVec3,
        reference_point: DVec3,
    ) -> Self {
        let d = direction.normalize();
        let (launch, ahead) = plane_wave_launch(scene, d, reference_point);
        let start = ahead.mul_f64(optics.ambient_index);
        let root = Beginning {
            sequence: Trail::shared(),
            points: Trail::shared_of(launch),
            dirs: Trail::shared_of(d),
            indices: Trail::shared_of(optics.ambient_index),
            denser_reflections: 0,
            has_tir: false,
            optical_path: start,
            out_of_extent: None,
            blocked: None,
            q2: None,
        };
        FarFieldPaths {
            scene,
            optics,
            stack: vec![root],
            start,
        }
    }

    /// The optical path at the launch point (m; [`SolvedPath::start_optical_path`]).
    pub fn start_optical_path(&self) -> DoubleDouble {
        self.start
    }

    /// Number of events of the current beginning.
    pub fn depth(&self) -> usize {
        self.stack.len() - 1
    }

    /// Back to the beginning of `depth` events.
    pub fn truncate(&mut self, depth: usize) {
        self.stack.truncate(depth + 1);
    }

    /// The launch point, launch direction and spreading (1: a plane wave) of every path.
    pub fn launch(&self) -> (DVec3, DVec3, f64) {
        let root = &self.stack[0];
        (
            *root.points.last().unwrap(),
            *root.dirs.last().unwrap(),
            1.0,
        )
    }

    /// Event `k` of the current beginning and its point.
    pub fn event(&self, k: usize) -> (Event, DVec3) {
        let b = &self.stack[k + 1];
        (*b.sequence.last().unwrap(), *b.points.last().unwrap())
    }

    /// The current beginning's sequence.
    pub fn sequence(&self) -> Trail<Event> {
        self.stack.last().unwrap().sequence.clone()
    }

    /// One event further; on an error (the ray misses the event's plane, meets it from the
    /// wrong medium, is totally reflected where it should refract, or the surface is opaque)
    /// the beginning is unchanged, and every sequence that begins with it fails with this error.
    pub fn advance(&mut self, ev: Event) -> Result<(), PathError> {
        let k = self.depth();
        let b = self.stack.last().unwrap();
        let (o, d, n) = (
            *b.points.last().unwrap(),
            *b.dirs.last().unwrap(),
            *b.indices.last().unwrap(),
        );
        let step = step_planes(self.scene, self.optics, k, ev, (o, d, n), b.q2)?;
        let mut next = b.clone();
        next.q2 = Some(step.q2);
        next.denser_reflections += usize::from(step.denser);
        next.has_tir |= step.tir;
        // The finite segment k, from the last point to this event, as `finish` checks it.
        let length = segment_length(o, step.x);
        next.optical_path += length.mul_f64(n);
        // The event's point back onto its plane (first order; as `finish` adds it).
        next.optical_path += DoubleDouble::from(
            self.scene.surfaces[ev.surface]
                .plane
                .off_plane_path_correction(step.x, (n, d), (step.n, step.d)),
        );
        let len = length.to_f64();
        if next.out_of_extent.is_none() {
            next.out_of_extent = out_of_extent(self.scene, k, ev, step.x);
        }
        if next.blocked.is_none() {
            let ends = [b.sequence.last().map(|e| e.surface), Some(ev.surface)];
            next.blocked = segment_blocked(self.scene, k, ends, o, d, len);
        }
        next.sequence.push(ev);
        next.points.push(step.x);
        next.dirs.push(step.d);
        next.indices.push(step.n);
        self.stack.push(next);
        Ok(())
    }

    /// The current beginning as a whole sequence into the far-field `target` (a
    /// [`Target::Direction`]): the path [`solve`] finds for it, or its error.
    pub fn path(&self, target: &Target) -> Result<SolvedPath, PathError> {
        let Target::Direction { dir, reference } = *target else {
            panic!("FarFieldPaths::path needs a far-field target, got {target:?}");
        };
        let b = self.stack.last().unwrap();
        let (x, d, n) = (
            *b.points.last().unwrap(),
            *b.dirs.last().unwrap(),
            *b.indices.last().unwrap(),
        );
        let landing_error = far_field_landing(d, dir)?;
        if let Some(e) = b.out_of_extent.clone().or_else(|| b.blocked.clone()) {
            return Err(e);
        }
        // The last segment runs from the last point to infinity.
        let k = self.depth();
        let ends = [b.sequence.last().map(|e| e.surface), None];
        if let Some(e) = segment_blocked(self.scene, k, ends, x, d, f64::INFINITY) {
            return Err(e);
        }
        Ok(SolvedPath {
            sequence: b.sequence.clone(),
            points: b.points.clone(),
            dirs: b.dirs.clone(),
            indices: b.indices.clone(),
            optical_path: b.optical_path + to_far_wavefront(x, dir.normalize(), n, reference),
            start_optical_path: self.start,
            landing_error,
            iterations: 0,
            denser_reflections: b.denser_reflections,
            has_tir: b.has_tir,
            spreading: 1.0,
        })
    }
}

/// Limits of sequence enumeration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnumerationLimits {
    /// Maximum number of reflections inside a medium other than the ambient one.
    pub max_internal_reflections: usize,
    /// Maximum number of events in a sequence.
    pub max_events: usize,
}

impl Default for EnumerationLimits {
    fn default() -> Self {
        EnumerationLimits {
            max_internal_reflections: 1,
            max_events: 8,
        }
    }
}

/// Discover the surface sequences light from `emitter` can follow: probe rays are traced
/// forward (toward each of `probe_targets`) through the real, bounded scene, branching into
/// reflected and refracted children, and every node of the resulting ray trees is a candidate
/// sequence. They are returned as one tree of common beginnings ([`SequenceTree`]: sorted,
/// without duplicates); the exact solver decides which of them reach a given point.
pub fn discover_sequences(
    scene: &Scene,
    optics: &SceneOptics,
    emitter: Emitter,
    probe_targets: &[DVec3],
    limits: &EnumerationLimits,
) -> SequenceTree {
    let mut found = TreeBuilder::new();
    for &p in probe_targets {
        let (o, d) = match emitter {
            Emitter::Point { position } => (position, (p - position).normalize()),
            Emitter::Line { point, axis } => {
                let a = axis.normalize();
                let o = point + (p - point).dot(a) * a;
                (o, (p - o).normalize())
            }
            Emitter::PlaneWave {
                direction,
                reference_point,
            } => {
                let d = direction.normalize();
                (p - (p - reference_point).dot(d) * d, d)
            }
        };
        if !d.is_finite() {
            continue;
        }
        explore(
            scene,
            optics,
            o,
            d,
            optics.ambient_index,
            None,
            0,
            (TreeBuilder::ROOT, 0),
            limits,
            &mut found,
        );
    }
    found.finish()
}

#[allow(clippy::too_many_arguments)]
fn explore(
    scene: &Scene,
    optics: &SceneOptics,
    o: DVec3,
    d: DVec3,
    n: f64,
    from: Option<usize>,
    internal: usize,
    (node, depth): (usize, usize),
    limits: &EnumerationLimits,
    found: &mut TreeBuilder,
) {
    found.mark(node);
    if depth >= limits.max_events {
        return;
    }
    // Nearest surface ahead that stops or splits the ray.
    let mut best: Option<(f64, usize)> = None;
    for (j, surf) in scene.surfaces.iter().enumerate() {
        if Some(j) == from {
            continue;
        }
        // Any plane ahead (t > 0, no distance epsilon: a film of 1 pm is found); the surface
        // the ray leaves is skipped by name.
        if let Some(t) = surf.plane.intersect(o, d)
            && t > 0.0
            && best.is_none_or(|(bt, _)| t < bt)
        {
            let x = o + t * d;
            if surf.blocks(x) || surf.interacts(x) {
                best = Some((t, j));
            }
        }
    }
    let Some((t, j)) = best else { return };
    // On the plane itself (as the solver's `step_planes` puts it).
    let x = scene.surfaces[j].plane.project(o + t * d);
    let Some(so) = optics.surfaces[j] else { return }; // opaque: absorbed
    let normal = scene.surfaces[j].plane.normal;
    let hit = InterfaceHit {
        surface: j,
        point: x,
        normal,
        optics: so,
        coherence: scene.surfaces[j].coherence(),
    };
    let (n1, n2) = interaction::indices_for(so, normal, d, n);
    let is_internal = n != optics.ambient_index;
    if !is_internal || internal < limits.max_internal_reflections {
        let child = found.child(
            node,
            Event {
                surface: j,
                kind: EventKind::Reflect,
            },
        );
        let inc = usize::from(is_internal);
        explore(
            scene,
            optics,
            x,
            fresnel::reflect(d, normal),
            n,
            Some(j),
            internal + inc,
            (child, depth + 1),
            limits,
            found,
        );
    }
    if let SurfaceOptics::Dielectric { .. } | SurfaceOptics::Splitter { .. } = hit.optics
        && let Some(d_t) = fresnel::refract(d, normal, n1, n2)
    {
        let child = found.child(
            node,
            Event {
                surface: j,
                kind: EventKind::Refract,
            },
        );
        explore(
            scene,
            optics,
            x,
            d_t,
            n2,
            Some(j),
            internal,
            (child, depth + 1),
            limits,
            found,
        );
    }
}
