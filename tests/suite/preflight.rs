//! The work preflight's cost model (`run::work_estimate`, `src/harness/case/run/budget.rs`):
//! what each term counts, and the estimate against the runs it was calibrated on. Work units
//! are deterministic (counted on the sequence tree, never timed), so these tests time nothing:
//! the measured CPU-seconds below are a record of `benches/preflight.rs` on the project's
//! machine, and the tests assert that the deterministic estimate still lands within 2× of them.

use crate::support::stacked_plates::stacked_plates;
use fringe::harness::case::load::{self, Case};
use fringe::harness::case::run::{
    self, DEPTH_SQUARE_UNITS, MOVED_TRACE, NEWTON_EVENT_UNITS, NODE_UNITS, PointKind, SAMPLE_UNITS,
    SECONDS_PER_WORK_UNIT, SURFACE_DEPTH_SQUARE_UNITS, TAIL_RULE_UNITS, TRACE_UNITS, VISIT_UNITS,
    WALKED_EVENT_UNITS, WorkCounts, WorkEstimate,
};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

fn library(name: &str) -> (PathBuf, Value) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("cases/{name}.json"));
    let doc = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    (path, doc)
}

/// A library case with `edit` applied to its JSON.
fn case(name: &str, edit: &dyn Fn(&mut Value)) -> Case {
    let (path, mut doc) = library(name);
    edit(&mut doc);
    load::parse(&path, &doc.to_string()).expect("valid case")
}

/// plate_two_beam_paper with `k` plates ([`stacked_plates`], the scenes of
/// `benches/preflight.rs`), then `edit`.
fn stacked(k: usize, edit: &dyn Fn(&mut Value)) -> Case {
    case("plate_two_beam_paper", &|doc| {
        *doc = stacked_plates(doc, k);
        edit(doc);
    })
}

fn estimate(c: &Case) -> WorkEstimate {
    run::work_estimate(c).expect("accepted")
}

