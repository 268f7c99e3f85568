//! The tiled side of a pool run (see [`super::pool`]): one job per tile and pass, the tiles'
//! fronts as the workers report them, and the whole-grid front assembled from them
//! ([`crate::tiling::assemble`]) on the page.
//!
//! A run of a slow method goes in two passes. The first runs greedy insertion on every tile,
//! so a whole-grid front shows within seconds; the second runs the chosen method on every tile,
//! and each tile's front replaces its first-pass front as it comes, so the whole-grid front
//! improves tile by tile. Mixing passes keeps the mesh crack-free, since a tile's border points
//! depend on its border profile alone. When every second-pass front is in, the front is the
//! one `paretomesh run --tile` gives for the same seed.

use super::algorithms::{self, Algorithm, Params};
use crate::baselines::{GreedyParams, GreedyStop};
use crate::catalogue::Config;
use crate::front::{Front, Solution};
use crate::front_file::{GridInfo, RunHeader};
use crate::tiling::TiledFrontFile;
use crate::tiling::{TileFront, TilePart, TilePlan, TiledFront, TiledMesh, assemble, tile_config};

/// The algorithm of the first, quick pass.
pub(crate) const QUICK: Algorithm = Algorithm::Greedy;

/// The first pass's greedy insertion on tile `tile`: it stops at a tenth of the tile's full
/// triangle count, which holds every mesh a whole-grid front is looked at for, in a fraction of
/// the time of inserting every point.
fn quick_config(plan: &TilePlan, tile: usize) -> Config {
    let t = plan.tile(tile).map_or(2, |t| 2 * (t.w - 1) * (t.h - 1));
    Config::Greedy(GreedyParams {
        stop: GreedyStop::Triangles((t / QUICK_SHARE).max(2)),
        ..GreedyParams::default()
    })
}

/// The first pass stops at 1 / this of a tile's full triangle count.
const QUICK_SHARE: usize = 10;

/// Members a first-pass tile front keeps (the second pass keeps
/// [`MEMBERS_PER_TILE`](crate::tiling::MEMBERS_PER_TILE)): each is scored over
/// the whole tile, which costs the first pass more than its greedy insertion, and the
/// whole-grid front combines the tiles' members, so it stays fine-grained with few per tile.
pub(crate) const QUICK_MEMBERS: usize = 16;

/// One tile job: which tile, with which method.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TileJob {
    /// The tile's index in the plan.
    pub tile: usize,
    /// The method and its parameters, as [`crate::tiling::run_tile`] takes them.
    pub config: Config,
    /// The run's seed (the tile's own seed is derived from it and the tile).
    pub seed: u64,
    /// True for a first-pass job.
    pub quick: bool,
    /// Members the tile's front keeps (see [`crate::tiling::run_tile_keeping`]).
    pub members: usize,
}

/// The tiles of a pool run and what their workers reported.
pub(crate) struct TiledRun {
    plan: TilePlan,
    algorithm: Algorithm,
    params: Params,
    /// Per tile: its latest front and whether it is the final (second-pass) one.
    fronts: Vec<Option<(TileFront, bool)>>,
    assembled: Option<TiledFront>,
}

impl TiledRun {
    /// A run of `algorithm` with `params` on the tiles of `plan`.
    pub(crate) fn new(plan: TilePlan, algorithm: Algorithm, params: Params) -> Self {
        let tiles = plan.len();
        Self {
            plan,
            algorithm,
            params,
            fronts: vec![None; tiles],
            assembled: None,
        }
    }

    /// The plan.
    pub(crate) fn plan(&self) -> &TilePlan {
        &self.plan
    }

    /// True when the run has a quick first pass (the chosen method is not the quick one).
    fn two_passes(&self) -> bool {
        self.algorithm != QUICK
    }

    /// Jobs: a pass over every tile, two when [`QUICK`] is not the chosen method.
    pub(crate) fn job_count(&self) -> usize {
        self.plan.len() * if self.two_passes() { 2 } else { 1 }
    }

    /// Job `index`: the first pass's tiles in order, then the second's.
    pub(crate) fn job(&self, index: usize) -> Option<TileJob> {
        if index >= self.job_count() {
            return None;
        }
        let tiles = self.plan.len();
        let quick = self.two_passes() && index < tiles;
        let tile = index % tiles;
        let config = if quick {
            quick_config(&self.plan, tile)
        } else {
            algorithms::config(self.algorithm, &self.params)
        };
        Some(TileJob {
            tile,
            config,
            seed: self.params.seed,
            quick,
            members: if quick {
                QUICK_MEMBERS
            } else {
                crate::tiling::MEMBERS_PER_TILE
            },
        })
    }

