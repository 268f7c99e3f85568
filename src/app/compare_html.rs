//! The compare panel's HTML: the rows of its three tables, the note that states the
//! normalisation, and the legend. Numbers and fixed labels only, so nothing needs escaping.

use super::compare::{CompareTable, METHODS, Picks};
use super::plot;
use crate::experiment::{Method, Pick};
use std::fmt::Write;

/// Okabe–Ito colours (distinguishable with the common colour-vision deficiencies), method `k`
/// of [`METHODS`] taking `COLOURS[k % COLOURS.len()]`; each method also has its own marker
/// shape.
pub(crate) const COLOURS: [&str; 8] = [
    "#0072B2", "#E69F00", "#009E73", "#CC79A7", "#000000", "#D55E00", "#56B4E9", "#F0E442",
];

/// Marker shapes, method `k` taking `SHAPES[k % SHAPES.len()]`, as the legend names them.
pub(crate) const SHAPES: [&str; 8] = ["●", "■", "▲", "◆", "★", "▼", "⬟", "✚"];

/// The colour of method `k` of [`METHODS`].
pub(crate) fn colour(k: usize) -> &'static str {
    COLOURS[k % COLOURS.len()]
}

/// The marker shape of method `k` of [`METHODS`].
pub(crate) fn shape(k: usize) -> &'static str {
    SHAPES[k % SHAPES.len()]
}

/// The short name of method `k` of [`METHODS`] for the tables (the legend gives the full
/// one), so that the tables fit the page's right column.
fn short(k: usize) -> &'static str {
    METHODS[k].algorithm.spec().short
}

/// Position of `m` in [`METHODS`] (the order of colours, shapes and fronts).
pub(crate) fn method_index(m: Method) -> usize {
    METHODS.iter().position(|&x| x == m).unwrap_or(0)
}

/// The three picks with their names, for marks and read-outs.
pub(crate) fn named_picks(p: &Picks) -> [(&'static str, Pick); 3] {
    [
        ("best error", p.best_error),
        ("fewest triangles", p.fewest_triangles),
        ("trade-off", p.trade_off),
    ]
}

/// A number for a cell: (shown with `digits` decimals, full precision for `data-value`); an
/// empty cell ("—", "") when there is no number yet.
fn fmt_opt(v: Option<f64>, digits: usize) -> (String, String) {
    match v {
        Some(x) => (format!("{x:.digits$}"), format!("{x}")),
        None => ("—".to_string(), String::new()),
    }
}

/// The rows of the three tables, as HTML (numbers and fixed labels only: nothing to escape).
/// Each number cell carries its full-precision value in `data-value`.
pub(crate) fn table_html(table: &CompareTable) -> (String, String, String) {
    let mut methods = String::new();
    let mut picks = String::new();
    let name = |m: Method| {
        let k = method_index(m);
        format!(
            "<span class=\"mark\" style=\"color:{}\">{}</span> {}",
            colour(k),
            shape(k),
            short(k)
        )
    };
    for row in &table.methods {
        let (hvr, hvr_value) = fmt_opt(row.hvr, 4);
        let _ = write!(
            methods,
            "<tr data-method=\"{}\"><th>{}</th><td>{}</td><td>{}</td><td>{}</td><td data-value=\"{hvr_value}\">{hvr}</td></tr>",
            row.method.name(),
            name(row.method),
            if row.done { "done" } else { "in progress" },
            row.evaluations,
            row.front_size,
        );
        let _ = write!(
            picks,
            "<tr data-method=\"{}\"><th>{}</th>",
            row.method.name(),
            name(row.method)
        );
        match &row.picks {
            Some(p) => {
                for (kind, pick) in named_picks(p) {
                    let _ = write!(
                        picks,
                        "<td class=\"pick\" data-pick=\"{kind}\" data-e=\"{}\" data-t=\"{}\" title=\"click to show this mesh\">{} / {}</td>",
                        pick.e,
                        pick.t,
                        plot::format_value(pick.e),
                        pick.t
                    );
                }
            }
            None => picks.push_str("<td>—</td><td>—</td><td>—</td>"),
        }
        picks.push_str("</tr>");
    }
    let mut pairs = String::new();
    for row in &table.pairs {
        let (eps, eps_value) = fmt_opt(row.epsilon, 4);
        let (cov, cov_value) = fmt_opt(row.coverage, 3);
        let _ = write!(
            pairs,
            "<tr data-a=\"{}\" data-b=\"{}\"><th>{}</th><th>{}</th><td data-value=\"{eps_value}\">{eps}</td><td data-value=\"{cov_value}\">{cov}</td></tr>",
            row.a.name(),
            row.b.name(),
            name(row.a),
            name(row.b),
        );
    }
    (methods, picks, pairs)
}

/// The note under the tables: the normalisation, reference point and front, the pick's seed,
/// and whether the table is final.
pub(crate) fn note_text(table: &CompareTable) -> String {
    let n = table.normalization;
    format!(
        "One normalisation for the five fronts: E ÷ {} (E of the corner-only mesh), T ÷ {} (the full \
         grid's triangles). HVR = hypervolume of the front ÷ that of the reference front (the \
         non-dominated merge of the five fronts, {} points), reference point ({}, {}). ε+ in \
         normalised units; C(A, B) = share of B's points weakly dominated by A's. Trade-off pick: \
         eq. 7–9 with 1000 weights from seed {}. The same computation as `paretomesh experiment`. {}",
        plot::format_value(n.e_scale()),
        n.t_scale(),
        table.reference_front_size,
        table.reference_point[0],
        table.reference_point[1],
        table.seed,
        if table.complete {
            "Final: all five methods are done."
        } else {
            "Live: updated at most 4 times a second until all five are done."
        }
    )
}

/// The legend under the compare plot.
pub(crate) fn legend_html() -> String {
    let mut html = String::new();
    for (k, m) in METHODS.iter().enumerate() {
        let _ = write!(
            html,
            "<li><span class=\"mark\" style=\"color:{}\">{}</span> {}</li>",
            colour(k),
            shape(k),
            m.label()
        );
    }
    html.push_str("<li><span class=\"ring\"></span> the three picks</li>");
    html
}
