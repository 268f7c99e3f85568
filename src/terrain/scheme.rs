//! The two tiling schemes of quantized-mesh (TMS: rows counted from the south): geographic
//! (EPSG:4326, two root tiles of 180° side by side) and Web Mercator (EPSG:3857, one root).
//! Scheme coordinates are degrees of longitude and latitude, or Mercator metres.

use std::f64::consts::PI;

/// The WGS84 semi-major axis, the sphere radius of Web Mercator.
const RADIUS: f64 = 6_378_137.0;

/// Half the width of the Web Mercator square, metres.
pub(crate) const MERCATOR_HALF: f64 = PI * RADIUS;

/// A TMS tiling scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// EPSG:4326, longitude and latitude in degrees.
    Geographic,
    /// EPSG:3857, Web Mercator metres.
    Mercator,
}

/// One tile of a scheme: zoom level and TMS column and row (row 0 at the south).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TileId {
    pub zoom: u32,
    pub x: u64,
    pub y: u64,
}

impl Scheme {
    /// The scheme's EPSG code as layer.json names it.
    pub fn projection(self) -> &'static str {
        match self {
            Self::Geographic => "EPSG:4326",
            Self::Mercator => "EPSG:3857",
        }
    }

    /// The scheme's bounds (west, south, east, north) in its coordinates.
    pub fn bounds(self) -> [f64; 4] {
        match self {
            Self::Geographic => [-180.0, -90.0, 180.0, 90.0],
            Self::Mercator => [-MERCATOR_HALF, -MERCATOR_HALF, MERCATOR_HALF, MERCATOR_HALF],
        }
    }

    /// Tiles along x and y at `zoom`.
    pub(crate) fn tiles_at(self, zoom: u32) -> (u64, u64) {
        match self {
            Self::Geographic => (2 << zoom, 1 << zoom),
            Self::Mercator => (1 << zoom, 1 << zoom),
        }
    }

    /// A tile's side in scheme units at `zoom`.
    pub fn tile_size(self, zoom: u32) -> f64 {
        let [w, _, e, _] = self.bounds();
        (e - w) / self.tiles_at(zoom).0 as f64
    }

    /// A tile's rectangle (west, south, east, north) in scheme units.
    pub fn rectangle(self, tile: TileId) -> [f64; 4] {
        let [w, s, _, _] = self.bounds();
        let size = self.tile_size(tile.zoom);
        [
            w + tile.x as f64 * size,
            s + tile.y as f64 * size,
            w + (tile.x + 1) as f64 * size,
            s + (tile.y + 1) as f64 * size,
        ]
    }

    /// The tile at `zoom` holding scheme point (`x`, `y`) (a point on a tile line goes east and
    /// north; the scheme's far edges stay in its last tiles).
    pub(crate) fn tile_at(self, zoom: u32, x: f64, y: f64) -> TileId {
        let [w, s, _, _] = self.bounds();
        let size = self.tile_size(zoom);
        let (nx, ny) = self.tiles_at(zoom);
        let clamp = |v: f64, n: u64| (v.floor().max(0.0) as u64).min(n - 1);
        TileId {
            zoom,
            x: clamp((x - w) / size, nx),
            y: clamp((y - s) / size, ny),
        }
    }

    /// The deepest tile (zoom at most `max_zoom`) holding the whole box (west, south, east,
    /// north).
    #[cfg(test)]
    pub(crate) fn covering_tile(self, bbox: [f64; 4], max_zoom: u32) -> TileId {
        let mut best = self.tile_at(0, bbox[0], bbox[1]);
        for zoom in 0..=max_zoom {
            let a = self.tile_at(zoom, bbox[0], bbox[1]);
            let b = self.tile_at(zoom, bbox[2], bbox[3]);
            if a != b {
                break;
            }
            best = a;
        }
        best
    }

    /// The tiles at `zoom` that a box (west, south, east, north) touches.
    pub(crate) fn block_at(self, zoom: u32, bbox: [f64; 4]) -> Block {
        let a = self.tile_at(zoom, bbox[0], bbox[1]);
        let b = self.tile_at(zoom, bbox[2], bbox[3]);
        Block {
            zoom,
            x0: a.x,
            y0: a.y,
            columns: b.x - a.x + 1,
            rows: b.y - a.y + 1,
        }
    }

    /// The deepest block (zoom at most `max_zoom`) of at most 2 × 2 tiles that holds the box
    /// (west, south, east, north): the quadtree roots of a DEM's tiles. A box on a tile line
    /// takes tiles on both sides of it, not a tile four times as large.
    pub(crate) fn covering_block(self, bbox: [f64; 4], max_zoom: u32) -> Block {
        let mut best = self.block_at(0, bbox);
        for zoom in 1..=max_zoom {
            let b = self.block_at(zoom, bbox);
            if b.columns > 2 || b.rows > 2 {
                break;
            }
            best = b;
        }
        best
    }

    /// A block's rectangle (west, south, east, north) in scheme units.
    pub(crate) fn block_rectangle(self, block: Block) -> [f64; 4] {
        let sw = self.rectangle(TileId {
            zoom: block.zoom,
            x: block.x0,
            y: block.y0,
        });
        let size = self.tile_size(block.zoom);
        [
            sw[0],
            sw[1],
            sw[0] + block.columns as f64 * size,
            sw[1] + block.rows as f64 * size,
        ]
    }

    /// Longitude and latitude (degrees) of scheme point (`x`, `y`).
    pub fn to_lon_lat(self, x: f64, y: f64) -> (f64, f64) {
        match self {
            Self::Geographic => (x, y),
            Self::Mercator => (
                (x / RADIUS).to_degrees(),
                (y / RADIUS).sinh().atan().to_degrees(),
            ),
        }
    }

    /// Scheme point of longitude `lon` and latitude `lat` (degrees).
    pub fn from_lon_lat(self, lon: f64, lat: f64) -> (f64, f64) {
        match self {
            Self::Geographic => (lon, lat),
            Self::Mercator => {
                let lat = lat.clamp(-85.051_128_779_806_6, 85.051_128_779_806_6);
                (
                    lon.to_radians() * RADIUS,
                    lat.to_radians().tan().asinh() * RADIUS,
                )
            }
        }
    }
}

