//! Multiple-choice allocation: one option per tile, minimising the total error for each total
//! triangle count, as JPEG 2000's rate–distortion optimisation allocates bits to code blocks.
//!
//! Each tile offers options (E, T) that add up across tiles. The lower convex hull of the sums
//! is found exactly by the Lagrangian method: for a slope λ each tile takes its option of least
//! E + λT, so walking every tile's hull segments from the steepest to the flattest visits every
//! hull vertex of the sums, each an optimal allocation for its T. Between two hull vertices the
//! sums may have better points that no λ finds; the walk fills those gaps with the options that
//! lie between the stepping tile's two hull options.
//!
//! The same walk serves E_sum and RMS: RMS = sqrt(Σ squared errors / N) is increasing in the
//! sum of the tiles' squared-error shares, so allocating those shares minimises it. E_max does
//! not add up across tiles but is the largest tile's, so [`allocate_max`] instead takes every
//! tile's E_max as a bound and gives each tile its fewest-triangle option within it.

/// One tile's option: its share of the whole-grid error and its triangles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct TileOption {
    /// Error share.
    pub e: f64,
    /// Largest point error.
    pub e_max: f64,
    /// Triangles.
    pub t: u64,
}

/// One whole-grid allocation: an option per tile and its sums.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Allocation {
    /// Σ E over the tiles, added in tile order.
    pub e: f64,
    /// The largest E_max of the chosen options.
    pub e_max: f64,
    /// Σ T.
    pub t: u64,
    /// The option index chosen in each tile.
    pub choice: Vec<usize>,
}

/// The indices of `options`' non-dominated members by increasing T (decreasing E); the first
/// of equal (E, T) options wins.
pub(super) fn non_dominated(options: &[TileOption]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..options.len()).collect();
    order.sort_by(|&a, &b| {
        let (x, y) = (&options[a], &options[b]);
        x.t.cmp(&y.t).then(x.e.total_cmp(&y.e)).then(a.cmp(&b))
    });
    let mut out: Vec<usize> = Vec::new();
    for i in order {
        if out.last().is_none_or(|&j| options[i].e < options[j].e) {
            out.push(i);
        }
    }
    out
}

/// The lower convex hull of non-dominated points `front` (indices into `options`, by
/// increasing T): positions into `front`.
fn lower_hull(options: &[TileOption], front: &[usize]) -> Vec<usize> {
    let mut hull: Vec<usize> = Vec::new();
    let p = |k: usize| (options[front[k]].t as f64, options[front[k]].e);
    for k in 0..front.len() {
        while hull.len() >= 2 {
            let (a, b, c) = (p(hull[hull.len() - 2]), p(hull[hull.len() - 1]), p(k));
            // b is above or on the segment a–c: not a hull vertex.
            let cross = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
            if cross <= 0.0 {
                hull.pop();
            } else {
                break;
            }
        }
        hull.push(k);
    }
    hull
}

/// The sums of `choice` over `options`.
fn sums(options: &[Vec<TileOption>], choice: &[usize]) -> Allocation {
    let (mut e, mut e_max, mut t) = (0.0, 0.0f64, 0);
    for (tile, &c) in options.iter().zip(choice) {
        e += tile[c].e;
        e_max = e_max.max(tile[c].e_max);
        t += tile[c].t;
    }
    Allocation {
        e,
        e_max,
        t,
        choice: choice.to_vec(),
    }
}

