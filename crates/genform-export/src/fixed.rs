//! Numbers with a fixed count of decimals, as `format!("{:.N}", f64::from(v))`
//! writes them (the exact binary value rounded half to even), trailing zeros
//! and a bare `.` trimmed, never `-0`: what SVG coordinates are written
//! with. A million-segment drawing writes millions of them; the standard
//! formatter's exact mode, and a `String` per number, were most of writing
//! its SVG.

/// Appends `v` with `decimals` decimals (trailing zeros trimmed, `-0` as
/// `0`) to `out`.
pub(crate) fn push_fixed(out: &mut String, v: f32, decimals: usize) {
    match scaled(v, decimals).map(u64::try_from) {
        Some(Ok(0)) => out.push('0'),
        Some(Ok(r)) => {
            let mut buf = [0u8; 48];
            let at = write_point_digits(&mut buf, r, decimals, v < 0.0);
            out.push_str(std::str::from_utf8(&buf[at..]).expect("ASCII"));
        }
        // Not finite, or |v| · 10^decimals of 20 digits or more: rare
        // enough for the standard formatter.
        _ => push_slow(out, v, decimals),
    }
}

/// `v` with `decimals` decimals, as [`push_fixed`] writes it.
pub(crate) fn fixed(v: f32, decimals: usize) -> String {
    let mut s = String::new();
    push_fixed(&mut s, v, decimals);
    s
}

/// 10^0 … 10^19.
const POW10: [u64; 20] = {
    let mut p = [1u64; 20];
    let mut i = 1;
    while i < 20 {
        p[i] = p[i - 1] * 10;
        i += 1;
    }
    p
};

/// |v| · 10^decimals rounded half to even, computed exactly in integers;
/// `None` where that does not fit (not finite, huge, or over 19 decimals).
fn scaled(v: f32, decimals: usize) -> Option<u128> {
    if !v.is_finite() || decimals > 19 {
        return None;
    }
    let bits = v.to_bits();
    let exp = ((bits >> 23) & 0xff) as i32;
    let frac = u64::from(bits & 0x7f_ffff);
    // |v| = m · 2^e exactly.
    let (m, e) = if exp == 0 { (frac, -149) } else { (frac | 0x80_0000, exp - 150) };
    let k = e.unsigned_abs();
    if e < 0 && k < 64 && decimals <= 12 {
        // The drawing case, in 64 bits: m < 2^24 and 10^12 < 2^40.
        let q = m * POW10[decimals];
        let (r, rem, half) = (q >> k, q & ((1 << k) - 1), 1 << (k - 1));
        return Some(u128::from(if rem > half || (rem == half && r & 1 == 1) { r + 1 } else { r }));
    }
    // m < 2^24 and 10^19 < 2^64: q < 2^88.
    let q = u128::from(m) * u128::from(POW10[decimals]);
    if e >= 0 {
        // At most 2^127: q · 2^e must fit.
        return (e <= 39).then(|| q << e);
    }
    if k >= 100 {
        // q < 2^88 < 2^(k-1): below one half.
        return Some(0);
    }
    let (r, rem) = (q >> k, q & ((1u128 << k) - 1));
    let half = 1u128 << (k - 1);
    Some(if rem > half || (rem == half && r & 1 == 1) { r + 1 } else { r })
}

/// Writes `r` · 10^−`decimals` (trailing zeros and a bare `.` trimmed,
/// after a `-` when `negative`) at the end of `buf`; returns where it
/// starts. One `push_str` of the whole number, not one `push` a digit.
fn write_point_digits(buf: &mut [u8; 48], mut r: u64, mut decimals: usize, negative: bool) -> usize {
    while decimals > 0 && r.is_multiple_of(10) {
        r /= 10;
        decimals -= 1;
    }
    let mut at = buf.len();
    // The decimals, the point, and at least one digit before it.
    for i in 0..decimals + 1 {
        if i == decimals && decimals > 0 {
            at -= 1;
            buf[at] = b'.';
        }
        at -= 1;
        buf[at] = b'0' + (r % 10) as u8;
        r /= 10;
    }
    while r > 0 {
        at -= 1;
        buf[at] = b'0' + (r % 10) as u8;
        r /= 10;
    }
    if negative {
        at -= 1;
        buf[at] = b'-';
    }
    at
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
