//! The interface every algorithm implements so it can run one slice at a time.
//!
//! An optimizer advances in *units* of work (one evaluation for the genetic algorithms, one
//! insertion or removal for the classical methods...), small enough that a browser frame can
//! always afford one. [`Optimizer::step`] does units until it has spent at least
//! `max_evaluations` evaluations or finished, so it overshoots by less than one unit. Every
//! algorithm documents its unit. How the work is sliced never changes the result: one call with a
//! large budget and many calls with small ones reach the identical state, because the state
//! only ever changes a whole unit at a time.

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
    /// Does one unit of work (the algorithm documents what that is); nothing once done.
    fn unit(&mut self);
    /// Does whole units of work until at least `max_evaluations` evaluations were spent in this
    /// call (at least one unit unless done), and reports.
    fn step(&mut self, max_evaluations: u64) -> Progress {
        let start = self.progress().evaluations;
        while !self.progress().done {
            self.unit();
            if self.progress().evaluations - start >= max_evaluations {
                break;
            }
        }
        self.progress()
    }
    /// Like [`Optimizer::step`], but also stops as soon as `generation` generations (or sweeps)
    /// are complete, so a re-run can stop exactly where a shared run stood. Stops at once, doing
    /// nothing, when they already are.
    fn step_until(&mut self, max_evaluations: u64, generation: u64) -> Progress {
        let start = self.progress().evaluations;
        loop {
            let p = self.progress();
            if p.done || p.generation >= generation {
                return p;
            }
            self.unit();
            if self.progress().evaluations - start >= max_evaluations {
                return self.progress();
            }
        }
    }
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
