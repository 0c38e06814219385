//! `fringe tradeoff`: what each knob of a case costs and what it buys.
//!
//! For each case, every fidelity rung (docs/PHYSICS.md §4) × internal-reflection budget ×
//! spectral sample count is run on its own and compared with the case's primary closed-form
//! reference, as in `fringe check` (deviations relative to the largest reference value of a
//! profile).
//!
//! **The verdict is deterministic.** Wall times on a shared machine vary by tens of percent
//! between runs, more than the differences between rungs, so a verdict "cheapest by time" flips
//! from run to run. Settings are therefore ranked by a *cost count* that does not depend on the
//! machine: the path events the tracer visits ([`crate::harness::case::run::preflight`]: probe points ×
//! spectral samples × path events per point, which tracing time is proportional to), then, at
//! equal count, the simpler rung of the ladder (every rung traces the same exact paths; a lower
//! rung drops physics from the accumulation), then fewer internal reflections and fewer spectral
//! samples. Exact tracing uses no random numbers, so deviations — and with them the verdict —
//! are the same on every run. Wall times are still measured (`repeats` runs per setting) and
//! reported with their spread (minimum, median, maximum) as information, never as the ranking.
//!
//! **A budget under which a case cannot be traced is a row, not an abort**: e.g. a Fresnel rhomb
//! with zero internal reflections has no path through its two TIRs ("no light reaches any probe
//! point"), and a tail bound may ask for more reflections than the cap; such a setting is
//! recorded as [`Outcome::NotTraced`] with the reason, and the other settings still run.

#![warn(missing_docs)]

use crate::accumulate::fidelity::Fidelity;
use crate::harness::case::load::{Case, CaseError};
use crate::harness::case::run;
use crate::harness::case::spec::{Light, ReferenceModel};
use std::cmp::Ordering;
use std::time::Instant;

/// One setting of a case and what it gave.
#[derive(Clone, Debug, PartialEq)]
pub struct TradeoffRow {
    /// The case name.
    pub case: String,
    /// The rung of the fidelity ladder.
    pub fidelity: Fidelity,
    /// The bounce budget: a fixed number of internal reflections, or chosen per probe point
    /// from the Airy tail bound ε (`auto(ε)`).
    pub budget: Budget,
    /// Spectral samples per probe point (1 for monochrome light).
    pub spectral_samples: usize,
    /// The primary reference's tolerance at `vector` (the accuracy the case asks for; relative
    /// deviation, dimensionless).
    pub tolerance: f64,
    /// The measurement, or why this setting could not be traced.
    pub outcome: Outcome,
}

/// What running one setting gave.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// The setting was traced and compared with the reference.
    Traced(Measurement),
    /// The setting could not be traced; `reason` is the case error (`JSON_PATH: message`).
    NotTraced {
        /// Why, as `JSON_PATH: message` of the error the case run gave.
        reason: String,
    },
}

/// A traced setting.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// Internal reflections used (the largest over the probe points).
    pub internal_reflections: usize,
    /// The deterministic cost count: path events traced (probe points × spectral samples ×
    /// path events per point, see [`crate::harness::case::run::preflight`]).
    pub path_events: f64,
    /// Max deviation from the primary reference (relative, as in `check`; dimensionless).
    /// Infinite when the rung cannot represent the reference's observable.
    pub max_abs_dev: f64,
    /// Wall time of the whole case run at this setting, over the repeated runs.
    pub wall: WallTime,
}

/// Repeated wall-time measurements of one setting, in seconds: information on the spread, not
/// a ranking.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallTime {
    /// Number of timed runs.
    pub runs: usize,
    /// Fastest run (s).
    pub min: f64,
    /// Median run (s).
    pub median: f64,
    /// Slowest run (s).
    pub max: f64,
}

impl WallTime {
    /// Summary of timed runs (seconds); `None` for no runs.
    pub fn from_runs(seconds: &[f64]) -> Option<WallTime> {
        let mut s: Vec<f64> = seconds.to_vec();
        s.sort_by(f64::total_cmp);
        let n = s.len();
        if n == 0 {
            return None;
        }
        let median = if n % 2 == 1 {
            s[n / 2]
        } else {
            0.5 * (s[n / 2 - 1] + s[n / 2])
        };
        Some(WallTime {
            runs: n,
            min: s[0],
            median,
            max: s[n - 1],
        })
    }
}