    /// The front of job `index` came: it becomes its tile's front unless the tile already has
    /// its final one (a first-pass front may come after the second pass's on a busy pool).
    /// Returns whether the whole-grid front changed.
    pub(crate) fn report(&mut self, index: usize, front: TileFront) -> Result<bool, String> {
        let job = self
            .job(index)
            .ok_or_else(|| format!("a worker reported job {index} of a run with fewer jobs"))?;
        if front.index != job.tile {
            return Err(format!(
                "a worker reported tile {} for job {index}, which is tile {}",
                front.index, job.tile
            ));
        }
        let slot = &mut self.fronts[job.tile];
        if slot.as_ref().is_some_and(|(_, last)| *last) {
            return Ok(false);
        }
        *slot = Some((front, !job.quick));
        if self.fronts.iter().all(Option::is_some) {
            let fronts = self
                .fronts
                .iter()
                .flatten()
                .map(|(f, _)| f.clone())
                .collect();
            self.assembled = Some(assemble(&self.plan, fronts).map_err(|e| e.to_string())?);
            return Ok(true);
        }
        Ok(false)
    }

    /// Tiles whose final front is in.
    pub(crate) fn tiles_final(&self) -> usize {
        self.fronts
            .iter()
            .filter(|f| f.as_ref().is_some_and(|(_, last)| *last))
            .count()
    }

    /// Tiles with a front of either pass.
    pub(crate) fn tiles_reported(&self) -> usize {
        self.fronts.iter().flatten().count()
    }

    /// Evaluations of the tiles' current fronts.
    pub(crate) fn evaluations(&self) -> u64 {
        self.fronts
            .iter()
            .flatten()
            .map(|(f, _)| f.evaluations)
            .sum()
    }

    /// The whole-grid front as the app's plot and selection read it: each member's E_sum,
    /// E_max and T, without kept lists (a member's mesh is rebuilt on demand by
    /// [`TiledRun::mesh`]). Empty until every tile has a front.
    pub(crate) fn front(&self) -> Front {
        let Some(assembled) = &self.assembled else {
            return Front::default();
        };
        let members: Vec<Solution> = assembled
            .members
            .iter()
            .map(|m| Solution::recorded(m.e_sum, m.e_max, m.t as usize, Vec::new()))
            .collect();
        Front::merged(&members)
    }

    /// The assembled whole-grid front, once every tile has a front.
    pub(crate) fn assembled(&self) -> Option<&TiledFront> {
        self.assembled.as_ref()
    }

    /// front.json of the run, as `paretomesh run --tile` writes it, once every tile's final
    /// front is in (before, some tiles hold the first pass's greedy fronts, which the file's
    /// algorithm would misname); the message says how far the run is.
    pub(crate) fn run_file(
        &self,
        hf: &crate::heightfield::Heightfield,
        millis: u64,
        workers: usize,
    ) -> Result<TiledFrontFile, String> {
        let assembled = self
            .assembled
            .as_ref()
            .filter(|_| self.tiles_final() == self.plan.len())
            .ok_or_else(|| {
                format!(
                    "the tiled front is saved once every tile's final front is in ({} of {})",
                    self.tiles_final(),
                    self.plan.len()
                )
            })?;
        let grid = GridInfo {
            width: hf.width(),
            height: hf.height(),
            source: hf.source().to_string(),
            import: None,
        };
        // As the tiles ran it (the memetic search's share per tile).
        let config = tile_config(
            &self.plan,
            &algorithms::config(self.algorithm, &self.params),
        );
        Ok(TiledFrontFile {
            header: RunHeader::new(
                grid,
                &config,
                self.params.seed,
                assembled.evaluations(),
                millis,
            ),
            threads: workers,
            tiled: assembled.clone(),
        })
    }

    /// The tile parts of the whole-grid member with objectives (`e_sum`, `t`): what a worker
    /// holding the grid needs to build its mesh ([`crate::tiling::mesh_of_parts`]).
    pub(crate) fn parts(&self, e_sum: f64, t: usize) -> Result<Vec<TilePart>, String> {
        let (assembled, member) = self.member(e_sum, t)?;
        assembled.parts(member).map_err(|e| e.to_string())
    }

    /// The assembled front and the index of its member with objectives (`e_sum`, `t`).
    fn member(&self, e_sum: f64, t: usize) -> Result<(&TiledFront, usize), String> {
        let assembled = self
            .assembled
            .as_ref()
            .ok_or("the tiled front is not assembled yet")?;
        let member = assembled
            .members
            .iter()
            .position(|m| m.t as usize == t && m.e_sum.to_bits() == e_sum.to_bits())
            .ok_or("this member is no longer on the tiled front")?;
        Ok((assembled, member))
    }

    /// The mesh of the whole-grid member with objectives (`e_sum`, `t`) on the grid `hf`.
    pub(crate) fn mesh(
        &self,
        hf: &crate::heightfield::Heightfield,
        e_sum: f64,
        t: usize,
    ) -> Result<TiledMesh, String> {
        let (assembled, member) = self.member(e_sum, t)?;
        assembled.mesh(hf, member).map_err(|e| e.to_string())
    }
}

