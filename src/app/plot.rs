//! The 2-D plot of E against T as data: the data ↔ pixel mapping ([`Layout`]), ticks and value
//! labels, the marks of teaching and comparison scenes, and hit-testing. The canvas drawing is
//! in the browser layer (`web::plot_view`).

use crate::evaluator::Score;

/// One point to plot, in data units: T (triangles) and E (by default Σ|z − z̃|; see
/// [`EAxis`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PlotPoint {
    /// Triangles.
    pub t: f64,
    /// The error the E axis shows.
    pub e: f64,
}

/// Which error the plot's E axis shows; the front is the same in all three (a member of least
/// E_sum for its T), only its drawing changes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum EAxis {
    /// E_sum = Σ|z − z̃| over every grid point, the objective the methods minimise.
    #[default]
    Sum,
    /// E_sum / N, the mean error per grid point, in the surface's z units.
    Mean,
    /// E_max, the largest vertical error at any grid point, in the surface's z units.
    Max,
}

impl EAxis {
    /// The axis a key names (`sum`, `mean`, `max`), as the page's menu spells it.
    pub(crate) fn from_key(key: &str) -> Option<Self> {
        match key {
            "sum" => Some(Self::Sum),
            "mean" => Some(Self::Mean),
            "max" => Some(Self::Max),
            _ => None,
        }
    }

    /// The value of `score` on this axis, on a grid of `grid_points` points.
    pub(crate) fn value(self, score: &Score, grid_points: usize) -> f64 {
        match self {
            Self::Sum => score.e_sum,
            Self::Mean => score.e_sum / grid_points.max(1) as f64,
            Self::Max => score.e_max,
        }
    }

    /// The axis title, with the surface's z unit (`""` when unknown) and the scale.
    pub(crate) fn title(self, z_unit: &str, log: bool) -> String {
        let unit = if z_unit.is_empty() { "z units" } else { z_unit };
        let scale = if log { ", log scale" } else { "" };
        match self {
            Self::Sum => format!("E = Σ|z − z̃| ({unit}{scale})"),
            Self::Mean => format!("mean |z − z̃| ({unit}{scale})"),
            Self::Max => format!("E_max = max |z − z̃| ({unit}{scale})"),
        }
    }
}

/// The hover read-out of a member: T and its error as a sum, a mean per grid point and a
/// maximum, the last two in the surface's units.
pub(crate) fn hover_text(score: &Score, grid_points: usize, z_unit: &str) -> String {
    let unit = if z_unit.is_empty() {
        String::new()
    } else {
        format!(" {z_unit}")
    };
    format!(
        "T = {} · E_sum = {} · mean = {}{unit} · E_max = {}{unit}",
        score.t,
        format_value(score.e_sum),
        format_value(EAxis::Mean.value(score, grid_points)),
        format_value(score.e_max),
    )
}

/// Margins around the plotting area, in CSS pixels (room for tick labels and axis titles); the
/// left one grows with the widest E tick label (see [`Layout::area`]).
const MARGIN_LEFT: f64 = 64.0;
const MARGIN_RIGHT: f64 = 14.0;
const MARGIN_TOP: f64 = 12.0;
const MARGIN_BOTTOM: f64 = 42.0;
/// Tick labels are drawn in an 11 px font, this far from the plotting area.
pub(crate) const TICK_FONT_PX: f64 = 11.0;
/// The gap between a tick label and the plotting area.
pub(crate) const TICK_GAP: f64 = 4.0;
/// The rotated E-axis title's band: it starts this far from the canvas's left edge and is one
/// line (the font plus its descent) wide.
pub(crate) const E_TITLE_LEFT: f64 = 2.0;
/// Width of one line of axis-title text.
pub(crate) const TITLE_LINE: f64 = 15.0;
/// Clear space between the E-axis title and the widest tick label.
const TITLE_GAP: f64 = 4.0;

/// An upper bound of `text`'s width in CSS pixels at [`TICK_FONT_PX`] in a sans-serif font
/// (digits are about 6.1 px, capitals up to 9.5 px): the margin is sized from it, so a label
/// never reaches the axis title whatever the font renders.
pub(crate) fn label_width(text: &str) -> f64 {
    text.chars()
        .map(|c| if c.is_ascii_uppercase() { 10.0 } else { 7.0 })
        .sum()
}

