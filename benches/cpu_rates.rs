//! CPU-time rates of the work in `benches/accumulate.rs` and `benches/airy.rs`
//! (`airy/spectrum`), for a machine shared with other builds, where criterion's wall times
//! measure the other load: the CPU time of every thread of this process (from
//! `/proc/self/task/*/schedstat`, nanoseconds on the CPU) around a fixed number of repetitions
//! of the same work as the benches, next to the wall time.
//!
//! Run (Linux only):
//!
//! ```text
//! cargo bench -p fringe-benches --bench cpu_rates -- accumulate # 1 M contributions, 16 k points, 4 groups (and 16 k, L2-resident)
//! cargo bench -p fringe-benches --bench cpu_rates -- accumulate-2t # only the 2-thread columns, 50 reps
//! cargo bench -p fringe-benches --bench cpu_rates -- accumulate-l2 # only the L2-resident columns, 6400 reps (for a profiler)
//! cargo bench -p fringe-benches --bench cpu_rates -- spectrum # traced Airy spectrum, 401 λ
//! ```
//!
//! Each line: what, repetitions, wall seconds, CPU seconds, and the rate per wall second and
//! per CPU-second. The numpy baseline of the accumulation is `examples/accumulate_numpy.py`.

mod accumulation_data;
use accumulation_data::data;

#[path = "../tests/suite/support/airy_plate.rs"]
#[allow(dead_code)] // `airy_plate` (n = 1.5) is not used here
mod airy_plate;

use airy_plate::airy_plate_of;
use fringe::accumulate::columns::{
    ColumnKernel, ContributionColumns, accumulate_columns, accumulate_columns_par,
    accumulate_columns_using,
};
use fringe::accumulate::fidelity::Fidelity;
use fringe::accumulate::{Summation, accumulate_points, accumulate_points_par};
use fringe::harness::analytic::plate::{Film, Pol};
use fringe::optics::material::{Dispersion, Medium};
use fringe::scene::Scene;
use fringe::trace::beats::{Beats, vector_rays};
use fringe::trace::path::{EnumerationLimits, Target};
use fringe::trace::{self, TraceSettings, dispersive_sweep, round_trips};
use glam::DVec3;
use std::hint::black_box;
use std::time::Instant;

/// CPU time (s) of every thread of this process so far.
fn cpu_seconds() -> f64 {
    let mut ns = 0u64;
    for task in std::fs::read_dir("/proc/self/task").expect("/proc/self/task (Linux)") {
        let path = task.expect("task entry").path().join("schedstat");
        if let Ok(s) = std::fs::read_to_string(path) {
            ns += s
                .split_whitespace()
                .next()
                .and_then(|v| v.parse::<u64>().ok())
                .unwrap_or(0);
        }
    }
    ns as f64 * 1e-9
}

/// Run `work` `reps` times and print the wall and CPU rates of `items` items per repetition:
/// the mean over all repetitions (total wall and CPU time), and the wall rate of the fastest
/// and of the median repetition (the statistics `examples/accumulate_numpy.py` prints for numpy:
/// compare best with best, median with median).
fn measure(what: &str, reps: usize, items: usize, mut work: impl FnMut()) {
    work(); // warm up (allocations, pools, caches)
    let mut per_rep = Vec::with_capacity(reps);
    let (w0, c0) = (Instant::now(), cpu_seconds());
    for _ in 0..reps {
        let r0 = Instant::now();
        work();
        per_rep.push(r0.elapsed().as_secs_f64());
    }
    let (wall, cpu) = (w0.elapsed().as_secs_f64(), cpu_seconds() - c0);
    per_rep.sort_by(f64::total_cmp);
    let n = (reps * items) as f64;
    println!(
        "{what}: {reps} reps, {wall:.3} s wall, {cpu:.3} CPU-s: {:.2} M/s wall, {:.2} M per CPU-second; best rep {:.2} M/s, median rep {:.2} M/s",
        n / wall / 1e6,
        n / cpu / 1e6,
        items as f64 / per_rep[0] / 1e6,
        items as f64 / per_rep[reps / 2] / 1e6,
    );
}

/// The summations the accumulation rows are measured with.
const SUMMATIONS: [(&str, Summation); 2] = [
    ("plain", Summation::Plain),
    ("compensated", Summation::Compensated),
];

/// A rayon pool of 2 threads (the issue's comparison: 2 threads on the 2-core machine).
fn two_threads() -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("rayon pool")
}

