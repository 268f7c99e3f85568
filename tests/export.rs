//! The mesh writers and the front's CSV: world coordinates, formats the project's own
//! importers read back, and one CSV row per front member.

use paretomesh::evaluator::Evaluator;
use paretomesh::export::WorldMesh;
use paretomesh::export::front_csv;
use paretomesh::export::to_obj;
use paretomesh::export::to_ply;
use paretomesh::export::to_stl;
use paretomesh::heightfield::{Heightfield, Placement};
use paretomesh::import::readers::raw;
use std::sync::Arc;

const GRID: &[u8] = include_bytes!("data/volcano_33x33.f32");
const SIDECAR: &[u8] = include_bytes!("data/volcano_33x33.json");

fn volcano() -> Arc<Heightfield> {
    Arc::new(raw::parse(GRID, SIDECAR, "volcano_33x33").unwrap())
}

/// The mesh the evaluator makes of `kept` (corners added), as the exports receive it.
struct Mesh {
    kept: Vec<u32>,
    triangles: Vec<[u32; 3]>,
    e_sum: f64,
}

fn mesh_of(hf: &Arc<Heightfield>, kept: &[u32]) -> Mesh {
    let mut evaluator = Evaluator::new(hf.clone());
    let evaluation = evaluator.evaluate(kept).unwrap();
    Mesh {
        kept: evaluator.kept().to_vec(),
        triangles: evaluation.triangles,
        e_sum: evaluation.score.e_sum,
    }
}

// Kept points spread over the 33×33 grid (interior points of a few rows and columns).
const KEPT: [u32; 6] = [34, 200, 530, 545, 800, 1000];

#[test]
fn exports_use_the_inputs_own_coordinates() {
    // A 3×2 grid with spacing (2, 5) and origin (10, 20): point 5 is (x=2, y=1).
    let hf = Heightfield::new(3, 2, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0])
        .unwrap()
        .with_geometry([10.0, 20.0], [2.0, 5.0])
        .unwrap();
    // Kept: point 1 and the four corners (0, 2, 3, 5) = 5 vertices.
    let mesh = mesh_of(&Arc::new(hf.clone()), &[1]);
    let world = WorldMesh::new(&hf, &mesh.kept, &mesh.triangles).unwrap();
    assert_eq!(world.vertices.last(), Some(&[14.0, 25.0, 5.0]));
    let ply = to_ply(&world, "test");
    assert!(ply.contains("element vertex 5\n"));
    assert!(ply.contains(&format!("element face {}\n", mesh.triangles.len())));
    assert!(ply.contains("\n14 25 5\n"));
    let obj = to_obj(&world, "test");
    assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), 5);
    assert!(
        obj.lines()
            .filter(|l| l.starts_with("f "))
            .all(|l| !l.contains(" 0"))
    );
    let stl = to_stl(&world, "solid-looking header");
    assert_eq!(stl.len(), 84 + 50 * mesh.triangles.len());
    assert_ne!(&stl[..5], b"solid");
}

#[test]
fn a_cylindrical_unwrap_exports_back_onto_the_cylinder() {
    // θ along x, ζ along y, ρ = z = 2 everywhere: every exported vertex is 2 from the axis.
    let hf = Heightfield::new(4, 3, vec![2.0; 12])
        .unwrap()
        .with_geometry([0.0, 0.0], [1.0, 1.0])
        .unwrap()
        .with_placement(Placement::Cylindrical {
            origin: [0.0; 3],
            axis: [0.0, 0.0, 1.0],
            reference: [1.0, 0.0, 0.0],
        });
    let mesh = mesh_of(&Arc::new(hf.clone()), &[5, 6]);
    let world = WorldMesh::new(&hf, &mesh.kept, &mesh.triangles).unwrap();
    for v in &world.vertices {
        assert!(
            ((v[0] * v[0] + v[1] * v[1]).sqrt() - 2.0).abs() < 1e-12,
            "{v:?}"
        );
    }
}

