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
    let dispersionless = super::dispersionless(&built.scene);
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

/// Work units (see [`preflight`]) a case may use before it is refused: about 380 CPU-seconds
/// at [`SECONDS_PER_WORK_UNIT`], about three minutes of wall time on the idle 2-core machine
/// of this project (more when it is busy). The Airy plate with 2000 internal reflections at
/// 2000 angles (7.4e8 units; 200 angles ran 27–40 CPU-s) is accepted; three plates stacked in
/// air under a point source (2.1e8 units, 81–140 CPU-s measured in seven series) too; four are
/// refused. It was 5e8 while the estimate under-counted the Airy walk by 1.75× (the same
/// 2000-angle plate at 3.7e8 units): raised with the estimate so that the cap admits the same
/// cases. The seventeenth session's refit kept the scale of the units (the same rate).
pub const MAX_PATH_EVENTS: f64 = 8.0e8;

/// Measured CPU-seconds (all threads) per work unit, used only to state the estimate in time;
/// the per-count constants ([`SAMPLE_UNITS`], [`TRACE_UNITS`], [`TAIL_RULE_UNITS`],
/// [`VISIT_UNITS`], [`DEPTH_SQUARE_UNITS`], [`SURFACE_DEPTH_SQUARE_UNITS`],
/// [`NEWTON_EVENT_UNITS`], [`NODE_UNITS`], [`WALKED_EVENT_UNITS`], and the weight
/// [`MOVED_TRACE`]) are in these units. Calibrated with `benches/preflight.rs` (CPU time from
/// `CLOCK_PROCESS_CPUTIME_ID`, short scenes repeated to at least 0.5 CPU-s) on the project's
/// 2-core Intel Xeon VM.
///
/// Procedure (29 November 2026, seventeenth session). A throw-away instrumentation of the
/// tracer and of `run::run` (never committed: solver calls, their traces of the planes,
/// Newton iterations, thread CPU time of discovery, of the solver or walk and of the rest of
/// each point) on the benched scenes showed what the counts of the sixteenth session missed:
/// the two-beam plates' solver launches every sequence exactly (one trace of the planes per
/// sequence, 16 µs per point), `michelson`'s (a tilted splitter) and `lloyd_mirror`'s (a line
/// source) start from a guess and take 15 and 11 traces per sequence (86 and 14 µs per point):
/// [`NEWTON_EVENT_UNITS`]; and the walk's passes over the arrivals' paths are per trace since
/// the sixteenth session's merge (the conditioning terms formed once per trace): the fit leaves
/// nothing to a per-sample part. The constants were then fitted in log space to the seven
/// recorded series of `tests/suite/preflight.rs` (numpy, throw-away), minimising the largest of
/// the seven spreads max/min of measured / estimate within a series (a soft maximum, Adam from
/// 8 random starts, then sharpened), rounded to three digits, and scaled together so that the
/// lowest and the highest ratio over all series are symmetric about 1 at this rate (unchanged,
/// so that the units keep their scale). Result: spreads 1.454, 1.423, 1.453, 1.460, 1.425,
/// 1.461, 1.454 in the seven series (before: 1.78, 1.88, 1.78, 1.83, 1.80, 1.92, 1.87), all
/// runs within 0.617–1.623 of the estimate (before: 0.545–1.846). One free number per scene
/// (with `plate_airy_p` and `plate_airy_s`, whose counts are the same, as one) could do no
/// better than 1.40 in the worst series: what is left is mostly the runs' own scatter between
/// series (`bk7_dispersion` over `thin_film_on_substrate` from 0.95 to 1.40, the case run having
/// changed between the fourth and the fifth series). The scenes at the ends: the Airy plates,
/// `bk7_dispersion` and two stacked plates low; `brewster_extinction`, `incoherent_sources`
/// and `plate_two_beam_unpolarized` high. Checked on two series the fit did not see (21:29 and
/// 21:33 UTC, another helper's build running, load average 1.8–4.1): spreads 1.84 (the VM sped
/// up half-way through it: `plate_two_beam_paper` at 1.22 and the same case as `1 stacked
/// plate(s)` at 0.87 minutes later) and 1.33, every run within 0.79–1.45 of the estimate; the
/// sixteenth session's constants on the same two series: 2.50 and 1.83, 0.68–1.69.
/// History: the sixteenth session fitted the same way on
/// three series (0.65–1.16 and 0.81–1.53 idle, 1.01–1.79 loaded) and set this rate, 4.8e-7, as
/// the geometric centre of the idle series' ends when a third idle series, 40 minutes after two
/// others, ran 1.9× slower (the VM's own phases: numpy's accumulation bench at half its speed).
pub const SECONDS_PER_WORK_UNIT: f64 = 4.8e-7;

