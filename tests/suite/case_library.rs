//! The case library as one data-driven test, and the documented case format
//! (`cases/schema.json`) checked against the serde types of `src/harness/case/spec.rs`.
//!
//! * `every_library_case_passes`: every `cases/*.json` loads, runs, passes every row that has a
//!   tolerance, has an exact `auto` level, matches its golden file, and produces only finite
//!   numbers.
//! * `the_committed_schema_is_the_one_generated_from_spec_rs`: `cases/schema.json` is what
//!   `fringe schema` prints (schemars, from the types and their attributes).
//! * The schema tests: every library case (as written, and re-serialized with every default
//!   filled in) validates against the schema; the schema and serde name the same keys and
//!   variants for every type, agree on which keys are required and on each key's JSON type; the
//!   schema's caps equal `load::limits`; and every bad case that serde rejects for its shape the
//!   schema rejects too.

use crate::support::schema;

use fringe::accumulate::fidelity::Fidelity;
use fringe::harness::case::load::{self, limits};
use fringe::harness::case::run;
use fringe::harness::case::spec;
use fringe::harness::verdict;
use serde::de::DeserializeOwned;
use serde_json::{Value, json};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The case files of the library, sorted (as `fringe check` lists them).
fn library() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("cases"))
        .expect("cases/ exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| {
            p.extension().is_some_and(|x| x == "json")
                && p.file_name().is_some_and(|n| n != "schema.json")
        })
        .collect();
    files.sort();
    assert!(!files.is_empty(), "the case library is empty");
    files
}

fn schema() -> schema::Schema {
    schema::Schema::load(&root().join("cases/schema.json"))
}

fn read_json(p: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap())
        .unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

// ---------------------------------------------------------------------------------------------
// The library, data-driven.

fn non_finite(r: &run::CaseResult) -> Vec<String> {
    let mut bad = Vec::new();
    let mut check = |what: String, xs: &[f64]| {
        if let Some(k) = xs.iter().position(|x| !x.is_finite()) {
            bad.push(format!("{what}[{k}] = {}", xs[k]));
        }
    };
    for m in &r.metrics {
        check(format!("{} coordinates", m.name), &m.coordinates);
        check(format!("{} analytic", m.name), &m.analytic);
        for (level, t) in &m.traced {
            check(format!("{} traced {level}", m.name), t);
        }
    }
    for c in &r.convergence {
        check(
            format!("convergence at {} orders", c.orders),
            &[c.max_abs_dev, c.bound],
        );
    }
    check("trace_seconds".into(), &[r.trace_seconds]);
    bad
}

