//! The compact text form of kept sets that front.json uses: increasing grid indices as gaps in
//! LEB128 varints, in base64.
//!
//! A kept set `k₀ < k₁ < …` is written as the varints of `k₀, k₁ − k₀, k₂ − k₁, …`: each an
//! unsigned LEB128 number (7 bits a byte, low bits first, the high bit set on every byte but
//! the last), the bytes in standard base64 (RFC 4648, `+/`, padded). A dense set's gaps take
//! one byte each. front.json stores a member either so (`kept_packed`) or, when shorter, as the
//! symmetric difference with the member before it in the file, in the same form (`kept_diff`):
//! the indices that member keeps and this one does not, and the other way round. Members
//! neighbouring in T share most of their points, so a diff is usually a few bytes.
//!
//! ```
//! use paretomesh::kept_codec::{decode, encode, toggle};
//! let text = encode(&[0, 5, 6, 300]);
//! assert_eq!(text, "AAUBpgI=");
//! assert_eq!(decode(&text).unwrap(), vec![0, 5, 6, 300]);
//! assert_eq!(toggle(&[0, 5, 6], &[5, 9]), vec![0, 6, 9]);
//! ```

use base64::Engine;
use base64::engine::general_purpose::STANDARD;
use std::fmt;

/// Why a packed kept set could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CodecError {
    /// The text is not base64.
    Base64(String),
    /// A varint runs past the end or past 32 bits.
    BadVarint { at: usize },
    /// An index repeats (a gap of zero after the first) or passes 2³² − 1.
    NotIncreasing { at: usize },
}

impl fmt::Display for CodecError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Base64(e) => write!(f, "the packed kept set is not base64: {e}"),
            Self::BadVarint { at } => write!(
                f,
                "the packed kept set has a broken varint at byte {at} (cut short or over 32 bits)"
            ),
            Self::NotIncreasing { at } => write!(
                f,
                "the packed kept set's index {at} does not increase (a zero gap or past 2^32 - 1)"
            ),
        }
    }
}

impl std::error::Error for CodecError {}

/// Packs increasing indices (see the module doc). Indices that do not increase are packed as
/// given and refused by [`decode`].
pub fn encode(indices: &[u32]) -> String {
    let mut bytes = Vec::with_capacity(indices.len() + 4);
    let mut previous = 0u32;
    for (k, &i) in indices.iter().enumerate() {
        let mut gap = if k == 0 { i } else { i.wrapping_sub(previous) };
        previous = i;
        loop {
            let low = (gap & 0x7f) as u8;
            gap >>= 7;
            if gap == 0 {
                bytes.push(low);
                break;
            }
            bytes.push(low | 0x80);
        }
    }
    STANDARD.encode(bytes)
}

/// Unpacks what [`encode`] packed: strictly increasing indices.
pub fn decode(text: &str) -> Result<Vec<u32>, CodecError> {
    let bytes = STANDARD
        .decode(text)
        .map_err(|e| CodecError::Base64(e.to_string()))?;
    let mut out = Vec::with_capacity(bytes.len());
    let (mut value, mut shift, mut start) = (0u64, 0u32, 0usize);
    for (at, &b) in bytes.iter().enumerate() {
        if shift == 0 {
            start = at;
        }
        value |= u64::from(b & 0x7f) << shift;
        shift += 7;
        if value > u64::from(u32::MAX) || (shift > 35 && b & 0x80 != 0) {
            return Err(CodecError::BadVarint { at: start });
        }
        if b & 0x80 != 0 {
            continue;
        }
        let index = match out.last() {
            None => value,
            Some(&last) if value > 0 => u64::from(last) + value,
            Some(_) => return Err(CodecError::NotIncreasing { at: out.len() }),
        };
        let index =
            u32::try_from(index).map_err(|_| CodecError::NotIncreasing { at: out.len() })?;
        out.push(index);
        (value, shift) = (0, 0);
    }
    if shift != 0 {
        return Err(CodecError::BadVarint { at: start });
    }
    Ok(out)
}

/// The symmetric difference of two increasing index lists, increasing: what turns one kept
/// set into the other, both ways.
pub fn toggle(a: &[u32], b: &[u32]) -> Vec<u32> {
    let mut out = Vec::new();
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        match (a.get(i), b.get(j)) {
            (Some(x), Some(y)) if x == y => {
                i += 1;
                j += 1;
            }
            (Some(&x), Some(&y)) if x < y => {
                out.push(x);
                i += 1;
            }
            (Some(_), Some(&y)) => {
                out.push(y);
                j += 1;
            }
            (Some(&x), None) => {
                out.push(x);
                i += 1;
            }
            (None, Some(&y)) => {
                out.push(y);
                j += 1;
            }
            (None, None) => break,
        }
    }
    out
}

/// A kept set of a list as front.json writes it: `packed` (its indices, [`encode`]d) or `diff`
/// (its [`toggle`] with the set before it in the list, encoded), whichever is shorter.
#[derive(Clone, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub(crate) struct PackedSet {
    /// The set's own indices, encoded.
    #[serde(
        rename = "kept_packed",
        skip_serializing_if = "Option::is_none",
        default
    )]
    pub packed: Option<String>,
    /// The difference with the set before it, encoded.
    #[serde(rename = "kept_diff", skip_serializing_if = "Option::is_none", default)]
    pub diff: Option<String>,
}

