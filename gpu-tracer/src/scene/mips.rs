//! Mip chains of the scene's images, for the footprint-filtered lookups of
//! `kernels::texture_filter`: level `l + 1` is the 2x2 box average of
//! level `l`, half its size rounded down (at least 1), down to 1x1; an odd
//! size's last row or column is clamped (read twice). Colour images are
//! averaged in linear light (sRGB decoded, averaged, re-encoded with
//! rounding); data images (metallic-roughness and the like) and alpha are
//! averaged as stored.

use super::Image;

/// The levels after level 0 of `image` (which must be valid: `width *
/// height` texels), from the largest to 1x1; empty for a 1x1 image. With
/// `srgb`, the RGB channels are averaged in linear light.
pub(super) fn mip_levels(image: &Image, srgb: bool) -> Vec<(u32, u32, Vec<[u8; 4]>)> {
    let mut levels = Vec::new();
    let (mut w, mut h) = (image.width, image.height);
    let mut texels = image.texels.clone();
    while w > 1 || h > 1 {
        let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
        let at = |x: u32, y: u32| texels[(y.min(h - 1) * w + x.min(w - 1)) as usize];
        let mut next = Vec::with_capacity((nw * nh) as usize);
        for y in 0..nh {
            for x in 0..nw {
                let quad = [
                    at(2 * x, 2 * y),
                    at(2 * x + 1, 2 * y),
                    at(2 * x, 2 * y + 1),
                    at(2 * x + 1, 2 * y + 1),
                ];
                let mut out = [0u8; 4];
                for (c, slot) in out.iter_mut().enumerate() {
                    *slot = if srgb && c < 3 {
                        let mean = quad.iter().map(|t| srgb_to_linear(t[c])).sum::<f64>() / 4.0;
                        linear_to_srgb(mean)
                    } else {
                        let sum: u32 = quad.iter().map(|t| t[c] as u32).sum();
                        ((sum + 2) / 4) as u8
                    };
                }
                next.push(out);
            }
        }
        levels.push((nw, nh, next.clone()));
        (w, h, texels) = (nw, nh, next);
    }
    levels
}

/// sRGB decoding (IEC 61966-2-1) of an 8-bit channel, in `[0, 1]`.
fn srgb_to_linear(c: u8) -> f64 {
    let c = c as f64 / 255.0;
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// sRGB encoding of a linear value in `[0, 1]`, rounded to 8 bits.
fn linear_to_srgb(v: f64) -> u8 {
    let v = v.clamp(0.0, 1.0);
    let c = if v <= 0.003_130_8 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (c * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, texels: Vec<[u8; 4]>) -> Image {
        Image {
            name: "test".into(),
            width,
            height,
            texels,
        }
    }

    #[test]
    fn levels_halve_down_to_one_texel() {
        let img = image(5, 2, vec![[10, 20, 30, 255]; 10]);
        let sizes: Vec<(u32, u32)> = mip_levels(&img, true).iter().map(|l| (l.0, l.1)).collect();
        assert_eq!(sizes, [(2, 1), (1, 1)]);
        // A constant image stays constant (sRGB round trip exact at 8 bits).
        for (_, _, t) in mip_levels(&img, true) {
            assert!(t.iter().all(|&x| x == [10, 20, 30, 255]), "{t:?}");
        }
        assert!(mip_levels(&image(1, 1, vec![[0; 4]]), true).is_empty());
    }

    /// Black and white average to linear grey 0.5 (sRGB 188) as colour, to
    /// 128 as data; alpha is averaged as stored.
    #[test]
    fn colour_averages_in_linear_light() {
        let img = image(2, 1, vec![[0, 0, 0, 0], [255, 255, 255, 255]]);
        let colour = &mip_levels(&img, true)[0].2[0];
        assert_eq!(colour, &[188, 188, 188, 128]);
        let data = &mip_levels(&img, false)[0].2[0];
        assert_eq!(data, &[128, 128, 128, 128]);
    }
}
