//! Solutions and the non-dominated front of (E, T), both minimised.

use crate::evaluator::Score;
use crate::measure::ErrorMeasure;
use serde::{Deserialize, Deserializer, Serialize, Serializer, ser::SerializeStruct};
use std::ops::Deref;

impl Score {
    /// The minimised objective vector (E, T).
    pub fn objectives(&self) -> [f64; 2] {
        [self.e_sum, self.t as f64]
    }
}

/// One simplified mesh: its kept grid points and their score as the
/// [`Evaluator`](crate::evaluator::Evaluator) gives it. It reads as its score (`s.e_sum`,
/// `s.t`).
///
/// front.json and results.json record E_sum, E_max and T, not the rms, so a solution read from
/// a file (or made by [`Solution::recorded`]) has an rms of NaN, and solutions compare by the
/// recorded numbers and the kept set alone.
#[derive(Clone, Debug)]
pub struct Solution {
    /// The score of the kept set.
    pub score: Score,
    /// Kept grid indices (y·W + x), increasing, corners included.
    pub kept: Vec<u32>,
}

impl Solution {
    /// A solution with the numbers a file records (E_sum, E_max, T) and no rms (NaN).
    pub fn recorded(e_sum: f64, e_max: f64, t: usize, kept: Vec<u32>) -> Self {
        let score = Score {
            e_sum,
            e_max,
            rms: f64::NAN,
            t,
        };
        Self { score, kept }
    }

    /// The objective vector (E, T).
    pub fn objectives(&self) -> [f64; 2] {
        self.score.objectives()
    }
}

impl Deref for Solution {
    type Target = Score;

    fn deref(&self) -> &Score {
        &self.score
    }
}

impl PartialEq for Solution {
    fn eq(&self, other: &Self) -> bool {
        let recorded = |s: &Self| (s.e_sum, s.e_max, s.t);
        recorded(self) == recorded(other) && self.kept == other.kept
    }
}

/// The fields of a solution in the files, in their order.
const RECORDED_FIELDS: [&str; 4] = ["E_sum", "E_max", "T", "kept"];

impl Serialize for Solution {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut record = serializer.serialize_struct("Solution", RECORDED_FIELDS.len())?;
        record.serialize_field(RECORDED_FIELDS[0], &self.e_sum)?;
        record.serialize_field(RECORDED_FIELDS[1], &self.e_max)?;
        record.serialize_field(RECORDED_FIELDS[2], &self.t)?;
        record.serialize_field(RECORDED_FIELDS[3], &self.kept)?;
        record.end()
    }
}

/// A solution as the files record it.
#[derive(Deserialize)]
struct Record {
    #[serde(rename = "E_sum")]
    e_sum: f64,
    #[serde(rename = "E_max")]
    e_max: f64,
    #[serde(rename = "T")]
    t: usize,
    kept: Vec<u32>,
}

impl<'de> Deserialize<'de> for Solution {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let r = Record::deserialize(deserializer)?;
        Ok(Self::recorded(r.e_sum, r.e_max, r.t, r.kept))
    }
}

/// Does `a` Pareto-dominate `b` (no worse in both objectives, better in one)? Minimisation.
pub fn dominates(a: [f64; 2], b: [f64; 2]) -> bool {
    a[0] <= b[0] && a[1] <= b[1] && (a[0] < b[0] || a[1] < b[1])
}

/// A set of mutually non-dominated solutions, sorted by increasing T (so decreasing E).
///
/// E is the front's [`ErrorMeasure`] (E_sum unless made by `Front::new` with another):
/// members are non-dominated in (that error, T), and still carry all three errors.
/// Solutions with identical objectives are kept once (the first one offered).
///
/// ```
/// use paretomesh::front::{Front, Solution};
/// let s = |e: f64, t: usize| Solution::recorded(e, e, t, vec![]);
/// let mut front = Front::default();
/// assert!(front.offer(s(10.0, 2)));
/// assert!(front.offer(s(4.0, 6)));
/// assert!(!front.offer(s(11.0, 6))); // dominated
/// assert!(front.offer(s(3.0, 4)));   // dominates (4, 6)
/// assert_eq!(front.solutions().iter().map(|s| s.t).collect::<Vec<_>>(), vec![2, 4]);
/// // The least error within 5 triangles is the member with 4; none has 1 or fewer.
/// assert_eq!(front.within(5).map(|s| s.t), Some(4));
/// assert!(front.within(1).is_none());
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Front {
    solutions: Vec<Solution>,
    /// The error the members are non-dominated in; written only when not E_sum, so a sum
    /// front reads and writes as before measures existed.
    #[serde(default, skip_serializing_if = "ErrorMeasure::is_sum")]
    measure: ErrorMeasure,
}

impl Front {
    /// An empty front in (`measure`, T).
    pub(crate) fn new(measure: ErrorMeasure) -> Self {
        Self {
            solutions: Vec::new(),
            measure,
        }
    }

