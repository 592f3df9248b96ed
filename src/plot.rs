//! `lsubdiv plot`: the control polygons of successive steps and the limit curve, its knot
//! intervals coloured by label (as \[N\] Fig. 2), with axes and a legend.
//!
//! The limit curve is the control polygon refined until its edges are shorter than a pixel.
//! Which interval of the last plotted step a fine point lies in is read off its parameter:
//! a third coordinate starts as each point's Greville abscissa (the mean of the d inner knots
//! of its word, knots spaced by the exact interval lengths) and is refined with the points;
//! B-splines reproduce linear functions, so after refinement it is the fine point's Greville
//! abscissa. A closed polygon is refined for this as the open polygon of its points followed by
//! the first d again, whose spline is the closed one over one period.

use crate::input_error;
use crate::limits::{count, Drawing, TREE_POINT};
use crate::picture::{bounds, Anchor, Frame, Picture, Style};
use lsubdiv::compiler::Error;
use lsubdiv::generic::GenericScheme;
use lsubdiv::runtime::{refine, Curve, CurveScheme, CurveTables};

/// Edges of the limit curve are at most this long in pixels.
const PIXEL: f64 = 1.0;
/// The limit curve stops refining at this many points whatever the edge length.
const MAX_POINTS: usize = 400_000;

/// Characters of an SVG coordinate pair at most (`-12345.67,-12345.67 `: the picture writes
/// two decimals, and is at most 10000 pixels a side).
const PAIR_TEXT: u128 = 20;
/// Characters of a point's circle element at most, its coordinates included.
const CIRCLE_TEXT: u128 = 100;
/// Characters of a limit piece's polyline element at most, without its points.
const PIECE_TEXT: u128 = 160;
/// Elements of the title, axes, ticks and legend at most, besides two per symbol; each at most
/// [`FRAME_TEXT`] characters of SVG and [`FRAME_GLYPHS`] of text.
const FRAME_ELEMENTS: u128 = 80;
const FRAME_TEXT: u128 = 240;
const FRAME_GLYPHS: u128 = 80;

/// What a plot of levels of `vertices` points (steps 0..=N) draws, predicted before refining
/// them, for the size guard: a circle and a polygon vertex per point of every level, and a
/// polyline per knot interval of the last holding the limit curve's points, counted here as
/// many as the last level's (each further point of the limit pass is counted as it is made:
/// [`limit_point_bytes`]).
pub fn predicted(t: &CurveTables<'_>, vertices: &[u128]) -> Drawing {
    let d = t.degree as u128;
    let last = vertices.last().copied().unwrap_or(0);
    let all = vertices.iter().fold(0u128, |a, &v| a.saturating_add(v));
    let (fine, pieces) = (last.saturating_add(d), last.saturating_add(2 * d + 1));
    let frame = FRAME_ELEMENTS + 2 * t.symbol_count() as u128;
    let sum = |terms: &[u128]| terms.iter().fold(0u128, |a, &x| a.saturating_add(x));
    Drawing {
        text: sum(&[
            all.saturating_mul(CIRCLE_TEXT + PAIR_TEXT),
            pieces.saturating_mul(PIECE_TEXT),
            fine.saturating_add(pieces).saturating_mul(PAIR_TEXT),
            frame * FRAME_TEXT,
        ]),
        elements: sum(&[all, vertices.len() as u128, pieces, frame]),
        points: sum(&[all.saturating_mul(3), fine, pieces, frame * 2]),
        texts: frame,
        glyphs: frame * FRAME_GLYPHS,
    }
}

/// Bytes the limit pass holds per point of its finest polygon at most: two levels of points
/// with their parameter and labels, the point in its piece, its SVG text and the document's
/// copy of it, and for a PNG its share of resvg's tree.
pub fn limit_point_bytes(png: bool) -> u128 {
    2 * (24 + 1) + 16 + 2 * PAIR_TEXT + if png { TREE_POINT } else { 0 }
}

/// Interval colours by symbol index (odd indices are also dashed, as \[N\] Fig. 2's S).
const PALETTE: [&str; 8] = [
    "#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
];

