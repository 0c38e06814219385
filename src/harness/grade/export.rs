//! `fringe export [CASE…] --out DIR`: a conformance pack per case, `DIR/<case>/`:
//!
//! | file | what |
//! | --- | --- |
//! | `case.json` | the case file as given (scene, light, probe, references, tolerances) |
//! | `pack.json` | conventions, the probe coordinate and its unit, the spectrum, every quantity with its observable, unit and definition, the references judging it with their tolerances per level |
//! | `probes.csv` | every probe point: coordinate, observer, position or swept parameter |
//! | `expected.csv` | per quantity, reference and point: the closed form and the exact traced value at every fidelity rung |
//! | `values_exact.csv` | a complete value file (the `vector` rung's traced values): the format `fringe grade` reads |

use super::{Observable, Quantity, coordinate_name, quantities, values};
use crate::accumulate::fidelity::Fidelity;
use crate::harness::case::build;
use crate::harness::case::load::{self, Case};
use crate::harness::case::run::{self, CaseResult};
use crate::harness::case::spec::{FarSide, Observer};
use crate::harness::check::{self, CheckOptions, Format, InputError};
use serde_json::json;
use std::path::Path;

/// The conventions another tracer must follow (docs/PHYSICS.md §1), as written into every pack.
pub fn conventions() -> serde_json::Value {
    json!({
        "time_dependence": "e^{-iωt}",
        "phase": "a wave that travelled optical path s = Σ n_i L_i carries e^{+i 2π s/λ0}, λ0 the vacuum wavelength",
        "s_p_frame": "at an interface with unit normal N (either orientation) and incident direction d_i: s = normalize(d_i × N); for every ray d ∈ {d_i, d_r, d_t}: p = d × s, so (s, p, d) is right-handed; E = a_s s + a_p p",
        "fresnel": "r_s = (n1 cos θi − n2 cos θt)/(n1 cos θi + n2 cos θt), r_p = (n2 cos θi − n1 cos θt)/(n2 cos θi + n1 cos θt), t_s = 2 n1 cos θi/(n1 cos θi + n2 cos θt), t_p = 2 n1 cos θi/(n2 cos θi + n1 cos θt); under total internal reflection cos θt = +i·sqrt((n1/n2)² sin²θi − 1)",
        "power": "R = |r|², T = (n2 cos θt)/(n1 cos θi)·|t|²",
        "units": "the case file names units in its keys (wavelength_nm, thickness_um, position_m); values are in the unit of their observable",
        "spectrum": "values of polychromatic light are the weighted sums over the spectral samples listed in pack.json (weights sum to 1)"
    })
}

fn observer_name(o: &Observer) -> &'static str {
    match o {
        Observer::Point { .. } => "point",
        Observer::FarField {
            side: FarSide::Reflected,
            ..
        } => "far_field_reflected",
        Observer::FarField {
            side: FarSide::Transmitted,
            ..
        } => "far_field_transmitted",
        Observer::Direction { .. } => "direction",
    }
}

/// `probes.csv` of a case.
pub(crate) fn probes_csv(case: &Case) -> String {
    let opt = |x: Option<f64>| x.map(|v| format!("{v:.17e}")).unwrap_or_default();
    let rows = build::probe_points(&case.spec.probe)
        .into_iter()
        .enumerate()
        .map(|(i, p)| {
            let pos = match &p.observer {
                Observer::Point { position_m, .. } => position_m.map(|x| format!("{x:.17e}")),
                _ => Default::default(),
            };
            let o = &p.overrides;
            let mut fields = vec![
                i.to_string(),
                format!("{:.17e}", p.coordinate),
                observer_name(&p.observer).to_string(),
            ];
            fields.extend(pos);
            fields.extend([
                opt(o.incidence.map(|x| x.0.to_degrees())),
                opt(o.wavelength_m.map(|x| x * 1e9)),
                opt(o.thickness.as_ref().map(|x| x.1 * 1e9)),
            ]);
            fields
        });
    crate::io::csv_text(
        &[
            "point",
            "coordinate",
            "observer",
            "position_x_m",
            "position_y_m",
            "position_z_m",
            "incidence_angle_deg",
            "wavelength_nm",
            "thickness_nm",
        ],
        rows,
    )
}

/// `expected.csv` of a case run.
pub(crate) fn expected_csv(result: &CaseResult, qs: &[Quantity]) -> String {
    let mut header: Vec<String> = ["quantity", "reference", "coordinate", "closed_form"]
        .map(String::from)
        .to_vec();
    header.extend(result.levels.iter().map(|l| format!("traced_{l}")));
    let mut rows = Vec::new();
    for q in qs {
        for &mi in &q.metrics {
            let m = &result.metrics[mi];
            for (k, x) in m.coordinates.iter().enumerate() {
                let mut fields = vec![
                    q.name.clone(),
                    m.name.clone(),
                    format!("{x:.17e}"),
                    format!("{:.17e}", m.analytic[k]),
                ];
                for l in &result.levels {
                    fields.push(
                        m.traced
                            .get(l)
                            .map(|t| format!("{:.17e}", t[k]))
                            .unwrap_or_default(),
                    );
                }
                rows.push(fields);
            }
        }
    }
    crate::io::csv_text(&header.iter().map(String::as_str).collect::<Vec<_>>(), rows)
}

