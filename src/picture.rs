//! The drawing layer of `plot`, `graph --svg` and `ev --characteristic-map`: a 2D picture kept
//! as SVG text, written as SVG or rasterised to PNG by resvg. PNG text uses DejaVu Sans,
//! embedded in the binary (the `dejavu` crate), so that no system font is needed.

use crate::limits::Drawing;
use crate::output::{format_by_extension, write_atomic};
use lsubdiv::compiler::Error;
use std::fmt::Write as _;
use std::path::Path;

/// The font family every text element names (embedded for PNG output).
const FONT: &str = "DejaVu Sans";

/// How an element is stroked and filled.
#[derive(Clone, Debug)]
pub struct Style {
    /// Stroke colour (SVG colour syntax), or `none`.
    pub stroke: String,
    /// Stroke width in pixels.
    pub width: f64,
    /// Fill colour, or `none`.
    pub fill: String,
    /// SVG dash array (e.g. `6 4`), if dashed.
    pub dash: Option<String>,
    /// Opacity of the whole element, 0 to 1.
    pub opacity: f64,
}

impl Style {
    /// An unfilled stroke.
    pub fn stroke(colour: &str, width: f64) -> Style {
        Style {
            stroke: colour.into(),
            width,
            fill: "none".into(),
            dash: None,
            opacity: 1.0,
        }
    }

    /// A fill without stroke.
    pub fn fill(colour: &str) -> Style {
        Style {
            stroke: "none".into(),
            width: 0.0,
            fill: colour.into(),
            dash: None,
            opacity: 1.0,
        }
    }

    /// The same, dashed.
    pub fn dashed(mut self, dash: &str) -> Style {
        self.dash = Some(dash.into());
        self
    }

    /// The same, filled.
    pub fn filled(mut self, colour: &str) -> Style {
        self.fill = colour.into();
        self
    }

    /// The same, with this opacity.
    pub fn opacity(mut self, opacity: f64) -> Style {
        self.opacity = opacity;
        self
    }

    fn attrs(&self) -> String {
        let mut s = format!(
            "stroke=\"{}\" stroke-width=\"{}\" fill=\"{}\"",
            self.stroke,
            num(self.width),
            self.fill
        );
        if let Some(d) = &self.dash {
            let _ = write!(s, " stroke-dasharray=\"{d}\"");
        }
        if self.opacity < 1.0 {
            let _ = write!(s, " opacity=\"{}\"", num(self.opacity));
        }
        s
    }
}

/// Horizontal text alignment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    /// Text starts at the point.
    Start,
    /// Text is centred on the point.
    Middle,
    /// Text ends at the point.
    End,
}

/// An SVG picture of a given pixel size; y grows downwards, as in SVG.
#[derive(Clone, Debug)]
pub struct Picture {
    width: u32,
    height: u32,
    body: String,
    /// Some coordinate given was not finite (the picture is refused, never written).
    non_finite: bool,
    /// Its elements, points and text, for the size guard ([`Picture::drawing`]).
    drawn: Drawing,
}

/// A coordinate with at most 2 decimals (enough for pixels, keeps files small).
fn num(x: f64) -> String {
    let r = (x * 100.0).round() / 100.0;
    if r == r.trunc() {
        format!("{}", r as i64)
    } else {
        format!("{r}")
    }
}

/// XML-escapes text.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn class_attr(class: &str) -> String {
    if class.is_empty() {
        String::new()
    } else {
        format!(" class=\"{class}\"")
    }
}

