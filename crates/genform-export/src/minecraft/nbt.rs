//! An order-preserving NBT tree for chunk rewriting.
//!
//! fastnbt's `Value` keeps compounds in a `HashMap`, so a decoded chunk
//! written back would come out in a different key order from run to run.
//! Chunks are edited through this tree instead: it keeps every tag, its
//! type, its key order and its string bytes (Java's modified UTF-8) exactly,
//! so re-encoding an unedited tree gives the same bytes, and an edit changes
//! only the tags it touches.

use std::fmt;

/// Tag ids.
const END: u8 = 0;
const BYTE: u8 = 1;
const SHORT: u8 = 2;
const INT: u8 = 3;
const LONG: u8 = 4;
const FLOAT: u8 = 5;
const DOUBLE: u8 = 6;
const BYTE_ARRAY: u8 = 7;
const STRING: u8 = 8;
const LIST: u8 = 9;
const COMPOUND: u8 = 10;
const INT_ARRAY: u8 = 11;
const LONG_ARRAY: u8 = 12;

/// Minecraft refuses NBT nested deeper than this.
const MAX_DEPTH: usize = 512;

/// One NBT tag.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tag {
    Byte(i8),
    Short(i16),
    Int(i32),
    Long(i64),
    Float(f32),
    Double(f64),
    ByteArray(Vec<i8>),
    /// Modified UTF-8 bytes, as stored.
    String(Vec<u8>),
    /// Element type id (kept for empty lists) and elements.
    List(u8, Vec<Tag>),
    /// Named tags in file order.
    Compound(Vec<(Vec<u8>, Tag)>),
    IntArray(Vec<i32>),
    LongArray(Vec<i64>),
}

/// Why NBT bytes could not be decoded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct NbtError(pub String);

impl fmt::Display for NbtError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl Tag {
    /// A string tag from Rust text.
    pub fn string(s: &str) -> Tag {
        Tag::String(to_mutf8(s))
    }

    /// The type id of this tag.
    fn id(&self) -> u8 {
        match self {
            Tag::Byte(_) => BYTE,
            Tag::Short(_) => SHORT,
            Tag::Int(_) => INT,
            Tag::Long(_) => LONG,
            Tag::Float(_) => FLOAT,
            Tag::Double(_) => DOUBLE,
            Tag::ByteArray(_) => BYTE_ARRAY,
            Tag::String(_) => STRING,
            Tag::List(..) => LIST,
            Tag::Compound(_) => COMPOUND,
            Tag::IntArray(_) => INT_ARRAY,
            Tag::LongArray(_) => LONG_ARRAY,
        }
    }

    /// The value under `key` of a compound.
    pub fn get(&self, key: &str) -> Option<&Tag> {
        match self {
            Tag::Compound(items) => items.iter().find(|(k, _)| k == key.as_bytes()).map(|(_, v)| v),
            _ => None,
        }
    }

    /// The value under `key` of a compound, mutably.
    pub fn get_mut(&mut self, key: &str) -> Option<&mut Tag> {
        match self {
            Tag::Compound(items) => items.iter_mut().find(|(k, _)| k == key.as_bytes()).map(|(_, v)| v),
            _ => None,
        }
    }

    /// Sets `key` of a compound (replacing in place, else appending); no-op
    /// on other tags.
    pub fn insert(&mut self, key: &str, value: Tag) {
        if let Tag::Compound(items) = self {
            match items.iter_mut().find(|(k, _)| k == key.as_bytes()) {
                Some((_, v)) => *v = value,
                None => items.push((key.as_bytes().to_vec(), value)),
            }
        }
    }

    /// Removes `key` from a compound.
    pub fn remove(&mut self, key: &str) {
        if let Tag::Compound(items) = self {
            items.retain(|(k, _)| k != key.as_bytes());
        }
    }

    /// Any integer tag as `i64`.
    pub fn as_i64(&self) -> Option<i64> {
        match *self {
            Tag::Byte(v) => Some(v.into()),
            Tag::Short(v) => Some(v.into()),
            Tag::Int(v) => Some(v.into()),
            Tag::Long(v) => Some(v),
            _ => None,
        }
    }

    /// A string tag as text (modified UTF-8 decoded; invalid sequences
    /// replaced).
    pub fn as_str(&self) -> Option<String> {
        match self {
            Tag::String(b) => Some(from_mutf8(b)),
            _ => None,
        }
    }

    /// The elements of a list.
    pub fn as_list(&self) -> Option<&[Tag]> {
        match self {
            Tag::List(_, items) => Some(items),
            _ => None,
        }
    }

