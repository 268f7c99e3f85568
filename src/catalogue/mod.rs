//! The catalogue of methods: every algorithm ParetoMesh runs, with its names, whether it is
//! stochastic, its kind of budget, the parameters it reads, how it is built and how a tile of
//! a tiled run shares its budget. The CLI, the experiment, compare mode, the browser app,
//! tiling and the Python bindings all take their methods from here.
//!
//! Every method is one entry of the `methods!` list below: its [`Spec`], its params type, how
//! the caller's [`Params`] configure it, how it is built, and its [`Running`] impl. From that
//! list (a new method goes at its end) the macro (`methods.rs`) makes [`Algorithm`] (and
//! [`Algorithm::ALL`]), [`Config`] and every match over them, so adding a method is its own
//! module (an [`Optimizer`]) plus one entry here. A run's method travels between modules,
//! threads and processes as a [`Config`], never as a name and JSON.

#[macro_use]
mod methods;
mod params;

pub use params::{Ablation, BudgetKind, Component, Param, Params};

use crate::baselines::{
    DecimationParams, EdgeDecimation, GreedyInsertion, GreedyParams, GreedyStop, InsertionRule,
};
use crate::evolution::memetic::search_budget;
use crate::evolution::oax::OaxRecord;
use crate::evolution::trace::GenerationTrace;
use crate::evolution::{GaParams, Memetic, MemeticParams, Nsga2, WeightedSum, WeightedSumParams};
use crate::heightfield::Heightfield;
use crate::measure::ErrorMeasure;
use crate::optimizer::Optimizer;
use methods::laid;
use std::sync::Arc;

/// The fixed facts about one method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spec {
    /// The command-line name, also front.json's `algorithm`.
    pub name: &'static str,
    /// The name tables and figures show.
    pub label: &'static str,
    /// A short name for legends.
    pub short: &'static str,
    /// The name inside a sentence ("re-runs greedy insertion").
    pub phrase: &'static str,
    /// Whether it draws random numbers (runs with different seeds differ).
    pub stochastic: bool,
    /// How its run is bounded.
    pub budget: BudgetKind,
    /// The parameters it reads; it refuses the others.
    pub reads: &'static [Param],
    /// Why it does not read a parameter, where that is more than the parameter's
    /// `owner`.
    pub refusals: &'static [(Param, &'static str)],
    /// Its colour in the experiment's fronts figure (the colour-blind-safe Okabe–Ito hues).
    pub colour: &'static str,
    /// Rough cost of one run, larger first in the experiment's scheduler.
    pub cost: u8,
    /// Its variants with one component switched off, as the experiment runs them.
    pub ablations: &'static [Ablation],
    /// The error measures whose (error, T) front it makes, `sum` first.
    pub measures: &'static [ErrorMeasure],
    /// How it serves its measures, or why it takes only `sum`.
    pub measure_note: &'static str,
}

const ALL_MEASURES: &[ErrorMeasure] = &ErrorMeasure::ALL;

const SUM_ONLY: &[ErrorMeasure] = &[ErrorMeasure::Sum];

const GA_PARAMS: &[Param] = &[
    Param::Population,
    Param::Generations,
    Param::CrossoverProbability,
    Param::MutationProbability,
    Param::Crossover,
    Param::Factors,
    Param::MaxEvaluations,
    Param::GreedySeedFraction,
];

const MEMETIC_OPERATORS: &str = "memetic mutates with its error-guided operators and crosses parents of similar T along a straight cut";

