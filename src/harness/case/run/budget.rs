//! The internal-reflection budget of a probe point (the Airy tail bound, or its exact closure
//! beyond the cap) and the work preflight that refuses an over-budget case before any tracing.

use super::*;

/// Reflected orders traced explicitly where the Airy tail is closed instead of refused
/// (`Budget::closed`): the closure (docs/PHYSICS.md §5a) needs two consecutive traced orders
/// with at least one round trip; a few more keep the traced part what it is below the cap.
pub const CLOSED_TAIL_ORDERS: usize = 8;

/// The internal-reflection budget at a probe point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Budget {
    /// Internal reflections traced per path.
    pub(super) internal: usize,
    /// The Airy tail beyond them is closed exactly ([`trace::tail::close`]) instead of bounded:
    /// the tail bound needs more internal reflections than the cap.
    pub(super) closed: bool,
}

/// The internal-reflection budget at a probe point.
pub(super) fn internal_reflections(
    case: &Case,
    built: &Built,
    lambda_m: f64,
) -> Result<usize, CaseError> {
    budget(case, built, lambda_m).map(|b| b.internal)
}

/// The budget at a probe point: `max_internal_reflections`, or the Airy tail rule: enough
/// orders that the tail bounds of both the reflected and the transmitted wave (in √R and √T,
/// `Film::tail_bound`) are below `airy_tail_epsilon` (the reflected bound alone let a
/// transmitted tail 275 times larger through: fuzz `airy` seed 1 scene 230); where that needs more
/// internal reflections than the cap (near grazing incidence), [`CLOSED_TAIL_ORDERS`] orders
/// with the tail beyond them closed exactly.
pub(super) fn budget(case: &Case, built: &Built, lambda_m: f64) -> Result<Budget, CaseError> {
    let spec = &case.spec;
    let Some(eps) = spec.trace.airy_tail_epsilon else {
        return Ok(Budget {
            internal: spec.trace.max_internal_reflections,
            closed: false,
        });
    };
    let film = spec
        .references
        .iter()
        .find_map(|r| match &r.model {
            ReferenceModel::Airy { film, .. } => Some(film.clone()),
            _ => None,
        })
        .ok_or_else(|| {
            case_err(
                case,
                "$.trace.airy_tail_epsilon",
                "needs an `airy` reference naming the film",
            )
        })?;
    let (f, cos1) = reference::airy_film(built, &film, lambda_m)
        .map_err(|e| case_err(case, "$.references", e))?;
    let pols = [
        crate::harness::analytic::plate::Pol::S,
        crate::harness::analytic::plate::Pol::P,
    ];
    // Beyond the critical angle of the film's top face the film carries no propagating wave:
    // the traced reflection (r_layer) and tunnelled wave (t_layer) are the whole Airy sum
    // (docs/PHYSICS.md §5), with no orders inside the film and no tail to bound or close. The
    // verdict is the tracer's ((n2 cos θ2)² < 0 from the double-double normal wavevector,
    // `interaction::normal_wavevector_squares`), with a margin of 1e-12 n1² so that no
    // rounding of the direction can put the tracer on the other side: an f64 cos θ1 called
    // films 1e-10 below the critical angle frustrated, and their orders were cut (fuzz `airy`
    // seed 1, near_critical scenes such as 77). Inside the margin the tail rule below applies.
    // Before this rule such points asked for a tail bound that does not decay (|r| = 1 inside)
    // and were refused as "the tail cannot be closed exactly" (fuzz `airy` seed 1: 13 of 300
    // scenes, e.g. 6, 55, 119, 285).
    // Only where no index depends on the wavelength: the budget is taken at one wavelength of
    // the spectrum, and a dispersive film evanescent there may carry a propagating wave at
    // another, whose orders one internal reflection would cut silently.
    let dispersionless = built.media.values().all(|m| {
        matches!(
            m.dispersion,
            crate::optics::material::Dispersion::Constant { .. }
        )
    });
    let top = built
        .surface(&format!("{film}.top"))
        .map_err(|e| case_err(case, "$.references", e))?;
    let direction = built.scene.sources.iter().find_map(|s| match s.emitter {
        crate::scene::source::Emitter::PlaneWave { direction, .. } => Some(direction),
        _ => None,
    });
    if let Some(d) = direction {
        let normal = built.scene.surfaces[top].plane.normal;
        let (_, q2_2) =
            crate::optics::interaction::normal_wavevector_squares(d, normal, (f.n1, f.n2), None);
        if dispersionless && q2_2.hi < -1e-12 * f.n1 * f.n1 {
            return Ok(Budget {
                internal: 3,
                closed: false,
            });
        }
    }
    // The most orders the cap allows (2 N + 1 internal reflections); the bound decreases with
    // N, so the bound needs more than the cap exactly when it is not met at N.
    let cap = crate::harness::case::load::limits::MAX_INTERNAL_REFLECTIONS;
    let most = (cap - 1) / 2;
    if pols
        .into_iter()
        .any(|p| f.tail_bound(cos1, lambda_m, p, most) > eps)
    {
        return Ok(Budget {
            internal: 2 * CLOSED_TAIL_ORDERS + 1,
            closed: true,
        });
    }
    let orders = pols
        .into_iter()
        .map(|p| f.orders_for_tail_bound(cos1, lambda_m, p, eps))
        .max()
        .unwrap_or(1);
    // The bound holds only if every order it asks for is traced: never cap silently.
    Ok(Budget {
        internal: 2 * orders + 1,
        closed: false,
    })
}

