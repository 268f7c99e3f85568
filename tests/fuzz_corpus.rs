//! Replays the fuzz targets' committed inputs on stable: the seed corpus (`fuzz/seeds/<target>/`)
//! and every input a campaign found a failure with (`fuzz/regressions/<target>/`), through the
//! same code the libFuzzer targets run (`fuzz/src/lib.rs`), which panics on a failed property.
//! See docs/fuzzing.md for running a campaign.

#[path = "../fuzz/src/lib.rs"]
mod fuzz_harness;

use fuzz_harness::{Target, run};
use paretomesh::import;
use paretomesh::import::{ImportError, ImportOptions};
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The system allocator, counting the bytes live at once, so that a test can check that an
/// import refuses a file before it allocates what the file's header claims.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(live, Ordering::Relaxed);
        }
        p
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(live, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

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

/// Every file of `fuzz/regressions/`: its target, its name, and words its error must contain.
/// Each is a tiny file whose header claims a huge grid or mesh, the shape of the inputs found
/// around the campaigns (docs/fuzzing.md): the PNG decoder refused such a claim only after a bare
/// "limits are exceeded", and every importer must refuse one before allocating what it claims.
const REGRESSIONS: [(Target, &str, &str); 9] = [
    (
        Target::Raw,
        "sidecar_claims_100000_square",
        "10000.0 M points",
    ),
    (
        Target::Raw,
        "sidecar_claims_2048_square",
        "needs 16777216 bytes",
    ),
    (Target::Png, "ihdr_claims_2pow30_square", "M points"),
    (Target::Png, "ihdr_claims_u32max_wide", "16384 per side"),
    (Target::Tiff, "claims_100000_square", "100000×100000"),
    (
        Target::Ply,
        "ascii_claims_1e12_vertices",
        "claims 1000000000000 vertices",
    ),
    (
        Target::Ply,
        "binary_claims_16m_vertices",
        "need at least 192000000 bytes",
    ),
    (
        Target::Stl,
        "claims_u32max_triangles",
        "claims 4294967295 triangles",
    ),
    (
        Target::Stl,
        "promises_30m_triangles",
        "promises 30000000 triangles",
    ),
];

#[test]
fn crash_regressions_replay_as_descriptive_refusals() {
    // Through the fuzz targets' own checks (no panic, an error naming the format), every kept
    // regression, and nothing but the listed ones, is refused under every option set.
    let outcomes = replay("regressions");
    let mut replayed: Vec<(Target, String)> = outcomes
        .iter()
        .map(|(target, file, _)| (*target, file.file_name().unwrap().to_string_lossy().into()))
        .collect();
    replayed.sort_by_key(|(t, name)| (t.name(), name.clone()));
    let mut listed: Vec<(Target, String)> = REGRESSIONS
        .iter()
        .map(|&(target, name, _)| (target, name.to_string()))
        .collect();
    listed.sort_by_key(|(t, name)| (t.name(), name.clone()));
    assert_eq!(replayed, listed, "fuzz/regressions/ and REGRESSIONS differ");
    for (target, file, lines) in &outcomes {
        assert!(
            !lines.is_empty() && lines.iter().all(|l| l.starts_with("error: ")),
            "{target:?} {}: {lines:?}",
            file.display()
        );
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

#[test]
fn absurd_declared_sizes_are_refused_before_allocating() {
    // Each file of fuzz/regressions/ is tiny but its header claims a huge grid or mesh; the
    // import must refuse it having allocated little (not the claimed size), with an error that
    // names the problem.
    for (target, file, expected) in REGRESSIONS {
        let data = std::fs::read(fuzz_dir("regressions", target).join(file)).expect("readable");
        let (bytes, sidecar) = match target {
            Target::Raw => {
                let (json, grid) = fuzz_harness::split_raw(&data);
                (grid, Some(json))
            }
            _ => (&data[..], None),
        };
        let name = target.file_name();
        let before = LIVE.load(Ordering::Relaxed);
        PEAK.store(before, Ordering::Relaxed);
        let result = import::from_bytes(name, bytes, sidecar, &ImportOptions::default());
        let peak = PEAK.load(Ordering::Relaxed).saturating_sub(before);
        let err: ImportError = match result {
            Ok(hf) => panic!(
                "{file} claiming a huge size imported as {}×{}",
                hf.width(),
                hf.height()
            ),
            Err(e) => e,
        };
        let message = err.to_string();
        assert!(message.contains(expected), "{file}: {message}");
        // Other tests run at the same time and allocate a little; the claims are gigabytes.
        assert!(
            peak < 64 << 20,
            "{file}: {peak} bytes allocated before refusing: {message}"
        );
    }
}

#[test]
fn long_crossing_triangles_are_refused_instead_of_rasterised_for_minutes() {
    // 40 000 triangles between points on a circle's rim, each spanning much of the disc: their
    // bounding boxes cover the automatic grid about a thousand times over (in a 10 MB file,
    // minutes of rasterisation). The import stops at the test budget with an error saying why.
    let rim = 4096;
    let point = |k: usize| {
        let a = std::f64::consts::TAU * (k % rim) as f64 / rim as f64;
        [a.cos() as f32, a.sin() as f32, (k % 7) as f32 * 1e-3]
    };
    let count: u32 = 40_000;
    let mut stl = vec![0u8; 80];
    stl.extend_from_slice(&count.to_le_bytes());
    for i in 0..count as usize {
        stl.extend_from_slice(&[0u8; 12]);
        for k in [i, i * 7919 + rim / 3, i * 104_729 + 2 * rim / 3] {
            for c in point(k) {
                stl.extend_from_slice(&c.to_le_bytes());
            }
        }
        stl.extend_from_slice(&[0, 0]);
    }
    let err = import::from_bytes("slivers.stl", &stl, None, &ImportOptions::default())
        .expect_err("crossing slivers are not a surface");
    assert!(matches!(err, ImportError::RasterLimit { .. }), "{err:?}");
    assert!(err.to_string().contains("remesh it"), "{err}");
}
