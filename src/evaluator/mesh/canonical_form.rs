//! Canonical forms of triangles and triangle lists, so that meshes made in different ways
//! compare (and rasterise) equal.

/// `tri` rotated so that its smallest grid index comes first (orientation kept): the
/// rotation every triangle is rasterised in, so its errors do not depend on how it was made.
#[inline]
pub(crate) fn canonical(tri: [u32; 3]) -> [u32; 3] {
    let [a, b, c] = tri;
    if a < b && a < c {
        tri
    } else if b < c {
        [b, c, a]
    } else {
        [c, a, b]
    }
}

/// `tris` as a sorted list of `canonical` triples (smallest index first): two triangulations are the same mesh
/// exactly when these lists are equal.
pub fn canonical_set(tris: &[[u32; 3]]) -> Vec<[u32; 3]> {
    // A counting sort by the first index, then each bucket by the other two: a triangle
    // starts at its smallest index, so a bucket holds about two triangles, and the buckets
    // cost less than a comparison sort of the whole list.
    let rotated: Vec<[u32; 3]> = tris.iter().map(|&t| canonical(t)).collect();
    let top = rotated.iter().map(|t| t[0] as usize).max().unwrap_or(0);
    if top > 4 * rotated.len() + 1024 {
        // Few triangles over a large range of indices: the buckets would cost more.
        let mut v = rotated;
        v.sort_unstable();
        return v;
    }
    let mut start = vec![0usize; top + 2];
    for t in &rotated {
        start[t[0] as usize + 1] += 1;
    }
    for i in 1..start.len() {
        start[i] += start[i - 1];
    }
    let mut next = start.clone();
    let mut sorted = vec![[0u32; 3]; rotated.len()];
    for t in rotated {
        let at = &mut next[t[0] as usize];
        sorted[*at] = t;
        *at += 1;
    }
    for w in start.windows(2) {
        if w[1] - w[0] > 1 {
            sorted[w[0]..w[1]].sort_unstable();
        }
    }
    sorted
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    #[test]
    fn canonical_rotation_starts_at_the_smallest_index_and_keeps_orientation() {
        // The three rotations of one counter-clockwise triangle map to the same triple.
        for tri in [[3, 9, 5], [9, 5, 3], [5, 3, 9]] {
            assert_eq!(canonical(tri), [3, 9, 5]);
        }
    }

    #[test]
    fn the_canonical_set_is_the_sorted_list_of_rotations() {
        // Random lists, with repeated first indices (buckets of several triangles), repeated
        // triangles, and indices spread far beyond the list's length (the comparison-sort path):
        // the result must equal the plain sort of the canonical rotations.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(4);
        for (len, range) in [(0, 10), (1, 5), (50, 20), (400, 300), (30, 1_000_000)] {
            let tris: Vec<[u32; 3]> = (0..len)
                .map(|_| {
                    let a = rng.random_range(0..range);
                    let t = [
                        a,
                        a + 1 + rng.random_range(0..9),
                        a + 10 + rng.random_range(0..9),
                    ];
                    let r = rng.random_range(0..3);
                    [t[r], t[(r + 1) % 3], t[(r + 2) % 3]]
                })
                .collect();
            let mut expected: Vec<[u32; 3]> = tris.iter().map(|&t| canonical(t)).collect();
            expected.sort_unstable();
            assert_eq!(canonical_set(&tris), expected, "{len} over {range}");
        }
    }
}
