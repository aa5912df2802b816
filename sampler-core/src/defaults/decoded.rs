//! Little-endian `u16` data widened to `u32` statics on first use.
//!
//! Decoding at compile time, as the smaller defaults are, keeps rustc's
//! const evaluator busy for a million words and trips its
//! `long_running_const_eval` guard; decoded at run time the statics are
//! zero-initialised (`.bss`: no bytes in the binary) and filled once.

use core::cell::UnsafeCell;
use core::sync::atomic::{AtomicU8, Ordering};

/// Not decoded yet.
const EMPTY: u8 = 0;
/// One caller is decoding.
const BUSY: u8 = 1;
/// Decoded: the words never change again.
const READY: u8 = 2;

/// `N` `u32`s decoded from `2 N` bytes of little-endian `u16`s by the first
/// caller of [`words`](Self::words).
pub(super) struct DecodedU16<const N: usize> {
    bytes: &'static [u8],
    state: AtomicU8,
    words: UnsafeCell<[u32; N]>,
}

// SAFETY: `words` is written only by the one caller that moved `state` from
// EMPTY to BUSY, and read only once `state` is READY (a Release store after
// the writes, Acquire loads before the reads); it never changes after that.
unsafe impl<const N: usize> Sync for DecodedU16<N> {}

impl<const N: usize> DecodedU16<N> {
    /// Wraps `bytes`; a length other than `2 N` is a compile error in a static.
    pub(super) const fn new(bytes: &'static [u8]) -> Self {
        assert!(bytes.len() == 2 * N, "data file has the wrong length");
        DecodedU16 {
            bytes,
            state: AtomicU8::new(EMPTY),
            words: UnsafeCell::new([0; N]),
        }
    }

    /// The decoded words, decoding them on the first call (callers that
    /// arrive meanwhile spin until it is done: about a millisecond for a
    /// million words).
    pub(super) fn words(&'static self) -> &'static [u32; N] {
        let first = self
            .state
            .compare_exchange(EMPTY, BUSY, Ordering::Acquire, Ordering::Acquire)
            .is_ok();
        if first {
            // SAFETY: this caller alone moved the state to BUSY, and nobody
            // reads the words before it is READY.
            let words = unsafe { &mut *self.words.get() };
            for (w, b) in words.iter_mut().zip(self.bytes.chunks_exact(2)) {
                *w = u32::from(u16::from_le_bytes([b[0], b[1]]));
            }
            self.state.store(READY, Ordering::Release);
        } else {
            while self.state.load(Ordering::Acquire) != READY {
                core::hint::spin_loop();
            }
        }
        // SAFETY: the state is READY (set by this caller, or seen with
        // Acquire ordering): the words are written and never change again.
        unsafe { &*self.words.get() }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::vec::Vec;

    static DATA: DecodedU16<3> = DecodedU16::new(&[1, 0, 0x34, 0x12, 0xFF, 0xFF]);

    /// Threads racing for the first call all see the decoded words.
    #[test]
    fn racing_first_callers_see_the_decoded_words() {
        let threads: Vec<_> = (0..4).map(|_| std::thread::spawn(|| *DATA.words())).collect();
        let seen: Vec<[u32; 3]> = threads.into_iter().map(|h| h.join().unwrap()).collect();
        assert!(seen.iter().all(|w| *w == [1, 0x1234, 0xFFFF]), "{seen:?}");
    }
}
