//! Pictures of a case: every pixel of a screen traced exactly (the same paths, rays and
//! accumulation core as `fringe check`; for point sources over parallel planes the same rays
//! from a per-pixel kernel held to that trace, below), at one or more rungs of the fidelity ladder, in
//! monochrome (the case's own light) or in colour (white light on a wavelength grid, streamed
//! into CIE XYZ).
//!
//! # What a pixel is
//!
//! A pixel is one screen point (the pixel centre of a [`Probe::Grid`], or a point of a
//! [`Probe::Line`], drawn as a strip): no area sampling, as in the paper's renders.
//!
//! # Wavelengths and streaming
//!
//! Per pixel, every wavelength sample λ_i is evaluated and immediately folded into that pixel's
//! sum `Σ_i W_i I_i` (W_i: the CIE weights (C1) of [`SpectralIntegrator`] for colour, the case's
//! spectral weights for its own light); no per-wavelength image is ever stored.
//!
//! When no medium is dispersive the geometry of every path is independent of λ (Snell's law and
//! the Fresnel coefficients see the same indices), so the exact paths are solved **once per
//! pixel** and each λ only changes the path phase: a contribution with optical path difference
//! Δs (m, from the pixel's first arrival) and λ-independent extra phase e (cycles: the π jumps of
//! `scalar_jump`) gets phase Δs/λ + e. With a dispersive medium the paths are re-solved per λ.
//! The pixel's rays then go through [`Beats`]: the accumulation core's eqs. 5–6 rewritten
//! exactly as a constant plus one beat term per distinct path difference, so a two-beam pixel
//! costs one batch of phasors over the wavelength grid whatever the number of channels (the
//! core itself is used when there are more pairs than rays, e.g. an Airy plate).
//!
//! Rows run in parallel (rayon); the result does not depend on the thread count.
//!
//! # The parallel-stack kernel
//!
//! For point sources over unbounded parallel interfaces (with absorbing rectangular shields),
//! non-dispersive, without spreading, the rays of a pixel come from
//! [`crate::output::stack_kernel`] instead of the exact trace, at every shading (one kernel
//! pass per pixel feeds all of a picture's shadings, as one trace does): the sequences' walks
//! through the slabs are found once per picture and each pixel only solves the 1-D lateral
//! equation (docs/PHYSICS.md §6, "Pictures of point sources over parallel planes"); the pixels
//! it cannot vouch for, and every other scene, are traced exactly ([`PixelPath::Exact`]
//! forces that everywhere). Line sources without any surface (Young's slits) have a kernel of
//! their own, `output::free_kernel`: one direct ray per source, its direction and
//! double-double optical path as the path solver forms them. With 16 wavelengths or more, the
//! kernels' pixels take their
//! spectral sums from `output::beat_table` (one table read per beat term instead of
//! one phasor per wavelength). `tests/suite/stack_kernel.rs` holds both to the exact trace.
//!
//! # Speed
//!
//! Profiled with `perf record` on `fringe render plate_amplitude_division --size 600x600
//! --samples 81`: after the 1-D Snell start of the path solver, the skipping of sequences that
//! cannot reach a pixel, the shared propagation of a source's channels and the beat terms, the
//! exact trace's profile is flat (solve, reachability test, beats and propagation each 9–15%).
//! With the kernel (900×900, 81 wavelengths) `StackKernel::rays` is ~3/4 of the CPU; its
//! profile is flat too, bound by chains of square roots and divisions (per pixel three
//! sequences reach the screen's slab: the direct one, which the shield stops, and the two
//! beams). Issue #14 cut the render's CPU by 1.2–1.4× (loaded VM) without changing a bit of
//! its PNG, mostly by one Newton evaluation per pixel and sequence instead of two (cubic start,
//! module docs of `output::stack_kernel`) and the shielded direct path dropped before its
//! solve; the rest is not resolved by criterion under load (`picture/..._vector` 47.4 ms
//! against `_vector_reference` 47.9 ms, 300×300, load ~3): real arithmetic
//! for the fields and Fresnel coefficients (bit for bit the complex ones), each pixel's beat
//! terms summed from the table straight from those fields (no `SpectralContribution`s, no
//! `Beats`), the shield's verdicts without a square root away from its edges, no divisions by
//! an index of 1. Interleaved with the previous binary on the 2-core VM loaded by other builds
//! (load 3–4), user + sys CPU of 8 runs each: 2 threads min 0.87 → 0.66 s, median 1.00 →
//! 0.71 s (another 10: min 0.67 → 0.49 s, median 0.89 → 0.76 s); `RAYON_NUM_THREADS=1` min
//! 0.66 → 0.48 s; README "Measured numbers" has the idle
//! VM's timings. The rest of the CPU: the pixel's beat terms and the table ~12%, sRGB ~4%, PNG
//! ~2%. `fringe figures --size 240x240 --samples 31` (what `fringe check` makes), with every
//! shading and Fig. 3 by the kernels: the renders ~47% of its CPU before issue #14 (the
//! kernel's rays ~18%, the beat table ~14%), Newton's sequence ~28%, the sRGB step ~8%
//! (`perf record --call-graph dwarf`, loaded 2-core VM); issue #14 took it from 0.26 to 0.24 s
//! (one thread, min of 5, its PNGs byte-identical). Session 17 (`output::stack_kernel`,
//! "Speed"): the kernel's roots first, cheaper shield tests, shared cosines, one-pass beat
//! terms, and here the rows written in place into one buffer (a one-shading white-light
//! picture is that buffer, no copy): 5–9% of the 900×900 render's CPU, PNG byte-identical.

