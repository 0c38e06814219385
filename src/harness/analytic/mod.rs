//! Closed-form references, one file per family. Each function cites the equation it evaluates
//! (docs/PHYSICS.md numbering, the paper, or Born & Wolf). They share only the Fresnel kernels of
//! [`crate::optics::fresnel`] (themselves pinned by tests against independently derived values); all
//! geometry (distances, angles, lateral offsets) is solved here independently of the tracer's
//! path solver.

pub mod coherence;
pub mod lloyd;
pub mod michelson;
pub mod plate;
pub mod precise;
pub mod tir;
pub mod wedge;
pub mod young;

use num_complex::Complex64;

/// Phasor e^{i 2π s/λ} of an optical path s (m) at vacuum wavelength λ (m) (docs/PHYSICS.md §1).
pub fn path_phasor(s_m: f64, lambda_m: f64) -> Complex64 {
    crate::accumulate::phasor_from_cycles(s_m / lambda_m)
}

/// Solve f(x) = 0 on [a, b] by bisection to the last bit (f must change sign).
pub(crate) fn bisect(mut a: f64, mut b: f64, f: impl Fn(f64) -> f64) -> f64 {
    let mut fa = f(a);
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        let fm = f(m);
        if (fm < 0.0) == (fa < 0.0) {
            a = m;
            fa = fm;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}
