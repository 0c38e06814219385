//! The work preflight's cost model (`run::work_estimate`, `src/harness/case/run/budget.rs`):
//! what each term counts, and the estimate against the runs it was calibrated on. Work units
//! are deterministic (counted on the sequence tree, never timed), so these tests time nothing:
//! the measured CPU-seconds below are a record of `benches/preflight.rs` on the project's
//! machine, and the tests assert that the deterministic estimate still lands within 2× of them.

use crate::support::stacked_plates::stacked_plates;
use fringe::harness::case::load::{self, Case};
use fringe::harness::case::run::{
    self, FURTHER_SAMPLE_UNITS, MOVED_TRACE, SAMPLE_UNITS, SECONDS_PER_WORK_UNIT,
    WALKED_SAMPLE_SCALE, WorkEstimate,
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

/// The benched scenes, each with the mean CPU-seconds (all threads) of its run recorded by
/// `cargo bench -p fringe-benches --bench preflight` on the project's 2-core Intel Xeon VM,
/// idle, 29 November 2026, in two series: the fourteenth session's merge, and the fifteenth
/// session's merge 1.2–1.4× slower in a slower phase of the VM (short scenes averaged over runs
/// of at least 0.5 CPU-s in all; `fresnel_rhomb`, a 40-µs run, from its mean ratio). The
/// estimate (work units × `SECONDS_PER_WORK_UNIT`) must be within 2× of each run in both
/// series: a term dropped or double-counted (the per-sample terms, the walk's per-event passes,
/// the solved points' units, the stacked plates' tree) moves some scene out. Scenes span 4
/// decades of work, so one rate fitting them all is the claim.
#[test]
fn the_estimate_is_within_2x_of_the_calibration_runs() {
    let scenes: Vec<(&str, Case, [f64; 2])> = vec![
        (
            "bk7_dispersion",
            case("bk7_dispersion", &|_| {}),
            [0.0643, 0.1013],
        ),
        (
            "brewster_extinction",
            case("brewster_extinction", &|_| {}),
            [0.0136, 0.0201],
        ),
        (
            "coherence_length",
            case("coherence_length", &|_| {}),
            [0.2091, 0.2558],
        ),
        (
            "coherence_length_paper_rule",
            case("coherence_length_paper_rule", &|_| {}),
            [0.011, 0.016],
        ),
        (
            "fresnel_rhomb",
            case("fresnel_rhomb", &|_| {}),
            [3.744e-05, 6.564e-05],
        ),
        (
            "incoherent_sources",
            case("incoherent_sources", &|_| {}),
            [0.0027, 0.0038],
        ),
        (
            "lloyd_mirror",
            case("lloyd_mirror", &|_| {}),
            [0.0089, 0.0119],
        ),
        ("michelson", case("michelson", &|_| {}), [0.0361, 0.052]),
        (
            "plate_airy_p",
            case("plate_airy_p", &|_| {}),
            [0.0746, 0.1096],
        ),
        (
            "plate_airy_s",
            case("plate_airy_s", &|_| {}),
            [0.0878, 0.121],
        ),
        (
            "plate_airy_wavelength",
            case("plate_airy_wavelength", &|_| {}),
            [0.0184, 0.029],
        ),
        (
            "plate_two_beam_paper",
            case("plate_two_beam_paper", &|_| {}),
            [0.0238, 0.029],
        ),
        (
            "plate_two_beam_unpolarized",
            case("plate_two_beam_unpolarized", &|_| {}),
            [0.0263, 0.0359],
        ),
        (
            "thin_film_on_substrate",
            case("thin_film_on_substrate", &|_| {}),
            [0.068, 0.0889],
        ),
        (
            "tir_interference",
            case("tir_interference", &|_| {}),
            [0.0125, 0.0157],
        ),
        (
            "wedge_fizeau",
            case("wedge_fizeau", &|_| {}),
            [0.0139, 0.0169],
        ),
        (
            "young_paper",
            case("young_paper", &|_| {}),
            [0.0054, 0.0066],
        ),
        ("1 stacked plate(s)", stacked(1, &|_| {}), [0.0246, 0.034]),
        ("2 stacked plate(s)", stacked(2, &|_| {}), [1.397, 1.776]),
        ("3 stacked plate(s)", stacked(3, &|_| {}), [95.99, 116.6]),
        (
            "plate_two_beam_paper, m = 40",
            stacked(1, &|d| {
                d["trace"] = json!({ "max_internal_reflections": 40 })
            }),
            [0.8462, 1.001],
        ),
        (
            "plate_airy_s, m = 2000, 200 angles",
            case("plate_airy_s", &|d| {
                d["trace"] = json!({ "max_internal_reflections": 2000 });
                d["probe"]["sweep"]["count"] = json!(200);
            }),
            [34.93, 35.21],
        ),
    ];
    for (name, c, measured) in scenes {
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

/// A spectrum through media whose indices do not depend on the wavelength is traced once per
/// point (`run::trace_point` moves the arrivals to the other samples), so the walk's part does
/// not grow with the samples; the case run's passes over the walked paths and the per-sample
/// term (`SAMPLE_UNITS` for a point's first sample, `FURTHER_SAMPLE_UNITS` for each further
/// one) grows exactly with them.
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
    // A far-field point of a plane wave: the walked points' per-sample terms.
    let per_point = |samples: f64| {
        WALKED_SAMPLE_SCALE * (SAMPLE_UNITS + FURTHER_SAMPLE_UNITS * (samples - 1.0))
    };
    assert!((a.sample_units - 400.0 * per_point(129.0)).abs() < 1e-9 * a.sample_units);
    assert!((b.sample_units - 400.0 * per_point(33.0)).abs() < 1e-9 * b.sample_units);
}

/// A sweep of the wavelength alone keeps the scene, observer and budget of the point before,
/// so `run::trace_point` moves that point's arrivals instead of tracing (plate_airy_wavelength):
/// the tracing is counted once, each further point `MOVED_TRACE` of it, while the per-point
/// terms (the case run's passes over the walked paths, the per-sample term) grow with the
/// points.
#[test]
fn a_wavelength_sweep_is_traced_once() {
    let with = |count: usize| {
        estimate(&case("plate_airy_wavelength", &|d| {
            d["probe"]["sweep"]["count"] = json!(count)
        }))
    };
    let (a, b) = (with(301), with(31));
    let traced = (1.0 + 300.0 * MOVED_TRACE) / (1.0 + 30.0 * MOVED_TRACE);
    assert!((a.linear_units / b.linear_units - traced).abs() < 1e-12 * traced);
    assert_eq!(a.sample_units, WALKED_SAMPLE_SCALE * SAMPLE_UNITS * 301.0);
    assert_eq!(b.sample_units, WALKED_SAMPLE_SCALE * SAMPLE_UNITS * 31.0);
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
    ] {
        assert!((x / y - r).abs() < 1e-12 * r, "{part}: {}", x / y);
    }
    assert!(a.sample_units > 3.0 * b.sample_units, "{a:?} {b:?}");
}

/// The per-sample term alone prices two slits (young_paper: no surfaces, so a few units of
/// tracing per point): it is `SAMPLE_UNITS` × 401 points, and the tracing is below it.
#[test]
fn the_per_sample_term_counts_every_point_of_a_scene_without_surfaces() {
    let e = estimate(&case("young_paper", &|_| {}));
    assert_eq!(e.sample_units, SAMPLE_UNITS * 401.0);
    assert!(e.linear_units + e.quadratic_units < e.sample_units, "{e:?}");
}
