//! The teaching view: steps through NSGA-II one phase (or one generation) at a time and shows
//! each phase on the plot with a one-line explanation. Pure (no DOM): [`Stepper`] decides what
//! a click does, [`scene`] turns a [`GenerationTrace`] and a [`Phase`] into marks and a caption.
//!
//! A generation is computed by the ordinary run (in frames, so the page stays smooth) up to
//! its boundary; its trace then holds every phase, and stepping reveals them in order. The run
//! is the same as without the teaching view (tracing never changes it).

use super::plot::{Mark, PlotPoint, Shape, format_value, rank_colour};
use crate::evaluator::Score;
use crate::evolution::CrossoverKind;
use crate::evolution::trace::{GenerationTrace, Member, Phase};

/// What the page must do after a teaching click.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Step {
    /// Show this phase of the last traced generation.
    Show(Phase),
    /// Run to the end of this generation first, then show the phase.
    Run {
        /// Generation to complete.
        generation: u64,
        /// Phase to show when it is complete.
        then: Phase,
    },
}

/// Where the teaching view stands: the phase shown, or the generation it waits for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Stepper {
    /// The phase shown (of the last traced generation), if any.
    pub shown: Option<Phase>,
    /// A generation being computed and the phase to show when it is done.
    pub waiting: Option<(u64, Phase)>,
}

impl Stepper {
    /// "Next phase": the phase after the shown one; after survival (or with nothing shown yet)
    /// the next generation runs and its selection is shown. `generation` is the run's completed
    /// generation count, `traced` the generation of the last trace.
    pub(crate) fn next_phase(&mut self, generation: u64, traced: Option<u64>) -> Step {
        let next = match (self.shown, traced) {
            (Some(p), Some(g)) if g == generation => Phase::ALL
                .iter()
                .position(|&q| q == p)
                .and_then(|i| Phase::ALL.get(i + 1)),
            _ => None,
        };
        match next {
            Some(&p) => self.show(p),
            None => self.run(generation + 1, Phase::Selection),
        }
    }

    /// "Next generation": runs one whole generation and shows its survival.
    pub(crate) fn next_generation(&mut self, generation: u64) -> Step {
        self.run(generation + 1, Phase::Survival)
    }

    /// The run reached `generation`: shows the phase that was waiting for it, if any.
    pub(crate) fn arrived(&mut self, generation: u64) -> Option<Phase> {
        let (target, then) = self.waiting?;
        if generation < target {
            return None;
        }
        self.waiting = None;
        self.shown = Some(then);
        Some(then)
    }

    fn show(&mut self, p: Phase) -> Step {
        self.shown = Some(p);
        self.waiting = None;
        Step::Show(p)
    }

    fn run(&mut self, generation: u64, then: Phase) -> Step {
        self.waiting = Some((generation, then));
        Step::Run { generation, then }
    }
}

/// What the plot shows for one phase.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TeachingScene {
    /// The points, drawn in order (later on top).
    pub marks: Vec<Mark>,
    /// The one-line explanation plus this generation's numbers.
    pub caption: String,
    /// Legend entries: label and colour.
    pub legend: Vec<(String, &'static str)>,
}

const FADED: &str = "#b8b8b8";
const CHILD: &str = "#17becf";
const CROSSED: &str = "#ff7f0e";
const DROPPED: &str = "#444444";

fn point(m: &Member) -> PlotPoint {
    PlotPoint {
        t: m.objectives.t as f64,
        e: m.objectives.e_sum,
    }
}

fn crowding_text(d: f64) -> String {
    if d.is_infinite() {
        "∞".to_string()
    } else {
        format!("{d:.3}")
    }
}

fn describe(who: &str, m: &Member) -> String {
    format!(
        "{who} · F{} · crowding {} · T = {} · E = {}",
        m.rank + 1,
        crowding_text(m.crowding),
        m.objectives.t,
        format_value(m.objectives.e_sum)
    )
}

fn mark(p: PlotPoint, colour: &'static str, shape: Shape, radius: f64, label: String) -> Mark {
    Mark {
        point: p,
        colour,
        shape,
        radius,
        filled: true,
        ring: 0.0,
        label,
    }
}

/// A mark for objectives `o` labelled "`who` · T = … · E = …".
fn objective_mark(o: &Score, colour: &'static str, shape: Shape, radius: f64, who: &str) -> Mark {
    let p = PlotPoint {
        t: o.t as f64,
        e: o.e_sum,
    };
    let label = format!("{who} · T = {} · E = {}", o.t, format_value(o.e_sum));
    mark(p, colour, shape, radius, label)
}

/// The front colours' legend: F1…F5 and "F6+".
fn front_legend(fronts: usize) -> Vec<(String, &'static str)> {
    (0..fronts.min(6))
        .map(|r| {
            let label = if r == 5 {
                "F6+".to_string()
            } else {
                format!("F{}", r + 1)
            };
            (label, rank_colour(r))
        })
        .collect()
}

