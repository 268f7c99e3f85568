//! `paretomesh info GRID [import options]`.

use super::input::InputArgs;
use paretomesh::heightfield::Placement;

pub fn run(input: &InputArgs) -> Result<(), String> {
    let hf = input.load()?;
    let (lo, hi) = hf.z_range();
    println!("size: {}×{} = {} points", hf.width(), hf.height(), hf.len());
    println!("z range: {lo} .. {hi}");
    println!("origin: {:?}", hf.origin());
    println!("spacing: {:?}", hf.spacing());
    println!(
        "placement: {}",
        match hf.placement() {
            Placement::Grid => "grid (x, y, z) as given",
            Placement::Planar { .. } => "planar projection onto the best-fit plane",
            Placement::Cylindrical { .. } =>
                "cylindrical unwrap (x = angle in radians, y = along the axis, z = radius)",
        }
    );
    println!("full mesh: {} triangles", hf.full_triangles());
    println!(
        "filled: {} grid points had no triangle and took their nearest value",
        hf.filled()
    );
    println!("source: {}", hf.source());
    Ok(())
}
