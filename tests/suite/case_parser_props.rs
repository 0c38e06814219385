//! Fuzzing the case parser with proptest: arbitrary JSON, mutated library cases (keys dropped,
//! types changed, numbers made huge / negative / zero / tiny, strings replaced, elements
//! duplicated) and mutated case text (truncated, spliced) go through
//! `fringe::harness::case::load::parse`, which must never panic; every error has a JSON path starting
//! with `$` and a message; every accepted case builds (`build::build_scene` for every probe
//! override, `build::probe_points`, the spectrum, the optics at every traced wavelength) into
//! finite tracer objects without panicking. The tracer itself is not run (too slow for random
//! scenes). Mutated values that the documented schema accepts must also be readable by serde
//! (the schema is never looser than spec.rs).
//!
//! Cases per property: 256 by default; `PROPTEST_CASES=100000 cargo test --release --test
//! case_parser_props` for a long run. Crashing inputs found this way are kept in
//! tests/bad_cases/.

use crate::support::library;
use crate::support::schema;

use fringe::harness::case::build::{self, Overrides};
use fringe::harness::case::load::{self, limits};
use fringe::harness::case::spec::{CaseFile, Probe, SweepParameter};
use fringe::scene::source::Emitter;
use proptest::prelude::*;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn config() -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(256);
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// The library cases as JSON values, and their texts.
fn library() -> &'static Vec<(Value, String)> {
    static LIB: OnceLock<Vec<(Value, String)>> = OnceLock::new();
    LIB.get_or_init(|| {
        library::case_files()
            .iter()
            .map(|p| {
                let t = std::fs::read_to_string(p).unwrap();
                (serde_json::from_str(&t).unwrap(), t)
            })
            .collect()
    })
}

fn schema() -> &'static schema::Schema {
    static S: OnceLock<schema::Schema> = OnceLock::new();
    S.get_or_init(|| schema::Schema::load(&root().join("cases/schema.json")))
}

/// Parse, and check the contract of the result. Returns the accepted case.
fn parse_checked(text: &str) -> Option<CaseFile> {
    let file = Path::new("fuzz.json");
    match load::parse(file, text) {
        Err(e) => {
            assert!(
                e.json_path.starts_with('$'),
                "JSON path {:?} does not start with $ ({e})",
                e.json_path
            );
            assert!(
                !e.message.trim().is_empty(),
                "empty message at {}",
                e.json_path
            );
            assert_eq!(e.file, file);
            let shown = e.to_string();
            assert!(shown.starts_with("fuzz.json: $"), "{shown}");
            None
        }
        Ok(case) => {
            check_builds(&case.spec);
            Some(case.spec)
        }
    }
}

fn finite(v: glam::DVec3) -> bool {
    v.is_finite()
}

