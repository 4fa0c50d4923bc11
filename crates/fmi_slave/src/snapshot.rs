//! FMU state as bytes. A model's state types implement [`Visit`], which walks their numeric fields
//! in a fixed order; [`to_bytes`] writes them as little-endian 8-byte words behind a header (magic,
//! format version, GUID, length), so a blob from another model, version or interface is refused
//! by [`from_bytes`] instead of misread.

use crate::Unreadable;

/// Walks over numeric fields; a writer reads them, a reader overwrites them.
pub trait Visitor {
    fn real(&mut self, x: &mut f64);
    fn int(&mut self, x: &mut i64);
}

/// Something whose fields can be visited.
pub trait Visit {
    fn visit<V: Visitor>(&mut self, v: &mut V);
}

/// Visits an `i32` as an integer word.
pub fn int32<V: Visitor>(v: &mut V, x: &mut i32) {
    let mut w = *x as i64;
    v.int(&mut w);
    *x = w as i32;
}

/// Visits a `usize` as an integer word.
pub fn uint<V: Visitor>(v: &mut V, x: &mut usize) {
    let mut w = *x as i64;
    v.int(&mut w);
    *x = w as usize;
}

/// Visits a `u64` as an integer word.
pub fn uint64<V: Visitor>(v: &mut V, x: &mut u64) {
    let mut w = *x as i64;
    v.int(&mut w);
    *x = w as u64;
}

/// Visits a `bool` as an integer word.
pub fn boolean<V: Visitor>(v: &mut V, x: &mut bool) {
    let mut w = *x as i64;
    v.int(&mut w);
    *x = w != 0;
}

const FORMAT_VERSION: u64 = 1;

struct Writer<'a>(&'a mut Vec<u8>);

impl Visitor for Writer<'_> {
    fn real(&mut self, x: &mut f64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn int(&mut self, x: &mut i64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
}

struct Reader<'a> {
    bytes: &'a [u8],
    short: bool,
}

impl Reader<'_> {
    fn word(&mut self) -> [u8; 8] {
        match self.bytes.split_first_chunk::<8>() {
            Some((w, rest)) => {
                self.bytes = rest;
                *w
            }
            None => {
                self.short = true;
                [0; 8]
            }
        }
    }
}

impl Visitor for Reader<'_> {
    fn real(&mut self, x: &mut f64) {
        *x = f64::from_le_bytes(self.word());
    }
    fn int(&mut self, x: &mut i64) {
        *x = i64::from_le_bytes(self.word());
    }
}

/// Whether every Real field of `item` is finite (a check for restored states).
pub fn all_finite<T: Visit + Clone>(item: &T) -> bool {
    struct Finite(bool);
    impl Visitor for Finite {
        fn real(&mut self, x: &mut f64) {
            self.0 &= x.is_finite();
        }
        fn int(&mut self, _: &mut i64) {}
    }
    let mut check = Finite(true);
    item.clone().visit(&mut check);
    check.0
}

/// Serialises `item` behind a header naming the model (`magic`) and its `guid`.
pub fn to_bytes<T: Visit + Clone>(magic: &[u8; 8], guid: &str, item: &T) -> Vec<u8> {
    let mut payload = Vec::new();
    item.clone().visit(&mut Writer(&mut payload));
    let mut out = Vec::with_capacity(payload.len() + 64);
    out.extend_from_slice(magic);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(guid.len() as u64).to_le_bytes());
    out.extend_from_slice(guid.as_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(&payload);
    out
}

/// Reads into `item` what [`to_bytes`] wrote; refuses a foreign or truncated blob, and one that
/// does not read back to the same bytes (a Boolean word other than 0 or 1, an integer out of its
/// type's range): what is accepted is exactly what a state of this layout serialises to. The
/// values' ranges are the model's to check.
pub fn from_bytes<T: Visit + Clone>(magic: &[u8; 8], guid: &str, bytes: &[u8], item: &mut T) -> Result<(), Unreadable> {
    let Some((head, rest)) = bytes.split_first_chunk::<8>() else { return Err(Unreadable::ShorterThanHeader) };
    if head != magic {
        return Err(Unreadable::BadMagic);
    }
    let mut r = Reader { bytes: rest, short: false };
    if u64::from_le_bytes(r.word()) != FORMAT_VERSION {
        return Err(Unreadable::FormatVersion);
    }
    let guid_len = u64::from_le_bytes(r.word()) as usize;
    if r.bytes.len() < guid_len || &r.bytes[..guid_len] != guid.as_bytes() {
        return Err(Unreadable::OtherGuid);
    }
    r.bytes = &r.bytes[guid_len..];
    let len = u64::from_le_bytes(r.word()) as usize;
    if r.short || r.bytes.len() != len {
        return Err(Unreadable::PayloadLength);
    }
    let payload = r.bytes;
    item.visit(&mut r);
    if r.short || !r.bytes.is_empty() {
        return Err(Unreadable::Layout);
    }
    let mut again = Vec::with_capacity(payload.len());
    item.clone().visit(&mut Writer(&mut again));
    if again != payload {
        return Err(Unreadable::FieldRange);
    }
    Ok(())
}
