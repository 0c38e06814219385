//! Contributions as columns (structure of arrays) and the batch accumulation over them
//! (eqs. 5–6, docs/PHYSICS.md §3; the same sums as [`Accumulator::add`], bit for bit).
//!
//! [`ContributionColumns`] holds the three parts of a [`Contribution`] in three slices:
//! coherence ids, phases (cycles) and fields. The bytes are the same as the row layout
//! (8 + 8 + 48 per contribution), but the phasor loop reads the phases as one contiguous
//! stream (4-lane vector loads instead of a strided gather from 64-byte rows) and writes the
//! cosines and sines to two aligned scratch rows (no interleaving shuffles), and the group loop
//! reads each field as one 48-byte vector.
//!
//! The SIMD kernels ([`ColumnKernel`], picked at run time: AVX-512F if the CPU has it, else
//! AVX2, else the portable loop through [`Accumulator::add_parts`]) compute a block's phasors
//! in one vector loop (8 lanes with AVX-512F, 4 with AVX2; the bits of [`phasor_from_cycles`]),
//! find the group of a contribution by a compare against the ids of the first four groups of
//! the point (the AVX2 kernel one 4-lane compare per contribution; the AVX-512F kernel, before
//! the sums, four 8-lane compares per eight contributions that give the byte offset of each
//! one's group sum, id 0 by mask; while the point has at most four groups, the new ones of the
//! eight created at once, in order of first appearance, by shifted compares and one compress;
//! `GroupTable::group` of `mod.rs` once per distinct new id or fifth and later group of the
//! eight otherwise), and form `E·e^{i2πc}` and the TwoSum update with the operations
//! and the operand order of `GroupTable::add_field` (no FMA, no reassociation), each group's
//! contributions in input order: in a 4-lane (x, y) and a 2-lane (z)
//! register with AVX2, in one 8-lane register with AVX-512F (the field read by one unmasked
//! 64-byte load, lanes 6, 7 the next field's x, which reach only the sums' padding; the last
//! field of the columns by a masked load; the sine broadcast from a (−sin, sin) pair written
//! after the phasor loop). Every group sum,
//! compensation term and intensity has the bits of [`Accumulator::add`], whichever kernel runs
//! (`tests/suite/accumulate.rs` checks each kernel the CPU has through
//! [`Accumulator::extend_columns_using`] and [`accumulate_columns_using`]). The kernels ask for
//! the fields one block (64 contributions, 3 KiB) ahead and the ids and phases two blocks ahead
//! by prefetch hints.
//!
//! # Performance
//!
//! Measured 29 November 2026 on the project's 2-core Intel Xeon VM (AVX-512F), two runs
//! interleaved with the previous kernel's bench binary (a5a4ef5) and `python3
//! examples/accumulate_numpy.py` (`cargo bench -p fringe-benches --bench cpu_rates --
//! accumulate`, 1 M contributions, 16 k points, 4 groups), M contributions/s wall, on the idle
//! VM (15:05 UTC) and, in brackets, while another build ran (15:00 UTC, load 1.3–1.7):
//!
//! | | before (AVX2, no prefetch) | AVX-512F + prefetch | AVX2 + prefetch |
//! |---|---|---|---|
//! | 1 thread plain | 74–83 (85–88) | 116–128 (122–131) | 95–109 (117–121) |
//! | 2 threads plain | 127–134 (147–230) | 200–275 (280–287) | |
//! | 1 thread compensated | 66–77 (80–81) | 110 (99–118) | 96–100 (93–107) |
//! | 2 threads compensated | 116–150 (154–186) | 170–189 (253–259) | |
//!
//! numpy `bincount` of the same work in the same series: 11.9–12.5 (12.4–12.9) M/s, so 2
//! threads plain is 16–22× (22–23×) numpy. Most of the gain is the field prefetch (without it
//! the AVX-512F kernel ran at 64–70 M/s on 1 thread); the 8-lane phasors and field update add
//! 5–20 % over AVX2 + prefetch. Loading and storing a group's sum as its whole 64-byte line
//! instead of masked 6-lane moves took 1 thread compensated from 89 to 122 M/s (a masked store
//! does not forward to the next load of the same group). A bare streaming read of the same
//! 64 MiB ran at 443–476 M/s on 2 threads in the idle series.
//!
//! Group offsets before the sums (the AVX-512F kernel's four 8-lane compares instead of a
//! broadcast, compare, mask move and bit scan per contribution; the first four groups of a
//! point not hashed): the bench binary before (32aa42f) and after, interleaved, six runs each,
//! 29 November 2026, on the VM shared with three other helpers' builds: M contributions/s
//! wall, best (median) of the six, at 16:28–16:29 UTC (load 2.7–3.2) and, in brackets, at
//! 16:13–16:15 UTC (load 5.1–5.6):
//!
//! | | before | after |
//! |---|---|---|
//! | 16 k, L2-resident, 1 thread plain | 161 (154) [139 (106)] | 215 (211) [218 (142)] |
//! | 16 k, L2-resident, 1 thread compensated | 131 (124) [132 (104)] | 166 (161) [169 (110)] |
//! | 1 M, 1 thread plain | 133 (127) [118 (81)] | 140 (98) [117 (106)] |
//! | 1 M, 2 threads plain | 146 (134) [282 (94)] | 124 (116) [145 (104)] |
//! | 1 M, 1 thread compensated | 120 (115) [97 (78)] | 123 (117) [86 (69)] |
//! | 1 M, 2 threads compensated | 123 (116) [113 (79)] | 126 (125) [116 (76)] |
//!
//! A third series (16:31–16:32 UTC, load 2.5–2.8), best (median), before → after: L2-resident
//! plain 161 (130) → 184 (146), compensated 128 (122) → 122 (112); 1 M, 2 threads plain
//! 272 (126) → 248 (201), compensated 202 (127) → 177 (160); the 2-thread streaming read
//! 556 (304) and 564 (526): on this shared VM run-to-run noise is as large as the compensated
//! gain, and only the plain L2-resident gain held in all three series.
//! numpy `bincount` in the 16:28 series: 10.7–11.1 M/s. The L2-resident rows (`accumulate
//! T16k_P256_G4 … (L2)` of the same bench) are the compute rate: +34–57 % plain, +27–28 %
//! compensated. The 1 M rows do not show it: the 2-thread rates equal the 1-thread ones (the
//! other CPU was busy with the other builds; CPU-seconds equal wall seconds), and the bare
//! 2-thread streaming read of the 64 MiB ran at 200–321 M/s (median) against 443–476 on the
//! idle VM, so the 64 MiB case was bound by what memory bandwidth and CPU the other processes
//! left, and whether 2 threads plain reach 25× numpy (≥ ~310 M/s) on the idle VM was not
//! measured. In a throw-away L2-resident microbenchmark of the kernel alone the phasor loop
//! took ~45 % of the time and the group search and sums ~55 % before this change, about half
//! each after it: the phasor polynomial (its operations fixed by the bit contract, no FMA) is
//! now as large a part as everything else. Not kept, no measurable gain: the phasor loop
//! without the `fast` select (216 vs 215 M/s L2-resident plain); in the microbenchmark,
//! (−sin, sin) pairs written by the phasor loop and broadcast instead of the sign flip
//! (slower), and group sums held in four registers with masked adds (no faster than the
//! line-wide load/add/store); longer field prefetch distances and L2 prefetch hints gave no
//! difference above the noise of the loaded VM.
//!
//! On the idle VM after the merge (fifteenth session, 16:39–17:12 UTC, 11 rounds of the bench
//! each next to a run of `examples/accumulate_numpy.py`): 2 threads plain 160–245 M/s against
//! numpy's 8.2–11.6 M/s (numpy's speed moved by 1.4× between minutes), 16–28× round by round,
//! ≥ 25× in 4 of 11; the kernel before this change 137–138 M/s in one of those series; L2-resident
//! 1 thread plain 94–95 → 128–163 M/s. One thread on the 1 M case runs at 86–122 M/s, about
//! what 10–12 outstanding line fills per core allow at DRAM latency for 64 bytes a
//! contribution; the fields prefetched two blocks ahead, or also into L2 four to eight blocks
//! ahead, and the buffers on 2 MB pages were within the noise there too.
//!
//! Sixteenth session (29 November 2026, 18:55–19:12 UTC, the VM otherwise idle but for the
//! lead's editing, load average 1.2–2.2; no hardware counters in this VM, so `perf record`
//! with the CPU clock only). The profile of `cpu_rates accumulate-2t` (1 M case) before: 68 %
//! in the kernel, 18 % in `group_offsets_512`'s lane-by-lane path, 4 % in
//! `Accumulator::intensity`. With 64 contributions a point (16 k points), the first chunk of
//! eight of every point has only new ids (`first` is empty), and with random ids of four groups
//! the second often has one too: each such chunk went through `GroupTable::group` lane by lane,
//! eight data-dependent branches on random ids. Now one call per distinct new id of the chunk
//! (its offset to all its lanes by one compare): the path fell from 18 % to 0.4 % of the
//! samples. The L2-resident rows did not show it (1 thread plain best rep 236/229 M/s before,
//! 227/232 after, in the first two interleaved runs: their 16 k
//! contributions repeat 1280 times, so the branch predictor learns the ids; the 1 M rows do
//! not repeat within 64 MiB), the 1 M rows did: interleaved, three `cpu_rates accumulate` runs
//! each (best rep M/s), before → after both changes of this session: 1 thread plain 126/162/168 → 220/230/225, 2 threads
//! plain 276/253/343 → 434/337/446, 2 threads compensated 201/186/277 → 342/257/236; stream
//! read 2t 604–674 in both. Second, `add_one_512`'s product without the masked add (LLVM
//! lowered `maskz_add` to an add and a `vexpandpd`, one more shuffle-port operation a
//! contribution; lanes 6, 7 reach only the padding): L2-resident 1 thread plain, best of four
//! interleaved runs, 232 → 260 M/s, compensated 177 → 190 (medians within the noise).
//!
//! Issue #14's comparison (`CPU_RATES=… python3 examples/accumulate_ratio.py 3`, four
//! alternations of the bench binary before and after, 12 rounds each, 19:11 UTC, load
//! 1.3–1.4; numpy 7.7–11.9 M/s best in this series): 2 threads plain before 229–332 M/s best,
//! 218–305 median, ratio best/best 22–37× (8 of 12 rounds ≥ 25×), median/median 20–29× (10 of
//! 12); after 296–429 best, 250–375 median, best/best 28.5–44× (12 of 12), median/median 26–39×
//! (12 of 12); compensated after 200–346 best, 19–39× (best/best). The 2-thread kernel now
//! runs at about 2/3 of the 2-thread streaming read (604–674 M/s in the same runs).
//!
//! Not kept (measured in the same session, interleaved): the columns on 2 MiB pages in the
//! library (`madvise(MADV_HUGEPAGE)` in `ContributionColumns::with_capacity`, checked to take
//! effect: `AnonHugePages` doubled): five rounds each of `accumulate-2t`, 2 threads plain best
//! 386/334/323/327/288 (4 KiB pages) against 368/274/350/305/320 (2 MiB), no gain above the
//! noise, so the bench's own 2 MiB-page rows stay as the only huge-page measurement; the
//! fields prefetched two blocks ahead instead of one (six rounds, 2 threads plain best 287–357
//! against 309–348 M/s); and the first four groups' sums held in registers through the block
//! (one pass per group over a 64-bit mask of its contributions, no store and reload of the sum
//! between two contributions, the next block's fields prefetched at the start of the sums):
//! slower, 1 thread plain on the 1 M case 86–114 against 119–205 M/s (mean), L2-resident no faster.
//!
//! Seventeenth session (29 November 2026, 21:00–21:45 UTC, the VM shared with two other
//! helpers' builds, load average 2–6 throughout; no hardware counters, so `perf record` with the
//! CPU clock, and a dependent-`imul` loop to calibrate the clock: ~2.4 GHz). In the profile of
//! `cpu_rates accumulate-l2` (the L2-resident rows alone) the plain kernel spent about a third
//! of its samples in the phasor loop (6.9 operations on the two 512-bit ports per
//! contribution), 38 % in the sums and 17 % finding group offsets, most of that in the first
//! chunk of each point, where every id is new; `Accumulator::intensity` 5–6 % of the whole.
//! Three changes, kept: each field by one unmasked 64-byte load (no mask register to rebuild
//! per contribution), the sine as a broadcast (−sin, sin) pair instead of an xor per
//! contribution (one xor and two permutes per eight, after the phasor loop), and a point's
//! first four groups created from a chunk at once (no call and no data-dependent loop per new
//! id). Interleaved, eight rounds each of the bench binary before (74d265e) and after, best
//! rep M/s, best (median) of the eight: at 21:26 UTC (load 4.0–4.5) L2-resident plain 234
//! (224) → 239 (230), compensated 177 (170) → 191 (184); at 21:42 (load 1.7–2.1) plain 251
//! (247) → 257 (246), compensated 190 (184) → 205 (197): compensated +7–8 %, plain within the
//! noise. Issue #14's comparison in the same session (`accumulate_ratio.py 3`, four
//! alternations, 12 rounds each, 21:42–21:44 UTC, load 2.1–3.0, numpy 7.9–13.3 M/s best): 2
//! threads plain best rep 136–448 M/s (median of the rounds 210) before, 130–425 (230) after;
//! the 2-thread rows ran at about the 1-thread rate in most rounds (the other core was busy),
//! so this series does not show the goal of issue #14 either way. The same at 21:49 UTC, once
//! the other builds had paused (load 1.2–1.5, numpy 8.0–12.0 M/s best): 2 threads plain best
//! rep 258–434 M/s (median of the 12 rounds 353) before, 279–421 (322) after, ratio best/best
//! 21.8–50× (11 of 12 rounds ≥ 25×) before, 25.1–51.7× (12 of 12) after; `cpu_rates
//! accumulate`, two interleaved series of five and six runs (21:50–21:51 UTC, load 1.2–1.5),
//! median (best) of the runs' best reps, before → after: 1 M, 2 threads plain 284 (345) → 316
//! (356) and 269 (399) → 332 (416); compensated 232 (311) → 296 (346) and 236 (245) → 254
//! (351); L2-resident plain 189 (235) → 239 (247) and 201 (234) → 233 (246), compensated
//! 141 (177) → 190 (197) and 155 (177) → 189 (204); the 2-thread streaming read 536–575 in
//! both. Plain gains between −9 % and +23 % by statistic and series: not the +15 % of the
//! goal beyond the noise of this shared VM; the lead's idle-VM series decides.
//!
//! What bounds the kernel here: one group (`G=1`, every contribution in the same sum) runs at
//! ~157 M/s, ~15 cycles a contribution, the latency of a group sum's store, reload and add;
//! two groups at 213, four at 230 M/s (best rep, same run): with four groups that chain costs
//! a few per cent. With the memory system shared (the 1 M case while the 1-thread streaming
//! read of the same 64 MiB ran at 110–150 M/s instead of 320 on the idle VM) the 1-thread 1 M
//! rows ran at the streaming read's rate before and after: about 16 outstanding line fills a
//! core at DRAM latency, which no change of the arithmetic moves.
//!
//! Not kept (same session, interleaved): the three columns also asked for four blocks ahead
//! into L2 (`prefetcht1`, once a line): slower in the shared phase, 1 thread plain on the 1 M
//! case 111 → 100 M/s and compensated 104 → 87 (median of six), as the fifteenth session
//! found at the idle VM; and phasors, group offsets and sums in chunks of 16 (the next chunk's
//! phasor arithmetic in flight with the previous chunk's sums): L2-resident plain best 254 →
//! 229 M/s, compensated 204 → 188 (eight rounds), the 1 M rows no faster; and
//! `Accumulator::intensity` for the AVX-512F kernel four groups at a time (their `(s + c)²`
//! transposed, each group's six squares added in order in one lane): L2-resident plain 239
//! (229) against 238 (230) M/s best (median) of ten rounds, no gain.