/// An accepted case becomes finite tracer objects, for every probe point's overrides.
fn check_builds(spec: &CaseFile) {
    let points = build::probe_points(&spec.probe);
    assert_eq!(points.len(), load::probe_point_count(&spec.probe));
    assert!(!points.is_empty());
    assert!(points.len() <= limits::MAX_PROBE_POINTS);
    if !matches!(spec.probe, Probe::Grid { .. }) {
        assert!(points.iter().all(|p| p.coordinate.is_finite()));
    }
    // The default scene, and the scenes of the first, middle and last probe point.
    let mut overrides = vec![Overrides::default()];
    for k in [0, points.len() / 2, points.len() - 1] {
        overrides.push(points[k].overrides.clone());
    }
    for (k, ov) in overrides.iter().enumerate() {
        let built = build::build_scene(&spec.scene, ov)
            .unwrap_or_else(|e| panic!("an accepted case does not build: {e}"));
        for s in &built.scene.surfaces {
            assert!(
                finite(s.plane.point) && finite(s.plane.normal),
                "{}",
                s.name
            );
            assert!((s.plane.normal.length() - 1.0).abs() < 1e-9, "{}", s.name);
        }
        for s in &built.scene.sources {
            let ok = match s.emitter {
                Emitter::Point { position } => finite(position),
                Emitter::Line { point, axis } => finite(point) && finite(axis),
                Emitter::PlaneWave {
                    direction,
                    reference_point,
                } => finite(direction) && finite(reference_point),
            };
            assert!(ok, "source {} is not finite: {:?}", s.name, s.emitter);
            assert!(s.intensity.is_finite() && s.intensity > 0.0);
            for ch in s.channels() {
                let v = match ch.field {
                    fringe::scene::source::ChannelField::Linear { reference, .. } => reference,
                    fringe::scene::source::ChannelField::Dipole { axis } => axis,
                };
                assert!(finite(v));
            }
        }
        let spectrum = build::spectrum(&spec.light, ov);
        assert!(!spectrum.is_empty());
        let total: f64 = spectrum.iter().map(|s| s.1).sum();
        assert!(
            (total - 1.0).abs() < 1e-9,
            "spectral weights sum to {total}"
        );
        for (lambda, w) in &spectrum {
            let nm = lambda * 1e9;
            assert!(
                nm >= limits::WAVELENGTH_NM.0 * (1.0 - 1e-12)
                    && nm <= limits::WAVELENGTH_NM.1 * (1.0 + 1e-12),
                "sampled wavelength {nm} nm"
            );
            assert!(w.is_finite() && *w >= 0.0);
        }
        // The optics (every index) at the traced wavelengths.
        let lambdas: Vec<f64> = if spectrum.len() > 3 {
            vec![
                spectrum[0].0,
                spectrum[spectrum.len() / 2].0,
                spectrum[spectrum.len() - 1].0,
            ]
        } else {
            spectrum.iter().map(|s| s.0).collect()
        };
        // (In a wavelength sweep the light's own wavelength is never traced: only the probe
        // points' spectra, k > 0, must have optics.)
        let wavelength_sweep = matches!(
            spec.probe,
            Probe::Sweep {
                parameter: SweepParameter::WavelengthNm {},
                ..
            }
        );
        for l in lambdas {
            if k == 0 && wavelength_sweep {
                continue;
            }
            built
                .scene
                .optics(l)
                .unwrap_or_else(|e| panic!("no optics at {} nm: {e}", l * 1e9));
            if k > 0 {
                let pt = &points[[0, points.len() / 2, points.len() - 1][k - 1]];
                let _ = build::target(&pt.observer, &built, l);
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Strategies.

const KEYS: &[&str] = &[
    "name",
    "description",
    "formula",
    "light",
    "scene",
    "probe",
    "references",
    "fidelities",
    "trace",
    "monochrome",
    "gaussian",
    "wavelength_nm",
    "center_nm",
    "fwhm_nm",
    "samples",
    "ambient",
    "media",
    "surfaces",
    "sources",
    "constant",
    "n",
    "plate",
    "thickness_um",
    "count",
    "line",
    "sweep",
    "grid",
    "pixels",
    "model",
    "tolerances",
    "vector",
];

fn number() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(json!(0)),
        Just(json!(-0.0)),
        Just(json!(1)),
        Just(json!(-1)),
        Just(json!(u64::MAX)),
        Just(json!(i64::MIN)),
        Just(json!(1e308)),
        Just(json!(-1e308)),
        Just(json!(5e-324)),
        Just(json!(1e-300)),
        Just(json!(1_000_000_000_000u64)),
        Just(json!(100_000)),
        Just(json!(100_001)),
        Just(json!(4096)),
        Just(json!(2001)),
        any::<i64>().prop_map(|x| json!(x)),
        any::<u64>().prop_map(|x| json!(x)),
        (-1e6..1e6f64).prop_map(|x| json!(x)),
        any::<f64>()
            .prop_filter("finite", |x| x.is_finite())
            .prop_map(|x| json!(x)),
    ]
}

fn string() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(String::new()),
        Just("../x".to_string()),
        Just("a/b".to_string()),
        Just("air".to_string()),
        Just("glass".to_string()),
        Just("plate".to_string()),
        Just("vector".to_string()),
        Just("plate.top".to_string()),
        Just("1.5+0.1i".to_string()),
        Just("NaN".to_string()),
        "[a-z_]{1,12}",
        ".{0,20}",
    ]
}

fn leaf() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(Value::Null),
        any::<bool>().prop_map(Value::Bool),
        number(),
        string().prop_map(Value::String),
    ]
}

fn arb_json() -> impl Strategy<Value = Value> {
    leaf().prop_recursive(4, 48, 6, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..6).prop_map(Value::Array),
            prop::collection::vec(
                (
                    prop_oneof![
                        prop::sample::select(KEYS).prop_map(str::to_string),
                        "[a-z]{1,6}"
                    ],
                    inner
                ),
                0..6
            )
            .prop_map(|kv| Value::Object(kv.into_iter().collect())),
        ]
    })
}