use crate::accumulate::Accumulator;
use crate::accumulate::fidelity::Fidelity;
use crate::colour::SpectralIntegrator;
use crate::harness::case::build::{self, Built, GridGeometry, Overrides};
use crate::harness::case::load::Case;
use crate::harness::case::spec::{Observer, Probe};
use crate::optics::material::Dispersion;
use crate::output::beat_table::BeatTable;
use crate::output::free_kernel::{FreeKernel, FreeScratch};
use crate::output::stack_kernel::{self, KernelArithmetic, KernelRay, KernelScratch, StackKernel};
use crate::scene::{Scene, SceneOptics};
use crate::trace::beats::{Beats, SpectralContribution};
use crate::trace::path::Target;
use crate::trace::{self, Arrival, Plan, TraceSettings};
use glam::DVec3;
use num_complex::Complex64;
use rayon::prelude::*;
use std::time::Instant;

/// Largest picture side `render` accepts (pixels).
pub(crate) const MAX_SIDE: usize = 8192;
/// Largest pixel count `render` accepts.
pub(crate) const MAX_PIXELS: usize = 16 * 1024 * 1024;

/// How the arrivals at a pixel are turned into an intensity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shading {
    /// A rung of the fidelity ladder ([`trace::contribution_from`]).
    Level(Fidelity),
    /// The paper's Fig. 6 (right) = Fig. 7 (left) model as its text implies: an unpolarized
    /// source sends **one scalar ray** along each path, carrying the total power of both
    /// polarizations after the exact Fresnel powers (I = Σ_channels |E|²), with phase from the
    /// optical path plus π per reflection from the denser side (the ⊥ rule for every ray).
    /// Its fringes are I1 + I2 + 2√(I1 I2) cos δ with I1 = I1s + I1p, I2 = I2s + I2p, while
    /// the s/p decomposition (`paper_rules`) gives 2(√(I1s I2s) + √(I1p I2p)) cos δ: by
    /// Cauchy–Schwarz the scalar ray overstates the fringe contrast except where
    /// I1s/I2s = I1p/I2p — at normal incidence and at Brewster's angle, where both p beams
    /// vanish. fringe's `scalar_jump` instead keeps the two polarization channels apart.
    UnpolarizedScalarJump,
}

impl Shading {
    /// Short name for files and tables.
    pub fn name(self) -> String {
        match self {
            Shading::Level(l) => l.name().to_string(),
            Shading::UnpolarizedScalarJump => "unpolarized_scalar_jump".into(),
        }
    }
}

/// Which light the picture is made with.
#[derive(Clone, Debug)]
pub enum Spectrum {
    /// The case's own light (monochrome or its sampled Gaussian): an intensity image, the
    /// spectral weights summing to 1.
    CaseLight,
    /// White light: the integrator's wavelength grid under its illuminant, an XYZ image with
    /// Y = 1 for a surface reflecting everything (C1).
    White(SpectralIntegrator),
}

/// The screen points of a picture.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Screen {
    /// The pixel grid (centre, axes, size, pixel counts).
    pub geometry: GridGeometry,
    /// One-sided screen (see [`Observer::Point`]).
    pub looks_toward: Option<DVec3>,
    /// True for a line probe (one row, drawn as a strip).
    pub strip: bool,
}

