//! NSGA-II and the weighted-sum GA on real terrain: determinism, slicing invariance,
//! non-dominated fronts and honest objectives (`tests/evolution.rs` runs them through the CLI).
//!
//! Runs are kept tiny (a 17×17 crop, populations of about a dozen) because the tests run in a
//! debug build.

use crate::baselines::{GreedyInsertion, GreedyParams};
use crate::evaluator::Evaluator;
use crate::evaluator::Score;
use crate::evaluator::test_grids::fixture;
use crate::evolution::{
    CrossoverKind, GaParams, Nsga2, ParamsError, WeightedSum, WeightedSumParams,
};
use crate::front::{Front, dominates};
use crate::heightfield::Heightfield;
use crate::optimizer::Optimizer;
use std::sync::Arc;

/// The top-left 17×17 corner of the 33×33 Jacksboro terrain: real relief, small enough that a
/// few hundred evaluations take well under a second in a debug build.
fn terrain_17() -> Arc<Heightfield> {
    let full = fixture("jacksboro_33x33");
    let z = (0..17)
        .flat_map(|y| (0..17).map(move |x| (x, y)))
        .map(|(x, y)| full.z_at(x, y))
        .collect();
    Arc::new(Heightfield::new(17, 17, z).unwrap())
}

fn small(crossover: CrossoverKind) -> GaParams {
    GaParams {
        population: 12,
        generations: 4,
        crossover,
        ..GaParams::default()
    }
}

fn nsga2_front(params: GaParams, seed: u64) -> Front {
    let mut opt = Nsga2::new(terrain_17(), params, seed).unwrap();
    opt.run_to_end();
    opt.front().clone()
}

fn assert_mutually_non_dominated(front: &Front) {
    let s = front.solutions();
    assert!(!s.is_empty());
    for a in s {
        for b in s {
            assert!(
                !dominates(a.objectives(), b.objectives()),
                "{a:?} dominates {b:?}"
            );
        }
    }
    assert!(
        s.windows(2)
            .all(|p| p[0].t < p[1].t && p[0].e_sum > p[1].e_sum)
    );
}

/// Each solution's numbers are exactly what a fresh evaluator says about its kept set.
fn assert_rescores_exactly(hf: &Arc<Heightfield>, front: &Front) {
    let mut ev = Evaluator::new(hf.clone());
    for s in front.solutions() {
        let fresh = ev.score(&s.kept).unwrap();
        assert_eq!((fresh.e_sum, fresh.e_max, fresh.t), (s.e_sum, s.e_max, s.t));
        assert!(hf.corners().iter().all(|c| s.kept.binary_search(c).is_ok()));
        assert!(s.kept.windows(2).all(|p| p[0] < p[1]));
    }
}

#[test]
fn same_seed_gives_the_identical_front_and_other_seeds_differ() {
    let a = nsga2_front(small(CrossoverKind::Oax), 7);
    assert_eq!(a, nsga2_front(small(CrossoverKind::Oax), 7));
    assert_ne!(a, nsga2_front(small(CrossoverKind::Oax), 8));
}

/// Steps `opt` by `slice` evaluations until done; returns the number of calls. With a slice of
/// 1, checks that every call spends at most one evaluation (the unit of work of both GAs).
fn run_sliced(opt: &mut impl Optimizer, slice: u64) -> usize {
    let mut calls = 0;
    loop {
        let before = opt.progress().evaluations;
        let p = opt.step(slice);
        calls += 1;
        if slice == 1 {
            assert!(
                p.evaluations - before <= 1,
                "step(1) spent {} evaluations",
                p.evaluations - before
            );
        }
        if p.done {
            return calls;
        }
    }
}

