//! Resampling a triangle mesh onto a regular grid: a planar projection onto the best-fit plane or
//! a cylindrical unwrap around the principal axis, rasterisation of the triangles, and filling of
//! the grid points no triangle covers.
//!
//! Rules, in the order they apply:
//! - **Frame.** Principal component analysis of the vertices (mean and covariance, each vertex
//!   weighted equally) gives axes e₀, e₁, e₂ by decreasing variance, each signed so that its
//!   largest component is positive.
//! - **Planar.** The best-fit plane's normal n is whichever of the area-weighted mean triangle
//!   normal, the PCA normal e₂ and the most consistently faced coordinate axis folds least, the
//!   first of them on ties (see `planar_normals`); u = the coordinate axis most orthogonal to n
//!   or the principal axis (made orthogonal to n), whichever gives the smaller bounding box;
//!   v = n × u. Grid coordinates are (d·u, d·v), height d·n, with d = p − origin and the origin
//!   at the mean, or at 0 when n is a coordinate axis (so a terrain keeps its own x, y, z).
//! - **Cylindrical.** Axis e₀ through the mean (the longest extent: a face scan's vertical axis, a
//!   tube's axis), reference direction e₁. Grid x is the angle θ from the reference (radians), grid
//!   y the position ζ along the axis, height the distance ρ from the axis. The seam is put in the
//!   widest angular gap between vertices; a triangle that crosses it is drawn on both sides.
//! - **Rasterisation.** A grid point takes a triangle's barycentric height when it lies inside or
//!   on the triangle (within 1e-9 in barycentric terms, so edges and vertices are never missed).
//!   Where several triangles cover a point, the highest wins: the surface seen from the +n side
//!   (planar) or from outside (cylindrical, largest ρ).
//! - **Folds.** A grid point strictly inside two or more triangles is covered twice. When more
//!   than [`MAX_OVERLAP`] of the points strictly inside some triangle are covered twice, the
//!   surface folds over itself and the projection is refused — unless the outer surface is asked
//!   for ([`Surface::Outer`]): then every point keeps its outermost hit, as the highest-wins rule
//!   already gives, and the doubly covered points are counted.
//! - **Fill.** A point no triangle covers takes the value of its nearest covered point in
//!   4-neighbour steps (breadth-first from all covered points, ties to the lower grid index).

use super::error::ImportError;
use super::options::{MAX_OVERLAP, Projection, Surface};
use super::triangle_mesh::{DEFAULT_MAX_SIDE, TriangleMesh};
use crate::heightfield::Placement;
use std::f64::consts::{PI, TAU};

/// A mesh resampled onto a grid.
pub(super) struct Resampled {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Heights, row-major, all finite.
    pub z: Vec<f64>,
    /// Grid coordinates of point (0, 0).
    pub origin: [f64; 2],
    /// Grid spacing.
    pub spacing: [f64; 2],
    /// How the grid maps back to the mesh's 3-D space.
    pub placement: Placement,
    /// Points no triangle covered, filled from their nearest covered neighbour.
    pub filled: usize,
    /// Share of covered grid points covered more than once (at most [`MAX_OVERLAP`] for
    /// [`Surface::Single`]).
    pub overlap: f64,
    /// Grid points covered more than once, which took the outermost hit.
    pub covered_twice: usize,
}

