//! The paper's figures (§4: Figs. 3, 5, 6, 7, 8), Newton's colour sequence, and the colour
//! error against the number of spectral samples, written to `<out>/figures/` with a manifest
//! (`figures.json`) that the HTML report reads.
//!
//! Scenes: `figures/young_fig3.json` and `figures/plate_amplitude_division.json` (case format
//! with a `grid` probe; compiled in so the report does not depend on the working directory).
//! The plate scene is rendered once, all rungs of the ladder from the same exact paths, in
//! white light; the Fig. 8 statistics compare 8-bit pictures exactly as the paper describes.

use crate::accumulate::fidelity::Fidelity;
use crate::colour::{
    self, Adaptation, Illuminant, SpectralIntegrator, WavelengthGrid, delta_e_2000, xyz_to_lab,
};
use crate::harness::case::load::{self, Case};
use crate::io::write_atomic;
use crate::output::render::{self, Image, ImageValues, Request, Screen, Shading, Spectrum};
use crate::output::report::image::{self as img, DiffStats, Rgb8Image};
use crate::output::report::plot;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

/// The Young scene of Fig. 3.
pub const YOUNG_SCENE: &str = include_str!("../../figures/young_fig3.json");
/// The amplitude-division scene of Figs. 5–8.
pub const PLATE_SCENE: &str = include_str!("../../figures/plate_amplitude_division.json");

/// The paper's Fig. 8 numbers for its own (unspecified) 900 × 900 scene (§4.2).
pub(crate) const PAPER_FIG8: PaperFig8 = PaperFig8 {
    pixels: 810_000,
    differing: 79_041,
    max_sum: 60,
    max_sum_at: (12, 42),
    max_channel: 31,
    max_channel_at: (10, 49),
};

/// The Fig. 8 statistics as the paper prints them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub(crate) struct PaperFig8 {
    pub pixels: usize,
    pub differing: usize,
    pub max_sum: u32,
    pub max_sum_at: (usize, usize),
    pub max_channel: u8,
    pub max_channel_at: (usize, usize),
}

/// Spectral sample counts of the colour-error study.
pub const ERROR_SAMPLES: [usize; 6] = [4, 8, 16, 31, 81, 401];
/// Uniform grids of the study span the visible range.
pub(crate) const VISIBLE_NM: (f64, f64) = (380.0, 780.0);
/// Newton's sequence: soap film index and thickness range (nm).
pub const NEWTON_N: f64 = 1.33;
pub(crate) const NEWTON_MAX_NM: usize = 1500;

/// Settings of a figure run.
#[derive(Clone, Debug)]
pub struct FigureOptions {
    /// Picture size (columns, rows) of Figs. 3 and 5–8.
    pub size: (usize, usize),
    /// White-light samples (uniform over `VISIBLE_NM`) of Figs. 5–8.
    pub samples: usize,
    pub illuminant: Illuminant,
    /// Picture side of the colour-error renders.
    pub error_size: usize,
    pub progress: bool,
}

impl FigureOptions {
    /// What `fringe check` makes for the whole library (kept fast for CI).
    pub fn check_default() -> Self {
        FigureOptions {
            size: (240, 240),
            samples: 31,
            illuminant: Illuminant::D65,
            error_size: 40,
            progress: false,
        }
    }
}

/// One picture of the figure set.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct FigureEntry {
    pub file: String,
    pub title: String,
    pub caption: String,
}

/// One Fig. 8 comparison: statistics of `left` vs `right` and the stretched difference picture.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Fig8Entry {
    pub left: String,
    pub right: String,
    pub file: String,
    pub stats: DiffStats,
    /// 255 / (largest channel difference): the histogram stretch applied.
    pub stretch_factor: f64,
}

/// One row of the colour-error table: CIEDE2000 against the 1 nm reference.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ColourErrorRow {
    pub samples: usize,
    pub newton_d65_mean: f64,
    pub newton_d65_max: f64,
    pub newton_e_mean: f64,
    pub newton_e_max: f64,
    pub plate_mean: f64,
    pub plate_max: f64,
    /// Wall time of the plate render with this many samples (s).
    pub plate_seconds: f64,
}