#[test]
fn slicing_does_not_change_nsga2() {
    // One big step against steps of 1 and of 7 evaluations, for every crossover kind and with
    // an evaluation cap that falls inside a mating: same front, population, crossover record
    // and progress.
    let capped = GaParams {
        max_evaluations: Some(61),
        ..small(CrossoverKind::Oax)
    };
    // Greedy seeding too, uncapped, with the cap inside the greedy run (285 insertions on
    // 17×17) and with it inside the scoring of the initial population.
    let seeded = |cap| GaParams {
        greedy_seed_fraction: 0.25,
        max_evaluations: cap,
        ..small(CrossoverKind::Oax)
    };
    let cases = [
        small(CrossoverKind::Oax),
        small(CrossoverKind::Uniform),
        small(CrossoverKind::TwoPoint),
        capped,
        seeded(None),
        seeded(Some(100)),
        seeded(Some(290)),
    ];
    for params in cases {
        let mut whole = Nsga2::new(terrain_17(), params.clone(), 3).unwrap();
        let end = whole.run_to_end();
        for slice in [1, 7] {
            let mut sliced = Nsga2::new(terrain_17(), params.clone(), 3).unwrap();
            let calls = run_sliced(&mut sliced, slice);
            assert!(calls >= 8, "really sliced: {calls} calls");
            assert_eq!(sliced.progress(), end, "{params:?}, slices of {slice}");
            assert_eq!(sliced.front(), whole.front());
            assert_eq!(sliced.population(), whole.population());
            assert_eq!(sliced.last_crossover(), whole.last_crossover());
        }
    }
}

#[test]
fn step_1_does_one_evaluation_through_an_oax_mating() {
    // Right after the initial population, an OAX crossover with probability 1 is in progress:
    // each step(1) spends exactly one evaluation (so a browser frame never waits for a whole
    // crossover), and the crossover record only appears once a crossover has completed.
    let params = GaParams {
        crossover_probability: 1.0,
        ..small(CrossoverKind::Oax)
    };
    let mut opt = Nsga2::new(terrain_17(), params, 11).unwrap();
    opt.step(12);
    assert_eq!(opt.progress().evaluations, 12, "the initial population");
    assert!(opt.last_crossover().is_none());
    let mut evaluations = 12;
    while opt.last_crossover().is_none() {
        let p = opt.step(1);
        assert_eq!(p.evaluations, evaluations + 1);
        evaluations = p.evaluations;
    }
    let record = opt.last_crossover().unwrap();
    // The step that completed the crossover may go on into the first mutation when the
    // best-levels child cost nothing, hence one evaluation of slack.
    let spent = evaluations - 12;
    let crossover = record.evaluations() as u64;
    assert!(
        crossover <= spent && spent <= crossover + 1,
        "the crossover spent {crossover} of the {spent} evaluations since the population"
    );
}

#[test]
fn slicing_does_not_change_the_weighted_sum_ga() {
    for crossover in [CrossoverKind::Oax, CrossoverKind::TwoPoint] {
        let params = WeightedSumParams {
            ga: GaParams {
                population: 6,
                generations: 2,
                crossover,
                ..GaParams::default()
            },
            weights: vec![0.2, 0.5, 0.9],
        };
        let mut whole = WeightedSum::new(terrain_17(), params.clone(), 5).unwrap();
        let end = whole.run_to_end();
        for slice in [1, 3] {
            let mut sliced = WeightedSum::new(terrain_17(), params.clone(), 5).unwrap();
            run_sliced(&mut sliced, slice);
            assert_eq!(sliced.progress(), end, "{crossover:?}, slices of {slice}");
            assert_eq!(sliced.front(), whole.front());
            assert_eq!(sliced.run_bests(), whole.run_bests());
            assert_eq!(sliced.last_crossover(), whole.last_crossover());
        }
    }
}

