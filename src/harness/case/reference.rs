//! Evaluating a case's closed-form references at a probe point. Each reference reads its
//! parameters (positions, indices, thicknesses, polarization) from the built scene, so the
//! scene and its reference cannot disagree; each says clearly when a scene does not fit it.

use super::build::{Built, plane_wave};
use super::spec::{BeamSpec, FarSide, Observer, ReferenceModel};
use crate::harness::analytic::plate::{FTIR_NEGLIGIBLE, Incidence, Pol};
use crate::harness::analytic::{self, michelson};
use crate::optics::fresnel;
use crate::optics::material::Medium;
use crate::optics::observable::{Observable, Returns, power_factor};
use crate::scene::SurfaceKind;
use crate::scene::source::{Channel, Emitter, Source};
use crate::trace::path::{Event, EventKind, Target};
use glam::DVec3;
use num_complex::Complex64;

/// How a reference is compared with the trace.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MetricKind {
    /// Intensity (or R, T) at every probe point, weighted over the spectrum; deviations are
    /// relative to the largest reference value of the profile.
    Intensity,
    /// Fringe spacing at the probe centre (m), from the traced optical-path difference.
    FringeSpacing,
    /// Retardance arg(E_p) − arg(E_s) (rad) at every probe point.
    Retardance,
    /// Two-beam fringe visibility at every probe point.
    Visibility,
}

/// What a reference model's values are (intensity, fringe spacing, retardance, visibility).
pub fn kind(model: &ReferenceModel) -> MetricKind {
    match model {
        ReferenceModel::YoungSpacing { .. } | ReferenceModel::WedgeSpacing { .. } => {
            MetricKind::FringeSpacing
        }
        ReferenceModel::RhombRetardance { .. } => MetricKind::Retardance,
        ReferenceModel::LloydVisibility {} => MetricKind::Visibility,
        _ => MetricKind::Intensity,
    }
}

/// What an intensity-kind closed form returns (`None` for spacing, retardance and visibility
/// references, which are not intensities).
pub fn returns(model: &ReferenceModel) -> Option<Returns> {
    Some(match model {
        ReferenceModel::Airy { .. }
        | ReferenceModel::CoherenceGaussian { .. }
        | ReferenceModel::CoherenceP9 { .. } => Returns::Power,
        ReferenceModel::PlaneWaveBeams { .. } => Returns::AsProbe,
        ReferenceModel::YoungExact {}
        | ReferenceModel::YoungParaxial {}
        | ReferenceModel::Lloyd {}
        | ReferenceModel::TwoBeamPlate { .. }
        | ReferenceModel::Wedge { .. }
        | ReferenceModel::Michelson { .. }
        | ReferenceModel::IncoherentSum {} => Returns::FieldIntensity,
        ReferenceModel::YoungSpacing { .. }
        | ReferenceModel::WedgeSpacing { .. }
        | ReferenceModel::RhombRetardance { .. }
        | ReferenceModel::LloydVisibility {} => return None,
    })
}

/// What a probe point observing through `observer` measures (docs/PHYSICS.md §3a): R or T for the
/// far field of a plane wave at a surface, |E|² everywhere else.
pub fn measured(observer: &Observer) -> Observable {
    match observer {
        Observer::FarField {
            side: FarSide::Reflected,
            ..
        } => Observable::Reflectance,
        Observer::FarField {
            side: FarSide::Transmitted,
            ..
        } => Observable::Transmittance,
        Observer::Point { .. } | Observer::Direction { .. } => Observable::FieldIntensity,
    }
}

/// The factor turning the traced far-field |E|² into the observable `observer` measures at
/// vacuum wavelength `lambda_m` ([`crate::optics::observable::power_factor`]; 1 for |E|² and for R).
pub(crate) fn observable_factor(
    observer: &Observer,
    built: &Built,
    target: &Target,
    lambda_m: f64,
) -> Result<f64, String> {
    let Observer::FarField {
        side: FarSide::Transmitted,
        surface_normal,
        exit_medium,
    } = observer
    else {
        return Ok(1.0);
    };
    let Target::Direction { dir, .. } = target else {
        return Ok(1.0);
    };
    let (d_in, _) = plane_wave(&built.scene).ok_or("a far_field observer needs a plane wave")?;
    let n_in = built
        .scene
        .ambient
        .index(lambda_m)
        .map_err(|e| e.to_string())?;
    let n_out = match exit_medium {
        Some(m) => index(built, m, lambda_m)?,
        None => n_in,
    };
    let normal = DVec3::from_array(*surface_normal);
    // (n_out cos θ_out)/(n_in cos θ_in) from the double-double normal wavevectors q² = (n cos θ)²
    // of the incident direction (Snell: q_out² = q_in² + n_out² − n_in²), as the tracer refracts
    // (`interaction::normal_wavevector_squares`): near grazing in a rotated frame an f64
    // d·N is a few u off absolutely, u/cos θ relatively (6.5e-8 of T at 89.9999999°,
    // 6 % at 89.9999999999999°; docs/PHYSICS.md §3a).
    let (q2_in, q2_out) =
        crate::optics::interaction::normal_wavevector_squares(d_in, normal, (n_in, n_out), None);
    if q2_in.hi > 0.0 && q2_out.hi >= 0.0 {
        return Ok((q2_out / q2_in).sqrt().to_f64());
    }
    Ok(power_factor(n_in, d_in, n_out, *dir, normal))
}

/// The relative representation sensitivity of [`observable_factor`]
/// ([`crate::harness::conditioning::power_factor_sensitivity`], docs/PHYSICS.md §8): 0 except
/// for a transmitted far-field probe of a plane wave.
pub(crate) fn observable_factor_representation(
    observer: &Observer,
    built: &Built,
    lambda_m: f64,
) -> f64 {
    let Observer::FarField {
        side: FarSide::Transmitted,
        surface_normal,
        exit_medium,
    } = observer
    else {
        return 0.0;
    };
    let (Some((d_in, _)), Ok(n_in)) = (plane_wave(&built.scene), ambient_index(built, lambda_m))
    else {
        return 0.0;
    };
    let n_out = match exit_medium {
        Some(m) => index(built, m, lambda_m).unwrap_or(n_in),
        None => n_in,
    };
    crate::harness::conditioning::power_factor_sensitivity(
        d_in,
        DVec3::from_array(*surface_normal),
        n_in,
        n_out,
    )
}

