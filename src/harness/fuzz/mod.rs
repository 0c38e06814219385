//! `fringe fuzz`: random valid scenes of every family with a closed form, each run through the
//! same load → preflight → run → compare path as `fringe check` (the case loader
//! [`crate::harness::case::load::parse`], [`crate::harness::case::run::preflight`] and
//! [`crate::harness::case::run::run_with`]) and judged at the `vector` level against its primary
//! reference at the scene's derived tolerance: what the arithmetic allows
//! ([`crate::harness::conditioning`], docs/PHYSICS.md §8), at least [`DERIVED_FLOOR`] and never looser
//! than the case's own tolerance.
//!
//! Each scene is drawn from its own seeded stream ([`draws::scene_seed`]: seed, family, index),
//! so a run is deterministic for a seed whatever the families or counts asked for. A scene is
//!
//! - **pass**: the `vector` deviation is within the tolerance;
//! - **fail**: above it, non-finite, or the tracer panicked; a failure is shrunk
//!   ([`shrink`]) and written as a minimal case file;
//! - **refused**: the loader, the work preflight, the runner or the reference returned a
//!   [`crate::harness::case::load::CaseError`] (a documented cap, or a scene outside the model's
//!   assumptions), or the generator could not build the family's geometry for the drawn
//!   parameters; counted with its reason;
//! - **skipped**: it carries a region tag the run was told to skip (`--skip`), not run.

pub mod draws;
pub mod families;
pub mod motion;
pub mod shrink;

use crate::accumulate::fidelity::Fidelity;
use crate::harness::case::{load, run};
use draws::Draws;
pub use families::Family;
use motion::RigidMotion;
use rayon::prelude::*;
use serde_json::Value;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Largest translation of a scene (m): with the generators' reach of 250 m every coordinate
/// stays inside the ±1000 m range of case files.
pub(crate) const MAX_OFFSET_M: f64 = 500.0;
/// Probability that a scene is rotated, and that it is translated.
pub(crate) const P_ROTATE: f64 = 0.75;
pub(crate) const P_TRANSLATE: f64 = 0.5;
/// Evaluations a failure's shrinking may spend.
pub(crate) const SHRINK_BUDGET: usize = 300;

/// A deliberate change applied to every generated scene after it is drawn (for tests that
/// show the fuzzer catches and shrinks a known defect, e.g. a wrong reference parameter).
pub(crate) type Mutation = fn(&mut Value);

/// Options of a fuzz run.
#[derive(Clone, Debug)]
pub struct FuzzOptions {
    pub families: Vec<Family>,
    /// Scenes per family.
    pub count: usize,
    pub seed: u64,
    /// Region tags whose scenes are skipped (not run).
    pub skip: Vec<String>,
    pub shrink_budget: usize,
    pub mutation: Option<Mutation>,
}

impl Default for FuzzOptions {
    fn default() -> Self {
        FuzzOptions {
            families: Family::ALL.to_vec(),
            count: 100,
            seed: 1,
            skip: Vec::new(),
            shrink_budget: SHRINK_BUDGET,
            mutation: None,
        }
    }
}

/// One generated scene: its draws (to replay or shrink), region tags and case file (or the
/// generator's reason for not building one).
#[derive(Clone, Debug)]
pub struct Scene {
    pub family: Family,
    pub draws: Vec<f64>,
    pub kinds: Vec<draws::DrawKind>,
    pub tags: Vec<&'static str>,
    pub case: Result<Value, String>,
}

/// Scene `index` of `family` for `seed`.
pub fn scene(family: Family, seed: u64, index: usize, mutation: Option<Mutation>) -> Scene {
    build(
        family,
        Draws::new(draws::scene_seed(seed, family as usize, index)),
        mutation,
    )
}

/// The scene of `family` regenerated from recorded draws.
pub fn replay(family: Family, values: &[f64], mutation: Option<Mutation>) -> Scene {
    build(family, Draws::replay(values.to_vec()), mutation)
}

fn build(family: Family, mut d: Draws, mutation: Option<Mutation>) -> Scene {
    let mut tags = Vec::new();
    let mut case = family.generate(&mut d, &mut tags);
    let motion = RigidMotion::draw(&mut d, P_ROTATE, P_TRANSLATE, MAX_OFFSET_M, &mut tags);
    if let Ok(c) = &mut case {
        motion.apply(c);
        if let Some(m) = mutation {
            m(c);
        }
    }
    Scene {
        family,
        kinds: d.kinds,
        draws: d.record,
        tags,
        case,
    }
}

