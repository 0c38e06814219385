//! The accumulation core (paper §3.6–3.7, eqs. 5–6; docs/PHYSICS.md §3).
//!
//! At a screen point, contributions are grouped by coherence id; each group's complex 3D field
//! vectors are summed with their path phasors, `E_g = Σ_j E_j e^{i 2π c_j}` (c_j: phase in
//! cycles, Op/λ0), and the intensity is `I = Σ_g |E_g|² + Σ_{id = 0} |E_j|²`.
//!
//! # Phase in cycles
//!
//! Phase is carried in *cycles*. [`phasor_from_cycles`] splits off the integer part exactly
//! (the quarter-cycle index of `4c` is found with the 1.5·2^52 rounding trick, and
//! `4c − round(4c)` is exact), so a metre-long path (10^6 cycles) keeps its fractional phase to
//! the last bit of the input, and no 10^6-radian argument reduction is ever done. The remainder
//! `x = (π/2)(4c − q) ∈ [−π/4, π/4]` goes through the fdlibm `__kernel_sin`/`__kernel_cos`
//! minimax polynomials (degree 13 and 14, truncation error < 2^-58 on that interval), and the
//! quarter-turn `q mod 4` is applied by swapping and negating exactly, branch-free.
//! Measured against a double-double reference (checked against mpmath) over ~10^6 arguments
//! (random up to 10^7 cycles, small and tiny ones, every octant boundary ± a few ulps, phases
//! ≥ 2^48), the error is at most 1.11e-16 (2^-53) per component, where
//! `f64::sin_cos(2π·frac)` reaches 3.6e-16 (see `tests/suite/accumulate.rs`).
//!
//! # Summation
//!
//! Group field sums and the incoherent sum are [`Summation::Compensated`] by default: every
//! addition goes through Knuth's branch-free TwoSum and the exact rounding error is kept in a
//! second accumulator (Kahan–Babuška/Neumaier), so 10^6 contributions to one group lose no
//! digits to the summation (error ≲ 2ε|E| + O(n ε²)Σ|E_j|). [`Summation::Plain`] is the cheap
//! alternative; the benches (`benches/accumulate.rs`) measure the difference.
//!
//! # Batches
//!
//! [`accumulate_points`] and [`accumulate_points_par`] (rayon, over points) take contributions
//! laid out point by point (CSR: `offsets`), which keeps one point's accumulators in L1.
//! Coherence ids are found by a compare against the ids of a point's first four groups, and
//! for a fifth and later group through a small open-addressing table (one probe, predictable),
//! and phasors are computed 64 contributions at a time in a branch-free loop the compiler
//! vectorizes. The core owns no allocation per contribution and can be benchmarked alone.
//!
//! # Performance
//!
//! The profile of the plain core (callgrind, before this design): glibc `sincos` ≈ 52% of the
//! instructions, `round` ≈ 10% (a libm call: baseline x86-64 has no `roundsd`), the linear group
//! search and complex multiply-add ≈ 38%; ≈ 22 M contributions/s per thread.
//!
//! The crate is built for baseline x86-64 (SSE2). The batch kernels ([`Accumulator::extend`],
//! hence the batch functions, and [`phasors_from_cycles`]) also have copies compiled for AVX2,
//! chosen at run time. Measured on this project's 2-core AMD EPYC (Zen 3) VM, one thread, best
//! of 2000–3000 runs of 16384 contributions into 4 groups at 256 points (L2-resident):
//!
//! | code | plain | compensated | callgrind instructions per contribution |
//! |------|-------|-------------|------------------------------------------|
//! | SSE2 | 98 M/s | 79 M/s | 130 / 163 |
//! | AVX2 | 124 M/s | 111 M/s | 91 / 108 |
//!
//! (+27% / +40%); the phasor loop alone goes from ~165 to ~340 M/s. No FMA is enabled and Rust
//! never contracts a·b + c, so both copies give the same bits (tests/suite/accumulate.rs checks the
//! batch path against [`Accumulator::add`], which is not dispatched). Two layout details
//! matter for the compensated AVX2 path (same measurement): the phasor scratch block is
//! cache-line aligned (from a `Vec<Complex64>`, only 8-byte aligned, throughput varied between
//! 81 and 111 M/s from run to run), and a group's compensation terms start on their own cache
//! line (84 M/s when they follow the sums directly).

