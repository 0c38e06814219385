//! Shrinking a failing scene: replace its recorded draws ([`super::draws`]) by simpler values
//! while it still fails, so the case file written for a failure has the fewest, roundest
//! numbers that still show it.
//!
//! An option or a flag is tried at 0 (the simplest option, the flag off). A real is tried, in
//! order, at 0 and 1 (when inside its range), its range's lower bound, its integer part, and
//! then rounded to 1, 2, … 6 significant digits; the first candidate that still fails is kept.
//! Passes repeat until none changes (or the evaluation budget is spent). What "still fails"
//! means is the caller's (`fringe fuzz`: the same family fails at `vector` with a deviation of
//! within a factor 10 of the original one, and the scene has no region the original did not
//! have), so the shrunk case shows the same defect, not a neighbouring one.

use super::draws::DrawKind;

/// Candidate replacements for a drawn value, simplest first, without repeats or `v` itself.
pub(crate) fn candidates(v: f64, kind: DrawKind) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    match kind {
        DrawKind::Choice | DrawKind::Flag => out.push(0.0),
        DrawKind::Real { lo, hi } => {
            let inside = |x: f64| x >= lo.min(hi) && x <= hi.max(lo);
            out.extend([0.0, 1.0].into_iter().filter(|x| inside(*x)));
            out.push(lo);
            out.push(v.trunc());
            for digits in 1..=6 {
                out.push(round_significant(v, digits));
            }
        }
    }
    let mut unique: Vec<f64> = Vec::new();
    for c in out {
        if c.is_finite() && simpler(c, v) && !unique.contains(&c) {
            unique.push(c);
        }
    }
    unique
}

/// How complex a number reads: 0, then 1, then by its significant digits, then by size.
fn complexity(x: f64) -> (u32, f64) {
    if x == 0.0 {
        (0, 0.0)
    } else if x == 1.0 {
        (1, 0.0)
    } else {
        let digits = (1..=17)
            .find(|&d| round_significant(x, d) == x)
            .unwrap_or(17);
        (1 + digits as u32, x.abs())
    }
}

/// Whether `a` is strictly simpler than `b` (so shrinking cannot cycle).
fn simpler(a: f64, b: f64) -> bool {
    complexity(a).partial_cmp(&complexity(b)) == Some(std::cmp::Ordering::Less)
}

/// `v` rounded to `digits` significant decimal digits.
pub(crate) fn round_significant(v: f64, digits: i32) -> f64 {
    if v == 0.0 || !v.is_finite() {
        return v;
    }
    let e = v.abs().log10().floor() as i32;
    let scale = 10f64.powi(digits - 1 - e);
    let r = (v * scale).round() / scale;
    // Reparse the shortest decimal form so the JSON shows the short number.
    format!("{r:.prec$e}", prec = (digits - 1).max(0) as usize)
        .parse()
        .unwrap_or(r)
}

/// Shrink `draws` while `still_fails` holds, with at most `budget` calls of `still_fails`.
/// Returns the simplest failing draws found (the input if none simpler fails).
pub(crate) fn shrink(
    draws: Vec<f64>,
    kinds: &[DrawKind],
    budget: usize,
    mut still_fails: impl FnMut(&[f64]) -> bool,
) -> Vec<f64> {
    let mut best = draws;
    let mut calls = 0;
    loop {
        let mut changed = false;
        for k in 0..best.len() {
            let kind = kinds.get(k).copied().unwrap_or(DrawKind::Real {
                lo: f64::MIN,
                hi: f64::MAX,
            });
            for c in candidates(best[k], kind) {
                if calls >= budget {
                    return best;
                }
                let mut trial = best.clone();
                trial[k] = c;
                calls += 1;
                if still_fails(&trial) {
                    best = trial;
                    changed = true;
                    break;
                }
            }
        }
        if !changed {
            return best;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
