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

/// A PNG chunk with its CRC-32 (the decoder checks it).
fn png_chunk(kind: &[u8; 4], body: &[u8]) -> Vec<u8> {
    let mut crc = !0u32;
    for &b in kind.iter().chain(body) {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    let mut out = (body.len() as u32).to_be_bytes().to_vec();
    out.extend_from_slice(kind);
    out.extend_from_slice(body);
    out.extend_from_slice(&(!crc).to_be_bytes());
    out
}

/// A PNG that claims `width`×`height` 16-bit RGBA pixels and holds a few bytes of image data.
fn png_claiming(width: u32, height: u32) -> Vec<u8> {
    let mut ihdr = width.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[16, 6, 0, 0, 0]);
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    out.extend(png_chunk(b"IHDR", &ihdr));
    out.extend(png_chunk(
        b"IDAT",
        &[0x78, 0x9c, 0x03, 0x00, 0x00, 0x00, 0x00, 0x01],
    ));
    out.extend(png_chunk(b"IEND", &[]));
    out
}

/// A little-endian TIFF that claims `width`×`height` 64-bit float samples in one uncompressed
/// strip of a few bytes.
fn tiff_claiming(width: u32, height: u32) -> Vec<u8> {
    // (tag, type, count, value): type 3 = SHORT, 4 = LONG.
    let entries: [(u16, u16, u32, u32); 10] = [
        (256, 4, 1, width),
        (257, 4, 1, height),
        (258, 3, 1, 64),
        (259, 3, 1, 1),
        (262, 3, 1, 1),
        (273, 4, 1, 8 + 2 + 10 * 12 + 4),
        (277, 3, 1, 1),
        (278, 4, 1, height),
        (279, 4, 1, 8),
        (339, 3, 1, 3),
    ];
    let mut out = b"II*\0".to_vec();
    out.extend_from_slice(&8u32.to_le_bytes());
    out.extend_from_slice(&(entries.len() as u16).to_le_bytes());
    for (tag, kind, count, value) in entries {
        out.extend_from_slice(&tag.to_le_bytes());
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(&count.to_le_bytes());
        out.extend_from_slice(&value.to_le_bytes());
    }
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&[0; 8]);
    out
}

/// A binary STL header that claims `count` triangles, with no triangle after it.
fn stl_claiming(count: u32) -> Vec<u8> {
    let mut out = vec![0u8; 80];
    out.extend_from_slice(&count.to_le_bytes());
    out
}

#[test]
fn absurd_declared_sizes_are_refused_before_allocating() {
    // Each file is tiny but its header claims a huge grid or mesh; the import must refuse it
    // having allocated little (not the claimed size), with an error that names the problem.
    let ply = |format: &str, vertices: &str| {
        format!(
            "ply\nformat {format} 1.0\nelement vertex {vertices}\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n"
        )
        .into_bytes()
    };
    let raw = |w: u64, h: u64| format!("{{\"width\": {w}, \"height\": {h}}}").into_bytes();
    // (file name, bytes, sidecar, words the error must contain)
    type Case = (&'static str, Vec<u8>, Option<Vec<u8>>, &'static str);
    let cases: Vec<Case> = vec![
        (
            "a.ply",
            ply("ascii", "1000000000000"),
            None,
            "claims 1000000000000 vertices",
        ),
        (
            "a.ply",
            ply("binary_little_endian", "16000000"),
            None,
            "need at least 192000000 bytes",
        ),
        (
            "a.f32",
            vec![0; 16],
            Some(raw(100_000, 100_000)),
            "10000.0 M points",
        ),
        (
            "a.f32",
            vec![0; 16],
            Some(raw(2048, 2048)),
            "needs 16777216 bytes",
        ),
        ("a.png", png_claiming(1 << 30, 1 << 30), None, "M points"),
        ("a.png", png_claiming(u32::MAX, 3), None, "16384 per side"),
        (
            "a.tif",
            tiff_claiming(100_000, 100_000),
            None,
            "100000×100000",
        ),
        (
            "a.stl",
            stl_claiming(u32::MAX),
            None,
            "claims 4294967295 triangles",
        ),
        (
            "a.stl",
            stl_claiming(30_000_000),
            None,
            "promises 30000000 triangles",
        ),
    ];
    for (name, bytes, sidecar, expected) in cases {
        let before = LIVE.load(Ordering::Relaxed);
        PEAK.store(before, Ordering::Relaxed);
        let result =
            import::from_bytes(name, &bytes, sidecar.as_deref(), &ImportOptions::default());
        let peak = PEAK.load(Ordering::Relaxed).saturating_sub(before);
        let err: ImportError = match result {
            Ok(hf) => panic!(
                "{name} claiming a huge size imported as {}×{}",
                hf.width(),
                hf.height()
            ),
            Err(e) => e,
        };
        let message = err.to_string();
        assert!(message.contains(expected), "{name}: {message}");
        // Other tests run at the same time and allocate a little; the claims are gigabytes.
        assert!(
            peak < 64 << 20,
            "{name}: {peak} bytes allocated before refusing: {message}"
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
