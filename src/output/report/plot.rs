//! Plots (plotters, bitmap backend, encoded to PNG in memory): a case's profile — traced and
//! closed-form curves per fidelity level with a log-scale deviation panel — its convergence
//! against the number of reflected orders, Newton's colour strip, the colour error against
//! the number of spectral samples, and the stability sweep's phase error against optical path.
//!
//! Text is drawn with DejaVu Sans shipped in `data/fonts/` (compiled in, so plots look the same
//! on machines without system fonts; licence in `data/fonts/LICENSE`).

use super::image::encode_rgb_bytes;
use crate::accumulate::fidelity::Fidelity;
use crate::harness::case::run::CaseResult;
use crate::harness::case::spec::{Probe, SweepParameter};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::sync::Once;

/// DejaVu Sans (Bitstream Vera licence, see `data/fonts/LICENSE`).
static DEJAVU_SANS: &[u8] = include_bytes!("../../../data/fonts/DejaVuSans.ttf");

/// Registers the shipped font as plotters' "sans-serif" (once per process).
pub(crate) fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is compiled in and parsed by a test: failure here is a build defect.
        if plotters::style::register_font("sans-serif", FontStyle::Normal, DEJAVU_SANS).is_err() {
            panic!("data/fonts/DejaVuSans.ttf is not a valid font");
        }
    });
}

/// Width of every case plot (pixels).
pub(crate) const WIDTH: u32 = 1000;
/// Height of the value panel and of the deviation panel of one metric (pixels).
pub(crate) const VALUE_PANEL: u32 = 320;
pub(crate) const DEVIATION_PANEL: u32 = 220;
/// Size of `convergence.png`.
pub const CONVERGENCE_SIZE: (u32, u32) = (800, 480);

/// Width of the legend column at the right of a profile plot (pixels).
const LEGEND_WIDTH: u32 = 150;

/// Tick labels for a linear axis over [y0, y1]: fixed decimals enough to tell the ticks of a
/// nearly flat curve apart, or scientific notation for values far from 1 or with more than six
/// decimals (so a label never outgrows the label area).
fn tick_formatter(y0: f64, y1: f64) -> impl Fn(f64) -> String {
    let span = (y1 - y0).abs().max(f64::MIN_POSITIVE);
    let magnitude = y0.abs().max(y1.abs());
    let decimals = (-span.log10()).ceil().max(0.0) as usize + 1;
    let scientific = !(1e-3..1e5).contains(&magnitude) || decimals > 6;
    // Significant digits that still separate ticks a tenth of the span apart.
    let digits = ((magnitude / span).log10().ceil().max(0.0) as usize + 1).min(10);
    move |v: f64| {
        if v == 0.0 {
            "0".to_string()
        } else if scientific {
            format!("{v:.digits$e}")
        } else {
            format!("{v:.decimals$}")
        }
    }
}

/// Draws a legend (label, colour, line width) as a column in `area`, beside the plot.
fn legend_column(
    area: &DrawingArea<BitMapBackend<'_>, Shift>,
    entries: &[(String, RGBColor, u32)],
) -> Result<(), String> {
    for (k, (label, colour, width)) in entries.iter().enumerate() {
        let y = 40 + 20 * k as i32;
        area.draw(&PathElement::new(
            vec![(6, y), (30, y)],
            colour.stroke_width(*width),
        ))
        .map_err(err)?;
        area.draw(&Text::new(
            label.clone(),
            (36, y - 7),
            ("sans-serif", 13).into_font().color(&BLACK),
        ))
        .map_err(err)?;
    }
    Ok(())
}

/// Floor of the log deviation axis: exact zeros are drawn here.
const DEV_FLOOR: f64 = 1e-17;

pub(crate) fn err<E: std::fmt::Display>(e: E) -> String {
    format!("plot: {e}")
}

