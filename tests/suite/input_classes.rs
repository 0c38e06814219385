//! Classes of bad input that once got through the case parser (issue 15), each refused as a
//! class over the whole library, not one instance: objects written as positional arrays, keys
//! repeated in any object (maps included), case names of the tool's own outputs, films thinner
//! than 1 pm, probes on sources or in faces, coincident sources, intersecting slabs, and scenes
//! whose sequence enumeration would run unbounded. One instance of each is also in
//! tests/bad_cases/ (run through the command line by `cli::every_bad_case_is_rejected_clearly`).

use crate::support::library;

use fringe::harness::case::load::{self, limits};
use fringe::harness::case::run;
use serde_json::{Value, json};
use std::path::Path;

/// The library cases as (file, JSON value).
fn cases() -> Vec<(std::path::PathBuf, Value)> {
    library::case_files()
        .into_iter()
        .map(|p| {
            let v = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
            (p, v)
        })
        .collect()
}

/// Every object of `v` with its JSON path (`$.a.b[2]`), depth first.
fn objects(v: &Value, at: String, out: &mut Vec<String>) {
    match v {
        Value::Object(o) => {
            out.push(at.clone());
            for (k, x) in o {
                objects(x, format!("{at}.{k}"), out);
            }
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                objects(x, format!("{at}[{i}]"), out);
            }
        }
        _ => {}
    }
}

/// The value at a path made by [`objects`].
fn at_path<'v>(root: &'v mut Value, path: &str) -> &'v mut Value {
    let mut v = root;
    for seg in path
        .trim_start_matches('$')
        .split('.')
        .filter(|s| !s.is_empty())
    {
        let (key, idx) = match seg.find('[') {
            Some(i) => (&seg[..i], &seg[i..]),
            None => (seg, ""),
        };
        if !key.is_empty() {
            v = v.get_mut(key).unwrap();
        }
        for i in idx.split('[').filter(|s| !s.is_empty()) {
            v = v
                .get_mut(i.trim_end_matches(']').parse::<usize>().unwrap())
                .unwrap();
        }
    }
    v
}

fn parse(file: &Path, v: &Value) -> Result<load::Case, load::CaseError> {
    load::parse(file, &serde_json::to_string_pretty(v).unwrap())
}

/// Writes `v` as JSON text with the first key of the object at `dup` written twice (the second
/// time with the value of `other`, or its own when `other` is `None`).
fn write_with_duplicate(v: &Value, at: &str, dup: &str, out: &mut String) {
    match v {
        Value::Object(o) => {
            out.push('{');
            let mut first = true;
            for (k, x) in o {
                if !first {
                    out.push(',');
                }
                first = false;
                out.push_str(&serde_json::to_string(k).unwrap());
                out.push(':');
                write_with_duplicate(x, &format!("{at}.{k}"), dup, out);
                if at == dup && o.keys().next() == Some(k) {
                    out.push(',');
                    out.push_str(&serde_json::to_string(k).unwrap());
                    out.push(':');
                    write_with_duplicate(x, &format!("{at}.{k}"), dup, out);
                }
            }
            out.push('}');
        }
        Value::Array(a) => {
            out.push('[');
            for (i, x) in a.iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                write_with_duplicate(x, &format!("{at}[{i}]"), dup, out);
            }
            out.push(']');
        }
        _ => out.push_str(&serde_json::to_string(v).unwrap()),
    }
}

/// serde reads a struct from a positional array (`"trace": [3]` was max_internal_reflections =
/// 3): every object of every library case, written as the array of its values, is refused at
/// (or above) its own path.
#[test]
fn objects_written_as_arrays_are_refused() {
    let mut tried = 0;
    for (file, v) in cases() {
        let mut paths = Vec::new();
        objects(&v, "$".into(), &mut paths);
        for p in paths.iter().filter(|p| p.as_str() != "$") {
            let mut doc = v.clone();
            let node = at_path(&mut doc, p);
            let values: Vec<Value> = node.as_object().unwrap().values().cloned().collect();
            *node = Value::Array(values);
            tried += 1;
            match parse(&file, &doc) {
                Ok(_) => panic!("{}: {p} written as an array is accepted", file.display()),
                Err(e) => assert!(
                    p.starts_with(&e.json_path) || e.json_path.starts_with(p.as_str()),
                    "{}: {p} as an array is refused at {} ({})",
                    file.display(),
                    e.json_path,
                    e.message
                ),
            }
        }
    }
    assert!(tried > 200, "only {tried} objects tried");
}

/// A key written twice keeps the last value in serde's maps (`scene.media` gave n = 2.5 for
/// 1.5): in every object of every library case, maps included, a repeated key is refused.
#[test]
fn repeated_keys_are_refused_in_every_object() {
    for (file, v) in cases() {
        let mut paths = Vec::new();
        objects(&v, "$".into(), &mut paths);
        for p in &paths {
            if at_path(&mut v.clone(), p)
                .as_object()
                .is_none_or(|o| o.is_empty())
            {
                continue; // no key to repeat
            }
            let mut text = String::new();
            write_with_duplicate(&v, "$", p, &mut text);
            let e = load::parse(&file, &text).expect_err(&format!(
                "{}: a repeated key in {p} is accepted",
                file.display()
            ));
            assert!(
                e.message.contains("appears twice"),
                "{}: {p}: {}: {}",
                file.display(),
                e.json_path,
                e.message
            );
        }
    }
}

