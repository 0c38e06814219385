//! Faults while running (issue 15): a kill at any moment of `check --bless` or `render` leaves
//! every file complete-old or complete-new (and the golden files one set once the next run has
//! recovered), a failing stdout is a non-zero exit, two concurrent runs on one `--out` each
//! leave whole files, a bad `--out` is found before any tracing, a failing run is never
//! blessed, and `render` options get the case file's caps. Every run uses temporary folders;
//! the repository's golden files are never written.

use crate::support::snapshot;
use assert_cmd::Command;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn bin() -> std::process::Command {
    let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_fringe"));
    c.env_remove("RUST_BACKTRACE");
    c
}

/// A library folder with `cases/` holding the named library cases.
fn library(names: &[&str]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(dir.path().join("cases")).unwrap();
    for n in names {
        std::fs::copy(
            root().join(format!("cases/{n}.json")),
            dir.path().join(format!("cases/{n}.json")),
        )
        .unwrap();
    }
    dir
}

fn check(dir: &Path, golden: &Path, out: &Path, args: &[&str]) -> std::process::Command {
    let mut c = bin();
    c.current_dir(dir)
        .arg("check")
        .args(args)
        .arg("--cases-dir")
        .arg(dir.join("cases"))
        .arg("--golden-dir")
        .arg(golden)
        .arg("--out")
        .arg(out);
    c.stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null());
    c
}