fn accumulate() {
    let (t, p, g) = (1usize << 20, 1usize << 14, 4u64);
    // The data of `benches/accumulate.rs`'s T1M_P16k_G4.
    let (d, offsets) = data(t, p, g, 1);
    let cols = ContributionColumns::from(&d[..]);
    let mut out = vec![0.0; p];
    let pool = two_threads();
    for (name, s) in SUMMATIONS {
        measure(&format!("accumulate T1M_P16k_G4 1t {name}"), 20, t, || {
            accumulate_points(black_box(&d), &offsets, s, &mut out);
            black_box(&out);
        });
        measure(&format!("accumulate T1M_P16k_G4 2t {name}"), 20, t, || {
            pool.install(|| accumulate_points_par(black_box(&d), &offsets, s, &mut out));
            black_box(&out);
        });
        measure(
            &format!("accumulate T1M_P16k_G4 columns 1t {name}"),
            20,
            t,
            || {
                accumulate_columns(black_box(&cols), &offsets, s, &mut out);
                black_box(&out);
            },
        );
        if ColumnKernel::Avx2.available() {
            measure(
                &format!("accumulate T1M_P16k_G4 columns avx2 1t {name}"),
                20,
                t,
                || {
                    accumulate_columns_using(
                        ColumnKernel::Avx2,
                        black_box(&cols),
                        &offsets,
                        s,
                        &mut out,
                    );
                    black_box(&out);
                },
            );
        }
        measure(
            &format!("accumulate T1M_P16k_G4 columns 2t {name}"),
            20,
            t,
            || {
                pool.install(|| accumulate_columns_par(black_box(&cols), &offsets, s, &mut out));
                black_box(&out);
            },
        );
    }
    // The same work L2-resident (16 k contributions, 256 points, 1 MiB of columns): the
    // compute rate alone, which other processes' memory traffic on a shared machine does not
    // change as much as the 64 MiB case above (same total: 20 · 2^20 contributions).
    accumulate_l2(20);
    // The memory floor: a bare streaming read of the same 64 MiB (8 words per contribution).
    let words = accumulation_data::as_words(&d);
    measure("accumulate T1M_P16k_G4 stream read 1t", 20, t, || {
        black_box(accumulation_data::stream_sum(black_box(words)));
    });
    measure("accumulate T1M_P16k_G4 stream read 2t", 20, t, || {
        black_box(pool.install(|| accumulation_data::stream_sum_par(black_box(words))));
    });
}

/// The L2-resident rows of [`accumulate`] (16 k contributions, 256 points, 4 groups, 1 MiB of
/// columns), `rounds` · 64 repetitions each: the compute rate alone (`accumulate-l2`: 100 rounds,
/// for a profiler).
fn accumulate_l2(rounds: usize) {
    let (t2, p2, g) = (1usize << 14, 1usize << 8, 4u64);
    let (d2, offsets2) = data(t2, p2, g, 2);
    let cols2 = ContributionColumns::from(&d2[..]);
    let mut out2 = vec![0.0; p2];
    for (name, s) in SUMMATIONS {
        measure(
            &format!("accumulate T16k_P256_G4 columns 1t {name} (L2)"),
            rounds * 64,
            t2,
            || {
                accumulate_columns(black_box(&cols2), &offsets2, s, &mut out2);
                black_box(&out2);
            },
        );
    }
}

/// A copy of `src` in memory asked to be backed by 2 MiB pages (`madvise(MADV_HUGEPAGE)` on the
/// 2 MiB-aligned interior of the allocation before it is first written), as numpy asks for its
/// own arrays of 4 MiB and more: with transparent huge pages in `madvise` mode (this VM) the
/// kernel then maps those parts with 2 MiB pages.
fn on_huge_pages<T: Copy>(src: &[T]) -> Vec<T> {
    const HUGE: usize = 2 << 20;
    let mut v: Vec<T> = Vec::with_capacity(src.len());
    let start = v.as_ptr() as usize;
    let end = start + std::mem::size_of_val(src);
    let (a, b) = (start.next_multiple_of(HUGE), end / HUGE * HUGE);
    if b > a {
        // SAFETY: [a, b) lies inside the allocation just made (nothing else refers to it);
        // madvise only changes how its pages are backed, never their contents.
        let rc = unsafe { libc::madvise(a as *mut libc::c_void, b - a, libc::MADV_HUGEPAGE) };
        assert_eq!(rc, 0, "madvise(MADV_HUGEPAGE)");
    }
    v.extend_from_slice(src);
    v
}

/// Only the 2-thread column rows of [`accumulate`] (the issue's comparison with numpy), with
/// more repetitions, the columns on ordinary pages and on 2 MiB pages ([`on_huge_pages`], as
/// numpy's own arrays): what `examples/accumulate_ratio.py` runs between numpy's runs.
fn accumulate_2t() {
    let (t, p, g) = (1usize << 20, 1usize << 14, 4u64);
    let (d, offsets) = data(t, p, g, 1);
    let cols = ContributionColumns::from(&d[..]);
    let huge = ContributionColumns {
        coherence_ids: on_huge_pages(&cols.coherence_ids),
        phase_cycles: on_huge_pages(&cols.phase_cycles),
        fields: on_huge_pages(&cols.fields),
    };
    drop(d);
    let mut out = vec![0.0; p];
    let pool = two_threads();
    for (name, s) in SUMMATIONS {
        for (pages, c) in [("", &cols), (" (2 MiB pages)", &huge)] {
            measure(
                &format!("accumulate T1M_P16k_G4 columns 2t {name}{pages}"),
                50,
                t,
                || {
                    pool.install(|| accumulate_columns_par(black_box(c), &offsets, s, &mut out));
                    black_box(&out);
                },
            );
        }
    }
}

