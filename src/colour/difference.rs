//! CIELAB and the CIEDE2000 colour difference.

/// XYZ → CIE 1976 L*a*b* relative to `white` (XYZ of the reference white, same scale as
/// `xyz`), CIE 15:2004 §8.2.1, with the exact CIE constants ε = 216/24389, κ = 24389/27:
///
/// ```text
/// f(t) = t^(1/3) if t > ε, else (κ t + 16)/116
/// L* = 116 f(Y/Yn) − 16,  a* = 500 (f(X/Xn) − f(Y/Yn)),  b* = 200 (f(Y/Yn) − f(Z/Zn))
/// ```
pub fn xyz_to_lab(xyz: [f64; 3], white: [f64; 3]) -> [f64; 3] {
    const EPSILON: f64 = 216.0 / 24389.0;
    const KAPPA: f64 = 24389.0 / 27.0;
    let f = |t: f64| {
        if t > EPSILON {
            t.cbrt()
        } else {
            (KAPPA * t + 16.0) / 116.0
        }
    };
    let [fx, fy, fz] = std::array::from_fn(|c| f(xyz[c] / white[c]));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// Hue angle atan2(b, a) in degrees in [0, 360), and 0 for a = b = 0 (Sharma et al. eq. 4).
fn hue_deg(a: f64, b: f64) -> f64 {
    if a == 0.0 && b == 0.0 {
        0.0
    } else {
        b.atan2(a).to_degrees().rem_euclid(360.0)
    }
}

/// CIEDE2000 colour difference ΔE00 between two CIELAB colours (kL = kC = kH = 1), following
/// G. Sharma, W. Wu, E. N. Dalal, "The CIEDE2000 color-difference formula: implementation
/// notes, supplementary test data, and mathematical observations", Color Res. Appl. 30(1),
/// 21–30 (2005), equations (1)–(22); CIE 142-2001. Angles in degrees as in the paper.
pub fn delta_e_2000(lab1: [f64; 3], lab2: [f64; 3]) -> f64 {
    let [l1, a1, b1] = lab1;
    let [l2, a2, b2] = lab2;
    const POW25_7: f64 = 6_103_515_625.0; // 25^7

    // Step 1: a' (eq. 2–3), C' and h' (eq. 4–6).
    let c_mean_ab = 0.5 * (a1.hypot(b1) + a2.hypot(b2));
    let c7 = c_mean_ab.powi(7);
    let g = 0.5 * (1.0 - (c7 / (c7 + POW25_7)).sqrt());
    let (a1p, a2p) = ((1.0 + g) * a1, (1.0 + g) * a2);
    let (c1p, c2p) = (a1p.hypot(b1), a2p.hypot(b2));
    let (h1p, h2p) = (hue_deg(a1p, b1), hue_deg(a2p, b2));

    // Step 2: ΔL', ΔC', Δh', ΔH' (eq. 8–11).
    let delta_lp = l2 - l1;
    let delta_cp = c2p - c1p;
    let chroma_product = c1p * c2p;
    let delta_hp = if chroma_product == 0.0 {
        0.0
    } else {
        let d = h2p - h1p;
        if d > 180.0 {
            d - 360.0
        } else if d < -180.0 {
            d + 360.0
        } else {
            d
        }
    };
    let delta_big_hp = 2.0 * chroma_product.sqrt() * (0.5 * delta_hp).to_radians().sin();

    // Step 3: means, weighting functions and rotation term (eq. 12–22).
    let l_mean = 0.5 * (l1 + l2);
    let c_mean = 0.5 * (c1p + c2p);
    let h_mean = if chroma_product == 0.0 {
        h1p + h2p
    } else if (h1p - h2p).abs() <= 180.0 {
        0.5 * (h1p + h2p)
    } else if h1p + h2p < 360.0 {
        0.5 * (h1p + h2p + 360.0)
    } else {
        0.5 * (h1p + h2p - 360.0)
    };
    let cos_deg = |x: f64| x.to_radians().cos();
    let t = 1.0 - 0.17 * cos_deg(h_mean - 30.0)
        + 0.24 * cos_deg(2.0 * h_mean)
        + 0.32 * cos_deg(3.0 * h_mean + 6.0)
        - 0.20 * cos_deg(4.0 * h_mean - 63.0);
    let delta_theta = 30.0 * (-((h_mean - 275.0) / 25.0).powi(2)).exp();
    let cm7 = c_mean.powi(7);
    let r_c = 2.0 * (cm7 / (cm7 + POW25_7)).sqrt();
    let l50 = (l_mean - 50.0).powi(2);
    let s_l = 1.0 + 0.015 * l50 / (20.0 + l50).sqrt();
    let s_c = 1.0 + 0.045 * c_mean;
    let s_h = 1.0 + 0.015 * c_mean * t;
    let r_t = -(2.0 * delta_theta).to_radians().sin() * r_c;

    let (dl, dc, dh) = (delta_lp / s_l, delta_cp / s_c, delta_big_hp / s_h);
    (dl * dl + dc * dc + dh * dh + r_t * dc * dh).sqrt()
}
