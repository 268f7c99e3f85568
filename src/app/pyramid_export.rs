//! The current front as a 3D Tiles pyramid in one `.zip` (tileset.json and the tiles' `.glb`
//! files, laid out as `paretomesh tiles` writes them) for the app's export button.

use super::state::App;
use crate::export::deflated_zip;
use crate::front::Solution;
use crate::heightfield::Heightfield;
use crate::pyramid::{build, default_levels};

/// Why a tiled run's front gives no pyramid: a pyramid's levels are whole-grid members, and a
/// tiled run keeps its members as tiles' fronts.
pub(crate) const TILED_FRONT: &str = "this run was cut into tiles, and a 3D Tiles pyramid is made from an untiled front: run `paretomesh run` with a --tile as large as the grid, then `paretomesh tiles` on its front";

/// The pyramid of `front` on `hf` as a zip archive, with the levels `paretomesh tiles` takes
/// by default. A front of fewer than two members is refused with the reason.
pub(crate) fn pyramid_zip(hf: &Heightfield, front: &[Solution]) -> Result<Vec<u8>, String> {
    let scores: Vec<_> = front.iter().map(|s| s.score).collect();
    let kept: Vec<&[u32]> = front.iter().map(|s| &s.kept[..]).collect();
    let levels = default_levels(&scores, hf.width(), hf.height());
    let files = build(hf, &scores, &kept, levels)?.into_files();
    let parts: Vec<(&str, &[u8])> = files
        .iter()
        .map(|(name, data)| (name.as_str(), &data[..]))
        .collect();
    deflated_zip(&parts)
}

impl App {
    /// The current front's pyramid as a zip archive; refused, with the reason, before a run, for
    /// a tiled run and for a front of one member.
    pub(crate) fn pyramid_zip(&self) -> Result<Vec<u8>, String> {
        if self.tiled_run().is_some() {
            return Err(TILED_FRONT.to_owned());
        }
        let front = self
            .front()
            .filter(|f| !f.is_empty())
            .ok_or("run an algorithm first: the front is empty")?;
        pyramid_zip(&self.surface().heightfield, front.solutions())
    }
}