/// Settings for the tail bound ε = 1e-12 of a plate of index `n` at `theta` (as the bench).
fn spectrum_settings(theta: f64, n: f64, thickness_m: f64, lambda_m: f64) -> TraceSettings {
    let film = Film {
        n1: 1.0,
        n2: n,
        n3: 1.0,
        thickness_m,
    };
    let orders = [Pol::S, Pol::P]
        .map(|p| film.orders_for_bound(theta.cos(), lambda_m, p, 1e-12))
        .into_iter()
        .max()
        .unwrap();
    let m = 2 * orders + 1;
    TraceSettings {
        limits: EnumerationLimits {
            max_internal_reflections: m,
            max_events: 2 * m + 8,
        },
        ..TraceSettings::default()
    }
}

fn spectrum() {
    const D: f64 = 3.217e-6;
    let theta = 35f64.to_radians();
    let lambdas: Vec<f64> = (0..401).map(|i| 400e-9 + 1e-9 * i as f64).collect();
    let mid = lambdas[200];
    let st = spectrum_settings(theta, 1.7, D, mid);
    let (scene, target) = airy_plate_of(theta, Medium::constant("glass", 1.7), D);
    let trace_once = |scene: &Scene, target: &Target| {
        let optics = scene.optics(mid).expect("indices");
        let plan = trace::plan(scene, &optics, &[DVec3::new(0.0, 0.0, 0.001)], &st.limits);
        trace::arrivals(scene, &optics, &plan, target, &st).0
    };
    let mut beats = Beats::default();
    let mut out = vec![0.0; lambdas.len()];
    measure("airy/spectrum traced_once", 2000, lambdas.len(), || {
        beats.set(&vector_rays(&trace_once(&scene, &target)));
        beats.intensities(&lambdas, &mut out);
        black_box(&out);
    });
    measure("airy/spectrum trace only", 2000, lambdas.len(), || {
        black_box(trace_once(&scene, &target));
    });
    let rays = vector_rays(&trace_once(&scene, &target));
    measure(
        "airy/spectrum phasor batch only",
        2000,
        lambdas.len(),
        || {
            beats.set(&rays);
            beats.intensities(&lambdas, &mut out);
            black_box(&out);
        },
    );
    // The same spectrum by round trips (`trace::round_trips::spectrum`: the first orders
    // traced by the walk, every further one by one exactly applied round trip).
    let probes = [DVec3::new(0.0, 0.0, 0.001)];
    measure("airy/spectrum round_trips", 2000, lambdas.len(), || {
        round_trips::spectrum(
            &scene, &probes, &target, &st, &lambdas, &mut beats, &mut out,
        )
        .expect("indices");
        black_box(&out);
    });
    let optics = scene.optics(mid).expect("indices");
    measure(
        "airy/spectrum round_trips trace only",
        2000,
        lambdas.len(),
        || {
            black_box(round_trips::rays(&scene, &optics, &probes, &target, &st).expect("applies"));
        },
    );
    // 16 spectra (angles 20°–50°) on two threads, as `airy/spectrum/traced_once_2t_16_spectra`.
    let spectra: Vec<(Scene, Target, TraceSettings)> = (0..16)
        .map(|k| {
            let th = (20.0 + 2.0 * k as f64).to_radians();
            let (s, t) = airy_plate_of(th, Medium::constant("glass", 1.7), D);
            (s, t, spectrum_settings(th, 1.7, D, mid))
        })
        .collect();
    let pool = two_threads();
    let sixteen = |route: bool| {
        use rayon::prelude::*;
        pool.install(|| {
            spectra
                .par_iter()
                .map_init(
                    || (Beats::default(), vec![0.0; lambdas.len()]),
                    |(beats, out), (s, t, st)| {
                        if route {
                            round_trips::spectrum(s, &probes, t, st, &lambdas, beats, out)
                                .expect("indices");
                        } else {
                            let optics = s.optics(mid).expect("indices");
                            let plan = trace::plan(s, &optics, &probes, &st.limits);
                            let arr = trace::arrivals(s, &optics, &plan, t, st).0;
                            beats.set(&vector_rays(&arr));
                            beats.intensities(&lambdas, out);
                        }
                        out[0]
                    },
                )
                .sum::<f64>()
        })
    };
    measure(
        "airy/spectrum 16 spectra 2t walk",
        200,
        16 * lambdas.len(),
        || {
            black_box(sixteen(false));
        },
    );
    measure(
        "airy/spectrum 16 spectra 2t round_trips",
        200,
        16 * lambdas.len(),
        || {
            black_box(sixteen(true));
        },
    );
    spectrum_dispersive();
}

