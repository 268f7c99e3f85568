//! `Front` and `Member`: a run's Pareto front as a Python sequence, its picks, its meshes in map
//! coordinates, and front.json.

use crate::errors::value_error;
use numpy::{IntoPyArray, PyArray1, PyArray2, ndarray::Array2};
use paretomesh::evaluator::{Evaluator, canonical_set, check_indices};
use paretomesh::export::WorldMesh;
use paretomesh::front_file::{FrontFile, RunHeader, RunSolution};
use paretomesh::heightfield::Heightfield;
use paretomesh::metrics::trade_off_pick;
use paretomesh::tiling::{TiledFront, TiledFrontFile};
use pyo3::exceptions::{PyIndexError, PyOSError};
use pyo3::prelude::*;
use std::io::Write;
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

/// A front's members: one kept set each (an untiled run), or one candidate per tile (a tiled
/// run, whose mesh is the union of its tiles' canonical triangulations).
pub enum Members {
    /// Each member with the triangles its file listed, if any (a saved tiled front lists them).
    Untiled(Vec<RunSolution>),
    Tiled(TiledFront),
}

/// Where a front's height field comes from when its meshes need it.
pub enum GridSource {
    /// Not known: the front was loaded without its grid.
    None,
    /// Held.
    Held(Arc<Heightfield>),
    /// Read from this file (any format the CLI reads) when first needed.
    File(PathBuf),
}

/// Everything a front knows: the run's record (as front.json holds it) and where its height
/// field is, which its meshes need.
pub struct FrontData {
    pub grid_source: GridSource,
    /// The height field once read from `grid_source`.
    pub hf: OnceLock<Arc<Heightfield>>,
    /// The grid, the method, the seed and the run's cost, as every front.json starts.
    pub header: RunHeader,
    /// By increasing T.
    pub members: Members,
}

/// A member's numbers.
#[derive(Clone, Copy)]
pub struct Numbers {
    pub e_sum: f64,
    pub e_max: f64,
    pub t: usize,
}

impl FrontData {
    /// A front read from front.json (or made by a run), with its grid from `grid_source`.
    pub fn of_file(file: FrontFile, grid_source: GridSource) -> Self {
        Self {
            grid_source,
            hf: OnceLock::new(),
            header: file.header,
            members: Members::Untiled(file.front),
        }
    }

    pub fn len(&self) -> usize {
        match &self.members {
            Members::Untiled(m) => m.len(),
            Members::Tiled(f) => f.members.len(),
        }
    }

    pub fn numbers(&self, i: usize) -> Numbers {
        match &self.members {
            Members::Untiled(m) => Numbers {
                e_sum: m[i].solution.e_sum,
                e_max: m[i].solution.e_max,
                t: m[i].solution.t,
            },
            Members::Tiled(f) => Numbers {
                e_sum: f.members[i].e_sum,
                e_max: f.members[i].e_max,
                t: f.members[i].t as usize,
            },
        }
    }

    fn all_numbers(&self) -> Vec<Numbers> {
        (0..self.len()).map(|i| self.numbers(i)).collect()
    }

    /// The height field, read on first use when the front names a file.
    pub fn heightfield(&self) -> Result<Arc<Heightfield>, String> {
        if let Some(hf) = self.hf.get() {
            return Ok(hf.clone());
        }
        let hf = match &self.grid_source {
            GridSource::None => {
                return Err("this front was loaded without its grid: pass the grid to load_front(path, grid=...) to build meshes".into());
            }
            GridSource::Held(hf) => hf.clone(),
            GridSource::File(path) => {
                Arc::new(paretomesh::import::load(path).map_err(|e| e.to_string())?)
            }
        };
        Ok(self.hf.get_or_init(|| hf).clone())
    }

    /// Member `i`'s kept grid points (increasing) and triangles (grid indices, canonical order).
    pub fn kept_and_triangles(&self, i: usize) -> Result<(Vec<u32>, Vec<[u32; 3]>), String> {
        let hf = self.heightfield()?;
        match &self.members {
            Members::Untiled(m) => {
                // A front.json written by another tool may list its points in any order.
                let mut kept = m[i].solution.kept.clone();
                kept.sort_unstable();
                kept.dedup();
                check_indices(&kept, hf.len()).map_err(|e| e.to_string())?;
                if let Some(listed) = &m[i].triangles {
                    // The file's own mesh (a tiled front's union of tile meshes).
                    check_indices(listed.as_flattened(), hf.len()).map_err(|e| e.to_string())?;
                    let mut kept = kept;
                    kept.extend(listed.as_flattened());
                    kept.sort_unstable();
                    kept.dedup();
                    return Ok((kept, canonical_set(listed)));
                }
                let evaluation = Evaluator::new(hf)
                    .evaluate(&kept)
                    .map_err(|e| e.to_string())?;
                Ok((kept, canonical_set(&evaluation.triangles)))
            }
            Members::Tiled(f) => {
                let mesh = f.mesh(&hf, i).map_err(|e| e.to_string())?;
                Ok((mesh.kept, canonical_set(&mesh.triangles)))
            }
        }
    }

