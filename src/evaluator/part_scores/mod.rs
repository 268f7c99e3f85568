//! Scoring the children of one orthogonal-array crossover without building their meshes.
//!
//! A crossover's children take each part (block) of the grid whole from parent A or B
//! ([`PartClasses`]). [`compose_parts`](crate::evaluator::Evaluator::compose_parts) builds such a child's
//! mesh from the triangles it reuses and the region R they leave uncovered; but factor analysis
//! needs only the children's scores, and only two of a crossover's children go on. Here a child
//! is scored from what its crossover's children share, found once per crossover
//! ([`PartScores::prepare`]):
//!
//! - **Classes.** Whether a parent's triangle is reused depends only on its *class*: the parent,
//!   the part of its smallest vertex and its kill mask. The error totals of each class are
//!   summed once, so the reused triangles' share of a child's score is a sum over classes.
//! - **Candidate edges.** R's boundary is made of edges between a reused triangle and one that
//!   is not, so only edges between triangles of different classes can be on it.
//! - **Variable points.** A child's point lies inside R only if none of its triangles is reused,
//!   which a point whose triangles all have its own part's plain class (reused whenever the
//!   point is in the child) never is.
//!
//! - **Level sets.** With at most 7 parts (an L8 array's factors, OAX's default) a crossover has
//!   at most 128 children, and whether a class is reused, a variable point is in R or a
//!   candidate edge is on R's boundary is, for each, a set of children (`LevelSet`, 128 bits)
//!   made once; a child tests a bit per variable point and candidate edge. With more parts a
//!   child finds them from the reused triangles near the blocks' edges.
//!
//! Then a child costs a pass over the candidate edges and variable points, the tiling of R
//! ([`Region::wrap`]), and the raster of R's triangles: the same triangles as `compose_parts`,
//! each with the same error bits, so the score is bit for bit the same as the composed (and
//! the fresh) one. Level sets make a child's pass several times cheaper, and a crossover, which
//! has 7 children or more, prepares them in the pass that finds the candidate edges.

use crate::evaluator::compose::{Crossing, PartClasses, counted_in, next_stamp, overlap};
use crate::evaluator::exact::fixed_point::{ErrorTotals, ErrorUnits};
use crate::evaluator::mesh::canonical_form::canonical;
use crate::evaluator::mesh::canonical_triangulation::{NONE, edge_from, next};
use crate::evaluator::mesh::state::MeshState;
use crate::evaluator::score::Score;

mod changes;
mod shared;

pub(crate) use changes::score_mutant;
pub(crate) use shared::Changes;
pub use shared::PartScores;
pub(crate) use shared::RowScratch;
use shared::{
    Candidate, Class, LABELLED, LEVEL_SET_PARTS, LevelSet, SPECIAL_SLOTS, UNKNOWN, bit_of,
    class_of, cross_twin, on_grid_border, score_from_scratch, score_of, special_slot,
};

impl PartScores {
    /// Was this made from the classification of `crossing`, for its parents as they are now?
    pub(crate) fn is_for(&self, crossing: Crossing<'_>) -> bool {
        let id = crossing.classes.id;
        self.made_from == id && id != 0 && crossing.classes_fit()
    }

    /// Prepares the children of `crossing` to be scored by `score` (through
    /// `Evaluator::score_parts`). False (and unusable) when its classification is not for its
    /// parents.
    pub fn prepare(&mut self, crossing: Crossing<'_>) -> bool {
        let Crossing {
            hf,
            parents,
            classes,
        } = crossing;
        let [a, b] = parents;
        self.made_from = 0;
        let ready = |s: &MeshState| s.lookup_valid && s.sat_valid;
        if !crossing.classes_fit() || classes.part.len() != hf.len() || !ready(a) || !ready(b) {
            return false;
        }
        self.units = ErrorUnits::of(hf);
        let plain = self.add_plain_classes(classes);
        self.find_variable_points(crossing, plain);
        self.find_candidate_edges(crossing);
        self.resolve_crossing_edges(crossing);
        if classes.rects.len() <= LEVEL_SET_PARTS {
            self.find_r_points(classes);
        }
        self.count_kept_per_part(crossing);
        self.made_from = classes.id;
        true
    }

