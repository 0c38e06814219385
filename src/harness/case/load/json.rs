//! JSON-level diagnostics of a case file: keys written twice, objects written as arrays, and
//! the allowed keys and ranges named in serde's errors.

use super::*;

/// The first key written twice in one object anywhere in `text` (JSON path of the object,
/// message), `None` when there is none or the text is not JSON: JSON leaves repeated keys
/// undefined and serde keeps the last, so a case file names every key once.
pub(super) fn repeated_key(text: &str) -> Option<(String, String)> {
    use serde::de::{Deserialize, Deserializer, Error, MapAccess, SeqAccess, Visitor};
    struct Unique;
    impl<'de> Deserialize<'de> for Unique {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            d.deserialize_any(Unique)
        }
    }
    impl<'de> Visitor<'de> for Unique {
        type Value = Unique;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("any JSON value")
        }
        fn visit_bool<E>(self, _: bool) -> Result<Unique, E> {
            Ok(Unique)
        }
        fn visit_i64<E>(self, _: i64) -> Result<Unique, E> {
            Ok(Unique)
        }
        fn visit_u64<E>(self, _: u64) -> Result<Unique, E> {
            Ok(Unique)
        }
        fn visit_f64<E>(self, _: f64) -> Result<Unique, E> {
            Ok(Unique)
        }
        fn visit_str<E>(self, _: &str) -> Result<Unique, E> {
            Ok(Unique)
        }
        fn visit_unit<E>(self) -> Result<Unique, E> {
            Ok(Unique)
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut a: A) -> Result<Unique, A::Error> {
            while a.next_element::<Unique>()?.is_some() {}
            Ok(Unique)
        }
        fn visit_map<A: MapAccess<'de>>(self, mut a: A) -> Result<Unique, A::Error> {
            let mut seen = std::collections::BTreeSet::new();
            while let Some(k) = a.next_key::<String>()? {
                if !seen.insert(k.clone()) {
                    return Err(A::Error::custom(format_args!("duplicate field `{k}`")));
                }
                a.next_value::<Unique>()?;
            }
            Ok(Unique)
        }
    }
    let de = &mut serde_json::Deserializer::from_str(text);
    match serde_path_to_error::deserialize::<_, Unique>(&mut *de) {
        Err(e) if e.inner().to_string().starts_with("duplicate field `") => {
            Some(serde_error(text, e))
        }
        _ => None,
    }
}

/// The first place (JSON path, message) where the file has an array and the case format an
/// object: `canonical` is the parsed case written back (every object with its keys), so the
/// two trees have the same shape wherever the file wrote objects as objects.
pub(super) fn positional_object(
    original: &serde_json::Value,
    canonical: &serde_json::Value,
    path: &str,
) -> Option<(String, String)> {
    use serde_json::Value;
    match (original, canonical) {
        (Value::Array(_), Value::Object(keys)) => Some((
            path.to_string(),
            format!(
                "expected an object with named keys, got an array: objects are never written as positional arrays; keys here: {:?}",
                keys.keys().collect::<Vec<_>>()
            ),
        )),
        (Value::Object(o), Value::Object(c)) => o
            .iter()
            .find_map(|(k, v)| positional_object(v, c.get(k)?, &format!("{path}.{k}"))),
        (Value::Array(o), Value::Array(c)) => o
            .iter()
            .zip(c)
            .enumerate()
            .find_map(|(i, (v, w))| positional_object(v, w, &format!("{path}[{i}]"))),
        _ => None,
    }
}

/// What is allowed for a key, by its name, where serde's message alone does not say it.
fn allowed(key: &str) -> Option<String> {
    Some(match key {
        "count" => format!("1 to {} probe points", limits::MAX_PROBE_POINTS),
        "pixels" => format!(
            "[columns, rows], whole numbers ≥ 1 with at most {} points in all",
            limits::MAX_PROBE_POINTS
        ),
        "samples" => format!("2 to {} spectral samples", limits::MAX_SPECTRAL_SAMPLES),
        "max_internal_reflections" => format!("0 to {}", limits::MAX_INTERNAL_REFLECTIONS),
        "tir_count" => format!("1 to {}", limits::MAX_TIR_COUNT),
        "coherence_group" => format!("0 to {}", limits::MAX_COHERENCE_GROUP),
        "n" | "index_override" => format!(
            "a real refractive index in [{}, {}]; complex (lossy) indices are out of scope",
            limits::INDEX.0,
            limits::INDEX.1
        ),
        _ => return None,
    })
}

/// The JSON value at a serde_path_to_error path (`a.b[2].c`), if the text is valid JSON.
fn value_at<'v>(root: &'v serde_json::Value, path: &str) -> Option<&'v serde_json::Value> {
    let mut v = root;
    for seg in path.split('.').filter(|s| !s.is_empty()) {
        let (key, rest) = match seg.find('[') {
            Some(i) => (&seg[..i], &seg[i..]),
            None => (seg, ""),
        };
        if !key.is_empty() {
            v = v.get(key)?;
        }
        for idx in rest.split('[').filter(|s| !s.is_empty()) {
            v = v.get(idx.trim_end_matches(']').parse::<usize>().ok()?)?;
        }
    }
    Some(v)
}