impl TradeoffRow {
    /// The measurement, if the setting was traced.
    pub fn measurement(&self) -> Option<&Measurement> {
        match &self.outcome {
            Outcome::Traced(m) => Some(m),
            Outcome::NotTraced { .. } => None,
        }
    }

    /// Traced and within the tolerance.
    pub fn meets_tolerance(&self) -> bool {
        self.measurement()
            .is_some_and(|m| m.max_abs_dev <= self.tolerance)
    }
}

/// A bounce budget.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Budget {
    /// At most this many internal reflections per path.
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

/// `JSON_PATH: message` of a case error (the file is the case's, named once per case).
fn reason(e: &CaseError) -> String {
    format!("{}: {}", e.json_path, e.message)
}

/// Run one setting `repeats` times (at least once).
fn measure_setting(c: &Case, level: Fidelity, repeats: usize) -> Outcome {
    let path_events = match run::preflight(c) {
        Ok(events) => events,
        Err(e) => return Outcome::NotTraced { reason: reason(&e) },
    };
    let mut seconds = Vec::new();
    let mut dev = f64::INFINITY;
    let mut internal = 0;
    for _ in 0..repeats.max(1) {
        let t0 = Instant::now();
        let r = match run::run_with(c, false) {
            Ok(r) => r,
            Err(e) => return Outcome::NotTraced { reason: reason(&e) },
        };
        seconds.push(t0.elapsed().as_secs_f64());
        dev = r.metrics[0]
            .stats(level)
            .map_or(f64::INFINITY, |s| s.max_abs_dev);
        internal = r.internal_reflections;
    }
    let wall = WallTime::from_runs(&seconds).expect("at least one run");
    Outcome::Traced(Measurement {
        internal_reflections: internal,
        path_events,
        max_abs_dev: dev,
        wall,
    })
}

/// Measure every setting of a case. Never fails: a setting that cannot be traced is a row
/// with its reason ([`Outcome::NotTraced`]).
pub fn measure(case: &Case, repeats: usize) -> Vec<TradeoffRow> {
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
                rows.push(TradeoffRow {
                    case: case.spec.name.clone(),
                    fidelity: level,
                    budget,
                    spectral_samples: samples,
                    tolerance,
                    outcome: measure_setting(&c, level, repeats),
                });
            }
        }
    }
    rows
}

/// The deterministic cost order of two traced settings: path events, then the simpler rung,
/// then fewer internal reflections, then fewer spectral samples. `None` if either was not
/// traced.
pub(crate) fn cost_order(a: &TradeoffRow, b: &TradeoffRow) -> Option<Ordering> {
    let (ma, mb) = (a.measurement()?, b.measurement()?);
    Some(
        ma.path_events
            .total_cmp(&mb.path_events)
            .then(a.fidelity.cmp(&b.fidelity))
            .then(ma.internal_reflections.cmp(&mb.internal_reflections))
            .then(a.spectral_samples.cmp(&b.spectral_samples)),
    )
}

/// The cheapest setting meeting the tolerance, by the deterministic cost order
/// (`cost_order`); wall times play no part.
pub fn cheapest(rows: &[TradeoffRow]) -> Option<&TradeoffRow> {
    rows.iter()
        .filter(|r| r.meets_tolerance())
        .min_by(|a, b| cost_order(a, b).unwrap_or(Ordering::Equal))
}