const MEMETIC_ABLATIONS: &[Ablation] = &[
    Ablation {
        without: Component::GreedySeeding,
        name: "memetic-no-seed",
        label: "Memetic, no greedy seeding",
        colour: "#E69F00",
        removes: "greedy seeding: the initial population is random kept sets at log-spaced densities instead of greedy-insertion snapshots, and the greedy fronts do not start the archive",
    },
    Ablation {
        without: Component::GuidedMutation,
        name: "memetic-random-mutation",
        label: "Memetic, random mutation",
        colour: "#56B4E9",
        removes: "error-guided mutation: a child flips one random grid point in or out instead of an error-guided insertion, removal or vertex move",
    },
    Ablation {
        without: Component::NeighbourMating,
        name: "memetic-no-neighbour-mating",
        label: "Memetic, random mates",
        colour: "#999999",
        removes: "mating among neighbours: a crossover mate is any other member, whatever its T, instead of one of the 4 nearest in T",
    },
    Ablation {
        without: Component::LocalSearch,
        name: "memetic-no-local-search",
        label: "Memetic, no local search",
        colour: "#F0E442",
        removes: "local search: no fixed-T swap moves on archive members; the budget goes to offspring only",
    },
];

methods! {
    /// NSGA-II with orthogonal-array crossover.
    Nsga2 {
        spec: Spec {
            name: "nsga2",
            label: "NSGA-II",
            short: "NSGA-II",
            phrase: "NSGA-II",
            stochastic: true,
            budget: BudgetKind::Generations,
            reads: GA_PARAMS,
            refusals: &[],
            colour: "#D55E00",
            cost: 2,
            ablations: &[],
            measures: SUM_ONLY,
            measure_note: "NSGA-II is the paper's method, on (E_sum, T), and stays bit for bit the paper's: use --algo memetic, greedy or decimation for rms or max",
        },
        params: GaParams,
        configure: |given| Ok(ga_params(given)),
        build: |p, hf, seed| Ok(Built {
            generations: p.generations as u64,
            budget: p.max_evaluations,
            optimizer: Box::new(Nsga2::new(hf, p, seed).map_err(|e| e.to_string())?),
        }),
        running: Nsga2 {
            fn population_points(&self) -> Vec<(f64, f64, usize)> {
                self.population()
                    .iter()
                    .map(|i| (i.objectives.t as f64, i.objectives.e_sum, i.rank))
                    .collect()
            }
            fn generation_trace(&self) -> Option<&GenerationTrace> {
                self.last_generation()
            }
            fn last_crossover(&self) -> Option<&OaxRecord> {
                Nsga2::last_crossover(self)
            }
        },
    },
    /// Weighted-sum GA, one run per weight 0, 0.1, …, 1.
    Weighted {
        spec: Spec {
            name: "weighted",
            label: "Weighted-sum GA",
            short: "Weighted",
            phrase: "weighted-sum GA",
            stochastic: true,
            budget: BudgetKind::Generations,
            reads: GA_PARAMS,
            refusals: &[],
            colour: "#0072B2",
            cost: 3,
            ablations: &[],
            measures: SUM_ONLY,
            measure_note: "the weighted-sum GA is the paper's baseline, a weighted sum of E_sum and T: use --algo memetic, greedy or decimation for rms or max",
        },
        params: WeightedSumParams,
        configure: |given| Ok(WeightedSumParams {
            ga: ga_params(given),
            ..WeightedSumParams::default()
        }),
        build: |p, hf, seed| Ok(Built {
            generations: (p.ga.generations * p.weights.len()) as u64,
            budget: p.ga.max_evaluations,
            optimizer: Box::new(WeightedSum::new(hf, p, seed).map_err(|e| e.to_string())?),
        }),
        runs: WeightedSumParams::default().weights.len(),
        running: WeightedSum {},
    },
    /// Edge decimation from the full grid to 5 %, 10 %, …, 50 % fewer triangles.
    Decimation {
        spec: Spec {
            name: "decimation",
            label: "Decimation",
            short: "Decimation",
            phrase: "edge decimation",
            stochastic: false,
            budget: BudgetKind::OwnRule,
            reads: &[],
            refusals: &[(
                Param::MaxEvaluations,
                "edge decimation runs to its last reduction",
            )],
            colour: "#009E73",
            cost: 0,
            ablations: &[],
            measures: ALL_MEASURES,
            measure_note: "its collapses follow E_sum; its recorded meshes are filtered by the chosen measure",
        },
        params: DecimationParams,
        configure: |given| Ok(DecimationParams {
            error: given.error,
            ..DecimationParams::default()
        }),
        build: |p, hf, _seed| Ok(Built {
            generations: p.reductions.len() as u64,
            budget: None,
            optimizer: Box::new(EdgeDecimation::new(hf, p).map_err(|e| e.to_string())?),
        }),
        running: EdgeDecimation {},
    },
    /// Greedy insertion (Garland & Heckbert 1995) from the corners; one run records a front.
    Greedy {
        spec: Spec {
            name: "greedy",
            label: "Greedy insertion",
            short: "Greedy",
            phrase: "greedy insertion",
            stochastic: false,
            budget: BudgetKind::OwnRule,
            reads: &[
                Param::Rule,
                Param::MaxErrorFraction,
                Param::MaxVerticalError,
                Param::MaxEvaluations,
            ],
            refusals: &[],
            colour: "#CC79A7",
            cost: 1,
            ablations: &[],
            measures: ALL_MEASURES,
            measure_note: "it inserts the point of largest error, the worst in every measure; its recorded meshes are filtered by the chosen measure",
        },
        params: GreedyParams,
        configure: |given| greedy_params(given),
        build: |p, hf, _seed| Ok(Built {
            generations: p.records as u64,
            budget: match p.stop {
                GreedyStop::Points(n) => Some(n.saturating_sub(4) as u64),
                _ => None,
            },
            optimizer: Box::new(GreedyInsertion::new(hf, p).map_err(|e| e.to_string())?),
        }),
        running: GreedyInsertion {},
    },
    /// Memetic NSGA-II: greedy and decimation seeding, error-guided operators and local search
    /// (default).
    Memetic {
        spec: Spec {
            name: "memetic",
            label: "Memetic",
            short: "Memetic",
            phrase: "memetic NSGA-II",
            stochastic: true,
            budget: BudgetKind::Evaluations,
            reads: &[
                Param::Population,
                Param::CrossoverProbability,
                Param::MaxEvaluations,
                Param::Without,
            ],
            refusals: &[
                (
                    Param::Generations,
                    "memetic runs to its evaluation budget, not for a number of generations: use --evals",
                ),
                (Param::MutationProbability, MEMETIC_OPERATORS),
                (Param::Crossover, MEMETIC_OPERATORS),
                (Param::Factors, MEMETIC_OPERATORS),
            ],
            colour: "#000000",
            cost: 2,
            ablations: MEMETIC_ABLATIONS,
            measures: ALL_MEASURES,
            measure_note: "its selection, archive, decimation costs and local search compare in the chosen measure",
        },
        params: MemeticParams,
        configure: |given| {
            let d = MemeticParams::default();
            let without = given.without;
            Ok(MemeticParams {
                population: given.population.unwrap_or(d.population),
                crossover_probability: given
                    .crossover_probability
                    .unwrap_or(d.crossover_probability),
                max_evaluations: given.max_evaluations,
                greedy_seeding: without != Some(Component::GreedySeeding),
                guided_mutation: without != Some(Component::GuidedMutation),
                neighbour_mating: without != Some(Component::NeighbourMating),
                local_search: without != Some(Component::LocalSearch),
                error: given.error,
                ..d
            })
        },
        build: |p, hf, seed| {
            let optimizer = Memetic::new(hf, p, seed).map_err(|e| e.to_string())?;
            Ok(Built {
                // Generations depend on the budget; progress is shown against it.
                generations: 0,
                budget: Some(optimizer.budget()),
                optimizer: Box::new(optimizer),
            })
        },
        // Unless given a budget (`max_evaluations` or `search_evaluations`), a tile searches
        // for the whole grid's search budget ([`search_budget`] of its points) shared evenly
        // among the tiles, on top of its own seeding: the sweeps and the decimation, which give
        // a tile's front nearly all its quality at the triangle counts the whole-grid front
        // combines tiles at, grow with the tile, while the search, whose gains are mostly on a
        // front's sparsest meshes, then costs as much in a tiled run as in an untiled one. A
        // one-tile plan gets the untiled budget.
        tile_share: |p, points, tiles| {
            if p.max_evaluations.is_some() || p.search_evaluations.is_some() {
                p
            } else {
                MemeticParams {
                    search_evaluations: Some(search_budget(points).div_ceil(tiles.max(1) as u64)),
                    ..p
                }
            }
        },
        running: Memetic {
            fn population_points(&self) -> Vec<(f64, f64, usize)> {
                self.population()
                    .iter()
                    .map(|m| (m.score.t as f64, m.score.e_sum, m.rank))
                    .collect()
            }
        },
    },
}

