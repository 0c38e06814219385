//! `fringe check`: resolve case names, run them, compare with closed forms and golden files,
//! and run the stability sweep (`src/harness/stability/`, on every run: it is cheap and checks
//! the tracer every case relies on). The verdict decides the exit code (0 pass, 1 a case or a
//! stability check failed, 2 bad input); the command layer (`src/cli.rs`) writes the reports
//! and the golden files of a bless.

use crate::harness::case::load::{self, Case, CaseError};
use crate::harness::case::run::{self, CaseResult};
use crate::harness::stability::{self, StabilityRow, Sweep};
use crate::harness::verdict::{self, GoldenError, Row};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// Output format of the verdict table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Aligned text columns, one row per case × fidelity × observable.
    Table,
    /// One pretty-printed JSON array of the rows.
    Json,
}

/// Options of a check run.
#[derive(Clone, Debug)]
pub struct CheckOptions {
    /// Case names from the library or paths to case files; empty: the whole library.
    pub cases: Vec<String>,
    /// The case library folder (default [`library_root`]`/cases`).
    pub cases_dir: PathBuf,
    /// The golden folder of every case; `None`: `golden_dir_for` (the library's `golden/`
    /// for library cases, a `golden/` folder beside any other case file).
    pub golden_dir: Option<PathBuf>,
    /// Output folder of the reports.
    pub out: PathBuf,
    /// Format of the verdict table on stdout.
    pub format: Format,
    /// Rewrite the golden files from this run (only if it passes).
    pub bless: bool,
}

/// Bad input or usage: exit code 2.
#[derive(Debug)]
pub struct InputError(pub String);

impl From<CaseError> for InputError {
    fn from(e: CaseError) -> Self {
        InputError(e.to_string())
    }
}

/// The environment variable naming the folder that holds `cases/`, `golden/` and `figures/`.
pub const ROOT_VARIABLE: &str = "FRINGE_ROOT";

/// The folder the case library (`cases/`), its golden files (`golden/`) and the figure scenes
/// (`figures/`) are found in when no folder is given on the command line: `$FRINGE_ROOT` if
/// set, else the checkout the binary was built from (so `cargo run`, `target/release/fringe`
/// and `cargo install --path .` work from any directory), else the current directory.
///
/// The library is resolved rather than compiled in so that `--bless` keeps writing the
/// repository's `golden/` files and an edited case file takes effect without a rebuild.
pub fn library_root() -> PathBuf {
    if let Some(r) = std::env::var_os(ROOT_VARIABLE).filter(|r| !r.is_empty()) {
        return PathBuf::from(r);
    }
    let built = Path::new(env!("CARGO_MANIFEST_DIR"));
    if built.join("cases").is_dir() {
        return built.to_path_buf();
    }
    PathBuf::from(".")
}

/// The golden folder of a case file: `--golden-dir` when given; else `golden/` beside the
/// library (`<cases_dir>/../golden`) for a case of the library `cases_dir`, and `golden/` in the
/// case file's own folder for any other case file (`path/to/case.json` →
/// `path/to/golden/<name>.csv`).
pub(crate) fn golden_dir_for(opts: &CheckOptions, file: &Path) -> PathBuf {
    if let Some(g) = &opts.golden_dir {
        return g.clone();
    }
    if in_library(&opts.cases_dir, file) {
        return library_golden_dir(&opts.cases_dir);
    }
    file.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .join("golden")
}

/// `golden/` beside a library folder.
fn library_golden_dir(cases_dir: &Path) -> PathBuf {
    let parent = cases_dir.parent().filter(|p| !p.as_os_str().is_empty());
    parent.unwrap_or(Path::new(".")).join("golden")
}