use super::{
    Accumulator, BLOCK, Contribution, FAST_LIMIT, GroupSum, INCOHERENT, Summation, check_offsets,
    par_over_points, phasor_from_cycles, phasor_quarters,
};
use crate::optics::ray::Field3;

/// Contributions of one or many points as three columns of equal length: `coherence_ids[j]`,
/// `phase_cycles[j]` (path phase in cycles, Op/λ0) and `fields[j]` (complex 3D amplitude,
/// Fresnel phases included, path phase excluded) are contribution `j` (see [`Contribution`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContributionColumns {
    /// Coherence ids; 0 adds intensity only.
    pub coherence_ids: Vec<u64>,
    /// Path phases in cycles.
    pub phase_cycles: Vec<f64>,
    /// Complex 3D field amplitudes.
    pub fields: Vec<Field3>,
}

impl ContributionColumns {
    /// Empty columns with room for `n` contributions.
    pub fn with_capacity(n: usize) -> Self {
        ContributionColumns {
            coherence_ids: Vec::with_capacity(n),
            phase_cycles: Vec::with_capacity(n),
            fields: Vec::with_capacity(n),
        }
    }

    /// Appends one contribution.
    pub fn push(&mut self, c: &Contribution) {
        self.coherence_ids.push(c.coherence_id);
        self.phase_cycles.push(c.phase_cycles);
        self.fields.push(c.field);
    }