    /// The front.json of this front, as JSON: a tiled front's file keeps every tile's kept sets
    /// and each member's choice of one per tile (the format `paretomesh run --tile` writes).
    fn to_json(&self, w: impl std::io::Write) -> Result<(), serde_json::Error> {
        match &self.members {
            Members::Untiled(front) => serde_json::to_writer(
                w,
                &FrontFile {
                    header: self.header.clone(),
                    front: front.clone(),
                },
            ),
            Members::Tiled(tiled) => serde_json::to_writer(
                w,
                &TiledFrontFile {
                    header: self.header.clone(),
                    threads: 0,
                    tiled: tiled.clone(),
                },
            ),
        }
    }

    /// A tiled front read from its front.json.
    pub fn of_tiled_file(file: TiledFrontFile, grid_source: GridSource) -> Self {
        Self {
            grid_source,
            hf: OnceLock::new(),
            header: file.header,
            members: Members::Tiled(file.tiled),
        }
    }
}

/// A mesh as numpy arrays: vertices (n, 3) and triangles (m, 3).
type MeshArrays<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<u32>>);

/// The Pareto front of a run: its members by increasing triangle count T (so decreasing
/// error). A sequence: ``len(front)``, ``front[i]``, ``for member in front``.
#[pyclass(frozen, name = "Front", module = "paretomesh")]
pub struct PyFront {
    pub data: Arc<FrontData>,
}

/// One member of a front: a kept set of grid points and its scores.
#[pyclass(frozen, name = "Member", module = "paretomesh")]
pub struct PyMember {
    data: Arc<FrontData>,
    index: usize,
}

impl PyFront {
    fn member(&self, index: usize) -> PyMember {
        PyMember {
            data: self.data.clone(),
            index,
        }
    }
}

#[pymethods]
impl PyFront {
    fn __len__(&self) -> usize {
        self.data.len()
    }

    fn __getitem__(&self, index: isize) -> PyResult<PyMember> {
        let n = self.data.len() as isize;
        let at = if index < 0 { index + n } else { index };
        if !(0..n).contains(&at) {
            return Err(PyIndexError::new_err(format!(
                "member {index} is out of range: the front has {n} members"
            )));
        }
        Ok(self.member(at as usize))
    }

    fn __repr__(&self) -> String {
        let d = &self.data;
        let n = d.len();
        let t = |i: usize| if n == 0 { 0 } else { d.numbers(i).t };
        let tiles = match &d.members {
            Members::Untiled(_) => String::new(),
            Members::Tiled(f) => format!(" in {} tiles", f.plan.len()),
        };
        format!(
            "<paretomesh.Front: {n} members, T {}..{}, {} on a {}×{} grid{tiles}, seed {}>",
            t(0),
            t(n.saturating_sub(1)),
            d.header.algorithm.name(),
            d.header.grid.width,
            d.header.grid.height,
            d.header.seed
        )
    }

    /// The method's name, as the CLI's ``--algo`` spells it.
    #[getter]
    fn method(&self) -> String {
        self.data.header.algorithm.name().to_string()
    }

    /// The seed of the run.
    #[getter]
    fn seed(&self) -> u64 {
        self.data.header.seed
    }

    /// Evaluations the run spent (over every tile of a tiled run).
    #[getter]
    fn evaluations(&self) -> u64 {
        self.data.header.evaluations
    }

    /// Wall time of the run in milliseconds.
    #[getter]
    fn millis(&self) -> u64 {
        self.data.header.millis
    }

    /// The grid's (width, height) = (columns, rows).
    #[getter]
    fn shape(&self) -> (usize, usize) {
        (self.data.header.grid.width, self.data.header.grid.height)
    }

    /// How the grid was made (the source note front.json keeps).
    #[getter]
    fn source(&self) -> String {
        self.data.header.grid.source.clone()
    }

    /// The tile side of a tiled run, None for an untiled one.
    #[getter]
    fn tile(&self) -> Option<usize> {
        match &self.data.members {
            Members::Untiled(_) => None,
            Members::Tiled(f) => Some(f.plan.tile_size()),
        }
    }

    /// The paper's trade-off pick (its eq. 7–9, the weights drawn with the run's seed): the
    /// member ``paretomesh export --tradeoff`` exports.
    fn knee(&self) -> PyResult<PyMember> {
        let points: Vec<[f64; 2]> = self
            .data
            .all_numbers()
            .iter()
            .map(|n| [n.e_sum, n.t as f64])
            .collect();
        let pick = trade_off_pick(&points, self.data.header.seed)
            .map_err(|e| value_error(format!("no trade-off pick: {e}")))?;
        Ok(self.member(pick.index))
    }

