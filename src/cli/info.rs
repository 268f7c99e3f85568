//! `paretomesh info GRID [import options]`.

use super::input::InputArgs;
use paretomesh::heightfield::Placement;
use paretomesh::tiling::{DEFAULT_TILE, TilePlan};

pub(super) fn run(input: &InputArgs) -> Result<(), String> {
    let hf = input.load()?;
    let (lo, hi) = hf.z_range();
    println!("size: {}×{} = {} points", hf.width(), hf.height(), hf.len());
    println!(
        "a run uses: this {}×{} grid, {}",
        hf.width(),
        hf.height(),
        if hf.resampled() || hf.source().contains("resampled") {
            "resampled as the source line says"
        } else {
            "the file's own size (--grid-size WxH chooses another)"
        }
    );
    println!("z range: {lo} .. {hi}");
    println!("origin: {:?}", hf.origin());
    println!("spacing: {:?}", hf.spacing());
    match hf.placement() {
        Placement::Grid => println!("placement: grid, world = (x, y, z) as given"),
        Placement::Planar { origin, u, v, n } => println!(
            "placement: planar projection, world = {origin:?} + x·{u:?} + y·{v:?} + z·{n:?}"
        ),
        Placement::Cylindrical {
            origin,
            axis,
            reference,
        } => println!(
            "placement: cylindrical unwrap around axis {axis:?} through {origin:?} (x = angle from {reference:?} in radians, y = along the axis, z = radius)"
        ),
    }
    println!("full mesh: {} triangles", hf.full_triangles());
    if let Ok(plan) = TilePlan::with_default_tile(hf.width(), hf.height()) {
        if plan.is_single() {
            println!(
                "tiles: none, a run optimises the grid whole (up to {DEFAULT_TILE} points a side)"
            );
        } else {
            println!(
                "tiles: a run cuts it into {} tiles ({}×{}) of at most {DEFAULT_TILE} points a side (--tile changes it)",
                plan.len(),
                plan.columns(),
                plan.rows()
            );
        }
    }
    if hf.georeference().is_some() {
        println!(
            "filled: {} nodata cells took their nearest valid value",
            hf.filled()
        );
    } else {
        println!(
            "filled: {} grid points had no triangle and took their nearest value",
            hf.filled()
        );
    }
    if let Some(geo) = hf.georeference() {
        if let Some([sx, sy, sz]) = geo.pixel_scale {
            println!("GeoTIFF pixel scale (tag 33550): x {sx}, y {sy}, z {sz}");
        }
        if let Some([i, j, k, x, y, z]) = geo.tiepoint {
            println!(
                "GeoTIFF tie point (tag 33922): raster ({i}, {j}, {k}) = map ({x}, {y}, {z}), {}",
                if geo.pixel_is_point {
                    "pixel is point"
                } else {
                    "pixel is area"
                }
            );
        }
        if let Some(nodata) = &geo.nodata {
            println!("GeoTIFF nodata (tag 42113): {nodata}");
        }
        if let Some(code) = geo.epsg {
            println!("GeoTIFF coordinate reference system: EPSG:{code}");
        }
    }
    println!("source: {}", hf.source());
    Ok(())
}
