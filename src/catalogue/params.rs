//! What a caller may set on a method of the catalogue: the parameters ([`Param`], filled in
//! [`Params`]), the kind of budget a method runs on, and the memetic method's components that
//! an ablation switches off.

use crate::baselines::InsertionRule;
use crate::evolution::CrossoverKind;
use crate::measure::ErrorMeasure;

/// A parameter a method may read. Each is a field of [`Params`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Param {
    /// [`Params::population`].
    Population,
    /// [`Params::generations`].
    Generations,
    /// [`Params::crossover_probability`].
    CrossoverProbability,
    /// [`Params::mutation_probability`].
    MutationProbability,
    /// [`Params::crossover`].
    Crossover,
    /// [`Params::factors`].
    Factors,
    /// [`Params::max_evaluations`].
    MaxEvaluations,
    /// [`Params::greedy_seed_fraction`].
    GreedySeedFraction,
    /// [`Params::rule`].
    Rule,
    /// [`Params::max_error_fraction`].
    MaxErrorFraction,
    /// [`Params::max_vertical_error`].
    MaxVerticalError,
    /// [`Params::without`].
    Without,
}

impl Param {
    /// Which methods a parameter belongs to, in the words of a refusal ("it belongs to …").
    pub fn owner(self) -> &'static str {
        match self {
            Param::Rule | Param::MaxErrorFraction | Param::MaxVerticalError => "greedy insertion",
            Param::Without => "the memetic method",
            _ => "the evolutionary methods",
        }
    }
}

/// A method's parameters as a caller sets them: `None` leaves the method's own default.
/// A method refuses nothing here by itself; callers check [`Algorithm::reads`]
/// (crate::catalogue::Algorithm::reads) before they set a field.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Params {
    /// Population size.
    pub population: Option<usize>,
    /// Generations (per weight, for the weighted-sum GA).
    pub generations: Option<usize>,
    /// Probability that a mating uses crossover.
    pub crossover_probability: Option<f64>,
    /// Bit-flip probability per free gene (`None`: 1/L).
    pub mutation_probability: Option<f64>,
    /// The GAs' crossover operator.
    pub crossover: Option<CrossoverKind>,
    /// Number of OAX factors.
    pub factors: Option<usize>,
    /// Stop after about this many evaluations (for greedy insertion: insertions).
    pub max_evaluations: Option<u64>,
    /// NSGA-II: the fraction of the initial population seeded from greedy insertion.
    pub greedy_seed_fraction: Option<f64>,
    /// Greedy insertion: which point to insert next.
    pub rule: Option<InsertionRule>,
    /// Greedy insertion: stop once E_max ≤ this fraction of the z range.
    pub max_error_fraction: Option<f64>,
    /// Greedy insertion: stop once E_max ≤ this height, in the surface's units (hmm's `-e`).
    pub max_vertical_error: Option<f64>,
    /// Memetic: a component switched off (an ablation).
    pub without: Option<Component>,
    /// The error the front minimises beside T (`sum` by default); a method refuses the
    /// measures its [`Spec::measures`](crate::catalogue::Spec::measures) does not list.
    pub error: ErrorMeasure,
}

/// How a method's run is bounded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BudgetKind {
    /// It runs to an evaluation budget (its own default, or [`Params::max_evaluations`]).
    Evaluations,
    /// A generational GA: population × generations, or an evaluation cap.
    Generations,
    /// It stops by its own rule (a list of reductions, or every point inserted).
    OwnRule,
}

impl BudgetKind {
    /// The kind's name as `paretomesh algorithms` lists it.
    pub fn name(self) -> &'static str {
        match self {
            BudgetKind::Evaluations => "evaluations",
            BudgetKind::Generations => "generations",
            BudgetKind::OwnRule => "own-rule",
        }
    }
}

/// A component of the memetic method that an ablation switches off.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Component {
    /// Greedy seeding (random kept sets at log-spaced densities instead).
    GreedySeeding,
    /// The error-guided mutation (a random bit flip instead).
    GuidedMutation,
    /// Mating among neighbours in T (any member instead).
    NeighbourMating,
    /// The local search.
    LocalSearch,
}

/// A variant of a method with one component switched off, as the experiment runs it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ablation {
    /// The component switched off.
    pub without: Component,
    /// The variant's name (results.json and the command line).
    pub name: &'static str,
    /// The name the tables and the figure show.
    pub label: &'static str,
    /// Its colour in the experiment's fronts figure.
    pub colour: &'static str,
    /// What the variant removes, in the report's words.
    pub removes: &'static str,
}
