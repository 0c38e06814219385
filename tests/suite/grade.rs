//! `fringe export` and `fringe grade`: a pack has what another tracer needs; values computed
//! here from independent closed forms are graded as such: the exact Airy plate passes (exit 0),
//! the incoherent plate a renderer ships fails (exit 1) on the right row and is recognised as the
//! `incoherent` rung, and malformed value files are refused (exit 2) naming line and column,
//! with nothing written.

use assert_cmd::Command;
use serde_json::Value;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn fringe() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_fringe"));
    c.current_dir(root())
        .env_remove("RUST_BACKTRACE")
        .env_remove("RUST_LIB_BACKTRACE");
    c
}

const CASE: &str = "plate_airy_s";

/// The probe of `cases/plate_airy_s.json`: 171 angles 0–85°, n = 1.5, d = 2 µm, λ = 550 nm, s.
fn angles() -> Vec<f64> {
    (0..171).map(|i| 85.0 * i as f64 / 170.0).collect()
}

/// s reflectance of one air–glass face, P1 written out: ((c1 − n c2)/(c1 + n c2))².
fn face_rs(theta_deg: f64) -> f64 {
    let n = 1.5;
    let c1 = theta_deg.to_radians().cos();
    let s1 = theta_deg.to_radians().sin();
    let c2 = (1.0 - (s1 / n).powi(2)).sqrt();
    ((c1 - n * c2) / (c1 + n * c2)).powi(2)
}

/// The Airy formula of a free-standing plate (B&W §7.6.1, eq. 17):
/// R = F sin²(δ/2)/(1 + F sin²(δ/2)), F = 4R/(1 − R)², δ = (4π/λ) n d cos θt.
fn airy_s(theta_deg: f64) -> f64 {
    let (n, d, lambda) = (1.5, 2e-6, 550e-9);
    let r = face_rs(theta_deg);
    let f = 4.0 * r / (1.0 - r).powi(2);
    let s1 = theta_deg.to_radians().sin();
    let c2 = (1.0 - (s1 / n).powi(2)).sqrt();
    let delta = 4.0 * std::f64::consts::PI * n * d * c2 / lambda;
    let s = (0.5 * delta).sin().powi(2);
    f * s / (1.0 + f * s)
}

/// pbrt-v4 / Mitsuba 3's thin dielectric for s light: R + T²R/(1 − R²) = 2R/(1 + R).
fn incoherent_s(theta_deg: f64) -> f64 {
    let r = face_rs(theta_deg);
    2.0 * r / (1.0 + r)
}

fn values_file(dir: &Path, name: &str, f: impl Fn(f64) -> f64) -> PathBuf {
    let mut s = String::from("# made by tests/suite/grade.rs\nquantity,coordinate,value\n");
    for a in angles() {
        s.push_str(&format!("reflectance,{a:.17e},{:.17e}\n", f(a)));
    }
    let p = dir.join(name);
    std::fs::write(&p, s).unwrap();
    p
}

#[test]
fn export_writes_the_pack_another_tracer_needs() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("pack");
    fringe()
        .args(["export", CASE])
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let dir = out.join(CASE);
    for f in [
        "case.json",
        "pack.json",
        "probes.csv",
        "expected.csv",
        "values_exact.csv",
    ] {
        assert!(dir.join(f).is_file(), "missing {f}");
    }
    let pack: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("pack.json")).unwrap()).unwrap();
    assert_eq!(pack["quantities"][0]["observable"], "reflectance");
    assert_eq!(pack["probe"]["coordinate"], "incidence_angle_deg");
    assert_eq!(pack["conventions"]["time_dependence"], "e^{-iωt}");
    assert_eq!(
        pack["quantities"][0]["references"][0]["tolerances"]["vector"],
        1e-11
    );
    assert_eq!(pack["spectrum"][0]["wavelength_nm"], 550.0);
    // The expected closed form in the pack is the Airy formula evaluated here.
    let expected = std::fs::read_to_string(dir.join("expected.csv")).unwrap();
    let mut lines = expected.lines();
    assert!(
        lines
            .next()
            .unwrap()
            .starts_with("quantity,reference,coordinate,closed_form")
    );
    for (line, a) in lines.zip(angles()) {
        let f: Vec<&str> = line.split(',').collect();
        let closed: f64 = f[3].parse().unwrap();
        let want = airy_s(a);
        assert!(
            (closed - want).abs() < 1e-12,
            "{a}°: pack {closed}, Airy {want}"
        );
    }
    // Its own values file grades as a pass.
    let rep = tmp.path().join("rep");
    fringe()
        .args(["grade", CASE, "--values"])
        .arg(dir.join("values_exact.csv"))
        .arg("--out")
        .arg(&rep)
        .assert()
        .code(0);
}

