//! The content of the teaching view's panel on the last orthogonal-array crossover: the array
//! (rows × factors, A = the block from parent A, B = from parent B), each row's child with its
//! fitness and objectives, the factor effects, the best-levels child, and which mesh each
//! thumbnail shows. The browser layer (`web::oax_panel`) puts it on the page.

use super::plot::format_value;
use crate::evolution::oax::{OaxChild, OaxRecord};
use crate::front::Solution;
use std::fmt::Write;

/// Every mesh the panel shows, in thumbnail order: parent A, parent B, the rows, best-levels.
pub(crate) fn meshes(record: &OaxRecord) -> Vec<Solution> {
    let parents = record.parents.iter().map(|(g, o)| (g, *o));
    let children = record
        .rows
        .iter()
        .chain(std::iter::once(&record.best_levels))
        .map(|c| (&c.genes, c.objectives));
    parents
        .chain(children)
        .map(|(genes, o)| Solution {
            score: o,
            kept: genes.indices(),
        })
        .collect()
}

fn levels(child: &OaxChild) -> String {
    child
        .levels
        .iter()
        .map(|&l| {
            format!(
                "<td class=\"lv{l}\">{}</td>",
                if l == 0 { 'A' } else { 'B' }
            )
        })
        .collect()
}

/// The panel's HTML for `record` (thumbnails are `<canvas data-mesh="k">`, drawn afterwards).
pub(crate) fn html(record: &OaxRecord) -> String {
    let factors = record.blocks.len();
    let m = record.array.rows();
    let mut h = String::new();
    let _ = write!(
        h,
        "<p class=\"small\">Array L<sub>{m}</sub>(2<sup>{}</sup>), {factors} factors (rectangular \
         blocks of the grid); scalar fitness F = w·E/E₀ + (1 − w)·T/T₀ with w = {:.3} (smaller \
         is better). ★ marks the two children kept.</p>",
        m - 1,
        record.weight
    );
    h.push_str(
        "<table class=\"oax\"><thead><tr><th>mesh</th><th></th><th>F</th><th>E</th><th>T</th>",
    );
    for f in 0..factors {
        let _ = write!(h, "<th>f{}</th>", f + 1);
    }
    h.push_str("</tr></thead><tbody>");
    for (k, name) in ["parent A", "parent B"].iter().enumerate() {
        let o = record.parents[k].1;
        let level = if k == 0 { 'A' } else { 'B' };
        let _ = write!(
            h,
            "<tr class=\"parent\"><td><canvas data-mesh=\"{k}\" title=\"show {name} in the 3-D view\"></canvas></td><th>{name}</th><td></td><td>{}</td><td class=\"t\">{}</td>{}</tr>",
            format_value(o.e_sum),
            o.t,
            format!("<td class=\"lv{k}\">{level}</td>").repeat(factors),
        );
    }
    let best = record.rows.len();
    for (i, child) in record
        .rows
        .iter()
        .chain(std::iter::once(&record.best_levels))
        .enumerate()
    {
        let star = if record.chosen.contains(&i) {
            " ★"
        } else {
            ""
        };
        let name = if i == best {
            "best levels".to_string()
        } else {
            format!("row {}", i + 1)
        };
        let class = if i == best { "best" } else { "row" };
        let _ = write!(
            h,
            "<tr class=\"{class}\"><td><canvas data-mesh=\"{}\" title=\"show {name} in the 3-D view\"></canvas></td><th>{name}{star}</th><td>{:.4}</td><td>{}</td><td class=\"t\">{}</td>{}</tr>",
            i + 2,
            child.fitness,
            format_value(child.objectives.e_sum),
            child.objectives.t,
            levels(child),
        );
    }
    for (l, label) in ["Σ F at A", "Σ F at B"].iter().enumerate() {
        let _ = write!(
            h,
            "<tr class=\"effects\"><td></td><th>{label}</th><td></td><td></td><td></td>"
        );
        for e in &record.effects {
            // The best level minimises F; ties go to A, as in the factor analysis.
            let best = usize::from(e[1] < e[0]);
            let better = l == best;
            let _ = write!(
                h,
                "<td{}>{:.2}</td>",
                if better { " class=\"chosen\"" } else { "" },
                e[l]
            );
        }
        h.push_str("</tr>");
    }
    h.push_str("</tbody></table>");
    h
}
