//! Natural logarithms of many numbers at once, for the kernel fills.
//!
//! The kernel fills (the log remainder L, the warping constant's double
//! integral) take one logarithm per pair of nodes: 2 million at N = 2048,
//! half their time with the C library's `ln`, one number per call. Here
//! the logarithm is straight-line arithmetic, so the compiler turns a loop
//! over a slice into vector instructions (4 numbers per instruction with
//! AVX2, chosen at run time; 2 without):
//!
//! * x = 2^k m with m in [1/√2, √2), k and m read from the bits of x;
//! * ln m = 2 atanh s = 2 (s + s³/3 + s⁵/5 + …), s = (m − 1)/(m + 1),
//!   |s| ≤ 0.1716: the series to s²¹/21 leaves a truncation below 1e-18
//!   relative;
//! * ln x = k ln2_hi + (ln m + k ln2_lo), ln 2 split so that k ln2_hi is
//!   exact.
//!
//! m − 1 is exact, m + 1 and the quotient are rounded once each: the result
//! is within a few units in the last place of the exact logarithm (the test
//! measures it against `f64::ln`). No fused multiply-adds are used, so both
//! paths (AVX2 or not) give the same bits.
//!
//! Inputs must be positive and normal (the fills clamp r² to at least
//! `f64::MIN_POSITIVE`); +∞ and NaN give themselves, as with `f64::ln`, so
//! an overflow still shows as a non-finite result.

/// ln 2 in two parts: the high part has 32 significant bits, so k ln2_hi is
/// exact for |k| < 2^20.
const LN2_HI: f64 = f64::from_bits(0x3fe6_2e42_fee0_0000);
const LN2_LO: f64 = f64::from_bits(0x3dea_39ef_3579_3c76);

/// The bits of 1/√2 (rounded): m is taken in [1/√2, √2).
const SQRT_HALF_BITS: u64 = 0x3fe6_a09e_667f_3bcd;

/// ln x for positive normal x, +∞ and NaN (see the module notes).
#[inline(always)]
fn ln_one(x: f64) -> f64 {
    // shift the bits so that the exponent field counts from 1/√2, not 1
    let u = x
        .to_bits()
        .wrapping_add(0x3ff0_0000_0000_0000 - SQRT_HALF_BITS);
    let k = ((u >> 52) as i32 - 0x3ff) as f64;
    let m = f64::from_bits((u & 0x000f_ffff_ffff_ffff) + SQRT_HALF_BITS);
    let s = (m - 1.0) / (m + 1.0);
    let z = s * s;
    // 1 + z/3 + z²/5 + … + z¹⁰/21 by Horner
    let mut p = 1.0 / 21.0;
    p = p * z + 1.0 / 19.0;
    p = p * z + 1.0 / 17.0;
    p = p * z + 1.0 / 15.0;
    p = p * z + 1.0 / 13.0;
    p = p * z + 1.0 / 11.0;
    p = p * z + 1.0 / 9.0;
    p = p * z + 1.0 / 7.0;
    p = p * z + 1.0 / 5.0;
    p = p * z + 1.0 / 3.0;
    let lnm = 2.0 * s + 2.0 * s * (z * p);
    let y = k * LN2_HI + (lnm + k * LN2_LO);
    // +∞ and NaN pass through, as with `f64::ln` (a select: no branch)
    if x.is_finite() { y } else { x }
}

/// Replaces every entry of `v` (positive and normal, or +∞, or NaN) by its natural
/// logarithm, in the instruction set of the caller (inlined into a row
/// loop compiled for AVX2 it runs 4 numbers per instruction, see
/// [`has_avx2`]).
#[inline(always)]
pub(crate) fn ln_slice(v: &mut [f64]) {
    for x in v.iter_mut() {
        *x = ln_one(*x);
    }
}

/// [`ln_slice`], with AVX2 where the CPU has it. The same bits whichever
/// instruction set runs it.
#[cfg(test)]
pub(crate) fn ln_in_place(v: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if has_avx2() {
        #[target_feature(enable = "avx2")]
        fn avx2(v: &mut [f64]) {
            ln_slice(v)
        }
        // SAFETY: the CPU has AVX2, the only feature `avx2` is compiled for.
        unsafe { avx2(v) };
        return;
    }
    ln_slice(v)
}

/// Whether the CPU has AVX2 (found at run time, once).
///
/// The kernel fills compile their row loops twice, for the baseline and
/// for AVX2 (4 lanes per instruction), and run the AVX2 copy where this
/// holds. Without fused multiply-adds (not enabled) and without reordering
/// (the compiler keeps the order of every floating-point operation) both
/// copies give the same bits.
#[inline]
pub(crate) fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Units in the last place of `b` between a and b.
    fn ulps(a: f64, b: f64) -> f64 {
        let ulp = f64::from_bits(b.abs().to_bits() + 1) - b.abs();
        (a - b).abs() / ulp
    }

    #[test]
    fn ln2_is_split_exactly() {
        assert_eq!(LN2_HI + LN2_LO, std::f64::consts::LN_2);
        assert_eq!(LN2_HI.to_bits() & 0x1f_ffff, 0, "k ln2_hi exact");
    }

    #[test]
    fn the_logarithm_is_within_two_units_in_the_last_place() {
        // a geometric sweep over the whole normal range, values next to 1
        // (where ln x is small), powers of two and the edges of the reduction
        let mut xs: Vec<f64> = (0..200_000)
            .map(|i| f64::MIN_POSITIVE * (1.0072f64).powi(i))
            .filter(|x| x.is_finite())
            .collect();
        xs.extend((1..20_000).map(|i| 1.0 + i as f64 * 1e-9));
        xs.extend((1..20_000).map(|i| 1.0 - i as f64 * 1e-9));
        xs.extend((1..20_000).map(|i| 0.5 + i as f64 * 5e-5));
        xs.extend((-1022..1023).map(|e| 2f64.powi(e)));
        xs.extend([
            f64::MIN_POSITIVE,
            f64::MAX,
            1.0,
            std::f64::consts::FRAC_1_SQRT_2,
            std::f64::consts::SQRT_2,
            f64::from_bits(SQRT_HALF_BITS),
            f64::from_bits(SQRT_HALF_BITS - 1),
        ]);
        let mut fast = xs.clone();
        ln_in_place(&mut fast);
        let mut generic = xs.clone();
        ln_slice(&mut generic);
        let mut worst: f64 = 0.0;
        for ((x, f), g) in xs.iter().zip(&fast).zip(&generic) {
            assert_eq!(f.to_bits(), g.to_bits(), "x = {x:e}: the two paths differ");
            let exact = x.ln();
            let e = if exact == 0.0 {
                assert_eq!(*f, 0.0, "ln 1");
                0.0
            } else {
                ulps(*f, exact)
            };
            assert!(e <= 2.0, "x = {x:e}: {f:e} vs {exact:e}, {e} ulp");
            worst = worst.max(e);
        }
        // the bound is not vacuous: some results are not the library's bits
        assert!(worst >= 0.5, "worst {worst}");
        // overflowed inputs stay visible
        let mut odd = [f64::INFINITY, f64::NAN];
        ln_in_place(&mut odd);
        assert_eq!(odd[0], f64::INFINITY);
        assert!(odd[1].is_nan());
    }
}
