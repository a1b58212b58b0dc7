//! Where a pixel's samples lie: the standard MSAA sample positions of Vulkan and D3D, which
//! the hardware rasteriser uses and the code that finds a sample's point again (the deferred
//! G-buffer reads, the compute rasteriser) must agree with.

/// `sample_offset(s)`: sample `s` of a pixel at the variant's `msaa` (1: the centre; 0, a
/// module's variants that have no sample count, the centre too).
#[shader_dsl::library(axes(msaa: u32 = [0, 1, 2, 4, 8]))]
pub mod sample_pattern {
    /// Where sample `s` of a pixel lies in it, in pixels from its top-left corner.
    pub fn sample_offset(s: u32) -> Vec2 {
        let mut o = Vec2::splat(0.5);
        if msaa == 2 {
            o = select(s == 0u32, Vec2::splat(0.75), Vec2::splat(0.25));
        } else if msaa == 4 {
            if s == 0u32 {
                o = Vec2::new(0.375, 0.125);
            } else if s == 1u32 {
                o = Vec2::new(0.875, 0.375);
            } else if s == 2u32 {
                o = Vec2::new(0.125, 0.625);
            } else {
                o = Vec2::new(0.625, 0.875);
            }
        } else if msaa == 8 {
            if s == 0u32 {
                o = Vec2::new(0.5625, 0.3125);
            } else if s == 1u32 {
                o = Vec2::new(0.4375, 0.6875);
            } else if s == 2u32 {
                o = Vec2::new(0.8125, 0.5625);
            } else if s == 3u32 {
                o = Vec2::new(0.3125, 0.1875);
            } else if s == 4u32 {
                o = Vec2::new(0.1875, 0.8125);
            } else if s == 5u32 {
                o = Vec2::new(0.0625, 0.4375);
            } else if s == 6u32 {
                o = Vec2::new(0.6875, 0.9375);
            } else {
                o = Vec2::new(0.9375, 0.0625);
            }
        }
        o
    }
}
