//! Packed palette indices: chunk sections (entries never straddle a long),
//! Litematica regions (entries straddle longs) and Sponge varints.

/// Bits per entry of a chunk section's block states: at least 4.
pub(crate) fn section_bits(palette_len: usize) -> u32 {
    ceil_log2(palette_len).max(4)
}

/// Bits per entry of a Litematica region: at least 2.
pub(crate) fn litematic_bits(palette_len: usize) -> u32 {
    ceil_log2(palette_len).max(2)
}

/// ⌈log₂ n⌉ (0 for n ≤ 1).
pub(crate) fn ceil_log2(n: usize) -> u32 {
    if n <= 1 { 0 } else { usize::BITS - (n - 1).leading_zeros() }
}

/// Number of longs holding `count` entries of `bits` bits without
/// straddling.
pub(crate) fn aligned_len(count: usize, bits: u32) -> usize {
    let per_long = (64 / bits) as usize;
    count.div_ceil(per_long)
}

/// Packs `values` (each below 2^bits) into longs, `64 / bits` entries per
/// long from the low bits up; the leftover high bits stay zero.
pub(crate) fn pack_aligned(values: &[u32], bits: u32) -> Vec<i64> {
    let per_long = (64 / bits) as usize;
    values
        .chunks(per_long)
        .map(|c| c.iter().enumerate().fold(0u64, |acc, (i, &v)| acc | (u64::from(v) << (i as u32 * bits))) as i64)
        .collect()
}

/// Unpacks `count` entries of `bits` bits, `None` when `data` is too short.
pub(crate) fn unpack_aligned(data: &[i64], bits: u32, count: usize) -> Option<Vec<u32>> {
    if !(1..=32).contains(&bits) || data.len() < aligned_len(count, bits) {
        return None;
    }
    let per_long = (64 / bits) as usize;
    let mask = (1u64 << bits) - 1;
    let mut out = Vec::with_capacity(count);
    for &l in data {
        let l = l as u64;
        for i in 0..per_long {
            if out.len() == count {
                return Some(out);
            }
            out.push(((l >> (i as u32 * bits)) & mask) as u32);
        }
    }
    Some(out)
}

/// Number of longs holding `count` entries of `bits` bits back to back.
pub(crate) fn tight_len(count: usize, bits: u32) -> usize {
    (count * bits as usize).div_ceil(64)
}

/// Packs entries back to back: entry `i` takes bits `i·bits ..` of the
/// little-endian bit string, crossing into the next long where it must.
pub(crate) fn pack_tight(values: &[u32], bits: u32) -> Vec<i64> {
    let mut out = vec![0u64; tight_len(values.len(), bits)];
    for (i, &v) in values.iter().enumerate() {
        let start = i * bits as usize;
        let (word, shift) = (start / 64, (start % 64) as u32);
        out[word] |= u64::from(v) << shift;
        if shift + bits > 64 {
            out[word + 1] |= u64::from(v) >> (64 - shift);
        }
    }
    out.into_iter().map(|l| l as i64).collect()
}

/// Unpacks `count` back-to-back entries, `None` when `data` is too short.
pub(crate) fn unpack_tight(data: &[i64], bits: u32, count: usize) -> Option<Vec<u32>> {
    if !(1..=32).contains(&bits) || data.len() < tight_len(count, bits) {
        return None;
    }
    let mask = (1u64 << bits) - 1;
    Some(
        (0..count)
            .map(|i| {
                let start = i * bits as usize;
                let (word, shift) = (start / 64, (start % 64) as u32);
                let mut v = (data[word] as u64) >> shift;
                if shift + bits > 64 {
                    v |= (data[word + 1] as u64) << (64 - shift);
                }
                (v & mask) as u32
            })
            .collect(),
    )
}

/// Appends `v` as an unsigned LEB128 varint (Sponge `BlockData`).
pub(crate) fn put_varint(out: &mut Vec<u8>, mut v: u32) {
    while v >= 0x80 {
        out.push((v as u8 & 0x7F) | 0x80);
        v >>= 7;
    }
    out.push(v as u8);
}

