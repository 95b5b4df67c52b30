//! Traversal heat maps: nodes visited per pixel as a colour-mapped picture with a legend bar
//! (the colour scale, its numbers and their unit) underneath. Drawn with a built-in 3x5 font
//! (digits and the capitals the units need), so the picture needs nothing but the `image` crate.

use anyhow::{anyhow, Context as _, Result};
use image::{Rgb, RgbImage};
use std::path::Path;

/// Viridis (van der Walt & Smith 2015) at five stops, interpolated linearly: perceptually
/// ordered and readable in grey and by colour-blind readers.
const STOPS: [[f32; 3]; 5] = [[68.0, 1.0, 84.0], [59.0, 82.0, 139.0], [33.0, 145.0, 140.0], [94.0, 201.0, 98.0], [253.0, 231.0, 37.0]];

/// Colour of `x` in [0, 1].
pub fn colour(x: f32) -> Rgb<u8> {
    let x = if x.is_nan() { 0.0 } else { x.clamp(0.0, 1.0) } * (STOPS.len() - 1) as f32;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f32;
    let c: [u8; 3] = std::array::from_fn(|k| (STOPS[i][k] + f * (STOPS[i + 1][k] - STOPS[i][k])).round() as u8);
    Rgb(c)
}

/// 3x5 bitmaps of 0-9, one row per 3-bit number (MSB = left).
const DIGITS: [[u8; 5]; 10] = [
    [7, 5, 5, 5, 7],
    [2, 6, 2, 2, 7],
    [7, 1, 7, 4, 7],
    [7, 1, 7, 1, 7],
    [5, 5, 7, 1, 1],
    [7, 4, 7, 1, 7],
    [7, 4, 7, 5, 7],
    [7, 1, 2, 2, 2],
    [7, 5, 7, 5, 7],
    [7, 5, 7, 1, 7],
];
const SCALE: u32 = 2;

/// 3x5 bitmaps of the capitals and marks the legends' units are written in.
const LETTERS: [(u8, [u8; 5]); 24] = [
    (b'A', [2, 5, 7, 5, 5]),
    (b'C', [3, 4, 4, 4, 3]),
    (b'F', [7, 4, 6, 4, 4]),
    (b'Y', [5, 5, 2, 2, 2]),
    (b'D', [6, 5, 5, 5, 6]),
    (b'E', [7, 4, 6, 4, 7]),
    (b'I', [7, 2, 2, 2, 7]),
    (b'L', [4, 4, 4, 4, 7]),
    (b'N', [6, 5, 5, 5, 5]),
    (b'O', [2, 5, 5, 5, 2]),
    (b'P', [6, 5, 6, 4, 4]),
    (b'Q', [2, 5, 5, 6, 3]),
    (b'R', [6, 5, 6, 5, 5]),
    (b'S', [3, 4, 2, 1, 6]),
    (b'T', [7, 2, 2, 2, 2]),
    (b'U', [5, 5, 5, 5, 7]),
    (b'V', [5, 5, 5, 5, 2]),
    (b'X', [5, 5, 2, 5, 5]),
    (b'-', [0, 0, 7, 0, 0]),
    (b'.', [0, 0, 0, 0, 2]),
    (b',', [0, 0, 0, 2, 4]),
    (b'(', [1, 2, 2, 2, 1]),
    (b')', [4, 2, 2, 2, 4]),
    (b' ', [0; 5]),
];

/// The glyph of `ch`: a digit, one of [`LETTERS`] (lower case drawn as capitals), else blank.
fn glyph(ch: u8) -> [u8; 5] {
    if ch.is_ascii_digit() {
        return DIGITS[(ch - b'0') as usize];
    }
    let up = ch.to_ascii_uppercase();
    LETTERS.iter().find(|(c, _)| *c == up).map_or([0; 5], |(_, g)| *g)
}

fn draw_number(img: &mut RgbImage, value: u32, x: u32, y: u32) {
    draw_text(img, &value.to_string(), x, y);
}

/// `text` in white from (x, y), clipped to the picture.
fn draw_text(img: &mut RgbImage, text: &str, x: u32, y: u32) {
    for (k, ch) in text.bytes().enumerate() {
        let glyph = &glyph(ch);
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..3u32 {
                if bits & (4 >> col) != 0 {
                    for dy in 0..SCALE {
                        for dx in 0..SCALE {
                            let px = x + (k as u32 * 4 + col) * SCALE + dx;
                            let py = y + row as u32 * SCALE + dy;
                            if px < img.width() && py < img.height() {
                                img.put_pixel(px, py, Rgb([255, 255, 255]));
                            }
                        }
                    }
                }
            }
        }
    }
}

/// The heat map of `counts` (row-major, `width` x `height`), scaled from 0 to the largest count,
/// with a legend underneath: the colour bar, the counts at its ends and quarters, and under them
/// `unit`, what the counts count.
pub fn render(counts: &[u32], width: u32, height: u32, unit: &str) -> Result<RgbImage> {
    if counts.len() != (width as usize) * (height as usize) || width == 0 {
        return Err(anyhow!("heat map: {} counts for {width}x{height} pixels", counts.len()));
    }
    let max = counts.iter().copied().max().unwrap_or(0).max(1);
    let legend = 16 * SCALE + 18;
    let mut img = RgbImage::new(width, height + legend);
    for (i, &c) in counts.iter().enumerate() {
        img.put_pixel(i as u32 % width, i as u32 / width, colour(c as f32 / max as f32));
    }
    let bar_y = height + 4;
    for x in 0..width {
        let c = colour(x as f32 / (width - 1).max(1) as f32);
        for y in bar_y..bar_y + 8 {
            img.put_pixel(x, y, c);
        }
    }
    let label_w = |v: u32| v.to_string().len() as u32 * 4 * SCALE;
    for q in 0..=4u32 {
        let v = max * q / 4;
        let x = ((width - 1) * q / 4).saturating_sub(label_w(v) * q / 4);
        draw_number(&mut img, v, x, bar_y + 10);
    }
    draw_text(&mut img, unit, 0, bar_y + 10 + 6 * SCALE + 2);
    Ok(img)
}

/// Render and write a heat map as PNG, atomically (`unit`: what the legend's numbers count).
pub fn write(path: &Path, counts: &[u32], width: u32, height: u32, unit: &str) -> Result<()> {
    let img = render(counts, width, height, unit)?;
    crate::files::write_whole(path, |tmp| Ok(img.save_with_format(tmp, image::ImageFormat::Png)?))
        .with_context(|| format!("writing heat map {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The legend's last row spells its unit: white pixels there, none without a unit.
    #[test]
    fn the_legend_names_its_unit() {
        let counts: Vec<u32> = (0..64 * 8).map(|i| i % 7).collect();
        let row_has_text = |img: &RgbImage| {
            let y0 = 8 + 4 + 10 + 6 * SCALE + 2;
            (y0..y0 + 5 * SCALE).any(|y| (0..img.width()).any(|x| img.get_pixel(x, y).0 == [255, 255, 255]))
        };
        assert!(row_has_text(&render(&counts, 64, 8, "NODES VISITED").unwrap()));
        assert!(!row_has_text(&render(&counts, 64, 8, "").unwrap()));
        assert_eq!(glyph(b'n'), glyph(b'N'));
        assert_ne!(glyph(b'O'), glyph(b'0'), "O and 0 are told apart");
    }
}
