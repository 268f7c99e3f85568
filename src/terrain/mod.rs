//! Terrain tiles for web globes in quantized-mesh-1.0 (CesiumTerrainProvider's format; native
//! builds only): a DEM reprojected onto a TMS scheme's grid ([`reproject`]), run tile by tile, and
//! its pyramid written as gzip `.terrain` files with edge indices, oct-encoded normals, a water
//! mask and availability metadata, tied together by layer.json ([`build_terrain`]).
//!
//! - `scheme`: the geographic (EPSG:4326) and Web Mercator (EPSG:3857) TMS schemes;
//! - `raster`: the DEM on the scheme's grid (proj4rs with EPSG definitions, EGM96);
//! - `build`: the levels, their tiles and layer.json;
//! - `tiles3d`: the same pyramid as 3D Tiles terrain (`Cesium3DTilesTerrainProvider`);
//! - `tile_file`, `codec`, `bounds`: the `.terrain` format, its number codings, its header's
//!   bounds.
//!
//! The files are private; what callers need is re-exported here.

mod bounds;
mod build;
mod codec;
mod raster;
mod scheme;
mod tile_file;
mod tiles3d;

pub use build::{
    DEFAULT_FINEST, TerrainLevel, TerrainOptions, TerrainTileset, build_3dtiles_terrain,
    build_terrain,
};
pub use raster::{GeoError, RasterOptions, SchemeRaster, reproject};
pub use scheme::{Scheme, TileId};

/// Decodes a `.terrain` file's bytes (after gunzip) into its vertices (u, v, quantized height),
/// triangles and edge lists, for tests and tools that check a tileset.
pub fn decode_tile(bytes: &[u8]) -> Result<DecodedTile, String> {
    let t = tile_file::TerrainTile::decode(bytes)?;
    Ok(DecodedTile {
        u: t.u,
        v: t.v,
        height: t.height,
        min_height: t.header.min_height,
        max_height: t.header.max_height,
        triangles: t.triangles,
        edges: t.edges,
        normals: t
            .normals
            .map(|n| n.into_iter().map(codec::oct_decode).collect()),
        metadata: t.metadata,
        water_mask_bytes: t.water.map(|w| match w {
            tile_file::WaterMask::Uniform(_) => 1,
            tile_file::WaterMask::Grid(g) => g.len(),
        }),
    })
}

/// A decoded `.terrain` tile.
#[derive(Clone, Debug, PartialEq)]
pub struct DecodedTile {
    /// u, v (0..=32767, west to east, south to north) and quantized heights per vertex.
    pub u: Vec<u16>,
    pub v: Vec<u16>,
    pub height: Vec<u16>,
    /// The height range the quantized heights span.
    pub min_height: f32,
    pub max_height: f32,
    /// Triangles over the vertices.
    pub triangles: Vec<[u32; 3]>,
    /// West, south, east and north edge vertices.
    pub edges: [Vec<u32>; 4],
    /// Unit normals, when the tile has them.
    pub normals: Option<Vec<[f64; 3]>>,
    /// The metadata extension's JSON.
    pub metadata: Option<String>,
    /// The water mask's size in bytes (1 or 65 536), when the tile has one.
    pub water_mask_bytes: Option<usize>,
}

impl DecodedTile {
    /// The height of vertex `i` over the ellipsoid.
    pub fn height_of(&self, i: usize) -> f64 {
        f64::from(self.min_height)
            + f64::from(self.height[i]) / 32767.0
                * (f64::from(self.max_height) - f64::from(self.min_height))
    }
}