impl Algorithm {
    /// The method run when none is named: the project's best.
    pub(crate) const DEFAULT: Algorithm = Algorithm::Memetic;

    /// The command-line name, also front.json's `algorithm`.
    pub fn name(self) -> &'static str {
        self.spec().name
    }

    /// The name tables and figures show.
    pub fn label(self) -> &'static str {
        self.spec().label
    }

    /// The method named `name`, if any.
    pub fn from_name(name: &str) -> Option<Algorithm> {
        Self::ALL.into_iter().find(|a| a.name() == name)
    }

    /// Does the method read `param`?
    pub fn reads(self, param: Param) -> bool {
        self.spec().reads.contains(&param)
    }

    /// Why the method refuses `param`, or `None` when it reads it.
    pub fn refusal(self, param: Param) -> Option<String> {
        if self.reads(param) {
            return None;
        }
        let spec = self.spec();
        Some(spec.refusals.iter().find(|(p, _)| *p == param).map_or_else(
            || format!("it belongs to {}", param.owner()),
            |(_, why)| why.to_string(),
        ))
    }

    /// Does the method make fronts in `measure`?
    pub(crate) fn supports(self, measure: ErrorMeasure) -> bool {
        self.spec().measures.contains(&measure)
    }

    /// Why the method refuses `measure`, naming both, or `None` when it supports it.
    pub(crate) fn measure_refusal(self, measure: ErrorMeasure) -> Option<String> {
        (!self.supports(measure)).then(|| {
            format!(
                "--algo {} does not take --error {}: {}",
                self.name(),
                measure.name(),
                self.spec().measure_note
            )
        })
    }

    /// The method's parameters with `params` filled in over its defaults. Errors: a parameter
    /// the method does not read is set, the method does not support the error measure, or two
    /// set parameters contradict each other.
    pub fn configure(self, params: &Params) -> Result<Config, String> {
        if let Some(why) = self.measure_refusal(params.error) {
            return Err(why);
        }
        for (param, set) in [
            (Param::Population, params.population.is_some()),
            (Param::Generations, params.generations.is_some()),
            (
                Param::CrossoverProbability,
                params.crossover_probability.is_some(),
            ),
            (
                Param::MutationProbability,
                params.mutation_probability.is_some(),
            ),
            (Param::Crossover, params.crossover.is_some()),
            (Param::Factors, params.factors.is_some()),
            (Param::MaxEvaluations, params.max_evaluations.is_some()),
            (
                Param::GreedySeedFraction,
                params.greedy_seed_fraction.is_some(),
            ),
            (Param::Rule, params.rule.is_some()),
            (Param::MaxErrorFraction, params.max_error_fraction.is_some()),
            (Param::MaxVerticalError, params.max_vertical_error.is_some()),
            (Param::Without, params.without.is_some()),
        ] {
            if let (true, Some(why)) = (set, self.refusal(param)) {
                return Err(format!("{} does not read {param:?}: {why}", self.name()));
            }
        }
        self.configure_checked(params)
    }

    /// Builds the method on `hf` with `params` over its defaults; `seed` drives a stochastic
    /// method and is ignored by the others.
    pub(crate) fn build(
        self,
        hf: Arc<Heightfield>,
        params: &Params,
        seed: u64,
    ) -> Result<Built, String> {
        self.configure(params)?.build(hf, seed)
    }
}