/// The cost of moving a point's traced arrivals to the next point's wavelength (the same
/// scene, observer and budget: `trace_point` relabels every arrival instead of tracing), as a
/// fraction of tracing them. It was 0.15 when plate_airy_wavelength (301 wavelengths, one
/// trace) ran at 1.8 times its estimate with a moved point counted as no tracing (the parallel
/// workers each start with a trace of their own: 19 traces of 301 points, while a move itself
/// costs next to nothing); refitted with the other constants ([`SECONDS_PER_WORK_UNIT`]) to
/// 0.05: at 0.15 the sweep sat at the low end of every series (0.60–1.08 of its estimate), its
/// tail-rule set-up ([`TAIL_RULE_UNITS`]) now priced higher.
pub const MOVED_TRACE: f64 = 0.05;

/// The reflected orders of the rungs of the bounce-convergence report of monochrome Airy cases
/// (`convergence::convergence`), each traced at 2·orders − 1 internal reflections while that is
/// within the case's budget.
pub(super) const CONVERGENCE_ORDERS: [usize; 12] = [1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64];

/// How a probe point is traced, which sets the price of its counts ([`WorkCounts`]); the
/// index of the per-kind cost tables below.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PointKind {
    /// A point observer lit by at least one point source: discovery, then the solver's
    /// Newton iterations on every candidate sequence.
    SolvedPointSource = 0,
    /// A point observer lit by plane waves only: discovery, then the solver.
    SolvedPlaneWave = 1,
    /// A far-field observer lit by plane waves only: the far-field walk of shared beginnings.
    Walked = 2,
}

/// The counts the preflight makes before anything is traced, each summed over the probe points
/// of one [`PointKind`] (the index). The sequence tree is enumerated as the tracer discovers it
/// (`trace::plan`) at one representative point (the largest budget m), and another point's
/// count is that one times r = (m + 2)/(m_rep + 2) for what grows like m (nodes of the walk) or
/// r² for what grows like m² (discovery visits, Σ depth² and the events of the candidates),
/// times the traces of the point. A point's traces: 1 for a spectrum through non-dispersive
/// media (traced once and moved to the other wavelengths), [`MOVED_TRACE`] for a point that
/// moves the previous point's arrivals, else its samples; a point of the bounce-convergence
/// report with rungs beyond its budget adds one trace at the deepest rung.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WorkCounts {
    /// Spectral samples of every probe point.
    pub samples: [f64; 3],
    /// Traces (see above; without the convergence rungs).
    pub traces: [f64; 3],
    /// Probe points whose budget the Airy tail rule sets (`airy_tail_epsilon`).
    pub tail_rule_points: [f64; 3],
    /// Discovery visits per trace: `trace::plan`'s probe rays times the nodes of the tree.
    pub visits: [f64; 3],
    /// Σ over the candidate sequences of their depth squared, per trace.
    pub depth_squares: [f64; 3],
    /// Σ over the candidate sequences of their depth squared times the surfaces of the scene,
    /// per trace ([`SURFACE_DEPTH_SQUARE_UNITS`]).
    pub surface_depth_squares: [f64; 3],
    /// Events of the candidate sequences the path solver cannot launch exactly, per trace
    /// ([`NEWTON_EVENT_UNITS`]).
    pub newton_events: [f64; 3],
    /// Nodes of the tree per trace.
    pub nodes: [f64; 3],
    /// Events of every candidate sequence, per trace.
    pub events: [f64; 3],
}

/// Work units per spectral sample of a probe point, whatever its kind: the contributions at
/// every fidelity level, the closed-form references, the conditioning terms' wavelength parts
/// (4.3 µs measured per sample of coherence_length, 129 samples per point, with the per-phase
/// instrumentation of [`SECONDS_PER_WORK_UNIT`]). Fitted to the seven series with the other
/// constants ([`SECONDS_PER_WORK_UNIT`]); carried by coherence_length (0.9 of its estimate).
pub const SAMPLE_UNITS: f64 = 9.88;

