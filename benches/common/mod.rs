//! Grids for the benches, so that they run from a fresh clone: fixtures from `tests/data`, and a
//! larger terrain made by `scripts/terrain.py`.

// Each bench includes this module and uses part of it.
#![allow(dead_code)]

use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use rand::{RngExt, SeedableRng};
use std::path::Path;

/// A fixture from `tests/data` by name (`jacksboro_65x65` reads `tests/data/jacksboro_65x65.f32`).
pub fn fixture(name: &str) -> Heightfield {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/data/{name}.f32"));
    import::load(&path).unwrap_or_else(|e| panic!("fixture {name}: {e}"))
}

/// The benches' larger grid, as its name and heights. Under `cargo bench` (which passes
/// `--bench`) it is `fractal_257`, the fbm terrain of `scripts/terrain.py` (the project's one
/// terrain generator; the same grid as `bash scripts/make-grids.sh`'s `fractal_257.f32`), made
/// once and kept beside the bench binaries. `cargo test --all-targets` (CI) runs every bench
/// once in a debug build to check that it works, where greedy insertion and decimation of
/// 257×257 points take most of a minute; that check needs only that the code runs, so it takes
/// the measured 65×65 grid `tests/data/bunny_65x65` and needs no Python.
pub fn large_grid() -> (String, Heightfield) {
    if std::env::args().any(|a| a == "--bench") {
        ("fractal_257".to_string(), generated_fbm(257))
    } else {
        ("bunny_65x65".to_string(), fixture("bunny_65x65"))
    }
}

/// `scripts/terrain.py fbm --seed 1 --size {size}`, generated into `bench-grids/` beside the
/// bench binaries unless already there, with the project's Python (`.venv-python`, made by
/// `bash scripts/setup.sh`) or else `python3`; either needs numpy.
fn generated_fbm(size: usize) -> Heightfield {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = std::env::current_exe().expect("the bench binary's path");
    // target/<profile>/deps/<bench> -> target/<profile>/bench-grids
    let dir = exe
        .ancestors()
        .nth(2)
        .expect("a target folder")
        .join("bench-grids");
    let grid = dir.join(format!("fractal_{size}.f32"));
    if !grid.exists() {
        // Made in a folder of this process and then renamed, so that a bench that runs at the
        // same time never reads a half-written grid.
        let scratch = dir.join(format!("making-{}", std::process::id()));
        std::fs::create_dir_all(&scratch).expect("the bench-grids folder");
        let venv = root.join(".venv-python/bin/python");
        let python = if venv.exists() {
            venv
        } else {
            "python3".into()
        };
        let made = scratch.join(grid.file_name().unwrap());
        let status = std::process::Command::new(&python)
            .arg(root.join("scripts/terrain.py"))
            .args(["fbm", "--seed", "1", "--size", &size.to_string(), "--out"])
            .arg(&made)
            .status()
            .unwrap_or_else(|e| panic!("running {}: {e}", python.display()));
        assert!(
            status.success(),
            "scripts/terrain.py failed ({status}): it needs numpy, which `bash scripts/setup.sh` \
             installs in .venv-python"
        );
        std::fs::rename(made.with_extension("json"), grid.with_extension("json"))
            .expect("moving the sidecar");
        std::fs::rename(&made, &grid).expect("moving the grid");
        let _ = std::fs::remove_dir(&scratch);
    }
    import::load(&grid).unwrap_or_else(|e| panic!("{}: {e}", grid.display()))
}

/// `fraction` of the `n` grid points, chosen at random with a fixed seed, plus `corners`,
/// sorted: a kept set as the GAs' chromosomes are.
pub fn kept_subset(n: usize, fraction: f64, seed: u64, corners: [u32; 4]) -> Vec<u32> {
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
    let mut kept: Vec<u32> = (0..n as u32)
        .filter(|_| rng.random::<f64>() < fraction)
        .collect();
    kept.extend(corners);
    kept.sort_unstable();
    kept.dedup();
    kept
}
