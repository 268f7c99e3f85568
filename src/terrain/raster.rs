//! A DEM resampled onto a tiling scheme's grid: the GeoTIFF's map coordinates are reprojected
//! from its EPSG system to longitude and latitude by `proj4rs` with the EPSG definitions of
//! `crs-definitions`, and the DEM is sampled bilinearly at the grid points of one scheme tile
//! (the deepest block of at most 2 × 2 that holds the whole DEM), so that every tile of the
//! quadtrees below is a block of whole grid cells. Points outside the DEM take the nearest
//! DEM point's height and count as water.
//! Heights above the EGM96 geoid become heights above the ellipsoid with the `egm96` crate's
//! spherical-harmonic model, evaluated on a lattice of at most 5′ and interpolated.

use super::scheme::{Block, Scheme};
use crate::heightfield::{Heightfield, Placement};
use proj4rs::Proj;
use proj4rs::transform::transform;
use rayon::prelude::*;

/// Why a DEM cannot be placed on the globe.
#[derive(Clone, Debug, PartialEq)]
pub enum GeoError {
    /// The input is not a georeferenced GeoTIFF (no pixel scale or tie point).
    NotGeoreferenced { missing: String },
    /// The GeoTIFF names no EPSG system.
    NoCrs,
    /// The projection library's EPSG definitions do not have the code.
    UnknownEpsg(u16),
    /// The projection failed for the DEM's points.
    Projection(String),
    /// The scheme grid would be too large.
    TooLarge { side: usize },
}

impl std::fmt::Display for GeoError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NotGeoreferenced { missing } => write!(
                f,
                "the input has no georeferencing: {missing}; terrain tiles for a globe need the DEM's place on Earth (a GeoTIFF with ModelPixelScale, ModelTiepoint and an EPSG code)"
            ),
            Self::NoCrs => write!(
                f,
                "the GeoTIFF names no EPSG coordinate system (GeoKey 3072 ProjectedCSType or 2048 GeographicType is missing or user-defined); terrain tiles for a globe need it"
            ),
            Self::UnknownEpsg(code) => write!(
                f,
                "EPSG:{code} is not in the projection library's EPSG definitions (proj4rs with crs-definitions); reproject the DEM to a known system first, e.g. EPSG:4326"
            ),
            Self::Projection(e) => write!(f, "cannot reproject the DEM: {e}"),
            Self::TooLarge { side } => write!(
                f,
                "the scheme grid would be {side} points a side; ask for fewer --levels"
            ),
        }
    }
}

impl std::error::Error for GeoError {}

/// The largest scheme grid side (the exact predicates' limit per side).
pub(crate) const MAX_SIDE: usize = 16_384;

/// A DEM on the grid of a block of scheme tiles.
pub struct SchemeRaster {
    /// The scheme.
    pub scheme: Scheme,
    /// The scheme tiles the grid covers: the quadtrees' roots.
    pub block: Block,
    /// Levels of the quadtrees, their roots included.
    pub levels: u32,
    /// Grid cells along a root tile's side.
    pub cells_per_root: usize,
    /// Heights above the ellipsoid, row 0 at the north edge.
    pub hf: Heightfield,
    /// Per grid point: outside the DEM, or on flat water (its four DEM cells equal).
    pub water: Vec<bool>,
    /// Longitude and latitude box (degrees) of the DEM.
    pub dem_box: [f64; 4],
}

impl SchemeRaster {
    /// Points per row.
    pub fn side(&self) -> usize {
        self.hf.width()
    }

    /// Scheme coordinates of grid point (`col`, `row`).
    pub(crate) fn scheme_xy(&self, col: usize, row: usize) -> (f64, f64) {
        let [w, _, _, n] = self.scheme.block_rectangle(self.block);
        let step = self.scheme.tile_size(self.block.zoom) / self.cells_per_root as f64;
        (w + col as f64 * step, n - row as f64 * step)
    }

    /// Longitude and latitude (degrees) of grid point (`col`, `row`).
    pub(crate) fn lon_lat(&self, col: usize, row: usize) -> (f64, f64) {
        let (x, y) = self.scheme_xy(col, row);
        self.scheme.to_lon_lat(x, y)
    }
}