/// Draws with `draw` on a white `size` bitmap and returns it as PNG bytes.
pub(crate) fn render_png(
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend<'_>, Shift>) -> Result<(), String>,
) -> Result<Vec<u8>, String> {
    register_font();
    let mut buf = vec![255u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        draw(&root)?;
        root.present().map_err(err)?;
    }
    // The backend's buffer is the PNG's row-major RGB bytes: encoded as it is. (`Fastest`,
    // rows filtered by `Up` only, saves little of the encoding and doubles the files.)
    encode_rgb_bytes(
        size.0 as usize,
        size.1 as usize,
        &buf,
        Some(png::Compression::Fast),
    )
}

/// Line colour of a fidelity level (the same in every plot).
pub(crate) fn level_colour(level: Fidelity) -> RGBColor {
    match level {
        Fidelity::Incoherent => RGBColor(140, 80, 170),
        Fidelity::Scalar => RGBColor(230, 140, 20),
        Fidelity::ScalarJump => RGBColor(40, 160, 60),
        Fidelity::PaperRules => RGBColor(30, 90, 220),
        Fidelity::Vector => RGBColor(210, 30, 40),
    }
}

/// Line width of a level: wider for the cheaper rungs, so coinciding curves stay visible
/// (vector, the thinnest, is drawn last on top).
fn level_width(level: Fidelity) -> u32 {
    match level {
        Fidelity::Incoherent | Fidelity::Scalar => 2,
        Fidelity::ScalarJump => 5,
        Fidelity::PaperRules => 3,
        Fidelity::Vector => 1,
    }
}

/// The x-axis label of a case's probe coordinate.
pub(crate) fn x_label(probe: &Probe) -> String {
    match probe {
        Probe::Line { .. } => "position along the probe line (m)".into(),
        Probe::Sweep { parameter, .. } => match parameter {
            SweepParameter::IncidenceAngleDeg { .. } => "angle of incidence (degrees)".into(),
            SweepParameter::WavelengthNm {} => "vacuum wavelength (nm)".into(),
            SweepParameter::ThicknessNm { surface } => format!("thickness of {surface} (nm)"),
        },
        Probe::Single { .. } => "probe point".into(),
        Probe::Grid { .. } => "pixel index (row-major)".into(),
    }
}

/// Indices of the metrics a profile plot shows: those with more than one probe point.
fn plotted_metrics(r: &CaseResult) -> Vec<usize> {
    (0..r.metrics.len())
        .filter(|&i| r.metrics[i].coordinates.len() > 1 && !r.metrics[i].traced.is_empty())
        .collect()
}

/// Size of `profile.png` for a case, or `None` when it has no profile to plot (only
/// single-point metrics such as a fringe spacing).
pub fn profile_size(r: &CaseResult) -> Option<(u32, u32)> {
    let n = plotted_metrics(r).len() as u32;
    (n > 0).then_some((WIDTH, 50 + n * (VALUE_PANEL + DEVIATION_PANEL)))
}

fn finite_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    if hi - lo <= 1e-300 + 1e-12 * hi.abs().max(lo.abs()) {
        let pad = if hi == 0.0 { 1.0 } else { 0.05 * hi.abs() };
        return (lo - pad, hi + pad);
    }
    let pad = 0.05 * (hi - lo);
    (lo - pad, hi + pad)
}

