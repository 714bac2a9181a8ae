//! The convergence plot of the optimisers: best error per iteration of each run (GA, PSO, GSA,
//! LM, ...; `optimization.history` of `report.json`) on a log scale, as a [`Drawing`] that the
//! PNG rasteriser and the SVG writer both take.
//!
//! Axes: x is the iteration (index into the history, from 0), linear with round ticks; y is the
//! error on a log10 scale from the decade below the smallest positive value to the decade above
//! the largest, a labelled grid line at each decade (`10⁻³`) and unlabelled ticks at `2..9 x
//! 10^e` when the plot spans at most 6 decades:
//!
//! ```text
//! X(i) = left + (right - left) i / i_max        Y(v) = bottom + (top - bottom) (log10 v - e_lo) / (e_hi - e_lo)
//! ```
//!
//! Values that a log scale cannot show (zero, negative, NaN, infinite) break the line; a lone
//! point between breaks is drawn as a dot.

use crate::drawing::{Anchor, Drawing, Item, Rgb, Stroke};

use super::raster::text_width_mm;
use crate::drawing::{format_tick, nice_ticks, power_of_ten};
use hull::format_sig;

/// Sheet size in millimetres (fits an A4 page with margins).
const WIDTH_MM: f64 = 200.0;
const HEIGHT_MM: f64 = 130.0;
/// Plot area: left, right, bottom, top edges in millimetres.
const LEFT: f64 = 24.0;
const RIGHT: f64 = WIDTH_MM - 6.0;
const BOTTOM: f64 = 18.0;
const TOP: f64 = HEIGHT_MM - 16.0;
/// Text heights (capital height) in millimetres.
const TITLE_MM: f64 = 4.0;
const LABEL_MM: f64 = 2.6;
/// Series line width in millimetres.
const LINE_MM: f64 = 0.45;

/// One colour per series: the Okabe–Ito palette, distinguishable with the common colour-vision
/// deficiencies (Okabe & Ito, "Color Universal Design", 2008), yellow left out (too pale on
/// white); it repeats after seven series.
pub(crate) const PALETTE: [Rgb; 7] = [
    Rgb(0, 114, 178),
    Rgb(213, 94, 0),
    Rgb(0, 158, 115),
    Rgb(204, 121, 167),
    Rgb(230, 159, 0),
    Rgb(86, 180, 233),
    Rgb(0, 0, 0),
];

fn text(at: [f64; 2], s: impl Into<String>, size_mm: f64, anchor: Anchor, layer: &str) -> Item {
    Item::Text { at, text: s.into(), size_mm, anchor, color: Rgb::BLACK, layer: layer.into() }
}

fn segment(a: [f64; 2], b: [f64; 2], stroke: Stroke, layer: &str) -> Item {
    Item::Polyline { points: vec![a, b], closed: false, stroke, layer: layer.into() }
}

