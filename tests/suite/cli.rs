//! The `fringe check` command line: exit codes (0 pass, 1 a case failed, 2 bad input), what it
//! prints, what it writes, and that bad input writes nothing. Every run uses a temporary
//! `--out` and, where a golden file could be touched, temporary copies of `cases/` and
//! `golden/`, so the repository's golden files are never written.
//!
//! `every_bad_case_is_rejected_clearly` runs the bad-input corpus `tests/bad_cases/` (each file a
//! minimal modification of a library case; `expected.json` maps it to the JSON path and a
//! message fragment saying what is allowed).

use crate::support::snapshot;
use assert_cmd::Command;
use predicates::prelude::*;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn fringe() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_fringe"));
    c.env_remove("RUST_BACKTRACE")
        .env_remove("RUST_LIB_BACKTRACE");
    c
}

/// A temporary library: `cases/` and `golden/` copies of the named library cases.
struct Lib {
    dir: tempfile::TempDir,
}

impl Lib {
    fn new(names: &[&str]) -> Lib {
        let dir = tempfile::tempdir().unwrap();
        std::fs::create_dir_all(dir.path().join("cases")).unwrap();
        std::fs::create_dir_all(dir.path().join("golden")).unwrap();
        let lib = Lib { dir };
        for n in names {
            std::fs::copy(
                root().join(format!("cases/{n}.json")),
                lib.cases().join(format!("{n}.json")),
            )
            .unwrap();
            std::fs::copy(
                root().join(format!("golden/{n}.csv")),
                lib.golden().join(format!("{n}.csv")),
            )
            .unwrap();
        }
        lib
    }
    fn path(&self) -> &Path {
        self.dir.path()
    }
    fn cases(&self) -> PathBuf {
        self.path().join("cases")
    }
    fn golden(&self) -> PathBuf {
        self.path().join("golden")
    }
    fn out(&self) -> PathBuf {
        self.path().join("out")
    }
    /// `fringe check ARGS --cases-dir cases --golden-dir golden --out out`, run in the library.
    fn check(&self, args: &[&str]) -> Command {
        let mut c = fringe();
        c.current_dir(self.path())
            .arg("check")
            .args(args)
            .arg("--cases-dir")
            .arg(self.cases())
            .arg("--golden-dir")
            .arg(self.golden())
            .arg("--out")
            .arg(self.out());
        c
    }
    fn edit_case(&self, name: &str, f: impl FnOnce(&mut Value)) {
        let p = self.cases().join(format!("{name}.json"));
        let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
        f(&mut v);
        std::fs::write(&p, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    }
}

fn absent_or_empty(dir: &Path) -> bool {
    snapshot(dir).is_empty()
}

fn no_panic() -> impl Predicate<str> {
    predicate::str::contains("panicked")
        .or(predicate::str::contains("stack backtrace"))
        .or(predicate::str::contains("RUST_BACKTRACE"))
        .not()
}

#[test]
fn a_passing_case_exits_0_and_writes_its_reports() {
    let lib = Lib::new(&["young_paper"]);
    let golden_before = snapshot(&lib.golden());
    lib.check(&["young_paper"])
        .assert()
        .code(0)
        .stdout(predicate::str::contains("young_paper").and(predicate::str::contains("pass")))
        .stdout(predicate::str::contains("FAIL").not())
        .stderr(predicate::str::contains("all 1 case(s) pass"));
    assert!(lib.out().join("summary.json").is_file());
    assert!(lib.out().join("young_paper/profile.csv").is_file());
    assert_eq!(
        snapshot(&lib.golden()),
        golden_before,
        "a check without --bless wrote golden/"
    );
}

/// Every check, with or without CASE arguments, runs the stability sweep: its verdict rows are
/// printed with the cases', and it writes stability.csv, stability_paths.png and the report's
/// stability section.
#[test]
fn check_runs_the_stability_sweep_and_reports_it() {
    let lib = Lib::new(&["young_paper"]);
    lib.check(&["young_paper"])
        .assert()
        .code(0)
        .stdout(predicate::function(|out: &str| {
            out.lines().any(|line| {
                let words: Vec<&str> = line.split_whitespace().collect();
                words.starts_with(&["stability", "vector", "paths"]) && words[3..].contains(&"pass")
            })
        }))
        .stderr(predicate::str::contains("stability checks"));
    let text = std::fs::read_to_string(lib.out().join("stability.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(fringe::harness::stability::CSV_HEADER));
    let rows: Vec<&str> = lines.collect();
    assert!(rows.len() >= 40, "{} stability rows", rows.len());
    assert!(
        rows.iter()
            .all(|l| l.ends_with(",pass") || l.ends_with(",info"))
    );
    assert!(rows.iter().any(|l| l.starts_with("paths,")));
    let png = std::fs::read(lib.out().join("stability_paths.png")).unwrap();
    assert!(
        png.starts_with(b"\x89PNG"),
        "stability_paths.png is not a PNG"
    );
    let page = std::fs::read_to_string(lib.out().join("index.html")).unwrap();
    assert!(page.contains("<section id=\"stability\">"));
    assert!(page.contains("href=\"#stability\""));
    assert!(page.contains("binary32"));
}

#[test]
fn a_case_file_given_by_path_runs() {
    let lib = Lib::new(&["young_paper"]);
    let moved = lib.path().join("elsewhere.json");
    std::fs::rename(lib.cases().join("young_paper.json"), &moved).unwrap();
    lib.check(&[moved.to_str().unwrap()]).assert().code(0);
}

#[test]
fn a_tightened_tolerance_exits_1_and_names_the_case() {
    let lib = Lib::new(&["young_paper"]);
    lib.edit_case("young_paper", |v| {
        v["references"][0]["tolerances"]["vector"] = serde_json::json!(1e-30)
    });
    lib.check(&["young_paper"])
        .assert()
        .code(1)
        .stdout(predicate::str::contains("FAIL"))
        .stderr(predicate::str::contains("FAILED: young_paper"))
        .stderr(no_panic());
}

#[test]
fn a_changed_golden_value_exits_1_and_names_the_case() {
    let lib = Lib::new(&["young_paper"]);
    let p = lib.golden().join("young_paper.csv");
    let text = std::fs::read_to_string(&p).unwrap();
    // Change the traced value of the first data row (a finite number, so the file still parses).
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut f: Vec<String> = lines[1].split(',').map(str::to_string).collect();
    let v: f64 = f[3].parse().unwrap();
    f[3] = format!("{:.17e}", v * 1.001 + 1e-3);
    lines[1] = f.join(",");
    std::fs::write(&p, lines.join("\n") + "\n").unwrap();
    lib.check(&["young_paper"])
        .assert()
        .code(1)
        .stdout(predicate::str::contains("golden").and(predicate::str::contains("FAIL")))
        .stderr(predicate::str::contains("FAILED: young_paper"));
}

#[test]
fn an_unparseable_golden_file_exits_2_and_writes_nothing() {
    let lib = Lib::new(&["young_paper"]);
    let p = lib.golden().join("young_paper.csv");
    std::fs::write(
        &p,
        "reference,fidelity,coordinate,traced\nyoung_exact,vector,zero,NaN\n",
    )
    .unwrap();
    let before = snapshot(&lib.golden());
    lib.check(&["young_paper"])
        .assert()
        .code(2)
        .stderr(
            predicate::str::contains("young_paper.csv").and(predicate::str::contains("corrupt")),
        )
        .stderr(predicate::str::contains("line 2"))
        .stderr(no_panic());
    assert!(absent_or_empty(&lib.out()), "exit 2 wrote into --out");
    assert_eq!(snapshot(&lib.golden()), before);
}

#[test]
fn a_malformed_case_exits_2_with_file_and_json_path_and_writes_nothing() {
    let lib = Lib::new(&["young_paper", "michelson"]);
    lib.edit_case("young_paper", |v| {
        v["probe"]["line"]["count"] = serde_json::json!("401")
    });
    let before = snapshot(&lib.golden());
    // One bad case stops the whole run before anything is traced or written.
    lib.check(&["michelson", "young_paper"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "young_paper.json: $.probe.line.count:",
        ))
        .stderr(predicate::str::contains("1 to 100000 probe points"))
        .stderr(no_panic());
    assert!(absent_or_empty(&lib.out()));
    assert_eq!(snapshot(&lib.golden()), before);
    // The same with --bless: no golden file is written.
    lib.check(&["michelson", "young_paper", "--bless"])
        .assert()
        .code(2);
    assert!(absent_or_empty(&lib.out()));
    assert_eq!(snapshot(&lib.golden()), before);
}

#[test]
fn json_format_prints_an_array_of_rows() {
    let lib = Lib::new(&["young_paper"]);
    let out = lib
        .check(&["young_paper", "--format", "json"])
        .assert()
        .code(0)
        .get_output()
        .stdout
        .clone();
    let v: Value = serde_json::from_slice(&out).expect("stdout is one JSON document");
    let rows = v.as_array().expect("a JSON array");
    assert!(!rows.is_empty());
    for r in rows {
        for key in [
            "case",
            "fidelity",
            "metric",
            "max_abs_dev",
            "rms_dev",
            "tolerance",
            "pass",
            "seconds",
        ] {
            assert!(r.get(key).is_some(), "row without {key}: {r}");
        }
        // The case's rows, then the stability sweep's (run on every check).
        assert!(
            r["case"] == "young_paper" || r["case"] == "stability",
            "{r}"
        );
    }
    assert!(
        rows.iter()
            .any(|r| r["case"] == "stability" && r["pass"] == true)
    );
    assert!(
        rows.iter()
            .any(|r| r["metric"] == "golden" && r["pass"] == true)
    );
    assert!(
        rows.iter()
            .any(|r| r["fidelity"] == "vector" && r["pass"] == true)
    );
    assert!(
        rows.iter()
            .any(|r| r["pass"].is_null() && r["tolerance"].is_null())
    );
}

#[test]
fn bless_writes_golden_files_only_into_the_given_folder() {
    let repo_golden = snapshot(&root().join("golden"));
    let lib = Lib::new(&["young_paper"]);
    std::fs::remove_file(lib.golden().join("young_paper.csv")).unwrap();
    // Without a golden file the case fails, telling how to create it.
    lib.check(&["young_paper"])
        .assert()
        .code(1)
        .stderr(predicate::str::contains("--bless"));
    lib.check(&["young_paper", "--bless"]).assert().code(0);
    let written: Vec<PathBuf> = snapshot(&lib.golden()).into_keys().collect();
    assert_eq!(written, vec![lib.golden().join("young_paper.csv")]);
    let text = std::fs::read_to_string(&written[0]).unwrap();
    assert!(text.starts_with("reference,fidelity,coordinate,traced\n"));
    // The blessed file is a baseline the next run passes against.
    lib.check(&["young_paper"]).assert().code(0);
    assert!(
        snapshot(&root().join("golden")) == repo_golden,
        "the repository's golden/ changed"
    );
}

#[test]
fn unknown_names_and_paths_exit_2_and_write_nothing() {
    let lib = Lib::new(&["young_paper"]);
    for name in [
        "no_such_case",
        "../young_paper",
        "../cases/young_paper",
        "cases/../../young_paper",
        "young_paper/..",
        "Young-Paper",
        "",
        "missing.json",
    ] {
        lib.check(&[name])
            .assert()
            .code(2)
            .stderr(predicate::str::starts_with("error: "))
            .stderr(no_panic());
        assert!(absent_or_empty(&lib.out()), "{name:?} wrote into --out");
    }
}

#[test]
fn an_empty_or_missing_library_exits_2() {
    let lib = Lib::new(&[]);
    lib.check(&[])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("empty"));
    std::fs::remove_dir(lib.cases()).unwrap();
    lib.check(&[])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("cases"));
    assert!(absent_or_empty(&lib.out()));
}

#[test]
fn two_files_with_one_case_name_exit_2() {
    let lib = Lib::new(&["young_paper"]);
    std::fs::copy(
        lib.cases().join("young_paper.json"),
        lib.cases().join("young_paper_copy.json"),
    )
    .unwrap();
    lib.check(&["young_paper", "young_paper_copy"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("$.name"));
    assert!(absent_or_empty(&lib.out()));
}

#[test]
fn usage_errors_exit_2() {
    fringe().args(["check", "--format", "xml"]).assert().code(2);
    fringe().args(["frobnicate"]).assert().code(2);
    fringe().arg("--help").assert().code(0);
}

#[test]
fn every_bad_case_is_rejected_clearly() {
    let dir = root().join("tests/bad_cases");
    let expected: BTreeMap<String, Value> =
        serde_json::from_str(&std::fs::read_to_string(dir.join("expected.json")).unwrap())
            .expect("tests/bad_cases/expected.json");
    let files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .filter(|n| n != "expected.json")
        .collect();
    for f in &files {
        assert!(
            expected.contains_key(f),
            "{f} is not listed in expected.json"
        );
    }
    assert!(expected.len() >= 30, "only {} bad cases", expected.len());
    let tmp = tempfile::tempdir().unwrap();
    let mut failures = Vec::new();
    for (k, (file, e)) in expected.iter().enumerate() {
        let path = dir.join(file);
        assert!(
            path.is_file(),
            "expected.json lists {file}, which does not exist"
        );
        let json_path = e["json_path"].as_str().unwrap();
        let message = e["message"].as_str().unwrap();
        let out = tmp.path().join(format!("out{k}"));
        let golden = tmp.path().join(format!("golden{k}"));
        let o = fringe()
            .current_dir(tmp.path())
            .arg("check")
            .arg(&path)
            .arg("--out")
            .arg(&out)
            .arg("--golden-dir")
            .arg(&golden)
            .arg("--bless")
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr);
        let lines: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
        let want = format!("{}: {json_path}: ", path.display());
        let mut why = Vec::new();
        if o.status.code() != Some(2) {
            why.push(format!("exit {:?}, not 2", o.status.code()));
        }
        if lines.len() != 1 || !lines[0].starts_with("error: ") {
            why.push("not exactly one `error: ` line".to_string());
        }
        if !stderr.contains(&want) {
            why.push(format!("no {want:?}"));
        }
        if !stderr.contains(message) {
            why.push(format!("no {message:?}"));
        }
        if stderr.contains("panicked") || stderr.contains("backtrace") {
            why.push("a panic".into());
        }
        if !absent_or_empty(&out) || !absent_or_empty(&golden) {
            why.push("wrote files".into());
        }
        if !o.stdout.is_empty() {
            why.push("printed to stdout".into());
        }
        if !why.is_empty() {
            failures.push(format!("{file}: {} — stderr: {stderr}", why.join(", ")));
        }
    }
    assert!(
        failures.is_empty(),
        "{} bad case(s) not rejected clearly:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

// ---------------------------------------------------------------------------------------------
// One consistent command line (issue 16, items 3 and 4)
// ---------------------------------------------------------------------------------------------

/// Every subcommand of `fringe --help`, in order.
fn subcommands() -> Vec<String> {
    let o = fringe().arg("--help").output().unwrap();
    let help = String::from_utf8(o.stdout).unwrap();
    help.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next().map(String::from))
        .filter(|c| c != "help")
        .collect()
}

#[test]
fn check_is_listed_first_and_every_flag_has_help() {
    let commands = subcommands();
    assert_eq!(commands.first().map(String::as_str), Some("check"));
    assert!(commands.iter().any(|c| c == "list"), "{commands:?}");
    for c in &commands {
        let o = fringe().args([c, "--help"]).output().unwrap();
        let help = String::from_utf8(o.stdout).unwrap();
        let lines: Vec<&str> = help
            .lines()
            .skip_while(|l| !l.starts_with("Options:"))
            .skip(1)
            .collect();
        for (k, line) in lines.iter().enumerate() {
            let text = line.trim_start();
            if !text.starts_with('-') {
                continue;
            }
            // "  -o, --out <OUT>  Output folder ... [default: reports]", or the flag alone with
            // its help on the next, further indented line: a description that is more than
            // the default.
            let same_line = text.split_once("  ").map(|(_, rest)| rest.trim());
            let next_line = lines
                .get(k + 1)
                .map(|l| l.trim())
                .filter(|l| !l.starts_with('-'));
            let described = same_line
                .or(next_line)
                .is_some_and(|rest| !rest.is_empty() && !rest.starts_with('['));
            assert!(described, "`fringe {c}`: a flag without help: {line:?}");
        }
    }
}

#[test]
fn every_command_that_writes_takes_dash_o_out() {
    for c in [
        "check", "render", "figures", "tradeoff", "fuzz", "forward", "models", "export", "grade",
    ] {
        let o = fringe().args([c, "--help"]).output().unwrap();
        let help = String::from_utf8(o.stdout).unwrap();
        assert!(
            help.contains("-o, --out <OUT>"),
            "`fringe {c} --help`:\n{help}"
        );
        assert!(
            !help.contains("--output"),
            "`fringe {c}`: --output is a hidden alias"
        );
    }
    // render's former `--output` still works.
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("y.png");
    fringe()
        .current_dir(dir.path())
        .args(["render", "young_fig3", "--size", "4x4", "--output"])
        .arg(&png)
        .assert()
        .code(0);
    assert!(png.is_file());
}

#[test]
fn the_forward_rays_help_shows_defaults_as_it_parses_them() {
    let o = fringe().args(["forward", "--help"]).output().unwrap();
    let help = String::from_utf8(o.stdout).unwrap();
    let rays = help.lines().find(|l| l.contains("--rays")).unwrap();
    assert!(rays.contains("comma-separated"), "{rays}");
    let default = rays
        .split("[default: ")
        .nth(1)
        .and_then(|d| d.strip_suffix(']'))
        .unwrap_or_else(|| panic!("no default shown: {rays}"));
    assert!(
        !default.contains(' ') && default.contains(','),
        "the default is not written the way --rays parses: {default:?}"
    );
    // And the shown default parses, in the range the help states: each value 1 to 1e8 here,
    // and clap takes it (with an invalid --pixels the run stops at our range check, after
    // clap parsed --rays, before any tracing: a parse error would name --rays and say
    // "invalid value"). Running the default study itself takes ~14 s of the test run.
    for v in default.split(',') {
        let n: u64 = v.parse().unwrap_or_else(|_| panic!("{v:?} in {default:?}"));
        assert!((1..=100_000_000).contains(&n), "{n} in {default:?}");
    }
    let dir = tempfile::tempdir().unwrap();
    let o = fringe()
        .args(["forward", "--rays", default, "--pixels", "0", "-o"])
        .arg(dir.path())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("--pixels") && !err.contains("invalid value"),
        "{err}"
    );
}

#[test]
fn results_go_to_stdout_and_diagnostics_to_stderr() {
    let dir = tempfile::tempdir().unwrap();
    // render: the picture is the result; what it wrote and its normalisation are diagnostics.
    let o = fringe()
        .args(["render", "young_fig3", "--size", "4x4", "-o"])
        .arg(dir.path().join("y.png"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0));
    assert!(o.stdout.is_empty(), "render printed to stdout");
    assert!(String::from_utf8_lossy(&o.stderr).contains("y.png"));
    // forward: the study is a file (-o), not a dump on stdout.
    let out = dir.path().join("fw");
    let o = fringe()
        .args(["forward", "--rays", "100", "--pixels", "2", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0));
    assert!(o.stdout.is_empty(), "forward printed to stdout");
    let csv = std::fs::read_to_string(out.join("forward/forward.csv")).unwrap();
    // Three scenes × one pixel count × one ray count × four estimators.
    assert_eq!(csv.lines().count(), 1 + 12, "{csv}");
    // list: the result (the library) on stdout, one line per case with its description.
    let o = fringe().arg("list").output().unwrap();
    assert_eq!(o.status.code(), Some(0));
    let text = String::from_utf8(o.stdout).unwrap();
    let library: Vec<String> = std::fs::read_dir(root().join("cases"))
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "json" && p.file_stem()? != "schema")
                .then(|| p.file_stem().unwrap().to_string_lossy().into_owned())
        })
        .collect();
    assert_eq!(text.lines().count(), library.len(), "{text}");
    for name in &library {
        let line = text
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name.as_str()))
            .unwrap_or_else(|| panic!("{name} not listed:\n{text}"));
        assert!(line.len() > name.len() + 10, "no description: {line:?}");
    }
    let young = text.lines().find(|l| l.starts_with("young_paper")).unwrap();
    assert!(
        young.contains("Fig. 3"),
        "cut at an abbreviation: {young:?}"
    );
}