/// `profile.png`: for each metric with a profile, the closed form (wide grey) and the traced
/// values of every level, and below it the deviation of every level on a log scale with the
/// level's tolerance as a dashed line. `None` when the case has nothing to plot.
pub(crate) fn profile_png(r: &CaseResult, x_label: &str) -> Result<Option<Vec<u8>>, String> {
    let Some(size) = profile_size(r) else {
        return Ok(None);
    };
    let metrics = plotted_metrics(r);
    render_png(size, |root| {
        let (title, body) = root.split_vertically(50);
        title
            .titled(
                &format!("{} — traced vs closed form, per fidelity level", r.name),
                ("sans-serif", 24),
            )
            .map_err(err)?;
        let panels = body.split_evenly((metrics.len(), 1));
        for (panel, &mi) in panels.iter().zip(&metrics) {
            let m = &r.metrics[mi];
            let (top, bottom) = panel.split_vertically(VALUE_PANEL);
            // The legend has a column of its own at the right: it never covers a curve.
            let (top, legend_area) = top.split_horizontally(WIDTH - LEGEND_WIDTH);
            let (bottom, _) = bottom.split_horizontally(WIDTH - LEGEND_WIDTH);
            let (x0, x1) = finite_range(m.coordinates.iter().copied());
            let (y0, y1) = finite_range(
                m.analytic
                    .iter()
                    .chain(m.traced.values().flatten())
                    .copied(),
            );
            // Values far from 1 (p light at Brewster's angle reflects ~1e-19) are drawn in
            // units of a power of ten named on the axis: plotters finds no ticks on such
            // ranges, and the labels stay short.
            let magnitude = y0.abs().max(y1.abs());
            let exponent = if magnitude > 0.0 && !(1e-3..1e5).contains(&magnitude) {
                magnitude.log10().floor() as i32
            } else {
                0
            };
            let scale = 10f64.powi(exponent);
            let (y0, y1) = (y0 / scale, y1 / scale);
            let y_desc = if exponent == 0 {
                m.quantity(r.observable).to_string()
            } else {
                format!("{} × 1e{exponent}", m.quantity(r.observable))
            };
            let mut chart = ChartBuilder::on(&top)
                .caption(
                    format!("{} ({:?})", m.name, m.kind).to_lowercase(),
                    ("sans-serif", 18),
                )
                .margin(8)
                .x_label_area_size(30)
                .y_label_area_size(100)
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(err)?;
            let tick = tick_formatter(y0, y1);
            chart
                .configure_mesh()
                .y_desc(y_desc)
                .y_label_formatter(&|v| tick(*v))
                .label_style(("sans-serif", 13))
                .light_line_style(WHITE.mix(0.0))
                .draw()
                .map_err(err)?;
            let pts = |v: &[f64]| -> Vec<(f64, f64)> {
                m.coordinates
                    .iter()
                    .zip(v)
                    .filter(|(x, y)| x.is_finite() && y.is_finite())
                    .map(|(x, y)| (*x, *y / scale))
                    .collect()
            };
            let grey = RGBColor(190, 190, 190);
            chart
                .draw_series(LineSeries::new(pts(&m.analytic), grey.stroke_width(8)))
                .map_err(err)?;
            let mut legend = vec![("closed form".to_string(), grey, 8)];
            for (level, values) in &m.traced {
                let c = level_colour(*level);
                let w = level_width(*level);
                chart
                    .draw_series(LineSeries::new(pts(values), c.stroke_width(w)))
                    .map_err(err)?;
                legend.push((level.name().to_string(), c, w.max(2)));
            }
            legend_column(&legend_area, &legend)?;

            // Deviation panel (log scale).
            let devs: Vec<(Fidelity, Vec<f64>)> = m
                .traced
                .keys()
                .filter_map(|l| m.deviations(*l).map(|d| (*l, d)))
                .collect();
            let dmax = devs
                .iter()
                .flat_map(|(_, d)| d.iter().copied())
                .chain(m.tolerances.values().copied())
                .filter(|v| v.is_finite())
                .fold(DEV_FLOOR, f64::max);
            let dmin = devs
                .iter()
                .flat_map(|(_, d)| d.iter().copied())
                .filter(|v| v.is_finite() && *v > 0.0)
                .fold(dmax, f64::min)
                .max(DEV_FLOOR);
            let mut dchart = ChartBuilder::on(&bottom)
                .margin(8)
                .x_label_area_size(40)
                .y_label_area_size(80)
                .build_cartesian_2d(
                    x0..x1,
                    ((dmin / 3.0).max(DEV_FLOOR)..dmax * 3.0).log_scale(),
                )
                .map_err(err)?;
            dchart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc("|deviation| (relative)")
                .y_label_formatter(&|v| format!("{v:.0e}"))
                .label_style(("sans-serif", 13))
                .light_line_style(WHITE.mix(0.0))
                .draw()
                .map_err(err)?;
            for (level, d) in &devs {
                let c = level_colour(*level);
                let floored: Vec<(f64, f64)> = m
                    .coordinates
                    .iter()
                    .zip(d)
                    .filter(|(x, y)| x.is_finite() && y.is_finite())
                    .map(|(x, y)| (*x, y.max(DEV_FLOOR)))
                    .collect();
                dchart
                    .draw_series(LineSeries::new(
                        floored,
                        c.stroke_width(level_width(*level).min(3)),
                    ))
                    .map_err(err)?;
                if let Some(t) = m.tolerances.get(level) {
                    dchart
                        .draw_series(DashedLineSeries::new(
                            vec![(x0, *t), (x1, *t)],
                            8,
                            6,
                            c.stroke_width(1),
                        ))
                        .map_err(err)?;
                }
            }
        }
        Ok(())
    })
    .map(Some)
}

