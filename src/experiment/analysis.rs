//! Every number of the report, computed from [`Results`] alone (so anyone holding results.json
//! can recompute the tables).
//!
//! Per dataset, with objectives normalised by the dataset's [`Scales`](super::Scales), for each
//! *contender* — a method run here, then each outside front (one run; its std and rank-sum
//! tests are `n/a` like a deterministic method's):
//! - each method's **merged front**: the non-dominated merge of all its runs' fronts, duplicates
//!   (equal (E, T)) kept once;
//! - the **reference front**: the non-dominated merge of every method's merged front;
//! - **HVR** (Table II): for each run, HV(run front) / HV(reference front) with the settings'
//!   reference point; mean ± sample std over the method's runs; also the HVR of the merged
//!   front (all runs together);
//! - **epsilon and coverage** (Table III), for every ordered pair (A, B): the additive epsilon
//!   I_ε+(A_i, B_j) (normalised units) and Zitzler's coverage C(A_i, B_j) (weak dominance) over
//!   every pair of a run i of A and a run j of B; mean ± sample std over those n_A·n_B pairs;
//! - **picks** (Table IV): the best-error, fewest-triangles and trade-off (eq. 7–9, weights drawn
//!   from the settings' seed) members of each merged front;
//! - **dominance probability** (Table V): P(a ≺ b) for a from a run front of A and b from a run
//!   front of B, averaged over every pair of runs; its mark compares the two methods' per-run
//!   HVR samples with the two-sided Wilcoxon rank-sum test at α = [`SIGNIFICANCE_LEVEL`]:
//!   `+` A's HVRs are significantly larger (better), `−` significantly smaller, `=` no
//!   significant difference, `n/a` when either method has a single run (a deterministic
//!   method): with one value in a sample the smallest two-sided p-value is 2/(n+1) ≥ 0.18 for
//!   n ≤ 10, so the test could never reject and an `=` would falsely read as "no difference".

use super::ExperimentError;
use super::contender::Contender;
use super::results::{DatasetResults, Results};
use super::stats::Summary;
use crate::front::{Front, Solution};
use crate::metrics::{
    self, MetricsError, Normalization, Point, RankSumTest, additive_epsilon, best_error_pick,
    coverage, dominance_probability, fewest_triangles_pick, hypervolume_ratio, rank_sum_test,
    trade_off_pick,
};
use serde::Serialize;
use std::cmp::Ordering;

/// The significance level of Table V's marks.
pub(crate) const SIGNIFICANCE_LEVEL: f64 = 0.05;

/// Table V's verdict for an ordered pair of methods (A, B).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Mark {
    /// A's per-run HVRs are significantly larger than B's.
    Better,
    /// A's per-run HVRs are significantly smaller than B's.
    Worse,
    /// No significant difference.
    Equal,
    /// One of the methods has a single run: the test is not applicable.
    NotApplicable,
}

impl Mark {
    /// The mark as printed: `+`, `−`, `=` or `n/a`.
    pub(crate) fn symbol(self) -> &'static str {
        match self {
            Mark::Better => "+",
            Mark::Worse => "−",
            Mark::Equal => "=",
            Mark::NotApplicable => "n/a",
        }
    }
}

/// One picked solution's objectives, in the dataset's own units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Pick {
    /// E = Σ|z − z̃|.
    pub e: f64,
    /// Triangles.
    pub t: usize,
}

/// Everything about one method (or outside front) on one dataset.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MethodAnalysis {
    /// The method or outside front.
    pub method: Contender,
    /// The non-dominated merge of its runs' fronts, by increasing T, in the dataset's units.
    pub merged: Vec<Solution>,
    /// HVR of each run, by run number.
    pub hvr_runs: Vec<f64>,
    /// Their summary (Table II).
    pub hvr: Summary,
    /// The HVR of the merged front.
    pub merged_hvr: f64,
    /// The member of the merged front with the lowest E.
    pub best_error: Pick,
    /// The member with the fewest triangles.
    pub fewest_triangles: Pick,
    /// The paper's trade-off pick (eq. 7–9).
    pub trade_off: Pick,
}

/// The binary comparisons of an ordered pair of methods (A, B) on one dataset.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PairAnalysis {
    /// A.
    pub a: Contender,
    /// B.
    pub b: Contender,
    /// I_ε+(A_i, B_j) over every pair of runs, normalised units.
    pub epsilon: Summary,
    /// C(A_i, B_j) over every pair of runs.
    pub coverage: Summary,
    /// P(a ≺ b) over every pair of runs.
    pub dominance: Summary,
    /// The rank-sum test of A's per-run HVRs against B's (`None` when either has one run).
    pub test: Option<RankSumTest>,
    /// Table V's mark.
    pub mark: Mark,
}

