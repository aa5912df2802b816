//! The reprojection in one sweep over the motion vectors, the common case
//! of [`reproject_frame`](crate::reproject_frame).
//!
//! Pixel row `y` claims (the keys of 16 pixels computed side by side,
//! `batch.rs`, with AVX2 where the CPU has it, then applied),
//! which makes source row `y - S` final while no claim reaches more than
//! `S = 16` rows (rows of claims are cleared `S` rows ahead, not in a
//! separate fill). That row hands out its seeds over the sources: the
//! winner of source `q` is the low [`index_bits`] of `claims[q]`, marked in
//! an on-stack ring of bits (16 KiB). Pixel row `y - 2S` is then final: its
//! unmarked pixels and the unclaimed sources are paired first in, first out
//! (both are met in buffer order, so the `k`-th gets the `k`-th), the
//! waiting ones queued in the rows of `claims` already read. A claim
//! reaching further gives up, and the caller starts over in two sweeps
//! (`two_sweeps.rs`).
//!
//! Memory traffic, the floor next to a copy: the pass reads 8 bytes of
//! motion and 4 of seeds and writes 4 of seeds per pixel (16 B), and its
//! claims are 4 B of scratch per pixel on top. In the sweep a claims line
//! is used while it is in cache, yet still fetched once (write-allocate)
//! and written back once: 8 B, so 24 B per pixel, plus 4 B for the
//! write-allocate of the seeds out. A copy of the same bytes (what the
//! bench measures) moves 12 B in and 12 B out, 24 B, or 36 B with
//! write-allocate. So a pass at the copy's speed is not excluded by the
//! traffic; what keeps it above is arithmetic (a key is about 15
//! instructions per pixel with SSE2, half with AVX2), one dependent
//! scattered minimum per pixel and one scattered store per seed.

use crate::permutation::cpu::prefetch;
use crate::permutation::layout::FrameParams;
use crate::reprojection::batch::{claim_batch, Batch, BATCH};
use crate::reprojection::claims::{index_bits, ReprojectStats, CLAIM_NONE};
use crate::reprojection::ring::{fits_ring, for_each_unseeded, RING_WORDS};
#[cfg(doc)]
use crate::reprojection::two_sweeps::assign_by_sources;

/// Rows a claim may reach from its pixel for [`reproject_fused`]: larger
/// keeps more vertical motion on the fused path, smaller keeps its rows of
/// claims and seeds in a smaller cache.
pub(crate) const FUSED_SPAN: usize = 16;

/// The whole reprojection in one sweep with the largest span (at most
/// [`FUSED_SPAN`]) whose marks fit the ring; `None` (having written
/// garbage) when a claim reaches further, or no span fits.
pub(crate) fn reproject_one_sweep(
    params: &FrameParams,
    motion: &[[f32; 2]],
    seeds_in: &[u32],
    claims: &mut [u32],
    out: &mut [u32],
) -> Option<ReprojectStats> {
    let span = (0..=FUSED_SPAN)
        .rev()
        .find(|&s| fits_ring(params, s, RING_WORDS))?;
    let mut ring = [0u64; RING_WORDS];
    reproject_fused(params, motion, seeds_in, claims, out, span, &mut ring)
}

/// Recycling queue of [`reproject_fused`], kept in the rows of `claims`
/// already read: the pixels without a seed still waiting for an unclaimed
/// source, or the unclaimed sources still waiting for such a pixel (never
/// both: one cancels the other, first in first out, which is the rule's
/// `k`-th with `k`-th since both are found in buffer order).
struct Recycling {
    head: usize,
    tail: usize,
    holds_pixels: bool,
}

