//! A simplified surface closed into a printable solid: the surface on top, vertical walls down
//! from its border vertices, and a flat bottom triangulated from those border vertices alone
//! (no full-resolution bottom). A cylindrical unwrap is closed differently: its seam is stitched
//! across the angular gap and its two end rings are capped by fans to the axis. The result is
//! closed, manifold and consistently oriented with outward normals, so slicers print it as it is.

use super::mesh::{WorldMesh, area_normal};
use crate::evaluator::Triangulation;
use crate::heightfield::{Heightfield, Placement};
use std::collections::{HashMap, HashSet};
use std::fmt;

/// The base height when none is given: this fraction of the scaled z range (of the grid's
/// extent in x and y for a flat surface), enough for a print to hold together.
pub(crate) const DEFAULT_BASE_FRACTION: f64 = 0.05;

/// How the solid is built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolidOptions {
    /// How far the flat bottom lies below the lowest grid point, in output z units (after
    /// `z_scale`); `None` for `DEFAULT_BASE_FRACTION` of the scaled z range. A cylindrical
    /// unwrap has no base and refuses one.
    pub base_height: Option<f64>,
    /// Heights are multiplied by this (1 keeps the input's z units); the radius in a
    /// cylindrical unwrap.
    pub z_scale: f64,
}

impl Default for SolidOptions {
    fn default() -> Self {
        Self {
            base_height: None,
            z_scale: 1.0,
        }
    }
}

/// Why a solid could not be built. The message is for the user.
#[derive(Clone, Debug, PartialEq)]
pub enum SolidError {
    /// The base height is zero, negative or not finite.
    BadBaseHeight(f64),
    /// The z scale is zero, negative or not finite.
    BadZScale(f64),
    /// A base height was given for a cylindrical unwrap, which is closed by caps instead.
    BaseOnCylinder(f64),
    /// An end ring of a cylindrical unwrap keeps fewer than 3 points, so its cap would be flat.
    ThinRing(usize),
    /// The triangles do not have one closed border (a mesh that is not a triangulation of the
    /// grid's rectangle).
    Border(String),
}

impl fmt::Display for SolidError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::BadBaseHeight(h) => write!(
                f,
                "the base height of a solid must be a number greater than 0, got {h}"
            ),
            Self::BadZScale(s) => write!(
                f,
                "the z scale of a solid must be a number greater than 0, got {s}"
            ),
            Self::BaseOnCylinder(h) => write!(
                f,
                "a base height ({h}) applies to a surface over a plane, but this grid is a cylindrical unwrap, closed by caps at its ends; leave out --base-height"
            ),
            Self::ThinRing(n) => write!(
                f,
                "an end of this cylindrical unwrap keeps only {n} points, too few to close it; take a member with more triangles"
            ),
            Self::Border(why) => write!(f, "cannot close the surface into a solid: {why}"),
        }
    }
}

impl std::error::Error for SolidError {}

impl SolidOptions {
    /// Checks the options before anything is built or written.
    pub fn check(&self) -> Result<(), SolidError> {
        if !(self.z_scale.is_finite() && self.z_scale > 0.0) {
            return Err(SolidError::BadZScale(self.z_scale));
        }
        match self.base_height {
            Some(h) if !(h.is_finite() && h > 0.0) => Err(SolidError::BadBaseHeight(h)),
            _ => Ok(()),
        }
    }
}

