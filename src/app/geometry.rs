//! Vertex data for the 3-D view, built on the CPU: the simplified mesh (flat shaded), its
//! wireframe, the original surface, the per-point error colours and the kept-vertex markers.
//!
//! The view works in normalised coordinates: the grid's longer side spans 1, centred on the
//! origin, north (row 0) at +y, and the relief spans [`RELIEF`] so every surface is visible at
//! the same camera distance. Exports use the input's own coordinates instead.

use crate::heightfield::Heightfield;
use bytemuck::{Pod, Zeroable};

/// Height of the relief in view units (the grid's longer side is 1).
pub(crate) const RELIEF: f32 = 0.3;
/// At most this many cells per side of the original surface are drawn; larger grids are drawn
/// with a stride (the statistics always describe the full grid).
pub(crate) const MAX_DRAWN_SIDE: usize = 512;

/// One vertex: position, normal (zero = unlit) and RGBA colour.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub(crate) struct Vertex {
    /// Position in view units.
    pub position: [f32; 3],
    /// Normal; the zero vector draws the colour unlit.
    pub normal: [f32; 3],
    /// Linear RGBA.
    pub colour: [f32; 4],
}

/// Indexed geometry of one layer.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Geometry {
    /// Vertices.
    pub vertices: Vec<Vertex>,
    /// Indices into `vertices` (triples for triangles, pairs for lines).
    pub indices: Vec<u32>,
}

/// Maps grid points to view coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ViewMapping {
    width: usize,
    scale: f32,
    half: [f32; 2],
    z_mid: f64,
    z_scale: f64,
}

impl ViewMapping {
    /// The mapping for `hf`.
    pub(crate) fn new(hf: &Heightfield) -> Self {
        let (lo, hi) = hf.z_range();
        let side = (hf.width().max(hf.height()) - 1) as f32;
        let span = hi - lo;
        Self {
            width: hf.width(),
            scale: 1.0 / side,
            half: [
                (hf.width() - 1) as f32 / 2.0,
                (hf.height() - 1) as f32 / 2.0,
            ],
            z_mid: (lo + hi) / 2.0,
            z_scale: if span > 0.0 {
                RELIEF as f64 / span
            } else {
                0.0
            },
        }
    }

    /// View position of grid point `index` at height `z`.
    pub(crate) fn position(&self, index: u32, z: f64) -> [f32; 3] {
        let (x, y) = (index as usize % self.width, index as usize / self.width);
        [
            (x as f32 - self.half[0]) * self.scale,
            (self.half[1] - y as f32) * self.scale,
            ((z - self.z_mid) * self.z_scale) as f32,
        ]
    }

    /// Size of one grid step in view units.
    pub(crate) fn step(&self) -> f32 {
        self.scale
    }
}

fn face_normal(p: [[f32; 3]; 3]) -> [f32; 3] {
    let u = [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]];
    let v = [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]];
    let n = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len > 0.0 {
        n.map(|c| c / len)
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// The triangles (grid-index triples) flat shaded in `colour`: three vertices per triangle so
/// each face has its own normal.
pub(crate) fn flat_mesh(
    hf: &Heightfield,
    map: &ViewMapping,
    triangles: &[[u32; 3]],
    colour: [f32; 4],
) -> Geometry {
    let mut g = Geometry::default();
    g.vertices.reserve(triangles.len() * 3);
    for tri in triangles {
        let p = tri.map(|i| map.position(i, hf.z()[i as usize]));
        let normal = face_normal(p);
        for position in p {
            g.indices.push(g.vertices.len() as u32);
            g.vertices.push(Vertex {
                position,
                normal,
                colour,
            });
        }
    }
    g
}

/// Every edge of the triangles once, as unlit lines in `colour`.
pub(crate) fn wireframe(
    hf: &Heightfield,
    map: &ViewMapping,
    triangles: &[[u32; 3]],
    colour: [f32; 4],
) -> Geometry {
    let mut edges: Vec<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b), a.max(b)))
        .collect();
    edges.sort_unstable();
    edges.dedup();
    let mut g = Geometry::default();
    let mut slot = std::collections::BTreeMap::new();
    for (a, b) in edges {
        for i in [a, b] {
            let k = *slot.entry(i).or_insert_with(|| {
                g.vertices.push(Vertex {
                    position: map.position(i, hf.z()[i as usize]),
                    normal: [0.0; 3],
                    colour,
                });
                g.vertices.len() as u32 - 1
            });
            g.indices.push(k);
        }
    }
    g
}

