//! Helpers shared by several test modules (and, through `#[path]`, by `benches/airy.rs`).

pub mod airy_plate;
pub mod draw;
pub mod library;
pub mod schema;
pub mod stacked_plates;

use fringe::harness::fuzz::{self, Family, Verdict};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Every file under `dir` (recursively) with its bytes (empty if `dir` is absent): what a
/// command left on disk, to compare before and after.
pub fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    if let Ok(rd) = std::fs::read_dir(dir) {
        for e in rd {
            let p = e.unwrap().path();
            if p.is_dir() {
                out.extend(snapshot(&p));
            } else {
                out.insert(p.clone(), std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

/// The 50-digit values of a `case,point,value` CSV under `tests/data/` (written by a
/// `tools/*_mpmath.py` script), by case name in probe order.
pub fn mpmath_profiles(csv: &str) -> BTreeMap<String, Vec<f64>> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(csv);
    let text = std::fs::read_to_string(&path).unwrap();
    let mut out: BTreeMap<String, Vec<f64>> = BTreeMap::new();
    for line in text.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let v = out.entry(f[0].to_string()).or_default();
        assert_eq!(f[1].parse::<usize>().unwrap(), v.len(), "{line}");
        v.push(f[2].parse().unwrap());
    }
    out
}

/// The rows of a two-beam plate CSV under `tests/data/` (`n1,n2,thickness_m,h_src_m,h_obs_m,x_m,
/// lambda_m,tan_theta_t,intensity`, written by `tools/beyond_critical_plate_mpmath.py` or
/// `tools/steep_plate_mpmath.py`): the plate, x (m), λ (m), tan θt of the beam through the plate
/// and the high-precision intensity.
pub fn two_beam_plate_rows(
    csv: &str,
) -> Vec<(
    fringe::harness::analytic::plate::TwoBeamPlate,
    f64,
    f64,
    f64,
    f64,
)> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(csv);
    let text = std::fs::read_to_string(&path).expect("the committed high-precision data");
    text.lines()
        .skip(1)
        .map(|line| {
            let v: Vec<f64> = line.split(',').map(|f| f.parse().unwrap()).collect();
            let t = fringe::harness::analytic::plate::TwoBeamPlate {
                n1: v[0],
                n2: v[1],
                thickness_m: v[2],
                h_src_m: v[3],
                h_obs_m: v[4],
            };
            (t, v[5], v[6], v[7], v[8])
        })
        .collect()
}

/// Largest deviation of the traced `vector` values of the case file
/// `tests/fuzz_found/{name}.json` from the 50-digit values `truth`, relative to the largest
/// 50-digit value of the profile (as the gate measures).
pub fn traced_error(name: &str, truth: &[f64]) -> f64 {
    profile_error(name, truth, |m| {
        &m.traced[&fringe::accumulate::fidelity::Fidelity::Vector]
    })
}

/// The same for the closed form's values of the case's first reference.
pub fn closed_form_error(name: &str, truth: &[f64]) -> f64 {
    profile_error(name, truth, |m| &m.analytic)
}

/// Largest deviation of `values` of the first reference's metric of the case file
/// `tests/fuzz_found/{name}.json` from `truth`, relative to the largest of `truth`.
fn profile_error(
    name: &str,
    truth: &[f64],
    values: fn(&fringe::harness::case::run::MetricResult) -> &Vec<f64>,
) -> f64 {
    use fringe::harness::case::{load, run};
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/fuzz_found/{name}.json"));
    let text = std::fs::read_to_string(&path).unwrap();
    let r = run::run_with(&load::parse(&path, &text).expect("a valid case"), false).unwrap();
    let values = values(&r.metrics[0]);
    assert_eq!(values.len(), truth.len(), "{name}: probe points");
    let scale = truth.iter().fold(0.0f64, |s, x| s.max(x.abs()));
    values
        .iter()
        .zip(truth)
        .map(|(t, m)| (t - m).abs() / scale)
        .fold(0.0, f64::max)
}

/// Asserts that every case file named in the 50-digit CSV `csv` (`tests/data/`, read by
/// [`mpmath_profiles`]; `profiles` of them) traces within `tol` of its profile's largest value
/// ([`traced_error`]); a NaN fails.
pub fn assert_traced_within(csv: &str, profiles: usize, tol: f64) {
    let truth = mpmath_profiles(csv);
    assert_eq!(truth.len(), profiles, "{csv}: profiles");
    let mut bad = Vec::new();
    for (name, values) in &truth {
        let err = traced_error(name, values);
        println!("{name}: traced vs {csv} {err:e}");
        if err.is_nan() || err > tol {
            bad.push(format!("{name}: err {err:e}"));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// Asserts that every drawn scene (family, seed, index) of `fringe fuzz` passes the fuzz gate
/// at its derived tolerance, as `fringe fuzz` judges it: none is refused, none fails.
pub fn assert_drawn_scenes_pass(scenes: impl IntoIterator<Item = (Family, u64, usize)>) {
    let mut bad = Vec::new();
    for (family, seed, index) in scenes {
        let scene = fuzz::scene(family, seed, index, None);
        let case = scene.case.expect("the generator builds it");
        let name = format!("fuzz_{}_s{seed}_{index}.json", family.name());
        let verdict = fuzz::judge(&case, Path::new(&name));
        println!("{name}: {verdict:?}");
        if !matches!(verdict, Verdict::Pass { .. }) {
            bad.push(format!("{name} {:?}: {verdict:?}", scene.tags));
        }
    }
    assert!(bad.is_empty(), "{bad:#?}");
}

/// Asserts that the found case `name` (one probe point) traces the Airy sum its tail bound
/// `epsilon` (`trace.airy_tail_epsilon`) cuts, not a rounding of the full one: the budget traces
/// `internal` internal reflections, the traced value is within 1e-14 of `cut` (50 digits of
/// those orders alone) and within the case's tail bound 2√O ε √I0 + ε² I0 (I0 = 1,
/// docs/PHYSICS.md §8) of `full` (50 digits of every order).
pub fn assert_traced_cut_sum(name: &str, full: f64, cut: f64, internal: usize, epsilon: f64) {
    use fringe::harness::case::{build, load, run};
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("tests/fuzz_found/{name}.json"));
    let case = load::parse(&path, &std::fs::read_to_string(&path).unwrap()).unwrap();
    let pt = &build::probe_points(&case.spec.probe)[0];
    let built = build::build_scene(&case.spec.scene, &pt.overrides).unwrap();
    let lambda_m = build::spectrum(&case.spec.light, &pt.overrides)[0].0;
    let st = run::trace_settings(&case, &built, lambda_m).unwrap();
    assert_eq!(
        st.limits.max_internal_reflections, internal,
        "{name}: the 50-digit cut sum is of {internal} internal reflections"
    );
    let to_cut = traced_error(name, &[cut]);
    let off = traced_error(name, &[full]) * full;
    let bound = 2.0 * full.sqrt() * epsilon + epsilon * epsilon;
    println!("{name}: traced vs the cut sum {to_cut:.3e}; vs the full sum {off:.3e} ≤ {bound:.3e}");
    assert!(to_cut <= 1e-14, "{name}: traced vs its cut sum {to_cut:e}");
    assert!(
        off <= bound,
        "{name}: {off:e} off the full sum, bound {bound:e}"
    );
}
