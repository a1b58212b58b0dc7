//! Decal materials as images: one RGBA8 image per channel (base colour with alpha, tangent-space
//! normal, occlusion-roughness-metalness, emissive), loaded from PNG files with the `image`
//! crate or made in code ([`super::procedural`]).

#[cfg(feature = "png")]
use std::path::Path;

use super::DecalError;

/// The channels a decal material may carry, in atlas order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Channel {
    /// sRGB colour and linear coverage (alpha); every material has it.
    BaseColor = 0,
    /// Tangent-space normal, `n · 0.5 + 0.5` (glTF convention: +Y up in the image).
    Normal = 1,
    /// Occlusion (R), roughness (G), metalness (B), as glTF stores them; linear.
    Orm = 2,
    /// sRGB emitted colour.
    Emissive = 3,
}

impl Channel {
    /// How many channels there are.
    pub const COUNT: usize = 4;
    /// Every channel, in atlas order (bit `c` of a channel mask is `ALL[c]`).
    pub const ALL: [Self; Self::COUNT] = [Self::BaseColor, Self::Normal, Self::Orm, Self::Emissive];

    /// The texel an absent channel is filled with (shading skips absent channels anyway).
    pub fn neutral(self) -> [u8; 4] {
        match self {
            Self::BaseColor => [255, 255, 255, 0],
            Self::Normal => [128, 128, 255, 255],
            Self::Orm => [255, 255, 0, 255],
            Self::Emissive => [0, 0, 0, 255],
        }
    }

    /// The channel's name in messages.
    pub fn name(self) -> &'static str {
        match self {
            Self::BaseColor => "base colour",
            Self::Normal => "normal",
            Self::Orm => "occlusion-roughness-metalness",
            Self::Emissive => "emissive",
        }
    }

    /// Whether the colour components are sRGB-encoded (alpha never is).
    pub fn is_srgb(self) -> bool {
        matches!(self, Self::BaseColor | Self::Emissive)
    }

    /// Component `c` of a stored byte as the value filtering averages.
    pub fn decode(self, c: usize, byte: u8) -> f32 {
        let v = f32::from(byte) / 255.0;
        match self {
            _ if c == 3 => v,
            s if s.is_srgb() => srgb_to_linear(v),
            Self::Normal => v * 2.0 - 1.0,
            _ => v,
        }
    }

    /// The byte stored for a filtered value of component `c`.
    pub fn encode(self, c: usize, value: f32) -> u8 {
        let v = match self {
            _ if c == 3 => value,
            s if s.is_srgb() => linear_to_srgb(value),
            Self::Normal => value * 0.5 + 0.5,
            _ => value,
        };
        (v.clamp(0.0, 1.0) * 255.0).round() as u8
    }
}

fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.003_130_8 {
        v * 12.92
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// An RGBA8 image, rows top to bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DecalImage {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width × height × 4` bytes, encoded as its [`Channel`] says.
    pub rgba: Vec<u8>,
}

impl DecalImage {
    /// A `width`×`height` image of one texel value.
    pub fn solid(width: u32, height: u32, rgba: [u8; 4]) -> Self {
        Self {
            width,
            height,
            rgba: rgba.repeat((width * height) as usize),
        }
    }

    /// An image from `f(x, y)` for every texel.
    pub fn from_fn(width: u32, height: u32, mut f: impl FnMut(u32, u32) -> [u8; 4]) -> Self {
        let mut rgba = Vec::with_capacity((width * height * 4) as usize);
        for y in 0..height {
            for x in 0..width {
                rgba.extend_from_slice(&f(x, y));
            }
        }
        Self {
            width,
            height,
            rgba,
        }
    }

