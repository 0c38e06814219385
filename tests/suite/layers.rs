//! The one-way flow of layers (`/work/shared/DESIGN.md`, the crate docs' "Layout"): each
//! top-level module of `src/` may use only the modules before it in [`LAYERS`]. Read from the
//! source text: a code line (not a comment) of a layer that names `crate::<later layer>` fails.

use std::path::{Path, PathBuf};

/// The layers, lowest first.
const LAYERS: [&str; 9] = [
    "io",
    "optics",
    "scene",
    "accumulate",
    "trace",
    "colour",
    "harness",
    "output",
    "cli",
];

fn rust_files(p: &Path, out: &mut Vec<PathBuf>) {
    if p.is_dir() {
        for e in std::fs::read_dir(p).unwrap() {
            rust_files(&e.unwrap().path(), out);
        }
    } else if p.is_file() && p.extension().is_some_and(|e| e == "rs") {
        out.push(p.to_path_buf());
    }
}

/// `(file:line, text)` of every code line of `layer` that names a module in `forbidden`.
fn upward_uses(layer: &str, forbidden: &[&str]) -> Vec<String> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src.join(layer), &mut files);
    rust_files(&src.join(format!("{layer}.rs")), &mut files);
    assert!(!files.is_empty(), "layer {layer}: no source files");
    let mut hits = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        for (k, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("//") {
                continue;
            }
            for up in forbidden {
                for form in [format!("crate::{up}::"), format!("crate::{up};")] {
                    if line.contains(&form) {
                        hits.push(format!("{}:{}: {}", f.display(), k + 1, line.trim()));
                    }
                }
            }
        }
    }
    hits
}

#[test]
fn the_harness_never_uses_the_outputs_or_the_commands() {
    let hits = upward_uses("harness", &["output", "cli"]);
    assert!(hits.is_empty(), "upward uses:\n{}", hits.join("\n"));
}

#[test]
fn every_layer_uses_only_the_layers_before_it() {
    let mut hits = Vec::new();
    for (k, layer) in LAYERS.iter().enumerate() {
        hits.extend(upward_uses(layer, &LAYERS[k + 1..]));
    }
    assert!(hits.is_empty(), "upward uses:\n{}", hits.join("\n"));
}

#[test]
fn the_layer_check_sees_an_upward_use() {
    // The check itself: `output` names `crate::harness::` (a downward use), so asking whether
    // output uses the harness as if the harness were above it finds lines.
    assert!(!upward_uses("output", &["harness"]).is_empty());
}
