//! `lsubdiv graph --svg`: the transition graph between (d+1)-words drawn as a picture, as
//! \[N\] Fig. 3 and \[G\] Figs. A.8–A.9: one box per word, one arrow per transition (the mask of
//! the first word reaches the second), strongly connected components filled (one colour each),
//! transitional words (those only the first steps make) dashed with their steps.
//!
//! The layered layout and the edge curves come from the `layout-rs` crate (a Graphviz-like
//! Sugiyama layout); this module records what it draws and paints it with its own styles.

use crate::picture::{Anchor, Picture, Style};
use crate::report::SCC_FILLS;
use layout::core::base::Orientation;
use layout::core::format::{ClipHandle, RenderBackend};
use layout::core::geometry::Point;
use layout::core::style::StyleAttr;
use layout::std_shapes::shapes::{Arrow, Element, ShapeKind};
use layout::topo::layout::VisualGraph;
use lsubdiv::compiler::exact::Scheme;

/// Font size of the word labels, in layout units.
const FONT: f64 = 14.0;

/// An edge as the layout drew it.
struct DrawnEdge {
    from: usize,
    to: usize,
    /// Bézier path as (point, control) pairs (layout-rs's convention: `M p0 C c0, p1' …`).
    path: Vec<[[f64; 2]; 2]>,
    /// Arrowheads at (start, end): a reversed back edge has its head at the start.
    heads: (bool, bool),
}

/// What the layout drew: node boxes and edge curves, in layout coordinates.
#[derive(Default)]
struct Recorder {
    /// (word index, top-left, size).
    boxes: Vec<(usize, [f64; 2], [f64; 2])>,
    curves: Vec<DrawnEdge>,
}

fn pt(p: Point) -> [f64; 2] {
    [p.x, p.y]
}

impl RenderBackend for Recorder {
    fn draw_rect(
        &mut self,
        xy: Point,
        size: Point,
        _look: &StyleAttr,
        properties: Option<String>,
        _clip: Option<ClipHandle>,
    ) {
        if let Some(i) = properties.and_then(|p| p.strip_prefix("node ")?.parse().ok()) {
            self.boxes.push((i, pt(xy), pt(size)));
        }
    }

    fn draw_line(&mut self, _: Point, _: Point, _: &StyleAttr, _: Option<String>) {}

    fn draw_circle(&mut self, _: Point, _: Point, _: &StyleAttr, _: Option<String>) {}

    fn draw_text(&mut self, _: Point, _: &str, _: &StyleAttr) {}

    fn draw_arrow(
        &mut self,
        path: &[(Point, Point)],
        _dashed: bool,
        head: (bool, bool),
        _look: &StyleAttr,
        properties: Option<String>,
        _text: &str,
    ) {
        let ends = properties.and_then(|p| {
            let mut it = p.strip_prefix("edge ")?.split(' ').map(str::parse::<usize>);
            Some((it.next()?.ok()?, it.next()?.ok()?))
        });
        if let Some((from, to)) = ends {
            let path = path.iter().map(|(a, b)| [pt(*a), pt(*b)]).collect();
            self.curves.push(DrawnEdge {
                from,
                to,
                path,
                heads: head,
            });
        }
    }

    fn create_clip(&mut self, _: Point, _: Point, _: usize) -> ClipHandle {
        0
    }
}

/// Lays the graph out in one orientation.
fn lay_out(s: &Scheme, labels: &[String], orientation: Orientation) -> Recorder {
    let mut vg = VisualGraph::new(orientation);
    let handles: Vec<_> = labels
        .iter()
        .enumerate()
        .map(|(i, label)| {
            let size = Point::new(label_width(label) + 18.0, 30.0);
            let look = StyleAttr::simple();
            let shape = ShapeKind::new_box(label);
            vg.add_node(Element::create_with_properties(
                shape,
                look,
                orientation,
                size,
                format!("node {i}"),
            ))
        })
        .collect();
    for (i, succ) in s.graph.edges.iter().enumerate() {
        for &j in succ {
            vg.add_edge(
                Arrow::simple_with_properties("", format!("edge {i} {j}")),
                handles[i],
                handles[j],
            );
        }
    }
    let mut rec = Recorder::default();
    vg.do_it(false, false, false, &mut rec);
    rec
}

/// Approximate width of a label in DejaVu Sans at [`FONT`].
fn label_width(label: &str) -> f64 {
    label.chars().count() as f64 * FONT * 0.68
}