/// Everything the report shows about the figures.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Manifest {
    /// How the pictures were made (size, samples, illuminant, exposure), in words.
    pub settings: Vec<String>,
    pub figures: Vec<FigureEntry>,
    pub fig8: Vec<Fig8Entry>,
    pub newton_strip: String,
    pub newton_csv: Vec<String>,
    pub colour_error: Vec<ColourErrorRow>,
    pub colour_error_plot: String,
    pub colour_error_csv: String,
    /// (what, seconds).
    pub timings: Vec<(String, f64)>,
}

fn parse_scene(name: &str, text: &str) -> Result<Case, String> {
    load::parse(Path::new(name), text).map_err(|e| e.to_string())
}

/// The amplitude-division scene (for tests and the CLI).
pub fn plate_case() -> Result<Case, String> {
    parse_scene("figures/plate_amplitude_division.json", PLATE_SCENE)
}

/// The Young scene of Fig. 3.
pub fn young_case() -> Result<Case, String> {
    parse_scene("figures/young_fig3.json", YOUNG_SCENE)
}

/// A uniform white-light grid of `samples` wavelengths over `VISIBLE_NM`.
pub fn visible_grid(samples: usize) -> Result<WavelengthGrid, String> {
    WavelengthGrid::uniform(VISIBLE_NM.0 * 1e-9, VISIBLE_NM.1 * 1e-9, samples)
}

/// The shadings of the plate figures, in order: Fig. 5, Fig. 6 left/right, Fig. 7 right, the
/// vector reference, and the paper's own Fig. 7 left model (one scalar ray per path).
pub(crate) const PLATE_SHADINGS: [Shading; 6] = [
    Shading::Level(Fidelity::Incoherent),
    Shading::Level(Fidelity::Scalar),
    Shading::Level(Fidelity::ScalarJump),
    Shading::Level(Fidelity::PaperRules),
    Shading::Level(Fidelity::Vector),
    Shading::UnpolarizedScalarJump,
];

fn xyz_of(im: &Image) -> &[[f64; 3]] {
    match &im.values {
        ImageValues::Xyz(x) => x,
        ImageValues::Intensity(_) => &[],
    }
}

/// Mean and max CIEDE2000 between two XYZ lists (Lab relative to `white`).
pub(crate) fn delta_e_stats(a: &[[f64; 3]], b: &[[f64; 3]], white: [f64; 3]) -> (f64, f64) {
    let mut sum = 0.0;
    let mut max = 0.0f64;
    for (p, q) in a.iter().zip(b) {
        let d = delta_e_2000(xyz_to_lab(*p, white), xyz_to_lab(*q, white));
        sum += d;
        max = max.max(d);
    }
    (sum / a.len().max(1) as f64, max)
}

/// Newton's sequence in reflection, thickness 0..=`NEWTON_MAX_NM` nm in 1 nm steps.
pub fn newton_thicknesses_m(step_nm: usize) -> Vec<f64> {
    (0..=NEWTON_MAX_NM)
        .step_by(step_nm)
        .map(|t| t as f64 * 1e-9)
        .collect()
}

/// The figure set computed in memory: the files of `<out>/figures/` (name and bytes, in the
/// order [`write`] writes them, `figures.json` last) and the manifest. Nothing is written
/// until [`write`], so `fringe check` computes it beside the case runs and still writes
/// nothing when a case is refused.
pub struct FigureSet {
    pub manifest: Manifest,
    files: Vec<(String, Vec<u8>)>,
}

/// One independent part of the figure set: its files, report entries, settings and timings.
#[derive(Default)]
struct Part {
    files: Vec<(String, Vec<u8>)>,
    figures: Vec<FigureEntry>,
    fig8: Vec<Fig8Entry>,
    settings: Vec<String>,
    timings: Vec<(String, f64)>,
}

/// The figure set: writes `<out>/figures/*` and `figures.json`, returns the manifest.
pub fn generate(out: &Path, opts: &FigureOptions) -> Result<Manifest, String> {
    let set = compute(opts)?;
    write(out, &set)?;
    Ok(set.manifest)
}

/// Write a computed figure set to `<out>/figures/`, each file atomically, `figures.json` last.
pub fn write(out: &Path, set: &FigureSet) -> Result<(), String> {
    let dir = out.join("figures");
    for (name, bytes) in &set.files {
        let p = dir.join(name);
        write_atomic(&p, bytes).map_err(|e| format!("{}: cannot write: {e}", p.display()))?;
    }
    Ok(())
}