/// The most a sum cut by the Airy tail rule can be off the full sum, in the units of the
/// observable `observed` (R or T times the source intensity): the left-out orders' amplitude is
/// at most ε √I0 in √R or √T units ([`budget`], `Film::tail_bound`), so
/// |δO| ≤ 2 √O ε √I0 + ε² I0. `sqrt_source` is √I0 (Σ over the sources of √I_k). The derived
/// tolerance (docs/PHYSICS.md §8) adds it: the traced value is that truncation by the case's own
/// request, not a rounding (fuzz `airy` seed 1 scene 230: ε = 1e-12 left 2.5e-12 of T out).
pub fn tail_truncation(observed: f64, epsilon: f64, sqrt_source: f64) -> f64 {
    let d = epsilon * sqrt_source;
    2.0 * observed.abs().sqrt() * d + d * d
}

/// Work units (see [`preflight`]) a case may use before it is refused: about 220 CPU-seconds
/// at [`SECONDS_PER_WORK_UNIT`], about two minutes of wall time on the idle 2-core machine of
/// this project (more when it is busy). The Airy plate with 2000 internal reflections at 2000 angles
/// (about 3.7e8 units) is accepted; three plates stacked in air under a point source (2.4e8 units,
/// 96–117 s measured) too; four are refused.
pub const MAX_PATH_EVENTS: f64 = 5.0e8;

/// Measured CPU-seconds (all threads) per work unit, used only to state the estimate in time.
/// Calibrated with `benches/preflight.rs` (CPU time from `CLOCK_PROCESS_CPUTIME_ID`, short
/// scenes repeated to at least 0.5 CPU-s) on the project's idle 2-core Intel Xeon VM, in two
/// series of 29 November 2026 (fourteenth session's merge, and the fifteenth session's merge
/// 1.2–1.4× slower in a slower phase of the VM), together with [`SOLVED_UNITS`],
/// [`WALKED_SAMPLE_SCALE`], [`SAMPLE_UNITS`], [`FURTHER_SAMPLE_UNITS`], `WALKED_NODE_UNITS`,
/// `WALKED_EVENT_UNITS` and [`MOVED_TRACE`], fitted so that every benched scene (the 17 library
/// cases, 1 to 3 stacked plates, 40 internal reflections, the Airy walk at m = 2000) lands
/// within 2× of its estimate in both series: measured / estimate 0.52 (`tir_interference`,
/// plane waves onto a point, in the faster series) to 1.92 (`lloyd_mirror`; `michelson` and
/// `thin_film_on_substrate` 1.90–1.91, in the slower one); README "Limits" gives the table and the command. (Before: 5e-7 with one
/// per-sample term for every point and the solved events at one unit, which put `fresnel_rhomb`
/// at 0.48 in the faster series and `michelson` at 2.09 in the slower one; 4.4e-7 to 1.05e-6 on
/// an AMD EPYC VM at an earlier runner.)
pub const SECONDS_PER_WORK_UNIT: f64 = 4.44e-7;