/// `convergence.png`: the traced error of the Airy sum and its geometric-tail bound against the
/// number of reflected orders (log scale). `None` without convergence rows.
pub(crate) fn convergence_png(r: &CaseResult) -> Result<Option<Vec<u8>>, String> {
    if r.convergence.is_empty() {
        return Ok(None);
    }
    let rows = &r.convergence;
    render_png(CONVERGENCE_SIZE, |root| {
        let xmax = rows.iter().map(|c| c.orders).max().unwrap_or(1) as f64;
        let ymax = rows
            .iter()
            .flat_map(|c| [c.max_abs_dev, c.bound])
            .filter(|v| v.is_finite())
            .fold(DEV_FLOOR, f64::max);
        let ymin = rows
            .iter()
            .flat_map(|c| [c.max_abs_dev, c.bound])
            .filter(|v| v.is_finite() && *v > 0.0)
            .fold(ymax, f64::min)
            .max(DEV_FLOOR);
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!("{} — error vs reflected orders", r.name),
                ("sans-serif", 20),
            )
            .margin(10)
            .x_label_area_size(45)
            .y_label_area_size(80)
            .build_cartesian_2d(
                (1.0..xmax * 1.2).log_scale(),
                ((ymin / 3.0).max(DEV_FLOOR)..ymax * 3.0).log_scale(),
            )
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("reflected orders N (internal reflections 2N − 1)")
            .y_desc("max |R_traced − R_Airy|")
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 13))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(err)?;
        let traced: Vec<(f64, f64)> = rows
            .iter()
            .map(|c| (c.orders as f64, c.max_abs_dev.max(DEV_FLOOR)))
            .collect();
        let bound: Vec<(f64, f64)> = rows
            .iter()
            .filter(|c| c.bound.is_finite())
            .map(|c| (c.orders as f64, c.bound.max(DEV_FLOOR)))
            .collect();
        let red = level_colour(Fidelity::Vector);
        chart
            .draw_series(LineSeries::new(traced.clone(), red.stroke_width(2)))
            .map_err(err)?
            .label("traced (vector) error")
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], red.stroke_width(2)));
        chart
            .draw_series(traced.iter().map(|p| Circle::new(*p, 4, red.filled())))
            .map_err(err)?;
        chart
            .draw_series(DashedLineSeries::new(bound, 8, 5, BLACK.stroke_width(2)))
            .map_err(err)?
            .label("geometric tail bound")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2)));
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
    .map(Some)
}

