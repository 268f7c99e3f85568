//! `fronts-<dataset>.svg`: every method's merged front in one plot, E against T, hand-written SVG.
//!
//! Structure (stable, so tools and tests can read it): one `<g class="front"
//! data-method="NAME">` per method, then per outside front (dashed, with `data-external="true"`),
//! holding a `<polyline>` through its points by increasing T
//! and one `<circle>` per point; a `<g class="legend">` with one `<g class="legend-entry"
//! data-method="NAME">` each; `<text class="axis-label">` for both axes, with units.

use super::analysis::{DatasetAnalysis, MethodAnalysis};
use super::contender::Contender;
use super::results::DatasetResults;
use crate::xml::escape;
use std::fmt::Write;

const WIDTH: f64 = 800.0;
const HEIGHT: f64 = 480.0;
const LEFT: f64 = 90.0;
const RIGHT: f64 = 240.0;
const TOP: f64 = 40.0;
const BOTTOM: f64 = 60.0;

/// Colours of outside fronts, in order (the Okabe–Ito hues the methods do not use, then grey).
const EXTERNAL_COLOURS: [&str; 4] = ["#E69F00", "#56B4E9", "#000000", "#999999"];

/// A front's colour and, for an outside front, its dash pattern.
type Style = (&'static str, Option<&'static str>);

/// The colour of a front and, for outside fronts, the dash pattern that sets them apart.
/// `external` counts the outside fronts before this one.
fn style(c: &Contender, external: usize) -> Style {
    match c {
        Contender::Method(m) => (m.spec().colour, None),
        Contender::External(_) => (
            EXTERNAL_COLOURS[external % EXTERNAL_COLOURS.len()],
            Some("6 3"),
        ),
    }
}

/// Tick positions from 0 to at least `max`: 1, 2 or 5 times a power of ten, about 5 steps.
/// Returns the ticks; the last one is the axis end.
fn ticks(max: f64) -> Vec<f64> {
    let max = if max > 0.0 && max.is_finite() {
        max
    } else {
        1.0
    };
    let rough = max / 5.0;
    let power = 10f64.powf(rough.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|f| f * power)
        .find(|&s| s >= rough)
        .unwrap_or(10.0 * power);
    let n = (max / step).ceil() as usize;
    (0..=n).map(|i| i as f64 * step).collect()
}

