//! Fast non-dominated sorting and crowding distance (Deb et al. 2002) on (E, T) pairs, both
//! minimised. Pure functions of the points, so they are tested on hand-made sets.

use crate::front::dominates;

/// The non-dominated fronts of `points`: `fronts[0]` holds the indices of the points no other
/// point dominates, `fronts[1]` those dominated only by points of `fronts[0]`, and so on. Each
/// front lists its indices in increasing order. Equal points share a front.
pub(crate) fn non_dominated_fronts(points: &[[f64; 2]]) -> Vec<Vec<usize>> {
    let n = points.len();
    let mut dominated_by_count = vec![0usize; n];
    let mut dominates_list: Vec<Vec<usize>> = vec![Vec::new(); n];
    for i in 0..n {
        for j in i + 1..n {
            if dominates(points[i], points[j]) {
                dominates_list[i].push(j);
                dominated_by_count[j] += 1;
            } else if dominates(points[j], points[i]) {
                dominates_list[j].push(i);
                dominated_by_count[i] += 1;
            }
        }
    }
    let mut fronts = Vec::new();
    let mut current: Vec<usize> = (0..n).filter(|&i| dominated_by_count[i] == 0).collect();
    while !current.is_empty() {
        let mut next = Vec::new();
        for &i in &current {
            for &j in &dominates_list[i] {
                dominated_by_count[j] -= 1;
                if dominated_by_count[j] == 0 {
                    next.push(j);
                }
            }
        }
        next.sort_unstable();
        fronts.push(std::mem::replace(&mut current, next));
    }
    fronts
}

/// The rank (0 = non-dominated) of every point.
#[cfg(test)]
pub(crate) fn ranks(points: &[[f64; 2]]) -> Vec<usize> {
    let mut rank = vec![0; points.len()];
    for (r, front) in non_dominated_fronts(points).iter().enumerate() {
        for &i in front {
            rank[i] = r;
        }
    }
    rank
}

/// The rank (0 = non-dominated) of every point and its crowding distance within its front.
pub(crate) fn ranks_and_crowding(points: &[[f64; 2]]) -> Vec<(usize, f64)> {
    let mut out = vec![(0, 0.0); points.len()];
    for (rank, front) in non_dominated_fronts(points).iter().enumerate() {
        for (&i, d) in front.iter().zip(crowding_distances(points, front)) {
            out[i] = (rank, d);
        }
    }
    out
}

/// (μ + λ) survival: the indices of the `mu` points kept, in the order they are taken. Whole
/// fronts (`fronts`, best rank first, as [`non_dominated_fronts`] gives them) are kept while they
/// fit; the front that does not fit keeps its members of largest crowding distance, ties going
/// to the earlier member of the front.
pub(crate) fn survivors(points: &[[f64; 2]], fronts: &[Vec<usize>], mu: usize) -> Vec<usize> {
    let mut kept = Vec::with_capacity(mu);
    for front in fronts {
        let room = mu - kept.len();
        if room == 0 {
            break;
        }
        if front.len() <= room {
            kept.extend_from_slice(front);
        } else {
            let d = crowding_distances(points, front);
            let mut order: Vec<usize> = (0..front.len()).collect();
            order.sort_by(|&a, &b| d[b].total_cmp(&d[a]).then(a.cmp(&b)));
            kept.extend(order[..room].iter().map(|&k| front[k]));
        }
    }
    kept
}

/// The crowding distance of each member of `front` (indices into `points`), in the order of
/// `front`: for each objective, the members are sorted by it (ties by position in `front`), the
/// two extremes get infinity and every other member adds the gap between its two neighbours,
/// divided by the objective's range over the front (nothing when the range is 0).
pub(crate) fn crowding_distances(points: &[[f64; 2]], front: &[usize]) -> Vec<f64> {
    let n = front.len();
    let mut distance = vec![0.0; n];
    if n <= 2 {
        return vec![f64::INFINITY; n];
    }
    let mut order: Vec<usize> = (0..n).collect();
    for m in [0, 1] {
        let value = |k: usize| points[front[k]][m];
        order.sort_by(|&a, &b| value(a).total_cmp(&value(b)).then(a.cmp(&b)));
        let (lo, hi) = (value(order[0]), value(order[n - 1]));
        distance[order[0]] = f64::INFINITY;
        distance[order[n - 1]] = f64::INFINITY;
        if hi > lo {
            for k in 1..n - 1 {
                distance[order[k]] += (value(order[k + 1]) - value(order[k - 1])) / (hi - lo);
            }
        }
    }
    distance
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fronts_of_a_hand_made_set() {
        // Three staircases: (1,5) (2,3) (4,1) | (3,4) (5,2) | (6,6); plus a copy of (2,3),
        // which is not dominated by its twin and so shares rank 0.
        let p = [
            [3.0, 4.0],
            [1.0, 5.0],
            [6.0, 6.0],
            [2.0, 3.0],
            [5.0, 2.0],
            [4.0, 1.0],
            [2.0, 3.0],
        ];
        assert_eq!(
            non_dominated_fronts(&p),
            vec![vec![1, 3, 5, 6], vec![0, 4], vec![2]]
        );
        assert_eq!(ranks(&p), vec![1, 0, 2, 0, 1, 0, 0]);
    }

    #[test]
    fn crowding_of_a_hand_made_front() {
        // Front (0,10) (1,6) (4,3) (10,0): ranges 10 and 10. Member (1,6): neighbours (0,10)
        // and (4,3) → (4−0)/10 + (10−3)/10 = 1.1; member (4,3): (10−1)/10 + (6−0)/10 = 1.5.
        let p = [[4.0, 3.0], [0.0, 10.0], [10.0, 0.0], [1.0, 6.0]];
        let d = crowding_distances(&p, &[0, 1, 2, 3]);
        assert!((d[0] - 1.5).abs() < 1e-12);
        assert!(d[1].is_infinite() && d[2].is_infinite());
        assert!((d[3] - 1.1).abs() < 1e-12);
        // Two or fewer members are all boundary points.
        assert_eq!(crowding_distances(&p, &[0, 3]), vec![f64::INFINITY; 2]);
    }

    #[test]
    fn survivors_take_whole_fronts_then_the_least_crowded() {
        // Front 1 is (0,10) (1,6) (4,3) (10,0), front 2 (2,9) (11,1). With μ = 5 front 1 fits
        // whole; of front 2 only one fits, and both of its members are extremes (crowding ∞),
        // so the earlier one, (2,9), is kept. With μ = 3, front 1 keeps its two extremes
        // (∞) and then (4,3), whose gap ((10−1)/10 + (6−0)/10) beats (1,6)'s (4/10 + 7/10).
        let points = [
            [0.0, 10.0],
            [2.0, 9.0],
            [1.0, 6.0],
            [4.0, 3.0],
            [11.0, 1.0],
            [10.0, 0.0],
        ];
        let fronts = non_dominated_fronts(&points);
        assert_eq!(survivors(&points, &fronts, 5), vec![0, 2, 3, 5, 1]);
        assert_eq!(survivors(&points, &fronts, 3), vec![0, 5, 3]);
        assert_eq!(survivors(&points, &fronts, 6).len(), 6);
    }
}
