//! How a sample of the 64-bit visibility buffer reads, for every shader that reads one.

/// A sample of `VIS64` read as its two 32-bit words, `(low, high)`: the compute rasteriser and
/// the masked draws merge `(!depth_bits << 32) | !id` into it with `fetch_max`, so the nearest
/// depth wins, and a sample no triangle covered keeps the cleared 0 (no written value is 0:
/// the complements of a depth in `[0, 1)` and of a 32-bit ID are never both 0). The readers
/// bind the buffer as `[UVec2]`, so no 64-bit type reaches their modules; the writers pack it
/// themselves.
#[shader_dsl::library]
pub mod vis64_sample {
    /// Whether a triangle covered the sample.
    pub fn vis64_covered(sample: UVec2) -> bool {
        sample.y != 0u32
    }

    /// The sample's depth: the far plane, 1.0, where no triangle covered it.
    pub fn vis64_depth(sample: UVec2) -> f32 {
        let mut depth = 1.0f32;
        if vis64_covered(sample) {
            depth = f32::from_bits(!sample.y);
        }
        depth
    }

    /// The ID of the triangle nearest at the sample; 0 where none covered it.
    pub fn vis64_id(sample: UVec2) -> u32 {
        select(vis64_covered(sample), !sample.x, 0u32)
    }
}