/// The proj4rs system of `hf`'s GeoTIFF, with the specific error when it has none.
pub(super) fn dem_projection(hf: &Heightfield) -> Result<(Proj, u16), GeoError> {
    let geo = hf.georeference().ok_or(GeoError::NotGeoreferenced {
        missing: format!("{} is not a GeoTIFF", hf.source()),
    })?;
    let mut missing = Vec::new();
    if geo.pixel_scale.is_none() {
        missing.push("ModelPixelScale (tag 33550)");
    }
    if geo.tiepoint.is_none() {
        missing.push("ModelTiepoint (tag 33922)");
    }
    if !missing.is_empty() {
        return Err(GeoError::NotGeoreferenced {
            missing: format!("the GeoTIFF has no {}", missing.join(" and no ")),
        });
    }
    if *hf.placement() != Placement::Grid {
        return Err(GeoError::NotGeoreferenced {
            missing: "the grid is not in its map's plane".into(),
        });
    }
    let code = geo.epsg.ok_or(GeoError::NoCrs)?;
    let proj = Proj::from_epsg_code(code).map_err(|_| GeoError::UnknownEpsg(code))?;
    Ok((proj, code))
}

fn wgs84() -> Proj {
    Proj::from_proj_string("+proj=longlat +datum=WGS84 +no_defs").expect("WGS84 is a valid system")
}

/// Longitude/latitude (degrees) of DEM map points, in place.
fn dem_to_lon_lat(proj: &Proj, points: &mut [(f64, f64, f64)]) -> Result<(), GeoError> {
    if proj.is_latlong() {
        for p in points.iter_mut() {
            *p = (p.0.to_radians(), p.1.to_radians(), p.2);
        }
    }
    transform(proj, &wgs84(), points).map_err(|e| GeoError::Projection(e.to_string()))?;
    for p in points.iter_mut() {
        *p = (p.0.to_degrees(), p.1.to_degrees(), p.2);
    }
    Ok(())
}

/// DEM map points of longitudes/latitudes (degrees), in place.
fn lon_lat_to_dem(proj: &Proj, points: &mut [(f64, f64, f64)]) -> Result<(), GeoError> {
    for p in points.iter_mut() {
        *p = (p.0.to_radians(), p.1.to_radians(), p.2);
    }
    let wgs84 = wgs84();
    let given = points.to_vec();
    if transform(&wgs84, proj, points).is_err() {
        // Some points lie where the projection is undefined (far outside a UTM zone): they are
        // outside the DEM, marked by NaN, and the others are projected one by one.
        points.copy_from_slice(&given);
        for p in points.iter_mut() {
            let mut one = *p;
            *p = match transform(&wgs84, proj, &mut one) {
                Ok(()) => one,
                Err(_) => (f64::NAN, f64::NAN, 0.0),
            };
        }
    }
    if proj.is_latlong() {
        for p in points.iter_mut() {
            *p = (p.0.to_degrees(), p.1.to_degrees(), p.2);
        }
    }
    Ok(())
}

/// The EGM96 undulation over a longitude/latitude box, on a lattice of at most 5′.
struct Geoid {
    west: f64,
    south: f64,
    step: (f64, f64),
    n: (usize, usize),
    values: Vec<f64>,
}

impl Geoid {
    fn over(bbox: [f64; 4]) -> Self {
        let most = 5.0 / 60.0;
        let nx = (((bbox[2] - bbox[0]) / most).ceil() as usize).max(1) + 1;
        let ny = (((bbox[3] - bbox[1]) / most).ceil() as usize).max(1) + 1;
        let step = (
            (bbox[2] - bbox[0]) / (nx - 1) as f64,
            (bbox[3] - bbox[1]) / (ny - 1) as f64,
        );
        let values = (0..nx * ny)
            .into_par_iter()
            .map(|i| {
                let lon = bbox[0] + (i % nx) as f64 * step.0;
                let lat = bbox[1] + (i / nx) as f64 * step.1;
                egm96::egm96_compute_altitude_offset(lat, lon)
            })
            .collect();
        Self {
            west: bbox[0],
            south: bbox[1],
            step,
            n: (nx, ny),
            values,
        }
    }

    fn at(&self, lon: f64, lat: f64) -> f64 {
        let fx = if self.step.0 > 0.0 {
            ((lon - self.west) / self.step.0).clamp(0.0, (self.n.0 - 1) as f64)
        } else {
            0.0
        };
        let fy = if self.step.1 > 0.0 {
            ((lat - self.south) / self.step.1).clamp(0.0, (self.n.1 - 1) as f64)
        } else {
            0.0
        };
        bilinear(&self.values, self.n.0, self.n.1, fx, fy)
    }
}

