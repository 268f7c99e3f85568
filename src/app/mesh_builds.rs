//! Meshes of a tiled run's members built off the page's thread: the page asks for the drawn
//! member's mesh ([`MeshBuilds::request`]), a Web Worker that holds the grid triangulates its
//! tile parts ([`crate::tiling::mesh_of_parts`]) and posts the mesh back, and the page draws it
//! if no newer request came in the meantime ([`MeshBuilds::finish`]). The page stays free while
//! the mesh is built, and the worker's result is the same bits the page would compute.

use crate::front::Solution;
use crate::tiling::TileBorders;
use crate::tiling::{TilePart, TilePlan};
use serde::{Deserialize, Serialize};

/// One mesh to build: the member to draw, with its tiles' parts.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct MeshJob {
    /// Identifies the request (a result of an older one is stale).
    pub id: u64,
    /// The member whose mesh is built (the drawn one: the selection, or the coarser member
    /// that stands in for it).
    pub member: Solution,
    /// How the grid is cut.
    pub plan: TilePlan,
    /// One part per tile, in tile order.
    pub parts: Vec<TilePart>,
}

/// A tile part without its kept set, which travels in [`MeshJobParts::kept`].
#[derive(Serialize, Deserialize)]
struct PartHeader {
    tile: usize,
    level: u8,
    borders: TileBorders,
}

/// The plan and the parts' headers, as JSON.
#[derive(Serialize, Deserialize)]
struct JobHeader {
    plan: TilePlan,
    parts: Vec<PartHeader>,
}

/// A [`MeshJob`]'s plan and parts packed for a worker: the small part as JSON, the kept sets
/// as one flat array (a transferable typed array on the way, so a member of millions of points
/// costs no parsing).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct MeshJobParts {
    /// The plan and each part's tile, level and borders, as JSON.
    pub header: String,
    /// Every part's kept set, one after another.
    pub kept: Vec<u32>,
    /// Where each part's kept set starts in `kept`, with the end as a last entry.
    pub offsets: Vec<u32>,
}

impl MeshJobParts {
    /// Packs `plan` and `parts`.
    pub(crate) fn of(plan: &TilePlan, parts: &[TilePart]) -> Result<Self, String> {
        let header = JobHeader {
            plan: plan.clone(),
            parts: parts
                .iter()
                .map(|p| PartHeader {
                    tile: p.tile,
                    level: p.level,
                    borders: p.borders.clone(),
                })
                .collect(),
        };
        let mut kept = Vec::with_capacity(parts.iter().map(|p| p.kept.len()).sum());
        let mut offsets = Vec::with_capacity(parts.len() + 1);
        offsets.push(0);
        for p in parts {
            kept.extend_from_slice(&p.kept);
            offsets.push(u32::try_from(kept.len()).map_err(|_| "a member too large to pack")?);
        }
        Ok(Self {
            header: serde_json::to_string(&header).map_err(|e| e.to_string())?,
            kept,
            offsets,
        })
    }

    /// Unpacks the plan and the parts, checking that the arrays fit the header: they come from
    /// another thread.
    pub(crate) fn unpack(self) -> Result<(TilePlan, Vec<TilePart>), String> {
        let header: JobHeader = serde_json::from_str(&self.header)
            .map_err(|e| format!("a mesh job with a bad header: {e}"))?;
        let n = header.parts.len();
        if self.offsets.len() != n + 1
            || self.offsets.first() != Some(&0)
            || self.offsets.last().map(|&o| o as usize) != Some(self.kept.len())
            || self.offsets.windows(2).any(|w| w[0] > w[1])
        {
            return Err("a mesh job whose arrays do not fit its header".to_string());
        }
        let parts = header
            .parts
            .into_iter()
            .enumerate()
            .map(|(i, h)| TilePart {
                tile: h.tile,
                level: h.level,
                borders: h.borders,
                kept: self.kept[self.offsets[i] as usize..self.offsets[i + 1] as usize].to_vec(),
            })
            .collect();
        Ok((header.plan, parts))
    }
}

/// The page's side of the mesh worker: the latest request, whether it was handed out, and
/// whether the worker holds the current grid.
#[derive(Debug, Default)]
pub(crate) struct MeshBuilds {
    next_id: u64,
    /// The request whose result the page waits for.
    wanted: Option<(u64, Solution)>,
    /// The request not yet handed to the worker (a newer one replaces it).
    pending: Option<MeshJob>,
    /// The worker holds the current surface's grid.
    grid_sent: bool,
}

impl MeshBuilds {
    /// Asks for the mesh of `member` from its `parts` on `plan`; any earlier request is
    /// superseded (its result, when it comes, is dropped). Returns the request's id.
    pub(crate) fn request(
        &mut self,
        member: Solution,
        plan: TilePlan,
        parts: Vec<TilePart>,
    ) -> u64 {
        self.next_id += 1;
        let id = self.next_id;
        self.wanted = Some((id, member.clone()));
        self.pending = Some(MeshJob {
            id,
            member,
            plan,
            parts,
        });
        id
    }

    /// The request to hand to the worker, once; `None` when there is none new.
    pub(crate) fn take(&mut self) -> Option<MeshJob> {
        self.pending.take()
    }

