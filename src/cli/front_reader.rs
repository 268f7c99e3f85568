//! A front.json as `export` reads it: the members with or without their triangles, and the grid
//! it was made on.

use paretomesh::front_file::FrontFile;
use paretomesh::tiling::TiledFrontFile;
use std::path::{Path, PathBuf};

/// A front.json of an untiled or a tiled run.
pub(super) enum AnyFront {
    /// An untiled run: a kept list per member.
    Untiled(Box<FrontFile>),
    /// A tiled run: per-tile kept sets and a choice per tile for each member.
    Tiled(Box<TiledFrontFile>),
}

/// Reads and parses the front.json at `path` (untiled, with or without triangles, or tiled);
/// the error names the file.
pub(super) fn read(path: &Path) -> Result<AnyFront, String> {
    /// Only whether the file has a tiled front.
    #[derive(serde::Deserialize)]
    struct Probe {
        #[serde(default)]
        tiled: Option<serde::de::IgnoredAny>,
    }
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let not_a_front = |e: serde_json::Error| format!("{} is not a front.json: {e}", path.display());
    let probe: Probe = serde_json::from_slice(&bytes).map_err(not_a_front)?;
    let (file, members) = if probe.tiled.is_some() {
        let file: TiledFrontFile = serde_json::from_slice(&bytes).map_err(not_a_front)?;
        let members = file.tiled.members.len();
        (AnyFront::Tiled(Box::new(file)), members)
    } else {
        let file: FrontFile = serde_json::from_slice(&bytes).map_err(not_a_front)?;
        let members = file.front.len();
        (AnyFront::Untiled(Box::new(file)), members)
    };
    if members == 0 {
        return Err(format!("{} has no members in its front", path.display()));
    }
    Ok(file)
}

/// Supported grid file extensions, to spot a file name inside a source note.
const GRID_EXTENSIONS: [&str; 7] = ["f32", "png", "tif", "tiff", "ply", "obj", "stl"];

/// The file names a source note may hold, longest first for each end: front.json records the
/// grid only in its note, which names the file as it was given to `run` (e.g. "raw f32 grid
/// tests/data/a.f32; …", "PLY mesh my scans/b.ply (…"). A name may contain spaces, so every
/// word start before a grid extension is a candidate; the caller keeps the first that exists.
pub(super) fn named_files(note: &str) -> Vec<&str> {
    let lower = note.to_ascii_lowercase();
    let mut names = Vec::new();
    for (dot, _) in lower.match_indices('.') {
        let rest = &lower[dot + 1..];
        for ext in GRID_EXTENSIONS {
            let end = dot + 1 + ext.len();
            let at_boundary = rest.starts_with(ext)
                && lower[end..]
                    .chars()
                    .next()
                    .is_none_or(|c| matches!(c, ';' | ' ' | ')' | ',' | ':'));
            if !at_boundary {
                continue;
            }
            let starts = std::iter::once(0).chain(
                note[..dot]
                    .match_indices(' ')
                    .map(|(space, _)| space + 1)
                    .filter(|&s| s < dot),
            );
            names.extend(starts.map(|s| &note[s..end]));
        }
    }
    names
}

/// The grid file that front.json at `front_path` names, looked for as named (absolute, or from
/// the current folder, as `run` was given it), then beside front.json with the same relative
/// path, then beside front.json by its file name alone.
pub(super) fn find_grid(front_path: &Path, note: &str) -> Result<PathBuf, String> {
    let folder = front_path.parent().unwrap_or(Path::new(""));
    let names = named_files(note);
    for name in &names {
        let named = Path::new(name);
        let mut tries = vec![named.to_path_buf()];
        if named.is_relative() {
            tries.push(folder.join(named));
        }
        if let Some(file_name) = named.file_name() {
            tries.push(folder.join(file_name));
        }
        if let Some(found) = tries.into_iter().find(|p| p.is_file()) {
            return Ok(found);
        }
    }
    if names.is_empty() {
        return Err(format!(
            "{} does not name its grid file (its grid note reads {note:?}); give the grid with --grid",
            front_path.display()
        ));
    }
    // Candidates with spaces are mostly the note's words before the name; show them only
    // when there is nothing else.
    let plain: Vec<&str> = names.iter().copied().filter(|n| !n.contains(' ')).collect();
    let shown = if plain.is_empty() {
        names.join(", ")
    } else {
        plain.join(", ")
    };
    let places = if folder.as_os_str().is_empty() {
        "the current folder".to_string()
    } else {
        format!("the current folder and in {}", folder.display())
    };
    Err(format!(
        "the grid of {} was not found: looked for {shown} in {places}; give the grid with --grid",
        front_path.display()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names_are_found_in_every_importers_note() {
        let cases = [
            (
                "raw f32 grid tests/data/bunny_33x33.f32; range image; units: m",
                "tests/data/bunny_33x33.f32",
            ),
            (
                "PLY mesh my scans/b.PLY (1089 vertices, 2048 triangles): exact grid",
                "my scans/b.PLY",
            ),
            (
                "GeoTIFF dem.tif (87×61); grid row 0 is the southern row",
                "dem.tif",
            ),
            (
                "16-bit grayscale PNG /tmp/h.png; image row 0 is grid row 0",
                "/tmp/h.png",
            ),
            ("STL mesh part.stl", "part.stl"),
        ];
        for (note, name) in cases {
            let names = named_files(note);
            assert!(names.contains(&name), "{note}: {names:?}");
            // Every candidate ends with the file name, so a wrong start only costs a lookup.
            assert!(names.iter().all(|n| n.ends_with(&name[name.len() - 4..])));
        }
        assert!(named_files("a grid made in memory; 3.5 m spacing").is_empty());
    }
}