/// Whether `file` sits directly in the library folder `cases_dir`.
fn in_library(cases_dir: &Path, file: &Path) -> bool {
    let folder = file.parent().filter(|p| !p.as_os_str().is_empty());
    let folder = folder.unwrap_or(Path::new("."));
    match (folder.canonicalize(), cases_dir.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

/// The case names of a library folder (its `*.json` files but `schema.json`), sorted.
pub fn library_names(cases_dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(cases_dir)
        .into_iter()
        .flatten()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .filter_map(|p| p.file_stem().and_then(|s| s.to_str()).map(String::from))
        .filter(|n| n != "schema")
        .collect();
    names.sort();
    names
}

/// ", did you mean `x`?" for the known name closest to `name` (Damerau–Levenshtein distance at
/// most a third of the name's length, at least 2), else "".
pub fn did_you_mean<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> String {
    let limit = (name.chars().count() / 3).max(2);
    known
        .into_iter()
        .map(|k| (strsim::damerau_levenshtein(name, k), k))
        .filter(|&(d, _)| d <= limit)
        .min()
        .map(|(_, k)| format!("; did you mean `{k}`? (`fringe list` shows the library)"))
        .unwrap_or_default()
}

/// Resolve `CASE` arguments: a library name (`<cases_dir>/<name>.json`) or a path to a case
/// file; none: every case of the library.
pub fn resolve(opts: &CheckOptions) -> Result<Vec<PathBuf>, InputError> {
    resolve_cases(&opts.cases, &opts.cases_dir)
}

/// [`resolve`] for a list of names and a library folder.
pub fn resolve_cases(cases: &[String], cases_dir: &Path) -> Result<Vec<PathBuf>, InputError> {
    if cases.is_empty() {
        let mut files: Vec<PathBuf> = std::fs::read_dir(cases_dir)
            .map_err(|e| {
                InputError(format!(
                    "{}: cannot list the case library: {e}",
                    cases_dir.display()
                ))
            })?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.extension().is_some_and(|x| x == "json")
                    && p.file_name().is_some_and(|n| n != "schema.json")
            })
            .collect();
        files.sort();
        if files.is_empty() {
            return Err(InputError(format!(
                "{}: the case library is empty (no *.json case files)",
                cases_dir.display()
            )));
        }
        return Ok(files);
    }
    cases
        .iter()
        .map(|c| {
            let as_path = Path::new(c);
            if c.ends_with(".json") || c.contains('/') {
                if as_path.is_file() {
                    Ok(as_path.to_path_buf())
                } else {
                    Err(InputError(format!("{c}: no such case file")))
                }
            } else if !c.is_empty()
                && c.chars()
                    .all(|ch| ch.is_ascii_lowercase() || ch.is_ascii_digit() || ch == '_')
            {
                let p = cases_dir.join(format!("{c}.json"));
                if p.is_file() {
                    Ok(p)
                } else {
                    let known = library_names(cases_dir);
                    Err(InputError(format!(
                        "{c}: no case of that name in {}{}",
                        cases_dir.display(),
                        did_you_mean(c, known.iter().map(String::as_str))
                    )))
                }
            } else {
                Err(InputError(format!(
                    "{c:?}: a case is a library name from [a-z0-9_] or a path to a .json file"
                )))
            }
        })
        .collect()
}

/// What a check produced.
pub struct CheckOutcome {
    /// Verdict rows of every case, then the stability rows (case `stability`).
    pub rows: Vec<Row>,
    pub results: Vec<CaseResult>,
    /// Failed cases by name; `stability` when a stability check failed.
    pub failed_cases: Vec<String>,
    pub stability: Sweep,
    /// `--bless` was asked for but the run failed: no golden file was written.
    pub bless_refused: bool,
}

/// The name under which the stability sweep appears in the verdict table (reserved: no case
/// may have it, `load::limits::RESERVED_CASE_NAMES`).
pub const STABILITY: &str = "stability";

