//! fringe: exact tracing of linearly polarized rays, and a verification harness, for light
//! interference in 3D scenes of optically isotropic transparent objects.
//!
//! fringe traces rays of zero thickness from sources to observation points along *exact*
//! paths (each path solved for the point, not sampled), carries each ray's complex 3D field
//! through every reflection and refraction with the Fresnel coefficients, sums the rays that
//! meet at a point by coherence group, and checks the result against closed-form physics. The
//! physics, its numbered equations (P1–P10) and the sources (the paper of Debelov and
//! Vasilieva; Born & Wolf) are in `docs/PHYSICS.md`; doc comments cite it by section and
//! equation.
//!
//! # Conventions (docs/PHYSICS.md §1)
//!
//! * **Units**: SI everywhere in the API — metres, radians; wavelengths are vacuum wavelengths
//!   in metres (`lambda_m`). Case files name their units in their keys (`wavelength_nm`).
//! * **Time and phase**: time dependence e^{-iωt}; a wave that has covered the optical path
//!   s = Σ n_k L_k carries e^{+i 2π s/λ0}. Phases are carried in cycles and formed from path
//!   *differences*, so metre-long paths keep their phase to ~1e-9 rad.
//! * **s/p frames**: at an interface with unit normal N and incident direction d_i,
//!   s = normalize(d_i × N) and p = d × s for each ray d, so (s, p, d) is right-handed; fields
//!   are complex 3D vectors E = a_s s + a_p p. The Fresnel coefficients (P1)–(P4) and the TIR
//!   phases (P5), (P6) are in this frame ([`optics::fresnel`]).
//! * **Observables**: a screen point reports the field intensity |E|² summed over coherence
//!   groups (in units of the source's |E|²); a far-field probe of a plane wave reports the power
//!   reflectance or transmittance R, T (docs/PHYSICS.md §3a).
//! * Refractive indices are real; absorbing media are rejected, not approximated.
//!
//! # Data flow
//!
//! One direction, each stage using only the ones before it:
//!
//! 1. **Scene** ([`Scene`]): an ambient [`Medium`], planar surfaces (interfaces, plates,
//!    wedges, mirrors, splitters, shields) and sources.
//! 2. **Sources** ([`Source`]): point, line or plane-wave emitters, linearly polarized or
//!    unpolarized (basis-free: three mutually incoherent dipole channels along x, y, z; or the
//!    paper's two channels from a reference), grouped by coherence.
//! 3. **Exact paths** ([`trace::plan`], [`trace::arrivals`], [`trace::path`]): the candidate
//!    surface sequences of each source are discovered once per scene; for each observation
//!    point (or far-field direction) every sequence is solved exactly, and each source
//!    channel's ray is propagated along it through the real interactions
//!    ([`optics::interaction`]) into an [`Arrival`] — under complex Fresnel and, alongside, the
//!    paper's rules.
//! 4. **Accumulation** ([`accumulate`]): each arrival becomes a [`Contribution`] at a rung of
//!    the [`Fidelity`] ladder ([`trace::contributions`]); contributions are grouped by
//!    coherence id, fields summed with their path phasors, groups added in intensity (the
//!    paper's eqs. 5–6). [`accumulate::fidelity::auto_select`] names the cheapest exact rung.
//! 5. **Observables** ([`optics::observable`]): |E|² at a point, R or T in the far field, and
//!    quantities derived from them (retardance, fringe spacing, visibility).
//! 6. **Comparison** ([`harness::analytic`], [`harness::case`], [`harness::check`]): closed
//!    forms evaluated independently of the tracer, case files that pair a scene with its closed
//!    forms and tolerances, and the gate `fringe check` with its reports ([`output::report`]).
//!
//! # Layout
//!
//! The modules are grouped by layer, each using only the layers before it (the test
//! `layers::every_layer_uses_only_the_layers_before_it` reads the sources and fails on an
//! upward use):
//!
//! * [`io`]: atomic files, folder locks, bless sets, CSV text (knows nothing of optics);
//! * [`optics`]: pure kernels — Fresnel coefficients, media, the polarized ray and its ledger,
//!   a ray meeting an interface, observables, double-double optical paths;
//! * [`scene`]: planes and the surfaces built from them, sources;
//! * [`accumulate`]: the accumulation core and the fidelity ladder;
//! * [`trace`]: the exact path solver, sequence enumeration, arrivals, forward fans, spectral
//!   beat terms (it builds the accumulation core's contributions, so it comes after it);
//! * [`colour`]: spectra → CIE XYZ → sRGB, CIEDE2000, Newton's colours;
//! * [`harness`]: case files, closed forms, the gate's evaluation and verdict, the stability
//!   sweep, fuzzing, grading and the cost studies;
//! * [`output`]: pictures, reports and figures;
//! * [`cli`]: the commands of the `fringe` binary, which run the harness and write through the
//!   outputs.
//!
//! # The embedding API and the tool's modules
//!
//! A renderer that embeds fringe needs [`optics`], [`scene`], [`trace`] and [`accumulate`]
//! (the types it names most are also at the crate root), [`colour`] to turn spectra into
//! colours, and for the case library [`harness::case`] (load, build and run a case file) with
//! the closed forms of [`harness::analytic`]. These are documented and kept stable.
//!
//! The rest serves the `fringe` tool: [`cli`], [`output`] (pictures with `output::render`;
//! the report and figures are hidden), [`io`], and the harness modules hidden from these docs
//! (the gate and its verdict, the stability sweep, fuzzing, grading, the cost studies). They
//! are public only because the binary and the integration tests (separate crates) use them;
//! what neither uses is `pub(crate)` or private. Count of the public items (rustdoc JSON,
//! hidden items included): `tools/count_pub_items.py`.