#[test]
fn nsga2_fronts_are_non_dominated_and_rescore_exactly_for_every_crossover() {
    let hf = terrain_17();
    for kind in [
        CrossoverKind::Oax,
        CrossoverKind::Uniform,
        CrossoverKind::TwoPoint,
    ] {
        let mut opt = Nsga2::new(hf.clone(), small(kind), 11).unwrap();
        let p = opt.run_to_end();
        assert_eq!(p.generation, 4);
        assert_mutually_non_dominated(opt.front());
        assert_rescores_exactly(&hf, opt.front());
        // The archive holds everything seen: no survivor beats it.
        for ind in opt.population() {
            assert!(opt.front().solutions().iter().any(|s| {
                let o = s.objectives();
                o == ind.objectives.objectives() || dominates(o, ind.objectives.objectives())
            }));
        }
    }
}

#[test]
fn population_reports_ranks_and_crowding() {
    let mut opt = Nsga2::new(terrain_17(), small(CrossoverKind::Oax), 2).unwrap();
    opt.run_to_end();
    let pop = opt.population();
    assert_eq!(pop.len(), 12);
    for a in pop {
        // Rank 0 ⇔ nobody in the population dominates it; rank r > 0 ⇒ someone of rank r − 1
        // dominates it.
        let dominators: Vec<_> = pop
            .iter()
            .filter(|b| dominates(b.objectives.objectives(), a.objectives.objectives()))
            .collect();
        assert_eq!(a.rank == 0, dominators.is_empty());
        if a.rank > 0 {
            assert!(dominators.iter().any(|b| b.rank == a.rank - 1));
        }
        assert!(a.crowding >= 0.0);
    }
    // The extremes of the first front have infinite crowding.
    let first = pop.iter().filter(|a| a.rank == 0);
    let min_t = first.clone().min_by_key(|a| a.objectives.t).unwrap();
    assert!(min_t.crowding.is_infinite());
}

#[test]
fn crossover_record_is_consistent_with_the_evaluator() {
    let hf = terrain_17();
    let mut opt = Nsga2::new(hf.clone(), small(CrossoverKind::Oax), 4).unwrap();
    opt.run_to_end();
    let r = opt
        .last_crossover()
        .expect("p_c = 0.8 over 24 matings crosses at least once");
    assert_eq!(r.rows.len(), 8);
    assert_eq!(r.rows[0].genes, r.parents[0].0);
    let mut ev = Evaluator::new(hf.clone());
    let scalar = |o: &Score| {
        let e0 = ev_corners(&hf);
        r.weight * o.e_sum / e0 + (1.0 - r.weight) * o.t as f64 / hf.full_triangles() as f64
    };
    for child in r.rows.iter().chain([&r.best_levels]) {
        let s = ev.score(&child.genes.indices()).unwrap();
        assert_eq!((s.e_sum, s.t), (child.objectives.e_sum, child.objectives.t));
        assert!((scalar(&child.objectives) - child.fitness).abs() < 1e-12);
    }
    // The best-levels child takes, for every factor, the level with the smaller fitness sum.
    for (f, effect) in r.effects.iter().enumerate() {
        assert_eq!(r.best_levels.levels[f], u8::from(effect[1] < effect[0]));
    }
    // The first child returned is the fittest, the second the fittest with other genes.
    let all: Vec<_> = r.rows.iter().chain([&r.best_levels]).collect();
    let (first, second) = (r.child(r.chosen[0]), r.child(r.chosen[1]));
    assert!(all.iter().all(|c| c.fitness >= first.fitness));
    assert!(
        all.iter()
            .filter(|c| c.genes != first.genes)
            .all(|c| c.fitness >= second.fitness)
    );
}

fn ev_corners(hf: &Arc<Heightfield>) -> f64 {
    Evaluator::new(hf.clone()).score(&[]).unwrap().e_sum
}

#[test]
fn evaluation_cap_stops_the_run() {
    // One unit spends at most 7 + 1 OAX children + 2 mutants = 10 evaluations.
    let params = GaParams {
        max_evaluations: Some(50),
        ..small(CrossoverKind::Oax)
    };
    let mut opt = Nsga2::new(terrain_17(), params, 1).unwrap();
    let p = opt.run_to_end();
    assert!((50..60).contains(&p.evaluations), "{}", p.evaluations);
    assert!(p.generation < 4);
}