    /// The elements of a list, mutably.
    pub fn as_list_mut(&mut self) -> Option<&mut Vec<Tag>> {
        match self {
            Tag::List(_, items) => Some(items),
            _ => None,
        }
    }

    /// The entries of a compound.
    pub fn as_compound(&self) -> Option<&[(Vec<u8>, Tag)]> {
        match self {
            Tag::Compound(items) => Some(items),
            _ => None,
        }
    }
}

/// A list tag of `items`, which must share one type (the first one's).
pub(crate) fn list(items: Vec<Tag>) -> Tag {
    Tag::List(items.first().map_or(END, Tag::id), items)
}

/// Decodes a whole NBT document: a named root compound. Returns the root
/// name and the root. Trailing bytes are an error.
pub(crate) fn decode(bytes: &[u8]) -> Result<(Vec<u8>, Tag), NbtError> {
    let mut r = Reader { bytes, pos: 0 };
    let id = r.u8()?;
    if id != COMPOUND {
        return Err(NbtError(format!("the root tag has type {id}, not a compound")));
    }
    let name = r.name()?;
    let root = r.payload(COMPOUND, 0)?;
    if r.pos != bytes.len() {
        return Err(NbtError(format!("{} stray bytes after the root compound", bytes.len() - r.pos)));
    }
    Ok((name, root))
}

/// Encodes a named root compound.
pub(crate) fn encode(name: &[u8], root: &Tag) -> Vec<u8> {
    let mut out = Vec::with_capacity(16 << 10);
    out.push(root.id());
    put_name(&mut out, name);
    write_payload(&mut out, root);
    out
}

struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], NbtError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or_else(|| NbtError(format!("the data ends early (at byte {})", self.bytes.len())))?;
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], NbtError> {
        let s = self.take(N)?;
        let mut a = [0u8; N];
        a.copy_from_slice(s);
        Ok(a)
    }

    fn u8(&mut self) -> Result<u8, NbtError> {
        Ok(self.array::<1>()?[0])
    }

    fn name(&mut self) -> Result<Vec<u8>, NbtError> {
        let n = u16::from_be_bytes(self.array()?);
        Ok(self.take(n.into())?.to_vec())
    }

    /// An array length that fits in the remaining bytes at `size` bytes each.
    fn len(&mut self, size: usize) -> Result<usize, NbtError> {
        let n = i32::from_be_bytes(self.array()?);
        let left = self.bytes.len() - self.pos;
        if n < 0 || (n as usize).saturating_mul(size) > left {
            return Err(NbtError(format!("an array or list claims {n} elements; only {left} bytes are left")));
        }
        Ok(n as usize)
    }

    fn payload(&mut self, id: u8, depth: usize) -> Result<Tag, NbtError> {
        if depth > MAX_DEPTH {
            return Err(NbtError(format!("tags nested deeper than {MAX_DEPTH}")));
        }
        Ok(match id {
            BYTE => Tag::Byte(self.u8()? as i8),
            SHORT => Tag::Short(i16::from_be_bytes(self.array()?)),
            INT => Tag::Int(i32::from_be_bytes(self.array()?)),
            LONG => Tag::Long(i64::from_be_bytes(self.array()?)),
            FLOAT => Tag::Float(f32::from_be_bytes(self.array()?)),
            DOUBLE => Tag::Double(f64::from_be_bytes(self.array()?)),
            BYTE_ARRAY => {
                let n = self.len(1)?;
                Tag::ByteArray(self.take(n)?.iter().map(|&b| b as i8).collect())
            }
            STRING => {
                let n = u16::from_be_bytes(self.array()?);
                Tag::String(self.take(n.into())?.to_vec())
            }
            LIST => {
                let elem = self.u8()?;
                // Every element but an end tag takes at least one byte.
                let n = self.len(1)?;
                if elem == END && n > 0 {
                    return Err(NbtError("a non-empty list of end tags".into()));
                }
                let items = (0..n).map(|_| self.payload(elem, depth + 1)).collect::<Result<_, _>>()?;
                Tag::List(elem, items)
            }
            COMPOUND => {
                let mut items = Vec::new();
                loop {
                    let id = self.u8()?;
                    if id == END {
                        break;
                    }
                    let name = self.name()?;
                    items.push((name, self.payload(id, depth + 1)?));
                }
                Tag::Compound(items)
            }
            INT_ARRAY => {
                let n = self.len(4)?;
                let s = self.take(4 * n)?;
                Tag::IntArray(s.chunks_exact(4).map(|c| i32::from_be_bytes([c[0], c[1], c[2], c[3]])).collect())
            }
            LONG_ARRAY => {
                let n = self.len(8)?;
                let s = self.take(8 * n)?;
                Tag::LongArray(
                    s.chunks_exact(8).map(|c| i64::from_be_bytes(c.try_into().expect("chunks of 8"))).collect(),
                )
            }
            _ => return Err(NbtError(format!("unknown tag type {id} at byte {}", self.pos))),
        })
    }
}