// The CLI's tiled run, which the tests compare with, runs threads: native only.
#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::*;
    use crate::heightfield::Heightfield;
    use crate::tiling::{run_tile_keeping, run_tiled};

    fn grid() -> Heightfield {
        let (w, h) = (70, 40);
        let z = (0..w * h)
            .map(|i| ((i % w) as f64 * 0.3).sin() * 4.0 + ((i / w) as f64 * 0.2).cos() * 3.0)
            .collect();
        Heightfield::new(w, h, z).unwrap()
    }

    fn params() -> Params {
        Params {
            population: 8,
            generations: 3,
            seed: 9,
            ..Params::default()
        }
    }

    /// Runs job `index` of `run` as a worker does.
    fn work(run: &TiledRun, hf: &Heightfield, index: usize) -> TileFront {
        let job = run.job(index).unwrap();
        let tile = run.plan().cut(hf, job.tile).unwrap();
        run_tile_keeping(
            &tile,
            run.plan(),
            job.tile,
            &job.config,
            job.seed,
            job.members,
        )
        .unwrap()
    }

    #[test]
    fn the_tiles_reported_in_any_order_give_the_clis_tiled_front() {
        let hf = grid();
        let plan = TilePlan::new(70, 40, 36).unwrap();
        let tiles = plan.len();
        let mut run = TiledRun::new(plan.clone(), Algorithm::Nsga2, params());
        assert_eq!(run.job_count(), 2 * tiles);
        assert!(run.job(0).unwrap().quick && !run.job(tiles).unwrap().quick);
        assert_eq!(run.job(tiles + 1).unwrap().tile, 1);
        assert!(run.job(2 * tiles).is_none());

        // The first pass: a whole-grid front once every tile has reported.
        for index in 0..tiles {
            assert!(run.front().is_empty());
            let changed = run.report(index, work(&run, &hf, index)).unwrap();
            assert_eq!(changed, index + 1 == tiles);
        }
        let quick = run.front();
        assert!(!quick.is_empty());
        assert!(
            run.assembled()
                .unwrap()
                .tiles
                .iter()
                .all(|t| t.members.len() <= QUICK_MEMBERS),
            "first-pass tile fronts keep at most {QUICK_MEMBERS} members"
        );
        assert_eq!(run.tiles_final(), 0);

        let early = run.run_file(&hf, 0, 1).unwrap_err();
        assert!(early.contains(&format!("(0 of {tiles})")), "{early}");

        // The second pass, backwards, with a late first-pass front for tile 0 in between.
        let late = work(&run, &hf, 0);
        for index in (tiles..2 * tiles).rev() {
            assert!(run.report(index, work(&run, &hf, index)).unwrap());
        }
        assert!(
            !run.report(0, late).unwrap(),
            "a late first-pass front is ignored"
        );
        assert_eq!(run.tiles_final(), tiles);

        let p = params();
        let cli = run_tiled(
            &hf,
            &plan,
            &algorithms::config(Algorithm::Nsga2, &p),
            p.seed,
            1,
        )
        .unwrap();
        assert_eq!(
            run.assembled().unwrap(),
            &cli,
            "the page's front is the CLI's"
        );
        let front = run.front();
        assert_eq!(front.len(), cli.members.len());
        for (s, m) in front.solutions().iter().zip(&cli.members) {
            assert_eq!(
                (s.e_sum.to_bits(), s.e_max.to_bits(), s.t as u64),
                (m.e_sum.to_bits(), m.e_max.to_bits(), m.t)
            );
        }
        // A member's mesh is rebuilt from the tiles: T triangles over the whole grid.
        let s = &front.solutions()[front.len() / 2];
        let mesh = run.mesh(&hf, s.e_sum, s.t).unwrap();
        assert_eq!(mesh.triangles.len(), s.t);
        assert_eq!(
            run.mesh(&hf, s.e_sum + 1.0, s.t).err().as_deref(),
            Some("this member is no longer on the tiled front")
        );
        // Its front.json is the CLI's, and reads back.
        let file = run.run_file(&hf, 5, 2).unwrap();
        assert_eq!(
            (file.tiled, file.header.algorithm, file.header.seed),
            (cli, Algorithm::Nsga2, 9)
        );
    }

    #[test]
    fn greedy_insertion_runs_in_one_pass_and_bad_reports_are_refused() {
        let hf = grid();
        let plan = TilePlan::new(70, 40, 36).unwrap();
        let mut run = TiledRun::new(plan.clone(), Algorithm::Greedy, params());
        assert_eq!(run.job_count(), plan.len());
        assert!(!run.job(0).unwrap().quick);
        let front = work(&run, &hf, 1);
        assert!(
            run.report(0, front.clone())
                .unwrap_err()
                .contains("tile 1 for job 0")
        );
        assert_eq!(
            run.report(plan.len(), front),
            Err(format!(
                "a worker reported job {} of a run with fewer jobs",
                plan.len()
            ))
        );
    }
}