/// Everything about one dataset.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DatasetAnalysis {
    /// The dataset's name.
    pub name: String,
    /// Per method, in settings order, then per outside front.
    pub methods: Vec<MethodAnalysis>,
    /// The non-dominated merge of all methods' merged fronts, normalised.
    pub reference_front: Vec<Point>,
    /// Every ordered pair (A, B) with A ≠ B, A-major in settings order.
    pub pairs: Vec<PairAnalysis>,
}

/// The analysis of a whole experiment.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Analysis {
    /// Per dataset, in input order.
    pub datasets: Vec<DatasetAnalysis>,
}

impl Analysis {
    /// Computes every table's numbers from `results`.
    ///
    /// Errors: [`ExperimentError::EmptyFront`] if a method has no run or a run has an empty
    /// front; [`ExperimentError::Metrics`] if an indicator is undefined (e.g. the reference
    /// front has no point better than the reference point, or a non-finite objective).
    pub fn of(results: &Results) -> Result<Analysis, ExperimentError> {
        let names = |d: &DatasetResults| d.external.iter().map(|x| x.name.clone()).collect();
        if let Some(first) = results.datasets.first() {
            let want: Vec<String> = names(first);
            if let Some(d) = results.datasets.iter().find(|d| names(d) != want) {
                return Err(ExperimentError::Settings(format!(
                    "every data set needs the same outside fronts in the same order: {} has {:?}, {} has {:?}",
                    first.name,
                    want,
                    d.name,
                    names(d)
                )));
            }
        }
        let datasets = results
            .datasets
            .iter()
            .map(|d| {
                analyse_dataset(d, results.settings.reference_point, results.settings.seed).map_err(
                    |e| match e {
                        Failure::Metrics(source) => ExperimentError::Metrics {
                            dataset: d.name.clone(),
                            source,
                        },
                        Failure::Empty(Contender::Method(method), run) => {
                            ExperimentError::EmptyFront {
                                dataset: d.name.clone(),
                                method,
                                run,
                            }
                        }
                        Failure::Empty(Contender::External(name), _) => {
                            ExperimentError::EmptyExternal {
                                dataset: d.name.clone(),
                                name,
                            }
                        }
                    },
                )
            })
            .collect::<Result<_, _>>()?;
        Ok(Analysis { datasets })
    }
}

/// A run's number and its front.
type RunFront<'a> = (usize, &'a [Solution]);

enum Failure {
    Metrics(MetricsError),
    Empty(Contender, usize),
}

impl From<MetricsError> for Failure {
    fn from(e: MetricsError) -> Self {
        Failure::Metrics(e)
    }
}

/// The analysis of one data set's runs: each contender's HVRs, merged front and picks, and
/// every ordered pair of contenders compared.
fn analyse_dataset(
    d: &DatasetResults,
    reference_point: Point,
    seed: u64,
) -> Result<DatasetAnalysis, Failure> {
    let n = Normalization::new(d.normalization.e_scale, d.normalization.t_scale)?;
    // Every contender's run fronts with their run numbers: the methods' runs, then each outside
    // front as a single run.
    let contenders: Vec<(Contender, Vec<RunFront>)> = d
        .methods
        .iter()
        .map(|m| {
            let runs = m.runs.iter().map(|r| (r.run, r.front.as_slice())).collect();
            (Contender::Method(m.method), runs)
        })
        .chain(d.external.iter().map(|x| {
            (
                Contender::External(x.name.clone()),
                vec![(0, x.front.as_slice())],
            )
        }))
        .collect();
    // Normalised run fronts per contender.
    let mut run_points: Vec<Vec<Vec<Point>>> = Vec::new();
    let mut merged: Vec<Vec<Solution>> = Vec::new();
    for (c, runs) in &contenders {
        if runs.is_empty() {
            return Err(Failure::Empty(c.clone(), 0));
        }
        if let Some((run, _)) = runs.iter().find(|(_, f)| f.is_empty()) {
            return Err(Failure::Empty(c.clone(), *run));
        }
        run_points.push(runs.iter().map(|(_, f)| n.solutions(f)).collect());
        let front = Front::merged(runs.iter().flat_map(|(_, f)| f.iter()));
        merged.push(front.solutions().to_vec());
    }
    let merged_points: Vec<Vec<Point>> = merged.iter().map(|s| n.solutions(s)).collect();
    let reference_front = metrics::merge(merged_points.iter().map(Vec::as_slice))?;

    let mut methods = Vec::new();
    for (k, (contender, _)) in contenders.iter().enumerate() {
        let hvr_runs = run_points[k]
            .iter()
            .map(|p| hypervolume_ratio(p, &reference_front, reference_point))
            .collect::<Result<Vec<_>, _>>()?;
        let hvr = Summary::of(&hvr_runs).expect("a method has at least one run");
        let points = &merged_points[k];
        let merged_hvr = hypervolume_ratio(points, &reference_front, reference_point)?;
        let pick = |i: usize| Pick {
            e: merged[k][i].e_sum,
            t: merged[k][i].t,
        };
        methods.push(MethodAnalysis {
            method: contender.clone(),
            best_error: pick(best_error_pick(points)?),
            fewest_triangles: pick(fewest_triangles_pick(points)?),
            trade_off: pick(trade_off_pick(points, seed)?.index),
            merged: merged[k].clone(),
            hvr_runs,
            hvr,
            merged_hvr,
        });
    }

    let mut pairs = Vec::new();
    for (ka, a) in methods.iter().enumerate() {
        for (kb, b) in methods.iter().enumerate() {
            if ka != kb {
                pairs.push(compare_pair([a, b], [&run_points[ka], &run_points[kb]])?);
            }
        }
    }
    Ok(DatasetAnalysis {
        name: d.name.clone(),
        methods,
        reference_front,
        pairs,
    })
}

