//! Renderer mode: forward ray fans into pixels, and what "a pixel is not a point" costs
//! (the paper's §5 open problem).
//!
//! Point sources emit stratified, seeded fans of rays into a cone; every ray is carried through
//! the scene by the same [`interact`] code as the exact tracer (a ray tree: reflected and
//! refracted children, depth- and power-limited) until it lands on the screen. Rays are grouped
//! into *families*: same source, same polarization channel, same surface sequence. The rays of
//! one family that land in one pixel are samples of **one** wave:
//!
//! * its irradiance is their power over the pixel area, so its amplitude is
//!   `|E_f| = sqrt(Σ P_r / (A_pixel cos θ_screen))` (the ray-density estimate);
//! * its phase at the pixel centre `c` is estimated from the rays' phases;
//! * families, not rays, are summed coherently (per coherence id), as in the exact tracer.
//!
//! Estimators of the family phase (and, for the naive one, of the whole sum):
//! * [`Estimator::NaiveRays`]: every ray is its own wave with amplitude from its own power,
//!   summed coherently with its landing phase — the intensity then grows with the ray count;
//! * [`Estimator::LandingPhase`]: family phase = mean phasor of the landing phases;
//! * [`Estimator::TransportedPhase`]: each ray's phase moved to the pixel centre to first order,
//!   φ(c) = φ(hit) + 2π n/λ · dir·(c − hit), then averaged;
//! * [`Estimator::Supersampled`]: the pixel split into k×k cells, each estimated as
//!   `TransportedPhase` at its own centre; the pixel intensity is the mean over cells.
//!
//! Determinism: rays are traced in fixed chunks in parallel (rayon), each chunk with its own
//! generator seeded from (seed, chunk); landings are merged in chunk order, so a seed gives the
//! same picture on any number of threads.

use crate::accumulate::{Accumulator, phasor_from_cycles};
use crate::optics::double_double::DoubleDouble;
use crate::optics::interaction::{InterfaceHit, interact};
use crate::optics::ray::{Field3, Ray};
use crate::scene::source::Emitter;
use crate::scene::{Scene, SceneOptics};
use crate::trace::path::{Event, EventKind};
use glam::DVec3;
use num_complex::Complex64;
use rayon::prelude::*;
use std::collections::HashMap;

/// A rectangular screen of pixels: centre, unit axes u (columns) and v (rows), size (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Screen {
    /// The screen's centre, m.
    pub center: DVec3,
    /// Unit axis along the columns (left → right).
    pub u: DVec3,
    /// Unit axis along the rows (bottom → top), ⊥ `u`.
    pub v: DVec3,
    /// [width along u, height along v], m.
    pub size_m: [f64; 2],
    /// [columns, rows].
    pub pixels: [usize; 2],
}

impl Screen {
    /// The screen's normal u × v.
    pub fn normal(&self) -> DVec3 {
        self.u.cross(self.v)
    }

    /// [width, height] of one pixel, m.
    pub(crate) fn pixel_size(&self) -> [f64; 2] {
        [
            self.size_m[0] / self.pixels[0] as f64,
            self.size_m[1] / self.pixels[1] as f64,
        ]
    }

    /// Centre of pixel (column i, row j).
    pub(crate) fn pixel_center(&self, i: usize, j: usize) -> DVec3 {
        let [w, h] = self.pixel_size();
        self.center
            + ((i as f64 + 0.5) * w - 0.5 * self.size_m[0]) * self.u
            + ((j as f64 + 0.5) * h - 0.5 * self.size_m[1]) * self.v
    }

    /// Screen coordinates (m, from the lower-left corner) of a point on the screen plane.
    fn coords(&self, x: DVec3) -> [f64; 2] {
        let d = x - self.center;
        [
            d.dot(self.u) + 0.5 * self.size_m[0],
            d.dot(self.v) + 0.5 * self.size_m[1],
        ]
    }
}

/// How a pixel's value is estimated from the rays that land in it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Estimator {
    /// Every ray its own wave, summed coherently with its landing phase.
    NaiveRays,
    /// Family phase = mean phasor of the landing phases.
    LandingPhase,
    /// Each ray's phase moved to the pixel centre to first order, then averaged.
    TransportedPhase,
    /// `TransportedPhase` in each of k×k cells of the pixel, averaged in intensity.
    Supersampled {
        /// k: cells per pixel side.
        cells: usize,
    },
}