/// How data maps to the canvas: the plotting rectangle and the data ranges it shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Layout {
    /// Canvas width in CSS pixels.
    pub width: f64,
    /// Canvas height in CSS pixels.
    pub height: f64,
    /// Shown T range (min, max), max > min.
    pub t_range: (f64, f64),
    /// Shown E range (min, max) in axis units (E, or log10 E with [`Layout::log_e`]), max > min.
    pub e_range: (f64, f64),
    /// E axis logarithmic: errors spanning decades stay readable.
    pub log_e: bool,
    /// On a log axis, E below this (E = 0 included) is drawn at this value.
    e_floor: f64,
    /// The left margin: room for the E-axis title and the widest E tick label.
    margin_left: f64,
}

impl Layout {
    /// A layout of a `width` × `height` canvas that shows every point with 5 % padding, E on a
    /// linear axis. An empty or degenerate set gets a unit range so the mapping stays finite.
    pub(crate) fn fit<'a>(
        width: f64,
        height: f64,
        points: impl IntoIterator<Item = &'a PlotPoint>,
    ) -> Self {
        Self::fit_scaled(width, height, points, false)
    }

    /// Like [`Layout::fit`], with E on a log axis when `log_e`. E = 0 (the full mesh) is drawn at
    /// half the smallest positive E.
    pub(crate) fn fit_scaled<'a>(
        width: f64,
        height: f64,
        points: impl IntoIterator<Item = &'a PlotPoint>,
        log_e: bool,
    ) -> Self {
        let points: Vec<PlotPoint> = points.into_iter().copied().collect();
        let e_floor = points
            .iter()
            .map(|p| p.e)
            .filter(|&e| e > 0.0)
            .fold(f64::INFINITY, f64::min);
        let e_floor = if e_floor.is_finite() {
            e_floor / 2.0
        } else {
            1.0
        };
        let mut layout = Self {
            width,
            height,
            t_range: (0.0, 1.0),
            e_range: (0.0, 1.0),
            log_e,
            e_floor,
            margin_left: MARGIN_LEFT,
        };
        let (mut t0, mut t1, mut e0, mut e1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for p in &points {
            let e = layout.axis_e(p.e);
            t0 = t0.min(p.t);
            t1 = t1.max(p.t);
            e0 = e0.min(e);
            e1 = e1.max(e);
        }
        let pad = |lo: f64, hi: f64, floor: Option<f64>| -> (f64, f64) {
            if !lo.is_finite() || !hi.is_finite() {
                return (floor.unwrap_or(0.0), floor.unwrap_or(0.0) + 1.0);
            }
            let span = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
            let low = lo - 0.05 * span;
            (floor.map_or(low, |f| low.max(f)), hi + 0.05 * span)
        };
        layout.t_range = pad(t0, t1, Some(0.0));
        layout.e_range = pad(e0, e1, (!log_e).then_some(0.0));
        let widest = layout
            .e_ticks()
            .iter()
            .map(|&v| label_width(&format_value(v)))
            .fold(0.0, f64::max);
        layout.margin_left =
            MARGIN_LEFT.max(E_TITLE_LEFT + TITLE_LINE + TITLE_GAP + widest + TICK_GAP);
        layout
    }

    /// E in axis units.
    fn axis_e(&self, e: f64) -> f64 {
        if self.log_e {
            e.max(self.e_floor).log10()
        } else {
            e
        }
    }

    /// Tick values for the E axis, in E (not axis) units.
    pub(crate) fn e_ticks(&self) -> Vec<f64> {
        if !self.log_e {
            return ticks(self.e_range.0, self.e_range.1, 5);
        }
        let (lo, hi) = self.e_range;
        let mut out = Vec::new();
        for k in lo.floor() as i32..=hi.ceil() as i32 {
            for m in [1.0, 2.0, 5.0] {
                let v = m * 10f64.powi(k);
                let a = v.log10();
                // 2 and 5 only when the axis spans less than two decades.
                if a >= lo && a <= hi && (m == 1.0 || hi - lo < 2.0) {
                    out.push(v);
                }
            }
        }
        out
    }

    /// The plotting rectangle: (left, top, right, bottom) in CSS pixels.
    pub(crate) fn area(&self) -> (f64, f64, f64, f64) {
        (
            self.margin_left,
            MARGIN_TOP,
            (self.width - MARGIN_RIGHT).max(self.margin_left + 1.0),
            (self.height - MARGIN_BOTTOM).max(MARGIN_TOP + 1.0),
        )
    }

    /// Pixel position of a data point (T to the right, E upwards).
    pub(crate) fn to_pixel(self, p: PlotPoint) -> (f64, f64) {
        let (l, t, r, b) = self.area();
        let x = l + (p.t - self.t_range.0) / (self.t_range.1 - self.t_range.0) * (r - l);
        let y =
            b - (self.axis_e(p.e) - self.e_range.0) / (self.e_range.1 - self.e_range.0) * (b - t);
        (x, y)
    }
}