/// The stroke of the limit curve over intervals labelled `symbol`.
fn symbol_style(symbol: u8) -> Style {
    let s = Style::stroke(PALETTE[symbol as usize % PALETTE.len()], 2.5);
    if symbol % 2 == 1 {
        s.dashed("7 4")
    } else {
        s
    }
}

/// A run of the limit curve over one knot interval of the last step.
#[derive(Clone, Debug)]
pub struct Piece {
    /// The interval's label.
    pub symbol: u8,
    /// Points of the refined polygon over it (the last one starts the next piece).
    pub points: Vec<[f64; 2]>,
}

/// The polygon after 0..=steps steps.
fn levels(scheme: &GenericScheme, curve: &Curve<2>, steps: usize) -> Result<Vec<Curve<2>>, Error> {
    let mut out = vec![curve.clone()];
    for _ in 0..steps {
        let next = refine(scheme, out.last().expect("non-empty"), 1).map_err(input_error)?;
        out.push(next);
    }
    Ok(out)
}

/// The limit curve of `last`, in pieces over its knot intervals, refined until every edge is
/// below `max_edge` (data units); a step that could make more than `max_points` points (the
/// size guard's room) is refused before it is taken.
pub fn limit(
    scheme: &mut GenericScheme,
    last: &Curve<2>,
    max_edge: f64,
    max_points: u128,
) -> Result<Vec<Piece>, Error> {
    let t = scheme.tables();
    let d = t.degree;
    let growth = (0..t.symbol_count() as u8)
        .map(|a| t.rule(a).len() as u128)
        .max()
        .unwrap_or(1);
    let lengths: Vec<f64> = scheme.scheme().lengths.iter().map(|e| e.to_f64()).collect();
    let (points, labels): (Vec<[f64; 2]>, Vec<u8>) = if last.closed {
        let m = last.points.len();
        let n = last.labels.len();
        (
            (0..m + d).map(|k| last.points[k % m]).collect(),
            (0..m + 2 * d).map(|k| last.labels[k % n]).collect(),
        )
    } else {
        (last.points.clone(), last.labels.clone())
    };
    // Knots t_0 = 0 < t_1 < …, spaced by the exact lengths (as f64).
    let mut knots = vec![0.0];
    for &s in &labels {
        knots.push(knots.last().expect("non-empty") + lengths[s as usize]);
    }
    let greville = |k: usize| knots[k + 1..=k + d].iter().sum::<f64>() / d as f64;
    let mut fine = Curve {
        points: points
            .iter()
            .enumerate()
            .map(|(k, p)| [p[0], p[1], greville(k)])
            .collect(),
        labels: labels.clone(),
        closed: false,
    };
    scheme.prepare(&fine)?;
    loop {
        let longest = fine
            .points
            .windows(2)
            .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
            .fold(0.0, f64::max);
        if longest <= max_edge || fine.points.len() > MAX_POINTS {
            break;
        }
        let next = (fine.points.len() as u128).saturating_mul(growth);
        if next > max_points {
            return Err(Error::input(format!(
                "drawing the limit curve to a pixel refines it to up to {} points, and --max-memory leaves room for {}; use fewer points or steps, or raise --max-memory",
                count(next),
                count(max_points)
            )));
        }
        fine = refine(scheme, &fine, 1).map_err(input_error)?;
    }
    // Cut the fine polygon where its parameter crosses a knot of `last`, over the spline's
    // domain [t_d, t_m] (m points; one period for the unrolled closed polygon).
    let domain = knots[d]..=knots[points.len()];
    let mut pieces: Vec<Piece> = Vec::new();
    let mut current = usize::MAX;
    for p in fine.points.iter().filter(|p| domain.contains(&p[2])) {
        let j = knots.partition_point(|&t| t <= p[2]).clamp(1, labels.len()) - 1;
        let xy = [p[0], p[1]];
        if j != current {
            if let Some(prev) = pieces.last_mut() {
                prev.points.push(xy); // join the pieces
            }
            pieces.push(Piece {
                symbol: labels[j],
                points: Vec::new(),
            });
            current = j;
        }
        pieces.last_mut().expect("pushed").points.push(xy);
    }
    Ok(pieces)
}

