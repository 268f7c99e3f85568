//! Share links: round trips of every surface kind and the refusal of every malformed link.

use crate::app::algorithms::{Algorithm, Params};
use crate::app::camera::OrbitCamera;
use crate::app::loader;
use crate::app::loader::BUILTIN_NAME;
use crate::app::share::{
    EmbeddedGrid, FileFingerprint, GridGeometry, ImportChoice, MAX_LINK_LEN, ShareError, ShareLink,
    SharedSurface, ViewToggles, decode, encode, fnv1a64,
};
use crate::evolution::CrossoverKind;
use crate::export::mesh::WorldMesh;
use crate::heightfield::{Georeference, Heightfield};
use crate::import::ImportOptions;
use crate::measure::ErrorMeasure;
use base64::Engine;
use base64::engine::general_purpose::URL_SAFE_NO_PAD;
use rand::{RngExt, SeedableRng};
use serde_json::{Value, json};

const VOLCANO: &[u8] = include_bytes!("../../../tests/data/volcano_33x33.f32");
const JACKSBORO_65: &[u8] = include_bytes!("../../../tests/data/jacksboro_65x65.f32");

fn grid(name: &str, side: usize, bytes: &[u8]) -> EmbeddedGrid {
    EmbeddedGrid {
        name: name.to_string(),
        width: side,
        height: side,
        z: bytes
            .chunks_exact(4)
            .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect(),
        geometry: GridGeometry::default(),
    }
}

/// A link with every field away from its default, so a dropped field shows.
fn link(surface: SharedSurface, algorithm: Algorithm) -> ShareLink {
    ShareLink {
        surface,
        algorithm,
        params: Params {
            population: 40,
            generations: 30,
            crossover: CrossoverKind::Uniform,
            crossover_probability: 0.7,
            mutation_probability: Some(0.013),
            seed: 987_654_321,
            // Away from sum wherever the method takes another measure.
            error: if algorithm.supports(ErrorMeasure::Max) {
                ErrorMeasure::Max
            } else {
                ErrorMeasure::Sum
            },
        },
        generations_run: 17,
        selected: Some(5),
        camera: OrbitCamera {
            yaw: -2.5,
            pitch: 0.3,
            distance: 2.25,
            target: [0.1, -0.2, 0.05],
        },
        toggles: ViewToggles {
            original: true,
            error: false,
            kept: true,
        },
    }
}

fn builtin_link() -> ShareLink {
    link(
        SharedSurface::Builtin(BUILTIN_NAME.to_string()),
        Algorithm::Nsga2,
    )
}

/// The settings JSON of a valid link, to tamper with.
fn settings_of(link: &ShareLink) -> Value {
    let encoded = encode(link);
    let part = encoded.split('.').nth(1).unwrap();
    serde_json::from_slice(&URL_SAFE_NO_PAD.decode(part).unwrap()).unwrap()
}

fn with_settings(settings: &Value) -> String {
    format!(
        "v1.{}",
        URL_SAFE_NO_PAD.encode(serde_json::to_vec(settings).unwrap())
    )
}

/// Decodes the built-in link after `edit` changed its settings JSON.
fn tampered(edit: impl FnOnce(&mut Value)) -> Result<ShareLink, ShareError> {
    let mut settings = settings_of(&builtin_link());
    edit(&mut settings);
    decode(&with_settings(&settings))
}

/// An embedded-grid link whose settings claim `width`×`height` and whose grid part is
/// `raw` deflated.
fn grid_link(width: usize, height: usize, raw: &[u8]) -> String {
    let mut settings = settings_of(&builtin_link());
    settings["surface"] =
        json!({"kind": "embedded", "name": "g.f32", "width": width, "height": height});
    format!(
        "{}.{}",
        with_settings(&settings),
        URL_SAFE_NO_PAD.encode(miniz_oxide::deflate::compress_to_vec_zlib(raw, 6))
    )
}

#[test]
fn every_algorithm_round_trips_on_the_built_in_surface() {
    for algorithm in Algorithm::ALL {
        let original = link(SharedSurface::Builtin(BUILTIN_NAME.to_string()), algorithm);
        let encoded = encode(&original);
        assert!(encoded.starts_with("v1."), "{encoded}");
        // URL-safe: nothing a hash fragment would need escaped.
        assert!(
            encoded
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || b"-_.".contains(&b))
        );
        assert_eq!(decode(&encoded).unwrap(), original, "{algorithm:?}");
        // The browser's location.hash keeps the '#'.
        assert_eq!(decode(&format!("#{encoded}")).unwrap(), original);
    }
    // No selection and the default mutation rate travel too.
    let mut plain = builtin_link();
    plain.selected = None;
    plain.params.mutation_probability = None;
    assert_eq!(decode(&encode(&plain)).unwrap(), plain);
}