    /// The member of least E_sum among those with at most ``n`` triangles.
    fn at_most_triangles(&self, n: usize) -> PyResult<PyMember> {
        let members = self.data.all_numbers();
        (0..members.len())
            .filter(|&i| members[i].t <= n)
            .min_by(|&i, &j| {
                let (a, b) = (&members[i], &members[j]);
                a.e_sum.total_cmp(&b.e_sum).then(a.t.cmp(&b.t))
            })
            .map(|i| self.member(i))
            .ok_or_else(|| {
                let fewest = members.iter().map(|m| m.t).min().unwrap_or(0);
                value_error(format!(
                    "no member has at most {n} triangles: the smallest member has {fewest}"
                ))
            })
    }

    /// The member of fewest triangles among those whose largest vertical error E_max is at
    /// most ``x`` (in the surface's height units); ties go to the lower E_sum.
    fn at_most_vertical_error(&self, x: f64) -> PyResult<PyMember> {
        let members = self.data.all_numbers();
        (0..members.len())
            .filter(|&i| members[i].e_max <= x)
            .min_by(|&i, &j| {
                let (a, b) = (&members[i], &members[j]);
                a.t.cmp(&b.t).then(a.e_sum.total_cmp(&b.e_sum))
            })
            .map(|i| self.member(i))
            .ok_or_else(|| {
                let least = members
                    .iter()
                    .map(|m| m.e_max)
                    .min_by(f64::total_cmp)
                    .unwrap_or(f64::NAN);
                value_error(format!(
                    "no member has E_max at most {x}: the most accurate member has {least}"
                ))
            })
    }

    /// Writes the front as front.json, the file ``paretomesh export`` and the app read.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let data = self.data.clone();
        py.detach(move || {
            let out = std::fs::File::create(&path).map_err(|e| {
                PyOSError::new_err(format!("cannot create {}: {e}", path.display()))
            })?;
            let mut w = std::io::BufWriter::with_capacity(1 << 18, out);
            data.to_json(&mut w)
                .map_err(std::io::Error::other)
                .and_then(|()| w.flush())
                .map_err(|e| PyOSError::new_err(format!("cannot write {}: {e}", path.display())))
        })
    }
}

#[pymethods]
impl PyMember {
    /// E_sum: Σ |z − z̃| over every grid point, in height units.
    #[getter(E_sum)]
    fn e_sum(&self) -> f64 {
        self.data.numbers(self.index).e_sum
    }

    /// E_max: the largest vertical error |z − z̃| over the grid, in height units.
    #[getter(E_max)]
    fn e_max(&self) -> f64 {
        self.data.numbers(self.index).e_max
    }

    /// T: the number of triangles.
    #[getter(T)]
    fn t(&self) -> usize {
        self.data.numbers(self.index).t
    }

    /// The kept grid points as increasing flat indices y·W + x (uint32), corners included.
    #[getter]
    fn kept<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<u32>>> {
        let kept = match &self.data.members {
            Members::Untiled(m) => m[self.index].solution.kept.clone(),
            Members::Tiled(_) => {
                let (data, index) = (self.data.clone(), self.index);
                py.detach(move || data.kept_and_triangles(index))
                    .map_err(value_error)?
                    .0
            }
        };
        Ok(kept.into_pyarray(py))
    }

    /// This member's position in its front.
    #[getter]
    fn index(&self) -> usize {
        self.index
    }

    fn __repr__(&self) -> String {
        let n = self.data.numbers(self.index);
        format!(
            "<paretomesh.Member {}: T={} E_sum={} E_max={}>",
            self.index, n.t, n.e_sum, n.e_max
        )
    }

    /// The mesh: ``(vertices, triangles)``, vertices float64 (n, 3) in map coordinates
    /// (x = origin_x + column·dx, y = origin_y + row·dy, z = height), one per kept point in the
    /// order of ``kept``; triangles uint32 (m, 3), counter-clockwise seen from +z, indexing
    /// ``vertices``. Untiled: the canonical Delaunay triangulation of the kept set; tiled: the
    /// union of the tiles' canonical triangulations.
    fn mesh<'py>(&self, py: Python<'py>) -> PyResult<MeshArrays<'py>> {
        let (data, index) = (self.data.clone(), self.index);
        let mesh = py.detach(move || -> Result<WorldMesh, String> {
            let hf = data.heightfield()?;
            let (kept, triangles) = data.kept_and_triangles(index)?;
            WorldMesh::new(&hf, &kept, &triangles)
        });
        let mesh = mesh.map_err(value_error)?;
        let (n, m) = (mesh.vertices.len(), mesh.triangles.len());
        let vertices =
            Array2::from_shape_vec((n, 3), mesh.vertices.into_iter().flatten().collect())
                .expect("three coordinates per vertex");
        let triangles =
            Array2::from_shape_vec((m, 3), mesh.triangles.into_iter().flatten().collect())
                .expect("three corners per triangle");
        Ok((vertices.into_pyarray(py), triangles.into_pyarray(py)))
    }
}