/// Work units of one spectral sample at one probe point besides its tracing: the contributions
/// at every fidelity level, the conditioning terms, the closed-form references and the
/// observable factor (about 9 µs on the Intel Xeon VM), for a point whose paths are solved
/// (a point observer); a far-field point of plane waves costs [`WALKED_SAMPLE_SCALE`] of it.
/// Without it the cheapest library cases (two slits or two point sources, a few units of
/// tracing per point) were estimated 11–18 times below their run (young_paper,
/// incoherent_sources; `benches/preflight.rs`).
pub const SAMPLE_UNITS: f64 = 20.0;

/// The per-sample terms ([`SAMPLE_UNITS`], [`FURTHER_SAMPLE_UNITS`]) of a far-field point of
/// plane waves (walked) relative to a solved point's: one reference and no detection geometry
/// per sample (fitted with [`SECONDS_PER_WORK_UNIT`]).
pub const WALKED_SAMPLE_SCALE: f64 = 0.8;

/// Work units per discovery visit and per solved event of a point whose paths are solved (a
/// point observer), relative to the walk's: the solver's Newton iterations per event (fitted
/// with [`SECONDS_PER_WORK_UNIT`]; at 1, `michelson`, a point source over four surfaces, ran
/// at 2.1 times its estimate in the slower series).
pub const SOLVED_UNITS: f64 = 1.35;

/// The cost of moving a point's traced arrivals to the next point's wavelength (the same
/// scene, observer and budget: `trace_point` relabels every arrival instead of tracing), as a
/// fraction of tracing them: plate_airy_wavelength (301 wavelengths, one trace) ran at 1.8
/// times its estimate when a moved point counted no tracing (`benches/preflight.rs`).
pub const MOVED_TRACE: f64 = 0.15;

/// Work units of each further spectral sample of a probe point besides its tracing: the
/// contributions at every fidelity level and the closed-form references again, without the
/// point's set-up (about 3 µs on the Intel Xeon VM: coherence_length, 129 samples per point,
/// ran at 0.35 of its estimate when every sample counted [`SAMPLE_UNITS`];
/// `benches/preflight.rs`).
pub const FURTHER_SAMPLE_UNITS: f64 = 6.4;

/// The reflected orders of the rungs of the bounce-convergence report of monochrome Airy cases
/// (`convergence::convergence`), each traced at 2·orders − 1 internal reflections while that is
/// within the case's budget.
pub(super) const CONVERGENCE_ORDERS: [usize; 12] = [1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64];

/// Work units of tracing one node of the sequence tree in the far-field walk (both polarized
/// models, extents and blockers), beside its discovery visits: about one more visit. It was
/// 20 when the walk's cost was taken to be linear in m; calibrated with its per-event part
/// ([`WALKED_EVENT_UNITS`]) against the library Airy cases and the Airy plate at m = 2000
/// (`benches/preflight.rs`, README "Limits").
const WALKED_NODE_UNITS: f64 = 1.0;

/// Work units per event of every traced path under the far-field walk: the walk shares each
/// path's beginning with the next order's, but the case run still passes over every arrival's
/// whole path (the phase ledger, the rounding and representation terms of
/// `harness::conditioning`) at every spectral sample, so an Airy point with m internal
/// reflections costs a part ∝ m (the walk) and a part ∝ m² (those passes). Calibrated with
/// `benches/preflight.rs` against the Airy plate at m = 2000 (0.04 put its run at 1.58 times
/// the estimate on the Intel Xeon VM, 29 November 2026).
const WALKED_EVENT_UNITS: f64 = 0.05;

/// The work of one point at its budget, in two parts that scale differently with the budget m.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PointWork {
    /// Units that grow like m + 2 (the far-field walk and its discovery).
    linear: f64,
    /// Units that grow like (m + 2)² (every event of every candidate sequence: the solver
    /// tracing each path, or the case run's passes over the walked paths).
    quadratic: f64,
}

