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
    println!(
        "filled: {} grid points had no triangle and took their nearest value",
        hf.filled()
    );
    println!("source: {}", hf.source());
    Ok(())
}
