//! Loading and validating a case file. Every error names the file, the JSON path of the bad
//! field and what is allowed; nothing is run or written for an invalid case.

use super::spec::*;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

/// Documented caps (also in cases/README.md).
pub mod limits {
    /// Wavelengths accepted anywhere (vacuum, nm).
    pub const WAVELENGTH_NM: (f64, f64) = (200.0, 2500.0);
    /// Probe points per case.
    pub const MAX_PROBE_POINTS: usize = 100_000;
    /// Spectral samples per case.
    pub const MAX_SPECTRAL_SAMPLES: usize = 4096;
    /// Internal reflections per path.
    pub const MAX_INTERNAL_REFLECTIONS: usize = 2000;
    /// Largest coordinate or length (m).
    pub const MAX_LENGTH_M: f64 = 1.0e3;
    /// Refractive indices accepted.
    pub const INDEX: (f64, f64) = (1.0e-3, 10.0);
    /// Probe points × spectral samples per case (the number of traced point-wavelength pairs).
    pub const MAX_POINT_SAMPLES: usize = 10_000_000;
    /// Largest `coherence_group` of a source.
    pub const MAX_COHERENCE_GROUP: u64 = 1_000_000_000;
    /// Largest `tir_count` of a `rhomb_retardance` reference.
    pub const MAX_TIR_COUNT: usize = 100;
    /// Largest case file (bytes).
    pub const MAX_FILE_BYTES: u64 = 16 << 20;
    /// Thinnest plate or wedge (µm): 1 pm. Films down to 1 pm trace correctly; below it a
    /// thickness is nonsense (1e-300 µm), not physics.
    pub const MIN_THICKNESS_UM: f64 = 1.0e-6;
    /// Case names the tool's own outputs use (folders and rows next to the cases' in `--out`):
    /// a case may not be called one of these.
    pub const RESERVED_CASE_NAMES: [&str; 6] = [
        "stability",
        "figures",
        "render",
        "tradeoff",
        "forward",
        "summary",
    ];
    /// Directions (normals, axes, polarization references) must have a length in this range.
    pub const DIRECTION_LENGTH: (f64, f64) = (1.0e-12, 1.0e12);
}

/// A case-file error: file, JSON path, message.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseError {
    /// The case file.
    pub file: PathBuf,
    /// Where in it (`$.scene.surfaces[2].plate.thickness_um`).
    pub json_path: String,
    /// What is wrong and what is allowed.
    pub message: String,
}

impl fmt::Display for CaseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: {}: {}",
            self.file.display(),
            self.json_path,
            self.message
        )
    }
}

impl std::error::Error for CaseError {}

/// A validated case.
#[derive(Clone, Debug)]
pub struct Case {
    /// The file it was read from.
    pub file: PathBuf,
    /// Its contents.
    pub spec: CaseFile,
}

