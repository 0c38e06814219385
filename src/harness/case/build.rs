//! From a validated case to tracer objects: the scene (with a sweep's overrides applied), the
//! spectral samples, and the probe points with their targets.

use super::spec::*;
use crate::optics::material::{CoherenceRules, Dispersion, Medium};
use crate::scene::geometry::{Extent, Plane, Rect};
use crate::scene::source::{Emitter, Polarization, Source};
use crate::scene::{Scene, Surface, SurfaceKind};
use crate::trace::path::Target;
use glam::DVec3;
use std::collections::BTreeMap;

fn v(a: &Vec3) -> DVec3 {
    DVec3::from_array(*a)
}

/// What a sweep value changes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Plane-wave direction sin θ·axis − cos θ·normal: (θ, normal, axis).
    pub incidence: Option<(f64, DVec3, DVec3)>,
    /// The vacuum wavelength, m (monochrome light).
    pub wavelength_m: Option<f64>,
    /// (plate or wedge name, thickness in metres).
    pub thickness: Option<(String, f64)>,
}

/// A built scene and the map from case surface names to scene surface indices (a plate or a
/// wedge `p` becomes `p.top` and `p.bottom`; the bare name maps to both).
#[derive(Clone, Debug)]
pub struct Built {
    /// The scene.
    pub scene: Scene,
    /// Case surface name → scene surface indices (two for a plate or wedge).
    pub surfaces: BTreeMap<String, Vec<usize>>,
    /// The case's media by name.
    pub media: BTreeMap<String, Medium>,
}

impl Built {
    /// The scene index of a surface name (`plate.top` style names for plates and wedges).
    pub fn surface(&self, name: &str) -> Result<usize, String> {
        match self.surfaces.get(name).map(|v| v.as_slice()) {
            Some([i]) => Ok(*i),
            Some(_) => Err(format!(
                "surface {name:?} has two faces: use {name:?}.top or .bottom"
            )),
            None => Err(format!("no surface named {name:?}")),
        }
    }

    /// The medium the case names `name`.
    pub fn medium(&self, name: &str) -> Result<&Medium, String> {
        self.media
            .get(name)
            .ok_or_else(|| format!("no medium named {name:?}"))
    }
}

/// The medium of a case file's medium entry `m` called `name`.
pub fn medium(name: &str, m: &MediumSpec) -> Medium {
    let dispersion = match m {
        MediumSpec::Constant { n } => Dispersion::Constant { n: *n },
        MediumSpec::Cauchy {
            a,
            b_um2,
            c_um4,
            min_nm,
            max_nm,
        } => Dispersion::Cauchy {
            a: *a,
            b_um2: *b_um2,
            c_um4: *c_um4,
            min_um: min_nm * 1e-3,
            max_um: max_nm * 1e-3,
        },
        MediumSpec::Sellmeier {
            b,
            c_um2,
            min_nm,
            max_nm,
        } => Dispersion::Sellmeier {
            b: *b,
            c_um2: *c_um2,
            min_um: min_nm * 1e-3,
            max_um: max_nm * 1e-3,
        },
        MediumSpec::Bk7 {} => Dispersion::bk7(),
    };
    Medium {
        name: name.into(),
        dispersion,
    }
}

fn coherence(c: &Option<CoherenceSpec>) -> CoherenceRules {
    c.map(|c| CoherenceRules {
        reflected_keeps: c.reflected_keeps,
        refracted_keeps: c.refracted_keeps,
    })
    .unwrap_or_default()
}

fn extent(rect: &Option<RectSpec>, plane: &Plane) -> Extent {
    match rect {
        None => Extent::Unbounded,
        Some(r) => {
            let (u, v) = plane.axes(DVec3::from_array(r.u_axis));
            Extent::Rect {
                u,
                v,
                rect: Rect {
                    center_uv: [0.0, 0.0],
                    half_width_m: 0.5 * r.size_m[0],
                    half_height_m: 0.5 * r.size_m[1],
                },
            }
        }
    }
}

