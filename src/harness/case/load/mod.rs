//! Loading and validating a case file. Every error names the file, the JSON path of the bad
//! field and what is allowed; nothing is run or written for an invalid case.

use super::spec::*;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

mod consistency;
mod fields;
mod json;
mod probe;
mod scene;

pub(crate) use fields::MIN_PROBE_DISTANCE_M;
pub use fields::probe_point_count;
use fields::{name_ok, num, surface_planes, unit};
use json::{positional_object, repeated_key, serde_error};

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
    pub(crate) const MAX_POINT_SAMPLES: usize = 10_000_000;
    /// Largest `coherence_group` of a source.
    pub const MAX_COHERENCE_GROUP: u64 = 1_000_000_000;
    /// Largest `tir_count` of a `rhomb_retardance` reference.
    pub const MAX_TIR_COUNT: usize = 100;
    /// Largest case file (bytes).
    pub(crate) const MAX_FILE_BYTES: u64 = 16 << 20;
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
    pub(crate) const DIRECTION_LENGTH: (f64, f64) = (1.0e-12, 1.0e12);
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

/// The errors found so far, (JSON path, message) in the order the checks met them.
struct Validator {
    errors: Vec<(String, String)>,
}
