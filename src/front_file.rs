//! front.json: the result of one optimizer run, self-contained so that any outside tool can
//! re-score every solution from its kept grid indices (y·W + x). The CLI writes it and the
//! browser exports the same format.
//!
//! ```json
//! {"grid":{"width":33,"height":33,"source":"…"},"algorithm":"nsga2","params":{…},"seed":1,
//!  "evaluations":21000,"millis":812,
//!  "front":[{"E_sum":…,"E_max":…,"T":…,"kept_packed":"AAUBpgI="},
//!           {"E_sum":…,"E_max":…,"T":…,"kept_diff":"GAE="},…]}
//! ```
//!
//! A member's kept set is written compactly ([`crate::kept_codec`]): `kept_packed` holds its
//! increasing indices as base64 of LEB128 varint gaps; `kept_diff`, in the same form, the
//! indices in which it differs from the member before it in the file (whichever is shorter).
//! Readers also take the plain `"kept":[…]` array that older files hold.
//!
//! The error measure a run minimised ([`ErrorMeasure`]) is its `params.error`, absent for
//! `sum` (the default, so a sum run's file is byte for byte what it was before measures
//! existed). A run in `rms` or `max` also writes each member's `"RMS"` after `E_max`, so that
//! its members' three errors are all on file.
//!
//! Triangles are listed only on request ([`FrontFile::add_triangles`], `paretomesh run
//! --triangles`), as `"triangles":[[a,b,c],…]` after `kept`: on large grids they are most of the
//! file, and the kept set determines them (the canonical Delaunay triangulation, which
//! `paretomesh eval --keep` reproduces).

use crate::catalogue::{Algorithm, Config};
use crate::evaluator::{EvaluateError, Evaluator, MeshState, canonical_set, check_indices};
use crate::evolution::chromosome::Chromosome;
use crate::front::{Front, Solution};
use crate::heightfield::Heightfield;
use crate::import::{ImportOptions, Projection, Surface};
use crate::measure::ErrorMeasure;
use serde::{Deserialize, Serialize};

/// The grid a run was made on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GridInfo {
    /// W.
    pub width: usize,
    /// H.
    pub height: usize,
    /// How the grid was made (the height field's source note).
    pub source: String,
    /// The import options the grid was read with, so that a reader of the file (`export`, the
    /// app) reads the same file into the same grid; absent in files written before it was
    /// recorded, and for grids made in memory.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub import: Option<ImportRecord>,
}

/// The import options of a run's grid as front.json records them: every choice that changes
/// the grid a file becomes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ImportRecord {
    /// How a mesh became a grid: `auto`, `planar` or `cylindrical`.
    pub projection: String,
    /// The grid size asked for, `[W, H]`, or `null` for the importer's own choice.
    pub grid_size: Option<[usize; 2]>,
    /// Which surface of a folding mesh was kept: `single` or `outer`.
    pub surface: String,
    /// An RGB PNG read as Mapbox terrain-RGB.
    pub terrain_rgb: bool,
}

impl ImportRecord {
    /// The record of `options`.
    pub fn of(options: &ImportOptions) -> Self {
        Self {
            projection: options.projection.name().to_string(),
            grid_size: options.grid_size.map(|(w, h)| [w, h]),
            surface: options.surface.name().to_string(),
            terrain_rgb: options.terrain_rgb,
        }
    }

    /// The options this record names; fails on a projection or surface name no importer knows.
    pub fn options(&self) -> Result<ImportOptions, String> {
        let projection = match self.projection.as_str() {
            "auto" => Projection::Auto,
            "planar" => Projection::Planar,
            "cylindrical" => Projection::Cylindrical,
            other => {
                return Err(format!(
                    "unknown projection {other:?} in the import options"
                ));
            }
        };
        let surface = match self.surface.as_str() {
            "single" => Surface::Single,
            "outer" => Surface::Outer,
            other => return Err(format!("unknown surface {other:?} in the import options")),
        };
        Ok(ImportOptions {
            projection,
            grid_size: self.grid_size.map(|[w, h]| (w, h)),
            surface,
            terrain_rgb: self.terrain_rgb,
            ..ImportOptions::default()
        })
    }
}

/// One front member, with its triangles when the file lists them.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSolution {
    /// E_sum, E_max, T and the kept indices.
    pub solution: Solution,
    /// The Delaunay triangles of the kept set, grid-index triples, counter-clockwise, each
    /// starting at its smallest index, sorted; `None` when the file leaves them out.
    pub triangles: Option<Vec<[u32; 3]>>,
}

