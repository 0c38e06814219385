//! Checks that a case's probe, observer and references measure the same observable and are
//! wired to the scene they name.

use super::*;

/// What the probe measures, after checking that every intensity reference returns the same
/// observable (docs/PHYSICS.md §3a) and that the observer makes sense: a mismatch is bad input.
pub(super) fn check_observables(
    case: &Case,
    points: &[ProbePoint],
) -> Result<Observable, CaseError> {
    let spec = &case.spec;
    let observer = &points
        .first()
        .ok_or_else(|| case_err(case, "$.probe", "the probe has no points"))?
        .observer;
    if let Observer::FarField {
        side: FarSide::Reflected,
        exit_medium: Some(m),
        ..
    } = observer
        && *m != spec.scene.ambient
    {
        return Err(case_err(
            case,
            &format!("{}.exit_medium", observer_path(&spec.probe)),
            format!(
                "the reflected wave leaves into the ambient medium {:?}, not {m:?}: \
                 exit_medium is for the transmitted side (omit it here)",
                spec.scene.ambient
            ),
        ));
    }
    check_wiring(case, observer)?;
    let measured = reference::measured(observer);
    for (ri, r) in spec.references.iter().enumerate() {
        if let Some(returns) = reference::returns(&r.model) {
            check_match(&reference::name(&r.model), returns, measured)
                .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
        }
    }
    Ok(measured)
}

/// Every surface a reference names must be of the kind its closed form describes, and a
/// far-field observer of an Airy film must look along the film's normal: a reference wired to
/// the wrong thing is bad input, never a NaN row or a deviation of 1.
fn check_wiring(case: &Case, observer: &Observer) -> Result<(), CaseError> {
    let spec = &case.spec;
    let kind_of = |name: &str| {
        spec.scene
            .surfaces
            .iter()
            .find(|s| s.name() == name)
            .map(|s| s.kind())
    };
    for (ri, r) in spec.references.iter().enumerate() {
        let (key, named, wanted): (&str, Vec<&String>, &str) = match &r.model {
            ReferenceModel::Airy { film, .. } => ("film", vec![film], "plate"),
            ReferenceModel::TwoBeamPlate { plate }
            | ReferenceModel::CoherenceGaussian { plate, .. }
            | ReferenceModel::CoherenceP9 { plate } => ("plate", vec![plate], "plate"),
            ReferenceModel::Wedge { wedge } | ReferenceModel::WedgeSpacing { wedge, .. } => {
                ("wedge", vec![wedge], "wedge")
            }
            ReferenceModel::Michelson { splitter, .. } => ("splitter", vec![splitter], "splitter"),
            _ => continue,
        };
        let mut checks = vec![(key.to_string(), named, wanted)];
        if let ReferenceModel::Michelson { mirrors, .. } = &r.model {
            checks.push(("mirrors".into(), mirrors.iter().collect(), "mirror"));
        }
        for (key, names, wanted) in checks {
            for (k, name) in names.iter().enumerate() {
                let path = if key == "mirrors" {
                    format!("$.references[{ri}].model.michelson.mirrors[{k}]")
                } else {
                    format!(
                        "$.references[{ri}].model.{}.{key}",
                        reference::name(&r.model)
                    )
                };
                match kind_of(name) {
                    Some(found) if found == wanted => {}
                    Some(found) => {
                        return Err(case_err(
                            case,
                            &path,
                            format!(
                                "{name:?} is a {found}; {} describes a {wanted} here",
                                reference::name(&r.model)
                            ),
                        ));
                    }
                    None => {} // a missing name is reported by the loader
                }
            }
        }
        if let (ReferenceModel::Airy { film, .. }, Observer::FarField { surface_normal, .. }) =
            (&r.model, observer)
            && let Some(crate::harness::case::spec::SurfaceSpec::Plate { normal, .. }) =
                spec.scene.surfaces.iter().find(|s| s.name() == film)
        {
            let (a, b) = (
                DVec3::from_array(*surface_normal).normalize(),
                DVec3::from_array(*normal).normalize(),
            );
            if a.cross(b).length() > 1e-9 {
                return Err(case_err(
                    case,
                    &format!("{}.surface_normal", observer_path(&spec.probe)),
                    format!(
                        "the far field of the airy film {film:?} is observed about the film's \
                         normal {b:?}; this surface_normal {a:?} is not parallel to it"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The JSON path of a probe's observer (`$.probe.<kind>.observe.far_field`), for errors.
fn observer_path(probe: &Probe) -> String {
    match probe {
        Probe::Sweep { .. } => "$.probe.sweep.observe.far_field".into(),
        Probe::Single { .. } => "$.probe.single.observe.far_field".into(),
        _ => "$.probe".into(),
    }
}
