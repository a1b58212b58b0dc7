//! How a material samples a texture: the glTF sampler (wrap and filter modes) and the
//! `KHR_texture_transform` of a texture reference.

use glam::{Mat3, Vec2};

/// What happens to texture coordinates outside `[0, 1]` (glTF `wrapS` / `wrapT`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Wrap {
    /// glTF's default.
    #[default]
    Repeat,
    /// Repeats, every other copy mirrored.
    MirroredRepeat,
    /// Takes the nearest edge texel.
    ClampToEdge,
}

/// A texel filter (glTF `magFilter`, `minFilter` and the mipmap part of `minFilter`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Filter {
    /// The nearest texel (or mip level).
    Nearest,
    /// Bilinear between texels (or linear between mip levels); the default.
    #[default]
    Linear,
}

/// A glTF sampler. Where the file leaves a filter undefined the renderer picks linear, with
/// linear mipmaps, as glTF lets implementations choose.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TextureSampler {
    /// Wrap along u (glTF `wrapS`).
    pub wrap_u: Wrap,
    /// Wrap along v (glTF `wrapT`).
    pub wrap_v: Wrap,
    /// Filter where a texel covers more than a pixel.
    pub mag_filter: Filter,
    /// Filter within a mip level where a texel covers less than a pixel.
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
    /// Added last, in UV units.
    pub offset: Vec2,
    /// Radians, counter-clockwise in UV space as drawn with v pointing down (the image turns
    /// clockwise): `(u, v)` becomes `(u cos r + v sin r, v cos r - u sin r)`.
    pub rotation: f32,
    /// Applied first, per axis.
    pub scale: Vec2,
}

impl UvTransform {
    /// No transform: offset 0, rotation 0, scale 1.
    pub const IDENTITY: Self = Self {
        offset: Vec2::ZERO,
        rotation: 0.0,
        scale: Vec2::ONE,
    };

    /// The 3×3 matrix that maps `(u, v, 1)`: translation × rotation × scale, as the extension
    /// specifies. The rotation is the one the extension's prose, its JSON examples and the
    /// Khronos `TextureTransformTest` model agree on; the GLSL listing in its README has the
    /// transposed rotation (KhronosGroup/glTF issue 1563), which turns the other way.
    pub fn matrix(&self) -> Mat3 {
        let (s, c) = self.rotation.sin_cos();
        let translation = Mat3::from_cols(glam::Vec3::X, glam::Vec3::Y, self.offset.extend(1.0));
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

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn apply(t: &UvTransform, uv: Vec2) -> Vec2 {
        (t.matrix() * uv.extend(1.0)).truncate()
    }

    fn assert_near(got: Vec2, want: Vec2) {
        assert!(got.abs_diff_eq(want, 1e-4), "got {got}, want {want}");
    }

    /// The extension's first JSON example ("only the lower left quadrant of the source image,
    /// rotated clockwise 90°"): the unit square's corners land on that quadrant's corners,
    /// computed by hand from `offset [0, 1]`, `rotation π/2`, `scale [0.5, 0.5]`.
    #[test]
    fn spec_example_maps_the_square_onto_the_lower_left_quadrant() {
        let t = UvTransform {
            offset: Vec2::new(0.0, 1.0),
            rotation: std::f32::consts::FRAC_PI_2,
            scale: Vec2::splat(0.5),
        };
        assert_near(apply(&t, Vec2::new(0.0, 0.0)), Vec2::new(0.0, 1.0));
        assert_near(apply(&t, Vec2::new(1.0, 0.0)), Vec2::new(0.0, 0.5));
        assert_near(apply(&t, Vec2::new(0.0, 1.0)), Vec2::new(0.5, 1.0));
        assert_near(apply(&t, Vec2::new(1.0, 1.0)), Vec2::new(0.5, 0.5));
    }

    /// `TextureTransformTest`'s rotation quad (UV = (x + 0.5, 0.5 − y) over its 1×1 quad):
    /// with rotation 22.5° the arrow that points at the "not supported" marker's UV
    /// (0.7778, 0.7778) must be drawn at the "correct" marker, node translation
    /// (−0.0790, −0.5163), i.e. UV (0.4210, 1.0163).
    #[test]
    fn rotation_matches_the_sample_models_correct_marker() {
        let t = UvTransform {
            rotation: std::f32::consts::FRAC_PI_8,
            ..UvTransform::IDENTITY
        };
        assert_near(
            apply(&t, Vec2::new(0.5 - 0.079_048_22, 0.5 + 0.516_267_5)),
            Vec2::new(0.5 + 0.277_817_46, 0.5 + 0.277_817_46),
        );
    }

    /// Scale first, then rotate, then offset: (1, 0) scaled by (2, 3) is (2, 0), turned by
    /// a quarter is (0, −2), offset by (0.25, 0.5) is (0.25, −1.5).
    #[test]
    fn order_is_translation_rotation_scale() {
        let t = UvTransform {
            offset: Vec2::new(0.25, 0.5),
            rotation: std::f32::consts::FRAC_PI_2,
            scale: Vec2::new(2.0, 3.0),
        };
        assert_near(apply(&t, Vec2::X), Vec2::new(0.25, -1.5));
        assert_near(apply(&t, Vec2::Y), Vec2::new(3.25, 0.5));
        assert_eq!(UvTransform::IDENTITY.matrix(), Mat3::IDENTITY);
        assert_eq!(t.matrix().row(2), Vec3::Z);
    }
}
