//! The convergence report of a case with an Airy tail bound: the traced sum against the
//! closed form as the order count grows.

use super::*;

/// The Airy reference the report compares with (its index and film), for a monochrome case
/// that has one.
fn airy_reference(case: &Case) -> Option<(usize, String)> {
    let spec = &case.spec;
    if !matches!(spec.light, Light::Monochrome { .. }) {
        return None;
    }
    spec.references
        .iter()
        .enumerate()
        .find_map(|(i, r)| match &r.model {
            ReferenceModel::Airy {
                film,
                index_override: None,
            } => Some((i, film.clone())),
            _ => None,
        })
}

/// The probe points (indices, ascending) the report sums over: at most 24, evenly spread;
/// none where the case has no report.
pub(super) fn convergence_points(case: &Case, n: usize) -> Vec<usize> {
    if airy_reference(case).is_none() {
        return Vec::new();
    }
    let stride = n.div_ceil(24).max(1);
    (0..n).step_by(stride).collect()
}

/// The arrivals of `arrivals` (traced with `traced_internal` internal reflections) that a
/// trace with `internal` internal reflections and at most `max_events` events per path gives,
/// in its order; `None` where that trace is not a part of this one (more internal reflections
/// than traced, or a closed tail whose arrival stands for orders beyond).
///
/// The sequence tree of the smaller budget is the larger one's with every subtree of more
/// internal reflections or events cut (both only grow along a path), and each arrival's ray is
/// formed along its own path from its parent's: the arrivals left are the smaller trace's, bit
/// for bit and in its order (`tests/suite/case_runs.rs` holds it to the trace).
pub fn orders_within(
    arrivals: &[Arrival],
    traced_internal: usize,
    internal: usize,
    max_events: usize,
    ambient_index: f64,
) -> Option<Vec<Arrival>> {
    if internal > traced_internal || arrivals.iter().any(|a| a.tail.is_some()) {
        return None;
    }
    Some(
        arrivals
            .iter()
            .filter(|a| {
                a.internal_reflections(ambient_index) <= internal
                    && a.path.sequence.len() <= max_events
            })
            .cloned()
            .collect(),
    )
}

/// A convergence point's rung-independent part, formed at its first rung: the scene, the
/// optics, the target, the observable factor, the closed form and the film (the same values
/// at every rung), and the arrivals of its deepest trace.
struct PointRungs {
    built: Built,
    lambda: f64,
    optics: crate::scene::SceneOptics,
    target: Target,
    factor: f64,
    exact: f64,
    film: (crate::harness::analytic::plate::Film, f64),
    /// The arrivals traced for the report at the deepest rung (internal reflections, arrivals).
    deepest: Option<(usize, Vec<Arrival>)>,
}

/// A convergence point before its first rung, with no propagating wave, or formed.
enum PointState {
    Fresh,
    Dark,
    Formed(Box<PointRungs>),
}

/// For cases with an Airy reference: the traced error against the number of reflected orders,
/// with the geometric-tail bound. `kept` holds, for the points [`convergence_points`] names,
/// the internal reflections and arrivals of the case run where it kept them: a rung within
/// them is summed from them ([`orders_within`]), any other is traced.
pub(super) fn convergence(
    case: &Case,
    points: &[ProbePoint],
    kept: Vec<Option<(usize, Vec<Arrival>)>>,
) -> Result<Vec<ConvergenceRow>, CaseError> {
    convergence_with(case, points, kept, true)
}