pub mod columns;
pub mod fidelity;

use crate::optics::ray::{Field3, INCOHERENT};
use num_complex::Complex64;
use rayon::prelude::*;
use std::sync::OnceLock;

/// One ray arriving at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contribution {
    /// Coherence id; 0 adds intensity only.
    pub coherence_id: u64,
    /// Path phase in cycles (Op/λ0, plus any half-cycle jumps of the scalar rungs).
    pub phase_cycles: f64,
    /// Complex 3D field amplitude (Fresnel phases included, path phase excluded).
    pub field: Field3,
}

// ---------------------------------------------------------------------------------------------
// Phasor
// ---------------------------------------------------------------------------------------------

/// 1.5·2^52: `(t + M) − M` rounds `t` to the nearest integer (ties to even) for |t| < 2^51,
/// and the low mantissa bits of `t + M` are that integer modulo 2^51.
const TO_NEAREST: f64 = 6_755_399_441_055_744.0;
/// Quarter-cycle counts below this take the fast path (2^50, i.e. |cycles| < 2^48 ≈ 2.8e14).
const FAST_LIMIT: f64 = 1_125_899_906_842_624.0;

// fdlibm (Sun Microsystems, freely distributable) k_sin.c / k_cos.c minimax coefficients on
// |x| ≤ π/4: |sin x − poly| < 2^-58 and |cos x − poly| < 2^-58 relative.
const S1: f64 = f64::from_bits(0xBFC55555_55555549); // -1.66666666666666324348e-01
const S2: f64 = f64::from_bits(0x3F811111_1110F8A6); // 8.33333333332248946124e-03
const S3: f64 = f64::from_bits(0xBF2A01A0_19C161D5); // -1.98412698298579493134e-04
const S4: f64 = f64::from_bits(0x3EC71DE3_57B1FE7D); // 2.75573137070700676789e-06
const S5: f64 = f64::from_bits(0xBE5AE5E6_8A2B9CEB); // -2.50507602534068634195e-08
const S6: f64 = f64::from_bits(0x3DE5D93A_5ACFD57C); // 1.58969099521155010221e-10
const C1: f64 = f64::from_bits(0x3FA55555_5555554C); // 4.16666666666666019037e-02
const C2: f64 = f64::from_bits(0xBF56C16C_16C15177); // -1.38888888888741095749e-03
const C3: f64 = f64::from_bits(0x3EFA01A0_19CB1590); // 2.48015872894767294178e-05
const C4: f64 = f64::from_bits(0xBE927E4F_809C52AD); // -2.75573143513906633035e-07
const C5: f64 = f64::from_bits(0x3E21EE9E_BDB4B1C4); // 2.08757232129817482790e-09
const C6: f64 = f64::from_bits(0xBDA8FAE9_BE8838D4); // -1.13596475577881948265e-11

/// e^{i 2π c} with the integer part of `c` removed exactly first (see the module docs).
///
/// Non-finite input gives NaN components.
#[inline]
pub fn phasor_from_cycles(cycles: f64) -> Complex64 {
    let t = 4.0 * cycles; // exact (power-of-two scaling)
    if t.abs() < FAST_LIMIT {
        phasor_quarters(t)
    } else {
        phasor_wide(cycles)
    }
}

/// Phasors of many phases (the same values as [`phasor_from_cycles`], bit for bit), in a loop
/// the compiler vectorizes. `out.len()` must equal `cycles.len()`.
pub fn phasors_from_cycles(cycles: &[f64], out: &mut [Complex64]) {
    assert_eq!(cycles.len(), out.len(), "one output per phase");
    #[cfg(target_arch = "x86_64")]
    if avx2() {
        // SAFETY: the CPU has AVX2 (checked just above), all that `phasors_avx2` requires.
        // Measured reason: 4 lanes instead of 2, ~2× (module docs, Performance).
        unsafe { phasors_avx2(cycles, out) };
        return;
    }
    phasors_kernel(cycles, out);
}