/// Short name of a reference model for tables (the serde tag).
pub fn name(model: &ReferenceModel) -> String {
    serde_json::to_value(model)
        .ok()
        .and_then(|v| v.as_object().and_then(|o| o.keys().next().cloned()))
        .unwrap_or_else(|| "reference".into())
}

fn index(built: &Built, medium: &str, lambda_m: f64) -> Result<f64, String> {
    built
        .medium(medium)?
        .index(lambda_m)
        .map_err(|e| e.to_string())
}

/// The index of the ambient medium (where sources and screen points sit) at `lambda_m`.
pub(crate) fn ambient_index(built: &Built, lambda_m: f64) -> Result<f64, String> {
    built
        .scene
        .ambient
        .index(lambda_m)
        .map_err(|e| e.to_string())
}

fn line_sources(built: &Built) -> Result<Vec<(&Source, DVec3, DVec3)>, String> {
    let v: Vec<_> = built
        .scene
        .sources
        .iter()
        .filter_map(|s| match s.emitter {
            Emitter::Line { point, axis } => Some((s, point, axis)),
            _ => None,
        })
        .collect();
    if v.is_empty() {
        return Err("this reference needs line sources".into());
    }
    Ok(v)
}

/// The thickness of a plate from its two faces: the difference of their heights when both are
/// held from the top point ([`crate::scene::geometry::Plane::offset`], exact), else from their points.
fn plate_thickness(scene: &crate::scene::Scene, top: usize, bottom: usize) -> f64 {
    let (t, b) = (&scene.surfaces[top].plane, &scene.surfaces[bottom].plane);
    t.separation_from(b)
        .unwrap_or_else(|| (t.point - b.point).dot(t.normal))
}

/// The source's and the probe's heights above `top` and their lateral distance along it, from
/// the f64 coordinates without rounding (docs/PHYSICS.md §5, "Plate, two beams"): exact
/// coordinate differences, the unit normal N/|N| of the held f64 normal (as
/// [`crate::scene::geometry::Plane::signed_distance_precise`] measures) and products and sums
/// in double-double, the lateral distance as the length of the part of p − s perpendicular to
/// N/|N| (no cancellation when x is small).
fn held_points(
    top: &crate::scene::geometry::Plane,
    s: DVec3,
    p: DVec3,
) -> analytic::plate::HeldPoints {
    use analytic::precise;
    let n = precise::unit(top.normal);
    let height = |x: DVec3| precise::dot2(&precise::diff(x, top.anchor), &n) - top.height_m;
    let v = precise::diff(p, s);
    let along = precise::dot2(&v, &n);
    let lateral = [0, 1, 2].map(|i| v[i] - along * n[i]);
    analytic::plate::HeldPoints {
        x_m: precise::length(&lateral),
        h_src_m: height(s),
        h_obs_m: height(p),
    }
}

/// Fraction of a source's intensity polarized along `axis` (1, 0 or 1/2), if its channels are
/// linear and along and perpendicular to `axis`; `None` for basis-free unpolarized light
/// (docs/PHYSICS.md §3), which has no such split.
fn axis_fraction(src: &Source, axis: DVec3) -> Result<Option<f64>, String> {
    if src.polarization == crate::scene::source::Polarization::Unpolarized {
        return Ok(None);
    }
    let chans = src.channels();
    let mut along = 0.0;
    for ch in &chans {
        let crate::scene::source::ChannelField::Linear {
            reference,
            angle_rad,
        } = ch.field
        else {
            unreachable!("only basis-free unpolarized light has dipole channels")
        };
        let r = reference.normalize();
        if r.cross(axis).length() > 1e-12 {
            return Err(format!(
                "source {:?}: its polarization reference must be the slit axis",
                src.name
            ));
        }
        let c = angle_rad.cos();
        if (c.abs() - 1.0).abs() > 1e-12 && c.abs() > 1e-12 {
            return Err(format!(
                "source {:?}: polarization must be along or across the slit axis",
                src.name
            ));
        }
        along += ch.intensity * c * c;
    }
    Ok(Some(along / src.intensity))
}

fn point(target: &Target) -> Result<DVec3, String> {
    match target {
        Target::Point(p) => Ok(*p),
        Target::Direction { .. } => {
            Err("this reference needs screen points, not a far-field direction".into())
        }
    }
}

