//! What makes a picture readable on its own: a title, and a colour bar that shows which
//! colour each value of the written quality gets — its ends labelled with the quality's
//! minimum and maximum, the colour map's saturation points marked where they lie inside —
//! drawn with an 8×8 bitmap font (font8x8's public-domain glyphs).

use super::render::diverging_color;

/// Pixel size of a glyph (font8x8's 8 × 8 at scale 1).
const GLYPH: usize = 8;

/// The colour bar's box in a picture of `width` × `height`: (x0, y0, x1, y1), x1 and y1
/// excluded. Top row: the quality's maximum; bottom row: its minimum.
pub fn colour_bar_box(width: u32, height: u32) -> (usize, usize, usize, usize) {
    let (w, h) = (width as usize, height as usize);
    let x0 = w.saturating_sub(110);
    (
        x0,
        40.min(h / 4),
        (x0 + 16).min(w),
        h.saturating_sub(40.min(h / 4)),
    )
}

/// A value as the bar labels it: 4 significant digits.
pub fn label(value: f64) -> String {
    format!("{value:.3e}")
}

/// Draws `text` with its top-left corner at (x, y), clipped to the image.
pub fn draw_text(image: &mut [u8], width: usize, x: usize, y: usize, text: &str, colour: [u8; 3]) {
    let height = image.len() / (3 * width);
    for (k, ch) in text.chars().enumerate() {
        let glyph = font8x8::legacy::BASIC_LEGACY
            .get(ch as usize)
            .copied()
            .unwrap_or(font8x8::legacy::NOTHING_TO_DISPLAY);
        for (row, bits) in glyph.iter().enumerate() {
            for col in 0..GLYPH {
                if bits >> col & 1 == 1 {
                    let (px, py) = (x + k * GLYPH + col, y + row);
                    if px < width && py < height {
                        image[(py * width + px) * 3..][..3].copy_from_slice(&colour);
                    }
                }
            }
        }
    }
}

/// The 8-bit colour the picture gives `value` under the colour range (lo, hi).
pub fn colour_of(value: f64, (lo, hi): (f64, f64)) -> [u8; 3] {
    diverging_color((value - lo) / (hi - lo)).map(|c| (255.0 * c.clamp(0.0, 1.0)) as u8)
}

/// Draws the colour bar for values from `min` to `max` coloured under `range`, its labels
/// and the quantity's name, into an RGB image of `width` × `height`.
pub fn draw_colour_bar(
    image: &mut [u8],
    width: u32,
    height: u32,
    (min, max): (f64, f64),
    range: (f64, f64),
    quantity: &str,
) {
    const TEXT: [u8; 3] = [230, 230, 230];
    let w = width as usize;
    let (x0, y0, x1, y1) = colour_bar_box(width, height);
    if y1 <= y0 + 1 || x1 <= x0 {
        return;
    }
    let rows = y1 - y0;
    let value_at = |row: usize| max - (max - min) * row as f64 / (rows - 1) as f64;
    for row in 0..rows {
        let c = colour_of(value_at(row), range);
        for x in x0..x1 {
            image[((y0 + row) * w + x) * 3..][..3].copy_from_slice(&c);
        }
    }
    let text_x = x1 + 6;
    draw_text(image, w, text_x, y0, &label(max), TEXT);
    draw_text(image, w, text_x, y1 - GLYPH, &label(min), TEXT);
    // Where the colours saturate inside the bar: a tick and its value.
    for end in [range.0, range.1] {
        if end > min && end < max && max > min {
            let row = ((max - end) / (max - min) * (rows - 1) as f64).round() as usize;
            for x in x0.saturating_sub(4)..x0 {
                image[((y0 + row) * w + x) * 3..][..3].copy_from_slice(&TEXT);
            }
            // Kept clear of the end labels.
            let (top, bottom) = (y0 + GLYPH + 2, y1.saturating_sub(2 * GLYPH + 2));
            if top <= bottom {
                let y = (y0 + row).saturating_sub(GLYPH / 2).clamp(top, bottom);
                draw_text(image, w, text_x, y, &label(end), TEXT);
            }
        }
    }
    let name_x = w
        .saturating_sub(quantity.chars().count() * GLYPH + 4)
        .min(x0);
    draw_text(
        image,
        w,
        name_x,
        y0.saturating_sub(GLYPH + 6),
        quantity,
        TEXT,
    );
}