    /// Starts the classes with the plain ones (an empty kill mask: the triangles a part's label
    /// alone decides), summed by the classification; returns how many there are.
    fn add_plain_classes(&mut self, classes: &PartClasses) -> usize {
        self.classes.clear();
        for (side, plain) in classes.plain.iter().enumerate() {
            for (home, &(totals, count)) in plain.iter().enumerate() {
                self.classes.push(Class {
                    side: side as u8,
                    home: home as u8,
                    kill: 0,
                    totals,
                    count,
                });
            }
        }
        self.classes.len()
    }

    /// The other classes, only among the triangles near a block's edge, with their totals;
    /// and the variable points: the vertices of a triangle whose class is not its own part's
    /// plain one, which is near a block's edge.
    fn find_variable_points(&mut self, crossing: Crossing<'_>, plain: usize) {
        let Crossing {
            hf,
            parents,
            classes,
        } = crossing;
        let n = hf.len();
        let part = &classes.part[..n];
        let parts = classes.rects.len();
        if parts <= LEVEL_SET_PARTS {
            self.special_index.resize(SPECIAL_SLOTS, NONE);
        }
        for (side, parent) in parents.into_iter().enumerate() {
            let (first, kill) = (&classes.first[side], &classes.kill[side]);
            let vertices = &parent.mesh.vertices;
            self.special[side].resize(first.len(), 0);
            let is_variable = &mut self.is_variable[side];
            is_variable.clear();
            is_variable.resize(n.div_ceil(64), 0);
            let variable = &mut self.variable[side];
            variable.clear();
            for &t in classes.near(side) {
                let t = t as usize;
                let (home, k) = (first[t], kill[t]);
                let tri = &vertices[3 * t..3 * t + 3];
                if k != 0 {
                    // By the table with few parts, else by a linear search (they are few).
                    let slot = (parts <= LEVEL_SET_PARTS).then(|| special_slot(side, home, k));
                    let found = match slot {
                        Some(i) => Some(self.special_index[i])
                            .filter(|&c| c != NONE)
                            .map(|c| c as usize - plain),
                        None => self.classes[plain..]
                            .iter()
                            .position(|c| c.side == side as u8 && c.home == home && c.kill == k),
                    };
                    let c = match found {
                        Some(i) => plain + i,
                        None => {
                            if let Some(i) = slot {
                                self.special_index[i] = self.classes.len() as u32;
                            }
                            self.classes.push(Class {
                                side: side as u8,
                                home,
                                kill: k,
                                totals: ErrorTotals::default(),
                                count: 0,
                            });
                            self.classes.len() - 1
                        }
                    };
                    let class = &mut self.classes[c];
                    class.count += 1;
                    class.totals.add(&parent.totals[t]);
                    self.special[side][t] = c as u32;
                }
                if k != 0 || tri.iter().any(|&v| part[v as usize] != home) {
                    for &v in tri {
                        let (word, bit) = ((v / 64) as usize, 1 << (v % 64));
                        if is_variable[word] & bit == 0 {
                            is_variable[word] |= bit;
                            variable.push(v);
                        }
                    }
                }
            }
        }
        if parts <= LEVEL_SET_PARTS {
            for c in &self.classes[plain..] {
                self.special_index[special_slot(c.side.into(), c.home, c.kill)] = NONE;
            }
        }
    }

    /// Coverage: the triangles with a vertex variable in either parent. Candidate edges are
    /// among their edges: two neighbours of different classes have a variable vertex in common
    /// (a kill mask makes all three vertices variable; different home parts make a shared
    /// vertex variable for at least one of them, being outside its home part). With level
    /// sets, each such triangle marks the children that reuse it on its vertices, and each
    /// candidate edge is kept with the children on whose R boundary it lies, in the same pass.
    fn find_candidate_edges(&mut self, crossing: Crossing<'_>) {
        let Crossing {
            hf,
            parents,
            classes,
        } = crossing;
        let n = hf.len();
        let [va, vb] = &self.is_variable;
        self.either.clear();
        self.either.extend(va.iter().zip(vb).map(|(a, b)| a | b));
        let level_sets = classes.rects.len() <= LEVEL_SET_PARTS;
        self.candidates.clear();
        self.r_points.clear();
        self.r_edges.clear();
        self.crossing.clear();
        if level_sets {
            self.class_levels.clear();
            self.class_levels
                .extend(self.classes.iter().map(Class::levels));
            self.reused_by.resize(n, LevelSet::default());
            for p in self.variable.iter().flatten() {
                self.reused_by[*p as usize] = LevelSet::default();
            }
        }
        for (side, parent) in parents.into_iter().enumerate() {
            self.coverage[side].clear();
            let len = self.find_covering(parent);
            if level_sets {
                self.stage_boundary_edges(side, crossing, len);
            } else {
                self.collect_candidates(side, crossing, len);
            }
        }
    }

