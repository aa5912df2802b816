//! Scalar spatiotemporal blue noise (the energy of Wolfe, Morrical,
//! Akenine-Moller & Ramamoorthi's STBN; our own implementation).
//!
//! Void-and-cluster over a `W x H x D` volume whose energy couples two
//! texels only if they lie in the same slice (2D Gaussian of their toroidal
//! distance) or at the same pixel in different slices (1D Gaussian of the
//! toroidal slice distance). Each slice is then blue in space and each
//! pixel's sequence blue in time. The volume-wide ranks are finally
//! re-ranked within each slice, so every slice holds each of `0..W*H`
//! exactly once (the volume-wide histogram of STBN is only roughly uniform
//! per slice).

use super::energy::Kernel;
use super::void_and_cluster::rank_texels;
use super::{check_sigma, check_size, BakeError, Progress};
use alloc::vec::Vec;

/// Parameters of a spatiotemporal mask.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StbnParams {
    /// Width in texels: a power of two.
    pub width: u32,
    /// Height in texels: a power of two.
    pub height: u32,
    /// Number of slices (frames): a power of two.
    pub depth: u32,
    /// Spatial Gaussian sigma in texels (1.9 in STBN).
    pub sigma: f64,
    /// Temporal Gaussian sigma in slices (1.9 in STBN).
    pub temporal_sigma: f64,
    /// Seed of the random initial pattern.
    pub seed: u64,
}

/// Bakes a spatiotemporal mask: `width * height * depth` ranks, slice-major
/// then row-major (`index = (z * height + y) * width + x`); within each
/// slice every rank of `0..width * height` occurs exactly once.
///
/// Sides must be powers of two within [`MAX_MASK_SIDE`](super::MAX_MASK_SIDE)
/// and the volume at most [`MAX_MASK_TEXELS`](super::MAX_MASK_TEXELS).
///
/// # Errors
/// [`BakeError::Size`], [`BakeError::Sigma`] (either sigma).
pub fn bake_stbn(params: &StbnParams, progress: Progress<'_>) -> Result<Vec<u32>, BakeError> {
    check_size(params.width, params.height, params.depth)?;
    check_sigma(params.sigma)?;
    check_sigma(params.temporal_sigma)?;
    let kernel = Kernel::new(
        params.width,
        params.height,
        params.depth,
        params.sigma,
        params.temporal_sigma,
    );
    let mut ranks = rank_texels(&kernel, params.seed, progress);
    rerank_slices(&mut ranks, params.width as usize * params.height as usize);
    Ok(ranks)
}

/// Replaces the ranks of each slice of `slice_len` texels by their order
/// within the slice (ties cannot occur: volume ranks are distinct).
fn rerank_slices(ranks: &mut [u32], slice_len: usize) {
    let mut order: Vec<u32> = Vec::with_capacity(slice_len);
    for slice in ranks.chunks_mut(slice_len) {
        order.clear();
        order.extend(0..slice.len() as u32);
        order.sort_unstable_by_key(|&i| slice[i as usize]);
        for (rank, &i) in order.iter().enumerate() {
            slice[i as usize] = rank as u32;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bake::no_progress;
    use alloc::vec;

    #[test]
    fn every_slice_has_an_exact_histogram() {
        for (w, h, d) in [(8, 8, 1), (8, 4, 2), (16, 16, 8), (4, 4, 32)] {
            let p = StbnParams {
                width: w,
                height: h,
                depth: d,
                sigma: 1.9,
                temporal_sigma: 1.9,
                seed: 2,
            };
            let ranks = bake_stbn(&p, &mut no_progress).unwrap();
            let n = (w * h) as usize;
            assert_eq!(ranks.len(), n * d as usize);
            for slice in ranks.chunks(n) {
                let mut seen = vec![false; n];
                for &r in slice {
                    assert!(!core::mem::replace(&mut seen[r as usize], true));
                }
            }
        }
    }

    /// Each pixel's sequence over time is blue: consecutive slices differ
    /// much more than independent ranks would (|a - b| averages n/3 for
    /// independent uniform ranks), because the temporal kernel pushes a
    /// pixel's ranks in neighbouring slices apart.
    #[test]
    fn neighbouring_slices_are_anticorrelated() {
        let p = StbnParams {
            width: 16,
            height: 16,
            depth: 16,
            sigma: 1.9,
            temporal_sigma: 1.9,
            seed: 4,
        };
        let ranks = bake_stbn(&p, &mut no_progress).unwrap();
        let n = 256usize;
        let mut sum = 0.0;
        for z in 0..16 {
            for i in 0..n {
                let a = ranks[z * n + i] as f64;
                let b = ranks[((z + 1) % 16) * n + i] as f64;
                sum += (a - b).abs();
            }
        }
        let mean = sum / (16.0 * n as f64) / n as f64;
        assert!(mean > 0.4, "mean |delta rank| / n = {mean} (independent: 1/3)");
    }

    #[test]
    fn rerank_orders_within_slices() {
        let mut r = vec![7, 2, 9, 0, 5, 1];
        rerank_slices(&mut r, 3);
        assert_eq!(r, vec![1, 0, 2, 0, 2, 1]);
    }
}