/// The GA parameters `params` set, over the paper's defaults.
fn ga_params(params: &Params) -> GaParams {
    let d = GaParams::default();
    GaParams {
        population: params.population.unwrap_or(d.population),
        generations: params.generations.unwrap_or(d.generations),
        crossover_probability: params
            .crossover_probability
            .unwrap_or(d.crossover_probability),
        mutation_probability: params.mutation_probability.or(d.mutation_probability),
        crossover: params.crossover.unwrap_or(d.crossover),
        factors: params.factors.unwrap_or(d.factors),
        max_evaluations: params.max_evaluations,
        greedy_seed_fraction: params
            .greedy_seed_fraction
            .unwrap_or(d.greedy_seed_fraction),
    }
}

/// Greedy insertion's parameters from `params`: its rule and the one stop it is given.
fn greedy_params(params: &Params) -> Result<GreedyParams, String> {
    let stops = [
        params.max_error_fraction.is_some(),
        params.max_vertical_error.is_some(),
        params.max_evaluations.is_some(),
    ];
    if stops.iter().filter(|&&given| given).count() > 1 {
        return Err(
            "greedy insertion stops on one of --max-error-fraction, --max-vertical-error or --evals, not several"
                .to_string(),
        );
    }
    let stop = match (
        params.max_error_fraction,
        params.max_vertical_error,
        params.max_evaluations,
    ) {
        (Some(f), _, _) => GreedyStop::MaxErrorFraction(f),
        (_, Some(x), _) => GreedyStop::MaxError(x),
        // One evaluation is one insertion, after the four corners.
        (_, _, Some(n)) => {
            GreedyStop::Points(4usize.saturating_add(usize::try_from(n).unwrap_or(usize::MAX)))
        }
        _ => GreedyStop::AllPoints,
    };
    // A bound on E_max is what the user asked for: the fewest triangles within it, in a front
    // of E_max (in E_sum, the bound's mesh can be dominated by the corners alone, and left
    // out), unless another measure is named.
    let bounded = matches!(
        stop,
        GreedyStop::MaxError(_) | GreedyStop::MaxErrorFraction(_)
    );
    Ok(GreedyParams {
        rule: params.rule.unwrap_or(InsertionRule::MaxError),
        stop,
        decimate: bounded,
        error: match params.error {
            ErrorMeasure::Sum if bounded => ErrorMeasure::Max,
            measure => measure,
        },
        ..GreedyParams::default()
    })
}