impl Screen {
    /// The screen of a case's probe: a [`Probe::Grid`] (at `size` = (columns, rows) pixels
    /// over the same rectangle when given) or a [`Probe::Line`] (one row of `size.0` points,
    /// default the probe's count, from end to end).
    pub fn from_probe(probe: &Probe, size: Option<(usize, usize)>) -> Result<Screen, String> {
        let check = |w: usize, h: usize| {
            if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE || w * h > MAX_PIXELS {
                Err(format!(
                    "picture size {w}x{h}: each side 1..={MAX_SIDE}, at most {MAX_PIXELS} pixels"
                ))
            } else {
                Ok(())
            }
        };
        let v = |a: &[f64; 3]| DVec3::from_array(*a);
        match probe {
            Probe::Grid {
                center_m,
                u_axis,
                v_axis,
                size_m,
                pixels,
                looks_toward,
            } => {
                let (w, h) = size.unwrap_or((pixels[0], pixels[1]));
                check(w, h)?;
                Ok(Screen {
                    geometry: GridGeometry::new(v(center_m), v(u_axis), v(v_axis), *size_m, [w, h]),
                    looks_toward: looks_toward.map(|l| v(&l)),
                    strip: false,
                })
            }
            Probe::Line {
                from_m,
                to_m,
                count,
                looks_toward,
                ..
            } => {
                let w = size.map_or(*count, |s| s.0);
                check(w, 1)?;
                let (a, b) = (v(from_m), v(to_m));
                Ok(Screen {
                    geometry: GridGeometry {
                        origin: a,
                        step_col: if w > 1 {
                            (b - a) / (w - 1) as f64
                        } else {
                            DVec3::ZERO
                        },
                        step_row: DVec3::ZERO,
                        columns: w,
                        rows: 1,
                    },
                    looks_toward: looks_toward.map(|l| v(&l)),
                    strip: true,
                })
            }
            Probe::Sweep { .. } | Probe::Single { .. } => Err(
                "a picture needs a `grid` probe (or a `line` probe, drawn as a strip); this case \
                 sweeps a parameter or observes a single point"
                    .into(),
            ),
        }
    }

    /// The observer of the screen point `position`.
    pub fn observer(&self, position: DVec3) -> Observer {
        Observer::Point {
            position_m: position.to_array(),
            looks_toward: self.looks_toward.map(|l| l.to_array()),
        }
    }
}

/// One rendered picture (row-major, row 0 at the top).
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// How its arrivals became intensities.
    pub shading: Shading,
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// The pixel values.
    pub values: ImageValues,
}

/// The pixel values of an [`Image`].
#[derive(Clone, Debug, PartialEq)]
pub enum ImageValues {
    /// Relative intensity (|E|² with a unit source), spectrally weighted by the case's light.
    Intensity(Vec<f64>),
    /// CIE XYZ under the white light's illuminant, Y = 1 for a perfect reflector.
    Xyz(Vec<[f64; 3]>),
}

/// What a render produced.
#[derive(Clone, Debug)]
pub struct Render {
    /// One image per requested shading, in the requested order.
    pub images: Vec<Image>,
    /// The wavelength whose hue shows an intensity image: the case's (centre) wavelength.
    pub display_lambda_m: f64,
    /// Number of wavelength samples per pixel.
    pub samples: usize,
    /// Whether some medium is dispersive (paths re-solved per wavelength).
    pub dispersive: bool,
    /// Arrivals traced (one per source channel and solved path), all pixels and wavelengths.
    pub paths: usize,
    /// Wall time of the render (s).
    pub seconds: f64,
    /// Pixels whose rays a kernel gave (the parallel-stack kernel, or the kernel of line
    /// sources without surfaces); the rest were traced exactly.
    pub kernel_pixels: usize,
}

/// How the rays of a pixel are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PixelPath {
    /// The parallel-stack kernel ([`crate::output::stack_kernel`]) or the kernel of line
    /// sources without surfaces (`output::free_kernel`) for the pixels they vouch
    /// for, where the scene is of their class (any shading); the exact trace everywhere else.
    Auto,
    /// Every pixel traced exactly ([`arrivals_at`]).
    Exact,
    /// As [`PixelPath::Auto`], but the kernels' fields in complex arithmetic and their spectral
    /// sums through [`Beats`] as the exact trace's pixels are summed: the reference that
    /// `Auto`'s real arithmetic and direct sums equal bit for bit
    /// (`tests/suite/stack_kernel.rs`).
    KernelReference,
}

/// A render request.
#[derive(Clone, Debug)]
pub struct Request {
    /// Where the pixels are.
    pub screen: Screen,
    /// One image per shading, in this order.
    pub shadings: Vec<Shading>,
    /// The light: the case's own, or white light.
    pub spectrum: Spectrum,
    /// Show a progress bar on stderr (only when stderr is a terminal).
    pub progress: bool,
}

/// Whether any medium of the built scene has a wavelength-dependent index.
pub(crate) fn is_dispersive(built: &Built) -> bool {
    built
        .media
        .values()
        .any(|m| !matches!(m.dispersion, Dispersion::Constant { .. }))
}

