//! `paretomesh export` on fronts written by a real `paretomesh run`: each selector picks the
//! right member, every format reads back as that member's mesh (whose kept set `eval` scores as
//! the front recorded), and bad requests get a message, not a panic.

use paretomesh::evaluator::Score;
use paretomesh::evaluator::canonical_set;
use paretomesh::front_file::FrontFile;
use paretomesh::heightfield::Heightfield;
use paretomesh::import;
use paretomesh::metrics::trade_off_pick;
use paretomesh::pick::knee;
use serde_json::Value;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

mod common;
use common::cli::{data, paretomesh, paretomesh_in, scratch, text};

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// The grid every round trip uses, named relative to the crate as `run` records it.
const GRID: &str = "tests/data/volcano_33x33.f32";

/// A front.json of greedy insertion on [`GRID`], with triangles (one run for the whole test
/// binary): run from the crate's folder, so front.json names the grid by its relative path.
fn front() -> &'static Path {
    static FRONT: OnceLock<PathBuf> = OnceLock::new();
    FRONT.get_or_init(|| {
        let out = scratch("front").join("front.json");
        let run = paretomesh(&[
            "run",
            GRID,
            "--algo",
            "greedy",
            "--seed",
            "7",
            "--triangles",
            "--out",
            s(&out),
        ]);
        assert!(run.status.success(), "{}", text(&run.stderr));
        out
    })
}

fn read_json(path: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

/// (E_sum, T, kept) of every member of a front.json, in the file's order.
fn members(front: &Path) -> Vec<(f64, usize, Vec<u32>)> {
    let file: FrontFile = serde_json::from_value(read_json(front)).unwrap();
    file.front
        .into_iter()
        .map(|m| (m.solution.e_sum, m.solution.t, m.solution.kept))
        .collect()
}

/// Runs `export` and returns the member index its stderr line names.
fn export(front: &Path, choice: &[&str], out: &Path, more: &[&str]) -> usize {
    let mut args = vec!["export", s(front)];
    args.extend_from_slice(choice);
    args.extend_from_slice(&["--out", s(out)]);
    args.extend_from_slice(more);
    let result = paretomesh(&args);
    let stderr = text(&result.stderr);
    assert!(result.status.success(), "{args:?}: {stderr}");
    assert!(
        stderr.contains(&format!("to {}", out.display())),
        "{stderr}"
    );
    let line = stderr.trim();
    assert_eq!(line.lines().count(), 1, "{stderr}");
    line.strip_prefix("wrote member ")
        .and_then(|rest| rest.split(' ').next())
        .and_then(|k| k.parse().ok())
        .unwrap_or_else(|| panic!("no member index in {stderr:?}"))
}

/// Grid index of every grid point's world position, by exact bits: PLY and OBJ print f64 in
/// Rust's shortest round-tripping form.
fn world_index(hf: &Heightfield) -> HashMap<[u64; 3], u32> {
    (0..hf.len() as u32)
        .map(|i| (hf.to_world(i, hf.z()[i as usize]).map(f64::to_bits), i))
        .collect()
}

/// Vertices and triangles of an ASCII PLY as `paretomesh`'s writer lays it out.
fn read_ply(text: &str) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut lines = text.lines();
    let (mut vertices, mut faces) = (0, 0);
    for line in lines.by_ref() {
        if let Some(n) = line.strip_prefix("element vertex ") {
            vertices = n.parse().unwrap();
        } else if let Some(n) = line.strip_prefix("element face ") {
            faces = n.parse().unwrap();
        } else if line == "end_header" {
            break;
        }
    }
    let numbers = |line: &str| -> Vec<f64> {
        line.split_whitespace()
            .map(|w| w.parse().unwrap())
            .collect()
    };
    let v = (&mut lines)
        .take(vertices)
        .map(|l| numbers(l).try_into().unwrap())
        .collect();
    let f = (&mut lines)
        .take(faces)
        .map(|l| {
            let n = numbers(l);
            assert_eq!(n[0], 3.0);
            [n[1] as u32, n[2] as u32, n[3] as u32]
        })
        .collect();
    assert!(lines.next().is_none(), "nothing after the faces");
    (v, f)
}

