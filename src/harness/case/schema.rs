//! The JSON Schema of the case file format, `cases/schema.json`, generated from the serde types
//! of [`super::spec`] with `schemars`: the types' doc comments become the descriptions, their
//! `#[schemars(...)]` attributes the per-key ranges (taken from [`super::load::limits`] where
//! the loader names the limit). `fringe schema` prints it; a test keeps the committed file
//! equal to it.

use super::load::limits;
use super::spec::CaseFile;
use crate::accumulate::fidelity::Fidelity;
use schemars::{JsonSchema, Schema, SchemaGenerator, json_schema};

/// Where the schema says it lives (its `$id`).
const SCHEMA_ID: &str = "https://github.com/fringe/fringe/cases/schema.json";

/// The schema of a case file (JSON Schema draft 2020-12), as `fringe schema` prints it and
/// `cases/schema.json` holds it.
pub(crate) fn case_schema() -> serde_json::Value {
    let generator = schemars::generate::SchemaSettings::draft2020_12().into_generator();
    let mut schema = generator.into_root_schema_for::<CaseFile>();
    schema.insert("$id".into(), SCHEMA_ID.into());
    schema.to_value()
}

/// `case_schema` as the text of `cases/schema.json`: pretty-printed, with a final newline.
pub fn case_schema_text() -> String {
    let mut s = serde_json::to_string_pretty(&case_schema()).expect("a schema serializes");
    s.push('\n');
    s
}

// Schema-only types: the case types hold a `Vec3` and name one of these with
// `#[schemars(with = ...)]`, so the schema has one definition of each.

/// A point [x, y, z] in metres, each coordinate in [-1000, 1000].
#[derive(JsonSchema)]
#[allow(dead_code)]
pub(crate) struct Point(
    #[schemars(inner(range(min = -limits::MAX_LENGTH_M, max = limits::MAX_LENGTH_M)))] [f64; 3],
);

/// A direction [x, y, z] (any length in [1e-12, 1e12]; it is normalized). Not the zero vector.
#[derive(JsonSchema)]
#[allow(dead_code)]
pub(crate) struct Direction([f64; 3]);

/// Every item of an array schema is > 0 (sizes).
pub(crate) fn positive_items(schema: &mut Schema) {
    if let Some(items) = schema.get_mut("items").and_then(|i| i.as_object_mut()) {
        items.insert("exclusiveMinimum".into(), 0.0.into());
    }
}

/// The `tolerances` map of a reference: one optional relative tolerance in [0, 10] per fidelity
/// level (docs/PHYSICS.md §4), no other key.
pub(crate) fn tolerances(_: &mut SchemaGenerator) -> Schema {
    let mut properties = serde_json::Map::new();
    for level in Fidelity::ALL {
        properties.insert(
            level.name().into(),
            serde_json::json!({
                "type": "number",
                "description": "Relative tolerance for this level.",
                "minimum": 0.0,
                "maximum": 10.0,
            }),
        );
    }
    json_schema!({
        "type": "object",
        "properties": properties,
        "additionalProperties": false,
    })
}