/// Compute the figure set (nothing is written). Its four parts are independent and run side
/// by side, the longest (the plate in white light) first; each render is itself parallel over
/// its pixels.
pub fn compute(opts: &FigureOptions) -> Result<FigureSet, String> {
    let (w, h) = opts.size;
    // The two pictures with progress bars are made one after the other (the bars would
    // overwrite each other on one terminal).
    let pictures = || {
        if opts.progress {
            (plate_figures(opts), young_figure(opts))
        } else {
            rayon::join(|| plate_figures(opts), || young_figure(opts))
        }
    };
    let ((plate, young), (error, newton)) = rayon::join(pictures, || {
        rayon::join(
            || {
                let t = Instant::now();
                colour_error_study(opts).map(|rows| (rows, t.elapsed().as_secs_f64()))
            },
            newton_figures,
        )
    });
    let (young, plate, newton, (colour_error, error_seconds)) = (young?, plate?, newton?, error?);
    let mut settings = vec![
        format!(
            "Pictures are {w}×{h} screen points (one exact trace per pixel centre, no area sampling)."
        ),
        "Monochrome pictures are drawn in the hue of their wavelength, normalised so that the \
         brightest pixel (fringe) is full scale."
            .to_string(),
    ];
    let mut files = Vec::new();
    let mut figures = Vec::new();
    let mut timings = Vec::new();
    let mut fig8 = Vec::new();
    for part in [young, plate, newton] {
        files.extend(part.files);
        figures.extend(part.figures);
        fig8.extend(part.fig8);
        settings.extend(part.settings);
        timings.extend(part.timings);
    }
    timings.push(("colour-error study".into(), error_seconds));
    let csv = crate::io::csv_text(
        &[
            "samples",
            "newton_d65_mean_de00",
            "newton_d65_max_de00",
            "newton_e_mean_de00",
            "newton_e_max_de00",
            "plate_mean_de00",
            "plate_max_de00",
            "plate_seconds",
        ],
        colour_error.iter().map(|r| {
            vec![
                r.samples.to_string(),
                format!("{:.6e}", r.newton_d65_mean),
                format!("{:.6e}", r.newton_d65_max),
                format!("{:.6e}", r.newton_e_mean),
                format!("{:.6e}", r.newton_e_max),
                format!("{:.6e}", r.plate_mean),
                format!("{:.6e}", r.plate_max),
                format!("{:.4}", r.plate_seconds),
            ]
        }),
    );
    files.push(("colour_error.csv".into(), csv.into_bytes()));
    let curve = |label: &str, value: fn(&ColourErrorRow) -> f64| {
        (
            label.to_string(),
            colour_error.iter().map(|r| (r.samples, value(r))).collect(),
        )
    };
    let series = vec![
        curve("Newton film, D65, mean", |r| r.newton_d65_mean),
        curve("Newton film, D65, max", |r| r.newton_d65_max),
        curve("plate scene, D65, mean", |r| r.plate_mean),
        curve("plate scene, D65, max", |r| r.plate_max),
    ];
    files.push(("colour_error.png".into(), plot::colour_error_png(&series)?));
    settings.push(format!(
        "Colour error: CIEDE2000 of each sample count against the 1 nm grid (471 samples, \
         360–830 nm); Newton film at 301 thicknesses 0–1500 nm; plate scene (paper_rules) at \
         {0}×{0} points under D65, exposure from the reference picture.",
        opts.error_size
    ));

    let newton_csv = files
        .iter()
        .map(|(name, _)| name)
        .filter(|n| n.starts_with("newton_") && n.ends_with(".csv"))
        .cloned()
        .collect();
    let manifest = Manifest {
        settings,
        figures,
        fig8,
        newton_strip: "newton_strip.png".into(),
        newton_csv,
        colour_error,
        colour_error_plot: "colour_error.png".into(),
        colour_error_csv: "colour_error.csv".into(),
        timings,
    };
    let json = serde_json::to_string_pretty(&manifest).map_err(|e| e.to_string())?;
    files.push(("figures.json".into(), json.into_bytes()));
    Ok(FigureSet { manifest, files })
}