fn put_name(out: &mut Vec<u8>, name: &[u8]) {
    // Names and strings longer than a u16 cannot be written; cut them
    // (never reached for data read from NBT or for block ids).
    let n = name.len().min(usize::from(u16::MAX));
    out.extend_from_slice(&(n as u16).to_be_bytes());
    out.extend_from_slice(&name[..n]);
}

fn write_payload(out: &mut Vec<u8>, tag: &Tag) {
    let len = |out: &mut Vec<u8>, n: usize| out.extend_from_slice(&(n as i32).to_be_bytes());
    match tag {
        Tag::Byte(v) => out.push(*v as u8),
        Tag::Short(v) => out.extend_from_slice(&v.to_be_bytes()),
        Tag::Int(v) => out.extend_from_slice(&v.to_be_bytes()),
        Tag::Long(v) => out.extend_from_slice(&v.to_be_bytes()),
        Tag::Float(v) => out.extend_from_slice(&v.to_be_bytes()),
        Tag::Double(v) => out.extend_from_slice(&v.to_be_bytes()),
        Tag::ByteArray(v) => {
            len(out, v.len());
            out.extend(v.iter().map(|&b| b as u8));
        }
        Tag::String(s) => put_name(out, s),
        Tag::List(elem, items) => {
            out.push(*elem);
            len(out, items.len());
            for t in items {
                write_payload(out, t);
            }
        }
        Tag::Compound(items) => {
            for (k, v) in items {
                out.push(v.id());
                put_name(out, k);
                write_payload(out, v);
            }
            out.push(END);
        }
        Tag::IntArray(v) => {
            len(out, v.len());
            v.iter().for_each(|x| out.extend_from_slice(&x.to_be_bytes()));
        }
        Tag::LongArray(v) => {
            len(out, v.len());
            v.iter().for_each(|x| out.extend_from_slice(&x.to_be_bytes()));
        }
    }
}

/// Text as Java's modified UTF-8: NUL as `C0 80`, characters beyond the
/// BMP as two 3-byte surrogates; everything else as UTF-8.
pub(crate) fn to_mutf8(s: &str) -> Vec<u8> {
    if s.bytes().all(|b| b != 0 && b < 0x80) {
        return s.as_bytes().to_vec();
    }
    let mut out = Vec::with_capacity(s.len() + 8);
    for c in s.chars() {
        match c as u32 {
            0 => out.extend_from_slice(&[0xC0, 0x80]),
            u @ 0x1_0000.. => {
                let u = u - 0x1_0000;
                for unit in [0xD800 | (u >> 10), 0xDC00 | (u & 0x3FF)] {
                    out.extend_from_slice(&[
                        0xE0 | (unit >> 12) as u8,
                        0x80 | ((unit >> 6) & 0x3F) as u8,
                        0x80 | (unit & 0x3F) as u8,
                    ]);
                }
            }
            _ => {
                let mut buf = [0u8; 4];
                out.extend_from_slice(c.encode_utf8(&mut buf).as_bytes());
            }
        }
    }
    out
}

