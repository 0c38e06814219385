//! Tests of single functions that lived as `#[cfg(test)]` modules in src/ (moved here so the
//! library is not compiled a second time, at opt-level 3, as its own unit-test harness:
//! `[lib] test = false` in Cargo.toml). One module per source file, named after it.

/// `src/trace/sequence_tree.rs`
mod sequence_tree {
    use fringe::trace::path::{Event, EventKind, Sequence};
    use fringe::trace::sequence_tree::SequenceTree;

    fn ev(surface: usize, reflect: bool) -> Event {
        Event {
            surface,
            kind: if reflect {
                EventKind::Reflect
            } else {
                EventKind::Refract
            },
        }
    }

    #[test]
    fn the_walk_gives_the_sorted_deduplicated_sequences_and_subtree_ends() {
        let (r0, t0, r1, t1) = (ev(0, true), ev(0, false), ev(1, true), ev(1, false));
        let given = vec![
            vec![t0, r1, t0],
            vec![r0],
            vec![t0, t1],
            vec![],
            vec![t0, r1, r0, r1, t0],
            vec![r0],
        ];
        let tree = SequenceTree::from_sequences(given.clone());
        let mut want = given;
        want.sort();
        want.dedup();
        assert_eq!(tree.sequences(), want);
        assert_eq!(tree.len(), 5);
        // Nodes: [], R0, T0, T0R1, T0R1R0, T0R1R0R1, T0R1R0R1T0, T0R1T0, T0T1.
        let depths: Vec<usize> = tree.nodes().iter().map(|n| n.depth).collect();
        assert_eq!(depths, vec![0, 1, 1, 2, 3, 4, 5, 3, 2]);
        let ends: Vec<usize> = tree.nodes().iter().map(|n| n.subtree_end).collect();
        assert_eq!(ends, vec![9, 2, 9, 8, 7, 7, 7, 8, 9]);
        let candidates: Vec<bool> = tree.nodes().iter().map(|n| n.candidate).collect();
        assert_eq!(
            candidates,
            vec![true, true, false, false, false, false, true, true, true]
        );
    }

    #[test]
    fn deep_trees_walk_like_shallow_ones() {
        // Zig-zags of 1..=45 events and their transmitted ends: deeper than the stack buffer.
        let zigzag = |k: usize| (0..k).map(|i| ev(i % 2, true)).collect::<Vec<_>>();
        let mut given: Vec<Sequence> = (1..=45).map(zigzag).collect();
        given.extend((1..=44).map(|k| {
            let mut s = zigzag(k);
            s.push(ev(k % 2, false));
            s
        }));
        let tree = SequenceTree::from_sequences(given.clone());
        given.sort();
        assert_eq!(tree.sequences(), given);
        assert_eq!(tree.nodes().iter().map(|n| n.depth).max(), Some(45));
    }
}

/// `src/optics/observable.rs`
mod observable {
    use fringe::optics::observable::{Observable, Returns, check_match, power_factor};
    use glam::DVec3;

    /// 1 → 1.5 at normal incidence: |t|² = (2/2.5)² = 0.64 but T = 1.5·0.64 = 0.96 = 1 − R
    /// with R = (0.5/2.5)² = 0.04 (B&W §1.5.3).
    #[test]
    fn power_factor_turns_t_squared_into_transmittance_at_normal_incidence() {
        let f = power_factor(1.0, -DVec3::Z, 1.5, -DVec3::Z, DVec3::Z);
        let t2 = (2.0f64 / 2.5).powi(2);
        let r = (0.5f64 / 2.5).powi(2);
        assert!((f * t2 + r - 1.0).abs() < 1e-15, "T + R = {}", f * t2 + r);
    }

    #[test]
    fn mismatched_observables_are_refused_and_matched_ones_accepted() {
        assert!(check_match("airy", Returns::Power, Observable::Transmittance).is_ok());
        assert!(check_match("airy", Returns::Power, Observable::FieldIntensity).is_err());
        assert!(check_match("young", Returns::FieldIntensity, Observable::Reflectance).is_err());
        assert!(check_match("beams", Returns::AsProbe, Observable::Reflectance).is_ok());
    }
}

/// `src/optics/double_double.rs`
mod double_double {
    use fringe::optics::double_double::*;
    use glam::DVec3;

