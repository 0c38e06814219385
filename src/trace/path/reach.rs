//! Reachability and obstruction: whether a sequence can reach its target at all, where a
//! segment crosses a plane, and whether a surface or its extent stops it.

use super::*;

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
    // A tunnel jumps across its layer: left to the solver (which names why it fails).
    if seq.iter().any(|e| e.kind == EventKind::Tunnel) {
        return false;
    }
    match seq.first() {
        None => straight_segment_stopped(scene, source, p),
        Some(first) => stack_cannot_reach(scene, seq, source, p, first.surface),
    }
}

/// An upper bound of |v| without a square root (|v| ≤ √3 max |v_i|).
pub(super) fn length_bound(v: DVec3) -> f64 {
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

/// The distance (m, double-double) from `x` to the line through `point` along the unit `axis`:
/// |v − (v·a) a| with v = x − point from exact coordinate differences.
pub(crate) fn distance_to_line(point: DVec3, axis: DVec3, x: DVec3) -> DoubleDouble {
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
pub(super) fn out_of_extent(scene: &Scene, k: usize, ev: Event, x: DVec3) -> Option<PathError> {
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
pub(super) fn segment_blocked(
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