/// The reference's value at one probe point and wavelength (Intensity, Retardance and
/// Visibility kinds; spacing references are evaluated in `run`).
pub fn value(
    model: &ReferenceModel,
    built: &Built,
    target: &Target,
    lambda_m: f64,
    spreading: bool,
) -> Result<f64, String> {
    let scene = &built.scene;
    match model {
        ReferenceModel::YoungExact {} => {
            let ls = line_sources(built)?;
            if ls.len() != 2 || ls[0].0.intensity != ls[1].0.intensity {
                return Err("young_exact needs exactly two line sources of equal intensity".into());
            }
            let f = axis_fraction(ls[0].0, ls[0].2)?;
            if axis_fraction(ls[1].0, ls[1].2)? != f {
                return Err("young_exact needs two line sources of equal polarization".into());
            }
            let p = point(target)?;
            let n = ambient_index(built, lambda_m)?;
            let (s1, s2, axis) = (ls[0].1, ls[1].1, ls[0].2);
            Ok(ls[0].0.intensity
                * match f {
                    Some(f) => analytic::young::exact_line_sources(s1, s2, axis, p, lambda_m, n, f),
                    None => {
                        analytic::young::exact_line_sources_basis_free(s1, s2, axis, p, lambda_m, n)
                    }
                })
        }
        ReferenceModel::YoungParaxial {} => {
            let ls = line_sources(built)?;
            if ls.len() != 2 {
                return Err("young_paraxial needs exactly two line sources".into());
            }
            let (s1, s2, axis) = (ls[0].1, ls[1].1, ls[0].2);
            let sep = s1 - s2;
            let d = sep.length();
            let mid = 0.5 * (s1 + s2);
            let p = point(target)?;
            let across = sep / d;
            let forward = axis.cross(across).normalize();
            let rel = p - mid;
            let n = ambient_index(built, lambda_m)?;
            Ok(ls[0].0.intensity
                * analytic::young::paraxial(
                    d,
                    rel.dot(forward).abs(),
                    rel.dot(across),
                    lambda_m,
                    n,
                ))
        }
        ReferenceModel::Lloyd {} | ReferenceModel::LloydVisibility {} => {
            let ls = line_sources(built)?;
            let (src, s, axis) = ls[0];
            if axis_fraction(src, axis)? != Some(1.0) {
                return Err(
                    "lloyd needs a line source polarized along its axis (s polarization)".into(),
                );
            }
            let mirror = scene
                .surfaces
                .first()
                .ok_or("lloyd needs the mirror as the first surface")?;
            let SurfaceKind::Interface { front, back, .. } = &mirror.kind else {
                return Err("lloyd's first surface must be a dielectric interface".into());
            };
            let h = mirror.plane.signed_distance(s);
            let (n1, n2) = if h > 0.0 {
                (front, back)
            } else {
                (back, front)
            };
            let (n1, n2) = (
                n1.index(lambda_m).map_err(|e| e.to_string())?,
                n2.index(lambda_m).map_err(|e| e.to_string())?,
            );
            let p = point(target)?;
            let l = analytic::lloyd::Lloyd {
                n1,
                n2,
                source: s,
                axis,
                mirror_point: mirror.plane.point,
                normal: mirror.plane.normal,
            };
            Ok(match model {
                ReferenceModel::Lloyd {} => src.intensity * l.intensity(p, lambda_m),
                _ => l.visibility(p),
            })
        }
        ReferenceModel::TwoBeamPlate { plate } => {
            let (top, bottom, [above, glass, below]) = layer_media(built, plate)?;
            let src = scene
                .sources
                .iter()
                .find(|s| matches!(s.emitter, Emitter::Point { .. }))
                .ok_or("two_beam_plate needs a point source")?;
            let Emitter::Point { position: s } = src.emitter else {
                unreachable!()
            };
            let n1 = above.index(lambda_m).map_err(|e| e.to_string())?;
            if below.index(lambda_m).map_err(|e| e.to_string())? != n1 {
                return Err(
                    "two_beam_plate needs the same medium above and below the plate".into(),
                );
            }
            let p = point(target)?;
            let plane = &scene.surfaces[top].plane;
            let nrm = plane.normal;
            let mut horiz = p - s;
            horiz -= horiz.dot(nrm) * nrm;
            // Basis-free light needs nothing more; the paper's two channels must be s and p.
            let basis_free = match src.polarization {
                crate::scene::source::Polarization::Unpolarized => true,
                crate::scene::source::Polarization::UnpolarizedTwoChannel { reference } => {
                    // Off the plane of incidence by an angle ε (a micrometre scene translated
                    // hundreds of metres holds p − s to ~1e-9 of itself), the channels mix s
                    // and p by ε; s and p fields are orthogonal at the probe, so the sum over
                    // the channels moves by O(ε²) of the profile: ≤ 2ε² = 8e-14 at ε = 2e-7,
                    // below the gate's least tolerance (1e-12, `fuzz::DERIVED_FLOOR`). The
                    // reference refused 1e-9 (`fringe fuzz --family two_beam_plate --seed 1`,
                    // scenes 5672, 6363, 6541).
                    const OFF_PLANE: f64 = 2e-7;
                    if reference.dot(horiz).abs() > OFF_PLANE * horiz.length()
                        || reference.dot(nrm).abs() > 1e-12
                    {
                        return Err("two_beam_plate: the source's polarization reference must be perpendicular to every plane of incidence (the probe must lie in one plane of incidence)".into());
                    }
                    false
                }
                crate::scene::source::Polarization::Linear { .. } => {
                    return Err("two_beam_plate needs an unpolarized source".into());
                }
            };
            // Heights and lateral distance of the f64 scene as written, in double-double
            // (`held_points`): an f64 x of 250 m is off by up to 2.8e-14 m, which near grazing
            // moves the phase by 4e-7 rad at 200 nm (`TwoBeamPlate::intensity_unpolarized_held`).
            let held = held_points(plane, s, p);
            let t = analytic::plate::TwoBeamPlate {
                n1,
                n2: glass.index(lambda_m).map_err(|e| e.to_string())?,
                thickness_m: plate_thickness(scene, top, bottom),
                h_src_m: held.h_src_m.hi(),
                h_obs_m: held.h_obs_m.hi(),
            };
            // Beyond the critical angle of the top face (an ambient denser than the plate) the
            // top beam is totally reflected and the beam through the plate still exists,
            // entering at a smaller angle nearer the source. The plate then also carries an
            // evanescent wave to its far face (frustrated total reflection): the top beam's
            // amplitude is the plate's r_layer at its angle (the plane-wave Airy sum with
            // imaginary cos θ2, docs/PHYSICS.md §5, `TwoBeamPlate::beam_top_frustrated`), as the
            // tracer applies it at the face (`fresnel::frustrated_layer`). The beam through the
            // plate is solved for tan θt in double-double however steeply it runs inside
            // (`TwoBeamPlate`, docs/PHYSICS.md §5).
            Ok(src.intensity * t.intensity_unpolarized_held(&held, lambda_m, basis_free))
        }
        ReferenceModel::Airy {
            film,
            index_override,
        } => airy(built, film, *index_override, target, lambda_m),
        ReferenceModel::Wedge { wedge } => {
            let (top, bottom, [above, glass, below]) = layer_media(built, wedge)?;
            let (tp, bp) = (&scene.surfaces[top].plane, &scene.surfaces[bottom].plane);
            let (d, _) = plane_wave(scene).ok_or("wedge needs a plane-wave source")?;
            if (d + tp.normal).length() > 1e-12 {
                return Err(
                    "wedge needs the plane wave at normal incidence on the top face".into(),
                );
            }
            let hinge = tp.normal.cross(bp.normal).normalize();
            let src = &scene.sources[0];
            // The hinge of a wedge of angle α is known to ~1e-16/α rad from its two normals;
            // a field ε off the hinge changes the intensity by O(ε²), so 1e-7 is exact enough.
            for ch in src.channels() {
                if ch.field_direction(d).cross(hinge).length() > 1e-7 {
                    return Err("wedge needs s polarization (field along the hinge axis)".into());
                }
            }
            let p = point(target)?;
            let ix = |m: &Medium| m.index(lambda_m).map_err(|e| e.to_string());
            let w = analytic::wedge::Wedge {
                n1: ix(above)?,
                n: ix(glass)?,
                n3: ix(below)?,
                top_point: tp.point,
                top_normal: tp.normal,
                bottom_point: bp.point,
                bottom_normal: bp.normal,
            };
            Ok(src.intensity * w.intensity_s(p, lambda_m))
        }
        ReferenceModel::RhombRetardance {
            glass,
            tir_surface,
            tir_count,
        } => {
            let (d, _) = plane_wave(scene).ok_or("rhomb_retardance needs a plane-wave source")?;
            let n = built.surface(tir_surface)?;
            let theta = d.dot(scene.surfaces[n].plane.normal).abs().acos();
            let n_glass = index(built, glass, lambda_m)?;
            // The medium beyond the TIR face: the side of the interface that is not the glass.
            let SurfaceKind::Interface { front, back, .. } = &scene.surfaces[n].kind else {
                return Err(format!("{tir_surface}: the TIR face must be an interface"));
            };
            let outside = if front.name == *glass { back } else { front };
            let n_out = outside.index(lambda_m).map_err(|e| e.to_string())?;
            // The closed form from the vectors in double-double (θ from acos in f64 is too coarse
            // near the critical angle, analytic::tir::rhomb_retardance_from_vectors).
            let normal = scene.surfaces[n].plane.normal;
            let r =
                analytic::tir::rhomb_retardance_from_vectors(n_glass, n_out, d, normal, *tir_count);
            let Some(r) = r else {
                return Err(format!(
                    "no total internal reflection at {tir_surface}: θ = {:.4}° inside {glass} \
                     (n = {n_glass}) against {} (n = {n_out}) is not beyond the critical angle \
                     ({}); the rhomb retardance exists only under TIR",
                    theta.to_degrees(),
                    outside.name,
                    if n_out < n_glass {
                        format!("{:.4}°", (n_out / n_glass).asin().to_degrees())
                    } else {
                        "none: the glass is not the denser medium".to_string()
                    }
                ));
            };
            Ok(wrap(r))
        }
        ReferenceModel::PlaneWaveBeams { beams } => {
            plane_wave_beams(built, beams, target, lambda_m)
        }
        ReferenceModel::Michelson { splitter, mirrors } => {
            michelson_ref(built, splitter, mirrors, target, lambda_m)
        }
        ReferenceModel::IncoherentSum {} => {
            let p = point(target)?;
            let mut sum = 0.0;
            for s in &scene.sources {
                let Emitter::Point { position } = s.emitter else {
                    return Err("incoherent_sum needs point sources".into());
                };
                let r2 = (p - position).length_squared();
                sum += if spreading {
                    s.intensity / r2
                } else {
                    s.intensity
                };
            }
            Ok(sum)
        }
        ReferenceModel::CoherenceGaussian { plate, .. } | ReferenceModel::CoherenceP9 { plate } => {
            Err(format!(
                "{plate}: evaluated over the whole spectrum by coherence()"
            ))
        }
        ReferenceModel::YoungSpacing { .. } | ReferenceModel::WedgeSpacing { .. } => {
            Err("spacing references are evaluated by spacing()".into())
        }
    }
}

