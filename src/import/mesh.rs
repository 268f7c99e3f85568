//! How a triangle mesh becomes a height field: exactly when its vertices already form a regular
//! grid, otherwise by resampling.

use super::error::ImportError;
use super::options::{ImportOptions, MAX_OVERLAP, Projection, Surface};
use super::resample;
use super::triangle_mesh::TriangleMesh;
use crate::heightfield::{Heightfield, Placement};

/// A regular grid found in a mesh's vertices.
struct Lattice {
    width: usize,
    height: usize,
    origin: [f64; 2],
    spacing: [f64; 2],
    z: Vec<f64>,
}

/// Distinct sorted values of one coordinate, if they are evenly spaced: `(values, spacing)`.
/// "Evenly" allows a relative error of 1e-9 of the spacing, for decimal coordinates such as 0.1.
fn even_steps(mut values: Vec<f64>) -> Option<(Vec<f64>, f64)> {
    values.sort_by(f64::total_cmp);
    values.dedup();
    if values.len() < 2 {
        return None;
    }
    let step = (values[values.len() - 1] - values[0]) / (values.len() - 1) as f64;
    let even = values
        .iter()
        .enumerate()
        .all(|(i, &v)| (v - (values[0] + i as f64 * step)).abs() <= 1e-9 * step);
    even.then_some((values, step))
}

/// The vertices as a regular grid in (x, y) with z as height, if they are exactly one: every
/// (x, y) of an evenly spaced W×H lattice occurs, and repeats of a point carry the same z.
fn lattice(vertices: &[[f64; 3]]) -> Option<Lattice> {
    let (xs, dx) = even_steps(vertices.iter().map(|p| p[0]).collect())?;
    let (ys, dy) = even_steps(vertices.iter().map(|p| p[1]).collect())?;
    let (width, height) = (xs.len(), ys.len());
    if crate::heightfield::check_size(width, height).is_err() || width * height > vertices.len() {
        return None;
    }
    let mut z = vec![f64::NAN; width * height];
    for p in vertices {
        // The binary search finds the exact value: xs and ys hold the vertices' own values.
        let x = xs.binary_search_by(|v| v.total_cmp(&p[0])).ok()?;
        let y = ys.binary_search_by(|v| v.total_cmp(&p[1])).ok()?;
        let slot = &mut z[y * width + x];
        if slot.is_nan() {
            *slot = p[2];
        } else if *slot != p[2] {
            return None;
        }
    }
    if z.iter().any(|v| v.is_nan()) {
        return None;
    }
    Some(Lattice {
        width,
        height,
        origin: [xs[0], ys[0]],
        spacing: [dx, dy],
        z,
    })
}

/// Turns a validated mesh into a height field as `options` say (see [`ImportOptions`] and
/// [`Projection`]); `format` and `name` go into errors and the source note.
pub fn to_heightfield(
    mesh: &TriangleMesh,
    format: &'static str,
    name: &str,
    options: &ImportOptions,
) -> Result<Heightfield, ImportError> {
    mesh.validate(format)?;
    if let Some((w, h)) = options.grid_size {
        crate::heightfield::check_size(w, h)?;
    }
    let summary = format!(
        "{format} mesh {name} ({} vertices, {} triangles)",
        mesh.vertices.len(),
        mesh.triangles.len()
    );
    let grid = match options.projection {
        Projection::Auto => lattice(&mesh.vertices),
        _ => None,
    };
    if let Some(grid) = grid {
        if let Some(hf) = from_lattice(mesh, format, &summary, grid, options)? {
            return Ok(hf);
        }
        // A lattice whose triangles fold in (x, y) (unusual faces): the general path decides.
    }
    if mesh.triangles.is_empty() {
        return Err(ImportError::EmptyMesh { format });
    }
    let mut tried: Vec<(Projection, Option<f64>)> = Vec::new();
    if let Some(hf) = as_single_surface(mesh, &summary, options, &mut tried)? {
        return Ok(hf);
    }
    if tried.iter().all(|(_, overlap)| overlap.is_none()) {
        // No projection has any area: every triangle is degenerate.
        return Err(ImportError::EmptyMesh { format });
    }
    if options.surface == Surface::Outer && options.projection == Projection::Auto {
        // Every single-surface projection folds: the outer surface in the projection that suits
        // the mesh's shape.
        if let Some(hf) = as_outer_surface(mesh, &summary, options, &tried)? {
            return Ok(hf);
        }
    }
    Err(ImportError::NoProjection { tried })
}

