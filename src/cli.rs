//! The commands behind the `fringe` binary, above every other layer: each runs the harness,
//! then writes what it produced through the outputs (reports, figures, the report page) and
//! [`crate::io`]. Nothing below this module calls up into it or into the outputs' writers.

use crate::harness::case::load::Case;
use crate::harness::case::run::CaseResult;
use crate::harness::check::{self, CheckOptions, CheckOutcome, InputError};
use crate::harness::grade::grading::{self, GradeOptions, GradeOutcome};
use crate::harness::verdict;
use crate::output::{figures, report};
use rayon::prelude::*;
use std::path::Path;

/// `fringe check`: evaluate the cases (`check::evaluate`) and, side by side with them when
/// the whole library runs, compute the paper's figures in memory; then write the reports (each
/// file atomically, one run at a time per `--out`), the figures, the report page, and with
/// `--bless` the golden files of a passing run as one set. Nothing is written for a refused
/// case.
pub fn check(opts: &CheckOptions) -> Result<CheckOutcome, InputError> {
    let whole_library = opts.cases.is_empty();
    let (evaluation, figures) = check::evaluate(opts, || {
        whole_library.then(|| figures::compute(&figures::FigureOptions::check_default()))
    })?;
    let check::Evaluation {
        cases,
        results,
        work,
        rows,
        goldens,
        golden_folders,
        sweep,
    } = evaluation;
    // The stability plot is drawn before anything is written.
    let stability_png = report::plot::stability_paths_png(&sweep.paths).map_err(InputError)?;

    // Everything ran: now write, each file atomically, one run at a time per `--out`.
    let io =
        |p: &Path, e: std::io::Error| InputError(format!("{}: cannot write: {e}", p.display()));
    let out_lock = crate::io::lock_dir(&opts.out).map_err(|e| io(&opts.out, e))?;
    crate::io::remove_stale_temp_files(&opts.out).map_err(|e| io(&opts.out, e))?;
    // Each case's files (in parallel: each case has its own folder), and beside them the
    // paper's figures computed during the evaluation (src/output/figures.rs); the first error
    // in case order is reported.
    let write_case = |(case, r): (&Case, &CaseResult)| -> Result<(), InputError> {
        let dir = opts.out.join(&r.name);
        crate::io::remove_stale_temp_files(&dir).map_err(|e| io(&dir, e))?;
        let p = dir.join("profile.csv");
        crate::io::write_atomic(&p, verdict::profile_csv(r).as_bytes()).map_err(|e| io(&p, e))?;
        if !r.convergence.is_empty() {
            let p = dir.join("convergence.csv");
            crate::io::write_atomic(&p, verdict::convergence_csv(r).as_bytes())
                .map_err(|e| io(&p, e))?;
        }
        // profile.png, convergence.png and probe pictures (src/output/report/html.rs).
        report::html::write_case_files(&dir, case, r).map_err(InputError)
    };
    let (written, figures) = rayon::join(
        || {
            cases
                .par_iter()
                .zip(&results)
                .map(write_case)
                .collect::<Vec<_>>()
        },
        || {
            figures.map(|set| {
                let set = set?;
                figures::write(&opts.out, &set)?;
                Ok::<_, String>(set.manifest)
            })
        },
    );
    written.into_iter().collect::<Result<(), _>>()?;
    let summary: Vec<verdict::CaseSummary> = results
        .iter()
        .zip(&work)
        .map(|(r, &work_units)| verdict::CaseSummary {
            case: &r.name,
            description: &r.description,
            formula: &r.formula,
            auto: r.auto.level.to_string(),
            auto_reason: &r.auto.reason,
            internal_reflections: r.internal_reflections,
            dark_points: r.dark_points,
            trace_seconds: r.trace_seconds,
            work_units,
            rows: rows.iter().filter(|x| x.case == r.name).cloned().collect(),
            point_values: verdict::point_values(r),
        })
        .collect();
    let p = opts.out.join("summary.json");
    let json = serde_json::to_string_pretty(&summary).map_err(|e| InputError(e.to_string()))?;
    crate::io::write_atomic(&p, json.as_bytes()).map_err(|e| io(&p, e))?;
    let p = opts.out.join("stability.csv");
    crate::io::write_atomic(&p, crate::harness::stability::csv(&sweep.rows).as_bytes())
        .map_err(|e| io(&p, e))?;
    let p = opts.out.join("stability_paths.png");
    crate::io::write_atomic(&p, &stability_png).map_err(|e| io(&p, e))?;
    // The whole library also makes the paper's figures (src/output/figures.rs); then the
    // one-page report index.html embeds everything written above.
    if let Some(m) = figures {
        let m = m.map_err(InputError)?;
        for e in &m.fig8 {
            eprint!("{}", figures::fig8_text(&e.left, &e.right, &e.stats));
        }
    }
    report::html::write_index(&opts.out).map_err(InputError)?;
    drop(out_lock);

    let mut failed_cases: Vec<String> = rows
        .iter()
        .filter(|r| r.pass == Some(false))
        .map(|r| r.case.clone())
        .collect();
    failed_cases.dedup();
    // Golden files are baselines of a correct tracer: only a passing run is blessed, and its
    // files are written as one set.
    let bless_refused = opts.bless && !failed_cases.is_empty();
    if opts.bless && !bless_refused {
        for g in &golden_folders {
            let set: Vec<(String, String)> = goldens
                .iter()
                .filter(|(dir, _, _)| dir == g)
                .map(|(_, name, text)| (name.clone(), text.clone()))
                .collect();
            std::fs::create_dir_all(g).map_err(|e| io(g, e))?;
            let _lock = crate::io::lock_dir(g).map_err(|e| io(g, e))?;
            crate::io::bless_set(g, &set).map_err(|e| io(g, e))?;
        }
    }
    Ok(CheckOutcome {
        rows,
        results,
        failed_cases,
        stability: sweep,
        bless_refused,
    })
}

/// `fringe grade`: grade a value file ([`grading::grade`], which writes its `grade.json` and
/// `values_profile.csv` only when the input is valid), then refresh `OUT/index.html`.
pub fn grade(opts: &GradeOptions) -> Result<GradeOutcome, InputError> {
    let outcome = grading::grade(opts)?;
    report::html::write_index(&opts.out).map_err(InputError)?;
    Ok(outcome)
}

/// `fringe models`: run the renderer-model study and write its tables
/// ([`crate::harness::renderer_models::study::write`]), then refresh `OUT/index.html`, which
/// shows the table (src/output/report/renderers.rs). Returns the table as Markdown.
pub fn models(out: &Path) -> Result<String, String> {
    let md = crate::harness::renderer_models::study::write(out)?;
    report::html::write_index(out)?;
    Ok(md)
}
