//! Plots of the trade-off reports: the Pareto plot of one case (cost count vs error, log–log) and the
//! renderer-mode study (error vs rays per pixel per estimator and pixel size).

#![warn(missing_docs)]

use super::plot::{err, level_colour, render_png as png};
use crate::accumulate::fidelity::Fidelity;
use crate::harness::forward_study::StudyRow;
use crate::harness::tradeoff::{Measurement, TradeoffRow, pareto};
use plotters::prelude::*;
use std::path::Path;

/// Deviations below this are drawn on the floor of the log axis.
const FLOOR: f64 = 1e-17;

fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if hi == 0.0 {
        (FLOOR, 1.0)
    } else {
        (lo.max(FLOOR) / 3.0, hi * 3.0)
    }
}

/// Cost (path events traced, the deterministic cost count of [`crate::harness::tradeoff`]) against the
/// max deviation from the primary reference of every traced setting of one case; the Pareto
/// front joined, the tolerance dashed. Rungs sharing a cost count are drawn side by side (a
/// small horizontal offset per rung, cheapest rung leftmost). Settings that could not be traced
/// are not drawn (they are rows of `tradeoff.csv` with their reason).
pub fn pareto_png(case: &str, rows: &[TradeoffRow]) -> Result<Vec<u8>, String> {
    // Rungs at one cost count are spread over ±8% of it so that they do not hide each other.
    let x_of = |r: &TradeoffRow, m: &Measurement| {
        m.path_events.max(1.0) * (1.0 + 0.04 * (r.fidelity as usize as f64 - 2.0))
    };
    let traced: Vec<(&TradeoffRow, &Measurement)> = rows
        .iter()
        .filter_map(|r| r.measurement().map(|m| (r, m)))
        .collect();
    // The legend sits lower left: a Pareto front runs from cheap and inaccurate (upper left)
    // to costly and accurate (lower right), so that corner is usually empty.
    png((900, 560), |root| {
        let (x0, x1) = log_range(traced.iter().map(|(r, m)| x_of(r, m)));
        let (y0, y1) = log_range(
            traced
                .iter()
                .map(|(_, m)| m.max_abs_dev.max(FLOOR))
                .chain(rows.iter().map(|r| r.tolerance)),
        );
        // Headroom: markers at the largest error are not cut by the frame.
        let y1 = y1 * 4.0;
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!("{case}: cost vs error of every setting"),
                ("sans-serif", 20),
            )
            .margin(10)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("path events traced (cost count; rungs offset)")
            .y_desc("max |dev| vs reference (relative)")
            .x_label_formatter(&|v| format!("{v:.0e}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(err)?;
        for level in Fidelity::ALL {
            let c = level_colour(level);
            let pts: Vec<(f64, f64)> = traced
                .iter()
                .filter(|(r, _)| r.fidelity == level)
                .map(|(r, m)| (x_of(r, m), m.max_abs_dev.max(FLOOR)))
                .collect();
            chart
                .draw_series(pts.iter().map(|p| Circle::new(*p, 5, c.filled())))
                .map_err(err)?
                .label(level.name())
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, c.filled()));
        }
        let flags = pareto(rows);
        let mut front: Vec<(f64, f64)> = rows
            .iter()
            .zip(&flags)
            .filter(|(_, f)| **f)
            .filter_map(|(r, _)| {
                r.measurement()
                    .map(|m| (x_of(r, m), m.max_abs_dev.max(FLOOR)))
            })
            .collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart
            .draw_series(LineSeries::new(front, BLACK.stroke_width(1)))
            .map_err(err)?
            .label("Pareto front")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(1)));
        if let Some(t) = rows.first().map(|r| r.tolerance).filter(|t| *t > 0.0) {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(x0, t), (x1, t)],
                    8,
                    5,
                    RED.stroke_width(1),
                ))
                .map_err(err)?
                .label("tolerance")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED.stroke_width(1)));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(err)?;
        Ok(())
    })
}

