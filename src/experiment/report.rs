//! report.md: the paper's Tables II–V, with a header that says what was run, the protocol in
//! one paragraph, every method's budget, and the outside fronts with the meshes they lost.
//!
//! Number formats (also what a reader or a test may parse): normalised quantities (HVR, I_ε+,
//! C, P) with 4 decimals as `mean ± std`, `± n/a` when there is one value; E with 6 significant
//! digits in the dataset's units; p-values in scientific notation with 2 decimals.

use super::analysis::{Analysis, DatasetAnalysis, MethodAnalysis, SIGNIFICANCE_LEVEL};
use super::contender::Contender;
use super::method::Method;
use super::registry;
use super::results::{DatasetResults, Results};
use super::settings::{Budget, DEFAULT_EQUAL_EVALUATIONS, Settings};
use super::stats::Summary;
use crate::evolution::memetic::MemeticParams;
use std::fmt::Write;

/// `mean ± std` with 4 decimals, `± n/a` for a single value.
pub(crate) fn format_summary(s: &Summary) -> String {
    match s.std {
        Some(std) => format!("{:.4} ± {:.4}", s.mean, std),
        None => format!("{:.4} ± n/a", s.mean),
    }
}

/// A value with 6 significant digits, without an exponent (E in the dataset's units).
///
/// ```
/// use paretomesh::experiment::format_significant;
/// assert_eq!(format_significant(12345.678), "12345.7");
/// assert_eq!(format_significant(0.012345678), "0.0123457");
/// assert_eq!(format_significant(0.0), "0");
/// ```
pub fn format_significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (5 - x.abs().log10().floor() as i64).clamp(0, 17) as usize;
    format!("{x:.digits$}")
}

/// The protocol in one paragraph: who gets which budget, and how the runs are counted.
fn protocol_paragraph(s: &Settings, has_external: bool) -> String {
    let ga: Vec<&str> = s
        .methods
        .iter()
        .filter(|m| m.is_ga())
        .map(|m| m.label())
        .collect();
    let mut p = match s.budget {
        Budget::Equal { evaluations } => {
            let parts = registry::ga_runs_per_run(Method::WEIGHTED);
            let share = evaluations / parts as u64;
            format!(
                "Equal budgets: every run of a genetic algorithm ({}) stops after {evaluations} evaluations, with no generation limit. The weighted-sum GA splits its run over its {parts} weights: each weight's GA run gets ⌊{evaluations} / {parts}⌋ = {share} evaluations, and the remaining {} are not spent. Each GA run (for the weighted-sum GA, each weight's) stops at the first mating boundary at or after its budget, so it may overshoot by less than one mating (at most 11 evaluations with the default crossover). Population {} for NSGA-II and the weighted-sum GA.",
                ga.join(", "),
                evaluations - share * parts as u64,
                s.population
            )
        }
        Budget::PerWeight => format!(
            "Per-weight budgets (the paper's): every GA run ({}) has population {} for {} generations with no evaluation cap, and the weighted-sum GA runs that for each of its {} weights, so one weighted-sum run costs about {} NSGA-II runs.",
            ga.join(", "),
            s.population,
            s.generations,
            registry::ga_runs_per_run(Method::WEIGHTED),
            registry::ga_runs_per_run(Method::WEIGHTED)
        ),
    };
    let times = |n: usize| {
        if n == 1 {
            "once".to_string()
        } else {
            format!("{n} times")
        }
    };
    let memetic: Vec<&str> = s
        .methods
        .iter()
        .filter(|&&m| registry::is_memetic(m))
        .map(|m| m.label())
        .collect();
    if !memetic.is_empty() {
        let which = memetic.join(", ");
        p.push_str(&match s.budget {
            Budget::Equal { evaluations } => format!(
                " The memetic method ({which}) gets the same {evaluations} evaluations per run, its seeding (greedy sweeps and decimation) included, with its own population of {}.",
                MemeticParams::default().population
            ),
            Budget::PerWeight => format!(
                " The memetic method ({which}) runs to an evaluation budget, not generations: it gets the NSGA-II run's budget, {} evaluations per run, its seeding (greedy sweeps and decimation) included (what an NSGA-II run of population {} for {} generations spends, taken as {DEFAULT_EQUAL_EVALUATIONS} for the paper's 100 × 50 and in proportion otherwise), with its own population of {}.",
                registry::nsga2_equivalent_evaluations(s),
                s.population,
                s.generations,
                MemeticParams::default().population
            ),
        });
    }
    p.push_str(&format!(
        " NSGA-II{} runs {} and the weighted-sum GA {} (run k with seed {} + k); decimation and greedy insertion are deterministic, stop by their own rule and run once.",
        if memetic.is_empty() {
            ""
        } else {
            " and each memetic method"
        },
        times(s.runs),
        times(s.weighted_runs),
        s.seed
    ));
    if has_external {
        p.push_str(" Outside fronts were made by other tools at budgets this experiment does not control; each is re-scored here and counts as a single run, so its std and rank-sum tests are n/a.");
    }
    p.push_str(" Every number below is computed from the runs' final fronts (see Statistics).");
    p
}

