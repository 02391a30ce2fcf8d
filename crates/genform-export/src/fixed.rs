//! Numbers with a fixed count of decimals, as `format!("{:.N}", f64::from(v))`
//! writes them (the exact binary value rounded half to even), trailing zeros
//! and a bare `.` trimmed, never `-0`: what SVG coordinates are written
//! with. A million-segment drawing writes millions of them; the standard
//! formatter's exact mode, and a `String` per number, were most of writing
//! its SVG.

/// Appends `v` with `decimals` decimals (trailing zeros trimmed, `-0` as
/// `0`) to `out`.
pub(crate) fn push_fixed(out: &mut String, v: f32, decimals: usize) {
    match scaled(v, decimals) {
        Some(0) => out.push('0'),
        Some(r) => {
            if v < 0.0 {
                out.push('-');
            }
            push_point_digits(out, r, decimals);
        }
        None => push_slow(out, v, decimals),
    }
}

/// `v` with `decimals` decimals, as [`push_fixed`] writes it.
pub(crate) fn fixed(v: f32, decimals: usize) -> String {
    let mut s = String::new();
    push_fixed(&mut s, v, decimals);
    s
}

/// |v| · 10^decimals rounded half to even, computed exactly in integers;
/// `None` where that does not fit (not finite, huge, or over 19 decimals).
fn scaled(v: f32, decimals: usize) -> Option<u128> {
    if !v.is_finite() || decimals > 19 {
        return None;
    }
    let bits = v.to_bits();
    let exp = ((bits >> 23) & 0xff) as i32;
    let frac = u128::from(bits & 0x7f_ffff);
    // |v| = m · 2^e exactly.
    let (m, e) = if exp == 0 { (frac, -149) } else { (frac | 0x80_0000, exp - 150) };
    // m < 2^24 and 10^19 < 2^64: q < 2^88.
    let q = m * 10u128.pow(decimals as u32);
    if e >= 0 {
        // At most 2^127: q · 2^e must fit.
        return (e <= 39).then(|| q << e);
    }
    let k = (-e) as u32;
    if k >= 100 {
        // q < 2^88 < 2^(k-1): below one half.
        return Some(0);
    }
    let (r, rem) = (q >> k, q & ((1u128 << k) - 1));
    let half = 1u128 << (k - 1);
    Some(if rem > half || (rem == half && r & 1 == 1) { r + 1 } else { r })
}

/// `r` · 10^−`decimals` in decimal, trailing zeros (and a bare `.`) trimmed.
fn push_point_digits(out: &mut String, r: u128, decimals: usize) {
    let mut digits = [0u8; 40];
    let mut n = 0;
    // Digits from 64-bit words (128-bit division is a library call):
    // drawings' numbers fit one; a larger one is 19 low digits, then the
    // rest (r < 2^127, so the rest is below 2^64, and decimals ≤ 19 lie in the
    // low part).
    let mut words = |mut x: u64, at_least: usize| {
        let start = n;
        while x > 0 || n - start < at_least {
            digits[n] = b'0' + (x % 10) as u8;
            x /= 10;
            n += 1;
        }
    };
    const TEN_19: u128 = 10_000_000_000_000_000_000;
    match u64::try_from(r) {
        Ok(x) => words(x, decimals + 1),
        Err(_) => {
            words((r % TEN_19) as u64, 19);
            words((r / TEN_19) as u64, 1);
        }
    }
    // digits[..n] hold the number from its last digit: digits[..decimals]
    // are the decimals. Trailing zeros of the decimals go.
    let zeros = digits[..decimals].iter().take_while(|&&d| d == b'0').count();
    for &d in digits[decimals..n].iter().rev() {
        out.push(char::from(d));
    }
    if zeros < decimals {
        out.push('.');
        for &d in digits[zeros..decimals].iter().rev() {
            out.push(char::from(d));
        }
    }
}

/// The standard formatter, for what [`scaled`] leaves out.
fn push_slow(out: &mut String, v: f32, decimals: usize) {
    let mut s = format!("{:.*}", decimals, f64::from(v));
    if s.contains('.') {
        let t = s.trim_end_matches('0').trim_end_matches('.').len();
        s.truncate(t);
    }
    out.push_str(if s == "-0" { "0" } else { &s });
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn oracle(v: f32, decimals: usize) -> String {
        let mut s = String::new();
        push_slow(&mut s, v, decimals);
        s
    }

    #[test]
    fn ties_round_to_even_and_signs_and_zeros_are_kept_apart() {
        for (v, d, want) in [
            (0.125, 2, "0.12"),
            (0.375, 2, "0.38"),
            (2.5, 0, "2"),
            (1.5, 0, "2"),
            (-0.125, 2, "-0.12"),
            (-0.0001, 3, "0"),
            (-0.0, 2, "0"),
            (100.0, 3, "100"),
            (1.25, 4, "1.25"),
            (-7.0, 0, "-7"),
            (f32::MIN_POSITIVE, 12, "0"),
            (f32::NAN, 2, "NaN"),
            (3.0e38, 2, "300000000549775575777803994281145270272"),
        ] {
            assert_eq!(fixed(v, d), want, "{v} with {d} decimals");
            assert_eq!(fixed(v, d), oracle(v, d), "{v} with {d} decimals");
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(20_000))]

        #[test]
        fn any_float_prints_as_the_standard_formatter_does(bits in any::<u32>(), decimals in 0usize..=20) {
            let v = f32::from_bits(bits);
            prop_assert_eq!(fixed(v, decimals), oracle(v, decimals));
        }

        #[test]
        fn drawing_coordinates_print_as_the_standard_formatter_does(v in -1.0e5f32..1.0e5, decimals in 0usize..=8) {
            prop_assert_eq!(fixed(v, decimals), oracle(v, decimals));
        }
    }
}
