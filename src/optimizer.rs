//! The interface every algorithm implements so it can run one slice at a time.
//!
//! An optimizer advances by at most `max_evaluations` evaluations per [`Optimizer::step`] call and
//! can report its front at any moment. How the work is sliced never changes the result: one call
//! with a large budget and many calls with small ones reach the identical state.

use crate::front::Front;

/// What a [`Optimizer::step`] call reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// Evaluations done since the start.
    pub evaluations: u64,
    /// Generations (or sweeps, for the classical methods) completed since the start.
    pub generation: u64,
    /// True once the algorithm has finished; further steps do nothing.
    pub done: bool,
}

/// An algorithm that produces a front of (E, T), advanced in bounded slices.
pub trait Optimizer {
    /// Does at most `max_evaluations` evaluations (at least one unless done) and reports.
    fn step(&mut self, max_evaluations: u64) -> Progress;
    /// The best front found so far.
    fn front(&self) -> &Front;
    /// The current state without stepping.
    fn progress(&self) -> Progress;
    /// Runs to the end.
    fn run_to_end(&mut self) -> Progress {
        loop {
            let p = self.step(u64::MAX);
            if p.done {
                return p;
            }
        }
    }
}