/// The whole report.md text for `results` and its `analysis` (which must be
/// [`Analysis::of`]`(results)`).
pub fn report_markdown(results: &Results, analysis: &Analysis) -> String {
    let mut out = String::new();
    let s = &results.settings;
    let w = &mut out;
    let _ = writeln!(w, "# ParetoMesh experiment\n");
    if let Some(command) = &results.command {
        let _ = writeln!(w, "```sh\n{command}\n```\n");
    }
    let _ = writeln!(
        w,
        "The source paper's protocol at the budget below, run by `paretomesh experiment`. Every run's front is in `results.json`; every number below can be recomputed from it.\n"
    );
    let has_external = results.datasets.iter().any(|d| !d.external.is_empty());
    let _ = writeln!(w, "## Protocol\n");
    let _ = writeln!(w, "{}\n", protocol_paragraph(s, has_external));

    settings_section(w, results);
    datasets_section(w, results);
    runs_section(w, results, analysis);
    if has_external {
        outside_fronts(w, results);
    }

    table_ii(w, results, analysis);
    ablations(w, s, analysis);
    table_iii(w, analysis);
    table_iv(w, results, analysis);
    table_v(w, analysis);
    out
}

/// The Settings section: methods, seeds, budget, parameters, normalisation, statistics and
/// wall time.
fn settings_section(w: &mut String, results: &Results) {
    let s = &results.settings;
    let _ = writeln!(w, "## Settings\n");
    let _ = writeln!(
        w,
        "- Methods: {}.",
        s.methods
            .iter()
            .map(|m| format!("{} (`{}`)", m.label(), m.name()))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let seeds = |runs: usize| match runs {
        1 => format!("1 run, seed {}", s.seed),
        n => format!("{n} runs, run k = 0…{} with seed {} + k", n - 1, s.seed),
    };
    if s.methods.contains(&Method::NSGA2) {
        let _ = writeln!(w, "- NSGA-II: {}.", seeds(s.runs));
    }
    for &m in s.methods.iter().filter(|&&m| registry::is_memetic(m)) {
        let _ = writeln!(w, "- {}: {}.", m.label(), seeds(s.runs));
    }
    if s.methods.contains(&Method::WEIGHTED) {
        let _ = writeln!(
            w,
            "- Weighted-sum GA: {}. One run is a sweep over all its weights w = 0, 0.1, …, 1, one GA run each (11 GA runs); the best solution of each weight makes that run's front.{}",
            seeds(s.weighted_runs),
            if s.weighted_runs == 1 {
                " One sweep is the paper's protocol; it gives one HVR sample, so its std and rank-sum tests are n/a (`--weighted-runs N` runs N sweeps)."
            } else {
                ""
            }
        );
    }
    let _ = writeln!(
        w,
        "- Deterministic methods (decimation, greedy insertion) run once."
    );
    match s.budget {
        Budget::Equal { evaluations } => {
            let _ = writeln!(
                w,
                "- GA budget: {evaluations} evaluations per run of every GA, population {} (`--budget equal --evals {evaluations}`).",
                s.population
            );
        }
        Budget::PerWeight => {
            let _ = writeln!(
                w,
                "- GA budget: population {}, {} generations (NSGA-II and each weighted-sum GA run; `--budget per-weight`).",
                s.population, s.generations
            );
        }
    }
    if let Some(d) = results.datasets.first() {
        let _ = writeln!(w, "- Parameters as run:");
        for m in &d.methods {
            let _ = writeln!(w, "  - {}: `{}`", m.method.label(), m.params);
        }
    }
    let _ = writeln!(
        w,
        "- Normalisation, per dataset: E / E(corner-only mesh), T / 2(W−1)(H−1) (the full grid's triangle count). Hypervolume reference point (normalised E, T) = ({}, {}).",
        s.reference_point[0], s.reference_point[1]
    );
    let _ = writeln!(
        w,
        "- Statistics: mean ± sample standard deviation (n − 1) over runs (Table II) or over every pair of runs of the two methods (Tables III, V); `± n/a` where there is a single value (a deterministic method has one run). Table V's mark: two-sided Wilcoxon rank-sum test of the row method's per-run HVRs against the column method's at α = {SIGNIFICANCE_LEVEL}: `+` row significantly higher HVR (better), `−` significantly lower, `=` no significant difference, `n/a` when either method has a single run (the test cannot reach significance with one value). The trade-off pick draws its 1 000 weights from seed {}.",
        s.seed
    );
    match &results.timings {
        Some(t) => {
            let _ = writeln!(
                w,
                "- Wall time: {:.1} s for the whole experiment on {} worker thread{}.",
                t.wall_seconds,
                t.threads,
                if t.threads == 1 { "" } else { "s" }
            );
        }
        None => {
            let _ = writeln!(w, "- Wall time: not measured.");
        }
    }
}

/// The Data sets table: grid, E unit, normalisation and source of each data set.
fn datasets_section(w: &mut String, results: &Results) {
    let _ = writeln!(w, "\n## Data sets\n");
    let _ = writeln!(
        w,
        "| Data set | Grid | E unit | E of corner-only mesh | Full-grid triangles | Source |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|");
    for d in &results.datasets {
        let _ = writeln!(
            w,
            "| {} | {}×{} | {} | {} | {} | {} |",
            d.name,
            d.grid.width,
            d.grid.height,
            cell(&d.e_units),
            format_significant(d.normalization.e_scale),
            d.normalization.t_scale,
            cell(&d.grid.source)
        );
    }
}

/// The Runs table: each method's budget and the evaluations its runs spent, per data set, with
/// the outside fronts.
fn runs_section(w: &mut String, results: &Results, analysis: &Analysis) {
    let s = &results.settings;
    let _ = writeln!(w, "\n## Runs\n");
    let _ = writeln!(
        w,
        "Budget: what one run may spend, in evaluations (one evaluation = one mesh triangulated and scored). Spent: the evaluations the runs actually made, mean and range over runs.\n"
    );
    let _ = writeln!(
        w,
        "| Data set | Method | Runs | Budget per run | Evaluations spent per run: mean (min–max) | Merged front size |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|");
    for (d, a) in results.datasets.iter().zip(&analysis.datasets) {
        for (m, ma) in d.methods.iter().zip(&a.methods) {
            let spent: Vec<u64> = m.runs.iter().map(|r| r.evaluations).collect();
            let mean = spent.iter().sum::<u64>() as f64 / spent.len().max(1) as f64;
            let (lo, hi) = (
                spent.iter().min().copied().unwrap_or(0),
                spent.iter().max().copied().unwrap_or(0),
            );
            let _ = writeln!(
                w,
                "| {} | {} | {} | {} | {mean:.0} ({lo}–{hi}) | {} |",
                d.name,
                m.method.label(),
                m.runs.len(),
                registry::budget_text(m.method, s),
                ma.merged.len()
            );
        }
        for x in &d.external {
            let _ = writeln!(
                w,
                "| {} | {} | 1 (outside) | not controlled here | unknown | {} |",
                d.name,
                cell(&x.name),
                x.front.len()
            );
        }
    }
}

/// Escapes a free-text table cell.
fn cell(text: &str) -> String {
    text.replace('|', "\\|").replace('\n', " ")
}

/// Refused meshes listed per outside front; a tool run on the wrong grid would otherwise list
/// every mesh of its front.
const LISTED_REFUSALS: usize = 20;

/// The outside fronts: where each came from, how many meshes were read, kept and refused, and
/// why.
fn outside_fronts(w: &mut String, results: &Results) {
    let _ = writeln!(w, "\n## Outside fronts\n");
    let _ = writeln!(
        w,
        "Meshes made by other tools, re-scored with this project's evaluator on their own triangles (which must cover the grid rectangle exactly once, over grid points only). Refused meshes are left out of every table. \"Not Delaunay\": valid meshes that are not a Delaunay triangulation of their points (the project's methods are always scored on one).\n"
    );
    let _ = writeln!(
        w,
        "| Data set | Front | Source | Meshes | Valid | Refused | Not Delaunay | On the front |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|---|---|");
    for d in &results.datasets {
        for x in &d.external {
            let _ = writeln!(
                w,
                "| {} | {} | `{}` | {} | {} | {} | {} | {} |",
                d.name,
                cell(&x.name),
                cell(&x.source),
                x.meshes,
                x.valid(),
                x.rejected.len(),
                x.not_delaunay,
                x.front.len()
            );
        }
    }
    for d in &results.datasets {
        for x in d.external.iter().filter(|x| !x.rejected.is_empty()) {
            let _ = writeln!(w, "\nRefused from {} on {}:\n", cell(&x.name), d.name);
            for r in x.rejected.iter().take(LISTED_REFUSALS) {
                let _ = writeln!(w, "- {}: {}", cell(&r.mesh), cell(&r.reason));
            }
            if x.rejected.len() > LISTED_REFUSALS {
                let _ = writeln!(
                    w,
                    "- and {} more (every one with its reason in results.json)",
                    x.rejected.len() - LISTED_REFUSALS
                );
            }
        }
    }
}

fn table_ii(w: &mut String, results: &Results, analysis: &Analysis) {
    let _ = writeln!(
        w,
        "\n## Table II. Hypervolume ratio HVR (mean ± std over runs)\n"
    );
    method_table(w, analysis, |m| format_summary(&m.hvr));
    let merged_note = match results.settings.budget {
        Budget::PerWeight => {
            "all its runs together; a weighted-sum sweep is 11 GA runs, about the evaluations of 10 NSGA-II runs"
        }
        Budget::Equal { .. } => "all its runs together: its runs × the budget per run",
    };
    let _ = writeln!(w, "\nHVR of each method's merged front ({merged_note}):\n");
    method_table(w, analysis, |m| format!("{:.4}", m.merged_hvr));
}

/// The ablation variants among the methods: what each removes, and its per-run HVR against
/// the full method's with the rank-sum test (the same test as Table V's marks).
fn ablations(w: &mut String, s: &Settings, analysis: &Analysis) {
    let variants: Vec<(Method, Method, &str)> = s
        .methods
        .iter()
        .filter_map(|&m| {
            m.spec()
                .ablation
                .filter(|(full, _)| s.methods.contains(full))
                .map(|(full, removes)| (m, full, removes))
        })
        .collect();
    if variants.is_empty() {
        return;
    }
    let _ = writeln!(
        w,
        "
## Ablations
"
    );
    let _ = writeln!(
        w,
        "Each variant is its full method with one component switched off, at the same budget and seeds. What each variant removes:
"
    );
    for (m, full, removes) in &variants {
        let _ = writeln!(
            w,
            "- {} (`{}`): {} without {removes}.",
            m.label(),
            m.name(),
            full.label()
        );
    }
    let _ = writeln!(
        w,
        "
Per-run HVR (Table II) of each variant against its full method: two-sided Wilcoxon rank-sum test at α = {SIGNIFICANCE_LEVEL}; mark `−`: the variant is significantly worse (the component earns its keep), `+` significantly better, `=` no significant difference.
"
    );
    let _ = writeln!(
        w,
        "| Data set | Variant | HVR | Full method's HVR | Difference of means | p | Mark |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|---|");
    for a in &analysis.datasets {
        let hvr = |m: Method| a.methods.iter().find(|x| x.method == m).map(|x| &x.hvr);
        for &(m, full, _) in &variants {
            let (Some(hv), Some(hf)) = (hvr(m), hvr(full)) else {
                continue;
            };
            let pair = a.pairs.iter().find(|p| p.a == m && p.b == full);
            let (p, mark) = match pair {
                Some(p) => (
                    p.test
                        .map_or("n/a".to_string(), |t| format!("{:.2e}", t.p_value)),
                    p.mark.symbol(),
                ),
                None => ("n/a".to_string(), "n/a"),
            };
            let _ = writeln!(
                w,
                "| {} | {} | {} | {} | {:+.4} | {p} | {mark} |",
                a.name,
                m.label(),
                format_summary(hv),
                format_summary(hf),
                hv.mean - hf.mean
            );
        }
    }
}

/// A table with one row per data set and one column per method (then outside front), cells
/// from `cell`.
fn method_table(w: &mut String, analysis: &Analysis, cell: impl Fn(&MethodAnalysis) -> String) {
    let columns: Vec<&Contender> = analysis
        .datasets
        .first()
        .map(|d| d.methods.iter().map(|m| &m.method).collect())
        .unwrap_or_default();
    let labels: Vec<_> = columns.iter().map(|m| m.label()).collect();
    let _ = writeln!(w, "| Data set | {} |", labels.join(" | "));
    let _ = writeln!(w, "|---|{}", "---|".repeat(columns.len()));
    for a in &analysis.datasets {
        let cells: Vec<_> = a.methods.iter().map(&cell).collect();
        let _ = writeln!(w, "| {} | {} |", a.name, cells.join(" | "));
    }
}

fn table_iii(w: &mut String, analysis: &Analysis) {
    let _ = writeln!(
        w,
        "\n## Table III. Additive epsilon I_ε+(A, B) (normalised) and coverage C(A, B) (mean ± std over pairs of runs)\n"
    );
    let _ = writeln!(
        w,
        "I_ε+(A, B): how far A must move (in normalised units) to weakly dominate all of B; ≤ 0 when it already does. C(A, B): the share of B weakly dominated by some member of A.\n"
    );
    for a in &analysis.datasets {
        let _ = writeln!(w, "### {}\n", a.name);
        let _ = writeln!(w, "| A | B | I_ε+(A, B) | C(A, B) |");
        let _ = writeln!(w, "|---|---|---|---|");
        for p in &a.pairs {
            let _ = writeln!(
                w,
                "| {} | {} | {} | {} |",
                p.a.label(),
                p.b.label(),
                format_summary(&p.epsilon),
                format_summary(&p.coverage)
            );
        }
        let _ = writeln!(w);
    }
}

fn table_iv(w: &mut String, results: &Results, analysis: &Analysis) {
    let _ = writeln!(
        w,
        "## Table IV. Best-error, fewest-triangles and trade-off solutions of each merged front\n"
    );
    let _ = writeln!(
        w,
        "| Data set | Method | Best error: E | T | Fewest triangles: E | T | Trade-off: E | T |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|---|---|");
    for (d, a) in results.datasets.iter().zip(&analysis.datasets) {
        for m in &a.methods {
            let _ = writeln!(
                w,
                "| {} | {} | {} | {} | {} | {} | {} | {} |",
                d.name,
                m.method.label(),
                format_significant(m.best_error.e),
                m.best_error.t,
                format_significant(m.fewest_triangles.e),
                m.fewest_triangles.t,
                format_significant(m.trade_off.e),
                m.trade_off.t
            );
        }
    }
    let units: Vec<String> = results
        .datasets
        .iter()
        .map(|d: &DatasetResults| format!("{}: {}", d.name, d.e_units))
        .collect();
    let _ = writeln!(w, "\nE units: {}.", units.join("; "));
}

fn table_v(w: &mut String, analysis: &Analysis) {
    let _ = writeln!(
        w,
        "\n## Table V. Averaged dominance probability P(row ≺ column) with rank-sum mark (α = {SIGNIFICANCE_LEVEL})\n"
    );
    let _ = writeln!(
        w,
        "P(A ≺ B): the probability that a solution of a run of A Pareto-dominates a solution of a run of B, averaged over every pair of runs. Mark: per-run HVR of A against B (see Settings); p is the two-sided p-value.\n"
    );
    for a in &analysis.datasets {
        table_v_dataset(w, a);
    }
}

fn table_v_dataset(w: &mut String, a: &DatasetAnalysis) {
    let methods: Vec<&Contender> = a.methods.iter().map(|m| &m.method).collect();
    let _ = writeln!(w, "### {}\n", a.name);
    let _ = writeln!(
        w,
        "| P(row ≺ column) | {} |",
        methods
            .iter()
            .map(|m| m.label())
            .collect::<Vec<_>>()
            .join(" | ")
    );
    let _ = writeln!(w, "|---|{}", "---|".repeat(methods.len()));
    for &row in &methods {
        let cells: Vec<String> = methods
            .iter()
            .map(|&col| {
                if col == row {
                    return "—".to_string();
                }
                let p = a
                    .pairs
                    .iter()
                    .find(|p| &p.a == row && &p.b == col)
                    .expect("every ordered pair is analysed");
                match p.test {
                    Some(t) => format!(
                        "{:.4} {} (p = {:.2e})",
                        p.dominance.mean,
                        p.mark.symbol(),
                        t.p_value
                    ),
                    None => format!("{:.4} {}", p.dominance.mean, p.mark.symbol()),
                }
            })
            .collect();
        let _ = writeln!(w, "| {} | {} |", row.label(), cells.join(" | "));
    }
    let _ = writeln!(w);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::analysis::tests::sample_results;

    #[test]
    fn report_has_the_four_tables_with_the_hand_computed_numbers() {
        let results = sample_results();
        let text = report_markdown(&results, &Analysis::of(&results).unwrap());
        for heading in [
            "## Table II.",
            "## Table III.",
            "## Table IV.",
            "## Table V.",
        ] {
            assert!(text.contains(heading), "missing {heading}");
        }
        // HVR (0.8 + 0.709…)/2 with std 0.0643; greedy one run.
        assert!(
            text.contains("| toy | 0.7545 ± 0.0643 | 0.6000 ± n/a |"),
            "{text}"
        );
        assert!(
            text.contains("| NSGA-II | Greedy insertion | 0.2500 ± 0.0707 | 0.5000 ± 0.0000 |")
        );
        assert!(text.contains("| toy | Greedy insertion | 2.00000 | 8 | 10.0000 | 2 |"));
        assert!(text.contains("| NSGA-II | — | 0.0000 n/a |"), "{text}");
        assert!(text.contains("Wall time: not measured."));
    }
}
