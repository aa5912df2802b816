//! The reprojection in two sweeps over the motion vectors, for claims
//! reaching further than the one sweep of `sweep.rs` allows: all
//! claims first ([`claim_all`]), then the winners' and recycling steps,
//! over sources with a ring of marks sized to the furthest claim
//! ([`assign_by_sources`]), or past the ring's 2^17 pixels per pixel, as the
//! GPU does ([`assign_by_pixels`]). Same output and counts as the one sweep.

use crate::permutation::layout::FrameParams;
use crate::reprojection::batch::{claim_batch, for_each_batch, Batch};
use crate::reprojection::claims::{index_bits, take_if_won, ReprojectStats, CLAIM_NONE};
use crate::reprojection::ring::{fits_ring, for_each_unseeded, RING_WORDS};

/// The reprojection in two sweeps (module docs).
pub(crate) fn reproject_two_sweeps(
    params: &FrameParams,
    motion: &[[f32; 2]],
    seeds_in: &[u32],
    claims: &mut [u32],
    out: &mut [u32],
) -> ReprojectStats {
    let span = claim_all(params, motion, claims);
    let mut ring = [0u64; RING_WORDS];
    if fits_ring(params, span, ring.len()) {
        assign_by_sources(params, seeds_in, claims, out, span, &mut ring)
    } else {
        assign_by_pixels(params, motion, seeds_in, claims, out)
    }
}

/// The claim step: leaves in `claims[q]` the minimum key over the pixels
/// whose source is visible pixel `q`, or [`CLAIM_NONE`]. Padding entries are
/// neither written nor read later (padding claims itself and always wins).
/// A row of `claims` is cleared when the first claim reaches it (or at the
/// end), so there is no separate clearing sweep. Returns the largest
/// distance in rows between a pixel and its source.
pub(crate) fn claim_all(params: &FrameParams, motion: &[[f32; 2]], claims: &mut [u32]) -> usize {
    let bits = index_bits(params.padded_width * params.padded_height);
    let (w, h, pw) = (
        params.width as usize,
        params.height as usize,
        params.padded_width as usize,
    );
    claims[..w].fill(CLAIM_NONE);
    let mut ready = 1; // rows [0, ready) of `claims` are cleared
    let mut span = 0;
    let mut batch = Batch::new();
    for_each_batch(w, motion, |y, x0, lanes, m| {
        // Rows within `span` of `y` and already cleared need no look.
        let rows = (y.saturating_sub(span) as u32, (y + span).min(ready - 1) as u32);
        if claim_batch(params, bits, (x0 as u32, y as u32), m, &mut batch, false, rows) {
            for (&t, &k) in batch.target[..lanes].iter().zip(&batch.key[..lanes]) {
                let row = t as usize / pw;
                if k != CLAIM_NONE || row != y {
                    span = span.max(row.abs_diff(y));
                    if row >= ready {
                        for r in claims[ready * pw..(row + 1) * pw].chunks_exact_mut(pw) {
                            r[..w].fill(CLAIM_NONE);
                        }
                        ready = row + 1;
                    }
                }
            }
        }
        batch.apply(lanes, claims);
    });
    for row in claims[ready * pw..h * pw].chunks_exact_mut(pw) {
        row[..w].fill(CLAIM_NONE);
    }
    span
}

/// The unclaimed visible sources in buffer order (the recycled seeds),
/// found by scanning `claims` (final after [`claim_all`]) 64 entries at a
/// time.
struct FreeSources {
    /// Next entry to scan: row and column.
    y: usize,
    x: usize,
    /// Unclaimed entries not yet handed out among the 64 scanned last,
    /// which start at `base`.
    pending: u64,
    base: usize,
}

impl FreeSources {
    fn new() -> Self {
        FreeSources {
            y: 0,
            x: 0,
            pending: 0,
            base: 0,
        }
    }

    /// The next unclaimed source.
    ///
    /// # Panics
    /// When there is none: more pixels without a seed than unclaimed
    /// sources would be a bug (module docs).
    #[inline]
    fn next(&mut self, claims: &[u32], w: usize, h: usize, pw: usize) -> usize {
        while self.pending == 0 {
            assert!(self.y < h, "as many unclaimed sources as pixels without a seed");
            self.base = self.y * pw + self.x;
            let lanes = (w - self.x).min(64);
            let entries = &claims[self.base..self.base + lanes];
            // Most windows have no unclaimed entry: a maximum (vectorised)
            // finds out before the per-entry mask.
            if entries.iter().copied().max() == Some(CLAIM_NONE) {
                self.pending = entries
                    .iter()
                    .enumerate()
                    .fold(0, |m, (i, &c)| m | u64::from(c == CLAIM_NONE) << i);
            }
            self.x += lanes;
            if self.x == w {
                (self.x, self.y) = (0, self.y + 1);
            }
        }
        let q = self.base + self.pending.trailing_zeros() as usize;
        self.pending &= self.pending - 1;
        q
    }
}