/// The representation term of a phase reference at vacuum wavelength `lambda_m` (rad,
/// docs/PHYSICS.md §8): for `rhomb_retardance`, how far its retardance moves when the wave's
/// direction and the TIR face's normal are held one rounding off
/// ([`analytic::tir::rhomb_retardance_representation`]; the direction inside the glass is the
/// plane wave's, as the closed form takes it); 0 for every other reference.
pub(crate) fn phase_representation(model: &ReferenceModel, built: &Built, lambda_m: f64) -> f64 {
    let ReferenceModel::RhombRetardance {
        glass,
        tir_surface,
        tir_count,
    } = model
    else {
        return 0.0;
    };
    let scene = &built.scene;
    let (Some((d, _)), Ok(n), Ok(n_glass)) = (
        plane_wave(scene),
        built.surface(tir_surface),
        index(built, glass, lambda_m),
    ) else {
        return 0.0;
    };
    let SurfaceKind::Interface { front, back, .. } = &scene.surfaces[n].kind else {
        return 0.0;
    };
    let outside = if front.name == *glass { back } else { front };
    let Ok(n_out) = outside.index(lambda_m) else {
        return 0.0;
    };
    analytic::tir::rhomb_retardance_representation(
        n_glass,
        n_out,
        d,
        scene.surfaces[n].plane.normal,
        *tir_count,
    )
    .unwrap_or(0.0)
}

/// Wrap an angle to (−π, π].
pub fn wrap(a: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let w = a - t * (a / t).round();
    if w <= -std::f64::consts::PI { w + t } else { w }
}