    /// Number of contributions (panics if the columns have different lengths).
    pub fn len(&self) -> usize {
        self.check_lengths();
        self.coherence_ids.len()
    }

    /// Whether there are no contributions.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Removes every contribution (keeps the allocations).
    pub fn clear(&mut self) {
        self.coherence_ids.clear();
        self.phase_cycles.clear();
        self.fields.clear();
    }

    /// Contribution `j` as a row.
    pub fn get(&self, j: usize) -> Contribution {
        Contribution {
            coherence_id: self.coherence_ids[j],
            phase_cycles: self.phase_cycles[j],
            field: self.fields[j],
        }
    }

    fn check_lengths(&self) {
        assert!(
            self.phase_cycles.len() == self.coherence_ids.len()
                && self.fields.len() == self.coherence_ids.len(),
            "columns must have equal lengths (ids {}, phases {}, fields {})",
            self.coherence_ids.len(),
            self.phase_cycles.len(),
            self.fields.len()
        );
    }
}

impl From<&[Contribution]> for ContributionColumns {
    fn from(rows: &[Contribution]) -> Self {
        let mut cols = ContributionColumns::with_capacity(rows.len());
        for c in rows {
            cols.push(c);
        }
        cols
    }
}

/// Cosines and sines of one block of phasors, each row on its own cache lines, and, for the
/// AVX-512F kernel, the byte offset of each contribution's group sum ([`INCOHERENT_OFFSET`] for
/// id 0) and each sine as the pair (−sin, sin) (`pair[2j]`, `pair[2j + 1]`: the lane pattern of
/// `GroupTable::add_field`'s `m`, which one 16-byte broadcast load spreads over a register).
#[derive(Clone, Debug)]
#[repr(C, align(64))]
pub(super) struct TrigBlock {
    cos: [f64; BLOCK],
    sin: [f64; BLOCK],
    offset: [u64; BLOCK],
    pair: [f64; 2 * BLOCK],
}

