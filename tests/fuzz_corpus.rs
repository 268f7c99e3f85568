//! Replays the fuzz targets' committed inputs on stable: the seed corpus (`fuzz/seeds/<target>/`)
//! and every input a campaign found a failure with (`fuzz/regressions/<target>/`), through the
//! same code the libFuzzer targets run (`fuzz/src/lib.rs`), which panics on a failed property.
//! See docs/fuzzing.md for running a campaign.

#[path = "../fuzz/src/lib.rs"]
mod fuzz_harness;

use fuzz_harness::{Target, run};
use std::path::{Path, PathBuf};

fn fuzz_dir(kind: &str, target: Target) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz")
        .join(kind)
        .join(target.name())
}

/// The files in a folder, sorted; none when the folder does not exist.
fn files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .map(|e| e.expect("readable folder entry").path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
}

/// Runs every file of `kind` for every target; returns (target, file, outcome per option set).
fn replay(kind: &str) -> Vec<(Target, PathBuf, Vec<String>)> {
    let mut outcomes = Vec::new();
    for target in Target::ALL {
        for file in files(&fuzz_dir(kind, target)) {
            let data = std::fs::read(&file).expect("readable input");
            let result = std::panic::catch_unwind(|| run(target, &data));
            match result {
                Ok(lines) => outcomes.push((target, file, lines)),
                Err(_) => panic!(
                    "{} failed a fuzz property (see the panic message above)",
                    file.display()
                ),
            }
        }
    }
    outcomes
}

#[test]
fn seed_corpus_imports_without_panic_and_every_format_has_a_valid_seed() {
    let outcomes = replay("seeds");
    for target in Target::ALL {
        let mine: Vec<_> = outcomes.iter().filter(|(t, ..)| *t == target).collect();
        assert!(
            mine.len() >= 3,
            "{}: only {} seeds; the corpus should cover the format's variants",
            target.name(),
            mine.len()
        );
        // The seeds are valid files (a few deliberately bad ones aside): the default import of
        // most of them must succeed, or the corpus only exercises error paths.
        let ok = mine
            .iter()
            .filter(|(.., lines)| lines[0].starts_with("ok "))
            .count();
        assert!(
            ok * 2 > mine.len(),
            "{}: only {ok} of {} seeds import: {:#?}",
            target.name(),
            mine.len(),
            mine
        );
    }
}

#[test]
fn crash_regressions_replay_without_panic() {
    // Each file once made a target panic, exceed its memory bound or time out; all now give an
    // import or a descriptive error.
    let outcomes = replay("regressions");
    for (target, file, lines) in &outcomes {
        assert!(!lines.is_empty(), "{target:?} {}", file.display());
    }
}

#[test]
fn raw_inputs_split_into_sidecar_and_grid() {
    let (json, grid) = fuzz_harness::split_raw(b"\x02\x00{}abcd");
    assert_eq!((json, grid), (&b"{}"[..], &b"abcd"[..]));
    // A length past the end takes everything as the sidecar.
    let (json, grid) = fuzz_harness::split_raw(b"\xff\x00{}");
    assert_eq!((json, grid), (&b"{}"[..], &b""[..]));
}
