//! Printable solids: closed, manifold and outward-facing on real grids and kept sets, in every
//! placement that has a flat side; the 3MF package reads back with an independent reader as the
//! same triangles; bad options are refused.

#![cfg(not(target_arch = "wasm32"))]

use paretomesh::evaluator::Evaluator;
use paretomesh::export::WorldMesh;
use paretomesh::export::{SolidError, SolidOptions, signed_volume, solid};
use paretomesh::export::{to_3mf, to_3mf_deflated};
use paretomesh::heightfield::{Heightfield, Placement};
use paretomesh::import::readers::raw;
use std::collections::HashMap;
use std::io::Cursor;
use std::sync::Arc;

mod common;
use common::cli::paretomesh;

fn grid(name: &str) -> Arc<Heightfield> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/");
    let z = std::fs::read(format!("{dir}{name}.f32")).unwrap();
    let sidecar = std::fs::read(format!("{dir}{name}.json")).unwrap();
    Arc::new(raw::parse(&z, &sidecar, name).unwrap())
}

/// The canonical triangles of `kept` on `hf`.
fn triangles(hf: &Arc<Heightfield>, kept: &[u32]) -> Vec<[u32; 3]> {
    Evaluator::new(hf.clone()).evaluate(kept).unwrap().triangles
}

/// Kept sets from sparse to full: every `step`-th grid point plus a few on the border.
fn kept_sets(hf: &Heightfield) -> Vec<Vec<u32>> {
    let n = hf.len() as u32;
    [97, 13, 5, 1]
        .iter()
        .map(|&step| (0..n).filter(|i| i % step == 0).collect())
        .chain(std::iter::once(vec![1, 2, hf.width() as u32 + 1]))
        .collect()
}

/// Asserts that `mesh` is closed, manifold and consistently oriented: every directed edge is
/// used by exactly one face and its reverse by exactly one other, no face is degenerate, and
/// no two vertices share a position (so a reader that welds by position sees the same mesh).
fn assert_closed_and_oriented(mesh: &WorldMesh, what: &str) {
    let mut directed: HashMap<(u32, u32), usize> = HashMap::new();
    for t in &mesh.triangles {
        assert!(
            t[0] != t[1] && t[1] != t[2] && t[0] != t[2],
            "{what}: face {t:?}"
        );
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &count) in &directed {
        assert_eq!(count, 1, "{what}: edge {a}→{b} used {count} times");
        assert_eq!(
            directed.get(&(b, a)),
            Some(&1),
            "{what}: edge {a}→{b} has no opposite"
        );
    }
    let mut positions: Vec<[u64; 3]> = mesh.vertices.iter().map(|p| p.map(f64::to_bits)).collect();
    positions.sort_unstable();
    positions.dedup();
    assert_eq!(
        positions.len(),
        mesh.vertices.len(),
        "{what}: welded vertices"
    );
    // Euler characteristic of a sphere: V − E + F = 2.
    let (v, e, f) = (
        mesh.vertices.len() as i64,
        directed.len() as i64 / 2,
        mesh.triangles.len() as i64,
    );
    assert_eq!(v - e + f, 2, "{what}: V − E + F");
}

#[test]
fn solids_of_real_grids_are_closed_manifold_and_face_outwards() {
    for name in ["volcano_33x33", "jacksboro_65x65", "bunny_33x33"] {
        let hf = grid(name);
        let (lo, hi) = hf.z_range();
        for kept in kept_sets(&hf) {
            let tris = triangles(&hf, &kept);
            let mesh = solid(&hf, &tris, &SolidOptions::default()).unwrap();
            let what = format!("{name} with {} kept", kept.len());
            assert_closed_and_oriented(&mesh, &what);
            // The surface is kept as it is, on top of the walls and the bottom.
            assert_eq!(&mesh.triangles[..tris.len()].len(), &tris.len());
            let volume = signed_volume(&mesh);
            assert!(volume > 0.0, "{what}: volume {volume}");
            // The bottom lies 5 % of the z range under the lowest point, and the volume is at
            // least the base slab's.
            let bottom = mesh
                .vertices
                .iter()
                .map(|p| p[2])
                .fold(f64::INFINITY, f64::min);
            assert!((bottom - (lo - 0.05 * (hi - lo))).abs() < 1e-9, "{what}");
            let area = ((hf.width() - 1) as f64 * hf.spacing()[0])
                * ((hf.height() - 1) as f64 * hf.spacing()[1]);
            assert!(volume >= 0.05 * (hi - lo) * area * (1.0 - 1e-9), "{what}");
        }
    }
}

