//! Pixel seeds and the random streams they define.
//!
//! A **seed** is a `u32` that determines every random number a pixel uses in
//! a frame: the whole stream for every sample and path vertex. The sorting
//! and retargeting passes move seeds between pixels; they never change a seed.
//!
//! The stream of a seed is counter based: number `i` of the stream is
//! `hash(seed ^ hash(i))`, so any dimension can be drawn directly
//! ([`random_u32`]) or in order ([`RandomStream`]). All arithmetic is `u32`
//! with `wrapping_*`, identical on the host and in shaders.

/// PCG-RXS-M-XS 32-bit output permutation applied to one LCG step
/// (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering").
///
/// A bijection on `u32`: distinct inputs give distinct outputs.
#[inline]
pub fn hash_u32(x: u32) -> u32 {
    // LCG step (Knuth's MMIX multiplier, PCG's default increment).
    let state = x.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    // Random xorshift (shift picked by the top 4 bits), multiply, xorshift.
    let word = ((state >> ((state >> 28).wrapping_add(4))) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// Initial (white-noise) seed of pixel `(x, y)` in a seed buffer `stride`
/// seeds wide; `salt` selects an independent set (e.g. a run index).
///
/// Distinct pixels of one buffer get distinct seeds (a bijective hash of the
/// row-major index), so no two pixels start correlated.
///
/// # Example
///
/// ```
/// use sampler_core::initial_seed;
/// let (w, h) = (64, 32);
/// let mut seeds: Vec<u32> = (0..h).flat_map(|y| (0..w).map(move |x| initial_seed(x, y, w, 0))).collect();
/// seeds.sort();
/// seeds.dedup();
/// assert_eq!(seeds.len(), (w * h) as usize); // all distinct
/// assert_ne!(initial_seed(0, 0, w, 0), initial_seed(0, 0, w, 1)); // another salt, another set
/// ```
#[inline]
pub fn initial_seed(x: u32, y: u32, stride: u32, salt: u32) -> u32 {
    hash_u32(y.wrapping_mul(stride).wrapping_add(x) ^ hash_u32(salt))
}

/// Salt of frame `frame`'s fresh white-noise seeds ([`initial_seed`]) in a
/// run salted `salt` that draws new seeds every frame: `salt` itself for
/// frame 0, a hash of both afterwards.
///
/// Runs with different salts are independent on every frame. (Adding the
/// frame to the salt, as the white-noise mode once did, made the run salted
/// `s + 1` replay the frames of the run salted `s` one frame later, so a
/// scatter over salts measured one realisation.)
///
/// # Example
///
/// ```
/// use sampler_core::sequences::seed::frame_salt;
/// assert_eq!(frame_salt(7, 0), 7);
/// assert_ne!(frame_salt(1, 2), frame_salt(2, 1));
/// ```
#[inline]
pub fn frame_salt(salt: u32, frame: u32) -> u32 {
    if frame == 0 {
        salt
    } else {
        hash_u32(hash_u32(salt) ^ hash_u32(frame.wrapping_add(0x6A09_E667)))
    }
}

/// Number `index` of the stream of `seed`, uniform over `u32`.
#[inline]
pub fn random_u32(seed: u32, index: u32) -> u32 {
    hash_u32(seed ^ hash_u32(index.wrapping_add(0x9E37_79B9)))
}

/// Number `index` of the stream of `seed`, uniform in `[0, 1)` with 24 bits.
///
/// # Example
///
/// ```
/// use sampler_core::random_f32;
/// let u = random_f32(0xC0FFEE, 3); // number 3 of the seed's stream
/// assert!((0.0..1.0).contains(&u));
/// assert_eq!(u, random_f32(0xC0FFEE, 3)); // a pure function of (seed, index)
/// ```
#[inline]
pub fn random_f32(seed: u32, index: u32) -> f32 {
    crate::sequences::r2::q32_to_f32(random_u32(seed, index))
}

/// Sequential reader of a seed's stream: sample `s` of a pixel starts at
/// stream index `s * dimensions_per_sample`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RandomStream {
    /// The pixel's seed.
    pub seed: u32,
    /// Next stream index to draw.
    pub index: u32,
}

impl RandomStream {
    /// Stream of `seed` positioned at the first dimension of sample `sample`
    /// when each sample uses `dimensions_per_sample` numbers.
    ///
    /// # Example
    ///
    /// ```
    /// use sampler_core::{random_u32, RandomStream};
    /// // Sample 2 of a pixel that draws 8 numbers per sample starts at index 16.
    /// let mut stream = RandomStream::new(42, 2, 8);
    /// assert_eq!(stream.next_u32(), random_u32(42, 16));
    /// assert_eq!(stream.next_u32(), random_u32(42, 17));
    /// ```
    #[inline]
    pub fn new(seed: u32, sample: u32, dimensions_per_sample: u32) -> Self {
        RandomStream {
            seed,
            index: sample.wrapping_mul(dimensions_per_sample),
        }
    }

    /// Next `u32` of the stream.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let v = random_u32(self.seed, self.index);
        self.index = self.index.wrapping_add(1);
        v
    }

    /// Next number of the stream in `[0, 1)`.
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        crate::sequences::r2::q32_to_f32(self.next_u32())
    }

    /// Next two numbers of the stream, in `[0, 1)^2`.
    #[inline]
    pub fn next_vec2(&mut self) -> glam::Vec2 {
        let x = self.next_f32();
        glam::Vec2::new(x, self.next_f32())
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    /// No two (salt, frame) pairs of a small grid share a frame salt, and
    /// frame 0 keeps the run's salt.
    #[test]
    fn frame_salts_of_different_runs_never_coincide() {
        let mut all = std::vec::Vec::new();
        for salt in 0..32u32 {
            assert_eq!(frame_salt(salt, 0), salt);
            for frame in 1..256u32 {
                all.push(frame_salt(salt, frame));
            }
        }
        let n = all.len();
        all.sort_unstable();
        all.dedup();
        assert_eq!(all.len(), n);
    }

    #[test]
    fn hash_is_injective_on_a_range() {
        // A bijection on u32: check injectivity on 2^16 consecutive inputs.
        let mut v: [u32; 1 << 16] = [0; 1 << 16];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = hash_u32(i as u32);
        }
        v.sort_unstable();
        assert!(v.windows(2).all(|w| w[0] != w[1]));
    }

    #[test]
    fn stream_reads_in_order() {
        let mut s = RandomStream::new(42, 3, 10);
        assert_eq!(s.next_u32(), random_u32(42, 30));
        assert_eq!(s.next_u32(), random_u32(42, 31));
        let f = random_f32(42, 7);
        assert!((0.0..1.0).contains(&f));
    }

    #[test]
    fn stream_mean_is_one_half() {
        let n = 100_000u32;
        let mean: f64 = (0..n).map(|i| random_f32(i / 17, i % 17) as f64).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 0.005, "{mean}");
    }
}
