//! The interface rows of the stability sweep: incidence from normal to grazing, the critical
//! angle, and index contrasts from 1e-12 to 1000, each reflection amplitude traced against a
//! closed form in its best-conditioned (sine, tangent, half-angle) form.

use super::*;

/// s or p input, as a source polarization angle about the reference Y (docs/PHYSICS.md §1: for the
/// plane of incidence xz, s ∥ Y and p = d × s).
pub(super) fn pol_angle(pol: Pol) -> f64 {
    match pol {
        Pol::S => 0.0,
        Pol::P => FRAC_PI_2,
    }
}

/// The plane wave of the sweep at `theta` in the xz plane, phase referred to `reference`.
pub(super) fn plane_wave_at(theta: f64, angle_rad: f64, reference: DVec3) -> Source {
    Source {
        name: "beam".into(),
        emitter: Emitter::PlaneWave {
            direction: DVec3::new(theta.sin(), 0.0, -theta.cos()),
            reference_point: reference,
        },
        polarization: Polarization::Linear {
            reference: DVec3::Y,
            angle_rad,
        },
        intensity: 1.0,
        coherence_group: 0,
        coherence_length_m: f64::INFINITY,
    }
}

/// [`plane_wave_at`] with the reference 1 mm above the interface.
fn plane_wave(theta: f64, angle_rad: f64) -> Source {
    plane_wave_at(theta, angle_rad, DEFAULT_REFERENCE)
}

/// The sweep's default phase reference of a plane wave: 1 mm above the film.
pub(super) const DEFAULT_REFERENCE: DVec3 = DVec3::new(0.0, 0.0, 1e-3);

/// The traced reflection amplitude r_s or r_p of one unbounded interface n1 | n2 (the plane
/// z = 0, n1 above) for a plane wave at angle θ, read from the traced 3D field in the frame of
/// docs/PHYSICS.md §1. NaN if the tracer finds no reflected ray.
fn traced_r(n1: f64, n2: f64, theta: f64, pol: Pol) -> Complex64 {
    let nan = Complex64::new(f64::NAN, f64::NAN);
    let mut scene = Scene::new(Medium::constant("n1", n1));
    scene.add_interface(
        "interface",
        crate::scene::geometry::Plane::new(DVec3::ZERO, DVec3::Z),
        Medium::constant("n1", n1),
        Medium::constant("n2", n2),
    );
    let source = plane_wave(theta, pol_angle(pol));
    let d_i = match source.emitter {
        Emitter::PlaneWave { direction, .. } => direction.normalize(),
        _ => return nan,
    };
    let e_i = source.channels()[0].field_direction(d_i);
    scene.sources.push(source);
    let Ok(optics) = scene.optics(WAVELENGTH_M) else {
        return nan;
    };
    let d_r = fresnel::reflect(d_i, DVec3::Z);
    let reference = DVec3::new(0.0, 0.0, 1e-3);
    let target = Target::Direction {
        dir: d_r,
        reference,
    };
    let limits = EnumerationLimits {
        max_internal_reflections: 0,
        max_events: 1,
    };
    let plan = trace::plan(&scene, &optics, &[reference], &limits);
    let (arr, _) = trace::arrivals(&scene, &optics, &plan, &target, &TraceSettings::default());
    let reflect = [Event {
        surface: 0,
        kind: EventKind::Reflect,
    }];
    let Some(a) = arr.iter().find(|a| a.path.sequence == reflect[..]) else {
        return nan;
    };
    let s = fresnel::s_direction(d_i, DVec3::Z, DVec3::Y);
    let (e_in, e_out) = match pol {
        Pol::S => (s, s),
        Pol::P => (d_i.cross(s), a.vector.dir.cross(s)),
    };
    let field = a.vector.field();
    let along = |v: DVec3| field[0] * v.x + field[1] * v.y + field[2] * v.z;
    along(e_out) / e_i.dot(e_in)
}

/// θt from Snell's law (outside total internal reflection).
fn theta_t(n1: f64, n2: f64, theta: f64) -> f64 {
    (n1 / n2 * theta.sin()).asin()
}

/// r_s by the sine form −sin(θi − θt)/sin(θi + θt) (B&W §1.5.2), independent of (P1).
fn r_s_sine(n1: f64, n2: f64, theta: f64) -> f64 {
    let t = theta_t(n1, n2, theta);
    -(theta - t).sin() / (theta + t).sin()
}

/// r_p by the tangent form tan(θi − θt)/tan(θi + θt) (B&W §1.5.2), independent of (P2).
fn r_p_tangent(n1: f64, n2: f64, theta: f64) -> f64 {
    let t = theta_t(n1, n2, theta);
    (theta - t).tan() / (theta + t).tan()
}

