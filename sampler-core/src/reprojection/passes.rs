//! The seed reprojection ([`reproject_frame`](crate::reproject_frame)) as data-parallel passes, the
//! form a GPU runs: the same rule and the same output as
//! [`reproject_frame`](crate::reproject_frame), bit for bit.
//!
//! # Passes, in dispatch order
//!
//! | pass | invocations | reads | writes |
//! |---|---|---|---|
//! | 1. clear | one per seed | | `claims[i] = CLAIM_NONE` ([`clear_claim`]) |
//! | 2. claim | one per visible pixel | motion | `atomicMin(claims[source], key)` ([`claim_at`]) |
//! | 3. take | one per chunk | motion, claims, seeds in | winners' and padding seeds out; chunk counts ([`take_chunk`]) |
//! | 4. scan | one workgroup of [`SCAN_LANES`] | chunk counts | exclusive offsets, in place ([`scan_chunk_counts`], in segments) |
//! | 5. list | one per chunk | claims, offsets | the unclaimed sources, in buffer order ([`list_free_chunk`]) |
//! | 6. recycle | one per chunk | motion, claims, offsets, free list, seeds in | the seeds of pixels without one ([`recycle_chunk`]) |
//!
//! A **chunk** is [`REPROJECT_CHUNK`] consecutive indices of the padded seed
//! buffer (the last one may be short); there are [`chunk_count`] of them.
//! The chunk counts buffer holds two `u32` per chunk: at `2c` the number of
//! visible pixels of chunk `c` without a seed (lost their claim, or had no
//! source), at `2c + 1` its unclaimed visible sources. The scan turns both
//! into exclusive prefix sums over chunks, so pass 5 writes the `k`-th
//! unclaimed source of the frame to `free[k]` and pass 6 gives the `k`-th
//! pixel without a seed `seeds_in[free[k]]`: the recycling order of
//! [`reproject_frame`](crate::reproject_frame).
//!
//! Only pass 2 needs atomics (a `u32` minimum, which is order independent,
//! so the result is deterministic); the claim itself is [`claim_at`], shared
//! with the CPU pass. Padding seeds are never claimed by a visible pixel and
//! stay put (pass 3), so their claims entries are not read.
//!
//! Buffers (all `u32` unless said): claims and seeds `seed_count`, the free
//! list `seed_count` (at most that many sources are unclaimed), motion
//! `width * height` `Vec2` (pixels, backward, NaN for disocclusion, as
//! [`reproject_frame`](crate::reproject_frame) takes it), chunk counts
//! `2 * chunk_count`.

use crate::permutation::layout::FrameParams;
use crate::reprojection::claims::{claim_at, index_bits, CLAIM_NONE};
use glam::Vec2;

/// Seeds per chunk of passes 3, 5 and 6 (one invocation each).
pub const REPROJECT_CHUNK: u32 = 256;

/// Number of chunks of the padded seed buffer of `params`:
/// `ceil(seed_count / REPROJECT_CHUNK)`.
#[inline]
pub fn chunk_count(params: &FrameParams) -> u32 {
    params.seed_count().div_ceil(REPROJECT_CHUNK)
}

/// Pass 1: the value every claims entry starts a frame with.
#[inline]
pub fn clear_claim() -> u32 {
    CLAIM_NONE
}

/// The padded-buffer index range `[start, end)` of chunk `chunk`.
#[inline]
pub(super) fn chunk_range(params: &FrameParams, chunk: u32) -> (u32, u32) {
    let start = chunk.wrapping_mul(REPROJECT_CHUNK);
    let end = start.wrapping_add(REPROJECT_CHUNK).min(params.seed_count());
    (start, end)
}

/// Whether seed-buffer index `i` is a visible pixel (not padding).
#[inline]
pub(super) fn is_visible(params: &FrameParams, i: u32) -> bool {
    i % params.padded_width < params.width && i / params.padded_width < params.height
}

/// Pass 2's claim `(source, key)` of the visible pixel at seed-buffer index
/// `i`; `source == CLAIM_NONE` when it has none.
#[inline]
pub(super) fn claim_of(params: &FrameParams, bits: u32, i: u32, motion: &[Vec2]) -> (u32, u32) {
    let x = i % params.padded_width;
    let y = i / params.padded_width;
    let m = motion[y.wrapping_mul(params.width).wrapping_add(x) as usize];
    claim_at(params, bits, x, y, [m.x, m.y])
}