/// Read, parse and validate a case file.
pub fn load(path: &Path) -> Result<Case, CaseError> {
    let err = |message: String| CaseError {
        file: path.to_path_buf(),
        json_path: "$".into(),
        message,
    };
    let meta = std::fs::metadata(path).map_err(|e| err(format!("cannot read the file: {e}")))?;
    if !meta.is_file() {
        return Err(err("not a regular file".into()));
    }
    if meta.len() > limits::MAX_FILE_BYTES {
        return Err(err(format!(
            "a case file is at most {} bytes, this one has {}",
            limits::MAX_FILE_BYTES,
            meta.len()
        )));
    }
    let bytes = std::fs::read(path).map_err(|e| err(format!("cannot read the file: {e}")))?;
    let text = String::from_utf8(bytes).map_err(|e| {
        err(format!(
            "the file is not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        ))
    })?;
    parse(path, &text)
}

/// Parse and validate case text (the file name is used in errors only).
pub fn parse(path: &Path, text: &str) -> Result<Case, CaseError> {
    let err = |(json_path, message): (String, String)| CaseError {
        file: path.to_path_buf(),
        json_path,
        message,
    };
    // A UTF-8 byte-order mark (some editors write one) is not an error.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if let Some(c) = text.trim_start().chars().next().filter(|c| *c != '{') {
        return Err(err((
            "$".into(),
            format!(
                "a case file is one JSON object {{\"name\": …, \"light\": …, …}}; this file starts with {c:?}"
            ),
        )));
    }
    let de = &mut serde_json::Deserializer::from_str(text);
    let spec: CaseFile = serde_path_to_error::deserialize(&mut *de).map_err(|e| {
        // A key written twice explains a failure the format names less clearly (a kind given
        // twice reads as an object with two kinds).
        err(repeated_key(text).unwrap_or_else(|| serde_error(text, e)))
    })?;
    if let Some(e) = repeated_key(text) {
        return Err(err(e));
    }
    de.end().map_err(|e| {
        err((
            "$".into(),
            format!(
                "malformed JSON: text after the case object (line {}, column {}); a case file holds one JSON object",
                e.line(),
                e.column()
            ),
        ))
    })?;
    // serde reads a struct from a positional array too (`"trace": [3]` would become
    // max_internal_reflections = 3): a case file writes every object with its keys.
    if let (Ok(original), Ok(canonical)) = (
        serde_json::from_str::<serde_json::Value>(text),
        serde_json::to_value(&spec),
    ) && let Some(e) = positional_object(&original, &canonical, "$")
    {
        return Err(err(e));
    }
    let mut v = Validator { errors: Vec::new() };
    v.case(&spec);
    match v.errors.into_iter().next() {
        Some(e) => Err(err(e)),
        None => Ok(Case {
            file: path.to_path_buf(),
            spec,
        }),
    }
}

/// The first key written twice in one object anywhere in `text` (JSON path of the object,
/// message), `None` when there is none or the text is not JSON: JSON leaves repeated keys
/// undefined and serde keeps the last, so a case file names every key once.
fn repeated_key(text: &str) -> Option<(String, String)> {
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
fn positional_object(
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
fn serde_error(text: &str, e: serde_path_to_error::Error<serde_json::Error>) -> (String, String) {
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

struct Validator {
    errors: Vec<(String, String)>,
}

/// The unit vector of a valid direction, `None` if it cannot be normalized.
fn unit(v: &Vec3) -> Option<glam::DVec3> {
    let (lo, hi) = limits::DIRECTION_LENGTH;
    let d = glam::DVec3::from_array(*v);
    let len = d.length();
    (len.is_finite() && len >= lo && len <= hi).then(|| d / len)
}

/// A number for a message: plain in [1e-3, 1e6), else in exponent form (1e-15, not 0.000…1).
fn num(x: f64) -> String {
    if x == 0.0 || (x.abs() >= 1e-3 && x.abs() < 1e6) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// The number of probe points of a probe (saturating: a grid's product cannot overflow).
pub fn probe_point_count(p: &Probe) -> usize {
    match p {
        Probe::Line { count, .. } | Probe::Sweep { count, .. } => *count,
        Probe::Single { .. } => 1,
        Probe::Grid { pixels, .. } => pixels[0].saturating_mul(pixels[1]),
    }
}

/// Surface and source names: 1–64 characters from [A-Za-z0-9_-].
fn name_ok(n: &str) -> bool {
    !n.is_empty()
        && n.len() <= 64
        && n.chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}

/// The nearest a probe point may be to a point or line source (m): about a wavelength; closer,
/// ray optics does not hold and on the source the wave is singular.
pub const MIN_PROBE_DISTANCE_M: f64 = 1.0e-6;

/// The planes of a surface's faces: (a point, the unit normal); one for thin surfaces, two for
/// plates and wedges (the wedge's bottom tilted by its angle about the hinge). A bounded
/// surface's plane extends beyond the surface: callers say which they need.
fn surface_planes(surf: &SurfaceSpec) -> Vec<(glam::DVec3, glam::DVec3)> {
    use glam::DVec3;
    let n = |v: &Vec3| unit(v).unwrap_or(DVec3::Z);
    match surf {
        SurfaceSpec::Interface {
            point_m, normal, ..
        }
        | SurfaceSpec::Mirror {
            point_m, normal, ..
        }
        | SurfaceSpec::Splitter {
            point_m, normal, ..
        }
        | SurfaceSpec::Shield {
            point_m, normal, ..
        }
        | SurfaceSpec::OpaqueScreen {
            point_m, normal, ..
        } => vec![(DVec3::from_array(*point_m), n(normal))],
        SurfaceSpec::Plate {
            top_point_m,
            normal,
            thickness_um,
            ..
        } => {
            let (t, n) = (DVec3::from_array(*top_point_m), n(normal));
            vec![(t, n), (t - thickness_um * 1e-6 * n, n)]
        }
        SurfaceSpec::Wedge {
            top_point_m,
            normal,
            thickness_um,
            angle_deg,
            hinge_axis,
            ..
        } => {
            let (t, n) = (DVec3::from_array(*top_point_m), n(normal));
            let h = DVec3::from_array(*hinge_axis);
            let axis = (h - h.dot(n) * n).normalize_or_zero();
            let tilted = glam::DQuat::from_axis_angle(axis, angle_deg.to_radians()) * n;
            vec![(t, n), (t - thickness_um * 1e-6 * n, tilted)]
        }
    }
}

impl Validator {
    fn fail(&mut self, path: &str, msg: impl Into<String>) {
        self.errors.push((path.to_string(), msg.into()));
    }

    fn finite(&mut self, path: &str, x: f64) -> bool {
        if !x.is_finite() {
            self.fail(path, format!("must be a finite number, got {x}"));
            return false;
        }
        true
    }

    fn range(&mut self, path: &str, x: f64, lo: f64, hi: f64, what: &str) {
        if self.finite(path, x) && !(x >= lo && x <= hi) {
            self.fail(
                path,
                format!(
                    "{what} must be in [{}, {}], got {}",
                    num(lo),
                    num(hi),
                    num(x)
                ),
            );
        }
    }

    fn positive(&mut self, path: &str, x: f64, hi: f64, what: &str) {
        if self.finite(path, x) && !(x > 0.0 && x <= hi) {
            self.fail(
                path,
                format!("{what} must be > 0 and ≤ {}, got {}", num(hi), num(x)),
            );
        }
    }

    fn point(&mut self, path: &str, v: &Vec3) {
        for (k, x) in v.iter().enumerate() {
            self.range(
                &format!("{path}[{k}]"),
                *x,
                -limits::MAX_LENGTH_M,
                limits::MAX_LENGTH_M,
                "a coordinate (m)",
            );
        }
    }

    /// A direction: finite, not zero, not so small or large that normalizing it fails.
    fn direction(&mut self, path: &str, v: &Vec3) -> bool {
        let (lo, hi) = limits::DIRECTION_LENGTH;
        if v.iter().any(|x| !x.is_finite()) {
            self.fail(path, "a direction must have finite components");
            return false;
        }
        let len = glam::DVec3::from_array(*v).length();
        if len == 0.0 {
            self.fail(path, "a direction must not be the zero vector");
            false
        } else if !(len >= lo && len <= hi) {
            self.fail(
                path,
                format!("a direction must have a length in [{lo:e}, {hi:e}], got {len:e}"),
            );
            false
        } else {
            true
        }
    }

    /// `a` (at `path`) must not be parallel to `b` (both valid directions, else no verdict).
    fn not_parallel(&mut self, path: &str, a: &Vec3, b: &Vec3, what: &str) {
        let (x, y) = (unit(a), unit(b));
        if let (Some(x), Some(y)) = (x, y)
            && x.cross(y).length() < 1e-9
        {
            self.fail(
                path,
                format!("{what}: the two are parallel, {a:?} and {b:?}"),
            );
        }
    }

    fn medium_ref(&mut self, path: &str, name: &str, media: &BTreeMap<String, MediumSpec>) {
        if !media.contains_key(name) {
            let known: Vec<&str> = media.keys().map(|s| s.as_str()).collect();
            self.fail(
                path,
                format!("unknown medium {name:?}; defined media: {known:?}"),
            );
        }
    }

    fn wavelength(&mut self, path: &str, nm: f64) {
        let (lo, hi) = limits::WAVELENGTH_NM;
        self.range(path, nm, lo, hi, "a wavelength (nm)");
    }

    fn rect(&mut self, path: &str, r: &RectSpec, normal: &Vec3) {
        for k in 0..2 {
            self.positive(
                &format!("{path}.size_m[{k}]"),
                r.size_m[k],
                2.0 * limits::MAX_LENGTH_M,
                "a size (m)",
            );
        }
        self.direction(&format!("{path}.u_axis"), &r.u_axis);
        self.not_parallel(
            &format!("{path}.u_axis"),
            &r.u_axis,
            normal,
            "u_axis must not be parallel to the surface normal",
        );
    }

    fn case(&mut self, c: &CaseFile) {
        if c.name.is_empty()
            || c.name.len() > 64
            || !c
                .name
                .chars()
                .all(|ch| ch.is_ascii_lowercase() || ch.is_ascii_digit() || ch == '_')
        {
            self.fail("$.name", format!("a case name is 1–64 characters from [a-z0-9_] (it names output files), got {:?}", c.name));
        } else if limits::RESERVED_CASE_NAMES.contains(&c.name.as_str()) {
            self.fail(
                "$.name",
                format!(
                    "the case name {:?} is reserved for fringe's own outputs (reserved: {:?}); choose another",
                    c.name,
                    limits::RESERVED_CASE_NAMES
                ),
            );
        }
        self.light(&c.light);
        self.scene(&c.scene);
        self.probe(&c.probe, &c.scene);
        if let Some(f) = &c.fidelities {
            if f.is_empty() {
                self.fail(
                    "$.fidelities",
                    "list at least one fidelity level, or omit the key for all",
                );
            }
            if !f.contains(&crate::accumulate::fidelity::Fidelity::Vector) {
                self.fail(
                    "$.fidelities",
                    "the `vector` level (the reference) must be run",
                );
            }
            for (k, level) in f.iter().enumerate() {
                if f[..k].contains(level) {
                    self.fail(
                        &format!("$.fidelities[{k}]"),
                        format!("level `{level}` is listed twice"),
                    );
                }
            }
        }
        if c.references.is_empty() {
            self.fail("$.references", "at least one reference is required");
        }
        let mut labels = std::collections::BTreeSet::new();
        for (i, r) in c.references.iter().enumerate() {
            self.reference(&format!("$.references[{i}]"), r, &c.scene, &c.light);
            let label = r
                .label
                .clone()
                .unwrap_or_else(|| super::reference::name(&r.model));
            if !label
                .chars()
                .all(|ch| ch.is_ascii_alphanumeric() || ch == '_')
                || label.is_empty()
            {
                self.fail(
                    &format!("$.references[{i}].label"),
                    format!("a label is 1+ characters from [A-Za-z0-9_], got {label:?}"),
                );
            }
            if !labels.insert(label.clone()) {
                self.fail(
                    &format!("$.references[{i}].label"),
                    format!(
                        "metric name {label:?} is used twice: give the reference a distinct `label`"
                    ),
                );
            }
            if let Some(f) = &c.fidelities {
                for level in r.tolerances.keys() {
                    if !f.contains(level) {
                        self.fail(
                            &format!("$.references[{i}].tolerances.{level}"),
                            format!("a tolerance for level `{level}`, which $.fidelities does not run: add `{level}` to $.fidelities or drop the tolerance"),
                        );
                    }
                }
            }
        }
        let t = &c.trace;
        if t.max_internal_reflections > limits::MAX_INTERNAL_REFLECTIONS {
            self.fail(
                "$.trace.max_internal_reflections",
                format!(
                    "at most {} internal reflections, got {}",
                    limits::MAX_INTERNAL_REFLECTIONS,
                    t.max_internal_reflections
                ),
            );
        }
        if let Some(e) = t.airy_tail_epsilon {
            self.range(
                "$.trace.airy_tail_epsilon",
                e,
                1e-15,
                0.5,
                "the Airy tail bound",
            );
            if !c
                .references
                .iter()
                .any(|r| matches!(r.model, ReferenceModel::Airy { .. }))
            {
                self.fail(
                    "$.trace.airy_tail_epsilon",
                    "needs an `airy` reference naming the film whose tail it bounds (or use max_internal_reflections)",
                );
            }
        }
        self.range(
            "$.trace.golden_tolerance",
            t.golden_tolerance,
            0.0,
            1.0,
            "the golden tolerance",
        );
        // Checks across sections need every field in range first.
        if self.errors.is_empty() {
            self.cross(c);
        }
    }

    /// Checks that combine sections of a field-by-field valid case: the sampled spectrum, the
    /// media at every wavelength the case uses, the work cap, where the sources sit.
    fn cross(&mut self, c: &CaseFile) {
        let s = &c.scene;
        // The wavelengths the case traces (nm): its spectrum, or the points of a wavelength sweep.
        let spectrum_nm: Vec<f64> = super::build::spectrum(&c.light, &Default::default())
            .iter()
            .map(|(l, _)| l * 1e9)
            .collect();
        let (lo, hi) = limits::WAVELENGTH_NM;
        if let Light::Gaussian { .. } = c.light {
            let min = spectrum_nm.iter().copied().fold(f64::INFINITY, f64::min);
            let max = spectrum_nm
                .iter()
                .copied()
                .fold(f64::NEG_INFINITY, f64::max);
            if spectrum_nm
                .iter()
                .any(|l| !(l.is_finite() && *l >= lo && *l <= hi))
            {
                self.fail(
                    "$.light.gaussian",
                    format!("the sampled spectrum (±sigmas standard deviations around center_nm) spans {min:.6} to {max:.6} nm; it must lie within [{lo}, {hi}] nm: reduce fwhm_nm or sigmas"),
                );
                return;
            }
        }
        let points = probe_point_count(&c.probe);
        if points.saturating_mul(spectrum_nm.len()) > limits::MAX_POINT_SAMPLES {
            let key = match &c.probe {
                Probe::Line { .. } => "$.probe.line.count",
                Probe::Sweep { .. } => "$.probe.sweep.count",
                Probe::Grid { .. } => "$.probe.grid.pixels",
                Probe::Single { .. } => "$.probe",
            };
            self.fail(
                key,
                format!(
                    "probe points × spectral samples must be at most {}, got {points} × {}",
                    limits::MAX_POINT_SAMPLES,
                    spectrum_nm.len()
                ),
            );
        }
        let has_plane_wave = s
            .sources
            .iter()
            .any(|x| matches!(x.emitter, EmitterSpec::PlaneWave { .. }));
        let observer = match &c.probe {
            Probe::Sweep { observe, .. } => Some(("$.probe.sweep.observe", observe)),
            Probe::Single { observe } => Some(("$.probe.single.observe", observe)),
            _ => None,
        };
        if let Some((op, Observer::FarField { .. })) = observer
            && !has_plane_wave
        {
            self.fail(
                    &format!("{op}.far_field"),
                    "a far_field observer needs a plane-wave source (it looks along the reflected or refracted plane wave)",
                );
        }
        if let Probe::Sweep { parameter, .. } = &c.probe {
            match parameter {
                SweepParameter::IncidenceAngleDeg { .. } if !has_plane_wave => self.fail(
                    "$.probe.sweep.parameter.incidence_angle_deg",
                    "an incidence-angle sweep turns the plane-wave sources: the scene has none",
                ),
                SweepParameter::WavelengthNm {} if !matches!(c.light, Light::Monochrome { .. }) => {
                    self.fail(
                        "$.probe.sweep.parameter.wavelength_nm",
                        "a wavelength sweep needs monochrome light (each point traces one wavelength)",
                    )
                }
                _ => {}
            }
        }
        let wavelengths: Vec<f64> = match &c.probe {
            Probe::Sweep {
                parameter: SweepParameter::WavelengthNm {},
                ..
            } => super::build::probe_points(&c.probe)
                .iter()
                .filter_map(|p| p.overrides.wavelength_m.map(|l| l * 1e9))
                .collect(),
            _ => spectrum_nm,
        };
        // Every medium the scene uses must have a real index in range at every wavelength.
        let mut used: Vec<(&str, String)> = vec![(s.ambient.as_str(), "$.scene.ambient".into())];
        for (i, surf) in s.surfaces.iter().enumerate() {
            let q = format!("$.scene.surfaces[{i}].{}", surf.kind());
            match surf {
                SurfaceSpec::Interface { front, back, .. } => {
                    used.push((front, format!("{q}.front")));
                    used.push((back, format!("{q}.back")));
                }
                SurfaceSpec::Plate {
                    medium,
                    above,
                    below,
                    ..
                }
                | SurfaceSpec::Wedge {
                    medium,
                    above,
                    below,
                    ..
                } => {
                    used.push((medium, format!("{q}.medium")));
                    used.push((above, format!("{q}.above")));
                    used.push((below, format!("{q}.below")));
                }
                _ => {}
            }
        }
        let mut checked = std::collections::BTreeSet::new();
        for (name, _) in used {
            let Some(spec) = s.media.get(name) else {
                continue;
            };
            if !checked.insert(name) {
                continue;
            }
            let m = super::build::medium(name, spec);
            let (ilo, ihi) = limits::INDEX;
            for l in &wavelengths {
                let bad = match m.index(l * 1e-9) {
                    Err(e) => Some(format!("at the case's wavelength {l} nm: {e}")),
                    Ok(n) if !(n >= ilo && n <= ihi) => Some(format!(
                        "the index at the case's wavelength {l} nm is {n}, outside [{ilo}, {ihi}]"
                    )),
                    Ok(_) => None,
                };
                if let Some(msg) = bad {
                    self.fail(&format!("$.scene.media.{name}"), msg);
                    break;
                }
            }
        }
        for (i, src) in s.sources.iter().enumerate() {
            self.placement(&format!("$.scene.sources[{i}]"), src, s);
        }
        if self.errors.is_empty() {
            self.coincident_sources(s);
        }
        if self.errors.is_empty() {
            self.probe_geometry(c);
        }
        if self.errors.is_empty() {
            self.intersecting_slabs(s);
        }
    }

    /// Two point sources at one place, or two line sources along one line (coincident Young
    /// slits): the "two beams" are one, and the closed forms that need their separation
    /// (Young's d) are undefined.
    fn coincident_sources(&mut self, s: &SceneSpec) {
        use glam::DVec3;
        let anchor = |e: &EmitterSpec| match e {
            EmitterSpec::Point { position_m } => Some((DVec3::from_array(*position_m), None)),
            EmitterSpec::Line { point_m, axis } => Some((DVec3::from_array(*point_m), unit(axis))),
            EmitterSpec::PlaneWave { .. } => None,
        };
        for (j, b) in s.sources.iter().enumerate() {
            for a in &s.sources[..j] {
                let (Some((pa, la)), Some((pb, lb))) = (anchor(&a.emitter), anchor(&b.emitter))
                else {
                    continue;
                };
                let same = match (la, lb) {
                    (None, None) => (pa - pb).length() < MIN_PROBE_DISTANCE_M,
                    (Some(u), Some(w)) => {
                        u.cross(w).length() < 1e-9
                            && (pb - pa - (pb - pa).dot(u) * u).length() < MIN_PROBE_DISTANCE_M
                    }
                    _ => false,
                };
                if same {
                    self.fail(
                        &format!("$.scene.sources[{j}].emitter"),
                        format!(
                            "sources {:?} and {:?} coincide (closer than {MIN_PROBE_DISTANCE_M:e} m, about a wavelength): they are one source, not two beams; separate them or merge them into one source of the summed intensity",
                            a.name, b.name
                        ),
                    );
                    return;
                }
            }
        }
    }

    /// Every probe point must be a place the tracer can mean: not within about a wavelength of
    /// a point or line source (ray optics needs the observer far from its sources; on the
    /// source the spherical or cylindrical wave is singular), and not on a surface (a detector
    /// in an interface has no side). A probe line or grid through a source is refused even if
    /// no sample lands on it.
    fn probe_geometry(&mut self, c: &CaseFile) {
        use glam::DVec3;
        let (key, segment): (&str, Option<(DVec3, DVec3)>) = match &c.probe {
            Probe::Line { from_m, to_m, .. } => (
                "$.probe.line",
                Some((DVec3::from_array(*from_m), DVec3::from_array(*to_m))),
            ),
            Probe::Grid { .. } => ("$.probe.grid", None),
            Probe::Sweep { .. } => ("$.probe.sweep.observe.point.position_m", None),
            Probe::Single { .. } => ("$.probe.single.observe.point.position_m", None),
        };
        let points: Vec<DVec3> = super::build::probe_points(&c.probe)
            .iter()
            .filter_map(|p| match &p.observer {
                Observer::Point { position_m, .. } => Some(DVec3::from_array(*position_m)),
                _ => None,
            })
            .collect();
        if points.is_empty() {
            return;
        }
        // Distance from a source (point, or line through a point) to the probe.
        let segment_distance = |a: DVec3, b: DVec3, x: DVec3| {
            let d = b - a;
            let t = if d.length_squared() > 0.0 {
                ((x - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a + t * d - x).length()
        };
        for src in &c.scene.sources {
            let (dist, what) = match &src.emitter {
                EmitterSpec::Point { position_m } => {
                    let x = DVec3::from_array(*position_m);
                    let near = match segment {
                        Some((a, b)) => segment_distance(a, b, x),
                        None => points
                            .iter()
                            .map(|p| (*p - x).length())
                            .fold(f64::INFINITY, f64::min),
                    };
                    (near, "point source")
                }
                EmitterSpec::Line { point_m, axis } => {
                    let (x, u) = (DVec3::from_array(*point_m), unit(axis).unwrap_or(DVec3::Z));
                    let off = |p: DVec3| (p - x - (p - x).dot(u) * u).length();
                    let near = match segment {
                        // The segment's distance to the line: the smallest over the segment
                        // of the perpendicular offset, a convex function of the parameter.
                        Some((a, b)) => {
                            let (mut lo, mut hi) = (0.0f64, 1.0f64);
                            for _ in 0..200 {
                                let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
                                if off(a + m1 * (b - a)) <= off(a + m2 * (b - a)) {
                                    hi = m2;
                                } else {
                                    lo = m1;
                                }
                            }
                            off(a + 0.5 * (lo + hi) * (b - a))
                        }
                        None => points.iter().map(|p| off(*p)).fold(f64::INFINITY, f64::min),
                    };
                    (near, "line source")
                }
                EmitterSpec::PlaneWave { .. } => continue,
            };
            if dist < MIN_PROBE_DISTANCE_M {
                self.fail(
                    key,
                    format!(
                        "the probe passes within {} m of the {what} {:?}: ray optics needs probe points farther than {MIN_PROBE_DISTANCE_M:e} m (about a wavelength) from a source, and on it the wave is singular",
                        num(dist),
                        src.name
                    ),
                );
                return;
            }
        }
        // A bounded surface: a probe point in its plane and on its rectangle, or within
        // 1e-12 of the scene's scale of its edge, is on the surface (refused as on an unbounded
        // one: which rays reach it, the direct one blocked or not and the reflected one
        // reflecting at the point itself, would be decided by rounding). Beside the rectangle
        // the plane is free space: a point there sees the rays that reach it without touching
        // the surface (a ray reflected by the surface would reflect at the point itself, off
        // the surface), docs/PHYSICS.md §8.
        for surf in &c.scene.surfaces {
            let (point_m, normal, rect) = match surf {
                SurfaceSpec::Interface {
                    point_m,
                    normal,
                    rect: Some(rect),
                    ..
                }
                | SurfaceSpec::Mirror {
                    point_m,
                    normal,
                    rect: Some(rect),
                    ..
                }
                | SurfaceSpec::Splitter {
                    point_m,
                    normal,
                    rect: Some(rect),
                    ..
                }
                | SurfaceSpec::OpaqueScreen {
                    point_m,
                    normal,
                    rect: Some(rect),
                    ..
                }
                | SurfaceSpec::Shield {
                    point_m,
                    normal,
                    rect,
                    ..
                } => (point_m, normal, rect),
                _ => continue,
            };
            let Some(n) = unit(normal) else { continue };
            let plane = crate::scene::geometry::Plane::new(DVec3::from_array(*point_m), n);
            let (u, v) = plane.axes(DVec3::from_array(rect.u_axis));
            let on_it = |p: &DVec3| {
                let scale = plane.point.length().max(p.length()).max(1.0);
                let margin = 1e-12 * scale;
                let d = *p - plane.point;
                d.dot(plane.normal).abs() <= margin
                    && d.dot(u).abs() <= 0.5 * rect.size_m[0] + margin
                    && d.dot(v).abs() <= 0.5 * rect.size_m[1] + margin
            };
            if let Some(p) = points.iter().find(|p| on_it(p)) {
                self.fail(
                    key,
                    format!(
                        "a probe point ({}, {}, {}) lies on {} {:?} (in its plane, on its rectangle or within 1e-12 of the scene's scale of its edge): a detector on a surface has no side; move the probe off the surface, or beside its rectangle",
                        num(p.x),
                        num(p.y),
                        num(p.z),
                        surf.kind(),
                        surf.name()
                    ),
                );
                return;
            }
        }
        // Unbounded faces: anywhere in their planes.
        let bounded = |x: &SurfaceSpec| match x {
            SurfaceSpec::Interface { rect, .. }
            | SurfaceSpec::Mirror { rect, .. }
            | SurfaceSpec::Splitter { rect, .. }
            | SurfaceSpec::OpaqueScreen { rect, .. } => rect.is_some(),
            SurfaceSpec::Shield { .. } => true,
            SurfaceSpec::Plate { .. } | SurfaceSpec::Wedge { .. } => false,
        };
        for surf in c.scene.surfaces.iter().filter(|x| !bounded(x)) {
            for (pt, n) in surface_planes(surf) {
                let scale = pt.length().max(1.0);
                let on = |p: &DVec3| (*p - pt).dot(n).abs() <= 1e-12 * scale;
                let lies_in = match segment {
                    Some((a, b)) => on(&a) && on(&b),
                    None => false,
                };
                if lies_in || points.iter().any(on) {
                    self.fail(
                        key,
                        format!(
                            "{} surface {:?}: a detector in an interface has no side; move the probe off the surface",
                            if lies_in { "the probe line lies in a face of" } else { "a probe point lies on" },
                            surf.name()
                        ),
                    );
                    return;
                }
            }
        }
    }

    /// Plates and wedges are unbounded slabs: two of them must not share any volume (nor a
    /// face). Non-parallel slabs always cross somewhere; parallel ones must be apart along the
    /// normal.
    fn intersecting_slabs(&mut self, s: &SceneSpec) {
        type Faces = Vec<(glam::DVec3, glam::DVec3)>;
        let slabs: Vec<(usize, &SurfaceSpec, Faces)> = s
            .surfaces
            .iter()
            .enumerate()
            .filter(|(_, x)| matches!(x, SurfaceSpec::Plate { .. } | SurfaceSpec::Wedge { .. }))
            .map(|(i, x)| (i, x, surface_planes(x)))
            .collect();
        for (k, (j, b, fb)) in slabs.iter().enumerate() {
            for (_, a, fa) in &slabs[..k] {
                let parallel = fa
                    .iter()
                    .chain(fb.iter())
                    .all(|(_, n)| n.cross(fa[0].1).length() < 1e-9);
                let apart = parallel && {
                    // Intervals along the common normal.
                    let n = fa[0].1;
                    let span = |f: &[(glam::DVec3, glam::DVec3)]| {
                        let (x, y) = (f[0].0.dot(n), f[1].0.dot(n));
                        (x.min(y), x.max(y))
                    };
                    let ((a0, a1), (b0, b1)) = (span(fa), span(fb));
                    a1 < b0 || b1 < a0
                };
                if !apart {
                    self.fail(
                        &format!("$.scene.surfaces[{j}].{}", b.kind()),
                        format!(
                            "{:?} and {:?} intersect or touch: {}; plates and wedges are unbounded slabs and must not share volume or a face",
                            a.name(),
                            b.name(),
                            if parallel {
                                "their thicknesses overlap along the normal"
                            } else {
                                "their faces are not parallel, so the unbounded slabs cross"
                            }
                        ),
                    );
                    return;
                }
            }
        }
    }

    fn light(&mut self, l: &Light) {
        match l {
            Light::Monochrome { wavelength_nm } => {
                self.wavelength("$.light.monochrome.wavelength_nm", *wavelength_nm)
            }
            Light::Gaussian {
                center_nm,
                fwhm_nm,
                samples,
                sigmas,
            } => {
                self.wavelength("$.light.gaussian.center_nm", *center_nm);
                self.positive(
                    "$.light.gaussian.fwhm_nm",
                    *fwhm_nm,
                    center_nm.abs() * 0.2,
                    "the FWHM (nm, at most 20% of the centre)",
                );
                if *samples < 2 || *samples > limits::MAX_SPECTRAL_SAMPLES {
                    self.fail(
                        "$.light.gaussian.samples",
                        format!(
                            "2 to {} spectral samples, got {samples}",
                            limits::MAX_SPECTRAL_SAMPLES
                        ),
                    );
                }
                self.range(
                    "$.light.gaussian.sigmas",
                    *sigmas,
                    1.0,
                    12.0,
                    "the sampled half-width in standard deviations",
                );
            }
        }
    }

    fn scene(&mut self, s: &SceneSpec) {
        if s.media.is_empty() {
            self.fail("$.scene.media", "define at least the ambient medium");
        }
        for (name, m) in &s.media {
            let p = format!("$.scene.media.{name}");
            match m {
                MediumSpec::Constant { n } => {
                    let (lo, hi) = limits::INDEX;
                    if self.finite(&format!("{p}.constant.n"), *n) && !(*n >= lo && *n <= hi) {
                        self.fail(&format!("{p}.constant.n"), format!("a refractive index must be real and in [{lo}, {hi}] (lossy/complex indices are out of scope), got {n}"));
                    }
                }
                MediumSpec::Cauchy {
                    a,
                    b_um2,
                    c_um4,
                    min_nm,
                    max_nm,
                } => {
                    for (k, x) in [("a", a), ("b_um2", b_um2), ("c_um4", c_um4)] {
                        self.finite(&format!("{p}.cauchy.{k}"), *x);
                    }
                    self.wavelength(&format!("{p}.cauchy.min_nm"), *min_nm);
                    self.wavelength(&format!("{p}.cauchy.max_nm"), *max_nm);
                    if min_nm >= max_nm {
                        self.fail(&format!("{p}.cauchy.max_nm"), "max_nm must exceed min_nm");
                    }
                }
                MediumSpec::Sellmeier {
                    b,
                    c_um2,
                    min_nm,
                    max_nm,
                } => {
                    for k in 0..3 {
                        self.finite(&format!("{p}.sellmeier.b[{k}]"), b[k]);
                        self.finite(&format!("{p}.sellmeier.c_um2[{k}]"), c_um2[k]);
                    }
                    self.wavelength(&format!("{p}.sellmeier.min_nm"), *min_nm);
                    self.wavelength(&format!("{p}.sellmeier.max_nm"), *max_nm);
                    if min_nm >= max_nm {
                        self.fail(
                            &format!("{p}.sellmeier.max_nm"),
                            "max_nm must exceed min_nm",
                        );
                    }
                }
                MediumSpec::Bk7 {} => {}
            }
        }
        self.medium_ref("$.scene.ambient", &s.ambient, &s.media);
        let mut names = std::collections::BTreeSet::new();
        for (i, surf) in s.surfaces.iter().enumerate() {
            let p = format!("$.scene.surfaces[{i}]");
            let np = format!("{p}.{}.name", surf.kind());
            if !names.insert(surf.name().to_string()) {
                self.fail(
                    &np,
                    format!(
                        "surface names must be unique: {:?} appears twice",
                        surf.name()
                    ),
                );
            }
            if !name_ok(surf.name()) {
                self.fail(
                    &np,
                    format!("a surface name is 1–64 characters from [A-Za-z0-9_-] (a plate or wedge `p` has faces `p.top` and `p.bottom`), got {:?}", surf.name()),
                );
            }
            self.surface(&p, surf, s);
        }
        if s.sources.is_empty() {
            self.fail("$.scene.sources", "at least one source is required");
        }
        let mut snames = std::collections::BTreeSet::new();
        for (i, src) in s.sources.iter().enumerate() {
            let p = format!("$.scene.sources[{i}]");
            if !name_ok(&src.name) {
                self.fail(
                    &format!("{p}.name"),
                    format!(
                        "a source name is 1–64 characters from [A-Za-z0-9_-], got {:?}",
                        src.name
                    ),
                );
            }
            if !snames.insert(src.name.clone()) {
                self.fail(
                    &format!("{p}.name"),
                    format!("source names must be unique: {:?} appears twice", src.name),
                );
            }
            self.source(&p, src);
        }
    }

    /// The thickness and the three media of a plate or wedge at `q`.
    fn slab(
        &mut self,
        q: &str,
        thickness_um: f64,
        media: [&String; 3],
        defined: &BTreeMap<String, MediumSpec>,
    ) {
        let path = format!("{q}.thickness_um");
        if self.finite(&path, thickness_um)
            && !(limits::MIN_THICKNESS_UM..=1e6).contains(&thickness_um)
        {
            self.fail(
                &path,
                format!(
                    "a thickness (µm) must be in [{}, 1e6] (1 pm to 1 m), got {}",
                    num(limits::MIN_THICKNESS_UM),
                    num(thickness_um)
                ),
            );
        }
        for (k, m) in ["medium", "above", "below"].into_iter().zip(media) {
            self.medium_ref(&format!("{q}.{k}"), m, defined);
        }
    }

    fn surface(&mut self, p: &str, surf: &SurfaceSpec, s: &SceneSpec) {
        match surf {
            SurfaceSpec::Interface {
                point_m,
                normal,
                front,
                back,
                rect,
                ..
            } => {
                let q = format!("{p}.interface");
                self.point(&format!("{q}.point_m"), point_m);
                self.direction(&format!("{q}.normal"), normal);
                self.medium_ref(&format!("{q}.front"), front, &s.media);
                self.medium_ref(&format!("{q}.back"), back, &s.media);
                if let Some(r) = rect {
                    self.rect(&format!("{q}.rect"), r, normal);
                }
            }
            SurfaceSpec::Plate {
                top_point_m,
                normal,
                thickness_um,
                medium,
                above,
                below,
                ..
            } => {
                let q = format!("{p}.plate");
                self.point(&format!("{q}.top_point_m"), top_point_m);
                self.direction(&format!("{q}.normal"), normal);
                self.slab(&q, *thickness_um, [medium, above, below], &s.media);
            }
            SurfaceSpec::Wedge {
                top_point_m,
                normal,
                thickness_um,
                angle_deg,
                hinge_axis,
                medium,
                above,
                below,
                ..
            } => {
                let q = format!("{p}.wedge");
                self.point(&format!("{q}.top_point_m"), top_point_m);
                self.direction(&format!("{q}.normal"), normal);
                self.direction(&format!("{q}.hinge_axis"), hinge_axis);
                self.not_parallel(
                    &format!("{q}.hinge_axis"),
                    hinge_axis,
                    normal,
                    "the hinge axis must not be parallel to the wedge's normal",
                );
                self.positive(
                    &format!("{q}.angle_deg"),
                    *angle_deg,
                    10.0,
                    "a wedge angle (degrees)",
                );
                self.slab(&q, *thickness_um, [medium, above, below], &s.media);
            }
            SurfaceSpec::Mirror {
                point_m,
                normal,
                rect,
                ..
            } => {
                let q = format!("{p}.mirror");
                self.point(&format!("{q}.point_m"), point_m);
                self.direction(&format!("{q}.normal"), normal);
                if let Some(r) = rect {
                    self.rect(&format!("{q}.rect"), r, normal);
                }
            }
            SurfaceSpec::Splitter {
                point_m,
                normal,
                reflectance,
                rect,
                ..
            } => {
                let q = format!("{p}.splitter");
                self.point(&format!("{q}.point_m"), point_m);
                self.direction(&format!("{q}.normal"), normal);
                self.range(
                    &format!("{q}.reflectance"),
                    *reflectance,
                    0.0,
                    1.0,
                    "a power reflectance",
                );
                if let Some(r) = rect {
                    self.rect(&format!("{q}.rect"), r, normal);
                }
            }
            SurfaceSpec::Shield {
                point_m,
                normal,
                rect,
                ..
            } => {
                let q = format!("{p}.shield");
                self.point(&format!("{q}.point_m"), point_m);
                self.direction(&format!("{q}.normal"), normal);
                self.rect(&format!("{q}.rect"), rect, normal);
            }
            SurfaceSpec::OpaqueScreen {
                point_m,
                normal,
                rect,
                u_axis,
                apertures,
                ..
            } => {
                let q = format!("{p}.opaque_screen");
                self.point(&format!("{q}.point_m"), point_m);
                self.direction(&format!("{q}.normal"), normal);
                self.direction(&format!("{q}.u_axis"), u_axis);
                self.not_parallel(
                    &format!("{q}.u_axis"),
                    u_axis,
                    normal,
                    "u_axis must not be parallel to the screen's normal",
                );
                if let Some(r) = rect {
                    self.rect(&format!("{q}.rect"), r, normal);
                }
                for (k, a) in apertures.iter().enumerate() {
                    let ap = format!("{q}.apertures[{k}]");
                    for j in 0..2 {
                        self.range(
                            &format!("{ap}.center_m[{j}]"),
                            a.center_m[j],
                            -limits::MAX_LENGTH_M,
                            limits::MAX_LENGTH_M,
                            "an aperture centre (m)",
                        );
                        self.positive(
                            &format!("{ap}.size_m[{j}]"),
                            a.size_m[j],
                            2.0 * limits::MAX_LENGTH_M,
                            "an aperture size (m)",
                        );
                    }
                    if let Some(r) = rect {
                        for j in 0..2 {
                            if (a.center_m[j].abs() + 0.5 * a.size_m[j]) > 0.5 * r.size_m[j] {
                                self.fail(&format!("{ap}.size_m[{j}]"), format!("the aperture reaches beyond its screen (screen half-size {} m)", 0.5 * r.size_m[j]));
                            }
                        }
                    }
                }
            }
        }
    }

    fn source(&mut self, p: &str, src: &SourceSpec) {
        match &src.emitter {
            EmitterSpec::Point { position_m } => {
                self.point(&format!("{p}.emitter.point.position_m"), position_m)
            }
            EmitterSpec::Line { point_m, axis } => {
                self.point(&format!("{p}.emitter.line.point_m"), point_m);
                self.direction(&format!("{p}.emitter.line.axis"), axis);
            }
            EmitterSpec::PlaneWave {
                direction,
                reference_point_m,
            } => {
                self.direction(&format!("{p}.emitter.plane_wave.direction"), direction);
                self.point(
                    &format!("{p}.emitter.plane_wave.reference_point_m"),
                    reference_point_m,
                );
            }
        }
        match &src.polarization {
            PolarizationSpec::Linear {
                reference,
                angle_deg,
            } => {
                self.direction(&format!("{p}.polarization.linear.reference"), reference);
                self.range(
                    &format!("{p}.polarization.linear.angle_deg"),
                    *angle_deg,
                    -360.0,
                    360.0,
                    "a polarization angle (degrees)",
                );
            }
            PolarizationSpec::Unpolarized { model, reference } => {
                let path = format!("{p}.polarization.unpolarized.reference");
                match (model, reference) {
                    (UnpolarizedModel::PaperTwoChannel, Some(r)) => {
                        self.direction(&path, r);
                    }
                    (UnpolarizedModel::PaperTwoChannel, None) => self.fail(
                        &path,
                        "the model \"paper_two_channel\" builds its two channels from a \
                         reference direction: give one, e.g. [0, 0, 1]",
                    ),
                    (UnpolarizedModel::BasisFree, Some(_)) => self.fail(
                        &path,
                        "unpolarized light is basis-free by default (three incoherent dipoles \
                         along x, y, z) and takes no reference; remove it, or write \
                         \"model\": \"paper_two_channel\" for the paper's two channels built \
                         from it",
                    ),
                    (UnpolarizedModel::BasisFree, None) => {}
                }
            }
        }
        self.positive(
            &format!("{p}.intensity"),
            src.intensity,
            1e12,
            "a source intensity",
        );
        if src.coherence_group > limits::MAX_COHERENCE_GROUP {
            self.fail(
                &format!("{p}.coherence_group"),
                format!(
                    "a coherence group is 0 to {}, got {}",
                    limits::MAX_COHERENCE_GROUP,
                    src.coherence_group
                ),
            );
        }
        if let Some(l) = src.coherence_length_m {
            self.positive(
                &format!("{p}.coherence_length_m"),
                l,
                limits::MAX_LENGTH_M,
                "a coherence length (m)",
            );
        }
    }

    /// Where a source sits relative to the surfaces (after every field is valid): not on a
    /// surface, not inside a plate or wedge, in the ambient medium, a line source not crossing
    /// an unbounded surface, and a plane wave's polarization reference not along its direction.
    fn placement(&mut self, p: &str, src: &SourceSpec, s: &SceneSpec) {
        use glam::DVec3;
        // The polarization reference, if the source has one (basis-free unpolarized light has
        // none).
        let pol_reference = match &src.polarization {
            PolarizationSpec::Linear { reference, .. } => {
                Some((format!("{p}.polarization.linear.reference"), reference))
            }
            PolarizationSpec::Unpolarized {
                reference: Some(reference),
                ..
            } => Some((format!("{p}.polarization.unpolarized.reference"), reference)),
            PolarizationSpec::Unpolarized {
                reference: None, ..
            } => None,
        };
        let (anchor, line_axis) = match &src.emitter {
            EmitterSpec::Point { position_m } => (DVec3::from_array(*position_m), None),
            EmitterSpec::Line { point_m, axis } => (DVec3::from_array(*point_m), unit(axis)),
            EmitterSpec::PlaneWave { direction, .. } => {
                if let Some((pol_path, reference)) = &pol_reference {
                    self.not_parallel(
                        pol_path,
                        reference,
                        direction,
                        "the polarization reference must not be parallel to the plane wave's direction (the field would be undefined)",
                    );
                }
                return;
            }
        };
        let on = |x: f64| x.abs() < 1e-12;
        for surf in &s.surfaces {
            let name = surf.name();
            // (plane point, unit normal, bounded?, medium in front, medium behind) per face.
            type Face<'a> = (DVec3, DVec3, bool, Option<&'a str>, Option<&'a str>);
            let mut faces: Vec<Face> = Vec::new();
            let mut slab = None;
            match surf {
                SurfaceSpec::Interface {
                    point_m,
                    normal,
                    rect,
                    front,
                    back,
                    ..
                } => faces.push((
                    DVec3::from_array(*point_m),
                    unit(normal).unwrap_or(DVec3::Z),
                    rect.is_some(),
                    Some(front),
                    Some(back),
                )),
                SurfaceSpec::Mirror {
                    point_m,
                    normal,
                    rect,
                    ..
                }
                | SurfaceSpec::Splitter {
                    point_m,
                    normal,
                    rect,
                    ..
                }
                | SurfaceSpec::OpaqueScreen {
                    point_m,
                    normal,
                    rect,
                    ..
                } => faces.push((
                    DVec3::from_array(*point_m),
                    unit(normal).unwrap_or(DVec3::Z),
                    rect.is_some(),
                    None,
                    None,
                )),
                SurfaceSpec::Shield {
                    point_m, normal, ..
                } => faces.push((
                    DVec3::from_array(*point_m),
                    unit(normal).unwrap_or(DVec3::Z),
                    true,
                    None,
                    None,
                )),
                SurfaceSpec::Plate {
                    top_point_m,
                    normal,
                    thickness_um,
                    above,
                    below,
                    ..
                } => {
                    let (t, n) = (
                        DVec3::from_array(*top_point_m),
                        unit(normal).unwrap_or(DVec3::Z),
                    );
                    let b = t - thickness_um * 1e-6 * n;
                    faces.push((t, n, false, Some(above), None));
                    faces.push((b, n, false, None, Some(below)));
                    slab = Some(((t, n), (b, n)));
                }
                SurfaceSpec::Wedge {
                    top_point_m,
                    normal,
                    thickness_um,
                    angle_deg,
                    hinge_axis,
                    above,
                    below,
                    ..
                } => {
                    let (t, n) = (
                        DVec3::from_array(*top_point_m),
                        unit(normal).unwrap_or(DVec3::Z),
                    );
                    let h = DVec3::from_array(*hinge_axis);
                    let axis = (h - h.dot(n) * n).normalize_or_zero();
                    let tilted = glam::DQuat::from_axis_angle(axis, angle_deg.to_radians()) * n;
                    let b = t - thickness_um * 1e-6 * n;
                    faces.push((t, n, false, Some(above), None));
                    faces.push((b, tilted, false, None, Some(below)));
                    slab = Some(((t, n), (b, tilted)));
                }
            }
            for (pt, n, bounded, front, back) in faces {
                let d = (anchor - pt).dot(n);
                if on(d) {
                    self.fail(
                        &format!("{p}.emitter"),
                        format!("the source lies on surface {name:?}: move it off the surface"),
                    );
                    return;
                }
                if bounded {
                    continue;
                }
                if let Some(a) = line_axis
                    && a.dot(n).abs() > 1e-9
                {
                    let kind = match &src.emitter {
                        EmitterSpec::Line { .. } => "line",
                        _ => "point",
                    };
                    self.fail(
                            &format!("{p}.emitter.{kind}.axis"),
                            format!("the line source crosses the unbounded surface {name:?}: its axis must be parallel to the surface"),
                        );
                    return;
                }
                let side = if d > 0.0 { front } else { back };
                if let Some(m) = side
                    && m != s.ambient
                {
                    self.fail(
                            &format!("{p}.emitter"),
                            format!("the source is on the {m:?} side of surface {name:?}, but sources must be in the ambient medium {:?}", s.ambient),
                        );
                    return;
                }
            }
            if let Some(((t, n), (b, nb))) = slab
                && (anchor - t).dot(n) < 0.0
                && (anchor - b).dot(nb) > 0.0
            {
                self.fail(
                        &format!("{p}.emitter"),
                        format!("the source is inside {name:?} (between its faces); sources must be in the ambient medium {:?}", s.ambient),
                    );
                return;
            }
        }
    }

    fn probe(&mut self, probe: &Probe, s: &SceneSpec) {
        let count_ok = |v: &mut Self, path: &str, n: usize| {
            if n == 0 || n > limits::MAX_PROBE_POINTS {
                v.fail(
                    path,
                    format!("1 to {} probe points, got {n}", limits::MAX_PROBE_POINTS),
                );
            }
        };
        match probe {
            Probe::Line {
                from_m,
                to_m,
                count,
                origin_m,
                looks_toward,
            } => {
                if let Some(l) = looks_toward {
                    self.direction("$.probe.line.looks_toward", l);
                }
                self.point("$.probe.line.from_m", from_m);
                self.point("$.probe.line.to_m", to_m);
                if let Some(o) = origin_m {
                    self.point("$.probe.line.origin_m", o);
                }
                count_ok(self, "$.probe.line.count", *count);
                if *count > 1 && from_m == to_m {
                    self.fail("$.probe.line.to_m", "the probe line has zero length");
                }
            }
            Probe::Sweep {
                parameter,
                from,
                to,
                count,
                observe,
            } => {
                count_ok(self, "$.probe.sweep.count", *count);
                match parameter {
                    SweepParameter::IncidenceAngleDeg {
                        surface_normal,
                        in_plane_axis,
                    } => {
                        // 90° is grazing: the wave runs along the surface and never meets it.
                        for (key, x) in [("from", *from), ("to", *to)] {
                            let path = format!("$.probe.sweep.{key}");
                            if self.finite(&path, x) && !(0.0..90.0).contains(&x) {
                                self.fail(
                                    &path,
                                    format!("an angle of incidence (degrees) must be in [0, 90) (90 is grazing), got {}", num(x)),
                                );
                            }
                        }
                        self.direction(
                            "$.probe.sweep.parameter.incidence_angle_deg.surface_normal",
                            surface_normal,
                        );
                        self.direction(
                            "$.probe.sweep.parameter.incidence_angle_deg.in_plane_axis",
                            in_plane_axis,
                        );
                        self.not_parallel(
                            "$.probe.sweep.parameter.incidence_angle_deg.in_plane_axis",
                            in_plane_axis,
                            surface_normal,
                            "in_plane_axis must not be parallel to surface_normal (they span the plane of incidence)",
                        );
                    }
                    SweepParameter::WavelengthNm {} => {
                        self.wavelength("$.probe.sweep.from", *from);
                        self.wavelength("$.probe.sweep.to", *to);
                    }
                    SweepParameter::ThicknessNm { surface } => {
                        let min_nm = limits::MIN_THICKNESS_UM * 1e3;
                        for (key, x) in [("from", *from), ("to", *to)] {
                            self.range(
                                &format!("$.probe.sweep.{key}"),
                                x,
                                min_nm,
                                1e9,
                                "a thickness (nm, 1 pm to 1 m)",
                            );
                        }
                        if !s.surfaces.iter().any(|x| {
                            x.name() == surface
                                && matches!(
                                    x,
                                    SurfaceSpec::Plate { .. } | SurfaceSpec::Wedge { .. }
                                )
                        }) {
                            self.fail(
                                "$.probe.sweep.parameter.thickness_nm.surface",
                                format!("no plate or wedge named {surface:?}"),
                            );
                        }
                    }
                }
                self.observer("$.probe.sweep.observe", observe, s);
            }
            Probe::Single { observe } => self.observer("$.probe.single.observe", observe, s),
            Probe::Grid {
                center_m,
                u_axis,
                v_axis,
                size_m,
                pixels,
                looks_toward,
            } => {
                self.point("$.probe.grid.center_m", center_m);
                self.direction("$.probe.grid.u_axis", u_axis);
                self.direction("$.probe.grid.v_axis", v_axis);
                let (u, w) = (
                    glam::DVec3::from_array(*u_axis),
                    glam::DVec3::from_array(*v_axis),
                );
                if u.length() > 0.0
                    && w.length() > 0.0
                    && u.normalize().cross(w.normalize()).length() < 1e-9
                {
                    self.fail(
                        "$.probe.grid.v_axis",
                        "v_axis must not be parallel to u_axis",
                    );
                }
                for (k, &size) in size_m.iter().enumerate() {
                    self.positive(
                        &format!("$.probe.grid.size_m[{k}]"),
                        size,
                        2.0 * limits::MAX_LENGTH_M,
                        "a size (m)",
                    );
                }
                if pixels[0] == 0
                    || pixels[1] == 0
                    || pixels[0].saturating_mul(pixels[1]) > limits::MAX_PROBE_POINTS
                {
                    self.fail(
                        "$.probe.grid.pixels",
                        format!(
                            "[columns, rows] ≥ 1 with at most {} points in all, got {pixels:?}",
                            limits::MAX_PROBE_POINTS
                        ),
                    );
                }
                if let Some(l) = looks_toward {
                    self.direction("$.probe.grid.looks_toward", l);
                }
            }
        }
    }

    fn observer(&mut self, p: &str, o: &Observer, s: &SceneSpec) {
        match o {
            Observer::Point {
                position_m,
                looks_toward,
            } => {
                self.point(&format!("{p}.point.position_m"), position_m);
                if let Some(l) = looks_toward {
                    self.direction(&format!("{p}.point.looks_toward"), l);
                }
            }
            Observer::FarField {
                surface_normal,
                exit_medium,
                ..
            } => {
                self.direction(&format!("{p}.far_field.surface_normal"), surface_normal);
                if let Some(m) = exit_medium {
                    self.medium_ref(&format!("{p}.far_field.exit_medium"), m, &s.media);
                }
            }
            Observer::Direction {
                direction,
                reference_point_m,
            } => {
                self.direction(&format!("{p}.direction.direction"), direction);
                self.point(
                    &format!("{p}.direction.reference_point_m"),
                    reference_point_m,
                );
            }
        }
    }

    fn reference(&mut self, p: &str, r: &ReferenceSpec, s: &SceneSpec, light: &Light) {
        if p.ends_with("[0]")
            && !r
                .tolerances
                .contains_key(&crate::accumulate::fidelity::Fidelity::Vector)
        {
            self.fail(&format!("{p}.tolerances"), "the first (primary) reference needs a `vector` tolerance, e.g. {\"vector\": 1e-9}; later references may be information only ({})");
        }
        for (f, t) in &r.tolerances {
            let tp = format!("{p}.tolerances.{f}");
            self.range(&tp, *t, 0.0, 10.0, "a relative tolerance");
            if *t > 1e-9
                && *f == crate::accumulate::fidelity::Fidelity::Vector
                && r.tolerance_note.is_none()
            {
                self.fail(&tp, "a vector tolerance looser than 1e-9 needs a `tolerance_note` saying why it is physically forced");
            }
        }
        if r.tolerance_note
            .as_deref()
            .is_some_and(|n| n.trim().is_empty())
        {
            self.fail(
                &format!("{p}.tolerance_note"),
                "a tolerance note says why the tolerance is physically forced: write it, or drop the key",
            );
        }
        let surface_exists = |name: &str| s.surfaces.iter().any(|x| x.name() == name);
        let variant = super::reference::name(&r.model);
        let need = |v: &mut Self, key: &str, name: &str| {
            if !surface_exists(name) {
                let known: Vec<&str> = s.surfaces.iter().map(|x| x.name()).collect();
                v.fail(
                    &format!("{p}.model.{variant}.{key}"),
                    format!("no surface named {name:?}; surfaces: {known:?}"),
                );
            }
        };
        match &r.model {
            ReferenceModel::TwoBeamPlate { plate } | ReferenceModel::CoherenceP9 { plate } => {
                need(self, "plate", plate)
            }
            ReferenceModel::CoherenceGaussian { plate, fwhm_nm } => {
                need(self, "plate", plate);
                if let Some(f) = fwhm_nm {
                    let fp = format!("{p}.model.coherence_gaussian.fwhm_nm");
                    match light {
                        Light::Gaussian { .. } => self.fail(
                            &fp,
                            "fwhm_nm is for monochromatic cases (to judge another coherence model); with Gaussian light the bandwidth is the light's: drop this key",
                        ),
                        Light::Monochrome { wavelength_nm } => self.positive(
                            &fp,
                            *f,
                            0.2 * wavelength_nm.abs(),
                            "a bandwidth (FWHM, nm, at most 20% of the wavelength)",
                        ),
                    }
                }
            }
            ReferenceModel::Airy {
                film,
                index_override,
            } => {
                need(self, "film", film);
                if let Some(n) = index_override {
                    self.range(
                        &format!("{p}.model.airy.index_override"),
                        *n,
                        limits::INDEX.0,
                        limits::INDEX.1,
                        "a refractive index",
                    );
                }
            }
            ReferenceModel::Wedge { wedge } | ReferenceModel::WedgeSpacing { wedge, .. } => {
                need(self, "wedge", wedge)
            }
            ReferenceModel::RhombRetardance {
                glass,
                tir_surface,
                tir_count,
            } => {
                self.medium_ref(
                    &format!("{p}.model.rhomb_retardance.glass"),
                    glass,
                    &s.media,
                );
                need(self, "tir_surface", tir_surface);
                if *tir_count == 0 || *tir_count > limits::MAX_TIR_COUNT {
                    self.fail(
                        &format!("{p}.model.rhomb_retardance.tir_count"),
                        format!("1 to {} TIRs, got {tir_count}", limits::MAX_TIR_COUNT),
                    );
                }
            }
            ReferenceModel::PlaneWaveBeams { beams } => {
                if beams.is_empty() {
                    self.fail(
                        &format!("{p}.model.plane_wave_beams.beams"),
                        "list at least one beam",
                    );
                }
                for (k, b) in beams.iter().enumerate() {
                    if !s.sources.iter().any(|x| x.name == b.source) {
                        self.fail(
                            &format!("{p}.model.plane_wave_beams.beams[{k}].source"),
                            format!("no source named {:?}", b.source),
                        );
                    }
                    for (j, e) in b.events.iter().enumerate() {
                        if !surface_exists(&e.surface)
                            && !surface_exists(e.surface.split('.').next().unwrap_or(""))
                        {
                            self.fail(
                                &format!(
                                    "{p}.model.plane_wave_beams.beams[{k}].events[{j}].surface"
                                ),
                                format!("no surface named {:?}", e.surface),
                            );
                        }
                    }
                }
            }
            ReferenceModel::Michelson { splitter, mirrors } => {
                need(self, "splitter", splitter);
                need(self, "mirrors[0]", &mirrors[0]);
                need(self, "mirrors[1]", &mirrors[1]);
            }
            ReferenceModel::YoungExact {}
            | ReferenceModel::YoungParaxial {}
            | ReferenceModel::YoungSpacing { .. }
            | ReferenceModel::Lloyd {}
            | ReferenceModel::LloydVisibility {}
            | ReferenceModel::IncoherentSum {} => {}
        }
    }
}
