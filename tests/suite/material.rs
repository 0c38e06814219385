//! Dispersion models (`material::Dispersion`).
//!
//! Expected values: the Schott N-BK7 data sheet's tabulated indices (not the Sellmeier formula
//! the code evaluates): n_d(587.56 nm) = 1.51680, n_F(486.13 nm) = 1.52238,
//! n_C(656.27 nm) = 1.51432, n_e(546.07 nm) = 1.51872, n(632.8 nm) = 1.51509,
//! n_i(365.01 nm) = 1.53627, n_t(1013.98 nm) = 1.50731 (n_d and n(632.8) as also quoted by
//! refractiveindex.info / the Schott catalogue). The data sheet's Sellmeier fit reproduces its own
//! table to a few 1e-6, so the 5-decimal values are asserted to 1e-5 and the brief's rounded
//! values (1.5168, 1.5224, 1.5143) to 1e-4. Cauchy values are by hand.

use fringe::optics::material::{Dispersion, IndexError, Medium};

fn check(d: &Dispersion, lambda_nm: f64, expected: f64, tol: f64) {
    let n = d
        .index(lambda_nm * 1e-9)
        .unwrap_or_else(|e| panic!("{lambda_nm} nm: unexpected error {e}"));
    let err = (n - expected).abs();
    assert!(
        err <= tol,
        "n({lambda_nm} nm): actual {n:.7}, expected {expected}, err {err:e} > tol {tol:e}"
    );
}

#[test]
fn bk7_matches_schott_principal_lines() {
    let bk7 = Dispersion::bk7();
    check(&bk7, 587.56, 1.5168, 1e-4);
    check(&bk7, 486.13, 1.5224, 1e-4);
    check(&bk7, 656.27, 1.5143, 1e-4);
}

#[test]
fn bk7_matches_schott_table_to_five_decimals() {
    let bk7 = Dispersion::bk7();
    for (nm, n) in [
        (587.56, 1.51680),
        (486.13, 1.52238),
        (656.27, 1.51432),
        (546.07, 1.51872),
        (632.8, 1.51509),
        (365.01, 1.53627),
        (1013.98, 1.50731),
    ] {
        check(&bk7, nm, n, 1e-5);
    }
    // Normal dispersion: n decreases with wavelength across the visible (by physics).
    let a = bk7.index(400e-9).unwrap();
    let b = bk7.index(700e-9).unwrap();
    assert!(a > b, "n(400 nm) {a} should exceed n(700 nm) {b}");
}

/// Outside the Sellmeier fit's validity range (0.3–2.5 µm) evaluation is an error, not an
/// extrapolation; the range ends themselves are valid.
#[test]
fn out_of_range_wavelength_is_an_error() {
    let bk7 = Dispersion::bk7();
    for nm in [200.0, 299.0, 2600.0, 10_000.0] {
        match bk7.index(nm * 1e-9) {
            Err(IndexError::OutOfRange {
                lambda_nm,
                min_nm,
                max_nm,
            }) => {
                assert!(
                    (lambda_nm - nm).abs() < 1e-6 * nm,
                    "reported wavelength {lambda_nm} nm, expected {nm}"
                );
                assert!(
                    (min_nm - 300.0).abs() < 1e-9 && (max_nm - 2500.0).abs() < 1e-9,
                    "reported range {min_nm}–{max_nm}, expected 300–2500"
                );
            }
            other => panic!("{nm} nm: actual {other:?}, expected Err(OutOfRange)"),
        }
    }
    assert!(
        bk7.index(f64::NAN).is_err(),
        "NaN wavelength must be an error"
    );
    for nm in [300.0, 2500.0] {
        assert!(
            bk7.index(nm * 1e-9).is_ok(),
            "{nm} nm is inside the validity range"
        );
    }
    // Through a Medium as well.
    let m = Medium {
        name: "N-BK7".into(),
        dispersion: Dispersion::bk7(),
    };
    assert!(
        matches!(m.index(250e-9), Err(IndexError::OutOfRange { .. })),
        "Medium::index must propagate the range error"
    );
}

/// Cauchy n = a + b/λ² + c/λ⁴ (λ in µm), by hand: a = 1.5, b = 0.004 µm², c = 1e-4 µm⁴ at 0.5 µm:
/// 1.5 + 0.004/0.25 + 0.0001/0.0625 = 1.5 + 0.016 + 0.0016 = 1.5176. Range enforced.
#[test]
fn cauchy_by_hand() {
    let d = Dispersion::Cauchy {
        a: 1.5,
        b_um2: 0.004,
        c_um4: 1e-4,
        min_um: 0.4,
        max_um: 0.8,
    };
    check(&d, 500.0, 1.5176, 1e-14);
    assert!(matches!(
        d.index(0.9e-6),
        Err(IndexError::OutOfRange { .. })
    ));
    assert!(matches!(
        d.index(0.3e-6),
        Err(IndexError::OutOfRange { .. })
    ));
}

/// A constant index has no range; a non-physical one (≤ 0 or not finite) is an error.
#[test]
fn constant_and_non_physical() {
    check(&Dispersion::Constant { n: 1.33 }, 123.0, 1.33, 0.0);
    check(&Dispersion::Constant { n: 1.33 }, 5000.0, 1.33, 0.0);
    for n in [0.0, -1.5, f64::NAN, f64::INFINITY] {
        assert!(
            matches!(
                Dispersion::Constant { n }.index(500e-9),
                Err(IndexError::NonPhysical { .. })
            ),
            "constant n = {n}: expected Err(NonPhysical)"
        );
    }
}