/// The benched scenes (`benches/preflight.rs`), each with the mean CPU-seconds (all threads) of
/// its run recorded by `cargo bench -p fringe-benches --bench preflight` on the project's 2-core
/// Intel Xeon VM, 29 November 2026, in seven series: the fourteenth session's merge (idle); the
/// fifteenth session's merge, 1.2–1.4× slower in a slower phase of the VM (idle); the sixteenth
/// session's preflight branch on the first fit of this model, under a load average of 2.5–3.5
/// from other builds (the constants were fitted to these three); and the same branch on the
/// final constants (load average 2.5–3.1, in a faster phase of the VM), the check on data the
/// fit did not see; then two idle series of the sixteenth session's merge (18:46 and 18:49 UTC,
/// a fast phase of the VM: numpy's accumulation bench at 12.3–13.3 M/s), whose case run forms a
/// dispersionless scene's optics once per point and cuts the Airy convergence report's rungs
/// from one deep trace (up to 12 % less CPU for the Airy cases; the tracing code is otherwise
/// the same); and a seventh, idle too, at 20:07 UTC, in a slow phase of the VM (numpy's
/// accumulation bench at 6.3–7.3 M/s, half its speed of 18:42: `lloyd_mirror` at 2.00 of the
/// estimate at 4.44e-7 CPU-s per unit, which is why the rate is now 4.8e-7). The seventeenth
/// session refitted the constants to these seven (`run::SECONDS_PER_WORK_UNIT`) and recorded
/// two more on the refitted model, the check on data the fit did not see, both while another
/// helper's build ran: the eighth at 21:29 UTC (load average 3.0–4.1, falling to 2.0 during the
/// series: the VM sped up half-way, `plate_two_beam_paper` at 1.22 of its estimate and the same
/// case as `1 stacked plate(s)` minutes later at 0.87), the ninth at 21:33 UTC (load average
/// 1.8–3.6); and a tenth, idle, on the merge of the refit (22:07 UTC, the accumulation bench's
/// numpy at 6.8–11.1 M/s a quarter of an hour before: 0.71–1.21 of the estimate, spread 1.70,
/// `coherence_length` low and the Airy walk at m = 2000 high). Short scenes are averaged over
/// runs of at least 0.5 CPU-s in all;
/// `fresnel_rhomb`, a 40-µs run, from its mean ratio.
fn benched() -> Vec<(&'static str, Case, [f64; 10])> {
    vec![
        (
            "bk7_dispersion",
            case("bk7_dispersion", &|_| {}),
            [
                0.0643, 0.1013, 0.1045, 0.0688, 0.076, 0.0762, 0.1289, 0.1199, 0.102, 0.0692,
            ],
        ),
        (
            "brewster_extinction",
            case("brewster_extinction", &|_| {}),
            [
                0.0136, 0.0201, 0.0215, 0.0131, 0.0155, 0.0128, 0.0256, 0.0228, 0.0204, 0.0136,
            ],
        ),
        (
            "coherence_length",
            case("coherence_length", &|_| {}),
            [
                0.2091, 0.2558, 0.2525, 0.1830, 0.2011, 0.1734, 0.3332, 0.3181, 0.291, 0.1805,
            ],
        ),
        (
            "coherence_length_paper_rule",
            case("coherence_length_paper_rule", &|_| {}),
            [
                0.011, 0.016, 0.0122, 0.0107, 0.0106, 0.0105, 0.0188, 0.0179, 0.0165, 0.0107,
            ],
        ),
        (
            "fresnel_rhomb",
            case("fresnel_rhomb", &|_| {}),
            [
                3.744e-05, 6.564e-05, 4.98e-05, 4.47e-05, 3.73e-05, 4.01e-05, 6.57e-05, 6.677e-05,
                6.625e-05, 3.9e-05,
            ],
        ),
        (
            "incoherent_sources",
            case("incoherent_sources", &|_| {}),
            [
                0.0027, 0.0038, 0.0040, 0.0022, 0.0032, 0.003, 0.0048, 0.004, 0.0037, 0.0034,
            ],
        ),
        (
            "lloyd_mirror",
            case("lloyd_mirror", &|_| {}),
            [
                0.0089, 0.0119, 0.0140, 0.0076, 0.0098, 0.0084, 0.0156, 0.0143, 0.0134, 0.0109,
            ],
        ),
        (
            "michelson",
            case("michelson", &|_| {}),
            [
                0.0361, 0.052, 0.0592, 0.0355, 0.0404, 0.0344, 0.0663, 0.0608, 0.0558, 0.0424,
            ],
        ),
        (
            "plate_airy_p",
            case("plate_airy_p", &|_| {}),
            [
                0.0746, 0.1096, 0.1186, 0.0797, 0.069, 0.0631, 0.1195, 0.1144, 0.1053, 0.0717,
            ],
        ),
        (
            "plate_airy_s",
            case("plate_airy_s", &|_| {}),
            [
                0.0878, 0.121, 0.1237, 0.0899, 0.073, 0.0736, 0.1153, 0.1163, 0.1059, 0.0907,
            ],
        ),
        (
            "plate_airy_wavelength",
            case("plate_airy_wavelength", &|_| {}),
            [
                0.0184, 0.029, 0.0310, 0.0190, 0.0222, 0.0182, 0.0328, 0.0309, 0.0288, 0.0218,
            ],
        ),
        (
            "plate_two_beam_paper",
            case("plate_two_beam_paper", &|_| {}),
            [
                0.0238, 0.029, 0.0358, 0.0228, 0.0248, 0.021, 0.041, 0.0366, 0.0349, 0.0262,
            ],
        ),
        (
            "plate_two_beam_unpolarized",
            case("plate_two_beam_unpolarized", &|_| {}),
            [
                0.0263, 0.0359, 0.0389, 0.0257, 0.026, 0.022, 0.0426, 0.0384, 0.0365, 0.0292,
            ],
        ),
        (
            "thin_film_on_substrate",
            case("thin_film_on_substrate", &|_| {}),
            [
                0.068, 0.0889, 0.1025, 0.0711, 0.0656, 0.0545, 0.1094, 0.1038, 0.0943, 0.0676,
            ],
        ),
        (
            "tir_interference",
            case("tir_interference", &|_| {}),
            [
                0.0125, 0.0157, 0.0184, 0.0120, 0.0122, 0.0108, 0.0193, 0.0175, 0.0157, 0.013,
            ],
        ),
        (
            "wedge_fizeau",
            case("wedge_fizeau", &|_| {}),
            [
                0.0139, 0.0169, 0.0210, 0.0132, 0.0137, 0.0119, 0.0225, 0.0175, 0.0183, 0.0144,
            ],
        ),
        (
            "young_paper",
            case("young_paper", &|_| {}),
            [
                0.0054, 0.0066, 0.0076, 0.0040, 0.0053, 0.0046, 0.0083, 0.0051, 0.0063, 0.005,
            ],
        ),
        (
            "1 stacked plate(s)",
            stacked(1, &|_| {}),
            [
                0.0246, 0.034, 0.0367, 0.0242, 0.0248, 0.0222, 0.0381, 0.0261, 0.0336, 0.023,
            ],
        ),
        (
            "2 stacked plate(s)",
            stacked(2, &|_| {}),
            [
                1.397, 1.776, 2.3238, 1.3977, 1.6766, 1.2869, 2.446, 1.875, 1.988, 1.4623,
            ],
        ),
        (
            "3 stacked plate(s)",
            stacked(3, &|_| {}),
            [
                95.99, 116.6, 117.1572, 89.3746, 82.8103, 81.4051, 140.2407, 146.2, 116.0, 107.974,
            ],
        ),
        (
            "plate_two_beam_paper, m = 40",
            stacked(1, &|d| {
                d["trace"] = json!({ "max_internal_reflections": 40 })
            }),
            [
                0.8462, 1.001, 0.9919, 0.7160, 0.7448, 0.8226, 1.0505, 1.256, 1.113, 1.0543,
            ],
        ),
        (
            "plate_airy_s, m = 2000, 200 angles",
            case("plate_airy_s", &|d| {
                d["trace"] = json!({ "max_internal_reflections": 2000 });
                d["probe"]["sweep"]["count"] = json!(200);
            }),
            [
                34.93, 35.21, 35.8844, 27.4433, 27.2738, 27.4544, 39.6064, 40.72, 35.73, 42.9574,
            ],
        ),
    ]
}