/// One edit of a JSON tree at the node selected by `at` (an index into its nodes).
#[derive(Clone, Debug)]
enum Edit {
    Remove,
    Replace(Value),
    Scale(f64),
    Nudge(f64),
    /// Replace a string by another string of the document (keeps references resolvable).
    Rename(usize),
    Duplicate,
    Empty,
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        2 => Just(Edit::Remove),
        3 => leaf().prop_map(Edit::Replace),
        1 => arb_json().prop_map(Edit::Replace),
        3 => prop_oneof![
            Just(0.0),
            Just(-1.0),
            Just(1e-12),
            Just(1e12),
            Just(1e300),
            Just(-1e300),
            0.5..2.0f64,
        ]
        .prop_map(Edit::Scale),
        3 => (-1.0..1.0f64).prop_map(Edit::Nudge),
        2 => any::<usize>().prop_map(Edit::Rename),
        1 => Just(Edit::Duplicate),
        1 => Just(Edit::Empty),
    ]
}

/// JSON pointers of every node below the root.
fn pointers(v: &Value, at: String, out: &mut Vec<String>) {
    match v {
        Value::Object(o) => {
            for (k, x) in o {
                let p = format!("{at}/{}", k.replace('~', "~0").replace('/', "~1"));
                out.push(p.clone());
                pointers(x, p, out);
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                let p = format!("{at}/{i}");
                out.push(p.clone());
                pointers(x, p, out);
            }
        }
        _ => {}
    }
}

fn strings(v: &Value, out: &mut Vec<String>) {
    match v {
        Value::String(s) if s.len() < 40 => out.push(s.clone()),
        Value::Object(o) => o.values().for_each(|x| strings(x, out)),
        Value::Array(a) => a.iter().for_each(|x| strings(x, out)),
        _ => {}
    }
}

fn apply(doc: &mut Value, at: usize, e: &Edit) {
    let mut ptrs = Vec::new();
    pointers(doc, String::new(), &mut ptrs);
    if ptrs.is_empty() {
        return;
    }
    let ptr = ptrs[at % ptrs.len()].clone();
    let (parent_ptr, last) = ptr.rsplit_once('/').unwrap();
    let mut names = Vec::new();
    strings(doc, &mut names);
    match e {
        Edit::Remove => match doc.pointer_mut(parent_ptr) {
            Some(Value::Object(o)) => {
                o.remove(&last.replace("~1", "/").replace("~0", "~"));
            }
            Some(Value::Array(a)) => {
                let i: usize = last.parse().unwrap();
                a.remove(i);
            }
            _ => {}
        },
        Edit::Duplicate => {
            if let Some(Value::Array(a)) = doc.pointer_mut(parent_ptr) {
                let i: usize = last.parse().unwrap();
                let x = a[i].clone();
                a.insert(i, x);
            }
        }
        _ => {
            let node = doc.pointer_mut(&ptr).unwrap();
            match e {
                Edit::Replace(v) => *node = v.clone(),
                Edit::Scale(f) => {
                    if let Some(x) = node.as_f64() {
                        *node = json!(x * f);
                    }
                }
                Edit::Nudge(d) => {
                    if let Some(x) = node.as_f64() {
                        *node = json!(x + d);
                    } else if let Some(x) = node.as_u64() {
                        *node = json!(x.saturating_add((d * 3.0) as u64));
                    }
                }
                Edit::Rename(k) => {
                    if node.is_string() && !names.is_empty() {
                        *node = json!(names[k % names.len()]);
                    }
                }
                Edit::Empty => match node {
                    Value::Array(a) => a.clear(),
                    Value::Object(o) => o.clear(),
                    _ => {}
                },
                _ => unreachable!(),
            }
        }
    }
}

fn mutated_case() -> impl Strategy<Value = Value> {
    (
        any::<prop::sample::Index>(),
        prop::collection::vec((any::<usize>(), edit()), 1..5),
    )
        .prop_map(|(which, edits)| {
            let lib = library();
            let mut doc = lib[which.index(lib.len())].0.clone();
            for (at, e) in &edits {
                apply(&mut doc, *at, e);
            }
            doc
        })
}

#[derive(Clone, Debug)]
enum TextEdit {
    Truncate(usize),
    Delete(usize, usize),
    Insert(usize, String),
}