/// [`phasors_kernel`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn phasors_avx2(cycles: &[f64], out: &mut [Complex64]) {
    phasors_kernel(cycles, out);
}

#[inline(always)]
fn phasors_kernel(cycles: &[f64], out: &mut [Complex64]) {
    let mut all_fast = true;
    for (o, &c) in out.iter_mut().zip(cycles) {
        let (p, fast) = phasor_or_flag(c);
        *o = p;
        all_fast &= fast;
    }
    if !all_fast {
        for (o, &c) in out.iter_mut().zip(cycles) {
            *o = phasor_from_cycles(c);
        }
    }
}

/// The fast path without a branch: the phasor and `true`, or garbage and `false` when the
/// phase needs [`phasor_wide`].
#[inline(always)]
fn phasor_or_flag(cycles: f64) -> (Complex64, bool) {
    let t = 4.0 * cycles;
    let fast = t.abs() < FAST_LIMIT;
    (phasor_quarters(if fast { t } else { 0.0 }), fast)
}

/// Huge (|c| ≥ 2^48) or non-finite phases: reduce with `round` first (exact for finite c).
#[cold]
#[inline(never)]
fn phasor_wide(cycles: f64) -> Complex64 {
    if cycles.is_finite() {
        phasor_quarters(4.0 * (cycles - cycles.round()))
    } else {
        Complex64::new(f64::NAN, f64::NAN)
    }
}

/// e^{i (π/2) t} for |t| < 2^51 (t: phase in quarter cycles).
#[inline(always)]
fn phasor_quarters(t: f64) -> Complex64 {
    let big = t + TO_NEAREST;
    let q = big - TO_NEAREST; // nearest integer to t
    let k = big.to_bits(); // low two bits: q mod 4
    // t − q ∈ [−½, ½] is exact; one rounding in the product.
    let x = std::f64::consts::FRAC_PI_2 * (t - q);
    let z = x * x;
    let w = z * z;
    // __kernel_sin(x, 0, 0)
    let r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let s = x + z * x * (S1 + z * r);
    // __kernel_cos(x, 0)
    let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let one_minus = 1.0 - hz;
    let c = one_minus + (((1.0 - one_minus) - hz) + z * r);
    // Rotate by q quarter turns: k=0 (s, c), 1 (c, −s), 2 (−s, −c), 3 (−c, s); branch-free.
    let swap = (k & 1).wrapping_neg();
    let (sb, cb) = (s.to_bits(), c.to_bits());
    let sin_b = (sb & !swap) | (cb & swap);
    let cos_b = (cb & !swap) | (sb & swap);
    Complex64::new(
        f64::from_bits(cos_b ^ ((k.wrapping_add(1) & 2) << 62)),
        f64::from_bits(sin_b ^ ((k & 2) << 62)),
    )
}

// ---------------------------------------------------------------------------------------------
// Summation
// ---------------------------------------------------------------------------------------------

/// How group field sums and the incoherent sum are added up.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Summation {
    /// Plain floating-point sums (worst-case error ~ n ε Σ|terms|).
    Plain,
    /// Kahan–Babuška/Neumaier: branch-free TwoSum with the exact rounding errors accumulated
    /// separately and added at the end (error ≲ 2ε|sum| + O(n ε²) Σ|terms|).
    #[default]
    Compensated,
}

/// `s += x` keeping the exact rounding error in `c` (Knuth's TwoSum, no branch).
#[inline(always)]
fn two_sum_add(s: &mut f64, c: &mut f64, x: f64) {
    let t = *s + x;
    let z = t - *s;
    *c += (*s - (t - z)) + (x - z);
    *s = t;
}