/// What a projection gives.
pub(super) enum Outcome {
    /// The resampled grid.
    Grid(Resampled),
    /// The surface folds over itself: `overlap` is the share of doubly covered grid points, or
    /// `None` when the projection has no area (no grid point is covered).
    Folded { overlap: Option<f64> },
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// Mean and covariance of the vertices, each weighted equally.
fn covariance(vertices: &[[f64; 3]]) -> ([f64; 3], [[f64; 3]; 3]) {
    let n = vertices.len() as f64;
    let mut mean = [0.0; 3];
    for p in vertices {
        for k in 0..3 {
            mean[k] += p[k] / n;
        }
    }
    let mut cov = [[0.0; 3]; 3];
    for p in vertices {
        let d = sub(*p, mean);
        for (i, row) in cov.iter_mut().enumerate() {
            for (j, c) in row.iter_mut().enumerate() {
                *c += d[i] * d[j] / n;
            }
        }
    }
    (mean, cov)
}

/// Mean of the vertices and the eigenvectors of their covariance by decreasing eigenvalue.
fn principal_frame(vertices: &[[f64; 3]]) -> ([f64; 3], [[f64; 3]; 3]) {
    let (mean, cov) = covariance(vertices);
    let (values, vectors) = symmetric_eigen(cov);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| values[b].total_cmp(&values[a]));
    let axes = order.map(|k| {
        let e = [vectors[0][k], vectors[1][k], vectors[2][k]];
        // Sign rule: the largest component (first on ties) is positive, for reproducible frames.
        let big = (0..3).fold(0, |m, i| if e[i].abs() > e[m].abs() { i } else { m });
        if e[big] < 0.0 { scale(e, -1.0) } else { e }
    });
    (mean, axes)
}

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations: the eigenvalues and
/// the matrix whose columns are the unit eigenvectors.
fn symmetric_eigen(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _sweep in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let diag = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1e-15 * diag || off == 0.0 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // A ← Jᵀ A J with the rotation J in the (p, q) plane; V ← V J.
            for row in a.iter_mut() {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
            a[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
            for row in v.iter_mut() {
                let (vkp, vkq) = (row[p], row[q]);
                row[p] = c * vkp - s * vkq;
                row[q] = s * vkp + c * vkq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

/// Each vertex as (grid x, grid y, height) in a projection, with its placement.
struct Projected {
    points: Vec<[f64; 3]>,
    placement: Placement,
    /// Grid-x period: 2π for the cylindrical angle (triangles across the seam are drawn twice).
    period: Option<f64>,
    /// World length of one unit of grid x (mean radius for the angle), for the automatic size.
    x_unit: f64,
}

/// Candidate normals for the planar projection: the area-weighted mean of the triangle normals
/// — the direction in which the surface's signed projected area is largest — when it is well
/// defined (not for closed or inconsistently wound meshes); the PCA normal (smallest-variance
/// axis) turned to the side most of the surface faces; and the coordinate axis along which the
/// triangles face most consistently one way, because a steep terrain is a height field only
/// along its own vertical axis.
fn planar_normals(mesh: &TriangleMesh) -> Vec<[f64; 3]> {
    let (_, [_, _, e2]) = principal_frame(&mesh.vertices);
    let (mut sum, mut magnitude) = ([0.0; 3], [0.0; 3]);
    let mut area = 0.0;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let n = cross(sub(b, a), sub(c, a));
        for k in 0..3 {
            sum[k] += n[k];
            magnitude[k] += n[k].abs();
        }
        area += dot(n, n).sqrt();
    }
    let length = dot(sum, sum).sqrt();
    let pca = if dot(sum, e2) < 0.0 {
        scale(e2, -1.0)
    } else {
        e2
    };
    let mut normals = Vec::new();
    // Under 5 % of the area facing one way on balance: the mean normal is mostly cancellation.
    if length > 0.05 * area && length.is_finite() {
        normals.push(scale(sum, 1.0 / length));
    }
    normals.push(pca);
    // The axis along which the triangles face most consistently one way: exactly 1 for a
    // height field over that axis's plane, however steep.
    let consistency = |k: usize| sum[k].abs() / magnitude[k].max(f64::MIN_POSITIVE);
    let k = (0..3).fold(0, |m, i| {
        if consistency(i) > consistency(m) {
            i
        } else {
            m
        }
    });
    let mut axis = [0.0; 3];
    axis[k] = if sum[k] < 0.0 { -1.0 } else { 1.0 };
    normals.push(axis);
    // Drop repeats (a flat terrain gives the same normal three times).
    let mut unique: Vec<[f64; 3]> = Vec::new();
    for n in normals {
        if unique.iter().all(|m| dot(*m, n) < 1.0 - 1e-12) {
            unique.push(n);
        }
    }
    unique
}

fn project_planar(mesh: &TriangleMesh, n: [f64; 3]) -> Projected {
    let (mean, [e0, e1, _]) = principal_frame(&mesh.vertices);
    // u: of the coordinate axis most orthogonal to n and the principal axis (each made orthogonal
    // to n), the one whose grid has the smaller bounding box; so a terrain's grid stays aligned
    // with its x axis and a rotated rectangle's with its sides.
    let k = (0..3).fold(0, |m, i| if n[i].abs() < n[m].abs() { i } else { m });
    let mut axis = [0.0; 3];
    axis[k] = 1.0;
    let principal = if dot(e0, n).abs() < 0.9 { e0 } else { e1 };
    let box_area = |u: [f64; 3]| {
        let v = cross(n, u);
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &mesh.vertices {
            let d = sub(*p, mean);
            let q = [dot(d, u), dot(d, v)];
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        }
        (hi[0] - lo[0]) * (hi[1] - lo[1])
    };
    let candidates = [axis, principal].map(|e| {
        let w = sub(e, scale(n, dot(e, n)));
        scale(w, 1.0 / dot(w, w).sqrt())
    });
    // Relative slack so that equal boxes (up to rounding) keep the coordinate axis.
    let u = if box_area(candidates[1]) < box_area(candidates[0]) * (1.0 - 1e-9) {
        candidates[1]
    } else {
        candidates[0]
    };
    let v = cross(n, u);
    // Along a coordinate axis the frame is the input's own (origin 0): a terrain keeps its
    // coordinates and heights. Otherwise the frame sits at the mean, away from large offsets.
    let along_axis = n.iter().filter(|c| **c != 0.0).count() == 1;
    let origin = if along_axis { [0.0; 3] } else { mean };
    let points = mesh
        .vertices
        .iter()
        .map(|p| {
            let d = sub(*p, origin);
            [dot(d, u), dot(d, v), dot(d, n)]
        })
        .collect();
    Projected {
        points,
        placement: Placement::Planar { origin, u, v, n },
        period: None,
        x_unit: 1.0,
    }
}

fn project_cylindrical(mesh: &TriangleMesh) -> Projected {
    let (mean, [axis, reference, _]) = principal_frame(&mesh.vertices);
    let side = cross(axis, reference);
    let mut points: Vec<[f64; 3]> = mesh
        .vertices
        .iter()
        .map(|p| {
            let d = sub(*p, mean);
            let zeta = dot(d, axis);
            let radial = sub(d, scale(axis, zeta));
            let rho = dot(radial, radial).sqrt();
            [dot(d, side).atan2(dot(d, reference)), zeta, rho]
        })
        .collect();
    // The seam goes in the middle of the widest angular gap; angles then run from its far side.
    let mut angles: Vec<f64> = points.iter().map(|p| p[0]).collect();
    angles.sort_by(f64::total_cmp);
    let mut start = angles[0];
    let mut widest = angles[0] + TAU - angles[angles.len() - 1];
    for pair in angles.windows(2) {
        if pair[1] - pair[0] > widest {
            widest = pair[1] - pair[0];
            start = pair[1];
        }
    }
    for p in &mut points {
        p[0] = start + (p[0] - start).rem_euclid(TAU);
    }
    let mean_rho = points.iter().map(|p| p[2]).sum::<f64>() / points.len() as f64;
    Projected {
        points,
        placement: Placement::Cylindrical {
            origin: mean,
            axis,
            reference,
        },
        period: Some(TAU),
        x_unit: mean_rho.max(f64::MIN_POSITIVE),
    }
}

/// Grid size with about one point per vertex and the projected extent's aspect ratio, each side
/// in `2..=DEFAULT_MAX_SIDE`.
fn automatic_size(vertices: usize, world_x: f64, world_y: f64) -> (usize, usize) {
    let aspect = world_x / world_y;
    let side = |s: f64| (s.round() as usize).clamp(2, DEFAULT_MAX_SIDE);
    let n = vertices as f64;
    (side((n * aspect).sqrt()), side((n / aspect).sqrt()))
}

/// The projection that shows a closed or thick mesh's outer surface best: planar (seen from
/// above) when the mesh is flat — its smallest principal variance under a quarter of the middle
/// one, like a terrain slab with a base — otherwise cylindrical, which sees a round object from
/// all sides instead of one.
pub(super) fn outer_projection(mesh: &TriangleMesh) -> Projection {
    let (_, cov) = covariance(&mesh.vertices);
    let (mut values, _) = symmetric_eigen(cov);
    values.sort_by(f64::total_cmp);
    if values[0] < 0.25 * values[1] {
        Projection::Planar
    } else {
        Projection::Cylindrical
    }
}

/// Projects `mesh` (validated, with triangles) and rasterises it onto a grid of `size` (or the
/// automatic size). The planar projection tries each candidate normal (`planar_normals`) and
/// keeps the one with the least overlap. When every candidate folds and the outer surface is
/// asked for, the outermost hits are kept instead: around the principal axis, or along the PCA
/// normal signed so that its largest component is positive (a slab lying in x, y is seen from
/// +z) — the candidates' facing rules mean nothing for a closed surface. Fails only on a grid
/// size over the limits.
pub(super) fn resample(
    mesh: &TriangleMesh,
    projection: Projection,
    size: Option<(usize, usize)>,
    surface: Surface,
) -> Result<Outcome, ImportError> {
    let single = resample_single(mesh, projection, size)?;
    if surface == Surface::Single || matches!(single, Outcome::Grid(_)) {
        return Ok(single);
    }
    let projected = match projection {
        Projection::Cylindrical => project_cylindrical(mesh),
        _ => {
            let (_, [_, _, normal]) = principal_frame(&mesh.vertices);
            project_planar(mesh, normal)
        }
    };
    resample_projected(mesh, projected, size, Surface::Outer)
}

fn resample_single(
    mesh: &TriangleMesh,
    projection: Projection,
    size: Option<(usize, usize)>,
) -> Result<Outcome, ImportError> {
    let candidates: Vec<Projected> = match projection {
        Projection::Cylindrical => vec![project_cylindrical(mesh)],
        _ => planar_normals(mesh)
            .into_iter()
            .map(|n| project_planar(mesh, n))
            .collect(),
    };
    // Every candidate is tried; the one with the least overlap wins (the first on ties).
    let mut best: Option<Resampled> = None;
    let mut least: Option<f64> = None;
    for projected in candidates {
        match resample_projected(mesh, projected, size, Surface::Single)? {
            Outcome::Grid(grid) => {
                if best.as_ref().is_none_or(|b| grid.overlap < b.overlap) {
                    best = Some(grid);
                }
            }
            Outcome::Folded { overlap } => {
                least = match (least, overlap) {
                    (Some(a), Some(b)) => Some(a.min(b)),
                    (a, b) => a.or(b),
                }
            }
        }
    }
    Ok(match best {
        Some(grid) => Outcome::Grid(grid),
        None => Outcome::Folded { overlap: least },
    })
}

/// Resamples `mesh` (validated, with triangles) by planar projection along the unit normal `n`
/// — used for a mesh that is already a grid in its own (x, y) plane, to give it another size.
pub(super) fn resample_along(
    mesh: &TriangleMesh,
    n: [f64; 3],
    size: Option<(usize, usize)>,
) -> Result<Outcome, ImportError> {
    resample_projected(mesh, project_planar(mesh, n), size, Surface::Single)
}

fn resample_projected(
    mesh: &TriangleMesh,
    projected: Projected,
    size: Option<(usize, usize)>,
    surface: Surface,
) -> Result<Outcome, ImportError> {
    let points = &projected.points;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let extent = [hi[0] - lo[0], hi[1] - lo[1]];
    if !(extent[0] > 0.0 && extent[1] > 0.0 && extent.iter().all(|e| e.is_finite())) {
        return Ok(Outcome::Folded { overlap: None });
    }
    let (width, height) = match size {
        Some(s) => s,
        None => automatic_size(mesh.vertices.len(), extent[0] * projected.x_unit, extent[1]),
    };
    crate::heightfield::check_size(width, height)?;
    let spacing = [
        extent[0] / (width - 1) as f64,
        extent[1] / (height - 1) as f64,
    ];
    let raster = rasterise(mesh, &projected, lo, spacing, width, height)?;
    let covered = raster.inside_once;
    if covered == 0 && raster.z.iter().all(|z| z.is_nan()) {
        return Ok(Outcome::Folded { overlap: None });
    }
    let overlap = if covered == 0 {
        0.0
    } else {
        raster.inside_twice as f64 / covered as f64
    };
    if overlap > MAX_OVERLAP && surface == Surface::Single {
        return Ok(Outcome::Folded {
            overlap: Some(overlap),
        });
    }
    let mut z = raster.z;
    let filled = fill_nearest(&mut z, width, height);
    Ok(Outcome::Grid(Resampled {
        width,
        height,
        z,
        origin: lo,
        spacing,
        placement: projected.placement,
        filled,
        overlap,
        covered_twice: raster.inside_twice,
    }))
}

struct Raster {
    /// Highest height per grid point, NaN where no triangle lands.
    z: Vec<f64>,
    /// Grid points strictly inside at least one triangle.
    inside_once: usize,
    /// Grid points strictly inside two or more triangles.
    inside_twice: usize,
}

/// Barycentric tolerance: a point this close outside an edge still counts as on it.
const ON_EDGE: f64 = 1e-9;

/// Most grid points one rasterisation may test, summed over the triangles' bounding boxes: the
/// larger of this and [`MAX_BOX_COVER`] times the grid. A surface's triangles tile the grid a
/// few times over at most; many long triangles lying across each other (a few MB of them can
/// ask for billions of tests) are refused instead of taking minutes.
pub(super) const MIN_RASTER_TESTS: u64 = 1 << 26;
/// See [`MIN_RASTER_TESTS`].
pub(super) const MAX_BOX_COVER: u64 = 64;

fn rasterise(
    mesh: &TriangleMesh,
    projected: &Projected,
    lo: [f64; 2],
    spacing: [f64; 2],
    width: usize,
    height: usize,
) -> Result<Raster, ImportError> {
    let limit = MIN_RASTER_TESTS.max(MAX_BOX_COVER * (width * height) as u64);
    let mut tests: u64 = 0;
    let mut z = vec![f64::NAN; width * height];
    let mut inside = vec![0u8; width * height];
    // In grid units: x = column, y = row (fractional).
    let to_grid = |p: [f64; 3]| {
        [
            (p[0] - lo[0]) / spacing[0],
            (p[1] - lo[1]) / spacing[1],
            p[2],
        ]
    };
    for t in &mesh.triangles {
        let mut corners = t.map(|i| to_grid(projected.points[i as usize]));
        let mut shifts = vec![0.0];
        if let Some(period) = projected.period {
            // A triangle across the seam: bring its low-angle corners round, then draw it both at
            // the grid's far end and one period back at its near end.
            let xs = corners.map(|c| c[0] * spacing[0]);
            let (min, max) = (
                xs.iter().copied().fold(f64::INFINITY, f64::min),
                xs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            );
            if max - min > PI {
                for c in &mut corners {
                    if c[0] * spacing[0] - min < PI {
                        c[0] += period / spacing[0];
                    }
                }
                shifts.push(-period / spacing[0]);
            }
        }
        for shift in shifts {
            let c = corners.map(|c| [c[0] + shift, c[1], c[2]]);
            tests += draw_triangle(&c, width, height, &mut z, &mut inside);
            if tests > limit {
                return Err(ImportError::RasterLimit {
                    width,
                    height,
                    limit,
                });
            }
        }
    }
    let inside_once = inside.iter().filter(|&&k| k >= 1).count();
    let inside_twice = inside.iter().filter(|&&k| k >= 2).count();
    Ok(Raster {
        z,
        inside_once,
        inside_twice,
    })
}

/// Draws one triangle given in grid units (x, y, height): keeps the highest height per point and
/// counts strict insides. Returns how many grid points it tested (its bounding box on the grid).
fn draw_triangle(
    c: &[[f64; 3]; 3],
    width: usize,
    height: usize,
    z: &mut [f64],
    inside: &mut [u8],
) -> u64 {
    let [a, b, d] = c;
    let area2 = (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]);
    if area2.is_nan() || area2.abs() <= 1e-12 {
        // Edge-on in this projection (or NaN): it covers no area.
        return 0;
    }
    let min_x = a[0].min(b[0]).min(d[0]);
    let max_x = a[0].max(b[0]).max(d[0]);
    let min_y = a[1].min(b[1]).min(d[1]);
    let max_y = a[1].max(b[1]).max(d[1]);
    let slack = 1e-7;
    if max_x < -slack || max_y < -slack {
        return 0;
    }
    let x0 = (min_x - slack).ceil().max(0.0) as usize;
    let y0 = (min_y - slack).ceil().max(0.0) as usize;
    let x1 = ((max_x + slack).floor() as usize).min(width - 1);
    let y1 = ((max_y + slack).floor() as usize).min(height - 1);
    for y in y0..=y1 {
        for x in x0..=x1 {
            let (px, py) = (x as f64, y as f64);
            // Barycentric weights from the edge functions, normalised by twice the signed area.
            let l0 = ((b[0] - px) * (d[1] - py) - (b[1] - py) * (d[0] - px)) / area2;
            let l1 = ((d[0] - px) * (a[1] - py) - (d[1] - py) * (a[0] - px)) / area2;
            let l2 = 1.0 - l0 - l1;
            if l0 < -ON_EDGE || l1 < -ON_EDGE || l2 < -ON_EDGE {
                continue;
            }
            let i = y * width + x;
            let h = l0 * a[2] + l1 * b[2] + l2 * d[2];
            if z[i].is_nan() || h > z[i] {
                z[i] = h;
            }
            if l0 > ON_EDGE && l1 > ON_EDGE && l2 > ON_EDGE {
                inside[i] = inside[i].saturating_add(1);
            }
        }
    }
    ((x1 + 1).saturating_sub(x0) * (y1 + 1).saturating_sub(y0)) as u64
}

/// Fills NaN points with the value of the nearest non-NaN point in 4-neighbour steps (ties: the
/// one reached first from the lower grid index); returns how many were filled. At least one
/// point must be non-NaN.
pub fn fill_nearest(z: &mut [f64], width: usize, height: usize) -> usize {
    let filled = z.iter().filter(|v| v.is_nan()).count();
    if filled > 0 {
        super::fill::spread_nearest(z, width, height, |_, _| {});
    }
    filled
}

/// Weights of the source samples `0..from` that a target sample of a `to`-point axis averages:
/// `(first source index, weights)` per target sample. Both axes span the same extent with their
/// end points on each other; each source sample stands for a cell one spacing wide around it, and
/// each target sample averages the source cells over the width of its own cell, by overlap length.
fn box_weights(from: usize, to: usize) -> Vec<(usize, Vec<f64>)> {
    let ratio = (from - 1) as f64 / (to - 1) as f64;
    // Never narrower than one source cell, so that enlarging interpolates between neighbours.
    let half = (ratio / 2.0).max(0.5);
    (0..to)
        .map(|t| {
            let centre = t as f64 * ratio;
            let lo = (centre - half).max(-0.5);
            let hi = (centre + half).min(from as f64 - 0.5);
            let first = ((lo + 0.5).floor().max(0.0) as usize).min(from - 1);
            let last = ((hi + 0.5).ceil() as usize).clamp(first + 1, from);
            let mut weights: Vec<f64> = (first..last)
                .map(|s| ((s as f64 + 0.5).min(hi) - (s as f64 - 0.5).max(lo)).max(0.0))
                .collect();
            let sum: f64 = weights.iter().sum();
            if sum > 0.0 {
                weights.iter_mut().for_each(|w| *w /= sum);
            } else {
                weights = vec![1.0];
            }
            (first, weights)
        })
        .collect()
}

/// Resamples a `width × height` grid (row-major, all finite) to `to_width × to_height` by area
/// averaging: each target point is the mean of the source over its own cell, the source's
/// samples weighted by how much of their cell falls inside. The corner points stay on the
/// corners, so the grid keeps its extent; both grids need at least 2 points per side.
pub(super) fn area_average(
    z: &[f64],
    width: usize,
    height: usize,
    to_width: usize,
    to_height: usize,
) -> Vec<f64> {
    let along_x = box_weights(width, to_width);
    let along_y = box_weights(height, to_height);
    // Separable: rows first (height × to_width), then columns.
    let mut rows = vec![0.0; height * to_width];
    for y in 0..height {
        let source = &z[y * width..(y + 1) * width];
        for (t, (first, weights)) in along_x.iter().enumerate() {
            rows[y * to_width + t] = weights
                .iter()
                .enumerate()
                .map(|(k, w)| w * source[first + k])
                .sum();
        }
    }
    let mut out = vec![0.0; to_width * to_height];
    for (t, (first, weights)) in along_y.iter().enumerate() {
        for x in 0..to_width {
            out[t * to_width + x] = weights
                .iter()
                .enumerate()
                .map(|(k, w)| w * rows[(first + k) * to_width + x])
                .sum();
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn area_average_halves_a_grid_by_cell_means() {
        // 5 → 3 points per side: each target cell is two source cells wide; the middle target
        // averages source 1 (half), 2 (whole), 3 (half); the ends keep half a cell inside.
        let z: Vec<f64> = (0..25).map(|i| (i % 5) as f64).collect();
        let out = area_average(&z, 5, 5, 3, 3);
        let expected_row = [
            (0.0 + 0.5 * 1.0) / 1.5,
            (0.5 * 1.0 + 2.0 + 0.5 * 3.0) / 2.0,
            (0.5 * 3.0 + 4.0) / 1.5,
        ];
        for y in 0..3 {
            for x in 0..3 {
                assert!((out[y * 3 + x] - expected_row[x]).abs() < 1e-12, "{out:?}");
            }
        }
    }

    #[test]
    fn area_average_keeps_a_plane_and_the_same_size() {
        // A plane stays a plane inside (symmetric weights), and the same size is the identity.
        let z: Vec<f64> = (0..7 * 4)
            .map(|i| (i % 7) as f64 * 2.0 + (i / 7) as f64)
            .collect();
        assert_eq!(area_average(&z, 7, 4, 7, 4), z);
        let small = area_average(&z, 7, 4, 4, 4);
        assert!((small[1] - (2.0 * 2.0)).abs() < 1e-12, "{small:?}");
        assert!((small[2] - (4.0 * 2.0)).abs() < 1e-12, "{small:?}");
    }

    #[test]
    fn jacobi_finds_axis_aligned_eigenvectors() {
        // Variances 9, 4, 1 along z, x, y: the frame must come out as z, x, y.
        let (values, vectors) =
            symmetric_eigen([[4.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 9.0]]);
        assert_eq!(values, [4.0, 1.0, 9.0]);
        assert_eq!(vectors, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    }

    #[test]
    fn jacobi_diagonalises_a_full_matrix() {
        // A symmetric matrix with all off-diagonals set: A·v = λ·v must hold for each pair.
        let a = [[2.0, 1.0, 0.5], [1.0, 3.0, 0.25], [0.5, 0.25, 1.0]];
        let (values, v) = symmetric_eigen(a);
        for k in 0..3 {
            let e = [v[0][k], v[1][k], v[2][k]];
            for i in 0..3 {
                let av = a[i][0] * e[0] + a[i][1] * e[1] + a[i][2] * e[2];
                assert!((av - values[k] * e[i]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn fill_takes_the_nearest_covered_value() {
        // 4×1 row: covered at both ends; the inner points take their nearer end.
        let mut z = [
            1.0,
            f64::NAN,
            f64::NAN,
            5.0,
            f64::NAN,
            f64::NAN,
            f64::NAN,
            f64::NAN,
        ];
        let filled = fill_nearest(&mut z, 4, 2);
        assert_eq!(filled, 6);
        assert_eq!(z, [1.0, 1.0, 5.0, 5.0, 1.0, 1.0, 5.0, 5.0]);
    }
}
