//! The claim keys of 16 pixels at a time: [`claim_at`] written
//! lane-parallel without branches, so the compiler vectorises it (SSE2, or
//! AVX2 in the builds of `sweep.rs`), bit for bit the same keys.

use crate::permutation::layout::FrameParams;
use crate::reprojection::claims::{claim_at, CLAIM_NONE};

/// Pixels whose claims are computed side by side (the compiler vectorises
/// the batch), then applied one by one.
pub(crate) const BATCH: usize = 16;

/// The claims of a batch of [`BATCH`] pixels.
pub(crate) struct Batch {
    /// As [`claim_at`] returns them, bit for bit.
    pub(crate) source: [u32; BATCH],
    pub(crate) key: [u32; BATCH],
    /// Where to apply the claim: `source`, or for a lane without a source
    /// the batch's first pixel (visible), whose entry a minimum with
    /// `key = CLAIM_NONE` leaves as it is: no branch per lane.
    pub(crate) target: [u32; BATCH],
}

impl Batch {
    pub(crate) fn new() -> Self {
        Batch {
            source: [CLAIM_NONE; BATCH],
            key: [CLAIM_NONE; BATCH],
            target: [0; BATCH],
        }
    }

    /// Applies the first `lanes` claims: `claims[source] = min(claims[source], key)`.
    #[inline(always)]
    pub(crate) fn apply(&self, lanes: usize, claims: &mut [u32]) {
        for (&t, &k) in self.target[..lanes].iter().zip(&self.key[..lanes]) {
            let c = &mut claims[t as usize];
            *c = (*c).min(k);
        }
    }
}

/// Lane offsets of a batch, as floats.
const LANE_X: [f32; BATCH] = {
    let mut x = [0.0; BATCH];
    let mut i = 0;
    while i < BATCH {
        x[i] = i as f32;
        i += 1;
    }
    x
};

/// Claims of pixels `x0 .. x0 + BATCH` of row `y` (lanes past the row's end
/// carry NaN motion, so no source) into `batch` (`batch.source` only if
/// `with_source`). Returns whether a lane's source row lies outside
/// `rows` (inclusive bounds): the callers' rare case, which they then look
/// at lane by lane.
#[inline(always)]
pub(crate) fn claim_batch(
    params: &FrameParams,
    bits: u32,
    (x0, y): (u32, u32),
    motion: &[[f32; 2]; BATCH],
    batch: &mut Batch,
    with_source: bool,
    rows: (u32, u32),
) -> bool {
    let pw = params.padded_width;
    let index0 = y.wrapping_mul(pw).wrapping_add(x0);
    if bits < 8 {
        // Tiny buffers (at most 128 seeds): the quantisation levels are not
        // all exact in f32 here, so take `claim_at` itself.
        let mut outside = false;
        for (i, m) in motion.iter().enumerate() {
            let x = x0 + i as u32;
            let (s, k) = if x < params.width {
                claim_at(params, bits, x, y, *m)
            } else {
                (CLAIM_NONE, CLAIM_NONE)
            };
            (batch.source[i], batch.key[i]) = (s, k);
            batch.target[i] = if s != CLAIM_NONE { s } else { index0 + i as u32 };
            outside |= s != CLAIM_NONE && !(rows.0..=rows.1).contains(&(s / pw));
        }
        return outside;
    }
    // `claim_at` written lane-parallel, without branches. With `bits >= 8`
    // the levels are at most 2^24 - 2 and every index below 2^24, all exact
    // in f32 (so the source index is computed in f32: SSE2 has no 32-bit
    // integer multiply). A lane without a source has its position replaced
    // by 0 (its results are masked at the end), so every float-to-int
    // conversion is of a finite value in `0 ..= 2^24`.
    let (wf, hf, pwf) = (params.width as f32, params.height as f32, pw as f32);
    // The quantisation of `claim_at`: levels one below the largest the
    // distance bits hold, so no key equals `CLAIM_NONE`; exact in f32 here,
    // so the minimum in f32 equals `claim_at`'s on the integer.
    let levels = ((1u32 << (32 - bits)) - 2) as f32;
    let xf = x0 as f32;
    let yc = y as f32 + 0.5;
    let (low, high) = (rows.0 as f32, rows.1 as f32);
    let mut outside = false;
    for i in 0..BATCH {
        // `x as f32 + 0.5 + m` of `claim_at`: `xf + LANE_X[i]` is exact.
        let px = (xf + LANE_X[i]) + 0.5 + motion[i][0];
        let py = yc + motion[i][1];
        // Comparisons are false for NaN, so NaN and infinities fail.
        let inside = (px >= 0.0) & (py >= 0.0) & (px < wf) & (py < hf);
        let (px, py) = if inside { (px, py) } else { (0.0, 0.0) };
        // SAFETY: `px`, `py` are in `[0, 2^24]` (the visible frame, or 0).
        // `trunc(px) <= width - 1` when `px < width`: no `min` needed.
        let (qx, qy) = unsafe {
            (
                px.to_int_unchecked::<i32>() as f32,
                py.to_int_unchecked::<i32>() as f32,
            )
        };
        let dx = px - (qx + 0.5);
        let dy = py - (qy + 0.5);
        let v = (dx * dx + dy * dy) * 2.0 * levels;
        // SAFETY: `v` is finite and in `[0, levels]` after the minimum;
        // `qy * pw + qx` is an index below 2^24.
        let (d, s) = unsafe {
            (
                (if v < levels { v } else { levels }).to_int_unchecked::<i32>() as u32,
                (qy * pwf + qx).to_int_unchecked::<i32>() as u32,
            )
        };
        let index = index0.wrapping_add(i as u32);
        if with_source {
            batch.source[i] = if inside { s } else { CLAIM_NONE };
        }
        batch.key[i] = if inside { (d << bits) | index } else { CLAIM_NONE };
        // A lane without a source targets its own (visible) entry: distinct
        // addresses, so no chain of stores to one entry.
        batch.target[i] = if inside { s } else { index };
        outside |= inside & ((qy < low) | (qy > high));
    }
    outside
}

/// Visits every visible row of `motion` in batches of [`BATCH`]:
/// `f(y, x0, lanes, motion)`, the last batch of a row padded with NaN.
#[inline(always)]
pub(crate) fn for_each_batch(
    width: usize,
    motion: &[[f32; 2]],
    mut f: impl FnMut(usize, usize, usize, &[[f32; 2]; BATCH]),
) {
    for (y, row) in motion.chunks_exact(width).enumerate() {
        for_each_batch_in_row(row, |x0, lanes, m| f(y, x0, lanes, m));
    }
}

/// [`for_each_batch`] for one row: `f(x0, lanes, motion)`.
#[inline(always)]
fn for_each_batch_in_row(row: &[[f32; 2]], mut f: impl FnMut(usize, usize, &[[f32; 2]; BATCH])) {
    let mut batches = row.chunks_exact(BATCH);
    let mut x0 = 0;
    for m in &mut batches {
        f(x0, BATCH, m.try_into().expect("a batch"));
        x0 += BATCH;
    }
    let rest = batches.remainder();
    if !rest.is_empty() {
        let mut m = [[f32::NAN; 2]; BATCH];
        m[..rest.len()].copy_from_slice(rest);
        f(x0, rest.len(), &m);
    }
}