/// A planar surface of the case's kind `kind`, through `point_m` with `normal`, bounded by
/// `rect` if given.
fn planar(
    name: &str,
    point_m: &Vec3,
    normal: &Vec3,
    rect: &Option<RectSpec>,
    kind: SurfaceKind,
) -> Surface {
    let plane = Plane::new(v(point_m), v(normal));
    Surface {
        name: name.to_string(),
        plane,
        extent: extent(rect, &plane),
        kind,
    }
}

/// The plane-wave direction of an incidence override.
pub(crate) fn incidence_direction(theta: f64, normal: DVec3, axis: DVec3) -> DVec3 {
    let n = normal.normalize();
    let a = (axis - axis.dot(n) * n).normalize();
    (theta.sin() * a - theta.cos() * n).normalize()
}

/// Build the scene of a case with `ov` applied.
pub fn build_scene(spec: &SceneSpec, ov: &Overrides) -> Result<Built, String> {
    let media: BTreeMap<String, Medium> = spec
        .media
        .iter()
        .map(|(k, m)| (k.clone(), medium(k, m)))
        .collect();
    let get = |name: &str| {
        media
            .get(name)
            .cloned()
            .ok_or_else(|| format!("no medium named {name:?}"))
    };
    let mut scene = Scene::new(get(&spec.ambient)?);
    let mut names: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    let thickness = |name: &str, um: f64| match &ov.thickness {
        Some((n, t)) if n == name => *t,
        _ => um * 1e-6,
    };
    for s in &spec.surfaces {
        let first = scene.surfaces.len();
        match s {
            SurfaceSpec::Interface {
                name,
                point_m,
                normal,
                front,
                back,
                rect,
                coherence: c,
            } => {
                let kind = SurfaceKind::Interface {
                    front: get(front)?,
                    back: get(back)?,
                    coherence: coherence(c),
                };
                scene
                    .surfaces
                    .push(planar(name, point_m, normal, rect, kind));
            }
            SurfaceSpec::Plate {
                name,
                top_point_m,
                normal,
                thickness_um,
                medium,
                above,
                below,
                coherence: c,
            } => {
                let (t, b) = scene.add_plate(
                    name,
                    v(top_point_m),
                    v(normal),
                    thickness(name, *thickness_um),
                    get(above)?,
                    get(medium)?,
                    get(below)?,
                );
                for i in [t, b] {
                    if let SurfaceKind::Interface { coherence: cc, .. } =
                        &mut scene.surfaces[i].kind
                    {
                        *cc = coherence(c);
                    }
                }
            }
            SurfaceSpec::Wedge {
                name,
                top_point_m,
                normal,
                thickness_um,
                angle_deg,
                hinge_axis,
                medium,
                above,
                below,
            } => {
                scene.add_wedge(
                    name,
                    v(top_point_m),
                    v(normal),
                    thickness(name, *thickness_um),
                    angle_deg.to_radians(),
                    v(hinge_axis),
                    get(above)?,
                    get(medium)?,
                    get(below)?,
                );
            }
            SurfaceSpec::Mirror {
                name,
                point_m,
                normal,
                rect,
            } => {
                let kind = SurfaceKind::IdealMirror {
                    coherence: CoherenceRules::default(),
                };
                scene
                    .surfaces
                    .push(planar(name, point_m, normal, rect, kind));
            }
            SurfaceSpec::Splitter {
                name,
                point_m,
                normal,
                reflectance,
                rect,
            } => {
                let kind = SurfaceKind::Splitter {
                    reflectance: *reflectance,
                    medium: get(&spec.ambient)?,
                    coherence: CoherenceRules::default(),
                };
                scene
                    .surfaces
                    .push(planar(name, point_m, normal, rect, kind));
            }
            SurfaceSpec::Shield {
                name,
                point_m,
                normal,
                rect,
            } => {
                let kind = SurfaceKind::Opaque { apertures: vec![] };
                scene
                    .surfaces
                    .push(planar(name, point_m, normal, &Some(rect.clone()), kind));
            }
            SurfaceSpec::OpaqueScreen {
                name,
                point_m,
                normal,
                rect,
                u_axis,
                apertures,
            } => {
                let plane = Plane::new(v(point_m), v(normal));
                let (u, w) = plane.axes(v(u_axis));
                let ext = match extent(rect, &plane) {
                    Extent::Rect { rect, .. } => Extent::Rect { u, v: w, rect },
                    Extent::Unbounded => Extent::Unbounded,
                };
                scene.surfaces.push(Surface {
                    name: name.clone(),
                    plane,
                    extent: ext,
                    kind: SurfaceKind::Opaque {
                        apertures: apertures
                            .iter()
                            .map(|a| Rect {
                                center_uv: a.center_m,
                                half_width_m: 0.5 * a.size_m[0],
                                half_height_m: 0.5 * a.size_m[1],
                            })
                            .collect(),
                    },
                });
            }
        }
        let idx: Vec<usize> = (first..scene.surfaces.len()).collect();
        if idx.len() == 2 {
            names.insert(format!("{}.top", s.name()), vec![idx[0]]);
            names.insert(format!("{}.bottom", s.name()), vec![idx[1]]);
        }
        names.insert(s.name().to_string(), idx);
    }
    for src in &spec.sources {
        let emitter = match &src.emitter {
            EmitterSpec::Point { position_m } => Emitter::Point {
                position: v(position_m),
            },
            EmitterSpec::Line { point_m, axis } => Emitter::Line {
                point: v(point_m),
                axis: v(axis).normalize(),
            },
            EmitterSpec::PlaneWave {
                direction,
                reference_point_m,
            } => Emitter::PlaneWave {
                direction: match ov.incidence {
                    Some((theta, n, a)) => incidence_direction(theta, n, a),
                    None => v(direction).normalize(),
                },
                reference_point: v(reference_point_m),
            },
        };
        let polarization = match &src.polarization {
            PolarizationSpec::Linear {
                reference,
                angle_deg,
            } => Polarization::Linear {
                reference: v(reference).normalize(),
                angle_rad: angle_deg.to_radians(),
            },
            PolarizationSpec::Unpolarized {
                model: UnpolarizedModel::BasisFree,
                ..
            } => Polarization::Unpolarized,
            // The loader guarantees the reference of this model.
            PolarizationSpec::Unpolarized {
                model: UnpolarizedModel::PaperTwoChannel,
                reference,
            } => Polarization::UnpolarizedTwoChannel {
                reference: v(&reference.ok_or("paper_two_channel needs a reference")?).normalize(),
            },
        };
        scene.sources.push(Source {
            name: src.name.clone(),
            emitter,
            polarization,
            intensity: src.intensity,
            coherence_group: src.coherence_group,
            coherence_length_m: src.coherence_length_m.unwrap_or(f64::INFINITY),
        });
    }
    Ok(Built {
        scene,
        surfaces: names,
        media,
    })
}

