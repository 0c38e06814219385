//! `fringe tradeoff`: a budget under which a case cannot be traced is a row with its reason, and
//! the verdict ("cheapest setting within tolerance") is the same on every run because it ranks
//! by a deterministic cost count, never by wall time.

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::case::load;
use fringe::harness::tradeoff::{self, Budget, Outcome, TradeoffRow, WallTime};
use std::path::PathBuf;

fn library_case(name: &str) -> load::Case {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("cases")
        .join(format!("{name}.json"));
    load::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The verdict without the machine-dependent wall times.
fn verdict(rows: &[TradeoffRow]) -> Option<(Fidelity, String, usize, f64, f64)> {
    tradeoff::cheapest(rows).map(|r| {
        let m = r.measurement().unwrap();
        (
            r.fidelity,
            r.budget.to_string(),
            r.spectral_samples,
            m.path_events,
            m.max_abs_dev,
        )
    })
}

/// The Fresnel rhomb turns 45° linear light circular through two TIRs. With a budget of zero
/// internal reflections no path gets through, which used to abort the whole command; it must be
/// a row saying why, while the budgets with room for both TIRs are traced. Only complex Fresnel
/// (P5, P6) gets the TIR retardance right (the scalar rungs carry no polarization state, and the
/// paper's TIR signs turn the light the other way), so the cheapest setting within tolerance is
/// `vector` with exactly the two internal reflections the rhomb needs.
#[test]
fn rhomb_budget_without_its_two_tirs_is_a_row_and_the_verdict_is_vector_with_two() {
    let case = library_case("fresnel_rhomb");
    let rows = tradeoff::measure(&case, 1);
    assert_eq!(rows.len(), 5 * 3, "5 rungs × budgets 0, 2, 4 × 1 sample");
    for r in &rows {
        match (&r.budget, &r.outcome) {
            (Budget::Fixed(0), Outcome::NotTraced { reason }) => assert!(
                reason.starts_with("$.probe: ") && reason.contains("no light reaches"),
                "{} budget 0: reason {reason:?}",
                r.fidelity
            ),
            (Budget::Fixed(0), Outcome::Traced(m)) => {
                panic!("{} budget 0 traced: {m:?}", r.fidelity)
            }
            (b, Outcome::NotTraced { reason }) => {
                panic!("{} budget {b} not traced: {reason}", r.fidelity)
            }
            (_, Outcome::Traced(m)) => assert!(
                m.internal_reflections >= 2 && m.path_events > 0.0,
                "{} {}: {m:?}",
                r.fidelity,
                r.budget
            ),
        }
    }
    let best = tradeoff::cheapest(&rows).expect("some setting meets the tolerance");
    assert_eq!(best.fidelity, Fidelity::Vector, "{best:?}");
    assert_eq!(best.budget, Budget::Fixed(2), "{best:?}");
    let line = tradeoff::summary("fresnel_rhomb", &rows);
    assert!(line.contains("5 setting(s) not traced"), "{line}");

    // The CSV keeps every setting: 16 columns each, the reason where it was not traced.
    let text = tradeoff::csv(&rows);
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let header = reader.headers().unwrap().clone();
    assert_eq!(header.len(), 16, "{header:?}");
    let reason_col = header.iter().position(|h| h == "reason").unwrap();
    let traced_col = header.iter().position(|h| h == "traced").unwrap();
    let records: Vec<csv::StringRecord> = reader.records().map(|r| r.unwrap()).collect();
    assert_eq!(records.len(), rows.len());
    for rec in &records {
        assert_eq!(rec.len(), 16, "{rec:?}");
        let traced = &rec[traced_col] == "true";
        assert_eq!(traced, rec[reason_col].is_empty(), "{rec:?}");
    }
}

/// Young's two coherent slits in free space (the paper's geometry, d = 500λ, l = 1000d), lit
/// unpolarized: path phase is the only phase, but the in-plane channel's two fields meet at the
/// angle α ≈ d/l = 1e-3 between the rays, so a scalar sum is off by about (1 − cos α)/4 ≈ 1e-7
/// of the maximum (docs/PHYSICS.md §5 "Young": I = 2 + 2 cos α cos δ for that channel), far
/// above the case's 1e-9 tolerance, while the levels that carry 3D fields are exact. Every level
/// traces the same paths (equal cost count): the verdict is the simplest exact level,
/// `paper_rules`, reported as a tie with `vector`; and two runs give the same verdict.
#[test]
fn young_verdict_is_the_simplest_exact_level_and_repeats() {
    let case = library_case("young_paper");
    let first = tradeoff::measure(&case, 1);
    let second = tradeoff::measure(&case, 2);
    let v = verdict(&first).expect("some setting meets the tolerance");
    assert_eq!(v.0, Fidelity::PaperRules, "{v:?}");
    assert_eq!(verdict(&second), Some(v.clone()));
    let alpha = 1e-3f64;
    let angle_error = (1.0 - alpha.cos()) / 4.0;
    for level in [Fidelity::Scalar, Fidelity::ScalarJump] {
        let r = first.iter().find(|r| r.fidelity == level).unwrap();
        let dev = r.measurement().unwrap().max_abs_dev;
        assert!(
            !r.meets_tolerance() && dev <= 4.0 * angle_error,
            "{level}: max |dev| {dev:e}, expected > tolerance {:e} and ≲ (1 − cos α)/4 = {angle_error:e}",
            r.tolerance
        );
    }
    let incoherent = first
        .iter()
        .find(|r| r.fidelity == Fidelity::Incoherent)
        .unwrap();
    assert!(!incoherent.meets_tolerance(), "{incoherent:?}");
    let line = tradeoff::summary("young_paper", &first);
    assert!(line.contains("tie in cost with vector"), "{line}");
    // Same Pareto front and same deviations on both runs.
    assert_eq!(tradeoff::pareto(&first), tradeoff::pareto(&second));
    for (a, b) in first.iter().zip(&second) {
        let (ma, mb) = (a.measurement().unwrap(), b.measurement().unwrap());
        assert_eq!(
            (ma.path_events, ma.max_abs_dev),
            (mb.path_events, mb.max_abs_dev)
        );
        assert_eq!(mb.wall.runs, 2);
        assert!(mb.wall.min <= mb.wall.median && mb.wall.median <= mb.wall.max);
    }
}

/// The verdict does not look at wall times: giving every setting another setting's timings
/// (the slowest made the fastest) leaves it unchanged.
#[test]
fn verdict_ignores_wall_times() {
    let rows = |times: &[f64]| -> Vec<TradeoffRow> {
        let settings = [
            (Fidelity::Vector, 100.0, 1e-12),
            (Fidelity::Scalar, 100.0, 1e-12),
            (Fidelity::Incoherent, 100.0, 0.5),
            (Fidelity::Scalar, 50.0, 0.2),
            (Fidelity::Vector, 400.0, 1e-14),
        ];
        settings
            .iter()
            .zip(times)
            .map(|(&(fidelity, events, dev), &t)| TradeoffRow {
                case: "synthetic".into(),
                fidelity,
                budget: Budget::Fixed(1),
                spectral_samples: 1,
                tolerance: 1e-9,
                outcome: Outcome::Traced(tradeoff::Measurement {
                    internal_reflections: 1,
                    path_events: events,
                    max_abs_dev: dev,
                    wall: WallTime::from_runs(&[t]).unwrap(),
                }),
            })
            .collect()
    };
    let a = rows(&[1.0, 2.0, 3.0, 4.0, 5.0]);
    let b = rows(&[5.0, 0.1, 3.0, 9.0, 0.01]);
    for r in [&a, &b] {
        let best = tradeoff::cheapest(r).unwrap();
        assert_eq!(
            (best.fidelity, best.measurement().unwrap().path_events),
            (Fidelity::Scalar, 100.0)
        );
    }
    assert_eq!(tradeoff::pareto(&a), tradeoff::pareto(&b));
    // The front: the cheap inaccurate scalar (50), scalar at 100 (exact), vector at 400 (more
    // exact); vector at 100 is dominated by scalar at 100 (same count, simpler rung, same error).
    assert_eq!(tradeoff::pareto(&a), [false, true, false, true, true]);
}

/// The wall-time summary: minimum, median (mean of the middle two for an even count), maximum.
#[test]
fn wall_time_spread() {
    let w = WallTime::from_runs(&[3.0, 1.0, 2.0]).unwrap();
    assert_eq!((w.runs, w.min, w.median, w.max), (3, 1.0, 2.0, 3.0));
    let w = WallTime::from_runs(&[4.0, 1.0, 2.0, 8.0]).unwrap();
    assert_eq!((w.runs, w.min, w.median, w.max), (4, 1.0, 3.0, 8.0));
    assert!(WallTime::from_runs(&[]).is_none());
}

/// The report page shows what `fringe tradeoff` wrote into the same folder: the verdict lines
/// (escaped) and a link to the CSV; without a tradeoff run the section is absent.
#[test]
fn report_page_shows_the_verdicts() {
    let dir = tempfile::tempdir().unwrap();
    let page = fringe::output::report::html::index_html(dir.path()).unwrap();
    assert!(!page.contains("id=\"tradeoff\""), "no tradeoff run yet");
    std::fs::create_dir_all(dir.path().join("tradeoff")).unwrap();
    let line = "young_paper: cheapest setting within 1e-9: paper_rules <tie>";
    std::fs::write(dir.path().join("tradeoff/summary.txt"), format!("{line}\n")).unwrap();
    let page = fringe::output::report::html::index_html(dir.path()).unwrap();
    assert!(page.contains("id=\"tradeoff\""), "section missing");
    assert!(
        page.contains("paper_rules &lt;tie&gt;") && page.contains("tradeoff/tradeoff.csv"),
        "verdict line or CSV link missing"
    );
}
