//! Reproducible pseudo-random inputs for the crate's tests, examples and profiles, without a
//! dependency: Marsaglia's xorshift64 (shifts 13, 7, 17; "Xorshift RNGs", Journal of Statistical
//! Software 8(14), 2003). Period 2⁶⁴ − 1; not for statistics or anything secret.

/// xorshift64 generator; the same seed gives the same sequence on every platform.
#[derive(Debug, Clone)]
pub struct XorShift64(u64);

impl XorShift64 {
    /// A generator from a non-zero seed (zero is the one fixed point; it is replaced by 1).
    pub fn new(seed: u64) -> Self {
        XorShift64(seed.max(1))
    }

    /// The next 64-bit state.
    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }

    /// Uniform in [0, 1) from the state's top 53 bits.
    #[inline]
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Smooth keys for the examples and benchmarks: a walk of `n` unit quaternions whose steps
/// rotate by 0.3 … 0.65 rad (cycling every 8 keys) about axes that turn slowly (deterministic,
/// no generator).
pub fn profile_keys(n: usize) -> Vec<crate::quat::Quat> {
    use crate::quat::Quat;
    let mut q = vec![Quat::new(0.5, 0.5, -0.5, 0.5)];
    for k in 1..n {
        let a = 0.3 + 0.05 * (k % 8) as f64;
        let (s, c) = (0.5 * a).sin_cos();
        let ax = [(k as f64).sin(), (1.7 * k as f64).cos(), 0.5];
        let m = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
        q.push(q[k - 1] * Quat::new(c, s * ax[0] / m, s * ax[1] / m, s * ax[2] / m));
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sequence_is_marsaglias_and_uniform_is_in_range() {
        // x = 1: 1 ^ 1<<13 = 8193; ^ >>7 = 8193 ^ 64 = 8257; ^ <<17 = 8257 ^ 1082261504.
        let mut g = XorShift64::new(1);
        assert_eq!(g.next_u64(), 8257 ^ (8257 << 17));
        let mut g = XorShift64::new(42);
        let mut lo = 1.0f64;
        let mut hi = 0.0f64;
        for _ in 0..10_000 {
            let u = g.uniform();
            assert!((0.0..1.0).contains(&u));
            lo = lo.min(u);
            hi = hi.max(u);
        }
        assert!(lo < 0.01 && hi > 0.99);
        assert_eq!(XorShift64::new(0).next_u64(), XorShift64::new(1).next_u64());
    }
}