/// The tracer settings `fringe check` uses for this case (mirrors `case::run`): the case's
/// internal-reflection budget (or the Airy tail rule at `lambda_m`), spreading as configured.
pub fn trace_settings(case: &Case, built: &Built, lambda_m: f64) -> Result<TraceSettings, String> {
    crate::harness::case::run::trace_settings(case, built, lambda_m).map_err(|e| e.to_string())
}

/// The arrivals a one-sided screen point records, with `plan`'s sequences; the rays under the
/// paper's rules are traced only when `paper_rules`.
pub fn arrivals_at(
    scene: &Scene,
    optics: &SceneOptics,
    plan: &Plan,
    point: DVec3,
    observer: &Observer,
    settings: &TraceSettings,
    paper_rules: bool,
) -> Vec<Arrival> {
    let target = Target::Point(point);
    let mut arr = trace::arrivals_with(scene, optics, plan, &target, settings, paper_rules, None);
    arr.retain(|a| build::records(observer, a.vector.dir));
    arr
}

/// The contributions of `arr` under `shading`, phases split for re-evaluation at any λ.
fn prepare(arr: &[Arrival], shading: Shading, out: &mut Vec<SpectralContribution>) {
    out.clear();
    let Some(first) = arr.first() else { return };
    // Path differences in double-double, rounded once (docs/PHYSICS.md §1).
    let reference = first.vector.optical_path;
    match shading {
        Shading::Level(level) => {
            for a in arr {
                let c = trace::contribution_from(a, level, reference);
                let ray = if level == Fidelity::PaperRules {
                    a.paper.as_ref().expect(trace::PAPER_MISSING)
                } else {
                    &a.vector
                };
                let delta_s_m = (ray.optical_path - reference).to_f64();
                out.push(SpectralContribution {
                    coherence_id: c.coherence_id,
                    delta_s_m,
                    extra_cycles: c.phase_cycles - delta_s_m / ray.wavelength_m,
                    field: c.field,
                });
            }
        }
        Shading::UnpolarizedScalarJump => {
            // The channels of one source along one path are consecutive arrivals.
            let mut k = 0;
            while k < arr.len() {
                let a = &arr[k];
                let mut power = 0.0;
                while k < arr.len()
                    && arr[k].source == a.source
                    && arr[k].path.sequence == a.path.sequence
                {
                    power += arr[k].vector.intensity();
                    k += 1;
                }
                out.push(SpectralContribution {
                    coherence_id: a.vector.coherence_id,
                    delta_s_m: (a.vector.optical_path - reference).to_f64(),
                    extra_cycles: 0.5 * a.path.denser_reflections as f64,
                    field: [
                        Complex64::from(power.sqrt()),
                        Complex64::default(),
                        Complex64::default(),
                    ],
                });
            }
        }
    }
}

/// Everything a pixel needs, shared by all threads.
struct Context<'a> {
    built: &'a Built,
    settings: &'a TraceSettings,
    /// (λ, weights [X, Y, Z] or [0, w, 0]) per sample.
    samples: Vec<(f64, [f64; 3])>,
    /// The same, as two lists.
    lambdas: Vec<f64>,
    weights: Vec<[f64; 3]>,
    /// Scene optics and plan per sample (dispersive), or one entry (the middle sample).
    optics: Vec<SceneOptics>,
    plans: Vec<Plan>,
    dispersive: bool,
    shadings: &'a [Shading],
    /// Whether some shading needs the rays under the paper's rules.
    paper_rules: bool,
    /// The parallel-stack kernel, where the scene is of its class.
    kernel: Option<StackKernel>,
    /// The kernel of line sources without surfaces, where the scene is of its class.
    free: Option<FreeKernel>,
    /// The spectral sums of the kernel's pixels from a table, for grids of 16 samples or more.
    table: Option<BeatTable>,
    /// [`PixelPath::KernelReference`]: the kernels' fields in complex arithmetic, their sums
    /// through [`Beats`].
    reference: bool,
}

/// Per-thread scratch space.
#[derive(Default)]
struct Scratch {
    acc: Accumulator,
    prepared: Vec<SpectralContribution>,
    /// One per shading.
    beats: Vec<Beats>,
    kernel: KernelScratch,
    free: FreeScratch,
    kernel_rays: Vec<KernelRay>,
    /// Scratch of [`stack_kernel::shade_terms`].
    contributions: Vec<(u64, f64, f64, DVec3)>,
    terms: Vec<(f64, f64, f64)>,
}