    /// Lists in `covering` the triangles of `parent` with a vertex variable in either parent;
    /// returns how many.
    fn find_covering(&mut self, parent: &MeshState) -> usize {
        let m = &parent.mesh;
        // Without branches (a quarter of the triangles, in no order the slots follow).
        let variable = |v: u32| bit_of(&self.either, v);
        // Written up to its length, so only grown (a clear would fill it again per parent
        // per crossover).
        let covering = &mut self.covering;
        if covering.len() < m.len() {
            covering.resize(m.len(), 0);
        }
        let mut len = 0;
        for (t, tri) in m.vertices.chunks_exact(3).enumerate() {
            covering[len] = t as u32;
            len += variable(tri[0]) | variable(tri[1]) | variable(tri[2]);
        }
        len
    }

    /// With level sets: each covering triangle of parent `side` marks the children that reuse
    /// it on its vertices, and stages each edge with the children that reuse it but not the
    /// triangle across (none across the grid border: the triangle itself stands in); the
    /// staged edges go to `r_edges`, or to `crossing` when the other parent may have them.
    fn stage_boundary_edges(&mut self, side: usize, crossing: Crossing<'_>, covering_len: usize) {
        let Crossing {
            parents, classes, ..
        } = crossing;
        let m = &parents[side].mesh;
        let covering = &self.covering[..covering_len];
        // Without branches: the classes of neighbours near a block's edge follow no pattern.
        let cl = &self.class_levels;
        let staged = &mut self.staged;
        if staged.len() < 3 * covering.len() {
            staged.resize(3 * covering.len(), (0, LevelSet::default()));
        }
        let mut len = 0;
        for &t in covering.iter() {
            let t = t as usize;
            let class = class_of(classes, &self.special, side, t);
            let set = cl[class as usize];
            for v in m.triangle(t) {
                let r = &mut self.reused_by[v as usize];
                *r = r.or(set);
            }
            for (k, &g) in m.twin[3 * t..3 * t + 3].iter().enumerate() {
                let across = if g == NONE { t } else { (g / 3) as usize };
                let twin_class = class_of(classes, &self.special, side, across);
                let on_boundary = set.and_not(cl[twin_class as usize]);
                staged[len] = ((3 * t + k) as u32, on_boundary);
                len += usize::from(!on_boundary.is_empty());
            }
        }
        // The staged edges lie on the R boundary of the children that reuse this triangle but
        // neither the one across nor the other parent's triangle across the edge.
        let other = parents[1 - side];
        for &(edge, set) in &staged[..len] {
            let (u, v) = (m.vertices[edge as usize], m.vertices[next(edge) as usize]);
            if other.kept[u as usize] && other.kept[v as usize] {
                // The other parent may have the edge: looked up later.
                self.crossing.push((side as u8, u, v, set));
            } else {
                self.r_edges.push((u, v, set));
            }
        }
    }

    /// Without level sets: the covering triangles of parent `side` with their classes, and
    /// the edges between triangles of different classes as candidates.
    fn collect_candidates(&mut self, side: usize, crossing: Crossing<'_>, covering_len: usize) {
        let classes = crossing.classes;
        let m = &crossing.parents[side].mesh;
        let coverage = &mut self.coverage[side];
        for &t in &self.covering[..covering_len] {
            let t = t as usize;
            let class = class_of(classes, &self.special, side, t);
            coverage.push((t as u32, class));
            for (k, &g) in m.twin[3 * t..3 * t + 3].iter().enumerate() {
                if g == NONE {
                    continue;
                }
                let twin_class = class_of(classes, &self.special, side, (g / 3) as usize);
                if twin_class != class {
                    self.candidates.push(Candidate {
                        side: side as u8,
                        edge: (3 * t + k) as u32,
                        class,
                        twin_class,
                        cross: UNKNOWN,
                        cross_class: 0,
                    });
                }
            }
        }
    }