impl Estimator {
    /// The estimator's name in reports (`supersampled_4x4`, …).
    pub fn name(&self) -> String {
        match self {
            Estimator::NaiveRays => "naive_rays".into(),
            Estimator::LandingPhase => "landing_phase".into(),
            Estimator::TransportedPhase => "transported_phase".into(),
            Estimator::Supersampled { cells } => format!("supersampled_{cells}x{cells}"),
        }
    }
}

/// Forward-tracing settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForwardSettings {
    /// Rays per source channel (rounded to a square stratification).
    pub rays: usize,
    /// Seed of the ray fans (a seed gives the same picture on any number of threads).
    pub seed: u64,
    /// Emission cone: unit axis and half-angle (rad).
    pub cone_axis: DVec3,
    /// Half-angle of the emission cone, rad.
    pub cone_half_angle: f64,
    /// Maximum interactions per ray.
    pub max_depth: usize,
    /// Children below this fraction of the emitted power are dropped.
    pub min_power: f64,
}

/// One ray that reached the screen.
#[derive(Clone, Debug)]
pub struct Landing {
    /// Where on the screen (m from the lower-left corner).
    pub coords: [f64; 2],
    /// Where it lands, m.
    pub point: DVec3,
    /// Family key: source, coherence id and surface sequence.
    pub family: (usize, u64, Vec<Event>),
    /// The ray at the screen.
    pub ray: Ray,
    /// Power carried (|E|²·sr of the source, times the Fresnel power factors).
    pub power: f64,
}

/// A small deterministic generator (SplitMix64).
struct SplitMix(u64);

