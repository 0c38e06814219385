//! Planes and the bounded pieces of planes that scenes are built from; ray–plane intersection.
//!
//! Lengths in metres. All scene surfaces are planar (the paper's scenes and the classical
//! interferometers are), which lets the path solver unfold reflections exactly.

use glam::DVec3;

/// An oriented plane through `point` with unit `normal` (the normal points to the *front*).
///
/// The plane is held exactly as the points x with (x − `anchor`)·normal = `height_m`; `point`
/// is a point of it rounded to f64 (`anchor + height_m·normal`). A plate's bottom face is its
/// top point as anchor and −thickness as height ([`Plane::offset`]), so its distance from the
/// top face is the thickness itself, not the difference of two rounded points (which at 1000 m
/// from the origin is off by ~1e-13 m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point of the plane (m), rounded to f64: `anchor + height_m·normal`.
    pub point: DVec3,
    /// The unit normal; its side is the plane's front.
    pub normal: DVec3,
    /// The point the plane's height is measured from (m).
    pub anchor: DVec3,
    /// Signed distance of the plane from `anchor` along `normal` (m).
    pub height_m: f64,
}

impl Plane {
    /// The plane through `point` with normal `normal` (normalized here).
    pub fn new(point: DVec3, normal: DVec3) -> Self {
        Plane {
            point,
            normal: normal.normalize(),
            anchor: point,
            height_m: 0.0,
        }
    }

    /// The plane at signed distance `height_m` from `anchor` along the unit `normal`, held as
    /// anchor and height (a plate's bottom face: top point and −thickness).
    pub fn offset(anchor: DVec3, normal: DVec3, height_m: f64) -> Self {
        let normal = normal.normalize();
        Plane {
            point: anchor + height_m * normal,
            normal,
            anchor,
            height_m,
        }
    }

    /// Signed distance of `x` from the plane (positive on the front side), formed as
    /// (x − anchor)·normal − height: near a plate, x − anchor is small and exact.
    pub(crate) fn signed_distance(&self, x: DVec3) -> f64 {
        (x - self.anchor).dot(self.normal) - self.height_m
    }

    /// [`Plane::signed_distance`] without rounding before the end: exact coordinate differences
    /// x − anchor, double-double products and sum, so the ~1e-16 m by which an f64 point misses
    /// a tilted plane is resolved even 1 cm from the anchor (where the f64 dot product rounds at
    /// ~1e-18 m).
    pub(crate) fn signed_distance_precise(&self, x: DVec3) -> f64 {
        self.signed_distance_dd(x).to_f64()
    }

    /// [`Plane::signed_distance_precise`] before its final rounding, in double-double: two
    /// planes held from one anchor along one normal (a plate's faces) keep their exact height
    /// difference in the difference of their distances from any point.
    pub(crate) fn signed_distance_dd(
        &self,
        x: DVec3,
    ) -> crate::optics::double_double::DoubleDouble {
        use crate::optics::double_double::{DoubleDouble, two_diff};
        let d = [
            two_diff(x.x, self.anchor.x),
            two_diff(x.y, self.anchor.y),
            two_diff(x.z, self.anchor.z),
        ];
        let n = self.normal;
        let dot = d[0].mul_f64(n.x) + d[1].mul_f64(n.y) + d[2].mul_f64(n.z);
        // The f64 normal is unit only to ~1e-16: the distance along N/|N| is dot/|N|. A plate
        // 1 m thick in a rotated frame otherwise held its far face ~1e-16 m off, 1e-8 rad of
        // its round trip at 200 nm (issue #12, `fuzz_airy_s1_159` rotated).
        let norm2 = DoubleDouble::dot(n, n);
        let dot = if norm2.hi == 1.0 && norm2.lo == 0.0 {
            dot
        } else {
            dot / norm2.sqrt()
        };
        dot - DoubleDouble::from(self.height_m)
    }

