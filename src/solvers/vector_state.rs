//! The CPU's vector-register state after faer's kernels.
//!
//! faer's matrix products run AVX-512 micro-kernels (the `gemm` crate) that
//! return with the upper halves of the vector registers in use. Until a
//! `vzeroupper`, every SSE-encoded instruction then merges with those upper
//! halves, and glibc's libm is SSE-encoded: measured on this project's
//! 2-core Xeon, `log10` 11 → 190 ns, a mix of `sin`, `exp`, `ln`, `atan2`,
//! `hypot` 61 → 754 ns per call, on every thread (a new thread inherits the
//! state of the one that spawned it). Rust code compiled for the baseline
//! target showed no loss in a latency-bound loop, and the FMA variants
//! glibc picks for `atan2` and `ln` are VEX-encoded and unaffected. Loops
//! of `log10`, `hypot` (complex magnitudes), `sin` and `cos` call [`clear`]
//! first.

/// Marks the upper halves of the vector registers unused (`vzeroupper`)
/// when the CPU has AVX; nothing elsewhere.
#[inline]
pub fn clear() {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the CPU has AVX (checked just above), so the
            // instruction exists. It zeroes bits 128 and up of the vector
            // registers; the intrinsic is a call across which the compiler
            // treats those registers as clobbered, so no value it keeps
            // live changes, whatever the target features.
            #[allow(unsafe_code)]
            unsafe {
                std::arch::x86_64::_mm256_zeroupper()
            }
        }
    }
}