impl SplitMix {
    fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

const CHUNK_ROWS: usize = 8;

/// Trace the fans of every point source of `scene` to `screen`.
pub fn trace_fans(
    scene: &Scene,
    optics: &SceneOptics,
    screen: &Screen,
    st: &ForwardSettings,
) -> Vec<Landing> {
    let side = (st.rays as f64).sqrt().ceil().max(1.0) as usize;
    let cos_max = st.cone_half_angle.cos();
    let solid_angle = std::f64::consts::TAU * (1.0 - cos_max);
    let d_omega = solid_angle / (side * side) as f64;
    let axis = st.cone_axis.normalize();
    let e1 = axis.any_orthonormal_vector();
    let e2 = axis.cross(e1);
    let mut out = Vec::new();
    for (si, src) in scene.sources.iter().enumerate() {
        let Emitter::Point { position } = src.emitter else {
            continue;
        };
        for ch in src.channels() {
            let chunks: Vec<Vec<Landing>> = (0..side.div_ceil(CHUNK_ROWS))
                .into_par_iter()
                .map(|chunk| {
                    let mut rng = SplitMix(
                        st.seed ^ ((si as u64) << 48) ^ (ch.coherence_id << 32) ^ chunk as u64,
                    );
                    let mut local = Vec::new();
                    for a in chunk * CHUNK_ROWS..((chunk + 1) * CHUNK_ROWS).min(side) {
                        for b in 0..side {
                            // Stratified equal-area sampling of the cone (cos θ uniform, φ uniform).
                            let cos_t =
                                1.0 - (1.0 - cos_max) * (a as f64 + rng.next_f64()) / side as f64;
                            let phi =
                                std::f64::consts::TAU * (b as f64 + rng.next_f64()) / side as f64;
                            let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                            let dir = cos_t * axis + sin_t * (phi.cos() * e1 + phi.sin() * e2);
                            // A dipole channel's field and power fall off as sin² from its
                            // axis (docs/PHYSICS.md §3); a linear channel's amplitude is 1.
                            let (e, amplitude) = ch.launch(dir);
                            let mut ray = Ray::linear(
                                position,
                                dir,
                                e,
                                amplitude * ch.intensity.sqrt(),
                                optics.lambda_m,
                                optics.ambient_index,
                            );
                            ray.coherence_id = ch.coherence_id;
                            let power = amplitude * amplitude * ch.intensity * d_omega;
                            follow(
                                scene,
                                optics,
                                screen,
                                st,
                                si,
                                ray,
                                power,
                                power,
                                &mut Vec::new(),
                                None,
                                &mut local,
                            );
                        }
                    }
                    local
                })
                .collect();
            out.extend(chunks.into_iter().flatten());
        }
    }
    out
}

/// Follow one ray: land on the screen, stop at a blocker, or split at an interface.
#[allow(clippy::too_many_arguments)]
fn follow(
    scene: &Scene,
    optics: &SceneOptics,
    screen: &Screen,
    st: &ForwardSettings,
    source: usize,
    ray: Ray,
    power: f64,
    emitted: f64,
    seq: &mut Vec<Event>,
    from: Option<usize>,
    out: &mut Vec<Landing>,
) {
    let (o, d) = (ray.origin, ray.dir);
    let mut best: Option<(f64, usize)> = None;
    for (j, surf) in scene.surfaces.iter().enumerate() {
        if Some(j) == from {
            continue;
        }
        if let Some(t) = surf.plane.intersect(o, d) {
            let x = o + t * d;
            if t > 1e-12
                && best.is_none_or(|(bt, _)| t < bt)
                && (surf.blocks(x) || surf.interacts(x))
            {
                best = Some((t, j));
            }
        }
    }
    // The screen absorbs whatever reaches it first.
    let n = screen.normal();
    let t_screen = (screen.center - o).dot(n) / d.dot(n);
    if t_screen > 1e-12 && best.is_none_or(|(t, _)| t_screen < t) {
        let x = o + t_screen * d;
        let c = screen.coords(x);
        if c[0] >= 0.0 && c[1] >= 0.0 && c[0] < screen.size_m[0] && c[1] < screen.size_m[1] {
            let mut ray = ray;
            ray.advance_to(x);
            out.push(Landing {
                coords: c,
                point: x,
                family: (source, ray.coherence_id, seq.clone()),
                ray,
                power,
            });
        }
        return;
    }
    let Some((t, j)) = best else { return };
    let Some(so) = optics.surfaces[j] else { return }; // opaque: absorbed
    if seq.len() >= st.max_depth {
        return;
    }
    let surf = &scene.surfaces[j];
    let hit = InterfaceHit {
        surface: j,
        point: o + t * d,
        normal: surf.plane.normal,
        optics: so,
        coherence: surf.coherence(),
        layers: optics.layers[j],
    };
    let children = interact(
        &ray,
        &hit,
        crate::optics::interaction::CoefficientModel::Vector,
    );
    let parent_i = ray.intensity();
    let branch =
        |child: Ray, kind: EventKind, factor: f64, seq: &mut Vec<Event>, out: &mut Vec<Landing>| {
            let p = if parent_i > 0.0 {
                power * child.intensity() / parent_i * factor
            } else {
                0.0
            };
            if p > st.min_power * emitted {
                seq.push(Event { surface: j, kind });
                follow(
                    scene,
                    optics,
                    screen,
                    st,
                    source,
                    child,
                    p,
                    emitted,
                    seq,
                    Some(j),
                    out,
                );
                seq.pop();
            }
        };
    branch(
        children.reflected.clone(),
        EventKind::Reflect,
        1.0,
        seq,
        out,
    );
    if let Some(t_child) = children.refracted.clone() {
        // Power transmission factor of the field: (n2 cos θt)/(n1 cos θi).
        let cos_t = t_child.dir.dot(surf.plane.normal).abs();
        let factor = if children.cos_theta_i > 0.0 {
            children.n2 * cos_t / (children.n1 * children.cos_theta_i)
        } else {
            0.0
        };
        branch(t_child, EventKind::Refract, factor, seq, out);
    }
}

/// Per-family running sums within one pixel (or cell).
#[derive(Clone, Debug, Default)]
struct FamilySum {
    power: f64,
    cos_sum: f64,
    count: usize,
    phasor: Complex64,
    /// Unit complex field of the ray nearest the centre, and its distance.
    field: Field3,
    nearest: f64,
    coherence_id: u64,
    index: f64,
}

/// An image (row-major, `pixels[1]` rows of `pixels[0]` values) from landings.
pub fn image(landings: &[Landing], screen: &Screen, estimator: Estimator) -> Vec<f64> {
    let [nx, ny] = screen.pixels;
    let cells = match estimator {
        Estimator::Supersampled { cells } => cells.max(1),
        _ => 1,
    };
    let [pw, ph] = screen.pixel_size();
    let (cw, chh) = (pw / cells as f64, ph / cells as f64);
    let cell_area = cw * chh;
    // Phase reference: a common optical path (only differences matter).
    let reference = landings
        .first()
        .map_or(DoubleDouble::ZERO, |l| l.ray.optical_path);
    // Bucket landings by (pixel, cell) in landing order (deterministic).
    let mut buckets: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for (k, l) in landings.iter().enumerate() {
        let i = ((l.coords[0] / pw) as usize).min(nx - 1);
        let j = ((l.coords[1] / ph) as usize).min(ny - 1);
        let ci = (((l.coords[0] - i as f64 * pw) / cw) as usize).min(cells - 1);
        let cj = (((l.coords[1] - j as f64 * ph) / chh) as usize).min(cells - 1);
        buckets
            .entry((j * nx + i, cj * cells + ci))
            .or_default()
            .push(k);
    }
    let normal = screen.normal();
    let mut img = vec![0.0; nx * ny];
    let mut keys: Vec<_> = buckets.keys().copied().collect();
    keys.sort_unstable();
    for (pix, cell) in keys {
        let (i, j) = (pix % nx, pix / nx);
        let (ci, cj) = (cell % cells, cell / cells);
        let corner = screen.pixel_center(i, j) - 0.5 * pw * screen.u - 0.5 * ph * screen.v;
        let c = corner + (ci as f64 + 0.5) * cw * screen.u + (cj as f64 + 0.5) * chh * screen.v;
        let idx = &buckets[&(pix, cell)];
        let value = match estimator {
            Estimator::NaiveRays => {
                let mut acc = Accumulator::new();
                for &k in idx {
                    let l = &landings[k];
                    let cos = l.ray.dir.dot(normal).abs();
                    let e = l.ray.field();
                    let norm = l.ray.intensity().sqrt();
                    let amp = (l.power / (cell_area * cos * l.ray.index)).sqrt() / norm;
                    acc.add_parts(
                        l.ray.coherence_id,
                        (l.ray.optical_path - reference).to_f64() / l.ray.wavelength_m,
                        &e.map(|x| x * amp),
                    );
                }
                acc.intensity()
            }
            _ => {
                let transport = !matches!(estimator, Estimator::LandingPhase);
                let mut fam: HashMap<&(usize, u64, Vec<Event>), FamilySum> = HashMap::new();
                let mut order = Vec::new();
                for &k in idx {
                    let l = &landings[k];
                    let f = fam.entry(&l.family).or_insert_with(|| {
                        order.push(&l.family);
                        FamilySum {
                            nearest: f64::INFINITY,
                            ..Default::default()
                        }
                    });
                    let mut op = (l.ray.optical_path - reference).to_f64();
                    if transport {
                        op += l.ray.index * l.ray.dir.dot(c - l.point);
                    }
                    f.power += l.power;
                    f.cos_sum += l.ray.dir.dot(normal).abs();
                    f.count += 1;
                    f.phasor += phasor_from_cycles(op / l.ray.wavelength_m);
                    f.coherence_id = l.ray.coherence_id;
                    f.index = l.ray.index;
                    let dist = (l.point - c).length();
                    if dist < f.nearest {
                        let norm = l.ray.intensity().sqrt();
                        f.field = l.ray.field().map(|x| x / norm);
                        f.nearest = dist;
                    }
                }
                let mut acc = Accumulator::new();
                for key in order {
                    let f = &fam[key];
                    let cos = f.cos_sum / f.count as f64;
                    let amp = (f.power / (cell_area * cos * f.index)).sqrt();
                    let ph = if f.phasor.norm() > 0.0 {
                        f.phasor / f.phasor.norm()
                    } else {
                        Complex64::from(1.0)
                    };
                    // Phase as a complex field factor (cycles 0: the phasor carries it).
                    acc.add_parts(f.coherence_id, 0.0, &f.field.map(|x| x * amp * ph));
                }
                acc.intensity()
            }
        };
        img[pix] += value / (cells * cells) as f64;
    }
    img
}