#[test]
fn base_height_and_z_scale_move_the_bottom_and_the_top() {
    let hf = grid("volcano_33x33");
    let (lo, hi) = hf.z_range();
    let tris = triangles(&hf, &kept_sets(&hf)[1]);
    let options = SolidOptions {
        base_height: Some(7.0),
        z_scale: 2.0,
    };
    let mesh = solid(&hf, &tris, &options).unwrap();
    let z = |f: fn(f64, f64) -> f64, init| mesh.vertices.iter().map(|p| p[2]).fold(init, f);
    assert_eq!(z(f64::min, f64::INFINITY), 2.0 * lo - 7.0);
    assert!(z(f64::max, f64::NEG_INFINITY) <= 2.0 * hi);
    // The surface's vertices come first, by increasing grid index, at twice their height.
    let mut corners: Vec<u32> = tris.iter().flatten().copied().collect();
    corners.sort_unstable();
    corners.dedup();
    for (k, &g) in corners.iter().enumerate() {
        assert_eq!(mesh.vertices[k][2], 2.0 * hf.z()[g as usize]);
    }
    assert_closed_and_oriented(&mesh, "scaled");
}

#[test]
fn a_mirrored_planar_placement_still_faces_outwards() {
    // A plane whose axes u, v, n form a left-handed frame turns the surface's triangles
    // clockwise in the world; the solid must turn them back.
    let base = grid("camera_33x33");
    let (w, h) = (base.width(), base.height());
    for n in [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]] {
        let hf = Arc::new(
            Heightfield::new(w, h, base.z().to_vec())
                .unwrap()
                .with_placement(Placement::Planar {
                    origin: [10.0, -3.0, 2.0],
                    u: [1.0, 0.0, 0.0],
                    v: [0.0, 1.0, 0.0],
                    n,
                }),
        );
        let tris = triangles(&hf, &kept_sets(&hf)[2]);
        let mesh = solid(&hf, &tris, &SolidOptions::default()).unwrap();
        assert_closed_and_oriented(&mesh, "planar");
        assert!(signed_volume(&mesh) > 0.0, "normal {n:?}");
    }
}

/// A real grid as a cylindrical unwrap (radius = its heights) over nearly one turn, as an
/// import of a closed mesh gives it, with its axis along `axis`.
fn as_cylinder(hf: &Heightfield, axis: [f64; 3], reference: [f64; 3]) -> Arc<Heightfield> {
    let turn = std::f64::consts::TAU;
    Arc::new(
        Heightfield::new(hf.width(), hf.height(), hf.z().to_vec())
            .unwrap()
            .with_geometry([0.3, -4.0], [turn / hf.width() as f64, 0.5])
            .unwrap()
            .with_placement(Placement::Cylindrical {
                origin: [10.0, -3.0, 2.0],
                axis,
                reference,
            }),
    )
}

#[test]
fn solids_of_cylindrical_unwraps_are_closed_by_seam_and_caps() {
    for name in ["volcano_33x33", "bunny_33x33"] {
        let flat = grid(name);
        // Both handednesses of the unwrap's frame.
        for reference in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            let hf = as_cylinder(&flat, [0.0, 0.0, 1.0], reference);
            let hf = if flat.z_range().0 > 0.0 {
                hf
            } else {
                // Radii must be positive: lift the bunny's heights off the axis.
                let (lo, hi) = flat.z_range();
                let z = flat.z().iter().map(|z| z - lo + (hi - lo)).collect();
                let lifted = Heightfield::new(flat.width(), flat.height(), z).unwrap();
                as_cylinder(&lifted, [0.0, 0.0, 1.0], reference)
            };
            for (k, kept) in kept_sets(&hf).iter().enumerate() {
                let tris = triangles(&hf, kept);
                let what = format!("{name} cylinder {reference:?} kept set {k}");
                let w = hf.width() as u32;
                let last_row = (hf.height() - 1) as u32 * w;
                let on_row = |row: u32| {
                    let mut on: Vec<u32> = tris
                        .iter()
                        .flatten()
                        .copied()
                        .filter(|&g| g / w == row / w)
                        .collect();
                    on.sort_unstable();
                    on.dedup();
                    on.len()
                };
                let ring = on_row(0).min(on_row(last_row));
                let result = solid(&hf, &tris, &SolidOptions::default());
                if ring < 3 {
                    assert_eq!(result, Err(SolidError::ThinRing(ring)), "{what}");
                    continue;
                }
                let mesh = result.unwrap();
                assert_closed_and_oriented(&mesh, &what);
                let v = signed_volume(&mesh);
                assert!(v > 0.0, "{what}: volume {v}");
                // The surface, a seam strip and two caps: one face more per kept point on
                // the seam columns and the end rings (minus the shared corners).
                assert!(mesh.triangles.len() > tris.len() + 2 * ring, "{what}");
                // Inside the cylinder of the largest radius.
                let (_, hi) = hf.z_range();
                let length = (hf.height() - 1) as f64 * 0.5;
                assert!(
                    v < std::f64::consts::PI * hi * hi * length,
                    "{what}: volume {v} for radii up to {hi}"
                );
            }
        }
    }
}