    /// The member whose mesh is being built, if any.
    pub(crate) fn building(&self) -> Option<&Solution> {
        self.wanted.as_ref().map(|(_, m)| m)
    }

    /// A result for request `id` came: the member it was built for when it is the latest
    /// request (which then ends), `None` for a stale one.
    pub(crate) fn finish(&mut self, id: u64) -> Option<Solution> {
        match &self.wanted {
            Some((wanted, _)) if *wanted == id => self.wanted.take().map(|(_, m)| m),
            _ => None,
        }
    }

    /// Drops every request (another surface, another run, nothing selected).
    pub(crate) fn cancel(&mut self) {
        self.wanted = None;
        self.pending = None;
    }

    /// Whether the worker must be sent the grid with the next job (it has not got this
    /// surface's yet); marks it sent.
    pub(crate) fn send_grid(&mut self) -> bool {
        !std::mem::replace(&mut self.grid_sent, true)
    }

    /// The surface changed, or the worker was lost: the next job carries the grid again.
    pub(crate) fn grid_lost(&mut self) {
        self.grid_sent = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::Heightfield;
    use crate::tiling::{TilingError, assemble, mesh_of_parts, run_tile};

    fn member(t: usize) -> Solution {
        Solution::recorded(t as f64, 1.0, t, Vec::new())
    }

    #[test]
    fn a_newer_request_supersedes_an_older_one() {
        let plan = TilePlan::new(70, 40, 36).unwrap();
        let mut builds = MeshBuilds::default();
        assert!(builds.take().is_none() && builds.building().is_none());
        let first = builds.request(member(10), plan.clone(), Vec::new());
        assert_eq!(builds.take().map(|j| j.id), Some(first));
        assert!(builds.take().is_none(), "a job is handed out once");
        let second = builds.request(member(20), plan.clone(), Vec::new());
        let third = builds.request(member(30), plan, Vec::new());
        assert_eq!(
            builds.take().map(|j| (j.id, j.member.t)),
            Some((third, 30)),
            "only the newest waiting job goes to the worker"
        );
        assert_eq!(builds.building().map(|m| m.t), Some(30));
        assert_eq!(builds.finish(first), None, "a stale result is dropped");
        assert_eq!(builds.finish(second), None);
        assert_eq!(builds.finish(third).map(|m| m.t), Some(30));
        assert!(builds.building().is_none());
        assert_eq!(builds.finish(third), None, "a result is taken once");
    }

    #[test]
    fn cancelling_drops_the_request_and_the_grid_is_sent_once() {
        let mut builds = MeshBuilds::default();
        let id = builds.request(member(5), TilePlan::new(70, 40, 36).unwrap(), Vec::new());
        builds.cancel();
        assert!(builds.take().is_none() && builds.finish(id).is_none());
        assert!(builds.send_grid() && !builds.send_grid());
        builds.grid_lost();
        assert!(builds.send_grid());
    }

    #[test]
    fn packed_parts_rebuild_the_same_mesh_bits() {
        let (w, h) = (70, 40);
        let z = (0..w * h)
            .map(|i| ((i % w) as f64 * 0.3).sin() * 4.0 + ((i / w) as f64 * 0.2).cos() * 3.0)
            .collect();
        let hf = Heightfield::new(w, h, z).unwrap();
        let plan = TilePlan::new(w, h, 36).unwrap();
        let greedy = crate::catalogue::Config::Greedy(crate::baselines::GreedyParams {
            records: 16,
            ..Default::default()
        });
        let fronts = (0..plan.len())
            .map(|i| run_tile(&plan.cut(&hf, i).unwrap(), &plan, i, &greedy, 3).unwrap())
            .collect();
        let front = assemble(&plan, fronts).unwrap();
        let k = front.members.len() / 2;
        let parts = front.parts(k).unwrap();
        let packed = MeshJobParts::of(&plan, &parts).unwrap();
        assert_eq!(packed.offsets.len(), plan.len() + 1);
        let (plan2, parts2) = packed.clone().unpack().unwrap();
        assert_eq!((&plan2, &parts2), (&plan, &parts));
        let direct = front.mesh(&hf, k).unwrap();
        let rebuilt = mesh_of_parts(&plan2, &hf, &parts2).unwrap();
        assert_eq!(rebuilt, direct);
        assert_eq!(rebuilt.e_sum.to_bits(), front.members[k].e_sum.to_bits());
        assert_eq!(rebuilt.triangles.len() as u64, front.members[k].t);

        let mut bad = packed.clone();
        *bad.offsets.last_mut().unwrap() += 1;
        assert!(bad.unpack().unwrap_err().contains("do not fit"));
        let mut short = packed;
        short.offsets.pop();
        assert_eq!(
            short.unpack().err().as_deref(),
            Some("a mesh job whose arrays do not fit its header")
        );
        // A tile missing.
        assert!(matches!(
            mesh_of_parts(&plan, &hf, &parts[1..]),
            Err(TilingError::WrongTiles { expected, ref given })
                if expected == plan.len() && given[..] == (1..plan.len()).collect::<Vec<_>>()[..]
        ));
    }
}