/// One running sum (value + compensation) of non-negative or signed terms.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct CompSum {
    s: f64,
    c: f64,
}

impl CompSum {
    #[inline(always)]
    fn add(&mut self, x: f64, comp: bool) {
        if comp {
            two_sum_add(&mut self.s, &mut self.c, x);
        } else {
            self.s += x;
        }
    }
    #[inline(always)]
    fn value(&self) -> f64 {
        self.s + self.c
    }
}

// ---------------------------------------------------------------------------------------------
// Group table
// ---------------------------------------------------------------------------------------------

/// A group's running field sum: (re, im) of x, y, z, and the compensation terms.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(64))]
struct GroupSum {
    s: [f64; 6],
    /// Puts `c` on its own cache line (module docs, Performance).
    _pad_s: [f64; 2],
    c: [f64; 6],
    _pad_c: [f64; 2],
}

/// Hash slot: coherence id (0 = empty; id 0 never forms a group) and the group's index.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Slot {
    id: u64,
    group: usize,
}

/// Coherence id → group: the first four groups by a compare against their ids (`first`), the
/// fifth and later through an open-addressing (linear probing) hash table; plus the groups in
/// order of first appearance. Clearing touches only the used slots.
#[derive(Clone, Debug, Default)]
struct GroupTable {
    ids: Vec<u64>,
    /// The hash slot of each group of the table (groups 4 and later; entry g − 4).
    slot_of: Vec<usize>,
    sums: Vec<GroupSum>,
    table: Vec<Slot>,
    /// 64 − log2(table.len()).
    shift: u32,
    /// The ids of groups 0..4 (0 where there is no such group yet): found by compare, never
    /// in the hash table (also the column kernels' one-compare lookup, `columns.rs`).
    first: [u64; 4],
}

const FIB: u64 = 0x9E37_79B9_7F4A_7C15;

impl GroupTable {
    fn clear(&mut self) {
        for &s in &self.slot_of {
            self.table[s] = Slot::default();
        }
        self.ids.clear();
        self.slot_of.clear();
        self.sums.clear();
        self.first = [0; 4];
    }

    #[inline(always)]
    fn home(&self, id: u64) -> usize {
        (id.wrapping_mul(FIB) >> self.shift) as usize
    }

    /// The group of `id` (≠ 0), created if new.
    #[inline(always)]
    fn group(&mut self, id: u64) -> usize {
        // `first` holds 0 for a group not created yet, and `id` ≠ 0.
        if let Some(g) = self.first.iter().position(|&f| f == id) {
            return g;
        }
        // The hash table holds groups only once there are more than four.
        if self.ids.len() > self.first.len() {
            let mask = self.table.len() - 1;
            let mut h = self.home(id);
            loop {
                let slot = self.table[h];
                if slot.id == id {
                    return slot.group;
                }
                if slot.id == 0 {
                    break;
                }
                h = (h + 1) & mask;
            }
        }
        self.insert(id)
    }

    /// A new group for `id`: one of the first four (its id in `first`), or a hash slot.
    #[inline(always)]
    fn insert(&mut self, id: u64) -> usize {
        let g = self.ids.len();
        match self.first.get_mut(g) {
            Some(f) => {
                *f = id;
                self.ids.push(id);
                self.sums.push(GroupSum::default());
                g
            }
            None => self.insert_hashed(id),
        }
    }

    /// A new group for `id` in a hash slot (the fifth and later groups).
    #[inline(never)]
    fn insert_hashed(&mut self, id: u64) -> usize {
        let g = self.ids.len();
        let hashed = g - self.first.len() + 1;
        if 2 * hashed > self.table.len() {
            self.grow();
        }
        let mask = self.table.len() - 1;
        let mut h = self.home(id);
        while self.table[h].id != 0 {
            h = (h + 1) & mask;
        }
        self.table[h] = Slot { id, group: g };
        self.slot_of.push(h);
        self.ids.push(id);
        self.sums.push(GroupSum::default());
        g
    }