/// Pass 2 for visible pixel `(x, y)`: `(source, key)` to `atomicMin` into
/// `claims[source]`, `source == CLAIM_NONE` when it claims nothing.
#[inline]
pub fn claim_pixel(params: &FrameParams, x: u32, y: u32, motion: &[Vec2]) -> (u32, u32) {
    let bits = index_bits(params.seed_count());
    let m = motion[y.wrapping_mul(params.width).wrapping_add(x) as usize];
    claim_at(params, bits, x, y, [m.x, m.y])
}

/// Pass 3 for chunk `chunk`: writes the seeds of winners (their source's)
/// and of padding (their own) to `seeds_out`, and the chunk's counts of
/// pixels without a seed and of unclaimed sources to `counts[2 * chunk]`
/// and `counts[2 * chunk + 1]`. `claims` holds every claim (pass 2 done).
#[inline]
pub fn take_chunk(
    params: &FrameParams,
    chunk: u32,
    motion: &[Vec2],
    claims: &[u32],
    seeds_in: &[u32],
    seeds_out: &mut [u32],
    counts: &mut [u32],
) {
    let bits = index_bits(params.seed_count());
    let (start, end) = chunk_range(params, chunk);
    let mut need = 0u32;
    let mut free = 0u32;
    let mut i = start;
    while i < end {
        if !is_visible(params, i) {
            seeds_out[i as usize] = seeds_in[i as usize];
        } else {
            let (source, key) = claim_of(params, bits, i, motion);
            if source != CLAIM_NONE && claims[source as usize] == key {
                seeds_out[i as usize] = seeds_in[source as usize];
            } else {
                need = need.wrapping_add(1);
            }
            if claims[i as usize] == CLAIM_NONE {
                free = free.wrapping_add(1);
            }
        }
        i = i.wrapping_add(1);
    }
    counts[(chunk * 2) as usize] = need;
    counts[(chunk * 2 + 1) as usize] = free;
}

/// Invocations of pass 4 (one workgroup; `kernels::reproject_entry::scan_cs`):
/// each sums a segment of [`scan_segment`] chunks, the workgroup scans the
/// `SCAN_LANES` sums, and each writes its segment's offsets.
pub const SCAN_LANES: u32 = 64;

/// The chunks `[first, end)` that lane `lane` (of [`SCAN_LANES`]) of pass 4
/// scans: consecutive segments of `ceil(chunks / SCAN_LANES)` chunks, in
/// lane order, the last ones short or empty. Together they cover
/// `0..chunks` once.
#[inline]
pub fn scan_segment(chunks: u32, lane: u32) -> (u32, u32) {
    let per = chunks.div_ceil(SCAN_LANES);
    let first = lane.wrapping_mul(per).min(chunks);
    (first, first.wrapping_add(per).min(chunks))
}

/// The sums `(need, free)` of the counts of chunks `[first, end)` (before
/// the scan): pass 4's first step, per lane.
#[inline]
pub fn sum_chunk_counts(counts: &[u32], first: u32, end: u32) -> (u32, u32) {
    let mut need = 0u32;
    let mut free = 0u32;
    let mut c = first;
    while c < end {
        need = need.wrapping_add(counts[(c * 2) as usize]);
        free = free.wrapping_add(counts[(c * 2 + 1) as usize]);
        c = c.wrapping_add(1);
    }
    (need, free)
}

/// Turns the counts of chunks `[first, end)` into exclusive prefix sums
/// that start at `(need, free)` (the totals of every chunk before `first`),
/// each of the two sequences on its own: pass 4's last step, per lane.
#[inline]
pub fn offset_chunk_counts(counts: &mut [u32], first: u32, end: u32, need: u32, free: u32) {
    let mut need = need;
    let mut free = free;
    let mut c = first;
    while c < end {
        let n = counts[(c * 2) as usize];
        let f = counts[(c * 2 + 1) as usize];
        counts[(c * 2) as usize] = need;
        counts[(c * 2 + 1) as usize] = free;
        need = need.wrapping_add(n);
        free = free.wrapping_add(f);
        c = c.wrapping_add(1);
    }
}

/// Pass 4 on one thread: turns the `chunks` pairs of counts into
/// exclusive prefix sums, each of the two sequences on its own. The GPU
/// computes the same sums in [`SCAN_LANES`] segments ([`scan_segment`],
/// [`sum_chunk_counts`], [`offset_chunk_counts`]).
#[inline]
pub fn scan_chunk_counts(chunks: u32, counts: &mut [u32]) {
    offset_chunk_counts(counts, 0, chunks, 0, 0);
}

