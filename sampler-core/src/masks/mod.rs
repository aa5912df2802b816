//! **Masks**: read-only access to spatiotemporal blue-noise masks
//! ([`SpatiotemporalMask`](crate::SpatiotemporalMask)): a `W x H x D` volume
//! of per-slice ranks, blue in space and along time.
//!
//! The crate ships two (feature `defaults`): an STBN-style mask
//! ([`defaults::stbn_128`](crate::defaults::stbn_128)) and one adapted to an
//! exponential history times a Gaussian blur
//! ([`defaults::filter_adapted_128`](crate::defaults::filter_adapted_128)).
//! Their generators (void-and-cluster, filter-adapted swaps) are host-only,
//! in `bake` (feature `bake`).

pub mod spatiotemporal;