/// Fig. 3: Young's fringes, monochrome.
fn young_figure(opts: &FigureOptions) -> Result<Part, String> {
    let (w, h) = opts.size;
    let mut part = Part::default();
    let young = young_case()?;
    let t = Instant::now();
    let r = render::render(
        &young,
        &Request {
            screen: Screen::from_probe(&young.spec.probe, Some(opts.size))?,
            shadings: vec![Shading::Level(Fidelity::Vector)],
            spectrum: Spectrum::CaseLight,
            progress: opts.progress,
        },
    )?;
    part.timings.push((
        format!("Fig. 3 Young, {w}×{h}, 1 wavelength"),
        t.elapsed().as_secs_f64(),
    ));
    if let ImageValues::Intensity(i) = &r.images[0].values {
        let pic = img::monochrome(w, h, i, r.display_lambda_m, img::peak(i));
        part.files.push(("fig3_young.png".into(), pic.png()?));
        part.figures.push(FigureEntry {
            file: "fig3_young.png".into(),
            title: "Fig. 3 — Young's fringes".into(),
            caption: format!(
                "{} λ = {:.0} nm, vector level; brightest fringe = full scale.",
                young.spec.description,
                r.display_lambda_m * 1e9
            ),
        });
    }
    Ok(part)
}

/// Figs. 5–7: the plate in white light, every rung from the same paths; Fig. 8: their 8-bit
/// differences, as the paper reports them.
fn plate_figures(opts: &FigureOptions) -> Result<Part, String> {
    let (w, h) = opts.size;
    let mut part = Part::default();
    let adaptation = opts.illuminant.default_adaptation();
    let plate = plate_case()?;
    let integrator = SpectralIntegrator::new(&visible_grid(opts.samples)?, opts.illuminant)?;
    let t = Instant::now();
    let r = render::render(
        &plate,
        &Request {
            screen: Screen::from_probe(&plate.spec.probe, Some(opts.size))?,
            shadings: PLATE_SHADINGS.to_vec(),
            spectrum: Spectrum::White(integrator),
            progress: opts.progress,
        },
    )?;
    part.timings.push((
        format!(
            "Figs. 5–7 plate, {w}×{h}, {} wavelengths, 6 shadings",
            opts.samples
        ),
        t.elapsed().as_secs_f64(),
    ));
    let exposure = img::exposure_for_peak_y(r.images.iter().map(xyz_of));
    part.settings.push(format!(
        "Figs. 5–8: white light, {} wavelengths uniform over {:.0}–{:.0} nm, illuminant {} \
         (adaptation {}), CIE 1931 2°; XYZ × {:.4} so that the brightest Y over all six plate \
         pictures is 1 (one exposure for all, so they compare), then the IEC sRGB matrix, clipping \
         and the sRGB curve.",
        opts.samples,
        VISIBLE_NM.0,
        VISIBLE_NM.1,
        opts.illuminant.name(),
        adaptation.name(),
        exposure
    ));
    let pictures: Vec<Rgb8Image> = r
        .images
        .iter()
        .map(|im| img::colour(w, h, xyz_of(im), exposure, opts.illuminant, adaptation))
        .collect();
    let plate_files = [
        (
            "fig5_incoherent.png",
            "Fig. 5 — no coherence (incoherent)",
            "I = I1 + I2: what most renderers compute.",
        ),
        (
            "fig6_scalar.png",
            "Fig. 6 left — path phase only (scalar)",
            "Coherent sum (P10) with δ from the optical path difference only.",
        ),
        (
            "fig6_scalar_jump.png",
            "Fig. 6 right — with the π jump (scalar_jump)",
            "As Fig. 6 left plus π for the reflection from the denser medium: the coloured stripes shift.",
        ),
        (
            "fig7_paper_rules.png",
            "Fig. 7 right — s/p decomposition (paper_rules)",
            "Unpolarized = ∥ + ⊥, |Fresnel| with the paper's π rules P7/P8 (paper eqs. 8, 9).",
        ),
        (
            "fig7_vector.png",
            "Vector reference (complex Fresnel, 3D fields)",
            "The reference rung; identical to paper_rules here (no total internal reflection).",
        ),
        (
            "fig7_unpolarized_scalar_jump.png",
            "Fig. 7 left as the paper describes it (unpolarized_scalar_jump)",
            "One scalar ray per path carrying the total unpolarized power, the π jump for every reflection from the denser side (the ⊥ rule for all rays): overstates the fringe contrast except at normal incidence and at Brewster's angle.",
        ),
    ];
    // The PNGs are encoded in parallel, kept in this order.
    let pngs: Vec<Vec<u8>> = pictures
        .par_iter()
        .map(|pic| pic.png())
        .collect::<Result<_, _>>()?;
    for ((file, title, what), png) in plate_files.iter().zip(pngs) {
        part.files.push((file.to_string(), png));
        part.figures.push(FigureEntry {
            file: file.to_string(),
            title: title.to_string(),
            caption: what.to_string(),
        });
    }

    // Fig. 8: 8-bit differences, as the paper reports them.
    let pairs = [
        (2usize, 3usize, "fig8_scalar_jump_vs_paper_rules.png"),
        (5, 3, "fig8_unpolarized_scalar_jump_vs_paper_rules.png"),
        (4, 3, "fig8_vector_vs_paper_rules.png"),
    ];
    let diffs: Vec<(DiffStats, Vec<u8>, f64)> = pairs
        .par_iter()
        .map(|&(left, right, _)| {
            let stats = img::diff_stats(&pictures[left], &pictures[right])?;
            let (pic, factor) = img::stretched_difference(&pictures[left], &pictures[right])?;
            Ok::<_, String>((stats, pic.png()?, factor))
        })
        .collect::<Result<_, _>>()?;
    let mut stats_text = String::new();
    for ((left, right, file), (stats, png, factor)) in pairs.into_iter().zip(diffs) {
        part.files.push((file.to_string(), png));
        let (ln, rn) = (PLATE_SHADINGS[left].name(), PLATE_SHADINGS[right].name());
        stats_text.push_str(&fig8_text(&ln, &rn, &stats));
        part.fig8.push(Fig8Entry {
            left: ln,
            right: rn,
            file: file.to_string(),
            stats,
            stretch_factor: factor,
        });
    }
    part.files
        .push(("fig8_stats.txt".into(), stats_text.into_bytes()));
    Ok(part)
}