/// Work units per trace, by [`PointKind`], besides the counted tree: the scene built, the
/// probe rays formed, the arrivals' rays and the per-point closed forms (measured 5–15 µs of
/// set-up per point besides discovery and solving under a point source, 13–28 µs per walked
/// point without the tail rule). Plane waves solved onto a point (`tir_interference`,
/// `wedge_fizeau`) cost their trace almost whatever the tree. Fitted to the seven series
/// ([`SECONDS_PER_WORK_UNIT`]).
pub const TRACE_UNITS: [f64; 3] = [21.2, 39.4, 24.5];

/// Work units per probe point whose internal-reflection budget the Airy tail rule sets: the
/// tail bounds of both polarizations searched order by order, and the film's closed forms
/// (measured 49–75 µs per point besides the walk in the tail-rule library cases, against
/// 13–28 µs without the rule). Fitted to the seven series ([`SECONDS_PER_WORK_UNIT`]);
/// carried by plate_airy_wavelength.
pub const TAIL_RULE_UNITS: f64 = 141.0;

/// Work units per discovery visit (a probe ray at a node of the tree) of a point lit by a point
/// source, by [`PointKind`]. Plane waves onto a point: the fit leaves nothing to their visits
/// ([`TRACE_UNITS`] and [`DEPTH_SQUARE_UNITS`] carry them); the walk's discovery is priced per
/// node ([`NODE_UNITS`]). Fitted to the seven series ([`SECONDS_PER_WORK_UNIT`]); the wide
/// trees of stacked plates carry it.
pub const VISIT_UNITS: [f64; 3] = [1.31, 0.0, 0.0];

/// Work units per squared depth of a solved candidate sequence (Σ d² over the candidates), by
/// [`PointKind`]: the solver's Newton iterations on a path of d events cost ∝ d each, and a
/// longer path takes more of them. This is what puts 40 internal reflections (few deep
/// sequences) and two or three stacked plates (many shallow ones) on one scale. Plane waves onto
/// a point are never launched exactly (the image method's guess, then Newton): 2.05 units,
/// against 0.018 where a point source's sequences through parallel planes are
/// ([`NEWTON_EVENT_UNITS`] prices the others). Fitted to the seven series
/// ([`SECONDS_PER_WORK_UNIT`]).
pub const DEPTH_SQUARE_UNITS: [f64; 3] = [0.0180, 2.05, 0.0];

/// Work units per squared depth of a solved candidate sequence times the surfaces of the scene
/// (Σ d² · surfaces), by [`PointKind`]: each trace of a path of d events looks for an
/// obstruction on every surface at every segment. Under a point source it separates the stacked
/// plates (5 and 7 surfaces with the shield) from 40 internal reflections in one plate (3): with
/// Σ d² alone, two plates sat 1.1–1.5 times lower than three in every series. Fitted to the seven
/// series ([`SECONDS_PER_WORK_UNIT`]); plane waves onto a point: nothing left to it.
pub const SURFACE_DEPTH_SQUARE_UNITS: [f64; 3] = [0.00645, 0.0, 0.0];

/// Work units per event of a candidate sequence that `path::solve` cannot launch exactly, per
/// trace, by [`PointKind`]: a point source's sequence through planes parallel to its first
/// event's is launched by Snell's invariant (`parallel_stack_launch`: one trace of the planes);
/// any other (a line source's, a point source's through tilted planes) starts from the image
/// method's guess, steepened until the sequence can be traced and iterated by Newton, each step
/// a trace of the sequence. Instrumented (see [`SECONDS_PER_WORK_UNIT`]): 15 traces of the
/// planes per sequence in `michelson` (86 µs of solving per point against 16 in the two-beam
/// plate with fewer events), 11 in `lloyd_mirror`, 1 in the two-beam plates. Without it
/// `michelson` and `lloyd_mirror` sat at the high end of every series and the two-beam plates
/// at the low end (their discovery visits priced for both). Plane waves onto a point are never
/// launched exactly ([`DEPTH_SQUARE_UNITS`] carries them): nothing here. Fitted to the seven
/// series ([`SECONDS_PER_WORK_UNIT`]); carried by `michelson` (0.45 of its estimate).
pub const NEWTON_EVENT_UNITS: [f64; 3] = [7.30, 0.0, 0.0];

/// Work units per node of a walked tree per trace: its discovery (the probe rays) and the walk
/// tracing it once (both polarized models, extents and blockers): measured 1.9–2.2 µs of walk
/// and 0.2–0.7 µs of discovery per node. Fitted to the seven series ([`SECONDS_PER_WORK_UNIT`]).
pub const NODE_UNITS: [f64; 3] = [0.0, 0.0, 5.43];

