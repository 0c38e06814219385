//! Scenes built from planes: interfaces (unbounded or rectangular), plates, wedges, mirrors,
//! opaque screens with apertures, absorbing shields; plus sources. Lengths in metres.
//!
//! Every interface separates a *front* medium (the side its normal points to) from a *back*
//! medium, so the tracer always knows the indices on both sides of an event; the region the
//! sources sit in is the scene's `ambient` medium.

pub mod geometry;
pub mod source;

use crate::optics::interaction::{Layer, SurfaceOptics};
use crate::optics::material::{CoherenceRules, IndexError, Medium};
use crate::scene::geometry::{Extent, Plane, Rect};
use crate::scene::source::Source;
use glam::DVec3;

/// What a surface does to light.
#[derive(Clone, Debug, PartialEq)]
pub enum SurfaceKind {
    /// A dielectric interface (Fresnel reflection and refraction).
    Interface {
        /// The medium on the side the normal points to.
        front: Medium,
        /// The medium behind.
        back: Medium,
        /// What the children keep of the parent's coherence.
        coherence: CoherenceRules,
    },
    /// A perfectly conducting mirror (both sides).
    IdealMirror {
        /// What the reflected child keeps of the parent's coherence.
        coherence: CoherenceRules,
    },
    /// An ideal thin beam splitter (power reflectance R) inside `medium`.
    Splitter {
        /// Power reflectance R in [0, 1]; the transmittance is 1 − R.
        reflectance: f64,
        /// The medium on both sides.
        medium: Medium,
        /// What the children keep of the parent's coherence.
        coherence: CoherenceRules,
    },
    /// Opaque everywhere on its extent except inside the rectangular `apertures` (u, v coords).
    Opaque {
        /// The holes, in the plane's (u, v) coordinates.
        apertures: Vec<Rect>,
    },
}

/// A planar surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// The surface's name (a plate `p` has faces `p.top` and `p.bottom`).
    pub name: String,
    /// Its plane (point and unit normal, m).
    pub plane: Plane,
    /// Where on the plane it exists.
    pub extent: Extent,
    /// What it does to light.
    pub kind: SurfaceKind,
}

impl Surface {
    /// Whether the surface stops a ray at the (in-plane) point `x`.
    pub fn blocks(&self, x: DVec3) -> bool {
        if !self.extent.contains(&self.plane, x) {
            return false;
        }
        match &self.kind {
            SurfaceKind::Opaque { apertures } => {
                let (u, v) = match self.extent {
                    Extent::Rect { u, v, .. } => (u, v),
                    Extent::Unbounded => self.plane.axes(DVec3::X),
                };
                let uv = Extent::uv(u, v, &self.plane, x);
                !apertures.iter().any(|a| a.contains(uv))
            }
            _ => false,
        }
    }

    /// Whether light interacts (reflects/refracts) at `x`.
    pub(crate) fn interacts(&self, x: DVec3) -> bool {
        !matches!(self.kind, SurfaceKind::Opaque { .. }) && self.extent.contains(&self.plane, x)
    }

    /// Whether every point of the plane within `margin` (m) of the in-plane point `x` stops a
    /// ray ([`Surface::blocks`]) or deflects it (`Surface::interacts`): a verdict that holds
    /// for `x` computed to within `margin`.
    pub fn surely_stops(&self, x: DVec3, margin: f64) -> bool {
        // Inside (or, with `outside`, outside) a rectangle by more than the margin, in (u, v)
        // coordinates that move by at most |u| resp. |v| per metre of x.
        let beyond = |rect: &Rect, uv: [f64; 2], m: [f64; 2], outside: bool| {
            let du = (uv[0] - rect.center_uv[0]).abs();
            let dv = (uv[1] - rect.center_uv[1]).abs();
            if outside {
                du > rect.half_width_m + m[0] || dv > rect.half_height_m + m[1]
            } else {
                du <= rect.half_width_m - m[0] && dv <= rect.half_height_m - m[1]
            }
        };
        let (u, v) = match self.extent {
            Extent::Rect { u, v, .. } => (u, v),
            Extent::Unbounded => match &self.kind {
                SurfaceKind::Opaque { .. } => self.plane.axes(DVec3::X),
                _ => return true,
            },
        };
        let uv = Extent::uv(u, v, &self.plane, x);
        // |w| ≤ √3 max |w_i| bounds the stretch without a square root (u, v are unit in practice).
        let stretch = |w: DVec3| 1.7320508075688772 * w.abs().max_element();
        let m = [margin * stretch(u), margin * stretch(v)];
        if let Extent::Rect { rect, .. } = &self.extent
            && !beyond(rect, uv, m, false)
        {
            return false;
        }
        match &self.kind {
            SurfaceKind::Opaque { apertures } => apertures.iter().all(|a| beyond(a, uv, m, true)),
            _ => true,
        }
    }