/// `pack.json` of a case run.
pub(crate) fn pack_json(case: &Case, result: &CaseResult, qs: &[Quantity]) -> serde_json::Value {
    let (coord, unit) = coordinate_name(&case.spec.probe);
    let spectrum: Vec<serde_json::Value> =
        build::spectrum(&case.spec.light, &build::Overrides::default())
            .iter()
            .map(|(l, w)| json!({"wavelength_nm": l * 1e9, "weight": w}))
            .collect();
    let quantities: Vec<serde_json::Value> = qs
        .iter()
        .map(|q| {
            let refs: Vec<serde_json::Value> = q
                .metrics
                .iter()
                .map(|&mi| {
                    let m = &result.metrics[mi];
                    let tol: serde_json::Map<String, serde_json::Value> = m
                        .tolerances
                        .iter()
                        .map(|(l, t)| (l.to_string(), json!(t)))
                        .collect();
                    json!({
                        "label": m.name,
                        "model": m.model,
                        "tolerances": tol,
                        "tolerance_note": m.tolerance_note,
                        "deviation": if q.observable == Observable::Retardance
                            || q.observable == Observable::Visibility
                            || q.observable == Observable::FringeSpacing {
                            "|value − closed form|/|closed form| at each point"
                        } else {
                            "|value − closed form| / max over the probe of |closed form| (floor 1e-15)"
                        },
                    })
                })
                .collect();
            json!({
                "name": q.name,
                "observable": q.observable.name(),
                "unit": q.observable.unit(),
                "definition": q.observable.definition(),
                "points": q.coordinates.len(),
                "references": refs,
            })
        })
        .collect();
    json!({
        "case": result.name,
        "description": result.description,
        "formula": result.formula,
        "conventions": conventions(),
        "probe": {
            "kind": serde_json::to_value(&case.spec.probe).ok()
                .and_then(|v| v.as_object().and_then(|o| o.keys().next().cloned())),
            "coordinate": coord,
            "coordinate_unit": unit,
            "points": build::probe_points(&case.spec.probe).len(),
            "file": "probes.csv",
        },
        "spectrum": spectrum,
        "spectrum_note": "a wavelength sweep replaces the spectrum by the swept wavelength at each point",
        "fidelity_rungs": result.levels.iter().map(|l| l.to_string()).collect::<Vec<_>>(),
        "quantities": quantities,
        "values_file": {
            "header": values::HEADER,
            "rows": "one per quantity and probe point, quantities in the order above, points in the order of probes.csv; coordinates as in probes.csv (relative precision 1e-9); values finite, in the observable's unit; lines starting with # are comments",
            "example": "values_exact.csv",
        },
        "expected_file": "expected.csv",
        "grade": format!("fringe grade {} --values FILE.csv", result.name),
    })
}

/// Export the packs of `cases` (library names or paths; none: the whole library) into `out`.
/// Every case is loaded, checked and run before anything is written. Returns one line per
/// case written.
pub fn export(cases: &[String], cases_dir: &Path, out: &Path) -> Result<Vec<String>, InputError> {
    let opts = CheckOptions {
        cases: cases.to_vec(),
        cases_dir: cases_dir.to_path_buf(),
        golden_dir: None,
        out: out.to_path_buf(),
        format: Format::Table,
        bless: false,
    };
    let files = check::resolve(&opts)?;
    let loaded: Vec<Case> = files
        .iter()
        .map(|f| load::load(f))
        .collect::<Result<_, _>>()?;
    for c in &loaded {
        run::preflight(c)?;
    }
    let mut packs = Vec::new();
    for c in &loaded {
        let r = run::run_with(c, false)?;
        let qs = quantities(&r, &c.spec.probe);
        let exact: Vec<Vec<f64>> = qs
            .iter()
            .map(|q| {
                let m = &r.metrics[q.metrics[0]];
                m.traced
                    .get(&Fidelity::Vector)
                    .cloned()
                    .unwrap_or_else(|| m.analytic.clone())
            })
            .collect();
        let case_bytes = std::fs::read(&c.file)
            .map_err(|e| InputError(format!("{}: cannot read: {e}", c.file.display())))?;
        let pack = serde_json::to_string_pretty(&pack_json(c, &r, &qs))
            .map_err(|e| InputError(e.to_string()))?;
        packs.push((
            r.name.clone(),
            vec![
                ("case.json", case_bytes),
                ("pack.json", pack.into_bytes()),
                ("probes.csv", probes_csv(c).into_bytes()),
                ("expected.csv", expected_csv(&r, &qs).into_bytes()),
                ("values_exact.csv", values::to_csv(&qs, &exact).into_bytes()),
            ],
        ));
    }
    let mut lines = Vec::new();
    for (name, files) in packs {
        let dir = out.join(&name);
        for (f, bytes) in files {
            let p = dir.join(f);
            crate::io::write_atomic(&p, &bytes)
                .map_err(|e| InputError(format!("{}: cannot write: {e}", p.display())))?;
        }
        lines.push(format!("{name}: {}", dir.display()));
    }
    Ok(lines)
}