/// Work units per event of every walked candidate sequence per trace: the walk's copy of each
/// arrival's path, and the case run's passes over it (the phase ledger, the rounding and
/// representation terms of `harness::conditioning`, formed once per trace since the sixteenth
/// session's merge), so an Airy point with m internal reflections costs a part ∝ m². Before,
/// the passes were priced per spectral sample with the walk's part a fixed 0.17 of them; the
/// seven series leave nothing to a per-sample part. Fitted to the seven series
/// ([`SECONDS_PER_WORK_UNIT`]); carried by the Airy plate at m = 2000 (0.94 of its estimate).
pub const WALKED_EVENT_UNITS: f64 = 0.0868;

impl WorkCounts {
    /// The work units of the counts in three parts: (∝ m per point: the walk's nodes;
    /// ∝ m² per point: visits, Σ d², events; per point and sample whatever the budget).
    fn units(&self) -> (f64, f64, f64) {
        let (mut linear, mut quadratic) = (0.0, 0.0);
        let mut fixed = SAMPLE_UNITS * self.samples.iter().sum::<f64>()
            + TAIL_RULE_UNITS * self.tail_rule_points.iter().sum::<f64>();
        for k in 0..3 {
            fixed += TRACE_UNITS[k] * self.traces[k];
            linear += NODE_UNITS[k] * self.nodes[k];
            quadratic += VISIT_UNITS[k] * self.visits[k]
                + DEPTH_SQUARE_UNITS[k] * self.depth_squares[k]
                + SURFACE_DEPTH_SQUARE_UNITS[k] * self.surface_depth_squares[k]
                + NEWTON_EVENT_UNITS[k] * self.newton_events[k];
        }
        quadratic += WALKED_EVENT_UNITS * self.events[PointKind::Walked as usize];
        (linear, quadratic, fixed)
    }
}

/// The sequence tree of the representative point at its budget, for one trace.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct TreeCounts {
    /// Discovery's probe rays times the nodes.
    visits: f64,
    /// Nodes.
    nodes: f64,
    /// Events of every candidate sequence.
    events: f64,
    /// Σ depth² over the candidate sequences.
    depth_squares: f64,
    /// Σ depth² over the candidate sequences times the surfaces of the scene.
    surface_depth_squares: f64,
    /// Events of the candidate sequences the solver cannot launch exactly ([`NEWTON_EVENT_UNITS`]).
    newton_events: f64,
}

impl TreeCounts {
    fn scaled(self, s: f64) -> TreeCounts {
        TreeCounts {
            visits: self.visits * s,
            nodes: self.nodes * s,
            events: self.events * s,
            depth_squares: self.depth_squares * s,
            surface_depth_squares: self.surface_depth_squares * s,
            newton_events: self.newton_events * s,
        }
    }
}

/// A point kind's weights: Σ traces·r, Σ traces·r² over its points, r = (m + 2)/(m_rep + 2).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Weights {
    trace_linear: f64,
    trace_quadratic: f64,
}

/// The tree's counts weighted for every point kind (the per-point counts, `samples`,
/// `traces` and `tail_rule_points`, are left at zero).
fn weighted(tree: &TreeCounts, weights: &[Weights; 3]) -> WorkCounts {
    let mut c = WorkCounts::default();
    for (k, w) in weights.iter().enumerate() {
        // The walk traces each node once per trace (∝ m); discovery and the solver at a point
        // observer follow every candidate sequence (∝ m²).
        if k == PointKind::Walked as usize {
            c.nodes[k] = tree.nodes * w.trace_linear;
        } else {
            c.visits[k] = tree.visits * w.trace_quadratic;
            c.depth_squares[k] = tree.depth_squares * w.trace_quadratic;
            c.surface_depth_squares[k] = tree.surface_depth_squares * w.trace_quadratic;
            c.newton_events[k] = tree.newton_events * w.trace_quadratic;
        }
        c.events[k] = tree.events * w.trace_quadratic;
    }
    c
}