/// [`convergence`]; `deep`: a rung beyond a point's kept arrivals traces the deepest rung of
/// the report once and sums every rung from it ([`orders_within`]: the same arrivals, bit for
/// bit, as a trace of that rung), instead of tracing each rung on its own.
///
/// Each point's scene, optics, target, observable factor, closed form and film are formed at
/// its first rung, in the order a rung forms them (so an error is the one a rung reports), and
/// reused at the others: they do not depend on the rung.
fn convergence_with(
    case: &Case,
    points: &[ProbePoint],
    kept: Vec<Option<(usize, Vec<Arrival>)>>,
    deep: bool,
) -> Result<Vec<ConvergenceRow>, CaseError> {
    let spec = &case.spec;
    let Some((ri, film)) = airy_reference(case) else {
        return Ok(Vec::new());
    };
    let indices = convergence_points(case, points.len());
    let points: Vec<ProbePoint> = indices.iter().map(|&i| points[i].clone()).collect();
    let points = &points[..];
    let kept: Vec<Option<(usize, Vec<Arrival>)>> = if kept.len() == points.len() {
        kept
    } else {
        vec![None; points.len()]
    };
    let mut rows = Vec::new();
    // Never more internal reflections than the case's own budget (the preflight counted it):
    // a kept point's budget is the one its run traced.
    let budget = points
        .iter()
        .zip(&kept)
        .map(|(pt, k)| match k {
            Some((internal, _)) => Ok(*internal),
            None => {
                let built = build::build_scene(&spec.scene, &pt.overrides)
                    .map_err(|e| case_err(case, "$.scene", e))?;
                let lambda = build::spectrum(&spec.light, &pt.overrides)[0].0;
                internal_reflections(case, &built, lambda)
            }
        })
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .max()
        .unwrap_or(0);
    // The deepest rung the report can reach (the loop below stops there at the latest).
    let deepest = super::budget::CONVERGENCE_ORDERS
        .iter()
        .map(|o| 2 * o - 1)
        .take_while(|&internal| internal <= budget.max(1))
        .last();
    let mut states: Vec<PointState> = (0..points.len()).map(|_| PointState::Fresh).collect();
    for orders in super::budget::CONVERGENCE_ORDERS {
        let internal = 2 * orders - 1;
        if internal > budget.max(1) {
            break;
        }
        let res: Vec<(f64, f64)> = points
            .par_iter()
            .zip(&kept)
            .zip(&mut states)
            .map(|((pt, k), state)| -> Result<(f64, f64), CaseError> {
                // The rung-independent part: formed at the first rung, in a rung's order.
                let (mut formed, arrivals) = match std::mem::replace(state, PointState::Dark) {
                    PointState::Dark => return Ok((0.0, 0.0)),
                    PointState::Formed(p) => (p, None),
                    PointState::Fresh => {
                        let lambda = build::spectrum(&spec.light, &pt.overrides)[0].0;
                        let Some((built, optics, target)) = point_at(case, pt, lambda)? else {
                            return Ok((0.0, 0.0)); // no transmitted wave: T = 0 traced and exact
                        };
                        let factor =
                            reference::observable_factor(&pt.observer, &built, &target, lambda)
                                .map_err(|e| case_err(case, "$.probe", e))?;
                        let st = settings(case, &built, internal);
                        let mut deepest_traced = None;
                        let arrivals = rung_arrivals(
                            case,
                            (&built, &optics, &target, &pt.observer),
                            k.as_ref(),
                            &mut deepest_traced,
                            (internal, &st),
                            deep.then_some(deepest).flatten(),
                        )?;
                        let exact = reference::value(
                            &spec.references[ri].model,
                            &built,
                            &target,
                            lambda,
                            false,
                        )
                        .map_err(|e| case_err(case, &format!("$.references[{ri}].model"), e))?;
                        let film = reference::airy_film(&built, &film, lambda)
                            .map_err(|e| case_err(case, "$.references", e))?;
                        let p = PointRungs {
                            built,
                            lambda,
                            optics,
                            target,
                            factor,
                            exact,
                            film,
                            deepest: deepest_traced,
                        };
                        (Box::new(p), Some(arrivals))
                    }
                };
                let arrivals = match arrivals {
                    Some(a) => a,
                    None => {
                        let p = &mut *formed;
                        let st = settings(case, &p.built, internal);
                        rung_arrivals(
                            case,
                            (&p.built, &p.optics, &p.target, &pt.observer),
                            k.as_ref(),
                            &mut p.deepest,
                            (internal, &st),
                            deep.then_some(deepest).flatten(),
                        )?
                    }
                };
                let traced = formed.factor * trace::intensity(&arrivals, Fidelity::Vector);
                let exact = formed.exact;
                let (f, cos1) = formed.film;
                let tau = [
                    crate::harness::analytic::plate::Pol::S,
                    crate::harness::analytic::plate::Pol::P,
                ]
                .into_iter()
                .map(|p| f.tail_bound(cos1, formed.lambda, p, orders))
                .fold(0.0f64, f64::max);
                let bound = 2.0 * exact.sqrt() * tau + tau * tau;
                *state = PointState::Formed(formed);
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

/// The arrivals of one rung (`internal` internal reflections, settings `st`) at a point: the
/// kept arrivals of the case run cut to the rung where they hold it ([`orders_within`]), else
/// those of the point's deepest trace (`deepest`), else a trace: of the rung `deep` (then kept
/// in `deepest` and cut) where given, else of the rung itself. A deep trace that fails, or that
/// cannot be cut, gives way to the rung's own trace, so a rung reports the error its own trace
/// gives.
fn rung_arrivals(
    case: &Case,
    (built, optics, target, observer): (&Built, &crate::scene::SceneOptics, &Target, &Observer),
    kept: Option<&(usize, Vec<Arrival>)>,
    deepest: &mut Option<(usize, Vec<Arrival>)>,
    (internal, st): (usize, &TraceSettings),
    deep: Option<usize>,
) -> Result<Vec<Arrival>, CaseError> {
    let cut = |(traced, arr): &(usize, Vec<Arrival>)| {
        orders_within(
            arr,
            *traced,
            internal,
            st.limits.max_events,
            optics.ambient_index,
        )
    };
    if let Some(arr) = kept.and_then(cut) {
        return Ok(arr);
    }
    if let Some(arr) = deepest.as_ref().and_then(cut) {
        return Ok(arr);
    }
    if let Some(d) = deep.filter(|&d| d > internal && deepest.is_none()) {
        let deep_st = settings(case, built, d);
        if let Ok(arr) = arrivals_at(case, built, optics, target, observer, &deep_st) {
            let traced = (d, arr);
            let within = cut(&traced);
            *deepest = Some(traced);
            if let Some(arr) = within {
                return Ok(arr);
            }
        }
    }
    arrivals_at(case, built, optics, target, observer, st).map_err(|e| case_err(case, "$.probe", e))
}

/// The convergence report of `case` with every rung traced (`convergence` without kept
/// arrivals): what a case run's report ([`CaseResult::convergence`]) equals bit for bit.
pub fn convergence_traced(case: &Case) -> Result<Vec<ConvergenceRow>, CaseError> {
    let points = build::probe_points(&case.spec.probe);
    convergence_with(case, &points, Vec::new(), false)
}