    /// The other parent's triangles across the staged edges it may have, found by a walk
    /// around an endpoint variable in either parent (all its triangles there have just been
    /// read, where a walk from the other endpoint would read cold memory); the edges still on
    /// some child's R boundary go to `r_edges`.
    fn resolve_crossing_edges(&mut self, crossing: Crossing<'_>) {
        let Crossing {
            parents, classes, ..
        } = crossing;
        for &(side, u, v, set) in &self.crossing {
            let side = usize::from(side);
            let other = parents[1 - side];
            let m = &other.mesh;
            let cross = if bit_of(&self.either, v) != 0 {
                cross_twin(other, u, v)
            } else {
                m.leaving(other.hint[u as usize], u)
                    .and_then(|e| edge_from(m, e, v))
                    .map_or(NONE, |e| m.twin[e as usize])
            };
            let mut set = set;
            if cross != NONE {
                let across = class_of(classes, &self.special, 1 - side, (cross / 3) as usize);
                set = set.and_not(self.class_levels[across as usize]);
            }
            if !set.is_empty() {
                self.r_edges.push((u, v, set));
            }
        }
    }

    /// With level sets: a variable point is in the R of the children that take it from its
    /// parent and reuse none of its triangles (all of which are in the coverage).
    fn find_r_points(&mut self, classes: &PartClasses) {
        for (side, variable) in self.variable.iter().enumerate() {
            for &p in variable {
                let part = usize::from(classes.part[p as usize]);
                let set = LABELLED[part][side].and_not(self.reused_by[p as usize]);
                if !set.is_empty() {
                    self.r_points.push((p, set));
                }
            }
        }
    }

    /// Kept points per part, and those on the grid border, for Euler's count: from each
    /// parent's summed-area table.
    fn count_kept_per_part(&mut self, crossing: Crossing<'_>) {
        let Crossing {
            hf,
            parents,
            classes,
        } = crossing;
        let (w, h) = (hf.width(), hf.height());
        for (side, parent) in parents.into_iter().enumerate() {
            let count = |r: [usize; 4]| counted_in(&parent.kept_sat, w, r);
            let counts = &mut self.counts[side];
            counts.clear();
            counts.extend(classes.rects.iter().map(|&r| {
                // The border: the bottom and top rows, and the side columns between them.
                let border = [
                    [0, 0, w, 1],
                    [0, h - 1, w, h],
                    [0, 1, 1, h - 1],
                    [w - 1, 1, w, h - 1],
                ];
                let on_border = border.iter().map(|&b| count(overlap(r, b))).sum::<u32>();
                (count(r), on_border)
            }));
        }
    }

    /// The score of the child of `crossing` that takes part `p` from B where bit `p` of
    /// `levels` is set and from A elsewhere: bit for bit what
    /// [`compose_parts`](crate::evaluator::Evaluator::compose_parts) (and a fresh evaluation)
    /// gives, without building the child's mesh. `None` when this was not prepared for the
    /// crossing's parents as they are now, or when a guard fails (the caller then scores the
    /// child another way).
    pub(crate) fn score(
        &mut self,
        crossing: Crossing<'_>,
        levels: u32,
        scratch: &mut RowScratch,
    ) -> Option<Score> {
        self.score_changed(crossing, levels, Changes::default(), scratch)
    }

