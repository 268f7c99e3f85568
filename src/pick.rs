//! Choosing one member of a front: by index, the paper's trade-off pick, the knee, or the best
//! member under a limit on triangles or on an error. The CLI's `export`, the app and the Python
//! package all pick through [`pick`], so one rule gives one member everywhere.
//!
//! Members are given as their scores in any order (a front.json's order, or a [`Front`]'s);
//! the answer is an index into that slice. Ties always go to the secondary objective, then to
//! the earlier member, so a pick depends on the scores alone.
//!
//! [`Front`]: crate::front::Front

use crate::evaluator::Score;
use crate::front::{Front, Solution};
use crate::metrics::trade_off_pick;
use std::cmp::Ordering;
use std::fmt;

/// How a member is chosen.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pick {
    /// The member at this index of the slice given.
    Index(usize),
    /// The paper's trade-off pick (eq. 7–9), its random weights drawn with the given seed.
    TradeOff,
    /// The knee: the member nearest the ideal point of the normalised front (see [`knee`]).
    Knee,
    /// The lowest E_sum among members with at most this many triangles.
    MaxTriangles(usize),
    /// The fewest triangles among members with E_sum (the sum over every grid point) at most
    /// this.
    MaxErrorSum(f64),
    /// The fewest triangles among members with E_sum / N (the mean error per grid point, in the
    /// surface's units) at most this.
    MaxMeanError(f64),
    /// The fewest triangles among members with E_max (the largest vertical error at any grid
    /// point, in the surface's units) at most this.
    MaxVerticalError(f64),
}

/// Why no member could be picked. The message says what the front has on offer.
#[derive(Clone, Debug, PartialEq)]
pub enum PickError {
    /// There are no members.
    Empty,
    /// The index is past the last member.
    IndexOutOfRange { index: usize, members: usize },
    /// A limit is negative or not a number.
    BadLimit { what: &'static str, limit: f64 },
    /// No member has at most this many triangles.
    TooFewTriangles { limit: usize, fewest: usize },
    /// No member's error (named by `what`) is within the limit; `least` is the smallest on
    /// offer.
    ErrorTooSmall {
        what: &'static str,
        limit: f64,
        least: f64,
    },
    /// The trade-off pick could not be made (a score is negative or not finite).
    TradeOff(String),
}

impl fmt::Display for PickError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Empty => write!(f, "the front has no members to pick from"),
            Self::IndexOutOfRange { index, members } => write!(
                f,
                "member {index} is out of range: the front has {members} members, numbered 0 to {}",
                members.saturating_sub(1)
            ),
            Self::BadLimit { what, limit } => write!(
                f,
                "the limit on {what} must be a number at least 0, got {limit}"
            ),
            Self::TooFewTriangles { limit, fewest } => write!(
                f,
                "no member has at most {limit} triangles: the smallest member has {fewest}"
            ),
            Self::ErrorTooSmall { what, limit, least } => write!(
                f,
                "no member has {what} at most {limit}: the smallest {what} on offer is {least}"
            ),
            Self::TradeOff(why) => write!(f, "no trade-off pick: {why}"),
        }
    }
}

impl std::error::Error for PickError {}

/// The index in `members` of the member `rule` picks. `seed` draws the trade-off pick's weights
/// (the run's seed, as the experiment draws them); `grid_points` is N, the number of grid
/// points, which turns E_sum into the mean error.
pub fn pick(
    members: &[Score],
    rule: Pick,
    seed: u64,
    grid_points: usize,
) -> Result<usize, PickError> {
    if members.is_empty() {
        return Err(PickError::Empty);
    }
    let n = grid_points.max(1) as f64;
    match rule {
        Pick::Index(index) if index < members.len() => Ok(index),
        Pick::Index(index) => Err(PickError::IndexOutOfRange {
            index,
            members: members.len(),
        }),
        Pick::TradeOff => {
            let points: Vec<[f64; 2]> = members.iter().map(Score::objectives).collect();
            trade_off_pick(&points, seed)
                .map(|p| p.index)
                .map_err(|e| PickError::TradeOff(e.to_string()))
        }
        Pick::Knee => Ok(knee(members)),
        Pick::MaxTriangles(limit) => {
            first_min(members, |s| s.t <= limit, by_e_then_t).ok_or(PickError::TooFewTriangles {
                limit,
                fewest: members.iter().map(|s| s.t).min().unwrap_or(0),
            })
        }
        Pick::MaxErrorSum(limit) => fewest_within(members, "E_sum", limit, |s| s.e_sum),
        Pick::MaxMeanError(limit) => fewest_within(members, "mean error", limit, |s| s.e_sum / n),
        Pick::MaxVerticalError(limit) => fewest_within(members, "E_max", limit, |s| s.e_max),
    }
}

