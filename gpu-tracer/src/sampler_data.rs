//! The a-priori samplers' data, as the trace kernel reads it from one
//! buffer (binding 7 of `kernels::abi::TRACE_ENTRY`): the screen-space Sobol
//! keys (`sampler_core::defaults::screen_sobol_keys()`), then the
//! spatiotemporal sampler's 64x64 shift tile (the ranks of
//! `sampler_core::defaults::tile_64()`, at index `key_count()` of the keys'
//! layout).

use kernels::abi::SPATIOTEMPORAL_TILE_LOG2;
use std::sync::OnceLock;

/// The buffer the CPU renderer passes and the GPU binds for every sampler.
///
/// # Panics
/// Never with the crate's baked defaults (the asserts check their sizes).
pub fn sampler_buffer() -> &'static [u32] {
    static BUFFER: OnceLock<Vec<u32>> = OnceLock::new();
    BUFFER.get_or_init(|| {
        let keys = sampler_core::defaults::screen_sobol_keys();
        let tile = sampler_core::defaults::tile_64();
        assert_eq!(
            tile.tile(),
            1 << SPATIOTEMPORAL_TILE_LOG2,
            "the shift tile's side"
        );
        assert_eq!(
            keys.keys().len(),
            keys.layout().key_count(),
            "keys fill their layout"
        );
        let mut buffer = keys.keys().to_vec();
        buffer.extend_from_slice(tile.values());
        buffer
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tile_follows_the_keys() {
        let b = sampler_buffer();
        let keys = sampler_core::defaults::screen_sobol_keys();
        let n = keys.layout().key_count();
        assert_eq!(&b[..n], keys.keys());
        assert_eq!(&b[n..], sampler_core::defaults::tile_64().values());
        assert_eq!(b.len() - n, 1 << (2 * SPATIOTEMPORAL_TILE_LOG2));
    }
}