/// The estimate (work units × `SECONDS_PER_WORK_UNIT`) is within 2× of each recorded run of
/// every benched scene in all ten series ([`benched`]): a term dropped or double-counted (the
/// per-sample and per-trace terms, the tail rule's set-up, the solver's Σ depth² and its events
/// without an exact launch, the walk's per-event passes, the stacked plates' tree) moves some
/// scene out. Scenes span 6 decades of work, so one rate fitting them all is the claim.
#[test]
fn the_estimate_is_within_2x_of_the_calibration_runs() {
    for (name, c, measured) in benched() {
        let seconds = estimate(&c).units() * SECONDS_PER_WORK_UNIT;
        for m in measured {
            let ratio = m / seconds;
            assert!(
                (0.5..=2.0).contains(&ratio),
                "{name}: estimate {seconds:.4} CPU-s, measured {m} (ratio {ratio:.2})"
            );
        }
    }
}

/// The estimate orders the benched scenes as their runs did (each step at least 1.5× in the
/// recorded CPU-seconds: 0.025, 0.85, 1.4, 35, 96 s), and four and six stacked plates are
/// refused by the estimate itself: `work_estimate` builds and enumerates, it never traces.
#[test]
fn the_estimate_orders_the_benched_scenes_and_refuses_four_and_six_plates() {
    let ordered = [
        estimate(&stacked(1, &|_| {})).units(),
        estimate(&stacked(1, &|d| {
            d["trace"] = json!({ "max_internal_reflections": 40 })
        }))
        .units(),
        estimate(&stacked(2, &|_| {})).units(),
        estimate(&case("plate_airy_s", &|d| {
            d["trace"] = json!({ "max_internal_reflections": 2000 });
            d["probe"]["sweep"]["count"] = json!(200);
        }))
        .units(),
        estimate(&stacked(3, &|_| {})).units(),
    ];
    for w in ordered.windows(2) {
        assert!(w[0] < w[1], "{ordered:?}");
    }
    for k in [4, 6] {
        let e = run::work_estimate(&stacked(k, &|_| {})).unwrap_err();
        assert_eq!(e.json_path, "$.trace.max_internal_reflections");
        assert!(
            e.message.contains("work units"),
            "{k} plates: {}",
            e.message
        );
    }
}

/// Each term of the model priced alone, work units (the parts of `WorkCounts::units`).
fn terms(c: &WorkCounts) -> Vec<(&'static str, f64)> {
    let w = PointKind::Walked as usize;
    let per_kind = |k: [f64; 3], n: [f64; 3]| (0..3).map(|i| k[i] * n[i]).sum::<f64>();
    vec![
        ("samples", SAMPLE_UNITS * c.samples.iter().sum::<f64>()),
        (
            "traces (solved, point sources)",
            TRACE_UNITS[0] * c.traces[0],
        ),
        ("traces (solved, plane waves)", TRACE_UNITS[1] * c.traces[1]),
        ("traces (walked)", TRACE_UNITS[2] * c.traces[2]),
        (
            "tail-rule points",
            TAIL_RULE_UNITS * c.tail_rule_points.iter().sum::<f64>(),
        ),
        ("visits", per_kind(VISIT_UNITS, c.visits)),
        (
            "depth squares",
            per_kind(DEPTH_SQUARE_UNITS, c.depth_squares),
        ),
        (
            "surface depth squares",
            per_kind(SURFACE_DEPTH_SQUARE_UNITS, c.surface_depth_squares),
        ),
        (
            "newton events",
            per_kind(NEWTON_EVENT_UNITS, c.newton_events),
        ),
        ("nodes", per_kind(NODE_UNITS, c.nodes)),
        ("walked events", WALKED_EVENT_UNITS * c.events[w]),
    ]
}

