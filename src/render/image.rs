//! An 8-bit RGB image and its encodings: PNG (the `png` crate) and binary PPM.

/// Row-major RGB pixels, top row first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width × height` pixels.
    pub pixels: Vec<[u8; 3]>,
}

/// An image file format (the command line picks it by the output's extension).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// `.png`
    Png,
    /// `.ppm` (binary P6)
    Ppm,
}

impl Image {
    /// The encoded file.
    pub fn encode(&self, format: Format) -> Result<Vec<u8>, String> {
        let bytes = self.pixels.iter().flatten().copied();
        match format {
            Format::Ppm => {
                let mut out = format!("P6\n{} {}\n255\n", self.width, self.height).into_bytes();
                out.extend(bytes);
                Ok(out)
            }
            Format::Png => {
                let mut out = Vec::new();
                let mut e = png::Encoder::new(&mut out, self.width as u32, self.height as u32);
                e.set_color(png::ColorType::Rgb);
                e.set_depth(png::BitDepth::Eight);
                e.set_compression(png::Compression::Best);
                e.set_adaptive_filter(png::AdaptiveFilterType::Adaptive);
                let data: Vec<u8> = bytes.collect();
                e.write_header()
                    .and_then(|mut w| w.write_image_data(&data))
                    .map_err(|e| format!("PNG encoding failed: {e}"))?;
                Ok(out)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_round_trip_and_ppm_header() {
        let img = Image {
            width: 3,
            height: 2,
            pixels: (0..6).map(|i| [i * 40, 255 - i * 40, 7]).collect(),
        };
        let png = img.encode(Format::Png).unwrap();
        let mut r = png::Decoder::new(png.as_slice()).read_info().unwrap();
        let mut buf = vec![0; r.output_buffer_size()];
        let info = r.next_frame(&mut buf).unwrap();
        assert_eq!((info.width, info.height), (3, 2));
        assert_eq!(&buf[..info.buffer_size()], img.pixels.concat().as_slice());
        let ppm = img.encode(Format::Ppm).unwrap();
        assert!(ppm.starts_with(b"P6\n3 2\n255\n") && ppm.len() == 11 + 18);
    }
}