impl serde::Serialize for Algorithm {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> serde::Deserialize<'de> for Algorithm {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Algorithm, D::Error> {
        let name = String::deserialize(d)?;
        Algorithm::from_name(&name)
            .ok_or_else(|| serde::de::Error::custom(format!("unknown algorithm {name:?}")))
    }
}

/// [`Config`] as it travels: the method's name and its parameters as front.json records them.
#[derive(serde::Serialize, serde::Deserialize)]
struct ConfigWire {
    algorithm: Algorithm,
    params: serde_json::Value,
}

impl serde::Serialize for Config {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        ConfigWire {
            algorithm: self.algorithm(),
            params: self.json(),
        }
        .serialize(s)
    }
}

impl<'de> serde::Deserialize<'de> for Config {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Config, D::Error> {
        let wire = ConfigWire::deserialize(d)?;
        Config::from_json(wire.algorithm, &wire.params).map_err(serde::de::Error::custom)
    }
}

/// A ready-to-run method with what a progress display needs.
pub struct Built {
    /// The optimizer.
    pub optimizer: Box<dyn Running>,
    /// How many generations it will run, or 0 when that depends on the run.
    pub generations: u64,
    /// The evaluations it stops at, when known.
    pub budget: Option<u64>,
}

/// A running method: an [`Optimizer`] plus what the app's views show beyond its front.
pub trait Running: Optimizer + Send {
    /// The current population as (T, E, non-domination rank); empty for methods without one.
    fn population_points(&self) -> Vec<(f64, f64, usize)> {
        Vec::new()
    }
    /// What the last completed generation did, phase by phase (NSGA-II only).
    fn generation_trace(&self) -> Option<&GenerationTrace> {
        None
    }
    /// The last completed orthogonal-array crossover (NSGA-II only).
    fn last_crossover(&self) -> Option<&OaxRecord> {
        None
    }
    /// The run as `Any`, so that a caller can reach a run type of its own (the app's Web Worker
    /// pool run) behind the same trait; `None` for the catalogue's methods.
    fn as_any_mut(&mut self) -> Option<&mut dyn std::any::Any> {
        None
    }
    /// [`Running::as_any_mut`], to read.
    fn as_any(&self) -> Option<&dyn std::any::Any> {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_distinct_and_round_trip() {
        for (i, a) in Algorithm::ALL.iter().enumerate() {
            assert_eq!(Algorithm::from_name(a.name()), Some(*a));
            for b in &Algorithm::ALL[..i] {
                let (sa, sb) = (a.spec(), b.spec());
                assert!(sa.name != sb.name && sa.label != sb.label && sa.colour != sb.colour);
            }
        }
        assert_eq!(Algorithm::from_name("nsga3"), None);
    }

    /// `ALL` is made by the same macro as the enum; clap's derive lists the variants on its
    /// own, so a variant missing from `ALL` (or out of the enum's order) fails here.
    #[cfg(not(target_arch = "wasm32"))]
    #[test]
    fn all_lists_every_variant_in_the_enums_order() {
        use clap::ValueEnum;
        assert_eq!(Algorithm::value_variants(), &Algorithm::ALL[..]);
        for (i, a) in Algorithm::ALL.into_iter().enumerate() {
            assert_eq!(a as usize, i, "{a:?}");
        }
        // The first methods' names and order are pinned by front.json files, share links and
        // the menu; a new method goes after them.
        let names: Vec<&str> = Algorithm::ALL.map(|a| a.name()).to_vec();
        assert_eq!(
            names[..5],
            ["nsga2", "weighted", "decimation", "greedy", "memetic"],
            "names and order are the command line's, front.json's and the menu's"
        );
    }

    #[test]
    fn a_config_travels_whole_and_reads_back() {
        for a in Algorithm::ALL {
            let config = a.configure(&Params::default()).unwrap();
            assert_eq!(config.algorithm(), a);
            let json = serde_json::to_value(&config).unwrap();
            assert_eq!(json["algorithm"], a.name());
            assert_eq!(json["params"], config.json());
            assert_eq!(serde_json::from_value::<Config>(json).unwrap(), config);
            assert_eq!(
                Config::from_json(a, &serde_json::Value::Null),
                Ok(a.defaults())
            );
        }
        // Params are read as front.json's: a subset over the defaults; a bad field is named.
        let json = serde_json::json!({"algorithm": "nsga2", "params": {"population": 6}});
        let Config::Nsga2(p) = serde_json::from_value(json).unwrap() else {
            panic!("nsga2 reads as nsga2");
        };
        assert_eq!(p.population, 6);
        let bad = serde_json::json!({"algorithm": "nsga2", "params": {"population": "many"}});
        let err = serde_json::from_value::<Config>(bad)
            .unwrap_err()
            .to_string();
        assert!(err.contains("invalid type"), "{err}");
        let unknown = serde_json::json!({"algorithm": "annealing", "params": null});
        let err = serde_json::from_value::<Config>(unknown)
            .unwrap_err()
            .to_string();
        assert!(err.contains("unknown algorithm \"annealing\""), "{err}");
    }

    #[test]
    fn memetic_tiles_share_the_whole_grids_search_budget() {
        use crate::evolution::memetic::search_budget;
        let share = |c: Config| match c {
            Config::Memetic(p) => p.search_evaluations,
            other => panic!("{other:?}"),
        };
        let memetic = Algorithm::Memetic.defaults();
        let points = 2048 * 2048;
        assert_eq!(
            share(memetic.clone().tile_share(points, 4)),
            Some(search_budget(points).div_ceil(4))
        );
        // Sharing twice changes nothing; one tile gets the untiled search.
        let once = memetic.clone().tile_share(points, 4);
        assert_eq!(once.clone().tile_share(points, 4), once);
        assert_eq!(
            share(memetic.tile_share(1000, 1)),
            Some(search_budget(1000))
        );
        // A run given a budget keeps it.
        let evals = Params {
            max_evaluations: Some(500),
            ..Params::default()
        };
        let given = Algorithm::Memetic.configure(&evals).unwrap();
        assert_eq!(given.clone().tile_share(points, 4), given);
        let searched = Config::Memetic(MemeticParams {
            search_evaluations: Some(7),
            ..MemeticParams::default()
        });
        assert_eq!(searched.clone().tile_share(points, 4), searched);
        // Other methods run as given on every tile.
        for a in Algorithm::ALL
            .into_iter()
            .filter(|&a| a != Algorithm::Memetic)
        {
            assert_eq!(a.defaults().tile_share(points, 4), a.defaults());
        }
    }

    #[cfg(not(target_arch = "wasm32"))]
    #[test]
    fn command_line_names_are_the_catalogue_names() {
        use clap::ValueEnum;
        for a in Algorithm::ALL {
            assert_eq!(a.to_possible_value().unwrap().get_name(), a.name());
        }
    }

    #[test]
    fn a_parameter_the_method_does_not_read_is_refused_with_its_reason() {
        let evals = Params {
            max_evaluations: Some(10),
            ..Params::default()
        };
        let err = Algorithm::Decimation.configure(&evals).unwrap_err();
        assert!(err.contains("runs to its last reduction"), "{err}");
        assert!(Algorithm::Greedy.configure(&evals).is_ok());
        let gens = Params {
            generations: Some(3),
            ..Params::default()
        };
        assert!(
            Algorithm::Memetic
                .refusal(Param::Generations)
                .unwrap()
                .contains("use --evals")
        );
        let err = Algorithm::Memetic.configure(&gens).unwrap_err();
        assert!(
            err.starts_with("memetic does not read Generations: ") && err.contains("use --evals"),
            "{err}"
        );
        assert_eq!(
            Algorithm::Greedy.refusal(Param::Population).as_deref(),
            Some("it belongs to the evolutionary methods")
        );
    }

    #[test]
    fn a_measure_the_method_does_not_support_is_refused_naming_both() {
        for a in Algorithm::ALL {
            assert!(a.supports(ErrorMeasure::Sum), "{}", a.name());
            for m in ErrorMeasure::ALL {
                let p = Params {
                    error: m,
                    ..Params::default()
                };
                match a.configure(&p) {
                    Ok(c) => {
                        assert!(a.supports(m));
                        // The measure is recorded in the parameters only when not sum.
                        let recorded = c.json().get("error").cloned();
                        let expected = (m != ErrorMeasure::Sum).then(|| m.name().into());
                        assert_eq!(recorded, expected, "{} {m}", a.name());
                        assert_eq!(Config::from_json(a, &c.json()).unwrap(), c);
                    }
                    Err(e) => {
                        assert!(!a.supports(m));
                        let both = format!("--algo {} does not take --error {m}", a.name());
                        assert!(e.starts_with(&both), "{e}");
                    }
                }
            }
        }
        assert!(!Algorithm::Nsga2.supports(ErrorMeasure::Max));
        assert!(!Algorithm::Weighted.supports(ErrorMeasure::Rms));
        assert!(Algorithm::Memetic.supports(ErrorMeasure::Max));
    }

    #[test]
    fn an_ablation_switches_off_its_component_only() {
        let p = Params {
            without: Some(Component::LocalSearch),
            ..Params::default()
        };
        let Config::Memetic(m) = Algorithm::Memetic.configure(&p).unwrap() else {
            panic!("memetic configures memetic parameters");
        };
        assert!(!m.local_search && m.greedy_seeding && m.guided_mutation && m.neighbour_mating);
        assert_eq!(
            Algorithm::Memetic
                .configure(&Params::default())
                .unwrap()
                .json(),
            serde_json::to_value(MemeticParams::default()).unwrap()
        );
    }
}