/// A case named like one of the tool's outputs (`stability` merged with the stability rows of
/// summary.json, `figures` shared the figures folder) is refused.
#[test]
fn case_names_of_the_tools_outputs_are_refused() {
    let (file, v) = cases().remove(0);
    for name in limits::RESERVED_CASE_NAMES {
        let mut doc = v.clone();
        doc["name"] = json!(name);
        let e = parse(&file, &doc).expect_err(name);
        assert_eq!(e.json_path, "$.name", "{name}: {}", e.message);
        assert!(e.message.contains("reserved"), "{name}: {}", e.message);
    }
    assert!(limits::RESERVED_CASE_NAMES.contains(&fringe::harness::check::STABILITY));
}

/// Films down to 1 pm trace (issue 13), so 1 pm is accepted; a thickness below it (1e-300 µm
/// reached the tracer) is refused, for plates, wedges and thickness sweeps.
#[test]
fn films_thinner_than_1_pm_are_refused_and_1_pm_is_accepted() {
    for (file, v) in cases() {
        let surfaces = v["scene"]["surfaces"].as_array().unwrap().clone();
        for (i, s) in surfaces.iter().enumerate() {
            let Some(kind) = ["plate", "wedge"].into_iter().find(|k| s.get(*k).is_some()) else {
                continue;
            };
            for (t, ok) in [
                (limits::MIN_THICKNESS_UM, true),
                (0.999e-6, false),
                (1e-300, false),
            ] {
                let mut doc = v.clone();
                doc["scene"]["surfaces"][i][kind]["thickness_um"] = json!(t);
                let r = parse(&file, &doc);
                let path = format!("$.scene.surfaces[{i}].{kind}.thickness_um");
                match (r, ok) {
                    (Ok(_), true) => {}
                    (Err(e), false) => assert_eq!(e.json_path, path, "{}", e.message),
                    (Ok(_), false) => panic!("{}: {t} µm accepted", file.display()),
                    // Other checks may refuse a 1 pm film (e.g. a wedge's geometry), never
                    // the thickness itself.
                    (Err(e), true) => assert_ne!(e.json_path, path, "{}", e.message),
                }
            }
        }
    }
}

/// Probe points on a point source, probe lines through a point or line source, coincident
/// sources and probe lines in a plate face are refused before tracing (they gave NaN rows or
/// deviations of 1.0): a probe at about a wavelength from a source is outside ray optics.
#[test]
fn nonsense_scenes_are_refused_before_tracing() {
    let (file, young) = cases()
        .into_iter()
        .find(|(f, _)| f.ends_with("young_paper.json"))
        .unwrap();
    // A probe line crossing slit 1 at its midpoint, sampled where no point lands on it.
    let mut doc = young.clone();
    doc["probe"]["line"] =
        json!({"from_m": [0.0, 0.0001375, -0.5], "to_m": [0.0, 0.0001375, 0.5], "count": 2});
    let e = parse(&file, &doc).unwrap_err();
    assert_eq!(e.json_path, "$.probe.line", "{}", e.message);
    // Slits 1 µm apart and closer are one slit.
    for gap in [0.0, 0.5e-6] {
        let mut doc = young.clone();
        doc["scene"]["sources"][1]["emitter"]["line"]["point_m"] =
            json!([0.0, 0.0001375 + gap, 0.3]);
        let e = parse(&file, &doc).unwrap_err();
        assert_eq!(e.json_path, "$.scene.sources[1].emitter", "{}", e.message);
    }
    // 2 µm apart is a (narrow) double slit.
    let mut doc = young.clone();
    doc["scene"]["sources"][1]["emitter"]["line"]["point_m"] = json!([0.0, 0.0001375 - 2e-6, 0.0]);
    parse(&file, &doc).expect("slits 2 µm apart");
    // A probe line just off the slits' plane at 2 µm from a slit is accepted.
    let mut doc = young;
    doc["probe"]["line"] =
        json!({"from_m": [2e-6, 0.0001375, -0.5], "to_m": [2e-6, 0.0001375, 0.5], "count": 3});
    parse(&file, &doc).expect("a probe 2 µm from the slit");
}

/// Stacked plates in air multiply the sequences (reflections between plates are not internal
/// reflections): four plates were 1.7 s, five 23 s, six never finished. The work estimate is
/// counted on the tree the tracer enumerates, grows with every plate, and six stacked plates
/// are refused by the preflight, with the estimate, before any tracing (this test would hang
/// otherwise).
#[test]
fn stacked_plates_are_counted_and_refused_before_work() {
    let (file, v) = cases()
        .into_iter()
        .find(|(f, _)| f.ends_with("plate_two_beam_paper.json"))
        .unwrap();
    let stacked = |k: usize| {
        parse(
            &file,
            &crate::support::stacked_plates::stacked_plates(&v, k),
        )
        .expect("stacked plates parse")
    };
    let mut last = 0.0;
    for k in 1..=3 {
        let work = run::preflight(&stacked(k)).expect("accepted");
        assert!(work > last, "{k} plates: {work:e} not above {last:e}");
        last = work;
    }
    let e = run::preflight(&stacked(6)).unwrap_err();
    assert_eq!(e.json_path, "$.trace.max_internal_reflections");
    assert!(
        e.message.contains("work units") && e.message.contains(" s on the"),
        "{}",
        e.message
    );
}
