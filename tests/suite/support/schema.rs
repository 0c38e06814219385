//! A small JSON Schema (draft 2020-12) validator for the subset `cases/schema.json` (generated
//! by schemars from src/harness/case/spec.rs) uses: `$ref` into `$defs`, `type` (one name or a list),
//! `properties`, `required`, `additionalProperties` (false or a schema), `minProperties`,
//! `items`, `minItems`, `maxItems`, `uniqueItems`, `oneOf`, `anyOf`, `enum`, `const`,
//! `minimum`, `maximum`, `exclusiveMinimum`, and `pattern` of the form `^[class]{m,n}$` or
//! `^[class]+$`; `format` is an annotation (as draft 2020-12 has it by default). Any other keyword makes [`Schema::new`] fail, so the schema cannot silently use
//! something this validator ignores. Included with `#[path]` by tests/case_library.rs and
//! tests/case_parser_props.rs (this folder is not a test target of its own).
#![allow(dead_code)]

use serde_json::Value;

/// Keywords that only annotate (ignored when validating).
const ANNOTATIONS: &[&str] = &[
    "$schema",
    "$id",
    "$defs",
    "title",
    "description",
    "default",
    "examples",
    "$comment",
    "format",
];
const KEYWORDS: &[&str] = &[
    "$ref",
    "type",
    "properties",
    "required",
    "additionalProperties",
    "minProperties",
    "items",
    "minItems",
    "maxItems",
    "uniqueItems",
    "oneOf",
    "anyOf",
    "enum",
    "const",
    "minimum",
    "maximum",
    "exclusiveMinimum",
    "pattern",
];

pub struct Schema {
    pub root: Value,
}

impl Schema {
    /// Check that every keyword is supported and every `$ref` and pattern resolves.
    pub fn new(root: Value) -> Result<Schema, String> {
        let s = Schema { root };
        s.check_keywords(&s.root, "#")?;
        Ok(s)
    }

    pub fn load(path: &std::path::Path) -> Schema {
        let text = std::fs::read_to_string(path).expect("read the schema");
        let v: Value = serde_json::from_str(&text).expect("the schema is JSON");
        Schema::new(v).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }

