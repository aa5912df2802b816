//! The sizes and ranges every input is validated against, in one place so
//! that [`Error`](crate::Error)'s messages can state them without depending on
//! the capability modules (each re-exports its own: `permutation::sort::MIN_BLOCK`,
//! `sequences::walk::MAX_TILE`, ...).

/// Smallest supported block side in pixels (a 2x2 block is the smallest
/// that sorts anything).
pub const MIN_BLOCK: u32 = 2;
/// Largest supported block side in pixels (the paper recommends 2 to 8).
pub const MAX_BLOCK: u32 = 8;

/// Largest supported tile side in texels.
pub const MAX_TILE: u32 = 1 << MAX_TILE_LOG2;
/// `log2` of [`MAX_TILE`].
pub const MAX_TILE_LOG2: u32 = 10;

/// Largest `|dx|` or `|dy|` of a retarget offset (the paper's radius 6).
pub const RETARGET_RADIUS: i32 = 6;

/// Largest key tile side of the screen-space Sobol sampler.
pub const MAX_KEY_TILE: u32 = 1024;
/// Largest number of spp levels of the screen-space Sobol sampler: the
/// ranking key has 8 bits, so levels `0..=8` (1 to 256 spp).
pub const MAX_KEY_LEVELS: u32 = 9;

/// Largest side (cells per row or rows) of a piecewise-constant distribution
/// or environment map: `2^15`, so a table of `1 + height + width * height`
/// entries is indexed by `u32` and a cell index is exact in `f32`
/// (`16384 x 8192` is the largest common environment map).
pub const MAX_DISTRIBUTION_SIDE: u32 = 1 << 15;