/// The least tolerance the fuzz gate applies (relative): the library's exact-reference
/// tolerance; the derived one is usually far below it (docs/PHYSICS.md §8).
pub const DERIVED_FLOOR: f64 = 1e-12;

/// The verdict on one scene.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    Pass {
        deviation: f64,
    },
    Fail {
        /// Largest `vector` deviation (NaN for non-finite values or a panic).
        deviation: f64,
        tolerance: f64,
        /// Probe coordinate of the largest deviation.
        at: f64,
        note: String,
    },
    Refused {
        reason: String,
    },
    Skipped,
}

impl Verdict {
    /// Severity of a failure for comparisons (NaN ranks above every number).
    fn severity(&self) -> Option<f64> {
        match self {
            Verdict::Fail { deviation, .. } if deviation.is_nan() => Some(f64::INFINITY),
            Verdict::Fail { deviation, .. } => Some(*deviation),
            _ => None,
        }
    }
}

/// Judge a case file (JSON) as `fringe check` would at the `vector` level of its primary
/// reference: load and validate, preflight the work, run, compare with the case's tolerance.
pub fn judge(case: &Value, file: &Path) -> Verdict {
    let refused = |e: load::CaseError| Verdict::Refused {
        reason: format!("{}: {}", e.json_path, e.message),
    };
    let text = match serde_json::to_string(case) {
        Ok(t) => t,
        Err(e) => {
            return Verdict::Refused {
                reason: format!("$: cannot serialize the case: {e}"),
            };
        }
    };
    let case = match load::parse(file, &text) {
        Ok(c) => c,
        Err(e) => return refused(e),
    };
    if let Err(e) = run::preflight(&case) {
        return refused(e);
    }
    let ran =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run::run_with(&case, false)));
    let result = match ran {
        Ok(Ok(r)) => r,
        Ok(Err(e)) => return refused(e),
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            return Verdict::Fail {
                deviation: f64::NAN,
                tolerance: 0.0,
                at: f64::NAN,
                note: format!("the tracer panicked: {msg}"),
            };
        }
    };
    let Some(primary) = result.metrics.first() else {
        return Verdict::Refused {
            reason: "$.references: no primary reference".into(),
        };
    };
    // The tolerance the arithmetic allows this scene (docs/PHYSICS.md §8, derived from the
    // conditioning of the traced sum, at least 1e-12), never looser than the case's own: a
    // verdict means "outside what the arithmetic allows", not "outside a flat 1e-9".
    let stated = primary
        .tolerances
        .get(&Fidelity::Vector)
        .copied()
        .unwrap_or(0.0);
    // Plus the scene's representation sensitivity (docs/PHYSICS.md §8): how far the exact
    // observable moves when the scene's plane-wave direction turns by the rounding an f64 scene
    // holds it to (a thick plate in a rotated frame), which no f64 tracer can avoid.
    let representation = result.representation_tolerance();
    let derived = primary.derived_tolerance(&result.rounding, DERIVED_FLOOR);
    let tolerance = derived.map_or(stated, |d| d.min(stated)) + representation;
    let Some(stats) = primary.stats(Fidelity::Vector) else {
        return Verdict::Refused {
            reason: "$.references[0]: the primary reference has no traced value at vector".into(),
        };
    };
    let traced = &primary.traced[&Fidelity::Vector];
    let finite = primary.analytic.iter().chain(traced).all(|x| x.is_finite());
    if !finite || stats.max_abs_dev.is_nan() {
        return Verdict::Fail {
            deviation: f64::NAN,
            tolerance,
            at: stats.at,
            note: "non-finite traced or closed-form values".into(),
        };
    }
    if stats.max_abs_dev <= tolerance {
        Verdict::Pass {
            deviation: stats.max_abs_dev,
        }
    } else if let Some(reason) =
        beyond_resolution(stats.max_abs_dev, stated, derived, representation)
    {
        Verdict::Refused { reason }
    } else {
        let k = primary
            .coordinates
            .iter()
            .position(|c| *c == stats.at)
            .unwrap_or(0);
        Verdict::Fail {
            deviation: stats.max_abs_dev,
            tolerance,
            at: stats.at,
            note: format!(
                "traced {:e}, closed form {:e} at coordinate {:e}{}",
                traced[k],
                primary.analytic[k],
                stats.at,
                if representation > 1e-3 * tolerance {
                    format!(
                        " (tolerance includes {representation:.2e}: the scene's direction \
                         held to one rounding moves the observable that far)"
                    )
                } else {
                    String::new()
                }
            ),
        }
    }
}