/// A tick label: no trailing zeros, no exponent for the ranges plotted here.
fn tick_label(v: f64) -> String {
    let s = format!("{v:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s.is_empty() || s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// The SVG of `dataset`'s merged fronts (`analysis` must be its analysis).
pub fn fronts_svg(dataset: &DatasetResults, analysis: &DatasetAnalysis) -> String {
    let all = analysis.methods.iter().flat_map(|m| &m.merged);
    let (max_t, max_e) = all.fold((0.0f64, 0.0f64), |(t, e), s| {
        (t.max(s.t as f64), e.max(s.e_sum))
    });
    let (xt, yt) = (ticks(max_t), ticks(max_e));
    let plot = Plot {
        x_end: *xt.last().unwrap_or(&1.0),
        y_end: *yt.last().unwrap_or(&1.0),
        w: WIDTH - LEFT - RIGHT,
        h: HEIGHT - TOP - BOTTOM,
    };

    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" viewBox="0 0 {WIDTH} {HEIGHT}" font-family="sans-serif" font-size="12">"#
    );
    let _ = writeln!(
        s,
        r#"<title>Merged fronts of every method on {} ({}×{})</title>"#,
        escape(&dataset.name),
        dataset.grid.width,
        dataset.grid.height
    );
    let _ = writeln!(
        s,
        r#"<rect x="0" y="0" width="{WIDTH}" height="{HEIGHT}" fill="white"/>"#
    );
    let _ = writeln!(
        s,
        r#"<text class="title" x="{}" y="24" text-anchor="middle" font-size="15">Merged fronts on {} ({}×{})</text>"#,
        LEFT + plot.w / 2.0,
        escape(&dataset.name),
        dataset.grid.width,
        dataset.grid.height
    );
    // Grid lines and ticks, then the axes over them; one group per method, then per outside
    // front; the legend.
    axes(&mut s, &plot, &xt, &yt, &dataset.e_units);
    let styles: Vec<_> = analysis
        .methods
        .iter()
        .scan(0, |external, m| {
            let st = style(&m.method, *external);
            *external += usize::from(m.method.method().is_none());
            Some(st)
        })
        .collect();
    fronts(&mut s, &plot, &analysis.methods, &styles);
    legend(&mut s, &analysis.methods, &styles);
    let _ = writeln!(s, "</svg>");
    s
}

/// The plotting area: the axes' ends in data units and the area's size in pixels.
struct Plot {
    x_end: f64,
    y_end: f64,
    w: f64,
    h: f64,
}

impl Plot {
    /// The x pixel of `t` triangles.
    fn x(&self, t: f64) -> f64 {
        LEFT + t / self.x_end * self.w
    }

    /// The y pixel of an error `e`.
    fn y(&self, e: f64) -> f64 {
        TOP + self.h - e / self.y_end * self.h
    }
}

/// The grid lines at the ticks `xt` and `yt` with their labels, the axes, and the axis labels
/// (E in `e_units`).
fn axes(s: &mut String, plot: &Plot, xt: &[f64], yt: &[f64], e_units: &str) {
    let (plot_w, plot_h) = (plot.w, plot.h);
    let (x, y) = (|t| plot.x(t), |e| plot.y(e));
    let _ = writeln!(s, r#"<g class="ticks">"#);
    for &t in xt {
        let px = x(t);
        let _ = writeln!(
            s,
            r##"<line x1="{px:.2}" y1="{TOP}" x2="{px:.2}" y2="{:.2}" stroke="#ddd"/><text x="{px:.2}" y="{:.2}" text-anchor="middle">{}</text>"##,
            TOP + plot_h,
            TOP + plot_h + 18.0,
            tick_label(t)
        );
    }
    for &e in yt {
        let py = y(e);
        let _ = writeln!(
            s,
            r##"<line x1="{LEFT}" y1="{py:.2}" x2="{:.2}" y2="{py:.2}" stroke="#ddd"/><text x="{:.2}" y="{:.2}" text-anchor="end">{}</text>"##,
            LEFT + plot_w,
            LEFT - 6.0,
            py + 4.0,
            tick_label(e)
        );
    }
    let _ = writeln!(s, "</g>");
    let _ = writeln!(s, r##"<g class="axes" stroke="#444" stroke-width="1">"##);
    let _ = writeln!(
        s,
        r#"<line x1="{LEFT}" y1="{}" x2="{}" y2="{}"/>"#,
        TOP + plot_h,
        LEFT + plot_w,
        TOP + plot_h
    );
    let _ = writeln!(
        s,
        r#"<line x1="{LEFT}" y1="{TOP}" x2="{LEFT}" y2="{}"/>"#,
        TOP + plot_h
    );
    let _ = writeln!(s, "</g>");
    let _ = writeln!(
        s,
        r#"<text class="axis-label" data-axis="x" x="{:.2}" y="{:.2}" text-anchor="middle">T (triangles)</text>"#,
        LEFT + plot_w / 2.0,
        HEIGHT - 16.0
    );
    let _ = writeln!(
        s,
        r#"<text class="axis-label" data-axis="y" x="20" y="{:.2}" text-anchor="middle" transform="rotate(-90 20 {:.2})">E = Σ|z − z̃| ({})</text>"#,
        TOP + plot_h / 2.0,
        TOP + plot_h / 2.0,
        escape(e_units)
    );
}

/// One group per method's merged front (a polyline and its points) in its `styles` entry.
fn fronts(s: &mut String, plot: &Plot, methods: &[MethodAnalysis], styles: &[Style]) {
    let (x, y) = (|t| plot.x(t), |e| plot.y(e));
    for (m, &(colour, dash)) in methods.iter().zip(styles) {
        let _ = writeln!(
            s,
            r#"<g class="front" data-method="{}"{} stroke="{colour}" fill="{colour}">"#,
            escape(m.method.key()),
            if dash.is_some() {
                r#" data-external="true""#
            } else {
                ""
            }
        );
        let dash_attr = dash.map_or(String::new(), |d| format!(r#" stroke-dasharray="{d}""#));
        let points: Vec<String> = m
            .merged
            .iter()
            .map(|p| format!("{:.2},{:.2}", x(p.t as f64), y(p.e_sum)))
            .collect();
        let _ = writeln!(
            s,
            r#"<polyline fill="none" stroke-width="1.5"{dash_attr} points="{}"/>"#,
            points.join(" ")
        );
        for p in &m.merged {
            let _ = writeln!(
                s,
                r#"<circle cx="{:.2}" cy="{:.2}" r="2.5" stroke="none"/>"#,
                x(p.t as f64),
                y(p.e_sum)
            );
        }
        let _ = writeln!(s, "</g>");
    }
}

/// The legend: each method's line style, name and number of front points.
fn legend(s: &mut String, methods: &[MethodAnalysis], styles: &[Style]) {
    let lx = WIDTH - RIGHT + 20.0;
    let _ = writeln!(s, r#"<g class="legend">"#);
    for (i, (m, &(colour, dash))) in methods.iter().zip(styles).enumerate() {
        let ly = TOP + 10.0 + i as f64 * 22.0;
        let dash_attr = dash.map_or(String::new(), |d| format!(r#" stroke-dasharray="{d}""#));
        let _ = writeln!(
            s,
            r#"<g class="legend-entry" data-method="{}"><line x1="{lx}" y1="{ly}" x2="{}" y2="{ly}" stroke="{colour}" stroke-width="2"{dash_attr}/><circle cx="{}" cy="{ly}" r="3" fill="{colour}"/><text x="{}" y="{}">{} ({} points)</text></g>"#,
            escape(m.method.key()),
            lx + 24.0,
            lx + 12.0,
            lx + 32.0,
            ly + 4.0,
            escape(m.method.label()),
            m.merged.len()
        );
    }
    let _ = writeln!(s, "</g>");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(
            ticks(2048.0),
            vec![0.0, 500.0, 1000.0, 1500.0, 2000.0, 2500.0]
        );
        assert_eq!(
            ticks(1.0),
            vec![0.0, 0.2, 0.4, 0.6000000000000001, 0.8, 1.0]
        );
        // An empty plot still gets an axis.
        assert_eq!(ticks(0.0).last(), Some(&1.0));
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick_label(0.6000000000000001), "0.6");
        assert_eq!(tick_label(1500.0), "1500");
    }
}

#[cfg(test)]
mod figure_tests {
    use super::*;
    use crate::experiment::analysis::{Analysis, tests::sample_results};

    #[test]
    fn one_group_and_one_legend_entry_per_method_and_units_on_the_axis() {
        let results = sample_results();
        let analysis = Analysis::of(&results).unwrap();
        let svg = fronts_svg(&results.datasets[0], &analysis.datasets[0]);
        assert_eq!(svg.matches(r#"<g class="front""#).count(), 2);
        assert_eq!(svg.matches(r#"<g class="legend-entry""#).count(), 2);
        // NSGA-II's merged front has 3 points, greedy's 2.
        assert_eq!(svg.matches(r#"r="2.5" stroke="none""#).count(), 5);
        assert!(svg.contains("T (triangles)") && svg.contains("E = Σ|z − z̃| (m)"));
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    }
}