/// Verdict-table rows of the stability sweep: one per group of judged checks, with deviations
/// as fractions of each check's own tolerance (so groups mixing absolute and relative checks
/// read alike: ≤ 1 passes), then one row per failing check with its own deviation and
/// tolerance.
pub fn stability_table_rows(sweep: &Sweep) -> Vec<Row> {
    let mut groups: Vec<&str> = Vec::new();
    for r in &sweep.rows {
        if r.pass.is_some() && !groups.contains(&r.group.as_str()) {
            groups.push(&r.group);
        }
    }
    let ratio = |r: &StabilityRow| {
        let finite = r.traced.is_finite() && r.closed_form.is_finite() && r.deviation.is_finite();
        if !finite {
            f64::NAN
        } else if r.deviation == 0.0 {
            // Also for exact checks (tolerance 0).
            0.0
        } else {
            r.deviation / r.tolerance.unwrap_or(f64::NAN)
        }
    };
    let mut out = Vec::new();
    for g in groups {
        let checks: Vec<&StabilityRow> = sweep
            .rows
            .iter()
            .filter(|r| r.group == g && r.pass.is_some())
            .collect();
        let ratios: Vec<f64> = checks.iter().map(|r| ratio(r)).collect();
        // NaN is the worst value.
        let (worst_k, worst) = ratios
            .iter()
            .enumerate()
            .fold((0, 0.0f64), |(k, w), (i, &v)| {
                if w.is_nan() || !(v.is_nan() || v > w) {
                    (k, w)
                } else {
                    (i, v)
                }
            });
        let rms = (ratios.iter().map(|v| v * v).sum::<f64>() / ratios.len() as f64).sqrt();
        let w = checks[worst_k];
        out.push(Row {
            case: STABILITY.into(),
            fidelity: "vector".into(),
            metric: g.into(),
            max_abs_dev: worst,
            rms_dev: rms,
            tolerance: Some(1.0),
            pass: Some(checks.iter().all(|r| r.pass == Some(true))),
            seconds: sweep.seconds,
            note: format!(
                "{} checks, deviation/tolerance; worst: {}, {}: {} deviation {:e} (tolerance {:e})",
                checks.len(),
                w.condition,
                w.quantity,
                w.deviation_kind.name(),
                w.deviation,
                w.tolerance.unwrap_or(f64::NAN)
            ),
        });
    }
    for r in sweep.failures() {
        out.push(Row {
            case: STABILITY.into(),
            fidelity: "vector".into(),
            metric: r.quantity.clone(),
            max_abs_dev: r.deviation,
            rms_dev: r.deviation,
            tolerance: r.tolerance,
            pass: Some(false),
            seconds: sweep.seconds,
            note: format!(
                "{}: {}: traced {:e}, closed form {:e}, {} deviation",
                r.group,
                r.condition,
                r.traced,
                r.closed_form,
                r.deviation_kind.name()
            ),
        });
    }
    out
}

/// The command that blesses one case of this run: its library name (with `--cases-dir` when
/// the library is not the default one) or its file path, and `--golden-dir` when one was given.
fn bless_command(opts: &CheckOptions, file: &Path, name: &str) -> String {
    let mut cmd = if in_library(&opts.cases_dir, file) {
        let default = library_root().join("cases");
        if in_library(&default, file) {
            format!("fringe check {name}")
        } else {
            format!(
                "fringe check {name} --cases-dir {}",
                opts.cases_dir.display()
            )
        }
    } else {
        format!("fringe check {}", file.display())
    };
    if let Some(g) = &opts.golden_dir {
        cmd.push_str(&format!(" --golden-dir {}", g.display()));
    }
    cmd.push_str(" --bless");
    cmd
}