impl Picture {
    /// An empty picture on a white background.
    pub fn new(width: u32, height: u32) -> Picture {
        let mut p = Picture {
            width,
            height,
            body: String::new(),
            non_finite: false,
            drawn: Drawing::default(),
        };
        p.rect(
            [0.0, 0.0],
            [f64::from(width), f64::from(height)],
            &Style::fill("white"),
            "",
        );
        p
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// A straight line.
    pub fn line(&mut self, a: [f64; 2], b: [f64; 2], style: &Style, class: &str) {
        self.element(&[a, b]);
        let _ = writeln!(
            self.body,
            "<line{} x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" {}/>",
            class_attr(class),
            num(a[0]),
            num(a[1]),
            num(b[0]),
            num(b[1]),
            style.attrs()
        );
    }

    /// A polyline through `points`, closed into a polygon when `closed`.
    pub fn polyline(&mut self, points: &[[f64; 2]], closed: bool, style: &Style, class: &str) {
        self.element(points);
        let coords: Vec<String> = points
            .iter()
            .map(|p| format!("{},{}", num(p[0]), num(p[1])))
            .collect();
        let _ = writeln!(
            self.body,
            "<{}{} points=\"{}\" {} stroke-linejoin=\"round\"/>",
            if closed { "polygon" } else { "polyline" },
            class_attr(class),
            coords.join(" "),
            style.attrs()
        );
    }

    /// An axis-aligned rectangle from its top-left corner and size.
    pub fn rect(&mut self, at: [f64; 2], size: [f64; 2], style: &Style, class: &str) {
        self.element(&[at, size]);
        let _ = writeln!(
            self.body,
            "<rect{} x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" rx=\"{}\" {}/>",
            class_attr(class),
            num(at[0]),
            num(at[1]),
            num(size[0]),
            num(size[1]),
            if class.is_empty() { "0" } else { "3" },
            style.attrs()
        );
    }

    /// A circle.
    pub fn circle(&mut self, centre: [f64; 2], r: f64, style: &Style, class: &str) {
        self.element(&[centre, [r, 0.0]]);
        let _ = writeln!(
            self.body,
            "<circle{} cx=\"{}\" cy=\"{}\" r=\"{}\" {}/>",
            class_attr(class),
            num(centre[0]),
            num(centre[1]),
            num(r),
            style.attrs()
        );
    }

    /// An SVG path (`d` in path syntax), e.g. the Bézier curve of a graph edge.
    pub fn path(&mut self, d: &str, style: &Style, class: &str) {
        // A point takes three characters of `d` at least (`1 2 `).
        self.element(&[]);
        self.drawn.points += d.len() as u128 / 3 + 1;
        let _ = writeln!(
            self.body,
            "<path{} d=\"{d}\" {}/>",
            class_attr(class),
            style.attrs()
        );
    }

    /// Text with its baseline at `at`.
    pub fn text(&mut self, at: [f64; 2], text: &str, size: f64, anchor: Anchor, colour: &str) {
        self.element(&[at, [size, 0.0]]);
        self.drawn.texts += 1;
        self.drawn.glyphs += text.chars().count() as u128;
        let anchor = match anchor {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        };
        let _ = writeln!(
            self.body,
            "<text x=\"{}\" y=\"{}\" font-family=\"{FONT}\" font-size=\"{}\" text-anchor=\"{anchor}\" fill=\"{colour}\">{}</text>",
            num(at[0]),
            num(at[1]),
            num(size),
            escape(text)
        );
    }

    /// What the picture holds so far, for the size guard ([`crate::limits::picture`]).
    pub fn drawing(&self) -> Drawing {
        Drawing {
            text: self.body.len() as u128,
            ..self.drawn
        }
    }

    /// Counts an element with its coordinates, and notes those that are not finite (or beyond
    /// what [`num`] writes): such a picture is refused by [`Picture::svg`].
    fn element(&mut self, points: &[[f64; 2]]) {
        self.drawn.elements += 1;
        self.drawn.points += points.len() as u128;
        self.non_finite |= points
            .iter()
            .flatten()
            .any(|x| !x.is_finite() || x.abs() >= 1e15);
    }

    /// The SVG document, refused when a coordinate was not finite (an SVG with `NaN` in it is
    /// broken) or too large to mean a pixel.
    pub fn svg(&self) -> Result<String, Error> {
        if self.non_finite {
            return Err(Error::input(
                "the picture would have coordinates that are not finite numbers (the data are beyond the f64 range once scaled to pixels); nothing was written",
            ));
        }
        Ok(format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n{}</svg>\n",
            self.body,
            w = self.width,
            h = self.height
        ))
    }

