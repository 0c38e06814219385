//! Tracing one probe point: the trace settings of a case, the paths its references require
//! (a required path that does not land refuses the case), and the arrivals.

use super::*;

/// The tracer settings of a case at a probe point: its internal-reflection budget (or the Airy
/// tail rule at `lambda_m`), spreading as configured.
pub fn trace_settings(
    case: &Case,
    built: &Built,
    lambda_m: f64,
) -> Result<TraceSettings, CaseError> {
    let b = budget(case, built, lambda_m)?;
    if b.closed {
        // Only the case runner closes the tail (trace::tail::close): a caller of these settings
        // would trace a cut sum.
        return Err(case_err(
            case,
            "$.trace.airy_tail_epsilon",
            format!(
                "the Airy tail bound {:e} needs more internal reflections than the cap of {} \
                 here (near grazing incidence); `fringe check` closes that tail exactly, this \
                 command does not: loosen airy_tail_epsilon or move away from grazing",
                case.spec.trace.airy_tail_epsilon.unwrap_or(0.0),
                crate::harness::case::load::limits::MAX_INTERNAL_REFLECTIONS
            ),
        ));
    }
    Ok(settings(case, built, b.internal))
}

pub(super) fn settings(case: &Case, built: &Built, internal: usize) -> TraceSettings {
    TraceSettings {
        limits: EnumerationLimits {
            max_internal_reflections: internal,
            max_events: 2 * internal + 2 * built.scene.surfaces.len() + 4,
        },
        solve: SolveOptions {
            spreading: case.spec.trace.spreading,
            ..SolveOptions::default()
        },
        ..TraceSettings::default()
    }
}

pub(super) fn probe_targets(target: &Target) -> Vec<DVec3> {
    match target {
        Target::Point(p) => vec![*p],
        Target::Direction { reference, .. } => vec![*reference],
    }
}

/// The paths a case's references model that exist in every scene the reference accepts, so a
/// solver that does not land one has lost a beam: for `two_beam_plate`, the top reflection and
/// the beam through the plate (Snell's invariant has its root at any lateral distance; over a
/// plate thinner than its ambient, beyond the top face's critical angle, the beam enters below
/// it nearer the source and runs grazing inside: docs/PHYSICS.md §5).
pub(super) fn required_paths(case: &Case, built: &Built) -> Vec<Vec<crate::trace::path::Event>> {
    use crate::trace::path::Event;
    let mut out = Vec::new();
    for r in &case.spec.references {
        if let ReferenceModel::TwoBeamPlate { plate } = &r.model
            && let (Ok(top), Ok(bottom)) = (
                built.surface(&format!("{plate}.top")),
                built.surface(&format!("{plate}.bottom")),
            )
        {
            let ev = |surface, kind| Event { surface, kind };
            out.push(vec![ev(top, EventKind::Reflect)]);
            out.push(vec![
                ev(top, EventKind::Refract),
                ev(bottom, EventKind::Reflect),
                ev(top, EventKind::Refract),
            ]);
        }
    }
    out
}

/// All arrivals at a target that the observer records, or why a path that exists could not be
/// traced: a path of [`required_paths`] whose solver fails for any reason but an obstruction
/// (`Blocked`, `OutOfExtent`: a scene that shields a beam) is a beam the tracer failed to find, and dropping it would lose
/// it silently (a two-beam plate lost its second beam so and was 0.25 off,
/// `tests/suite/truth_plates.rs`); the case is refused with that reason instead. (Other
/// sequences that do not converge are, as before, taken as paths that do not exist.)
pub(super) fn arrivals_at(
    case: &Case,
    built: &Built,
    optics: &crate::scene::SceneOptics,
    target: &Target,
    observer: &Observer,
    st: &TraceSettings,
) -> Result<Vec<Arrival>, String> {
    let required = required_paths(case, built);
    let plan = trace::plan(&built.scene, optics, &probe_targets(target), &st.limits);
    let (mut arr, failed) = trace::arrivals(&built.scene, optics, &plan, target, st);
    if let Some(f) = failed.iter().find(|f| {
        !matches!(
            f.error,
            PathError::Blocked { .. } | PathError::OutOfExtent { .. }
        ) && required.iter().any(|q| f.sequence.iter().eq(q.iter()))
    }) {
        return Err(format!(
            "the path solver could not land the path {} on a probe point ({}): the beam \
             exists (Snell's invariant has its root at any lateral distance) but the solver did \
             not find it to 1e-12 of the scene; the case is refused rather than traced without \
             it (a solver defect, not a limit of the scene: report it)",
            crate::trace::path::sequence_label(f.sequence.iter()),
            f.error
        ));
    }
    arr.retain(|a| build::records(observer, a.vector.dir));
    Ok(arr)
}

/// Group-summed field of the arrivals at one level (for retardance).
pub(super) fn summed_field(
    arr: &[Arrival],
    level: Fidelity,
) -> Option<[num_complex::Complex64; 3]> {
    let mut acc = Accumulator::new();
    for c in trace::contributions(arr, level) {
        acc.add(&c);
    }
    acc.groups().first().map(|(_, e)| *e)
}