impl Context<'_> {
    /// Adds each shading's Σ_i W_i I_i over the wavelength grid, from its beat terms in
    /// `s.beats`, into `out`: from the table where there is one (the kernel's pixels), else
    /// phasor by phasor ([`Beats::weighted_sum`]).
    fn add_spectral_sums(&self, s: &mut Scratch, out: &mut [[f64; 3]]) {
        for (beats, sum) in s.beats.iter_mut().zip(out.iter_mut()) {
            let w = match self.table.as_ref().and_then(|t| t.weighted_sum(beats)) {
                Some(w) => w,
                None => beats.weighted_sum(&self.lambdas, &self.weights, &mut s.acc),
            };
            for c in 0..3 {
                sum[c] += w[c];
            }
        }
    }

    /// Adds Σ_i W_i I_i of every shading at `point` into `out` (one [f64; 3] per shading);
    /// returns the number of arrivals and whether the kernel gave them.
    fn pixel(
        &self,
        point: DVec3,
        observer: &Observer,
        s: &mut Scratch,
        out: &mut [[f64; 3]],
    ) -> (usize, bool) {
        let scene = &self.built.scene;
        s.beats.resize_with(self.shadings.len(), Beats::default);
        // The kernels serve every shading of a non-dispersive scene (`render_with`).
        let by_kernel = match (&self.kernel, &self.free) {
            (Some(k), _) => k.rays(
                point,
                observer,
                self.paper_rules,
                if self.reference {
                    KernelArithmetic::Complex
                } else {
                    KernelArithmetic::Real
                },
                &mut s.kernel,
                &mut s.kernel_rays,
            ),
            (None, Some(f)) => f.rays(point, observer, &mut s.free, &mut s.kernel_rays),
            (None, None) => false,
        };
        if let (true, false, Some(table)) = (by_kernel, self.reference, &self.table) {
            // Each shading's beat terms straight from the real fields, summed from the table
            // (bit for bit what `shade`, `Beats` and `add_spectral_sums` give).
            for (k, sh) in self.shadings.iter().enumerate() {
                let direct = stack_kernel::shade_terms(
                    &s.kernel_rays,
                    *sh,
                    &mut s.contributions,
                    &mut s.terms,
                )
                .and_then(|constant| table.weighted_sum_real(constant, &s.terms));
                let w = match direct {
                    Some(w) => w,
                    None => {
                        stack_kernel::shade(&s.kernel_rays, *sh, &mut s.prepared);
                        s.beats[k].set(&s.prepared);
                        s.beats[k].weighted_sum(&self.lambdas, &self.weights, &mut s.acc)
                    }
                };
                for c in 0..3 {
                    out[k][c] += w[c];
                }
            }
            return (s.kernel_rays.len(), true);
        }
        if by_kernel {
            for (k, sh) in self.shadings.iter().enumerate() {
                stack_kernel::shade(&s.kernel_rays, *sh, &mut s.prepared);
                s.beats[k].set(&s.prepared);
            }
            self.add_spectral_sums(s, out);
            return (s.kernel_rays.len(), true);
        }
        if !self.dispersive {
            let optics = &self.optics[0];
            let arr = arrivals_at(
                scene,
                optics,
                &self.plans[0],
                point,
                observer,
                self.settings,
                self.paper_rules,
            );
            for (k, sh) in self.shadings.iter().enumerate() {
                prepare(&arr, *sh, &mut s.prepared);
                s.beats[k].set(&s.prepared);
            }
            self.add_spectral_sums(s, out);
            (arr.len(), false)
        } else {
            let mut paths = 0;
            for (j, &(lambda, w)) in self.samples.iter().enumerate() {
                let optics = &self.optics[j];
                let arr = arrivals_at(
                    scene,
                    optics,
                    &self.plans[j],
                    point,
                    observer,
                    self.settings,
                    self.paper_rules,
                );
                paths += arr.len();
                for (k, sh) in self.shadings.iter().enumerate() {
                    prepare(&arr, *sh, &mut s.prepared);
                    s.beats[k].set(&s.prepared);
                    let i = s.beats[k].intensity(lambda, &mut s.acc);
                    for c in 0..3 {
                        out[k][c] += w[c] * i;
                    }
                }
            }
            (paths, false)
        }
    }
}

/// The probe targets a render plans its sequences with: a 5 × 5 lattice of the screen's pixels
/// (corners and edges included).
fn plan_targets(g: &GridGeometry) -> Vec<DVec3> {
    let pick = |n: usize, k: usize| if n <= 1 { 0 } else { k * (n - 1) / 4 };
    let mut t = Vec::new();
    for a in 0..5 {
        for b in 0..5 {
            t.push(g.position(pick(g.columns, a), pick(g.rows, b)));
        }
    }
    t.dedup();
    t
}