    #[test]
    fn two_sum_and_two_prod_are_exact() {
        // 1 + 2⁻⁶⁰ is not an f64: the sum keeps the small part in lo.
        let s = two_sum(1.0, 2f64.powi(-60));
        assert_eq!((s.hi, s.lo), (1.0, 2f64.powi(-60)));
        // (1 + 2⁻³⁰)² = 1 + 2⁻²⁹ + 2⁻⁶⁰.
        let a = 1.0 + 2f64.powi(-30);
        let p = two_prod(a, a);
        assert_eq!((p.hi, p.lo), (1.0 + 2f64.powi(-29), 2f64.powi(-60)));
        // 0.1 − 0.1·(1 + 2⁻⁵²) as an exact difference.
        let b = 0.1 * (1.0 + f64::EPSILON);
        let d = two_diff(0.1, b);
        assert_eq!(d.hi + d.lo, 0.1 - b);
    }

    /// x = m·2^e exactly, m an odd integer of at most 53 bits (m = 0 for 0); finite x only.
    fn integer_and_exponent(x: f64) -> (i128, i32) {
        let bits = x.to_bits();
        let sign = if bits >> 63 == 1 { -1 } else { 1 };
        let biased = ((bits >> 52) & 0x7ff) as i32;
        let frac = (bits & ((1u64 << 52) - 1)) as i128;
        let (m, e) = if biased == 0 {
            (frac, -1074)
        } else {
            (frac | (1 << 52), biased - 1075)
        };
        if m == 0 {
            return (0, 0);
        }
        let tz = m.trailing_zeros();
        (sign * (m >> tz), e + tz as i32)
    }

    /// Whether hi + lo = a·b exactly (a, b ≠ 0), in integer arithmetic (no floating point):
    /// every term is an integer times a power of two, brought to the exponent of a·b's last bit
    /// (hi and lo, if they sum to a·b, are multiples of it).
    fn sums_exactly_to_the_product(a: f64, b: f64, hi: f64, lo: f64) -> bool {
        let ((ma, ea), (mb, eb)) = (integer_and_exponent(a), integer_and_exponent(b));
        let e0 = ea + eb;
        let at = |x: f64| {
            let (m, e) = integer_and_exponent(x);
            if m == 0 {
                return Some(0);
            }
            let shift = u32::try_from(e - e0).ok().filter(|&s| s < 120)?;
            let v = m << shift;
            (v >> shift == m).then_some(v)
        };
        match (at(hi), at(lo)) {
            (Some(h), Some(l)) => ma * mb == h + l,
            _ => false,
        }
    }