/// The work of one probe point at one wavelength, counted on the sequence tree the tracer
/// itself discovers there (`trace::plan`): every probe ray of discovery visits at most every
/// node of the tree (one unit each), and the solver then traces every candidate sequence event
/// by event (one unit per event), or, for a plane wave observed in the far field, every node
/// of the tree once (the walk of shared beginnings, [`WALKED_NODE_UNITS`] per node) and the
/// case run passes over every event of every walked path ([`WALKED_EVENT_UNITS`] each).
/// Returns (work, measured): `measured` is false when the tree grew so fast with
/// the allowed depth that the work was extrapolated (polynomially from the last doubling of the
/// depth, which under-counts an exponential growth) instead of enumerated, because it already
/// exceeds `cap`.
fn point_work(
    case: &Case,
    pt: &ProbePoint,
    internal: usize,
    cap: f64,
) -> Result<(PointWork, bool), CaseError> {
    let spec = &case.spec;
    let built =
        build::build_scene(&spec.scene, &pt.overrides).map_err(|e| case_err(case, "$.scene", e))?;
    let spectrum = build::spectrum(&spec.light, &pt.overrides);
    let lambda = spectrum[spectrum.len() / 2].0;
    let optics = built
        .scene
        .optics(lambda)
        .map_err(|e| case_err(case, "$.light", e.to_string()))?;
    let nothing = PointWork {
        linear: 0.0,
        quadratic: 0.0,
    };
    let Some(target) = build::propagating_target(&pt.observer, &built, lambda)
        .map_err(|e| case_err(case, "$.probe", e))?
    else {
        return Ok((nothing, true)); // no transmitted wave: nothing is traced
    };
    let walked = walked(&built, pt);
    let probe = probe_targets(&target);
    // trace::plan's probe rays per source: the probe points, each surface's plane point and the
    // specular points of the probe on each plane.
    let rays = (probe.len()
        + built.scene.surfaces.len() * (1 + probe.len() * built.scene.sources.len()))
        as f64;
    let full = settings(case, &built, internal).limits;
    let mut depth = full.max_events.min(8);
    let mut previous: Option<f64> = None;
    loop {
        let limits = EnumerationLimits {
            max_events: depth,
            ..full
        };
        let plan = trace::plan(&built.scene, &optics, &probe, &limits);
        let (mut nodes, mut events) = (0.0, 0.0);
        for tree in &plan.sequences {
            nodes += tree.nodes().len() as f64;
            events += tree
                .nodes()
                .iter()
                .filter(|n| n.candidate)
                .map(|n| n.depth as f64)
                .sum::<f64>();
        }
        let work = if walked {
            PointWork {
                linear: (rays + WALKED_NODE_UNITS) * nodes,
                quadratic: WALKED_EVENT_UNITS * events,
            }
        } else {
            PointWork {
                linear: 0.0,
                quadratic: SOLVED_UNITS * (rays * nodes + events),
            }
        };
        let total = work.linear + work.quadratic;
        if depth == full.max_events {
            return Ok((work, true));
        }
        if let Some(w0) = previous {
            let p = (total / w0).log2().max(0.0);
            let grow = (full.max_events as f64 / depth as f64).powf(p);
            // Stop early only where the refusal is clear: the work counted so far already
            // exceeds the cap, or the extrapolation exceeds it 4-fold (from a shallow depth it
            // can overshoot a polynomial growth by a third: the walked Airy plate at m = 2000,
            // whose part in m² takes over only with depth; it under-counts an exponential one).
            if total > cap || total * grow > 4.0 * cap {
                let predicted = PointWork {
                    linear: work.linear * grow,
                    quadratic: work.quadratic * grow,
                };
                return Ok((predicted, false));
            }
        }
        previous = Some(total);
        depth = (2 * depth).min(full.max_events);
    }
}

/// Whether a point is traced by the far-field walk: a far-field observer lit by plane waves only.
fn walked(built: &Built, pt: &ProbePoint) -> bool {
    !matches!(pt.observer, Observer::Point { .. })
        && built
            .scene
            .sources
            .iter()
            .all(|s| matches!(s.emitter, Emitter::PlaneWave { .. }))
}

