//! How a material samples a texture: the glTF sampler (wrap and filter modes) and the
//! `KHR_texture_transform` of a texture reference.

use glam::{Mat3, Vec2};

/// What happens to texture coordinates outside `[0, 1]` (glTF `wrapS` / `wrapT`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Wrap {
    /// glTF's default.
    #[default]
    Repeat,
    MirroredRepeat,
    ClampToEdge,
}

/// A texel filter (glTF `magFilter`, `minFilter` and the mipmap part of `minFilter`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Filter {
    Nearest,
    #[default]
    Linear,
}

/// A glTF sampler. Where the file leaves a filter undefined the renderer picks linear, with
/// linear mipmaps, as glTF lets implementations choose.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TextureSampler {
    pub wrap_u: Wrap,
    pub wrap_v: Wrap,
    pub mag_filter: Filter,
    pub min_filter: Filter,
    /// How mip levels are filtered; `None`: only level 0 is sampled (glTF `NEAREST` or `LINEAR`
    /// as `minFilter`).
    pub mipmap_filter: Option<Filter>,
}

impl Default for TextureSampler {
    fn default() -> Self {
        Self {
            wrap_u: Wrap::Repeat,
            wrap_v: Wrap::Repeat,
            mag_filter: Filter::Linear,
            min_filter: Filter::Linear,
            mipmap_filter: Some(Filter::Linear),
        }
    }
}

/// `KHR_texture_transform`: texture coordinates are scaled, then rotated, then offset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UvTransform {
    pub offset: Vec2,
    /// Radians, counter-clockwise in UV space.
    pub rotation: f32,
    pub scale: Vec2,
}

impl UvTransform {
    pub const IDENTITY: Self = Self {
        offset: Vec2::ZERO,
        rotation: 0.0,
        scale: Vec2::ONE,
    };

    /// The 3×3 matrix that maps `(u, v, 1)`: translation × rotation × scale, as the extension
    /// specifies.
    pub fn matrix(&self) -> Mat3 {
        let (s, c) = self.rotation.sin_cos();
        let translation = Mat3::from_cols(
            glam::Vec3::X,
            glam::Vec3::Y,
            self.offset.extend(1.0),
        );
        let rotation = Mat3::from_cols(
            glam::Vec3::new(c, -s, 0.0),
            glam::Vec3::new(s, c, 0.0),
            glam::Vec3::Z,
        );
        translation * rotation * Mat3::from_diagonal(self.scale.extend(1.0))
    }
}

impl Default for UvTransform {
    fn default() -> Self {
        Self::IDENTITY
    }
}
