//! The app's "3D Tiles (.zip)" download, natively: the current front's pyramid in one zip, read
//! back through the archive's central directory, and the fronts it refuses.

use crate::app::algorithms::{Algorithm, Params};
use crate::app::pool::PoolSetup;
use crate::app::pyramid_export::{TILED_FRONT, pyramid_zip};
use crate::app::state::{App, RunConfig, Surface};
use crate::heightfield::Heightfield;
use crate::import::raw;
use serde_json::Value;
use std::collections::BTreeMap;
use std::sync::Arc;

const GRID: &[u8] = include_bytes!("../../../tests/data/volcano_33x33.f32");
const SIDECAR: &[u8] = include_bytes!("../../../tests/data/volcano_33x33.json");

fn app(hf: Heightfield) -> App {
    App::new(
        Surface {
            name: "volcano_33x33".into(),
            heightfield: Arc::new(hf),
        },
        RunConfig {
            algorithm: Algorithm::Nsga2,
            params: Params {
                population: 16,
                generations: 8,
                seed: 3,
                ..Params::default()
            },
            budget_ms: 8.0,
        },
    )
}

fn volcano() -> Heightfield {
    raw::parse(GRID, SIDECAR, "volcano_33x33").unwrap()
}

/// Little-endian integers at `at`.
fn u16_at(b: &[u8], at: usize) -> usize {
    u16::from_le_bytes([b[at], b[at + 1]]) as usize
}
fn u32_at(b: &[u8], at: usize) -> usize {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap()) as usize
}

/// The entries of a zip archive by name, inflated and checked against their CRC-32, read
/// through the central directory as an unzip tool does.
fn unzip(zip: &[u8]) -> BTreeMap<String, Vec<u8>> {
    let end = (0..zip.len() - 3)
        .rev()
        .find(|&i| zip[i..i + 4] == [0x50, 0x4b, 0x05, 0x06])
        .expect("an end-of-directory record");
    let entries = u16_at(zip, end + 10);
    let mut at = u32_at(zip, end + 16);
    let mut out = BTreeMap::new();
    for _ in 0..entries {
        assert_eq!(u32_at(zip, at), 0x0201_4b50, "a central directory entry");
        let method = u16_at(zip, at + 10);
        let crc = u32_at(zip, at + 16) as u32;
        let packed = u32_at(zip, at + 20);
        let size = u32_at(zip, at + 24);
        let name_len = u16_at(zip, at + 28);
        let skip = name_len + u16_at(zip, at + 30) + u16_at(zip, at + 32);
        let local = u32_at(zip, at + 42);
        let name = String::from_utf8(zip[at + 46..at + 46 + name_len].to_vec()).unwrap();
        assert_eq!(u32_at(zip, local), 0x0403_4b50, "{name}: a local header");
        let start = local + 30 + u16_at(zip, local + 26) + u16_at(zip, local + 28);
        let data = &zip[start..start + packed];
        let data = match method {
            8 => miniz_oxide::inflate::decompress_to_vec(data).expect("inflates"),
            0 => data.to_vec(),
            m => panic!("{name}: method {m}"),
        };
        assert_eq!(data.len(), size, "{name}: its recorded size");
        assert_eq!(crc32fast::hash(&data), crc, "{name}: its recorded CRC");
        assert!(out.insert(name, data).is_none(), "names are unique");
        at += 46 + skip;
    }
    out
}

/// Every content URI in the tileset's tree.
fn content_uris(node: &Value, out: &mut Vec<String>) {
    if let Some(uri) = node["content"]["uri"].as_str() {
        out.push(uri.to_owned());
    }
    for child in node["children"].as_array().into_iter().flatten() {
        content_uris(child, out);
    }
}

#[test]
fn a_finished_run_downloads_a_pyramid_whose_every_tile_is_in_the_zip() {
    let mut app = app(volcano());
    assert!(
        app.pyramid_zip()
            .unwrap_err()
            .contains("run an algorithm first"),
        "nothing to tile before a run"
    );
    app.run().unwrap();
    let mut clock = {
        let mut now = 0.0;
        move || {
            now += 1.0;
            now
        }
    };
    for _ in 0..100_000 {
        if !app.is_running() {
            break;
        }
        app.tick(8.0, &mut clock);
    }
    assert!(app.status().done, "the run finishes");
    let front = app.front().unwrap().solutions().to_vec();
    assert!(front.len() >= 4, "a front of {} members", front.len());

    let files = unzip(&app.pyramid_zip().unwrap());
    let tileset: Value = serde_json::from_slice(&files["tileset.json"]).unwrap();
    assert_eq!(tileset["asset"]["version"], "1.1");
    let mut uris = Vec::new();
    content_uris(&tileset["root"], &mut uris);
    // 33×33 takes four levels: 1 + 4 + 16 + 64 tiles.
    assert_eq!(uris.len(), 85, "{uris:?}");
    for uri in &uris {
        let glb = files
            .get(uri)
            .unwrap_or_else(|| panic!("{uri} is in the zip"));
        assert_eq!(&glb[..4], b"glTF", "{uri} starts with the glTF magic");
        let gltf = gltf::Gltf::from_slice(glb).unwrap_or_else(|e| panic!("{uri}: {e}"));
        assert_eq!(gltf.meshes().count(), 1, "{uri} holds one mesh");
    }
    // Nothing else: the tileset and its tiles.
    assert_eq!(files.len(), uris.len() + 1);

    // The same front gives the same bytes as the library's pyramid of it, and the zip is the
    // same however often it is made.
    assert_eq!(
        app.pyramid_zip().unwrap(),
        pyramid_zip(&app.surface().heightfield, &front).unwrap()
    );
}

#[test]
fn a_front_of_one_member_is_refused_with_the_reason() {
    let hf = volcano();
    let mut app = app(hf.clone());
    app.step_once().unwrap();
    let one = vec![app.front().unwrap().solutions()[0].clone()];
    let err = pyramid_zip(&hf, &one).unwrap_err();
    assert!(
        err.contains("1 member") && err.contains("at least two members"),
        "{err}"
    );
    assert!(pyramid_zip(&hf, &[]).unwrap_err().contains("0 member"));
}

#[test]
fn a_tiled_runs_front_is_refused_with_the_reason() {
    let z = (0..70 * 40)
        .map(|i| ((i % 70) as f64 * 0.3).sin() * 4.0 + ((i / 70) as f64 * 0.2).cos() * 3.0)
        .collect();
    let mut app = app(Heightfield::new(70, 40, z).unwrap());
    app.set_pool_setup(PoolSetup {
        workers: 2,
        always: false,
        tile: 36,
    });
    app.run().unwrap();
    assert!(app.tiled_run().is_some(), "a tiled run");
    assert_eq!(app.pyramid_zip().unwrap_err(), TILED_FRONT);
}