#[test]
fn weighted_sum_keeps_the_best_of_each_weight() {
    let hf = terrain_17();
    let params = WeightedSumParams {
        ga: GaParams {
            population: 6,
            generations: 2,
            ..GaParams::default()
        },
        ..WeightedSumParams::default()
    };
    let mut opt = WeightedSum::new(hf.clone(), params, 9).unwrap();
    opt.run_to_end();
    let weights: Vec<f64> = opt.run_bests().iter().map(|(w, _)| *w).collect();
    assert_eq!(
        weights,
        (0..=10).map(|k| k as f64 / 10.0).collect::<Vec<_>>()
    );
    assert_eq!(
        opt.front(),
        &Front::merged(opt.run_bests().iter().map(|(_, s)| s))
    );
    assert_mutually_non_dominated(opt.front());
    assert_rescores_exactly(&hf, opt.front());
}

#[test]
fn bad_parameters_are_typed_errors() {
    let hf = terrain_17();
    let bad = |p: GaParams| Nsga2::new(hf.clone(), p, 1).err();
    assert_eq!(
        bad(GaParams {
            population: 1,
            ..GaParams::default()
        }),
        Some(ParamsError::PopulationTooSmall(1))
    );
    assert!(matches!(
        bad(GaParams {
            crossover_probability: 1.5,
            ..GaParams::default()
        }),
        Some(ParamsError::BadProbability { .. })
    ));
    assert!(matches!(
        bad(GaParams {
            mutation_probability: Some(-0.1),
            ..GaParams::default()
        }),
        Some(ParamsError::BadProbability { .. })
    ));
    assert_eq!(
        bad(GaParams {
            factors: 1,
            ..GaParams::default()
        }),
        Some(ParamsError::BadFactors(1))
    );
    for fraction in [-0.1, 1.5, f64::NAN] {
        assert!(matches!(
            bad(GaParams {
                greedy_seed_fraction: fraction,
                ..GaParams::default()
            }),
            Some(ParamsError::BadSeedFraction(_))
        ));
    }
    // Seeding is NSGA-II's option; the weighted-sum GA says so rather than ignore it.
    let seeded_weighted = WeightedSumParams {
        ga: GaParams {
            greedy_seed_fraction: 0.5,
            ..GaParams::default()
        },
        ..WeightedSumParams::default()
    };
    assert_eq!(
        WeightedSum::new(hf.clone(), seeded_weighted, 1).err(),
        Some(ParamsError::SeedingUnsupported)
    );
    let weights = WeightedSumParams {
        weights: vec![0.5, 1.2],
        ..WeightedSumParams::default()
    };
    assert_eq!(
        WeightedSum::new(hf, weights, 1).err(),
        Some(ParamsError::BadWeights)
    );
}

