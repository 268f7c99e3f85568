//! One mating, shared by NSGA-II and the weighted-sum GA: crossover (with the crossover
//! probability) of two parents into two children, bit-flip mutation of both, and evaluation of
//! whatever changed.

use super::chromosome::Chromosome;
use super::oax::{self, OaxRecord};
use super::objectives::{Objectives, Scalarisation, Scorer};
use super::operators::{self, CrossoverKind};
use super::params::GaParams;
use rand::RngExt;
use rand_pcg::Pcg64Mcg;

/// What a mating needs besides the parents.
pub(crate) struct Mating<'a> {
    pub params: &'a GaParams,
    /// Bit-flip probability per free gene.
    pub mutation: f64,
    /// The scalar fitness OAX's factor analysis minimises.
    pub scalar: Scalarisation,
    pub rng: &'a mut Pcg64Mcg,
    pub scorer: &'a mut Scorer,
}

impl Mating<'_> {
    /// Makes two evaluated children of `a` and `b`. `seen` is called on every chromosome
    /// evaluated (OAX rows included), in order; an OAX crossover's record goes into `record`.
    pub fn children(
        self,
        a: (&Chromosome, Objectives),
        b: (&Chromosome, Objectives),
        seen: &mut impl FnMut(&Chromosome, &Objectives),
        record: &mut Option<OaxRecord>,
    ) -> [(Chromosome, Objectives); 2] {
        let Mating {
            params,
            mutation,
            scalar,
            rng,
            scorer,
        } = self;
        let hf = scorer.heightfield().clone();
        let mut score = |c: &Chromosome| {
            let o = scorer.score(c);
            seen(c, &o);
            o
        };
        // Children with objectives when they are already known.
        let crossed: [(Chromosome, Option<Objectives>); 2] = if rng.random::<f64>()
            < params.crossover_probability
        {
            match params.crossover {
                CrossoverKind::Oax => {
                    let blocks = oax::spatial_blocks(hf.width(), hf.height(), params.factors, rng);
                    let r = oax::crossover(a, b, hf.width(), blocks, scalar.w, &mut score, |o| {
                        scalar.value(o)
                    });
                    let pick = |i: usize| {
                        let c = r.child(i);
                        (c.genes.clone(), Some(c.objectives))
                    };
                    let children = [pick(r.chosen[0]), pick(r.chosen[1])];
                    *record = Some(r);
                    children
                }
                CrossoverKind::Uniform => operators::uniform(a.0, b.0, rng).map(|c| (c, None)),
                CrossoverKind::TwoPoint => operators::two_point(a.0, b.0, rng).map(|c| (c, None)),
            }
        } else {
            [(a.0.clone(), Some(a.1)), (b.0.clone(), Some(b.1))]
        };
        let corners = hf.corners();
        crossed.map(|(mut genes, known)| {
            let flipped = operators::mutate(&mut genes, &corners, mutation, rng);
            let objectives = match known {
                Some(o) if flipped == 0 => o,
                _ => score(&genes),
            };
            (genes, objectives)
        })
    }
}