/// "Nice" tick positions covering [lo, hi]: multiples of 1, 2 or 5 × 10^k, about `count`.
fn ticks(lo: f64, hi: f64, count: usize) -> Vec<f64> {
    // Halves first: the span of bounds near ±f64::MAX does not overflow.
    let raw = (0.5 * hi - 0.5 * lo) / count.max(1) as f64 * 2.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag);
    // Multiples of the step counted in f64, not i64 (which saturates past 9.2e18 steps).
    let (first, last) = ((lo / step).ceil(), (hi / step).floor());
    (0..=count.max(1) * 10 + 2)
        .map(|k| (first + k as f64) * step)
        .take_while(|&t| t / step <= last)
        .collect()
}

/// A tick label without float noise: fixed decimals for steps from 1e-6 to 1e6, else
/// scientific notation with the digits the step needs.
fn tick_label(x: f64, step: f64) -> String {
    if !(1e-6..1e6).contains(&step) {
        if x == 0.0 {
            return "0".into();
        }
        let digits = (x.abs().log10().floor() - step.log10().floor()).max(0.0) as usize;
        return format!("{x:.digits$e}");
    }
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let s = format!("{x:.decimals$}");
    if s.starts_with('-') && s.trim_start_matches(['-', '0', '.']).is_empty() {
        s[1..].to_string()
    } else {
        s
    }
}

/// Draws the frame of the plot box, its ticks and their labels.
fn axes(pic: &mut Picture, frame: &Frame, plot_box: [f64; 4]) {
    let [x0, y0, w, h] = plot_box;
    let axis = Style::stroke("#333333", 1.0);
    let grid = Style::stroke("#eeeeee", 1.0);
    pic.rect([x0, y0], [w, h], &axis, "");
    let b = frame.bounds;
    let xt = ticks(b[0], b[1], (w / 90.0).max(2.0) as usize);
    let yt = ticks(b[2], b[3], (h / 70.0).max(2.0) as usize);
    let xstep = xt.get(1).map_or(1.0, |t| t - xt[0]);
    let ystep = yt.get(1).map_or(1.0, |t| t - yt[0]);
    for &x in &xt {
        let px = frame.map([x, 0.0])[0];
        pic.line([px, y0 + 1.0], [px, y0 + h - 1.0], &grid, "");
        pic.line([px, y0 + h], [px, y0 + h + 5.0], &axis, "tick");
        pic.text(
            [px, y0 + h + 19.0],
            &tick_label(x, xstep),
            12.0,
            Anchor::Middle,
            "#333333",
        );
    }
    for &y in &yt {
        let py = frame.map([0.0, y])[1];
        pic.line([x0 + 1.0, py], [x0 + w - 1.0, py], &grid, "");
        pic.line([x0 - 5.0, py], [x0, py], &axis, "tick");
        pic.text(
            [x0 - 8.0, py + 4.0],
            &tick_label(y, ystep),
            12.0,
            Anchor::End,
            "#333333",
        );
    }
}

/// Grey of the control polygon of step `s` of `steps`: lighter for coarser steps.
fn step_grey(s: usize, steps: usize) -> String {
    let t = if steps == 0 {
        1.0
    } else {
        s as f64 / steps as f64
    };
    let v = (205.0 - 140.0 * t).round() as u8;
    format!("#{v:02x}{v:02x}{v:02x}")
}

