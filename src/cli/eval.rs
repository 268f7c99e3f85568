//! `paretomesh eval GRID (--keep FILE|- | --triangles FILE|-) [import options]`.

use super::input::InputArgs;
use paretomesh::evaluator::Evaluator;
use std::io::Read;

/// The text of `source`: a file, or standard input for `-`.
fn read_text(source: &str, what: &str) -> Result<String, String> {
    if source == "-" {
        let mut s = String::new();
        std::io::stdin()
            .read_to_string(&mut s)
            .map_err(|e| format!("cannot read the {what} from standard input: {e}"))?;
        Ok(s)
    } else {
        std::fs::read_to_string(source).map_err(|e| format!("cannot read {source}: {e}"))
    }
}

/// `eval --triangles`: the score of a given triangulation (E over every grid point, each
/// counted once on the triangle that owns it), as JSON.
pub(super) fn run_triangles(input: &InputArgs, triangles: &str) -> Result<(), String> {
    let hf = input.load()?;
    let text = read_text(triangles, "triangles")?;
    let triangles: Vec<[u32; 3]> = serde_json::from_str(&text)
        .map_err(|e| format!("--triangles must be a JSON array of [a, b, c] grid indices: {e}"))?;
    let score = Evaluator::new(std::sync::Arc::new(hf))
        .score_triangulation(&triangles)
        .map_err(|e| e.to_string())?;
    println!(
        "{}",
        serde_json::to_string(&score).expect("plain numbers serialise")
    );
    Ok(())
}

pub(super) fn run(input: &InputArgs, keep: &str) -> Result<(), String> {
    let hf = input.load()?;
    let text = read_text(keep, "kept indices")?;
    let kept: Vec<u32> = serde_json::from_str(&text)
        .map_err(|e| format!("--keep must be a JSON array of grid indices: {e}"))?;
    let evaluation = Evaluator::new(std::sync::Arc::new(hf))
        .evaluate(&kept)
        .map_err(|e| e.to_string())?;
    println!(
        "{}",
        serde_json::to_string(&evaluation).expect("plain numbers serialise")
    );
    Ok(())
}
