//! `paretomesh eval GRID --keep FILE|- [import options]`.

use super::input::InputArgs;
use paretomesh::evaluator::Evaluator;
use std::io::Read;

pub fn run(input: &InputArgs, keep: &str) -> Result<(), String> {
    let hf = input.load()?;
    let text = if keep == "-" {
        let mut s = String::new();
        std::io::stdin()
            .read_to_string(&mut s)
            .map_err(|e| format!("cannot read the kept indices from standard input: {e}"))?;
        s
    } else {
        std::fs::read_to_string(keep).map_err(|e| format!("cannot read {keep}: {e}"))?
    };
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