/// The solid of the mesh with grid-index `triangles` (counter-clockwise in the grid, as the
/// evaluator gives them) over `hf`, in the input's own coordinates.
///
/// Vertices: the surface's (every triangle corner, by increasing grid index), then one bottom
/// vertex per border vertex. Faces: the surface, two per border edge for the wall, and the
/// bottom. The faces point outwards (the signed volume is positive), also for a planar
/// projection whose axes are mirrored.
pub fn solid(
    hf: &Heightfield,
    triangles: &[[u32; 3]],
    options: &SolidOptions,
) -> Result<WorldMesh, SolidError> {
    options.check()?;
    if matches!(hf.placement(), Placement::Cylindrical { .. }) {
        return match options.base_height {
            Some(h) => Err(SolidError::BaseOnCylinder(h)),
            None => cylinder(hf, triangles, options.z_scale),
        };
    }
    let mut kept: Vec<u32> = triangles.iter().flatten().copied().collect();
    kept.sort_unstable();
    kept.dedup();
    let local = |g: u32| kept.binary_search(&g).expect("every corner is kept") as u32;
    let border = border_loop(triangles)?;
    let scale = options.z_scale;
    let (lo, hi) = hf.z_range();
    let base_height = options.base_height.unwrap_or_else(|| {
        let range = (hi - lo) * scale;
        let extent = ((hf.width() - 1) as f64 * hf.spacing()[0])
            .max((hf.height() - 1) as f64 * hf.spacing()[1]);
        DEFAULT_BASE_FRACTION * if range > 0.0 { range } else { extent }
    });
    let bottom_z = lo * scale - base_height;

    let mut vertices: Vec<[f64; 3]> = kept
        .iter()
        .map(|&g| hf.to_world(g, hf.z()[g as usize] * scale))
        .collect();
    let top = |k: usize| local(border[k]);
    let first_bottom = vertices.len() as u32;
    vertices.extend(border.iter().map(|&g| hf.to_world(g, bottom_z)));
    let bottom = |k: usize| first_bottom + k as u32;

    let mut faces: Vec<[u32; 3]> = triangles.iter().map(|t| t.map(local)).collect();
    let n = border.len();
    for k in 0..n {
        // The surface runs a → b along its border; the wall runs b → a on top, so each edge
        // is used once in each direction.
        let (a, b) = (k, (k + 1) % n);
        faces.push([top(b), top(a), bottom(a)]);
        faces.push([top(b), bottom(a), bottom(b)]);
    }
    // The bottom is the canonical Delaunay triangulation of the border vertices (the grid's
    // rectangle with points along its sides), counter-clockwise like the surface, so reversed:
    // it faces the other way.
    let mut on_border: Vec<(u32, u32)> = border
        .iter()
        .enumerate()
        .map(|(k, &g)| (g, bottom(k)))
        .collect();
    on_border.sort_unstable();
    let sorted: Vec<u32> = on_border.iter().map(|&(g, _)| g).collect();
    let below = |g: u32| on_border[sorted.binary_search(&g).expect("a border vertex")].1;
    let mut floor = Triangulation::default();
    floor.rebuild_delaunay(hf.width(), &sorted);
    for [a, b, c] in floor.triangles() {
        faces.push([below(a), below(c), below(b)]);
    }
    let mut mesh = WorldMesh {
        vertices,
        triangles: faces,
    };
    if signed_volume(&mesh) < 0.0 {
        for t in &mut mesh.triangles {
            t.swap(1, 2);
        }
    }
    Ok(mesh)
}