    /// `two_prod` returns the exact rounding error of the product (hi + lo = a·b), checked in
    /// integer arithmetic on adversarial factors (all-ones significands, which make the largest
    /// errors; powers of two; 26- and 27-bit significands, where a Veltkamp split would cut;
    /// extreme and subnormal magnitudes; signs)
    /// and on pseudo-random ones over the whole exponent range; and non-finite products keep
    /// IEEE's answers.
    #[test]
    fn two_prod_is_the_exact_error_of_the_product() {
        let ones = 2.0 - f64::EPSILON; // 1.11…1 (53 ones)
        let mut special = vec![
            1.0,
            ones,
            1.0 + f64::EPSILON,
            1.0 + 2f64.powi(-26),
            1.0 + 2f64.powi(-27),
            1.0 - 2f64.powi(-27),
            (1u64 << 26) as f64 - 1.0,
            ((1u64 << 27) - 1) as f64,
            134_217_729.0,
            0.1,
            1.0 / 3.0,
            std::f64::consts::PI,
            2f64.powi(450),
            2f64.powi(450) * ones,
            2f64.powi(-450),
            2f64.powi(-450) * ones,
            2f64.powi(451),
            2f64.powi(-451) * ones,
            1e300,
            1e-300,
            f64::MIN_POSITIVE,
            5e-324,
            0.0,
        ];
        special.extend(special.clone().iter().map(|x| -x));
        let mut factors = special.clone();
        // SplitMix64: significands and exponents over the whole finite range.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            z ^ (z >> 31)
        };
        for _ in 0..4000 {
            let r = next();
            let exponent = match r % 3 {
                0 => 1023 - 40 + (r >> 8) % 80, // near 1, where paths and indices are
                1 => 1023 - 470 + (r >> 8) % 940, // within 2^±470
                _ => 1 + (r >> 8) % 2046,       // anywhere
            };
            let significand = next() & ((1 << 52) - 1);
            factors.push(f64::from_bits(
                ((r >> 40) & 1) << 63 | exponent << 52 | significand,
            ));
        }
        let mut checked = 0;
        for (i, &a) in factors.iter().enumerate() {
            // Every pair of the special values, and each factor with its neighbours and with
            // every special value.
            let partners = special.iter().chain(factors[i..].iter().take(8));
            for &b in partners {
                let p = two_prod(a, b);
                // Where the error is representable (the product neither overflows nor leaves
                // bits below the subnormal range), hi + lo is a·b exactly.
                let e = (a.abs().log2() + b.abs().log2()).floor();
                if a != 0.0 && b != 0.0 && (-960.0..1000.0).contains(&e) {
                    assert!(
                        sums_exactly_to_the_product(a, b, p.hi, p.lo),
                        "two_prod({a:e}, {b:e}) = {p:?} is not the exact product"
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 20_000, "only {checked} exact checks");
        // An infinite or NaN product is the product, and its error term is not finite.
        for (a, b) in [(f64::INFINITY, 2.0), (f64::NAN, 1.0), (1e300, 1e300)] {
            let p = two_prod(a, b);
            assert_eq!(p.hi.to_bits(), (a * b).to_bits());
            assert!(!p.lo.is_finite(), "two_prod({a:e}, {b:e}) = {p:?}");
        }
    }

    #[test]
    fn sum_of_a_large_and_a_small_path_keeps_both() {
        // 100 m + 1 pm − 100 m = 1 pm (f64 alone keeps 1.4e-14 m steps at 100 m).
        let s = DoubleDouble::from(100.0) + 1e-12 - DoubleDouble::from(100.0);
        let err = (s.to_f64() - 1e-12).abs();
        assert!(
            err <= 1e-28,
            "actual {:e}, expected 1e-12, err {err:e}",
            s.to_f64()
        );
    }

    #[test]
    fn division_recovers_a_double_double_quotient() {
        // (1/3) · 3 and 2/7 against their exact decimal expansions (to ~1e-31).
        let third = DoubleDouble::from(1.0) / DoubleDouble::from(3.0);
        let back = third * 3.0;
        assert_eq!(back.hi, 1.0);
        assert!(back.lo.abs() < 1e-31, "{back:?}");
        // 2/7 = 0.285714285714285714285714285714285714…: hi + lo from the 34-digit value.
        let q = DoubleDouble::from(2.0) / DoubleDouble::from(7.0);
        let hi = 0.285_714_285_714_285_7_f64;
        assert_eq!(q.hi, hi);
        // lo = 2/7 − hi, evaluated in exact rational arithmetic (Python `fractions`) and rounded.
        let lo = 1.586_032_892_321_652e-17;
        assert!((q.lo - lo).abs() < 1e-32, "{q:?} vs lo {lo:e}");
    }

    #[test]
    fn square_root_of_a_square() {
        // √(x²) = x for x = 1 + 2⁻⁴⁰ (x² needs 81 bits: hi + lo).
        let x = 1.0 + 2f64.powi(-40);
        let r = two_prod(x, x).sqrt();
        assert_eq!(r.hi, x);
        assert!(r.lo.abs() <= 1e-31, "lo {:e}", r.lo);
        // √2² = 2 to double-double precision.
        let s2 = DoubleDouble::from(2.0).sqrt();
        let back = s2 * s2 - DoubleDouble::from(2.0);
        assert!(
            back.to_f64().abs() <= 1e-30,
            "√2² − 2 = {:e}",
            back.to_f64()
        );
        assert_eq!(DoubleDouble::ZERO.sqrt(), DoubleDouble::ZERO);
    }

    #[test]
    fn segment_length_of_a_3_4_5_triangle_far_from_the_origin() {
        // The same 3-4-5 µm segment at the origin and 100 m away: exact differences make the
        // two lengths agree to double-double precision.
        let len = |o: DVec3| segment_length(o, o + DVec3::new(3e-6, 4e-6, 0.0));
        let near = len(DVec3::ZERO);
        assert!((near.to_f64() - 5e-6).abs() <= 1e-21);
        let o = DVec3::new(100.0, -37.0, 12.5);
        let b = o + DVec3::new(3e-6, 4e-6, 0.0);
        // The f64 point b is o + (3e-6, 4e-6, 0) rounded; its exact differences give the length.
        let (ex, ey) = (b.x - o.x, b.y - o.y); // exact: Sterbenz (b within a factor 2 of o)
        let expected = ex.hypot(ey);
        let err = (segment_length(o, b).to_f64() - expected).abs();
        assert!(
            err <= 1e-21,
            "actual {:e}, expected {expected:e}",
            segment_length(o, b).to_f64()
        );
    }

    #[test]
    fn segment_length_equals_the_double_double_norm() {
        // The fast sum of squares against the general double-double arithmetic.
        let pts = [
            (DVec3::new(0.1, -0.2, 0.3), DVec3::new(100.0, 3e-7, -12.5)),
            (DVec3::new(1e-12, 0.0, 0.0), DVec3::new(0.0, 1e-12, 1e-12)),
            (
                DVec3::new(567.0, 0.0, 1e-3),
                DVec3::new(567.0 + 1e-6, 0.0, -2e-6),
            ),
        ];
        for (a, b) in pts {
            let [dx, dy, dz] = difference(a, b);
            let general = (dx * dx + dy * dy + dz * dz).sqrt();
            let fast = segment_length(a, b);
            let err = (fast - general).to_f64().abs();
            assert!(
                err <= 1e-30 * general.hi,
                "{a} → {b}: {fast:?} vs {general:?}"
            );
        }
    }

    #[test]
    fn projection_of_a_far_reference_keeps_the_difference() {
        // x − reference = (0, 0, −100) + (1e-9, 0, 0) along d = z: the projection is −100 m;
        // two points 1 nm apart along d differ by exactly 1 nm.
        let d = DVec3::Z;
        let r = DVec3::new(0.0, 0.0, 100.0);
        let p1 = projection(d, DVec3::new(1e-3, 0.0, 0.0), r);
        let p2 = projection(d, DVec3::new(1e-3, 0.0, 1e-9), r);
        let diff = (p2 - p1).to_f64();
        assert!(
            (diff - 1e-9).abs() <= 1e-25,
            "actual {diff:e}, expected 1e-9"
        );
        assert_eq!(p1.to_f64(), -100.0);
    }
}

/// `src/optics/trail.rs`
mod trail {
    use fringe::optics::trail::Trail;

    #[test]
    fn shared_clones_keep_their_own_ends() {
        let mut a = Trail::shared();
        for i in 0..5 {
            a.push(i);
        }
        let mut b = a.clone();
        b.push(10);
        a.push(20);
        a.push(21);
        assert_eq!(a.to_vec(), vec![0, 1, 2, 3, 4, 20, 21]);
        assert_eq!(b.to_vec(), vec![0, 1, 2, 3, 4, 10]);
        assert_eq!((a.len(), b.len()), (7, 6));
        assert_eq!((a[0], a[4], a[6], b[5]), (0, 4, 21, 10));
        assert_eq!((a.first(), a.last(), a.get(7)), (Some(&0), Some(&21), None));
        // Equality sees elements only, whatever the storage.
        assert_eq!(b, Trail::from(vec![0, 1, 2, 3, 4, 10]));
        assert_ne!(a, b);
        assert_eq!(b, vec![0, 1, 2, 3, 4, 10]);
    }

    #[test]
    fn a_long_shared_trail_drops_without_deep_recursion() {
        let mut t = Trail::shared();
        for i in 0..1_000_000u32 {
            t.push(i);
        }
        let keep = t.clone();
        drop(t);
        assert_eq!(keep.len(), 1_000_000);
        assert_eq!(keep.last(), Some(&999_999));
        drop(keep);
    }
}

/// `src/harness/analytic/precise.rs`
mod precise {
    use fringe::harness::analytic::precise::{distance, path_phasor};
    use glam::DVec3;
    use num_complex::Complex64;
    use twofloat::TwoFloat;

    /// Two distances of 1 m that differ by 1e-13 m: their f64 difference loses ~3 digits,
    /// the double-double one keeps it to ~1e-27 m (the points are exact f64 coordinates).
    #[test]
    fn distances_keep_their_difference() {
        let o = DVec3::ZERO;
        let a = DVec3::new(1.0, 0.0, 0.0);
        let b = DVec3::new(1.0 + 2f64.powi(-43), 0.0, 0.0); // 1.1368683772161603e-13 past a
        let d = distance(b, o) - distance(a, o);
        assert_eq!(f64::from(d), 2f64.powi(-43));
        // Off axis: |(3, 4, 0) + (0, 0, ε)| − 5 = ε²/10 to first order.
        let eps = 1e-6;
        let l = distance(DVec3::new(3.0, 4.0, eps), o) - TwoFloat::from(5.0);
        let exact = eps * eps / (5.0 + (25.0 + eps * eps).sqrt()); // (√(25+ε²) − 5), stable
        // twofloat's square root is good to ~1e-31 relative of the length (5 here), far below
        // what any phase needs; f64 would lose the whole difference (ulp(25) = 3.6e-15).
        assert!(
            (f64::from(l) - exact).abs() <= 1e-13 * exact,
            "actual {:e}, expected {exact:e}",
            f64::from(l)
        );
    }

    /// A path of 10 m + λ/4 has the phasor i whatever the path's size.
    #[test]
    fn phasor_of_a_long_path_keeps_the_quarter_cycle() {
        let lambda = 550e-9;
        let s = TwoFloat::new_mul(lambda, 18_181_818.0) + 0.25 * lambda;
        let p = path_phasor(s, lambda);
        assert!((p - Complex64::i()).norm() < 1e-15, "{p}");
    }
}

/// `src/harness/fuzz/shrink.rs`
mod shrink {
    use fringe::harness::fuzz::draws::DrawKind;
    use fringe::harness::fuzz::shrink::{candidates, round_significant, shrink};

    #[test]
    fn rounding_keeps_the_leading_digits() {
        assert_eq!(round_significant(123.456, 1), 100.0);
        assert_eq!(round_significant(123.456, 2), 120.0);
        assert_eq!(round_significant(-0.0012345, 3), -0.00123);
        assert_eq!(round_significant(0.0, 3), 0.0);
    }

    #[test]
    fn candidates_are_simplest_first_and_exclude_the_value() {
        let c = candidates(2.5, DrawKind::Real { lo: -1.0, hi: 10.0 });
        assert_eq!(&c[..4], &[0.0, 1.0, -1.0, 2.0]);
        assert!(candidates(0.0, DrawKind::Real { lo: -1.0, hi: 1.0 }).is_empty());
        assert_eq!(
            candidates(1.0, DrawKind::Real { lo: -1.0, hi: 1.0 }),
            vec![0.0]
        );
        assert!(!c.contains(&2.5));
        assert_eq!(candidates(2.0, DrawKind::Choice), vec![0.0]);
        assert!(candidates(0.0, DrawKind::Flag).is_empty());
    }

    #[test]
    fn shrinks_to_the_boundary_of_the_failing_region() {
        // "Fails" while x ≥ 3.7 and y anything: x becomes a round number ≥ 3.7, y becomes 0.
        let real = DrawKind::Real { lo: 0.0, hi: 100.0 };
        let out = shrink(vec![17.123456, 5.4321], &[real, real], 1000, |d| {
            d[0] >= 3.7
        });
        assert_eq!(out[1], 0.0);
        assert!(out[0] >= 3.7, "{out:?}");
        assert!(out[0].to_string().len() <= 2, "{out:?}");
    }
}

/// `src/harness/stability/paths.rs`
mod binary32 {
    use fringe::harness::stability::round_to_binary32;

    #[test]
    fn binary32_rounding_of_hand_checked_values() {
        let p = |k: i32| 2f64.powi(k);
        // Ties go to the even significand.
        assert_eq!(round_to_binary32(1.0 + p(-24)), 1.0);
        assert_eq!(round_to_binary32(1.0 + 3.0 * p(-24)), 1.0 + p(-22));
        assert_eq!(round_to_binary32(16_777_217.0), 16_777_216.0);
        assert_eq!(round_to_binary32(16_777_219.0), 16_777_220.0);
        // Just above a tie rounds up; representable values stay.
        assert_eq!(round_to_binary32(1.0 + p(-24) + p(-40)), 1.0 + p(-23));
        assert_eq!(round_to_binary32(1.0 + p(-23)), 1.0 + p(-23));
        // 0.1 in binary32 is 13421773·2^-27 = 0.100000001490116119384765625.
        assert_eq!(round_to_binary32(0.1), 13_421_773.0 * p(-27));
        assert_eq!(round_to_binary32(-0.1), -13_421_773.0 * p(-27));
        // A carry into the exponent: 2 − 2^-25 rounds to 2.
        assert_eq!(round_to_binary32(2.0 - p(-25)), 2.0);
        // Largest finite binary32, overflow, subnormals, zero, NaN.
        let max = (2.0 - p(-23)) * p(127);
        assert_eq!(round_to_binary32(max), max);
        assert_eq!(round_to_binary32(p(128)), f64::INFINITY);
        assert_eq!(round_to_binary32(-p(128)), f64::NEG_INFINITY);
        assert_eq!(round_to_binary32(p(-149)), p(-149));
        assert_eq!(round_to_binary32(p(-150)), 0.0);
        assert_eq!(round_to_binary32(1.5 * p(-149)), p(-148));
        assert_eq!(round_to_binary32(3.0 * p(-130)), 3.0 * p(-130));
        assert_eq!(round_to_binary32(0.0), 0.0);
        assert!(round_to_binary32(f64::NAN).is_nan());
        // The spacing of binary32 at 1 m: 2^-23 above 1, 2^-24 below.
        assert_eq!(round_to_binary32(1.0 + 0.6 * p(-23)), 1.0 + p(-23));
        assert_eq!(round_to_binary32(1.0 - 0.6 * p(-24)), 1.0 - p(-24));
    }

    #[test]
    fn binary32_rounding_is_idempotent_and_monotone() {
        let mut x = 1e-30;
        let mut prev = 0.0;
        while x < 1e30 {
            let r = round_to_binary32(x);
            assert_eq!(round_to_binary32(r), r, "{x:e}");
            assert!(r >= prev, "{x:e}");
            assert!((r - x).abs() <= x * 2f64.powi(-24), "{x:e} → {r:e}");
            prev = r;
            x *= 1.0 + 1e-3;
        }
    }
}

/// `src/harness/stability/mod.rs`
mod stability_csv {
    use fringe::harness::stability::{DeviationKind, StabilityRow, csv};

    #[test]
    fn csv_quotes_fields_with_commas() {
        let r = StabilityRow::new(
            "incidence",
            "θ = 0, s".into(),
            "r_s",
            -0.2,
            -0.2,
            DeviationKind::Absolute,
            Some(1e-14),
        );
        let text = csv(&[r]);
        let line = text.lines().nth(1).unwrap();
        assert!(line.starts_with("incidence,\"θ = 0, s\",r_s,"), "{line}");
        assert!(line.ends_with(",absolute,1e-14,pass"), "{line}");
    }
}

/// `src/output/memory.rs`
mod memory {
    use fringe::output::memory::{BUDGET_VAR, cgroup_room, check_fits, meminfo_bytes};

    #[test]
    fn meminfo_is_read_in_kib() {
        let t = "MemTotal:       24000000 kB\nMemFree: 100 kB\nMemAvailable:   2048 kB\n";
        assert_eq!(meminfo_bytes(t, "MemAvailable"), Some(2048 * 1024));
        assert_eq!(meminfo_bytes(t, "MemFree"), Some(100 * 1024));
        assert_eq!(meminfo_bytes(t, "Cached"), None);
    }

    #[test]
    fn cgroup_room_is_limit_minus_usage() {
        assert_eq!(cgroup_room("1000\n", "300\n"), Some(700));
        assert_eq!(cgroup_room("max\n", "300\n"), None);
        assert_eq!(cgroup_room("100", "300"), Some(0));
    }

    #[test]
    fn refusal_names_both_amounts() {
        assert!(check_fits("x", 10, None).is_ok());
        assert!(check_fits("x", 10, Some(10)).is_ok());
        let e = check_fits("a 900x900 render", 3 << 30, Some(1 << 30)).unwrap_err();
        assert!(
            e.contains("3.0 GiB") && e.contains("1.0 GiB") && e.contains(BUDGET_VAR),
            "{e}"
        );
    }
}