/// The refusal of a scene the case's tolerance cannot judge: its deviation `deviation` exceeds
/// the `stated` tolerance but not what the arithmetic allows (`derived`, the bound of
/// [`crate::harness::conditioning::intensity_rounding`] relative to the profile, plus the
/// `representation` sensitivity), and that bound is above the stated tolerance. There an f64
/// tracer, which holds every event point to a rounding of its coordinates, cannot be told
/// right from wrong at the stated tolerance: the scene is refused, never passed (a deviation
/// beyond the bound still fails). The class met (docs/PHYSICS.md §8): a point source and a
/// plate of n2 ≪ n1 translated metres away with sub-millimetre legs, the top beam within 1e-6
/// of the critical angle, where one rounding of a hit point's coordinates (u X, X ~ 10 m) moves
/// sin θ by u X/ℓ ~ 1e-8 of itself and r_p by 1e-5 (fuzz `two_beam_plate` seed 1, near_brewster;
/// the same scenes untranslated trace to 1e-15 of 50 digits, `tests/suite/truth_point_sources.rs`).
pub fn beyond_resolution(
    deviation: f64,
    stated: f64,
    derived: Option<f64>,
    representation: f64,
) -> Option<String> {
    let bound = derived? + representation;
    (bound > stated + representation && deviation <= bound).then(|| {
        format!(
            "$.probe: the tracer holds its event points in f64, which resolves this scene only \
             to {bound:.1e} of the profile (one rounding of a hit point's coordinates tilts \
             the incidence angles, docs/PHYSICS.md §8), beyond the case's tolerance \
             {stated:e}: deviation {deviation:.1e} cannot be judged (a tracer limit, not a pass)"
        )
    })
}

fn scene_file(family: Family, seed: u64, index: usize) -> PathBuf {
    PathBuf::from(format!("fuzz_{}_s{seed}_{index}.json", family.name()))
}

fn skipped(scene: &Scene, skip: &[String]) -> bool {
    scene.tags.iter().any(|t| skip.iter().any(|s| s == t))
}

/// The outcome of one scene.
#[derive(Clone, Debug)]
pub struct SceneResult {
    pub family: Family,
    pub index: usize,
    pub tags: Vec<&'static str>,
    pub verdict: Verdict,
}

/// A failure and its shrunk case.
#[derive(Clone, Debug)]
pub struct Failure {
    pub family: Family,
    pub index: usize,
    pub tags: Vec<&'static str>,
    /// The verdict on the scene as drawn.
    pub original: Verdict,
    /// The verdict on the shrunk scene.
    pub shrunk: Verdict,
    pub shrunk_tags: Vec<&'static str>,
    /// The shrunk case file, named and described.
    pub case: Value,
    /// File name under the output folder.
    pub file_name: String,
}

/// Everything a fuzz run found.
#[derive(Clone, Debug)]
pub struct FuzzReport {
    pub seed: u64,
    pub results: Vec<SceneResult>,
    pub failures: Vec<Failure>,
}

/// Run the scenes of `opts`, then shrink every failure. Deterministic for a seed.
pub fn run(opts: &FuzzOptions) -> FuzzReport {
    let jobs: Vec<(Family, usize)> = opts
        .families
        .iter()
        .flat_map(|f| (0..opts.count).map(move |i| (*f, i)))
        .collect();
    let results: Vec<SceneResult> = jobs
        .par_iter()
        .map(|&(family, index)| {
            let sc = scene(family, opts.seed, index, opts.mutation);
            let verdict = if skipped(&sc, &opts.skip) {
                Verdict::Skipped
            } else {
                match &sc.case {
                    Err(reason) => Verdict::Refused {
                        reason: format!("generator: {reason}"),
                    },
                    Ok(c) => judge(c, &scene_file(family, opts.seed, index)),
                }
            };
            SceneResult {
                family,
                index,
                tags: sc.tags,
                verdict,
            }
        })
        .collect();
    let failures: Vec<Failure> = results
        .par_iter()
        .filter(|r| matches!(r.verdict, Verdict::Fail { .. }))
        .map(|r| shrink_failure(r, opts))
        .collect();
    FuzzReport {
        seed: opts.seed,
        results,
        failures,
    }
}