/// Bounds [xmin, xmax, ymin, ymax] of what the layout drew.
fn extent(r: &Recorder) -> [f64; 4] {
    let mut b = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    let mut grow = |p: [f64; 2]| {
        b[0] = b[0].min(p[0]);
        b[1] = b[1].max(p[0]);
        b[2] = b[2].min(p[1]);
        b[3] = b[3].max(p[1]);
    };
    for (_, at, size) in &r.boxes {
        grow(*at);
        grow([at[0] + size[0], at[1] + size[1] + 16.0]); // room for "steps …"
    }
    for c in &r.curves {
        for [a, c] in &c.path {
            grow(*a);
            grow(*c);
        }
    }
    b
}

/// An arrowhead at `tip`, pointing away from `from`.
fn arrowhead(pic: &mut Picture, from: [f64; 2], tip: [f64; 2], size: f64, colour: &str) {
    let (dx, dy) = (tip[0] - from[0], tip[1] - from[1]);
    let len = dx.hypot(dy).max(1e-9);
    let (ux, uy) = (dx / len, dy / len);
    let base = [tip[0] - ux * size, tip[1] - uy * size];
    let left = [base[0] - uy * size * 0.45, base[1] + ux * size * 0.45];
    let right = [base[0] + uy * size * 0.45, base[1] - ux * size * 0.45];
    pic.polyline(&[tip, left, right], true, &Style::fill(colour), "");
}

/// Edge colours, by the index of the source word (so that a word's arrows can be followed).
const EDGE_COLOURS: [&str; 8] = [
    "#4e79a7", "#e15759", "#59a14f", "#b07aa1", "#f28e2b", "#76b7b2", "#9c755f", "#edc948",
];

/// Room above the drawing (title) and below it (legend).
const TITLE_H: f64 = 44.0;
const LEGEND_H: f64 = 54.0;