    fn check_keywords(&self, s: &Value, at: &str) -> Result<(), String> {
        let Some(o) = s.as_object() else {
            return match s {
                Value::Bool(_) => Ok(()),
                _ => Err(format!("{at}: a schema must be an object or a boolean")),
            };
        };
        for (k, v) in o {
            if ANNOTATIONS.contains(&k.as_str()) && k != "$defs" {
                continue;
            }
            if !KEYWORDS.contains(&k.as_str()) && k != "$defs" {
                return Err(format!("{at}: unsupported keyword {k:?}"));
            }
            let here = format!("{at}/{k}");
            match k.as_str() {
                "$defs" | "properties" => {
                    for (name, sub) in v.as_object().ok_or(format!("{here}: not an object"))? {
                        self.check_keywords(sub, &format!("{here}/{name}"))?;
                    }
                }
                "items" | "additionalProperties" => self.check_keywords(v, &here)?,
                "oneOf" | "anyOf" => {
                    for (i, sub) in v
                        .as_array()
                        .ok_or(format!("{here}: not an array"))?
                        .iter()
                        .enumerate()
                    {
                        self.check_keywords(sub, &format!("{here}/{i}"))?;
                    }
                }
                "$ref" => {
                    self.resolve(v.as_str().unwrap_or(""))
                        .ok_or(format!("{here}: unresolved {v}"))?;
                }
                "pattern" => {
                    Pattern::parse(v.as_str().unwrap_or(""))
                        .ok_or(format!("{here}: unsupported pattern {v}"))?;
                }
                "type" => {
                    let names: Vec<&str> = match v {
                        Value::String(t) => vec![t.as_str()],
                        Value::Array(ts) => ts.iter().filter_map(|t| t.as_str()).collect(),
                        _ => vec![],
                    };
                    if names.is_empty() {
                        return Err(format!("{here}: a type name or a list of them"));
                    }
                    for t in names {
                        if ![
                            "object", "array", "string", "number", "integer", "boolean", "null",
                        ]
                        .contains(&t)
                        {
                            return Err(format!("{here}: unknown type {t}"));
                        }
                    }
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// The schema a `#/$defs/Name` reference points to.
    pub fn resolve(&self, r: &str) -> Option<&Value> {
        let name = r.strip_prefix("#/$defs/")?;
        self.root.get("$defs")?.get(name)
    }

    /// Follow `$ref`s.
    pub fn deref<'a>(&'a self, mut s: &'a Value) -> &'a Value {
        while let Some(r) = s.get("$ref").and_then(|r| r.as_str()) {
            s = self.resolve(r).expect("checked in new()");
        }
        s
    }

    /// Validate an instance; errors name the instance path (`$.scene.sources[0]`).
    pub fn validate(&self, v: &Value) -> Result<(), Vec<String>> {
        let mut errors = Vec::new();
        self.check(&self.root, v, "$", &mut errors);
        if errors.is_empty() {
            Ok(())
        } else {
            Err(errors)
        }
    }

    pub fn is_valid(&self, v: &Value) -> bool {
        let mut errors = Vec::new();
        self.check(&self.root, v, "$", &mut errors);
        errors.is_empty()
    }

    fn check(&self, s: &Value, v: &Value, at: &str, errors: &mut Vec<String>) {
        let s = match s {
            Value::Bool(true) => return,
            Value::Bool(false) => {
                errors.push(format!("{at}: not allowed"));
                return;
            }
            _ => s,
        };
        let mut fail = |m: String| errors.push(format!("{at}: {m}"));
        if let Some(r) = s.get("$ref").and_then(|r| r.as_str()) {
            let target = self.resolve(r).expect("checked in new()");
            self.check(target, v, at, errors);
            return;
        }
        if let Some(t) = s.get("type") {
            let is = |t: &str| match t {
                "object" => v.is_object(),
                "array" => v.is_array(),
                "string" => v.is_string(),
                "number" => v.is_number(),
                // As serde reads integers: no fraction, no exponent (1.0 is a float to serde).
                "integer" => v.is_u64() || v.is_i64(),
                "boolean" => v.is_boolean(),
                "null" => v.is_null(),
                _ => false,
            };
            let ok = match t {
                Value::String(t) => is(t),
                Value::Array(ts) => ts.iter().filter_map(|t| t.as_str()).any(is),
                _ => false,
            };
            if !ok {
                fail(format!("expected {t}, got {v}"));
                return;
            }
        }
        if let Some(c) = s.get("const")
            && c != v
        {
            fail(format!("{v} is not {c}"));
        }
        if let Some(e) = s.get("enum").and_then(|e| e.as_array())
            && !e.contains(v)
        {
            fail(format!("{v} is not one of {e:?}"));
        }
        if let Some(x) = v.as_f64() {
            if let Some(lo) = s.get("minimum").and_then(|x| x.as_f64())
                && x < lo
            {
                fail(format!("{x} < minimum {lo}"));
            }
            if let Some(lo) = s.get("exclusiveMinimum").and_then(|x| x.as_f64())
                && x <= lo
            {
                fail(format!("{x} ≤ exclusiveMinimum {lo}"));
            }
            if let Some(hi) = s.get("maximum").and_then(|x| x.as_f64())
                && x > hi
            {
                fail(format!("{x} > maximum {hi}"));
            }
        }
        if let (Some(p), Some(text)) = (s.get("pattern").and_then(|p| p.as_str()), v.as_str())
            && !Pattern::parse(p).expect("checked in new()").matches(text)
        {
            fail(format!("{text:?} does not match {p}"));
        }
        if let Some(items) = v.as_array() {
            let n = items.len() as u64;
            if let Some(m) = s.get("minItems").and_then(|x| x.as_u64())
                && n < m
            {
                fail(format!("{n} items, at least {m} required"));
            }
            if let Some(m) = s.get("maxItems").and_then(|x| x.as_u64())
                && n > m
            {
                fail(format!("{n} items, at most {m} allowed"));
            }
            if s.get("uniqueItems") == Some(&Value::Bool(true)) {
                for (i, x) in items.iter().enumerate() {
                    if items[..i].contains(x) {
                        fail(format!("item {i} repeats {x}"));
                    }
                }
            }
            if let Some(is) = s.get("items") {
                for (i, x) in items.iter().enumerate() {
                    self.check(is, x, &format!("{at}[{i}]"), errors);
                }
            }
        }
        if let Some(o) = v.as_object() {
            let props = s.get("properties").and_then(|p| p.as_object());
            if let Some(m) = s.get("minProperties").and_then(|x| x.as_u64())
                && (o.len() as u64) < m
            {
                errors.push(format!("{at}: at least {m} keys required"));
            }
            if let Some(req) = s.get("required").and_then(|r| r.as_array()) {
                for k in req.iter().filter_map(|k| k.as_str()) {
                    if !o.contains_key(k) {
                        errors.push(format!("{at}: missing required key {k:?}"));
                    }
                }
            }
            for (k, x) in o {
                let sub = format!("{at}.{k}");
                match props.and_then(|p| p.get(k)) {
                    Some(ps) => self.check(ps, x, &sub, errors),
                    None => match s.get("additionalProperties") {
                        None => {}
                        Some(ap) => self.check(ap, x, &sub, errors),
                    },
                }
            }
        }
        if let Some(alts) = s.get("anyOf").and_then(|a| a.as_array()) {
            let mut closest: Option<Vec<String>> = None;
            for alt in alts {
                let mut e = Vec::new();
                self.check(alt, v, at, &mut e);
                if e.is_empty() {
                    closest = None;
                    break;
                }
                if closest.as_ref().is_none_or(|c| e.len() < c.len()) {
                    closest = Some(e);
                }
            }
            if let Some(e) = closest {
                errors.push(format!(
                    "{at}: matches none of the {} alternatives; closest: {}",
                    alts.len(),
                    e.join("; ")
                ));
            }
        }
        if let Some(alts) = s.get("oneOf").and_then(|a| a.as_array()) {
            let mut matching = 0;
            let mut first_errors = Vec::new();
            for alt in alts {
                let mut e = Vec::new();
                self.check(alt, v, at, &mut e);
                if e.is_empty() {
                    matching += 1;
                } else if first_errors.is_empty() || e.len() < first_errors.len() {
                    first_errors = e;
                }
            }
            if matching != 1 {
                errors.push(format!(
                    "{at}: matches {matching} of the {} alternatives (exactly one required){}",
                    alts.len(),
                    if matching == 0 {
                        format!("; closest: {}", first_errors.join("; "))
                    } else {
                        String::new()
                    }
                ));
            }
        }
    }
}

/// `^[class]{m,n}$` or `^[class]+$` with a class of single characters and `a-z` style ranges.
pub struct Pattern {
    ranges: Vec<(char, char)>,
    min: usize,
    max: usize,
}

impl Pattern {
    pub fn parse(p: &str) -> Option<Pattern> {
        let body = p.strip_prefix("^[")?.strip_suffix('$')?;
        let close = body.find(']')?;
        let (class, quant) = (&body[..close], &body[close + 1..]);
        let chars: Vec<char> = class.chars().collect();
        let mut ranges = Vec::new();
        let mut i = 0;
        while i < chars.len() {
            if chars[i] == '\\' || chars[i] == '^' || chars[i] == '[' {
                return None;
            }
            if i + 2 < chars.len() && chars[i + 1] == '-' {
                ranges.push((chars[i], chars[i + 2]));
                i += 3;
            } else {
                ranges.push((chars[i], chars[i]));
                i += 1;
            }
        }
        let (min, max) = if quant == "+" {
            (1, usize::MAX)
        } else {
            let q = quant.strip_prefix('{')?.strip_suffix('}')?;
            let (a, b) = q.split_once(',')?;
            (a.parse().ok()?, b.parse().ok()?)
        };
        Some(Pattern { ranges, min, max })
    }

    pub fn matches(&self, s: &str) -> bool {
        let n = s.chars().count();
        n >= self.min
            && n <= self.max
            && s.chars()
                .all(|c| self.ranges.iter().any(|(a, b)| c >= *a && c <= *b))
    }
}