impl Default for TrigBlock {
    fn default() -> Self {
        TrigBlock {
            cos: [0.0; BLOCK],
            sin: [0.0; BLOCK],
            offset: [0; BLOCK],
            pair: [0.0; 2 * BLOCK],
        }
    }
}

/// The group-offset marker of an id-0 (incoherent) contribution in [`TrigBlock::offset`].
const INCOHERENT_OFFSET: u64 = u64::MAX;

/// Bytes from one group sum to the next in `GroupTable::sums`.
const SUM_BYTES: u64 = std::mem::size_of::<GroupSum>() as u64;

/// The code that adds columns. Every kernel gives the same bits ([`Accumulator::add`]'s).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ColumnKernel {
    /// The fastest the running CPU has (what [`Accumulator::extend_columns`] and the batch
    /// functions use).
    #[default]
    Auto,
    /// One contribution at a time through [`Accumulator::add_parts`]'s code (any CPU).
    Portable,
    /// 4-lane phasors; a contribution's field in a 4-lane and a 2-lane register (x86-64 AVX2).
    Avx2,
    /// 8-lane phasors; a contribution's field in one 8-lane register (x86-64 AVX2 + AVX-512F).
    Avx512,
}

impl ColumnKernel {
    /// Whether the running CPU can run this kernel.
    pub fn available(self) -> bool {
        match self {
            ColumnKernel::Auto | ColumnKernel::Portable => true,
            #[cfg(target_arch = "x86_64")]
            ColumnKernel::Avx2 => super::avx2(),
            #[cfg(target_arch = "x86_64")]
            ColumnKernel::Avx512 => super::avx2() && std::arch::is_x86_feature_detected!("avx512f"),
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The kernel that runs: `Auto` resolved to the fastest available.
    fn resolve(self) -> ColumnKernel {
        match self {
            ColumnKernel::Auto if ColumnKernel::Avx512.available() => ColumnKernel::Avx512,
            ColumnKernel::Auto if ColumnKernel::Avx2.available() => ColumnKernel::Avx2,
            ColumnKernel::Auto => ColumnKernel::Portable,
            k => k,
        }
    }
}

impl Accumulator {
    /// Adds contributions given as columns: `(coherence_ids[j], phase_cycles[j], fields[j])`
    /// is added as by [`Accumulator::add_parts`], in order, with the same bits. The three
    /// slices must have equal lengths (panics otherwise).
    pub fn extend_columns(
        &mut self,
        coherence_ids: &[u64],
        phase_cycles: &[f64],
        fields: &[Field3],
    ) {
        self.extend_columns_using(ColumnKernel::Auto, coherence_ids, phase_cycles, fields);
    }

    /// [`Accumulator::extend_columns`] through the given kernel (all give the same bits; for
    /// tests and benches). Panics if the running CPU cannot run it ([`ColumnKernel::available`])
    /// or if the slices have different lengths.
    pub fn extend_columns_using(
        &mut self,
        kernel: ColumnKernel,
        coherence_ids: &[u64],
        phase_cycles: &[f64],
        fields: &[Field3],
    ) {
        assert!(
            kernel.available(),
            "columns: kernel {kernel:?} is not available on this CPU"
        );
        assert!(
            phase_cycles.len() == coherence_ids.len() && fields.len() == coherence_ids.len(),
            "columns must have equal lengths (ids {}, phases {}, fields {})",
            coherence_ids.len(),
            phase_cycles.len(),
            fields.len()
        );
        self.invalidate();
        let comp = self.summation == Summation::Compensated;
        let (a, b, c) = (coherence_ids, phase_cycles, fields);
        match kernel.resolve() {
            // SAFETY (both arms): `resolve` returns a SIMD kernel only where the running CPU
            // has its features (AVX2; AVX2 and AVX-512F), all that the kernel requires.
            // Measured reason: module docs (Performance) and the `columns_*` benches in
            // benches/accumulate.rs.
            #[cfg(target_arch = "x86_64")]
            ColumnKernel::Avx512 => unsafe {
                if comp {
                    self.columns_avx512::<true>(a, b, c)
                } else {
                    self.columns_avx512::<false>(a, b, c)
                }
            },
            #[cfg(target_arch = "x86_64")]
            ColumnKernel::Avx2 => unsafe {
                if comp {
                    self.columns_avx2::<true>(a, b, c)
                } else {
                    self.columns_avx2::<false>(a, b, c)
                }
            },
            _ => {
                for ((&id, &c), f) in a.iter().zip(b).zip(c) {
                    if comp {
                        self.add_mode::<true>(id, c, f);
                    } else {
                        self.add_mode::<false>(id, c, f);
                    }
                }
            }
        }
    }

    /// The column kernel compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn columns_avx2<const COMP: bool>(&mut self, ids: &[u64], cycles: &[f64], fields: &[Field3]) {
        self.columns_kernel::<COMP, false>(ids, cycles, fields)
    }

    /// The column kernel compiled for AVX-512F: the phasor loop in 8 lanes and a
    /// contribution's six field components in one register (same operations, same bits).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,avx512f")]
    fn columns_avx512<const COMP: bool>(&mut self, ids: &[u64], cycles: &[f64], fields: &[Field3]) {
        self.columns_kernel::<COMP, true>(ids, cycles, fields)
    }

    /// The column kernel: a block's phasors in one vector loop, then each contribution's
    /// `E·e^{i2πc}` added to its group (4-lane (x, y) and 2-lane (z) operations, or one 8-lane
    /// masked operation when `W512`), with the ids and phases two blocks ahead and the fields
    /// one block ahead asked for by prefetch hints.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn columns_kernel<const COMP: bool, const W512: bool>(
        &mut self,
        ids: &[u64],
        cycles: &[f64],
        fields: &[Field3],
    ) {
        use std::arch::x86_64::*;
        let Accumulator {
            table,
            incoherent,
            trig,
            ..
        } = self;
        let trig = trig.get_or_insert_with(Box::default);
        let mut start = 0;
        while start < ids.len() {
            let len = (ids.len() - start).min(BLOCK);
            let (idb, cyb, fb) = (
                &ids[start..start + len],
                &cycles[start..start + len],
                &fields[start..start + len],
            );
            // Phasors of the block (`phasor_from_cycles`, bit for bit).
            let mut all_fast = true;
            for ((co, si), &c) in trig.cos[..len]
                .iter_mut()
                .zip(trig.sin[..len].iter_mut())
                .zip(cyb)
            {
                let t = 4.0 * c;
                let fast = t.abs() < FAST_LIMIT;
                let p = phasor_quarters(if fast { t } else { 0.0 });
                (*co, *si) = (p.re, p.im);
                all_fast &= fast;
            }
            if !all_fast {
                for ((co, si), &c) in trig.cos[..len]
                    .iter_mut()
                    .zip(trig.sin[..len].iter_mut())
                    .zip(cyb)
                {
                    let p = phasor_from_cycles(c);
                    (*co, *si) = (p.re, p.im);
                }
            }
            // Ask for the ids and phases two blocks ahead (64 bytes a line, 8 per line).
            for k in (0..BLOCK).step_by(8) {
                prefetch(cycles.as_ptr().wrapping_add(start + 2 * BLOCK + k));
                prefetch(ids.as_ptr().wrapping_add(start + 2 * BLOCK + k));
            }
            if W512 {
                // SAFETY: the caller has AVX2 and AVX-512F (`columns_avx512`).
                unsafe {
                    sine_pairs_512(trig, len);
                    group_offsets_512(table, idb, &mut trig.offset);
                    add_block_512::<COMP>(table, incoherent, trig, fields, start, len);
                }
                start += len;
                continue;
            }
            // Grouped sums.
            // SAFETY (loads below): `first` is a `[u64; 4]` (32 bytes, unaligned load).
            let mut first = unsafe { _mm256_loadu_si256(table.first.as_ptr().cast()) };
            for j in 0..len {
                let (id, field) = (idb[j], &fb[j]);
                // The field a block ahead (48 bytes apart: every cache line is asked for).
                prefetch(std::ptr::from_ref(field).wrapping_add(BLOCK));
                if id == INCOHERENT {
                    let e2 = field[0].norm_sqr() + field[1].norm_sqr() + field[2].norm_sqr();
                    incoherent.add(e2, COMP);
                    continue;
                }
                // SAFETY: the caller has AVX2 (`columns_avx2`, `columns_avx512`).
                let hit = unsafe {
                    _mm256_movemask_pd(_mm256_castsi256_pd(_mm256_cmpeq_epi64(
                        first,
                        _mm256_set1_epi64x(id as i64),
                    )))
                };
                let g = if hit != 0 {
                    hit.trailing_zeros() as usize
                } else {
                    let g = table.group(id);
                    // SAFETY: as above.
                    first = unsafe { _mm256_loadu_si256(table.first.as_ptr().cast()) };
                    g
                };
                // SAFETY: the caller has AVX2 (`columns_avx2`, `columns_avx512`).
                unsafe { add_one_256::<COMP>(&mut table.sums[g], field, trig.cos[j], trig.sin[j]) }
            }
            start += len;
        }
    }
}

