//! A rigid motion (rotation, then translation) applied to a whole case file: every point
//! (a 3-vector under a key ending in `_m`) becomes R p + t, every direction (a 3-vector under
//! one of the direction keys of `cases/README.md`) becomes R d. Scalars, 2-vectors (rect and
//! aperture sizes, aperture centres in the screen's own axes) and Sellmeier coefficients are
//! unchanged. Physics is invariant under this motion, so a valid scene must keep its verdict.

use super::draws::Draws;
use glam::{DMat3, DVec3};
use serde_json::Value;

/// Keys whose 3-vector values are directions (normalized by the loader).
pub const DIRECTION_KEYS: [&str; 10] = [
    "normal",
    "axis",
    "hinge_axis",
    "direction",
    "reference",
    "u_axis",
    "v_axis",
    "surface_normal",
    "in_plane_axis",
    "looks_toward",
];

/// A proper rotation and a translation (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RigidMotion {
    pub rotation: DMat3,
    pub translation_m: DVec3,
}

impl RigidMotion {
    pub const IDENTITY: RigidMotion = RigidMotion {
        rotation: DMat3::IDENTITY,
        translation_m: DVec3::ZERO,
    };

    /// A random motion: with probability `p_rotate` a rotation by an angle uniform in
    /// [0°, 180°] about an axis from three uniform components (every orientation is reached);
    /// with probability `p_translate` a translation in a random direction of length
    /// log-uniform in [1 µm, `max_offset_m`]. Tags say which were drawn.
    pub fn draw(
        d: &mut Draws,
        p_rotate: f64,
        p_translate: f64,
        max_offset_m: f64,
        tags: &mut Vec<&'static str>,
    ) -> RigidMotion {
        let mut m = RigidMotion::IDENTITY;
        if d.flag(p_rotate) {
            let axis = DVec3::new(d.real(-1.0, 1.0), d.real(-1.0, 1.0), d.real(-1.0, 1.0));
            let angle = d.real(0.0, 180.0).to_radians();
            let axis = axis.try_normalize().unwrap_or(DVec3::Z);
            m.rotation = DMat3::from_axis_angle(axis, angle);
            if angle != 0.0 {
                tags.push("rotated");
            }
        }
        if d.flag(p_translate) {
            let dir = DVec3::new(d.real(-1.0, 1.0), d.real(-1.0, 1.0), d.real(-1.0, 1.0));
            let len = d.log(1e-6, max_offset_m);
            if let Some(u) = dir.try_normalize() {
                m.translation_m = u * len;
                tags.push("translated");
            }
        }
        m
    }

    pub fn point(&self, p: DVec3) -> DVec3 {
        self.rotation * p + self.translation_m
    }

    pub fn direction(&self, v: DVec3) -> DVec3 {
        self.rotation * v
    }

    /// Apply the motion to every point and direction of a case file (JSON).
    pub fn apply(&self, case: &mut Value) {
        self.walk(case, None);
    }

    fn walk(&self, v: &mut Value, key: Option<&str>) {
        match v {
            Value::Object(map) => {
                for (k, child) in map.iter_mut() {
                    self.walk(child, Some(k.as_str()));
                }
            }
            Value::Array(items) => {
                let triple = items.len() == 3 && items.iter().all(Value::is_number);
                match key {
                    Some(k) if triple && k.ends_with("_m") => {
                        *v = vec3_json(self.point(vec3(items)));
                    }
                    Some(k) if triple && DIRECTION_KEYS.contains(&k) => {
                        *v = vec3_json(self.direction(vec3(items)));
                    }
                    _ => {
                        for child in items.iter_mut() {
                            self.walk(child, None);
                        }
                    }
                }
            }
            _ => {}
        }
    }
}

fn vec3(items: &[Value]) -> DVec3 {
    let c = |k: usize| items[k].as_f64().unwrap_or(0.0);
    DVec3::new(c(0), c(1), c(2))
}

/// A 3-vector as JSON numbers; a component within 1e-300 of zero is written as 0.
pub(crate) fn vec3_json(v: DVec3) -> Value {
    let c = |x: f64| if x.abs() < 1e-300 { 0.0 } else { x };
    serde_json::json!([c(v.x), c(v.y), c(v.z)])
}
