//! [`reproject_frame`]: validates the buffers and runs the reprojection in
//! one sweep ([`super::sweep`]) or, when a claim reaches too far, in two
//! ([`super::two_sweeps`]).

use super::claims::{ReprojectStats, MAX_REPROJECT_SEEDS};
use crate::error::{Buffer, Error};
use crate::permutation::layout::FrameLayout;
use crate::reprojection::sweep::reproject_one_sweep;
use crate::reprojection::two_sweeps::reproject_two_sweeps;

/// Reprojects `seeds_in` (laid out for the previous frame's screen) along
/// frame `t + 1`'s backward motion vectors into `seeds_out` (see the module
/// docs for the rule); `claims` is scratch. The output is a permutation of
/// the input.
///
/// `motion` holds one `[dx, dy]` per visible pixel, row-major,
/// `width * height` entries, in pixels (raster `y` down): where the pixel's
/// point was in the previous frame minus the pixel's centre. NaN marks a
/// pixel whose point was not visible (disocclusion).
///
/// # Panics
/// Never for valid input: the recycling step relies on the invariant that
/// unclaimed sources and pixels without a seed are equally many (module
/// docs); a panic there is a bug.
///
/// # Errors
/// [`Error::BufferSize`] when a buffer's length does not match the layout
/// (`seeds_in`, `seeds_out`, `claims`: `seed_count`; `motion`:
/// `pixel_count`); [`Error::FrameSize`] when the padded frame has more than
/// [`MAX_REPROJECT_SEEDS`] seeds.
///
/// # Example
///
/// The camera panned 3 pixels to the left: every pixel's surface was 3 pixels
/// to its right in the previous frame (backward motion `+3`), so seeds follow.
///
/// ```
/// use sampler_core::{reproject_frame, FrameLayout};
/// let layout = FrameLayout::new(32, 16, 4, 16)?;
/// let n = layout.seed_count();
/// let motion = vec![[3.0f32, 0.0]; 32 * 16];
/// let seeds: Vec<u32> = (0..n as u32).collect();
/// let (mut claims, mut next) = (vec![0; n], vec![0; n]);
/// let stats = reproject_frame(&layout, &motion, &seeds, &mut claims, &mut next)?;
/// assert_eq!(next[5], seeds[8]); // pixel (5, 0) takes the seed of (8, 0)
/// assert!(stats.recycled > 0);  // the right edge had no source: recycled seeds
/// let mut check = next.clone();
/// check.sort();
/// assert_eq!(check, seeds); // never a duplicated seed
/// # Ok::<(), sampler_core::Error>(())
/// ```
pub fn reproject_frame(
    layout: &FrameLayout,
    motion: &[[f32; 2]],
    seeds_in: &[u32],
    claims: &mut [u32],
    seeds_out: &mut [u32],
) -> Result<ReprojectStats, Error> {
    let n = layout.seed_count();
    if n > MAX_REPROJECT_SEEDS {
        return Err(Error::FrameSize {
            width: layout.width(),
            height: layout.height(),
        });
    }
    layout.check_seed_buffer(Buffer::SeedsIn, seeds_in.len())?;
    layout.check_seed_buffer(Buffer::SeedsOut, seeds_out.len())?;
    layout.check_seed_buffer(Buffer::Claims, claims.len())?;
    if motion.len() != layout.pixel_count() {
        return Err(Error::BufferSize {
            buffer: Buffer::Motion,
            expected: layout.pixel_count(),
            actual: motion.len(),
        });
    }
    let params = layout.params(0);
    Ok(reproject_one_sweep(&params, motion, seeds_in, claims, seeds_out)
        .unwrap_or_else(|| reproject_two_sweeps(&params, motion, seeds_in, claims, seeds_out)))
}