#[test]
fn an_unknown_case_name_suggests_the_closest() {
    for command in ["check", "render"] {
        fringe()
            .args([command, "young_papr"])
            .assert()
            .code(2)
            .stderr(predicate::str::contains("did you mean `young_paper`?"))
            .stderr(no_panic());
    }
    // Nothing close: no suggestion.
    fringe()
        .args(["check", "zzzzzzzz"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("did you mean").not());
}

#[test]
fn render_refuses_bad_samples_and_non_png_outputs_as_user_errors() {
    let dir = tempfile::tempdir().unwrap();
    for samples in ["0", "1"] {
        fringe()
            .args([
                "render",
                "young_fig3",
                "--size",
                "4x4",
                "--samples",
                samples,
                "-o",
            ])
            .arg(dir.path().join("a.png"))
            .assert()
            .code(2)
            .stderr(predicate::str::starts_with(format!(
                "error: --samples {samples}: "
            )))
            .stderr(predicate::str::contains("::").not())
            .stderr(no_panic());
    }
    for name in ["x.jpg", "x.JPEG", "x"] {
        let target = dir.path().join(name);
        fringe()
            .args(["render", "young_fig3", "--size", "4x4", "-o"])
            .arg(&target)
            .assert()
            .code(2)
            .stderr(predicate::str::contains("allowed extension: .png"));
        assert!(!target.exists(), "{name} was written");
    }
    assert!(absent_or_empty(dir.path()));
}

/// The built binary run from a temporary directory (no `cases/` or `golden/` there): the library
/// is found in the checkout it was built from, or under `FRINGE_ROOT`.
#[test]
fn library_commands_work_from_any_directory() {
    let cwd = tempfile::tempdir().unwrap();
    fringe()
        .current_dir(cwd.path())
        .arg("list")
        .assert()
        .code(0)
        .stdout(predicate::str::contains("young_paper"));
    fringe()
        .current_dir(cwd.path())
        .args(["check", "young_paper", "-o", "out"])
        .assert()
        .code(0)
        .stdout(predicate::str::contains("golden"));
    assert!(cwd.path().join("out/young_paper/profile.csv").is_file());
    fringe()
        .current_dir(cwd.path())
        .args(["render", "young_fig3", "--size", "4x4", "-o", "y.png"])
        .assert()
        .code(0);
    assert!(cwd.path().join("y.png").is_file());
    // FRINGE_ROOT names another library.
    let lib = Lib::new(&["lloyd_mirror"]);
    fringe()
        .current_dir(cwd.path())
        .env("FRINGE_ROOT", lib.path())
        .arg("list")
        .assert()
        .code(0)
        .stdout(predicate::str::starts_with("lloyd_mirror "))
        .stdout(predicate::str::contains("young_paper").not());
}

#[test]
fn a_case_file_outside_the_library_blesses_beside_itself() {
    let repo_golden = snapshot(&root().join("golden"));
    let cwd = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(cwd.path().join("mine")).unwrap();
    std::fs::copy(
        root().join("cases/young_paper.json"),
        cwd.path().join("mine/young_paper.json"),
    )
    .unwrap();
    let run = |args: &[&str]| {
        fringe()
            .current_dir(cwd.path())
            .args(args)
            .args(["-o", "out"])
            .output()
            .unwrap()
    };
    // No golden file yet: the case fails and prints the command that creates it.
    let o = run(&["check", "mine/young_paper.json"]);
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
    let hint = stderr
        .split('`')
        .find(|s| s.starts_with("fringe check") && s.ends_with("--bless"))
        .unwrap_or_else(|| panic!("no bless command in: {stderr}"));
    assert_eq!(hint, "fringe check mine/young_paper.json --bless");
    // The printed command works, and writes the golden file beside the case file.
    let args: Vec<&str> = hint.split_whitespace().skip(1).collect();
    assert_eq!(run(&args).status.code(), Some(0));
    let golden = cwd.path().join("mine/golden/young_paper.csv");
    assert!(golden.is_file());
    assert_eq!(
        run(&["check", "mine/young_paper.json"]).status.code(),
        Some(0)
    );
    // The blessed file is a baseline: a changed value fails against it.
    let text = std::fs::read_to_string(&golden).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let last = lines.last_mut().unwrap();
    let (head, value) = last.rsplit_once(',').unwrap();
    let v: f64 = value.parse().unwrap();
    *last = format!("{head},{:e}", v * 1.01 + 1e-3);
    std::fs::write(&golden, lines.join("\n") + "\n").unwrap();
    assert_eq!(
        run(&["check", "mine/young_paper.json"]).status.code(),
        Some(1)
    );
    assert!(
        snapshot(&root().join("golden")) == repo_golden,
        "the repository's golden/ changed"
    );
}

/// `fringe schema` prints the case-file schema generated from the case types: the text of the
/// committed cases/schema.json (which `case_library::the_committed_schema_is_…` keeps current),
/// on stdout, with nothing on stderr; it runs from any directory (nothing is read from disk).
#[test]
fn schema_prints_the_committed_case_schema() {
    let dir = tempfile::tempdir().unwrap();
    let o = fringe()
        .arg("schema")
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(0));
    assert!(
        o.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let committed = std::fs::read_to_string(root().join("cases/schema.json")).unwrap();
    let printed = String::from_utf8(o.stdout).unwrap();
    assert!(
        printed == committed,
        "fringe schema differs from cases/schema.json; regenerate with \
         `cargo run -- schema > cases/schema.json`"
    );
    let v: serde_json::Value = serde_json::from_str(&printed).unwrap();
    assert_eq!(
        v["$schema"], "https://json-schema.org/draft/2020-12/schema",
        "a draft 2020-12 schema"
    );
}