fn bilinear(z: &[f64], w: usize, h: usize, fx: f64, fy: f64) -> f64 {
    let x0 = (fx.floor() as usize).min(w.saturating_sub(2));
    let y0 = (fy.floor() as usize).min(h.saturating_sub(2));
    let (x1, y1) = ((x0 + 1).min(w - 1), (y0 + 1).min(h - 1));
    let (tx, ty) = (fx - x0 as f64, fy - y0 as f64);
    let top = z[y0 * w + x0] * (1.0 - tx) + z[y0 * w + x1] * tx;
    let bottom = z[y1 * w + x0] * (1.0 - tx) + z[y1 * w + x1] * tx;
    top * (1.0 - ty) + bottom * ty
}

/// How a DEM is put on a scheme's grid.
#[derive(Clone, Copy, Debug)]
pub struct RasterOptions {
    /// The tiling scheme.
    pub scheme: Scheme,
    /// Heights are above the EGM96 geoid: add the undulation.
    pub geoid: bool,
    /// Grid cells along a finest tile's side (a power of two).
    pub cells_per_tile: usize,
    /// Quadtree levels, the roots included; by default enough for the finest
    /// tiles' cells to be no larger than the DEM's.
    pub levels: Option<u32>,
}

/// `dem` resampled onto the grid of the deepest block of at most 2 × 2 scheme tiles that
/// holds it.
pub fn reproject(dem: &Heightfield, options: RasterOptions) -> Result<SchemeRaster, GeoError> {
    let (proj, _) = dem_projection(dem)?;
    let (w, h) = (dem.width(), dem.height());
    let [ox, oy] = dem.origin();
    let [sx, sy] = dem.spacing();
    // The DEM's outline, every few points along each edge, in longitude and latitude.
    let mut outline = Vec::new();
    let k = 64usize;
    for i in 0..=k {
        let gx = (w - 1) as f64 * i as f64 / k as f64;
        let gy = (h - 1) as f64 * i as f64 / k as f64;
        for (x, y) in [
            (gx, 0.0),
            (gx, (h - 1) as f64),
            (0.0, gy),
            ((w - 1) as f64, gy),
        ] {
            outline.push((ox + x * sx, oy + y * sy, 0.0));
        }
    }
    dem_to_lon_lat(&proj, &mut outline)?;
    let mut dem_box = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in &outline {
        if !(p.0.is_finite() && p.1.is_finite()) {
            return Err(GeoError::Projection(
                "the DEM's corners do not map to longitude and latitude".into(),
            ));
        }
        dem_box = [
            dem_box[0].min(p.0),
            dem_box[1].min(p.1),
            dem_box[2].max(p.0),
            dem_box[3].max(p.1),
        ];
    }
    let scheme = options.scheme;
    let (x0, y0) = scheme.from_lon_lat(dem_box[0], dem_box[1]);
    let (x1, y1) = scheme.from_lon_lat(dem_box[2], dem_box[3]);
    let block = scheme.covering_block([x0, y0, x1, y1], 28);
    let tile_side = scheme.tile_size(block.zoom);
    let dem_step = ((x1 - x0) / (w - 1) as f64).min((y1 - y0) / (h - 1) as f64);
    let cells = options.cells_per_tile;
    let across = block.columns.max(block.rows) as usize;
    let levels = options.levels.unwrap_or_else(|| {
        // The default stops where the grid would pass the largest side, rather than refuse.
        let mut levels = 1;
        while tile_side / ((cells << (levels - 1)) as f64) > dem_step
            && levels < 12
            && (cells << levels) * across < MAX_SIDE
        {
            levels += 1;
        }
        levels
    });
    let per_root = cells << (levels - 1);
    let (width, height) = (
        per_root * block.columns as usize + 1,
        per_root * block.rows as usize + 1,
    );
    if width.max(height) > MAX_SIDE {
        return Err(GeoError::TooLarge {
            side: width.max(height),
        });
    }
    let geoid = options.geoid.then(|| Geoid::over(dem_box));
    let mut raster = SchemeRaster {
        scheme,
        block,
        levels,
        cells_per_root: per_root,
        hf: Heightfield::new(2, 2, vec![0.0; 4]).expect("a 2×2 grid"),
        water: Vec::new(),
        dem_box,
    };
    // Each row is written in place: the scheme grid's heights and water flags are the only
    // whole-grid arrays (9 bytes a point) beside the DEM.
    let mut z = vec![0.0; width * height];
    let mut water = vec![false; width * height];
    z.par_chunks_mut(width)
        .zip(water.par_chunks_mut(width))
        .enumerate()
        .try_for_each(|(row, (z_row, water_row))| {
            let mut points: Vec<(f64, f64, f64)> = (0..width)
                .map(|col| {
                    let (lon, lat) = raster.lon_lat(col, row);
                    (lon, lat, 0.0)
                })
                .collect();
            let lon_lat = points.clone();
            lon_lat_to_dem(&proj, &mut points)?;
            let sample = |p: &(f64, f64, f64), ll: &(f64, f64, f64)| {
                let fx = (p.0 - ox) / sx;
                let fy = (p.1 - oy) / sy;
                let inside = fx.is_finite()
                    && fy.is_finite()
                    && fx >= -1e-9
                    && fy >= -1e-9
                    && fx <= (w - 1) as f64 + 1e-9
                    && fy <= (h - 1) as f64 + 1e-9;
                if !inside {
                    return (f64::NAN, true);
                }
                let (fx, fy) = (fx.clamp(0.0, (w - 1) as f64), fy.clamp(0.0, (h - 1) as f64));
                let z = bilinear(dem.z(), w, h, fx, fy);
                let (cx, cy) = (
                    (fx.floor() as usize).min(w - 2),
                    (fy.floor() as usize).min(h - 2),
                );
                let corners = [
                    dem.z_at(cx, cy),
                    dem.z_at(cx + 1, cy),
                    dem.z_at(cx, cy + 1),
                    dem.z_at(cx + 1, cy + 1),
                ];
                let flat = corners.iter().all(|&c| c == corners[0]);
                let lift = geoid.as_ref().map_or(0.0, |g| g.at(ll.0, ll.1));
                (z + lift, flat)
            };
            for (i, (p, ll)) in points.iter().zip(&lon_lat).enumerate() {
                (z_row[i], water_row[i]) = sample(p, ll);
            }
            Ok::<(), GeoError>(())
        })?;
    if z.iter().all(|v| v.is_nan()) {
        return Err(GeoError::Projection(
            "no grid point of the scheme's tiles falls inside the DEM".into(),
        ));
    }
    // Outside the DEM, the nearest DEM height: a wall at the DEM's edge would cost its
    // tiles' meshes many triangles and any re-triangulation an error of the wall's height.
    crate::import::fill_nearest(&mut z, width, height);
    raster.hf =
        Heightfield::new(width, height, z).map_err(|e| GeoError::Projection(e.to_string()))?;
    raster.water = water;
    Ok(raster)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::Georeference;

    #[test]
    fn the_geoid_lattice_follows_the_model() {
        let direct = egm96::egm96_compute_altitude_offset(48.14, 11.58);
        // EGM96 puts the geoid about 45.5 m above the ellipsoid at Munich.
        assert!((direct - 45.5).abs() < 1.0, "{direct}");
        let lattice = Geoid::over([11.4, 48.0, 11.8, 48.3]);
        assert!((lattice.at(11.58, 48.14) - direct).abs() < 0.05);
    }

    fn georeferenced(epsg: Option<u16>, placed: bool) -> Heightfield {
        let geo = Georeference {
            pixel_scale: placed.then_some([30.0, 30.0, 0.0]),
            tiepoint: placed.then_some([0.0, 0.0, 0.0, 731_000.0, 4_068_000.0, 0.0]),
            epsg,
            ..Default::default()
        };
        Heightfield::new(3, 3, vec![0.0; 9])
            .unwrap()
            .with_georeference(geo)
    }

    #[test]
    fn what_is_missing_for_the_globe_is_named() {
        let err = |hf: &Heightfield| dem_projection(hf).err().unwrap();
        assert_eq!(
            err(&georeferenced(Some(32600), true)),
            GeoError::UnknownEpsg(32600)
        );
        assert_eq!(err(&georeferenced(None, true)), GeoError::NoCrs);
        let missing = err(&georeferenced(Some(32616), false)).to_string();
        assert!(
            missing.contains("no ModelPixelScale (tag 33550) and no ModelTiepoint"),
            "{missing}"
        );
        let plain = Heightfield::new(3, 3, vec![0.0; 9]).unwrap();
        assert!(matches!(err(&plain), GeoError::NotGeoreferenced { .. }));
        assert!(dem_projection(&georeferenced(Some(32616), true)).is_ok());
    }
}