/// Peak memory of a render and of writing its pictures (bytes), estimated from its size: the
/// per-row sums and the images built from them (3 f64 per pixel and shading each), the 8-bit
/// RGB picture and its PNG encoding (≤ 3 bytes per pixel each; a strip is drawn at most
/// `MAX_SIDE` rows tall), plus 64 MiB for the program, the scene and the thread scratch.
/// The wavelength grid is inside that allowance: each pixel's spectrum is summed into XYZ as it
/// is traced and never stored, and the per-thread phasor batches grow with the sample count
/// only; at the cap of 4096 samples a 100×100 render peaks 0.5 MB above one with 81 samples
/// (7.5 against 7.1 MB, `/usr/bin/time -f %M fringe render plate_amplitude_division --size
/// 100x100 --samples N`).
pub fn memory_estimate(screen: &Screen, shadings: usize) -> u64 {
    let g = &screen.geometry;
    let pixels = (g.columns * g.rows) as u64;
    let picture_rows = if screen.strip { MAX_SIDE } else { g.rows } as u64;
    let sums = 2 * pixels * shadings as u64 * 3 * 8;
    let picture = 2 * g.columns as u64 * picture_rows * 3;
    sums + picture + (64 << 20)
}

/// Render `case` as requested ([`PixelPath::Auto`]).
pub fn render(case: &Case, req: &Request) -> Result<Render, String> {
    render_with(case, req, PixelPath::Auto)
}

/// Render `case` as requested, the pixels' rays found as `path` says.
pub fn render_with(case: &Case, req: &Request, path: PixelPath) -> Result<Render, String> {
    let t0 = Instant::now();
    if req.shadings.is_empty() {
        return Err("render: no shading (fidelity level) requested".into());
    }
    let g = req.screen.geometry;
    crate::output::memory::check_fits(
        &format!(
            "a {}x{} render of {} picture(s)",
            g.columns,
            g.rows,
            req.shadings.len()
        ),
        memory_estimate(&req.screen, req.shadings.len()),
        crate::output::memory::available_bytes()?,
    )?;
    let built = build::build_scene(&case.spec.scene, &Overrides::default())?;
    let case_light = build::spectrum(&case.spec.light, &Overrides::default());
    let display_lambda_m = case_light[case_light.len() / 2].0;
    let samples: Vec<(f64, [f64; 3])> = match &req.spectrum {
        Spectrum::CaseLight => case_light
            .iter()
            .map(|&(l, w)| (l, [0.0, w, 0.0]))
            .collect(),
        Spectrum::White(integ) => integ
            .lambdas_m()
            .iter()
            .enumerate()
            .map(|(i, &l)| (l, integ.sample_weights(i)))
            .collect(),
    };
    let reference_sample = samples.len() / 2;
    let dispersive = is_dispersive(&built);
    let settings = trace_settings(case, &built, samples[reference_sample].0)?;
    let targets = plan_targets(&req.screen.geometry);
    let lambdas: Vec<f64> = if dispersive {
        samples.iter().map(|s| s.0).collect()
    } else {
        vec![samples[reference_sample].0]
    };
    let mut optics = Vec::new();
    let mut plans = Vec::new();
    for &l in &lambdas {
        let o = built
            .scene
            .optics(l)
            .map_err(|e| format!("at {:.1} nm: {e}", l * 1e9))?;
        plans.push(trace::plan(&built.scene, &o, &targets, &settings.limits));
        optics.push(o);
    }
    let kernel = if path != PixelPath::Exact && !dispersive {
        StackKernel::new(&built.scene, &optics[0], &plans[0], &settings)
    } else {
        None
    };
    let free = if path != PixelPath::Exact && !dispersive {
        FreeKernel::new(&built.scene, &optics[0], &settings)
    } else {
        None
    };
    let table = if (kernel.is_some() || free.is_some()) && samples.len() >= 16 {
        let l: Vec<f64> = samples.iter().map(|s| s.0).collect();
        let w: Vec<[f64; 3]> = samples.iter().map(|s| s.1).collect();
        BeatTable::new(&l, &w)
    } else {
        None
    };
    let ctx = Context {
        kernel,
        free,
        table,
        reference: path == PixelPath::KernelReference,
        built: &built,
        settings: &settings,
        lambdas: samples.iter().map(|s| s.0).collect(),
        weights: samples.iter().map(|s| s.1).collect(),
        samples,
        optics,
        plans,
        dispersive,
        shadings: &req.shadings,
        paper_rules: req.shadings.contains(&Shading::Level(Fidelity::PaperRules)),
    };
    let bar = progress_bar(g.rows as u64, req.progress);
    let ns = req.shadings.len();
    // The rows are written in place into one buffer (pixel-major, one [f64; 3] per shading):
    // a picture of one shading in white light is that buffer, without a copy.
    let width = g.columns * ns;
    let mut buf = vec![[0.0; 3]; g.rows * width];
    let counts: Vec<(usize, usize)> = buf
        .par_chunks_mut(width.max(1))
        .enumerate()
        .map_init(Scratch::default, |s, (row, out)| {
            let (mut paths, mut by_kernel) = (0, 0);
            s.kernel.new_row();
            for col in 0..g.columns {
                let p = g.position(col, row);
                let (n, k) = ctx.pixel(
                    p,
                    &req.screen.observer(p),
                    s,
                    &mut out[col * ns..(col + 1) * ns],
                );
                paths += n;
                by_kernel += usize::from(k);
            }
            bar.inc(1);
            (paths, by_kernel)
        })
        .collect();
    bar.finish_and_clear();
    let paths = counts.iter().map(|r| r.0).sum();
    let kernel_pixels = counts.iter().map(|r| r.1).sum();
    let image = |shading: Shading, values: ImageValues| Image {
        shading,
        width: g.columns,
        height: g.rows,
        values,
    };
    let images = match (&req.spectrum, &req.shadings[..]) {
        (Spectrum::White(_), &[sh]) => vec![image(sh, ImageValues::Xyz(buf))],
        _ => req
            .shadings
            .iter()
            .enumerate()
            .map(|(k, sh)| {
                let pixels = buf.iter().skip(k).step_by(ns).copied();
                image(
                    *sh,
                    match req.spectrum {
                        Spectrum::CaseLight => {
                            ImageValues::Intensity(pixels.map(|p| p[1]).collect())
                        }
                        Spectrum::White(_) => ImageValues::Xyz(pixels.collect()),
                    },
                )
            })
            .collect(),
    };
    Ok(Render {
        images,
        display_lambda_m,
        samples: ctx.samples.len(),
        dispersive,
        paths,
        seconds: t0.elapsed().as_secs_f64(),
        kernel_pixels,
    })
}

