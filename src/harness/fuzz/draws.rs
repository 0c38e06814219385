//! The random source of `fringe fuzz`: seeded draws that are recorded, so a scene can be
//! regenerated from its recorded values with some of them replaced (the shrinker's move).
//!
//! Every value a generator uses comes from one of [`Draws::real`], [`Draws::choose`] or
//! [`Draws::flag`]. Recording stores each draw as one `f64` (the real itself, the option
//! index, 1 or 0 for a flag); replay returns the stored values clamped into each draw's own
//! range, so any replacement still yields a value the generator accepts. Generators put the
//! simplest option first (index 0, flag false), so shrinking a draw towards 0 simplifies the
//! scene.

/// SplitMix64 (Steele, Lea and Flood 2014): a small, well-mixed 64-bit generator; enough for
/// sampling scenes and fully reproducible from its seed on every platform.
#[derive(Clone, Debug)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    pub fn new(seed: u64) -> Self {
        SplitMix64(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
}

/// The seed of scene `index` of family number `family` in a run seeded with `seed`: each scene
/// has its own stream, so a scene does not depend on which other families or how many scenes
/// were asked for.
/// The run's seed is hashed before family and index are mixed in: mixed in directly
/// (`seed ^ index`), seeds 1 and 7 drew the same scenes at indices k and k ^ 6.
pub fn scene_seed(seed: u64, family: usize, index: usize) -> u64 {
    let run = SplitMix64::new(seed).next_u64();
    let mut m = SplitMix64::new(run ^ ((family as u64) << 56) ^ (index as u64));
    m.next_u64()
}

/// What kind of draw a recorded value came from (the shrinker's candidates depend on it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DrawKind {
    /// A real in [lo, hi].
    Real { lo: f64, hi: f64 },
    /// An option index (0 is the simplest).
    Choice,
    /// A flag (false, recorded as 0, is the simpler variant).
    Flag,
}

/// A recording (or replaying) stream of draws.
#[derive(Clone, Debug)]
pub struct Draws {
    rng: SplitMix64,
    replay: Vec<f64>,
    /// Every value drawn so far, in order.
    pub record: Vec<f64>,
    /// The kind of each recorded value.
    pub kinds: Vec<DrawKind>,
}

impl Draws {
    /// Fresh draws from a seed.
    pub fn new(seed: u64) -> Self {
        Draws {
            rng: SplitMix64::new(seed),
            replay: Vec::new(),
            record: Vec::new(),
            kinds: Vec::new(),
        }
    }

    /// Replay `values`; draws beyond them come from a fixed stream (deterministic).
    pub fn replay(values: Vec<f64>) -> Self {
        Draws {
            rng: SplitMix64::new(0x5EED),
            replay: values,
            record: Vec::new(),
            kinds: Vec::new(),
        }
    }

    /// The replayed value of the next draw, if any.
    fn replayed(&self) -> Option<f64> {
        self.replay.get(self.record.len()).copied()
    }

    /// A real uniform in [lo, hi].
    pub fn real(&mut self, lo: f64, hi: f64) -> f64 {
        let v = match self.replayed() {
            Some(v) if v.is_finite() => v.clamp(lo.min(hi), hi.max(lo)),
            Some(_) => lo,
            None => lo + (hi - lo) * self.rng.unit(),
        };
        self.record.push(v);
        self.kinds.push(DrawKind::Real { lo, hi });
        v
    }

    /// 10^u with u uniform in [log10 lo, log10 hi] (lo, hi > 0): log-uniform. The recorded
    /// value is the exponent.
    pub fn log(&mut self, lo: f64, hi: f64) -> f64 {
        10f64.powf(self.real(lo.log10(), hi.log10()))
    }

    /// An option index in 0..n, uniform (option 0 is the simplest).
    pub fn choose(&mut self, n: usize) -> usize {
        let n = n.max(1);
        let k = match self.replayed() {
            Some(v) if v.is_finite() => (v.round().max(0.0) as usize).min(n - 1),
            Some(_) => 0,
            None => ((self.rng.unit() * n as f64) as usize).min(n - 1),
        };
        self.record.push(k as f64);
        self.kinds.push(DrawKind::Choice);
        k
    }

    /// True with probability `p` (false is the simpler variant).
    pub fn flag(&mut self, p: f64) -> bool {
        let b = match self.replayed() {
            Some(v) => v != 0.0,
            None => self.rng.unit() < p,
        };
        self.record.push(if b { 1.0 } else { 0.0 });
        self.kinds.push(DrawKind::Flag);
        b
    }
}