/// Normal, 1e-12 rad, Brewster ± 1e-12, 89.9999° and exactly grazing, air → glass 1.5.
pub(super) fn incidence_rows(rows: &mut Vec<StabilityRow>) {
    use DeviationKind::*;
    let g = "incidence";
    let (n1, n2) = (1.0, 1.5);
    let r0 = (n1 - n2) / (n1 + n2);
    // Normal and near-normal incidence: r_s = (n1 − n2)/(n1 + n2), r_p = −r_s in this frame
    // (P1, P2 at θ = 0; the O(θ²) terms are 1e-24 at 1e-12 rad).
    for (theta, label) in [(0.0, "θ = 0"), (1e-12, "θ = 1e-12 rad")] {
        for (pol, exact) in [(Pol::S, r0), (Pol::P, -r0)] {
            rows.push(StabilityRow::new(
                g,
                format!("{label}, {}, n 1 → 1.5", pol_name(pol)),
                &format!("r_{} (real)", pol_name(pol)),
                traced_r(n1, n2, theta, pol).re,
                exact,
                Absolute,
                Some(1e-14),
            ));
        }
    }
    // Brewster ± 1e-12: first order in ε = θ − θB, r_p = −(n⁴ − 1)/(2n³)·ε (n = n2/n1): from
    // the tangent form, tan(θ + θt) ≈ −1/((1 + 1/n²)ε) and tan(θB − θtB) = (n² − 1)/(2n).
    // ε is formed from the f64 angles (exact subtraction); its O(ε²) remainder is 1e-24.
    let tb = brewster_angle(n1, n2);
    let n = n2 / n1;
    for (theta, label) in [(tb - 1e-12, "θB − 1e-12"), (tb + 1e-12, "θB + 1e-12")] {
        let eps = theta - tb;
        rows.push(StabilityRow::new(
            g,
            format!("θ = {label} rad, p, n 1 → 1.5"),
            "r_p (real)",
            traced_r(n1, n2, theta, Pol::P).re,
            -(n.powi(4) - 1.0) / (2.0 * n.powi(3)) * eps,
            Relative,
            Some(1e-3),
        ));
    }
    // 89.9999°: sine and tangent forms, well conditioned there.
    let theta = 89.9999f64.to_radians();
    rows.push(StabilityRow::new(
        g,
        format!("θ = {}, s, n 1 → 1.5", deg(theta)),
        "r_s (real)",
        traced_r(n1, n2, theta, Pol::S).re,
        r_s_sine(n1, n2, theta),
        Absolute,
        Some(1e-14),
    ));
    rows.push(StabilityRow::new(
        g,
        format!("θ = {}, p, n 1 → 1.5", deg(theta)),
        "r_p (real)",
        traced_r(n1, n2, theta, Pol::P).re,
        r_p_tangent(n1, n2, theta),
        Absolute,
        Some(1e-14),
    ));
    // Exactly grazing: no ray meets a plane at 90°, so the Fresnel kernel the tracer calls is
    // evaluated directly; the limit of (P1), (P2) is r_s = r_p = −1 (all light reflected).
    let f = fresnel::fresnel(n1, n2, 0.0);
    for (pol, r) in [(Pol::S, f.r_s), (Pol::P, f.r_p)] {
        rows.push(StabilityRow::new(
            g,
            format!(
                "θ = 90° exactly, {} (Fresnel kernel: no ray meets the plane)",
                pol_name(pol)
            ),
            &format!("r_{} (real)", pol_name(pol)),
            r.re,
            -1.0,
            Absolute,
            Some(0.0),
        ));
    }
}