/// The group of every contribution of a block, as the byte offset of its sum in `table.sums`
/// (`g · size_of::<GroupSum>()`, or [`INCOHERENT_OFFSET`] for id 0), groups created in order of
/// first appearance exactly as `GroupTable::group` one contribution at a time would. Eight ids
/// at a time: one 8-lane compare against each of the first four groups' ids gives the offsets
/// of a chunk whose ids all belong to those groups (the common case, about one vector
/// instruction per contribution); id-0 lanes get [`INCOHERENT_OFFSET`] by mask, and the other
/// lanes (a new id, or a fifth or later group) one `GroupTable::group` call per distinct id,
/// lowest lane first, whose offset goes to all the lanes of that id by one more compare (the
/// first chunk of a point, where every id is new: one call per group, not per lane).
///
/// # Safety
/// The CPU must have AVX2 and AVX-512F.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn group_offsets_512(table: &mut super::GroupTable, ids: &[u64], offset: &mut [u64; BLOCK]) {
    use std::arch::x86_64::*;
    let lane_by_lane = |table: &mut super::GroupTable, r: std::ops::Range<usize>, o: &mut [u64]| {
        for (o, &id) in o[r.clone()].iter_mut().zip(&ids[r]) {
            *o = if id == INCOHERENT {
                INCOHERENT_OFFSET
            } else {
                SUM_BYTES * table.group(id) as u64
            };
        }
    };
    let mut j = 0;
    // SAFETY: AVX-512F is the caller's promise; `ids[j..j + 8]` is in bounds (loop condition)
    // and `offset[j..j + 8]` too (`ids.len() ≤ BLOCK`), both unaligned 64-byte moves.
    unsafe {
        let zero = _mm512_setzero_si512();
        while j + 8 <= ids.len() {
            let id = _mm512_loadu_si512(ids.as_ptr().add(j).cast());
            // `first` holds 0 for a group not created yet: lanes with id 0 are excluded from
            // the fast case, so a match is always a group that exists.
            let f = new_first_groups_512(table, id);
            let k0 = _mm512_cmpeq_epi64_mask(id, _mm512_set1_epi64(f[0] as i64));
            let k1 = _mm512_cmpeq_epi64_mask(id, _mm512_set1_epi64(f[1] as i64));
            let k2 = _mm512_cmpeq_epi64_mask(id, _mm512_set1_epi64(f[2] as i64));
            let k3 = _mm512_cmpeq_epi64_mask(id, _mm512_set1_epi64(f[3] as i64));
            let kz = _mm512_cmpeq_epi64_mask(id, zero);
            let b = SUM_BYTES as i64;
            let mut o = _mm512_maskz_mov_epi64(k1, _mm512_set1_epi64(b));
            o = _mm512_mask_mov_epi64(o, k2, _mm512_set1_epi64(2 * b));
            o = _mm512_mask_mov_epi64(o, k3, _mm512_set1_epi64(3 * b));
            // Lanes of neither id 0 nor one of the first four groups (a new id, or a fifth and
            // later group): one `GroupTable::group` call per distinct such id, lowest lane
            // first (so new groups are created in order of first appearance), its offset
            // given to every lane of that id at once. None of these ids is in `first` (else
            // its lanes would have matched), so every lane of the id is among them.
            let mut rest = !((k0 | k1 | k2 | k3) & !kz | kz);
            while rest != 0 {
                let id_l = ids[j + rest.trailing_zeros() as usize];
                let g = table.group(id_l);
                let same = _mm512_cmpeq_epi64_mask(id, _mm512_set1_epi64(id_l as i64));
                o = _mm512_mask_mov_epi64(o, same, _mm512_set1_epi64(b * g as i64));
                rest &= !same;
            }
            o = _mm512_mask_mov_epi64(o, kz, _mm512_set1_epi64(INCOHERENT_OFFSET as i64));
            _mm512_storeu_si512(offset.as_mut_ptr().add(j).cast(), o);
            j += 8;
        }
    }
    if j < ids.len() {
        lane_by_lane(table, j..ids.len(), offset);
    }
}

