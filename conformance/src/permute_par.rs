//! [`permute_frame_par`]: `sampler_core::permute_frame` on a rayon thread
//! pool, through the band entry point `sampler_core::permute_frame_rows`.
//!
//! It lives here, not in `sampler-core`, because the core is `no_std` and
//! depends on nothing but glam, libm and bytemuck: `permute_frame_rows` is
//! what makes any thread pool a few lines, and this is those lines for
//! rayon (used by the permutation bench and the band property test).

use rayon::prelude::*;
use sampler_core::{
    band_seed_range, permute_frame_rows_isa, DitherTile, Error, FrameLayout, Intensity, Isa, RetargetTables,
};

/// [`sampler_core::permute_frame`] split into `bands` bands of block rows
/// (at least 1; more than the frame has are clamped), run on the current
/// rayon pool with the ranker of `isa` ([`Isa::best`] for the normal
/// choice). Output identical to `permute_frame` for every `bands`.
///
/// Each band also ranks the blocks within 6 seed rows of it (the retarget
/// radius), so more bands cost more work: use as many as threads. A pool
/// that sleeps between frames may start with its woken threads on one core
/// for a few milliseconds (BENCHMARKS.md, issue 18); a pool kept busy by the
/// renderer does not.
///
/// # Errors
/// As `permute_frame`.
#[allow(clippy::too_many_arguments)]
pub fn permute_frame_par<T: Intensity + Sync>(
    isa: Isa,
    layout: &FrameLayout,
    frame: u32,
    intensities: &[T],
    tile: &DitherTile<'_>,
    tables: &RetargetTables<'_>,
    seeds_in: &[u32],
    seeds_out: &mut [u32],
    bands: u32,
) -> Result<(), Error> {
    layout.check_seed_buffer(sampler_core::Buffer::SeedsOut, seeds_out.len())?;
    let blocks = layout.params(frame).blocks_y();
    let bands = bands.clamp(1, blocks);
    let rows = |k: u32| blocks * k / bands..blocks * (k + 1) / bands;
    // Cut `seeds_out` into the bands' slices, in order.
    let mut slices = Vec::with_capacity(bands as usize);
    let mut rest = seeds_out;
    for k in 0..bands {
        let (band, tail) = rest.split_at_mut(band_seed_range(layout, rows(k)).len());
        slices.push((rows(k), band));
        rest = tail;
    }
    slices.into_par_iter().try_for_each(|(rows, out)| {
        permute_frame_rows_isa(isa, layout, frame, intensities, tile, tables, seeds_in, rows, out)
    })
}