/// Method `a` against method `b` (`methods`), from their normalised run fronts (`runs`):
/// ε, C and dominance over every pair of runs, and the rank-sum test of their HVRs.
fn compare_pair(
    [a, b]: [&MethodAnalysis; 2],
    [runs_a, runs_b]: [&[Vec<Point>]; 2],
) -> Result<PairAnalysis, Failure> {
    let (mut eps, mut cov, mut dom) = (Vec::new(), Vec::new(), Vec::new());
    for fa in runs_a {
        for fb in runs_b {
            eps.push(additive_epsilon(fa, fb)?);
            cov.push(coverage(fa, fb)?);
            dom.push(dominance_probability(fa, fb)?);
        }
    }
    let test = if a.hvr_runs.len() > 1 && b.hvr_runs.len() > 1 {
        Some(rank_sum_test(&a.hvr_runs, &b.hvr_runs)?)
    } else {
        None
    };
    let mark = match test.map(|t| t.verdict(SIGNIFICANCE_LEVEL)) {
        None => Mark::NotApplicable,
        Some(Ordering::Greater) => Mark::Better,
        Some(Ordering::Less) => Mark::Worse,
        Some(Ordering::Equal) => Mark::Equal,
    };
    let summary = |v: &[f64]| Summary::of(v).expect("both methods have runs");
    Ok(PairAnalysis {
        a: a.method.clone(),
        b: b.method.clone(),
        epsilon: summary(&eps),
        coverage: summary(&cov),
        dominance: summary(&dom),
        test,
        mark,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::experiment::method::Method;
    use crate::experiment::results::{GridSummary, MethodRuns, RESULTS_FORMAT, RunRecord, Scales};
    use crate::experiment::settings::{Budget, Settings};

    fn run(run: usize, points: &[(f64, usize)]) -> RunRecord {
        RunRecord {
            run,
            seed: Some(run as u64),
            evaluations: 1,
            front: points
                .iter()
                .map(|&(e, t)| Solution::recorded(e, e, t, vec![]))
                .collect(),
        }
    }

    /// Two methods on one dataset with scales (10, 10), so normalised = raw / 10: "NSGA-II"
    /// with two runs {(10, 2), (5, 4)} and {(10, 2), (4, 6)}, "greedy" with one run
    /// {(10, 2), (2, 8)}. Small enough to work every number out by hand.
    pub(crate) fn sample_results() -> Results {
        Results {
            format: RESULTS_FORMAT.to_string(),
            settings: Settings {
                methods: vec![Method::NSGA2, Method::GREEDY],
                runs: 2,
                weighted_runs: 1,
                budget: Budget::PerWeight,
                ..Settings::default()
            },
            datasets: vec![DatasetResults {
                name: "toy".to_string(),
                grid: GridSummary {
                    width: 3,
                    height: 3,
                    source: "hand-made".to_string(),
                },
                e_units: "m".to_string(),
                normalization: Scales {
                    e_scale: 10.0,
                    t_scale: 10.0,
                },
                methods: vec![
                    MethodRuns {
                        method: Method::NSGA2,
                        params: serde_json::Value::Null,
                        runs: vec![
                            run(0, &[(10.0, 2), (5.0, 4)]),
                            run(1, &[(10.0, 2), (4.0, 6)]),
                        ],
                    },
                    MethodRuns {
                        method: Method::GREEDY,
                        params: serde_json::Value::Null,
                        runs: vec![run(0, &[(10.0, 2), (2.0, 8)])],
                    },
                ],
                external: Vec::new(),
            }],
            timings: None,
            command: None,
        }
    }

    #[test]
    fn hand_computed_tables() {
        let a = Analysis::of(&sample_results()).unwrap();
        let d = &a.datasets[0];
        // Reference front (1, .2), (.5, .4), (.4, .6), (.2, .8) under (1.1, 1.1): slabs
        // .1·.2 + .6·.2 + .7·.2 + .9·.3 = 0.55. NSGA-II runs: .02 + .6·.7 = .44 → 0.8 and
        // .1·.4 + .7·.5 = .39 → 0.709…; greedy: .1·.6 + .9·.3 = .33 → 0.6.
        assert_eq!(d.reference_front.len(), 4);
        let close = |x: f64, y: f64| (x - y).abs() < 1e-12;
        assert!(close(d.methods[0].hvr_runs[0], 0.8));
        assert!(close(d.methods[0].hvr_runs[1], 0.39 / 0.55));
        assert!(close(d.methods[0].hvr.mean, (0.8 + 0.39 / 0.55) / 2.0));
        assert!(close(
            d.methods[0].hvr.std.unwrap(),
            (0.8 - 0.39 / 0.55) / 2f64.sqrt()
        ));
        assert!(close(d.methods[1].hvr.mean, 0.6));
        // NSGA-II's merged front {(1, .2), (.5, .4), (.4, .6)}: .1·.2 + .6·.2 + .7·.5 = .49.
        assert!(close(d.methods[0].merged_hvr, 0.49 / 0.55));
        assert!(close(d.methods[1].merged_hvr, 0.6));
        assert_eq!(d.methods[1].hvr.std, None);
        // NSGA-II's merged front keeps the shared corner mesh once.
        assert_eq!(d.methods[0].merged.len(), 3);

        let ab = &d.pairs[0];
        assert_eq!(
            (&ab.a, &ab.b),
            (&Method::NSGA2.into(), &Method::GREEDY.into())
        );
        // (2, 8) is missed by 0.3 (from (5, 4)) and by 0.2 (from (4, 6)) in normalised E.
        assert!(close(ab.epsilon.mean, 0.25));
        // Each NSGA-II run weakly dominates the shared (10, 2) but not (2, 8).
        assert_eq!((ab.coverage.mean, ab.coverage.std), (0.5, Some(0.0)));
        // No NSGA-II point strictly dominates a greedy point (the shared one is equal).
        assert_eq!(ab.dominance.mean, 0.0);
        // One greedy run: no test.
        assert_eq!((ab.test, ab.mark), (None, Mark::NotApplicable));
        let ba = &d.pairs[1];
        assert!(ba.a == Method::GREEDY && ba.b == Method::NSGA2);
        assert_eq!(ba.coverage.std, Some(0.0));

        let g = &d.methods[1];
        assert_eq!(g.best_error, Pick { e: 2.0, t: 8 });
        assert_eq!(g.fewest_triangles, Pick { e: 10.0, t: 2 });
    }

    #[test]
    fn empty_runs_are_an_error_not_a_panic() {
        let mut r = sample_results();
        r.datasets[0].methods[1].runs[0].front.clear();
        assert!(matches!(
            Analysis::of(&r),
            Err(ExperimentError::EmptyFront {
                method: Method::GREEDY,
                run: 0,
                ..
            })
        ));
        // No runs at all: the method has no front, reported as its first run's.
        r.datasets[0].methods[1].runs.clear();
        let err = Analysis::of(&r).unwrap_err();
        assert!(
            matches!(
                err,
                ExperimentError::EmptyFront {
                    method: Method::GREEDY,
                    run: 0,
                    ..
                }
            ),
            "{err:?}"
        );
    }

    #[test]
    fn two_stochastic_methods_get_a_rank_sum_mark() {
        // Give "greedy" three distinct runs, all worse than NSGA-II's (HVR (.17 − .02k)/.55):
        // U1 = 6 of 6 pairs, but with 2 against 3 values the exact two-sided p is
        // 2/C(5, 2) = 0.2 > 0.05: "=".
        let mut r = sample_results();
        let worse = |k: usize| run(k, &[(10.0, 2), (6.0 + k as f64, 9)]);
        r.datasets[0].methods[1].runs = vec![worse(0), worse(1), worse(2)];
        let a = Analysis::of(&r).unwrap();
        let t = a.datasets[0].pairs[0].test.unwrap();
        assert!((t.p_value - 0.2).abs() < 1e-12, "{t:?}");
        assert_eq!(a.datasets[0].pairs[0].mark, Mark::Equal);
    }
}
