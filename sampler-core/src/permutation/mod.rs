//! **Permutation**: the a-posteriori seed permutation of Heitz & Belcour
//! (EGSR 2019), the library's core.
//!
//! - [`layout`]: frame geometry ([`FrameLayout`](crate::FrameLayout): visible
//!   size, the seed buffer padded to whole tiles, blocks).
//! - [`dither`]: the blue-noise dither tile the sorting pass ranks against
//!   ([`DitherTile`](crate::DitherTile)).
//! - [`sort`]: the sorting pass on one block ([`sort_block`](crate::sort_block))
//!   and the intensity key it sorts by.
//! - [`sort_pixel`]: the same sorting pass as two passes of one call per
//!   seed ([`sort_rank_pixel`](crate::sort_rank_pixel),
//!   [`sort_gather_pixel`](crate::sort_gather_pixel)), the form the GPU runs.
//! - [`retarget`]: the retarget tables that move seeds laid out for the tile
//!   of frame `t` to frame `t + 1`'s ([`RetargetTables`](crate::RetargetTables)).
//! - [`frame`]: what a renderer calls once a frame
//!   ([`permute_frame`](crate::permute_frame) = sort + retarget), and the
//!   per-block / per-seed functions the GPU kernels call
//!   ([`sort_block_in_frame`](crate::sort_block_in_frame),
//!   [`retarget_pixel`](crate::retarget_pixel)).
//! - [`temporal`]: the temporally blue permutation, whose sorting target is
//!   slice `t mod D` of a spatiotemporal mask and whose tables move seeds
//!   from one slice to the next ([`permute_frame_temporal`](crate::permute_frame_temporal),
//!   [`SliceTables`](crate::SliceTables)).
//! - `cpu` (private): the CPU fast path behind `permute_frame`, with run-time
//!   choice of AVX-512 / AVX2 / SSE2 ([`Isa`](crate::Isa)) and the banded form
//!   for thread pools ([`permute_frame_rows`](crate::permute_frame_rows)).
//!
//! The tile's offset walk lives in [`crate::sequences::walk`]; a seed follows
//! motion with [`crate::reprojection`], and edges are respected by
//! [`crate::features`].

pub(crate) mod cpu;
pub mod dither;
pub mod frame;
pub mod layout;
pub mod retarget;
pub mod sort;
pub mod sort_pixel;
pub mod temporal;