    /// Doubles the hash table (at least 16 slots) and puts the hashed groups back in.
    #[cold]
    fn grow(&mut self) {
        let len = (2 * self.table.len()).max(16);
        self.table = vec![Slot::default(); len];
        self.shift = 64 - len.trailing_zeros();
        let mask = len - 1;
        let skip = self.first.len();
        for (g, &id) in self.ids.iter().enumerate().skip(skip) {
            let mut h = self.home(id);
            while self.table[h].id != 0 {
                h = (h + 1) & mask;
            }
            self.table[h] = Slot { id, group: g };
            self.slot_of[g - skip] = h;
        }
    }

    /// E_g += E·e^{i2πc} for the group `g`.
    #[inline(always)]
    fn add_field(&mut self, g: usize, phasor: Complex64, field: &Field3, comp: bool) {
        // (fr, fi)·pc + (fi, fr)·(−ps, ps): the lane form of E·e^{iφ} (same bits as
        // fr·pc − fi·ps, fi·pc + fr·ps), which the compiler keeps in vector registers.
        let (pc, m) = (phasor.re, [-phasor.im, phasor.im]);
        let mut p = [0.0; 6];
        for k in 0..3 {
            let a = [field[k].re, field[k].im];
            let b = [field[k].im, field[k].re];
            p[2 * k] = a[0] * pc + b[0] * m[0];
            p[2 * k + 1] = a[1] * pc + b[1] * m[1];
        }
        let sum = &mut self.sums[g];
        if comp {
            for ((s, c), x) in sum.s.iter_mut().zip(&mut sum.c).zip(p) {
                two_sum_add(s, c, x);
            }
        } else {
            for (s, x) in sum.s.iter_mut().zip(p) {
                *s += x;
            }
        }
    }

    /// |E_g|² summed over the groups (compensation folded in).
    fn intensity(&self, total: &mut CompSum, comp: bool) {
        for gs in &self.sums {
            let mut e2 = 0.0;
            for k in 0..6 {
                let v = gs.s[k] + gs.c[k];
                e2 += v * v;
            }
            total.add(e2, comp);
        }
    }

    fn field(&self, g: usize) -> Field3 {
        let gs = &self.sums[g];
        let v = |k: usize| gs.s[k] + gs.c[k];
        [
            Complex64::new(v(0), v(1)),
            Complex64::new(v(2), v(3)),
            Complex64::new(v(4), v(5)),
        ]
    }
}

// ---------------------------------------------------------------------------------------------
// Accumulator
// ---------------------------------------------------------------------------------------------

/// Per-point accumulator of coherence groups; reuse it across points with [`Accumulator::clear`].
#[derive(Clone, Debug, Default)]
pub struct Accumulator {
    table: GroupTable,
    incoherent: CompSum,
    summation: Summation,
    /// `groups()` view, built on demand and dropped by every change.
    view: OnceLock<Vec<(u64, Field3)>>,
    /// Scratch phasors of one block.
    phasors: Box<PhasorBlock>,
    /// Scratch cosines and sines of the column kernel (`columns.rs`), allocated on first use.
    trig: Option<Box<columns::TrigBlock>>,
}

/// Whether the CPU has AVX2 (cached by std after the first query).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn avx2() -> bool {
    std::arch::is_x86_feature_detected!("avx2")
}

/// Contributions whose phasors are computed together in one vectorized loop.
const BLOCK: usize = 64;

/// Scratch phasors of one block, cache-line aligned.
#[derive(Clone, Debug)]
#[repr(C, align(64))]
struct PhasorBlock([Complex64; BLOCK]);

impl Default for PhasorBlock {
    fn default() -> Self {
        PhasorBlock([Complex64::new(0.0, 0.0); BLOCK])
    }
}

impl Accumulator {
    /// An empty accumulator with [`Summation::Compensated`].
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty accumulator with the given summation.
    pub fn with_summation(summation: Summation) -> Self {
        Accumulator {
            summation,
            ..Self::default()
        }
    }