/// Pass 5 for chunk `chunk`: writes the chunk's unclaimed visible sources,
/// in buffer order, to `free[offset..]` (`offset = counts[2 * chunk + 1]`
/// after the scan).
#[inline]
pub fn list_free_chunk(params: &FrameParams, chunk: u32, claims: &[u32], counts: &[u32], free: &mut [u32]) {
    let (start, end) = chunk_range(params, chunk);
    let mut k = counts[(chunk * 2 + 1) as usize];
    let mut i = start;
    while i < end {
        if is_visible(params, i) && claims[i as usize] == CLAIM_NONE {
            free[k as usize] = i;
            k = k.wrapping_add(1);
        }
        i = i.wrapping_add(1);
    }
}

/// Pass 6 for chunk `chunk`: gives each visible pixel of the chunk that
/// took no seed in pass 3, in buffer order, the seed of the next unclaimed
/// source: `seeds_in[free[k]]` from `k = counts[2 * chunk]` (after the scan).
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn recycle_chunk(
    params: &FrameParams,
    chunk: u32,
    motion: &[Vec2],
    claims: &[u32],
    counts: &[u32],
    free: &[u32],
    seeds_in: &[u32],
    seeds_out: &mut [u32],
) {
    let bits = index_bits(params.seed_count());
    let (start, end) = chunk_range(params, chunk);
    let mut k = counts[(chunk * 2) as usize];
    let mut i = start;
    while i < end {
        if is_visible(params, i) {
            let (source, key) = claim_of(params, bits, i, motion);
            if source == CLAIM_NONE || claims[source as usize] != key {
                seeds_out[i as usize] = seeds_in[free[k as usize] as usize];
                k = k.wrapping_add(1);
            }
        }
        i = i.wrapping_add(1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::permutation::layout::FrameLayout;
    use crate::reprojection::reproject_frame;

    const CAP: usize = 64 * 128;

    /// Passes 1 and 2 on one thread (the atomic minimum as a plain minimum):
    /// the claims both forms start from.
    fn claims(l: &FrameLayout, motion: &[Vec2]) -> [u32; CAP] {
        let p = l.params(0);
        let mut claims = [clear_claim(); CAP];
        for y in 0..p.height {
            for x in 0..p.width {
                let (s, k) = claim_pixel(&p, x, y, motion);
                if s != CLAIM_NONE {
                    claims[s as usize] = claims[s as usize].min(k);
                }
            }
        }
        claims
    }

    /// The six passes in order on one thread, as a GPU runs them.
    fn passes(l: &FrameLayout, motion: &[Vec2], seeds_in: &[u32], out: &mut [u32]) {
        let p = l.params(0);
        let n = l.seed_count();
        let claims = claims(l, motion);
        let mut free = [0u32; CAP];
        let mut counts = [0u32; 2 * CAP / REPROJECT_CHUNK as usize + 2];
        let chunks = chunk_count(&p);
        for c in 0..chunks {
            take_chunk(&p, c, motion, &claims[..n], seeds_in, out, &mut counts);
        }
        scan_chunk_counts(chunks, &mut counts);
        for c in 0..chunks {
            list_free_chunk(&p, c, &claims[..n], &counts, &mut free);
        }
        for c in 0..chunks {
            recycle_chunk(&p, c, motion, &claims[..n], &counts, &free, seeds_in, out);
        }
    }

    /// The per-seed form (`seed_passes`: passes 3a, 3b, 5 and 6 per seed or
    /// per chunk of flags), in order on one thread.
    fn seed_passes(l: &FrameLayout, motion: &[Vec2], seeds_in: &[u32], out: &mut [u32]) {
        use crate::reprojection::seed_passes::{count_chunk_flags, list_free_seed, recycle_seed, take_seed};
        let p = l.params(0);
        let n = l.seed_count();
        let claims = claims(l, motion);
        let mut flags = [u32::MAX; CAP];
        let mut free = [0u32; CAP];
        let mut counts = [0u32; 2 * CAP / REPROJECT_CHUNK as usize + 2];
        for i in 0..n as u32 {
            take_seed(&p, i, motion, &claims[..n], seeds_in, out, &mut flags[..n]);
        }
        let chunks = chunk_count(&p);
        for c in 0..chunks {
            count_chunk_flags(&p, c, &flags[..n], &mut counts);
        }
        scan_chunk_counts(chunks, &mut counts);
        for i in 0..n as u32 {
            list_free_seed(i, &flags[..n], &counts, &mut free);
        }
        for i in 0..n as u32 {
            recycle_seed(i, &flags[..n], &counts, &free, seeds_in, out);
        }
    }

    /// Pass 4 as the GPU runs it (segment sums, a scan of the lanes' sums,
    /// segment offsets) equals the one-thread scan, for chunk counts around
    /// multiples of the lanes.
    #[test]
    fn the_segmented_scan_equals_the_serial_scan() {
        for chunks in [0u32, 1, 2, 63, 64, 65, 127, 130, 3840, 4001] {
            let mut serial = [0u32; 2 * 4001];
            let n = 2 * chunks as usize;
            for (i, c) in serial[..n].iter_mut().enumerate() {
                *c = (i as u32).wrapping_mul(0x9e37_79b9) >> 24;
            }
            let mut lanes = serial;
            scan_chunk_counts(chunks, &mut serial);
            let mut sums = [(0u32, 0u32); SCAN_LANES as usize];
            let mut covered = 0;
            for lane in 0..SCAN_LANES {
                let (first, end) = scan_segment(chunks, lane);
                assert!(
                    first == covered.min(chunks) && first <= end,
                    "{chunks}: lane {lane}"
                );
                covered = end;
                sums[lane as usize] = sum_chunk_counts(&lanes, first, end);
            }
            assert_eq!(covered, chunks);
            let (mut need, mut free) = (0u32, 0u32);
            for lane in 0..SCAN_LANES {
                let (first, end) = scan_segment(chunks, lane);
                let (n, f) = sums[lane as usize];
                offset_chunk_counts(&mut lanes, first, end, need, free);
                need = need.wrapping_add(n);
                free = free.wrapping_add(f);
            }
            assert_eq!(lanes[..n], serial[..n], "{chunks} chunks");
        }
    }

    #[test]
    fn the_passes_equal_reproject_frame() {
        // Sizes with padding on both axes, several chunks and a short last one.
        for (w, h) in [(23u32, 17u32), (64, 64), (70, 5), (1, 1)] {
            let l = FrameLayout::new(w, h, 4, 64).unwrap();
            let n = l.seed_count();
            assert!(n <= CAP);
            let mut seeds = [0u32; CAP];
            seeds[..n]
                .iter_mut()
                .enumerate()
                .for_each(|(i, s)| *s = (i as u32).wrapping_mul(0x9e37_79b9));
            let fields: [fn(u32, u32, u32) -> Vec2; 6] = [
                |_, _, _| Vec2::new(-2.0, 0.5),
                |x, y, _| Vec2::new(3.0 - x as f32, 2.0 - y as f32),
                |_, _, _| Vec2::NAN,
                |x, y, _| Vec2::new((y as f32 - 8.0) * 0.3, -(x as f32 - 11.0) * 0.3),
                |x, y, _| Vec2::new((x as f32 - 11.0) * -0.5, (y as f32 - 8.0) * 0.25),
                |x, y, s| {
                    let h = (x ^ y.rotate_left(11) ^ s).wrapping_mul(0x2c1b_3c6d);
                    if h % 7 == 0 {
                        Vec2::splat(f32::INFINITY)
                    } else {
                        Vec2::new(
                            (h >> 8 & 15) as f32 * 0.7 - 5.0,
                            (h >> 16 & 15) as f32 * 0.6 - 4.0,
                        )
                    }
                },
            ];
            let mut motion = [Vec2::ZERO; CAP];
            let mut motion_arr = [[0.0f32; 2]; CAP];
            for (f, field) in fields.iter().enumerate() {
                for y in 0..h {
                    for x in 0..w {
                        let i = (y * w + x) as usize;
                        motion[i] = field(x, y, f as u32);
                        motion_arr[i] = motion[i].to_array();
                    }
                }
                let m = (w * h) as usize;
                let mut expected = [0u32; CAP];
                let mut claims = [0u32; CAP];
                reproject_frame(
                    &l,
                    &motion_arr[..m],
                    &seeds[..n],
                    &mut claims[..n],
                    &mut expected[..n],
                )
                .unwrap();
                let mut got = [0u32; CAP];
                passes(&l, &motion[..m], &seeds[..n], &mut got[..n]);
                assert_eq!(got[..n], expected[..n], "{w}x{h}, field {f}");
                let mut got = [0u32; CAP];
                seed_passes(&l, &motion[..m], &seeds[..n], &mut got[..n]);
                assert_eq!(got[..n], expected[..n], "per seed, {w}x{h}, field {f}");
            }
        }
    }
}