    /// The first-order change of an optical path when its point `x` on this plane, rounded off
    /// it by ε = `Plane::signed_distance_precise`, is moved back onto it along the normal (m of
    /// optical path): with the path arriving along `u_in` in index `n_in` and leaving along
    /// `u_out` in index `n_out` (any lengths: normalised here), the path n_in|x − a| +
    /// n_out|b − x| (or a far-field projection) changes by ε N·(n_out û_out − n_in û_in).
    /// An f64 point D from the origin lies only within ~ulp(D) of a tilted plane, a first-order
    /// path error; this restores the path of the plane as held (anchor + height), leaving the
    /// tangential rounding, second order by Fermat. Zero (exactly) for a point on the plane.
    #[inline]
    pub fn off_plane_path_correction(
        &self,
        x: DVec3,
        (n_in, u_in): (f64, DVec3),
        (n_out, u_out): (f64, DVec3),
    ) -> f64 {
        let eps = self.signed_distance_precise(x);
        if eps == 0.0 {
            return 0.0;
        }
        eps * self
            .normal
            .dot(n_out * u_out.normalize() - n_in * u_in.normalize())
    }

    /// The distance from `other` to this plane along this plane's normal, when both are held
    /// from the same anchor with the same or the opposite normal (the faces of one plate):
    /// exactly the difference of their heights, no coordinates differenced.
    pub(crate) fn separation_from(&self, other: &Plane) -> Option<f64> {
        if self.anchor != other.anchor {
            return None;
        }
        if self.normal == other.normal {
            Some(self.height_m - other.height_m)
        } else if self.normal == -other.normal {
            Some(self.height_m + other.height_m)
        } else {
            None
        }
    }

    /// Ray parameter t (distance along the unit `dir`) where the ray from `origin` meets the
    /// plane, or `None` if it runs parallel to it.
    pub(crate) fn intersect(&self, origin: DVec3, dir: DVec3) -> Option<f64> {
        let denom = dir.dot(self.normal);
        if denom == 0.0 {
            return None;
        }
        Some(-self.signed_distance(origin) / denom)
    }

    /// The point of the plane nearest `x` (the orthogonal projection x − s·normal, s the signed
    /// distance). In f64 the result is off the plane by the rounding of `x − point` only.
    #[inline(always)]
    pub(crate) fn project(&self, x: DVec3) -> DVec3 {
        x - self.signed_distance(x) * self.normal
    }

    /// Mirror image of a point in the plane (the image method).
    pub fn mirror_point(&self, x: DVec3) -> DVec3 {
        x - 2.0 * self.signed_distance(x) * self.normal
    }

    /// Two unit in-plane axes (u, v) with u × v = normal; `u_hint` is projected into the plane.
    pub fn axes(&self, u_hint: DVec3) -> (DVec3, DVec3) {
        let u = u_hint - u_hint.dot(self.normal) * self.normal;
        let u = if u.length() > 1e-12 {
            u.normalize()
        } else {
            self.normal.any_orthonormal_vector()
        };
        (u, self.normal.cross(u))
    }
}

/// An axis-aligned rectangle in a plane's (u, v) coordinates, centred at `center_uv` (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rect {
    /// The centre (u, v), m.
    pub center_uv: [f64; 2],
    /// Half the width along u, m.
    pub half_width_m: f64,
    /// Half the height along v, m.
    pub half_height_m: f64,
}

impl Rect {
    /// Whether (u, v) (m) is inside or on the boundary.
    pub fn contains(&self, uv: [f64; 2]) -> bool {
        (uv[0] - self.center_uv[0]).abs() <= self.half_width_m
            && (uv[1] - self.center_uv[1]).abs() <= self.half_height_m
    }
}

/// The extent of a surface within its plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Extent {
    /// The whole plane.
    Unbounded,
    /// A rectangle in the plane's (u, v) axes.
    Rect {
        /// Unit u axis (in the plane).
        u: DVec3,
        /// Unit v axis (in the plane, normal × u).
        v: DVec3,
        /// The rectangle in (u, v).
        rect: Rect,
    },
}

impl Extent {
    /// In-plane coordinates of `x` relative to the plane point.
    pub(crate) fn uv(u: DVec3, v: DVec3, plane: &Plane, x: DVec3) -> [f64; 2] {
        let d = x - plane.point;
        [d.dot(u), d.dot(v)]
    }

    /// Whether the point `x` (on the plane) lies on the surface.
    pub fn contains(&self, plane: &Plane, x: DVec3) -> bool {
        match self {
            Extent::Unbounded => true,
            Extent::Rect { u, v, rect } => rect.contains(Self::uv(*u, *v, plane, x)),
        }
    }
}

/// The angle between two vectors, atan2(|a×b|, a·b): accurate for small angles, where
/// acos(a·b) loses half the digits (for 1 mrad, acos errs by ~1e-13 rad).
pub(crate) fn angle_between(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}