/// A mesh whose vertices form an exact grid: that grid as is, or resampled in its own (x, y)
/// plane to the asked size (heights stay z). `None` when its triangles fold in (x, y).
fn from_lattice(
    mesh: &TriangleMesh,
    format: &'static str,
    summary: &str,
    grid: Lattice,
    options: &ImportOptions,
) -> Result<Option<Heightfield>, ImportError> {
    let found = format!(
        "{summary}: the vertices form an exact {}×{} grid",
        grid.width, grid.height
    );
    if options
        .grid_size
        .is_none_or(|size| size == (grid.width, grid.height))
    {
        return Ok(Some(
            Heightfield::new(grid.width, grid.height, grid.z)?
                .with_geometry(grid.origin, grid.spacing)?
                .with_placement(Placement::Grid)
                .with_source(format!("{found}, used as is")),
        ));
    }
    if mesh.triangles.is_empty() {
        return Err(ImportError::EmptyMesh { format });
    }
    match resample::resample_along(mesh, [0.0, 0.0, 1.0], options.grid_size)? {
        resample::Outcome::Grid(r) => {
            let note = format!(
                "{found}, resampled in its (x, y) plane onto a {}×{} grid; {} grid points had no triangle and took their nearest value",
                r.width, r.height, r.filled
            );
            resampled(r, note).map(Some)
        }
        resample::Outcome::Folded { .. } => Ok(None),
    }
}

/// The mesh as a single surface, in the projection `options` name or, with the automatic
/// choice, planar then cylindrical; each projection that folds is pushed on `tried` with its
/// share covered more than once. `None` when all fold.
fn as_single_surface(
    mesh: &TriangleMesh,
    summary: &str,
    options: &ImportOptions,
    tried: &mut Vec<(Projection, Option<f64>)>,
) -> Result<Option<Heightfield>, ImportError> {
    let tries: &[Projection] = match options.projection {
        Projection::Auto => &[Projection::Planar, Projection::Cylindrical],
        other => std::slice::from_ref(match other {
            Projection::Planar => &Projection::Planar,
            _ => &Projection::Cylindrical,
        }),
    };
    // With the automatic choice, every projection is first tried as a single surface; the outer
    // surface comes after, in the projection that suits the mesh's shape.
    let surface = match options.projection {
        Projection::Auto => Surface::Single,
        _ => options.surface,
    };
    for &projection in tries {
        match resample::resample(mesh, projection, options.grid_size, surface)? {
            resample::Outcome::Grid(grid) => {
                let note = format!(
                    "{summary}: resampled onto a {}×{} grid by {}; {:.1} % of the covered grid covered more than once (highest wins); {} grid points had no triangle and took their nearest value",
                    grid.width,
                    grid.height,
                    projection_words(projection),
                    grid.overlap * 100.0,
                    grid.filled
                );
                // Say why an earlier projection was passed over.
                let note = match tried.first() {
                    Some((first, Some(share))) => format!(
                        "{note} (the {} projection folds: {:.0} % covered more than once)",
                        first.name(),
                        share * 100.0
                    ),
                    Some((first, None)) => {
                        format!("{note} (the {} projection has no area)", first.name())
                    }
                    None => note,
                };
                let note = if grid.overlap > MAX_OVERLAP {
                    outer_note(&note, &grid)
                } else {
                    note
                };
                return resampled(grid, note).map(Some);
            }
            resample::Outcome::Folded { overlap } => tried.push((projection, overlap)),
        }
    }
    Ok(None)
}

/// The mesh's outer surface, in the projection that suits its shape, once every
/// single-surface projection in `tried` folds. `None` when that folds too.
fn as_outer_surface(
    mesh: &TriangleMesh,
    summary: &str,
    options: &ImportOptions,
    tried: &[(Projection, Option<f64>)],
) -> Result<Option<Heightfield>, ImportError> {
    let projection = resample::outer_projection(mesh);
    let resample::Outcome::Grid(grid) =
        resample::resample(mesh, projection, options.grid_size, Surface::Outer)?
    else {
        return Ok(None);
    };
    let folds = tried
        .iter()
        .map(|(p, share)| match share {
            Some(share) => format!("{}: {:.0} %", p.name(), share * 100.0),
            None => format!("{}: no area", p.name()),
        })
        .collect::<Vec<_>>()
        .join(", ");
    let note = format!(
        "{summary}: resampled onto a {}×{} grid by {}; {} grid points had no triangle and took their nearest value (as a single surface every projection folds, covered more than once: {folds})",
        grid.width,
        grid.height,
        projection_words(projection),
        grid.filled
    );
    let note = outer_note(&note, &grid);
    resampled(grid, note).map(Some)
}

/// How the source note names a projection.
fn projection_words(projection: Projection) -> &'static str {
    match projection {
        Projection::Cylindrical => "cylindrical unwrap around the principal axis",
        _ => "planar projection onto the best-fit plane",
    }
}

/// The height field of a resampled grid, with its source `note`.
fn resampled(grid: resample::Resampled, note: String) -> Result<Heightfield, ImportError> {
    Ok(Heightfield::new(grid.width, grid.height, grid.z)?
        .with_geometry(grid.origin, grid.spacing)?
        .with_placement(grid.placement)
        .with_filled(grid.filled)
        .with_resampled()
        .with_source(note))
}

/// The import report's words on an outer surface: how many grid points were covered more than
/// once and took the outer wall's height, and their share of the covered grid.
fn outer_note(note: &str, grid: &resample::Resampled) -> String {
    format!(
        "{note}; outer surface: {} grid points ({:.1} % of the covered grid) were covered more than once and took the outermost hit",
        grid.covered_twice,
        grid.overlap * 100.0
    )
}