impl Recycling {
    /// Pairs `index` (a pixel without a seed if `is_pixel`, else an
    /// unclaimed source) with the oldest waiting entry of the other kind, or
    /// queues it in `claims[..room]` (entries below `room` are read).
    /// Returns the pair `(pixel, source)`.
    #[inline]
    fn offer(
        &mut self,
        claims: &mut [u32],
        index: usize,
        is_pixel: bool,
        room: usize,
    ) -> Option<(usize, usize)> {
        if self.head != self.tail && self.holds_pixels != is_pixel {
            let other = claims[self.head] as usize;
            self.head += 1;
            if self.head == self.tail {
                (self.head, self.tail) = (0, 0);
            }
            return Some(if is_pixel { (index, other) } else { (other, index) });
        }
        self.holds_pixels = is_pixel;
        if self.tail == room {
            // The waiting entries are at most the pixels or sources already
            // visited, all below `room`: moving them down makes room.
            claims.copy_within(self.head..self.tail, 0);
            (self.head, self.tail) = (0, self.tail - self.head);
            assert!(self.tail < room, "recycling queue within the read claims");
        }
        claims[self.tail] = index as u32;
        self.tail += 1;
        None
    }
}

/// The whole reprojection in one sweep over the motion vectors, while every
/// claim stays within `span` rows of its pixel (rows of `claims` are
/// cleared `span` rows ahead; source row `y - span` is final once pixel row
/// `y` has claimed, and pixel row `y - 2 * span` once that source row is
/// handed out). The claims, seeds and marks it works on stay in cache.
/// Returns `None` (having written garbage) at the first claim further away;
/// the caller then runs the two-sweep form. `ring`: zeroed, a power of two
/// words, [`fits_ring`] for `span`. With AVX2 where the CPU has it (the
/// claims of a batch then take half the instructions).
pub(crate) fn reproject_fused(
    params: &FrameParams,
    motion: &[[f32; 2]],
    seeds_in: &[u32],
    claims: &mut [u32],
    out: &mut [u32],
    span: usize,
    ring: &mut [u64],
) -> Option<ReprojectStats> {
    #[cfg(target_arch = "x86_64")]
    if crate::permutation::cpu::avx2::available() {
        // SAFETY: the CPU and the OS support AVX2.
        return unsafe { avx2::reproject_fused(params, motion, seeds_in, claims, out, span, ring) };
    }
    fused_body(params, motion, seeds_in, claims, out, span, ring)
}

/// AVX2 builds of the fused sweep.
#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::*;

    /// [`fused_body`] compiled for AVX2.
    ///
    /// # Safety
    /// The CPU must support AVX2 (`permute_cpu::avx2::available`, the
    /// check the permutation's fast path uses).
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn reproject_fused(
        params: &FrameParams,
        motion: &[[f32; 2]],
        seeds_in: &[u32],
        claims: &mut [u32],
        out: &mut [u32],
        span: usize,
        ring: &mut [u64],
    ) -> Option<ReprojectStats> {
        fused_body(params, motion, seeds_in, claims, out, span, ring)
    }
}