/// The solid of a cylindrical unwrap (grid x = angle, grid y = along the axis, z = radius): the
/// surface, a strip across the seam from its last column (largest angle) to its first (the same
/// side of the unwrap's angular gap, one turn on), and on each end ring a fan to the axis. Every
/// ring vertex has its own angle, so each fan is a flat star around the axis that cannot fold.
fn cylinder(
    hf: &Heightfield,
    triangles: &[[u32; 3]],
    z_scale: f64,
) -> Result<WorldMesh, SolidError> {
    let (w, h) = (hf.width() as u32, hf.height() as u32);
    let mut kept: Vec<u32> = triangles.iter().flatten().copied().collect();
    kept.sort_unstable();
    kept.dedup();
    let local = |g: u32| kept.binary_search(&g).expect("every corner is kept") as u32;
    // The seam and the caps follow the grid's rectangle, so the surface's border must be
    // exactly the kept points on it, as one loop.
    let border = border_loop(triangles)?;
    let on_rim = |g: &&u32| {
        let (x, y) = (**g % w, **g / w);
        x == 0 || x == w - 1 || y == 0 || y == h - 1
    };
    if border.len() != kept.iter().filter(on_rim).count() {
        return Err(SolidError::Border(
            "the border does not run along the grid's rectangle".into(),
        ));
    }
    let column = |x: u32| -> Vec<u32> { kept.iter().copied().filter(|g| g % w == x).collect() };
    let row = |y: u32| -> Vec<u32> { kept.iter().copied().filter(|g| g / w == y).collect() };
    let (first, last) = (column(0), column(w - 1));
    let (bottom, top) = (row(0), row(h - 1));
    let thinnest = bottom.len().min(top.len());
    if thinnest < 3 {
        return Err(SolidError::ThinRing(thinnest));
    }

    let mut vertices: Vec<[f64; 3]> = kept
        .iter()
        .map(|&g| hf.to_world(g, hf.z()[g as usize] * z_scale))
        .collect();
    let mut faces: Vec<[u32; 3]> = triangles.iter().map(|t| t.map(local)).collect();
    // The seam strip, counter-clockwise as if the first column lay one column past the last:
    // walk up both columns, always to the lower of the two next points.
    let (mut i, mut j) = (0, 0);
    while i + 1 < last.len() || j + 1 < first.len() {
        let up_last =
            j + 1 == first.len() || (i + 1 < last.len() && last[i + 1] / w <= first[j + 1] / w);
        if up_last {
            faces.push([last[i], first[j], last[i + 1]].map(local));
            i += 1;
        } else {
            faces.push([last[i], first[j], first[j + 1]].map(local));
            j += 1;
        }
    }
    // The surface and the strip run along the bottom ring by increasing angle and along the top
    // ring by decreasing angle; each cap runs the other way, so every edge is used both ways.
    for (ring, forward) in [(bottom, true), (top, false)] {
        let centre = vertices.len() as u32;
        vertices.push(hf.to_world(ring[0], 0.0));
        let n = ring.len();
        for k in 0..n {
            let (a, b) = (ring[k], ring[(k + 1) % n]);
            let (a, b) = if forward { (a, b) } else { (b, a) };
            faces.push([local(b), local(a), centre]);
        }
    }
    let mut mesh = WorldMesh {
        vertices,
        triangles: faces,
    };
    if signed_volume(&mesh) < 0.0 {
        for t in &mut mesh.triangles {
            t.swap(1, 2);
        }
    }
    Ok(mesh)
}

/// The signed volume enclosed by `mesh`'s triangles (positive when they face outwards);
/// meaningful for a closed mesh.
pub fn signed_volume(mesh: &WorldMesh) -> f64 {
    // Relative to the first vertex, so that map coordinates in the millions keep their digits.
    let Some(&o) = mesh.vertices.first() else {
        return 0.0;
    };
    let at = |i: u32| {
        let p = mesh.vertices[i as usize];
        [p[0] - o[0], p[1] - o[1], p[2] - o[2]]
    };
    mesh.triangles
        .iter()
        .map(|&[a, b, c]| {
            let (a, n) = (at(a), area_normal([0.0; 3], at(b), at(c)));
            a[0] * n[0] + a[1] * n[1] + a[2] * n[2]
        })
        .sum::<f64>()
        / 6.0
}

/// The grid indices of the surface's border, in the order the surface runs along it
/// (counter-clockwise for counter-clockwise triangles): the edges no other triangle shares,
/// chained into one loop.
fn border_loop(triangles: &[[u32; 3]]) -> Result<Vec<u32>, SolidError> {
    let mut edges: HashSet<(u32, u32)> = HashSet::with_capacity(3 * triangles.len());
    for t in triangles {
        for k in 0..3 {
            edges.insert((t[k], t[(k + 1) % 3]));
        }
    }
    let mut next: HashMap<u32, u32> = HashMap::new();
    for &(a, b) in &edges {
        if !edges.contains(&(b, a)) && next.insert(a, b).is_some() {
            return Err(SolidError::Border(format!(
                "the border passes through grid point {a} twice"
            )));
        }
    }
    let Some(&start) = next.keys().min() else {
        return Err(SolidError::Border("the surface has no border".into()));
    };
    let mut border = vec![start];
    let mut at = start;
    loop {
        at = next[&at];
        if at == start {
            break;
        }
        if border.len() > next.len() {
            return Err(SolidError::Border("the border does not close".into()));
        }
        border.push(at);
    }
    if border.len() != next.len() {
        return Err(SolidError::Border(format!(
            "the border is in more than one piece ({} of its {} edges form a loop)",
            border.len(),
            next.len()
        )));
    }
    Ok(border)
}
