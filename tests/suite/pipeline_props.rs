//! Random valid scenes through the whole pipeline (robustness issue: "no output anywhere may
//! contain NaN or infinity"). A library case has every real number scaled by its own random
//! factor in [0.6, 1.6] (indices, thicknesses, distances, angles, wavelengths, directions;
//! counts and tolerances stay) and its probe cut to at most 7 points; what the loader accepts
//! is run exactly as `fringe check` runs it (preflight, trace at every fidelity level, closed
//! forms, the Airy convergence report) and turned into the report's rows and the golden CSV.
//! Nothing may panic, a rejection must be a `CaseError` with a JSON path and a message, and every
//! number of an accepted run must be finite.
//!
//! 64 scenes by default; `PROPTEST_CASES=1000 cargo test --release --test pipeline_props` for
//! a longer run.

use fringe::harness::case::load;
use fringe::harness::case::run;
use fringe::harness::verdict;
use proptest::prelude::*;
use serde_json::Value;
use std::path::{Path, PathBuf};

use crate::support::library as support_library;

fn library() -> Vec<(String, Value)> {
    support_library::case_files()
        .iter()
        .map(|p| {
            let v = serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap();
            (p.file_name().unwrap().to_string_lossy().into_owned(), v)
        })
        .collect()
}

/// Keys whose numbers are counts, ids or verdict settings: kept as they are.
const KEEP: &[&str] = &[
    "tolerances",
    "golden_tolerance",
    "count",
    "pixels",
    "samples",
    "tir_count",
    "max_internal_reflections",
    "coherence_group",
];

/// Scale every real number of `v` by the next factor of `factors` (cycled).
fn perturb(v: &mut Value, key: &str, factors: &[f64], k: &mut usize) {
    match v {
        _ if KEEP.contains(&key) => {}
        Value::Number(n) => {
            let x = n.as_f64().unwrap();
            let f = factors[*k % factors.len()];
            *k += 1;
            if let Some(m) = serde_json::Number::from_f64(x * f) {
                *v = Value::Number(m);
            }
        }
        Value::Array(a) => a.iter_mut().for_each(|e| perturb(e, key, factors, k)),
        Value::Object(o) => o.iter_mut().for_each(|(kk, e)| perturb(e, kk, factors, k)),
        _ => {}
    }
}

/// At most 7 probe points (a grid: 3 × 2).
fn shrink_probe(case: &mut Value) {
    let Some(probe) = case.get_mut("probe").and_then(Value::as_object_mut) else {
        return;
    };
    for (kind, p) in probe.iter_mut() {
        if kind == "grid" {
            p["pixels"] = serde_json::json!([3, 2]);
        } else if let Some(c) = p.get("count").and_then(Value::as_u64) {
            p["count"] = Value::from(c.min(7));
        }
    }
}

fn all_finite(xs: &[f64]) -> bool {
    xs.iter().all(|x| x.is_finite())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: std::env::var("PROPTEST_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(64),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn random_valid_scenes_give_finite_reports(
        which in 0usize..16,
        factors in proptest::collection::vec(0.6..1.6f64, 1..40),
    ) {
        let lib = library();
        let (file, base) = &lib[which % lib.len()];
        let mut case = base.clone();
        let mut k = 0;
        perturb(&mut case, "", &factors, &mut k);
        shrink_probe(&mut case);
        let text = serde_json::to_string_pretty(&case).unwrap();
        let path = Path::new("perturbed").join(file);
        let loaded = match load::parse(&path, &text) {
            Ok(c) => c,
            Err(e) => {
                // Rejected by the loader: a clear error is all that is asked here.
                prop_assert!(e.json_path.starts_with('$') && !e.message.is_empty(), "{e:?}");
                return Ok(());
            }
        };
        let result = run::preflight(&loaded).and_then(|_| run::run_with(&loaded, true));
        let r = match result {
            Ok(r) => r,
            Err(e) => {
                // e.g. no light reaches the moved probe: an error naming the key, never a panic.
                prop_assert!(e.json_path.starts_with('$') && !e.message.is_empty(), "{e:?}");
                return Ok(());
            }
        };
        for m in &r.metrics {
            prop_assert!(all_finite(&m.coordinates), "{file}: {} coordinates {:?}", m.name, m.coordinates);
            prop_assert!(all_finite(&m.analytic), "{file}: {} closed form {:?}\n{text}", m.name, m.analytic);
            for (level, t) in &m.traced {
                prop_assert!(all_finite(t), "{file}: {} traced at {level:?}: {t:?}\n{text}", m.name);
            }
        }
        for c in &r.convergence {
            let line = format!("{c:?}");
            prop_assert!(!line.contains("NaN") && !line.contains("inf"), "{file}: convergence row {line}");
        }
        for row in verdict::rows(&r) {
            prop_assert!(
                row.max_abs_dev.is_finite() && row.rms_dev.is_finite()
                    && row.tolerance.is_none_or(f64::is_finite),
                "{file}: report row {row:?}\n{text}"
            );
        }
        let csv = verdict::golden_csv(&r);
        prop_assert!(!csv.contains("NaN") && !csv.contains("inf"), "{file}: golden CSV has a non-finite value");
    }
}

/// The library's Fresnel rhomb with `air` of index `n_out` and glass of index `n_glass`.
fn rhomb(n_out: f64, n_glass: f64) -> load::Case {
    let text = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("cases/fresnel_rhomb.json"),
    )
    .unwrap();
    let mut v: Value = serde_json::from_str(&text).unwrap();
    v["scene"]["media"]["air"]["constant"]["n"] = Value::from(n_out);
    v["scene"]["media"]["glass"]["constant"]["n"] = Value::from(n_glass);
    load::parse(Path::new("rhomb.json"), &v.to_string()).unwrap()
}