/// The winners' and recycling steps over the claims, without the motion
/// vectors: source `q` in buffer order hands its seed to the pixel in its
/// key's low bits and marks that pixel in `ring`. A pixel row `span` rows
/// above the source row is then final (no later source has a winner
/// there): its unmarked pixels take the next unclaimed sources' seeds.
/// `ring`: zeroed, a power of two words, [`fits_ring`].
pub(crate) fn assign_by_sources(
    params: &FrameParams,
    seeds_in: &[u32],
    claims: &[u32],
    out: &mut [u32],
    span: usize,
    ring: &mut [u64],
) -> ReprojectStats {
    let bits = index_bits(params.padded_width * params.padded_height);
    let (w, h, pw) = (
        params.width as usize,
        params.height as usize,
        params.padded_width as usize,
    );
    debug_assert!(ring.len().is_power_of_two() && fits_ring(params, span, ring.len()));
    let ring_mask = ring.len() * 64 - 1;
    let index_mask = ((1u64 << bits) - 1) as u32;
    let mut free = FreeSources::new();
    let mut recycled = 0;
    let mut finish_row = |y: usize, out: &mut [u32], ring: &mut [u64]| {
        for_each_unseeded(ring, ring_mask, y * pw, w, |p| {
            out[p] = seeds_in[free.next(claims, w, h, pw)];
            recycled += 1;
        });
    };
    for r in 0..h {
        let row = r * pw;
        // Marks gather in a register while the winners stay in one ring
        // word (the common case: coherent motion), so consecutive sources
        // do not wait on each other through memory.
        let (mut word, mut marks) = (0, 0u64);
        for q in row..row + w {
            let c = claims[q];
            if c != CLAIM_NONE {
                let p = (c & index_mask) as usize;
                out[p] = seeds_in[q];
                let b = p & ring_mask;
                if b >> 6 != word {
                    ring[word] |= marks;
                    (word, marks) = (b >> 6, 0);
                }
                marks |= 1 << (b & 63);
            }
        }
        ring[word] |= marks;
        out[row + w..row + pw].copy_from_slice(&seeds_in[row + w..row + pw]);
        if r >= span {
            finish_row(r - span, out, ring);
        }
    }
    for y in h.saturating_sub(span)..h {
        finish_row(y, out, ring);
    }
    out[h * pw..].copy_from_slice(&seeds_in[h * pw..]);
    ReprojectStats {
        followed: (w * h) as u32 - recycled,
        recycled,
    }
}

/// The winners' and recycling steps in pixel order, recomputing each
/// pixel's claim from its motion vector (the form of [`take_if_won`]): for
/// claims too far from their pixels for [`assign_by_sources`]'s ring.
pub(crate) fn assign_by_pixels(
    params: &FrameParams,
    motion: &[[f32; 2]],
    seeds_in: &[u32],
    claims: &[u32],
    out: &mut [u32],
) -> ReprojectStats {
    let bits = index_bits(params.padded_width * params.padded_height);
    let (w, h, pw) = (
        params.width as usize,
        params.height as usize,
        params.padded_width as usize,
    );
    let mut stats = ReprojectStats::default();
    let mut free = FreeSources::new();
    let mut batch = Batch::new();
    for_each_batch(w, motion, |y, x0, lanes, m| {
        claim_batch(
            params,
            bits,
            (x0 as u32, y as u32),
            m,
            &mut batch,
            true,
            (0, u32::MAX),
        );
        let row = y * pw + x0;
        for (i, (&s, &k)) in batch.source[..lanes].iter().zip(&batch.key[..lanes]).enumerate() {
            out[row + i] = if let Some(seed) = take_if_won(claims, seeds_in, s, k) {
                stats.followed += 1;
                seed
            } else {
                stats.recycled += 1;
                seeds_in[free.next(claims, w, h, pw)]
            };
        }
        if x0 + lanes == w {
            let pad = y * pw + w..(y + 1) * pw;
            out[pad.clone()].copy_from_slice(&seeds_in[pad]);
        }
    });
    out[h * pw..].copy_from_slice(&seeds_in[h * pw..]);
    stats
}
