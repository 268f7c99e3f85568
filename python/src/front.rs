//! `Front` and `Member`: a run's Pareto front as a Python sequence, its picks, its meshes in map
//! coordinates, and front.json.

use crate::errors::value_error;
use numpy::{IntoPyArray, PyArray1, PyArray2, ndarray::Array2};
use paretomesh::evaluator::{Evaluator, canonical_set, check_indices};
use paretomesh::export::mesh::WorldMesh;
use paretomesh::front::Solution;
use paretomesh::heightfield::Heightfield;
use paretomesh::metrics::trade_off_pick;
use paretomesh::run_file::{GridInfo, RunFile, RunSolution};
use pyo3::exceptions::{PyIndexError, PyOSError};
use pyo3::prelude::*;
use std::io::Write;
use std::path::PathBuf;
use std::sync::Arc;

/// Everything a front knows: the run's record (as front.json holds it) and, when known, the
/// height field it was made on, which its meshes need.
pub struct FrontData {
    pub hf: Option<Arc<Heightfield>>,
    pub grid: GridInfo,
    pub algorithm: String,
    pub params: serde_json::Value,
    pub seed: u64,
    pub evaluations: u64,
    pub millis: u64,
    /// By increasing T.
    pub members: Vec<Solution>,
}

impl FrontData {
    /// The record of a finished run on `hf`.
    pub fn of_run(hf: Arc<Heightfield>, file: RunFile) -> Self {
        let mut data = Self::of_file(file);
        data.hf = Some(hf);
        data
    }

    /// A front read from front.json, without its height field.
    pub fn of_file(file: RunFile) -> Self {
        Self {
            hf: None,
            grid: file.grid,
            algorithm: file.algorithm,
            params: file.params,
            seed: file.seed,
            evaluations: file.evaluations,
            millis: file.millis,
            members: file.front.into_iter().map(|m| m.solution).collect(),
        }
    }

    fn run_file(&self) -> RunFile {
        RunFile {
            grid: self.grid.clone(),
            algorithm: self.algorithm.clone(),
            params: self.params.clone(),
            seed: self.seed,
            evaluations: self.evaluations,
            millis: self.millis,
            front: self
                .members
                .iter()
                .map(|s| RunSolution {
                    solution: s.clone(),
                    triangles: None,
                })
                .collect(),
        }
    }
}

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
        self.data.members.len()
    }

    fn __getitem__(&self, index: isize) -> PyResult<PyMember> {
        let n = self.data.members.len() as isize;
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
        let t = |s: Option<&Solution>| s.map_or(0, |s| s.t);
        format!(
            "<paretomesh.Front: {} members, T {}..{}, {} on a {}×{} grid, seed {}>",
            d.members.len(),
            t(d.members.first()),
            t(d.members.last()),
            d.algorithm,
            d.grid.width,
            d.grid.height,
            d.seed
        )
    }

    /// The method's name, as the CLI's ``--algo`` spells it.
    #[getter]
    fn method(&self) -> String {
        self.data.algorithm.clone()
    }

    /// The seed of the run.
    #[getter]
    fn seed(&self) -> u64 {
        self.data.seed
    }

    /// Evaluations the run spent.
    #[getter]
    fn evaluations(&self) -> u64 {
        self.data.evaluations
    }

    /// Wall time of the run in milliseconds.
    #[getter]
    fn millis(&self) -> u64 {
        self.data.millis
    }

    /// The grid's (width, height) = (columns, rows).
    #[getter]
    fn shape(&self) -> (usize, usize) {
        (self.data.grid.width, self.data.grid.height)
    }

    /// How the grid was made (the source note front.json keeps).
    #[getter]
    fn source(&self) -> String {
        self.data.grid.source.clone()
    }

    /// The paper's trade-off pick (its eq. 7–9, the weights drawn with the run's seed): the
    /// member ``paretomesh export --tradeoff`` exports.
    fn knee(&self) -> PyResult<PyMember> {
        let points: Vec<[f64; 2]> = self.data.members.iter().map(Solution::objectives).collect();
        let pick = trade_off_pick(&points, self.data.seed)
            .map_err(|e| value_error(format!("no trade-off pick: {e}")))?;
        Ok(self.member(pick.index))
    }

    /// The member of least E_sum among those with at most ``n`` triangles.
    fn at_most_triangles(&self, n: usize) -> PyResult<PyMember> {
        let members = &self.data.members;
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
        let members = &self.data.members;
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
            let file = data.run_file();
            let out = std::fs::File::create(&path).map_err(|e| {
                PyOSError::new_err(format!("cannot create {}: {e}", path.display()))
            })?;
            let mut w = std::io::BufWriter::with_capacity(1 << 18, out);
            serde_json::to_writer(&mut w, &file)
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
        self.data.members[self.index].e_sum
    }

    /// E_max: the largest vertical error |z − z̃| over the grid, in height units.
    #[getter(E_max)]
    fn e_max(&self) -> f64 {
        self.data.members[self.index].e_max
    }

    /// T: the number of triangles.
    #[getter(T)]
    fn t(&self) -> usize {
        self.data.members[self.index].t
    }

    /// The kept grid points as increasing flat indices y·W + x (uint32), corners included.
    #[getter]
    fn kept<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<u32>> {
        self.data.members[self.index].kept.clone().into_pyarray(py)
    }

    /// This member's position in its front.
    #[getter]
    fn index(&self) -> usize {
        self.index
    }

    fn __repr__(&self) -> String {
        let s = &self.data.members[self.index];
        format!(
            "<paretomesh.Member {}: T={} E_sum={} E_max={} kept={}>",
            self.index,
            s.t,
            s.e_sum,
            s.e_max,
            s.kept.len()
        )
    }

    /// The mesh: ``(vertices, triangles)``, vertices float64 (n, 3) in map coordinates
    /// (x = origin_x + column·dx, y = origin_y + row·dy, z = height), one per kept point in the
    /// order of ``kept``; triangles uint32 (m, 3), counter-clockwise seen from +z, indexing
    /// ``vertices``: the canonical Delaunay triangulation of the kept set.
    fn mesh<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<u32>>)> {
        let Some(hf) = self.data.hf.clone() else {
            return Err(value_error(
                "this front was loaded without its grid: pass the grid to load_front(path, grid=...) to build meshes",
            ));
        };
        // A front.json written by another tool may list its points in any order.
        let mut kept = self.data.members[self.index].kept.clone();
        kept.sort_unstable();
        kept.dedup();
        let mesh = py.detach(move || -> Result<WorldMesh, String> {
            check_indices(&kept, hf.len()).map_err(|e| e.to_string())?;
            let evaluation = Evaluator::new(hf.clone())
                .evaluate(&kept)
                .map_err(|e| e.to_string())?;
            WorldMesh::new(&hf, &kept, &canonical_set(&evaluation.triangles))
        });
        let mesh = mesh.map_err(value_error)?;
        let (n, m) = (mesh.vertices.len(), mesh.triangles.len());
        let vertices = Array2::from_shape_vec((n, 3), mesh.vertices.into_iter().flatten().collect())
            .expect("three coordinates per vertex");
        let triangles =
            Array2::from_shape_vec((m, 3), mesh.triangles.into_iter().flatten().collect())
                .expect("three corners per triangle");
        Ok((vertices.into_pyarray(py), triangles.into_pyarray(py)))
    }
}
