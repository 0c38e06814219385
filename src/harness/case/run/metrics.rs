//! Metrics other than an intensity profile: the traced retardance and visibility, and fringe
//! spacings traced and in closed form.

use super::*;

/// The traced value at `level` of a metric that is not an intensity, from the arrivals at one
/// probe point: the rhomb's retardance arg E_p − arg E_s (rad, of the output relative to the
/// input's s/p phases) or Lloyd's fringe visibility; `None` where the metric is undefined at
/// that level.
pub(super) fn special_value(
    model: &ReferenceModel,
    built: &Built,
    arr: &[Arrival],
    level: Fidelity,
) -> Option<f64> {
    match model {
        ReferenceModel::RhombRetardance { tir_surface, .. } => {
            if !matches!(level, Fidelity::Vector | Fidelity::PaperRules) {
                return None;
            }
            let e = summed_field(arr, level)?;
            let (d_in, _) = build::plane_wave(&built.scene)?;
            let n = built.scene.surfaces[built.surface(tir_surface).ok()?]
                .plane
                .normal;
            let s = d_in.cross(n).normalize();
            let d_out = arr.first()?.vector.dir;
            let p = d_out.cross(s);
            let dot = |v: DVec3| e[0] * v.x + e[1] * v.y + e[2] * v.z;
            // The retardance is what the TIRs add: the output's relative phase of p and s minus
            // the input's (0 or π for linear light: a field at −45° starts at π).
            let src = built.scene.sources.first()?;
            let e_in = src.channels().first()?.field_direction(d_in);
            let phase_in =
                Complex64::from(e_in.dot(d_in.cross(s))).arg() - Complex64::from(e_in.dot(s)).arg();
            Some(reference::wrap(dot(p).arg() - dot(s).arg() - phase_in))
        }
        ReferenceModel::LloydVisibility {} => {
            if level != Fidelity::Vector {
                return None;
            }
            let id = arr.first()?.vector.coherence_id;
            let i: Vec<f64> = arr
                .iter()
                .filter(|a| a.vector.coherence_id == id)
                .map(|a| a.vector.intensity())
                .collect();
            if i.len() != 2 {
                return None;
            }
            Some(2.0 * (i[0] * i[1]).sqrt() / (i[0] + i[1]))
        }
        _ => None,
    }
}

/// Fringe spacing at the probe centre from the two strongest mutually coherent arrivals. The
/// gradient of a ray's optical path with respect to its end point is n·d (the eikonal
/// equation), so the traced phase-difference gradient along the probe line t̂ is
/// (2π/λ)·n (d_a − d_b)·t̂ and the local spacing λ/|n (d_a − d_b)·t̂|, free of finite differences.
pub(super) fn traced_spacing(case: &Case, built: &Built) -> Result<(f64, f64), CaseError> {
    let Probe::Line {
        from_m,
        to_m,
        looks_toward,
        ..
    } = &case.spec.probe
    else {
        return Err(case_err(
            case,
            "$.probe",
            "spacing references need a line probe",
        ));
    };
    let (a, b) = (DVec3::from_array(*from_m), DVec3::from_array(*to_m));
    let dir = (b - a).normalize();
    let p0 = a.lerp(b, 0.5);
    let spectrum = build::spectrum(&case.spec.light, &Overrides::default());
    let lambda = spectrum[spectrum.len() / 2].0;
    let optics = built
        .scene
        .optics(lambda)
        .map_err(|e| case_err(case, "$.light", e.to_string()))?;
    let st = settings(case, built, case.spec.trace.max_internal_reflections);
    let observer = Observer::Point {
        position_m: p0.to_array(),
        looks_toward: *looks_toward,
    };
    let mut arr = arrivals_at(case, built, &optics, &Target::Point(p0), &observer, &st)
        .map_err(|e| case_err(case, "$.probe", e))?;
    let id = arr.first().map(|x| x.vector.coherence_id);
    arr.retain(|x| Some(x.vector.coherence_id) == id);
    arr.sort_by(|x, y| y.vector.intensity().total_cmp(&x.vector.intensity()));
    match (arr.first(), arr.get(1)) {
        (Some(x), Some(y)) => {
            let g = x.vector.index * x.vector.dir - y.vector.index * y.vector.dir;
            Ok((lambda / g.dot(dir).abs(), lambda))
        }
        _ => Err(case_err(
            case,
            "$.probe",
            "fewer than two coherent beams reach the probe centre",
        )),
    }
}

pub(super) fn analytic_spacing(
    case: &Case,
    built: &Built,
    model: &ReferenceModel,
    lambda: f64,
) -> Result<f64, String> {
    match model {
        ReferenceModel::YoungSpacing { paraxial } => {
            let srcs: Vec<(DVec3, DVec3)> = built
                .scene
                .sources
                .iter()
                .filter_map(|s| match s.emitter {
                    crate::scene::source::Emitter::Line { point, axis } => Some((point, axis)),
                    _ => None,
                })
                .collect();
            if srcs.len() != 2 {
                return Err("young_spacing needs two line sources".into());
            }
            let Probe::Line { from_m, to_m, .. } = &case.spec.probe else {
                return Err("needs a line probe".into());
            };
            let p0 = DVec3::from_array(*from_m).lerp(DVec3::from_array(*to_m), 0.5);
            let sep = srcs[0].0 - srcs[1].0;
            let d = sep.length();
            let forward = srcs[0].1.cross(sep / d).normalize();
            let l = (p0 - 0.5 * (srcs[0].0 + srcs[1].0)).dot(forward).abs();
            let n = reference::ambient_index(built, lambda)?;
            Ok(if *paraxial {
                crate::harness::analytic::young::fringe_spacing_paraxial(d, l, lambda, n)
            } else {
                crate::harness::analytic::young::fringe_spacing_exact_on_axis(d, l, lambda, n)
            })
        }
        ReferenceModel::WedgeSpacing { wedge, small_angle } => {
            let top = &built.scene.surfaces[built.surface(&format!("{wedge}.top"))?];
            let bottom = &built.scene.surfaces[built.surface(&format!("{wedge}.bottom"))?];
            let crate::scene::SurfaceKind::Interface { back: glass, .. } = &top.kind else {
                return Err("wedge faces must be interfaces".into());
            };
            let n = glass.index(lambda).map_err(|e| e.to_string())?;
            let alpha =
                crate::scene::geometry::angle_between(top.plane.normal, bottom.plane.normal);
            Ok(if *small_angle {
                crate::harness::analytic::wedge::fringe_spacing_small_angle(lambda, n, alpha)
            } else {
                crate::harness::analytic::wedge::fringe_spacing_exact(lambda, n, alpha)
            })
        }
        _ => unreachable!(),
    }
}