/// Index of the point nearest to pixel (`x`, `y`) within `radius` pixels, if any. Ties go to
/// the lower index, so the answer is deterministic.
pub(crate) fn hit_test(
    layout: &Layout,
    points: &[PlotPoint],
    x: f64,
    y: f64,
    radius: f64,
) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (i, p) in points.iter().enumerate() {
        let (px, py) = layout.to_pixel(*p);
        let d2 = (px - x).powi(2) + (py - y).powi(2);
        if d2 <= radius * radius && best.is_none_or(|(_, b)| d2 < b) {
            best = Some((i, d2));
        }
    }
    best.map(|(i, _)| i)
}

/// "Nice" tick values covering `lo..=hi`: about `count` steps of 1, 2 or 5 × 10^k.
pub(crate) fn ticks(lo: f64, hi: f64, count: usize) -> Vec<f64> {
    if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) || count == 0 {
        return vec![lo];
    }
    let raw = (hi - lo) / count as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() * step;
    let mut out = Vec::new();
    let mut v = first;
    while v <= hi + step * 1e-9 {
        out.push(if v.abs() < step * 1e-9 { 0.0 } else { v });
        v += step;
    }
    out
}

/// A compact label for a tick value (1.2k, 35, 0.5, 1.05G).
pub(crate) fn format_value(v: f64) -> String {
    let a = v.abs();
    let trimmed = |x: f64| {
        format!("{x:.3}")
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    };
    if a >= 1e9 {
        trimmed(v / 1e9) + "G"
    } else if a >= 1e6 {
        trimmed(v / 1e6) + "M"
    } else if a >= 1e4 {
        format!("{:.1}k", v / 1e3)
    } else if a >= 100.0 || v == v.round() {
        format!("{v:.0}")
    } else {
        format!("{v:.3}")
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    }
}

/// Colour of non-domination rank `rank` (0 = first front).
pub(crate) fn rank_colour(rank: usize) -> &'static str {
    const PALETTE: [&str; 6] = [
        "#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#bcbd22", "#7f7f7f",
    ];
    PALETTE[rank.min(PALETTE.len() - 1)]
}

/// Everything the plot shows in one frame.
pub(crate) struct Scene<'a> {
    /// The population with its non-domination ranks (empty for non-population methods).
    pub population: &'a [(PlotPoint, usize)],
    /// The archive front, by increasing T.
    pub front: &'a [PlotPoint],
    /// Index into `front` of the selection.
    pub selected: Option<usize>,
    /// Index into `front` under the mouse.
    pub hovered: Option<usize>,
    /// Unit of z, for the E axis title ("" when unknown).
    pub z_unit: &'a str,
    /// Which error the E axis shows.
    pub e_axis: EAxis,
    /// The hover read-out of each member of `front` (empty: T and E alone).
    pub labels: &'a [String],
}

/// The shape of a [`Mark`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Shape {
    /// A dot.
    Circle,
    /// A square.
    Square,
    /// A diamond.
    Diamond,
    /// An upward triangle.
    Triangle,
    /// An ×.
    Cross,
}

/// One styled point of a teaching or comparison scene.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Mark {
    /// Where, in data units.
    pub point: PlotPoint,
    /// CSS colour.
    pub colour: &'static str,
    /// Shape.
    pub shape: Shape,
    /// Half-size in CSS pixels.
    pub radius: f64,
    /// Filled, or only outlined.
    pub filled: bool,
    /// Width of a black ring around it (0: none), e.g. how often a parent was picked.
    pub ring: f64,
    /// Read-out text on hover.
    pub label: String,
}

/// Index of the mark nearest to pixel (`x`, `y`) within `radius` pixels, if any (the topmost,
/// i.e. the last drawn, on ties).
pub(crate) fn hit_test_marks(
    layout: &Layout,
    marks: &[Mark],
    x: f64,
    y: f64,
    radius: f64,
) -> Option<usize> {
    // Reversed, so that hit_test's tie rule (lower index) picks the last drawn.
    let points: Vec<PlotPoint> = marks.iter().rev().map(|m| m.point).collect();
    hit_test(layout, &points, x, y, radius).map(|i| marks.len() - 1 - i)
}