    /// The picture rasterised by resvg (text in the embedded font): premultiplied RGBA.
    pub fn pixmap(&self) -> Result<resvg::tiny_skia::Pixmap, Error> {
        use resvg::{tiny_skia, usvg};
        let mut opt = usvg::Options {
            font_family: FONT.into(),
            ..usvg::Options::default()
        };
        opt.fontdb_mut()
            .load_font_data(dejavu::sans::regular().to_vec());
        let tree = usvg::Tree::from_str(&self.svg()?, &opt)
            .map_err(|e| Error::internal(None, format!("the picture is not valid SVG: {e}")))?;
        let mut pixmap = tiny_skia::Pixmap::new(self.width, self.height).ok_or_else(|| {
            Error::input(format!(
                "cannot allocate a {}x{} image",
                self.width, self.height
            ))
        })?;
        resvg::render(&tree, tiny_skia::Transform::default(), &mut pixmap.as_mut());
        Ok(pixmap)
    }

    /// The picture rasterised to PNG.
    pub fn png(&self) -> Result<Vec<u8>, Error> {
        self.pixmap()?
            .encode_png()
            .map_err(|e| Error::internal(None, format!("PNG encoding failed: {e}")))
    }
}

/// An output format, chosen by the file name's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// SVG text.
    Svg,
    /// A PNG image.
    Png,
}

/// The format of `path` from its extension (`.svg` or `.png`, any case).
pub fn format_of(path: &Path) -> Result<Format, Error> {
    format_by_extension(
        path,
        "picture",
        &[("svg", Format::Svg), ("png", Format::Png)],
    )
}

/// Parses `--size WxH` (pixels, each 16 to 10000).
pub fn parse_size(text: &str) -> Result<(u32, u32), Error> {
    let fail = || {
        Error::input(format!(
            "--size `{text}`: expected WxH in pixels, e.g. 800x600, each 16 to 10000"
        ))
    };
    let (w, h) = text.split_once(['x', 'X']).ok_or_else(fail)?;
    let parse = |t: &str| t.trim().parse::<u32>().map_err(|_| fail());
    let (w, h) = (parse(w)?, parse(h)?);
    if !(16..=10_000).contains(&w) || !(16..=10_000).contains(&h) {
        return Err(fail());
    }
    Ok((w, h))
}

/// Writes the picture to `path` in the format its extension names, whole or not at all; a PNG
/// whose rasterising would hold more than `max_memory` bytes is refused first
/// ([`crate::limits::picture`]).
pub fn save(picture: &Picture, path: &Path, max_memory: u64) -> Result<(), Error> {
    let bytes = match format_of(path)? {
        Format::Svg => picture.svg()?.into_bytes(),
        Format::Png => {
            crate::limits::picture(
                (picture.width, picture.height),
                &picture.drawing(),
                max_memory,
            )?;
            picture.png()?
        }
    };
    write_atomic(path, &bytes)
}

/// A linear map from data coordinates to a pixel box, with equal scales on both axes
/// (geometry keeps its shape) and y pointing up.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// Data point drawn at the box centre.
    centre: [f64; 2],
    /// Pixels per data unit.
    scale: f64,
    /// Box centre in pixels.
    at: [f64; 2],
    /// Data bounds shown: [xmin, xmax, ymin, ymax].
    pub bounds: [f64; 4],
}

