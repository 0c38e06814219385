//! Calibration of the work preflight (`fringe::harness::case::run::preflight`): for each scene,
//! the estimate in work units and in seconds (`SECONDS_PER_WORK_UNIT`, CPU-seconds per unit)
//! against the measured run of the case (`run::run`, what `fringe check` traces): its CPU-seconds
//! (all threads of the process, `clock_gettime(CLOCK_PROCESS_CPUTIME_ID)`, nanosecond
//! resolution, so the number depends little on how loaded the machine is) and its wall time.
//! Not a criterion bench: the table is the output. A scene is run again until its runs add up to
//! at least [`MIN_TOTAL_CPU_S`] CPU-seconds and number at least [`MIN_RUNS`], unless one run
//! alone takes [`LONG_RUN_CPU_S`] or more (then it runs once); the table gives the mean
//! CPU-seconds per run, the spread (smallest–largest run) and the ratio of the mean to the
//! estimate with its spread. Scenes: every library case; plate_two_beam_paper with 1–3 plates
//! stacked 1 mm apart (4 and more are refused by the preflight and are not run);
//! plate_two_beam_paper with 40 internal reflections; plate_airy_s at m = 2000 internal
//! reflections (no tail rule) at 200 angles (the far-field walk of `benches/airy.rs`).
//!
//! Run: `cargo bench -p fringe-benches --bench preflight` (optionally a substring of the scene
//! names as the first argument).

use fringe::harness::case::load;
use fringe::harness::case::run::{self, MAX_PATH_EVENTS, SECONDS_PER_WORK_UNIT};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// CPU-seconds of every thread of this process so far, live or exited (user + system), from
/// `clock_gettime(CLOCK_PROCESS_CPUTIME_ID)` (nanoseconds; /proc/self/stat counts 10 ms ticks,
/// which were 20–30 % of the 1-plate scene's run).
fn cpu_seconds() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `t` is a valid, writable timespec; the clock id is a constant the kernel knows.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_PROCESS_CPUTIME_ID)");
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

/// A scene is run again until its runs add up to at least this many CPU-seconds...
const MIN_TOTAL_CPU_S: f64 = 0.5;
/// ... and number at least this many,
const MIN_RUNS: usize = 3;
/// unless one run takes this many CPU-seconds or more (the 2- and 3-plate scenes, the Airy walk
/// at m = 2000): then that one run is the measurement.
const LONG_RUN_CPU_S: f64 = 5.0;

fn cases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../cases")
}

fn read(name: &str) -> (PathBuf, Value) {
    let file = cases_dir().join(format!("{name}.json"));
    let text = std::fs::read_to_string(&file).expect("library case");
    (file, serde_json::from_str(&text).expect("case JSON"))
}

#[path = "../tests/suite/support/stacked_plates.rs"]
mod stacked_plates;

/// plate_two_beam_paper with `k` plates, each 1 mm below the one above (as the tests build
/// them).
fn stacked(k: usize) -> Value {
    stacked_plates::stacked_plates(&read("plate_two_beam_paper").1, k)
}

fn scenes() -> Vec<(String, PathBuf, Value)> {
    let mut names: Vec<String> = std::fs::read_dir(cases_dir())
        .expect("cases/")
        .filter_map(|e| {
            let p = e.ok()?.path();
            let stem = p.file_stem()?.to_str()?.to_string();
            (p.extension()? == "json" && stem != "schema").then_some(stem)
        })
        .collect();
    names.sort();
    let mut out: Vec<(String, PathBuf, Value)> = names
        .iter()
        .map(|n| {
            let (f, v) = read(n);
            (n.clone(), f, v)
        })
        .collect();
    let (paper, _) = read("plate_two_beam_paper");
    for k in 1..=3 {
        out.push((format!("{k} stacked plate(s)"), paper.clone(), stacked(k)));
    }
    let mut forty = stacked(1);
    forty["trace"] = json!({ "max_internal_reflections": 40 });
    out.push(("plate_two_beam_paper, m = 40".into(), paper.clone(), forty));
    let (airy, mut walk) = read("plate_airy_s");
    walk["trace"] = json!({ "max_internal_reflections": 2000 });
    walk["probe"]["sweep"]["count"] = json!(200);
    out.push(("plate_airy_s, m = 2000, 200 angles".into(), airy, walk));
    out
}

fn main() {
    // `cargo bench` passes `--bench`; a first argument that is not an option filters the scenes.
    let filter = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    // `--counts`: each scene's counts (`run::WorkCounts`) and estimate, without running it.
    let counts_only = std::env::args().any(|a| a == "--counts");
    println!(
        "rate: {SECONDS_PER_WORK_UNIT:.2e} CPU-s per work unit; cap {MAX_PATH_EVENTS:.0e} units"
    );
    println!(
        "| scene | work units (∝ m + ∝ m² + per point and sample) | estimate (CPU-s) | runs | measured CPU-s per run (spread) | wall s per run | measured / estimate (spread) |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- |");
    for (name, file, doc) in scenes() {
        if filter.as_ref().is_some_and(|f| !name.contains(f.as_str())) {
            continue;
        }
        let text = serde_json::to_string_pretty(&doc).unwrap();
        let case = load::parse(&file, &text).expect("valid case");
        let (units, parts) = match run::work_estimate(&case) {
            Ok(e) => (e.units(), e),
            Err(e) => {
                println!("| {name} | refused: {} | | | | | |", e.message);
                continue;
            }
        };
        let estimate = units * SECONDS_PER_WORK_UNIT;
        if counts_only {
            println!("COUNTS {name}: {units:.6e} {:?}", parts.counts);
            continue;
        }
        let mut cpu = Vec::new();
        let t0 = Instant::now();
        loop {
            let c0 = cpu_seconds();
            let result = run::run(&case).expect("the case runs");
            cpu.push(cpu_seconds() - c0);
            std::hint::black_box(result);
            let total: f64 = cpu.iter().sum();
            if cpu[0] >= LONG_RUN_CPU_S || (total >= MIN_TOTAL_CPU_S && cpu.len() >= MIN_RUNS) {
                break;
            }
        }
        let n = cpu.len() as f64;
        let wall = t0.elapsed().as_secs_f64() / n;
        let mean = cpu.iter().sum::<f64>() / n;
        let lo = cpu.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = cpu.iter().copied().fold(0.0, f64::max);
        println!(
            "| {name} | {units:.2e} ({:.2e} + {:.2e} + {:.2e}) | {estimate:.4} | {} | {mean:.4} ({lo:.4}–{hi:.4}) | {wall:.4} | {:.2} ({:.2}–{:.2}) |",
            parts.linear_units,
            parts.quadratic_units,
            parts.sample_units,
            cpu.len(),
            mean / estimate,
            lo / estimate,
            hi / estimate
        );
    }
}
