//! The scorer gives a fresh evaluation's bits whichever way it takes, and keeps the meshes
//! the GA will need.

use super::*;
use rand::{RngExt, SeedableRng};

#[test]
fn normalisers_are_the_corner_mesh_error_and_the_full_grid_triangles() {
    // 3×3 grid, flat but for a bump of 4 in the middle: E₀ = 4 (corners only), T₀ = 8.
    let mut z = vec![0.0; 9];
    z[4] = 4.0;
    let hf = Arc::new(Heightfield::new(3, 3, z).unwrap());
    let mut scorer = Scorer::new(hf);
    let f = scorer.scalarisation(0.25);
    assert_eq!((f.e0, f.t0), (4.0, 8.0));
    let corners = Chromosome::from_indices(9, &[0, 2, 6, 8]);
    let o = scorer.score(&corners);
    assert_eq!((o.e_sum, o.t), (4.0, 2));
    assert_eq!(f.value(&o), 0.25 * 1.0 + 0.75 * 2.0 / 8.0);
    assert_eq!(scorer.evaluations(), 1, "E₀ itself is not counted");
}

/// A 9×7 grid of random heights with some exact ties (integers).
fn bumpy(seed: u64) -> Arc<Heightfield> {
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(seed);
    let z = (0..63).map(|_| rng.random_range(0..6) as f64).collect();
    Arc::new(Heightfield::new(9, 7, z).unwrap())
}

/// A chromosome of `hf` keeping each point with probability `density`, and the corners.
fn random_genes(hf: &Heightfield, density: f64, rng: &mut rand_pcg::Pcg64Mcg) -> Chromosome {
    let n = hf.len();
    let kept: Vec<u32> = (0..n as u32)
        .filter(|_| rng.random::<f64>() < density)
        .chain(hf.corners())
        .collect();
    Chromosome::from_indices(n, &kept)
}

/// The bits of a fresh evaluation's score of `c`.
fn fresh(hf: &Arc<Heightfield>, c: &Chromosome) -> (u64, u64, u64, usize) {
    bits(Evaluator::new(hf.clone()).score(&c.indices()).unwrap())
}

/// Every number of `s`, as bits.
fn bits(s: Score) -> (u64, u64, u64, usize) {
    (s.e_sum.to_bits(), s.e_max.to_bits(), s.rms.to_bits(), s.t)
}

#[test]
fn pooled_scoring_equals_fresh_scoring_bit_for_bit() {
    // A GA-like stream: random chromosomes, mutants (1–2 flips) and block crossovers of
    // earlier ones, and exact repeats; the pool is kept tiny (3 meshes) so that eviction,
    // editing the base in place and fresh builds all happen. Every score must be the fresh
    // score's bits, and every call counts one evaluation.
    let hf = bumpy(3);
    let n = hf.len();
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(21);
    for capacity in [1, 3] {
        let mut scorer = Scorer::new(hf.clone());
        scorer.capacity = capacity;
        let mut seen: Vec<Chromosome> = Vec::new();
        for step in 0..300 {
            let c = match (seen.len(), rng.random_range(0..4)) {
                (0, _) | (_, 0) => {
                    let density = rng.random::<f64>();
                    let kept: Vec<u32> = (0..n as u32)
                        .filter(|_| rng.random::<f64>() < density)
                        .chain(hf.corners())
                        .collect();
                    Chromosome::from_indices(n, &kept)
                }
                (m, 1) => {
                    let mut c = seen[rng.random_range(0..m)].clone();
                    for _ in 0..rng.random_range(1..3) {
                        let i = rng.random_range(0..n);
                        if !hf.corners().contains(&(i as u32)) {
                            c.flip(i);
                        }
                    }
                    c
                }
                (m, 2) => {
                    let (a, b) = (&seen[rng.random_range(0..m)], &seen[rng.random_range(0..m)]);
                    let mut c = a.clone();
                    let start = rng.random_range(0..n);
                    c.copy_range_from(b, start, n.min(start + 20));
                    c
                }
                (m, _) => seen[rng.random_range(0..m)].clone(),
            };
            let o = scorer.score(&c);
            assert_eq!(bits(o), fresh(&hf, &c), "capacity {capacity}, step {step}");
            assert_eq!(scorer.evaluations(), step as u64 + 1);
            assert!(scorer.pool.len() <= capacity);
            seen.push(c);
        }
    }
}