#[test]
fn bad_options_and_cylinders_are_refused_with_their_reason() {
    let hf = grid("volcano_33x33");
    let tris = triangles(&hf, &[]);
    for (options, expected) in [
        (
            SolidOptions {
                base_height: Some(-1.0),
                z_scale: 1.0,
            },
            SolidError::BadBaseHeight(-1.0),
        ),
        (
            SolidOptions {
                base_height: None,
                z_scale: 0.0,
            },
            SolidError::BadZScale(0.0),
        ),
    ] {
        assert_eq!(solid(&hf, &tris, &options), Err(expected.clone()));
        assert!(expected.to_string().contains("greater than 0"));
    }
    let cylinder = Arc::new(
        Heightfield::new(hf.width(), hf.height(), hf.z().to_vec())
            .unwrap()
            .with_placement(Placement::Cylindrical {
                origin: [0.0; 3],
                axis: [0.0, 0.0, 1.0],
                reference: [1.0, 0.0, 0.0],
            }),
    );
    let with_base = SolidOptions {
        base_height: Some(2.0),
        z_scale: 1.0,
    };
    let out = solid(&cylinder, &tris, &with_base).unwrap_err();
    assert_eq!(out, SolidError::BaseOnCylinder(2.0));
    assert!(out.to_string().contains("cylindrical unwrap"), "{out}");
    // Two separate triangles have two borders, not one.
    let out = solid(
        &hf,
        &[[0, 1, 33], [500, 501, 534]],
        &SolidOptions::default(),
    )
    .unwrap_err();
    assert!(out.to_string().contains("more than one piece"), "{out}");
}

#[test]
fn a_3mf_package_reads_back_as_the_same_triangles() {
    let hf = grid("jacksboro_65x65");
    let tris = triangles(&hf, &kept_sets(&hf)[1]);
    let mesh = solid(&hf, &tris, &SolidOptions::default()).unwrap();
    // The zip crate's package natively, the browser's own writer's, the same model in both.
    for write in [to_3mf, to_3mf_deflated] {
        reads_back(
            &mesh,
            &write(&mesh, "jacksboro <solid> & \"base\"").unwrap(),
        );
    }
    // The browser's package is deflated, not stored.
    let own = to_3mf_deflated(&mesh, "jacksboro").unwrap();
    assert!(
        own.len() * 3 < 64 * mesh.triangles.len(),
        "{} bytes",
        own.len()
    );
}

fn reads_back(mesh: &WorldMesh, bytes: &[u8]) {
    let models = threemf::read(Cursor::new(bytes)).unwrap();
    assert_eq!(models.len(), 1);
    let object = &models[0].resources.object[0];
    assert_eq!(object.name.as_deref(), Some("jacksboro <solid> & \"base\""));
    let read = object.mesh.as_ref().unwrap();
    let vertices: Vec<[f64; 3]> = read
        .vertices
        .vertex
        .iter()
        .map(|v| [v.x, v.y, v.z])
        .collect();
    let triangles: Vec<[u32; 3]> = read
        .triangles
        .triangle
        .iter()
        .map(|t| [t.v1, t.v2, t.v3].map(|i| i as u32))
        .collect();
    assert_eq!(vertices, mesh.vertices);
    assert_eq!(triangles, mesh.triangles);
    // The model part has the name slicers look for.
    let text = String::from_utf8_lossy(bytes);
    assert!(text.contains("3D/3dmodel.model"));
}

