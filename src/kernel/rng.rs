//! The crate's one seeded random generator: SplitMix64.
//!
//! Every random choice in the crate (the integration lines of the union's
//! measures, the synthetic trees, the tests' random inputs) draws from it with
//! a fixed seed, so every result is the same from run to run and from machine
//! to machine. It is small and fast, and good enough for geometry; nothing
//! here needs cryptographic quality.

use super::hash::mix64;

/// SplitMix64: a counter stepped by the golden ratio, mixed by SplitMix64's
/// finaliser.
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    /// The generator seeded with `seed` (any value, zero included).
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        let z = mix64(self.0);
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z
    }

    /// Uniform in [0, 1).
    pub fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform on the unit sphere.
    #[cfg(any(test, feature = "internals"))]
    pub fn unit(&mut self) -> glam::DVec3 {
        let z = 2.0 * self.f64() - 1.0;
        let phi = std::f64::consts::TAU * self.f64();
        let s = (1.0 - z * z).max(0.0).sqrt();
        glam::DVec3::new(s * phi.cos(), s * phi.sin(), z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_stream_and_uniform_mean() {
        let (mut a, mut b) = (Rng::new(3), Rng::new(3));
        let xs: Vec<f64> = (0..10_000).map(|_| a.f64()).collect();
        assert!(xs.iter().all(|&x| (0.0..1.0).contains(&x)));
        assert_eq!(xs[..5], (0..5).map(|_| b.f64()).collect::<Vec<_>>()[..]);
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        assert!((mean - 0.5).abs() < 0.01, "{mean}");
        let u = Rng::new(9).unit();
        assert!((u.length() - 1.0).abs() < 1e-12);
    }
}
