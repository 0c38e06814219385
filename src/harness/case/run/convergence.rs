//! The convergence report of a case with an Airy tail bound: the traced sum against the
//! closed form as the order count grows.

use super::*;

/// For cases with an Airy reference: the traced error against the number of reflected orders,
/// with the geometric-tail bound.
pub(super) fn convergence(
    case: &Case,
    points: &[ProbePoint],
) -> Result<Vec<ConvergenceRow>, CaseError> {
    let spec = &case.spec;
    let Some((ri, film)) = spec
        .references
        .iter()
        .enumerate()
        .find_map(|(i, r)| match &r.model {
            ReferenceModel::Airy {
                film,
                index_override: None,
            } => Some((i, film.clone())),
            _ => None,
        })
    else {
        return Ok(Vec::new());
    };
    if !matches!(spec.light, Light::Monochrome { .. }) {
        return Ok(Vec::new());
    }
    // At most 24 probe points, evenly spread, keep the report cheap.
    let stride = points.len().div_ceil(24).max(1);
    let points: Vec<ProbePoint> = points.iter().step_by(stride).cloned().collect();
    let points = &points[..];
    let mut rows = Vec::new();
    // Never more internal reflections than the case's own budget (the preflight counted it).
    let budget = points
        .iter()
        .map(|pt| {
            let built = build::build_scene(&spec.scene, &pt.overrides)
                .map_err(|e| case_err(case, "$.scene", e))?;
            let lambda = build::spectrum(&spec.light, &pt.overrides)[0].0;
            internal_reflections(case, &built, lambda)
        })
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .max()
        .unwrap_or(0);
    for orders in super::budget::CONVERGENCE_ORDERS {
        let internal = 2 * orders - 1;
        if internal > budget.max(1) {
            break;
        }
        let res: Vec<(f64, f64)> = points
            .par_iter()
            .map(|pt| -> Result<(f64, f64), CaseError> {
                let built = build::build_scene(&spec.scene, &pt.overrides)
                    .map_err(|e| case_err(case, "$.scene", e))?;
                let lambda = build::spectrum(&spec.light, &pt.overrides)[0].0;
                let optics = built
                    .scene
                    .optics(lambda)
                    .map_err(|e| case_err(case, "$.light", e.to_string()))?;
                let Some(target) = build::propagating_target(&pt.observer, &built, lambda)
                    .map_err(|e| case_err(case, "$.probe", e))?
                else {
                    return Ok((0.0, 0.0)); // no transmitted wave: T = 0 traced and exact
                };
                let st = settings(case, &built, internal);
                let factor = reference::observable_factor(&pt.observer, &built, &target, lambda)
                    .map_err(|e| case_err(case, "$.probe", e))?;
                let traced = factor
                    * trace::intensity(
                        &arrivals_at(
                            &built,
                            &optics,
                            &target,
                            &pt.observer,
                            &st,
                            &required_paths(case, &built),
                        )
                        .map_err(|e| case_err(case, "$.probe", e))?,
                        Fidelity::Vector,
                    );
                let exact =
                    reference::value(&spec.references[ri].model, &built, &target, lambda, false)
                        .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
                let (f, cos1) = reference::airy_film(&built, &film, lambda)
                    .map_err(|e| case_err(case, "$.references", e))?;
                let tau = [
                    crate::harness::analytic::plate::Pol::S,
                    crate::harness::analytic::plate::Pol::P,
                ]
                .into_iter()
                .map(|p| f.tail_bound(cos1, lambda, p, orders))
                .fold(0.0f64, f64::max);
                let bound = 2.0 * exact.sqrt() * tau + tau * tau;
                Ok(((traced - exact).abs(), bound))
            })
            .collect::<Vec<_>>()
            .into_iter()
            .collect::<Result<_, _>>()?;
        rows.push(ConvergenceRow {
            orders,
            internal_reflections: internal,
            max_abs_dev: res.iter().map(|r| r.0).fold(0.0, f64::max),
            bound: res.iter().map(|r| r.1).fold(0.0, f64::max),
        });
        if internal > spec.trace.max_internal_reflections.max(8)
            && rows.last().is_some_and(|r| r.max_abs_dev < 1e-15)
        {
            break;
        }
    }
    Ok(rows)
}