/// The member of `front` that `rule` picks (see [`pick`]).
pub(crate) fn pick_in_front(
    front: &Front,
    rule: Pick,
    seed: u64,
    grid_points: usize,
) -> Result<&Solution, PickError> {
    let scores: Vec<Score> = front.solutions().iter().map(|s| s.score).collect();
    pick(&scores, rule, seed, grid_points).map(|i| &front.solutions()[i])
}

/// The knee of a front: each objective is scaled to [0, 1] over the members (E by its range,
/// T by its range; an objective every member shares counts 0), and the member nearest the
/// ideal point (0, 0) in that plane wins. Ties go to the fewer triangles, then the lower
/// E_sum, then the earlier member. An empty slice gives 0.
///
/// On a front this is the member that gives up least of either objective relative to what the
/// front spans: not the full mesh (no error, every triangle) and not the corners-only mesh,
/// but the bend of the curve between them.
pub fn knee(members: &[Score]) -> usize {
    let range = |f: fn(&Score) -> f64| {
        let lo = members.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = members.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
        (lo, hi - lo)
    };
    let e = |s: &Score| s.e_sum;
    let t = |s: &Score| s.t as f64;
    let ((e0, de), (t0, dt)) = (range(e), range(t));
    let scaled = |v: f64, lo: f64, span: f64| if span > 0.0 { (v - lo) / span } else { 0.0 };
    let distance = |s: &Score| scaled(e(s), e0, de).hypot(scaled(t(s), t0, dt));
    (0..members.len())
        .min_by(|&i, &j| {
            let (a, b) = (&members[i], &members[j]);
            distance(a).total_cmp(&distance(b)).then(by_t_then_e(a, b))
        })
        .unwrap_or(0)
}

/// The member with the fewest triangles among those whose `error` is at most `limit`.
fn fewest_within(
    members: &[Score],
    what: &'static str,
    limit: f64,
    error: impl Fn(&Score) -> f64,
) -> Result<usize, PickError> {
    if limit.is_nan() || limit < 0.0 {
        return Err(PickError::BadLimit { what, limit });
    }
    first_min(members, |s| error(s) <= limit, by_t_then_e).ok_or_else(|| PickError::ErrorTooSmall {
        what,
        limit,
        least: members.iter().map(&error).fold(f64::INFINITY, f64::min),
    })
}

/// The first member (in the slice's order) that is smallest by `order` among those `allowed`.
fn first_min(
    members: &[Score],
    allowed: impl Fn(&Score) -> bool,
    order: fn(&Score, &Score) -> Ordering,
) -> Option<usize> {
    (0..members.len())
        .filter(|&i| allowed(&members[i]))
        .min_by(|&i, &j| order(&members[i], &members[j]))
}

fn by_t_then_e(a: &Score, b: &Score) -> Ordering {
    a.t.cmp(&b.t).then(a.e_sum.total_cmp(&b.e_sum))
}