    /// The summation scheme this accumulator adds fields and intensities with.
    pub fn summation(&self) -> Summation {
        self.summation
    }

    /// Removes every contribution, keeping the summation scheme (and the allocation).
    pub fn clear(&mut self) {
        self.table.clear();
        self.incoherent = CompSum::default();
        self.invalidate();
    }

    #[inline(always)]
    fn invalidate(&mut self) {
        if self.view.get().is_some() {
            self.view = OnceLock::new();
        }
    }

    /// Add one contribution (eq. 5 for its group, or eq. 6's incoherent term for id 0).
    #[inline]
    pub fn add(&mut self, c: &Contribution) {
        self.add_parts(c.coherence_id, c.phase_cycles, &c.field);
    }

    /// [`Accumulator::add`] without building a [`Contribution`].
    #[inline]
    pub fn add_parts(&mut self, coherence_id: u64, phase_cycles: f64, field: &Field3) {
        self.invalidate();
        match self.summation {
            Summation::Compensated => self.add_mode::<true>(coherence_id, phase_cycles, field),
            Summation::Plain => self.add_mode::<false>(coherence_id, phase_cycles, field),
        }
    }

    #[inline(always)]
    fn add_mode<const COMP: bool>(&mut self, id: u64, cycles: f64, field: &Field3) {
        if id == INCOHERENT {
            let e2 = field[0].norm_sqr() + field[1].norm_sqr() + field[2].norm_sqr();
            self.incoherent.add(e2, COMP);
            return;
        }
        let ph = phasor_from_cycles(cycles);
        let g = self.table.group(id);
        self.table.add_field(g, ph, field, COMP);
    }

    /// Add every contribution of a slice.
    pub fn extend(&mut self, contributions: &[Contribution]) {
        self.invalidate();
        let comp = self.summation == Summation::Compensated;
        #[cfg(target_arch = "x86_64")]
        if avx2() {
            // SAFETY: `extend_avx2` only requires AVX2, which the running CPU has (checked by
            // `avx2()` just above). Measured reason: +27% plain, +40% compensated, same bits
            // (module docs, Performance).
            unsafe {
                if comp {
                    self.extend_avx2::<true>(contributions)
                } else {
                    self.extend_avx2::<false>(contributions)
                }
            }
            return;
        }
        if comp {
            self.extend_mode::<true>(contributions)
        } else {
            self.extend_mode::<false>(contributions)
        }
    }

    /// [`Accumulator::extend_mode`] compiled with AVX2 (4-lane phasor loop, 3-operand forms).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn extend_avx2<const COMP: bool>(&mut self, contributions: &[Contribution]) {
        self.extend_mode::<COMP>(contributions)
    }

    /// Phasors first, a block at a time in a vectorizable loop, then the grouped sums.
    #[inline(always)]
    fn extend_mode<const COMP: bool>(&mut self, contributions: &[Contribution]) {
        let Accumulator {
            table,
            incoherent,
            phasors,
            ..
        } = self;
        for block in contributions.chunks(BLOCK) {
            let ph = &mut phasors.0[..block.len()];
            let mut all_fast = true;
            for (p, c) in ph.iter_mut().zip(block) {
                let (v, fast) = phasor_or_flag(c.phase_cycles);
                *p = v;
                all_fast &= fast;
            }
            if !all_fast {
                for (p, c) in ph.iter_mut().zip(block) {
                    *p = phasor_from_cycles(c.phase_cycles);
                }
            }
            for (p, c) in ph.iter().zip(block) {
                if c.coherence_id == INCOHERENT {
                    let f = &c.field;
                    let e2 = f[0].norm_sqr() + f[1].norm_sqr() + f[2].norm_sqr();
                    incoherent.add(e2, COMP);
                } else {
                    let g = table.group(c.coherence_id);
                    table.add_field(g, *p, &c.field, COMP);
                }
            }
        }
    }

    /// I = Σ_g |E_g|² + Σ incoherent |E|² (eq. 6).
    pub fn intensity(&self) -> f64 {
        let comp = self.summation == Summation::Compensated;
        let mut total = CompSum::default();
        total.add(self.incoherent.value(), comp);
        self.table.intensity(&mut total, comp);
        total.value()
    }

    /// The summed field of each coherence group, in order of first appearance.
    pub fn groups(&self) -> &[(u64, Field3)] {
        self.view.get_or_init(|| {
            (0..self.table.ids.len())
                .map(|g| (self.table.ids[g], self.table.field(g)))
                .collect()
        })
    }
}