/// Turn a serde error into (JSON path, message saying what is wrong and what is allowed).
pub(super) fn serde_error(
    text: &str,
    e: serde_path_to_error::Error<serde_json::Error>,
) -> (String, String) {
    use serde_json::error::Category;
    // serde_path_to_error writes `?` for a segment it could not name (a map key that failed to
    // parse, or the next element after a syntax error).
    let mut raw = e.path().to_string();
    let e = e.into_inner();
    let full = e.to_string();
    let (line, column) = (e.line(), e.column());
    let msg = match full.rfind(" at line ") {
        Some(i) if line > 0 => full[..i].to_string(),
        _ => full.clone(),
    };
    let tick = |m: &str, prefix: &str| -> Option<String> {
        let rest = m.strip_prefix(prefix)?;
        Some(rest[..rest.find('`')?].to_string())
    };
    // An unparseable map key (a fidelity name in `tolerances`): name it in the path.
    if raw.ends_with('?') {
        raw.truncate(raw.len() - 1);
        if let Some(k) = tick(&msg, "unknown variant `") {
            raw.push_str(&k);
        }
    }
    let mut raw = raw.trim_end_matches('.').to_string();
    if raw == "." {
        raw.clear();
    }
    let key = raw
        .rsplit('.')
        .next()
        .unwrap_or("")
        .split('[')
        .next()
        .unwrap_or("")
        .to_string();
    // serde's words for JSON's.
    let nice_expected = |x: &str| -> String {
        match x {
            "f64" => "a number".into(),
            "usize" | "u64" => "a whole number ≥ 0 (no decimal point or exponent)".into(),
            "a boolean" => "true or false".into(),
            "a sequence" => "an array".into(),
            "a map" => "an object".into(),
            _ if x.starts_with("struct variant ") => {
                "an object naming the kind with its keys, e.g. {\"kind\": {…}}".into()
            }
            _ if x.starts_with("struct ") => "an object".into(),
            _ => x.to_string(),
        }
    };
    let nice_got = |x: &str| -> String {
        match x {
            "sequence" => "an array".into(),
            "map" => "an object".into(),
            "unit" => "null".into(),
            _ => x.to_string(),
        }
    };
    let json_kind = |v: &serde_json::Value| match v {
        serde_json::Value::Null => "null",
        serde_json::Value::Bool(_) => "a boolean",
        serde_json::Value::Number(_) => "a number",
        serde_json::Value::String(_) => "a string",
        serde_json::Value::Array(_) => "an array",
        serde_json::Value::Object(_) => "an object",
    };
    let mut message = if msg == "number out of range" {
        "the number is out of range: write a finite number (64-bit floats reach ±1.8e308, 1e999 is not one)".to_string()
    } else if let Some(k) = tick(&msg, "missing field `") {
        raw = format!("{raw}.{k}");
        format!("missing required key `{k}`")
    } else if let Some(k) = tick(&msg, "duplicate field `") {
        format!("the key `{k}` appears twice in one object")
    } else if let Some(rest) = msg
        .strip_prefix("invalid type: ")
        .or_else(|| msg.strip_prefix("invalid value: "))
    {
        match rest.rsplit_once(", expected ") {
            Some((got, want)) => format!("expected {}, got {}", nice_expected(want), nice_got(got)),
            None => msg.clone(),
        }
    } else {
        match e.classify() {
            Category::Eof => format!("malformed JSON: the file ends early ({msg})"),
            Category::Syntax => {
                let parsed = serde_json::from_str::<serde_json::Value>(text);
                match parsed.as_ref().ok().map(|v| (v, value_at(v, &raw))) {
                    // Valid JSON that the case format cannot read here: the structure is wrong.
                    Some((v, _)) if raw.is_empty() && !v.is_object() => {
                        "a case file is one JSON object {\"name\": …, \"light\": …, …}".to_string()
                    }
                    Some((_, Some(serde_json::Value::Object(o)))) if o.len() != 1 => format!(
                        "an object naming its kind must have exactly one key (the kind, e.g. {{\"monochrome\": {{…}}}}), got {} keys {:?}",
                        o.len(),
                        o.keys().collect::<Vec<_>>()
                    ),
                    Some((_, Some(serde_json::Value::Array(a))))
                        if msg == "trailing characters" =>
                    {
                        format!(
                            "too many elements ({}) here: a point or direction is [x, y, z], a size or centre [u, v]",
                            a.len()
                        )
                    }
                    Some((_, Some(v))) if msg == "expected value" => format!(
                        "expected an object naming its kind (e.g. {{\"monochrome\": {{…}}}}), got {}",
                        json_kind(v)
                    ),
                    Some(_) => format!("this value does not fit the case format here ({msg})"),
                    None => format!("malformed JSON: {msg}"),
                }
            }
            _ => msg.clone(),
        }
    };
    if let Some(a) = allowed(&key) {
        message = format!("{message}; allowed: {a}");
    }
    if line > 0 {
        message = format!("{message} (line {line}, column {column})");
    }
    let json_path = if raw.is_empty() {
        "$".to_string()
    } else if raw.starts_with('[') || raw.starts_with('.') {
        format!("${raw}")
    } else {
        format!("$.{raw}")
    };
    (json_path, message)
}