#[test]
fn params_round_trip_through_json_with_paper_defaults() {
    let p = GaParams::default();
    assert_eq!(
        (
            p.population,
            p.generations,
            p.crossover_probability,
            p.mutation_probability
        ),
        (100, 50, 0.8, None)
    );
    let json = serde_json::to_string(&WeightedSumParams::default()).unwrap();
    assert!(json.contains("\"crossover\":\"oax\""), "{json}");
    let back: WeightedSumParams = serde_json::from_str(&json).unwrap();
    assert_eq!(back, WeightedSumParams::default());
    // Missing fields take the defaults (share links may carry only what differs).
    let partial: GaParams =
        serde_json::from_str(r#"{"population": 20, "crossover": "two-point"}"#).unwrap();
    assert_eq!(
        (partial.population, partial.crossover, partial.generations),
        (20, CrossoverKind::TwoPoint, 50)
    );
    // JSON written before greedy seeding existed parses with seeding off.
    assert_eq!(partial.greedy_seed_fraction, 0.0);
}

#[test]
fn greedy_seeds_are_greedy_solutions_spread_over_its_front() {
    let hf = terrain_17();
    // 0.25 of 12 → 3 seeds: the sparsest, a middle and the densest mesh of greedy's front.
    let params = GaParams {
        greedy_seed_fraction: 0.25,
        ..small(CrossoverKind::Oax)
    };
    assert_eq!(params.greedy_seeds(), 3);
    let mut greedy = GreedyInsertion::new(hf.clone(), GreedyParams::default()).unwrap();
    greedy.run_to_end();
    let greedy_front = greedy.front().solutions();
    let n = greedy_front.len();
    assert!(n >= 3, "greedy front of {n}");

    let mut opt = Nsga2::new(hf.clone(), params, 5).unwrap();
    while opt.population().len() < 12 {
        opt.step(1);
    }
    let population = opt.population();
    let seeds = &population[..3];
    let kept: Vec<Vec<u32>> = seeds.iter().map(|s| s.genes.indices()).collect();
    assert_eq!(kept[0], greedy_front[0].kept);
    assert_eq!(
        kept[1],
        greedy_front[n / 2].kept,
        "round((n − 1)/2) = ⌊n/2⌋"
    );
    assert_eq!(kept[2], greedy_front[n - 1].kept);
    for (seed, solution) in seeds
        .iter()
        .zip([0, n / 2, n - 1].map(|i| &greedy_front[i]))
    {
        assert_eq!(seed.objectives.objectives(), solution.objectives());
    }
    // The others are random, not greedy meshes.
    for other in &population[3..] {
        let indices = other.genes.indices();
        assert!(greedy_front.iter().all(|s| s.kept != indices));
    }
    // Greedy's insertions are charged to the run, on top of one evaluation per individual.
    let insertions = greedy.progress().evaluations;
    assert_eq!(insertions, 285, "every free point of the 17×17 grid");
    assert_eq!(opt.greedy_evaluations(), insertions);
    assert_eq!(opt.progress().evaluations, insertions + 12);
    // The seeds enter the archive: the sparsest (corners only, T = 2) stays non-dominated.
    assert!(
        opt.front()
            .solutions()
            .iter()
            .any(|s| s.kept == greedy_front[0].kept)
    );
}

#[test]
fn seeded_runs_are_deterministic_and_differ_from_unseeded() {
    let seeded = GaParams {
        greedy_seed_fraction: 0.25,
        ..small(CrossoverKind::Oax)
    };
    let a = nsga2_front(seeded.clone(), 7);
    assert_eq!(a, nsga2_front(seeded, 7));
    assert_mutually_non_dominated(&a);
    assert_rescores_exactly(&terrain_17(), &a);
    assert_ne!(a, nsga2_front(small(CrossoverKind::Oax), 7));
}

#[test]
fn explicit_zero_seed_fraction_is_the_default_run() {
    // A fraction too small to seed one individual (⌊0.05 · 12⌋ = 0) is also no seeding.
    for fraction in [0.0, 0.05] {
        let explicit = GaParams {
            greedy_seed_fraction: fraction,
            ..small(CrossoverKind::Oax)
        };
        let mut a = Nsga2::new(terrain_17(), small(CrossoverKind::Oax), 4).unwrap();
        let mut b = Nsga2::new(terrain_17(), explicit, 4).unwrap();
        assert_eq!(a.run_to_end(), b.run_to_end());
        assert_eq!(a.front(), b.front());
        assert_eq!(a.population(), b.population());
        assert_eq!(b.greedy_evaluations(), 0);
    }
}

#[test]
fn step_until_stops_exactly_at_a_generation_boundary() {
    // A share link re-runs to generation g of a longer run: the state there must be the state
    // of a run that has only g generations, however small the slices.
    let hf = terrain_17();
    let params = small(CrossoverKind::Oax);
    for slice in [1, 7, u64::MAX] {
        let mut run = Nsga2::new(hf.clone(), params.clone(), 5).unwrap();
        let mut calls = 0;
        while run.progress().generation < 2 {
            let p = run.step_until(slice, 2);
            assert!(p.generation <= 2, "never past the target");
            calls += 1;
            assert!(calls < 1_000_000);
        }
        let mut short = Nsga2::new(
            hf.clone(),
            GaParams {
                generations: 2,
                ..params.clone()
            },
            5,
        )
        .unwrap();
        short.run_to_end();
        assert_eq!(run.front(), short.front(), "slice {slice}");
        assert_eq!(run.progress().evaluations, short.progress().evaluations);
        assert!(!run.progress().done, "the longer run goes on");
        // At the target already: nothing more happens.
        let before = run.progress();
        assert_eq!(run.step_until(slice, 2), before);
    }
}

#[test]
fn the_generation_trace_agrees_with_the_population_it_produced() {
    use crate::evolution::ranking::non_dominated_fronts;
    let hf = terrain_17();
    let params = small(CrossoverKind::Oax);
    let mu = params.population;
    let mut run = Nsga2::new(hf, params, 3).unwrap();
    assert!(run.last_generation().is_none(), "no generation yet");
    run.step_until(u64::MAX, 2);
    let trace = run
        .last_generation()
        .expect("generation 2 is traced")
        .clone();
    assert_eq!(trace.generation, 2);
    assert_eq!(trace.parents.len(), mu);
    assert_eq!(trace.offspring.len(), mu);
    assert_eq!(trace.matings.len(), mu / 2, "two children per mating");
    // Tournaments: the winner is the better-ranked, then the less crowded, then the first.
    for m in &trace.matings {
        for (t, &winner) in m.tournaments.iter().zip(&m.parents) {
            let [a, b] = t.map(|i| trace.parents[i]);
            let second_wins = b.rank < a.rank || (b.rank == a.rank && b.crowding > a.crowding);
            assert_eq!(winner, if second_wins { t[1] } else { t[0] });
        }
        // An uncrossed, unmutated child is its parent.
        for k in 0..2 {
            if !m.crossed && m.flipped[k] == 0 {
                assert_eq!(m.children[k], trace.parents[m.parents[k]].objectives);
            }
        }
        // Before mutation: OAX's chosen children are scored; an uncrossed pair is the parents.
        if m.crossed {
            assert!(m.before_mutation.iter().all(|o| o.is_some()));
        } else {
            assert_eq!(m.crossover_evaluations, 0);
            assert_eq!(
                m.before_mutation,
                m.parents.map(|p| Some(trace.parents[p].objectives))
            );
        }
    }
    let children: Vec<_> = trace.matings.iter().flat_map(|m| m.children).collect();
    assert_eq!(children, trace.offspring);
    // The union's fronts are the non-dominated sort of parents + offspring.
    let points: Vec<[f64; 2]> = trace
        .union
        .iter()
        .map(|m| m.objectives.objectives())
        .collect();
    assert_eq!(trace.union.len(), 2 * mu);
    for (rank, front) in non_dominated_fronts(&points).iter().enumerate() {
        for &i in front {
            assert_eq!(trace.union[i].rank, rank);
        }
    }
    // Survivors: μ distinct union members, and exactly the new population, in order.
    let mut distinct = trace.survivors.clone();
    distinct.sort_unstable();
    distinct.dedup();
    assert_eq!(distinct.len(), mu);
    let survivors: Vec<_> = trace
        .survivors
        .iter()
        .map(|&i| trace.union[i].objectives)
        .collect();
    let population: Vec<_> = run.population().iter().map(|i| i.objectives).collect();
    assert_eq!(survivors, population);
    // No survivor is in a worse front than a member that did not survive.
    let kept = trace.survived();
    let worst_kept = (0..2 * mu)
        .filter(|&i| kept[i])
        .map(|i| trace.union[i].rank)
        .max();
    let best_dropped = (0..2 * mu)
        .filter(|&i| !kept[i])
        .map(|i| trace.union[i].rank)
        .min();
    assert!(worst_kept <= best_dropped);
    assert_eq!(trace.selection_counts().iter().sum::<usize>(), mu);
}