    /// [`score`](Self::score) for that child with `changes` made to its kept points (a mutant
    /// of it): bit for bit a fresh evaluation of the changed set, still without a mesh. The
    /// reused triangles that a removed point is a vertex of, or whose circle an inserted point
    /// is inside, join R. `None` also when a removed point is not the child's or an inserted
    /// one is.
    #[allow(clippy::needless_range_loop)] // a side indexes the parents and several tables at once
    pub(crate) fn score_changed(
        &mut self,
        crossing: Crossing<'_>,
        levels: u32,
        changes: Changes<'_>,
        scratch: &mut RowScratch,
    ) -> Option<Score> {
        if !self.is_for(crossing) {
            return None;
        }
        let Crossing { hf, classes, .. } = crossing;
        let changed = !changes.removed.is_empty() || !changes.inserted.is_empty();
        let n = hf.len();
        let (mut totals, mut taken_count) = self.reused_totals(classes, levels, scratch);
        if taken_count == 0 {
            // Nothing to reuse (say, a corners-only parent whose corner 0 is labelled for the
            // other): the child is scored from scratch.
            return Some(self.fresh(crossing, levels, changes, scratch));
        }
        let expected = self.euler_count(crossing, levels, changes)?;
        scratch.listed.resize(n, false);
        scratch.points.clear();
        scratch.open.clear();
        if classes.rects.len() <= LEVEL_SET_PARTS {
            self.r_by_level_sets(levels, scratch);
        } else {
            self.r_by_search(crossing, levels, scratch);
        }
        if changed {
            self.change(crossing, changes, scratch, &mut totals, &mut taken_count)?;
            if taken_count == 0 {
                // The changes dropped every reused triangle (a sparse child on a small grid).
                for &p in &scratch.points {
                    scratch.listed[p as usize] = false;
                }
                return Some(self.fresh(crossing, levels, changes, scratch));
            }
        }
        for &p in &scratch.points {
            scratch.listed[p as usize] = false;
        }
        if scratch.open.is_empty() {
            // Nothing is new: the parents' triangles tile the grid (or the guard fails).
            return (taken_count == expected && scratch.points.is_empty())
                .then(|| score_of(self.units, &totals, taken_count, n));
        }
        add_region_totals(crossing, scratch, taken_count, expected, &mut totals)?;
        Some(score_of(self.units, &totals, expected, n))
    }

    /// Marks in `scratch.taken` the classes the child with `levels` reuses; returns their
    /// summed totals and their number of triangles.
    fn reused_totals(
        &self,
        classes: &PartClasses,
        levels: u32,
        scratch: &mut RowScratch,
    ) -> (ErrorTotals, u32) {
        let all = u32::MAX >> (32 - classes.rects.len());
        // The parts labelled for the other parent, by side.
        let other = [levels & all, !levels & all];
        let label = |part: u8| ((levels >> part) & 1) as u8;
        let mut totals = ErrorTotals::default();
        let mut taken_count = 0u32;
        scratch.taken.clear();
        for c in &self.classes {
            let take = label(c.home) == c.side && c.kill & other[c.side as usize] == 0;
            scratch.taken.push(take);
            if take {
                totals.add(&c.totals);
                taken_count += c.count;
            }
        }
        (totals, taken_count)
    }

    /// Euler's count of the triangles of the child with `levels` and `changes`: 2V − B − 2.
    /// `None` when a removed point is not the child's or an inserted one is.
    fn euler_count(
        &self,
        crossing: Crossing<'_>,
        levels: u32,
        changes: Changes<'_>,
    ) -> Option<u32> {
        let Crossing {
            hf,
            parents,
            classes,
        } = crossing;
        let label = |part: u8| ((levels >> part) & 1) as u8;
        let (mut vertices, mut on_border) = (0u32, 0u32);
        for p in 0..classes.rects.len() {
            let (k, border) = self.counts[usize::from(label(p as u8))][p];
            vertices += k;
            on_border += border;
        }
        let kept = |p: u32| parents[usize::from(label(classes.part[p as usize]))].kept[p as usize];
        let on_edge = |p: u32| u32::from(on_grid_border(hf, p));
        for &p in changes.removed {
            if !kept(p) {
                return None;
            }
            vertices -= 1;
            on_border -= on_edge(p);
        }
        for &p in changes.inserted {
            if kept(p) {
                return None;
            }
            vertices += 1;
            on_border += on_edge(p);
        }
        (2 * vertices).checked_sub(on_border + 2)
    }
}

/// Tiles R (its points and boundary edges in `scratch`) and adds its triangles' totals, through
/// the memo, to `totals`; `None` when R's triangles do not complete the `expected` count.
fn add_region_totals(
    crossing: Crossing<'_>,
    scratch: &mut RowScratch,
    taken_count: u32,
    expected: u32,
    totals: &mut ErrorTotals,
) -> Option<()> {
    let Crossing {
        hf,
        parents: [a, _],
        ..
    } = crossing;
    let region = &mut scratch.region;
    region.wrap(hf.width(), hf.height(), &scratch.points, &scratch.open)?;
    scratch.memo.prepare(
        a.hf.as_ref()
            .filter(|f| std::ptr::eq(f.as_ref(), hf.as_ref())),
    );
    if taken_count + region.triangles.len() as u32 != expected {
        debug_assert!(false, "R's triangles do not complete the child");
        return None;
    }
    // R's triangles, each in the canonical rotation every triangle is rasterised in.
    let tris = region.triangles.iter().map(|&t| ((), canonical(t)));
    scratch
        .memo
        .sum_triangles(hf, tris, &mut scratch.unknown, |_, t| totals.add(&t));
    Some(())
}

