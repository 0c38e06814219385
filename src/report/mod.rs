//! Outputs of a check: the verdict table, CSV profiles, the JSON summary and golden files.
//! Every file is written atomically (temporary file in the same folder, then rename).

pub mod html;
pub mod image;
pub mod plot;
pub mod tradeoff_plot;

use crate::case::run::CaseResult;
use crate::fidelity::Fidelity;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::Path;

/// Write `bytes` to `path` atomically, creating the parent folder.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    let mut tmp = tempfile::NamedTempFile::new_in(dir)?;
    std::io::Write::write_all(&mut tmp, bytes)?;
    tmp.as_file().sync_all()?;
    // Reports are for reading by anyone (tempfile creates 0600 files).
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        tmp.as_file()
            .set_permissions(std::fs::Permissions::from_mode(0o644))?;
    }
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// One line of the verdict table.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Row {
    pub case: String,
    pub fidelity: String,
    pub metric: String,
    pub max_abs_dev: f64,
    pub rms_dev: f64,
    /// `None`: reported for information, no verdict.
    pub tolerance: Option<f64>,
    /// `None` for information rows.
    pub pass: Option<bool>,
    pub seconds: f64,
    /// Where the largest deviation occurs, or why a row failed.
    pub note: String,
}

/// The verdict rows of a case (golden rows are added by the caller).
pub fn rows(r: &CaseResult) -> Vec<Row> {
    let mut out = Vec::new();
    for m in &r.metrics {
        for (level, _) in m.traced.iter() {
            let Some(st) = m.stats(*level) else { continue };
            let tol = m.tolerances.get(level).copied();
            out.push(Row {
                case: r.name.clone(),
                fidelity: level.to_string(),
                metric: m.name.clone(),
                max_abs_dev: st.max_abs_dev,
                rms_dev: st.rms_dev,
                tolerance: tol,
                pass: tol.map(|t| st.max_abs_dev <= t),
                seconds: r.trace_seconds,
                note: format!("max at {:.6e}", st.at),
            });
        }
    }
    // The auto choice must be exact for the primary reference.
    if let Some(primary) = r.metrics.first() {
        let (level, why) = (&r.auto.level, &r.auto.reason);
        let tol = primary.tolerances.get(&Fidelity::Vector).copied();
        if let (Some(st), Some(t)) = (primary.stats(*level), tol) {
            out.push(Row {
                case: r.name.clone(),
                fidelity: format!("auto={level}"),
                metric: primary.name.clone(),
                max_abs_dev: st.max_abs_dev,
                rms_dev: st.rms_dev,
                tolerance: Some(t),
                pass: Some(st.max_abs_dev <= t),
                seconds: r.trace_seconds,
                note: why.clone(),
            });
        }
    }
    out
}

/// `profile.csv`: per reference, coordinate, analytic, then traced and deviation per level.
pub fn profile_csv(r: &CaseResult) -> String {
    let mut s = String::new();
    let levels = &r.levels;
    let _ = write!(s, "reference,quantity,coordinate,analytic");
    for l in levels {
        let _ = write!(s, ",traced_{l},deviation_{l}");
    }
    s.push('\n');
    for m in &r.metrics {
        let devs: Vec<Option<Vec<f64>>> = levels.iter().map(|l| m.deviations(*l)).collect();
        for i in 0..m.coordinates.len() {
            let _ = write!(
                s,
                "{},{},{:.17e},{:.17e}",
                m.name,
                m.quantity(r.observable), // labels hold no comma
                m.coordinates[i],
                m.analytic[i]
            );
            for (k, l) in levels.iter().enumerate() {
                match (m.traced.get(l), &devs[k]) {
                    (Some(t), Some(d)) => {
                        let _ = write!(s, ",{:.17e},{:.6e}", t[i], d[i]);
                    }
                    _ => s.push_str(",,"),
                }
            }
            s.push('\n');
        }
    }
    s
}

/// `convergence.csv` of Airy cases.
pub fn convergence_csv(r: &CaseResult) -> String {
    let mut s = String::from("orders,internal_reflections,max_abs_dev,tail_bound\n");
    for c in &r.convergence {
        let _ = writeln!(
            s,
            "{},{},{:.6e},{:.6e}",
            c.orders, c.internal_reflections, c.max_abs_dev, c.bound
        );
    }
    s
}

