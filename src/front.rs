//! Solutions and the non-dominated front of (E, T), both minimised.

use serde::{Deserialize, Serialize};

/// One simplified mesh: its kept grid points and its objectives as the
/// [`Evaluator`](crate::evaluator::Evaluator) scores them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Solution {
    /// E = Σ over all grid points of |z − z̃|.
    #[serde(rename = "E_sum")]
    pub e_sum: f64,
    /// Largest |z − z̃| over all grid points.
    #[serde(rename = "E_max")]
    pub e_max: f64,
    /// Number of triangles.
    #[serde(rename = "T")]
    pub t: usize,
    /// Kept grid indices (y·W + x), increasing, corners included.
    pub kept: Vec<u32>,
}

impl Solution {
    /// The objective vector (E, T).
    pub fn objectives(&self) -> [f64; 2] {
        [self.e_sum, self.t as f64]
    }
}

/// Does `a` Pareto-dominate `b` (no worse in both objectives, better in one)? Minimisation.
pub fn dominates(a: [f64; 2], b: [f64; 2]) -> bool {
    a[0] <= b[0] && a[1] <= b[1] && (a[0] < b[0] || a[1] < b[1])
}

/// A set of mutually non-dominated solutions, sorted by increasing T (so decreasing E).
///
/// Solutions with identical objectives are kept once (the first one offered).
///
/// ```
/// use paretomesh::front::{Front, Solution};
/// let s = |e: f64, t: usize| Solution { e_sum: e, e_max: e, t, kept: vec![] };
/// let mut front = Front::default();
/// assert!(front.offer(s(10.0, 2)));
/// assert!(front.offer(s(4.0, 6)));
/// assert!(!front.offer(s(11.0, 6))); // dominated
/// assert!(front.offer(s(3.0, 4)));   // dominates (4, 6)
/// assert_eq!(front.solutions().iter().map(|s| s.t).collect::<Vec<_>>(), vec![2, 4]);
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Front {
    solutions: Vec<Solution>,
}

impl Front {
    /// Offers a solution; returns true when it enters the front (dominated members leave).
    pub fn offer(&mut self, s: Solution) -> bool {
        let o = s.objectives();
        if self
            .solutions
            .iter()
            .any(|m| m.objectives() == o || dominates(m.objectives(), o))
        {
            return false;
        }
        self.solutions.retain(|m| !dominates(o, m.objectives()));
        let at = self
            .solutions
            .partition_point(|m| (m.t, m.e_sum.to_bits()) < (s.t, s.e_sum.to_bits()));
        self.solutions.insert(at, s);
        true
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

    /// Merges solutions from any number of fronts or runs into one front.
    pub fn merged<'a>(solutions: impl IntoIterator<Item = &'a Solution>) -> Front {
        let mut f = Front::default();
        for s in solutions {
            f.offer(s.clone());
        }
        f
    }
}
