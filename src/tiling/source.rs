//! Where a tiled run gets each tile's grid: cut from a whole grid in memory, or read as a
//! window of the grid file when the tile starts ([`GridWindows`]), so that a run holds only
//! the tiles in flight. Both give a tile the same bits.

use super::{TilePlan, TilingError};
use crate::heightfield::Heightfield;
use crate::import::GridWindows;

/// A grid that gives tile grids, for [`run_tiled_with_progress`](super::run_tiled_with_progress).
pub trait TileSource: Sync {
    /// (W, H) of the whole grid.
    fn size(&self) -> (usize, usize);
    /// Tile `index`'s own height field (see [`TilePlan::cut`]).
    fn cut(&self, plan: &TilePlan, index: usize) -> Result<Heightfield, TilingError>;
}

impl TileSource for Heightfield {
    fn size(&self) -> (usize, usize) {
        (self.width(), self.height())
    }

    fn cut(&self, plan: &TilePlan, index: usize) -> Result<Heightfield, TilingError> {
        plan.cut(self, index)
    }
}

impl TileSource for GridWindows {
    fn size(&self) -> (usize, usize) {
        (self.width(), self.height())
    }

    fn cut(&self, plan: &TilePlan, index: usize) -> Result<Heightfield, TilingError> {
        plan.check_size(self.size())?;
        let t = plan.tile(index).ok_or(TilingError::NoSuchTile {
            index,
            tiles: plan.len(),
        })?;
        let z = self
            .read(t.x0, t.y0, t.w, t.h)
            .map_err(|e| TilingError::Grid(e.to_string()))?;
        plan.tile_grid(t, z, self.origin(), self.spacing(), self.source())
    }
}

// Runs tiles on threads and reads files: native only.
#[cfg(all(test, not(target_arch = "wasm32")))]
mod tests {
    use super::*;
    use crate::baselines::GreedyParams;
    use crate::catalogue::Config;
    use crate::import::{ImportOptions, load};
    use std::path::{Path, PathBuf};

    fn data(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data")
            .join(name)
    }

    /// A float GeoTIFF of `w`×`h` in 16×16 tiles whose NaN cells (missing) form a lake far
    /// wider than a tile, a band along the top and scattered holes, at a fresh temporary path.
    fn lake_tiff(w: u32, h: u32) -> PathBuf {
        use tiff::encoder::{TiffEncoder, colortype};
        let z: Vec<f32> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f32, (i / w) as f32);
                let lake = (x - 60.0).powi(2) + (y - 50.0).powi(2) < 35.0f32.powi(2);
                if lake || y < 3.0 || (i * 7919) % 53 == 0 {
                    f32::NAN
                } else {
                    (x * 0.21).sin() * 40.0 + (y * 0.13).cos() * 25.0 + x * 0.5
                }
            })
            .collect();
        let path = std::env::temp_dir().join(format!(
            "paretomesh-lake-{}-{w}x{h}.tif",
            std::process::id()
        ));
        let mut file = std::fs::File::create(&path).unwrap();
        let mut encoder = TiffEncoder::new(&mut file).unwrap();
        let mut image = encoder.new_image::<colortype::Gray32Float>(w, h).unwrap();
        image.rows_per_strip(16).unwrap();
        image.write_data(&z).unwrap();
        path
    }

    /// Windows of `path` give every tile of a `tile`-point plan the whole grid's tile, the
    /// whole grid's source note, and the same tiled front for 1 and 2 threads.
    fn windows_match_the_whole_grid(path: &Path, tile: usize) {
        let whole = load(path).unwrap();
        let windows = GridWindows::open(path, &ImportOptions::default())
            .unwrap()
            .expect("read by windows")
            .scan()
            .unwrap();
        assert_eq!(windows.source(), whole.source());
        assert_eq!(windows.filled(), whole.filled());
        let plan = TilePlan::new(whole.width(), whole.height(), tile).unwrap();
        assert!(plan.len() >= 4, "{}", plan.len());
        for i in 0..plan.len() {
            let (a, b) = (plan.cut(&whole, i).unwrap(), windows.cut(&plan, i).unwrap());
            let bits = |h: &Heightfield| h.z().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&a), bits(&b), "tile {i} of {}", path.display());
            assert_eq!((a.origin(), a.spacing()), (b.origin(), b.spacing()));
            assert_eq!(a.source(), b.source());
        }
        let greedy = Config::Greedy(GreedyParams {
            records: 12,
            ..GreedyParams::default()
        });
        let front = |source: &dyn TileSource, threads| {
            let f =
                super::super::run_tiled_with_progress(source, &plan, &greedy, 3, threads, &|_| {})
                    .unwrap();
            serde_json::to_string(&f).unwrap()
        };
        let reference = front(&whole, 1);
        assert_eq!(front(&windows, 1), reference);
        assert_eq!(front(&windows, 2), reference);
    }

    #[test]
    fn geotiff_windows_with_nodata_give_the_whole_grids_tiles_and_front() {
        windows_match_the_whole_grid(&data("volcano_87x61_int16_lzw_nodata.tif"), 33);
        windows_match_the_whole_grid(&data("jacksboro_65x65_float32_tiled_deflate.tif"), 33);
        windows_match_the_whole_grid(&data("volcano_87x61.f32"), 33);
    }

    #[test]
    fn a_lake_wider_than_a_tile_fills_as_the_whole_grid() {
        let path = lake_tiff(130, 100);
        let whole = load(&path).unwrap();
        assert!(whole.filled() > 3000, "{}", whole.filled());
        windows_match_the_whole_grid(&path, 33);
        std::fs::remove_file(&path).unwrap();
    }
}
