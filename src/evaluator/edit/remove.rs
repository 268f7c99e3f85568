//! Removing kept points: one hole at a time, or a whole region at once.

use super::scratch::{EditScratch, INSIDE, REGION_POINTS_PER_REMOVAL};
use crate::evaluator::exact::predicates::{self, Lattice};
use crate::evaluator::mesh::canonical_triangulation::{NONE, edge_from, next};
use crate::evaluator::mesh::hole_fill as hole;
use crate::evaluator::mesh::state::MeshState;
use crate::heightfield::Heightfield;

impl MeshState {
    /// Removes the kept vertices `remove` (not corners) all at once: the union of their stars
    /// (the region) is the only part of the mesh that changes, since a removal never makes
    /// another triangle's circle non-empty. The new triangles there are those of the canonical
    /// triangulation of the region's remaining kept points (plus the grid corners, so that it can
    /// be built by insertion) that lie inside the region: every triangle of the edited mesh
    /// inside the region has an empty circle among all kept points, so among these too. They are
    /// found by a flood from the region's boundary edges. Returns false, changing nothing, when
    /// the region holds too many points for this to pay ([`REGION_POINTS_PER_REMOVAL`]).
    ///
    /// Why: an OAX child takes whole blocks from the other parent, so its removals are dense in
    /// a few blocks, where re-triangulating the block's survivors costs less than removing
    /// its points one hole at a time.
    pub(super) fn remove_region(
        &mut self,
        hf: &Heightfield,
        lattice: Lattice,
        remove: &[u32],
        scratch: &mut EditScratch,
    ) -> bool {
        // Nothing changes until every check has passed; only the last step rewrites the mesh.
        if !self.collect_region(lattice, remove, scratch)
            || !self.triangulate_region_points(hf, remove.len(), scratch)
            || !self.find_region_triangles(hf.len(), lattice, scratch)
        {
            return false;
        }
        self.replace_region(scratch);
        true
    }

    /// Lists the region, the union of the stars of `remove`, in `scratch.region` (marked in
    /// `scratch.in_region`), by rotating around each removed vertex from a triangle that has it.
    fn collect_region(&self, lattice: Lattice, remove: &[u32], scratch: &mut EditScratch) -> bool {
        let m = &self.mesh;
        scratch.in_region.clear();
        scratch.in_region.resize(m.len(), false);
        scratch.region.clear();
        for &v in remove {
            let t = self.locate(lattice, self.hint[v as usize], lattice.point(v));
            let Some(e) = m.leaving(t, v) else {
                return false;
            };
            for e in m.fan(e) {
                let slot = (e / 3) as usize;
                if !scratch.in_region[slot] {
                    scratch.in_region[slot] = true;
                    scratch.region.push(slot as u32);
                }
            }
        }
        true
    }

    /// Triangulates the region's remaining kept points (`kept` already says which are removed)
    /// and the corners into `scratch.sub`; false when they are more than pays for
    /// `removals` removals.
    fn triangulate_region_points(
        &self,
        hf: &Heightfield,
        removals: usize,
        scratch: &mut EditScratch,
    ) -> bool {
        let m = &self.mesh;
        // The marks are cleared again right after, so the buffer is only ever resized.
        scratch.listed.resize(hf.len(), false);
        scratch.region_points.clear();
        scratch.region_points.extend(hf.corners());
        for &c in &scratch.region_points {
            scratch.listed[c as usize] = true;
        }
        let limit = REGION_POINTS_PER_REMOVAL * removals + 4;
        for &slot in &scratch.region {
            for k in 0..3 {
                let v = m.vertices[3 * slot as usize + k];
                if self.kept[v as usize] && !scratch.listed[v as usize] {
                    scratch.listed[v as usize] = true;
                    scratch.region_points.push(v);
                }
            }
            if scratch.region_points.len() > limit {
                break;
            }
        }
        for &v in &scratch.region_points {
            scratch.listed[v as usize] = false;
        }
        if scratch.region_points.len() > limit {
            return false;
        }
        scratch.region_points.sort_unstable();
        scratch.sub.insert_all(hf.width(), &scratch.region_points)
    }

