//! The colour bar of the curvature map, labelled with its range: drawn by the picture layer
//! (SVG rasterised by resvg, text in the embedded DejaVu Sans) and copied into the image.

use super::curvature::{colour, Range};
use super::image::Image;
use crate::picture::{Anchor, Picture, Style};

/// A number in at most three significant digits: `1.83`, `0.0421`, `125`, `1.83e-5`.
pub fn label(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 {
        return "0".into();
    }
    if (0.01..1000.0).contains(&a) {
        let decimals = (2 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.2e}")
    }
}

/// Pixels at the right edge the bar and its labels take.
pub const WIDTH: usize = 100;

/// Whether an image of this size has room for the bar (beside a picture at least as wide).
pub fn fits(width: usize, height: usize) -> bool {
    width >= 2 * WIDTH && height >= 64
}

/// Hex colour of a curvature in [−1, 1] on the map's scale.
fn hex(t: f64) -> String {
    let [r, g, b] = colour(t).map(|c| (c * 255.0).round() as u8);
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// The bar as a picture [`WIDTH`] wide and `height` high: +span at the top, −span at the
/// bottom, labelled (`H·r` when the range is relative to the bounding box's half side r).
fn picture(height: usize, range: &Range) -> Picture {
    let span = range.span;
    let mut p = Picture::new(WIDTH as u32, height as u32);
    let (x0, x1) = (WIDTH as f64 - 30.0, WIDTH as f64 - 16.0);
    let (y0, y1) = ((height / 5) as f64, (height - height / 5) as f64);
    let rows = (y1 - y0).round() as usize;
    for i in 0..rows {
        let t = 1.0 - 2.0 * (i as f64 + 0.5) / rows as f64;
        let y = y0 + i as f64;
        p.rect([x0, y], [x1 - x0, 1.0], &Style::fill(&hex(t)), "");
    }
    p.rect(
        [x0, y0],
        [x1 - x0, y1 - y0],
        &Style::stroke("black", 1.0),
        "",
    );
    let right = x0 - 4.0;
    p.text(
        [(x0 + x1) / 2.0, y0 - 8.0],
        if range.relative { "H·r" } else { "H" },
        12.0,
        Anchor::Middle,
        "black",
    );
    for (y, text) in [
        (y0, format!("+{}", label(span))),
        ((y0 + y1) / 2.0, "0".to_string()),
        (y1, label(-span)),
    ] {
        p.text([right, y + 4.0], &text, 11.0, Anchor::End, "black");
    }
    p
}

/// Draws the bar of `range` into the right [`WIDTH`] pixels of `img` (nothing if it does not
/// fit).
pub fn bar(img: &mut Image, range: &Range) -> Result<(), String> {
    let (w, h) = (img.width, img.height);
    if !fits(w, h) {
        return Ok(());
    }
    let pixmap = picture(h, range).pixmap().map_err(|e| e.message)?;
    // The picture's background is opaque white, so its premultiplied pixels are the colours.
    for (y, row) in pixmap.pixels().chunks_exact(WIDTH).enumerate() {
        for (x, px) in row.iter().enumerate() {
            img.pixels[y * w + w - WIDTH + x] = [px.red(), px.green(), px.blue()];
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_have_three_significant_digits() {
        assert_eq!(label(1.8349), "1.83");
        assert_eq!(label(-0.042149), "-0.0421");
        assert_eq!(label(125.4), "125");
        assert_eq!(label(0.0000183), "1.83e-5");
        assert_eq!(label(25000.0), "2.50e4");
    }

    #[test]
    fn the_bar_runs_from_red_at_the_top_to_blue_at_the_bottom_with_text() {
        let mut img = Image {
            width: 300,
            height: 200,
            pixels: vec![[7; 3]; 300 * 200],
        };
        bar(&mut img, &crate::render::curvature::range(&[1.5], None)).unwrap();
        let at = |x: usize, y: usize| img.pixels[y * 300 + x];
        let x = 300 - 23;
        let (top, bottom) = (at(x, 200 / 5 + 2), at(x, 200 - 200 / 5 - 2));
        assert!(top[0] > 200 && top[2] < 80, "{top:?}");
        assert!(bottom[2] > 200 && bottom[0] < 80, "{bottom:?}");
        assert_eq!(at(0, 0), [7; 3], "the picture part is left alone");
        // The labels left of the bar put dark pixels on the white strip.
        let dark = (200..270)
            .flat_map(|x| (0..200).map(move |y| (x, y)))
            .filter(|&(x, y)| at(x, y)[0] < 100)
            .count();
        assert!(dark > 20, "{dark} dark label pixels");
    }
}