fn airy(
    built: &Built,
    film: &str,
    index_override: Option<f64>,
    target: &Target,
    lambda_m: f64,
) -> Result<f64, String> {
    let scene = &built.scene;
    let (mut f, _) = airy_film(built, film, lambda_m)?;
    if let Some(n) = index_override {
        f.n2 = n;
    }
    let nrm = scene.surfaces[built.surface(&format!("{film}.top"))?]
        .plane
        .normal;
    let src = scene.sources.first().ok_or("airy needs a source")?;
    let Emitter::PlaneWave { direction: d, .. } = src.emitter else {
        return Err("airy needs a plane-wave source".into());
    };
    let Target::Direction { dir, .. } = target else {
        return Err("airy needs a far-field observer".into());
    };
    // cos²θ1 in double-double from the f64 direction and normal, as the tracer forms it: near
    // a critical angle an f64 cos θ1 moved R by up to 5e-5 (docs/PHYSICS.md §5).
    let inc = Incidence::between(d, nrm);
    let reflected = dir.dot(nrm).signum() != d.dot(nrm).signum();
    // Beyond the critical angle of the top face (frustrated total reflection): the exact Airy
    // sum with imaginary cos θ2 (`Film::reflectance`, `Film::transmittance`). The tracer
    // applies it to the reflected wave at the top face and traces the tunnelled wave from the
    // far face (`fresnel::frustrated_layer`, `EventKind::Tunnel`), so R and T are compared at
    // any coupling (docs/PHYSICS.md §5).
    // Split each channel into s and p at the film (one plane of incidence for every beam).
    let s = fresnel::s_direction(d, nrm, src.channels()[0].field_direction(d));
    let p = d.cross(s);
    let (vs, vp) = if reflected {
        (
            f.reflectance(inc, lambda_m, Pol::S),
            f.reflectance(inc, lambda_m, Pol::P),
        )
    } else {
        (
            f.transmittance(inc, lambda_m, Pol::S),
            f.transmittance(inc, lambda_m, Pol::P),
        )
    };
    let mut total = 0.0;
    for ch in src.channels() {
        let e = ch.launch_field(d);
        let (fs, fp) = (e.dot(s).powi(2), e.dot(p).powi(2));
        total += ch.intensity * (fs * vs + fp * vp);
    }
    Ok(total)
}

/// Whether a probe of the `airy` reference `model` sees a film beyond its top face's critical
/// angle (frustrated total reflection with negligible coupling, `airy`): the transmitted
/// side is then dark by physics (T = 0 to [`FTIR_NEGLIGIBLE`]), not a misplaced probe.
pub fn frustrated(model: &ReferenceModel, built: &Built, lambda_m: f64) -> bool {
    let ReferenceModel::Airy {
        film,
        index_override,
    } = model
    else {
        return false;
    };
    let Ok((mut f, _)) = airy_film(built, film, lambda_m) else {
        return false;
    };
    if let Some(n) = index_override {
        f.n2 = *n;
    }
    let (Ok(top), Some((d, _))) = (
        built.surface(&format!("{film}.top")),
        plane_wave(&built.scene),
    ) else {
        return false;
    };
    let inc = Incidence::between(d, built.scene.surfaces[top].plane.normal);
    f.frustration(inc, lambda_m)
        .is_some_and(|fr| fr.transmittance <= FTIR_NEGLIGIBLE)
}