/// The ids of the first four groups (`table.first`) after creating, if the point has at most
/// four groups and this chunk of eight ids (`id`) brings new ones that keep it at four or
/// fewer, those groups, in order of first appearance in the chunk, without a branch per id: the
/// first lane of each distinct new id by seven shifted compares, the new ids gathered in order
/// by one compress and put after the existing ones in `first`, `table.ids` and (zero sums)
/// `table.sums`. Any other chunk (new ids beyond the fourth group, or a point past four
/// groups) is left to [`group_offsets_512`]'s lookup per distinct id. Same groups, same order
/// as `GroupTable::group` one id at a time.
///
/// # Safety
/// The CPU must have AVX-512F.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn new_first_groups_512(
    table: &mut super::GroupTable,
    id: std::arch::x86_64::__m512i,
) -> [u64; 4] {
    use std::arch::x86_64::*;
    let n = table.ids.len();
    if n >= 4 {
        return table.first;
    }
    // SAFETY: AVX-512F is the caller's promise. `first` is `[u64; 4]` (32-byte unaligned moves);
    // `reserve(4)` makes room for four more entries of `ids` and `sums`, of which the first
    // `d ≤ 4 − n` are written and then counted by `set_len` (the other written ones are
    // beyond the length, unread).
    unsafe {
        let zero = _mm512_setzero_si512();
        let f = _mm512_castsi256_si512(_mm256_loadu_si256(table.first.as_ptr().cast()));
        // Lanes of an id that is neither 0 nor one of the point's groups yet (`first` holds 0
        // for a group not created yet, which matches only the id-0 lanes).
        let fs = table.first;
        let known = _mm512_cmpeq_epi64_mask(id, zero)
            | _mm512_cmpeq_epi64_mask(id, _mm512_set1_epi64(fs[0] as i64))
            | _mm512_cmpeq_epi64_mask(id, _mm512_set1_epi64(fs[1] as i64))
            | _mm512_cmpeq_epi64_mask(id, _mm512_set1_epi64(fs[2] as i64))
            | _mm512_cmpeq_epi64_mask(id, _mm512_set1_epi64(fs[3] as i64));
        let new = !known;
        if new == 0 {
            return table.first;
        }
        // Lanes whose id is also in a lower lane (lane l against lane l − r, r = 1..8).
        let seen = _mm512_cmpeq_epi64_mask(id, _mm512_alignr_epi64::<7>(id, zero))
            | _mm512_cmpeq_epi64_mask(id, _mm512_alignr_epi64::<6>(id, zero))
            | _mm512_cmpeq_epi64_mask(id, _mm512_alignr_epi64::<5>(id, zero))
            | _mm512_cmpeq_epi64_mask(id, _mm512_alignr_epi64::<4>(id, zero))
            | _mm512_cmpeq_epi64_mask(id, _mm512_alignr_epi64::<3>(id, zero))
            | _mm512_cmpeq_epi64_mask(id, _mm512_alignr_epi64::<2>(id, zero))
            | _mm512_cmpeq_epi64_mask(id, _mm512_alignr_epi64::<1>(id, zero));
        let firsts = new & !seen;
        let d = firsts.count_ones() as usize;
        if n + d > 4 {
            return table.first;
        }
        // The new ids in order of first appearance, in lanes 0..d.
        let u = _mm512_castsi512_si256(_mm512_maskz_compress_epi64(firsts, id));
        let f = _mm512_mask_expand_epi64(f, ((1u8 << d) - 1) << n, _mm512_castsi256_si512(u));
        _mm256_storeu_si256(table.first.as_mut_ptr().cast(), _mm512_castsi512_si256(f));
        table.ids.reserve(4);
        _mm256_storeu_si256(table.ids.as_mut_ptr().add(n).cast(), u);
        table.ids.set_len(n + d);
        table.sums.reserve(4);
        for k in 0..4 {
            table
                .sums
                .as_mut_ptr()
                .add(n + k)
                .write(GroupSum::default());
        }
        table.sums.set_len(n + d);
    }
    table.first
}

/// `trig.pair[2j]`, `trig.pair[2j + 1]` = (−`trig.sin[j]`, `trig.sin[j]`) for `j < len` (rounded
/// up to a multiple of eight; the lanes past `len` hold stale sines nobody reads). The negation
/// is a sign flip, as `-phasor.im` in `GroupTable::add_field`. Per eight sines one xor and two
/// two-source permutes, instead of one xor per contribution in the sums.
///
/// # Safety
/// The CPU must have AVX-512F; `len ≤ BLOCK`.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn sine_pairs_512(trig: &mut TrigBlock, len: usize) {
    use std::arch::x86_64::*;
    // SAFETY: AVX-512F is the caller's promise; `8k + 8 ≤ BLOCK` (k < ⌈len/8⌉ ≤ BLOCK/8), so
    // `sin[8k..8k + 8]` and `pair[16k..16k + 16]` are in bounds (unaligned 64-byte moves).
    unsafe {
        let sign = _mm512_set1_epi64(i64::MIN);
        let lo = _mm512_set_epi64(11, 3, 10, 2, 9, 1, 8, 0);
        let hi = _mm512_set_epi64(15, 7, 14, 6, 13, 5, 12, 4);
        for k in 0..len.div_ceil(8) {
            let s = _mm512_loadu_pd(trig.sin.as_ptr().add(8 * k));
            let n = _mm512_castsi512_pd(_mm512_xor_si512(_mm512_castpd_si512(s), sign));
            // (−s0, s0, −s1, s1, −s2, s2, −s3, s3) and the same of lanes 4..8.
            let p = trig.pair.as_mut_ptr().add(16 * k);
            _mm512_storeu_pd(p, _mm512_permutex2var_pd(n, lo, s));
            _mm512_storeu_pd(p.add(8), _mm512_permutex2var_pd(n, hi, s));
        }
    }
}