fn read_obj(text: &str) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let (mut v, mut f) = (Vec::new(), Vec::new());
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => v.push(std::array::from_fn(|_| {
                words.next().unwrap().parse::<f64>().unwrap()
            })),
            Some("f") => f.push(std::array::from_fn(|_| {
                words.next().unwrap().parse::<u32>().unwrap() - 1
            })),
            _ => {}
        }
    }
    (v, f)
}

/// The grid indices of a mesh read back, and its triangles in grid indices.
fn to_grid(
    hf: &Heightfield,
    (vertices, faces): (Vec<[f64; 3]>, Vec<[u32; 3]>),
) -> (Vec<u32>, Vec<[u32; 3]>) {
    let index = world_index(hf);
    let grid: Vec<u32> = vertices
        .iter()
        .map(|v| index[&v.map(f64::to_bits)])
        .collect();
    let triangles = faces.iter().map(|t| t.map(|k| grid[k as usize])).collect();
    (grid, triangles)
}

/// `paretomesh eval` of `kept` on [`GRID`]: (E_sum, T, canonical triangles).
fn eval(kept: &[u32]) -> (f64, usize, Vec<[u32; 3]>) {
    let keep = scratch("eval").join(format!("keep-{}.json", kept.len()));
    std::fs::write(&keep, serde_json::to_string(kept).unwrap()).unwrap();
    let out = paretomesh(&["eval", GRID, "--keep", s(&keep)]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let json: Value = serde_json::from_slice(&out.stdout).unwrap();
    let triangles: Vec<[u32; 3]> = serde_json::from_value(json["triangles"].clone()).unwrap();
    (
        json["E_sum"].as_f64().unwrap(),
        json["T"].as_u64().unwrap() as usize,
        canonical_set(&triangles),
    )
}

#[test]
fn ply_and_obj_round_trip_to_the_members_score_through_eval() {
    let front = front();
    let all = members(front);
    let hf = import::load(&data("volcano_33x33.f32")).unwrap();
    let dir = scratch("round-trip");
    for k in [0, all.len() / 3, all.len() - 1] {
        let (e_sum, t, ref kept) = all[k];
        for format in ["ply", "obj"] {
            let out = dir.join(format!("m{k}.{format}"));
            let k_str = k.to_string();
            assert_eq!(export(front, &["--member", &k_str], &out, &[]), k);
            let written = std::fs::read_to_string(&out).unwrap();
            let mesh = if format == "ply" {
                read_ply(&written)
            } else {
                read_obj(&written)
            };
            let (vertices, triangles) = to_grid(&hf, mesh);
            assert_eq!(triangles.len(), t, "member {k} {format}");
            let mut sorted = vertices.clone();
            sorted.sort_unstable();
            sorted.dedup();
            assert_eq!(sorted.len(), vertices.len(), "each vertex once");
            // The file's kept set scores as the front recorded, and its triangles are the
            // evaluator's.
            let (e, t_eval, fresh) = eval(&sorted);
            assert_eq!(t_eval, t, "member {k} {format}");
            assert!(
                (e - e_sum).abs() <= 1e-9 * e_sum.max(1.0),
                "member {k} {format}: {e} vs {e_sum}"
            );
            assert_eq!(canonical_set(&triangles), fresh, "member {k} {format}");
            // Greedy members keep the corners, so the mesh's points are the kept list.
            assert_eq!(&sorted, kept, "member {k} {format}");
        }
    }
}

#[test]
fn stl_corners_are_the_members_points_in_single_precision() {
    let front = front();
    let all = members(front);
    let k = all.len() / 2;
    let (_, t, ref kept) = all[k];
    let out = scratch("stl").join("m.stl");
    export(front, &["--member", &k.to_string()], &out, &[]);
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(bytes.len(), 84 + 50 * t);
    assert_eq!(
        u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize,
        t
    );
    let hf = import::load(&data("volcano_33x33.f32")).unwrap();
    let world: HashMap<[u32; 3], u32> = kept
        .iter()
        .map(|&i| {
            let p = hf.to_world(i, hf.z()[i as usize]);
            (p.map(|c| (c as f32).to_bits()), i)
        })
        .collect();
    let mut triangles = Vec::new();
    for record in bytes[84..].chunks_exact(50) {
        let f = |k: usize| f32::from_le_bytes(record[4 * k..4 * k + 4].try_into().unwrap());
        let corner =
            |c: usize| world[&[f(3 + 3 * c), f(4 + 3 * c), f(5 + 3 * c)].map(f32::to_bits)];
        triangles.push([corner(0), corner(1), corner(2)]);
    }
    assert_eq!(canonical_set(&triangles), eval(kept).2);
}

#[test]
fn glb_reads_back_with_the_gltf_crate_as_the_members_mesh() {
    let front = front();
    let all = members(front);
    let k = all.len() / 4;
    let (_, t, ref kept) = all[k];
    let out = scratch("glb").join("m.glb");
    // The format comes from --format even when the name says otherwise.
    let named_bin = out.with_extension("bin");
    export(front, &["--member", &k.to_string()], &out, &[]);
    export(
        front,
        &["--member", &k.to_string()],
        &named_bin,
        &["--format", "glb"],
    );
    let bytes = std::fs::read(&out).unwrap();
    assert_eq!(bytes, std::fs::read(&named_bin).unwrap());
    let file = gltf::Gltf::from_slice(&bytes).expect("a valid .glb");
    let mesh = file.meshes().next().unwrap();
    let primitive = mesh.primitives().next().unwrap();
    let blob = file.blob.as_deref();
    let reader = primitive.reader(|buffer| match buffer.source() {
        gltf::buffer::Source::Bin => blob,
        _ => None,
    });
    let positions: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
    let normals: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
    let indices: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
    let translation = file.nodes().next().unwrap().transform().decomposed().0;
    assert_eq!(positions.len(), kept.len());
    assert_eq!(normals.len(), kept.len());
    assert_eq!(indices.len(), 3 * t);
    // Vertices are in increasing grid order: each lands on its grid point's world position.
    let hf = import::load(&data("volcano_33x33.f32")).unwrap();
    for (p, &i) in positions.iter().zip(kept) {
        let w = hf.to_world(i, hf.z()[i as usize]);
        for c in 0..3 {
            let got = p[c] as f64 + translation[c] as f64;
            assert!(
                (got - w[c]).abs() < 1e-3,
                "grid point {i}: {got} vs {}",
                w[c]
            );
        }
    }
    let triangles: Vec<[u32; 3]> = indices
        .chunks_exact(3)
        .map(|t| {
            [
                kept[t[0] as usize],
                kept[t[1] as usize],
                kept[t[2] as usize],
            ]
        })
        .collect();
    assert_eq!(canonical_set(&triangles), eval(kept).2);
    // A height field seen from above: every normal points up.
    assert!(normals.iter().all(|n| n[2] > 0.0));
}

#[test]
fn each_selector_picks_the_member_its_rule_names() {
    let front = front();
    let all = members(front);
    let seed = read_json(front)["seed"].as_u64().unwrap();
    let dir = scratch("selectors");
    let out = dir.join("m.ply");
    let points: Vec<[f64; 2]> = all.iter().map(|m| [m.0, m.1 as f64]).collect();
    let trade_off = trade_off_pick(&points, seed).unwrap().index;
    assert_eq!(export(front, &["--tradeoff"], &out, &[]), trade_off);
    let faces = |path: &Path| read_ply(&std::fs::read_to_string(path).unwrap()).1.len();
    assert_eq!(faces(&out), all[trade_off].1);

    // Budgets at a member's own T or E, just under it, and between members.
    let lowest_e_within = |n: usize| {
        (0..all.len())
            .filter(|&i| all[i].1 <= n)
            .min_by(|&i, &j| all[i].0.total_cmp(&all[j].0))
            .unwrap()
    };
    let fewest_t_within = |e: f64| {
        (0..all.len())
            .filter(|&i| all[i].0 <= e)
            .min_by_key(|&i| all[i].1)
    };
    for k in [1, all.len() / 2, all.len() - 1] {
        let (e, t, _) = all[k];
        // 2048: the full 33×33 mesh, which no member can grow past.
        for n in [t, t - 1, t + 1, (t * 2 + 7).min(2048)] {
            let picked = export(front, &["--max-triangles", &n.to_string()], &out, &[]);
            assert_eq!(picked, lowest_e_within(n), "--max-triangles {n}");
            assert!(all[picked].1 <= n);
            // Between 0.99·N and N: the member itself, or it grown when it has fewer.
            let floor = n - n / 100;
            if all[picked].1 >= floor {
                assert_eq!(faces(&out), all[picked].1);
            } else {
                let f = faces(&out);
                assert!(f <= n && (f >= floor || f + 1 == n), "{f} for {n}");
            }
        }
        for budget in [e, e * (1.0 - 1e-9), e * 1.01] {
            // Under the most accurate member, nothing qualifies (tested with the errors).
            let Some(expected) = fewest_t_within(budget) else {
                continue;
            };
            let picked = export(front, &["--max-error", &budget.to_string()], &out, &[]);
            assert_eq!(picked, expected, "--max-error {budget}");
            assert!(all[picked].0 <= budget);
        }
    }
    // A greedy front is sorted by T with E falling: a member's own T picks it.
    let k = all.len() / 2;
    assert_eq!(
        export(
            front,
            &["--max-triangles", &all[k].1.to_string()],
            &out,
            &[]
        ),
        k
    );
}

#[test]
fn a_budget_between_members_is_met_by_growing_the_member_below_exactly() {
    // The greedy front records a geometric sweep, so its members are far apart at large T: a
    // budget just under a member is met by growing the one below, scored as `eval` scores it.
    let front = front();
    let all = members(front);
    let hf = import::load(&data("volcano_33x33.f32")).unwrap();
    let out = scratch("grown").join("m.ply");
    let gaps: Vec<usize> = (1..all.len())
        .filter(|&k| all[k].1 > all[k - 1].1 * 102 / 100 + 4)
        .collect();
    assert!(gaps.len() >= 3, "the greedy front has gaps to fill");
    for &k in &gaps[gaps.len() - 3..] {
        let n = all[k].1 - 1;
        let args = [
            "export",
            s(front),
            "--max-triangles",
            &n.to_string(),
            "--out",
            s(&out),
        ];
        let result = paretomesh(&args);
        let stderr = text(&result.stderr);
        assert!(result.status.success(), "{stderr}");
        assert!(
            stderr.starts_with(&format!("wrote member {} of {}", k - 1, all.len()))
                && stderr.contains("exact insertions of its worst points"),
            "{stderr}"
        );
        let (kept, triangles) = to_grid(&hf, read_ply(&std::fs::read_to_string(&out).unwrap()));
        let mut kept = kept;
        kept.sort_unstable();
        assert!(all[k - 1].2.iter().all(|i| kept.binary_search(i).is_ok()));
        let (e_sum, t, fresh) = eval(&kept);
        assert!(t <= n && t >= n - n / 100, "T = {t} for a budget of {n}");
        assert_eq!(canonical_set(&triangles), fresh);
        // The message's E_sum is the fresh score's, to the last bit.
        assert!(
            stderr.contains(&format!("(T = {t}, E_sum = {e_sum}, ")),
            "{stderr}"
        );
    }
}

#[test]
fn a_front_without_triangles_exports_the_same_mesh() {
    // A front may list kept indices only; the evaluator rebuilds the same triangles.
    let front = front();
    let dir = scratch("no-triangles");
    let mut json = read_json(front);
    for m in json["front"].as_array_mut().unwrap() {
        m.as_object_mut().unwrap().remove("triangles");
    }
    let bare = dir.join("bare.json");
    std::fs::write(&bare, json.to_string()).unwrap();
    let grid = data("volcano_33x33.f32");
    for k in ["0", "5", "20"] {
        let (with, without) = (
            dir.join(format!("with{k}.obj")),
            dir.join(format!("without{k}.obj")),
        );
        export(front, &["--member", k], &with, &[]);
        export(&bare, &["--member", k], &without, &["--grid", s(&grid)]);
        let (a, b) = (
            std::fs::read(&with).unwrap(),
            std::fs::read(&without).unwrap(),
        );
        // Only the comment naming the front file differs.
        let body = |bytes: &[u8]| {
            text(bytes)
                .lines()
                .filter(|l| !l.starts_with('#'))
                .collect::<Vec<_>>()
                .join("\n")
        };
        assert_eq!(body(&a), body(&b));
    }
}

#[test]
fn a_kept_list_without_the_corners_still_exports_them() {
    // The triangulation always has the four corners, listed or not, and so does the mesh.
    let dir = scratch("no-corners");
    let mut json = read_json(front());
    let corners = [0u32, 32, 1056, 1088];
    let kept = members(front())[6].2.clone();
    let member = &mut json["front"][6];
    let inner: Vec<u32> = kept
        .iter()
        .copied()
        .filter(|i| !corners.contains(i))
        .collect();
    assert_eq!(inner.len(), kept.len() - 4);
    // A plain kept array, as older files hold, in place of the packed forms.
    member["kept"] = serde_json::to_value(&inner).unwrap();
    for key in ["triangles", "kept_packed", "kept_diff"] {
        member.as_object_mut().unwrap().remove(key);
    }
    let edited = dir.join("front.json");
    std::fs::write(&edited, json.to_string()).unwrap();
    let out = dir.join("m.ply");
    export(&edited, &["--member", "6"], &out, &["--grid", GRID]);
    let hf = import::load(&data("volcano_33x33.f32")).unwrap();
    let (mut vertices, triangles) = to_grid(&hf, read_ply(&std::fs::read_to_string(&out).unwrap()));
    vertices.sort_unstable();
    assert_eq!(vertices, kept);
    assert_eq!(canonical_set(&triangles), eval(&kept).2);
}

#[test]
fn the_grid_is_found_beside_front_json_from_any_folder() {
    let dir = scratch("beside");
    let front = dir.join("front.json");
    std::fs::copy(self::front(), &front).unwrap();
    let elsewhere = scratch("elsewhere");
    let out = elsewhere.join("m.ply");
    // Not beside it, and the recorded relative path means nothing from here.
    let result = paretomesh_in(
        &elsewhere,
        &["export", s(&front), "--member", "2", "--out", s(&out)],
    );
    assert_eq!(result.status.code(), Some(1));
    let stderr = text(&result.stderr);
    assert!(
        stderr.contains("was not found") && stderr.contains(GRID) && stderr.contains("--grid"),
        "{stderr}"
    );
    for name in ["volcano_33x33.f32", "volcano_33x33.json"] {
        std::fs::copy(data(name), dir.join(name)).unwrap();
    }
    let result = paretomesh_in(
        &elsewhere,
        &["export", s(&front), "--member", "2", "--out", s(&out)],
    );
    assert!(result.status.success(), "{}", text(&result.stderr));
    assert!(out.is_file());
}

/// Runs `export` expecting failure: exit status 1 (a panic exits with 101) and a message.
fn refused(args: &[&str]) -> String {
    let result = paretomesh(args);
    let stderr = text(&result.stderr);
    assert_eq!(result.status.code(), Some(1), "{args:?}: {stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

#[test]
fn bad_requests_get_a_clear_message() {
    let front = front();
    let count = members(front).len();
    let out = scratch("errors").join("m.ply");
    let (f, o) = (s(front), s(&out));

    let e = refused(&["export", f, "--member", &count.to_string(), "--out", o]);
    assert!(
        e.contains("out of range") && e.contains(&format!("has {count} members")),
        "{e}"
    );
    for n in ["1", "0"] {
        let e = refused(&["export", f, "--max-triangles", n, "--out", o]);
        assert!(
            e.contains("--max-triangles must be at least 2") && e.contains(&format!("got {n}")),
            "{e}"
        );
        assert!(!out.exists());
    }
    // Greedy insertion ends at the full grid (E_sum 0): a negative budget is refused as such.
    let e = refused(&["export", f, "--max-error=-0.5", "--out", o]);
    assert!(
        e.contains("--max-error") && e.contains("at least 0, got -0.5"),
        "{e}"
    );
    let other = data("volcano_87x61.f32");
    let e = refused(&[
        "export",
        f,
        "--member",
        "0",
        "--out",
        o,
        "--grid",
        s(&other),
    ]);
    assert!(e.contains("is 87×61") && e.contains("33×33"), "{e}");
    // Same size, other heights: the member does not score as recorded.
    let other = data("bunny_33x33.f32");
    let e = refused(&[
        "export",
        f,
        "--member",
        "3",
        "--out",
        o,
        "--grid",
        s(&other),
    ]);
    assert!(e.contains("not the grid the front was made on"), "{e}");
    let missing = data("no_such_grid.f32");
    let e = refused(&[
        "export",
        f,
        "--member",
        "0",
        "--out",
        o,
        "--grid",
        s(&missing),
    ]);
    assert!(e.contains("no_such_grid.f32"), "{e}");
    let e = refused(&[
        "export",
        f,
        "--member",
        "0",
        "--out",
        s(&out.with_extension("dae")),
    ]);
    assert!(e.contains("--format"), "{e}");
    let e = refused(&[
        "export",
        s(&data("no_such_front.json")),
        "--member",
        "0",
        "--out",
        o,
    ]);
    assert!(
        e.contains("cannot read") && e.contains("no_such_front.json"),
        "{e}"
    );
    let e = refused(&[
        "export",
        s(&data("volcano_33x33.json")),
        "--member",
        "0",
        "--out",
        o,
    ]);
    assert!(e.contains("is not a front.json"), "{e}");

    // Triangles changed after writing are refused, not exported.
    let mut json = read_json(front);
    let tri = &mut json["front"][4]["triangles"][0];
    let first = tri[0].clone();
    tri[0] = tri[1].clone();
    tri[1] = first;
    let changed = scratch("errors").join("changed.json");
    std::fs::write(&changed, json.to_string()).unwrap();
    let e = refused(&[
        "export",
        s(&changed),
        "--member",
        "4",
        "--out",
        o,
        "--grid",
        GRID,
    ]);
    assert!(e.contains("not the Delaunay triangulation"), "{e}");

    // Clap enforces exactly one selector.
    let result = paretomesh(&["export", f, "--out", o]);
    assert_eq!(result.status.code(), Some(2));
    let result = paretomesh(&["export", f, "--member", "1", "--tradeoff", "--out", o]);
    assert_eq!(result.status.code(), Some(2));
}

#[test]
fn a_georeferenced_geotiff_exports_in_map_coordinates() {
    // Tie point: raster (0, 0) is map (500005, 4000645) at a sample centre, 10 m pixels, 65×65:
    // the mesh spans x 500005..500645 and y 4000005..4000645, whatever the grid indices are.
    let dir = scratch("geotiff");
    let front = dir.join("front.json");
    let tif = "tests/data/jacksboro_65x65_float32_tiled_deflate.tif";
    let run = paretomesh(&[
        "run",
        tif,
        "--algo",
        "greedy",
        "--evals",
        "60",
        "--out",
        s(&front),
    ]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let out = dir.join("m.ply");
    export(&front, &["--max-triangles", "100"], &out, &[]);
    let (vertices, _) = read_ply(&std::fs::read_to_string(&out).unwrap());
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for v in &vertices {
        for k in 0..2 {
            lo[k] = lo[k].min(v[k]);
            hi[k] = hi[k].max(v[k]);
        }
    }
    assert_eq!(lo, [500_005.0, 4_000_005.0]);
    assert_eq!(hi, [500_645.0, 4_000_645.0]);
    // Every vertex is a grid point's map position: its offset from the origin is whole pixels.
    for v in &vertices {
        for k in 0..2 {
            let steps = (v[k] - lo[k]) / 10.0;
            assert_eq!(steps, steps.round(), "{v:?}");
        }
    }
}

/// (E_sum, E_max, T) of every member of a front.json, in the file's order.
fn scores(front: &Path) -> Vec<Score> {
    read_json(front)["front"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| Score {
            e_sum: m["E_sum"].as_f64().unwrap(),
            e_max: m["E_max"].as_f64().unwrap(),
            rms: f64::NAN,
            t: m["T"].as_u64().unwrap() as usize,
        })
        .collect()
}

#[test]
fn errors_in_the_surfaces_units_and_the_knee_pick_their_member() {
    let front = front();
    let all = scores(front);
    let n = 33.0 * 33.0;
    let out = scratch("units").join("m.ply");
    let fewest_within = |ok: &dyn Fn(&Score) -> bool| {
        (0..all.len())
            .filter(|&i| ok(&all[i]))
            .min_by_key(|&i| all[i].t)
            .unwrap()
    };
    for k in [1, all.len() / 3, all.len() / 2, all.len() - 2] {
        let x = all[k].e_max;
        // A mesh at least as small as the fewest-triangle member within x, within x afresh.
        let (t, e_max) = export_within(front, x, &out);
        assert!(t <= all[fewest_within(&|s| s.e_max <= x)].t, "E_max ≤ {x}");
        assert!(e_max <= x, "{e_max} > {x}");
        let mean = all[k].e_sum / n * 1.001;
        let picked = export(front, &["--max-mean-error", &mean.to_string()], &out, &[]);
        assert_eq!(
            picked,
            fewest_within(&|s| s.e_sum / n <= mean),
            "mean ≤ {mean}"
        );
    }
    let picked = export(front, &["--knee"], &out, &[]);
    assert_eq!(picked, knee(&all));
    assert!(
        picked > 0 && picked < all.len() - 1,
        "a middle member: {picked}"
    );

    // Without the full grid on the front, a limit under every member's E_max is reached on
    // demand, from the nearest member.
    let mut json = read_json(front);
    let members = json["front"].as_array_mut().unwrap();
    members.truncate(members.len() / 2);
    let least = members
        .iter()
        .map(|m| m["E_max"].as_f64().unwrap())
        .fold(f64::INFINITY, f64::min);
    let dir = scratch("units-short");
    let short = dir.join("short.json");
    std::fs::write(&short, json.to_string()).unwrap();
    let (_, e_max) = export_within(&short, least / 2.0, &dir.join("m.ply"));
    assert!(e_max <= least / 2.0);

    // A bound below what the grid allows gets a message that says why, and no file.
    let o = dir.join("m.stl");
    for (x, why) in [
        ("-1", "is negative"),
        ("NaN", "is not a number"),
        ("1e-30", "below this grid's exactness floor"),
    ] {
        let e = refused(&[
            "export",
            s(&short),
            "--max-vertical-error",
            x,
            "--grid",
            GRID,
            "--out",
            s(&o),
        ]);
        assert!(
            e.contains("--max-vertical-error") && e.contains(why),
            "{x}: {e}"
        );
        assert!(!o.exists());
    }
}

/// Runs `export --max-vertical-error x` to a PLY and returns the mesh's T and its E_max scored
/// afresh from the triangles read back; the message must say how the mesh was reached.
fn export_within(front: &Path, x: f64, out: &Path) -> (usize, f64) {
    let result = paretomesh(&[
        "export",
        s(front),
        "--max-vertical-error",
        &x.to_string(),
        "--grid",
        GRID,
        "--out",
        s(out),
    ]);
    let stderr = text(&result.stderr);
    assert!(result.status.success(), "{stderr}");
    assert!(
        stderr.contains("meets it as it is") || stderr.contains("made for it from member"),
        "{stderr}"
    );
    let hf = import::load(&data("volcano_33x33.f32")).unwrap();
    let (_, triangles) = to_grid(&hf, read_ply(&std::fs::read_to_string(out).unwrap()));
    let score = paretomesh::evaluator::Evaluator::new(std::sync::Arc::new(hf))
        .score_triangulation(&triangles)
        .unwrap();
    (score.t, score.e_max)
}

/// Directed edges of indexed triangles, each with its count.
fn directed_edges(triangles: &[[u32; 3]]) -> HashMap<(u32, u32), usize> {
    let mut edges = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            *edges.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    edges
}

fn volume(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> f64 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0])
        })
        .sum::<f64>()
        / 6.0
}