/// The body of [`reproject_fused`], for each instruction set.
#[inline(always)]
pub(crate) fn fused_body(
    params: &FrameParams,
    motion: &[[f32; 2]],
    seeds_in: &[u32],
    claims: &mut [u32],
    out: &mut [u32],
    span: usize,
    ring: &mut [u64],
) -> Option<ReprojectStats> {
    let bits = index_bits(params.padded_width * params.padded_height);
    let (w, h, pw) = (
        params.width as usize,
        params.height as usize,
        params.padded_width as usize,
    );
    debug_assert!(ring.len().is_power_of_two() && fits_ring(params, span, ring.len()));
    let ring_mask = ring.len() * 64 - 1;
    let index_mask = ((1u64 << bits) - 1) as u32;
    let mut queue = Recycling {
        head: 0,
        tail: 0,
        holds_pixels: false,
    };
    let mut recycled = 0u32;
    let (mut ready, mut taken, mut finished) = (0, 0, 0); // rows cleared, sources handed out, pixels final
    let mut batch = Batch::new();
    for y in 0..=h {
        if y < h {
            for row in claims[ready * pw..(y + span + 1).min(h) * pw].chunks_exact_mut(pw) {
                row[..w].fill(CLAIM_NONE);
            }
            ready = ready.max((y + span + 1).min(h));
            let mut far = false;
            // The row handed out next: its seeds and output lines are fetched
            // while this row claims (one line per batch of 16).
            let next = (y + 1).saturating_sub(span) * pw;
            let rows = (y.saturating_sub(span) as u32, (y + span) as u32);
            // A plain loop, not `for_each_batch_in_row`: a closure would not
            // be inlined into the AVX2 build.
            let mut batches = motion[y * w..(y + 1) * w].chunks_exact(BATCH);
            let mut x0 = 0;
            for m in &mut batches {
                prefetch(out, next + x0, true);
                prefetch(seeds_in, next + x0, false);
                let m = m.try_into().expect("a batch");
                far |= claim_batch(params, bits, (x0 as u32, y as u32), m, &mut batch, false, rows);
                batch.apply(BATCH, claims);
                x0 += BATCH;
            }
            let rest = batches.remainder();
            if !rest.is_empty() {
                let mut m = [[f32::NAN; 2]; BATCH];
                m[..rest.len()].copy_from_slice(rest);
                far |= claim_batch(params, bits, (x0 as u32, y as u32), &m, &mut batch, false, rows);
                batch.apply(rest.len(), claims);
            }
            if far {
                return None;
            }
        }
        // Source rows below `y + 1 - span` are final (all of them after the last row).
        let final_sources = if y == h { h } else { (y + 1).saturating_sub(span) };
        while taken < final_sources {
            let row = taken * pw;
            let (mut word, mut marks) = (0, 0u64);
            // Claims and seeds are read a batch ahead of the batch whose
            // seeds are written: `out` sits at the same offsets modulo 4 KiB
            // as `claims` and `seeds_in` (page-aligned buffers), and a load
            // behind a store to such an address waits for it.
            let load = |claims: &[u32], q: usize| -> ([u32; BATCH], [u32; BATCH], usize) {
                let lanes = (row + w - q).min(BATCH);
                let (mut c, mut s) = ([CLAIM_NONE; BATCH], [0; BATCH]);
                c[..lanes].copy_from_slice(&claims[q..q + lanes]);
                s[..lanes].copy_from_slice(&seeds_in[q..q + lanes]);
                (c, s, lanes)
            };
            let mut ahead = load(claims, row);
            let mut q0 = row;
            while q0 < row + w {
                let (c, sd, lanes) = ahead;
                if q0 + lanes < row + w {
                    ahead = load(claims, q0 + lanes);
                }
                for i in 0..lanes {
                    if c[i] != CLAIM_NONE {
                        let p = (c[i] & index_mask) as usize;
                        out[p] = sd[i];
                        let b = p & ring_mask;
                        if b >> 6 != word {
                            ring[word] |= marks;
                            (word, marks) = (b >> 6, 0);
                        }
                        marks |= 1 << (b & 63);
                    } else if let Some((p, q)) = queue.offer(claims, q0 + i, false, q0 + i + 1) {
                        out[p] = seeds_in[q];
                    }
                }
                q0 += lanes;
            }
            ring[word] |= marks;
            out[row + w..row + pw].copy_from_slice(&seeds_in[row + w..row + pw]);
            taken += 1;
            // Pixel rows below `taken - span` have all their winners' sources handed out.
            let final_pixels = if taken == h { h } else { taken.saturating_sub(span) };
            while finished < final_pixels {
                let row = finished * pw;
                for_each_unseeded(ring, ring_mask, row, w, |p| {
                    recycled += 1;
                    if let Some((p, q)) = queue.offer(claims, p, true, taken * pw) {
                        out[p] = seeds_in[q];
                    }
                });
                finished += 1;
            }
        }
    }
    out[h * pw..].copy_from_slice(&seeds_in[h * pw..]);
    Some(ReprojectStats {
        followed: (w * h) as u32 - recycled,
        recycled,
    })
}