/// Modified UTF-8 to text; invalid sequences become U+FFFD.
pub(crate) fn from_mutf8(b: &[u8]) -> String {
    if let Ok(s) = std::str::from_utf8(b)
        && !b.contains(&0xED)
    {
        return s.to_string();
    }
    // Decode to UTF-16 units by hand, then let std pair the surrogates.
    let mut units = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let cont = |k: usize| b.get(i + k).copied().filter(|x| x & 0xC0 == 0x80).map(|x| u32::from(x & 0x3F));
        let (unit, used) = if c < 0x80 {
            (u32::from(c), 1)
        } else if c & 0xE0 == 0xC0 {
            cont(1).map_or((0xFFFD, 1), |x| ((u32::from(c & 0x1F) << 6) | x, 2))
        } else if c & 0xF0 == 0xE0 {
            match (cont(1), cont(2)) {
                (Some(x), Some(y)) => ((u32::from(c & 0x0F) << 12) | (x << 6) | y, 3),
                _ => (0xFFFD, 1),
            }
        } else if c & 0xF8 == 0xF0 {
            // Plain 4-byte UTF-8 (not Java's, but harmless to accept).
            match (cont(1), cont(2), cont(3)) {
                (Some(x), Some(y), Some(z)) => {
                    let u = (u32::from(c & 0x07) << 18) | (x << 12) | (y << 6) | z;
                    let u = u.wrapping_sub(0x1_0000);
                    units.push((0xD800 | ((u >> 10) & 0x3FF)) as u16);
                    (0xDC00 | (u & 0x3FF), 4)
                }
                _ => (0xFFFD, 1),
            }
        } else {
            (0xFFFD, 1)
        };
        units.push(unit as u16);
        i += used;
    }
    String::from_utf16_lossy(&units)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Tag {
        Tag::Compound(vec![
            (b"z".to_vec(), Tag::Int(-7)),
            (b"a".to_vec(), Tag::string("minecraft:stone")),
            (b"list".to_vec(), list(vec![Tag::Long(1), Tag::Long(-2)])),
            (b"empty".to_vec(), Tag::List(END, vec![])),
            (
                b"nested".to_vec(),
                Tag::Compound(vec![
                    (b"b".to_vec(), Tag::ByteArray(vec![-1, 0, 1])),
                    (b"i".to_vec(), Tag::IntArray(vec![1, -2, 3])),
                    (b"l".to_vec(), Tag::LongArray(vec![i64::MIN, 0, i64::MAX])),
                    (b"f".to_vec(), Tag::Float(1.5)),
                    (b"d".to_vec(), Tag::Double(-0.25)),
                    (b"s".to_vec(), Tag::Short(-300)),
                    (b"y".to_vec(), Tag::Byte(-4)),
                ]),
            ),
        ])
    }

    #[test]
    fn round_trips_keep_order_and_agree_with_fastnbt() {
        let t = sample();
        let bytes = encode(b"", &t);
        let (name, back) = decode(&bytes).unwrap();
        assert!(name.is_empty());
        assert_eq!(back, t);
        assert_eq!(encode(b"", &back), bytes);
        // An independent decoder reads the same values.
        let v: fastnbt::Value = fastnbt::from_bytes(&bytes).unwrap();
        let fastnbt::Value::Compound(m) = v else { panic!("not a compound") };
        assert_eq!(m["z"], fastnbt::Value::Int(-7));
        assert_eq!(m["a"], fastnbt::Value::String("minecraft:stone".into()));
        let fastnbt::Value::Compound(n) = &m["nested"] else { panic!() };
        assert_eq!(n["l"], fastnbt::Value::LongArray(fastnbt::LongArray::new(vec![i64::MIN, 0, i64::MAX])));
        assert_eq!(n["s"], fastnbt::Value::Short(-300));
        // Key order is the file's, not sorted.
        let keys: Vec<_> = back.as_compound().unwrap().iter().map(|(k, _)| k.clone()).collect();
        assert_eq!(keys[0], b"z");
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        let bytes = encode(b"root", &sample());
        for cut in 0..bytes.len() {
            assert!(decode(&bytes[..cut]).is_err(), "cut at {cut}");
        }
        let mut rng = 0x1234_5678_u64;
        for _ in 0..2000 {
            let mut b = bytes.clone();
            for _ in 0..3 {
                rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                let i = (rng >> 33) as usize % b.len();
                b[i] = (rng >> 13) as u8;
            }
            let _ = decode(&b);
        }
        // A huge claimed length is refused before allocating.
        let mut b = vec![COMPOUND, 0, 0, LONG_ARRAY, 0, 1, b'x'];
        b.extend_from_slice(&i32::MAX.to_be_bytes());
        assert!(decode(&b).unwrap_err().0.contains("claims"));
        // Deep nesting is refused.
        let mut b = vec![COMPOUND, 0, 0, LIST, 0, 0];
        for _ in 0..600 {
            b.extend_from_slice(&[LIST, 0, 0, 0, 1]);
        }
        b.extend_from_slice(&[END, 0, 0, 0, 0]);
        assert!(decode(&b).unwrap_err().0.contains("deeper"));
    }

    #[test]
    fn modified_utf8() {
        for s in ["plain", "nul\0byte", "é ü", "emoji 🧱 block"] {
            let m = to_mutf8(s);
            assert!(!m.contains(&0), "{s}");
            assert_eq!(from_mutf8(&m), s);
        }
        assert_eq!(to_mutf8("🧱").len(), 6);
        assert_eq!(from_mutf8(&[0x61, 0xFF, 0x62]), "a\u{FFFD}b");
    }
}