/// The convergence plot of `series` (name, best error per iteration), errors in `units`
/// (e.g. `m`; empty for none). A 200 x 130 mm sheet with layers `frame`, `grid`, `axes`,
/// `series`, `legend`, `title`; the legend gives each series' last value.
///
/// Never fails: series without a positive finite value are listed in the legend only, and a
/// plot without any shows the decades `10⁻³..10⁰` and the note "no positive values".
pub fn convergence_plot(series: &[(&str, &[f64])], title: &str, units: &str) -> Drawing {
    let mut d = Drawing::new(WIDTH_MM, HEIGHT_MM, title);
    let shown = |v: f64| v.is_finite() && v > 0.0;
    let values = series.iter().flat_map(|(_, s)| s.iter().copied()).filter(|&v| shown(v));
    let (vmin, vmax) = values.fold((f64::INFINITY, 0.0f64), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let (e_lo, mut e_hi) = if vmax > 0.0 { (vmin.log10().floor() as i32, vmax.log10().ceil() as i32) } else { (-3, 0) };
    if e_hi <= e_lo {
        e_hi = e_lo + 1;
    }
    let i_max = series.iter().map(|(_, s)| s.len()).max().unwrap_or(0).saturating_sub(1).max(1) as f64;
    let x_of = |i: f64| LEFT + (RIGHT - LEFT) * i / i_max;
    let y_of = |v: f64| BOTTOM + (TOP - BOTTOM) * (v.log10() - e_lo as f64) / (e_hi - e_lo) as f64;

    // Grid and y ticks: a line per decade, labels thinned to at most 8.
    let grid = Stroke::solid(Rgb(215, 215, 215), 0.15);
    let tick = Stroke::solid(Rgb::BLACK, 0.2);
    let label_every = ((e_hi - e_lo) as f64 / 8.0).ceil().max(1.0) as i32;
    for e in e_lo..=e_hi {
        let y = y_of(10f64.powi(e));
        d.push(segment([LEFT, y], [RIGHT, y], grid.clone(), "grid"));
        d.push(segment([LEFT - 1.5, y], [LEFT, y], tick.clone(), "axes"));
        if (e - e_lo) % label_every == 0 {
            d.push(text([LEFT - 2.5, y - 0.5 * LABEL_MM], power_of_ten(e), LABEL_MM, Anchor::End, "axes"));
        }
        if e_hi - e_lo <= 6 && e < e_hi {
            for m in 2..=9 {
                let y = y_of(m as f64 * 10f64.powi(e));
                d.push(segment([LEFT - 0.8, y], [LEFT, y], tick.clone(), "axes"));
            }
        }
    }
    // x ticks: round iteration numbers.
    let (mut xs, mut step) = nice_ticks(0.0, i_max, 6);
    if step < 1.0 {
        (xs, step) = ((0..=i_max as usize).map(|i| i as f64).collect(), 1.0);
    }
    for &i in &xs {
        let x = x_of(i);
        d.push(segment([x, BOTTOM], [x, TOP], grid.clone(), "grid"));
        d.push(segment([x, BOTTOM - 1.5], [x, BOTTOM], tick.clone(), "axes"));
        d.push(text([x, BOTTOM - 2.5 - LABEL_MM], format_tick(i, step), LABEL_MM, Anchor::Middle, "axes"));
    }
    d.push(text([0.5 * (LEFT + RIGHT), 4.0], "iteration", LABEL_MM, Anchor::Middle, "axes"));
    let y_label = if units.is_empty() { "best error".to_string() } else { format!("best error ({units})") };
    d.push(text([LEFT - 8.0, TOP + 3.0], y_label, LABEL_MM, Anchor::Start, "axes"));
    d.push(Item::Polyline {
        points: vec![[LEFT, BOTTOM], [RIGHT, BOTTOM], [RIGHT, TOP], [LEFT, TOP]],
        closed: true,
        stroke: Stroke::solid(Rgb::BLACK, 0.25),
        layer: "frame".into(),
    });
    d.push(text([0.5 * WIDTH_MM, HEIGHT_MM - 8.0], title, TITLE_MM, Anchor::Middle, "title"));
    if vmax <= 0.0 {
        d.push(text(
            [0.5 * (LEFT + RIGHT), 0.5 * (BOTTOM + TOP)],
            "no positive values",
            LABEL_MM,
            Anchor::Middle,
            "title",
        ));
    }

    // The series: runs of plottable values as polylines, lone points as dots.
    for (k, (_, values)) in series.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        let mut runs: Vec<Vec<[f64; 2]>> = vec![Vec::new()];
        for (i, &v) in values.iter().enumerate() {
            match runs.last_mut() {
                Some(run) if shown(v) => run.push([x_of(i as f64), y_of(v)]),
                Some(run) if !run.is_empty() => runs.push(Vec::new()),
                _ => {}
            }
        }
        for run in runs.into_iter().filter(|r| !r.is_empty()) {
            if run.len() == 1 {
                d.push(Item::Marker { at: run[0], size_mm: 1.2, fill: color, layer: "series".into() });
            } else {
                d.push(Item::Polyline {
                    points: run,
                    closed: false,
                    stroke: Stroke::solid(color, LINE_MM),
                    layer: "series".into(),
                });
            }
        }
    }
    legend(&mut d, series, units);
    d
}