/// Adds the block `fields[start..start + len]` whose group offsets [`group_offsets_512`] has
/// found (`trig.offset`) and whose phasors are in `trig.cos`, `trig.pair` ([`sine_pairs_512`]):
/// each contribution through [`add_one_512`] into its group's sum, or its |E|² into the
/// incoherent sum, in order; the fields a block ahead asked for by prefetch hints. A field that
/// another one of `fields` follows is read by one unmasked 64-byte load (its six components and
/// the next field's x in lanes 6, 7, which reach only the sums' padding); the last of `fields`
/// by a masked load of its 48 bytes.
///
/// # Safety
/// The CPU must have AVX-512F; `start + len ≤ fields.len()`, `len ≤ BLOCK`;
/// `trig.offset[..len]` must be offsets of groups that exist in `table.sums` (or
/// [`INCOHERENT_OFFSET`]), as [`group_offsets_512`] writes them.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn add_block_512<const COMP: bool>(
    table: &mut super::GroupTable,
    incoherent: &mut super::CompSum,
    trig: &TrigBlock,
    fields: &[Field3],
    start: usize,
    len: usize,
) {
    use std::arch::x86_64::*;
    let base = table.sums.as_mut_ptr().cast::<u8>();
    let f0 = fields.as_ptr().wrapping_add(start);
    // Contributions `0..full` of the block have another field after theirs in `fields`.
    let full = len.min(fields.len() - start - 1);
    // (A loop body in an `#[inline(always)]` function, not a closure: a closure that is not
    // inlined does not get the AVX-512F of its caller, and its intrinsics become calls.)
    for j in 0..full {
        // SAFETY: `start + j + 1 < fields.len()`: the 64 bytes from `fields[start + j]` lie in
        // it and the next field (unaligned load); the rest: the caller's promises.
        unsafe {
            let a = _mm512_loadu_pd(f0.add(j).cast::<f64>());
            add_at_512::<COMP>(base, incoherent, trig, f0.add(j), j, a);
        }
    }
    for j in full..len {
        // SAFETY: `fields[start + j]` is 6 contiguous f64 (`Field3`: three `#[repr(C)]`
        // `Complex64`), masked load of those 6; the rest: the caller's promises.
        unsafe {
            let a = _mm512_maskz_loadu_pd(0b0011_1111, f0.add(j).cast::<f64>());
            add_at_512::<COMP>(base, incoherent, trig, f0.add(j), j, a);
        }
    }
}

/// Contribution `j` of a block in [`add_block_512`]: its field `*field` (also in `a`, lanes
/// 0..6) added with the phasor `trig.cos[j]`, `trig.pair[2j..2j + 2]` to the group sum at byte
/// offset `trig.offset[j]` from `base`, or its |E|² to `incoherent`; the field a block ahead
/// asked for.
///
/// # Safety
/// The CPU must have AVX-512F; `j < BLOCK`; `field` points to a `Field3`; `trig.offset[j]` is
/// [`INCOHERENT_OFFSET`] or `g · size_of::<GroupSum>()` of a group sum `g` of the table that
/// `base` points to, which nothing else refers to during the call.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn add_at_512<const COMP: bool>(
    base: *mut u8,
    incoherent: &mut super::CompSum,
    trig: &TrigBlock,
    field: *const Field3,
    j: usize,
    a: std::arch::x86_64::__m512d,
) {
    use std::arch::x86_64::*;
    // The field a block ahead (48 bytes apart: every cache line is asked for).
    prefetch(field.wrapping_add(BLOCK));
    let off = trig.offset[j];
    if off == INCOHERENT_OFFSET {
        // SAFETY: `field` points to a `Field3` (the caller's promise).
        let f = unsafe { &*field };
        let e2 = f[0].norm_sqr() + f[1].norm_sqr() + f[2].norm_sqr();
        incoherent.add(e2, COMP);
        return;
    }
    // SAFETY: `base + off` is group sum `g`, aligned, not referred to elsewhere (the caller's
    // promise); `2j + 2 ≤ 2 BLOCK` (a 16-byte load of `pair`); AVX-512F: the caller's promise.
    unsafe {
        let sum = &mut *base.add(off as usize).cast::<GroupSum>();
        // `vbroadcastf32x4` (AVX-512F; the f64x2 form is AVX-512DQ): the same 16 bytes.
        let pair = _mm_castpd_ps(_mm_loadu_pd(trig.pair.as_ptr().add(2 * j)));
        let m = _mm512_castps_pd(_mm512_broadcast_f32x4(pair));
        add_one_512::<COMP>(sum, a, trig.cos[j], m);
    }
}

/// A hint to bring the cache line of `p` into L1 (no effect on results). `p` may point anywhere,
/// past the end of its allocation included: a prefetch never faults (callers form it with
/// `wrapping_add`).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn prefetch<T>(p: *const T) {
    use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
    // SAFETY: `_mm_prefetch` (SSE, baseline x86-64) only hints the cache; the address is never
    // dereferenced.
    unsafe { _mm_prefetch::<_MM_HINT_T0>(p.cast::<i8>()) };
}