/// Intensity of a set of contributions at one point.
pub fn intensity(contributions: &[Contribution]) -> f64 {
    let mut acc = Accumulator::new();
    acc.extend(contributions);
    acc.intensity()
}

// ---------------------------------------------------------------------------------------------
// Batches
// ---------------------------------------------------------------------------------------------

fn check_offsets(contributions: usize, offsets: &[usize], out: &[f64]) {
    assert_eq!(
        offsets.len(),
        out.len() + 1,
        "offsets must have one entry more than there are points"
    );
    assert!(
        offsets.first().is_none_or(|&o| o == 0)
            && offsets.windows(2).all(|w| w[0] <= w[1])
            && offsets.last().is_none_or(|&o| o == contributions),
        "offsets must start at 0, never decrease and end at contributions.len()"
    );
}

/// Intensities of many points (eq. 6 at each), contributions laid out point by point:
/// point `k` owns `contributions[offsets[k]..offsets[k + 1]]` and its intensity goes to
/// `out[k]`. Requires `offsets.len() == out.len() + 1`, `offsets[0] == 0`, non-decreasing
/// offsets and `offsets[last] == contributions.len()` (panics otherwise).
pub fn accumulate_points(
    contributions: &[Contribution],
    offsets: &[usize],
    summation: Summation,
    out: &mut [f64],
) {
    check_offsets(contributions.len(), offsets, out);
    let mut acc = Accumulator::with_summation(summation);
    for (k, o) in out.iter_mut().enumerate() {
        acc.clear();
        acc.extend(&contributions[offsets[k]..offsets[k + 1]]);
        *o = acc.intensity();
    }
}

/// [`accumulate_points`] in parallel over points (rayon's current pool). Gives bit-for-bit the
/// same intensities: each point is accumulated in order by one thread.
pub fn accumulate_points_par(
    contributions: &[Contribution],
    offsets: &[usize],
    summation: Summation,
    out: &mut [f64],
) {
    check_offsets(contributions.len(), offsets, out);
    par_over_points(contributions.len(), summation, out, |acc, k| {
        acc.clear();
        acc.extend(&contributions[offsets[k]..offsets[k + 1]]);
        acc.intensity()
    });
}

/// `out[k] = point(acc, k)` for every point k, in parallel over points (rayon's current pool),
/// each point by one thread with an accumulator of `summation` reused across a task's points:
/// so the intensities are bit for bit those of a serial loop. `total` contributions in all.
pub(crate) fn par_over_points(
    total: usize,
    summation: Summation,
    out: &mut [f64],
    point: impl Fn(&mut Accumulator, usize) -> f64 + Sync + Send,
) {
    // About 4096 contributions per task keeps the scheduling overhead below ~1%.
    let mean = total / out.len().max(1);
    let min_len = (4096 / mean.max(1)).max(1);
    out.par_iter_mut()
        .enumerate()
        .with_min_len(min_len)
        .for_each_init(
            || Accumulator::with_summation(summation),
            |acc, (k, o)| *o = point(acc, k),
        );
}

/// CSR offsets from per-point contribution counts (`counts.len() + 1` entries).
pub fn offsets_from_counts(counts: &[usize]) -> Vec<usize> {
    let mut offsets = Vec::with_capacity(counts.len() + 1);
    let mut total = 0;
    offsets.push(0);
    for &n in counts {
        total += n;
        offsets.push(total);
    }
    offsets
}
