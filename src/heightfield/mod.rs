//! The height field z = f(x, y) sampled on a regular W×H grid. Files become height fields in
//! [`crate::import`].
//!
//! Grid point `(x, y)` (x = column, y = row) has index `y * width + x`; every other module speaks
//! in these indices. [`Placement`] remembers how the grid sits in the input's 3-D space so that a
//! simplified mesh can be exported in the input's own coordinates.

use std::fmt;

/// Smallest grid side: a 2×2 grid is the smallest surface with a triangle.
pub const MIN_SIDE: usize = 2;
/// Largest grid side (2¹⁴): coordinate differences below it keep the exact integer predicates
/// inside `i64` (see `evaluator::exact::predicates`).
pub const MAX_SIDE: usize = 16_384;
/// Largest number of grid points (16 384² = 2²⁸ ≈ 268 M): grid indices and the predicates'
/// index-to-coordinate conversion stay exact in 32/64-bit integers up to it. What a machine's
/// memory holds is checked separately; a browser tab sets its own, lower cap.
pub const MAX_POINTS: usize = MAX_SIDE * MAX_SIDE;

/// How grid coordinates map back to the 3-D space the surface came from.
///
/// Grid coordinates are `gx = origin[0] + x * spacing[0]`, `gy = origin[1] + y * spacing[1]`.
#[derive(Clone, Debug, PartialEq, Default)]
pub enum Placement {
    /// The surface is a height field already: world = (gx, gy, z).
    #[default]
    Grid,
    /// Projection onto a best-fit plane: world = `origin + gx·u + gy·v + z·n`.
    Planar {
        origin: [f64; 3],
        u: [f64; 3],
        v: [f64; 3],
        n: [f64; 3],
    },
    /// Cylindrical unwrap around an axis: θ = gx (radians), ζ = gy, ρ = z.
    /// world = `origin + ζ·axis + ρ·(cos θ·reference + sin θ·(axis × reference))`.
    Cylindrical {
        origin: [f64; 3],
        axis: [f64; 3],
        reference: [f64; 3],
    },
}

/// A GeoTIFF's georeferencing as the file gives it, kept so that `info` and exports can show where
/// the grid lies on the map.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Georeference {
    /// ModelPixelScale (tag 33550): map units per pixel along x, y and z.
    pub pixel_scale: Option<[f64; 3]>,
    /// ModelTiepoint (tag 33922), the first tie point: raster (i, j, k) and map (x, y, z).
    pub tiepoint: Option<[f64; 6]>,
    /// Raster type (GeoKey 1025) is PixelIsPoint: the tie point is a pixel's centre, not its
    /// upper-left corner.
    pub pixel_is_point: bool,
    /// GDAL_NODATA (tag 42113) as written in the file.
    pub nodata: Option<String>,
    /// The EPSG code of the map's coordinate reference system: ProjectedCSTypeGeoKey (3072)
    /// for a projected map, else GeographicTypeGeoKey (2048); `None` when the file names
    /// neither or a user-defined one.
    pub epsg: Option<u16>,
}

/// Why a height field could not be built.
#[derive(Clone, Debug, PartialEq)]
pub enum HeightfieldError {
    /// A side is under [`MIN_SIDE`].
    TooSmall { width: usize, height: usize },
    /// A side is over [`MAX_SIDE`] or the grid has more than [`MAX_POINTS`] points.
    TooLarge { width: usize, height: usize },
    /// `z.len()` is not `width * height`.
    WrongLength { expected: usize, found: usize },
    /// A z value is NaN or infinite.
    NotFinite { index: usize },
    /// A spacing is not a positive finite number.
    BadSpacing { dx: f64, dy: f64 },
}

impl fmt::Display for HeightfieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooSmall { width, height } => write!(
                f,
                "the grid is {width}×{height}; a height field needs at least {MIN_SIDE}×{MIN_SIDE} points"
            ),
            Self::TooLarge { width, height } => write!(
                f,
                "this grid has {}×{} = {:.1} M points; the exact integer predicates hold at most {:.1} M points and {} per side; choose a smaller grid size",
                width,
                height,
                (*width as f64) * (*height as f64) / 1e6,
                MAX_POINTS as f64 / 1e6,
                MAX_SIDE
            ),
            Self::WrongLength { expected, found } => write!(
                f,
                "expected {expected} height values for the grid, found {found}"
            ),
            Self::NotFinite { index } => write!(
                f,
                "height value at grid point {index} is not a finite number (NaN or infinity)"
            ),
            Self::BadSpacing { dx, dy } => {
                write!(
                    f,
                    "grid spacing must be positive and finite, got dx={dx}, dy={dy}"
                )
            }
        }
    }
}