/// The media above, inside and below the plate or wedge `name`, read from its two faces (the
/// top face's front and back, the bottom face's back), with the faces' scene indices.
fn layer_media<'a>(
    built: &'a Built,
    name: &str,
) -> Result<(usize, usize, [&'a Medium; 3]), String> {
    let (top, bottom) = (
        built.surface(&format!("{name}.top"))?,
        built.surface(&format!("{name}.bottom"))?,
    );
    let scene = &built.scene;
    let (
        SurfaceKind::Interface {
            front: above,
            back: inside,
            ..
        },
        SurfaceKind::Interface { back: below, .. },
    ) = (&scene.surfaces[top].kind, &scene.surfaces[bottom].kind)
    else {
        return Err(format!("the faces of {name:?} must be interfaces"));
    };
    Ok((top, bottom, [above, inside, below]))
}

/// The film of an Airy reference (for the bounce-count choice and the convergence report).
pub fn airy_film(
    built: &Built,
    film: &str,
    lambda_m: f64,
) -> Result<(analytic::plate::Film, f64), String> {
    let scene = &built.scene;
    let (top, bottom, [m1, m2, m3]) = layer_media(built, film)?;
    let ix = |m: &Medium| m.index(lambda_m).map_err(|e| e.to_string());
    let nrm = scene.surfaces[top].plane.normal;
    let (d, _) = plane_wave(scene).ok_or("needs a plane-wave source")?;
    let film = analytic::plate::Film {
        n1: ix(m1)?,
        n2: ix(m2)?,
        n3: ix(m3)?,
        thickness_m: plate_thickness(scene, top, bottom),
    };
    // Beyond the critical angle of the top face the film carries an evanescent wave
    // (frustrated total reflection): the Airy sum holds with imaginary cos θ2
    // ([`analytic::plate::Film::terms`]), and [`airy`] decides whether the ray model's total
    // reflection is exact enough to be compared.
    let cos1 = d.dot(nrm).abs();
    Ok((film, cos1))
}

/// Plane waves through planar faces: optical path by wavefront continuity,
/// φ_k(x) = φ_{k−1}(Q_k) + n_k u_k·(x − Q_k) at each face through Q_k (tangential n·u is
/// conserved), amplitudes by complex Fresnel products for s and p (one plane of incidence).
fn plane_wave_beams(
    built: &Built,
    beams: &[BeamSpec],
    target: &Target,
    lambda_m: f64,
) -> Result<f64, String> {
    let scene = &built.scene;
    // Sum per (coherence group, channel index).
    let mut groups: Vec<((u64, usize), [Complex64; 3])> = Vec::new();
    for b in beams {
        let src = scene
            .sources
            .iter()
            .find(|s| s.name == b.source)
            .ok_or(format!("no source {:?}", b.source))?;
        let Emitter::PlaneWave {
            direction,
            reference_point,
        } = src.emitter
        else {
            return Err(format!("source {:?} must be a plane wave", b.source));
        };
        let mut u = direction;
        // The direction in double-double (`twofloat`, independent of the tracer's arithmetic):
        // the Fresnel coefficients take cos θi and cos²θt from it, since near a critical angle
        // or leaving a film at near-grazing outside, cos²θt from an f64 direction is a small
        // difference of large terms (~1e-8 of T off).
        let mut ud = analytic::precise::unit(direction);
        let mut n = scene.ambient.index(lambda_m).map_err(|e| e.to_string())?;
        // The optical path: [`analytic::tir::plane_wave_path`], double-double.
        let n0 = n;
        let mut faces = Vec::new();
        let mut amp_s = Complex64::from(1.0);
        let mut amp_p = Complex64::from(1.0);
        let mut s_axis: Option<DVec3> = None;
        for ev in &b.events {
            let k = built.surface(&ev.surface)?;
            let surf = &scene.surfaces[k];
            let SurfaceKind::Interface { front, back, .. } = &surf.kind else {
                return Err(format!(
                    "surface {:?} must be a dielectric interface",
                    ev.surface
                ));
            };
            let nrm = surf.plane.normal;
            let (n1, n2) = if u.dot(nrm) < 0.0 {
                (front, back)
            } else {
                (back, front)
            };
            let (n1, n2) = (
                n1.index(lambda_m).map_err(|e| e.to_string())?,
                n2.index(lambda_m).map_err(|e| e.to_string())?,
            );
            if (n1 - n).abs() > 0.0 {
                return Err(format!(
                    "beam from {:?} reaches {:?} from the wrong medium",
                    b.source, ev.surface
                ));
            }
            let cos_i = u.dot(nrm).abs();
            // One plane of incidence: every oblique event's s is ± the first one. The
            // coefficients are unchanged when s (and with it every p) flips, so one s serves
            // all events. An event at normal incidence does not constrain s: it multiplies the
            // 3D field by r (or t) whatever the frame (r_p = −r_s with p_r = −p_i, t_p = t_s).
            match (fresnel::s_of_plane_of_incidence(u, nrm), s_axis) {
                (Some(s), Some(prev)) if prev.cross(s).length() > 1e-9 => {
                    return Err(
                        "plane_wave_beams needs every event in one plane of incidence".into(),
                    );
                }
                (Some(s), None) => s_axis = Some(s),
                _ => {}
            }
            let nd = analytic::precise::unit(nrm);
            let cos_i_dd = analytic::precise::dot2(&ud, &nd).abs();
            let one = twofloat::TwoFloat::from(1.0);
            let eta = analytic::precise::div(n1.into(), n2.into());
            let c2t = one - eta * eta * (one - cos_i_dd * cos_i_dd);
            let f = if n1 == n2 {
                fresnel::fresnel(n1, n2, cos_i)
            } else {
                fresnel::fresnel_with_cos2_t(n1, n2, f64::from(cos_i_dd), f64::from(c2t))
            };
            faces.push(analytic::tir::Face {
                point: surf.plane.point,
                normal: nrm,
                n_before: n1,
                n_after: n2,
                reflect: ev.reflect,
            });
            if ev.reflect {
                u = fresnel::reflect(u, nrm);
                ud = analytic::precise::reflect(&ud, &nd);
                amp_s *= f.r_s;
                amp_p *= f.r_p;
            } else {
                ud = analytic::precise::refract(&ud, &nd, n1, n2)
                    .ok_or(format!("TIR at {:?} on a refraction event", ev.surface))?;
                // The f64 direction rounded from the double-double one: just below a critical
                // angle the f64 Snell law leaves the grazing beam's direction ~1e-9 off (or
                // totally reflected), and the beam would miss its far-field direction.
                u = DVec3::new(f64::from(ud[0]), f64::from(ud[1]), f64::from(ud[2])).normalize();
                amp_s *= f.t_s;
                amp_p *= f.t_p;
                n = n2;
            }
        }
        let x = match target {
            Target::Point(x) => *x,
            Target::Direction { dir, reference } => {
                if u.cross(*dir).length() > 1e-9 {
                    continue; // this beam does not reach the far-field direction
                }
                *reference
            }
        };
        let (op, _) = analytic::tir::plane_wave_path(direction, reference_point, n0, &faces, x)
            .ok_or(format!(
                "beam from {:?}: total internal reflection on a refraction event",
                b.source
            ))?;
        let s = s_axis.unwrap_or_else(|| u.any_orthonormal_vector());
        let ph = analytic::precise::path_phasor(op, lambda_m);
        for (ci, ch) in src.channels().iter().enumerate() {
            let e0 = ch.launch_field(direction) * ch.intensity.sqrt();
            let p0 = direction.cross(s);
            let (a_s, a_p) = (e0.dot(s), e0.dot(p0));
            let p_out = u.cross(s);
            let e = [0, 1, 2].map(|k| (amp_s * a_s * s[k] + amp_p * a_p * p_out[k]) * ph);
            let key = (src.coherence_group, ci);
            match groups.iter_mut().find(|(g, _)| *g == key) {
                Some((_, acc)) => (0..3).for_each(|k| acc[k] += e[k]),
                None => groups.push((key, e)),
            }
        }
    }
    Ok(groups
        .iter()
        .map(|(_, e)| e.iter().map(|c| c.norm_sqr()).sum::<f64>())
        .sum())
}

/// A Michelson scene as its closed form reads it ([`michelson_layout`]).
struct MichelsonLayout<'a> {
    /// Index of the splitter.
    splitter: usize,
    source: &'a Source,
    /// The point source's position (m).
    position: DVec3,
    /// Per mirror: its index, and whether the splitter reflects its arm first (the mirror lies
    /// on the source's side of the splitter) rather than transmitting it first.
    arms: Vec<(usize, bool)>,
}

/// The layout the Michelson closed form assumes: the splitter's index, the point source, and
/// for each mirror its index and whether it lies on the source's side of the splitter (its arm
/// is reflected by the splitter first, else transmitted first). Shared by the closed form
/// ([`michelson_ref`]) and the sequences it models ([`michelson_sequences`]).
fn michelson_layout<'a>(
    built: &'a Built,
    splitter: &str,
    mirrors: &[String; 2],
) -> Result<MichelsonLayout<'a>, String> {
    let scene = &built.scene;
    let b = built.surface(splitter)?;
    let src = scene.sources.first().ok_or("michelson needs a source")?;
    let Emitter::Point { position: s } = src.emitter else {
        return Err("michelson needs a point source".into());
    };
    let plane = &scene.surfaces[b].plane;
    let side_src = plane.signed_distance(s).signum();
    let arms = mirrors
        .iter()
        .map(|m| {
            let mi = built.surface(m)?;
            if !matches!(scene.surfaces[mi].kind, SurfaceKind::IdealMirror { .. }) {
                return Err(format!(
                    "{m:?} must be a mirror (the michelson closed form treats it as a perfect \
                     conductor), got another kind of surface"
                ));
            }
            let side_m = plane
                .signed_distance(scene.surfaces[mi].plane.point)
                .signum();
            Ok((mi, side_m == side_src))
        })
        .collect::<Result<_, String>>()?;
    Ok(MichelsonLayout {
        splitter: b,
        source: src,
        position: s,
        arms,
    })
}

