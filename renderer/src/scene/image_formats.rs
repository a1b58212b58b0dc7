//! Every pixel format the gltf crate decodes an image to, converted to the RGBA8 the renderer
//! uploads: 16-bit channels become `round(v / 257)`, float channels are clamped to [0, 1] and
//! scaled to 255 (rounded), grey is replicated to RGB, and a missing alpha is opaque. The gltf
//! crate reports a grey+alpha PNG as `R8G8` / `R16G16` (its only source of two-channel
//! images), so the second channel is alpha.

use gltf::image::Format;

/// `pixels` (in `format`, channels in native byte order as the gltf crate hands them over) as
/// RGBA8. Trailing bytes that do not fill a pixel are dropped; the caller checks the length.
pub(super) fn to_rgba8(format: Format, pixels: Vec<u8>) -> Vec<u8> {
    let (channels, values) = match format {
        Format::R8G8B8A8 => return pixels,
        Format::R8 => (1, pixels),
        Format::R8G8 => (2, pixels),
        Format::R8G8B8 => (3, pixels),
        Format::R16 => (1, unorm16(&pixels)),
        Format::R16G16 => (2, unorm16(&pixels)),
        Format::R16G16B16 => (3, unorm16(&pixels)),
        Format::R16G16B16A16 => (4, unorm16(&pixels)),
        Format::R32G32B32FLOAT => (3, float32(&pixels)),
        Format::R32G32B32A32FLOAT => (4, float32(&pixels)),
    };
    match channels {
        1 => values.iter().flat_map(|&g| [g, g, g, 255]).collect(),
        2 => values
            .chunks_exact(2)
            .flat_map(|c| [c[0], c[0], c[0], c[1]])
            .collect(),
        3 => values
            .chunks_exact(3)
            .flat_map(|c| [c[0], c[1], c[2], 255])
            .collect(),
        _ => values,
    }
}

/// Each 16-bit channel as 8 bits, rounded to nearest: `(v + 128) / 257` in integers equals
/// `round(v / 257)` for every `v` (no `v + 128.5` is a multiple of 257).
fn unorm16(bytes: &[u8]) -> Vec<u8> {
    bytes
        .chunks_exact(2)
        .map(|b| {
            let v = u32::from(u16::from_ne_bytes([b[0], b[1]]));
            u8::try_from((v + 128) / 257).unwrap_or(u8::MAX)
        })
        .collect()
}

/// Each 32-bit float channel clamped to [0, 1] and scaled to 255, rounded; NaN becomes 0.
fn float32(bytes: &[u8]) -> Vec<u8> {
    bytes
        .chunks_exact(4)
        .map(|b| {
            let v = f32::from_ne_bytes([b[0], b[1], b[2], b[3]]);
            // `as` saturates and maps NaN to 0; the value is already in [0, 255].
            (v.clamp(0.0, 1.0) * 255.0).round() as u8
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ne16(values: &[u16]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_ne_bytes()).collect()
    }

    fn ne32(values: &[f32]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_ne_bytes()).collect()
    }

    #[test]
    fn sixteen_bit_channels_round_to_nearest() {
        assert_eq!(
            to_rgba8(Format::R16, ne16(&[0, 128, 129, 25828, 25829, 65535])),
            [
                0, 0, 0, 255, 0, 0, 0, 255, 1, 1, 1, 255, 100, 100, 100, 255, 101, 101, 101, 255,
                255, 255, 255, 255
            ]
        );
        assert_eq!(
            to_rgba8(Format::R16G16, ne16(&[514, 65535])),
            [2, 2, 2, 255]
        );
        assert_eq!(
            to_rgba8(Format::R16G16B16, ne16(&[257, 514, 771])),
            [1, 2, 3, 255]
        );
        assert_eq!(
            to_rgba8(Format::R16G16B16A16, ne16(&[257, 514, 771, 0])),
            [1, 2, 3, 0]
        );
    }

    #[test]
    fn float_channels_clamp_and_round() {
        assert_eq!(
            to_rgba8(Format::R32G32B32FLOAT, ne32(&[-1.0, 0.5, 2.0])),
            [0, 128, 255, 255]
        );
        assert_eq!(
            to_rgba8(Format::R32G32B32A32FLOAT, ne32(&[0.2, f32::NAN, 1.0, 0.0])),
            [51, 0, 255, 0]
        );
    }

    #[test]
    fn eight_bit_grey_rgb_and_rgba() {
        assert_eq!(to_rgba8(Format::R8, vec![9]), [9, 9, 9, 255]);
        assert_eq!(to_rgba8(Format::R8G8, vec![9, 40]), [9, 9, 9, 40]);
        assert_eq!(to_rgba8(Format::R8G8B8, vec![1, 2, 3]), [1, 2, 3, 255]);
        assert_eq!(to_rgba8(Format::R8G8B8A8, vec![1, 2, 3, 4]), [1, 2, 3, 4]);
    }
}