impl std::error::Error for HeightfieldError {}

/// Checks a grid size against [`MIN_SIDE`], [`MAX_SIDE`] and [`MAX_POINTS`] before anything is
/// allocated for it.
pub fn check_size(width: usize, height: usize) -> Result<(), HeightfieldError> {
    if width < MIN_SIDE || height < MIN_SIDE {
        return Err(HeightfieldError::TooSmall { width, height });
    }
    if width > MAX_SIDE || height > MAX_SIDE || width.saturating_mul(height) > MAX_POINTS {
        return Err(HeightfieldError::TooLarge { width, height });
    }
    Ok(())
}

/// A height field: `width × height` finite z values, row-major, with spacing and provenance.
///
/// ```
/// use paretomesh::heightfield::Heightfield;
/// let hf = Heightfield::new(3, 2, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0]).unwrap();
/// assert_eq!(hf.len(), 6);
/// assert_eq!(hf.z_at(2, 1), 5.0);
/// assert_eq!(hf.corners(), [0, 2, 3, 5]);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Heightfield {
    width: usize,
    height: usize,
    z: Vec<f64>,
    /// (min z, max z), found once: the evaluator's error units depend on it.
    z_range: (f64, f64),
    origin: [f64; 2],
    spacing: [f64; 2],
    placement: Placement,
    source: String,
    filled: usize,
    resampled: bool,
    georeference: Option<Georeference>,
}

impl Heightfield {
    /// A grid with unit spacing at the origin. Fails on a bad size or a non-finite value.
    pub fn new(width: usize, height: usize, z: Vec<f64>) -> Result<Self, HeightfieldError> {
        check_size(width, height)?;
        if z.len() != width * height {
            return Err(HeightfieldError::WrongLength {
                expected: width * height,
                found: z.len(),
            });
        }
        if let Some(index) = z.iter().position(|v| !v.is_finite()) {
            return Err(HeightfieldError::NotFinite { index });
        }
        let z_range = z
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        Ok(Self {
            width,
            height,
            z,
            z_range,
            origin: [0.0, 0.0],
            spacing: [1.0, 1.0],
            placement: Placement::Grid,
            source: String::new(),
            filled: 0,
            resampled: false,
            georeference: None,
        })
    }

    /// Sets the grid coordinates of point (0, 0) and the x/y spacing.
    pub fn with_geometry(
        mut self,
        origin: [f64; 2],
        spacing: [f64; 2],
    ) -> Result<Self, HeightfieldError> {
        let [dx, dy] = spacing;
        if !(dx.is_finite() && dy.is_finite() && dx > 0.0 && dy > 0.0) {
            return Err(HeightfieldError::BadSpacing { dx, dy });
        }
        self.origin = origin;
        self.spacing = spacing;
        Ok(self)
    }

    /// Sets how the grid maps back to 3-D.
    pub fn with_placement(mut self, placement: Placement) -> Self {
        self.placement = placement;
        self
    }

    /// Sets the human-readable note on how the grid was made.
    pub fn with_source(mut self, source: impl Into<String>) -> Self {
        self.source = source.into();
        self
    }

    /// Records how many grid points were filled from their nearest valid neighbour.
    pub fn with_filled(mut self, filled: usize) -> Self {
        self.filled = filled;
        self
    }

    /// Keeps the georeferencing the grid was read with.
    pub(crate) fn with_georeference(mut self, georeference: Georeference) -> Self {
        self.georeference = Some(georeference);
        self
    }

    /// The GeoTIFF georeferencing the grid was read with, if any.
    pub fn georeference(&self) -> Option<&Georeference> {
        self.georeference.as_ref()
    }

    /// Marks the grid as made by rasterising a mesh (not read as is), so an app can offer the
    /// projection and grid-size choice again.
    pub(crate) fn with_resampled(mut self) -> Self {
        self.resampled = true;
        self
    }

    /// True when the grid was made by rasterising a mesh onto a grid (planar, cylindrical or
    /// in the mesh's own plane at another size); false for grids read as they are.
    pub fn resampled(&self) -> bool {
        self.resampled
    }

