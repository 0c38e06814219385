//! Plane waves into the far field: the wavefront projection, the landing on a direction, and
//! the depth-first walk of a sequence tree that traces each shared beginning once.

use super::*;

/// The optical path from the exit point `x` (index `n`) to the far-field wavefront through
/// `reference` perpendicular to the unit far-field direction `d`: −n·d·(x − reference), in
/// double-double ([`projection`]: a reference 100 m away keeps the digits of the path).
///
/// `d` is the *target's* direction, the same for every path into it, not each path's own exit
/// direction: those agree only to the rounding of their events (~1e-16 per event, more over
/// many reflected orders), and a direction error δ moves the projection of a point ℓ from the
/// reference by δ·ℓ — 1e-16 m at ℓ = 1 m, a 1e-9 rad phase error that grows with the
/// distance to the reference.
pub(super) fn to_far_wavefront(x: DVec3, d: DVec3, n: f64, reference: DVec3) -> DoubleDouble {
    -projection(d, x, reference).mul_f64(n)
}

/// Whether a far-field path's exit direction `d_f` meets the target direction `dir`: the sine
/// of the angle between them (the landing error), or the mismatch.
///
/// `exit_normal` is the normal of the face the path leaves last (`None` for a path without
/// events). The exit direction must lie on the target's side of that face: d_f·N and dir·N
/// may not have opposite signs (in double-double, from the f64 vectors). Near grazing the
/// reflected and transmitted directions of a face are only 2 cos θ apart, inside the 1e-9
/// landing tolerance below cos θ = 5e-10, and without this test a reflected order was taken
/// for the transmitted wave and the reverse (`fringe fuzz --family airy --seed 2`: scene
/// 8945 traced T as the whole source intensity against 3.6e-94, scene 9003 R = 1 + 4.2e-10;
/// `tests/suite/truth_grazing_plane_waves.rs`).
pub(super) fn far_field_landing(
    d_f: DVec3,
    dir: DVec3,
    exit_normal: Option<DVec3>,
) -> Result<f64, PathError> {
    let err = d_f.cross(dir.normalize()).length();
    if err > 1e-9 || d_f.dot(dir) <= 0.0 {
        return Err(PathError::DirectionMismatch);
    }
    if let Some(m) = exit_normal {
        let side = |v: DVec3| DoubleDouble::dot(v, m).hi;
        if side(d_f) * side(dir) < 0.0 {
            return Err(PathError::DirectionMismatch);
        }
    }
    Ok(err)
}

/// A beginning of a sequence traced by [`FarFieldPaths`]: the records so far, and what the
/// checks of [`finish`] found on it.
#[derive(Clone)]
pub(super) struct Beginning {
    pub(super) sequence: Trail<Event>,
    pub(super) points: Trail<DVec3>,
    pub(super) dirs: Trail<DVec3>,
    pub(super) indices: Trail<f64>,
    pub(super) denser_reflections: usize,
    pub(super) has_tir: bool,
    /// Σ n_i L_i over the finite segments so far (double-double, summed in order as
    /// [`finish`] sums them).
    pub(super) optical_path: DoubleDouble,
    /// The first event outside its extent, if any.
    pub(super) out_of_extent: Option<PathError>,
    /// The first blocked finite segment, if any.
    pub(super) blocked: Option<PathError>,
    /// The normal and Snell's invariant after the last event (`Ray::normal_q2`).
    pub(super) q2: Option<(DVec3, super::stack::Invariant)>,
    /// Where the next segment starts and the surface it leaves: the last point and the last
    /// event's surface, except after a tunnel event, where it is the foot of the normal on the
    /// layer's far face and that face ([`tunnel_exit`]).
    pub(super) start: (DVec3, Option<usize>),
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
            start: (launch, None),
        };
        FarFieldPaths {
            scene,
            optics,
            stack: vec![root],
            start,
        }
    }

    /// The optical path at the launch point (m; [`SolvedPath::start_optical_path`]).
    pub(crate) fn start_optical_path(&self) -> DoubleDouble {
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

    /// The direction and index of segment `k` of the current beginning: from event k − 1 (the
    /// launch for k = 0) to event k, or out of the last event for k = [`Self::depth`].
    pub fn segment(&self, k: usize) -> (DVec3, f64) {
        let b = &self.stack[k];
        (*b.dirs.last().unwrap(), *b.indices.last().unwrap())
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
        let ((o, from), d, n) = (b.start, *b.dirs.last().unwrap(), *b.indices.last().unwrap());
        let step = step_planes(self.scene, self.optics, k, ev, (o, d, n), b.q2, from)?;
        let mut next = b.clone();
        next.start = if ev.kind == EventKind::Tunnel {
            let (exit, partner) = tunnel_exit(self.scene, self.optics, ev.surface, step.x, d)
                .ok_or(PathError::NoTunnel { event: k })?;
            (exit, Some(partner))
        } else {
            (step.x, Some(ev.surface))
        };
        next.q2 = Some(step.p2);
        next.denser_reflections += usize::from(step.denser);
        next.has_tir |= step.tir;
        // The finite segment k, from the last point to this event, as `finish` measures it:
        // along the ray's own direction (`path::event_segment_length`).
        let length = super::event_segment_length(o, step.x, d);
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
            let ends = [from, Some(ev.surface)];
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
        let ((x, from), d, n) = (b.start, *b.dirs.last().unwrap(), *b.indices.last().unwrap());
        let exit_normal = from.map(|i| self.scene.surfaces[i].plane.normal);
        let landing_error = far_field_landing(d, dir, exit_normal)?;
        if let Some(e) = b.out_of_extent.clone().or_else(|| b.blocked.clone()) {
            return Err(e);
        }
        // The last segment runs from the last point to infinity.
        let k = self.depth();
        let ends = [from, None];
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
            launch_normal_q2: None,
        })
    }
}