/// Every term of the model carries a benched scene: it is at least the given share of that
/// scene's estimate, and the scene's slowest recorded run would be more than 2× an estimate
/// without it (a term dropped fails here, and the 2× test with it): the solver's events that
/// no exact launch covers in `michelson` (a tilted splitter), the obstruction tests of Σ d² ·
/// surfaces in three stacked plates. The terms sum to the estimate.
#[test]
fn every_term_carries_a_benched_scene() {
    let scenes = benched();
    let carried = [
        ("samples", "coherence_length", 0.9),
        ("traces (solved, point sources)", "young_paper", 0.6),
        ("traces (solved, plane waves)", "tir_interference", 0.45),
        ("traces (walked)", "coherence_length_paper_rule", 0.3),
        ("tail-rule points", "plate_airy_wavelength", 0.75),
        ("visits", "2 stacked plate(s)", 0.6),
        ("depth squares", "wedge_fizeau", 0.4),
        ("surface depth squares", "3 stacked plate(s)", 0.3),
        ("newton events", "michelson", 0.4),
        ("nodes", "brewster_extinction", 0.7),
        ("walked events", "plate_airy_s, m = 2000, 200 angles", 0.9),
    ];
    let mut checked = 0;
    for (scene, c, measured) in &scenes {
        let e = estimate(c);
        let sum: f64 = terms(&e.counts).iter().map(|t| t.1).sum();
        assert!(
            (sum - e.units()).abs() < 1e-9 * e.units(),
            "{scene}: {sum} vs {e:?}"
        );
        for (term, carrier, least) in carried {
            if *scene != carrier {
                continue;
            }
            let part = terms(&e.counts).iter().find(|t| t.0 == term).unwrap().1;
            let share = part / e.units();
            assert!(share >= least, "{term} in {scene}: share {share:.2}");
            let without = (e.units() - part) * SECONDS_PER_WORK_UNIT;
            let slowest = measured.iter().copied().fold(0.0, f64::max);
            assert!(
                slowest / without > 2.0,
                "{term} in {scene}: {slowest} CPU-s is within 2x of {without:.4} without it"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, carried.len(), "every carrier is a benched scene");
}

/// The solver's events without an exact launch (`run::NEWTON_EVENT_UNITS`) are counted where
/// `path::solve` has none: a point source's sequences through planes that are not parallel
/// (`michelson`: a splitter at 45° to its mirrors; only its single-event sequences, on one
/// plane, are launched exactly) and a line source's (`lloyd_mirror`: every sequence, its one
/// reflection), never a point source's through parallel planes (the two-beam plate and its
/// shield, stacked plates) nor a walked plate.
#[test]
fn the_solver_events_without_an_exact_launch_are_counted_where_there_is_none() {
    let sp = PointKind::SolvedPointSource as usize;
    let michelson = estimate(&case("michelson", &|_| {})).counts;
    assert!(michelson.newton_events[sp] > 0.0, "{michelson:?}");
    assert!(
        michelson.newton_events[sp] < michelson.events[sp],
        "{michelson:?}"
    );
    let lloyd = estimate(&case("lloyd_mirror", &|_| {})).counts;
    assert_eq!(lloyd.newton_events[sp], lloyd.events[sp], "{lloyd:?}");
    assert!(lloyd.events[sp] > 0.0);
    for c in [
        estimate(&case("plate_two_beam_paper", &|_| {})).counts,
        estimate(&stacked(2, &|_| {})).counts,
        estimate(&case("plate_airy_s", &|_| {})).counts,
    ] {
        assert_eq!(c.newton_events, [0.0; 3], "{c:?}");
    }
}

/// A spectrum through media whose indices do not depend on the wavelength is traced once per
/// point (`run::trace_point` moves the arrivals to the other samples), so the walk's nodes,
/// its events (the case run's passes over the walked paths, formed once per trace) and the
/// per-trace terms do not grow with the samples; the per-sample term grows exactly with them.
#[test]
fn a_non_dispersive_spectrum_is_traced_once_and_every_sample_counts() {
    let with = |samples: usize| {
        estimate(&case("coherence_length", &|d| {
            d["light"]["gaussian"]["samples"] = json!(samples)
        }))
    };
    let (a, b) = (with(129), with(33));
    let w = PointKind::Walked as usize;
    assert_eq!(a.linear_units, b.linear_units);
    assert_eq!(a.counts.events, b.counts.events);
    assert_eq!(a.counts.traces, b.counts.traces);
    assert_eq!(a.quadratic_units, b.quadratic_units);
    assert!(a.counts.events[w] > 0.0);
    // 400 angles, each traced once: its samples and its trace.
    for (e, samples) in [(a, 129.0), (b, 33.0)] {
        let fixed = 400.0 * (SAMPLE_UNITS * samples + TRACE_UNITS[w]);
        assert!((e.sample_units - fixed).abs() < 1e-9 * fixed, "{e:?}");
    }
}

/// A sweep of the wavelength alone keeps the scene, observer and budget of the point before,
/// so `run::trace_point` moves that point's arrivals instead of tracing (plate_airy_wavelength):
/// the tracing (with the case run's passes over the walked paths, per trace) is counted once,
/// each further point `MOVED_TRACE` of it, while the per-point terms (the per-sample and
/// tail-rule terms) grow with the points.
#[test]
fn a_wavelength_sweep_is_traced_once() {
    let with = |count: usize| {
        estimate(&case("plate_airy_wavelength", &|d| {
            d["probe"]["sweep"]["count"] = json!(count)
        }))
    };
    let (a, b) = (with(301), with(31));
    let w = PointKind::Walked as usize;
    let traced = (1.0 + 300.0 * MOVED_TRACE) / (1.0 + 30.0 * MOVED_TRACE);
    assert!((a.linear_units / b.linear_units - traced).abs() < 1e-12 * traced);
    for (e, n) in [(a, 301.0), (b, 31.0)] {
        let traces = 1.0 + (n - 1.0) * MOVED_TRACE;
        assert!((e.counts.traces[w] - traces).abs() < 1e-12 * traces);
        let fixed = n * (SAMPLE_UNITS + TAIL_RULE_UNITS) + TRACE_UNITS[w] * traces;
        assert!((e.sample_units - fixed).abs() < 1e-9 * fixed, "{e:?}");
    }
    // A thickness sweep changes the scene at every point: traced at each.
    let thick = |count: usize| {
        estimate(&case("plate_airy_wavelength", &|d| {
            d["probe"]["sweep"]["count"] = json!(count);
            d["probe"]["sweep"]["parameter"] = json!({ "thickness_nm": { "surface": "plate" } });
            d["probe"]["sweep"]["from"] = json!(1000);
            d["probe"]["sweep"]["to"] = json!(3000);
        }))
    };
    let (c, d) = (thick(301), thick(31));
    assert!(c.linear_units > 5.0 * d.linear_units, "{c:?} {d:?}");
}

/// Through a dispersive medium (the BK7 plate) each sample is traced on its own: every part
/// grows with the samples.
#[test]
fn a_dispersive_spectrum_is_traced_per_sample() {
    let with = |samples: usize| {
        estimate(&case("coherence_length", &|d| {
            d["scene"]["media"]["glass"] = json!({ "bk7": {} });
            d["light"]["gaussian"]["samples"] = json!(samples);
        }))
    };
    let (a, b) = (with(129), with(33));
    let r = 129.0 / 33.0;
    for (part, x, y) in [
        ("linear", a.linear_units, b.linear_units),
        ("quadratic", a.quadratic_units, b.quadratic_units),
        ("per point and sample", a.sample_units, b.sample_units),
    ] {
        assert!((x / y - r).abs() < 1e-12 * r, "{part}: {}", x / y);
    }
}

/// Two slits (young_paper: no surfaces, so two nodes of discovery per point) are priced by
/// their 401 samples and traces alone, and two plane waves solved onto a point
/// (tir_interference) by their traces: each kind of point has its own price per trace.
#[test]
fn the_per_point_terms_price_the_scenes_without_a_tree() {
    let e = estimate(&case("young_paper", &|_| {}));
    let sp = PointKind::SolvedPointSource as usize;
    let fixed = (SAMPLE_UNITS + TRACE_UNITS[sp]) * 401.0;
    assert!((e.sample_units - fixed).abs() < 1e-12 * fixed, "{e:?}");
    assert!(e.linear_units + e.quadratic_units < e.sample_units, "{e:?}");
    let t = estimate(&case("tir_interference", &|_| {}));
    let pw = PointKind::SolvedPlaneWave as usize;
    assert_eq!(t.counts.traces[pw], 401.0);
    let fixed = (SAMPLE_UNITS + TRACE_UNITS[pw]) * 401.0;
    assert!((t.sample_units - fixed).abs() < 1e-12 * fixed, "{t:?}");
}