/// The Michelson closed form at `target` ([`michelson::intensity`]): one virtual source per
/// arm of [`michelson_layout`], summed over the source's channels.
fn michelson_ref(
    built: &Built,
    splitter: &str,
    mirrors: &[String; 2],
    target: &Target,
    lambda_m: f64,
) -> Result<f64, String> {
    let scene = &built.scene;
    let MichelsonLayout {
        splitter: b,
        source: src,
        position: s,
        arms: layout,
    } = michelson_layout(built, splitter, mirrors)?;
    let bs = &scene.surfaces[b];
    let SurfaceKind::Splitter { reflectance, .. } = bs.kind else {
        return Err(format!("{splitter:?} must be a splitter"));
    };
    let p = point(target)?;
    let side_src = bs.plane.signed_distance(s).signum();
    let (r, t) = (reflectance.sqrt(), (1.0 - reflectance).sqrt());
    // E_r = σ R_N(E_i): σ = −√R from the front, +√R from the back.
    let sigma = |side: f64| if side > 0.0 { -r } else { r };
    let arms: Vec<michelson::Arm> = layout
        .iter()
        .map(|&(mi, reflected_first)| {
            let plane = &scene.surfaces[mi].plane;
            let mirror = michelson::Reflection {
                point: plane.point,
                normal: plane.normal,
                factor: -1.0,
            };
            let split = |side: f64| michelson::Reflection {
                point: bs.plane.point,
                normal: bs.plane.normal,
                factor: sigma(side),
            };
            let reflections = if reflected_first {
                vec![split(side_src), mirror]
            } else {
                vec![
                    mirror,
                    split(bs.plane.signed_distance(plane.point).signum()),
                ]
            };
            michelson::Arm {
                reflections,
                transmission: t,
            }
        })
        .collect();
    let n = ambient_index(built, lambda_m)?;
    Ok(src
        .channels()
        .iter()
        .map(|ch: &Channel| {
            ch.intensity * michelson::intensity(&arms, s, p, lambda_m, n, |d| ch.launch_field(d))
        })
        .sum())
}

/// The surface sequences the Michelson closed form models (`michelson_ref`): for each mirror,
/// splitter (reflect) → mirror → splitter (transmit) when the mirror is on the source's side of
/// the splitter, else splitter (transmit) → mirror → splitter (reflect). Light that reaches the
/// probe along any other sequence (a mirror large enough to be lit directly, a second pass
/// through the splitter) is outside the two-arm closed form, and a case whose scene lets it
/// through is refused by the runner rather than compared (docs/PHYSICS.md §5 "Michelson").
pub(crate) fn michelson_sequences(
    built: &Built,
    splitter: &str,
    mirrors: &[String; 2],
) -> Result<Vec<Vec<Event>>, String> {
    let MichelsonLayout {
        splitter: b,
        arms: layout,
        ..
    } = michelson_layout(built, splitter, mirrors)?;
    let ev = |surface, kind| Event { surface, kind };
    Ok(layout
        .into_iter()
        .map(|(mi, reflected_first)| {
            if reflected_first {
                vec![
                    ev(b, EventKind::Reflect),
                    ev(mi, EventKind::Reflect),
                    ev(b, EventKind::Refract),
                ]
            } else {
                vec![
                    ev(b, EventKind::Refract),
                    ev(mi, EventKind::Reflect),
                    ev(b, EventKind::Reflect),
                ]
            }
        })
        .collect())
}

