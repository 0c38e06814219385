//! `fringe grade CASE --values FILE.csv`: judge another tracer's values like `fringe check`
//! judges the traced ones.
//!
//! The case is run as `check` runs it (closed forms and every fidelity rung, no golden file).
//! Each reference gets a verdict row for the values, fidelity `values`: the deviation is the
//! check's (|value − closed form| over the profile's largest |closed form| for intensities,
//! pointwise relative otherwise) and the tolerance is the case's tolerance at `--level`
//! (default `vector`, the exact physics). Information rows `values~<rung>` give the deviation of
//! the values from each traced rung (relative to that rung's largest |value| for intensities), and
//! the closest rung of each quantity is named. Exit codes as `check`: 0 pass, 1 a reference
//! fails, 2 bad input (nothing written).

use super::{Quantity, quantities, values};
use crate::accumulate::fidelity::Fidelity;
use crate::harness::case::load;
use crate::harness::case::run::{self, CaseResult, MetricResult};
use crate::harness::check::{self, CheckOptions, Format, InputError};
use crate::harness::verdict::Row;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Options of `fringe grade`.
#[derive(Clone, Debug)]
pub struct GradeOptions {
    pub case: String,
    pub values: PathBuf,
    pub cases_dir: PathBuf,
    pub out: PathBuf,
    /// The rung whose tolerance the values are judged with.
    pub level: Fidelity,
}

/// The rung a quantity's values are closest to.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Closest {
    pub quantity: String,
    pub fidelity: String,
    /// max |values − rung| over the quantity's probe, relative as in the rows.
    pub max_abs_dev: f64,
}

/// What a grading produced (also `OUT/grade/<case>/grade.json`).
#[derive(Clone, Debug, Serialize)]
pub struct GradeOutcome {
    pub case: String,
    pub values_file: String,
    pub level: String,
    pub rows: Vec<Row>,
    pub closest: Vec<Closest>,
    pub failed: bool,
}

/// The deviation statistics of `values` against `reference` with the scale rule of
/// [`MetricResult::deviations`] (intensity: largest |reference|; other kinds: pointwise).
fn stats(m: &MetricResult, reference: &[f64], values: &[f64]) -> Option<run::LevelStats> {
    let probe = MetricResult {
        analytic: reference.to_vec(),
        traced: BTreeMap::from([(Fidelity::Vector, values.to_vec())]),
        ..m.clone()
    };
    probe.stats(Fidelity::Vector)
}

/// Verdict rows and the closest rungs of `values` (one vector per quantity) for a case result.
pub fn judge(
    result: &CaseResult,
    quantities: &[Quantity],
    values: &[Vec<f64>],
    level: Fidelity,
) -> (Vec<Row>, Vec<Closest>) {
    let mut rows = Vec::new();
    let mut closest = Vec::new();
    for (q, v) in quantities.iter().zip(values) {
        let mut per_rung: BTreeMap<Fidelity, f64> = BTreeMap::new();
        for &mi in &q.metrics {
            let m = &result.metrics[mi];
            if let Some(st) = stats(m, &m.analytic, v) {
                let tol = m.tolerances.get(&level).copied();
                rows.push(Row {
                    case: result.name.clone(),
                    fidelity: "values".into(),
                    metric: m.name.clone(),
                    max_abs_dev: st.max_abs_dev,
                    rms_dev: st.rms_dev,
                    tolerance: tol,
                    pass: tol.map(|t| st.max_abs_dev <= t),
                    seconds: 0.0,
                    note: format!(
                        "{} against the closed form, {} tolerance; max at {:.6e}",
                        q.name, level, st.at
                    ),
                });
            }
        }
        // The rungs are the same for every metric of the quantity: compare with the first.
        let m = &result.metrics[q.metrics[0]];
        for (l, traced) in &m.traced {
            if let Some(st) = stats(m, traced, v) {
                per_rung.insert(*l, st.max_abs_dev);
                rows.push(Row {
                    case: result.name.clone(),
                    fidelity: format!("values~{l}"),
                    metric: q.name.clone(),
                    max_abs_dev: st.max_abs_dev,
                    rms_dev: st.rms_dev,
                    tolerance: None,
                    pass: None,
                    seconds: 0.0,
                    note: format!("against the traced {l} rung; max at {:.6e}", st.at),
                });
            }
        }
        // Ties (rungs that trace identically) go to the cheapest rung.
        if let Some((l, d)) = per_rung
            .iter()
            .fold(None::<(Fidelity, f64)>, |best, (l, d)| match best {
                Some((_, bd)) if bd <= *d => best,
                _ => Some((*l, *d)),
            })
        {
            closest.push(Closest {
                quantity: q.name.clone(),
                fidelity: l.to_string(),
                max_abs_dev: d,
            });
        }
    }
    (rows, closest)
}

