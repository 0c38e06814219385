//! A per-pixel kernel for line sources in a uniform medium without surfaces (Young's slits,
//! the paper's Fig. 3), at every shading of the ladder, non-dispersive and without spreading:
//! each source sends one ray to a pixel, its direct path, so the exact trace's plan, path solve
//! and ray propagation reduce to what they compute for that path (docs/PHYSICS.md §5 "Young"):
//!
//! - the direction: perpendicular from the line itself to the pixel,
//!   [`line_launch_direction`] (the path solver's own call for a line source's direct ray);
//! - the optical path: n₀ times the pixel's distance to the line, |v − (v·a) a| with
//!   v = x − point from exact coordinate differences, in double-double (what the path solver's
//!   start and the ray's segment sum to, [`distance_to_line`]);
//! - the field: each channel's launch field along that direction ([`Channel::launch`],
//!   amplitude √intensity), the same under every rung (no events, so the paper's ray is the
//!   `vector` one);
//! - the paper's coherence-length rule (P9) on the rounded optical path, and the screen's
//!   one-sidedness ([`build::records`]).
//!
//! Path differences are formed as the render forms them from the exact trace, the
//! double-double paths subtracted and rounded once. A pixel on a line (no direction) or with
//! an optical path within 1e-9 of its source's coherence length goes to the exact trace.

use crate::harness::case::build;
use crate::harness::case::spec::Observer;
use crate::optics::double_double::DoubleDouble;
use crate::optics::ray::INCOHERENT;
use crate::output::stack_kernel::KernelRay;
use crate::scene::source::{Channel, Emitter, line_launch_direction};
use crate::scene::{Scene, SceneOptics};
use crate::trace::TraceSettings;
use crate::trace::path::distance_to_line;
use glam::DVec3;

#[derive(Clone, Debug)]
struct LineSource {
    point: DVec3,
    /// The unit axis (the path solver's `axis.normalize()`).
    axis: DVec3,
    channels: Vec<Channel>,
    coherence_length_m: f64,
}

/// The kernel of one picture (module docs).
#[derive(Clone, Debug)]
pub(crate) struct FreeKernel {
    ambient_index: f64,
    sources: Vec<LineSource>,
}

/// Per-thread scratch space: each recorded ray's optical path (m, double-double).
#[derive(Clone, Debug, Default)]
pub(crate) struct FreeScratch {
    paths: Vec<DoubleDouble>,
}

impl FreeKernel {
    /// The kernel of a picture, or `None` when the scene is not of its class: no surfaces,
    /// every source a line source, no spreading.
    pub(crate) fn new(
        scene: &Scene,
        optics: &SceneOptics,
        settings: &TraceSettings,
    ) -> Option<FreeKernel> {
        if settings.solve.spreading || !scene.surfaces.is_empty() || scene.sources.is_empty() {
            return None;
        }
        let sources = scene
            .sources
            .iter()
            .map(|src| match src.emitter {
                Emitter::Line { point, axis } => Some(LineSource {
                    point,
                    axis: axis.normalize(),
                    channels: src.channels(),
                    coherence_length_m: src.coherence_length_m,
                }),
                _ => None,
            })
            .collect::<Option<Vec<_>>>()?;
        Some(FreeKernel {
            ambient_index: optics.ambient_index,
            sources,
        })
    }

    /// The rays reaching `point` (seen by `observer`), in the exact trace's order (source by
    /// source, channel by channel), into `out` for [`crate::output::stack_kernel::shade`];
    /// `false` (with `out` undefined) where the pixel must be traced exactly (module docs).
    pub(crate) fn rays(
        &self,
        point: DVec3,
        observer: &Observer,
        s: &mut FreeScratch,
        out: &mut Vec<KernelRay>,
    ) -> bool {
        out.clear();
        s.paths.clear();
        for (si, src) in self.sources.iter().enumerate() {
            let Some(d) = line_launch_direction(src.point, src.axis, point) else {
                return false;
            };
            if !build::records(observer, d) {
                continue;
            }
            let path = distance_to_line(src.point, src.axis, point).mul_f64(self.ambient_index);
            let length = path.to_f64();
            if (length - src.coherence_length_m).abs() <= 1e-9 * length {
                return false;
            }
            let lost_length = length > src.coherence_length_m;
            for ch in &src.channels {
                let (e, amplitude) = ch.launch(d);
                let a = amplitude * ch.intensity.sqrt();
                let field = DVec3::new(e.x * a, e.y * a, e.z * a);
                let coherent = !lost_length && ch.coherence_id != INCOHERENT;
                s.paths.push(path);
                out.push(KernelRay::new(
                    si,
                    if coherent {
                        ch.coherence_id
                    } else {
                        INCOHERENT
                    },
                    0.0,
                    0,
                    field,
                    field,
                ));
            }
        }
        // Δs from the first recorded ray, formed in double-double and rounded once.
        if let Some(&reference) = s.paths.first() {
            for (r, &p) in out.iter_mut().zip(&s.paths) {
                r.set_delta((p - reference).to_f64());
            }
        }
        true
    }
}