/// Renderer mode: relative RMS error against mean rays per pixel, one panel per scene, one
/// colour per estimator, one marker size per pixel count.
pub fn forward_png(rows: &[StudyRow]) -> Result<Vec<u8>, String> {
    let mut scenes: Vec<&str> = Vec::new();
    for r in rows {
        if !scenes.contains(&r.scene) {
            scenes.push(r.scene);
        }
    }
    let mut estimators: Vec<String> = rows.iter().map(|r| r.estimator.clone()).collect();
    estimators.sort();
    estimators.dedup();
    let mut pixel_counts: Vec<usize> = rows.iter().map(|r| r.pixels).collect();
    pixel_counts.sort_unstable();
    pixel_counts.dedup();
    let palette = [
        RGBColor(200, 40, 40),
        RGBColor(230, 150, 20),
        RGBColor(30, 120, 200),
        RGBColor(40, 160, 80),
        RGBColor(120, 60, 160),
    ];
    png((1000, 360 * scenes.len().max(1) as u32), |root| {
        let panels = root.split_evenly((scenes.len().max(1), 1));
        for (panel, scene) in panels.iter().zip(&scenes) {
            let sel: Vec<&StudyRow> = rows.iter().filter(|r| r.scene == *scene).collect();
            let (x0, x1) = log_range(sel.iter().map(|r| r.mean_rays_per_pixel));
            let (y0, y1) = log_range(sel.iter().map(|r| r.rel_rms_error));
            let mut chart = ChartBuilder::on(panel)
                .caption(
                    format!("{scene}: error vs rays per pixel (marker size: pixels per side)"),
                    ("sans-serif", 17),
                )
                .margin(8)
                .x_label_area_size(40)
                .y_label_area_size(70)
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(err)?;
            chart
                .configure_mesh()
                .x_desc("mean rays per pixel per channel")
                .y_desc("relative RMS error")
                .x_label_formatter(&|v| format!("{v:.0}"))
                .y_label_formatter(&|v| format!("{v:.0e}"))
                .label_style(("sans-serif", 12))
                .draw()
                .map_err(err)?;
            for (k, est) in estimators.iter().enumerate() {
                let c = palette[k % palette.len()];
                for (pi, p) in pixel_counts.iter().enumerate() {
                    let mut pts: Vec<(f64, f64)> = sel
                        .iter()
                        .filter(|r| &r.estimator == est && r.pixels == *p)
                        .map(|r| (r.mean_rays_per_pixel, r.rel_rms_error))
                        .collect();
                    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                    chart
                        .draw_series(LineSeries::new(pts.clone(), c.stroke_width(1)))
                        .map_err(err)?;
                    let s = chart
                        .draw_series(
                            pts.iter()
                                .map(|q| Circle::new(*q, 3 + 2 * pi as u32, c.filled())),
                        )
                        .map_err(err)?;
                    if pi == 0 {
                        s.label(est.as_str())
                            .legend(move |(x, y)| Circle::new((x + 10, y), 4, c.filled()));
                    }
                }
            }
            chart
                .configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 12))
                .draw()
                .map_err(err)?;
        }
        Ok(())
    })
}

/// The `fringe tradeoff` and `fringe forward` results for the report page, from the files those
/// commands wrote under `out` (`tradeoff/summary.txt`, `tradeoff/<case>_pareto.png`,
/// `forward/forward.png`); `None` when neither command has run into `out`.
pub(crate) fn report_section(out: &Path) -> Option<String> {
    use super::html::{base64, escape};
    use std::fmt::Write as _;
    let img = |path: &Path, alt: &str| -> Option<String> {
        let bytes = std::fs::read(path).ok()?;
        Some(format!(
            "<img class=\"plot\" alt=\"{}\" src=\"data:image/png;base64,{}\">",
            escape(alt),
            base64(&bytes)
        ))
    };
    let mut h = String::new();
    if let Ok(text) = std::fs::read_to_string(out.join("tradeoff").join("summary.txt")) {
        h.push_str("<h2 id=\"tradeoff\">Cost and accuracy of every setting (<code>fringe tradeoff</code>)</h2>\n");
        h.push_str(
            "<p>Every fidelity level × internal-reflection budget × spectral sample count of a \
             case against its primary reference. The cheapest setting within the case's \
             tolerance is ranked by the number of path events traced (deterministic), then by \
             the simpler level; wall times (min, median, max of repeated runs) are information \
             only. Settings that cannot be traced are rows of \
             <a href=\"tradeoff/tradeoff.csv\">tradeoff.csv</a> with their reason.</p>\n<ul>\n",
        );
        for line in text.lines().filter(|l| !l.trim().is_empty()) {
            let _ = writeln!(h, "<li>{}</li>", escape(line));
        }
        h.push_str("</ul>\n");
        let mut plots: Vec<_> = std::fs::read_dir(out.join("tradeoff"))
            .map(|d| {
                d.filter_map(|e| e.ok().map(|e| e.path()))
                    .filter(|p| p.to_string_lossy().ends_with("_pareto.png"))
                    .collect()
            })
            .unwrap_or_default();
        plots.sort();
        for p in plots {
            let name = p.file_name().map(|n| n.to_string_lossy().into_owned());
            if let Some(tag) = img(&p, name.as_deref().unwrap_or("Pareto plot")) {
                h.push_str(&tag);
            }
        }
    }
    if let Some(tag) = img(&out.join("forward").join("forward.png"), "forward.png") {
        h.push_str("<h2 id=\"forward\">Renderer mode (<code>fringe forward</code>)</h2>\n");
        h.push_str(
            "<p>Forward ray fans into pixels: each estimator's error against the exact tracer \
             over rays per pixel and pixel size (<a href=\"forward/forward.csv\">forward.csv</a>).</p>\n",
        );
        h.push_str(&tag);
    }
    (!h.is_empty()).then_some(h)
}
