//! The table-driven 8-bit sRGB conversion (`fringe::colour::to_srgb8`) against the `powf` path
//! it replaces (`to_srgb8_powf`: round(255 V(L)) with V the IEC 61966-2-1 transfer curve, eq.
//! (5.3)): the same byte for every input tried, at and around every threshold, over random
//! values on every scale and for the special values; the thresholds are the exact curve's.

use fringe::colour::{srgb8_thresholds, to_srgb8, to_srgb8_powf};

/// splitmix64: a fixed, dependency-free stream of random bits.
struct Stream(u64);

impl Stream {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn assert_same(l: f64) {
    let (t, p) = (to_srgb8([l, l, l]), to_srgb8_powf([l, l, l]));
    assert_eq!(t, p, "L = {l:e} ({:#018x})", l.to_bits());
}

/// The threshold of code k is the exact curve's: L_k = V⁻¹((k − ½)/255), with V⁻¹ the IEC
/// 61966-2-1 eq. (5.1) written out here (v/12.92 below 0.04045, ((v + 0.055)/1.055)^2.4 above),
/// to within 1e-13 relative (the `powf` path's own rounding moves it by a few ulps at most);
/// the thresholds increase strictly, so every code 0–255 is reached.
#[test]
fn srgb8_thresholds_are_the_transfer_curve_at_half_codes() {
    let t = srgb8_thresholds();
    for (i, &l) in t.iter().enumerate() {
        let v = (i as f64 + 0.5) / 255.0;
        let exact = if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        };
        assert!(
            (l - exact).abs() <= 1e-13 * exact,
            "code {}: threshold {l:e}, curve {exact:e}",
            i + 1
        );
        if i > 0 {
            assert!(
                t[i - 1] < l,
                "thresholds {} and {} not increasing",
                i,
                i + 1
            );
        }
    }
}

/// At and around every threshold (±64 ulps) the table gives the `powf` path's byte, and the
/// `powf` path steps from k − 1 to k exactly there: it never steps down near a threshold, so
/// "the number of thresholds at or below L" is its code (and it is constant between
/// thresholds, where both are checked on random values below).
#[test]
fn srgb8_table_equals_the_powf_path_around_every_threshold() {
    for (i, &t) in srgb8_thresholds().iter().enumerate() {
        let k = i as u8 + 1;
        let bits = t.to_bits();
        for d in 1..=64u64 {
            let below = f64::from_bits(bits - d);
            let above = f64::from_bits(bits + d - 1);
            assert_same(below);
            assert_same(above);
            assert_eq!(to_srgb8_powf([below; 3])[0], k - 1, "below code {k}");
            assert_eq!(to_srgb8_powf([above; 3])[0], k, "at/above code {k}");
        }
    }
}

/// Random values: uniform in [0, 1] (2 M), log-uniform from 1e-300 to 1 (the dark end and the
/// linear segment, 1 M), uniform in [−0.5, 1.5] (clipping, 1 M), and the special values.
#[test]
fn srgb8_table_equals_the_powf_path_on_random_and_special_values() {
    let mut s = Stream(0x5eed_0014);
    for _ in 0..2_000_000 {
        assert_same(s.unit());
    }
    for _ in 0..1_000_000 {
        assert_same(10f64.powf(-300.0 * s.unit()));
    }
    for _ in 0..1_000_000 {
        assert_same(2.0 * s.unit() - 0.5);
    }
    for l in [
        0.0,
        -0.0,
        1.0,
        f64::from_bits(1),
        f64::MIN_POSITIVE,
        0.0031308,
        0.04045 / 12.92,
        1.0 - f64::EPSILON / 2.0,
        1.0 + f64::EPSILON,
        -1e-300,
        -1.0,
        2.0,
        1e300,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NAN,
        -f64::NAN,
    ] {
        assert_same(l);
    }
    // Channels are independent.
    assert_eq!(
        to_srgb8([0.0, 0.214_041_140_482_232_53, 1.0]),
        to_srgb8_powf([0.0, 0.214_041_140_482_232_53, 1.0])
    );
}