/// Shrink one failing scene and name and describe its case file.
fn shrink_failure(r: &SceneResult, opts: &FuzzOptions) -> Failure {
    let original = scene(r.family, opts.seed, r.index, opts.mutation);
    let file = scene_file(r.family, opts.seed, r.index);
    // The same defect: a deviation within a factor 10 of the original's (a shrink towards a
    // degenerate scene, e.g. a profile that vanishes everywhere, is another defect).
    let original_severity = r.verdict.severity().unwrap_or(0.0);
    let still_fails = |values: &[f64]| {
        let sc = replay(r.family, values, opts.mutation);
        if !sc.tags.iter().all(|t| r.tags.contains(t)) {
            return false;
        }
        match &sc.case {
            Ok(c) => match judge(c, &file) {
                v @ Verdict::Fail { .. } => {
                    let x = v.severity().unwrap_or(0.0);
                    if original_severity.is_finite() {
                        x >= 0.1 * original_severity && x <= 10.0 * original_severity
                    } else {
                        x.is_infinite()
                    }
                }
                _ => false,
            },
            Err(_) => false,
        }
    };
    let values = shrink::shrink(
        original.draws.clone(),
        &original.kinds,
        opts.shrink_budget,
        still_fails,
    );
    let sc = replay(r.family, &values, opts.mutation);
    let mut case = sc.case.clone().unwrap_or(Value::Null);
    let shrunk = judge(&case, &file);
    let name = format!("fuzz_{}_s{}_{}", r.family.name(), opts.seed, r.index);
    if let Value::Object(map) = &mut case {
        map.insert("name".into(), Value::String(name.clone()));
        map.insert(
            "description".into(),
            Value::String(format!(
                "Found by `fringe fuzz --family {} --seed {}` (scene {}), shrunk. Regions: {}. \
                 As drawn: {}. Shrunk: {}.",
                r.family.name(),
                opts.seed,
                r.index,
                sc.tags.join(", "),
                verdict_text(&r.verdict),
                verdict_text(&shrunk)
            )),
        );
        map.insert(
            "formula".into(),
            Value::String(format!(
                "The `{}` closed form (cases/README.md, References), vector level, tolerance {:e}.",
                r.family.name(),
                families::VECTOR_TOLERANCE
            )),
        );
    }
    Failure {
        family: r.family,
        index: r.index,
        tags: r.tags.clone(),
        original: r.verdict.clone(),
        shrunk,
        shrunk_tags: sc.tags,
        case,
        file_name: format!("{name}.json"),
    }
}

fn verdict_text(v: &Verdict) -> String {
    match v {
        Verdict::Pass { deviation } => format!("pass, max|dev| {deviation:.3e}"),
        Verdict::Fail {
            deviation,
            tolerance,
            note,
            ..
        } => format!("fail, max|dev| {deviation:.3e} > {tolerance:e}; {note}"),
        Verdict::Refused { reason } => format!("refused: {reason}"),
        Verdict::Skipped => "skipped".into(),
    }
}

/// A refusal reason with its numbers replaced by `#`, so refusals group by kind.
pub(crate) fn reason_kind(reason: &str) -> String {
    let mut out = String::new();
    let mut chars = reason.chars().peekable();
    while let Some(c) = chars.next() {
        if c.is_ascii_digit() {
            while let Some(&n) = chars.peek() {
                let exponent = (n == 'e' || n == 'E') && out.ends_with('#');
                if n.is_ascii_digit() || n == '.' || exponent || n == '-' && out.ends_with('#') {
                    chars.next();
                } else {
                    break;
                }
            }
            if !out.ends_with('#') {
                out.push('#');
            }
        } else {
            out.push(c);
        }
    }
    if out.chars().count() > 200 {
        out = out.chars().take(200).collect::<String>() + "…";
    }
    out
}

/// Counts of one family.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counts {
    pub pass: usize,
    pub fail: usize,
    pub refused: usize,
    pub skipped: usize,
}

impl Counts {
    pub fn run(&self) -> usize {
        self.pass + self.fail + self.refused
    }

    /// Refusals as a fraction of the scenes run.
    pub fn refusal_rate(&self) -> f64 {
        self.refused as f64 / self.run().max(1) as f64
    }

    fn add(&mut self, v: &Verdict) {
        match v {
            Verdict::Pass { .. } => self.pass += 1,
            Verdict::Fail { .. } => self.fail += 1,
            Verdict::Refused { .. } => self.refused += 1,
            Verdict::Skipped => self.skipped += 1,
        }
    }
}