fn by_e_then_t(a: &Score, b: &Score) -> Ordering {
    a.e_sum.total_cmp(&b.e_sum).then(a.t.cmp(&b.t))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn member(e_sum: f64, e_max: f64, t: usize) -> Score {
        Score {
            e_sum,
            e_max,
            rms: f64::NAN,
            t,
        }
    }

    fn pick1(members: &[Score], rule: Pick) -> Result<usize, PickError> {
        pick(members, rule, 1, 10)
    }

    #[test]
    fn limits_pick_by_their_rule_in_the_slices_order() {
        // Not sorted by T, with a tie in E under the triangle limit and a tie in T under the
        // error limits: the secondary objective decides, then the earlier member.
        let members = [
            member(5.0, 1.0, 10),
            member(9.0, 3.0, 4),
            member(5.0, 2.0, 8),
            member(2.0, 0.5, 30),
            member(5.0, 2.0, 8),
        ];
        assert_eq!(pick1(&members, Pick::Index(3)), Ok(3));
        assert_eq!(pick1(&members, Pick::MaxTriangles(10)), Ok(2));
        assert_eq!(pick1(&members, Pick::MaxTriangles(4)), Ok(1));
        assert_eq!(pick1(&members, Pick::MaxTriangles(1000)), Ok(3));
        assert_eq!(pick1(&members, Pick::MaxErrorSum(5.0)), Ok(2));
        assert_eq!(pick1(&members, Pick::MaxErrorSum(100.0)), Ok(1));
        assert_eq!(pick1(&members, Pick::MaxErrorSum(2.0)), Ok(3));
        // N = 10 grid points: mean errors 0.5, 0.9, 0.5, 0.2, 0.5.
        assert_eq!(pick1(&members, Pick::MaxMeanError(0.5)), Ok(2));
        assert_eq!(pick1(&members, Pick::MaxMeanError(0.3)), Ok(3));
        assert_eq!(pick1(&members, Pick::MaxVerticalError(3.0)), Ok(1));
        assert_eq!(pick1(&members, Pick::MaxVerticalError(2.0)), Ok(2));
        assert_eq!(pick1(&members, Pick::MaxVerticalError(1.5)), Ok(0));
        assert_eq!(pick1(&members, Pick::MaxVerticalError(0.5)), Ok(3));
    }

    #[test]
    fn picks_that_find_nothing_say_what_the_front_has() {
        let members = [member(5.0, 1.5, 10), member(9.0, 2.0, 4)];
        let text = |rule| pick1(&members, rule).unwrap_err().to_string();
        let out = text(Pick::Index(2));
        assert!(out.contains("2 members, numbered 0 to 1"), "{out}");
        let out = text(Pick::MaxTriangles(3));
        assert!(
            out.contains("at most 3 triangles") && out.contains("has 4"),
            "{out}"
        );
        let out = text(Pick::MaxErrorSum(4.5));
        assert!(
            out.contains("E_sum at most 4.5") && out.contains("is 5"),
            "{out}"
        );
        let out = text(Pick::MaxVerticalError(1.0));
        assert!(
            out.contains("E_max at most 1") && out.contains("smallest E_max on offer is 1.5"),
            "{out}"
        );
        let out = text(Pick::MaxMeanError(0.1));
        assert!(out.contains("mean error on offer is 0.5"), "{out}");
        let out = text(Pick::MaxVerticalError(-1.0));
        assert!(out.contains("at least 0, got -1"), "{out}");
        assert_eq!(pick1(&[], Pick::Knee), Err(PickError::Empty));
    }

    #[test]
    fn the_trade_off_rule_is_the_metrics_pick() {
        let members = [
            member(100.0, 9.0, 2),
            member(20.0, 3.0, 10),
            member(5.0, 1.0, 40),
            member(1.0, 0.1, 200),
        ];
        let points: Vec<[f64; 2]> = members.iter().map(Score::objectives).collect();
        for seed in [1, 7] {
            let expected = trade_off_pick(&points, seed).unwrap().index;
            assert_eq!(pick(&members, Pick::TradeOff, seed, 10), Ok(expected));
        }
    }

    #[test]
    fn the_knee_is_the_bend_of_the_front() {
        // Normalised: (1, 0), (0.25, 0.0408), (0.05, 0.1429), (0, 1): the third is nearest
        // (0, 0) (0.151 against 0.253 for the second).
        let members = [
            member(100.0, 9.0, 2),
            member(25.0, 3.0, 10),
            member(5.0, 1.0, 30),
            member(0.0, 0.0, 198),
        ];
        assert_eq!(knee(&members), 2);
        // The order of the slice does not matter, only the scores.
        let reversed: Vec<Score> = members.iter().rev().copied().collect();
        assert_eq!(knee(&reversed), 1);
        // A single member, and members equal in one objective.
        assert_eq!(knee(&members[..1]), 0);
        let flat = [member(3.0, 1.0, 8), member(3.0, 1.0, 4)];
        assert_eq!(knee(&flat), 1);
        assert_eq!(pick1(&members, Pick::Knee), Ok(2));
    }
}