/// Glass 1.5 → air at θc ± 1e-12, the Fresnel rhomb angle and 89.9999°.
pub(super) fn critical_rows(rows: &mut Vec<StabilityRow>) {
    use DeviationKind::*;
    let g = "critical angle";
    let (n1, n2) = (1.5, 1.0);
    let Some(tc) = critical_angle(n1, n2) else {
        return;
    };
    // Just below θc: 1 − r_s = 2 n2 cos θt/(n1 cos θ + n2 cos θt) (from the cosine form, but with
    // cos θt = (n1/n2)·sqrt(sin(θc − θ)·sin(θc + θ)) in place of Snell's cancelling difference).
    let theta = tc - 1e-12;
    let cos_t = n1 / n2 * ((tc - theta).sin() * (tc + theta).sin()).sqrt();
    let one_minus = 2.0 * n2 * cos_t / (n1 * theta.cos() + n2 * cos_t);
    rows.push(StabilityRow::new(
        g,
        "θ = θc − 1e-12 rad, s, n 1.5 → 1".into(),
        "1 − r_s",
        1.0 - traced_r(n1, n2, theta, Pol::S).re,
        one_minus,
        Relative,
        Some(1e-3),
    ));
    // Total internal reflection: |r| = 1 and the retardance |Δ| = |arg r_p − arg r_s| from
    // tan(|Δ|/2) = cos θ·sqrt(sin²θ − n21²)/sin²θ (docs/PHYSICS.md §1).
    let retardance = |theta: f64| {
        let s2 = theta.sin().powi(2);
        let root = ((theta - tc).sin() * (theta + tc).sin()).sqrt();
        2.0 * (theta.cos() * root / s2).atan()
    };
    let rhomb = 54.6f64.to_radians();
    for (theta, label, tol) in [
        (tc + 1e-12, "θ = θc + 1e-12 rad".to_string(), 1e-3),
        (rhomb, format!("θ = {} (Fresnel rhomb)", deg(rhomb)), 1e-12),
        (
            89.9999f64.to_radians(),
            format!("θ = {}", deg(89.9999f64.to_radians())),
            1e-9,
        ),
    ] {
        let rs = traced_r(n1, n2, theta, Pol::S);
        let rp = traced_r(n1, n2, theta, Pol::P);
        for (pol, r) in [(Pol::S, rs), (Pol::P, rp)] {
            rows.push(StabilityRow::new(
                g,
                format!("{label}, {}, TIR n 1.5 → 1", pol_name(pol)),
                &format!("|r_{}|", pol_name(pol)),
                r.norm(),
                1.0,
                Absolute,
                Some(1e-14),
            ));
        }
        // At the rhomb angle the closed form is analytic::tir's half-angle formula.
        let exact = if theta == rhomb {
            tir::retardance_magnitude(n1, n2, theta)
        } else {
            retardance(theta)
        };
        rows.push(StabilityRow::new(
            g,
            format!("{label}, TIR n 1.5 → 1"),
            "retardance |arg r_p − arg r_s| (rad)",
            (rp * rs.conj()).arg().abs(),
            exact,
            Relative,
            Some(tol),
        ));
    }
}

/// n1 = n2, n2 − n1 = 1e-12, and n = 4.
pub(super) fn index_rows(rows: &mut Vec<StabilityRow>) {
    use DeviationKind::*;
    let g = "indices";
    // No interface: r = 0 at every angle.
    for theta in [0.0, 60f64.to_radians()] {
        for pol in [Pol::S, Pol::P] {
            rows.push(StabilityRow::new(
                g,
                format!("n1 = n2 = 1.5, θ = {}, {}", deg(theta), pol_name(pol)),
                &format!("r_{} (real)", pol_name(pol)),
                traced_r(1.5, 1.5, theta, pol).re,
                0.0,
                Absolute,
                Some(1e-14),
            ));
        }
    }
    // n2 − n1 = 1e-12: r_s = −Δn/(2n + Δn) exactly at θ = 0 (P1), −Δn/(2 n cos²θ) to first order
    // at 60° (derivative of the sine form with Snell); Δn is the exact f64 difference.
    let n1 = 1.5;
    let n2 = n1 + 1e-12;
    let dn = n2 - n1;
    let c60 = 60f64.to_radians().cos();
    for (theta, exact) in [
        (0.0, -dn / (2.0 * n1 + dn)),
        (60f64.to_radians(), -dn / (2.0 * n1 * c60 * c60)),
    ] {
        rows.push(StabilityRow::new(
            g,
            format!("n2 − n1 = 1e-12 (n1 = 1.5), θ = {}, s", deg(theta)),
            "r_s (real)",
            traced_r(n1, n2, theta, Pol::S).re,
            exact,
            Relative,
            Some(1e-3),
        ));
    }
    // A large index: sine and tangent forms (cos θ = 1 uses (1 − n)/(1 + n)).
    for theta in [0.0, 60f64.to_radians(), 0.01f64.acos()] {
        for pol in [Pol::S, Pol::P] {
            let exact = match (pol, theta == 0.0) {
                (Pol::S, true) => (1.0 - 4.0) / (1.0 + 4.0),
                (Pol::P, true) => -(1.0 - 4.0) / (1.0 + 4.0),
                (Pol::S, false) => r_s_sine(1.0, 4.0, theta),
                (Pol::P, false) => r_p_tangent(1.0, 4.0, theta),
            };
            rows.push(StabilityRow::new(
                g,
                format!("n 1 → 4, θ = {}, {}", deg(theta), pol_name(pol)),
                &format!("r_{} (real)", pol_name(pol)),
                traced_r(1.0, 4.0, theta, pol).re,
                exact,
                Absolute,
                Some(1e-14),
            ));
        }
    }
}