    /// Loads a PNG (any colour type; converted to RGBA8).
    #[cfg(feature = "png")]
    pub fn load_png(path: &Path) -> Result<Self, DecalError> {
        let image = image::open(path).map_err(|e| DecalError::Image {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        let rgba = image.to_rgba8();
        Ok(Self {
            width: rgba.width(),
            height: rgba.height(),
            rgba: rgba.into_raw(),
        })
    }
}

/// A decal material: its base colour and the optional channels, all the same size.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DecalMaterial {
    /// Its name in errors and sidecar files (unique in a sidecar).
    pub name: String,
    /// [`Channel::BaseColor`]: sRGB colour, alpha the decal's coverage.
    pub base_color: DecalImage,
    /// [`Channel::Normal`]; `None`: the surface's normal is kept.
    pub normal: Option<DecalImage>,
    /// [`Channel::Orm`]; `None`: the surface's occlusion, roughness and metalness are kept.
    pub orm: Option<DecalImage>,
    /// [`Channel::Emissive`]; `None`: no emission.
    pub emissive: Option<DecalImage>,
}

/// Largest side of one decal image, in texels.
pub const MAX_DECAL_IMAGE: u32 = 2048;

impl DecalMaterial {
    /// The image of `channel`, when the material has it.
    pub fn channel(&self, channel: Channel) -> Option<&DecalImage> {
        match channel {
            Channel::BaseColor => Some(&self.base_color),
            Channel::Normal => self.normal.as_ref(),
            Channel::Orm => self.orm.as_ref(),
            Channel::Emissive => self.emissive.as_ref(),
        }
    }

    /// Bit `c` for every channel `c` the material has.
    pub fn channel_mask(&self) -> u32 {
        Channel::ALL
            .iter()
            .filter(|&&c| self.channel(c).is_some())
            .fold(0, |m, &c| m | 1 << c as u32)
    }

    /// Every channel non-empty, within [`MAX_DECAL_IMAGE`], and the size of the base colour.
    pub fn check(&self) -> Result<(), DecalError> {
        let (w, h) = (self.base_color.width, self.base_color.height);
        for c in Channel::ALL {
            let Some(image) = self.channel(c) else {
                continue;
            };
            let why = if image.width == 0 || image.height == 0 {
                Some("is empty".to_string())
            } else if image.width.max(image.height) > MAX_DECAL_IMAGE {
                Some(format!("is over {MAX_DECAL_IMAGE} texels on a side"))
            } else if (image.width, image.height) != (w, h) {
                Some(format!(
                    "is {}×{}, the base colour {w}×{h}",
                    image.width, image.height
                ))
            } else if image.rgba.len() != (image.width * image.height * 4) as usize {
                Some("has the wrong number of bytes".to_string())
            } else {
                None
            };
            if let Some(reason) = why {
                return Err(DecalError::Material {
                    name: self.name.clone(),
                    channel: c.name(),
                    reason,
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoding_round_trips_every_byte() {
        for c in Channel::ALL {
            for comp in 0..4 {
                for b in 0..=255u8 {
                    assert_eq!(c.encode(comp, c.decode(comp, b)), b, "{c:?} {comp} {b}");
                }
            }
        }
    }

    #[test]
    fn mismatched_or_empty_channels_name_the_material_and_channel() {
        let mut m = DecalMaterial {
            name: "sign".into(),
            base_color: DecalImage::solid(8, 8, [0; 4]),
            normal: Some(DecalImage::solid(4, 8, [0; 4])),
            orm: None,
            emissive: None,
        };
        let e = m.check().unwrap_err().to_string();
        assert!(
            e.contains("sign") && e.contains("normal channel") && e.contains("4×8"),
            "{e}"
        );
        m.normal = None;
        m.base_color = DecalImage::solid(0, 8, [0; 4]);
        assert!(m.check().unwrap_err().to_string().contains("empty"));
    }

    #[test]
    fn a_missing_png_is_an_error_with_its_path() {
        let e = DecalImage::load_png(Path::new("no/such/decal.png")).unwrap_err();
        assert!(e.to_string().contains("no/such/decal.png"), "{e}");
    }
}