/// Newton's colour sequence: a CSV per illuminant and the strip of both.
fn newton_figures() -> Result<Part, String> {
    let mut part = Part::default();
    let t = Instant::now();
    let thick = newton_thicknesses_m(1);
    let cie = WavelengthGrid::cie_1nm();
    let mut bands = Vec::new();
    let lights = [
        (Illuminant::D65, Adaptation::None),
        (Illuminant::E, Adaptation::Bradford),
    ];
    // The rows once, for the CSV and the strip; each thickness's spectrum once for both lights.
    let sequences = colour::newton_sequences(NEWTON_N, &thick, &cie, &lights)?;
    for ((ill, adapt), rows) in lights.into_iter().zip(sequences) {
        let csv = colour::newton_csv(&rows, NEWTON_N, &cie, ill, adapt);
        part.files
            .push((format!("newton_{}.csv", ill.name()), csv.into_bytes()));
        bands.push((
            format!("{} ({})", ill.name(), adapt.name()),
            rows.iter().map(|r| r.srgb8).collect::<Vec<_>>(),
        ));
    }
    part.files.push((
        "newton_strip.png".into(),
        plot::newton_strip_png(&bands, 0.0, NEWTON_MAX_NM as f64)?,
    ));
    part.timings.push((
        "Newton sequence, 1501 thicknesses × 471 wavelengths × 2".into(),
        t.elapsed().as_secs_f64(),
    ));
    Ok(part)
}