/// The grid points drawn (every `stride`-th row and column plus the last ones).
fn drawn_lines(n: usize, stride: usize) -> Vec<usize> {
    let mut v: Vec<usize> = (0..n).step_by(stride).collect();
    if *v.last().expect("n >= 2") != n - 1 {
        v.push(n - 1);
    }
    v
}

/// The original surface as a smooth-shaded grid mesh, coloured per point by `colour_of(index)`.
/// Grids over [`MAX_DRAWN_SIDE`] per side are drawn with a stride.
pub(crate) fn grid_surface(
    hf: &Heightfield,
    map: &ViewMapping,
    colour_of: &dyn Fn(usize) -> [f32; 4],
) -> Geometry {
    let stride = hf.width().max(hf.height()).div_ceil(MAX_DRAWN_SIDE).max(1);
    let xs = drawn_lines(hf.width(), stride);
    let ys = drawn_lines(hf.height(), stride);
    let mut g = Geometry::default();
    let w = hf.width();
    let at = |x: usize, y: usize| map.position((y * w + x) as u32, hf.z()[y * w + x]);
    for (j, &y) in ys.iter().enumerate() {
        for (i, &x) in xs.iter().enumerate() {
            // Central differences on the drawn lattice give a smooth normal.
            let xl = xs[i.saturating_sub(1)];
            let xr = xs[(i + 1).min(xs.len() - 1)];
            let yu = ys[j.saturating_sub(1)];
            let yd = ys[(j + 1).min(ys.len() - 1)];
            let dx = sub(at(xr, y), at(xl, y));
            let dy = sub(at(x, yu), at(x, yd));
            let n = cross(dx, dy);
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt().max(1e-12);
            g.vertices.push(Vertex {
                position: at(x, y),
                normal: n.map(|c| c / len),
                colour: colour_of(y * w + x),
            });
        }
    }
    let cols = xs.len() as u32;
    for j in 0..ys.len() as u32 - 1 {
        for i in 0..cols - 1 {
            let a = j * cols + i;
            let (b, c, d) = (a + 1, a + cols, a + cols + 1);
            g.indices.extend_from_slice(&[a, c, b, b, c, d]);
        }
    }
    g
}

/// A small octahedron at every kept point, unlit, `size` view units across.
pub(crate) fn markers(
    hf: &Heightfield,
    map: &ViewMapping,
    kept: &[u32],
    size: f32,
    colour: [f32; 4],
) -> Geometry {
    const DIRS: [[f32; 3]; 6] = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    const FACES: [[u32; 3]; 8] = [
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    let mut g = Geometry::default();
    let r = size / 2.0;
    for &i in kept {
        let c = map.position(i, hf.z()[i as usize]);
        let base = g.vertices.len() as u32;
        for d in DIRS {
            g.vertices.push(Vertex {
                position: [c[0] + d[0] * r, c[1] + d[1] * r, c[2] + d[2] * r],
                normal: [0.0; 3],
                colour,
            });
        }
        for f in FACES {
            g.indices.extend(f.iter().map(|k| base + k));
        }
    }
    g
}

/// The error colour map (dark blue → teal → yellow → red) at `t` in 0..=1, linear RGBA.
pub(crate) fn error_colour(t: f64) -> [f32; 4] {
    const STOPS: [[f32; 3]; 4] = [
        [0.05, 0.10, 0.45],
        [0.10, 0.60, 0.60],
        [0.95, 0.85, 0.15],
        [0.85, 0.10, 0.10],
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0) as f32
    } else {
        0.0
    };
    let x = t * (STOPS.len() - 1) as f32;
    let k = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - k as f32;
    let c: [f32; 3] = std::array::from_fn(|i| STOPS[k][i] * (1.0 - f) + STOPS[k + 1][i] * f);
    [c[0], c[1], c[2], 1.0]
}

/// The CSS gradient of [`error_colour`], for the legend.
pub(crate) fn error_legend_css() -> String {
    let stops: Vec<String> = (0..=4)
        .map(|k| {
            let c = error_colour(k as f64 / 4.0);
            format!(
                "rgb({},{},{})",
                (c[0] * 255.0) as u8,
                (c[1] * 255.0) as u8,
                (c[2] * 255.0) as u8
            )
        })
        .collect();
    format!("linear-gradient(to right, {})", stops.join(", "))
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
