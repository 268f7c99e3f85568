//! What the page's thread spends its time on: named spans of main-thread work (the frame's
//! steps, taking in the workers' fronts, handing out jobs), each with its count, total and
//! longest time. A benchmark reads them (`mainThreadCosts`) to tell which step holds frames up.

use serde::Serialize;
use std::cell::RefCell;
use std::collections::BTreeMap;

/// One span's record, in milliseconds.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub(super) struct Cost {
    /// Times it ran.
    pub count: u64,
    /// Milliseconds in all.
    pub total: f64,
    /// The longest run.
    pub max: f64,
}

thread_local! {
    static COSTS: RefCell<BTreeMap<&'static str, Cost>> = const { RefCell::new(BTreeMap::new()) };
}

/// Runs `f`, adding its time to span `name`.
pub(super) fn timed<T>(name: &'static str, f: impl FnOnce() -> T) -> T {
    let start = performance_now();
    let out = f();
    let took = performance_now() - start;
    COSTS.with(|c| {
        let mut c = c.borrow_mut();
        let cost = c.entry(name).or_default();
        cost.count += 1;
        cost.total += took;
        cost.max = cost.max.max(took);
    });
    out
}

/// Every span so far as JSON (`{name: {count, total, max}}`); `reset` starts afresh.
pub(super) fn report(reset: bool) -> String {
    COSTS.with(|c| {
        let mut c = c.borrow_mut();
        let text = serde_json::to_string(&*c).unwrap_or_default();
        if reset {
            c.clear();
        }
        text
    })
}

/// Milliseconds on the page's performance clock (0 without one).
pub(super) fn performance_now() -> f64 {
    web_sys::window()
        .and_then(|w| w.performance())
        .map_or(0.0, |p| p.now())
}
