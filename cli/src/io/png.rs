//! PNG encoding of an 8-bit RGB image, by the `png` crate (default
//! compression and filtering).

use crate::error::{CliError, CliResult};

/// The PNG file of the `w` x `h` image `rgb` (rows top to bottom, 3 bytes a
/// pixel).
pub fn png_rgb(w: u32, h: u32, rgb: &[u8]) -> CliResult<Vec<u8>> {
    let fail = |e: png::EncodingError| CliError::failure(format!("cannot encode PNG: {e}"));
    let mut file = Vec::new();
    let mut encoder = png::Encoder::new(&mut file, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(fail)?;
    writer.write_image_data(rgb).map_err(fail)?;
    writer.finish().map_err(fail)?;
    Ok(file)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decodes_to_the_same_pixels() {
        let (w, h) = (300u32, 257u32);
        let rgb: Vec<u8> = (0..w * h * 3).map(|i| (i * 7 % 251) as u8).collect();
        let file = png_rgb(w, h, &rgb).unwrap();
        let mut reader = png::Decoder::new(std::io::Cursor::new(file))
            .read_info()
            .unwrap();
        let mut out = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut out).unwrap();
        assert_eq!((info.width, info.height), (w, h));
        assert_eq!(
            (info.color_type, info.bit_depth),
            (png::ColorType::Rgb, png::BitDepth::Eight)
        );
        assert_eq!(&out[..info.buffer_size()], &rgb[..]);
        assert!(png_rgb(w, h, &rgb[1..]).is_err());
    }
}