impl Frame {
    /// Fits the data bounds `[xmin, xmax, ymin, ymax]` into the pixel box `[x, y, w, h]`.
    pub fn fit(bounds: [f64; 4], pixels: [f64; 4]) -> Frame {
        // Half sides and centre from halves: nothing overflows for data near ±f64::MAX.
        let half = |lo: f64, hi: f64| (0.5 * hi - 0.5 * lo).max(f64::MIN_POSITIVE);
        let (hx, hy) = (half(bounds[0], bounds[1]), half(bounds[2], bounds[3]));
        let scale = (0.5 * pixels[2] / hx).min(0.5 * pixels[3] / hy);
        let centre = [
            0.5 * bounds[0] + 0.5 * bounds[1],
            0.5 * bounds[2] + 0.5 * bounds[3],
        ];
        let at = [pixels[0] + 0.5 * pixels[2], pixels[1] + 0.5 * pixels[3]];
        let hw = 0.5 * pixels[2] / scale;
        let hh = 0.5 * pixels[3] / scale;
        let clamp = |x: f64| x.clamp(-f64::MAX, f64::MAX);
        Frame {
            centre,
            scale,
            at,
            bounds: [
                clamp(centre[0] - hw),
                clamp(centre[0] + hw),
                clamp(centre[1] - hh),
                clamp(centre[1] + hh),
            ],
        }
    }

    /// Pixel position of a data point (its offset from the centre halved first, so that it
    /// does not overflow).
    pub fn map(&self, p: [f64; 2]) -> [f64; 2] {
        let d = |c: usize| (0.5 * p[c] - 0.5 * self.centre[c]) * self.scale * 2.0;
        [self.at[0] + d(0), self.at[1] - d(1)]
    }

    /// Pixels per data unit.
    pub fn scale(&self) -> f64 {
        self.scale
    }
}

/// Bounds `[xmin, xmax, ymin, ymax]` of points, widened by `margin` of the larger side.
pub fn bounds<'a>(points: impl IntoIterator<Item = &'a [f64; 2]>, margin: f64) -> [f64; 4] {
    let mut b = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    for p in points {
        b[0] = b[0].min(p[0]);
        b[1] = b[1].max(p[0]);
        b[2] = b[2].min(p[1]);
        b[3] = b[3].max(p[1]);
    }
    if !b[0].is_finite() {
        return [-1.0, 1.0, -1.0, 1.0];
    }
    // A margin relative to the data's size (halves first, against overflow); a single point
    // gets one relative to its magnitude, or 1 at the origin.
    let side = (0.5 * b[1] - 0.5 * b[0]).max(0.5 * b[3] - 0.5 * b[2]) * 2.0;
    let size = if side > 0.0 {
        side
    } else {
        let at = b.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
        if at > 0.0 {
            at * 1e-6
        } else {
            1.0
        }
    };
    let m = margin * size;
    let grow = |x: f64, d: f64| (x + d).clamp(-f64::MAX, f64::MAX);
    [grow(b[0], -m), grow(b[1], m), grow(b[2], -m), grow(b[3], m)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_and_formats_are_checked() {
        assert_eq!(parse_size("800x600"), Ok((800, 600)));
        assert!(parse_size("800").is_err());
        assert!(parse_size("0x600").is_err());
        assert!(parse_size("axb").is_err());
        assert_eq!(format_of(Path::new("a.SVG")), Ok(Format::Svg));
        assert_eq!(format_of(Path::new("a.png")), Ok(Format::Png));
        assert!(format_of(Path::new("a.jpg"))
            .unwrap_err()
            .message
            .contains(".svg or .png"));
    }

    #[test]
    fn a_picture_with_a_non_finite_coordinate_is_refused() {
        let mut p = Picture::new(20, 20);
        p.line([0.0, 0.0], [5.0, 5.0], &Style::stroke("black", 1.0), "");
        assert!(p.svg().is_ok());
        p.line(
            [0.0, 0.0],
            [f64::NAN, 5.0],
            &Style::stroke("black", 1.0),
            "",
        );
        assert!(p.svg().unwrap_err().message.contains("not finite"));
        assert!(p.pixmap().is_err());
    }

    #[test]
    fn text_renders_with_the_embedded_font() {
        // A black word on white: some pixels must be dark, which needs the font.
        let mut p = Picture::new(120, 40);
        p.text([10.0, 30.0], "ρ ≈ 1.6", 24.0, Anchor::Start, "black");
        let png = p.png().unwrap();
        let decoder = png::Decoder::new(std::io::Cursor::new(png));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (120, 40));
        let dark = buf.chunks(4).filter(|px| px[0] < 100).count();
        assert!(dark > 50, "{dark} dark pixels");
    }
}
