//! Run-time choice of the instruction set for the CPU permutation, without
//! `std`: CPUID for what the CPU has, XGETBV for what the operating system
//! saves on a context switch (a CPU with AVX-512 under an OS that does not
//! save the ZMM registers must not use them), checked once and cached.

#[cfg(target_arch = "x86_64")]
use core::sync::atomic::{AtomicU8, Ordering};

/// Instruction set of the CPU permutation's block ranker. Every choice gives
/// the same output, bit for bit; they differ only in speed.
///
/// [`Isa::best`] is what [`permute_frame`](crate::permute_frame) and
/// [`permute_frame_rows`](crate::permute_frame_rows) use. The others exist
/// so that benchmarks and tests can compare them on one machine (through
/// the hidden `permute_frame_rows_isa`, which takes the `Isa` to use, or
/// the best available below it). Only 4x4 blocks have vector rankers; other
/// block sizes run the baseline ranker whatever the choice.
///
/// ```
/// use sampler_core::Isa;
/// let best = Isa::best(); // CPUID and XGETBV, checked once
/// assert!(best.is_available() && Isa::Baseline.is_available());
/// println!("permute_frame ranks with {} here", best.name());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Isa {
    /// The build's baseline: on x86-64, SSE2 (eight 4x4 blocks ranked at
    /// once, their counts in 16-bit lanes); elsewhere portable code that
    /// the compiler vectorises for whatever the target has.
    Baseline,
    /// x86-64 with AVX2 (most x86-64 CPUs since 2013-2015): eight 4x4 blocks
    /// in one 256-bit register.
    Avx2,
    /// x86-64 with AVX-512 F (Intel since Skylake-SP, AMD since Zen 4):
    /// sixteen 4x4 blocks sorted at once by a sorting network, eight in
    /// each of two 512-bit registers.
    Avx512,
}

impl Isa {
    /// Every instruction set, slowest first.
    pub const ALL: [Isa; 3] = [Isa::Baseline, Isa::Avx2, Isa::Avx512];

    /// The fastest instruction set this CPU and operating system support
    /// (checked once per process, then cached).
    pub fn best() -> Isa {
        #[cfg(target_arch = "x86_64")]
        match STATE.load(Ordering::Relaxed) {
            UNKNOWN => {
                let isa = detect();
                STATE.store(isa as u8 + 1, Ordering::Relaxed);
                isa
            }
            2 => Isa::Avx2,
            3 => Isa::Avx512,
            _ => Isa::Baseline,
        }
        #[cfg(not(target_arch = "x86_64"))]
        Isa::Baseline
    }

    /// True when this CPU and operating system can run `self`.
    pub fn is_available(self) -> bool {
        self <= Isa::best()
    }

    /// Short lower-case name (`baseline`, `avx2`, `avx512`), for reports.
    pub fn name(self) -> &'static str {
        match self {
            Isa::Baseline => "baseline",
            Isa::Avx2 => "avx2",
            Isa::Avx512 => "avx512",
        }
    }
}

/// Cached [`Isa::best`]: `UNKNOWN`, or the `Isa` discriminant plus one.
#[cfg(target_arch = "x86_64")]
static STATE: AtomicU8 = AtomicU8::new(UNKNOWN);
#[cfg(target_arch = "x86_64")]
const UNKNOWN: u8 = 0;

/// True when AVX2 is usable (the reprojection's AVX2 build uses this too).
#[cfg(target_arch = "x86_64")]
pub(crate) fn avx2_available() -> bool {
    Isa::Avx2.is_available()
}

/// CPUID leaf 1 (AVX, OSXSAVE), XCR0 (which register states the OS saves)
/// and CPUID leaf 7 (AVX2, AVX-512 F), as the Intel SDM (vol. 1, 14.3 and
/// 15.2) prescribes.
#[cfg(target_arch = "x86_64")]
#[allow(unused_unsafe)] // CPUID is a safe intrinsic in newer toolchains
fn detect() -> Isa {
    use core::arch::x86_64::{__cpuid, __cpuid_count, _xgetbv};
    const ECX_OSXSAVE: u32 = 1 << 27;
    const ECX_AVX: u32 = 1 << 28;
    /// XCR0 bits 1 and 2: SSE and AVX (YMM upper halves) state.
    const XCR0_YMM: u64 = 0b110;
    /// XCR0 bits 5, 6, 7: opmask registers, ZMM0-15 upper halves, ZMM16-31.
    const XCR0_ZMM: u64 = 0b1110_0000;
    const EBX_AVX2: u32 = 1 << 5;
    const EBX_AVX512F: u32 = 1 << 16;
    // SAFETY: every x86_64 CPU has CPUID.
    let max_leaf = unsafe { __cpuid(0) }.eax;
    if max_leaf < 7 {
        return Isa::Baseline;
    }
    // SAFETY: as above.
    let leaf1 = unsafe { __cpuid(1) };
    if leaf1.ecx & (ECX_OSXSAVE | ECX_AVX) != ECX_OSXSAVE | ECX_AVX {
        return Isa::Baseline;
    }
    // SAFETY: OSXSAVE is set, so XGETBV is available.
    let xcr0 = unsafe { _xgetbv(0) };
    if xcr0 & XCR0_YMM != XCR0_YMM {
        return Isa::Baseline;
    }
    // SAFETY: leaf 7 exists (max_leaf >= 7).
    let ebx = unsafe { __cpuid_count(7, 0) }.ebx;
    if ebx & EBX_AVX2 == 0 {
        Isa::Baseline
    } else if ebx & EBX_AVX512F != 0 && xcr0 & XCR0_ZMM == XCR0_ZMM {
        Isa::Avx512
    } else {
        Isa::Avx2
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detection_is_cached_and_ordered() {
        let best = Isa::best();
        assert_eq!(Isa::best(), best);
        assert!(Isa::Baseline.is_available());
        for isa in Isa::ALL {
            assert_eq!(isa.is_available(), isa <= best, "{isa:?}");
        }
        // The detector agrees with std's (tests link std).
        #[cfg(target_arch = "x86_64")]
        {
            extern crate std;
            let avx2 = std::is_x86_feature_detected!("avx2");
            let avx512 = std::is_x86_feature_detected!("avx512f");
            assert_eq!(Isa::Avx2.is_available(), avx2);
            assert_eq!(Isa::Avx512.is_available(), avx2 && avx512);
        }
    }
}
