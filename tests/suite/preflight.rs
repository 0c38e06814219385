//! The work preflight's cost model (`run::work_estimate`, `src/harness/case/run/budget.rs`):
//! what each term counts, and the estimate against the runs it was calibrated on. Work units
//! are deterministic (counted on the sequence tree, never timed), so these tests time nothing:
//! the measured CPU-seconds below are a record of `benches/preflight.rs` on the project's
//! machine, and the tests assert that the deterministic estimate still lands within 2× of them.

use fringe::harness::case::load::{self, Case};
use fringe::harness::case::run::{self, SAMPLE_UNITS, SECONDS_PER_WORK_UNIT, WorkEstimate};
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

/// plate_two_beam_paper with `k` plates, each 1 mm below the one above (the scenes of
/// `benches/preflight.rs` and of `input_classes::stacked_plates_are_counted_and_refused_before_work`).
fn stacked(k: usize, edit: &dyn Fn(&mut Value)) -> Case {
    case("plate_two_beam_paper", &|doc| {
        let plate = doc["scene"]["surfaces"][0].clone();
        for j in 1..k {
            let mut p = plate.clone();
            p["plate"]["name"] = json!(format!("plate{j}"));
            p["plate"]["top_point_m"] = json!([0.0, 0.0, -0.001 * j as f64]);
            doc["scene"]["surfaces"]
                .as_array_mut()
                .unwrap()
                .insert(j, p);
        }
        edit(doc);
    })
}

fn estimate(c: &Case) -> WorkEstimate {
    run::work_estimate(c).expect("accepted")
}

/// The benched scenes, each with the mean CPU-seconds (all threads) of its run recorded by
/// `cargo bench -p fringe-benches --bench preflight` on the project's 2-core Intel Xeon VM,
/// 29 November 2026, load 5–7 from other builds (short scenes averaged over runs of at least
/// 0.5 CPU-s in all). The estimate (work units × `SECONDS_PER_WORK_UNIT`) must be within 2× of
/// each: a term dropped or double-counted (the per-sample term, the walk's per-event passes,
/// the stacked plates' tree) moves some scene out. Scenes span 4 decades of work, so one rate
/// fitting them all is the claim.
#[test]
fn the_estimate_is_within_2x_of_the_calibration_runs() {
    let scenes: Vec<(&str, Case, f64)> = vec![
        ("1 plate", stacked(1, &|_| {}), 0.0373),
        ("2 stacked plates", stacked(2, &|_| {}), 2.32),
        ("3 stacked plates", stacked(3, &|_| {}), 119.6),
        (
            "plate_two_beam_paper, m = 40",
            stacked(1, &|d| {
                d["trace"] = json!({ "max_internal_reflections": 40 })
            }),
            1.015,
        ),
        (
            "plate_airy_s, m = 2000, 200 angles",
            case("plate_airy_s", &|d| {
                d["trace"] = json!({ "max_internal_reflections": 2000 });
                d["probe"]["sweep"]["count"] = json!(200);
            }),
            35.03,
        ),
        ("plate_airy_s", case("plate_airy_s", &|_| {}), 0.1405),
        (
            "plate_airy_wavelength",
            case("plate_airy_wavelength", &|_| {}),
            0.0995,
        ),
        ("coherence_length", case("coherence_length", &|_| {}), 0.548),
        ("young_paper", case("young_paper", &|_| {}), 0.0085),
        (
            "incoherent_sources",
            case("incoherent_sources", &|_| {}),
            0.0058,
        ),
    ];
    for (name, c, measured) in scenes {
        let seconds = estimate(&c).units() * SECONDS_PER_WORK_UNIT;
        let ratio = measured / seconds;
        assert!(
            (0.5..=2.0).contains(&ratio),
            "{name}: estimate {seconds:.4} CPU-s, measured {measured} (ratio {ratio:.2})"
        );
    }
}

/// The estimate orders the benched scenes as their runs did (each step at least 1.5× in the
/// recorded CPU-seconds: 0.037, 1.0, 2.3, 35, 120 s), and four and six stacked plates are
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

/// A spectrum through media whose indices do not depend on the wavelength is traced once per
/// point (`run::trace_point` moves the arrivals to the other samples), so the walk's part does
/// not grow with the samples; the case run's passes over the walked paths and the per-sample
/// term (`SAMPLE_UNITS` per point and sample) grow exactly with them.
#[test]
fn a_non_dispersive_spectrum_is_traced_once_and_every_sample_counts() {
    let with = |samples: usize| {
        estimate(&case("coherence_length", &|d| {
            d["light"]["gaussian"]["samples"] = json!(samples)
        }))
    };
    let (a, b) = (with(129), with(33));
    assert_eq!(a.linear_units, b.linear_units);
    let r = 129.0 / 33.0;
    assert!((a.quadratic_units / b.quadratic_units - r).abs() < 1e-12 * r);
    // 400 angles.
    assert_eq!(a.sample_units, SAMPLE_UNITS * 400.0 * 129.0);
    assert_eq!(b.sample_units, SAMPLE_UNITS * 400.0 * 33.0);
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
        ("sample", a.sample_units, b.sample_units),
    ] {
        assert!((x / y - r).abs() < 1e-12 * r, "{part}: {}", x / y);
    }
}

/// The per-sample term alone prices two slits (young_paper: no surfaces, so a few units of
/// tracing per point): it is `SAMPLE_UNITS` × 401 points, and the tracing is below it.
#[test]
fn the_per_sample_term_counts_every_point_of_a_scene_without_surfaces() {
    let e = estimate(&case("young_paper", &|_| {}));
    assert_eq!(e.sample_units, SAMPLE_UNITS * 401.0);
    assert!(e.linear_units + e.quadratic_units < e.sample_units, "{e:?}");
}
