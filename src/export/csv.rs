//! The front as CSV, as `paretomesh run --csv` and the browser app's export write it.

use crate::front::Solution;
use std::fmt::Write;

/// The header line of [`front_csv`].
pub(super) const HEADER: &str = "T,E_sum,E_max,kept";

/// One row per solution, in the order given (a front lists them by increasing T): triangles,
/// summed and largest vertical error, and the number of kept grid points.
pub fn front_csv<'a>(solutions: impl IntoIterator<Item = &'a Solution>) -> String {
    let mut s = format!("{HEADER}\n");
    for m in solutions {
        let _ = writeln!(s, "{},{},{},{}", m.t, m.e_sum, m.e_max, m.kept.len());
    }
    s
}
