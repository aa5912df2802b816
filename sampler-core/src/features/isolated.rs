//! What an isolated position's seed becomes: the seed of a position whose
//! retarget edges in and out both cross an edge (a chain of one position in
//! [`super::permute`]) is replaced by a fresh one every frame, so the pixel
//! does not repeat its estimate.

use crate::sequences::seed::hash_u32;

/// The seed that replaces `seed` at a position whose retarget edges in and
/// out are both cut ([`super::permute`], step 3): a bijective hash of it, so
/// two isolated seeds never become one, and a seed isolated frame after
/// frame walks through new values.
#[inline]
pub fn refresh_isolated_seed(seed: u32) -> u32 {
    hash_u32(seed ^ 0x5BD1_E995)
}