#[test]
fn the_error_measure_travels_and_links_without_it_read_as_sum() {
    for error in ErrorMeasure::ALL {
        let mut original = link(
            SharedSurface::Builtin(BUILTIN_NAME.to_string()),
            Algorithm::Memetic,
        );
        original.params.error = error;
        let settings = settings_of(&original);
        // A sum link is written as links were before the measure existed.
        let written = settings["params"].get("error").cloned();
        let expected = (error != ErrorMeasure::Sum).then(|| json!(error.name()));
        assert_eq!(written, expected);
        assert_eq!(decode(&encode(&original)).unwrap(), original);
    }
    // A link made before the measure existed (the README's first example) reads as sum.
    let old = decode("v1.eyJzdXJmYWNlIjp7ImtpbmQiOiJidWlsdGluIiwibmFtZSI6ImphY2tzYm9yb182NXg2NSJ9LCJhbGdvcml0aG0iOiJuc2dhMiIsInBhcmFtcyI6eyJwb3B1bGF0aW9uIjoxMDAsImdlbmVyYXRpb25zIjo1MCwiY3Jvc3NvdmVyIjoib2F4IiwiY3Jvc3NvdmVyX3Byb2JhYmlsaXR5IjowLjgsIm11dGF0aW9uX3Byb2JhYmlsaXR5IjpudWxsLCJzZWVkIjoxfSwiZ2VuZXJhdGlvbnNfcnVuIjo1MCwic2VsZWN0ZWQiOjcwLCJjYW1lcmEiOnsieWF3IjotMi4yLCJwaXRjaCI6MC43NSwiZGlzdGFuY2UiOjEuOCwidGFyZ2V0IjpbMC4wLDAuMCwwLjBdfSwidG9nZ2xlcyI6eyJvcmlnaW5hbCI6ZmFsc2UsImVycm9yIjp0cnVlLCJrZXB0IjpmYWxzZX19").unwrap();
    assert_eq!(
        (old.algorithm, old.params.error),
        (Algorithm::Nsga2, ErrorMeasure::Sum)
    );
    assert!(tampered(|s| s["params"]["error"] = json!("mean")).is_err());
    assert!(tampered(|s| s["params"]["error"] = json!(2)).is_err());
}

#[test]
fn a_file_fingerprint_round_trips_and_recognises_its_file() {
    let fingerprint = FileFingerprint::of("volcano.f32", VOLCANO);
    let original = link(
        SharedSurface::File(fingerprint.clone()),
        Algorithm::Decimation,
    );
    assert_eq!(decode(&encode(&original)).unwrap(), original);
    assert!(fingerprint.matches(VOLCANO));
    // One flipped byte, or one byte missing, is another file.
    let mut altered = VOLCANO.to_vec();
    altered[100] ^= 1;
    assert!(!fingerprint.matches(&altered));
    assert!(!fingerprint.matches(&VOLCANO[1..]));
    // FNV-1a 64 reference values (empty input is the offset basis; "a" from the spec).
    assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
    assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
}

#[test]
fn a_mesh_files_import_choice_travels_and_is_checked() {
    // A mesh that had to be resampled carries how: projection and the grid size it gave.
    let mut fingerprint = FileFingerprint::of("face.stl", VOLCANO);
    fingerprint.import = Some(ImportChoice {
        projection: "cylindrical".into(),
        width: 48,
        height: 40,
        surface: None,
    });
    let original = link(SharedSurface::File(fingerprint.clone()), Algorithm::Nsga2);
    let encoded = encode(&original);
    assert_eq!(decode(&encoded).unwrap(), original);
    // A grid file's link has no `import` field at all (links written before it existed
    // read the same way).
    let plain = encode(&link(
        SharedSurface::File(FileFingerprint::of("v.f32", VOLCANO)),
        Algorithm::Nsga2,
    ));
    let json = |e: &str| {
        String::from_utf8(
            URL_SAFE_NO_PAD
                .decode(e.split('.').nth(1).unwrap())
                .unwrap(),
        )
        .unwrap()
    };
    assert!(!json(&plain).contains("import"), "{}", json(&plain));
    assert!(json(&encoded).contains("\"import\":{\"projection\":\"cylindrical\""));
    assert!(
        json(&encoded).contains("\"width\":48,\"height\":40}"),
        "a single surface is not written: {}",
        json(&encoded)
    );
    // An outer surface travels too; an unknown one is refused.
    let mut outer = fingerprint.clone();
    outer.import.as_mut().unwrap().surface = Some("outer".into());
    let outer_link = link(SharedSurface::File(outer.clone()), Algorithm::Nsga2);
    assert_eq!(decode(&encode(&outer_link)).unwrap(), outer_link);
    outer.import.as_mut().unwrap().surface = Some("inner".into());
    let e = decode(&encode(&link(SharedSurface::File(outer), Algorithm::Nsga2))).unwrap_err();
    assert!(e.to_string().contains("unknown surface"), "{e}");
    // Bad choices are refused with a message that says what is wrong.
    for (projection, width, height, expect) in [
        ("spherical", 48, 40, "unknown projection"),
        ("planar", 1, 40, "sides must be 2"),
        ("planar", 0, 0, "sides must be 2"),
        ("auto", 16_385, 2, "sides must be 2"),
        ("auto", 16_384, 16_384, "at most"),
    ] {
        fingerprint.import = Some(ImportChoice {
            projection: projection.into(),
            width,
            height,
            surface: None,
        });
        let bad = encode(&link(
            SharedSurface::File(fingerprint.clone()),
            Algorithm::Nsga2,
        ));
        let e = decode(&bad).unwrap_err();
        assert!(matches!(e, ShareError::BadImport(_)), "{e:?}");
        assert!(
            e.to_string().contains(expect),
            "{projection} {width}×{height}: {e}"
        );
    }
}

