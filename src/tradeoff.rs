//! `fringe tradeoff`: the measured speed–accuracy trade of every knob, per case.
//!
//! For each case, every fidelity level × internal-reflection budget × spectral sample count is
//! run on its own (wall time measured around the whole case run at that setting, single level)
//! and compared with the case's primary closed-form reference. The output is `tradeoff.csv`
//! (machine described in its header) and one summary line per case naming the cheapest setting
//! that meets the case's own tolerance at that level. Settings are deterministic (no random
//! numbers are involved in exact tracing); timings are best-of-`repeats` wall times.

use crate::case::load::{Case, CaseError};
use crate::case::run;
use crate::case::spec::{Light, ReferenceModel};
use crate::fidelity::Fidelity;
use std::fmt::Write as _;
use std::time::Instant;

/// One measured setting.
#[derive(Clone, Debug, PartialEq)]
pub struct TradeoffRow {
    pub case: String,
    pub fidelity: Fidelity,
    /// The bounce budget: a fixed number of internal reflections, or chosen per probe point
    /// from the Airy tail bound ε (`auto(ε)`).
    pub budget: Budget,
    /// Internal reflections used (the largest over the probe points).
    pub internal_reflections: usize,
    pub spectral_samples: usize,
    pub seconds: f64,
    /// Max deviation from the primary reference (relative, as in `check`).
    pub max_abs_dev: f64,
    /// The primary reference's tolerance at `vector` (the accuracy the case asks for).
    pub tolerance: f64,
}

/// A bounce budget.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Budget {
    Fixed(usize),
    /// Orders chosen per probe point so the Airy amplitude tail is below ε.
    TailBound(f64),
}

impl std::fmt::Display for Budget {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Budget::Fixed(n) => write!(f, "{n}"),
            Budget::TailBound(e) => write!(f, "auto({e:.0e})"),
        }
    }
}

/// The bounce budgets tried for a case.
fn bounce_budgets(case: &Case) -> Vec<Budget> {
    if case.spec.scene.surfaces.is_empty() {
        return vec![Budget::Fixed(case.spec.trace.max_internal_reflections)];
    }
    let airy = case
        .spec
        .references
        .iter()
        .any(|r| matches!(r.model, ReferenceModel::Airy { .. }));
    if airy {
        let mut v: Vec<Budget> = [1, 3, 5, 9, 17, 33]
            .into_iter()
            .map(Budget::Fixed)
            .collect();
        v.extend([1e-4, 1e-7, 1e-10, 1e-13].map(Budget::TailBound));
        v
    } else {
        let base = case.spec.trace.max_internal_reflections;
        let mut v = vec![0, base, base + 2];
        v.dedup();
        v.into_iter().map(Budget::Fixed).collect()
    }
}

fn sample_counts(case: &Case) -> Vec<usize> {
    match case.spec.light {
        Light::Monochrome { .. } => vec![1],
        Light::Gaussian { samples, .. } => {
            let mut v: Vec<usize> = [9, 17, 33, 65, samples]
                .into_iter()
                .filter(|&s| s <= samples)
                .collect();
            v.sort_unstable();
            v.dedup();
            v
        }
    }
}

/// A copy of `case` at one setting (the copy bypasses validation: only knobs change).
fn at_setting(case: &Case, level: Fidelity, budget: Budget, samples: usize) -> Case {
    let mut c = case.clone();
    c.spec.fidelities = Some(vec![level]);
    match budget {
        Budget::Fixed(n) => {
            c.spec.trace.max_internal_reflections = n;
            c.spec.trace.airy_tail_epsilon = None;
        }
        Budget::TailBound(e) => c.spec.trace.airy_tail_epsilon = Some(e),
    }
    if let Light::Gaussian { samples: s, .. } = &mut c.spec.light {
        *s = samples;
    }
    // Only the primary reference is measured.
    c.spec.references.truncate(1);
    c
}

/// Measure every setting of a case.
pub fn measure(case: &Case, repeats: usize) -> Result<Vec<TradeoffRow>, CaseError> {
    let tolerance = case.spec.references[0]
        .tolerances
        .get(&Fidelity::Vector)
        .copied()
        .unwrap_or(0.0);
    let mut rows = Vec::new();
    for level in Fidelity::ALL {
        for &budget in &bounce_budgets(case) {
            for &samples in &sample_counts(case) {
                let c = at_setting(case, level, budget, samples);
                let mut best = f64::INFINITY;
                let mut dev = f64::NAN;
                let mut internal = 0;
                for _ in 0..repeats.max(1) {
                    let t0 = Instant::now();
                    let r = run::run_with(&c, false)?;
                    best = best.min(t0.elapsed().as_secs_f64());
                    dev = r.metrics[0]
                        .stats(level)
                        .map_or(f64::INFINITY, |s| s.max_abs_dev);
                    internal = r.internal_reflections;
                }
                rows.push(TradeoffRow {
                    case: case.spec.name.clone(),
                    fidelity: level,
                    budget,
                    internal_reflections: internal,
                    spectral_samples: samples,
                    seconds: best,
                    max_abs_dev: dev,
                    tolerance,
                });
            }
        }
    }
    Ok(rows)
}

/// The cheapest setting meeting the tolerance, if any.
pub fn cheapest(rows: &[TradeoffRow]) -> Option<&TradeoffRow> {
    rows.iter()
        .filter(|r| r.max_abs_dev <= r.tolerance)
        .min_by(|a, b| a.seconds.total_cmp(&b.seconds))
}

/// Whether each row is on the Pareto front (time vs error): no other setting is both faster
/// and more accurate.
pub fn pareto(rows: &[TradeoffRow]) -> Vec<bool> {
    rows.iter()
        .map(|r| {
            !rows
                .iter()
                .any(|o| o.seconds < r.seconds && o.max_abs_dev < r.max_abs_dev)
        })
        .collect()
}

/// A description of this machine for the CSV header.
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .map(|l| l.split(':').nth(1).unwrap_or("").trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let threads = rayon::current_num_threads();
    format!(
        "{cpu}; {threads} threads; {} {}",
        std::env::consts::OS,
        std::env::consts::ARCH
    )
}

/// `tradeoff.csv` text.
pub fn csv(rows: &[TradeoffRow]) -> String {
    let mut s = format!(
        "# machine: {}\n# timings: best wall time of repeated runs; deviations relative to the primary reference, as in `fringe check`\n",
        machine()
    );
    s.push_str("case,fidelity,bounce_budget,internal_reflections,spectral_samples,seconds,max_abs_dev,tolerance,meets_tolerance,pareto\n");
    for (r, on_front) in rows.iter().zip(pareto(rows)) {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{:.6e},{:.6e},{:.1e},{},{}",
            r.case,
            r.fidelity,
            r.budget,
            r.internal_reflections,
            r.spectral_samples,
            r.seconds,
            r.max_abs_dev,
            r.tolerance,
            r.max_abs_dev <= r.tolerance,
            on_front
        );
    }
    s
}

/// The summary line of a case.
pub fn summary(case: &str, rows: &[TradeoffRow]) -> String {
    match cheapest(rows) {
        Some(r) => format!(
            "{case}: cheapest setting within {:.0e}: {} with bounce budget {} ({} internal reflections) and {} spectral sample(s), {:.3e} s (max |dev| {:.2e})",
            r.tolerance,
            r.fidelity,
            r.budget,
            r.internal_reflections,
            r.spectral_samples,
            r.seconds,
            r.max_abs_dev
        ),
        None => format!("{case}: no setting tried meets the tolerance"),
    }
}
