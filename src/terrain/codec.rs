//! The number codings of quantized-mesh-1.0: zig-zag deltas of the vertex coordinates,
//! high-water-mark triangle indices, and oct-encoded unit normals (as CesiumJS's
//! `AttributeCompression.octEncode` / `octDecode` with 8 bits per component).

/// Zig-zag delta coding of one coordinate array (u, v or height, each 0..=32767): each value
/// is the difference from the previous one (the first from 0), zig-zagged so that small
/// differences of either sign are small numbers.
pub(crate) fn zigzag_deltas(values: &[u16]) -> Vec<u16> {
    let mut previous = 0i32;
    values
        .iter()
        .map(|&v| {
            let delta = i32::from(v) - previous;
            previous = i32::from(v);
            (((delta << 1) ^ (delta >> 31)) & 0xFFFF) as u16
        })
        .collect()
}

/// The inverse of [`zigzag_deltas`].
pub(crate) fn unzigzag_deltas(codes: &[u16]) -> Vec<u16> {
    let mut value = 0i32;
    codes
        .iter()
        .map(|&c| {
            let c = i32::from(c);
            value += (c >> 1) ^ -(c & 1);
            value as u16
        })
        .collect()
}

/// High-water-mark coding of triangle indices: each index is written as the highest index
/// seen so far plus one, less the index, so a vertex used for the first time is written as 0.
/// The vertices must be numbered in the order the indices first use them.
pub(crate) fn high_water_mark(indices: &[u32]) -> Vec<u32> {
    let mut highest = 0u32;
    indices
        .iter()
        .map(|&i| {
            let code = highest - i;
            if code == 0 {
                highest += 1;
            }
            code
        })
        .collect()
}

/// The inverse of [`high_water_mark`].
pub(crate) fn un_high_water_mark(codes: &[u32]) -> Vec<u32> {
    let mut highest = 0u32;
    codes
        .iter()
        .map(|&c| {
            let i = highest - c;
            if c == 0 {
                highest += 1;
            }
            i
        })
        .collect()
}

fn sign_not_zero(v: f64) -> f64 {
    if v < 0.0 { -1.0 } else { 1.0 }
}

fn to_snorm(v: f64) -> u8 {
    ((v.clamp(-1.0, 1.0) * 0.5 + 0.5) * 255.0).round() as u8
}

fn from_snorm(b: u8) -> f64 {
    f64::from(b) / 255.0 * 2.0 - 1.0
}

/// A unit vector as two bytes: projected onto the octahedron |x| + |y| + |z| = 1, the lower
/// half folded over the upper.
pub(crate) fn oct_encode(n: [f64; 3]) -> [u8; 2] {
    let l1 = n[0].abs() + n[1].abs() + n[2].abs();
    let (mut x, mut y) = (n[0] / l1, n[1] / l1);
    if n[2] < 0.0 {
        let (ox, oy) = (x, y);
        x = (1.0 - oy.abs()) * sign_not_zero(ox);
        y = (1.0 - ox.abs()) * sign_not_zero(oy);
    }
    [to_snorm(x), to_snorm(y)]
}

/// The unit vector two oct-encoded bytes stand for.
pub(crate) fn oct_decode(b: [u8; 2]) -> [f64; 3] {
    let (mut x, mut y) = (from_snorm(b[0]), from_snorm(b[1]));
    let z = 1.0 - x.abs() - y.abs();
    if z < 0.0 {
        let ox = x;
        x = (1.0 - y.abs()) * sign_not_zero(ox);
        y = (1.0 - ox.abs()) * sign_not_zero(y);
    }
    let len = (x * x + y * y + z * z).sqrt();
    [x / len, y / len, z / len]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zigzag_matches_the_spec_and_round_trips() {
        // The spec's examples: deltas 0, -1, 1, -2, 2 are written 0, 1, 2, 3, 4.
        assert_eq!(zigzag_deltas(&[0, 0, 1, 1, 3]), vec![0, 0, 2, 0, 4]);
        assert_eq!(zigzag_deltas(&[5, 4, 6, 4]), vec![10, 1, 4, 3]);
        let values: Vec<u16> = (0..500u32).map(|i| ((i * 7919) % 32768) as u16).collect();
        assert_eq!(unzigzag_deltas(&zigzag_deltas(&values)), values);
        assert_eq!(
            unzigzag_deltas(&zigzag_deltas(&[32767, 0, 32767])),
            vec![32767, 0, 32767]
        );
    }

    #[test]
    fn high_water_mark_writes_a_new_vertex_as_zero_and_round_trips() {
        let indices = [0, 1, 2, 2, 1, 3, 0, 3, 4];
        let codes = high_water_mark(&indices);
        assert_eq!(codes, vec![0, 0, 0, 1, 2, 0, 4, 1, 0]);
        assert_eq!(un_high_water_mark(&codes), indices);
    }

    #[test]
    fn oct_encoding_matches_cesium_and_round_trips_within_its_precision() {
        // +z is the octahedron's top: both components at the middle of the range.
        assert_eq!(oct_encode([0.0, 0.0, 1.0]), [128, 128]);
        assert_eq!(oct_encode([1.0, 0.0, 0.0]), [255, 128]);
        assert_eq!(oct_encode([0.0, -1.0, 0.0]), [128, 0]);
        // −z folds to a corner.
        assert_eq!(oct_encode([0.0, 0.0, -1.0]), [255, 255]);
        let mut worst = 0.0f64;
        for i in 0..2000 {
            let t = i as f64 * 0.7;
            let p = (i as f64 * 0.013).sin() * 1.5;
            let n = [t.cos() * p.cos(), t.sin() * p.cos(), p.sin()];
            let d = oct_decode(oct_encode(n));
            let dot = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
            worst = worst.max(dot.clamp(-1.0, 1.0).acos());
        }
        // 8 bits per component: under a degree everywhere.
        assert!(worst.to_degrees() < 1.0, "{}", worst.to_degrees());
    }
}