#[test]
fn independent_airy_values_pass_and_match_an_exact_rung() {
    let tmp = tempfile::tempdir().unwrap();
    let values = values_file(tmp.path(), "airy.csv", airy_s);
    let rep = tmp.path().join("rep");
    let a = fringe()
        .args(["grade", CASE, "--values"])
        .arg(&values)
        .arg("--out")
        .arg(&rep)
        .assert()
        .code(0);
    let o = a.get_output();
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stdout
            .lines()
            .any(|l| l.contains(" values ") && l.contains("airy") && l.contains("pass")),
        "{stdout}"
    );
    // For s light without TIR, scalar_jump, paper_rules and vector trace identically (the π
    // rule is exact for s): the rung named (the cheapest of the tie) matches to rounding.
    let g: Value = serde_json::from_str(
        &std::fs::read_to_string(rep.join("grade").join(CASE).join("grade.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(g["failed"], false);
    let closest = &g["closest"][0];
    assert!(
        ["scalar_jump", "paper_rules", "vector"].contains(&closest["fidelity"].as_str().unwrap()),
        "{stderr}"
    );
    assert!(closest["max_abs_dev"].as_f64().unwrap() < 1e-9, "{stderr}");
    let html = std::fs::read_to_string(rep.join("index.html")).unwrap();
    assert!(html.contains("Graded external values"));
}

#[test]
fn the_incoherent_plate_fails_on_the_values_row_and_matches_the_incoherent_rung() {
    let tmp = tempfile::tempdir().unwrap();
    let values = values_file(tmp.path(), "pbrt.csv", incoherent_s);
    let a = fringe()
        .args(["grade", CASE, "--values"])
        .arg(&values)
        .arg("--out")
        .arg(tmp.path().join("rep"))
        .assert()
        .code(1);
    let o = a.get_output();
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    let failing: Vec<&str> = stdout.lines().filter(|l| l.contains("FAIL")).collect();
    assert_eq!(failing.len(), 1, "{stdout}");
    assert!(
        failing[0].contains("values") && failing[0].contains("airy"),
        "{stdout}"
    );
    assert!(
        stderr.contains("closest to the incoherent rung"),
        "{stderr}"
    );
    assert!(stderr.contains("FAILED: plate_airy_s"), "{stderr}");
    // The values~incoherent row: the traced incoherent rung is 2R/(1+R) to rounding.
    let row = stdout
        .lines()
        .find(|l| l.contains("values~incoherent"))
        .unwrap();
    let dev: f64 = row.split_whitespace().nth(3).unwrap().parse().unwrap();
    assert!(dev < 1e-9, "{row}");
}

/// A malformed value file: exit 2, one `error: FILE: line L, column C: …` line, nothing written.
fn refused(tmp: &Path, name: &str, text: &str, line: usize, column: usize, says: &str) {
    let p = tmp.join(name);
    std::fs::write(&p, text).unwrap();
    let rep = tmp.join(format!("rep_{name}"));
    let a = fringe()
        .args(["grade", CASE, "--values"])
        .arg(&p)
        .arg("--out")
        .arg(&rep)
        .assert()
        .code(2);
    let stderr = String::from_utf8_lossy(&a.get_output().stderr).to_string();
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    let want = format!("error: {}: line {line}, column {column}: ", p.display());
    assert!(stderr.starts_with(&want), "{stderr} (wanted {want})");
    assert!(stderr.contains(says), "{stderr} (wanted {says:?})");
    assert!(!rep.exists(), "{name}: something was written");
}

#[test]
fn malformed_value_files_exit_2_naming_line_and_column() {
    let tmp = tempfile::tempdir().unwrap();
    let good: Vec<String> = angles()
        .iter()
        .map(|a| format!("reflectance,{a},{}", airy_s(*a)))
        .collect();
    let file = |rows: &[String]| format!("quantity,coordinate,value\n{}\n", rows.join("\n"));
    let mut nan = good.clone();
    nan[3] = format!("reflectance,{},NaN", angles()[3]);
    refused(tmp.path(), "nan.csv", &file(&nan), 5, 3, "finite");
    let short = &good[..170];
    refused(
        tmp.path(),
        "short.csv",
        &file(short),
        172,
        1,
        "ends after 170 of 171",
    );
    let mut long = good.clone();
    long.push("reflectance,86,0.5".into());
    refused(tmp.path(), "long.csv", &file(&long), 173, 1, "more rows");
    let radians: Vec<String> = angles()
        .iter()
        .map(|a| format!("reflectance,{},{}", a.to_radians(), airy_s(*a)))
        .collect();
    refused(
        tmp.path(),
        "radians.csv",
        &file(&radians),
        3,
        2,
        "coordinate",
    );
    let percent: Vec<String> = angles()
        .iter()
        .map(|a| format!("reflectance,{a},{}", 100.0 * airy_s(*a)))
        .collect();
    // The first value above 1 in percent is the first outside [0, 1].
    let first = angles()
        .iter()
        .position(|a| 100.0 * airy_s(*a) > 1.0 + 1e-9)
        .unwrap();
    refused(
        tmp.path(),
        "percent.csv",
        &file(&percent),
        first + 2,
        3,
        "wrong units",
    );
    let mut text = file(&good);
    text = text.replacen("quantity,coordinate,value", "angle,R", 1);
    refused(tmp.path(), "header.csv", &text, 1, 1, "header");
    let mut wrong_name = good.clone();
    wrong_name[0] = wrong_name[0].replace("reflectance", "transmittance");
    refused(
        tmp.path(),
        "name.csv",
        &file(&wrong_name),
        2,
        1,
        "expected quantity \"reflectance\"",
    );
    let mut fields = good.clone();
    fields[1] = format!("{},0.1", fields[1]);
    refused(
        tmp.path(),
        "fields.csv",
        &file(&fields),
        3,
        4,
        "3 comma-separated fields",
    );
}