#[test]
fn solids_in_every_format_are_closed_and_face_outwards() {
    let front = front();
    let dir = scratch("solid");
    let ply = dir.join("knee.ply");
    let k = export(front, &["--knee", "--solid"], &ply, &[]);
    let (vertices, triangles) = read_ply(&std::fs::read_to_string(&ply).unwrap());
    let edges = directed_edges(&triangles);
    for (&(a, b), &count) in &edges {
        assert_eq!(count, 1, "edge {a}→{b}");
        assert_eq!(edges.get(&(b, a)), Some(&1), "edge {a}→{b} has no opposite");
    }
    let v = volume(&vertices, &triangles);
    assert!(v > 0.0, "volume {v}");
    // The surface's triangles are the member's; walls and bottom add the rest.
    assert!(triangles.len() > scores(front)[k].t);

    // Every other format holds the same solid.
    let obj = dir.join("knee.obj");
    assert_eq!(export(front, &["--knee", "--solid"], &obj, &[]), k);
    assert_eq!(
        read_obj(&std::fs::read_to_string(&obj).unwrap()),
        (vertices.clone(), triangles.clone())
    );
    let three = dir.join("knee.3mf");
    assert_eq!(export(front, &["--knee", "--solid"], &three, &[]), k);
    let models = threemf::read(std::fs::File::open(&three).unwrap()).unwrap();
    let mesh = models[0].resources.object[0].mesh.as_ref().unwrap();
    let read: Vec<[u32; 3]> = mesh
        .triangles
        .triangle
        .iter()
        .map(|t| [t.v1, t.v2, t.v3].map(|i| i as u32))
        .collect();
    assert_eq!(read, triangles);
    assert_eq!(mesh.vertices.vertex.len(), vertices.len());
    let stl = dir.join("knee.stl");
    assert_eq!(export(front, &["--knee", "--solid"], &stl, &[]), k);
    assert_eq!(
        std::fs::read(&stl).unwrap().len(),
        84 + 50 * triangles.len()
    );
    let glb = dir.join("knee.glb");
    assert_eq!(export(front, &["--knee", "--solid"], &glb, &[]), k);
    let file = gltf::Gltf::from_slice(&std::fs::read(&glb).unwrap()).expect("a valid .glb");
    let prim = file.meshes().next().unwrap().primitives().next().unwrap();
    let blob = file.blob.as_deref();
    let reader = prim.reader(|buffer| match buffer.source() {
        gltf::buffer::Source::Bin => blob,
        _ => None,
    });
    assert_eq!(
        reader.read_indices().unwrap().into_u32().count(),
        3 * triangles.len()
    );

    // Bad solid options are refused before anything is written.
    let o = dir.join("bad.stl");
    let e = refused(&[
        "export",
        s(front),
        "--knee",
        "--solid",
        "--base-height",
        "-2",
        "--out",
        s(&o),
    ]);
    assert!(
        e.contains("base height") && e.contains("greater than 0, got -2"),
        "{e}"
    );
    assert!(!o.exists());
    let result = paretomesh(&[
        "export",
        s(front),
        "--knee",
        "--base-height",
        "2",
        "--out",
        s(&o),
    ]);
    assert_eq!(result.status.code(), Some(2), "--base-height needs --solid");
}