    /// Lists in `scratch.inside` the triangles of `scratch.sub` that lie inside the region, by a
    /// flood from its boundary edges (whose outer half-edges go to `scratch.across`), and checks
    /// that they cover exactly the region's area.
    fn find_region_triangles(&self, n: usize, lattice: Lattice, scratch: &mut EditScratch) -> bool {
        let m = &self.mesh;
        let sub = &scratch.sub;
        // Where each of sub's points has a half-edge leaving it.
        scratch.leaving.resize(n, NONE);
        for (e, &v) in sub.vertices.iter().enumerate() {
            scratch.leaving[v as usize] = e as u32;
        }
        // The region's boundary edges that face a triangle outside it: each is an edge of sub
        // with the region on its left, the same direction as in the mesh.
        scratch.across.clear();
        scratch.across.resize(sub.vertices.len(), INSIDE);
        scratch.taken.clear();
        scratch.taken.resize(sub.len(), NONE);
        scratch.inside.clear();
        for &slot in &scratch.region {
            for h in 3 * slot..3 * slot + 3 {
                let outer = m.twin[h as usize];
                if outer == NONE || scratch.in_region[(outer / 3) as usize] {
                    continue;
                }
                let (u, v) = (m.vertices[h as usize], m.vertices[next(h) as usize]);
                let Some(e) = edge_from(sub, scratch.leaving[u as usize], v) else {
                    return false;
                };
                scratch.across[e as usize] = outer;
                let t = e / 3;
                if scratch.taken[t as usize] == NONE {
                    scratch.taken[t as usize] = 0;
                    scratch.inside.push(t);
                }
            }
        }
        if scratch.inside.is_empty() {
            // The region is the whole mesh: every triangle of sub is inside.
            if scratch.region.len() != m.len() {
                return false;
            }
            scratch.inside.extend(0..sub.len() as u32);
        } else {
            // Flood from the triangles on the boundary, never across it.
            let (across, taken) = (&scratch.across, &mut scratch.taken);
            sub.flood(
                &mut scratch.inside,
                |e| across[e as usize] != INSIDE,
                |t| std::mem::replace(&mut taken[t as usize], 0) == NONE,
            );
        }
        // A guard on the reasoning above: the new triangles cover exactly the region's area.
        let area = |v: &[u32]| -> i64 {
            let [a, b, c] = [v[0], v[1], v[2]].map(|i| lattice.point(i));
            predicates::orient(a, b, c)
        };
        let old_area: i64 = scratch
            .region
            .iter()
            .map(|&t| area(&m.vertices[3 * t as usize..]))
            .sum();
        let new_area: i64 = scratch
            .inside
            .iter()
            .map(|&t| area(&sub.vertices[3 * t as usize..]))
            .sum();
        if old_area != new_area {
            debug_assert!(
                false,
                "a region's new triangles cover {new_area}, not {old_area}"
            );
            return false;
        }
        true
    }

    /// Rewrites the region with the triangles [`find_region_triangles`](Self::find_region_triangles)
    /// found: the region's slots take them, further ones are appended, left-over slots die.
    fn replace_region(&mut self, scratch: &mut EditScratch) {
        let m = &mut self.mesh;
        let sub = &scratch.sub;
        let mut slots = scratch.region.iter().copied();
        for &t in &scratch.inside {
            let slot = match slots.next() {
                Some(slot) => slot,
                None => {
                    m.vertices.extend_from_slice(&[NONE; 3]);
                    m.twin.extend_from_slice(&[NONE; 3]);
                    (m.len() - 1) as u32
                }
            };
            scratch.taken[t as usize] = slot;
            let base = 3 * slot as usize;
            m.vertices[base..base + 3]
                .copy_from_slice(&sub.vertices[3 * t as usize..3 * t as usize + 3]);
            scratch.touched.push(slot);
        }
        let live = scratch.taken[scratch.inside[0] as usize];
        for slot in slots {
            let base = 3 * slot as usize;
            m.vertices[base..base + 3].fill(NONE);
            m.twin[base..base + 3].fill(NONE);
            // Forwards a walk that starts here to a live triangle of the region.
            m.twin[base] = live;
            scratch.dead.push(slot);
        }
        for &t in &scratch.inside {
            let slot = scratch.taken[t as usize];
            for k in 0..3 {
                let e = 3 * t + k;
                let h = 3 * slot + k;
                let outer = scratch.across[e as usize];
                let twin = if outer != INSIDE {
                    outer
                } else {
                    let f = sub.twin[e as usize];
                    if f == NONE {
                        NONE
                    } else {
                        3 * scratch.taken[(f / 3) as usize] + f % 3
                    }
                };
                m.twin[h as usize] = twin;
                if twin != NONE {
                    m.twin[twin as usize] = h;
                }
            }
        }
    }