/// What every front.json holds before its members, untiled ([`FrontFile`]) or tiled
/// ([`TiledFrontFile`](crate::tiling::TiledFrontFile)): the grid, the method and its
/// parameters, the seed and the run's cost. Both files flatten it, so its fields are the
/// file's first ones, in this order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunHeader {
    /// The grid.
    pub grid: GridInfo,
    /// The method, written as its command-line name (`nsga2`, `weighted`, …).
    pub algorithm: Algorithm,
    /// The method's parameters, as its params type serialises them (for a tiled run, as each
    /// tile ran them).
    pub params: serde_json::Value,
    /// The seed of the run's random generator (tile k of a tiled run runs with
    /// `tile_seed``(seed, k)`).
    pub seed: u64,
    /// Evaluations spent (over all tiles).
    pub evaluations: u64,
    /// Wall time of the run in milliseconds (0 when unknown).
    pub millis: u64,
}

impl RunHeader {
    /// The header of a run of `config` with `seed` on the grid `grid`.
    pub fn new(grid: GridInfo, config: &Config, seed: u64, evaluations: u64, millis: u64) -> Self {
        Self {
            grid,
            algorithm: config.algorithm(),
            params: config.json(),
            seed,
            evaluations,
            millis,
        }
    }
}

/// The whole file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrontFile {
    /// The grid, the method, the seed and the run's cost.
    #[serde(flatten)]
    pub header: RunHeader,
    /// The front, by increasing T; kept sets are written compactly (see the module doc).
    #[serde(with = "members")]
    pub front: Vec<RunSolution>,
}

/// front.json's members with their kept sets packed or as diffs (see the module doc).
mod members {
    use super::RunSolution;
    use crate::front::Solution;
    use crate::kept_codec::{decode, encode, toggle};
    use serde::de::Error as _;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// A member as written.
    #[derive(Serialize)]
    struct Written<'a> {
        #[serde(rename = "E_sum")]
        e_sum: f64,
        #[serde(rename = "E_max")]
        e_max: f64,
        #[serde(rename = "RMS", skip_serializing_if = "Option::is_none")]
        rms: Option<f64>,
        #[serde(rename = "T")]
        t: usize,
        #[serde(skip_serializing_if = "Option::is_none")]
        kept_packed: Option<String>,
        #[serde(skip_serializing_if = "Option::is_none")]
        kept_diff: Option<String>,
        #[serde(skip_serializing_if = "Option::is_none")]
        triangles: Option<&'a Vec<[u32; 3]>>,
    }

    /// A member as read: one of the three forms of its kept set.
    #[derive(Deserialize)]
    struct Read {
        #[serde(rename = "E_sum")]
        e_sum: f64,
        #[serde(rename = "E_max")]
        e_max: f64,
        #[serde(rename = "RMS", default)]
        rms: Option<f64>,
        #[serde(rename = "T")]
        t: usize,
        #[serde(default)]
        kept: Option<Vec<u32>>,
        #[serde(default)]
        kept_packed: Option<String>,
        #[serde(default)]
        kept_diff: Option<String>,
        #[serde(default)]
        triangles: Option<Vec<[u32; 3]>>,
    }

    pub(super) fn serialize<S: Serializer>(front: &[RunSolution], s: S) -> Result<S::Ok, S::Error> {
        let mut previous: &[u32] = &[];
        let written: Vec<Written<'_>> = front
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let kept = &m.solution.kept;
                let packed = encode(kept);
                let diff = (i > 0).then(|| encode(&toggle(previous, kept)));
                previous = kept;
                let (kept_packed, kept_diff) = match diff {
                    Some(d) if d.len() < packed.len() => (None, Some(d)),
                    _ => (Some(packed), None),
                };
                Written {
                    e_sum: m.solution.e_sum,
                    e_max: m.solution.e_max,
                    rms: (!m.solution.rms.is_nan()).then_some(m.solution.rms),
                    t: m.solution.t,
                    kept_packed,
                    kept_diff,
                    triangles: m.triangles.as_ref(),
                }
            })
            .collect();
        written.serialize(s)
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Vec<RunSolution>, D::Error> {
        let read = Vec::<Read>::deserialize(d)?;
        let mut out: Vec<RunSolution> = Vec::with_capacity(read.len());
        for (i, r) in read.into_iter().enumerate() {
            let kept = match (r.kept, r.kept_packed, r.kept_diff) {
                (Some(kept), None, None) => kept,
                (None, Some(packed), None) => decode(&packed)
                    .map_err(|e| D::Error::custom(format!("front member {i}: {e}")))?,
                (None, None, Some(diff)) => {
                    let before = out.last().ok_or_else(|| {
                        D::Error::custom("front member 0 has kept_diff, but no member before it")
                    })?;
                    let diff = decode(&diff)
                        .map_err(|e| D::Error::custom(format!("front member {i}: {e}")))?;
                    toggle(&before.solution.kept, &diff)
                }
                _ => {
                    return Err(D::Error::custom(format!(
                        "front member {i} needs exactly one of kept, kept_packed and kept_diff"
                    )));
                }
            };
            let mut solution = Solution::recorded(r.e_sum, r.e_max, r.t, kept);
            if let Some(rms) = r.rms {
                solution.score.rms = rms;
            }
            out.push(RunSolution {
                solution,
                triangles: r.triangles,
            });
        }
        Ok(out)
    }
}