/// The Fig. 8 statistics in the paper's words, with the paper's values beside them.
pub fn fig8_text(left: &str, right: &str, s: &DiffStats) -> String {
    let p = PAPER_FIG8;
    format!(
        "Fig. 8 statistics, {left} vs {right} ({}x{}; positions (column, row) from the top left):\n\
         \x20 pixels               {:>9}   (paper: {})\n\
         \x20 differing pixels     {:>9}   (paper: {})\n\
         \x20 max (r+g+b)          {:>9} at ({}, {})   (paper: {} at ({}, {}))\n\
         \x20 max channel (r|g|b)  {:>9} at ({}, {})   (paper: {} at ({}, {}))\n",
        s.width,
        s.height,
        s.pixels,
        p.pixels,
        s.differing,
        p.differing,
        s.max_sum,
        s.max_sum_at.0,
        s.max_sum_at.1,
        p.max_sum,
        p.max_sum_at.0,
        p.max_sum_at.1,
        s.max_channel,
        s.max_channel_at.0,
        s.max_channel_at.1,
        p.max_channel,
        p.max_channel_at.0,
        p.max_channel_at.1,
    )
}

/// CIEDE2000 of K-sample white light against the 1 nm reference, for Newton's film (D65 and
/// E) and the plate scene (D65, paper_rules).
pub fn colour_error_study(opts: &FigureOptions) -> Result<Vec<ColourErrorRow>, String> {
    let reference = WavelengthGrid::cie_1nm();
    let thick = newton_thicknesses_m(5);
    // XYZ of the Newton sequence under D65 and E (each thickness's spectrum once for both).
    let newton = |grid: &WavelengthGrid| -> Result<[Vec<[f64; 3]>; 2], String> {
        let lights = [Illuminant::D65, Illuminant::E].map(|ill| (ill, ill.default_adaptation()));
        let [d65, e] = <[Vec<colour::NewtonRow>; 2]>::try_from(colour::newton_sequences(
            NEWTON_N, &thick, grid, &lights,
        )?)
        .map_err(|_| "newton_sequences: one row list per light".to_string())?;
        let xyz = |rows: Vec<colour::NewtonRow>| rows.iter().map(|r| r.xyz).collect();
        Ok([xyz(d65), xyz(e)])
    };
    let plate = plate_case()?;
    let screen = Screen::from_probe(&plate.spec.probe, Some((opts.error_size, opts.error_size)))?;
    let plate_xyz = |grid: &WavelengthGrid| -> Result<(Vec<[f64; 3]>, f64), String> {
        let r = render::render(
            &plate,
            &Request {
                screen,
                shadings: vec![Shading::Level(Fidelity::PaperRules)],
                spectrum: Spectrum::White(SpectralIntegrator::new(grid, Illuminant::D65)?),
                progress: false,
            },
        )?;
        Ok((xyz_of(&r.images[0]).to_vec(), r.seconds))
    };
    // The reference and every sample count are independent: all are computed side by side
    // (the renders are small), then compared.
    let grids: Vec<WavelengthGrid> = std::iter::once(Ok(reference))
        .chain(ERROR_SAMPLES.iter().map(|&k| visible_grid(k)))
        .collect::<Result<_, String>>()?;
    type Computed = (Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<[f64; 3]>, f64);
    let computed: Vec<Computed> = grids
        .par_iter()
        .map(|grid| {
            let (p, secs) = plate_xyz(grid)?;
            let [d65, e] = newton(grid)?;
            Ok((d65, e, p, secs))
        })
        .collect::<Result<_, String>>()?;
    let (ref_d65, ref_e, ref_plate, _) = &computed[0];
    let exposure = img::exposure_for_peak_y([ref_plate.as_slice()]);
    let scaled =
        |v: &[[f64; 3]]| -> Vec<[f64; 3]> { v.iter().map(|p| p.map(|c| c * exposure)).collect() };
    let ref_plate = scaled(ref_plate);
    Ok(ERROR_SAMPLES
        .iter()
        .zip(&computed[1..])
        .map(|(&k, (d65, e, p, secs))| {
            let (nd_mean, nd_max) = delta_e_stats(d65, ref_d65, Illuminant::D65.white_xyz());
            let (ne_mean, ne_max) = delta_e_stats(e, ref_e, Illuminant::E.white_xyz());
            let (p_mean, p_max) =
                delta_e_stats(&scaled(p), &ref_plate, Illuminant::D65.white_xyz());
            ColourErrorRow {
                samples: k,
                newton_d65_mean: nd_mean,
                newton_d65_max: nd_max,
                newton_e_mean: ne_mean,
                newton_e_max: ne_max,
                plate_mean: p_mean,
                plate_max: p_max,
                plate_seconds: *secs,
            }
        })
        .collect())
}
