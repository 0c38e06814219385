//! plate_two_beam_paper with more plates, shared by `tests/suite/preflight.rs`,
//! `tests/suite/input_classes.rs` and `benches/preflight.rs`: the scenes whose sequence tree
//! grows with the number of plates (reflections between separate plates in the ambient medium
//! are not internal reflections).

use serde_json::{Value, json};

/// `doc` (the JSON of plate_two_beam_paper) with `k` plates: copies of its first plate, each
/// 1 mm below the one above.
pub fn stacked_plates(doc: &Value, k: usize) -> Value {
    let mut doc = doc.clone();
    let plate = doc["scene"]["surfaces"][0].clone();
    for j in 1..k {
        let mut p = plate.clone();
        p["plate"]["name"] = json!(format!("plate{j}"));
        p["plate"]["top_point_m"] = json!([0.0, 0.0, -0.001 * j as f64]);
        doc["scene"]["surfaces"]
            .as_array_mut()
            .unwrap()
            .insert(j, p);
    }
    doc
}