/// Spectral samples (vacuum wavelength in metres, weight; weights sum to 1).
pub fn spectrum(light: &Light, ov: &Overrides) -> Vec<(f64, f64)> {
    if let Some(l) = ov.wavelength_m {
        return vec![(l, 1.0)];
    }
    match light {
        Light::Monochrome { wavelength_nm } => vec![(wavelength_nm * 1e-9, 1.0)],
        Light::Gaussian {
            center_nm,
            fwhm_nm,
            samples,
            sigmas,
        } => {
            // Gaussian in wavenumber k = 2π/λ: FWHM Δk = 2π Δλ/λ0², σ = Δk/(2√(2 ln 2)).
            let k0 = std::f64::consts::TAU / (center_nm * 1e-9);
            let dk = std::f64::consts::TAU * fwhm_nm * 1e-9 / (center_nm * 1e-9).powi(2);
            let sigma = dk / (2.0 * (2.0 * std::f64::consts::LN_2).sqrt());
            let n = *samples;
            let mut out: Vec<(f64, f64)> = (0..n)
                .map(|i| {
                    let x = -sigmas + 2.0 * sigmas * i as f64 / (n - 1) as f64;
                    let k = k0 + x * sigma;
                    let trapezoid = if i == 0 || i == n - 1 { 0.5 } else { 1.0 };
                    (std::f64::consts::TAU / k, trapezoid * (-0.5 * x * x).exp())
                })
                .collect();
            let total: f64 = out.iter().map(|(_, w)| w).sum();
            for (_, w) in &mut out {
                *w /= total;
            }
            out
        }
    }
}