/// The picture of the transition graph of `s`, in a `size` image; without a size, the size
/// that draws the layout at its natural scale (words in 14 px type).
pub fn picture(s: &Scheme, size: Option<(u32, u32)>) -> Picture {
    let ls = &s.ls;
    let g = &s.graph;
    let labels: Vec<String> = g.words.iter().map(|w| ls.word_str(&w.word)).collect();
    let layouts: Vec<Recorder> = [Orientation::LeftToRight, Orientation::TopToBottom]
        .into_iter()
        .map(|o| lay_out(s, &labels, o))
        .collect();
    let size = size.unwrap_or_else(|| {
        // The orientation with the smaller area, at scale 1, at least wide enough for the legend.
        let natural = |r: &Recorder| {
            let e = extent(r);
            (
                ((e[1] - e[0]) + 40.0).max(720.0),
                (e[3] - e[2]) + TITLE_H + LEGEND_H + 20.0,
            )
        };
        let (w, h) = layouts
            .iter()
            .map(natural)
            .fold((f64::INFINITY, f64::INFINITY), |a, b| {
                if b.0 * b.1 < a.0 * a.1 {
                    b
                } else {
                    a
                }
            });
        (w.ceil() as u32, h.ceil() as u32)
    });
    let (w, h) = (f64::from(size.0), f64::from(size.1));
    let area = [16.0, TITLE_H, w - 32.0, h - TITLE_H - LEGEND_H];
    // Both orientations; keep the one drawn larger.
    let fit = |r: &Recorder| {
        let e = extent(r);
        (area[2] / (e[1] - e[0]).max(1.0))
            .min(area[3] / (e[3] - e[2]).max(1.0))
            .min(1.6)
    };
    let (rec, scale) = layouts
        .into_iter()
        .map(|r| {
            let k = fit(&r);
            (r, k)
        })
        .fold(None, |best: Option<(Recorder, f64)>, (r, k)| match best {
            Some((b, kb)) if kb >= k => Some((b, kb)),
            _ => Some((r, k)),
        })
        .expect("two layouts");
    let e = extent(&rec);
    let off = [
        area[0] + 0.5 * (area[2] - scale * (e[1] - e[0])) - scale * e[0],
        area[1] + 0.5 * (area[3] - scale * (e[3] - e[2])) - scale * e[2],
    ];
    let map = |p: [f64; 2]| [off[0] + scale * p[0], off[1] + scale * p[1]];

    let scc_of: Vec<Option<usize>> = (0..g.words.len())
        .map(|i| g.sccs.iter().position(|c| c.contains(&i)))
        .collect();
    let mut pic = Picture::new(size.0, size.1);
    let edges: usize = g.edges.iter().map(Vec::len).sum();
    pic.text(
        [0.5 * w, 26.0],
        &format!(
            "{}: transition graph of the {}-words ({} words, {} transitions, {} SCC{})",
            ls.name,
            ls.degree + 1,
            g.words.len(),
            edges,
            g.sccs.len(),
            if g.sccs.len() == 1 { "" } else { "s" }
        ),
        15.0,
        Anchor::Middle,
        "black",
    );
    for DrawnEdge {
        from,
        to,
        path,
        heads: head,
    } in &rec.curves
    {
        let edge_colour = EDGE_COLOURS[from % EDGE_COLOURS.len()];
        let p: Vec<[[f64; 2]; 2]> = path.iter().map(|[a, c]| [map(*a), map(*c)]).collect();
        if p.len() < 2 {
            continue;
        }
        let mut d = format!(
            "M {:.1} {:.1} C {:.1} {:.1}, {:.1} {:.1}, {:.1} {:.1}",
            p[0][0][0],
            p[0][0][1],
            p[0][1][0],
            p[0][1][1],
            p[1][0][0],
            p[1][0][1],
            p[1][1][0],
            p[1][1][1]
        );
        for [c, q] in &p[2..] {
            d.push_str(&format!(
                " S {:.1} {:.1}, {:.1} {:.1}",
                c[0], c[1], q[0], q[1]
            ));
        }
        let class = format!("edge e{from}-{to}");
        pic.path(&d, &Style::stroke(edge_colour, 1.2), &class);
        let last = p[p.len() - 1];
        if head.1 {
            arrowhead(&mut pic, last[0], last[1], 9.0 * scale.sqrt(), edge_colour);
        }
        if head.0 {
            arrowhead(&mut pic, p[0][1], p[0][0], 9.0 * scale.sqrt(), edge_colour);
        }
    }
    for (i, at, sz) in &rec.boxes {
        let info = &g.words[*i];
        let fill = scc_of[*i].map_or("white", |c| SCC_FILLS[c % SCC_FILLS.len()]);
        let mut style = Style::stroke("#222222", 1.3).filled(fill);
        if info.transitional {
            style = style.dashed("5 3");
        }
        let (a, b) = (map(*at), [sz[0] * scale, sz[1] * scale]);
        let class = if info.transitional {
            "node transitional"
        } else {
            "node"
        };
        pic.rect(a, b, &style, class);
        let fs = FONT * scale;
        pic.text(
            [a[0] + 0.5 * b[0], a[1] + 0.5 * b[1] + 0.36 * fs],
            &labels[*i],
            fs,
            Anchor::Middle,
            "black",
        );
        if info.transitional {
            let steps: Vec<String> = info.steps.iter().map(usize::to_string).collect();
            pic.text(
                [a[0] + 0.5 * b[0], a[1] + b[1] + 0.9 * fs],
                &format!("step {}", steps.join(", ")),
                0.75 * fs,
                Anchor::Middle,
                "#444444",
            );
        }
    }
    legend(&mut pic, s, [16.0, h - LEGEND_H + 8.0]);
    pic
}

/// The key: one swatch per SCC, the transitional style, the arrow's meaning.
fn legend(pic: &mut Picture, s: &Scheme, at: [f64; 2]) {
    let mut x = at[0];
    let y = at[1];
    for (c, _) in s.graph.sccs.iter().enumerate() {
        pic.rect(
            [x, y],
            [26.0, 16.0],
            &Style::stroke("#222222", 1.0).filled(SCC_FILLS[c % SCC_FILLS.len()]),
            "legend",
        );
        pic.text(
            [x + 32.0, y + 13.0],
            &format!("SCC {}", c + 1),
            12.0,
            Anchor::Start,
            "black",
        );
        x += 90.0;
    }
    pic.rect(
        [x, y],
        [26.0, 16.0],
        &Style::stroke("#222222", 1.0).filled("white").dashed("5 3"),
        "legend",
    );
    pic.text(
        [x + 32.0, y + 13.0],
        "transitional (only in the steps shown)",
        12.0,
        Anchor::Start,
        "black",
    );
    pic.text(
        [at[0], y + 36.0],
        "A → B: the mask of word A has an entry at a new point whose word is B (arrows coloured by A)",
        12.0,
        Anchor::Start,
        "black",
    );
}