#[test]
fn the_population_stays_pooled_while_others_come_and_go() {
    // A pool of 4 meshes: two chromosomes declared alive must survive 40 other scorings,
    // which evict everything else; once no longer alive, they are replaced like the rest.
    let hf = bumpy(5);
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(8);
    let mut random = |density: f64| random_genes(&hf, density, &mut rng);
    let alive = [random(0.3), random(0.6)];
    let mut scorer = Scorer::new(hf.clone());
    scorer.capacity = 4;
    for c in &alive {
        scorer.score(c);
    }
    scorer.keep_alive(alive.iter());
    let others: Vec<Chromosome> = (0..40).map(|k| random(0.1 + 0.02 * k as f64)).collect();
    for c in &others {
        scorer.score(c);
    }
    assert!(alive.iter().all(|c| scorer.pooled(c).is_some()));
    assert!(scorer.pooled(&others[0]).is_none(), "the pool is full");
    scorer.keep_alive([]);
    // Far from every pooled chromosome (a near one would be scored without a mesh, as its
    // mutant): each takes a slot.
    for _ in 0..4 {
        let c = random(0.5);
        scorer.score(&c);
        assert!(scorer.pooled(&c).is_some());
    }
    assert!(alive.iter().all(|c| scorer.pooled(c).is_none()));
}

#[test]
fn mutants_of_pooled_chromosomes_are_scored_without_copies_and_pooled_when_alive() {
    // A population on a 33×29 grid, each member mutated in 1–4 genes: every mutant scores
    // as a fresh evaluation does, none takes a pool slot (its mesh is deferred), and those
    // declared alive then hold meshes equal to fresh ones; the others stay unpooled.
    let (w, h) = (33, 29);
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(21);
    let z = (0..w * h).map(|_| rng.random_range(0..40) as f64).collect();
    let hf = Arc::new(Heightfield::new(w, h, z).unwrap());
    let n = hf.len();
    let corners = hf.corners();
    let population: Vec<Chromosome> = (0..12)
        .map(|k| random_genes(&hf, 0.05 + 0.07 * k as f64, &mut rng))
        .collect();
    let mut scorer = Scorer::new(hf.clone());
    for c in &population {
        scorer.score(c);
    }
    scorer.keep_alive(population.iter());
    let pooled_before = scorer.pool.len();
    let mut mutants = Vec::new();
    for c in &population {
        let mut m = c.clone();
        for _ in 0..rng.random_range(1..=4) {
            let i = loop {
                let i = rng.random_range(0..n as u32);
                if !corners.contains(&i) {
                    break i;
                }
            };
            m.flip(i as usize);
        }
        let o = scorer.score(&m);
        assert_eq!(bits(o), fresh(&hf, &m));
        mutants.push(m);
    }
    assert_eq!(scorer.pool.len(), pooled_before, "no mutant took a slot");
    assert!(mutants.iter().all(|m| scorer.pooled(m).is_none()));
    let alive: Vec<&Chromosome> = mutants.iter().step_by(2).collect();
    scorer.keep_alive(alive.iter().copied());
    for (k, m) in mutants.iter().enumerate() {
        match scorer.pooled(m) {
            Some(i) => {
                assert!(k % 2 == 0, "mutant {k} was not declared alive");
                let s = scorer.pool[i].state.score().unwrap();
                assert_eq!(bits(s), fresh(&hf, m));
                assert!(scorer.pool[i].alive);
            }
            None => assert!(k % 2 == 1, "alive mutant {k} has no mesh"),
        }
    }
}

#[test]
fn the_pool_grows_to_hold_two_populations_of_the_declared_size() {
    // A population of 150 on a small grid (the bytes allow thousands of meshes): a fixed
    // pool of POOL_STATES = 200 could not hold it and as many offspring, so composing new
    // members would replace their parents; declaring it sizes the pool for both.
    let hf = bumpy(6);
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(9);
    let mut random = |density: f64| random_genes(&hf, density, &mut rng);
    let population: Vec<Chromosome> = (0..150).map(|k| random(0.05 + 0.005 * k as f64)).collect();
    let mut scorer = Scorer::new(hf.clone());
    assert_eq!(scorer.capacity, POOL_STATES);
    for c in &population {
        scorer.score(c);
    }
    scorer.keep_alive(population.iter());
    assert_eq!(scorer.capacity, POOL_PER_MEMBER * population.len());
    let offspring: Vec<Chromosome> = (0..150).map(|k| random(0.8 - 0.004 * k as f64)).collect();
    for c in &offspring {
        scorer.score(c);
    }
    assert!(population.iter().all(|c| scorer.pooled(c).is_some()));
    assert!(offspring.iter().all(|c| scorer.pooled(c).is_some()));
    // It never shrinks: a smaller population leaves it as it is.
    scorer.keep_alive(population[..10].iter());
    assert_eq!(scorer.capacity, POOL_PER_MEMBER * population.len());
}