/// What a check computed before anything is written: the loaded cases and their results (in
/// file order), each case's work units, the verdict rows (cases, then the stability sweep), the
/// golden files a `--bless` would write, and the stability sweep.
pub(crate) struct Evaluation {
    /// The cases, in the order of their files.
    pub cases: Vec<Case>,
    /// Each case's result.
    pub results: Vec<CaseResult>,
    /// Each case's work units (`run::preflight`).
    pub work: Vec<f64>,
    /// Verdict rows of every case, then the stability rows (case [`STABILITY`]).
    pub rows: Vec<Row>,
    /// With `--bless`: (golden folder, file name, text) of every case's golden file.
    pub goldens: Vec<(PathBuf, String, String)>,
    /// The distinct golden folders of the cases, in first-seen order.
    pub golden_folders: Vec<PathBuf>,
    /// The stability sweep.
    pub sweep: Sweep,
}

/// Load every case (all must be valid before anything runs), show that the folders the run
/// writes are writable, run the cases and the stability sweep, and compare with the closed
/// forms and the golden files. Writes nothing but the recovery of an interrupted bless: the
/// reports and a bless are written by the command layer (`fringe::cli::check`).
///
/// `alongside` runs side by side with the cases and the sweep once every case has passed its
/// preflight and the folders are shown writable (the command layer computes the paper's
/// figures there, in memory); its value is returned with the evaluation.
pub(crate) fn evaluate<T: Send>(
    opts: &CheckOptions,
    alongside: impl FnOnce() -> T + Send,
) -> Result<(Evaluation, T), InputError> {
    let files = resolve(opts)?;
    let cases: Vec<Case> = files
        .iter()
        .map(|f| load::load(f))
        .collect::<Result<_, _>>()?;
    let mut seen = std::collections::BTreeSet::new();
    for c in &cases {
        if !seen.insert(c.spec.name.clone()) {
            return Err(InputError(format!(
                "{}: $.name: case name {:?} is used by two case files",
                c.file.display(),
                c.spec.name
            )));
        }
    }
    // Every case's work is checked before any runs: a refused case costs nothing. The cases
    // are counted side by side; the first refused one in file order is the error reported.
    let work: Vec<f64> = cases
        .par_iter()
        .map(run::preflight)
        .collect::<Vec<_>>()
        .into_iter()
        .collect::<Result<_, _>>()?;
    // So are the folders the run writes: a bad `--out` is found before the tracing, not after.
    let unwritable = |what: &str, dir: &Path, e: std::io::Error| {
        InputError(format!(
            "{}: {what} is not a writable folder: {e}",
            dir.display()
        ))
    };
    crate::io::probe_writable(&opts.out).map_err(|e| unwritable("--out", &opts.out, e))?;
    // Each case's golden folder (`golden_dir_for`), and the distinct folders in first-seen order.
    let golden_dirs: Vec<PathBuf> = files.iter().map(|f| golden_dir_for(opts, f)).collect();
    let mut golden_folders: Vec<&PathBuf> = Vec::new();
    for g in &golden_dirs {
        if !golden_folders.contains(&g) {
            golden_folders.push(g);
        }
    }
    for &g in &golden_folders {
        if opts.bless {
            crate::io::probe_writable(g).map_err(|e| unwritable("the golden folder", g, e))?;
        }
        // A bless interrupted by a kill is finished (or undone) before goldens are read.
        if g.join(crate::io::BLESS_STAGE).exists() {
            let _lock =
                crate::io::lock_dir(g).map_err(|e| unwritable("the golden folder", g, e))?;
            crate::io::recover_bless(g).map_err(|e| unwritable("the golden folder", g, e))?;
        }
    }
    // The cases (each parallel over its probe points), the stability sweep and `alongside`
    // run side by side, the cases (the longest part) first; the first failing case in file
    // order is the error reported.
    let ((results, sweep), beside) = rayon::join(
        || {
            rayon::join(
                || cases.par_iter().map(run::run).collect::<Vec<_>>(),
                stability::sweep,
            )
        },
        alongside,
    );
    let results: Vec<CaseResult> = results.into_iter().collect::<Result<_, _>>()?;

    // Each case's rows and golden comparison, side by side (each reads only its own golden
    // file); collected in case order, so the first corrupt golden file in file order is the
    // error reported, as a loop over the cases would report it.
    type CaseVerdict = (Vec<Row>, Option<(PathBuf, String, String)>);
    let verdicts: Vec<Result<CaseVerdict, InputError>> = cases
        .par_iter()
        .zip(&results)
        .enumerate()
        .map(|(k, (case, r))| -> Result<CaseVerdict, InputError> {
            let mut case_rows = verdict::rows(r);
            // A NaN deviation compares false with every tolerance and would read as a pass: any
            // non-finite traced or closed-form value fails the case.
            let non_finite: Vec<String> = r
                .metrics
                .iter()
                .flat_map(|m| {
                    let analytic = (!m.analytic.iter().all(|x| x.is_finite()))
                        .then(|| format!("{} analytic", m.name));
                    let traced = m
                        .traced
                        .iter()
                        .filter(|(_, t)| !t.iter().all(|x| x.is_finite()))
                        .map(|(l, _)| format!("{} traced {l}", m.name));
                    analytic.into_iter().chain(traced)
                })
                .collect();
            if !non_finite.is_empty() {
                case_rows.push(Row {
                    case: r.name.clone(),
                    fidelity: "all".into(),
                    metric: "finite".into(),
                    max_abs_dev: f64::NAN,
                    rms_dev: f64::NAN,
                    tolerance: None,
                    pass: Some(false),
                    seconds: 0.0,
                    note: format!("non-finite values in {}", non_finite.join(", ")),
                });
            }
            let golden_path = golden_dirs[k].join(format!("{}.csv", r.name));
            // The case's golden tolerance, or its values' conditioning when larger (golden files
            // are reproducible across CPUs to their conditioning, not bit for bit).
            let golden_tolerance = verdict::golden_tolerance(case, r);
            let golden_row = |pass: bool, dev: f64, note: String| Row {
                case: r.name.clone(),
                fidelity: "all".into(),
                metric: "golden".into(),
                max_abs_dev: dev,
                rms_dev: dev,
                tolerance: Some(golden_tolerance),
                pass: Some(pass),
                seconds: 0.0,
                note,
            };
            let mut golden = None;
            if opts.bless {
                golden = Some((
                    golden_dirs[k].clone(),
                    format!("{}.csv", r.name),
                    verdict::golden_csv(r),
                ));
            } else {
                match std::fs::read_to_string(&golden_path) {
                    Err(_) => case_rows.push(golden_row(
                        false,
                        1.0,
                        format!(
                            "no golden file {}: run `{}` to create it",
                            golden_path.display(),
                            bless_command(opts, &files[k], &r.name)
                        ),
                    )),
                    Ok(g) => match verdict::compare_golden(r, &g, golden_tolerance) {
                        Ok(dev) => {
                            case_rows.push(golden_row(true, dev, golden_path.display().to_string()))
                        }
                        Err(GoldenError::Corrupt(m)) => {
                            return Err(InputError(format!(
                                "{}: corrupt golden file: {m}",
                                golden_path.display()
                            )));
                        }
                        Err(GoldenError::Mismatch(m)) => case_rows.push(golden_row(
                            false,
                            1.0,
                            format!("{}: {m}", golden_path.display()),
                        )),
                    },
                }
            }
            Ok((case_rows, golden))
        })
        .collect();
    let mut rows = Vec::new();
    let mut goldens = Vec::new();
    for v in verdicts {
        let (case_rows, golden) = v?;
        rows.extend(case_rows);
        goldens.extend(golden);
    }

    // The stability sweep: judged like a case.
    rows.extend(stability_table_rows(&sweep));
    let evaluation = Evaluation {
        cases,
        results,
        work,
        rows,
        goldens,
        golden_folders: golden_folders.into_iter().cloned().collect(),
        sweep,
    };
    Ok((evaluation, beside))
}