impl FrontFile {
    /// Builds the file of a run that produced `front` on `evaluator`'s height field, without
    /// triangles ([`add_triangles`](Self::add_triangles) adds them). Fails only when a kept
    /// index is out of range ([`EvaluateError::IndexOutOfRange`]).
    pub fn new(
        evaluator: &mut Evaluator,
        config: &Config,
        seed: u64,
        evaluations: u64,
        millis: u64,
        front: &Front,
    ) -> Result<Self, EvaluateError> {
        let hf: &Heightfield = evaluator.heightfield();
        let grid = GridInfo {
            width: hf.width(),
            height: hf.height(),
            source: hf.source().to_string(),
            import: None,
        };
        for s in front.solutions() {
            check_indices(&s.kept, hf.len())?;
        }
        // A sum front's file records E_sum, E_max and T only, as it always has.
        let sum = front.measure().is_sum();
        let members = front
            .solutions()
            .iter()
            .map(|s| {
                let mut solution = s.clone();
                if sum {
                    solution.score.rms = f64::NAN;
                }
                RunSolution {
                    solution,
                    triangles: None,
                }
            })
            .collect();
        Ok(Self {
            header: RunHeader::new(grid, config, seed, evaluations, millis),
            front: members,
        })
    }

    /// The error measure the run minimised: its parameters' `error`, `sum` when absent. Fails
    /// on a name no measure has.
    pub fn measure(&self) -> Result<ErrorMeasure, String> {
        measure_of(&self.header.params)
    }

    /// Records the import options the grid was read with (see [`GridInfo::import`]).
    pub fn with_import(mut self, options: &ImportOptions) -> Self {
        self.header.grid.import = Some(ImportRecord::of(options));
        self
    }

    /// Lists every member's triangles, recomputed with `evaluator` (on the file's grid).
    ///
    /// Members close in T usually share most of their points, so each member is scored by
    /// editing the mesh of the one before it in a nearest-neighbour tour (by Hamming distance)
    /// of the front, or from scratch when that is nearer than half its kept points: the
    /// triangles are the same either way (the evaluator's contract), listed in canonical order
    /// so that the file does not depend on how they were made.
    pub fn add_triangles(&mut self, evaluator: &mut Evaluator) -> Result<(), EvaluateError> {
        let hf: &Heightfield = evaluator.heightfield();
        let (n, corners) = (hf.len(), hf.corners());
        for m in &self.front {
            check_indices(&m.solution.kept, n)?;
        }
        let genes: Vec<Chromosome> = self
            .front
            .iter()
            .map(|m| Chromosome::from_indices(n, &m.solution.kept))
            .collect();
        let mut state = MeshState::default();
        let mut previous: Option<usize> = None;
        let (mut removed, mut inserted) = (Vec::new(), Vec::new());
        for m in edit_tour(&genes) {
            let near = previous.is_some_and(|p| {
                genes[p].write_edit(&genes[m], &corners, &mut removed, &mut inserted);
                2 * (removed.len() + inserted.len()) < self.front[m].solution.kept.len()
            });
            if !near || evaluator.edit(&mut state, &removed, &inserted).is_err() {
                evaluator.score_into(&self.front[m].solution.kept, &mut state)?;
            }
            self.front[m].triangles = Some(canonical_set(&state.triangles()));
            previous = Some(m);
        }
        Ok(())
    }
}