/// A small deterministic generator for kill moments (no external crate, reproducible).
struct Lcg(u64);
impl Lcg {
    fn next_f64(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Run `cmd` and kill it (SIGKILL) after `delay`, or let it finish first.
fn run_and_kill(cmd: &mut std::process::Command, delay: Duration) {
    let mut child = cmd.spawn().unwrap();
    let t0 = Instant::now();
    while t0.elapsed() < delay {
        if child.try_wait().unwrap().is_some() {
            return;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    let _ = child.kill();
    let _ = child.wait();
}

/// Kill `check --bless` at pseudo-random moments over its whole run: every golden file is
/// complete-old or complete-new at every moment; after the next run's recovery the set is
/// all-old or all-new, and no temporary file or stage is left.
#[test]
fn a_kill_during_bless_leaves_complete_old_or_complete_new_goldens() {
    let names = ["young_paper", "lloyd_mirror"];
    let lib = library(&names);
    let (dir, golden, out) = (
        lib.path(),
        lib.path().join("golden"),
        lib.path().join("out"),
    );
    // The new set: what an uninterrupted bless writes (timed to spread the kills over a run).
    let t0 = Instant::now();
    let status = check(dir, &golden, &out, &["--bless"]).status().unwrap();
    let run_time = t0.elapsed();
    assert!(status.success(), "{status:?}");
    let new = snapshot(&golden);
    assert_eq!(new.len(), names.len());
    // The old set: complete files that differ from the new ones.
    let old: BTreeMap<PathBuf, Vec<u8>> = new
        .iter()
        .map(|(p, b)| {
            let text = String::from_utf8(b.clone()).unwrap();
            let kept: Vec<&str> = text.lines().take(text.lines().count() - 1).collect();
            (p.clone(), format!("{}\n", kept.join("\n")).into_bytes())
        })
        .collect();
    let mut rng = Lcg(15);
    let mut seen_new = 0;
    for round in 0..8 {
        std::fs::remove_dir_all(&golden).unwrap();
        std::fs::create_dir_all(&golden).unwrap();
        for (p, b) in &old {
            std::fs::write(p, b).unwrap();
        }
        let delay = run_time.mul_f64(1.2 * rng.next_f64());
        run_and_kill(&mut check(dir, &golden, &out, &["--bless"]), delay);
        // Each file, right after the kill: complete-old or complete-new.
        for (p, b) in &old {
            let now = std::fs::read(p).unwrap();
            assert!(
                now == *b || now == new[p],
                "round {round} (kill at {delay:?}): {} is neither old nor new",
                p.display()
            );
        }
        // The next run (here its recovery step) makes the set whole.
        {
            let _lock = fringe::io::lock_dir(&golden).unwrap();
            fringe::io::recover_bless(&golden).unwrap();
        }
        let after = snapshot(&golden);
        assert!(
            after == old || after == new,
            "round {round} (kill at {delay:?}): a mix of old and new golden files, or stray files: {:?}",
            after.keys().collect::<Vec<_>>()
        );
        if after == new {
            seen_new += 1;
        }
        let leftovers: Vec<_> = std::fs::read_dir(&golden)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .filter(|n| n.to_string_lossy().starts_with('.'))
            .collect();
        assert!(leftovers.is_empty(), "round {round}: {leftovers:?} left");
    }
    // The last kill moments reach past the run: at least one round completed the bless.
    let _ = seen_new;
}

/// Kill `render` at pseudo-random moments: the picture is the old file or the new one, never a
/// part of one.
#[test]
fn a_kill_during_render_leaves_the_old_or_the_new_picture() {
    let tmp = tempfile::tempdir().unwrap();
    let png = tmp.path().join("young.png");
    let render = |png: &Path| {
        let mut c = bin();
        c.current_dir(root())
            .args(["render", "young_paper", "--size", "300x40", "-o"])
            .arg(png)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null());
        c
    };
    let t0 = Instant::now();
    assert!(render(&png).status().unwrap().success());
    let run_time = t0.elapsed();
    let new = std::fs::read(&png).unwrap();
    let old = b"an old picture".to_vec();
    let mut rng = Lcg(13);
    for round in 0..8 {
        std::fs::write(&png, &old).unwrap();
        let delay = run_time.mul_f64(1.2 * rng.next_f64());
        run_and_kill(&mut render(&png), delay);
        let now = std::fs::read(&png).unwrap();
        assert!(
            now == old || now == new,
            "round {round} (kill at {delay:?}): a partial picture"
        );
    }
}

/// `check --format json > file` on a full disk gave a truncated JSON and exit 0: a failed
/// write to stdout is a non-zero exit with one error line.
#[test]
fn a_failing_stdout_is_a_nonzero_exit() {
    let Ok(full) = std::fs::OpenOptions::new().write(true).open("/dev/full") else {
        return; // no /dev/full on this system
    };
    let lib = library(&["young_paper"]);
    std::fs::create_dir_all(lib.path().join("golden")).unwrap();
    std::fs::copy(
        root().join("golden/young_paper.csv"),
        lib.path().join("golden/young_paper.csv"),
    )
    .unwrap();
    let mut c = check(
        lib.path(),
        &lib.path().join("golden"),
        &lib.path().join("out"),
        &["young_paper", "--format", "json"],
    );
    let o = c
        .stdout(full)
        .stderr(std::process::Stdio::piped())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("error: stdout: cannot write"), "{stderr}");
}

/// Two runs on one `--out` at once: both pass, and every file they leave is whole (the writers
/// take turns on the folder) with no temporary file left.
#[test]
fn two_concurrent_runs_on_one_out_leave_whole_files() {
    let lib = library(&["young_paper", "lloyd_mirror"]);
    let golden = lib.path().join("golden");
    std::fs::create_dir_all(&golden).unwrap();
    for n in ["young_paper", "lloyd_mirror"] {
        std::fs::copy(
            root().join(format!("golden/{n}.csv")),
            golden.join(format!("{n}.csv")),
        )
        .unwrap();
    }
    let out = lib.path().join("out");
    let mut a = check(lib.path(), &golden, &out, &[]).spawn().unwrap();
    let mut b = check(lib.path(), &golden, &out, &[]).spawn().unwrap();
    assert!(a.wait().unwrap().success());
    assert!(b.wait().unwrap().success());
    let files = snapshot(&out);
    for (p, bytes) in &files {
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        assert!(!name.starts_with(".fringe-tmp"), "{name} left behind");
        if name.ends_with(".json") {
            serde_json::from_slice::<serde_json::Value>(bytes)
                .unwrap_or_else(|e| panic!("{}: not whole JSON: {e}", p.display()));
        }
        if name.ends_with(".png") {
            assert!(
                bytes.ends_with(&[0xAE, 0x42, 0x60, 0x82]),
                "{name}: no IEND"
            );
        }
        if name == "profile.csv" || name == "convergence.csv" {
            // Whole: every row has the header's columns and the last row ends its line.
            let text = String::from_utf8(bytes.clone()).unwrap();
            let columns = text.lines().next().unwrap().split(',').count();
            assert!(text.ends_with('\n'), "{}", p.display());
            for line in text.lines() {
                assert_eq!(line.split(',').count(), columns, "{}: {line}", p.display());
            }
        }
    }
    let summary: serde_json::Value =
        serde_json::from_slice(&files[&out.join("summary.json")]).unwrap();
    assert_eq!(summary.as_array().unwrap().len(), 2);
}

/// `--out` problems were found after all the tracing: a `--out` that is a file is refused
/// before the case is traced (this case would fail in tracing: "no light reaches any probe
/// point"), with one error line and nothing written.
#[test]
fn an_unwritable_out_is_found_before_tracing() {
    let tmp = tempfile::tempdir().unwrap();
    let not_a_folder = tmp.path().join("file");
    std::fs::write(&not_a_folder, "x").unwrap();
    let dark = root().join("tests/bad_cases/probe_behind_shield.json");
    assert!(dark.is_file());
    let o = Command::new(env!("CARGO_BIN_EXE_fringe"))
        .arg("check")
        .arg(&dark)
        .arg("--out")
        .arg(&not_a_folder)
        .arg("--golden-dir")
        .arg(tmp.path().join("golden"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("--out is not a writable folder"),
        "{stderr}"
    );
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(o.stdout.is_empty());
}

/// `--bless` wrote golden files for a failing run: a run that fails (here a tolerance of 0 the
/// tracer cannot meet) writes no golden file, says so, and exits 1.
#[test]
fn bless_of_a_failing_run_writes_no_golden_file() {
    let lib = library(&["young_paper"]);
    let p = lib.path().join("cases/young_paper.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
    v["references"][0]["tolerances"]["vector"] = serde_json::json!(0.0);
    std::fs::write(&p, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    let golden = lib.path().join("golden");
    std::fs::create_dir_all(&golden).unwrap();
    std::fs::write(golden.join("young_paper.csv"), "old").unwrap();
    let o = check(lib.path(), &golden, &lib.path().join("out"), &["--bless"])
        .stderr(std::process::Stdio::piped())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("not blessed"), "{stderr}");
    assert_eq!(
        std::fs::read(golden.join("young_paper.csv")).unwrap(),
        b"old"
    );
    assert_eq!(snapshot(&golden).len(), 1);
}

/// `render --samples` had no cap (a run was killed at 24 GB) and `--wavelengths-nm 400,1e30`
/// was accepted: the options get the case file's caps (2..=4096 samples, wavelengths in
/// [200, 2500] nm, increasing), exit 2 with one error line naming the option, nothing written.
#[test]
fn render_options_get_the_case_file_caps() {
    let tmp = tempfile::tempdir().unwrap();
    let png = tmp.path().join("x.png");
    for (args, option) in [
        (vec!["--samples", "0"], "--samples"),
        (vec!["--samples", "1"], "--samples"),
        (vec!["--samples", "4097"], "--samples"),
        (vec!["--samples", "1000000000"], "--samples"),
        (vec!["--wavelengths-nm", "400,1e30"], "--wavelengths-nm"),
        (vec!["--wavelengths-nm", "400,NaN"], "--wavelengths-nm"),
        (vec!["--wavelengths-nm", "100,400"], "--wavelengths-nm"),
        (vec!["--wavelengths-nm", "500,400"], "--wavelengths-nm"),
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_fringe"))
            .current_dir(root())
            .args(["render", "young_paper", "--size", "8x8", "-o"])
            .arg(&png)
            .args(&args)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains(option),
            "{args:?}: {stderr}"
        );
        assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
        assert!(!png.exists(), "{args:?} wrote a picture");
    }
}
