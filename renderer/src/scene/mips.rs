//! Mip chains of scene images, built on the CPU at upload: each level a box filter of the one
//! above (2×2 texels, the last row or column of an odd size folded into its neighbour's
//! average, so every texel of the level above counts). Colour images (sRGB-encoded) are
//! averaged in linear light, data images (normals, metallic-roughness, occlusion) as stored.

use super::Image;

/// The number of levels of a full chain for a `width` × `height` image (down to 1×1).
pub fn level_count(width: u32, height: u32) -> u32 {
    32 - width.max(height).max(1).leading_zeros()
}

/// The size of `level` of a `width` × `height` image.
fn level_size(width: u32, height: u32, level: u32) -> (u32, u32) {
    ((width >> level).max(1), (height >> level).max(1))
}

/// Every level of `image`'s chain, level 0 first, concatenated (the layout wgpu's
/// `create_texture_with_data` takes for one layer). `srgb`: the texels are sRGB-encoded colour,
/// averaged in linear light and re-encoded.
pub fn mip_chain(image: &Image, srgb: bool) -> Vec<u8> {
    let levels = level_count(image.width, image.height);
    let mut out = image.rgba8.clone();
    // Decoding is a table per channel kind: sRGB colour channels to linear, alpha and data as
    // stored.
    let data_table: [f32; 256] = std::array::from_fn(|v| v as f32 / 255.0);
    let colour_table: [f32; 256] = if srgb {
        std::array::from_fn(|v| srgb_to_linear(v as u8))
    } else {
        data_table
    };
    let encode = |v: f32, channel: usize| -> u8 {
        let v = if srgb && channel != 3 {
            linear_to_srgb(v)
        } else {
            v
        };
        (v.clamp(0.0, 1.0) * 255.0).round() as u8
    };
    let mut above: Vec<[f32; 4]> = image
        .rgba8
        .chunks_exact(4)
        .map(|t| {
            [
                colour_table[usize::from(t[0])],
                colour_table[usize::from(t[1])],
                colour_table[usize::from(t[2])],
                data_table[usize::from(t[3])],
            ]
        })
        .collect();
    for level in 1..levels {
        let (aw, ah) = level_size(image.width, image.height, level - 1);
        let (w, h) = level_size(image.width, image.height, level);
        let columns: Vec<std::ops::Range<u32>> = (0..w).map(|x| source_span(x, w, aw)).collect();
        let mut next = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            let rows = source_span(y, h, ah);
            for xs in &columns {
                let count = (xs.len() * rows.len()) as f32;
                let mut sum = [0.0f32; 4];
                for sy in rows.clone() {
                    let row = &above[(sy * aw) as usize..][..aw as usize];
                    for texel in &row[xs.start as usize..xs.end as usize] {
                        for (s, v) in sum.iter_mut().zip(texel) {
                            *s += v;
                        }
                    }
                }
                next.push(sum.map(|s| s / count));
            }
        }
        out.extend(
            next.iter()
                .flat_map(|t| (0..4).map(move |c| encode(t[c], c))),
        );
        above = next;
    }
    out
}

/// The texels of the level above that texel `i` of a `size`-texel level averages: `2i, 2i + 1`,
/// plus `2i + 2` for the last texel when the level above has an odd size (or `0` alone when the
/// level above is 1 texel wide).
fn source_span(i: u32, size: u32, above: u32) -> std::ops::Range<u32> {
    let start = (2 * i).min(above - 1);
    let mut end = (2 * i + 2).min(above);
    if i + 1 == size {
        end = above;
    }
    start..end.max(start + 1)
}

fn srgb_to_linear(v: u8) -> f32 {
    let c = f32::from(v) / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(c: f32) -> f32 {
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, rgba8: Vec<u8>) -> Image {
        Image {
            width,
            height,
            rgba8,
        }
    }

    #[test]
    fn chain_sizes() {
        assert_eq!(level_count(1, 1), 1);
        assert_eq!(level_count(4, 4), 3);
        assert_eq!(level_count(5, 3), 3);
        assert_eq!(level_count(256, 1), 9);
        // 5×3 → 2×1 → 1×1.
        let chain = mip_chain(&image(5, 3, vec![0; 60]), false);
        assert_eq!(chain.len(), (15 + 2 + 1) * 4);
    }

    #[test]
    fn data_averages_as_stored_and_colour_in_linear_light() {
        // A 2×1 image, black and white: data averages to 128 (127.5 rounded), colour to linear
        // 0.5, which sRGB encodes as 188.
        let texels = vec![0, 0, 0, 0, 255, 255, 255, 255];
        let data = mip_chain(&image(2, 1, texels.clone()), false);
        assert_eq!(&data[8..], &[128, 128, 128, 128]);
        let colour = mip_chain(&image(2, 1, texels), true);
        assert_eq!(&colour[8..], &[188, 188, 188, 128], "alpha stays linear");
    }

    #[test]
    fn odd_sizes_count_every_texel() {
        // 3×1: 0, 0, 255 → one texel (level 1 is 1×1) averaging all three: 85.
        let chain = mip_chain(&image(3, 1, [0, 0, 255].repeat(4)), false);
        let chain_r: Vec<u8> = chain.chunks(4).map(|t| t[0]).collect();
        // The input repeats 0, 0, 255 per byte: texels (0,0,255,0), (0,255,0,0), (255,0,0,255).
        assert_eq!(chain_r, vec![0, 0, 255, 85]);
    }
}