//! # Example: a glass plate against the Airy formula
//!
//! A free-standing glass plate (n = 1.5, 2 µm thick) in vacuum, lit by an s-polarized plane
//! wave at 30°; the reflected light is observed in the far field (an ideal lens). Tracing every
//! reflected order with up to 30 internal reflections (order m has 2m − 1 of them, so orders 0
//! to 15) and accumulating them must reproduce the Airy reflectance R = |r|² (docs/PHYSICS.md
//! §5; the omitted amplitude tail is below |r21 r23|^15 ≈ 0.058^15 ≈ 3e-19).
//!
//! ```
//! use fringe::accumulate::Accumulator;
//! use fringe::harness::analytic::plate::{Film, Pol};
//! use fringe::accumulate::fidelity::{self, Fidelity};
//! use fringe::optics::material::Medium;
//! use fringe::trace::path::Target;
//! use fringe::scene::Scene;
//! use fringe::scene::source::{Emitter, Polarization, Source};
//! use fringe::trace::{self, TraceSettings};
//! use glam::DVec3;
//!
//! // Scene: top face at z = 0 with normal +z, vacuum above and below.
//! let thickness_m = 2e-6;
//! let mut scene = Scene::new(Medium::vacuum());
//! scene.add_plate(
//!     "plate",
//!     DVec3::ZERO,
//!     DVec3::Z,
//!     thickness_m,
//!     Medium::vacuum(),
//!     Medium::constant("glass", 1.5),
//!     Medium::vacuum(),
//! );
//!
//! // Source: a plane wave in the x–z plane at θ = 30°, field along y (s polarization), phase 0
//! // on the wavefront through (0, 0, 1 mm).
//! let (sin, cos) = 30f64.to_radians().sin_cos();
//! let reference = DVec3::new(0.0, 0.0, 1e-3);
//! scene.sources.push(Source {
//!     name: "beam".into(),
//!     emitter: Emitter::PlaneWave {
//!         direction: DVec3::new(sin, 0.0, -cos),
//!         reference_point: reference,
//!     },
//!     polarization: Polarization::Linear {
//!         reference: DVec3::Y,
//!         angle_rad: 0.0,
//!     },
//!     intensity: 1.0,
//!     coherence_group: 0,
//!     coherence_length_m: f64::INFINITY,
//! });
//!
//! // Exact paths into the specular far-field direction, up to 30 internal reflections.
//! let lambda_m = 550e-9;
//! let optics = scene.optics(lambda_m).expect("indices defined at 550 nm");
//! let mut settings = TraceSettings::default();
//! settings.limits.max_internal_reflections = 30;
//! settings.limits.max_events = 2 * 30 + 6;
//! let specular = DVec3::new(sin, 0.0, cos);
//! let plan = trace::plan(&scene, &optics, &[reference + 0.02 * specular], &settings.limits);
//! let target = Target::Direction { dir: specular, reference };
//! let (arrivals, _unreached) = trace::arrivals(&scene, &optics, &plan, &target, &settings);
//! assert_eq!(arrivals.len(), 16, "order 0 (top face) and 15 orders through the plate");
//!
//! // Accumulate at the top of the ladder: complex 3D fields summed by coherence group.
//! let mut acc = Accumulator::new();
//! acc.extend(&trace::contributions(&arrivals, Fidelity::Vector));
//! let reflectance = acc.intensity();
//!
//! // Compare with the closed form, evaluated independently of the tracer.
//! let film = Film { n1: 1.0, n2: 1.5, n3: 1.0, thickness_m };
//! let airy = film.reflectance(cos, lambda_m, Pol::S);
//! assert!((reflectance - airy).abs() < 1e-12, "traced {reflectance}, Airy {airy}");
//!
//! // Interfaces without total internal reflection: the paper's rules are exact here too.
//! let auto = fidelity::auto_select(&trace::needs(&arrivals));
//! assert_eq!(auto.level, Fidelity::PaperRules, "{auto}");
//! let paper = trace::intensity(&arrivals, Fidelity::PaperRules);
//! assert!((paper - airy).abs() < 1e-12, "paper_rules {paper}, Airy {airy}");
//! ```
//!
//! The types this example names are also at the crate root (`fringe::Scene`,
//! `fringe::Source`, `fringe::Medium`, `fringe::Accumulator`, `fringe::Fidelity`, …).
//!
//! The same flow runs from a case file with `fringe check` (see `cases/README.md`), which
//! builds the scene ([`harness::case::build`]), traces every probe point
//! ([`harness::case::run`]) and compares with the references named in the file.

#![warn(missing_docs)]

// The embedding API is the optics, the scene, the tracer, accumulation, colour, observables,
// closed forms and case files: every public item is documented (`missing_docs` above,
// crate-wide). The harness behind the `fringe` binary (the gate, reports, sweeps, figures,
// fuzzing, grading) is public only for that binary and the integration tests:
// `#[doc(hidden)]`, not a stable API; what neither needs is `pub(crate)` or private.

// What an embedding renderer needs most, at the crate root (the modules hold the rest).
pub use crate::accumulate::fidelity::{AutoChoice, Fidelity};
pub use crate::accumulate::{Accumulator, Contribution};
pub use crate::harness::analytic::plate::{Film, Pol};
pub use crate::optics::material::{Dispersion, Medium};
pub use crate::scene::source::{Emitter, Polarization, Source};
pub use crate::scene::{Scene, SceneOptics};
pub use crate::trace::path::Target;
pub use crate::trace::{Arrival, TraceSettings};

pub mod accumulate;
pub mod cli;
pub mod colour;
pub mod harness;
pub mod io;
pub mod optics;
pub mod output;
pub mod scene;
pub mod trace;
