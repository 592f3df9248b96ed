//! The colour bar of the curvature map, labelled with its range in a 3 × 5 pixel font.

use super::curvature::colour;
use super::image::Image;

/// Glyph rows, 3 bits each (the high bit is the left column), top row first.
fn glyph(c: char) -> Option<[u8; 5]> {
    Some(match c {
        '0' => [7, 5, 5, 5, 7],
        '1' => [2, 6, 2, 2, 7],
        '2' => [7, 1, 7, 4, 7],
        '3' => [7, 1, 7, 1, 7],
        '4' => [5, 5, 7, 1, 1],
        '5' => [7, 4, 7, 1, 7],
        '6' => [7, 4, 7, 5, 7],
        '7' => [7, 1, 1, 1, 1],
        '8' => [7, 5, 7, 5, 7],
        '9' => [7, 5, 7, 1, 7],
        '.' => [0, 0, 0, 0, 2],
        '-' => [0, 0, 7, 0, 0],
        '+' => [0, 2, 7, 2, 0],
        'e' => [2, 5, 7, 4, 3],
        'H' => [5, 5, 7, 5, 5],
        _ => return None,
    })
}

/// Pixels per font pixel.
const SCALE: usize = 2;
/// Width of one character cell, spacing included.
const ADVANCE: usize = 4 * SCALE;

fn put(img: &mut Image, x: usize, y: usize, c: [u8; 3]) {
    if x < img.width && y < img.height {
        img.pixels[y * img.width + x] = c;
    }
}

/// Draws `text` with its top right corner at (right, top).
fn text(img: &mut Image, text: &str, right: usize, top: usize) {
    let left = right.saturating_sub(text.chars().count() * ADVANCE);
    for (i, c) in text.chars().enumerate() {
        let Some(rows) = glyph(c) else { continue };
        for (r, bits) in rows.iter().enumerate() {
            for col in 0..3 {
                if bits >> (2 - col) & 1 == 1 {
                    for dy in 0..SCALE {
                        for dx in 0..SCALE {
                            let x = left + i * ADVANCE + col * SCALE + dx;
                            put(img, x, top + r * SCALE + dy, [0, 0, 0]);
                        }
                    }
                }
            }
        }
    }
}

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

/// A vertical colour bar in the right [`WIDTH`] pixels, +span at the top, −span at the bottom,
/// labelled.
pub fn bar(img: &mut Image, span: f64) {
    let (w, h) = (img.width, img.height);
    if !fits(w, h) {
        return;
    }
    for y in 0..h {
        img.pixels[y * w + w - WIDTH..(y + 1) * w].fill([255; 3]);
    }
    let (x0, x1) = (w - 30, w - 16);
    let (y0, y1) = (h / 5, h - h / 5);
    for y in y0..=y1 {
        let t = 1.0 - 2.0 * (y - y0) as f64 / (y1 - y0) as f64;
        let c = colour(t).map(|c| (c * 255.0).round() as u8);
        for x in x0..=x1 {
            let frame = y == y0 || y == y1 || x == x0 || x == x1;
            put(img, x, y, if frame { [0, 0, 0] } else { c });
        }
    }
    let right = x0 - 4;
    let glyph_height = 5 * SCALE;
    text(img, "H", x1 - 3, y0 - glyph_height - 6);
    text(img, &format!("+{}", label(span)), right, y0);
    text(img, "0", right, (y0 + y1 - glyph_height) / 2);
    text(img, &label(-span), right, y1 + 1 - glyph_height);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_have_three_significant_digits_and_only_drawable_characters() {
        assert_eq!(label(1.8349), "1.83");
        assert_eq!(label(-0.042149), "-0.0421");
        assert_eq!(label(125.4), "125");
        assert_eq!(label(0.0000183), "1.83e-5");
        assert_eq!(label(25000.0), "2.50e4");
        for x in [1.8349, -0.042149, 0.0000183, 2.5e4, 7.0] {
            assert!(label(x).chars().all(|c| glyph(c).is_some()), "{x}");
        }
    }
}
