//! Choices for turning a file into a height field, shared by every parser.

/// Largest accepted share of doubly covered grid points (10 %) for [`Surface::Single`]: small
/// overhangs are resolved by "highest wins", a surface folded over on a larger share is not a
/// height field.
pub(super) const MAX_OVERLAP: f64 = 0.10;

/// How a mesh that is not already a regular grid is turned into one.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Projection {
    /// Use the mesh's own vertices when they form an exact regular grid in (x, y) (resampled in
    /// that plane when another grid size is asked for); otherwise a planar projection, and when
    /// that folds over itself, a cylindrical unwrap.
    #[default]
    Auto,
    /// Project onto the best-fit plane (principal component analysis of the vertices); the height
    /// is the distance along the plane's normal.
    Planar,
    /// Unwrap around the vertices' principal axis: x = angle θ, y = position ζ along the axis,
    /// z = distance ρ from the axis.
    Cylindrical,
}

impl Projection {
    /// The word used on the command line and in messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Planar => "planar",
            Self::Cylindrical => "cylindrical",
        }
    }
}

/// Which surface a mesh keeps where its projection covers a grid point more than once.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Surface {
    /// The mesh must be a single surface in the projection: one that folds over itself on more
    /// than `MAX_OVERLAP` of the grid is refused.
    #[default]
    Single,
    /// The outermost hit at every grid point (largest radius in a cylindrical unwrap, highest
    /// point in a planar one), like a depth map seen from outside: for closed and thick meshes.
    Outer,
}

impl Surface {
    /// The word used on the command line and in messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::Single => "single",
            Self::Outer => "outer",
        }
    }
}

/// Choices for turning a file into a height field. `Default` gives the documented defaults:
/// automatic projection, automatic grid size, plain grayscale PNG.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportOptions {
    /// How a mesh becomes a grid (meshes only). Default: [`Projection::Auto`].
    pub projection: Projection,
    /// Grid size `(width, height)` for resampling a mesh or a GeoTIFF. `None`: for a mesh, about
    /// as many grid points as the mesh has vertices, with the aspect ratio of the projected
    /// surface, each side capped at `super::triangle_mesh::DEFAULT_MAX_SIDE`; a GeoTIFF keeps
    /// its own size (over [`max_points`](Self::max_points) it is refused, or fitted when a cap
    /// is set). With [`Projection::Auto`], a mesh whose vertices already form a grid is used as
    /// is unless a different size is asked for.
    pub grid_size: Option<(usize, usize)>,
    /// Which surface a folding mesh keeps (meshes only). Default: [`Surface::Single`].
    pub surface: Surface,
    /// Read an RGB PNG as Mapbox terrain-RGB: h = −10000 + (R·65536 + G·256 + B)·0.1.
    pub terrain_rgb: bool,
    /// A cap on grid points below the library's own limit
    /// ([`MAX_POINTS`](crate::heightfield::MAX_POINTS)), e.g. what one browser tab holds. A
    /// GeoTIFF over it with no grid size asked for is fitted under it by area averaging, and
    /// its source note says so (the app then shows its import dialog). `None`: a GeoTIFF over
    /// the library's limit is refused instead, never resampled unasked.
    pub max_points: Option<usize>,
    /// Bytes of memory the grid may take (e.g. the machine's available memory). A GeoTIFF
    /// whose grid would need more is refused from its header, before anything is decoded.
    /// `None`: no check beyond the size limits.
    pub memory_budget: Option<u64>,
}