#[test]
fn offspring_scored_without_meshes_get_them_when_they_join_the_population() {
    // OAX crossovers of two pooled parents on a 33×29 grid, as NSGA-II runs them: the rows
    // are scored without meshes, each chosen child is mutated (0–3 flips) and scored, an
    // unchanged one promoted. Every score must be the fresh one's bits, mutants must be
    // scored without a mesh (deferred), and those declared alive afterwards must be pooled
    // with the mesh of their genes, while the others are not.
    use crate::evolution::oax;
    let (w, h) = (33, 29);
    let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(4);
    let z = (0..w * h).map(|_| rng.random_range(0..9) as f64).collect();
    let hf = Arc::new(Heightfield::new(w, h, z).unwrap());
    let n = hf.len();
    let corners = hf.corners();
    let random = |rng: &mut rand_pcg::Pcg64Mcg, density: f64| {
        let kept: Vec<u32> = (0..n as u32)
            .filter(|_| rng.random::<f64>() < density)
            .chain(corners)
            .collect();
        Chromosome::from_indices(n, &kept)
    };
    let mut scorer = Scorer::new(hf.clone());
    let mut population = vec![random(&mut rng, 0.3), random(&mut rng, 0.12)];
    let (mut deferred_mutants, mut deferred_rows) = (0, 0);
    for round in 0..12 {
        let scored: Vec<Score> = population.iter().map(|c| scorer.score(c)).collect();
        scorer.keep_alive(population.iter());
        let blocks = oax::spatial_blocks(w, h, 7, &mut rng);
        let record = oax::crossover(
            (&population[0], scored[0]),
            (&population[1], scored[1]),
            w,
            blocks,
            0.5,
            |c, made| {
                let o = scorer.score_crossed(c, made);
                assert_eq!(bits(o), fresh(&hf, c), "round {round}: row");
                o
            },
            |o| o.e_sum + o.t as f64,
        );
        let mut offspring = Vec::new();
        for (k, &i) in record.chosen.iter().enumerate() {
            let mut c = record.child(i).genes.clone();
            // The first mutated by 1–3 flips, the second unchanged every other round.
            let flips = if k == 0 { 1 + round % 3 } else { round % 2 };
            for _ in 0..flips {
                let g = rng.random_range(0..n);
                if !corners.contains(&(g as u32)) {
                    c.flip(g);
                }
            }
            if c == record.child(i).genes {
                scorer.promote(&c);
            } else {
                let o = scorer.score(&c);
                assert_eq!(bits(o), fresh(&hf, &c), "round {round}: mutant");
            }
            offspring.push(c);
        }
        let deferred: Vec<Chromosome> = scorer.deferred.iter().map(|d| d.genes.clone()).collect();
        for (k, c) in offspring.iter().enumerate() {
            if deferred.contains(c) {
                match *c == record.child(record.chosen[k]).genes {
                    true => deferred_rows += 1,
                    false => deferred_mutants += 1,
                }
            }
        }
        // The first offspring joins the population (with the better parent); the second
        // dies.
        let next = [population[0].clone(), offspring[0].clone()];
        scorer.keep_alive(next.iter());
        assert!(scorer.deferred.is_empty());
        let i = scorer
            .pooled(&offspring[0])
            .expect("a new member is pooled");
        assert_eq!(
            scorer.pool[i].state.score().map(bits),
            Some(fresh(&hf, &offspring[0])),
            "round {round}: the member's mesh"
        );
        if offspring[1] != offspring[0] && deferred.contains(&offspring[1]) {
            assert!(scorer.pooled(&offspring[1]).is_none(), "round {round}");
        }
        // New parents for the next round (rounds of one lineage converge, and their
        // children come near pooled chromosomes, which are edited instead).
        population = vec![random(&mut rng, 0.3), random(&mut rng, 0.12)];
    }
    assert!(
        deferred_mutants >= 6 && deferred_rows >= 2,
        "{deferred_mutants} mutants and {deferred_rows} unchanged rows deferred"
    );
}

#[test]
fn a_chromosome_without_its_corners_scores_like_one_with_them() {
    // The evaluator forces the corners in, so a chromosome missing one (built by hand) must
    // score exactly as with it, fresh or edited from a pooled mesh that has it.
    let hf = bumpy(4);
    let mut scorer = Scorer::new(hf.clone());
    let with = Chromosome::from_indices(63, &[0, 8, 30, 54, 62]);
    let without = Chromosome::from_indices(63, &[0, 30, 31, 54, 62]);
    let a = scorer.score(&with);
    let b = scorer.score(&without);
    assert_eq!(bits(a), fresh(&hf, &with));
    assert_eq!(bits(b), fresh(&hf, &without));
}