/// Newton's colour strip with a thickness axis: one band per (label, sRGB colours), the
/// colours evenly spaced from `t0_nm` to `t1_nm`.
pub(crate) fn newton_strip_png(
    bands: &[(String, Vec<[u8; 3]>)],
    t0_nm: f64,
    t1_nm: f64,
) -> Result<Vec<u8>, String> {
    let size = (1200, 90 + 70 * bands.len() as u32);
    render_png(size, |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Newton's interference colours: soap film n = 1.33 in air, normal incidence, reflected light",
                ("sans-serif", 18),
            )
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(150)
            .build_cartesian_2d(t0_nm..t1_nm, 0.0..bands.len() as f64)
            .map_err(err)?;
        let names: Vec<String> = bands.iter().map(|b| b.0.clone()).collect();
        let n = bands.len();
        chart
            .configure_mesh()
            .disable_y_mesh()
            .disable_x_mesh()
            .x_desc("film thickness (nm)")
            .y_labels(n * 2 + 1)
            .y_label_formatter(&|y| {
                let k = (y - 0.5).round();
                if (y - 0.5 - k).abs() < 1e-6 && k >= 0.0 && (k as usize) < n {
                    names[n - 1 - k as usize].clone()
                } else {
                    String::new()
                }
            })
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(err)?;
        for (b, (_, colours)) in bands.iter().enumerate() {
            let m = colours.len().max(1);
            let dt = (t1_nm - t0_nm) / m as f64;
            let y0 = (n - 1 - b) as f64;
            chart
                .draw_series(colours.iter().enumerate().map(|(i, c)| {
                    let x = t0_nm + i as f64 * dt;
                    Rectangle::new(
                        [(x, y0 + 0.05), (x + dt, y0 + 0.95)],
                        RGBColor(c[0], c[1], c[2]).filled(),
                    )
                }))
                .map_err(err)?;
        }
        Ok(())
    })
}

