//! Gzipped NBT files (schematics) through fastnbt: compression, decoding
//! to `fastnbt::Value` with bounded allocations, and typed field access
//! with errors that name the field.

use super::error::{MinecraftError, malformed};
use fastnbt::Value;
use flate2::Compression;
use flate2::read::GzDecoder;
use flate2::write::GzEncoder;
use serde::Serialize;
use std::collections::HashMap;
use std::io::{Read, Write};

/// Decompressed files larger than this are refused (about half a billion
/// blocks; it stops a small garbled file inflating without bound).
const MAX_NBT: u64 = 1 << 29;

/// A compound's entries.
pub(crate) type Compound = HashMap<String, Value>;

/// `value` as gzipped NBT under root name `root` (flate2's gzip header has
/// no timestamp, so the bytes are deterministic).
pub(crate) fn write_gzipped<T: Serialize>(value: &T, root: &str) -> Vec<u8> {
    let nbt = fastnbt::to_bytes_with_opts(value, fastnbt::SerOpts::new().root_name(root))
        .expect("schematic structs always serialize");
    let mut enc = GzEncoder::new(Vec::with_capacity(nbt.len() / 4), Compression::default());
    enc.write_all(&nbt).expect("writing to a Vec cannot fail");
    enc.finish().expect("writing to a Vec cannot fail")
}

/// Decodes a (possibly gzipped) NBT file whose root is a compound.
pub(crate) fn read_root(bytes: &[u8], format: &'static str) -> Result<Compound, MinecraftError> {
    let raw;
    let nbt = if bytes.starts_with(&[0x1F, 0x8B]) {
        let mut out = Vec::new();
        GzDecoder::new(bytes)
            .take(MAX_NBT + 1)
            .read_to_end(&mut out)
            .map_err(|e| malformed(format, format!("bad gzip data: {e}")))?;
        if out.len() as u64 > MAX_NBT {
            return Err(malformed(format, format!("it decompresses to more than {MAX_NBT} bytes")));
        }
        raw = out;
        &raw[..]
    } else {
        bytes
    };
    // Lists cannot hold more elements than there are bytes: this stops a
    // garbled length from allocating gigabytes.
    let opts = fastnbt::DeOpts::new().max_seq_len(nbt.len());
    match fastnbt::from_bytes_with_opts(nbt, opts) {
        Ok(Value::Compound(m)) => Ok(m),
        Ok(_) => Err(malformed(format, "the root tag is not a compound")),
        Err(e) => Err(malformed(format, format!("bad NBT: {e}"))),
    }
}

/// Integer field `key` (any integer tag).
pub(crate) fn int(m: &Compound, key: &str, format: &'static str) -> Result<i64, MinecraftError> {
    opt_int(m, key).ok_or_else(|| malformed(format, format!("`{key}` is missing or not an integer")))
}

/// Integer field `key`, if present.
pub(crate) fn opt_int(m: &Compound, key: &str) -> Option<i64> {
    match m.get(key)? {
        Value::Byte(v) => Some((*v).into()),
        Value::Short(v) => Some((*v).into()),
        Value::Int(v) => Some((*v).into()),
        Value::Long(v) => Some(*v),
        _ => None,
    }
}

/// Compound field `key`.
pub(crate) fn compound<'a>(m: &'a Compound, key: &str, format: &'static str) -> Result<&'a Compound, MinecraftError> {
    match m.get(key) {
        Some(Value::Compound(c)) => Ok(c),
        _ => Err(malformed(format, format!("`{key}` is missing or not a compound"))),
    }
}

/// `{x, y, z}` integer compound field `key`.
pub(crate) fn xyz(m: &Compound, key: &str, format: &'static str) -> Result<[i64; 3], MinecraftError> {
    let c = compound(m, key, format)?;
    let f = |k: &str| int(c, k, format).map_err(|_| malformed(format, format!("`{key}.{k}` is missing")));
    Ok([f("x")?, f("y")?, f("z")?])
}
