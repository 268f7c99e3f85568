//! A front.json as `export` reads it: the members with or without their triangles, the grid it
//! was made on, and the member a selector picks.

use paretomesh::evaluator::Score;
use paretomesh::metrics::trade_off_pick;
use paretomesh::run_file::RunFile;
use paretomesh::tiling::TiledRunFile;
use std::path::{Path, PathBuf};

/// A front.json of an untiled or a tiled run.
pub enum AnyFront {
    /// An untiled run: a kept list per member.
    Untiled(RunFile),
    /// A tiled run: per-tile kept sets and a choice per tile for each member.
    Tiled(Box<TiledRunFile>),
}

/// Reads and parses the front.json at `path` (untiled, with or without triangles, or tiled);
/// the error names the file.
pub fn read(path: &Path) -> Result<AnyFront, String> {
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
        let file: TiledRunFile = serde_json::from_slice(&bytes).map_err(not_a_front)?;
        let members = file.tiled.members.len();
        (AnyFront::Tiled(Box::new(file)), members)
    } else {
        let file: RunFile = serde_json::from_slice(&bytes).map_err(not_a_front)?;
        let members = file.front.len();
        (AnyFront::Untiled(file), members)
    };
    if members == 0 {
        return Err(format!("{} has no members in its front", path.display()));
    }
    Ok(file)
}

/// How the member to export is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Selector {
    /// The member at this index in the file's order.
    Index(usize),
    /// The paper's trade-off pick (eq. 7–9), its weights drawn with the front's seed.
    TradeOff,
    /// The lowest E_sum among members with at most this many triangles.
    MaxTriangles(usize),
    /// The fewest triangles among members with E_sum at most this.
    MaxError(f64),
}

/// The index of the member `selector` picks from the members' scores `members` (in the file's
/// order); `seed` draws the trade-off pick's weights. Ties go to the earlier member after the secondary objective,
/// so the pick depends on the file alone.
pub fn select(members: &[Score], selector: Selector, seed: u64) -> Result<usize, String> {
    let count = members.len();
    match selector {
        Selector::Index(k) if k < count => Ok(k),
        Selector::Index(k) => Err(format!(
            "--member {k} is out of range: the front has {count} members, numbered 0 to {}",
            count - 1
        )),
        Selector::TradeOff => {
            let points: Vec<[f64; 2]> = members.iter().map(Score::objectives).collect();
            trade_off_pick(&points, seed)
                .map(|pick| pick.index)
                .map_err(|e| format!("no trade-off pick: {e}"))
        }
        Selector::MaxTriangles(n) => (0..count)
            .filter(|&i| members[i].t <= n)
            .min_by(|&i, &j| {
                let (a, b) = (&members[i], &members[j]);
                a.e_sum.total_cmp(&b.e_sum).then(a.t.cmp(&b.t))
            })
            .ok_or_else(|| {
                let fewest = members.iter().map(|m| m.t).min().unwrap_or(0);
                format!("no member has at most {n} triangles: the smallest member has {fewest}")
            }),
        Selector::MaxError(e) => (0..count)
            .filter(|&i| members[i].e_sum <= e)
            .min_by(|&i, &j| {
                let (a, b) = (&members[i], &members[j]);
                a.t.cmp(&b.t).then(a.e_sum.total_cmp(&b.e_sum))
            })
            .ok_or_else(|| {
                let least = members
                    .iter()
                    .map(|m| m.e_sum)
                    .min_by(f64::total_cmp)
                    .unwrap_or(f64::NAN);
                format!("no member has E_sum at most {e}: the most accurate member has {least}")
            }),
    }
}

/// Supported grid file extensions, to spot a file name inside a source note.
const GRID_EXTENSIONS: [&str; 7] = ["f32", "png", "tif", "tiff", "ply", "obj", "stl"];

/// The file names a source note may hold, longest first for each end: front.json records the
/// grid only in its note, which names the file as it was given to `run` (e.g. "raw f32 grid
/// tests/data/a.f32; …", "PLY mesh my scans/b.ply (…"). A name may contain spaces, so every
/// word start before a grid extension is a candidate; the caller keeps the first that exists.
pub fn named_files(note: &str) -> Vec<&str> {
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
pub fn find_grid(front_path: &Path, note: &str) -> Result<PathBuf, String> {
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

    fn member(e: f64, t: usize) -> Score {
        paretomesh::front::Solution::recorded(e, e, t, vec![]).score
    }

    #[test]
    fn selectors_pick_by_their_rule_in_the_files_order() {
        // Not sorted by T, with a tie in E under the triangle limit and a tie in T under the
        // error limit: the secondary objective decides, then the earlier member.
        let members = [
            member(5.0, 10),
            member(9.0, 4),
            member(5.0, 8),
            member(2.0, 30),
            member(5.0, 8),
        ];
        let pick = |s| select(&members, s, 1);
        assert_eq!(pick(Selector::Index(3)), Ok(3));
        assert_eq!(pick(Selector::MaxTriangles(10)), Ok(2));
        assert_eq!(pick(Selector::MaxTriangles(4)), Ok(1));
        assert_eq!(pick(Selector::MaxTriangles(1000)), Ok(3));
        assert_eq!(pick(Selector::MaxError(5.0)), Ok(2));
        assert_eq!(pick(Selector::MaxError(100.0)), Ok(1));
        assert_eq!(pick(Selector::MaxError(2.0)), Ok(3));
    }

    #[test]
    fn selectors_that_find_nothing_say_what_the_front_has() {
        let members = [member(5.0, 10), member(9.0, 4)];
        let out = select(&members, Selector::Index(2), 1).unwrap_err();
        assert!(out.contains("2 members, numbered 0 to 1"), "{out}");
        let out = select(&members, Selector::MaxTriangles(3), 1).unwrap_err();
        assert!(
            out.contains("at most 3 triangles") && out.contains("has 4"),
            "{out}"
        );
        let out = select(&members, Selector::MaxError(4.5), 1).unwrap_err();
        assert!(
            out.contains("at most 4.5") && out.contains("has 5"),
            "{out}"
        );
    }

    #[test]
    fn the_trade_off_selector_is_the_metrics_pick() {
        let members = [
            member(100.0, 2),
            member(20.0, 10),
            member(5.0, 40),
            member(1.0, 200),
        ];
        let points: Vec<[f64; 2]> = members.iter().map(Score::objectives).collect();
        for seed in [1, 7] {
            let expected = trade_off_pick(&points, seed).unwrap().index;
            assert_eq!(select(&members, Selector::TradeOff, seed), Ok(expected));
        }
    }

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