/// The legend in the top-right corner of the plot: a line sample, the name and the last value.
fn legend(d: &mut Drawing, series: &[(&str, &[f64])], units: &str) {
    if series.is_empty() {
        return;
    }
    let row = 1.8 * LABEL_MM;
    let sample = 7.0;
    let labels: Vec<String> = series
        .iter()
        .enumerate()
        .map(|(k, (name, values))| {
            let name = if name.is_empty() { format!("series {}", k + 1) } else { name.to_string() };
            match values.last() {
                Some(&v) if units.is_empty() => format!("{name}: {}", format_sig(v, 3)),
                Some(&v) => format!("{name}: {} {units}", format_sig(v, 3)),
                None => format!("{name}: no data"),
            }
        })
        .collect();
    let text_w = labels.iter().map(|l| text_width_mm(l, LABEL_MM)).fold(0.0, f64::max);
    let (w, h) = (sample + 4.0 + text_w + 2.0, row * labels.len() as f64 + 1.5);
    let (x1, y1) = (RIGHT - 2.0, TOP - 2.0);
    let (x0, y0) = (x1 - w, y1 - h);
    let corners = vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]];
    d.push(Item::Polygon { points: corners.clone(), fill: Rgb::WHITE, layer: "legend".into() });
    d.push(Item::Polyline {
        points: corners,
        closed: true,
        stroke: Stroke::solid(Rgb(160, 160, 160), 0.15),
        layer: "legend".into(),
    });
    for (k, label) in labels.into_iter().enumerate() {
        let y = y1 - row * (k as f64 + 1.0);
        let color = PALETTE[k % PALETTE.len()];
        d.push(segment(
            [x0 + 2.0, y + 0.45 * LABEL_MM],
            [x0 + 2.0 + sample, y + 0.45 * LABEL_MM],
            Stroke::solid(color, LINE_MM),
            "legend",
        ));
        d.push(text([x0 + sample + 4.0, y], label, LABEL_MM, Anchor::Start, "legend"));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series_lines(d: &Drawing) -> Vec<&Vec<[f64; 2]>> {
        d.layer("series")
            .filter_map(|i| match i {
                Item::Polyline { points, .. } => Some(points),
                _ => None,
            })
            .collect()
    }

    fn texts<'a>(d: &'a Drawing, layer: &'a str) -> Vec<&'a str> {
        d.layer(layer)
            .filter_map(|i| match i {
                Item::Text { text, .. } => Some(text.as_str()),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn decreasing_series_descends_on_a_log_scale() {
        // 1, 0.1, 0.01, 0.001: equal steps on a log scale, spanning decades -3..0.
        let h = [1.0, 0.1, 0.01, 0.001];
        let d = convergence_plot(&[("GA", &h)], "t", "m");
        let lines = series_lines(&d);
        assert_eq!(lines.len(), 1);
        let p = lines[0];
        assert!((p[0][0] - LEFT).abs() < 1e-12 && (p[3][0] - RIGHT).abs() < 1e-12);
        assert!((p[0][1] - TOP).abs() < 1e-9 && (p[3][1] - BOTTOM).abs() < 1e-9);
        let dy: Vec<f64> = p.windows(2).map(|w| w[1][1] - w[0][1]).collect();
        for s in &dy {
            // One decade is (TOP - BOTTOM) / 3 mm; rounding in log10 only.
            assert!((s + (TOP - BOTTOM) / 3.0).abs() < 1e-9, "{dy:?}");
        }
        assert_eq!(texts(&d, "axes").iter().filter(|t| t.starts_with("10")).count(), 4);
        assert!(texts(&d, "legend").contains(&"GA: 0.00100 m"));
    }

    #[test]
    fn non_positive_values_break_the_line() {
        let h = [1.0, 0.5, 0.0, 0.2, f64::NAN, 0.1, 0.05];
        let d = convergence_plot(&[("PSO", &h)], "t", "");
        let lens: Vec<usize> = series_lines(&d).iter().map(|p| p.len()).collect();
        assert_eq!(lens, vec![2, 2]);
        assert_eq!(d.layer("series").filter(|i| matches!(i, Item::Marker { .. })).count(), 1);
        // the lone 0.2
    }

    #[test]
    fn empty_input_still_makes_a_plot() {
        let d = convergence_plot(&[], "nothing", "m");
        assert!(texts(&d, "title").contains(&"no positive values"));
        let none: [f64; 0] = [];
        let d = convergence_plot(&[("LM", &none)], "t", "m");
        assert!(texts(&d, "legend").contains(&"LM: no data"));
    }

    #[test]
    fn each_series_has_its_colour_and_legend_row() {
        let a = [3.0, 2.0, 1.0];
        let b = [5.0, 0.5];
        let d = convergence_plot(&[("GA", &a), ("", &b)], "t", "mm");
        let colors: Vec<Rgb> = d
            .layer("series")
            .filter_map(|i| match i {
                Item::Polyline { stroke, .. } => Some(stroke.color),
                _ => None,
            })
            .collect();
        assert_eq!(colors, vec![PALETTE[0], PALETTE[1]]);
        assert!(texts(&d, "legend").contains(&"series 2: 0.500 mm"));
        // x runs over the longest history: 3 points -> i_max = 2, so b ends at the middle.
        let lines = series_lines(&d);
        assert!((lines[1][1][0] - 0.5 * (LEFT + RIGHT)).abs() < 1e-9);
    }
}