/// A progress bar over `len` rows on stderr, hidden unless `show` and stderr is a terminal.
fn progress_bar(len: u64, show: bool) -> indicatif::ProgressBar {
    use std::io::IsTerminal;
    if !show || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(len);
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "{spinner} rendering [{bar:40}] {pos}/{len} rows, {elapsed} elapsed, ~{eta} left",
    ) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

// ---------------------------------------------------------------------------------------------
// The `fringe render` command
// ---------------------------------------------------------------------------------------------

/// Parses `WxH` (e.g. `900x900`).
pub fn parse_size(s: &str) -> Result<(usize, usize), String> {
    let bad = || format!("--size {s:?}: expected WxH with positive integers, e.g. 300x300");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (usize, usize) = (
        w.trim().parse().map_err(|_| bad())?,
        h.trim().parse().map_err(|_| bad())?,
    );
    if w == 0 || h == 0 || w > MAX_SIDE || h > MAX_SIDE || w * h > MAX_PIXELS {
        return Err(format!(
            "--size {s}: each side 1..={MAX_SIDE}, at most {MAX_PIXELS} pixels"
        ));
    }
    Ok((w, h))
}

/// Parses a fidelity level name, or `unpolarized_scalar_jump` ([`Shading::UnpolarizedScalarJump`]).
pub fn parse_shading(s: &str) -> Result<Shading, String> {
    if s == "unpolarized_scalar_jump" {
        return Ok(Shading::UnpolarizedScalarJump);
    }
    Fidelity::parse(s).map(Shading::Level).ok_or_else(|| {
        format!(
            "--fidelity {s:?}: expected one of incoherent, scalar, scalar_jump, paper_rules, \
             vector, unpolarized_scalar_jump"
        )
    })
}

/// A case argument: a path to a `.json` file, or a name in `cases_dir` or `figures/`.
pub fn resolve_case(name: &str, cases_dir: &std::path::Path) -> Result<std::path::PathBuf, String> {
    let p = std::path::Path::new(name);
    if name.ends_with(".json") || name.contains('/') {
        return if p.is_file() {
            Ok(p.to_path_buf())
        } else {
            Err(format!("{name}: no such case file"))
        };
    }
    let candidates = [
        cases_dir.join(format!("{name}.json")),
        std::path::Path::new("figures").join(format!("{name}.json")),
    ];
    candidates
        .iter()
        .find(|c| c.is_file())
        .cloned()
        .ok_or_else(|| {
            format!(
                "{name}: no case of that name in {} or figures/",
                cases_dir.display()
            )
        })
}