    /// Removes kept vertex `v` (not a corner): deletes its star and fills the hole with the
    /// Delaunay triangles of its boundary, in the star's slots; emptied slots go to
    /// `scratch.dead`.
    pub(super) fn remove_vertex(&mut self, lattice: Lattice, v: u32, scratch: &mut EditScratch) {
        let t = self.locate(lattice, self.hint[v as usize], lattice.point(v));
        let m = &mut self.mesh;
        let leaving = m
            .leaving(t, v)
            .expect("a kept point is a vertex of the triangle that holds it");
        m.star_of(
            leaving,
            &mut scratch.star,
            &mut scratch.boundary,
            &mut scratch.outer,
        );
        scratch.fill.clear();
        let filled = hole::fill(&scratch.boundary, lattice, &mut scratch.fill);
        assert!(filled, "the star of a Delaunay vertex has a Delaunay fill");
        let links = scratch.outer.len();
        let b = &scratch.boundary;
        for (j, &slot) in scratch.star.iter().enumerate() {
            let base = 3 * slot as usize;
            match scratch.fill.get(j) {
                Some(tri) => {
                    m.vertices[base..base + 3].copy_from_slice(tri);
                    scratch.touched.push(slot);
                }
                None => {
                    // Dead until compaction; its first twin forwards a walk that starts here to
                    // a live triangle of the same hole.
                    m.vertices[base..base + 3].fill(NONE);
                    m.twin[base..base + 3].fill(NONE);
                    m.twin[base] = scratch.star[0];
                    scratch.dead.push(slot);
                }
            }
        }
        // Link the new triangles: a boundary edge bᵢ → bᵢ₊₁ to the outer side of the hole (or
        // to nothing: the border segment that closes a border vertex's chain), a diagonal to
        // its reverse in another new triangle.
        let slots = &scratch.star[..scratch.fill.len()];
        let diagonals = &mut scratch.diagonals;
        diagonals.clear();
        for (j, &slot) in slots.iter().enumerate() {
            let at = scratch.fill[j].map(|v| {
                b.iter()
                    .position(|&x| x == v)
                    .expect("the fill's vertices are the boundary's")
            });
            for kk in 0..3 {
                let h = 3 * slot + kk as u32;
                let (from, to) = (at[kk], at[(kk + 1) % 3]);
                let successor = if from + 1 == b.len() { 0 } else { from + 1 };
                let twin = if to == successor {
                    if from < links {
                        scratch.outer[from]
                    } else {
                        NONE
                    }
                } else if let Some(q) = diagonals.iter().position(|d| (d.0, d.1) == (to, from)) {
                    diagonals.swap_remove(q).2
                } else {
                    diagonals.push((from, to, h));
                    continue;
                };
                m.twin[h as usize] = twin;
                if twin != NONE {
                    m.twin[twin as usize] = h;
                }
            }
        }
        debug_assert!(diagonals.is_empty(), "every diagonal has two sides");
    }

    /// Moves the last live triangles into the slots removals emptied, so slots are `0..T`
    /// again, and sets `scratch.dirty` for every slot whose triangle must be rasterised again
    /// (written or moved by this edit).
    pub(super) fn compact(&mut self, scratch: &mut EditScratch) {
        let m = &mut self.mesh;
        let dirty = &mut scratch.dirty;
        dirty.clear();
        dirty.resize(m.len(), false);
        for &s in &scratch.touched {
            dirty[s as usize] = true;
        }
        scratch.dead.sort_unstable();
        let mut len = m.len();
        for &d in &scratch.dead {
            while len > 0 && m.vertices[3 * (len - 1)] == NONE {
                len -= 1;
            }
            if d as usize >= len {
                break;
            }
            let from = len - 1;
            for k in 0..3 {
                let (src, dst) = (3 * from + k, 3 * d as usize + k);
                m.vertices[dst] = m.vertices[src];
                let tw = m.twin[src];
                m.twin[dst] = tw;
                if tw != NONE {
                    m.twin[tw as usize] = dst as u32;
                }
            }
            // A moved triangle keeps its errors but its points' hints name the old slot.
            dirty[d as usize] = true;
            len -= 1;
        }
        m.vertices.truncate(3 * len);
        m.twin.truncate(3 * len);
    }
}