/// A rectangle of tiles at one zoom: its south-west tile and its size in tiles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Block {
    pub zoom: u32,
    pub x0: u64,
    pub y0: u64,
    pub columns: u64,
    pub rows: u64,
}

impl Block {
    /// Whether the block holds `tile` (at its zoom).
    pub fn contains(&self, tile: TileId) -> bool {
        tile.zoom == self.zoom
            && (self.x0..self.x0 + self.columns).contains(&tile.x)
            && (self.y0..self.y0 + self.rows).contains(&tile.y)
    }

    /// Its tiles.
    pub fn tiles(&self) -> Vec<TileId> {
        (0..self.rows)
            .flat_map(|j| {
                (0..self.columns).map(move |i| TileId {
                    zoom: self.zoom,
                    x: self.x0 + i,
                    y: self.y0 + j,
                })
            })
            .collect()
    }
}

impl TileId {
    /// The tile's parent.
    pub fn parent(self) -> Option<TileId> {
        (self.zoom > 0).then(|| TileId {
            zoom: self.zoom - 1,
            x: self.x / 2,
            y: self.y / 2,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geographic_zoom_zero_has_two_hemispheres() {
        let s = Scheme::Geographic;
        assert_eq!(s.tiles_at(0), (2, 1));
        assert_eq!(
            s.rectangle(TileId {
                zoom: 0,
                x: 1,
                y: 0
            }),
            [0.0, -90.0, 180.0, 90.0]
        );
        // TMS rows count from the south.
        assert_eq!(
            s.rectangle(TileId {
                zoom: 1,
                x: 0,
                y: 1
            }),
            [-180.0, 0.0, -90.0, 90.0]
        );
        assert_eq!(
            s.tile_at(3, -97.9, 33.2),
            TileId {
                zoom: 3,
                x: 3,
                y: 5
            }
        );
    }

    #[test]
    fn the_covering_tile_holds_the_box_and_no_child_does() {
        for scheme in [Scheme::Geographic, Scheme::Mercator] {
            let (x0, y0) = scheme.from_lon_lat(-98.2, 33.21);
            let (x1, y1) = scheme.from_lon_lat(-98.17, 33.23);
            let tile = scheme.covering_tile([x0, y0, x1, y1], 30);
            let r = scheme.rectangle(tile);
            assert!(r[0] <= x0 && x1 <= r[2] && r[1] <= y0 && y1 <= r[3]);
            let child = |p: (f64, f64)| scheme.tile_at(tile.zoom + 1, p.0, p.1);
            assert_ne!(child((x0, y0)), child((x1, y1)));
        }
    }

    #[test]
    fn a_box_on_a_tile_line_takes_the_tiles_on_both_sides() {
        // Longitude -84.375 is a tile line from zoom 5 on (11.25° / 2).
        let s = Scheme::Geographic;
        let block = s.covering_block([-84.41, 36.43, -84.08, 36.73], 30);
        assert!(block.zoom >= 8, "{block:?}");
        assert!(block.columns <= 2 && block.rows <= 2);
        let r = s.block_rectangle(block);
        assert!(r[0] <= -84.41 && r[2] >= -84.08 && r[1] <= 36.43 && r[3] >= 36.73);
        let deeper = s.block_at(block.zoom + 1, [-84.41, 36.43, -84.08, 36.73]);
        assert!(deeper.columns > 2 || deeper.rows > 2);
    }

    #[test]
    fn mercator_round_trips_and_its_square_is_the_world() {
        let s = Scheme::Mercator;
        let (x, y) = s.from_lon_lat(12.5, -41.25);
        let (lon, lat) = s.to_lon_lat(x, y);
        assert!((lon - 12.5).abs() < 1e-12 && (lat + 41.25).abs() < 1e-12);
        let (_, top) = s.to_lon_lat(0.0, MERCATOR_HALF);
        assert!((top - 85.051_128_779_806_6).abs() < 1e-9);
        assert_eq!(s.tiles_at(0), (1, 1));
    }
}
