//! The gate's verdict on a case run: its rows (case × fidelity × observable against the
//! tolerance), the golden file of its traced values and the comparison with it, the per-case
//! CSV profiles and the JSON summary. Data only: files are written by the command layer
//! through [`crate::io`], the table and pictures drawn by the outputs (`output::report`).

use crate::accumulate::fidelity::Fidelity;
use crate::harness::case::run::CaseResult;
use crate::io::csv_text;
use serde::Serialize;

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
                note: match m.derived_tolerance(&r.rounding, 0.0) {
                    // What the arithmetic allows (docs/PHYSICS.md §8): the fuzz gate's tolerance.
                    Some(d) if *level == Fidelity::Vector => {
                        format!("max at {:.6e}; the arithmetic allows {d:.1e}", st.at)
                    }
                    _ => format!("max at {:.6e}", st.at),
                },
            });
        }
    }
    // What the primary reference's gate can see: an injected error of the floor's size on one
    // path fails it; a floor beyond FLOOR_FACTOR × tolerance means the case cannot see errors.
    if let (Some(d), Some(primary)) = (&r.detection, r.metrics.first()) {
        use crate::harness::case::detection::{FLOOR_FACTOR, Floor};
        for (what, floor) in [("phase", d.phase_rad), ("amplitude", d.amplitude)] {
            let limit = FLOOR_FACTOR * d.tolerance;
            let unit = if what == "phase" { "rad" } else { "relative" };
            let (value, tolerance, pass, note) = match floor {
                Floor::Caught(f) => (
                    f,
                    Some(limit),
                    Some(f <= limit),
                    format!(
                        "smallest {what} error on one path ({unit}) that fails {} at tolerance {:e}",
                        primary.name, d.tolerance
                    ),
                ),
                Floor::Blind => (
                    f64::INFINITY,
                    Some(limit),
                    Some(false),
                    format!(
                        "a {what} error of 1 on one path does not fail {}",
                        primary.name
                    ),
                ),
                // Nothing to detect (no interference for a phase, a vanishing closed form):
                // no row, so every row of the table stays a finite number.
                Floor::NotApplicable(_) => continue,
            };
            out.push(Row {
                case: r.name.clone(),
                fidelity: "vector".into(),
                metric: format!("detect_{what}"),
                max_abs_dev: value,
                rms_dev: value,
                tolerance,
                pass,
                seconds: 0.0,
                note,
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
pub(crate) fn profile_csv(r: &CaseResult) -> String {
    let levels = &r.levels;
    let mut header: Vec<String> = ["reference", "quantity", "coordinate", "analytic"]
        .map(String::from)
        .to_vec();
    for l in levels {
        header.push(format!("traced_{l}"));
        header.push(format!("deviation_{l}"));
    }
    let mut rows = Vec::new();
    for m in &r.metrics {
        let devs: Vec<Option<Vec<f64>>> = levels.iter().map(|l| m.deviations(*l)).collect();
        for i in 0..m.coordinates.len() {
            let mut row = vec![
                m.name.clone(),
                m.quantity(r.observable).to_string(),
                format!("{:.17e}", m.coordinates[i]),
                format!("{:.17e}", m.analytic[i]),
            ];
            for (k, l) in levels.iter().enumerate() {
                match (m.traced.get(l), &devs[k]) {
                    (Some(t), Some(d)) => {
                        row.push(format!("{:.17e}", t[i]));
                        row.push(format!("{:.6e}", d[i]));
                    }
                    _ => row.extend([String::new(), String::new()]),
                }
            }
            rows.push(row);
        }
    }
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    csv_text(&header, rows)
}

/// `convergence.csv` of Airy cases.
pub(crate) fn convergence_csv(r: &CaseResult) -> String {
    csv_text(
        &[
            "orders",
            "internal_reflections",
            "max_abs_dev",
            "tail_bound",
        ],
        r.convergence.iter().map(|c| {
            vec![
                c.orders.to_string(),
                c.internal_reflections.to_string(),
                format!("{:.6e}", c.max_abs_dev),
                format!("{:.6e}", c.bound),
            ]
        }),
    )
}

/// The header of a golden file.
const GOLDEN_HEADER: [&str; 4] = ["reference", "fidelity", "coordinate", "traced"];

/// The golden file: every traced value of every reference and level.
pub fn golden_csv(r: &CaseResult) -> String {
    let mut rows = Vec::new();
    for m in &r.metrics {
        for (l, t) in &m.traced {
            for (x, v) in m.coordinates.iter().zip(t) {
                rows.push(vec![
                    m.name.clone(),
                    l.to_string(),
                    format!("{x:.17e}"),
                    format!("{v:.17e}"),
                ]);
            }
        }
    }
    csv_text(&GOLDEN_HEADER, rows)
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
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(golden.as_bytes());
    let mut records = reader.records();
    let header_ok = matches!(records.next(), Some(Ok(h)) if h.iter().eq(GOLDEN_HEADER));
    if !header_ok {
        return Err(GoldenError::Corrupt(
            "line 1: expected the header `reference,fidelity,coordinate,traced`".into(),
        ));
    }
    let mut expected = Vec::new();
    for (k, record) in records.enumerate() {
        let bad = |got: String| {
            GoldenError::Corrupt(format!(
                "line {}: expected `reference,fidelity,coordinate,traced` with finite numbers, got {got}",
                k + 2
            ))
        };
        let f = record.map_err(|e| bad(e.to_string()))?;
        let parse = |x: &str| x.parse::<f64>().ok().filter(|v| v.is_finite());
        match (f.len(), f.get(2).and_then(parse), f.get(3).and_then(parse)) {
            (4, Some(x), Some(v)) => expected.push((f[0].to_string(), f[1].to_string(), x, v)),
            _ => return Err(bad(format!("{:?}", f.iter().collect::<Vec<_>>()))),
        }
    }
    let mut actual = Vec::new();
    for m in &r.metrics {
        let scale = m
            .traced
            .values()
            .flatten()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            // brewster_extinction's R_p is exactly 0; its traced ~1e-32 change with any rounding.
            .max(crate::harness::case::run::VANISHING_SCALE);
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

/// Roundings a traced optical path may carry, in units of the f64 unit roundoff, per unit of
/// its length: every segment length (differences, a dot product, a square root) and the sum of
/// segments round a few times; 8 covers them with room.
const PATH_ROUNDINGS: f64 = 8.0;

/// The tolerance of a case's golden comparison: the case's `golden_tolerance`, or the
/// conditioning bound of its traced values when that is larger. Golden files are not bit for
/// bit reproducible across CPUs (libm's sin, cos, exp and pow differ in the last bit between
/// implementations, e.g. glibc's FMA variants): a traced value is reproducible only to its
/// conditioning. An interference intensity I = |Σ E_k e^{iφ_k}|² with phases φ_k = 2π s_k/λ
/// (P10) moves by |δI| ≤ 2 (Σ|E_k|)² max|δφ_k| when its phases move by δφ_k, and a path s
/// rounded with relative error ε·u moves its phase by 2π n s ε u/λ: relative to the profile's
/// largest value (≈ (Σ|E_k|)² at a bright fringe) the deviation is at most 2 Φ ε u with
/// Φ = 2π n_max S/λ_min, S = (m + 2 + 2 × surfaces) × D the longest path (segments × the
/// diameter D of the scene's points: sources, probe points, surface points), m the internal
/// reflections traced. Michelson (S ≈ 0.6 m at 600 nm): Φ ≈ 6e6 rad, bound ≈ 1.2e-8.
pub fn golden_tolerance(case: &crate::harness::case::load::Case, r: &CaseResult) -> f64 {
    use crate::harness::case::spec::{EmitterSpec, Observer, SurfaceSpec};
    let spec = &case.spec;
    let mut points: Vec<glam::DVec3> = Vec::new();
    for s in &spec.scene.sources {
        points.push(glam::DVec3::from_array(match &s.emitter {
            EmitterSpec::Point { position_m } => *position_m,
            EmitterSpec::Line { point_m, .. } => *point_m,
            EmitterSpec::PlaneWave {
                reference_point_m, ..
            } => *reference_point_m,
        }));
    }
    for s in &spec.scene.surfaces {
        points.push(glam::DVec3::from_array(match s {
            SurfaceSpec::Interface { point_m, .. }
            | SurfaceSpec::Mirror { point_m, .. }
            | SurfaceSpec::Splitter { point_m, .. }
            | SurfaceSpec::Shield { point_m, .. }
            | SurfaceSpec::OpaqueScreen { point_m, .. } => *point_m,
            SurfaceSpec::Plate { top_point_m, .. } | SurfaceSpec::Wedge { top_point_m, .. } => {
                *top_point_m
            }
        }));
    }
    for p in crate::harness::case::build::probe_points(&spec.probe) {
        match &p.observer {
            Observer::Point { position_m, .. } => points.push(glam::DVec3::from_array(*position_m)),
            Observer::Direction {
                reference_point_m, ..
            } => points.push(glam::DVec3::from_array(*reference_point_m)),
            Observer::FarField { .. } => {}
        }
    }
    let mut diameter = 0.0f64;
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            diameter = diameter.max((*a - *b).length());
        }
    }
    // Far-field observers and thin scenes: at least the thickest slab.
    for s in &spec.scene.surfaces {
        if let SurfaceSpec::Plate { thickness_um, .. } | SurfaceSpec::Wedge { thickness_um, .. } = s
        {
            diameter = diameter.max(thickness_um * 1e-6);
        }
    }
    let spectrum = crate::harness::case::build::spectrum(&spec.light, &Default::default());
    let mut lambda_min = spectrum.iter().map(|s| s.0).fold(f64::INFINITY, f64::min);
    if let crate::harness::case::spec::Probe::Sweep {
        parameter: crate::harness::case::spec::SweepParameter::WavelengthNm {},
        from,
        to,
        ..
    } = &spec.probe
    {
        lambda_min = lambda_min.min(from.min(*to) * 1e-9);
    }
    let n_max = spec
        .scene
        .media
        .iter()
        .filter_map(|(name, m)| {
            let m = crate::harness::case::build::medium(name, m);
            spectrum
                .iter()
                .filter_map(|s| m.index(s.0).ok())
                .reduce(f64::max)
        })
        .fold(1.0f64, f64::max);
    let segments = (r.internal_reflections + 2 + spec.scene.surfaces.len() * 2) as f64;
    let phase = 2.0 * std::f64::consts::PI * n_max * segments * diameter / lambda_min;
    let bound = 2.0 * phase * PATH_ROUNDINGS * f64::EPSILON / 2.0;
    spec.trace.golden_tolerance.max(bound)
}

/// The summary of one case for `summary.json`.
#[derive(Serialize)]
pub(crate) struct CaseSummary<'a> {
    pub case: &'a str,
    pub description: &'a str,
    pub formula: &'a str,
    pub auto: String,
    pub auto_reason: &'a str,
    pub internal_reflections: usize,
    pub dark_points: usize,
    pub trace_seconds: f64,
    /// The work the preflight estimated (units of `case::run::preflight`), to compare with
    /// `trace_seconds`.
    pub work_units: f64,
    pub rows: Vec<Row>,
    /// The metrics with one value (a retardance, a fringe spacing, a visibility): the page
    /// shows their numbers, as they have no profile to plot.
    pub point_values: Vec<PointValue>,
}

/// A single-valued metric of a case: its closed form and what every level traced.
#[derive(Serialize)]
pub(crate) struct PointValue {
    /// The reference's name in the case file.
    pub metric: String,
    /// What is measured, with its unit (e.g. "retardance arg E_p − arg E_s (rad)").
    pub quantity: &'static str,
    /// The closed-form value.
    pub closed_form: f64,
    /// The traced value per fidelity level (levels where the metric is undefined are absent).
    pub traced: Vec<(String, f64)>,
}

/// The [`PointValue`]s of a case result: every metric evaluated at a single coordinate.
pub(crate) fn point_values(r: &CaseResult) -> Vec<PointValue> {
    r.metrics
        .iter()
        .filter(|m| m.analytic.len() == 1)
        .map(|m| PointValue {
            metric: m.name.clone(),
            quantity: m.quantity(r.observable),
            closed_form: m.analytic[0],
            traced: m
                .traced
                .iter()
                .filter_map(|(l, v)| Some((l.name().to_string(), *v.first()?)))
                .collect(),
        })
        .collect()
}
