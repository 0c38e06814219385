//! The report side of the robustness issue: the stability sweep of `fringe check`
//! (`src/harness/stability.rs`) passes every judged row with finite numbers, and its single-precision
//! illustration shows the failure that forming path differences before phases avoids.

use fringe::harness::stability::{self, DeviationKind, PATH_PHASE_TOLERANCE_RAD, WAVELENGTH_M};

#[test]
fn every_stability_row_passes_with_finite_numbers() {
    let sweep = stability::sweep();
    assert!(sweep.rows.len() >= 40, "{} rows", sweep.rows.len());
    for r in &sweep.rows {
        assert!(
            r.traced.is_finite() && r.closed_form.is_finite() && r.deviation.is_finite(),
            "{} / {} / {}: traced {:e}, closed form {:e}, deviation {:e}",
            r.group,
            r.condition,
            r.quantity,
            r.traced,
            r.closed_form,
            r.deviation
        );
        if let Some(tol) = r.tolerance {
            assert_eq!(
                r.pass,
                Some(true),
                "{} / {} / {}: traced {:e}, closed form {:e}, {} deviation {:e} > {tol:e}",
                r.group,
                r.condition,
                r.quantity,
                r.traced,
                r.closed_form,
                r.deviation_kind.name(),
                r.deviation
            );
        } else {
            assert_eq!(r.pass, None, "an illustration row has no verdict");
        }
    }
    // Every group of tests/stability.rs is covered by judged rows.
    for group in [
        "incidence",
        "critical angle",
        "indices",
        "films",
        "finesse",
        "random films",
        "paths",
    ] {
        assert!(
            sweep
                .rows
                .iter()
                .any(|r| r.group == group && r.pass == Some(true)),
            "no judged row in group {group}"
        );
    }
    // The path sweep spans 1 nm … 10 m, every point finite.
    let first = sweep.paths.first().unwrap();
    let last = sweep.paths.last().unwrap();
    assert_eq!((first.path_m, last.path_m), (1e-9, 10.0));
    for p in &sweep.paths {
        assert!(
            p.fringe_rad.is_finite()
                && p.f64_absolute_rad.is_finite()
                && p.binary32_absolute_rad.is_finite(),
            "{p:?}"
        );
    }
}

/// At 1 m and 550 nm one binary32 spacing of the path, 2^-24 m below 1 m and 2^-23 m above, is
/// 0.68–1.37 rad of phase: absolute phases from binary32 paths are wrong by a large fraction of a
/// fringe, while fringe's differenced f64 paths stay within the 1e-6 rad.
#[test]
fn binary32_absolute_phases_fail_at_one_metre_where_fringe_does_not() {
    let p = stability::path_points(&[1.0])[0];
    assert!(
        p.binary32_absolute_rad > 0.1,
        "binary32 absolute phase error at 1 m: {:e} rad",
        p.binary32_absolute_rad
    );
    // Rounding one path changes the phase by at most half a spacing (2^-24 m above 1 m).
    let half_spacing_rad = std::f64::consts::TAU * 2f64.powi(-24) / WAVELENGTH_M;
    assert!(
        p.binary32_absolute_rad <= 1.01 * half_spacing_rad,
        "{:e} > {half_spacing_rad:e}",
        p.binary32_absolute_rad
    );
    assert!(
        p.fringe_rad <= PATH_PHASE_TOLERANCE_RAD,
        "fringe phase error at 1 m: {:e} rad",
        p.fringe_rad
    );
    // f64 absolute phases: a few f64 spacings of 1 m (2.2e-16 m ≈ 2.5e-9 rad) and of the phase
    // itself (1.1e7 rad, spacing 1.9e-9 rad).
    assert!(
        p.f64_absolute_rad < 1e-8,
        "f64 absolute phase error at 1 m: {:e} rad",
        p.f64_absolute_rad
    );
    let sweep_row = stability::sweep()
        .rows
        .into_iter()
        .find(|r| r.group == "paths" && r.condition.starts_with("s = 1 m,"))
        .expect("a judged row at 1 m");
    assert_eq!(sweep_row.deviation_kind, DeviationKind::Absolute);
    assert!(sweep_row.deviation <= PATH_PHASE_TOLERANCE_RAD);
}

/// A failing stability check fails `fringe check` (case `stability` in the failed list, exit 1):
/// its group row fails, and the check itself is printed as a row of its own. A NaN fails too.
#[test]
fn a_failing_stability_check_becomes_failing_table_rows() {
    let mut sweep = stability::sweep();
    let good = sweep.rows.len();
    let k = sweep.rows.iter().position(|r| r.group == "films").unwrap();
    sweep.rows[k].deviation = 1.0;
    sweep.rows[k].pass = Some(false);
    let nan = sweep.rows.iter().position(|r| r.group == "paths").unwrap();
    sweep.rows[nan].deviation = f64::NAN;
    sweep.rows[nan].pass = Some(false);
    let rows = fringe::harness::check::stability_table_rows(&sweep);
    assert!(
        rows.iter()
            .all(|r| r.case == fringe::harness::check::STABILITY)
    );
    let group = |g: &str| rows.iter().find(|r| r.metric == g).unwrap();
    assert_eq!(group("films").pass, Some(false));
    assert!(group("films").max_abs_dev > 1.0);
    assert_eq!(group("paths").pass, Some(false));
    assert!(group("paths").max_abs_dev.is_nan());
    assert_eq!(group("incidence").pass, Some(true));
    let failing: Vec<_> = rows
        .iter()
        .filter(|r| r.metric == sweep.rows[k].quantity && r.note.contains(&sweep.rows[k].condition))
        .collect();
    assert_eq!(failing.len(), 1, "{rows:#?}");
    assert_eq!(failing[0].max_abs_dev, 1.0);
    assert_eq!(sweep.rows.len(), good);
    let table = fringe::output::report::table(&rows);
    assert!(table.contains("FAIL"), "{table}");
}

/// Issue #13 item 4: the sweep can fail. A deliberately naive build — every traced optical path
/// rounded to an absolute f64 before phases are formed — fails it: the path rows from about
/// 1 mm on (an f64 path of 1 m is off by up to 1.1e-16 m, ~1e-9 rad) and the film whose wave
/// is referred to a point 100 m away (5e-6 in R in the issue), while fringe's double-double
/// paths pass every row.
#[test]
fn a_naive_build_with_absolute_f64_paths_fails_the_sweep() {
    let naive = stability::sweep_with(stability::PathArithmetic::AbsoluteF64);
    let failed: Vec<_> = naive
        .rows
        .iter()
        .filter(|r| r.pass == Some(false))
        .collect();
    for r in &failed {
        eprintln!(
            "naive build fails: {} / {}: deviation {:e} > {:e}",
            r.group,
            r.condition,
            r.deviation,
            r.tolerance.unwrap_or(f64::NAN)
        );
    }
    for group in ["paths", "films"] {
        assert!(
            failed.iter().any(|r| r.group == group),
            "the naive build passes every {group} row"
        );
    }
    let at_100_m = failed
        .iter()
        .find(|r| r.condition.contains("100 m above the film"))
        .expect("the naive build fails the 100 m reference row");
    assert!(at_100_m.deviation > 1e-9, "{at_100_m:?}");
    let one_metre = failed
        .iter()
        .find(|r| r.group == "paths" && r.condition.starts_with("s = 1 m,"))
        .expect("the naive build fails the 1 m path row");
    assert!(one_metre.deviation > 1e-11, "{one_metre:?}");
    // The honest build passes the same rows.
    let good = stability::sweep();
    assert!(good.rows.iter().all(|r| r.pass != Some(false)));
}