/// The tracing work of a case, checked before anything runs, in work units (one unit: a probe
/// ray of sequence discovery visiting one node of the sequence tree, or the solver tracing one
/// surface event; about `SECONDS_PER_WORK_UNIT` each). The tree is enumerated as the tracer enumerates it, at the probe point with
/// the largest internal-reflection budget (the Airy tail rule may raise it near grazing
/// incidence up to the cap; beyond it the budget is [`CLOSED_TAIL_ORDERS`] orders and the
/// closed tail, one arrival of O(1) work per channel, docs/PHYSICS.md §5a), so the count follows the surfaces: reflections between separate surfaces in
/// the ambient medium are not internal reflections, and stacked plates multiply the sequences
/// (the tree is enumerated with doubling depth and refused as soon as it outgrows the cap).
/// Every other point costs the same, scaled by its own budget m as the tracer scales
/// (the walk of a plane wave in the far field: its part ∝ (m + 2) and its per-event part
/// ∝ (m + 2)²; otherwise (m + 2)²): the tracing once per point where no index depends on the
/// wavelength (the tracer moves one trace's arrivals to every other sample), else once per
/// spectral sample, and the passes over the walked paths once per sample; every sample of
/// every point adds [`SAMPLE_UNITS`] (what a sample costs besides its tracing); the bounce-convergence report of monochrome Airy cases adds its ladder of
/// budgets (`CONVERGENCE_ORDERS`) at up to 24 of the points where a rung exceeds the point's own budget (the rungs within it are summed from the arrivals traced). A case over `MAX_PATH_EVENTS` is refused with the estimate (units
/// and seconds) and the key that drives it.
pub fn preflight(case: &Case) -> Result<f64, CaseError> {
    work_estimate(case).map(|e| e.units())
}

/// A case's work estimate in its two parts (work units, every point and wavelength weighted):
/// what grows like the internal-reflection budget and what grows like its square
/// ([`preflight`] is their sum; `benches/preflight.rs` calibrates the constants with them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorkEstimate {
    /// The far-field walk and its discovery (∝ m + 2 per point).
    pub linear_units: f64,
    /// Every event of every candidate sequence (∝ (m + 2)² per point), and everything of a
    /// point that is not walked.
    pub quadratic_units: f64,
    /// [`SAMPLE_UNITS`] per spectral sample of every probe point: what a sample costs besides
    /// its tracing, whatever the budget.
    pub sample_units: f64,
}

impl WorkEstimate {
    /// The whole estimate, work units.
    pub fn units(&self) -> f64 {
        self.linear_units + self.quadratic_units + self.sample_units
    }
}