#[test]
fn every_library_case_passes() {
    let mut failures = Vec::new();
    for file in library() {
        let case = match load::load(&file) {
            Ok(c) => c,
            Err(e) => {
                failures.push(format!("does not load: {e}"));
                continue;
            }
        };
        let name = case.spec.name.clone();
        let stem = file.file_stem().unwrap().to_string_lossy().to_string();
        if stem != name {
            failures.push(format!(
                "{}: the case is named {name:?}; library files are named after their case",
                file.display()
            ));
        }
        let result = match run::run(&case) {
            Ok(r) => r,
            Err(e) => {
                failures.push(format!("{name}: does not run: {e}"));
                continue;
            }
        };
        for x in non_finite(&result) {
            failures.push(format!("{name}: non-finite value {x}"));
        }
        let rows = verdict::rows(&result);
        for row in &rows {
            if row.pass == Some(false) || row.max_abs_dev.is_nan() || row.rms_dev.is_nan() {
                failures.push(format!(
                    "{name}: level {} metric {}: max |dev| {:e} (rms {:e}) > tolerance {:e} ({})",
                    row.fidelity,
                    row.metric,
                    row.max_abs_dev,
                    row.rms_dev,
                    row.tolerance.unwrap_or(f64::NAN),
                    row.note
                ));
            }
        }
        // `auto` must name a level that is exact for the scene: its row (primary metric) passes,
        // and every metric defined at that level meets its `vector` tolerance there (a
        // retardance, for instance, is undefined at the scalar levels, so the row can be absent).
        let (auto, why) = (&result.auto.level, &result.auto.reason);
        if let Some(a) = rows.iter().find(|r| r.fidelity.starts_with("auto="))
            && a.pass != Some(true)
        {
            failures.push(format!(
                "{name}: auto level {} is not exact: max |dev| {:e} > {:e}",
                a.fidelity,
                a.max_abs_dev,
                a.tolerance.unwrap_or(f64::NAN)
            ));
        }
        let mut judged = 0;
        for m in &result.metrics {
            if let (Some(st), Some(t)) = (m.stats(*auto), m.tolerances.get(&Fidelity::Vector)) {
                judged += 1;
                // Written so that a NaN deviation fails too.
                let within = st.max_abs_dev <= *t;
                if !within {
                    failures.push(format!(
                        "{name}: auto level {auto} ({why}) is not exact for {}: max |dev| {:e} > {t:e}",
                        m.name, st.max_abs_dev
                    ));
                }
            }
        }
        if judged == 0 {
            failures.push(format!(
                "{name}: no metric with a vector tolerance is defined at the auto level {auto}"
            ));
        }
        // The vector level is the reference: it is run and has a verdict for the primary metric.
        if !rows
            .iter()
            .any(|r| r.fidelity == Fidelity::Vector.name() && r.pass.is_some())
        {
            failures.push(format!("{name}: no vector row with a tolerance"));
        }
        let golden = root().join("golden").join(format!("{name}.csv"));
        match std::fs::read_to_string(&golden) {
            Err(e) => failures.push(format!("{name}: {}: {e}", golden.display())),
            Ok(text) => {
                if let Err(e) = verdict::compare_golden(
                    &result,
                    &text,
                    verdict::golden_tolerance(&case, &result),
                ) {
                    failures.push(format!("{name}: golden {}: {e:?}", golden.display()));
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} failure(s):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

// ---------------------------------------------------------------------------------------------
// The schema is generated from spec.rs.

#[test]
fn the_committed_schema_is_the_one_generated_from_spec_rs() {
    let path = root().join("cases/schema.json");
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    let generated = fringe::harness::case::schema::case_schema_text();
    if committed != generated {
        let line = committed
            .lines()
            .zip(generated.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(committed.lines().count().min(generated.lines().count()));
        panic!(
            "{} is not the schema generated from src/harness/case/spec.rs (first difference at line {}: \
             committed {:?}, generated {:?}); regenerate it with\n    \
             cargo run -- schema > cases/schema.json",
            path.display(),
            line + 1,
            committed.lines().nth(line).unwrap_or("<end>"),
            generated.lines().nth(line).unwrap_or("<end>")
        );
    }
}

// ---------------------------------------------------------------------------------------------
// The schema against the library.

#[test]
fn every_library_case_matches_the_schema() {
    let s = schema();
    let mut failures = Vec::new();
    for file in library() {
        // As written.
        if let Err(e) = s.validate(&read_json(&file)) {
            failures.push(format!("{}: {}", file.display(), e.join("; ")));
        }
        // As serde writes it back, with every default filled in (null for absent options).
        let case = load::load(&file).unwrap_or_else(|e| panic!("{e}"));
        let v = serde_json::to_value(&case.spec).unwrap();
        if let Err(e) = s.validate(&v) {
            failures.push(format!(
                "{} re-serialized: {}",
                file.display(),
                e.join("; ")
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

// ---------------------------------------------------------------------------------------------
// The schema against spec.rs. serde's own messages list the keys and variants it knows
// ("unknown field `x`, expected one of `a`, `b`"), so the Rust side is read at run time.

const UNKNOWN: &str = "zz_not_a_key";

type Probe = fn(Value) -> Result<(), String>;

fn de<T: DeserializeOwned>(v: Value) -> Result<(), String> {
    serde_json::from_value::<T>(v)
        .map(|_| ())
        .map_err(|e| e.to_string())
}

/// Every `$defs` entry and the Rust type it documents (`None`: the whole case file).
fn types() -> Vec<(&'static str, Probe)> {
    vec![
        ("#", de::<spec::CaseFile>),
        ("Point", de::<spec::Vec3>),
        ("Direction", de::<spec::Vec3>),
        ("Light", de::<spec::Light>),
        ("Medium", de::<spec::MediumSpec>),
        ("Coherence", de::<spec::CoherenceSpec>),
        ("Rect", de::<spec::RectSpec>),
        ("Aperture", de::<spec::ApertureSpec>),
        ("Surface", de::<spec::SurfaceSpec>),
        ("Emitter", de::<spec::EmitterSpec>),
        ("Polarization", de::<spec::PolarizationSpec>),
        ("Source", de::<spec::SourceSpec>),
        ("Scene", de::<spec::SceneSpec>),
        ("UnpolarizedModel", de::<spec::UnpolarizedModel>),
        ("FarSide", de::<spec::FarSide>),
        ("SweepParameter", de::<spec::SweepParameter>),
        ("Observer", de::<spec::Observer>),
        ("Probe", de::<spec::Probe>),
        ("Fidelity", de::<Fidelity>),
        ("BeamEvent", de::<spec::BeamEvent>),
        ("Beam", de::<spec::BeamSpec>),
        ("ReferenceModel", de::<spec::ReferenceModel>),
        ("Reference", de::<spec::ReferenceSpec>),
        ("Trace", de::<spec::TraceSpec>),
    ]
}

fn def<'a>(s: &'a schema::Schema, name: &str) -> &'a Value {
    if name == "#" {
        &s.root
    } else {
        s.resolve(&format!("#/$defs/{name}"))
            .unwrap_or_else(|| panic!("no $defs/{name}"))
    }
}

/// The names serde lists after "expected" in an unknown-field/variant message.
fn serde_names(message: &str) -> BTreeSet<String> {
    if message.contains("there are no fields") || message.contains("there are no variants") {
        return BTreeSet::new();
    }
    let after = message
        .split_once("expected")
        .unwrap_or_else(|| panic!("unexpected serde message {message:?}"))
        .1;
    after
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

fn keys(o: Option<&Value>) -> BTreeSet<String> {
    o.and_then(|p| p.as_object())
        .map(|p| p.keys().cloned().collect())
        .unwrap_or_default()
}

/// An externally tagged enum in the schema: `oneOf` of single-key objects → [(tag, content)].
fn variants(s: &Value) -> Option<Vec<(String, Value)>> {
    let alts = s.get("oneOf")?.as_array()?;
    alts.iter()
        .map(|a| {
            let props = a.get("properties")?.as_object()?;
            (props.len() == 1).then(|| {
                let (k, v) = props.iter().next().unwrap();
                (k.clone(), v.clone())
            })
        })
        .collect()
}

/// A unit enum in the schema: `enum` of strings, or `oneOf` of `const` strings (schemars writes
/// the latter when the variants have doc comments) → the variant names.
fn unit_variants(s: &Value) -> Option<BTreeSet<String>> {
    if let Some(e) = s.get("enum").and_then(|e| e.as_array()) {
        return Some(e.iter().map(|x| x.as_str().unwrap().to_string()).collect());
    }
    s.get("oneOf")?
        .as_array()?
        .iter()
        .map(|a| a.get("const")?.as_str().map(str::to_string))
        .collect()
}

/// The alternatives of a choice: `oneOf` or `anyOf` (schemars writes an optional object as
/// `anyOf: [{$ref}, {type: null}]`).
fn alternatives(x: &Value) -> Option<&Vec<Value>> {
    x.get("oneOf")
        .or_else(|| x.get("anyOf"))
        .and_then(|a| a.as_array())
}

/// The JSON type a schema names, leaving out `null` when it names a list (`["number", "null"]`
/// for an optional number).
fn type_name(x: &Value) -> Option<&str> {
    match x.get("type")? {
        Value::String(t) => Some(t),
        Value::Array(ts) => ts.iter().filter_map(|t| t.as_str()).find(|t| *t != "null"),
        _ => None,
    }
}

/// A value the schema accepts, with every optional key present (the first alternative of
/// every choice except `null`).
fn instance(s: &schema::Schema, x: &Value) -> Value {
    let x = s.deref(x);
    if let Some(alts) = alternatives(x) {
        let alt = alts
            .iter()
            .find(|a| s.deref(a).get("type") != Some(&json!("null")))
            .unwrap();
        return instance(s, alt);
    }
    if let Some(c) = x.get("const") {
        return c.clone();
    }
    if let Some(e) = x.get("enum").and_then(|e| e.as_array()) {
        return e[0].clone();
    }
    let f = |k: &str| x.get(k).and_then(|v| v.as_f64());
    match type_name(x) {
        Some("object") => {
            let mut o = serde_json::Map::new();
            if let Some(p) = x.get("properties").and_then(|p| p.as_object()) {
                for (k, sub) in p {
                    o.insert(k.clone(), instance(s, sub));
                }
            } else if let Some(ap) = x.get("additionalProperties").filter(|a| a.is_object()) {
                o.insert("a".into(), instance(s, ap));
            }
            Value::Object(o)
        }
        Some("array") => {
            let n = x.get("minItems").and_then(|v| v.as_u64()).unwrap_or(1);
            let item = instance(s, x.get("items").unwrap_or(&json!({})));
            Value::Array(vec![item; n as usize])
        }
        Some("string") => json!("a"),
        Some("boolean") => json!(true),
        Some("integer") => json!(f("minimum").unwrap_or(1.0).max(1.0) as u64),
        Some("number") => {
            let lo = f("minimum").or(f("exclusiveMinimum"));
            let v = match (lo, f("maximum")) {
                (Some(a), Some(b)) => 0.5 * (a + b),
                (Some(a), None) => a + 1.0,
                (None, Some(b)) => b - 1.0,
                (None, None) => 1.0,
            };
            json!(v)
        }
        Some("null") => Value::Null,
        _ => json!({}),
    }
}

/// A value of the wrong JSON type for schema `x` (serde and the schema must both reject it).
fn wrong_type(s: &schema::Schema, x: &Value) -> Value {
    let x = s.deref(x);
    let nullable_of = alternatives(x).and_then(|alts| {
        alts.iter()
            .find(|a| s.deref(a).get("type") != Some(&json!("null")))
            .filter(|_| alts.len() == 2)
    });
    let t = match nullable_of {
        Some(inner) => type_name(s.deref(inner)),
        None => type_name(x),
    };
    match t {
        Some("string") => json!(12),
        Some("number") | Some("integer") => json!("12"),
        Some("boolean") => json!("true"),
        Some("array") => json!({"a": 1}),
        // objects and tagged enums
        _ => json!(true),
    }
}

/// Object schemas to compare with serde: (where, object schema, how to wrap an instance of it
/// into a value of the probed Rust type).
fn objects(s: &schema::Schema) -> Vec<(String, Value, Probe, Option<String>)> {
    let mut out = Vec::new();
    for (name, probe) in types() {
        let d = def(s, name).clone();
        if d.get("type") == Some(&json!("object")) {
            out.push((name.to_string(), d, probe, None));
        } else if let Some(vs) = variants(&d) {
            for (tag, content) in vs {
                let content = s.deref(&content).clone();
                out.push((format!("{name}.{tag}"), content, probe, Some(tag)));
            }
        }
    }
    out
}

fn wrap(tag: &Option<String>, v: Value) -> Value {
    match tag {
        Some(t) => json!({ t.clone(): v }),
        None => v,
    }
}

#[test]
fn schema_and_spec_rs_name_the_same_keys_and_variants() {
    let s = schema();
    let mut failures = Vec::new();
    let listed: BTreeSet<String> = keys(s.root.get("$defs"));
    let mapped: BTreeSet<String> = types()
        .iter()
        .map(|t| t.0.to_string())
        .filter(|n| n != "#")
        .collect();
    if listed != mapped {
        failures.push(format!(
            "$defs {listed:?} and the Rust types of this test {mapped:?} differ"
        ));
    }
    for (name, probe) in types() {
        let d = def(&s, name);
        // Enums: the variant names.
        let units = unit_variants(d);
        let schema_variants: Option<BTreeSet<String>> = match variants(d) {
            Some(vs) => Some(vs.into_iter().map(|v| v.0).collect()),
            None => units.clone(),
        };
        if let Some(sv) = schema_variants {
            let probe_value = if units.is_some() {
                json!(UNKNOWN)
            } else {
                json!({ UNKNOWN: {} })
            };
            match probe(probe_value) {
                Ok(()) => failures.push(format!("{name}: serde accepts an unknown variant")),
                Err(m) => {
                    let rv = serde_names(&m);
                    if rv != sv {
                        failures.push(format!(
                            "{name}: schema variants {sv:?}, spec.rs variants {rv:?}"
                        ));
                    }
                }
            }
        }
    }
    // Objects: the key names (serde lists them when it meets an unknown key).
    for (at, obj, probe, tag) in objects(&s) {
        let sk = keys(obj.get("properties"));
        if obj.get("additionalProperties") != Some(&json!(false)) {
            failures.push(format!(
                "{at}: additionalProperties must be false (deny_unknown_fields)"
            ));
        }
        match probe(wrap(&tag, json!({ UNKNOWN: 0 }))) {
            Ok(()) => failures.push(format!("{at}: serde accepts an unknown key")),
            Err(m) if m.contains("unknown field") => {
                let rk = serde_names(&m);
                if rk != sk {
                    failures.push(format!("{at}: schema keys {sk:?}, spec.rs keys {rk:?}"));
                }
            }
            Err(m) => failures.push(format!("{at}: unexpected serde message {m:?}")),
        }
    }
    // The tolerance map's keys are the fidelity levels.
    let tol = keys(
        def(&s, "Reference")
            .pointer("/properties/tolerances/properties")
            .cloned()
            .as_ref(),
    );
    let levels: BTreeSet<String> = Fidelity::ALL.iter().map(|f| f.name().to_string()).collect();
    if tol != levels {
        failures.push(format!(
            "tolerances keys {tol:?}, fidelity levels {levels:?}"
        ));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn schema_and_serde_agree_on_required_keys_and_types() {
    let s = schema();
    let mut failures = Vec::new();
    for (at, obj, probe, tag) in objects(&s) {
        let full = instance(&s, &obj);
        if let Err(m) = probe(wrap(&tag, full.clone())) {
            failures.push(format!(
                "{at}: serde rejects the schema-valid instance {full}: {m}"
            ));
            continue;
        }
        let required: BTreeSet<String> = obj
            .get("required")
            .and_then(|r| r.as_array())
            .map(|r| r.iter().map(|x| x.as_str().unwrap().to_string()).collect())
            .unwrap_or_default();
        for (key, sub) in obj
            .get("properties")
            .and_then(|p| p.as_object())
            .cloned()
            .unwrap_or_default()
        {
            let mut without = full.clone();
            without.as_object_mut().unwrap().remove(&key);
            let serde_requires = match probe(wrap(&tag, without)) {
                Ok(()) => false,
                Err(m) if m.contains(&format!("missing field `{key}`")) => true,
                Err(m) => {
                    failures.push(format!("{at}.{key}: removing it gives {m:?}"));
                    continue;
                }
            };
            if serde_requires != required.contains(&key) {
                failures.push(format!(
                    "{at}.{key}: required by serde: {serde_requires}, by the schema: {}",
                    required.contains(&key)
                ));
            }
            let mut bad = full.clone();
            bad[&key] = wrong_type(&s, &sub);
            if probe(wrap(&tag, bad.clone())).is_ok() {
                failures.push(format!(
                    "{at}.{key}: serde accepts the wrong type {}",
                    bad[&key]
                ));
            }
        }
    }
    // The whole generated case is schema-valid and readable by serde.
    let case = instance(&s, &s.root);
    if let Err(e) = s.validate(&case) {
        failures.push(format!("the generated case is not schema-valid: {e:?}"));
    }
    if let Err(e) = de::<spec::CaseFile>(case) {
        failures.push(format!("serde rejects the generated case: {e}"));
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn schema_caps_equal_the_loaders_limits() {
    let s = schema();
    // keyword `kw` of key `key` in $defs/`name` (in its variant `tag` for an enum).
    let cap = |name: &str, tag: Option<&str>, key: &str, kw: &str| -> f64 {
        let d = def(&s, name);
        let obj = match tag {
            None => d.clone(),
            Some(t) => {
                variants(d)
                    .unwrap()
                    .into_iter()
                    .find(|v| v.0 == t)
                    .unwrap_or_else(|| panic!("{name} has no variant {t}"))
                    .1
            }
        };
        let sub = if key.is_empty() {
            obj
        } else {
            s.deref(&obj["properties"][key]).clone()
        };
        sub[kw]
            .as_f64()
            .unwrap_or_else(|| panic!("{name}.{tag:?}.{key}: no {kw}"))
    };
    let checks = [
        (
            cap("Light", Some("monochrome"), "wavelength_nm", "minimum"),
            limits::WAVELENGTH_NM.0,
        ),
        (
            cap("Light", Some("monochrome"), "wavelength_nm", "maximum"),
            limits::WAVELENGTH_NM.1,
        ),
        (
            cap("Light", Some("gaussian"), "samples", "maximum"),
            limits::MAX_SPECTRAL_SAMPLES as f64,
        ),
        (
            cap("Probe", Some("line"), "count", "maximum"),
            limits::MAX_PROBE_POINTS as f64,
        ),
        (
            cap("Probe", Some("sweep"), "count", "maximum"),
            limits::MAX_PROBE_POINTS as f64,
        ),
        (
            cap("Trace", None, "max_internal_reflections", "maximum"),
            limits::MAX_INTERNAL_REFLECTIONS as f64,
        ),
        (
            cap("Medium", Some("constant"), "n", "minimum"),
            limits::INDEX.0,
        ),
        (
            cap("Medium", Some("constant"), "n", "maximum"),
            limits::INDEX.1,
        ),
        (
            cap("Source", None, "coherence_group", "maximum"),
            limits::MAX_COHERENCE_GROUP as f64,
        ),
        (
            cap(
                "ReferenceModel",
                Some("rhomb_retardance"),
                "tir_count",
                "maximum",
            ),
            limits::MAX_TIR_COUNT as f64,
        ),
        (
            s.root["$defs"]["Point"]["items"]["maximum"]
                .as_f64()
                .unwrap(),
            limits::MAX_LENGTH_M,
        ),
    ];
    for (k, (schema_cap, limit)) in checks.iter().enumerate() {
        assert_eq!(
            schema_cap, limit,
            "check {k}: schema {schema_cap}, load::limits {limit}"
        );
    }
}

#[test]
fn schema_rejects_every_bad_case_whose_shape_serde_rejects() {
    let s = schema();
    let dir = root().join("tests/bad_cases");
    let mut shape_errors = 0;
    let mut failures = Vec::new();
    for e in std::fs::read_dir(&dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_none_or(|x| x != "json") || p.ends_with("expected.json") {
            continue;
        }
        let Ok(text) = std::fs::read_to_string(&p) else {
            continue;
        };
        let Ok(v) = serde_json::from_str::<Value>(&text) else {
            continue; // malformed JSON: no instance to validate
        };
        let serde_ok = de::<spec::CaseFile>(v.clone()).is_ok();
        let schema_ok = s.is_valid(&v);
        if !serde_ok {
            shape_errors += 1;
            if schema_ok {
                failures.push(format!(
                    "{}: serde rejects it, the schema accepts it",
                    p.display()
                ));
            }
        }
    }
    assert!(
        shape_errors >= 10,
        "only {shape_errors} shape errors in the corpus"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// A case run measures its detection floors on the arrivals it traced itself (`run::run` keeps
/// the sampled points' arrivals): the floors equal those of a fresh trace of the same points
/// (`detection::detection_floors`), for a two-beam point-source case, a spectral case (Gaussian
/// light, 129 wavelengths per point) and an Airy case.
#[test]
fn a_runs_detection_floors_are_those_of_a_fresh_trace() {
    use fringe::harness::case::detection;
    for name in ["plate_two_beam_paper", "coherence_length", "plate_airy_s"] {
        let case = load::load(&root().join("cases").join(format!("{name}.json"))).unwrap();
        let r = run::run(&case).unwrap();
        let fresh = detection::detection_floors(&case, &r).unwrap();
        println!("{name}: run {:?}, fresh trace {fresh:?}", r.detection);
        assert!(r.detection.is_some(), "{name}: no floors measured");
        assert_eq!(r.detection, fresh, "{name}");
    }
}
