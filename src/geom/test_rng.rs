//! Deterministic pseudo-random numbers for the geometry modules' tests (xorshift64), so
//! that a failure reproduces from its seed.

use super::P3;

/// Xorshift64 from a non-zero seed.
pub(crate) struct Rng(pub u64);

impl Rng {
    /// The next 64 random bits.
    #[allow(clippy::should_implement_trait)]
    pub fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [-0.5, 0.5).
    pub fn f(&mut self) -> f64 {
        self.unit() - 0.5
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform in 0..n.
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    pub fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.below(xs.len())]
    }

    pub fn shuffle<T>(&mut self, xs: &mut [T]) {
        for i in (1..xs.len()).rev() {
            xs.swap(i, self.below(i + 1));
        }
    }

    /// A point uniform in the cube of side `s` around the origin.
    pub fn v(&mut self, s: f64) -> P3 {
        [self.f() * s, self.f() * s, self.f() * s]
    }

    /// A unit direction (rejection from the ball shell 0.1..1).
    pub fn dir(&mut self) -> P3 {
        loop {
            let v = self.v(2.0);
            let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if n > 0.1 && n < 1.0 {
                return v.map(|x| x / n);
            }
        }
    }

    /// Positive barycentric weights.
    pub fn bary(&mut self) -> [f64; 3] {
        let w = [self.f() + 0.55, self.f() + 0.55, self.f() + 0.55];
        let s = w[0] + w[1] + w[2];
        w.map(|x| x / s)
    }
}

/// The rotation matrix of the unit quaternion `[w, x, y, z]`.
pub(crate) fn rotation_of([w, x, y, z]: [f64; 4]) -> [[f64; 3]; 3] {
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}