/// N-BK7 (Sellmeier): a trace at every wavelength by the general walk; by round trips traced
/// once and swept over the wavelengths (`trace::dispersive_sweep`), on one thread and 16
/// spectra on two (`cpu_rates spectrum` runs it last; `cpu_rates bk7` alone).
fn spectrum_dispersive() {
    const D: f64 = 3.217e-6;
    let theta = 35f64.to_radians();
    let lambdas: Vec<f64> = (0..401).map(|i| 400e-9 + 1e-9 * i as f64).collect();
    let mid = lambdas[200];
    let probes = [DVec3::new(0.0, 0.0, 0.001)];
    let mut beats = Beats::default();
    let mut out = vec![0.0; lambdas.len()];
    let bk7 = Medium {
        name: "N-BK7".into(),
        dispersion: Dispersion::bk7(),
    };
    let st_bk7 = spectrum_settings(theta, bk7.index(mid).expect("index"), D, mid);
    let (scene_bk7, target_bk7) = airy_plate_of(theta, bk7.clone(), D);
    measure(
        "airy/spectrum bk7 per_wavelength walk",
        3,
        lambdas.len(),
        || {
            for (&l, o) in lambdas.iter().zip(out.iter_mut()) {
                let optics = scene_bk7.optics(l).expect("indices");
                let plan = trace::plan(&scene_bk7, &optics, &probes, &st_bk7.limits);
                let arr = trace::arrivals(&scene_bk7, &optics, &plan, &target_bk7, &st_bk7).0;
                *o = trace::intensity(&arr, Fidelity::Vector);
            }
            black_box(&out);
        },
    );
    // Traced once by round trips at the middle wavelength, then a sweep of the indices,
    // Fresnel coefficients and round trip (`trace::dispersive_sweep`).
    measure("airy/spectrum bk7 round_trips", 2000, lambdas.len(), || {
        let route = round_trips::spectrum(
            &scene_bk7,
            &probes,
            &target_bk7,
            &st_bk7,
            &lambdas,
            &mut beats,
            &mut out,
        )
        .expect("indices");
        assert_eq!(route, round_trips::Route::RoundTrips);
        black_box(&out);
    });
    // The sweep alone (set up once): the per-wavelength cost.
    let optics = scene_bk7.optics(mid).expect("indices");
    let sweep = dispersive_sweep::Sweep::new(&scene_bk7, &optics, &probes, &target_bk7, &st_bk7)
        .expect("the sweep holds");
    measure("airy/spectrum bk7 sweep only", 2000, lambdas.len(), || {
        for (&l, o) in lambdas.iter().zip(out.iter_mut()) {
            *o = sweep
                .intensity(&scene_bk7, l)
                .expect("indices")
                .expect("holds");
        }
        black_box(&out);
    });
    // 16 N-BK7 spectra (angles 20°–50°) on two threads, one spectrum per task.
    let spectra: Vec<(Scene, Target, TraceSettings)> = (0..16)
        .map(|k| {
            let th = (20.0 + 2.0 * k as f64).to_radians();
            let (s, t) = airy_plate_of(th, bk7.clone(), D);
            (
                s,
                t,
                spectrum_settings(th, bk7.index(mid).expect("index"), D, mid),
            )
        })
        .collect();
    let pool = two_threads();
    measure(
        "airy/spectrum bk7 16 spectra 2t round_trips",
        200,
        16 * lambdas.len(),
        || {
            use rayon::prelude::*;
            black_box(pool.install(|| {
                spectra
                    .par_iter()
                    .map_init(
                        || (Beats::default(), vec![0.0; lambdas.len()]),
                        |(beats, out), (s, t, st)| {
                            round_trips::spectrum(s, &probes, t, st, &lambdas, beats, out)
                                .expect("indices");
                            out[0]
                        },
                    )
                    .sum::<f64>()
            }));
        },
    );
}

fn main() {
    match std::env::args().nth(1).as_deref() {
        Some("accumulate") => accumulate(),
        Some("accumulate-2t") => accumulate_2t(),
        Some("accumulate-l2") => accumulate_l2(100),
        Some("spectrum") => spectrum(),
        Some("bk7") => spectrum_dispersive(),
        _ => {
            eprintln!("usage: cpu_rates accumulate|accumulate-2t|accumulate-l2|spectrum|bk7");
            std::process::exit(2);
        }
    }
}