    /// The surface's optics at vacuum wavelength `lambda_m`, `None` for opaque surfaces.
    pub fn optics(&self, lambda_m: f64) -> Result<Option<SurfaceOptics>, IndexError> {
        Ok(match &self.kind {
            SurfaceKind::Interface { front, back, .. } => Some(SurfaceOptics::Dielectric {
                n_front: front.index(lambda_m)?,
                n_back: back.index(lambda_m)?,
            }),
            SurfaceKind::IdealMirror { .. } => Some(SurfaceOptics::IdealMirror),
            SurfaceKind::Splitter {
                reflectance,
                medium,
                ..
            } => Some(SurfaceOptics::Splitter {
                reflectance: *reflectance,
                n: medium.index(lambda_m)?,
            }),
            SurfaceKind::Opaque { .. } => None,
        })
    }

    /// The coherence rules of the rays it creates (the default rules for an opaque surface).
    pub fn coherence(&self) -> CoherenceRules {
        match &self.kind {
            SurfaceKind::Interface { coherence, .. }
            | SurfaceKind::IdealMirror { coherence }
            | SurfaceKind::Splitter { coherence, .. } => *coherence,
            SurfaceKind::Opaque { .. } => CoherenceRules::default(),
        }
    }
}

/// A scene: an ambient medium, planar surfaces and sources.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The medium around the sources.
    pub ambient: Medium,
    /// The surfaces; a ray event names a surface by its index here.
    pub surfaces: Vec<Surface>,
    /// The sources.
    pub sources: Vec<Source>,
}

/// Indices of every surface at one wavelength (`None` for opaque ones) plus the ambient index.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneOptics {
    /// The vacuum wavelength, m.
    pub lambda_m: f64,
    /// The ambient medium's index there.
    pub ambient_index: f64,
    /// Each surface's optics there, in the order of [`Scene::surfaces`].
    pub surfaces: Vec<Option<SurfaceOptics>>,
    /// Per surface, the layer behind it for light arriving from its front (`[0]`) and from its
    /// back (`[1]`) ([`Scene::layer_behind`]), with the index beyond the layer at `lambda_m`:
    /// what frustrated total reflection couples to (docs/PHYSICS.md §5).
    pub layers: Vec<[Option<Layer>; 2]>,
}

impl Scene {
    /// An empty scene in `ambient`.
    pub fn new(ambient: Medium) -> Self {
        Scene {
            ambient,
            surfaces: Vec::new(),
            sources: Vec::new(),
        }
    }

    /// Evaluate every index at `lambda_m`.
    pub fn optics(&self, lambda_m: f64) -> Result<SceneOptics, IndexError> {
        Ok(SceneOptics {
            lambda_m,
            ambient_index: self.ambient.index(lambda_m)?,
            surfaces: self
                .surfaces
                .iter()
                .map(|s| s.optics(lambda_m))
                .collect::<Result<_, _>>()?,
            layers: (0..self.surfaces.len())
                .map(|i| {
                    let side = |from_front| {
                        self.layer_behind(i, from_front)
                            .map(|(partner, thickness_m, beyond)| {
                                Ok::<_, IndexError>(Layer {
                                    partner,
                                    thickness_m,
                                    n_beyond: beyond.index(lambda_m)?,
                                    lambda_m,
                                })
                            })
                            .transpose()
                    };
                    Ok([side(true)?, side(false)?])
                })
                .collect::<Result<_, IndexError>>()?,
        })
    }