/// What `fringe render` was asked.
#[derive(Clone, Debug)]
pub struct Command {
    /// The case file.
    pub case: std::path::PathBuf,
    /// The shadings to render.
    pub shadings: Vec<Shading>,
    /// White light (grid, illuminant); `None`: the case's own light.
    pub white: Option<(crate::colour::WavelengthGrid, crate::colour::Illuminant)>,
    /// Picture size (columns, rows); `None`: the probe's pixels.
    pub size: Option<(usize, usize)>,
    /// Output PNG; with several shadings `_<name>` is inserted before the extension.
    pub output: Option<std::path::PathBuf>,
    /// Show a progress bar on stderr (only when stderr is a terminal).
    pub progress: bool,
}

/// Runs `fringe render`: renders, writes the PNG(s) atomically, and returns the lines to print
/// (files, size, light, normalisation, timing).
pub fn run_command(cmd: &Command) -> Result<Vec<String>, String> {
    use crate::output::report::image as img;
    let case = crate::harness::case::load::load(&cmd.case).map_err(|e| e.to_string())?;
    let screen = Screen::from_probe(&case.spec.probe, cmd.size)?;
    let spectrum = match &cmd.white {
        None => Spectrum::CaseLight,
        Some((grid, ill)) => Spectrum::White(SpectralIntegrator::new(grid, *ill)?),
    };
    let g = screen.geometry;
    let height = if screen.strip {
        cmd.size.map_or(60, |s| s.1)
    } else {
        g.rows
    };
    let r = render(
        &case,
        &Request {
            screen,
            shadings: cmd.shadings.clone(),
            spectrum: spectrum.clone(),
            progress: cmd.progress,
        },
    )?;
    let mut lines = vec![format!(
        "{}: {}x{} points, {} wavelength sample(s){}, {} arrival(s) in {:.2} s ({} pixel(s) by \
         a kernel, the rest traced exactly)",
        case.spec.name,
        g.columns,
        g.rows,
        r.samples,
        if r.dispersive {
            " (dispersive: paths re-solved per wavelength)"
        } else {
            " (non-dispersive: paths solved once per pixel)"
        },
        r.paths,
        r.seconds,
        r.kernel_pixels
    )];
    let base = cmd.output.clone().unwrap_or_else(|| {
        std::path::Path::new("reports")
            .join("render")
            .join(format!("{}.png", case.spec.name))
    });
    let file_for = |sh: Shading| {
        if cmd.shadings.len() == 1 {
            base.clone()
        } else {
            let stem = base
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("render");
            base.with_file_name(format!("{stem}_{}.png", sh.name()))
        }
    };
    match &spectrum {
        Spectrum::CaseLight => {
            let scale = r
                .images
                .iter()
                .filter_map(|im| match &im.values {
                    ImageValues::Intensity(i) => Some(img::peak(i)),
                    ImageValues::Xyz(_) => None,
                })
                .fold(0.0, f64::max);
            lines.push(format!(
                "monochrome, drawn in the hue of {:.1} nm; normalised so the brightest pixel over \
                 the picture(s) (I = {scale:.6e}) is full scale",
                r.display_lambda_m * 1e9
            ));
            for im in &r.images {
                if let ImageValues::Intensity(i) = &im.values {
                    let mut pic =
                        img::monochrome(im.width, im.height, i, r.display_lambda_m, scale);
                    if screen.strip {
                        pic = pic.extrude(height);
                    }
                    let f = file_for(im.shading);
                    crate::io::write_atomic(&f, &pic.png()?)
                        .map_err(|e| format!("{}: cannot write: {e}", f.display()))?;
                    lines.push(format!("{}: {}", im.shading.name(), f.display()));
                }
            }
        }
        Spectrum::White(integ) => {
            let ill = integ.illuminant();
            let adaptation = ill.default_adaptation();
            let exposure =
                img::exposure_for_peak_y(r.images.iter().filter_map(|im| match &im.values {
                    ImageValues::Xyz(x) => Some(x.as_slice()),
                    ImageValues::Intensity(_) => None,
                }));
            lines.push(format!(
                "white light, illuminant {} (adaptation {}), CIE 1931 2°; XYZ × {exposure:.6} so the \
                 brightest Y over the picture(s) is 1, then sRGB (IEC matrix, clip, transfer curve)",
                ill.name(),
                adaptation.name()
            ));
            for im in &r.images {
                if let ImageValues::Xyz(x) = &im.values {
                    let mut pic = img::colour(im.width, im.height, x, exposure, ill, adaptation);
                    if screen.strip {
                        pic = pic.extrude(height);
                    }
                    let f = file_for(im.shading);
                    crate::io::write_atomic(&f, &pic.png()?)
                        .map_err(|e| format!("{}: cannot write: {e}", f.display()))?;
                    lines.push(format!("{}: {}", im.shading.name(), f.display()));
                }
            }
        }
    }
    Ok(lines)
}