#[test]
fn exported_meshes_parse_back_with_the_projects_importers() {
    use paretomesh::import::readers::{obj, ply, stl};
    // volcano_33x33 has spacing 1 and origin 0, so grid and world coordinates agree.
    let hf = volcano();
    let mesh = mesh_of(&hf, &KEPT);
    let world = WorldMesh::new(&hf, &mesh.kept, &mesh.triangles).unwrap();
    // The importers may renumber vertices (e.g. in order of first use), so compare positions:
    // the vertex sets, and each triangle as its corner positions in order (rotation-normalised,
    // so the orientation must survive).
    let sorted = |mut v: Vec<[f64; 3]>| {
        v.sort_by(|a, b| a.partial_cmp(b).unwrap());
        v
    };
    let shapes = |vs: &[[f64; 3]], ts: &[[u32; 3]]| {
        let mut out: Vec<[[f64; 3]; 3]> = ts
            .iter()
            .map(|t| {
                let p = t.map(|i| vs[i as usize]);
                let k = (0..3)
                    .min_by(|&a, &b| p[a].partial_cmp(&p[b]).unwrap())
                    .unwrap();
                [p[k], p[(k + 1) % 3], p[(k + 2) % 3]]
            })
            .collect();
        out.sort_by(|a, b| a.partial_cmp(b).unwrap());
        out
    };
    let expected = shapes(&world.vertices, &world.triangles);
    let from_ply = ply::parse(to_ply(&world, "round trip").as_bytes()).unwrap();
    assert_eq!(
        sorted(from_ply.vertices.clone()),
        sorted(world.vertices.clone())
    );
    assert_eq!(shapes(&from_ply.vertices, &from_ply.triangles), expected);
    let from_obj = obj::parse(to_obj(&world, "round trip").as_bytes()).unwrap();
    assert_eq!(
        sorted(from_obj.vertices.clone()),
        sorted(world.vertices.clone())
    );
    assert_eq!(shapes(&from_obj.vertices, &from_obj.triangles), expected);
    // STL stores f32 corners: the same triangles up to f32 rounding (heights here are f32s
    // already and x, y small integers, so the rounding is exact).
    let from_stl = stl::parse(&to_stl(&world, "round trip")).unwrap();
    assert_eq!(shapes(&from_stl.vertices, &from_stl.triangles), expected);
    // The exported PLY scores like the selection on the original grid.
    let index_of = |p: [f64; 3]| hf.index(p[0] as usize, p[1] as usize);
    let grid_tris: Vec<[u32; 3]> = from_ply
        .triangles
        .iter()
        .map(|t| t.map(|i| index_of(from_ply.vertices[i as usize])))
        .collect();
    let e = Evaluator::new(hf.clone())
        .score_triangulation(&grid_tris)
        .unwrap()
        .e_sum;
    assert_eq!(e, mesh.e_sum);
}
#[test]
fn a_triangle_on_a_point_that_is_not_kept_is_an_error() {
    let hf = Heightfield::new(2, 2, vec![0.0; 4]).unwrap();
    let err = WorldMesh::new(&hf, &[0, 1, 3], &[[0, 1, 2]]).err();
    assert_eq!(
        err.as_deref(),
        Some("triangle vertex 2 is not a kept point")
    );
}

#[test]
fn the_front_csv_has_one_row_per_member() {
    use paretomesh::front::{Front, Solution};
    let mut f = Front::default();
    f.offer(Solution::recorded(9.0, 3.0, 2, vec![0, 1, 2, 3]));
    f.offer(Solution::recorded(1.5, 1.0, 4, vec![0, 1, 2, 3, 4]));
    assert_eq!(
        front_csv(f.solutions()),
        "T,E_sum,E_max,kept\n2,9,3,4\n4,1.5,1,5\n"
    );
}
