//! `paretomesh info GRID`.

use paretomesh::heightfield;
use std::path::Path;

pub fn run(path: &Path) -> Result<(), String> {
    let hf = heightfield::load(path).map_err(|e| e.to_string())?;
    let (lo, hi) = hf.z_range();
    println!("size: {}×{} = {} points", hf.width(), hf.height(), hf.len());
    println!("z range: {lo} .. {hi}");
    println!("spacing: {:?}", hf.spacing());
    println!("full mesh: {} triangles", hf.full_triangles());
    if hf.filled() > 0 {
        println!(
            "filled: {} grid points had no triangle and took their nearest value",
            hf.filled()
        );
    }
    println!("source: {}", hf.source());
    Ok(())
}