/// For every bound that is some option's E_max, the allocation of fewest total T whose every
/// tile's E_max is at most the bound (of a tile's equal-T options within it, the one of least
/// E, then the first), non-dominated in (E_max, T), by increasing T: exactly the whole-grid
/// front in (E_max, T) over these options, since an allocation's E_max is one of its options'
/// and no allocation within a bound has fewer triangles than each tile's fewest within it.
/// Every tile needs at least one option; an empty list of tiles has none.
pub(super) fn allocate_max(options: &[Vec<TileOption>]) -> Vec<Allocation> {
    if options.is_empty() || options.iter().any(|o| o.is_empty()) {
        return Vec::new();
    }
    // Per tile, its options by increasing E_max with the running best (fewest T, then least
    // E, then first) among those up to each.
    let best_upto: Vec<(Vec<f64>, Vec<usize>)> = options
        .iter()
        .map(|tile| {
            let mut order: Vec<usize> = (0..tile.len()).collect();
            order.sort_by(|&a, &b| tile[a].e_max.total_cmp(&tile[b].e_max).then(a.cmp(&b)));
            let mut bounds = Vec::with_capacity(order.len());
            let mut best = Vec::with_capacity(order.len());
            let mut current: Option<usize> = None;
            for i in order {
                let better = current.is_none_or(|c| {
                    let (x, y) = (&tile[i], &tile[c]);
                    x.t < y.t || (x.t == y.t && x.e < y.e)
                });
                if better {
                    current = Some(i);
                }
                bounds.push(tile[i].e_max);
                best.push(current.expect("set on the first option"));
            }
            (bounds, best)
        })
        .collect();
    let mut limits: Vec<f64> = options.iter().flatten().map(|o| o.e_max).collect();
    limits.sort_by(f64::total_cmp);
    limits.dedup();
    let mut found = Vec::new();
    'bounds: for &bound in &limits {
        let mut choice = Vec::with_capacity(options.len());
        for (bounds, best) in &best_upto {
            let within = bounds.partition_point(|&e| e <= bound);
            if within == 0 {
                continue 'bounds;
            }
            choice.push(best[within - 1]);
        }
        found.push(sums(options, &choice));
    }
    // Non-dominated in (E_max, T): by increasing T, keep an allocation when its E_max is below
    // every kept one's.
    found.sort_by(|a, b| a.t.cmp(&b.t).then(a.e_max.total_cmp(&b.e_max)));
    let mut out: Vec<Allocation> = Vec::new();
    for a in found {
        if out.last().is_none_or(|l| a.e_max < l.e_max) {
            out.push(a);
        }
    }
    out
}

/// The non-dominated whole-grid allocations found by the hull walk and its gap filling, by
/// increasing T. Every tile needs at least one option; an empty list of tiles has none.
pub(super) fn allocate(options: &[Vec<TileOption>]) -> Vec<Allocation> {
    if options.is_empty() || options.iter().any(|o| o.is_empty()) {
        return Vec::new();
    }
    let fronts: Vec<Vec<usize>> = options.iter().map(|o| non_dominated(o)).collect();
    let hulls: Vec<Vec<usize>> = options
        .iter()
        .zip(&fronts)
        .map(|(o, f)| lower_hull(o, f))
        .collect();
    // Every hull segment of every tile: (slope, tile, segment number).
    let mut segments: Vec<(f64, usize, usize)> = Vec::new();
    for (tile, hull) in hulls.iter().enumerate() {
        let front = &fronts[tile];
        for s in 0..hull.len().saturating_sub(1) {
            let (a, b) = (
                &options[tile][front[hull[s]]],
                &options[tile][front[hull[s + 1]]],
            );
            segments.push(((b.e - a.e) / (b.t - a.t) as f64, tile, s));
        }
    }
    // Steepest descent first; a tile's own slopes increase along its hull, so its segments
    // keep their order.
    segments.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
    let mut at: Vec<usize> = vec![0; options.len()];
    let mut choice: Vec<usize> = fronts.iter().map(|f| f[0]).collect();
    let mut found = vec![sums(options, &choice)];
    for &(_, tile, s) in &segments {
        let (from, to) = (hulls[tile][s], hulls[tile][s + 1]);
        debug_assert_eq!(at[tile], s);
        for &between in &fronts[tile][from + 1..to] {
            choice[tile] = between;
            found.push(sums(options, &choice));
        }
        choice[tile] = fronts[tile][to];
        at[tile] = s + 1;
        found.push(sums(options, &choice));
    }
    let points: Vec<TileOption> = found
        .iter()
        .map(|a| TileOption {
            e: a.e,
            e_max: a.e_max,
            t: a.t,
        })
        .collect();
    let keep = non_dominated(&points);
    let mut taken: Vec<Option<Allocation>> = found.into_iter().map(Some).collect();
    keep.into_iter()
        .map(|i| {
            taken[i]
                .take()
                .expect("each allocation is kept at most once")
        })
        .collect()
}