/// One probe point: its coordinate, the overrides of a sweep, and what it observes.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbePoint {
    /// The point's coordinate in the profile (the probe's unit).
    pub coordinate: f64,
    /// What the sweep value changes in the scene.
    pub overrides: Overrides,
    /// Where it observes.
    pub observer: Observer,
}

/// The probe points of a case, in order.
pub fn probe_points(probe: &Probe) -> Vec<ProbePoint> {
    let lin = |from: f64, to: f64, n: usize, i: usize| {
        if n == 1 {
            from
        } else {
            from + (to - from) * i as f64 / (n - 1) as f64
        }
    };
    match probe {
        Probe::Line {
            from_m,
            to_m,
            count,
            origin_m,
            looks_toward,
        } => {
            let (a, b) = (v(from_m), v(to_m));
            let dir = (b - a).normalize_or_zero();
            let o = origin_m.map(|o| v(&o)).unwrap_or(a);
            (0..*count)
                .map(|i| {
                    let p = a.lerp(b, lin(0.0, 1.0, *count, i));
                    ProbePoint {
                        coordinate: (p - o).dot(dir),
                        overrides: Overrides::default(),
                        observer: Observer::Point {
                            position_m: p.to_array(),
                            looks_toward: *looks_toward,
                        },
                    }
                })
                .collect()
        }
        Probe::Sweep {
            parameter,
            from,
            to,
            count,
            observe,
        } => (0..*count)
            .map(|i| {
                let x = lin(*from, *to, *count, i);
                let mut ov = Overrides::default();
                match parameter {
                    SweepParameter::IncidenceAngleDeg {
                        surface_normal,
                        in_plane_axis,
                    } => ov.incidence = Some((x.to_radians(), v(surface_normal), v(in_plane_axis))),
                    SweepParameter::WavelengthNm {} => ov.wavelength_m = Some(x * 1e-9),
                    SweepParameter::ThicknessNm { surface } => {
                        ov.thickness = Some((surface.clone(), x * 1e-9))
                    }
                }
                ProbePoint {
                    coordinate: x,
                    overrides: ov,
                    observer: observe.clone(),
                }
            })
            .collect(),
        Probe::Single { observe } => vec![ProbePoint {
            coordinate: 0.0,
            overrides: Overrides::default(),
            observer: observe.clone(),
        }],
        Probe::Grid {
            center_m,
            u_axis,
            v_axis,
            size_m,
            pixels,
            looks_toward,
        } => {
            let g = GridGeometry::new(v(center_m), v(u_axis), v(v_axis), *size_m, *pixels);
            (0..pixels[0] * pixels[1])
                .map(|k| ProbePoint {
                    coordinate: k as f64,
                    overrides: Overrides::default(),
                    observer: Observer::Point {
                        position_m: g.position(k % pixels[0], k / pixels[0]).to_array(),
                        looks_toward: *looks_toward,
                    },
                })
                .collect()
        }
    }
}

/// The pixel centres of a [`Probe::Grid`] rectangle: `columns` × `rows` pixels, row 0 at the top.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridGeometry {
    /// Centre of pixel (0, 0), the top-left one (m).
    pub origin: DVec3,
    /// From one column to the next (m).
    pub step_col: DVec3,
    /// From one row to the next, downwards (m).
    pub step_row: DVec3,
    /// Pixel columns.
    pub columns: usize,
    /// Pixel rows.
    pub rows: usize,
}