/// Parents are squares, children triangles.
fn union_shape(i: usize, mu: usize) -> Shape {
    if i < mu {
        Shape::Square
    } else {
        Shape::Triangle
    }
}

/// Label of union member `i` (parents first, then children).
fn union_name(trace: &GenerationTrace, i: usize) -> String {
    let mu = trace.parents.len();
    if i < mu {
        format!("parent {}", i + 1)
    } else {
        format!("child {}", i - mu + 1)
    }
}

/// The marks and caption of `phase` of `trace`; `crossover` and `crossover_probability` are
/// the run's, for the caption.
pub(crate) fn scene(
    trace: &GenerationTrace,
    phase: Phase,
    crossover: CrossoverKind,
    crossover_probability: f64,
) -> TeachingScene {
    let intro = format!(
        "Generation {} · {}: {}",
        trace.generation,
        phase.label(),
        phase.explanation()
    );
    let (marks, numbers, legend) = match phase {
        Phase::Selection => selection(trace),
        Phase::Crossover | Phase::Mutation => {
            variation(trace, phase, crossover, crossover_probability)
        }
        Phase::Evaluation => evaluation(trace),
        Phase::Sorting | Phase::Crowding => ranking(trace, phase),
        Phase::Survival => survival(trace),
    };
    TeachingScene {
        marks,
        caption: format!("{intro} {numbers}"),
        legend,
    }
}

/// A phase's marks, the numbers of its caption, and its legend.
type Parts = (Vec<Mark>, String, Vec<(String, &'static str)>);

/// Number of non-domination fronts among parents and children together.
fn front_count(trace: &GenerationTrace) -> usize {
    trace.union.iter().map(|m| m.rank + 1).max().unwrap_or(0)
}

/// The parents as small grey squares, the backdrop of the phases that make children.
fn faded_parents(trace: &GenerationTrace) -> Vec<Mark> {
    trace
        .parents
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let mut k = mark(
                point(m),
                FADED,
                Shape::Square,
                2.5,
                describe(&format!("parent {}", i + 1), m),
            );
            k.filled = true;
            k
        })
        .collect()
}

/// Tournament selection: each parent ringed by how often it was picked.
fn selection(trace: &GenerationTrace) -> Parts {
    let mu = trace.parents.len();
    let counts = trace.selection_counts();
    let picked = counts.iter().filter(|&&c| c > 0).count();
    let most = counts.iter().copied().max().unwrap_or(0);
    let marks = trace
        .parents
        .iter()
        .zip(&counts)
        .enumerate()
        .map(|(i, (m, &c))| {
            let mut k = mark(
                point(m),
                rank_colour(m.rank),
                Shape::Circle,
                3.0,
                format!(
                    "{} · picked {c}×",
                    describe(&format!("parent {}", i + 1), m)
                ),
            );
            k.ring = c as f64;
            if c == 0 {
                k.filled = false;
            }
            k
        })
        .collect();
    (
        marks,
        format!(
            "{} tournaments picked {picked} of the {mu} individuals (ringed; the most \
             picked {most}×); hollow ones were not picked.",
            2 * trace.matings.len()
        ),
        front_legend(trace.parents.iter().map(|m| m.rank + 1).max().unwrap_or(0)),
    )
}

/// Crossover or mutation: the children before mutation over the faded parents.
fn variation(
    trace: &GenerationTrace,
    phase: Phase,
    crossover: CrossoverKind,
    crossover_probability: f64,
) -> Parts {
    let crossed = trace.matings.iter().filter(|m| m.crossed).count();
    let rows: usize = trace.matings.iter().map(|m| m.crossover_evaluations).sum();
    let mut marks = faded_parents(trace);
    for (k, m) in trace.matings.iter().enumerate() {
        for (c, known) in m.before_mutation.iter().enumerate() {
            if let (true, Some(o)) = (m.crossed, known) {
                let who = format!("crossover child {} of mating {}", c + 1, k + 1);
                marks.push(objective_mark(o, CROSSED, Shape::Diamond, 4.0, &who));
            }
        }
    }
    let numbers = if phase == Phase::Crossover {
        let how = match crossover {
            CrossoverKind::Oax => format!(
                "orthogonal-array crossover scored {rows} array rows and best-levels \
                 children; diamonds: the two children each crossover kept"
            ),
            CrossoverKind::Uniform => {
                "uniform crossover: its children are scored only after mutation".into()
            }
            CrossoverKind::TwoPoint => {
                "two-point crossover: its children are scored only after mutation".into()
            }
        };
        format!(
            "{crossed} of {} pairs were recombined (p_c = {crossover_probability}); {how}.",
            trace.matings.len()
        )
    } else {
        let flips: Vec<usize> = trace.matings.iter().flat_map(|m| m.flipped).collect();
        let total: usize = flips.iter().sum();
        let unchanged = flips.iter().filter(|&&f| f == 0).count();
        format!(
            "{total} genes flipped over {} children ({:.2} per child); {unchanged} \
             children were not changed by mutation.",
            flips.len(),
            total as f64 / flips.len().max(1) as f64
        )
    };
    let legend = vec![
        ("parents".to_string(), FADED),
        ("children before mutation".to_string(), CROSSED),
    ];
    (marks, numbers, legend)
}