/// Reads `count` varints; `None` when the bytes end early or a varint is
/// longer than 5 bytes.
pub(crate) fn read_varints(bytes: &[u8], count: usize) -> Option<Vec<u32>> {
    let mut out = Vec::with_capacity(count.min(bytes.len()));
    let mut it = bytes.iter();
    for _ in 0..count {
        let mut v = 0u32;
        let mut shift = 0;
        loop {
            let b = *it.next()?;
            if shift >= 32 {
                return None;
            }
            v |= u32::from(b & 0x7F) << shift;
            if b & 0x80 == 0 {
                break;
            }
            shift += 7;
        }
        out.push(v);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn bit_widths() {
        assert_eq!(ceil_log2(0), 0);
        assert_eq!(ceil_log2(1), 0);
        assert_eq!(ceil_log2(2), 1);
        assert_eq!(ceil_log2(5), 3);
        assert_eq!(ceil_log2(16), 4);
        assert_eq!(ceil_log2(17), 5);
        assert_eq!(section_bits(2), 4);
        assert_eq!(section_bits(33), 6);
        assert_eq!(litematic_bits(1), 2);
        assert_eq!(litematic_bits(5), 3);
        // A 4096-entry section at 5 bits: 12 per long, 342 longs.
        assert_eq!(aligned_len(4096, 5), 342);
        assert_eq!(aligned_len(4096, 4), 256);
    }

    #[test]
    fn aligned_packing_leaves_the_top_bits_unused() {
        // 5 bits: 12 entries per long, bits 60..64 stay zero; the 13th
        // entry starts the next long.
        let v: Vec<u32> = (0..13).map(|i| 31 - i).collect();
        let p = pack_aligned(&v, 5);
        assert_eq!(p.len(), 2);
        assert_eq!((p[0] as u64) >> 60, 0);
        assert_eq!(p[0] as u64 & 31, 31);
        assert_eq!((p[0] as u64 >> 55) & 31, 20);
        assert_eq!(p[1], 19);
        assert_eq!(unpack_aligned(&p, 5, 13).unwrap(), v);
        assert_eq!(unpack_aligned(&p[..1], 5, 13), None);
    }

    #[test]
    fn tight_packing_straddles_longs_by_hand() {
        // 3 bits per entry: entry 21 takes bits 63..66, one bit in the
        // first long and two in the second.
        let mut v = vec![0u32; 23];
        v[0] = 0b101;
        v[21] = 0b110;
        v[22] = 0b111;
        let p = pack_tight(&v, 3);
        assert_eq!(p.len(), 2);
        assert_eq!(p[0] as u64, 0b101);
        // Low bit of 0b110 (0) lands in bit 63 of long 0; its top two bits
        // (0b11) in bits 0..2 of long 1; entry 22 in bits 2..5.
        assert_eq!(p[1] as u64, 0b1_1111);
        let mut w = v.clone();
        w[21] = 0b111;
        let q = pack_tight(&w, 3);
        assert_eq!(q[0] as u64, 0b101 | 1 << 63);
        assert_eq!(unpack_tight(&q, 3, 23).unwrap(), w);
    }

    #[test]
    fn varints() {
        let mut b = Vec::new();
        for v in [0, 127, 128, 300, u32::MAX] {
            put_varint(&mut b, v);
        }
        assert_eq!(&b[..4], &[0, 127, 0x80, 1]);
        assert_eq!(read_varints(&b, 5).unwrap(), vec![0, 127, 128, 300, u32::MAX]);
        assert_eq!(read_varints(&b, 6), None);
        assert_eq!(read_varints(&[0xFF; 8], 1), None);
    }

    proptest! {
        #[test]
        fn packings_round_trip(bits in 1u32..=16, raw in proptest::collection::vec(any::<u32>(), 0..300)) {
            let v: Vec<u32> = raw.iter().map(|x| x & ((1 << bits) - 1)).collect();
            prop_assert_eq!(unpack_aligned(&pack_aligned(&v, bits), bits, v.len()).unwrap(), v.clone());
            prop_assert_eq!(unpack_tight(&pack_tight(&v, bits), bits, v.len()).unwrap(), v);
        }
    }
}