/// [`preflight`] with its two parts; refuses the same cases with the same message.
pub fn work_estimate(case: &Case) -> Result<WorkEstimate, CaseError> {
    let spec = &case.spec;
    let points = build::probe_points(&spec.probe);
    let mut budgets = Vec::with_capacity(points.len());
    let mut previous: Option<(usize, Observer, crate::scene::Scene)> = None;
    for pt in &points {
        let built = build::build_scene(&spec.scene, &pt.overrides)
            .map_err(|e| case_err(case, "$.scene", e))?;
        let spectrum = build::spectrum(&spec.light, &pt.overrides);
        let internal = internal_reflections(case, &built, spectrum[spectrum.len() / 2].0)?;
        // `trace_point` traces a spectrum through media whose indices do not depend on the
        // wavelength once, and moves the arrivals to every other sample (`at_wavelength`).
        let dispersionless = built.media.values().all(|m| {
            matches!(
                m.dispersion,
                crate::optics::material::Dispersion::Constant { .. }
            )
        });
        // `trace_point` also moves the previous point's arrivals to this one where the scene,
        // observer and budget are the same (a sweep of the wavelength only): no new trace,
        // [`MOVED_TRACE`] of one.
        let same = previous
            .as_ref()
            .is_some_and(|(m, o, sc)| *m == internal && *o == pt.observer && *sc == built.scene);
        let samples = spectrum.len() as f64;
        let traces = match (dispersionless, same) {
            (true, true) => MOVED_TRACE,
            (true, false) => 1.0,
            (false, _) => samples,
        };
        budgets.push((internal, walked(&built, pt), traces, samples));
        previous = Some((internal, pt.observer.clone(), built.scene));
    }
    let sample_units = budgets
        .iter()
        .map(|b| {
            let scale = if b.1 { WALKED_SAMPLE_SCALE } else { 1.0 };
            scale * (SAMPLE_UNITS + FURTHER_SAMPLE_UNITS * (b.3 - 1.0))
        })
        .sum::<f64>();
    // The representative point: the largest budget, the centre among equals.
    let centre = points.len() / 2;
    let worst = budgets.iter().map(|b| b.0).max().unwrap_or(0);
    let rep = if budgets[centre].0 == worst {
        centre
    } else {
        budgets.iter().position(|b| b.0 == worst).unwrap_or(centre)
    };
    // Each point relative to the representative one: the weights of its linear and its
    // quadratic part. The tracing (the walk and its discovery, or the solver) counts once per
    // trace of the point; the case run's passes over the walked paths once per sample.
    let scale = |&(m, walked, traces, samples): &(usize, bool, f64, f64)| {
        let r = (m as f64 + 2.0) / (worst as f64 + 2.0);
        if walked {
            (traces * r, samples * r * r)
        } else {
            (traces * r * r, traces * r * r)
        }
    };
    let (mut linear_weight, mut quadratic_weight) = budgets
        .iter()
        .map(scale)
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let convergence_report = matches!(spec.light, Light::Monochrome { .. })
        && spec.references.iter().any(|r| {
            matches!(
                r.model,
                ReferenceModel::Airy {
                    index_override: None,
                    ..
                }
            )
        });
    if convergence_report {
        // convergence::convergence: at every `stride`-th point (at most 24), the rungs
        // 2·orders − 1 of its ladder up to the largest budget of those points; a rung within
        // the point's own budget is summed from the arrivals its run traced
        // (`run::orders_within`), a larger one is traced, scaled like a point of that budget.
        let stride = points.len().div_ceil(24).max(1);
        let sampled: Vec<&(usize, bool, f64, f64)> = budgets.iter().step_by(stride).collect();
        let top = sampled.iter().map(|b| b.0).max().unwrap_or(0).max(1);
        for orders in CONVERGENCE_ORDERS {
            let internal = 2 * orders - 1;
            if internal > top {
                break;
            }
            for &&(own, walked, _, _) in &sampled {
                if internal > own {
                    let (l, q) = scale(&(internal, walked, 1.0, 1.0));
                    linear_weight += l;
                    quadratic_weight += q;
                }
            }
        }
    }
    // Enumeration stops early only where the part it has counted already exceeds the cap at
    // the smaller weight, so the case is refused whatever the split.
    let least = linear_weight.min(quadratic_weight);
    let (per_point, measured) = point_work(case, &points[rep], worst, MAX_PATH_EVENTS / least)?;
    let estimate = WorkEstimate {
        linear_units: per_point.linear * linear_weight,
        quadratic_units: per_point.quadratic * quadratic_weight,
        sample_units,
    };
    let work = estimate.units();
    if work > MAX_PATH_EVENTS {
        let key = if spec.trace.airy_tail_epsilon.is_some() {
            "$.trace.airy_tail_epsilon"
        } else {
            "$.trace.max_internal_reflections"
        };
        return Err(case_err(
            case,
            key,
            format!(
                "this case would take {} {work:.2e} work units (≈ {:.0} s on the 2-core \
                 machine of this project), more than the work cap of {MAX_PATH_EVENTS:.0e}: \
                 {} surface(s) with up to {worst} internal reflections give {:.2e} \
                 units per probe point and wavelength (sequence discovery and solving; \
                 reflections between separate surfaces in the ambient medium multiply the \
                 sequences), times {} probe point(s) (and their spectral samples through \
                 dispersive media), plus {SAMPLE_UNITS} units per point and sample: use fewer \
                 surfaces, internal reflections, probe points or spectral samples",
                if measured { "about" } else { "at least" },
                work * SECONDS_PER_WORK_UNIT,
                spec.scene.surfaces.len(),
                per_point.linear + per_point.quadratic,
                points.len()
            ),
        ));
    }
    Ok(estimate)
}
