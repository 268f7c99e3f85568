//! A parsed height field taken apart into plain numbers and strings, and put back together: the
//! form in which the import Worker hands a surface to the page (`web::transfer` maps it to a
//! JavaScript object). Everything a height field holds travels, the GeoTIFF georeferencing
//! included, so the page's surface is the one the Worker parsed and its exports lie where
//! `paretomesh export` puts them.

use crate::heightfield::{Georeference, Heightfield, Placement};

/// Every part of a [`Heightfield`], as plain values.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct SurfaceParts {
    /// Grid width W.
    pub width: usize,
    /// Grid height H.
    pub height: usize,
    /// The W·H heights, row by row.
    pub z: Vec<f64>,
    /// Grid coordinates of point (0, 0).
    pub origin: [f64; 2],
    /// Grid spacing along x and y.
    pub spacing: [f64; 2],
    /// The placement's kind: `grid`, `planar` or `cylindrical`.
    pub placement_kind: String,
    /// The placement's vectors, flattened in declaration order (empty for `grid`).
    pub placement_values: Vec<f64>,
    /// The note on how the grid was made.
    pub source: String,
    /// Grid points filled from their nearest valid neighbour.
    pub filled: usize,
    /// True when the grid was resampled (see [`Heightfield::resampled`]).
    pub resampled: bool,
    /// The GeoTIFF georeferencing, for a grid read from a GeoTIFF.
    pub georeference: Option<Georeference>,
}

impl SurfaceParts {
    /// Takes `hf` apart.
    pub(crate) fn of(hf: &Heightfield) -> Self {
        let (kind, values): (&str, Vec<f64>) = match hf.placement() {
            Placement::Grid => ("grid", vec![]),
            Placement::Planar { origin, u, v, n } => ("planar", [*origin, *u, *v, *n].concat()),
            Placement::Cylindrical {
                origin,
                axis,
                reference,
            } => ("cylindrical", [*origin, *axis, *reference].concat()),
        };
        Self {
            width: hf.width(),
            height: hf.height(),
            z: hf.z().to_vec(),
            origin: hf.origin(),
            spacing: hf.spacing(),
            placement_kind: kind.to_string(),
            placement_values: values,
            source: hf.source().to_string(),
            filled: hf.filled(),
            resampled: hf.resampled(),
            georeference: hf.georeference().cloned(),
        }
    }

    /// Puts the height field back together, validating it like any input: the parts come from
    /// another thread's JavaScript object, so a message names what does not fit.
    pub(crate) fn into_heightfield(self) -> Result<Heightfield, String> {
        let values = &self.placement_values;
        let vector = |at: usize| -> Result<[f64; 3], String> {
            values
                .get(at..at + 3)
                .and_then(|s| s.try_into().ok())
                .ok_or_else(|| "parsed surface: placement has too few values".to_string())
        };
        let placement = match self.placement_kind.as_str() {
            "grid" => Placement::Grid,
            "planar" => Placement::Planar {
                origin: vector(0)?,
                u: vector(3)?,
                v: vector(6)?,
                n: vector(9)?,
            },
            "cylindrical" => Placement::Cylindrical {
                origin: vector(0)?,
                axis: vector(3)?,
                reference: vector(6)?,
            },
            other => return Err(format!("parsed surface: unknown placement {other}")),
        };
        let mut hf = Heightfield::new(self.width, self.height, self.z)
            .map_err(|e| e.to_string())?
            .with_geometry(self.origin, self.spacing)
            .map_err(|e| e.to_string())?
            .with_placement(placement)
            .with_source(self.source)
            .with_filled(self.filled);
        if self.resampled {
            hf = hf.with_resampled();
        }
        if let Some(georeference) = self.georeference {
            hf = hf.with_georeference(georeference);
        }
        Ok(hf)
    }
}