/// `sum += E·(co + i si)` with the operations and operand order of `GroupTable::add_field`
/// and `two_sum_add` (no FMA), in 4-lane (x, y) and 2-lane (z) form.
///
/// # Safety
/// The CPU must have AVX2.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn add_one_256<const COMP: bool>(sum: &mut GroupSum, field: &Field3, co: f64, si: f64) {
    use std::arch::x86_64::*;
    let f = field.as_ptr().cast::<f64>();
    // SAFETY: `Field3` is three `Complex64` (`#[repr(C)]` re, im): 6 contiguous f64 at `f`;
    // `sum.s` and `sum.c` are `[f64; 6]` at 64-byte aligned offsets of the
    // `#[repr(C, align(64))]` `GroupSum`, so elements 0..4 are 32-byte and 4..6 16-byte aligned
    // (aligned loads and stores). AVX2: the caller's promise.
    unsafe {
        // Lanes (re, im, re, im): −sin in the re lanes, +sin in the im lanes.
        let neg_re = _mm256_set_pd(0.0, -0.0, 0.0, -0.0);
        let a = _mm256_loadu_pd(f); // x.re x.im y.re y.im
        let a2 = _mm_loadu_pd(f.add(4)); // z.re z.im
        let b = _mm256_permute_pd::<0b0101>(a); // x.im x.re y.im y.re
        let b2 = _mm_permute_pd::<0b01>(a2);
        let pc = _mm256_set1_pd(co);
        let m = _mm256_xor_pd(_mm256_set1_pd(si), neg_re);
        // (fr·pc + fi·(−ps), fi·pc + fr·ps): `add_field`'s lane form.
        let p = _mm256_add_pd(_mm256_mul_pd(a, pc), _mm256_mul_pd(b, m));
        let p2 = _mm_add_pd(
            _mm_mul_pd(a2, _mm256_castpd256_pd128(pc)),
            _mm_mul_pd(b2, _mm256_castpd256_pd128(m)),
        );
        let sp = sum.s.as_mut_ptr();
        let s = _mm256_load_pd(sp);
        let s2 = _mm_load_pd(sp.add(4));
        if COMP {
            // TwoSum (`two_sum_add`): t = s + x, z = t − s, c += (s − (t − z)) + (x − z), s = t.
            let cp = sum.c.as_mut_ptr();
            let t = _mm256_add_pd(s, p);
            let z = _mm256_sub_pd(t, s);
            let e = _mm256_add_pd(_mm256_sub_pd(s, _mm256_sub_pd(t, z)), _mm256_sub_pd(p, z));
            _mm256_store_pd(cp, _mm256_add_pd(_mm256_load_pd(cp), e));
            _mm256_store_pd(sp, t);
            let t2 = _mm_add_pd(s2, p2);
            let z2 = _mm_sub_pd(t2, s2);
            let e2 = _mm_add_pd(_mm_sub_pd(s2, _mm_sub_pd(t2, z2)), _mm_sub_pd(p2, z2));
            _mm_store_pd(cp.add(4), _mm_add_pd(_mm_load_pd(cp.add(4)), e2));
            _mm_store_pd(sp.add(4), t2);
        } else {
            _mm256_store_pd(sp, _mm256_add_pd(s, p));
            _mm_store_pd(sp.add(4), _mm_add_pd(s2, p2));
        }
    }
}

/// [`add_one_256`] with the six field components (x, y, z; re, im) in lanes 0..6 of one
/// 8-lane register `a` and the sine as `m` = (−sin, sin, −sin, sin, …): the same operations
/// lane by lane, so the same bits. The group sum is loaded and stored as its whole 64-byte line
/// (`s` and its padding; `c` and its padding; lanes 6 and 7 of the product, whatever `a` holds
/// there, go only to the padding, which nothing reads): a plain aligned store that the next
/// contribution of the group can load without a masked-store forwarding stall.
///
/// # Safety
/// The CPU must have AVX-512F.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn add_one_512<const COMP: bool>(
    sum: &mut GroupSum,
    a: std::arch::x86_64::__m512d,
    co: f64,
    m: std::arch::x86_64::__m512d,
) {
    use std::arch::x86_64::*;
    // SAFETY: `GroupSum` is `#[repr(C, align(64))]` { s: [f64; 6], _pad_s: [f64; 2],
    // c: [f64; 6], _pad_c: [f64; 2] }: 16 f64, `s` + `_pad_s` the first 64-byte aligned line
    // and `c` + `_pad_c` the second, read and written through a pointer to the whole struct.
    // AVX-512F: the caller's promise.
    unsafe {
        let b = _mm512_permute_pd::<0b0101_0101>(a); // x.im x.re y.im y.re z.im z.re · ·
        let pc = _mm512_set1_pd(co);
        // (fr·pc + fi·(−ps), fi·pc + fr·ps): `add_field`'s lane form. Lanes 6, 7 only reach
        // the padding (no mask: a masked add costs one more shuffle-port operation,
        // `vexpandpd`, per contribution).
        let p = _mm512_add_pd(_mm512_mul_pd(a, pc), _mm512_mul_pd(b, m));
        let sp = std::ptr::from_mut(sum).cast::<f64>();
        let s = _mm512_load_pd(sp);
        if COMP {
            // TwoSum (`two_sum_add`): t = s + x, z = t − s, c += (s − (t − z)) + (x − z), s = t.
            let cp = sp.add(8);
            let t = _mm512_add_pd(s, p);
            let z = _mm512_sub_pd(t, s);
            let e = _mm512_add_pd(_mm512_sub_pd(s, _mm512_sub_pd(t, z)), _mm512_sub_pd(p, z));
            _mm512_store_pd(cp, _mm512_add_pd(_mm512_load_pd(cp), e));
            _mm512_store_pd(sp, t);
        } else {
            _mm512_store_pd(sp, _mm512_add_pd(s, p));
        }
    }
}

/// Intensities of many points from columns (eq. 6 at each): point `k` owns contributions
/// `offsets[k]..offsets[k + 1]` and its intensity goes to `out[k]`. The same layout rules and
/// the same bits as [`super::accumulate_points`] on the rows (panics on bad offsets).
pub fn accumulate_columns(
    columns: &ContributionColumns,
    offsets: &[usize],
    summation: Summation,
    out: &mut [f64],
) {
    accumulate_columns_using(ColumnKernel::Auto, columns, offsets, summation, out);
}

/// [`accumulate_columns`] through the given kernel (all give the same bits; for tests and
/// benches). Panics if the running CPU cannot run it ([`ColumnKernel::available`]).
pub fn accumulate_columns_using(
    kernel: ColumnKernel,
    columns: &ContributionColumns,
    offsets: &[usize],
    summation: Summation,
    out: &mut [f64],
) {
    check_offsets(columns.len(), offsets, out);
    let mut acc = Accumulator::with_summation(summation);
    for (k, o) in out.iter_mut().enumerate() {
        *o = point_intensity(kernel, &mut acc, columns, offsets[k]..offsets[k + 1]);
    }
}

/// [`accumulate_columns`] in parallel over points (rayon's current pool), bit for bit the same.
pub fn accumulate_columns_par(
    columns: &ContributionColumns,
    offsets: &[usize],
    summation: Summation,
    out: &mut [f64],
) {
    check_offsets(columns.len(), offsets, out);
    par_over_points(columns.len(), summation, out, |acc, k| {
        point_intensity(ColumnKernel::Auto, acc, columns, offsets[k]..offsets[k + 1])
    });
}

fn point_intensity(
    kernel: ColumnKernel,
    acc: &mut Accumulator,
    columns: &ContributionColumns,
    r: std::ops::Range<usize>,
) -> f64 {
    acc.clear();
    acc.extend_columns_using(
        kernel,
        &columns.coherence_ids[r.clone()],
        &columns.phase_cycles[r.clone()],
        &columns.fields[r],
    );
    acc.intensity()
}
