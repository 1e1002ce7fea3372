//! Stage 5, film: a single-part OpenEXR header's attributes put in name order, so that a file's
//! bytes do not depend on a hash map's iteration order.
//!
//! The `exr` crate keeps custom attributes (a tile's `scnc:identity`, `scnc:tile`, …) in a
//! `HashMap` with a random seed and writes them in its iteration order, so two renders of the
//! same tile gave files that differed in their header. An attribute is `name\0 type\0 size
//! value`; the header ends with an empty name. Reordering them keeps the header's length, so the
//! offset table after it stays right. Used by [`encode_tile`](super::tile::encode_tile).

/// The OpenEXR magic number, little-endian.
const MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
/// Version-field flags of a multi-part or deep file, whose header this does not parse.
const MULTI_PART_OR_DEEP: u32 = 0x1000 | 0x800;

/// Sorts the header attributes of the single-part EXR file `bytes` by name, in place.
/// `Err` says why the bytes are not such a file (then they are left as they were).
pub fn sort_attributes(bytes: &mut [u8]) -> Result<(), &'static str> {
    let version = bytes
        .get(4..8)
        .ok_or("shorter than an EXR's magic and version")?;
    if bytes[..4] != MAGIC {
        return Err("not an OpenEXR file");
    }
    let flags = u32::from_le_bytes([version[0], version[1], version[2], version[3]]);
    if flags & MULTI_PART_OR_DEEP != 0 {
        return Err("a multi-part or deep file");
    }
    let start = 8;
    let mut spans = Vec::new();
    let mut at = start;
    loop {
        let name_end = nul_after(bytes, at)?;
        if name_end == at {
            break; // the empty name ends the header
        }
        let type_end = nul_after(bytes, name_end + 1)?;
        let size_at = type_end + 1;
        let size = bytes
            .get(size_at..size_at + 4)
            .ok_or("a header attribute's size is cut off")?;
        let size = i32::from_le_bytes([size[0], size[1], size[2], size[3]]);
        let size = usize::try_from(size).map_err(|_| "a negative attribute size")?;
        let end = size_at + 4 + size;
        if end > bytes.len() {
            return Err("a header attribute's value is cut off");
        }
        spans.push((at, name_end, end));
        at = end;
    }
    let mut sorted: Vec<_> = spans.clone();
    sorted.sort_by(|a, b| bytes[a.0..a.1].cmp(&bytes[b.0..b.1]));
    let mut header = Vec::with_capacity(at - start);
    for &(from, _, to) in &sorted {
        header.extend_from_slice(&bytes[from..to]);
    }
    bytes[start..at].copy_from_slice(&header);
    Ok(())
}

/// The index of the first NUL byte at or after `from`.
fn nul_after(bytes: &[u8], from: usize) -> Result<usize, &'static str> {
    bytes
        .get(from..)
        .and_then(|rest| rest.iter().position(|&b| b == 0))
        .map(|k| from + k)
        .ok_or("a header name runs past the end")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn attribute(name: &str, kind: &str, value: &[u8]) -> Vec<u8> {
        let mut a = Vec::new();
        a.extend_from_slice(name.as_bytes());
        a.push(0);
        a.extend_from_slice(kind.as_bytes());
        a.push(0);
        a.extend_from_slice(&(value.len() as i32).to_le_bytes());
        a.extend_from_slice(value);
        a
    }

    fn file(attributes: &[Vec<u8>]) -> Vec<u8> {
        let mut f = MAGIC.to_vec();
        f.extend_from_slice(&2u32.to_le_bytes());
        for a in attributes {
            f.extend_from_slice(a);
        }
        f.push(0);
        f.extend_from_slice(&[9, 8, 7, 6]); // the offset table and pixels, untouched
        f
    }

    #[test]
    fn attributes_come_out_in_name_order_and_the_rest_is_untouched() {
        let (a, b, c) = (
            attribute("scnc:tonemap", "string", b"filmic"),
            attribute("channels", "chlist", &[1, 2, 3]),
            attribute("scnc:exposure", "float", &[0, 0, 0, 0]),
        );
        let mut shuffled = file(&[a.clone(), b.clone(), c.clone()]);
        let mut other = file(&[c.clone(), a.clone(), b.clone()]);
        sort_attributes(&mut shuffled).expect("a header");
        sort_attributes(&mut other).expect("a header");
        assert_eq!(shuffled, file(&[b, c, a]));
        assert_eq!(shuffled, other);
    }

    #[test]
    fn foreign_or_cut_bytes_are_refused_and_left_alone() {
        let whole = file(&[attribute("x", "int", &[1, 0, 0, 0])]);
        for cut in [0, 3, 8, 12, 18] {
            let mut part = whole[..cut].to_vec();
            assert!(sort_attributes(&mut part).is_err(), "cut at {cut}");
            assert_eq!(part, whole[..cut]);
        }
        let mut png = b"\x89PNG\r\n\x1a\n....".to_vec();
        assert!(sort_attributes(&mut png).is_err());
    }
}
