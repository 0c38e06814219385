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
        1e-12
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

// ---------------------------------------------------------------------------------------------
// A real renderer: Mitsuba 3 (3.9.1, `scalar_spectral_polarized`) rendered plate_airy_s and
// plate_airy_p with examples/mitsuba_render_values.py (README "Mitsuba 3"); its value files and
// their Monte Carlo standard errors are committed under tests/data/mitsuba_*. Python is not
// needed here: the files are graded as any external tracer's would be.

/// p reflectance of one air–glass face, P1 written out: ((n c1 − c2)/(n c1 + c2))².
fn face_rp(theta_deg: f64) -> f64 {
    let n = 1.5;
    let c1 = theta_deg.to_radians().cos();
    let s1 = theta_deg.to_radians().sin();
    let c2 = (1.0 - (s1 / n).powi(2)).sqrt();
    ((n * c1 - c2) / (n * c1 + c2)).powi(2)
}

/// The incoherent plate of one face reflectance R (every internal reflection added in power,
/// T = 1 − R): R + T²R/(1 − R²) = 2R/(1 + R).
fn incoherent_plate(r: f64) -> f64 {
    2.0 * r / (1.0 + r)
}

/// One committed Mitsuba render: (angle °, value, standard error) per probe point, from
/// `tests/data/<name>.stderr.csv`, checked against the value file `tests/data/<name>.csv` that
/// `fringe grade` reads (same coordinates, same values).
fn mitsuba_render(name: &str) -> (PathBuf, Vec<(f64, f64, f64)>) {
    let data = root().join("tests").join("data");
    let rows = |file: &str| -> Vec<Vec<String>> {
        std::fs::read_to_string(data.join(file))
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#'))
            .skip(1)
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect()
    };
    let num = |s: &str| -> f64 { s.parse().unwrap() };
    let with_error: Vec<(f64, f64, f64)> = rows(&format!("{name}.stderr.csv"))
        .iter()
        .map(|r| (num(&r[0]), num(&r[1]), num(&r[2])))
        .collect();
    let values = rows(&format!("{name}.csv"));
    assert_eq!(values.len(), 171, "{name}");
    assert_eq!(with_error.len(), 171, "{name}");
    for (v, (a, x, s)) in values.iter().zip(&with_error) {
        assert_eq!((num(&v[1]), num(&v[2])), (*a, *x), "{name}");
        assert!(
            *s > 0.0,
            "{name}: a render without noise is not a Monte Carlo estimate"
        );
    }
    (data.join(format!("{name}.csv")), with_error)
}

/// Mitsuba works in float32: its Fresnel factors carry ~1e-7 relative rounding; 1e-6 absolute
/// covers that for values ≤ 1.
const FLOAT32_FLOOR: f64 = 1e-6;

/// The Monte Carlo bound: the value is the mean of 256 independent pixel estimates (the
/// sampler is seeded per pixel), so it is normal with the standard error σ from their spread;
/// |z| > 5 at any of 171 points has probability 171 × 5.7e-7 ≈ 1e-4 for a correct model.
fn within_noise(value: f64, model: f64, sigma: f64) -> bool {
    (value - model).abs() <= 5.0 * sigma + FLOAT32_FLOOR
}

/// The residuals z = (value − model)/σ of a render against the model it implements: each
/// point has its own seed, so for a correct model they are 171 independent standard normals
/// (σ from 256 pixels is itself good to 4%): every |z| ≤ 5 (`within_noise`), their mean
/// within 5/√N of 0 (no bias in the estimator or the model) and their mean square within
/// 5·√(2/N) of 1 (σ neither under- nor overstated).
fn assert_pure_noise(what: &str, z: &[f64]) {
    let n = z.len() as f64;
    let mean = z.iter().sum::<f64>() / n;
    let mean_square = z.iter().map(|z| z * z).sum::<f64>() / n;
    assert!(mean.abs() <= 5.0 / n.sqrt(), "{what}: mean z {mean}");
    assert!(
        (mean_square - 1.0).abs() <= 5.0 * (2.0 / n).sqrt(),
        "{what}: mean z² {mean_square}"
    );
}

/// Grade a committed file: exit 1 (the Airy closed form's 1e-9 is far below Monte Carlo
/// noise, and the incoherent plate has no fringes), exactly one FAIL row (`values` against
/// `airy`); returns the rung `fringe grade` names, its max|dev|, the values~incoherent row's
/// max|dev| (from grade.json, unrounded) and stdout.
fn grade_committed(case: &str, values: &Path) -> (String, f64, f64, String) {
    let tmp = tempfile::tempdir().unwrap();
    let a = fringe()
        .args(["grade", case, "--values"])
        .arg(values)
        .arg("--out")
        .arg(tmp.path().join("rep"))
        .assert()
        .code(1);
    let o = a.get_output();
    let stdout = String::from_utf8_lossy(&o.stdout).to_string();
    let failing: Vec<&str> = stdout.lines().filter(|l| l.contains("FAIL")).collect();
    assert_eq!(failing.len(), 1, "{stdout}");
    assert!(
        failing[0].contains("values") && failing[0].contains("airy"),
        "{stdout}"
    );
    let g: Value = serde_json::from_str(
        &std::fs::read_to_string(tmp.path().join("rep/grade").join(case).join("grade.json"))
            .unwrap(),
    )
    .unwrap();
    assert_eq!(g["failed"], true);
    let closest = &g["closest"][0];
    let incoherent = g["rows"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["fidelity"] == "values~incoherent")
        .unwrap()["max_abs_dev"]
        .as_f64()
        .unwrap();
    (
        closest["fidelity"].as_str().unwrap().to_string(),
        closest["max_abs_dev"].as_f64().unwrap(),
        incoherent,
        stdout,
    )
}