/// Evaluation: the scored children over the faded parents.
fn evaluation(trace: &GenerationTrace) -> Parts {
    let mu = trace.parents.len();
    let mut marks = faded_parents(trace);
    let new_front = trace.union[mu..].iter().filter(|m| m.rank == 0).count();
    for (i, o) in trace.offspring.iter().enumerate() {
        let who = format!("child {}", i + 1);
        marks.push(objective_mark(o, CHILD, Shape::Triangle, 3.5, &who));
    }
    (
        marks,
        format!(
            "{} children scored; {new_front} of them are on the first front of parents \
             and children together.",
            trace.offspring.len()
        ),
        vec![
            ("parents".to_string(), FADED),
            ("children".to_string(), CHILD),
        ],
    )
}

/// Non-dominated sorting or crowding: parents and children by front, sized by crowding
/// distance in the crowding phase.
fn ranking(trace: &GenerationTrace, phase: Phase) -> Parts {
    let mu = trace.parents.len();
    let fronts = front_count(trace);
    let max_finite = trace
        .union
        .iter()
        .map(|m| m.crowding)
        .filter(|d| d.is_finite())
        .fold(0.0, f64::max);
    let marks = trace
        .union
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let shape = union_shape(i, mu);
            let radius = if phase == Phase::Crowding {
                // Size grows with the crowding distance; the ends (∞) are largest.
                let d = if m.crowding.is_infinite() {
                    1.0
                } else if max_finite > 0.0 {
                    m.crowding / max_finite
                } else {
                    0.0
                };
                2.5 + 4.5 * d
            } else {
                3.0
            };
            mark(
                point(m),
                rank_colour(m.rank),
                shape,
                radius,
                describe(&union_name(trace, i), m),
            )
        })
        .collect();
    let first = trace.union.iter().filter(|m| m.rank == 0).count();
    let numbers = if phase == Phase::Sorting {
        format!(
            "The {} parents (squares) and children (triangles) fall into {fronts} fronts; \
             F1 has {first}.",
            trace.union.len()
        )
    } else {
        "Point size grows with the crowding distance; hover a point to read it.".into()
    };
    (marks, numbers, front_legend(fronts))
}

/// Survival: who stays, who is dropped, and the front that was cut.
fn survival(trace: &GenerationTrace) -> Parts {
    let mu = trace.parents.len();
    let fronts = front_count(trace);
    let kept = trace.survived();
    let marks = trace
        .union
        .iter()
        .enumerate()
        .map(|(i, m)| {
            let shape = union_shape(i, mu);
            if kept[i] {
                mark(
                    point(m),
                    rank_colour(m.rank),
                    shape,
                    3.5,
                    format!("{} · survives", describe(&union_name(trace, i), m)),
                )
            } else {
                let mut k = mark(
                    point(m),
                    DROPPED,
                    Shape::Cross,
                    3.0,
                    format!("{} · dropped", describe(&union_name(trace, i), m)),
                );
                k.filled = false;
                k
            }
        })
        .collect();
    // The last front that fits only in part, if any.
    let cut = (0..fronts).find(|&r| {
        let members: Vec<usize> = (0..trace.union.len())
            .filter(|&i| trace.union[i].rank == r)
            .collect();
        let survivors = members.iter().filter(|&&i| kept[i]).count();
        survivors > 0 && survivors < members.len()
    });
    let children_kept = (mu..trace.union.len()).filter(|&i| kept[i]).count();
    let cut_text = match cut {
        Some(r) => {
            let size = trace.union.iter().filter(|m| m.rank == r).count();
            let survivors = (0..trace.union.len())
                .filter(|&i| trace.union[i].rank == r && kept[i])
                .count();
            format!(
                "F{} did not fit and kept its {survivors} least crowded of {size}",
                r + 1
            )
        }
        None => "the kept fronts fitted exactly".to_string(),
    };
    (
        marks,
        format!(
            "{} of {} survive ({children_kept} of them children); {cut_text}. Crosses \
             were dropped.",
            trace.survivors.len(),
            trace.union.len()
        ),
        {
            let mut l = front_legend(fronts);
            l.push(("dropped".to_string(), DROPPED));
            l
        },
    )
}