#[test]
fn an_embedded_grid_round_trips_bit_for_bit() {
    let volcano = grid("volcano_33x33.f32", 33, VOLCANO);
    let original = link(
        SharedSurface::Embedded(Box::new(volcano.clone())),
        Algorithm::Weighted,
    );
    let encoded = encode(&original);
    let decoded = decode(&encoded).unwrap();
    assert_eq!(decoded, original);
    let SharedSurface::Embedded(g) = &decoded.surface else {
        panic!("not embedded");
    };
    let bits = |z: &[f32]| z.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&g.z), bits(&volcano.z));
    let hf = g.to_heightfield().unwrap();
    assert_eq!((hf.width(), hf.height()), (33, 33));
    // The largest embeddable grid, a 65×65 terrain, fits under the link cap.
    let big = link(
        SharedSurface::Embedded(Box::new(grid("j.f32", 65, JACKSBORO_65))),
        Algorithm::Nsga2,
    );
    let encoded = encode(&big);
    assert!(encoded.len() <= MAX_LINK_LEN, "{}", encoded.len());
    assert_eq!(decode(&encoded).unwrap(), big);
}

/// A DEM read as the page reads a dropped file.
fn dem(name: &str, grid_size: Option<(usize, usize)>) -> Heightfield {
    let bytes = std::fs::read(format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap();
    let options = ImportOptions {
        grid_size,
        ..ImportOptions::default()
    };
    loader::parse_file(name, &bytes, None, &options).unwrap()
}

/// The surface a reader of `hf`'s embedded-grid link gets.
fn reopened(hf: &Heightfield) -> Heightfield {
    let (grid, _) = EmbeddedGrid::of("dem.tif", hf).expect("small enough to embed");
    let decoded = decode(&encode(&link(
        SharedSurface::Embedded(Box::new(grid.clone())),
        Algorithm::Nsga2,
    )))
    .unwrap();
    let SharedSurface::Embedded(back) = &decoded.surface else {
        panic!("not embedded");
    };
    assert_eq!(**back, grid);
    back.to_heightfield().unwrap()
}

#[test]
fn a_georeferenced_dem_reopens_where_it_lies_on_the_map() {
    // A DEM with nodata cells, resampled to embeddable size (non-unit spacing), and a
    // PixelIsPoint DEM read as it is.
    let resampled = dem("volcano_87x61_int16_lzw_nodata.tif", Some((44, 31)));
    let point = dem("jacksboro_65x65_float32_tiled_deflate.tif", None);
    assert_eq!(resampled.filled(), 14);
    assert!(point.georeference().unwrap().pixel_is_point);
    for hf in [resampled, point] {
        let page = reopened(&hf);
        assert_eq!((page.width(), page.height()), (hf.width(), hf.height()));
        let as_f32: Vec<f64> = hf.z().iter().map(|&z| f64::from(z as f32)).collect();
        assert_eq!(page.z(), &as_f32[..]);
        assert_eq!(page.origin(), hf.origin());
        assert_eq!(page.spacing(), hf.spacing());
        assert_eq!(page.placement(), hf.placement());
        assert_eq!(page.filled(), hf.filled());
        assert_eq!(page.georeference(), hf.georeference());
        assert_eq!(
            loader::georeference_summary(&page),
            loader::georeference_summary(&hf)
        );
        // Exports of the reopened surface land on the same map coordinates (heights
        // travel as f32).
        let corners = hf.corners();
        let triangles = [[corners[0], corners[1], corners[2]]];
        let vertices = |hf: &Heightfield| {
            let mesh = WorldMesh::new(hf, &corners, &triangles).unwrap();
            let [x, y, z] = mesh.vertices[3];
            [x, y, f64::from(z as f32)]
        };
        assert_eq!(vertices(&page), vertices(&hf));
    }
    // Grid point (0, 0) of the reopened DEM is its south-west sample centre in map units
    // (the tie point's corner plus half a 10 m pixel east and 60.5 pixels south), not (0, 0).
    let page = reopened(&dem("volcano_87x61_int16_lzw_nodata.tif", Some((44, 31))));
    assert_eq!(page.to_world(0, 0.0)[..2], [2_667_405.0, 6_478_105.0]);
}

#[test]
fn a_mesh_grids_placement_travels_and_plain_grids_stay_as_they_were() {
    let resampled_mesh = dem("bunny_33x33.ply", Some((20, 17)));
    assert_ne!(
        resampled_mesh.placement(),
        &crate::heightfield::Placement::Grid
    );
    let page = reopened(&resampled_mesh);
    assert_eq!(page.placement(), resampled_mesh.placement());
    assert_eq!(page.spacing(), resampled_mesh.spacing());
    assert_eq!(page.origin(), resampled_mesh.origin());
    // A plain grid's link carries no geometry, exactly as before it could.
    let plain = link(
        SharedSurface::Embedded(Box::new(grid("v.f32", 33, VOLCANO))),
        Algorithm::Nsga2,
    );
    let settings = settings_of(&plain);
    assert!(settings["surface"].get("geometry").is_none(), "{settings}");
    let hf = decode(&encode(&plain)).map(|l| match l.surface {
        SharedSurface::Embedded(g) => g.to_heightfield().unwrap(),
        _ => panic!("not embedded"),
    });
    let hf = hf.unwrap();
    assert_eq!((hf.origin(), hf.spacing()), ([0.0, 0.0], [1.0, 1.0]));
    assert!(hf.georeference().is_none());
}

/// A 4×3 embedded-grid link as written before grids carried their geometry.
const LINK_WITHOUT_GEOMETRY: &str = "v1.eyJzdXJmYWNlIjp7ImtpbmQiOiJlbWJlZGRlZCIsIm5hbWUiOiJidW1wIiwid2lkdGgiOjQsImhlaWdodCI6M30sImFsZ29yaXRobSI6Im5zZ2EyIiwicGFyYW1zIjp7InBvcHVsYXRpb24iOjQwLCJnZW5lcmF0aW9ucyI6MjAsImNyb3Nzb3ZlciI6Im9heCIsImNyb3Nzb3Zlcl9wcm9iYWJpbGl0eSI6MC44LCJtdXRhdGlvbl9wcm9iYWJpbGl0eSI6bnVsbCwic2VlZCI6N30sImdlbmVyYXRpb25zX3J1biI6MjAsInNlbGVjdGVkIjozLCJjYW1lcmEiOnsieWF3IjotMS45LCJwaXRjaCI6MC45LCJkaXN0YW5jZSI6MS45LCJ0YXJnZXQiOlswLjAsMC4wLDAuMF19LCJ0b2dnbGVzIjp7Im9yaWdpbmFsIjp0cnVlLCJlcnJvciI6ZmFsc2UsImtlcHQiOmZhbHNlfX0.eNpjYFA4wMDgsJ8BDBr2AYkDUNoeSNsxoMkDANhRCTY";

/// A 4×3 embedded-grid link with a GeoTIFF-like geometry, in the current format.
const LINK_WITH_GEOMETRY: &str = "v1.eyJzdXJmYWNlIjp7ImtpbmQiOiJlbWJlZGRlZCIsIm5hbWUiOiJidW1wIiwid2lkdGgiOjQsImhlaWdodCI6MywiZ2VvbWV0cnkiOnsib3JpZ2luIjpbMjY2NzQwNS4wLDY0Nzg2ODUuMF0sInNwYWNpbmciOlsxMC4wLDEyLjVdLCJmaWxsZWQiOjIsImdlb3JlZmVyZW5jZSI6eyJwaXhlbF9zY2FsZSI6WzEwLjAsMTIuNSwwLjBdLCJ0aWVwb2ludCI6WzAuMCwwLjAsMC4wLDI2Njc0MDAuMCw2NDc4NzEwLjAsMC4wXSwibm9kYXRhIjoiLTk5OTkifX19LCJhbGdvcml0aG0iOiJuc2dhMiIsInBhcmFtcyI6eyJwb3B1bGF0aW9uIjo0MCwiZ2VuZXJhdGlvbnMiOjIwLCJjcm9zc292ZXIiOiJvYXgiLCJjcm9zc292ZXJfcHJvYmFiaWxpdHkiOjAuOCwibXV0YXRpb25fcHJvYmFiaWxpdHkiOm51bGwsInNlZWQiOjd9LCJnZW5lcmF0aW9uc19ydW4iOjIwLCJzZWxlY3RlZCI6MywiY2FtZXJhIjp7InlhdyI6LTEuOSwicGl0Y2giOjAuOSwiZGlzdGFuY2UiOjEuOSwidGFyZ2V0IjpbMC4wLDAuMCwwLjBdfSwidG9nZ2xlcyI6eyJvcmlnaW5hbCI6dHJ1ZSwiZXJyb3IiOmZhbHNlLCJrZXB0IjpmYWxzZX19.eNpdibERAEAEwDLKT_KMZjKMxjmVFEkReAkaDOat3Er3c34B2FEJNg";

#[test]
fn links_of_both_formats_decode() {
    let old = decode(LINK_WITHOUT_GEOMETRY).unwrap();
    let SharedSurface::Embedded(g) = &old.surface else {
        panic!("not embedded");
    };
    assert_eq!((g.name.as_str(), g.width, g.height), ("bump", 4, 3));
    assert_eq!(g.geometry, GridGeometry::default());
    let hf = g.to_heightfield().unwrap();
    assert_eq!((hf.origin(), hf.spacing()), ([0.0, 0.0], [1.0, 1.0]));
    assert_eq!((hf.filled(), hf.georeference()), (0, None));
    // Re-encoding it writes the same settings (the deflated grid may differ, as deflaters
    // do): a plain grid's links did not change.
    let settings = |link: &str| link.split('.').nth(1).unwrap().to_string();
    assert_eq!(settings(&encode(&old)), settings(LINK_WITHOUT_GEOMETRY));

    // The same grid with a GeoTIFF-like geometry, as links were written before they carried
    // the EPSG code: frozen, so such links keep decoding to the same surface.
    let mut with_geometry = old;
    if let SharedSurface::Embedded(g) = &mut with_geometry.surface {
        let geometry = geo_geometry();
        g.geometry = GridGeometry {
            georeference: geometry
                .georeference
                .map(|r| Georeference { epsg: None, ..r }),
            ..geometry
        };
    }
    assert_eq!(
        settings(&encode(&with_geometry)),
        settings(LINK_WITH_GEOMETRY)
    );
    let new = decode(LINK_WITH_GEOMETRY).unwrap();
    assert_eq!(new, with_geometry);
    let SharedSurface::Embedded(g) = &new.surface else {
        panic!("not embedded");
    };
    let hf = g.to_heightfield().unwrap();
    assert_eq!(hf.origin(), [2_667_405.0, 6_478_685.0]);
    assert_eq!(hf.spacing(), [10.0, 12.5]);
    assert_eq!(hf.filled(), 2);
    assert_eq!(
        hf.georeference().and_then(|g| g.nodata.as_deref()),
        Some("-9999")
    );
}

#[test]
fn the_share_link_fuzz_seeds_are_valid_links() {
    // The fuzz corpus starts from valid links of every surface kind, geometries included.
    let dir = format!("{}/fuzz/seeds/share_link", env!("CARGO_MANIFEST_DIR"));
    let mut with_geometry = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let text = std::fs::read_to_string(&path).unwrap();
        let link = decode(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        if let SharedSurface::Embedded(g) = &link.surface
            && g.geometry != GridGeometry::default()
        {
            g.to_heightfield().unwrap();
            with_geometry += 1;
        }
    }
    assert!(with_geometry >= 2, "{with_geometry}");
}

/// A GeoTIFF-like geometry: 10 m pixels, a tie point, two nodata cells filled.
fn geo_geometry() -> GridGeometry {
    GridGeometry {
        origin: [2_667_405.0, 6_478_685.0],
        spacing: [10.0, 12.5],
        placement: crate::heightfield::Placement::Grid,
        filled: 2,
        georeference: Some(Georeference {
            pixel_scale: Some([10.0, 12.5, 0.0]),
            tiepoint: Some([0.0, 0.0, 0.0, 2_667_400.0, 6_478_710.0, 0.0]),
            pixel_is_point: false,
            nodata: Some("-9999".into()),
            epsg: Some(2193),
        }),
    }
}

#[test]
fn malformed_geometry_is_refused_with_a_message() {
    let mut with_geometry = decode(LINK_WITHOUT_GEOMETRY).unwrap();
    if let SharedSurface::Embedded(g) = &mut with_geometry.surface {
        g.geometry = geo_geometry();
    }
    let encoded = encode(&with_geometry);
    let parts: Vec<&str> = encoded.split('.').collect();
    let settings: Value =
        serde_json::from_slice(&URL_SAFE_NO_PAD.decode(parts[1]).unwrap()).unwrap();
    let edited = |edit: &dyn Fn(&mut Value)| {
        let mut s = settings.clone();
        edit(&mut s["surface"]["geometry"]);
        decode(&format!("{}.{}", with_settings(&s), parts[2]))
    };
    assert_eq!(edited(&|_| {}).unwrap(), with_geometry);
    type Edit<'a> = &'a dyn Fn(&mut Value);
    let bad_geometry: [(Edit, &str); 8] = [
        (&|g| g["spacing"] = json!([0.0, 1.0]), "spacing"),
        (&|g| g["spacing"] = json!([-10.0, 10.0]), "spacing"),
        (&|g| g["origin"] = json!([1e300, 0.0]), "origin"),
        (&|g| g["filled"] = json!(13), "13 filled points"),
        (
            &|g| g["georeference"]["nodata"] = json!("-99\n99"),
            "nodata",
        ),
        (
            &|g| g["georeference"]["nodata"] = json!("9".repeat(65)),
            "nodata",
        ),
        (
            &|g| g["georeference"]["tiepoint"] = json!([0, 0, 0, 1e17, 0, 0]),
            "georeference",
        ),
        (
            &|g| {
                g["placement"] = json!({"kind": "planar", "origin": [0, 0, 0],
                    "u": [1, 0, 0], "v": [0, 1e20, 0], "n": [0, 0, 1]})
            },
            "placement",
        ),
    ];
    for (edit, expect) in bad_geometry {
        let e = edited(edit).unwrap_err();
        let ShareError::BadGeometry(reason) = &e else {
            panic!("{e:?}");
        };
        assert!(reason.contains(expect), "{reason}");
        let text = e.to_string();
        assert!(
            text.starts_with("This share link cannot be opened: ") && text.len() < 300,
            "{text}"
        );
    }
    let malformed: [Edit; 9] = [
        &|g| g["spacing"] = json!("10"),
        &|g| g["spacing"] = json!([10.0]),
        &|g| g["origin"] = Value::Null,
        &|g| g["filled"] = json!(-1),
        &|g| g["crs"] = json!("EPSG:2193"),
        &|g| g["placement"] = json!({"kind": "spherical"}),
        &|g| g["georeference"]["tiepoint"] = json!([0, 0, 0, 1, 2]),
        &|g| g["georeference"]["pixel_is_point"] = json!("yes"),
        &|g| *g = json!([1, 2]),
    ];
    for edit in malformed {
        let e = edited(edit).unwrap_err();
        assert!(matches!(e, ShareError::Malformed(_)), "{e:?}");
        assert!(e.to_string().len() < 300, "{e}");
    }
    // A geometry on a surface that is not an embedded grid is not a field it has.
    let e = tampered(|s| s["surface"]["geometry"] = settings["surface"]["geometry"].clone())
        .unwrap_err();
    assert!(matches!(e, ShareError::Malformed(_)), "{e:?}");
}

#[test]
fn framing_errors_are_named() {
    let good = encode(&builtin_link());
    assert!(matches!(
        decode(&"A".repeat(MAX_LINK_LEN + 1)),
        Err(ShareError::TooLong { .. })
    ));
    assert!(matches!(decode(""), Err(ShareError::UnsupportedVersion(_))));
    assert!(matches!(
        decode(&good.replacen("v1", "v2", 1)),
        Err(ShareError::UnsupportedVersion(_))
    ));
    assert!(matches!(decode("v1"), Err(ShareError::Malformed(_))));
    assert!(matches!(decode("v1.a.b.c"), Err(ShareError::Malformed(_))));
    // '+' and '=' are standard base64, not URL-safe; '!' is no base64 at all.
    assert!(matches!(
        decode("v1.ab+c"),
        Err(ShareError::BadBase64("settings"))
    ));
    assert!(matches!(
        decode("v1.e30="),
        Err(ShareError::BadBase64("settings"))
    ));
    assert!(matches!(
        decode(&format!("{good}!")),
        Err(ShareError::BadBase64("settings"))
    ));
    // Valid base64 of bytes that are not JSON.
    assert!(matches!(
        decode(&format!(
            "v1.{}",
            URL_SAFE_NO_PAD.encode([0xff, 0x00, 0x7b])
        )),
        Err(ShareError::Malformed(_))
    ));
    // A grid part on a link whose surface is built in.
    assert!(matches!(
        decode(&format!("{good}.AAAA")),
        Err(ShareError::UnexpectedGrid)
    ));
}

#[test]
fn wrong_types_and_unknown_names_are_refused() {
    let err = |edit: fn(&mut Value)| tampered(edit).unwrap_err();
    assert!(matches!(
        err(|s| s["generations_run"] = json!("17")),
        ShareError::Malformed(_)
    ));
    assert!(matches!(
        err(|s| s["params"]["population"] = json!(-3)),
        ShareError::Malformed(_)
    ));
    assert!(matches!(
        err(|s| s["camera"] = json!([1, 2])),
        ShareError::Malformed(_)
    ));
    assert!(matches!(
        err(|s| s["toggles"]["kept"] = json!(1)),
        ShareError::Malformed(_)
    ));
    assert!(matches!(
        err(|s| s["extra"] = json!(1)),
        ShareError::Malformed(_)
    ));
    assert!(matches!(
        err(|s| s
            .as_object_mut()
            .unwrap()
            .remove("camera")
            .map(drop)
            .unwrap()),
        ShareError::Malformed(_)
    ));
    assert!(matches!(
        err(|s| s["params"]["crossover"] = json!("three-point")),
        ShareError::Malformed(_)
    ));
    assert!(matches!(
        err(|s| s["surface"] = json!({"kind": "remote", "name": "x"})),
        ShareError::Malformed(_)
    ));
    // Beyond u64, and a float where an integer belongs.
    assert!(matches!(
        err(|s| s["params"]["seed"] = serde_json::from_str("1e30").unwrap()),
        ShareError::Malformed(_)
    ));
    assert_eq!(
        err(|s| s["algorithm"] = json!("simulated-annealing")),
        ShareError::UnknownAlgorithm("simulated-annealing".into())
    );
    assert_eq!(
        err(|s| s["surface"]["name"] = json!("everest")),
        ShareError::UnknownBuiltin("everest".into())
    );
    let file = |s: &mut Value| {
        s["surface"] =
            json!({"kind": "file", "name": "a.ply", "size": 10, "fnv1a64": "00112233445566ff"})
    };
    assert!(tampered(file).is_ok());
    assert!(matches!(
        err(
            |s| s["surface"] = json!({"kind": "file", "name": "a.ply", "size": 10, "fnv1a64": "0011223344556677ff"})
        ),
        ShareError::BadFingerprint(_)
    ));
    assert!(matches!(
        err(|s| s["surface"] =
            json!({"kind": "file", "name": "a.ply", "size": 10, "fnv1a64": "+011223344556677"})),
        ShareError::BadFingerprint(_)
    ));
    assert!(matches!(
        err(|s| s["surface"] =
            json!({"kind": "file", "name": "a.ply", "size": 0, "fnv1a64": "0011223344556677"})),
        ShareError::BadFingerprint(_)
    ));
    assert_eq!(
        err(|s| s["surface"] =
            json!({"kind": "file", "name": "", "size": 10, "fnv1a64": "0011223344556677"})),
        ShareError::BadName
    );
    assert_eq!(
        err(
            |s| s["surface"] = json!({"kind": "file", "name": "a\u{7}b", "size": 10, "fnv1a64": "0011223344556677"})
        ),
        ShareError::BadName
    );
    assert_eq!(
        err(
            |s| s["surface"] = json!({"kind": "file", "name": "n".repeat(300), "size": 10, "fnv1a64": "0011223344556677"})
        ),
        ShareError::BadName
    );
}

#[test]
fn huge_and_non_finite_numbers_are_refused() {
    let err = |edit: fn(&mut Value)| tampered(edit).unwrap_err();
    let range = |e: ShareError| match e {
        ShareError::OutOfRange { field, .. } => field,
        other => panic!("{other:?}"),
    };
    assert_eq!(
        range(err(|s| s["params"]["seed"] = json!(u64::MAX))),
        "seed"
    );
    assert_eq!(
        range(err(|s| s["generations_run"] = json!(u64::MAX))),
        "generation count"
    );
    assert_eq!(
        range(err(|s| s["selected"] = json!(u64::MAX))),
        "selected solution"
    );
    assert_eq!(
        range(err(|s| s["camera"]["yaw"] = json!(1e30))),
        "camera yaw"
    );
    assert_eq!(
        range(err(|s| s["camera"]["pitch"] = json!(2.0))),
        "camera pitch"
    );
    assert_eq!(
        range(err(|s| s["camera"]["distance"] = json!(0.0))),
        "camera distance"
    );
    assert_eq!(
        range(err(|s| s["camera"]["distance"] = json!(1e6))),
        "camera distance"
    );
    assert_eq!(
        range(err(|s| s["camera"]["target"][1] = json!(-1e9))),
        "camera target"
    );
    assert!(matches!(
        err(|s| s["params"]["population"] = json!(10_000_000)),
        ShareError::InvalidParams(_)
    ));
    assert!(matches!(
        err(|s| s["params"]["generations"] = json!(0)),
        ShareError::InvalidParams(_)
    ));
    assert!(matches!(
        err(|s| s["params"]["crossover_probability"] = json!(3.5)),
        ShareError::InvalidParams(_)
    ));
    // JSON has no NaN or infinity: serde_json writes NaN as null and 1e400 overflows; both
    // fail to parse as a number.
    assert!(matches!(
        err(|s| s["camera"]["yaw"] = Value::Null),
        ShareError::Malformed(_)
    ));
    let json = serde_json::to_string(&settings_of(&builtin_link()))
        .unwrap()
        .replacen("\"pitch\":0.3", "\"pitch\":1e400", 1);
    assert!(json.contains("1e400"));
    assert!(matches!(
        decode(&format!("v1.{}", URL_SAFE_NO_PAD.encode(json))),
        Err(ShareError::Malformed(_))
    ));
    // A NaN built in Rust is written, then refused on reading.
    let mut nan = builtin_link();
    nan.camera.pitch = f32::NAN;
    assert!(decode(&encode(&nan)).is_err());
    // And the same check is reachable without a round trip.
    let mut inf = builtin_link();
    inf.camera.target[0] = f32::INFINITY;
    assert!(matches!(
        inf.validate(),
        Err(ShareError::OutOfRange {
            field: "camera target",
            ..
        })
    ));
}

#[test]
fn hostile_grids_are_refused_before_they_cost_anything() {
    let heights = |n: usize, v: f32| -> Vec<u8> { (0..n).flat_map(|_| v.to_le_bytes()).collect() };
    // Sanity: a well-formed hand-made 3×2 grid is accepted.
    assert!(decode(&grid_link(3, 2, &heights(6, 1.5))).is_ok());
    // Sides outside 2..=65, including absurd ones that would overflow w·h·4.
    assert_eq!(
        decode(&grid_link(66, 2, &[])).unwrap_err(),
        ShareError::BadGridSize {
            width: 66,
            height: 2
        }
    );
    assert!(matches!(
        decode(&grid_link(1, 5, &[])),
        Err(ShareError::BadGridSize { .. })
    ));
    let mut s = settings_of(&builtin_link());
    s["surface"] = json!({"kind": "embedded", "name": "g", "width": u64::MAX, "height": u64::MAX});
    assert!(matches!(
        decode(&with_settings(&s)),
        Err(ShareError::BadGridSize { .. })
    ));
    // Embedded, but no grid part.
    s["surface"] = json!({"kind": "embedded", "name": "g", "width": 3, "height": 3});
    assert_eq!(
        decode(&with_settings(&s)).unwrap_err(),
        ShareError::MissingGrid
    );
    // A deflate bomb: 4 MiB of zeros is a few KiB deflated; inflation stops at 3·3·4 bytes.
    assert_eq!(
        decode(&grid_link(3, 3, &vec![0u8; 4 << 20])).unwrap_err(),
        ShareError::GridTooLarge
    );
    // Too few bytes for the dimensions, and a count that is not whole f32s.
    assert_eq!(
        decode(&grid_link(3, 3, &heights(8, 1.0))).unwrap_err(),
        ShareError::GridLengthMismatch {
            expected: 36,
            found: 32
        }
    );
    assert!(matches!(
        decode(&grid_link(3, 3, &[0u8; 35])),
        Err(ShareError::GridLengthMismatch { .. })
    ));
    // Not deflate data at all, and deflate data cut short.
    let good = grid_link(3, 3, &heights(9, 2.0));
    let (head, _) = good.rsplit_once('.').unwrap();
    assert_eq!(
        decode(&format!(
            "{head}.{}",
            URL_SAFE_NO_PAD.encode(b"not deflate")
        ))
        .unwrap_err(),
        ShareError::CorruptGrid
    );
    let deflated = miniz_oxide::deflate::compress_to_vec_zlib(&heights(9, 2.0), 6);
    assert_eq!(
        decode(&format!(
            "{head}.{}",
            URL_SAFE_NO_PAD.encode(&deflated[..deflated.len() / 2])
        ))
        .unwrap_err(),
        ShareError::CorruptGrid
    );
    assert_eq!(
        decode(&format!("{head}.%%")).unwrap_err(),
        ShareError::BadBase64("grid")
    );
    // NaN and infinity among the heights, at a known index.
    let mut raw = heights(9, 2.0);
    raw[4 * 7..4 * 8].copy_from_slice(&f32::NAN.to_le_bytes());
    assert_eq!(
        decode(&grid_link(3, 3, &raw)).unwrap_err(),
        ShareError::NonFiniteHeight { index: 7 }
    );
    raw[4 * 7..4 * 8].copy_from_slice(&f32::NEG_INFINITY.to_le_bytes());
    assert_eq!(
        decode(&grid_link(3, 3, &raw)).unwrap_err(),
        ShareError::NonFiniteHeight { index: 7 }
    );
}

#[test]
fn every_error_has_a_message_for_people() {
    let errors = [
        decode(&"A".repeat(MAX_LINK_LEN + 1)).unwrap_err(),
        decode("v9.x").unwrap_err(),
        decode("v1.!!").unwrap_err(),
        tampered(|s| s["algorithm"] = json!("x")).unwrap_err(),
        tampered(|s| s["camera"]["pitch"] = json!(9)).unwrap_err(),
    ];
    for e in errors {
        let text = e.to_string();
        assert!(
            text.starts_with("This share link cannot be opened: "),
            "{text}"
        );
        assert!(text.len() < 300, "{text}");
    }
    // Hostile text is echoed clipped, not whole.
    let long = "z".repeat(5000);
    let e = tampered(|s| s["algorithm"] = json!("z".repeat(5000))).unwrap_err();
    assert!(!e.to_string().contains(&long));
}

#[test]
fn random_and_corrupted_links_give_an_error_or_a_valid_link() {
    // Fixed seed: a failure reproduces.
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(6);
    let valid = [
        encode(&builtin_link()),
        encode(&link(
            SharedSurface::File(FileFingerprint::of("v.f32", VOLCANO)),
            Algorithm::Greedy,
        )),
        encode(&link(
            SharedSurface::Embedded(Box::new(grid("v.f32", 33, VOLCANO))),
            Algorithm::Nsga2,
        )),
    ];
    let alphabet = b"v1.-_#ABCxyz0189+/=%{}\":,[] \x00";
    let (mut accepted, mut refused) = (0, 0);
    for i in 0..2_000 {
        let input: Vec<u8> = match i % 4 {
            // Random strings over an alphabet near the link's own.
            0 => {
                let len = rng.random_range(0..200);
                (0..len)
                    .map(|_| alphabet[rng.random_range(0..alphabet.len())])
                    .collect()
            }
            // "v1." and random base64 of random bytes.
            1 => {
                let len = rng.random_range(0..300);
                let bytes: Vec<u8> = (0..len).map(|_| rng.random::<u8>()).collect();
                format!("v1.{}", URL_SAFE_NO_PAD.encode(bytes)).into_bytes()
            }
            // A valid link with 1–4 bytes flipped.
            2 => {
                let mut bytes = valid[rng.random_range(0..valid.len())].clone().into_bytes();
                for _ in 0..rng.random_range(1..5) {
                    let at = rng.random_range(0..bytes.len());
                    bytes[at] ^= 1 << rng.random_range(0..7);
                }
                bytes
            }
            // A valid link truncated.
            _ => {
                let bytes = valid[rng.random_range(0..valid.len())].clone().into_bytes();
                let at = rng.random_range(0..bytes.len());
                bytes[..at].to_vec()
            }
        };
        // Bytes flipped within ASCII stay ASCII, so the input is a string.
        let text = String::from_utf8_lossy(&input);
        match decode(&text) {
            Ok(link) => {
                // Whatever is accepted satisfies every limit and re-encodes to itself.
                link.validate().unwrap();
                assert_eq!(decode(&encode(&link)).unwrap(), link);
                accepted += 1;
            }
            Err(e) => {
                assert!(!e.to_string().is_empty());
                refused += 1;
            }
        }
    }
    assert_eq!(accepted + refused, 2_000);
    // The corruptions mostly break the link; nearly all inputs are refused.
    assert!(refused > 1_500, "{refused}");
}