/// Found by `random_valid_scenes_give_finite_reports`: the rhomb's closed form assumed air
/// (n = 1) beyond the TIR face and gave NaN when the glass was rarer than 1. With the medium
/// the scene has there, the closed form tan(Δ/2) = cos θ sqrt(sin²θ − n21²)/sin²θ (n21 =
/// n_out/n_glass) agrees with the trace in water-like surroundings; where the face does not
/// totally reflect, the reference is refused with a message instead of a NaN.
#[test]
fn rhomb_retardance_uses_the_medium_beyond_the_face() {
    // The library rhomb's TIR angle is 54.6°: 1.8 sin 54.6° = 1.47 > 1.2 (TIR).
    let r = run::run(&rhomb(1.2, 1.8)).unwrap();
    let m = r.metrics.iter().find(|m| m.name == "retardance").unwrap();
    let theta = 54.6f64.to_radians();
    let n21 = 1.2 / 1.8;
    let one =
        2.0 * (theta.cos() * (theta.sin().powi(2) - n21 * n21).sqrt() / theta.sin().powi(2)).atan();
    assert!(
        (m.analytic[0].abs() - 2.0 * one).abs() < 1e-3,
        "closed form {} vs two TIRs at about 54.6° {}",
        m.analytic[0],
        2.0 * one
    );
    let s = m
        .stats(fringe::accumulate::fidelity::Fidelity::Vector)
        .unwrap();
    assert!(
        s.max_abs_dev <= 1e-9,
        "traced vs closed form: {}",
        s.max_abs_dev
    );
    // 1.51 sin 54.6° = 1.23 < 1.3: no TIR, so no retardance to compare with.
    let e = run::run(&rhomb(1.3, 1.51)).unwrap_err();
    assert!(e.message.contains("no total internal reflection"), "{e:?}");
}

/// The work preflight counts what the tracer does, on the sequence tree the tracer enumerates:
/// a plane wave observed in the far field is walked as a tree of shared beginnings, so the
/// Airy plate with 2000 internal reflections at 2000 angles (7.4e8 units, about 6 CPU-minutes:
/// the walk is linear in m, the case run's passes over each walked path are not) is accepted;
/// the work is proportional to the probe points (of one tree) and grows with the internal reflections.
/// (Stacked plates: `input_classes::stacked_plates_are_counted_and_refused_before_work`.)
#[test]
fn the_work_estimate_follows_the_tracer() {
    let with = |name: &str, edit: &dyn Fn(&mut Value)| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("cases/{name}.json"));
        let mut doc: Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        edit(&mut doc);
        let case = load::parse(&path, &doc.to_string()).expect("valid case");
        run::preflight(&case)
    };
    let airy = with("plate_airy_s", &|d| {
        d["trace"] = serde_json::json!({ "max_internal_reflections": 2000 });
        d["probe"]["sweep"]["count"] = 2000.into();
    });
    assert!(airy.is_ok(), "{airy:?}");
    let two_beam = |m: usize, count: usize| {
        with("plate_two_beam_paper", &|d| {
            d["trace"] = serde_json::json!({ "max_internal_reflections": m });
            d["probe"]["line"]["count"] = count.into();
        })
        .expect("accepted")
    };
    // 361 and 721 points share the centre point, where the tree is counted.
    let (w1, w2) = (two_beam(10, 361), two_beam(10, 721));
    assert!((w2 / w1 - 721.0 / 361.0).abs() < 1e-12, "{w1:e} {w2:e}");
    assert!(two_beam(20, 361) > w1);
}

/// The bounce-convergence report of a monochrome Airy case sums the rungs 2·orders − 1 of its
/// ladder (1, 3, 5, …, 127 internal reflections) at up to 24 points from the arrivals the run
/// traced there (`run::orders_within`), and traces only a rung beyond a point's own budget. At
/// m = 2000 for every angle no rung is beyond it, so the report adds no tracing: 401 angles
/// cost exactly 401/201 of 201 in each part (before the rungs were summed from the traced
/// arrivals they were counted as traced: (401 + 24 w)/(201 + 23 w) for a w between
/// Σ(m_k + 2)²/2002² ≈ 0.009 and Σ(m_k + 2)/2002 ≈ 0.23).
#[test]
fn the_convergence_report_is_counted_at_its_own_budgets() {
    let airy = |count: usize| {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("cases/plate_airy_s.json");
        let mut doc: Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        doc["trace"] = serde_json::json!({ "max_internal_reflections": 2000 });
        doc["probe"]["sweep"]["count"] = count.into();
        let case = load::parse(&path, &doc.to_string()).expect("valid case");
        run::work_estimate(&case).expect("accepted")
    };
    let (a, b) = (airy(401), airy(201));
    let expected = 401.0 / 201.0;
    for (part, ratio) in [
        ("linear", a.linear_units / b.linear_units),
        ("quadratic", a.quadratic_units / b.quadratic_units),
    ] {
        assert!(
            (ratio - expected).abs() < 1e-12 * expected,
            "{part}: {ratio} vs {expected}"
        );
    }
    // The per-point terms (`run::SAMPLE_UNITS` per sample, `run::TRACE_UNITS` per trace)
    // follow the angles alone.
    let ratio = a.sample_units / b.sample_units;
    assert!((ratio - expected).abs() < 1e-12 * expected, "{ratio}");
}
