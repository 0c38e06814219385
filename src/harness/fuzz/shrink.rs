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
pub fn candidates(v: f64, kind: DrawKind) -> Vec<f64> {
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
pub fn round_significant(v: f64, digits: i32) -> f64 {
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
pub fn shrink(
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