/// The picture: `curve` refined `steps` times by `scheme`, in a `size` image.
pub fn plot(
    mut scheme: GenericScheme,
    curve: &Curve<2>,
    steps: usize,
    size: (u32, u32),
    max_limit_points: u128,
) -> Result<Picture, Error> {
    scheme.prepare(curve)?;
    let all = levels(&scheme, curve, steps)?;
    let s = scheme.scheme();
    let ls = &s.ls;
    let length_text: Vec<String> = s.lengths.iter().map(|e| e.to_string()).collect();
    let rho = (s.analysis.rho.to_string(), s.analysis.rho.to_f64());
    let (name, degree, symbols) = (ls.name.clone(), ls.degree, ls.symbols.clone());

    let (w, h) = (f64::from(size.0), f64::from(size.1));
    let legend_w = 170.0_f64.min(0.3 * w);
    let plot_box = [
        58.0,
        44.0,
        (w - 58.0 - legend_w - 16.0).max(10.0),
        (h - 44.0 - 34.0).max(10.0),
    ];
    let data = bounds(all.iter().flat_map(|c| c.points.iter()), 0.04);
    let frame = Frame::fit(data, plot_box);
    let last = all.last().expect("non-empty");
    let pieces = limit(&mut scheme, last, PIXEL / frame.scale(), max_limit_points)?;

    let mut pic = Picture::new(size.0, size.1);
    pic.text(
        [0.5 * w, 26.0],
        &format!(
            "{name} (degree {degree}): {steps} step{}, ρ = {} ≈ {:.6}",
            if steps == 1 { "" } else { "s" },
            rho.0,
            rho.1
        ),
        16.0,
        Anchor::Middle,
        "black",
    );
    axes(&mut pic, &frame, plot_box);
    for (k, c) in all.iter().enumerate() {
        let pts: Vec<[f64; 2]> = c.points.iter().map(|p| frame.map(*p)).collect();
        let grey = step_grey(k, steps);
        pic.polyline(&pts, c.closed, &Style::stroke(&grey, 1.2), "step");
        for p in &pts {
            pic.circle(
                *p,
                if k == steps { 2.6 } else { 1.8 },
                &Style::fill(&grey),
                "",
            );
        }
    }
    for piece in &pieces {
        let pts: Vec<[f64; 2]> = piece.points.iter().map(|p| frame.map(*p)).collect();
        pic.polyline(&pts, false, &symbol_style(piece.symbol), "limit");
    }

    // Legend: one entry per symbol (its exact length), then the control polygons.
    let lx = w - legend_w - 4.0;
    let mut ly = plot_box[1] + 14.0;
    pic.text(
        [lx, ly],
        "limit curve over intervals",
        12.0,
        Anchor::Start,
        "black",
    );
    ly += 20.0;
    for (i, sym) in symbols.iter().enumerate() {
        pic.line(
            [lx, ly - 4.0],
            [lx + 30.0, ly - 4.0],
            &symbol_style(i as u8),
            "legend-symbol",
        );
        pic.text(
            [lx + 38.0, ly],
            &format!("{sym}: length {}", length_text[i]),
            12.0,
            Anchor::Start,
            "black",
        );
        ly += 20.0;
    }
    ly += 8.0;
    pic.text([lx, ly], "control polygons", 12.0, Anchor::Start, "black");
    for k in [0, steps] {
        ly += 20.0;
        pic.line(
            [lx, ly - 4.0],
            [lx + 30.0, ly - 4.0],
            &Style::stroke(&step_grey(k, steps), 1.2),
            "",
        );
        pic.text(
            [lx + 38.0, ly],
            &format!("step {k}"),
            12.0,
            Anchor::Start,
            "black",
        );
        if steps == 0 {
            break;
        }
    }
    Ok(pic)
}

/// The default polygon of `plot` without an input file: a regular hexagon of circumradius 1.
pub fn hexagon() -> Vec<[f64; 2]> {
    (0..6)
        .map(|i| {
            let t = std::f64::consts::TAU * f64::from(i) / 6.0;
            [t.cos(), t.sin()]
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        assert_eq!(ticks(-1.1, 1.1, 4), vec![-1.0, 0.0, 1.0]);
        assert_eq!(ticks(-1.1, 1.1, 5), vec![-1.0, -0.5, 0.0, 0.5, 1.0]);
        assert_eq!(tick_label(-0.0, 0.5), "0.0");
        assert_eq!(tick_label(-1e-17, 1.0), "0");
        assert_eq!(tick_label(0.5, 0.5), "0.5");
        assert_eq!(tick_label(20.0, 10.0), "20");
    }
}