/// A closed UV sphere of radius `r` around (0, 0, 5) as ASCII STL facets, outward facing.
fn sphere_facets(r: f64, rings: usize, segments: usize) -> String {
    let point = |i: usize, j: usize| {
        let theta = std::f64::consts::PI * i as f64 / rings as f64;
        let phi = 2.0 * std::f64::consts::PI * j as f64 / segments as f64;
        [
            r * theta.sin() * phi.cos(),
            r * theta.sin() * phi.sin(),
            5.0 + r * theta.cos(),
        ]
    };
    let mut out = String::new();
    let mut facet = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
        out.push_str("facet normal 0 0 0\nouter loop\n");
        for p in [a, b, c] {
            out.push_str(&format!("vertex {} {} {}\n", p[0], p[1], p[2]));
        }
        out.push_str("endloop\nendfacet\n");
    };
    for i in 0..rings {
        for j in 0..segments {
            let (a, b) = (point(i, j), point(i, j + 1));
            let (c, d) = (point(i + 1, j), point(i + 1, j + 1));
            if i > 0 {
                facet(a, c, b);
            }
            if i + 1 < rings {
                facet(b, c, d);
            }
        }
    }
    out
}

#[test]
fn a_closed_mesh_run_with_its_outer_surface_exports_with_the_same_options() {
    // front.json records `--surface outer`; export reads the grid the same way without being
    // told, where the default (a single surface) would refuse the closed mesh.
    let dir = scratch("closed");
    // A thick shell (two nested spheres) folds over itself in every projection.
    let stl = dir.join("sphere.stl");
    let shell = format!(
        "solid shell\n{}{}endsolid shell\n",
        sphere_facets(10.0, 16, 24),
        sphere_facets(8.0, 12, 18)
    );
    std::fs::write(&stl, shell).unwrap();
    let front = dir.join("front.json");
    let run = paretomesh_in(
        &dir,
        &[
            "run",
            "sphere.stl",
            "--surface",
            "outer",
            "--grid-size",
            "25x25",
            "--algo",
            "greedy",
            "--out",
            "front.json",
        ],
    );
    assert!(run.status.success(), "{}", text(&run.stderr));
    let import = &read_json(&front)["grid"]["import"];
    assert_eq!(import["surface"], "outer");
    assert_eq!(import["grid_size"], serde_json::json!([25, 25]));
    let glb = dir.join("bust.glb");
    let out = paretomesh(&[
        "export",
        s(&front),
        "--tradeoff",
        "--format",
        "glb",
        "--out",
        s(&glb),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(gltf::Gltf::from_slice(&std::fs::read(&glb).unwrap()).is_ok());
    // An option given on the command line still wins over the recorded one.
    let e = refused(&[
        "export",
        s(&front),
        "--tradeoff",
        "--surface",
        "single",
        "--out",
        s(&dir.join("single.glb")),
    ]);
    assert!(e.contains("fold"), "{e}");
}