/// The error measure a run's recorded parameters name (`error`), `sum` when absent.
pub(crate) fn measure_of(params: &serde_json::Value) -> Result<ErrorMeasure, String> {
    match params.get("error") {
        None | Some(serde_json::Value::Null) => Ok(ErrorMeasure::Sum),
        Some(serde_json::Value::String(name)) => ErrorMeasure::parse(name),
        Some(other) => Err(format!(
            "params.error must be a measure's name, not {other}"
        )),
    }
}

/// An order that visits every chromosome once, starting at the first, each next one the nearest
/// (Hamming distance) not yet visited; of equally near ones, the first found by the scan below
/// (a fixed order, so the tour depends on the chromosomes alone). The distance is at least the
/// difference of the two counts of set genes, so candidates are scanned in increasing order of
/// that difference, outward from the current one in a list sorted by count, and the scan stops
/// where it reaches the best distance found.
fn edit_tour(genes: &[Chromosome]) -> Vec<usize> {
    let counts: Vec<usize> = genes.iter().map(Chromosome::count_ones).collect();
    let mut by_count: Vec<usize> = (0..genes.len()).collect();
    by_count.sort_by_key(|&i| (counts[i], i));
    let mut rank = vec![0; genes.len()];
    for (r, &i) in by_count.iter().enumerate() {
        rank[i] = r;
    }
    let mut visited = vec![false; genes.len()];
    let mut tour = Vec::with_capacity(genes.len());
    let mut current = 0;
    while current < genes.len() {
        visited[current] = true;
        tour.push(current);
        let gap = |m: usize| counts[m].abs_diff(counts[current]);
        // (distance, member) of the nearest unvisited member found so far.
        let mut best: Option<(usize, usize)> = None;
        // by_count[..below] and by_count[above..] are still to scan.
        let (mut below, mut above) = (rank[current], rank[current] + 1);
        loop {
            let down = below.checked_sub(1).map(|b| by_count[b]);
            let up = by_count.get(above).copied();
            let candidate = match (down, up) {
                (Some(d), Some(u)) if gap(d) <= gap(u) => d,
                (Some(d), None) => d,
                (_, Some(u)) => u,
                (None, None) => break,
            };
            let bound = best.map_or(usize::MAX, |(d, _)| d);
            if gap(candidate) >= bound {
                // Every member not scanned yet is at least this far in count.
                break;
            }
            if Some(candidate) == down {
                below -= 1;
            } else {
                above += 1;
            }
            if !visited[candidate]
                && let Some(d) = genes[current].hamming_below(&genes[candidate], bound)
            {
                best = Some((d, candidate));
            }
        }
        current = best.map_or(genes.len(), |(_, m)| m);
    }
    tour
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use std::sync::Arc;

    fn greedy() -> Config {
        Algorithm::Greedy.defaults()
    }

    #[test]
    fn triangles_are_the_canonical_fresh_ones_whether_edited_or_rebuilt() {
        // A 17×13 grid of integer heights (many co-circular ties) and a chain of kept sets: most
        // a few points from the previous one (scored by an edit), some far (rebuilt), some with
        // a corner missing from the list. Each member's triangles must be its fresh
        // triangulation, in canonical order.
        let (w, h) = (17usize, 13usize);
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(5);
        let z = (0..w * h).map(|_| rng.random_range(0..5) as f64).collect();
        let hf = Arc::new(Heightfield::new(w, h, z).unwrap());
        let n = (w * h) as u32;
        let mut keep: Vec<bool> = (0..n).map(|_| rng.random::<f64>() < 0.3).collect();
        let mut front = Front::default();
        for step in 0..40usize {
            if step % 9 == 8 {
                let density = rng.random::<f64>();
                keep = (0..n).map(|_| rng.random::<f64>() < density).collect();
            } else {
                for _ in 0..rng.random_range(1..6) {
                    let i = rng.random_range(0..n) as usize;
                    keep[i] = !keep[i];
                }
            }
            let kept: Vec<u32> = (0..n).filter(|&i| keep[i as usize]).collect();
            // Objectives made up so that every member enters, in this order (the file takes
            // the triangles from the kept points alone).
            assert!(front.offer(Solution::recorded(100.0 - step as f64, 0.0, step, kept)));
        }
        let mut ev = Evaluator::new(hf.clone());
        let mut file = FrontFile::new(&mut ev, &greedy(), 1, 0, 0, &front).unwrap();
        assert_eq!(file.front.len(), 40);
        file.add_triangles(&mut ev).unwrap();
        let mut fresh = Evaluator::new(hf);
        for m in &file.front {
            let expected = canonical_set(&fresh.evaluate(&m.solution.kept).unwrap().triangles);
            assert_eq!(m.triangles.as_ref(), Some(&expected), "T {}", m.solution.t);
        }
    }

    #[test]
    fn members_list_triangles_only_when_asked() {
        // By default a member is its numbers and packed kept set; with triangles, they follow
        // it, and both forms read back to the same file.
        let hf = Arc::new(
            Heightfield::new(3, 3, vec![0.0, 0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0, 0.0]).unwrap(),
        );
        let mut front = Front::default();
        front.offer(Solution::recorded(4.0, 4.0, 2, vec![0, 2, 6, 8]));
        let mut ev = Evaluator::new(hf);
        let mut file = FrontFile::new(&mut ev, &greedy(), 1, 0, 0, &front).unwrap();
        let json = serde_json::to_string(&file).unwrap();
        assert!(
            json.ends_with(
                r#""front":[{"E_sum":4.0,"E_max":4.0,"T":2,"kept_packed":"AAIEAg=="}]}"#
            ),
            "{json}"
        );
        assert_eq!(serde_json::from_str::<FrontFile>(&json).unwrap(), file);
        file.add_triangles(&mut ev).unwrap();
        let json = serde_json::to_string(&file).unwrap();
        assert!(
            json.ends_with(r#""kept_packed":"AAIEAg==","triangles":[[0,2,6],[2,8,6]]}]}"#),
            "{json}"
        );
        assert_eq!(serde_json::from_str::<FrontFile>(&json).unwrap(), file);
    }

    #[test]
    fn the_import_options_are_recorded_and_read_back() {
        let hf = Arc::new(Heightfield::new(3, 3, vec![0.0; 9]).unwrap());
        let mut front = Front::default();
        front.offer(Solution::recorded(0.0, 0.0, 2, vec![0, 2, 6, 8]));
        let mut ev = Evaluator::new(hf);
        let options = ImportOptions {
            projection: Projection::Cylindrical,
            grid_size: Some((65, 33)),
            surface: Surface::Outer,
            terrain_rgb: true,
            ..ImportOptions::default()
        };
        let file = FrontFile::new(&mut ev, &greedy(), 1, 0, 0, &front)
            .unwrap()
            .with_import(&options);
        let json = serde_json::to_string(&file).unwrap();
        assert!(
            json.contains(r#""import":{"projection":"cylindrical","grid_size":[65,33],"surface":"outer","terrain_rgb":true}"#),
            "{json}"
        );
        let read: FrontFile = serde_json::from_str(&json).unwrap();
        assert_eq!(read.header.grid.import.unwrap().options(), Ok(options));
        // A file without the record reads as before; a bad name is an error, not a default.
        let old = json.replace(r#","import":{"projection":"cylindrical","grid_size":[65,33],"surface":"outer","terrain_rgb":true}"#, "");
        assert_eq!(
            serde_json::from_str::<FrontFile>(&old)
                .unwrap()
                .header
                .grid
                .import,
            None
        );
        let bad = ImportRecord {
            surface: "inner".into(),
            ..ImportRecord::of(&ImportOptions::default())
        };
        assert!(bad.options().unwrap_err().contains("\"inner\""));
    }

    #[test]
    fn a_kept_index_out_of_range_is_an_error_not_a_panic() {
        // A front read from a file may name points the grid does not have.
        let hf = Arc::new(Heightfield::new(3, 3, vec![0.0; 9]).unwrap());
        let mut front = Front::default();
        front.offer(Solution::recorded(1.0, 1.0, 2, vec![0, 2, 6, 8]));
        front.offer(Solution::recorded(0.0, 0.0, 4, vec![0, 2, 6, 8, 9]));
        let mut ev = Evaluator::new(hf);
        let made = FrontFile::new(&mut ev, &greedy(), 1, 0, 0, &front);
        assert!(
            matches!(made, Err(EvaluateError::IndexOutOfRange { .. })),
            "{made:?}"
        );
    }

    #[test]
    fn the_edit_tour_visits_each_member_once_going_to_a_nearest_unvisited_one() {
        // Random bitsets of very different densities (so the count bound prunes) and a few
        // duplicates (distance 0, ties): the tour must be a permutation starting at 0 whose
        // every step goes to an unvisited member at the least distance, checked by brute force.
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(3);
        let n = 300;
        let mut genes: Vec<Chromosome> = (0..60)
            .map(|_| {
                let density = rng.random::<f64>();
                let kept: Vec<u32> = (0..n as u32)
                    .filter(|_| rng.random::<f64>() < density)
                    .collect();
                Chromosome::from_indices(n, &kept)
            })
            .collect();
        for i in [5, 17, 17, 40] {
            genes.push(genes[i].clone());
        }
        let tour = edit_tour(&genes);
        let mut seen = vec![false; genes.len()];
        for &m in &tour {
            assert!(!seen[m], "member {m} twice");
            seen[m] = true;
        }
        assert!(seen.iter().all(|&s| s), "every member visited");
        assert_eq!(tour[0], 0);
        let mut visited = vec![false; genes.len()];
        for step in tour.windows(2) {
            visited[step[0]] = true;
            let nearest = (0..genes.len())
                .filter(|&j| !visited[j])
                .map(|j| genes[step[0]].hamming(&genes[j]))
                .min()
                .unwrap();
            assert_eq!(genes[step[0]].hamming(&genes[step[1]]), nearest);
        }
        assert!(edit_tour(&[]).is_empty());
    }

    #[test]
    fn neighbours_are_written_as_diffs_and_old_arrays_still_read() {
        let hf = Arc::new(Heightfield::new(40, 40, vec![0.0; 1600]).unwrap());
        let mut front = Front::default();
        let base: Vec<u32> = (0..1599).step_by(3).chain([1599]).collect();
        let mut dense = base.clone();
        dense.insert(1, 1);
        front.offer(Solution::recorded(1.0, 1.0, 900, dense.clone()));
        front.offer(Solution::recorded(2.0, 1.0, 800, base.clone()));
        front.offer(Solution::recorded(9.0, 1.0, 2, vec![0, 39, 1560, 1599]));
        let mut ev = Evaluator::new(hf);
        let file = FrontFile::new(&mut ev, &greedy(), 1, 0, 0, &front).unwrap();
        let json: serde_json::Value = serde_json::to_value(&file).unwrap();
        let members = json["front"].as_array().unwrap();
        // By T: the corners packed whole, then the 534-point member in whichever form is
        // shorter, then the 535-point one as a one-index diff.
        assert_eq!(members[0]["kept_packed"], "ACfxCyc=");
        assert!(members[1]["kept_packed"].is_string() != members[1]["kept_diff"].is_string());
        assert_eq!(members[2]["kept_diff"], "AQ==");
        assert!(members[2].get("kept_packed").is_none());
        let back: FrontFile = serde_json::from_value(json.clone()).unwrap();
        assert_eq!(back, file);
        assert_eq!(back.front[2].solution.kept, dense);

        // An older file's plain arrays.
        let mut old = json.clone();
        for (m, s) in old["front"]
            .as_array_mut()
            .unwrap()
            .iter_mut()
            .zip(&file.front)
        {
            let m = m.as_object_mut().unwrap();
            m.remove("kept_packed");
            m.remove("kept_diff");
            m.insert(
                "kept".into(),
                serde_json::to_value(&s.solution.kept).unwrap(),
            );
        }
        assert_eq!(serde_json::from_value::<FrontFile>(old).unwrap(), file);

        // A diff with nothing before it, two forms at once, or broken text: errors.
        let mut bad = json.clone();
        bad["front"].as_array_mut().unwrap().remove(0);
        bad["front"].as_array_mut().unwrap().remove(0);
        let err = serde_json::from_value::<FrontFile>(bad)
            .unwrap_err()
            .to_string();
        assert!(err.contains("no member before it"), "{err}");
        let mut bad = json.clone();
        bad["front"][0]["kept"] = serde_json::json!([0, 39]);
        let err = serde_json::from_value::<FrontFile>(bad)
            .unwrap_err()
            .to_string();
        assert!(err.contains("exactly one"), "{err}");
        let mut bad = json;
        bad["front"][0]["kept_packed"] = "!!".into();
        let err = serde_json::from_value::<FrontFile>(bad)
            .unwrap_err()
            .to_string();
        assert!(err.contains("not base64"), "{err}");
    }
}