/// An ASCII STL of a closed bumpy tube around the z axis: radius 1 + 0.15·sin 5θ·cos ζ on
/// ζ ∈ [−2, 2], closed by flat discs; longer than wide, so its principal axis is z.
fn bumpy_tube_stl() -> String {
    let (turns, rings) = (48, 21);
    let at = |i: usize, j: usize| {
        let theta = std::f64::consts::TAU * (i % turns) as f64 / turns as f64;
        let zeta = -2.0 + 4.0 * j as f64 / (rings - 1) as f64;
        let r = 1.0 + 0.15 * (5.0 * theta).sin() * zeta.cos();
        [r * theta.cos(), r * theta.sin(), zeta]
    };
    let mut faces: Vec<[[f64; 3]; 3]> = Vec::new();
    for j in 0..rings - 1 {
        for i in 0..turns {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    for i in 0..turns {
        faces.push([[0.0, 0.0, -2.0], at(i + 1, 0), at(i, 0)]);
        faces.push([[0.0, 0.0, 2.0], at(i, rings - 1), at(i + 1, rings - 1)]);
    }
    let mut stl = String::from("solid tube\n");
    for f in faces {
        stl.push_str("facet normal 0 0 0\n outer loop\n");
        for p in f {
            stl.push_str(&format!("  vertex {} {} {}\n", p[0], p[1], p[2]));
        }
        stl.push_str(" endloop\nendfacet\n");
    }
    stl.push_str("endsolid tube\n");
    stl
}

/// A binary STL's triangles, with corners welded by their exact position.
fn read_binary_stl(bytes: &[u8]) -> WorldMesh {
    let count = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    assert_eq!(bytes.len(), 84 + 50 * count);
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    let mut mesh = WorldMesh {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    for t in 0..count {
        let record = &bytes[84 + 50 * t..84 + 50 * (t + 1)];
        let corner = |k: usize| -> [u32; 3] {
            std::array::from_fn(|c| {
                let at = 12 + 12 * k + 4 * c;
                u32::from_le_bytes(record[at..at + 4].try_into().unwrap())
            })
        };
        let face = [0, 1, 2].map(|k| {
            let bits = corner(k);
            let next = index.len() as u32;
            *index.entry(bits).or_insert_with(|| {
                mesh.vertices.push(bits.map(|b| f32::from_bits(b) as f64));
                next
            })
        });
        mesh.triangles.push(face);
    }
    mesh
}

#[test]
fn a_closed_scan_goes_from_file_to_a_printable_3mf_and_stl() {
    let dir = std::env::temp_dir().join(format!("paretomesh-solid-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let input = dir.join("tube.stl");
    std::fs::write(&input, bumpy_tube_stl()).unwrap();
    let front = dir.join("front.json");
    let s = |p: &std::path::Path| p.to_str().unwrap().to_owned();
    let run = paretomesh(&[
        "run",
        &s(&input),
        "--surface",
        "outer",
        "--grid-size",
        "48x24",
        "--algo",
        "greedy",
        "--out",
        &s(&front),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );

    let three = dir.join("tube.3mf");
    let out = paretomesh(&[
        "export",
        &s(&front),
        "--tradeoff",
        "--solid",
        "--format",
        "3mf",
        "--out",
        &s(&three),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let models = threemf::read(std::fs::File::open(&three).unwrap()).unwrap();
    let read = models[0].resources.object[0].mesh.as_ref().unwrap();
    let from_3mf = WorldMesh {
        vertices: read
            .vertices
            .vertex
            .iter()
            .map(|v| [v.x, v.y, v.z])
            .collect(),
        triangles: read
            .triangles
            .triangle
            .iter()
            .map(|t| [t.v1, t.v2, t.v3].map(|i| i as u32))
            .collect(),
    };
    assert_closed_and_oriented(&from_3mf, "3MF");
    let v = signed_volume(&from_3mf);
    // The tube's volume is 4π (its bumps cancel to first order); a simplified member inscribes
    // its surface, so somewhat less.
    let tube = 4.0 * std::f64::consts::PI;
    assert!(v > 0.6 * tube && v < 1.05 * tube, "volume {v}");

    let stl = dir.join("tube.stl.out");
    let out = paretomesh(&[
        "export",
        &s(&front),
        "--tradeoff",
        "--solid",
        "--format",
        "stl",
        "--out",
        &s(&stl),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let from_stl = read_binary_stl(&std::fs::read(&stl).unwrap());
    assert_closed_and_oriented(&from_stl, "STL");
    assert_eq!(from_stl.triangles.len(), from_3mf.triangles.len());
    let w = signed_volume(&from_stl);
    assert!((w - v).abs() < 1e-4 * v, "STL volume {w}, 3MF volume {v}");

    // A base height has no meaning for it, and says so before writing anything.
    let refused = dir.join("refused.3mf");
    let out = paretomesh(&[
        "export",
        &s(&front),
        "--tradeoff",
        "--solid",
        "--base-height",
        "1",
        "--out",
        &s(&refused),
    ]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("cylindrical unwrap"), "{stderr}");
    assert!(!refused.exists());
    std::fs::remove_dir_all(dir).ok();
}