impl PackedSet {
    /// Packs `kept`, the set after `previous` in its list (`None` for the first).
    pub(crate) fn new(previous: Option<&[u32]>, kept: &[u32]) -> Self {
        let packed = encode(kept);
        match previous.map(|p| encode(&toggle(p, kept))) {
            Some(diff) if diff.len() < packed.len() => Self {
                packed: None,
                diff: Some(diff),
            },
            _ => Self {
                packed: Some(packed),
                diff: None,
            },
        }
    }

    /// The set, given the one before it in its list (`None` for the first). `what` names the
    /// set in errors ("front member 3").
    pub(crate) fn unpack(&self, previous: Option<&[u32]>, what: &str) -> Result<Vec<u32>, String> {
        match (&self.packed, &self.diff) {
            (Some(packed), None) => decode(packed).map_err(|e| format!("{what}: {e}")),
            (None, Some(diff)) => {
                let before = previous
                    .ok_or_else(|| format!("{what} has kept_diff, but no set before it"))?;
                let diff = decode(diff).map_err(|e| format!("{what}: {e}"))?;
                Ok(toggle(before, &diff))
            }
            _ => Err(format!(
                "{what} needs exactly one of kept_packed and kept_diff"
            )),
        }
    }
}

/// Packs a list of kept sets, each whole or as a diff with the one before (see [`PackedSet`]).
pub(crate) fn pack_list(sets: &[Vec<u32>]) -> Vec<PackedSet> {
    let mut previous: Option<&[u32]> = None;
    sets.iter()
        .map(|kept| {
            let p = PackedSet::new(previous, kept);
            previous = Some(kept);
            p
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_gaps_of_every_varint_length() {
        let indices = vec![3, 4, 131, 131 + 16_384, 131 + 16_384 + 2_097_152, u32::MAX];
        assert_eq!(decode(&encode(&indices)).unwrap(), indices);
        assert_eq!(decode(&encode(&[])).unwrap(), Vec::<u32>::new());
        assert_eq!(decode(&encode(&[0])).unwrap(), vec![0]);
    }

    #[test]
    fn a_dense_set_takes_about_one_byte_an_index() {
        let indices: Vec<u32> = (0..3000).map(|i| i * 3 + 1).collect();
        // 3000 one-byte gaps, base64: 4 characters per 3 bytes.
        assert_eq!(encode(&indices).len(), 4000);
    }

    #[test]
    fn broken_text_is_an_error_not_a_panic() {
        assert!(matches!(decode("@@@"), Err(CodecError::Base64(_))));
        // A varint whose continuation bit is set on the last byte.
        assert_eq!(
            decode(&STANDARD.encode([5u8, 0x80])),
            Err(CodecError::BadVarint { at: 1 })
        );
        // Over 32 bits.
        assert!(matches!(
            decode(&STANDARD.encode([0xff, 0xff, 0xff, 0xff, 0x7f])),
            Err(CodecError::BadVarint { .. })
        ));
        // A zero gap repeats an index; a gap past 2^32 - 1 overflows.
        assert_eq!(
            decode(&STANDARD.encode([5u8, 0])),
            Err(CodecError::NotIncreasing { at: 1 })
        );
        assert_eq!(
            decode(&encode(&[u32::MAX, 3])),
            Err(CodecError::NotIncreasing { at: 1 })
        );
    }

    #[test]
    fn toggling_twice_gives_the_set_back() {
        let a = vec![0, 2, 4, 6, 8, 100];
        let b = vec![0, 1, 4, 8, 9, 200];
        let d = toggle(&a, &b);
        assert_eq!(d, vec![1, 2, 6, 9, 100, 200]);
        assert_eq!(toggle(&a, &d), b);
        assert_eq!(toggle(&b, &d), a);
    }

    #[test]
    fn a_list_packs_near_sets_as_diffs_and_unpacks() {
        let sets: Vec<Vec<u32>> = vec![
            (0..500).map(|i| i * 7).collect(),
            (0..500).map(|i| i * 7).chain([4000]).collect(),
            vec![1, 2],
        ];
        let packed = pack_list(&sets);
        assert!(packed[0].packed.is_some() && packed[0].diff.is_none());
        assert_eq!(packed[1].diff.as_deref(), Some(encode(&[4000]).as_str()));
        assert!(packed[2].packed.is_some());
        let mut previous: Option<&[u32]> = None;
        for (p, set) in packed.iter().zip(&sets) {
            assert_eq!(&p.unpack(previous, "set").unwrap(), set);
            previous = Some(set);
        }
        let orphan = PackedSet {
            packed: None,
            diff: Some(encode(&[2])),
        };
        let e = orphan.unpack(None, "tile 0's member 0").unwrap_err();
        assert!(e.contains("tile 0's member 0 has kept_diff"), "{e}");
        assert_eq!(
            PackedSet::default().unpack(None, "set"),
            Err("set needs exactly one of kept_packed and kept_diff".to_string())
        );
    }
}
