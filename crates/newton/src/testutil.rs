//! Seeded randomness for tests (fastrand, seeded).

/// Seeded test randomness: fastrand's generator with a fixed seed.
pub(crate) struct Lcg(fastrand::Rng);

impl Lcg {
    pub(crate) fn new(seed: u64) -> Self {
        Lcg(fastrand::Rng::with_seed(seed))
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0.u64(..)
    }

    /// Uniform in [0, 1).
    pub(crate) fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [-1, 1).
    pub(crate) fn sym(&mut self) -> f64 {
        2.0 * self.unit() - 1.0
    }
}