    /// The error the members are non-dominated in.
    pub fn measure(&self) -> ErrorMeasure {
        self.measure
    }

    /// Offers a solution; returns true when it enters the front (dominated members leave).
    pub fn offer(&mut self, s: Solution) -> bool {
        let measure = self.measure;
        let o = measure.objectives(&s.score);
        if self.solutions.iter().any(|m| {
            let p = measure.objectives(&m.score);
            p == o || dominates(p, o)
        }) {
            return false;
        }
        self.solutions
            .retain(|m| !dominates(o, measure.objectives(&m.score)));
        let e = |m: &Solution| measure.of(&m.score).to_bits();
        let at = self
            .solutions
            .partition_point(|m| (m.t, e(m)) < (s.t, e(&s)));
        self.solutions.insert(at, s);
        true
    }

    /// [`offer`](Self::offer) of a solution with `score`, asking for its kept set (`kept`)
    /// only when it enters: most offers of a run are refused, and listing the kept set is the
    /// costly part.
    pub(crate) fn offer_score(&mut self, score: Score, kept: impl FnOnce() -> Vec<u32>) -> bool {
        // Sorted by increasing T and decreasing E: the member with the largest T ≤ score.t is
        // the only one that can dominate or equal the score.
        let measure = self.measure;
        if self
            .within(score.t)
            .is_some_and(|m| measure.of(&m.score) <= measure.of(&score))
        {
            return false;
        }
        self.offer(Solution {
            score,
            kept: kept(),
        })
    }

    /// The member with the most triangles at most `t`, which is the one of least E among
    /// them (the members are sorted by increasing T and so decreasing E); `None` when every
    /// member has more.
    pub fn within(&self, t: usize) -> Option<&Solution> {
        let at = self.solutions.partition_point(|m| m.t <= t);
        at.checked_sub(1).map(|k| &self.solutions[k])
    }

    /// The members, by increasing T.
    pub fn solutions(&self) -> &[Solution] {
        &self.solutions
    }

    /// Number of members.
    pub fn len(&self) -> usize {
        self.solutions.len()
    }

    /// True when there is no member.
    pub fn is_empty(&self) -> bool {
        self.solutions.is_empty()
    }

    /// Merges solutions from any number of fronts or runs into one front of (E_sum, T).
    pub(crate) fn merged<'a>(solutions: impl IntoIterator<Item = &'a Solution>) -> Front {
        Self::merged_in(ErrorMeasure::Sum, solutions)
    }

    /// Merges solutions into one front of (`measure`, T).
    pub(crate) fn merged_in<'a>(
        measure: ErrorMeasure,
        solutions: impl IntoIterator<Item = &'a Solution>,
    ) -> Front {
        let mut f = Front::new(measure);
        for s in solutions {
            f.offer(s.clone());
        }
        f
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};

    #[test]
    fn offer_score_agrees_with_offer() {
        // Random errors and T on a coarse lattice, so that ties in E, in T and in both occur:
        // the shortcut must accept exactly what `Front::offer` accepts, in every measure, and
        // the members must be non-dominated in that measure.
        for measure in ErrorMeasure::ALL {
            let mut rng = rand_pcg::Pcg64Mcg::seed_from_u64(8);
            let (mut fast, mut plain) = (Front::new(measure), Front::new(measure));
            let kept = vec![0, 1, 2, 3];
            for _ in 0..2000 {
                let score = Score {
                    e_sum: rng.random_range(0..40) as f64,
                    e_max: rng.random_range(0..40) as f64,
                    rms: rng.random_range(0..40) as f64,
                    t: rng.random_range(2..40),
                };
                let entered = fast.offer_score(score, || kept.clone());
                let expected = plain.offer(Solution {
                    score,
                    kept: kept.clone(),
                });
                assert_eq!(entered, expected, "{measure} {score:?}");
            }
            assert_eq!(fast, plain);
            let members = fast.solutions();
            for (i, a) in members.iter().enumerate() {
                for b in &members[..i] {
                    let (pa, pb) = (measure.objectives(a), measure.objectives(b));
                    assert!(!dominates(pa, pb) && !dominates(pb, pa) && pa != pb);
                }
            }
            assert!(members.windows(2).all(|w| w[0].t < w[1].t));
        }
    }

    #[test]
    fn a_solution_is_written_and_read_as_its_recorded_numbers() {
        // The files hold E_sum, E_max, T and kept, in this order; the rms is not recorded.
        let s = Solution {
            score: Score {
                e_sum: 2.5,
                e_max: 1.0,
                rms: 0.75,
                t: 6,
            },
            kept: vec![0, 2, 6, 8],
        };
        let json = serde_json::to_string(&s).unwrap();
        assert_eq!(json, r#"{"E_sum":2.5,"E_max":1.0,"T":6,"kept":[0,2,6,8]}"#);
        let read: Solution = serde_json::from_str(&json).unwrap();
        assert_eq!(read, s);
        assert!(read.rms.is_nan());
    }
}