impl FuzzReport {
    /// Per-family counts (families in the order run).
    pub fn counts(&self) -> Vec<(Family, Counts)> {
        let mut out: Vec<(Family, Counts)> = Vec::new();
        for r in &self.results {
            match out.iter_mut().find(|(f, _)| *f == r.family) {
                Some((_, c)) => c.add(&r.verdict),
                None => {
                    let mut c = Counts::default();
                    c.add(&r.verdict);
                    out.push((r.family, c));
                }
            }
        }
        out
    }

    pub fn total(&self) -> Counts {
        let mut c = Counts::default();
        for r in &self.results {
            c.add(&r.verdict);
        }
        c
    }

    /// The printed report: per-family counts and refusal rates, refusals by reason, failures by
    /// region tag, and one line per failure.
    pub fn text(&self, out_dir: Option<&Path>) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{:<20} {:>7} {:>7} {:>7} {:>8} {:>8} {:>9}",
            "family", "scenes", "pass", "fail", "refused", "skipped", "refused%"
        );
        let row = |s: &mut String, name: &str, c: &Counts| {
            let _ = writeln!(
                s,
                "{:<20} {:>7} {:>7} {:>7} {:>8} {:>8} {:>8.2}%",
                name,
                c.run() + c.skipped,
                c.pass,
                c.fail,
                c.refused,
                c.skipped,
                100.0 * c.refusal_rate()
            );
        };
        for (f, c) in self.counts() {
            row(&mut s, f.name(), &c);
        }
        row(&mut s, "total", &self.total());

        let mut reasons: BTreeMap<(&str, String), usize> = BTreeMap::new();
        for r in &self.results {
            if let Verdict::Refused { reason } = &r.verdict {
                *reasons
                    .entry((r.family.name(), reason_kind(reason)))
                    .or_default() += 1;
            }
        }
        if !reasons.is_empty() {
            let _ = writeln!(s, "\nrefusals by reason:");
            for ((f, why), n) in &reasons {
                let _ = writeln!(s, "  {f}: {n} × {why}");
            }
        }

        // Failures by region: for each family with failures, fails / scenes run per tag.
        let mut by_tag: BTreeMap<(&str, &str), (usize, usize)> = BTreeMap::new();
        let failing: Vec<Family> = self.failures.iter().map(|f| f.family).collect();
        for r in &self.results {
            if !failing.contains(&r.family) || matches!(r.verdict, Verdict::Skipped) {
                continue;
            }
            for t in &r.tags {
                let e = by_tag.entry((r.family.name(), t)).or_default();
                e.1 += 1;
                if matches!(r.verdict, Verdict::Fail { .. }) {
                    e.0 += 1;
                }
            }
        }
        if !by_tag.is_empty() {
            let _ = writeln!(s, "\nfailures by region (family: region fails/scenes run):");
            let mut last = "";
            for ((f, t), (fails, n)) in &by_tag {
                if *f != last {
                    let _ = write!(s, "{}  {f}:", if last.is_empty() { "" } else { "\n" });
                    last = f;
                }
                let _ = write!(s, " {t} {fails}/{n}");
            }
            let _ = writeln!(s);
        }
        if !self.failures.is_empty() {
            let _ = writeln!(s, "\nfailures (shrunk case files):");
            for f in &self.failures {
                let path = match out_dir {
                    Some(d) => d.join(&f.file_name).display().to_string(),
                    None => f.file_name.clone(),
                };
                let _ = writeln!(
                    s,
                    "  {} #{} [{}]: {}\n      shrunk [{}]: {} → {path}",
                    f.family.name(),
                    f.index,
                    f.tags.join(","),
                    verdict_text(&f.original),
                    f.shrunk_tags.join(","),
                    verdict_text(&f.shrunk),
                );
            }
        }
        s
    }

    /// Write each failure's shrunk case file into `dir` (atomically), returning the paths.
    pub fn write_failures(&self, dir: &Path) -> Result<Vec<PathBuf>, String> {
        let mut written = Vec::new();
        for f in &self.failures {
            let path = dir.join(&f.file_name);
            let text = serde_json::to_string_pretty(&f.case).map_err(|e| e.to_string())? + "\n";
            crate::io::write_atomic(&path, text.as_bytes())
                .map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
            written.push(path);
        }
        Ok(written)
    }
}