/// The sequence tree of one probe point at one wavelength at the budget `internal`, counted as
/// the tracer discovers it (`trace::plan`). Returns (counts, measured): `measured` is false
/// when the tree grew so fast with the allowed depth that the counts were extrapolated
/// (polynomially from the last doubling of the depth, which under-counts an exponential
/// growth) instead of enumerated, because the case's units (`units` of the counts) already
/// exceed the cap.
fn tree_counts(
    case: &Case,
    pt: &ProbePoint,
    internal: usize,
    units: &dyn Fn(&TreeCounts) -> f64,
) -> Result<(TreeCounts, bool), CaseError> {
    let cap = MAX_PATH_EVENTS;
    let spectrum = build::spectrum(&case.spec.light, &pt.overrides);
    let Some((built, optics, target)) = point_at(case, pt, spectrum[spectrum.len() / 2].0)? else {
        return Ok((TreeCounts::default(), true)); // no transmitted wave: nothing is traced
    };
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
        let mut t = TreeCounts::default();
        for (tree, source) in plan.sequences.iter().zip(&built.scene.sources) {
            t.nodes += tree.nodes().len() as f64;
            // `path::solve` launches a point source's sequence through planes parallel to its
            // first event's exactly (Snell's invariant, `parallel_stack_launch`); any other
            // (a line source's, a plane wave's onto a point, a point source's through tilted
            // planes) starts from the image method's guess, steepened and iterated by Newton,
            // each step a trace of the sequence. `stacked[d - 1]`: the beginning of depth d
            // on the current branch lies on planes parallel to its first event's (depth first
            // order: a node's beginnings are the nodes before it on the branch).
            let point = matches!(source.emitter, Emitter::Point { .. });
            let surfaces = built.scene.surfaces.len();
            let mut stacked: Vec<bool> = Vec::new();
            let mut first = DVec3::ZERO;
            for n in tree.nodes() {
                if let Some(ev) = n.event {
                    let normal = built.scene.surfaces[ev.surface].plane.normal;
                    stacked.truncate(n.depth - 1);
                    let parallel = match stacked.last() {
                        None => {
                            first = normal;
                            true
                        }
                        Some(&s) => s && normal.cross(first).length_squared() <= 1e-30,
                    };
                    stacked.push(parallel);
                }
                if n.candidate {
                    t.events += n.depth as f64;
                    t.depth_squares += (n.depth * n.depth) as f64;
                    t.surface_depth_squares += (n.depth * n.depth * surfaces) as f64;
                    if !(point && stacked.last().copied().unwrap_or(true)) {
                        t.newton_events += n.depth as f64;
                    }
                }
            }
        }
        t.visits = rays * t.nodes;
        let total = units(&t);
        if depth == full.max_events {
            return Ok((t, true));
        }
        if let Some(w0) = previous {
            let p = (total / w0).log2().max(0.0);
            let grow = (full.max_events as f64 / depth as f64).powf(p);
            // Stop early only where the refusal is clear: the work counted so far already
            // exceeds the cap, or the extrapolation exceeds it 4-fold (from a shallow depth it
            // can overshoot a polynomial growth by a third: the walked Airy plate at m = 2000,
            // whose part in m² takes over only with depth; it under-counts an exponential one).
            if total > cap || total * grow > 4.0 * cap {
                return Ok((t.scaled(grow), false));
            }
        }
        previous = Some(total);
        depth = (2 * depth).min(full.max_events);
    }
}

/// How a point is traced ([`PointKind`]).
fn kind(built: &Built, pt: &ProbePoint) -> PointKind {
    let plane = built
        .scene
        .sources
        .iter()
        .all(|s| matches!(s.emitter, Emitter::PlaneWave { .. }));
    match (matches!(pt.observer, Observer::Point { .. }), plane) {
        (false, true) => PointKind::Walked,
        (true, true) => PointKind::SolvedPlaneWave,
        _ => PointKind::SolvedPointSource,
    }
}

/// The work of a case, checked before anything runs, in work units (about
/// [`SECONDS_PER_WORK_UNIT`] CPU-seconds each): the [`WorkCounts`] priced by [`PointKind`].
/// The tree is enumerated as the tracer enumerates it, at the probe point with
/// the largest internal-reflection budget (the Airy tail rule may raise it near grazing
/// incidence up to the cap; beyond it the budget is [`CLOSED_TAIL_ORDERS`] orders and the
/// closed tail, one arrival of O(1) work per channel, docs/PHYSICS.md §5a), so the count
/// follows the surfaces: reflections between separate surfaces in the ambient medium are not
/// internal reflections, and stacked plates multiply the sequences (the tree is enumerated
/// with doubling depth and refused as soon as it outgrows the cap). Every other point is
/// scaled by its own budget as the tracer scales ([`WorkCounts`]). A case over
/// [`MAX_PATH_EVENTS`] is refused with the estimate (units and seconds) and the key that
/// drives it.
pub fn preflight(case: &Case) -> Result<f64, CaseError> {
    work_estimate(case).map(|e| e.units())
}