/// A `dielectric` slab path-traced with polarization is the incoherent plate done per
/// polarization: every point is within Monte Carlo noise of 2R_s/(1 + R_s) (s light) or
/// 2R_p/(1 + R_p) (p light), far outside it from the s/p-averaged plate and from Airy, and
/// `fringe grade` names the `incoherent` rung with a max|dev| the noise bound allows.
#[test]
fn mitsuba_dielectric_slab_render_is_the_incoherent_plate_per_polarization() {
    for (case, face) in [
        ("plate_airy_s", face_rs as fn(f64) -> f64),
        ("plate_airy_p", face_rp as fn(f64) -> f64),
    ] {
        let (file, rows) = mitsuba_render(&format!("mitsuba_slab_{case}"));
        let mut far_from_average = 0.0_f64;
        let mut far_from_airy = 0.0_f64;
        let mut bound = 0.0_f64;
        let mut scale = 0.0_f64;
        let mut z = Vec::new();
        for &(a, v, s) in &rows {
            let model = incoherent_plate(face(a));
            assert!(
                within_noise(v, model, s),
                "{case} {a}°: Mitsuba {v} ± {s}, incoherent plate {model}"
            );
            z.push((v - model) / s);
            let averaged = incoherent_plate(0.5 * (face_rs(a) + face_rp(a)));
            far_from_average = far_from_average.max((v - averaged).abs() / s);
            if case == "plate_airy_s" {
                far_from_airy = far_from_airy.max((v - airy_s(a)).abs() / s);
            }
            bound = bound.max(5.0 * s + FLOAT32_FLOOR);
            scale = scale.max(model);
        }
        assert_pure_noise(case, &z);
        assert!(far_from_average > 20.0, "{case}: {far_from_average}σ");
        if case == "plate_airy_s" {
            assert!(far_from_airy > 20.0, "{case}: {far_from_airy}σ");
        }
        let (rung, dev, _, stdout) = grade_committed(case, &file);
        assert_eq!(rung, "incoherent", "{stdout}");
        // The traced incoherent rung is the same 2R/(1 + R) to rounding; its deviation is
        // relative to its largest value (at 85°).
        assert!(
            dev <= bound / scale + 1e-12,
            "{case}: {dev} > {}",
            bound / scale
        );
    }
}

/// Mitsuba's `thindielectric` averages s and p before the incoherent sum: both renders are
/// within Monte Carlo noise of 2R̄/(1 + R̄), R̄ = (R_s + R_p)/2, whatever the light's
/// polarization, and far outside it from the per-polarization plate the physics asks for.
#[test]
fn mitsuba_thindielectric_render_is_the_polarization_averaged_plate() {
    for (case, face) in [
        ("plate_airy_s", face_rs as fn(f64) -> f64),
        ("plate_airy_p", face_rp as fn(f64) -> f64),
    ] {
        let (file, rows) = mitsuba_render(&format!("mitsuba_thindielectric_{case}"));
        let mut far_from_incoherent = 0.0_f64;
        let mut cost = 0.0_f64;
        let mut scale = 0.0_f64;
        let mut bound = 0.0_f64;
        let mut z = Vec::new();
        for &(a, v, s) in &rows {
            let averaged = incoherent_plate(0.5 * (face_rs(a) + face_rp(a)));
            assert!(
                within_noise(v, averaged, s),
                "{case} {a}°: Mitsuba {v} ± {s}, averaged plate {averaged}"
            );
            z.push((v - averaged) / s);
            let per_polarization = incoherent_plate(face(a));
            far_from_incoherent = far_from_incoherent.max((v - per_polarization).abs() / s);
            cost = cost.max((averaged - per_polarization).abs());
            scale = scale.max(per_polarization);
            bound = bound.max(5.0 * s + FLOAT32_FLOOR);
        }
        assert_pure_noise(case, &z);
        assert!(far_from_incoherent > 20.0, "{case}: {far_from_incoherent}σ");
        let (_, _, dev, stdout) = grade_committed(case, &file);
        // The values~incoherent row measures the cost of averaging: the closed-form cost
        // max|R̄' − R'| relative to the rung's largest value, up to the noise bound (triangle
        // inequality: the two maxima differ by at most max|value − R̄'|).
        assert!(
            (dev - cost / scale).abs() <= bound / scale,
            "{case}: values~incoherent {dev}, averaging costs {}\n{stdout}",
            cost / scale
        );
    }
}
