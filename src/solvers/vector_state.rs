//! The CPU's vector-register state after faer's kernels.
//!
//! faer's matrix products run AVX-512 micro-kernels (the `gemm` crate) that
//! return with the upper halves of the vector registers in use. Until a
//! `vzeroupper`, every SSE-encoded instruction then merges with those upper
//! halves, and glibc's libm is SSE-encoded: measured on this project's
//! 2-core Xeon, `log10` 11 → 190 ns, a mix of `sin`, `exp`, `ln`, `atan2`,
//! `hypot` 61 → 754 ns per call, on every thread (a new thread inherits the
//! state of the one that spawned it). Rust code compiled for the baseline
//! target showed no loss in a latency-bound loop. Loops that call libm
//! (complex logarithms and arguments, magnitudes in decibels) call
//! [`clear`] first.

/// Marks the upper halves of the vector registers unused (`vzeroupper`)
/// when the CPU has AVX; nothing elsewhere.
#[inline]
pub fn clear() {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the CPU has AVX (checked just above), so the
            // instruction exists. It zeroes bits 128 and up of the vector
            // registers; code compiled for this crate's target (SSE2) keeps
            // values only in their low 128 bits, so no live value changes.
            #[allow(unsafe_code)]
            unsafe {
                std::arch::x86_64::_mm256_zeroupper()
            }
        }
    }
}