/// Colour error (CIEDE2000) against the number of spectral samples, one line per series
/// (label, [(samples, ΔE00)]), log–log.
pub(crate) fn colour_error_png(series: &[(String, Vec<(usize, f64)>)]) -> Result<Vec<u8>, String> {
    render_png((800, 480), |root| {
        let xmax = series
            .iter()
            .flat_map(|s| s.1.iter().map(|p| p.0))
            .max()
            .unwrap_or(2) as f64;
        let vals = || series.iter().flat_map(|s| s.1.iter().map(|p| p.1));
        let ymax = vals().filter(|v| v.is_finite()).fold(1e-6, f64::max);
        let ymin = vals()
            .filter(|v| v.is_finite() && *v > 0.0)
            .fold(ymax, f64::min)
            .max(1e-6);
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Colour error vs spectral samples (reference: 1 nm, 360–830 nm)",
                ("sans-serif", 18),
            )
            .margin(10)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(
                (3.0..xmax * 1.3).log_scale(),
                ((ymin / 2.0)..ymax * 2.0).log_scale(),
            )
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("wavelength samples (uniform, 380–780 nm)")
            .y_desc("ΔE00")
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .label_style(("sans-serif", 13))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(err)?;
        let palette = [
            RGBColor(210, 30, 40),
            RGBColor(30, 90, 220),
            RGBColor(40, 160, 60),
            RGBColor(230, 140, 20),
            RGBColor(120, 60, 170),
            RGBColor(90, 90, 90),
        ];
        for (k, (label, pts)) in series.iter().enumerate() {
            let c = palette[k % palette.len()];
            let p: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| p.1.is_finite() && p.1 > 0.0)
                .map(|p| (p.0 as f64, p.1))
                .collect();
            chart
                .draw_series(LineSeries::new(p.clone(), c.stroke_width(2)))
                .map_err(err)?
                .label(label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                });
            chart
                .draw_series(p.into_iter().map(move |q| Circle::new(q, 4, c.filled())))
                .map_err(err)?;
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

/// Size of `stability_paths.png`.
pub(crate) const STABILITY_PATHS_SIZE: (u32, u32) = (900, 560);

/// `stability_paths.png`: the two-beam phase error against optical path, log–log, for phases
/// formed from absolute binary32 paths, from absolute f64 paths, and fringe's traced paths
/// differenced in metres; the bound (dashed) and π (dotted, beyond it a fringe can be
/// anywhere). Both axes are drawn in decades (log10 on linear axes, labelled 1e-n, so every
/// decade gets a tick); exact zeros are drawn at the floor of the axis.
pub(crate) fn stability_paths_png(
    points: &[crate::harness::stability::PathPoint],
) -> Result<Vec<u8>, String> {
    use std::f64::consts::PI;
    let bound = crate::harness::stability::PATH_PHASE_TOLERANCE_RAD;
    render_png(STABILITY_PATHS_SIZE, |root| {
        let errs = || {
            points
                .iter()
                .flat_map(|p| [p.fringe_rad, p.f64_absolute_rad, p.binary32_absolute_rad])
        };
        let ymax = errs().filter(|v| v.is_finite()).fold(PI, f64::max);
        let ymin = errs()
            .filter(|v| v.is_finite() && *v > 0.0)
            .fold(ymax, f64::min)
            .max(DEV_FLOOR * 1e-3);
        // Decades of the axes.
        let (y0, y1) = (ymin.log10().floor() - 0.5, ymax.log10().ceil() + 0.3);
        let (x0, x1) = points
            .iter()
            .map(|p| p.path_m)
            .filter(|x| x.is_finite() && *x > 0.0)
            .fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
        let (x0, x1) = if x0 < x1 { (x0, x1) } else { (1e-9, 10.0) };
        let (lx0, lx1) = (x0.log10() - 0.3, x1.log10() + 0.3);
        let mut chart = ChartBuilder::on(root)
            .caption(
                format!(
                    "Two-beam phase error vs optical path (λ = {:.0} nm, worst of {} path differences)",
                    crate::harness::stability::WAVELENGTH_M * 1e9,
                    crate::harness::stability::PATH_OFFSETS
                ),
                ("sans-serif", 18),
            )
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(lx0..lx1, y0..y1)
            .map_err(err)?;
        let decade = |v: &f64| {
            if (v - v.round()).abs() < 1e-6 {
                format!("1e{}", v.round() as i32)
            } else {
                String::new()
            }
        };
        chart
            .configure_mesh()
            .x_desc("optical path s of the nearer beam (m)")
            .y_desc("|phase error| (rad)")
            .x_labels(((lx1 - lx0).ceil() as usize + 1) * 2)
            .y_labels(((y1 - y0).ceil() as usize + 1) * 2)
            .x_label_formatter(&decade)
            .y_label_formatter(&decade)
            .label_style(("sans-serif", 13))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(err)?;
        let series = [
            (
                "binary32 paths, absolute phases",
                RGBColor(210, 30, 40),
                2,
                points
                    .iter()
                    .map(|p| (p.path_m, p.binary32_absolute_rad))
                    .collect::<Vec<_>>(),
            ),
            (
                "f64 paths, absolute phases",
                RGBColor(30, 90, 220),
                2,
                points
                    .iter()
                    .map(|p| (p.path_m, p.f64_absolute_rad))
                    .collect(),
            ),
            (
                "fringe: traced f64 paths, differenced in metres",
                RGBColor(40, 160, 60),
                3,
                points.iter().map(|p| (p.path_m, p.fringe_rad)).collect(),
            ),
        ];
        for (label, c, w, pts) in series {
            let pts: Vec<(f64, f64)> = pts
                .into_iter()
                .filter(|(x, y)| x.is_finite() && *x > 0.0 && y.is_finite())
                .map(|(x, y)| (x.log10(), y.max(ymin).log10()))
                .collect();
            chart
                .draw_series(LineSeries::new(pts.clone(), c.stroke_width(w)))
                .map_err(err)?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(w))
                });
            chart
                .draw_series(pts.into_iter().map(move |q| Circle::new(q, 3, c.filled())))
                .map_err(err)?;
        }
        let lb = bound.log10();
        chart
            .draw_series(DashedLineSeries::new(
                vec![(lx0, lb), (lx1, lb)],
                8,
                6,
                BLACK.stroke_width(1),
            ))
            .map_err(err)?
            .label(format!("bound {bound:.0e} rad (issue #6)"))
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(1)));
        let grey = RGBColor(120, 120, 120);
        let lpi = PI.log10();
        chart
            .draw_series(DashedLineSeries::new(
                vec![(lx0, lpi), (lx1, lpi)],
                2,
                4,
                grey.stroke_width(1),
            ))
            .map_err(err)?
            .label("π (beyond it a fringe can be anywhere)")
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], grey.stroke_width(1))
            });
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()
            .map_err(err)?;
        Ok(())
    })
}