/// The coherence references over the whole spectrum: plane wave at normal incidence on a
/// plate, two beams (top reflection and one internal reflection) in the reflected far field.
/// Returns (I1, I2, Δs, φ, Op1, Op2) pieces as the final intensity.
pub fn coherence(
    model: &ReferenceModel,
    built: &Built,
    target: &Target,
    spectrum: &[(f64, f64)],
    center_m: f64,
    fwhm_m: Option<f64>,
) -> Result<f64, String> {
    let (plate, fwhm_m) = match model {
        ReferenceModel::CoherenceGaussian {
            plate,
            fwhm_nm: Some(f),
        } => {
            if fwhm_m.is_some() {
                return Err("coherence_gaussian: fwhm_nm is for monochromatic cases; this case's light already has a bandwidth".into());
            }
            (plate, Some(f * 1e-9))
        }
        ReferenceModel::CoherenceGaussian {
            plate,
            fwhm_nm: None,
        } => (plate, fwhm_m),
        ReferenceModel::CoherenceP9 { plate } => (plate, fwhm_m),
        _ => return Err("not a coherence reference".into()),
    };
    // Normal incidence: the two beams' amplitudes are r12 and t12 r23 t21 for any polarization.
    let beams = |lambda_m: f64| -> Result<(f64, f64, analytic::plate::Film), String> {
        let (film, cos1) = airy_film(built, plate, lambda_m)?;
        if (cos1 - 1.0).abs() > 1e-12 {
            return Err("coherence references need normal incidence".into());
        }
        let f12 = fresnel::fresnel(film.n1, film.n2, 1.0);
        let f23 = fresnel::fresnel(film.n2, film.n3, 1.0);
        let f21 = fresnel::fresnel(film.n2, film.n1, 1.0);
        Ok((f12.r_s.re, (f12.t_s * f23.r_s * f21.t_s).re, film))
    };
    let (a1, a2, film) = beams(center_m)?;
    let ds = 2.0 * film.n2 * film.thickness_m;
    let src = &built.scene.sources[0];
    let i0 = src.intensity;
    match model {
        ReferenceModel::CoherenceGaussian { fwhm_nm: None, .. } => {
            // Gaussian light: the case's sampled spectrum is what the tracer sums (incoherent
            // across wavelength), so the reference is the same discrete sum of two-beam terms,
            // Σ w_i (a1² + a2² + 2 a1 a2 cos(2π Δs/λ_i)) (docs/PHYSICS.md §3), with Δs = 2 n2 d
            // formed in double-double. Its distance from the continuous-spectrum form |γ(Δs)|
            // is the spectral sampling error ([`gaussian_sampling_error`]), not part of the verdict.
            fwhm_m.ok_or("coherence_gaussian needs Gaussian light")?;
            // The plate's thickness as held (top point + thickness, `Plane::separation_from`),
            // never a difference of its faces' rounded points: the bottom face's f64 point of a
            // 2 nm plate 10 m from the origin is ~1e-15 m off, 1e-7 of R (fuzz
            // coherence_gaussian seed 7, test precision_classes::…thickness_as_held).
            // The film as `airy_film` gives it at each wavelength: the faces' media and the
            // thickness found once, the indices at each λ (the normal incidence and the plane
            // wave were checked at the centre above).
            let (top, bottom, media) = layer_media(built, plate)?;
            let thickness_m = plate_thickness(&built.scene, top, bottom);
            let index = |m: &Medium, lam: f64| m.index(lam).map_err(|e| e.to_string());
            let mut two_beam: Option<analytic::coherence::TwoBeamNormal> = None;
            let mut sum = 0.0;
            for &(lam, w) in spectrum {
                let n = [
                    index(media[0], lam)?,
                    index(media[1], lam)?,
                    index(media[2], lam)?,
                ];
                // a1² + a2² + 2 a1 a2 cos δ as (a1 + a2)² − 4 a1 a2 sin²(δ/2): for a thin film
                // a1 ≈ −a2 and the first form cancels to ~ε a1²/I (4e-13 of a 2 nm film's R).
                // In double-double (analytic::coherence::two_beam_normal_reflectance): near a
                // dark fringe the two terms cancel, and in f64 the closed form lost 1e-11.
                // The beams are formed again only where the indices change (dispersion).
                let beams = match two_beam {
                    Some(b) if b.indices == n => b,
                    _ => analytic::coherence::TwoBeamNormal::new(n[0], n[1], n[2]),
                };
                two_beam = Some(beams);
                let half = twofloat::TwoFloat::new_mul(n[1], thickness_m);
                sum += w * beams.reflectance(half, lam);
            }
            Ok(i0 * sum)
        }
        ReferenceModel::CoherenceGaussian { .. } => {
            // Monochrome light with the truth's bandwidth `fwhm_nm`: the continuous Gaussian
            // spectrum in k, ⟨cos(kΔs)⟩ = |γ(Δs)| cos(k0 Δs) exactly.
            let fwhm = fwhm_m.ok_or("coherence_gaussian needs Gaussian light")?;
            let gamma = analytic::coherence::gaussian_visibility(ds, center_m, fwhm);
            let delta = std::f64::consts::TAU * ds / center_m;
            Ok(i0 * (a1 * a1 + a2 * a2 + 2.0 * a1 * a2 * gamma * delta.cos()))
        }
        _ => {
            // P9: each ray keeps coherence while its own optical path (from the plane wave's
            // reference plane to the far-field wavefront through the same point) is ≤ L.
            let Target::Direction { reference, .. } = target else {
                return Err("coherence_p9 needs a far-field observer".into());
            };
            let (d, r0) = plane_wave(&built.scene).ok_or("needs a plane wave")?;
            let top = &built.scene.surfaces[built.surface(&format!("{plate}.top"))?].plane;
            // Launched at r0, the ray meets the top face after h; the far-field projection
            // adds −d_r·(X − reference) with X = r0 + h d (reference = r0 here).
            let h = top
                .intersect(r0, d)
                .ok_or("the plane wave misses the plate")?;
            let d_r = fresnel::reflect(d, top.normal);
            let n1 = film.n1;
            let op1 = n1 * (h - d_r.dot(r0 + h * d - *reference));
            let op2 = op1 + ds;
            let l = src.coherence_length_m;
            let mut sum = 0.0;
            for &(lam, w) in spectrum {
                let coherent = op1 <= l && op2 <= l;
                let c = if coherent {
                    2.0 * a1 * a2 * (std::f64::consts::TAU * ds / lam).cos()
                } else {
                    0.0
                };
                sum += w * (a1 * a1 + a2 * a2 + c);
            }
            Ok(i0 * sum)
        }
    }
}

/// The spectral sampling error of a `coherence_gaussian` case with Gaussian light at one probe
/// point: the continuous-spectrum two-beam intensity (|γ(Δs)|, docs/PHYSICS.md §3) minus the
/// discrete sum over the case's samples that the reference evaluates. It is a property of the
/// case's `samples` and `sigmas`, not of the tracer, and is not part of the verdict.
pub fn gaussian_sampling_error(
    built: &Built,
    plate: &str,
    target: &Target,
    spectrum: &[(f64, f64)],
    center_m: f64,
    fwhm_m: f64,
) -> Result<f64, String> {
    let model = ReferenceModel::CoherenceGaussian {
        plate: plate.to_string(),
        fwhm_nm: None,
    };
    let sampled = coherence(&model, built, target, spectrum, center_m, Some(fwhm_m))?;
    let (film, _) = airy_film(built, plate, center_m)?;
    let f12 = fresnel::fresnel(film.n1, film.n2, 1.0);
    let f23 = fresnel::fresnel(film.n2, film.n3, 1.0);
    let f21 = fresnel::fresnel(film.n2, film.n1, 1.0);
    let (a1, a2) = (f12.r_s.re, (f12.t_s * f23.r_s * f21.t_s).re);
    let ds = 2.0 * film.n2 * film.thickness_m;
    let gamma = analytic::coherence::gaussian_visibility(ds, center_m, fwhm_m);
    let c = analytic::precise::path_phasor(
        twofloat::TwoFloat::new_mul(film.n2, film.thickness_m) * 2.0,
        center_m,
    )
    .re;
    let continuous =
        built.scene.sources[0].intensity * (a1 * a1 + a2 * a2 + 2.0 * a1 * a2 * gamma * c);
    Ok(continuous - sampled)
}