/// `values_profile.csv`: per quantity, coordinate, values, closed form of its first reference,
/// and every traced rung.
fn profile_csv(result: &CaseResult, quantities: &[Quantity], values: &[Vec<f64>]) -> String {
    let mut header: Vec<String> = ["quantity", "coordinate", "values", "closed_form"]
        .map(String::from)
        .to_vec();
    header.extend(result.levels.iter().map(|l| format!("traced_{l}")));
    let mut rows = Vec::new();
    for (q, v) in quantities.iter().zip(values) {
        let m = &result.metrics[q.metrics[0]];
        for (k, x) in q.coordinates.iter().enumerate() {
            let mut fields = vec![
                q.name.clone(),
                format!("{x:.17e}"),
                format!("{:.17e}", v[k]),
                format!("{:.17e}", m.analytic[k]),
            ];
            for l in &result.levels {
                fields.push(
                    m.traced
                        .get(l)
                        .map(|t| format!("{:.17e}", t[k]))
                        .unwrap_or_default(),
                );
            }
            rows.push(fields);
        }
    }
    crate::io::csv_text(&header.iter().map(String::as_str).collect::<Vec<_>>(), rows)
}

/// Load and run the case named by `case` (library name or path), as `check` does.
pub fn run_case(case: &str, cases_dir: &Path) -> Result<(load::Case, CaseResult), InputError> {
    let opts = CheckOptions {
        cases: vec![case.to_string()],
        cases_dir: cases_dir.to_path_buf(),
        golden_dir: None,
        out: PathBuf::from("reports"),
        format: Format::Table,
        bless: false,
    };
    let file = check::resolve(&opts)?.remove(0);
    let c = load::load(&file)?;
    run::preflight(&c)?;
    let r = run::run_with(&c, false)?;
    Ok((c, r))
}

/// Grade a value file; writes `OUT/grade/<case>/grade.json` and `values_profile.csv` only
/// when the input is valid (the command, `fringe::cli::grade`, then refreshes the report page).
pub fn grade(opts: &GradeOptions) -> Result<GradeOutcome, InputError> {
    let (case, result) = run_case(&opts.case, &opts.cases_dir)?;
    let qs = quantities(&result, &case.spec.probe);
    let text = std::fs::read_to_string(&opts.values)
        .map_err(|e| InputError(format!("{}: cannot read: {e}", opts.values.display())))?;
    let vals = values::parse(&text, &qs)
        .map_err(|e| InputError(format!("{}: {e}", opts.values.display())))?;
    if result
        .metrics
        .iter()
        .all(|m| !m.tolerances.contains_key(&opts.level))
    {
        return Err(InputError(format!(
            "--level {}: the case {} has no tolerance at this level; allowed: {}",
            opts.level,
            result.name,
            result.metrics[0]
                .tolerances
                .keys()
                .map(|l| l.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    let (rows, closest) = judge(&result, &qs, &vals, opts.level);
    let failed = rows.iter().any(|r| r.pass == Some(false));
    let outcome = GradeOutcome {
        case: result.name.clone(),
        values_file: opts.values.display().to_string(),
        level: opts.level.to_string(),
        rows,
        closest,
        failed,
    };
    let dir = opts.out.join("grade").join(&result.name);
    let io =
        |p: &Path, e: std::io::Error| InputError(format!("{}: cannot write: {e}", p.display()));
    let p = dir.join("grade.json");
    let json = serde_json::to_string_pretty(&outcome).map_err(|e| InputError(e.to_string()))?;
    crate::io::write_atomic(&p, json.as_bytes()).map_err(|e| io(&p, e))?;
    let p = dir.join("values_profile.csv");
    crate::io::write_atomic(&p, profile_csv(&result, &qs, &vals).as_bytes())
        .map_err(|e| io(&p, e))?;
    Ok(outcome)
}

/// The lines `fringe grade` prints after the table: the closest rung of each quantity.
pub fn closest_lines(outcome: &GradeOutcome) -> Vec<String> {
    outcome
        .closest
        .iter()
        .map(|c| {
            format!(
                "{}: {} values are closest to the {} rung (max|dev| {:.3e})",
                outcome.case, c.quantity, c.fidelity, c.max_abs_dev
            )
        })
        .collect()
}
