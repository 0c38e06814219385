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
    // The order counts of the report: every internal-reflection count within the budget.
    let counts: Vec<(usize, usize)> = super::budget::CONVERGENCE_ORDERS
        .iter()
        .map(|&orders| (orders, 2 * orders - 1))
        .take_while(|&(_, internal)| internal <= budget.max(1))
        .collect();
    let Some(&(_, deepest)) = counts.last() else {
        return Ok(rows);
    };
    // Each point is traced once, at the deepest count; a shallower count's sum is the sum of
    // the arrivals its own trace finds: those with at most that many internal reflections
    // and events (`EnumerationLimits`, as `settings` sets them), in the same order (the
    // enumeration is depth-first, so a smaller tree visits the same sequences in the same
    // order), each arrival the same (a path's solve and amplitudes do not depend on the
    // budget), so the same intensity to the bit.
    let per_point: Vec<Vec<(f64, f64)>> = points
        .par_iter()
        .map(|pt| -> Result<Vec<(f64, f64)>, CaseError> {
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
                // No transmitted wave: T = 0 traced and exact.
                return Ok(vec![(0.0, 0.0); counts.len()]);
            };
            let factor = reference::observable_factor(&pt.observer, &built, &target, lambda)
                .map_err(|e| case_err(case, "$.probe", e))?;
            let arrivals = arrivals_at(
                &built,
                &optics,
                &target,
                &pt.observer,
                &settings(case, &built, deepest),
                &required_paths(case, &built),
            )
            .map_err(|e| case_err(case, "$.probe", e))?;
            let exact =
                reference::value(&spec.references[ri].model, &built, &target, lambda, false)
                    .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
            let (f, cos1) = reference::airy_film(&built, &film, lambda)
                .map_err(|e| case_err(case, "$.references", e))?;
            let ambient = optics.ambient_index;
            counts
                .iter()
                .map(|&(orders, internal)| {
                    let limits = settings(case, &built, internal).limits;
                    let within = within_limits(&arrivals, &limits, ambient);
                    let traced = factor * trace::intensity(&within, Fidelity::Vector);
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
                .collect()
        })
        .collect::<Vec<_>>()
        .into_iter()
        .collect::<Result<_, _>>()?;
    for (k, &(orders, internal)) in counts.iter().enumerate() {
        let res: Vec<(f64, f64)> = per_point.iter().map(|p| p[k]).collect();
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

/// The arrivals of a deeper trace that a trace under `limits` finds, in their order: those
/// with at most `limits.max_internal_reflections` reflections inside a medium other than the
/// ambient one (`ambient`, the index the enumeration counts them against) and at most
/// `limits.max_events` events.
fn within_limits(arrivals: &[Arrival], limits: &EnumerationLimits, ambient: f64) -> Vec<Arrival> {
    arrivals
        .iter()
        .filter(|a| {
            let p = &a.path;
            let reflections = p
                .sequence
                .iter()
                .zip(p.indices.iter())
                .filter(|(e, n)| e.kind == EventKind::Reflect && **n != ambient)
                .count();
            reflections <= limits.max_internal_reflections && p.sequence.len() <= limits.max_events
        })
        .cloned()
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `convergence` relies on: the arrivals of one deep trace that fit a smaller budget
    /// are the arrivals a trace with that budget finds, in the same order and with the same
    /// sequences, so their `vector` intensity is the same to the bit, at every order count of
    /// the report and at probe points across each Airy case of the library.
    #[test]
    fn a_deep_trace_holds_every_smaller_budgets_arrivals() {
        let root = crate::harness::check::library_root().join("cases");
        for name in [
            "plate_airy_s",
            "plate_airy_p",
            "plate_airy_wavelength",
            "thin_film_on_substrate",
            "bk7_dispersion",
            "brewster_extinction",
        ] {
            let case = crate::harness::case::load::load(&root.join(format!("{name}.json")))
                .expect("a library case");
            let points = build::probe_points(&case.spec.probe);
            let stride = points.len().div_ceil(4).max(1);
            for pt in points.iter().step_by(stride) {
                let built = build::build_scene(&case.spec.scene, &pt.overrides).unwrap();
                let lambda = build::spectrum(&case.spec.light, &pt.overrides)[0].0;
                let optics = built.scene.optics(lambda).unwrap();
                let Some(target) = build::propagating_target(&pt.observer, &built, lambda).unwrap()
                else {
                    continue;
                };
                let trace_with = |internal: usize| {
                    arrivals_at(
                        &built,
                        &optics,
                        &target,
                        &pt.observer,
                        &settings(&case, &built, internal),
                        &required_paths(&case, &built),
                    )
                    .unwrap()
                };
                let deep = trace_with(127);
                for orders in super::super::budget::CONVERGENCE_ORDERS {
                    let internal = 2 * orders - 1;
                    let own = trace_with(internal);
                    let limits = settings(&case, &built, internal).limits;
                    let within = within_limits(&deep, &limits, optics.ambient_index);
                    let labels = |arr: &[Arrival]| -> Vec<String> {
                        arr.iter()
                            .map(|a| crate::trace::path::sequence_label(a.path.sequence.iter()))
                            .collect()
                    };
                    assert_eq!(
                        labels(&own),
                        labels(&within),
                        "{name} at {}: {internal} internal reflections",
                        pt.coordinate
                    );
                    let (a, b) = (
                        trace::intensity(&own, Fidelity::Vector),
                        trace::intensity(&within, Fidelity::Vector),
                    );
                    assert_eq!(
                        a.to_bits(),
                        b.to_bits(),
                        "{name} at {}: {internal} internal reflections: own trace {a:e}, \
                         from the deep trace {b:e}",
                        pt.coordinate
                    );
                }
                assert!(!deep.is_empty(), "{name}: no arrivals");
            }
        }
    }
}
