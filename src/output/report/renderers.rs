//! Report sections about other renderers: the error table of the production thin-layer models
//! (`fringe models`, from `OUT/models/summary.csv`) and the gradings of external values
//! (`fringe grade`, from `OUT/grade/<case>/grade.json`). Each section is absent when its files
//! are.

use super::html::escape;
use std::fmt::Write as _;
use std::path::Path;

/// The models' error table, if `OUT/models/summary.csv` exists.
pub(crate) fn models_section(h: &mut String, out: &Path) {
    let Ok(text) = std::fs::read_to_string(out.join("models/summary.csv")) else {
        return;
    };
    h.push_str(
        "<h2 id=\"models\">Production thin-layer models against exact Airy</h2>\n<p>pbrt-v4 / \
         Mitsuba 3 thin dielectric (incoherent, s/p averaged), the incoherent plate per \
         polarization, Belcour &amp; Barla 2017 (glTF <code>KHR_materials_iridescence</code>), \
         and the Airy sum with the TIR phase dropped, over angles 0–88° × thickness × 360–830 nm; \
         R is the unpolarized power reflectance, colours under D65, ΔE00 against the exact \
         colour. <code>cost:</code> rows isolate one simplification each. Made by \
         <code>fringe models</code>; every grid point is in <code>models/models.csv</code>.</p>\n<table>",
    );
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(text.as_bytes());
    for (i, record) in reader.records().enumerate() {
        let Ok(record) = record else { break };
        let cell = if i == 0 { "th" } else { "td" };
        h.push_str("<tr>");
        for f in record.iter() {
            let _ = write!(h, "<{cell}>{}</{cell}>", escape(f));
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</table>\n");
}

/// One section per graded case, if `OUT/grade/*/grade.json` exist.
pub(crate) fn grade_section(h: &mut String, out: &Path) {
    let Ok(dirs) = std::fs::read_dir(out.join("grade")) else {
        return;
    };
    let mut files: Vec<_> = dirs
        .filter_map(|e| e.ok().map(|e| e.path().join("grade.json")))
        .filter(|p| p.is_file())
        .collect();
    if files.is_empty() {
        return;
    }
    files.sort();
    h.push_str(
        "<h2 id=\"grade\">Graded external values</h2>\n<p>Values of another tracer at a case's \
         probes (<code>fringe grade</code>), judged with the case's tolerances; \
         <code>values~rung</code> rows compare them with each traced fidelity rung.</p>\n",
    );
    for f in files {
        let Some(g) = std::fs::read_to_string(&f)
            .ok()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        else {
            continue;
        };
        let s = |k: &str| g.get(k).and_then(|v| v.as_str()).unwrap_or("").to_string();
        let _ = writeln!(
            h,
            "<h3>{} — {}</h3>\n<p>values file <code>{}</code>, judged at the {} tolerance: <span class=\"badge {}\">{}</span></p>",
            escape(&s("case")),
            escape(&s("values_file")),
            escape(&s("values_file")),
            escape(&s("level")),
            if g.get("failed") == Some(&serde_json::Value::Bool(true)) {
                "fail"
            } else {
                "pass"
            },
            if g.get("failed") == Some(&serde_json::Value::Bool(true)) {
                "FAIL"
            } else {
                "pass"
            },
        );
        for c in g
            .get("closest")
            .and_then(|c| c.as_array())
            .into_iter()
            .flatten()
        {
            let _ = writeln!(
                h,
                "<p>{}: closest to the <b>{}</b> rung (max|dev| {:.3e})</p>",
                escape(c.get("quantity").and_then(|v| v.as_str()).unwrap_or("")),
                escape(c.get("fidelity").and_then(|v| v.as_str()).unwrap_or("")),
                c.get("max_abs_dev")
                    .and_then(|v| v.as_f64())
                    .unwrap_or(f64::NAN)
            );
        }
        h.push_str("<table><tr><th>fidelity</th><th>metric</th><th>max|dev|</th><th>rms dev</th><th>tol</th><th>verdict</th></tr>\n");
        for r in g
            .get("rows")
            .and_then(|r| r.as_array())
            .into_iter()
            .flatten()
        {
            let num = |k: &str| {
                r.get(k)
                    .and_then(|v| v.as_f64())
                    .map(|x| format!("{x:.3e}"))
                    .unwrap_or_else(|| "-".into())
            };
            let verdict = match r.get("pass").and_then(|v| v.as_bool()) {
                Some(true) => "pass",
                Some(false) => "FAIL",
                None => "info",
            };
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{verdict}</td></tr>",
                escape(r.get("fidelity").and_then(|v| v.as_str()).unwrap_or("")),
                escape(r.get("metric").and_then(|v| v.as_str()).unwrap_or("")),
                num("max_abs_dev"),
                num("rms_dev"),
                num("tolerance"),
            );
        }
        h.push_str("</table>\n");
    }
}