fn text_edit() -> impl Strategy<Value = TextEdit> {
    prop_oneof![
        any::<usize>().prop_map(TextEdit::Truncate),
        (any::<usize>(), 1..40usize).prop_map(|(a, n)| TextEdit::Delete(a, n)),
        (
            any::<usize>(),
            prop_oneof![
                Just("{".to_string()),
                Just("}".to_string()),
                Just(",".to_string()),
                Just("\"".to_string()),
                Just("[".to_string()),
                Just("1e999".to_string()),
                Just("-".to_string()),
                Just("NaN".to_string()),
                Just("\u{feff}".to_string()),
                Just("é".to_string()),
                ".{0,8}",
            ]
        )
            .prop_map(|(a, s)| TextEdit::Insert(a, s)),
    ]
}

fn floor_char_boundary(s: &str, mut i: usize) -> usize {
    i = i.min(s.len());
    while !s.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn mutated_text() -> impl Strategy<Value = String> {
    (
        any::<prop::sample::Index>(),
        prop::collection::vec(text_edit(), 1..4),
    )
        .prop_map(|(which, edits)| {
            let lib = library();
            let mut t = lib[which.index(lib.len())].1.clone();
            for e in edits {
                match e {
                    TextEdit::Truncate(a) => {
                        let i = floor_char_boundary(&t, a % (t.len() + 1));
                        t.truncate(i);
                    }
                    TextEdit::Delete(a, n) => {
                        let i = floor_char_boundary(&t, a % (t.len() + 1));
                        let j = floor_char_boundary(&t, i + n);
                        t.replace_range(i..j, "");
                    }
                    TextEdit::Insert(a, s) => {
                        let i = floor_char_boundary(&t, a % (t.len() + 1));
                        t.insert_str(i, &s);
                    }
                }
            }
            t
        })
}

// ---------------------------------------------------------------------------------------------
// Properties.

#[test]
fn every_library_case_parses_and_builds() {
    for (v, text) in library() {
        let spec = parse_checked(text).unwrap_or_else(|| panic!("{} does not parse", v["name"]));
        assert_eq!(spec.name, v["name"].as_str().unwrap());
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn arbitrary_json_never_panics(v in arb_json()) {
        let text = serde_json::to_string(&v).unwrap();
        parse_checked(&text);
    }

    #[test]
    fn arbitrary_json_in_a_case_never_panics(
        which in any::<prop::sample::Index>(),
        key in prop::sample::select(&["light", "scene", "probe", "references", "trace",
            "fidelities", "name"][..]),
        v in arb_json(),
    ) {
        let lib = library();
        let mut doc = lib[which.index(lib.len())].0.clone();
        doc[key] = v;
        parse_checked(&serde_json::to_string(&doc).unwrap());
    }

    #[test]
    fn mutated_cases_never_panic_and_accepted_ones_build(doc in mutated_case()) {
        let text = serde_json::to_string_pretty(&doc).unwrap();
        parse_checked(&text);
        // The schema is never looser than spec.rs: what it accepts, serde reads.
        if schema().is_valid(&doc) {
            let r = serde_json::from_value::<CaseFile>(doc.clone());
            prop_assert!(r.is_ok(), "schema-valid but serde says {:?}", r.err());
        }
    }

    #[test]
    fn mutated_case_text_never_panics(text in mutated_text()) {
        parse_checked(&text);
    }
}

/// Inputs that once slipped through or crashed, kept as regressions (the same inputs are in
/// tests/bad_cases/ for the command line).
#[test]
fn regressions() {
    let dir = root().join("tests/bad_cases");
    let expected: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("expected.json")).unwrap()).unwrap();
    for (file, e) in expected.as_object().unwrap() {
        let Ok(text) = std::fs::read_to_string(dir.join(file)) else {
            continue; // not UTF-8: load() rejects it before parse()
        };
        match load::parse(Path::new(file), &text) {
            Ok(case) => {
                // Errors found by the work preflight or by tracing pass parse(); `fringe check`
                // finds them before anything is written, and so must this.
                let err = fringe::harness::case::run::preflight(&case)
                    .and_then(|_| fringe::harness::case::run::run_with(&case, false).map(|_| 0.0))
                    .expect_err(&format!(
                        "{file} is accepted by the parser, preflight and run"
                    ));
                assert_eq!(err.json_path, e["json_path"].as_str().unwrap(), "{file}");
            }
            Err(err) => assert_eq!(err.json_path, e["json_path"].as_str().unwrap(), "{file}"),
        }
    }
}