    /// Number of columns.
    pub fn width(&self) -> usize {
        self.width
    }
    /// Number of rows.
    pub fn height(&self) -> usize {
        self.height
    }
    /// Number of grid points, N = width × height.
    pub fn len(&self) -> usize {
        self.z.len()
    }
    /// Always false: a height field has at least 2×2 points.
    pub fn is_empty(&self) -> bool {
        self.z.is_empty()
    }
    /// All z values, row-major.
    pub fn z(&self) -> &[f64] {
        &self.z
    }
    /// z at column `x`, row `y`.
    pub fn z_at(&self, x: usize, y: usize) -> f64 {
        self.z[y * self.width + x]
    }
    /// Index of column `x`, row `y`.
    pub fn index(&self, x: usize, y: usize) -> u32 {
        (y * self.width + x) as u32
    }
    /// (column, row) of an index.
    pub fn coords(&self, index: u32) -> (usize, usize) {
        let i = index as usize;
        (i % self.width, i / self.width)
    }
    /// The four corner indices in increasing order: (0,0), (W−1,0), (0,H−1), (W−1,H−1).
    pub fn corners(&self) -> [u32; 4] {
        let (w, h) = (self.width, self.height);
        [0, (w - 1) as u32, ((h - 1) * w) as u32, (h * w - 1) as u32]
    }
    /// (min z, max z).
    pub fn z_range(&self) -> (f64, f64) {
        self.z_range
    }
    /// Grid coordinates of point (0, 0).
    pub fn origin(&self) -> [f64; 2] {
        self.origin
    }
    /// x and y spacing between neighbouring grid points.
    pub fn spacing(&self) -> [f64; 2] {
        self.spacing
    }
    /// How the grid maps back to 3-D.
    pub fn placement(&self) -> &Placement {
        &self.placement
    }
    /// How the grid was made (file, format, resampling), for people.
    pub fn source(&self) -> &str {
        &self.source
    }
    /// How many grid points were filled from their nearest valid neighbour: points no triangle
    /// covered when a mesh was resampled, or a GeoTIFF's nodata cells.
    pub fn filled(&self) -> usize {
        self.filled
    }
    /// Number of triangles of the full-resolution grid mesh: 2·(W−1)·(H−1).
    pub fn full_triangles(&self) -> usize {
        2 * (self.width - 1) * (self.height - 1)
    }

    /// The 3-D position of grid point `index` lifted to height `z`, in the input's own coordinates.
    pub fn to_world(&self, index: u32, z: f64) -> [f64; 3] {
        let (x, y) = self.coords(index);
        let gx = self.origin[0] + x as f64 * self.spacing[0];
        let gy = self.origin[1] + y as f64 * self.spacing[1];
        match &self.placement {
            Placement::Grid => [gx, gy, z],
            Placement::Planar { origin, u, v, n } => {
                std::array::from_fn(|k| origin[k] + gx * u[k] + gy * v[k] + z * n[k])
            }
            Placement::Cylindrical {
                origin,
                axis,
                reference,
            } => {
                let side = cross(*axis, *reference);
                let (s, c) = gx.sin_cos();
                std::array::from_fn(|k| {
                    origin[k] + gy * axis[k] + z * (c * reference[k] + s * side[k])
                })
            }
        }
    }
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_grids_under_two_by_two() {
        // A 1×5 strip has no triangle at all.
        assert_eq!(
            Heightfield::new(1, 5, vec![0.0; 5]).unwrap_err(),
            HeightfieldError::TooSmall {
                width: 1,
                height: 5
            }
        );
    }

    #[test]
    fn rejects_non_finite_values() {
        let err = Heightfield::new(2, 2, vec![0.0, f64::NAN, 0.0, 0.0]).unwrap_err();
        assert_eq!(err, HeightfieldError::NotFinite { index: 1 });
        assert!(err.to_string().contains("grid point 1"));
    }

    #[test]
    fn rejects_oversized_grids_before_allocating() {
        assert!(check_size(16_384, 16_384).is_ok());
        let err = check_size(16_385, 16_384).unwrap_err();
        assert!(err.to_string().contains("268.4 M points"), "{err}");
        assert!(
            err.to_string().contains("exact integer predicates"),
            "{err}"
        );
    }

    #[test]
    fn cylindrical_placement_maps_theta_and_rho() {
        // θ = π/2, ζ = 2, ρ = 3 around the z axis with reference x: the point is (0, 3, 2).
        let hf = Heightfield::new(2, 2, vec![0.0; 4])
            .unwrap()
            .with_geometry([std::f64::consts::FRAC_PI_2, 2.0], [1.0, 1.0])
            .unwrap()
            .with_placement(Placement::Cylindrical {
                origin: [0.0; 3],
                axis: [0.0, 0.0, 1.0],
                reference: [1.0, 0.0, 0.0],
            });
        let p = hf.to_world(0, 3.0);
        assert!((p[0]).abs() < 1e-12 && (p[1] - 3.0).abs() < 1e-12 && (p[2] - 2.0).abs() < 1e-12);
    }
}