/// A case's work estimate (work units, every point and wavelength weighted) in three parts,
/// with the counts they price ([`preflight`] is the sum of the parts).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorkEstimate {
    /// What grows like the budget m + 2 per point: the walk's nodes.
    pub linear_units: f64,
    /// What grows like (m + 2)² per point: discovery visits and Σ depth² of solved points, the
    /// events of walked ones (per trace and per sample).
    pub quadratic_units: f64,
    /// What every sample, trace and tail-rule point costs whatever the budget.
    pub sample_units: f64,
    /// The counts priced.
    pub counts: WorkCounts,
}

impl WorkEstimate {
    /// The whole estimate, work units.
    pub fn units(&self) -> f64 {
        self.linear_units + self.quadratic_units + self.sample_units
    }
}

/// [`preflight`] with its parts; refuses the same cases with the same message.
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
        let dispersionless = super::dispersionless(&built.scene);
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
        budgets.push((internal, kind(&built, pt), traces, samples));
        previous = Some((internal, pt.observer.clone(), built.scene));
    }
    let mut per_point = WorkCounts::default();
    for &(_, k, traces, samples) in &budgets {
        let k = k as usize;
        per_point.samples[k] += samples;
        per_point.traces[k] += traces;
        if spec.trace.airy_tail_epsilon.is_some() {
            per_point.tail_rule_points[k] += 1.0;
        }
    }
    // The representative point: the largest budget, the centre among equals.
    let centre = points.len() / 2;
    let worst = budgets.iter().map(|b| b.0).max().unwrap_or(0);
    let rep = if budgets[centre].0 == worst {
        centre
    } else {
        budgets.iter().position(|b| b.0 == worst).unwrap_or(centre)
    };
    let mut weights = [Weights::default(); 3];
    let mut add = |m: usize, k: PointKind, traces: f64| {
        let r = (m as f64 + 2.0) / (worst as f64 + 2.0);
        let w = &mut weights[k as usize];
        w.trace_linear += traces * r;
        w.trace_quadratic += traces * r * r;
    };
    for &(m, k, traces, _) in &budgets {
        add(m, k, traces);
    }
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
        // (`run::orders_within`); a point with a rung beyond its budget traces the deepest
        // rung once, scaled like a point of that budget, and sums every such rung from it
        // (the passes over the paths are per trace, [`WALKED_EVENT_UNITS`]: the rungs summed
        // add nothing the counts price).
        let stride = points.len().div_ceil(24).max(1);
        let sampled: Vec<(usize, PointKind)> =
            budgets.iter().step_by(stride).map(|b| (b.0, b.1)).collect();
        let top = sampled.iter().map(|b| b.0).max().unwrap_or(0).max(1);
        let deepest = CONVERGENCE_ORDERS
            .iter()
            .map(|o| 2 * o - 1)
            .take_while(|&internal| internal <= top)
            .last()
            .unwrap_or(0);
        for &(own, k) in &sampled {
            if deepest > own {
                add(deepest, k, 1.0);
            }
        }
    }
    let tree_units = |t: &TreeCounts| {
        let (l, q, _) = weighted(t, &weights).units();
        l + q
    };
    let (tree, measured) = tree_counts(case, &points[rep], worst, &tree_units)?;
    let counts = WorkCounts {
        samples: per_point.samples,
        traces: per_point.traces,
        tail_rule_points: per_point.tail_rule_points,
        ..weighted(&tree, &weights)
    };
    let (linear_units, quadratic_units, sample_units) = counts.units();
    let estimate = WorkEstimate {
        linear_units,
        quadratic_units,
        sample_units,
        counts,
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
                 units of tracing per probe point and wavelength (sequence discovery and \
                 solving; reflections between separate surfaces in the ambient medium multiply \
                 the sequences), times {} probe point(s) (and their spectral samples through \
                 dispersive media), plus {:.2e} units for every point and sample: use fewer \
                 surfaces, internal reflections, probe points or spectral samples",
                if measured { "about" } else { "at least" },
                work * SECONDS_PER_WORK_UNIT,
                spec.scene.surfaces.len(),
                (linear_units + quadratic_units) / points.len() as f64,
                points.len(),
                sample_units,
            ),
        ));
    }
    Ok(estimate)
}