impl GridGeometry {
    /// The rectangle of `size_m` = [width, height] centred on `center`, width along `u_axis`,
    /// height along `v_axis` made perpendicular to it, split into `pixels` = [columns, rows].
    pub fn new(
        center: DVec3,
        u_axis: DVec3,
        v_axis: DVec3,
        size_m: [f64; 2],
        pixels: [usize; 2],
    ) -> Self {
        let u = u_axis.normalize();
        let w = (v_axis - v_axis.dot(u) * u).normalize();
        let step_col = size_m[0] / pixels[0] as f64 * u;
        let step_row = -(size_m[1] / pixels[1] as f64) * w;
        GridGeometry {
            origin: center - 0.5 * size_m[0] * u
                + 0.5 * size_m[1] * w
                + 0.5 * (step_col + step_row),
            step_col,
            step_row,
            columns: pixels[0],
            rows: pixels[1],
        }
    }

    /// Centre of pixel (`col`, `row`) (m).
    pub fn position(&self, col: usize, row: usize) -> DVec3 {
        self.origin + col as f64 * self.step_col + row as f64 * self.step_row
    }
}

/// The first plane-wave source of a scene: (direction, reference point).
pub fn plane_wave(scene: &Scene) -> Option<(DVec3, DVec3)> {
    scene.sources.iter().find_map(|s| match s.emitter {
        Emitter::PlaneWave {
            direction,
            reference_point,
        } => Some((direction, reference_point)),
        _ => None,
    })
}

/// The tracer target of an observer at wavelength `lambda_m`; an error where no wave
/// propagates toward it (`propagating_target`).
pub fn target(observer: &Observer, built: &Built, lambda_m: f64) -> Result<Target, String> {
    propagating_target(observer, built, lambda_m)?
        .ok_or_else(|| "no transmitted wave: total internal reflection".to_string())
}

/// The tracer target of an observer at wavelength `lambda_m`, or `None` for a transmitted
/// far-field probe beyond the critical angle of the ambient → exit medium pair: no transmitted
/// plane wave propagates there, nothing arrives, and the power transmittance is exactly 0
/// (docs/PHYSICS.md §3a), which the runner records instead of refusing the sweep.
pub(crate) fn propagating_target(
    observer: &Observer,
    built: &Built,
    lambda_m: f64,
) -> Result<Option<Target>, String> {
    match observer {
        Observer::Point { position_m, .. } => Ok(Some(Target::Point(v(position_m)))),
        Observer::Direction {
            direction,
            reference_point_m,
        } => Ok(Some(Target::Direction {
            dir: v(direction).normalize(),
            reference: v(reference_point_m),
        })),
        Observer::FarField {
            side,
            surface_normal,
            exit_medium,
        } => {
            let (d, reference) =
                plane_wave(&built.scene).ok_or("a far_field observer needs a plane-wave source")?;
            let n = v(surface_normal).normalize();
            let dir = match side {
                FarSide::Reflected => Some(crate::optics::fresnel::reflect(d, n)),
                FarSide::Transmitted => {
                    let n1 = built
                        .scene
                        .ambient
                        .index(lambda_m)
                        .map_err(|e| e.to_string())?;
                    let n3 = match exit_medium {
                        Some(m) => built
                            .medium(m)?
                            .index(lambda_m)
                            .map_err(|e| e.to_string())?,
                        None => n1,
                    };
                    // Snell's law on the double-double normal wavevector, as the tracer
                    // refracts (`interaction::normal_wavevector_squares`): near the critical
                    // angle into a much thinner medium the f64 cos²θt is ~1e-9 off.
                    let (_, q2_t) =
                        crate::optics::interaction::normal_wavevector_squares(d, n, (n1, n3), None);
                    (q2_t.hi >= 0.0 && n1 != n3)
                        .then(|| {
                            crate::optics::interaction::snell_direction(
                                d,
                                n,
                                (n1, n3),
                                q2_t.sqrt().to_f64() / n3,
                            )
                        })
                        .or_else(|| (n1 == n3).then_some(d))
                }
            };
            Ok(dir.map(|dir| Target::Direction { dir, reference }))
        }
    }
}

/// Whether an observer records a ray arriving along `dir` (one-sided screens).
pub fn records(observer: &Observer, dir: DVec3) -> bool {
    match observer {
        Observer::Point {
            looks_toward: Some(l),
            ..
        } => dir.dot(v(l)) < 0.0,
        _ => true,
    }
}