/// Whether each row is on the Pareto front of cost (path events, then rung) against error: no
/// other traced setting is at most as costly and at most as wrong, and strictly better in one.
/// Settings that were not traced are never on the front.
pub fn pareto(rows: &[TradeoffRow]) -> Vec<bool> {
    let key = |r: &TradeoffRow| r.measurement().map(|m| (m.path_events, r.fidelity));
    rows.iter()
        .map(|r| {
            let (Some((cost, rung)), Some(m)) = (key(r), r.measurement()) else {
                return false;
            };
            !rows.iter().any(|o| {
                let (Some((oc, orung)), Some(om)) = (key(o), o.measurement()) else {
                    return false;
                };
                let cheaper_or_equal = (oc, orung) <= (cost, rung);
                let strictly_cheaper = (oc, orung) < (cost, rung);
                cheaper_or_equal
                    && om.max_abs_dev <= m.max_abs_dev
                    && (strictly_cheaper || om.max_abs_dev < m.max_abs_dev)
            })
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

/// The columns of `tradeoff.csv`.
pub const CSV_HEADER: [&str; 15] = [
    "case",
    "fidelity",
    "bounce_budget",
    "spectral_samples",
    "traced",
    "internal_reflections",
    "path_events",
    "max_abs_dev",
    "tolerance",
    "meets_tolerance",
    "pareto",
    "runs",
    "seconds_min",
    "seconds_median",
    "seconds_max",
];

/// `tradeoff.csv` text: two `#` comment lines (machine, how to read it), the header
/// [`CSV_HEADER`] plus a `reason` column, one row per setting. A setting that was not traced has
/// `traced` = false, empty measurement columns and its reason.
pub fn csv(rows: &[TradeoffRow]) -> String {
    let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
    let mut header: Vec<&str> = CSV_HEADER.to_vec();
    header.push("reason");
    // Writing CSV records into a Vec cannot fail.
    let _ = w.write_record(&header);
    for (r, on_front) in rows.iter().zip(pareto(rows)) {
        let mut rec = vec![
            r.case.clone(),
            r.fidelity.to_string(),
            r.budget.to_string(),
            r.spectral_samples.to_string(),
        ];
        match &r.outcome {
            Outcome::Traced(m) => {
                rec.extend([
                    "true".to_string(),
                    m.internal_reflections.to_string(),
                    format!("{:.0}", m.path_events),
                    format!("{:.6e}", m.max_abs_dev),
                    format!("{:.1e}", r.tolerance),
                    r.meets_tolerance().to_string(),
                    on_front.to_string(),
                    m.wall.runs.to_string(),
                    format!("{:.6e}", m.wall.min),
                    format!("{:.6e}", m.wall.median),
                    format!("{:.6e}", m.wall.max),
                    String::new(),
                ]);
            }
            Outcome::NotTraced { reason } => {
                let empty = String::new;
                rec.extend([
                    "false".to_string(),
                    empty(),
                    empty(),
                    empty(),
                    format!("{:.1e}", r.tolerance),
                    "false".to_string(),
                    "false".to_string(),
                    empty(),
                    empty(),
                    empty(),
                    empty(),
                    reason.clone(),
                ]);
            }
        }
        let _ = w.write_record(&rec);
    }
    let body = w
        .into_inner()
        .map(|b| String::from_utf8_lossy(&b).into_owned())
        .unwrap_or_default();
    format!(
        "# machine: {}\n# ranking: path_events (deterministic cost count), then the simpler rung; seconds are repeated wall times (min, median, max) for information; deviations relative to the primary reference, as in `fringe check`\n{body}",
        machine()
    )
}

/// The summary line of a case: the cheapest setting within tolerance by the deterministic cost
/// order, its cost count, its measured wall time with the spread, the settings of equal cost
/// count that also meet the tolerance (a tie, settled for the simpler rung), and how many
/// settings could not be traced.
pub fn summary(case: &str, rows: &[TradeoffRow]) -> String {
    let not_traced = rows.iter().filter(|r| r.measurement().is_none()).count();
    let untraced = if not_traced > 0 {
        format!("; {not_traced} setting(s) not traced (see tradeoff.csv)")
    } else {
        String::new()
    };
    let Some(best) = cheapest(rows) else {
        return format!("{case}: no setting tried meets the tolerance{untraced}");
    };
    let m = best.measurement().expect("the cheapest setting was traced");
    let ties: Vec<String> = rows
        .iter()
        .filter(|r| {
            !std::ptr::eq(*r, best)
                && r.meets_tolerance()
                && r.measurement().map(|o| o.path_events) == Some(m.path_events)
                && r.fidelity != best.fidelity
        })
        .map(|r| r.fidelity.to_string())
        .collect();
    let tie = if ties.is_empty() {
        String::new()
    } else {
        let mut t = ties;
        t.dedup();
        format!(
            "; tie in cost with {} (the simpler model is chosen)",
            t.join(", ")
        )
    };
    format!(
        "{case}: cheapest setting within {:.0e}: {} with bounce budget {} ({} internal reflections) and {} spectral sample(s): {:.3e} path events, wall time {:.3e} s (median of {}; range {:.3e}–{:.3e} s), max |dev| {:.2e}{tie}{untraced}",
        best.tolerance,
        best.fidelity,
        best.budget,
        m.internal_reflections,
        best.spectral_samples,
        m.path_events,
        m.wall.median,
        m.wall.runs,
        m.wall.min,
        m.wall.max,
        m.max_abs_dev
    )
}