/// The golden file: every traced value of every reference and level.
pub fn golden_csv(r: &CaseResult) -> String {
    let mut s = String::from("reference,fidelity,coordinate,traced\n");
    for m in &r.metrics {
        for (l, t) in &m.traced {
            for (x, v) in m.coordinates.iter().zip(t) {
                let _ = writeln!(s, "{},{},{:.17e},{:.17e}", m.name, l, x, v);
            }
        }
    }
    s
}

/// Compare a result with its golden text. `Err(Corrupt)` if the file does not parse,
/// `Err(Mismatch)` naming the first differing row; deviations are relative to each reference's
/// largest traced magnitude.
#[derive(Debug, Clone, PartialEq)]
pub enum GoldenError {
    Corrupt(String),
    Mismatch(String),
}

pub fn compare_golden(r: &CaseResult, golden: &str, tolerance: f64) -> Result<f64, GoldenError> {
    let mut lines = golden.lines();
    if lines.next() != Some("reference,fidelity,coordinate,traced") {
        return Err(GoldenError::Corrupt(
            "line 1: expected the header `reference,fidelity,coordinate,traced`".into(),
        ));
    }
    let mut expected = Vec::new();
    for (k, line) in lines.enumerate() {
        let f: Vec<&str> = line.split(',').collect();
        let parse = |x: &str| x.parse::<f64>().ok().filter(|v| v.is_finite());
        match (
            f.len(),
            f.get(2).and_then(|x| parse(x)),
            f.get(3).and_then(|x| parse(x)),
        ) {
            (4, Some(x), Some(v)) => expected.push((f[0].to_string(), f[1].to_string(), x, v)),
            _ => {
                return Err(GoldenError::Corrupt(format!(
                    "line {}: expected `reference,fidelity,coordinate,traced` with finite numbers, got {line:?}",
                    k + 2
                )));
            }
        }
    }
    let mut actual = Vec::new();
    for m in &r.metrics {
        let scale = m
            .traced
            .values()
            .flatten()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        for (l, t) in &m.traced {
            for (x, v) in m.coordinates.iter().zip(t) {
                actual.push((m.name.clone(), l.to_string(), *x, *v, scale));
            }
        }
    }
    if actual.len() != expected.len() {
        return Err(GoldenError::Mismatch(format!(
            "{} golden rows, {} traced rows (probe or references changed?)",
            expected.len(),
            actual.len()
        )));
    }
    let mut worst = 0.0f64;
    for (a, e) in actual.iter().zip(&expected) {
        if a.0 != e.0 || a.1 != e.1 || (a.2 - e.2).abs() > 1e-9 * (1.0 + e.2.abs()) {
            return Err(GoldenError::Mismatch(format!(
                "row ({}, {}, {:e}) where the golden file has ({}, {}, {:e})",
                a.0, a.1, a.2, e.0, e.1, e.2
            )));
        }
        let dev = (a.3 - e.3).abs() / a.4;
        worst = worst.max(dev);
        if dev > tolerance {
            return Err(GoldenError::Mismatch(format!(
                "{} at {} {:e}: traced {:e}, golden {:e}, relative deviation {:e} > {:e}",
                a.0, a.1, a.2, a.3, e.3, dev, tolerance
            )));
        }
    }
    Ok(worst)
}

/// The summary of one case for `summary.json`.
#[derive(Serialize)]
pub struct CaseSummary<'a> {
    pub case: &'a str,
    pub description: &'a str,
    pub formula: &'a str,
    pub auto: String,
    pub auto_reason: &'a str,
    pub internal_reflections: usize,
    pub dark_points: usize,
    pub trace_seconds: f64,
    pub rows: Vec<Row>,
}

/// Print rows as an aligned table.
pub fn table(rows: &[Row]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<26} {:<19} {:<22} {:>10} {:>10} {:>9} {:<7} {:>8}",
        "case", "fidelity", "metric", "max|dev|", "rms dev", "tol", "verdict", "seconds"
    );
    for r in rows {
        let verdict = match r.pass {
            Some(true) => "pass",
            Some(false) => "FAIL",
            None => "info",
        };
        let tol = r
            .tolerance
            .map(|t| format!("{t:.0e}"))
            .unwrap_or_else(|| "-".into());
        let _ = writeln!(
            s,
            "{:<26} {:<19} {:<22} {:>10.3e} {:>10.3e} {:>9} {:<7} {:>8.3}",
            r.case, r.fidelity, r.metric, r.max_abs_dev, r.rms_dev, tol, verdict, r.seconds
        );
    }
    s
}