    /// The layer behind interface `i` for light arriving from its front (`from_front`) or its
    /// back: the nearest surface on the far side that is parallel to it (normal bitwise ±), an
    /// interface whose near medium is the medium behind `i` (a plate's or film's other face),
    /// with no other surface entering the slab between them. Returns the partner's index, the
    /// layer's thickness d (m; exactly the difference of the heights for the two faces of a
    /// plate, `Plane::separation_from`) and the medium beyond the partner. `None` for
    /// anything else (an unbounded half-space behind, a wedge, a slab another surface cuts):
    /// there the tracer keeps the ray model's total reflection (docs/PHYSICS.md §5).
    pub fn layer_behind(&self, i: usize, from_front: bool) -> Option<(usize, f64, Medium)> {
        let face = &self.surfaces[i];
        let SurfaceKind::Interface { front, back, .. } = &face.kind else {
            return None;
        };
        let layer_medium = if from_front { back } else { front };
        let n = face.plane.normal;
        // Depth below face i along the direction into the layer (−n from the front).
        let into = if from_front { -1.0 } else { 1.0 };
        let depth_of_plane = |p: &Plane| -> Option<f64> {
            let offset = if p.anchor == face.plane.anchor {
                if p.normal == n {
                    p.height_m - face.plane.height_m
                } else if p.normal == -n {
                    -p.height_m - face.plane.height_m
                } else {
                    return None;
                }
            } else if p.normal == n || p.normal == -n {
                face.plane.signed_distance(p.point)
            } else {
                return None;
            };
            Some(into * offset)
        };
        // The nearest parallel surface strictly behind the face.
        let (j, d) = self
            .surfaces
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != i)
            .filter_map(|(j, s)| depth_of_plane(&s.plane).map(|d| (j, d)))
            .filter(|&(_, d)| d > 0.0)
            .min_by(|a, b| a.1.total_cmp(&b.1))?;
        let partner = &self.surfaces[j];
        let SurfaceKind::Interface {
            front: pf,
            back: pb,
            ..
        } = &partner.kind
        else {
            return None;
        };
        if !matches!(partner.extent, Extent::Unbounded) {
            return None;
        }
        // The partner's side facing face i: its front if its normal points back toward i.
        let faces_i = if from_front {
            partner.plane.normal == n
        } else {
            partner.plane.normal == -n
        };
        let (near, beyond) = if faces_i { (pf, pb) } else { (pb, pf) };
        if near != layer_medium {
            return None;
        }
        // No other surface may enter the slab 0 < depth < d (conservatively: any part of it).
        let depth = |x: DVec3| into * face.plane.signed_distance(x);
        let enters = |s: &Surface| match s.extent {
            Extent::Unbounded => depth_of_plane(&s.plane).is_none_or(|e| e > 0.0 && e < d),
            Extent::Rect { u, v, rect } => {
                let c = s.plane.point + rect.center_uv[0] * u + rect.center_uv[1] * v;
                let corners = [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)].map(|(a, b)| {
                    depth(c + a * rect.half_width_m * u + b * rect.half_height_m * v)
                });
                let lo = corners.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = corners.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                lo < d && hi > 0.0
            }
        };
        if self
            .surfaces
            .iter()
            .enumerate()
            .any(|(k, s)| k != i && k != j && enters(s))
        {
            return None;
        }
        Some((j, d, beyond.clone()))
    }

    /// Add an unbounded interface; returns its index.
    pub fn add_interface(
        &mut self,
        name: &str,
        plane: Plane,
        front: Medium,
        back: Medium,
    ) -> usize {
        self.surfaces.push(Surface {
            name: name.into(),
            plane,
            extent: Extent::Unbounded,
            kind: SurfaceKind::Interface {
                front,
                back,
                coherence: CoherenceRules::default(),
            },
        });
        self.surfaces.len() - 1
    }

    /// A plane-parallel plate: top face through `top_point` with outward normal `normal`,
    /// thickness `thickness_m`, `medium` inside, `above` over it and `below` under it. The
    /// bottom face is held as the top point and −thickness along the normal
    /// ([`Plane::offset`]), so no coordinate difference enters the thickness. Returns the
    /// indices of (top, bottom).
    #[allow(clippy::too_many_arguments)]
    pub fn add_plate(
        &mut self,
        name: &str,
        top_point: DVec3,
        normal: DVec3,
        thickness_m: f64,
        above: Medium,
        medium: Medium,
        below: Medium,
    ) -> (usize, usize) {
        let n = normal.normalize();
        let top = self.add_interface(
            &format!("{name}.top"),
            Plane::new(top_point, n),
            above,
            medium.clone(),
        );
        // Held as top point + normal + thickness (docs: [`Plane::offset`]).
        let bottom = self.add_interface(
            &format!("{name}.bottom"),
            Plane::offset(top_point, n, -thickness_m),
            medium,
            below,
        );
        (top, bottom)
    }

    /// A wedge: the top face as in [`Scene::add_plate`], the bottom face through the point
    /// `thickness_m` below `top_point`, tilted by `angle_rad` about the in-plane `hinge_axis`.
    #[allow(clippy::too_many_arguments)]
    pub fn add_wedge(
        &mut self,
        name: &str,
        top_point: DVec3,
        normal: DVec3,
        thickness_m: f64,
        angle_rad: f64,
        hinge_axis: DVec3,
        above: Medium,
        medium: Medium,
        below: Medium,
    ) -> (usize, usize) {
        let n = normal.normalize();
        let axis = (hinge_axis - hinge_axis.dot(n) * n).normalize();
        let tilted = glam::DQuat::from_axis_angle(axis, angle_rad) * n;
        let top = self.add_interface(
            &format!("{name}.top"),
            Plane::new(top_point, n),
            above,
            medium.clone(),
        );
        let bottom = self.add_interface(
            &format!("{name}.bottom"),
            Plane::new(top_point - thickness_m * n, tilted),
            medium,
            below,
        );
        (top, bottom)
    }
}