impl PartScores {
    /// R's points and boundary edges of the child with `levels`, read off the level sets
    /// (made by `prepare` when there are at most [`LEVEL_SET_PARTS`] parts).
    fn r_by_level_sets(&self, levels: u32, scratch: &mut RowScratch) {
        for &(p, set) in &self.r_points {
            if set.has(levels) {
                scratch.listed[p as usize] = true;
                scratch.points.push(p);
            }
        }
        for &(u, v, set) in &self.r_edges {
            if set.has(levels) {
                scratch.open.push((0, u, v));
                for p in [u, v] {
                    if !std::mem::replace(&mut scratch.listed[p as usize], true) {
                        scratch.points.push(p);
                    }
                }
            }
        }
    }

    /// R's points and boundary edges of the child with `levels`, found from the reused
    /// triangles near the blocks' edges, the variable points and the candidate edges.
    #[allow(clippy::needless_range_loop)] // a side indexes the parents and several tables at once
    fn r_by_search(&mut self, crossing: Crossing<'_>, levels: u32, scratch: &mut RowScratch) {
        let Crossing {
            hf,
            parents,
            classes,
        } = crossing;
        let n = hf.len();
        let label = |part: u8| ((levels >> part) & 1) as u8;
        let taken = &scratch.taken;
        // The child's points that a reused triangle has.
        let stamp = next_stamp(&mut scratch.stamp, &mut scratch.covered, n);
        for side in 0..2 {
            let m = &parents[side].mesh;
            for &(t, class) in &self.coverage[side] {
                if taken[class as usize] {
                    for v in m.triangle(t as usize) {
                        scratch.covered[v as usize] = stamp;
                    }
                }
            }
        }
        // R's points: the child's variable points no reused triangle has, and the ends of R's
        // boundary edges.
        for side in 0..2 {
            for &p in &self.variable[side] {
                let p = p as usize;
                if usize::from(label(classes.part[p])) == side
                    && scratch.covered[p] != stamp
                    && !std::mem::replace(&mut scratch.listed[p], true)
                {
                    scratch.points.push(p as u32);
                }
            }
        }
        for cand in &mut self.candidates {
            let side = cand.side as usize;
            let m = &parents[side].mesh;
            let e = cand.edge;
            if !taken[cand.class as usize] || taken[cand.twin_class as usize] {
                continue;
            }
            let (u, v) = (m.vertices[e as usize], m.vertices[next(e) as usize]);
            if cand.cross == UNKNOWN {
                cand.cross = cross_twin(parents[1 - side], u, v);
                if cand.cross != NONE {
                    let t = (cand.cross / 3) as usize;
                    cand.cross_class = class_of(classes, &self.special, 1 - side, t);
                }
            }
            if cand.cross != NONE && taken[cand.cross_class as usize] {
                continue;
            }
            scratch.open.push((0, u, v));
            for p in [u, v] {
                if !std::mem::replace(&mut scratch.listed[p as usize], true) {
                    scratch.points.push(p);
                }
            }
        }
    }

    /// The child's score, with `changes` made, from its canonical triangulation built from
    /// scratch.
    fn fresh(
        &self,
        crossing: Crossing<'_>,
        levels: u32,
        changes: Changes<'_>,
        scratch: &mut RowScratch,
    ) -> Score {
        let Crossing {
            hf,
            parents,
            classes,
        } = crossing;
        scratch.points.clear();
        for (i, &part) in classes.part.iter().enumerate() {
            if parents[((levels >> part) & 1) as usize].kept[i] {
                scratch.points.push(i as u32);
            }
        }
        if !changes.removed.is_empty() || !changes.inserted.is_empty() {
            scratch.points.retain(|p| !changes.removed.contains(p));
            scratch.points.extend_from_slice(changes.inserted);
            scratch.points.sort_unstable();
        }
        score_from_scratch(hf, self.units, &scratch.points, &mut scratch.sub)
    }
}
