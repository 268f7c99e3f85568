//! The evaluator's four ways of scoring a kept set, each beside a fresh score of the same set.
//!
//! - `jacksboro_65x65/*`, `fractal_257/*` (`tests/data/jacksboro_65x65`, and the fbm terrain
//!   of `scripts/terrain.py`, `tests/data/bunny_65x65` when run as a test; see
//!   `common::large_grid`): a fresh evaluation (`evaluate`) of 2 %, 10 % and
//!   30 % of the grid, the evaluator's triangulation alone (`triangulate`, so the raster's share
//!   is the difference), and spade's bare bulk load of the same points (`spade_bulk_load`), the
//!   yardstick for a fresh evaluation. Read the ratio of `evaluate` to `spade_bulk_load` from one
//!   run of the group: on a shared machine two runs minutes apart differ by more than the ratio
//!   does.
//! - `incremental/*`: scoring a kept set by editing the mesh of a set d genes away
//!   ([`Evaluator::edit`], including the copy of the base mesh, as the GA's scorer does it) beside
//!   a fresh score of the same set, on `jacksboro_65x65` at 30 % density: where the two cross is
//!   the scorer's edit limit.
//! - `compose/*`: a child of two parents (35 % and 25 % kept) taking each of 7 spatial blocks
//!   from one of them, as the rows of an OAX crossover do: composed from both parents' meshes
//!   ([`Evaluator::compose`]), composed with both parents' triangles classified once for the
//!   crossover's blocks ([`Evaluator::compose_parts`]; `classify` is that classification, paid
//!   once per crossover), edited from parent A's, and scored fresh.

mod common;

use common::{fixture, kept_subset, large_grid};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use paretomesh::evaluator::{Evaluator, MeshState, PartClasses, Triangulation as Mesh};
use rand::{RngExt, SeedableRng};
use spade::{DelaunayTriangulation, Point2, Triangulation};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let grids = [
        ("jacksboro_65x65".to_string(), fixture("jacksboro_65x65")),
        large_grid(),
    ];
    for (name, hf) in grids {
        let mut group = c.benchmark_group(name);
        for percent in [2u32, 10, 30] {
            let kept = kept_subset(hf.len(), percent as f64 / 100.0, 7, hf.corners());
            let w = hf.width() as u32;
            let points: Vec<Point2<f64>> = kept
                .iter()
                .map(|&i| Point2::new((i % w) as f64, (i / w) as f64))
                .collect();
            group.bench_with_input(
                BenchmarkId::new("spade_bulk_load", percent),
                &points,
                |b, p| {
                    b.iter(|| {
                        let t =
                            DelaunayTriangulation::<Point2<f64>>::bulk_load(black_box(p.clone()))
                                .unwrap();
                        black_box(t.num_inner_faces())
                    })
                },
            );
            // The evaluator's own triangulation alone (Lawson insertion), to show what the
            // error raster adds on top.
            let mut mesh = Mesh::default();
            group.bench_with_input(BenchmarkId::new("triangulate", percent), &kept, |b, k| {
                b.iter(|| {
                    mesh.rebuild_delaunay(hf.width(), black_box(k));
                    black_box(mesh.len())
                })
            });
            let mut ev = Evaluator::new(std::sync::Arc::new(hf.clone()));
            group.bench_with_input(BenchmarkId::new("evaluate", percent), &kept, |b, k| {
                b.iter(|| black_box(ev.score(black_box(k)).unwrap()))
            });
        }
        group.finish();
    }
}

fn bench_incremental(c: &mut Criterion) {
    let hf = std::sync::Arc::new(fixture("jacksboro_65x65"));
    let n = hf.len();
    let base_kept = kept_subset(n, 0.3, 7, hf.corners());
    let mut ev = Evaluator::new(hf.clone());
    let mut base = MeshState::default();
    ev.score_into(&base_kept, &mut base).unwrap();
    let mut group = c.benchmark_group("incremental");
    group.sample_size(20);
    for distance in [1usize, 16, 128, 512, 1024, 2048] {
        // `distance` distinct free points flipped, in grid order (as the scorer passes them).
        let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(distance as u64);
        let mut flip = vec![false; n];
        let corners = hf.corners();
        let mut count = 0;
        while count < distance {
            let i = rng.random_range(0..n as u32);
            if !corners.contains(&i) && !flip[i as usize] {
                flip[i as usize] = true;
                count += 1;
            }
        }
        let (mut remove, mut insert) = (Vec::new(), Vec::new());
        for i in 0..n as u32 {
            if flip[i as usize] {
                if base.is_kept(i) {
                    remove.push(i);
                } else {
                    insert.push(i);
                }
            }
        }
        let child: Vec<u32> = (0..n as u32)
            .filter(|&i| base.is_kept(i) != flip[i as usize])
            .collect();
        let mut state = MeshState::default();
        group.bench_function(BenchmarkId::new("edit", distance), |b| {
            b.iter(|| {
                state.clone_from(&base);
                black_box(ev.edit(&mut state, &remove, &insert).unwrap())
            })
        });
        group.bench_function(BenchmarkId::new("fresh", distance), |b| {
            b.iter(|| black_box(ev.score_into(&child, &mut state).unwrap()))
        });
    }
    group.finish();
}

fn bench_compose(c: &mut Criterion) {
    use paretomesh::evolution::{chromosome::Chromosome, oax::spatial_blocks};
    let hf = std::sync::Arc::new(fixture("jacksboro_65x65"));
    let (w, n) = (hf.width(), hf.len());
    let mut ev = Evaluator::new(hf.clone());
    let corners = hf.corners();
    let kept = [
        kept_subset(n, 0.35, 11, corners),
        kept_subset(n, 0.25, 12, corners),
    ];
    let parents = kept.clone().map(|k| {
        let mut s = MeshState::default();
        ev.score_into(&k, &mut s).unwrap();
        s.ensure_discs();
        s
    });
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(3);
    let blocks = spatial_blocks(w, hf.height(), 7, &mut rng);
    let mut group = c.benchmark_group("compose");
    group.sample_size(20);
    let rects: Vec<[usize; 4]> = blocks.iter().map(|b| [b.x0, b.y0, b.x1, b.y1]).collect();
    let mut classes = PartClasses::default();
    group.bench_function("classify", |b| {
        b.iter(|| black_box(classes.reset(&hf, &parents[0], &parents[1], &rects)))
    });
    // Rows 1, 2 and 5 of L8 (level = parity of popcount(row & column)).
    for row in [1u32, 2, 5] {
        let mut levels = 0u32;
        let mut from_b = Chromosome::empty(n);
        for (k, b) in blocks.iter().enumerate() {
            if ((k as u32 + 1) & row).count_ones() % 2 == 1 {
                levels |= 1 << k;
                for y in b.y0..b.y1 {
                    from_b.set_range(y * w + b.x0, y * w + b.x1);
                }
            }
        }
        let in_child = |i: u32| {
            let side = usize::from(from_b.get(i as usize));
            parents[side].is_kept(i)
        };
        let child: Vec<u32> = (0..n as u32).filter(|&i| in_child(i)).collect();
        let (remove, insert): (Vec<u32>, Vec<u32>) = (0..n as u32)
            .filter(|&i| parents[0].is_kept(i) != in_child(i))
            .partition(|&i| parents[0].is_kept(i));
        let mut state = MeshState::default();
        group.bench_function(BenchmarkId::new("compose", row), |b| {
            b.iter(|| {
                black_box(
                    ev.compose(&mut state, &parents[0], &parents[1], from_b.words())
                        .unwrap(),
                )
            })
        });
        group.bench_function(BenchmarkId::new("compose_parts", row), |b| {
            b.iter(|| {
                black_box(
                    ev.compose_parts(&mut state, &parents[0], &parents[1], &classes, levels)
                        .unwrap(),
                )
            })
        });
        group.bench_function(BenchmarkId::new("edit", row), |b| {
            b.iter(|| {
                state.clone_from(&parents[0]);
                black_box(ev.edit(&mut state, &remove, &insert).unwrap())
            })
        });
        group.bench_function(BenchmarkId::new("fresh", row), |b| {
            b.iter(|| black_box(ev.score_into(&child, &mut state).unwrap()))
        });
    }
    group.finish();
}

criterion_group!(benches, bench, bench_incremental, bench_compose);
criterion_main!(benches);
