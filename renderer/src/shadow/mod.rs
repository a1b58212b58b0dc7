//! Shadow planning on the CPU, below the passes and free of GPU objects: which lights cast a
//! shadow this frame and at what resolution (`resolution`), where their regions sit in the
//! one depth atlas (`atlas`, regions from `etagere`), the light-space projections of spot
//! lights, cube faces and directional cascades with the frusta casters are culled against
//! (`views`), and which regions a frame must redraw, recompose or leave alone (`cache`).
//!
//! Depth convention of every shadow view: reversed Z (the near plane maps to 1, the far plane
//! to 0), cleared to 0, compared with `GreaterEqual`.

pub mod atlas;
pub mod cache;
pub mod frame;
pub mod region_test;
pub mod resolution;
pub mod views;

/// Shadow settings of a renderer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowConfig {
    /// Draw shadows at all (lights marked `casts_shadow` are then unshadowed).
    pub enabled: bool,
    /// Side of the square depth atlas, in texels.
    pub atlas_size: u32,
    /// Smallest region side a shadowed light gets before it loses its shadow.
    pub min_resolution: u32,
    /// Largest region side of a spot light or cube face.
    pub max_resolution: u32,
    /// Side of each of the directional light's four cascades.
    pub cascade_resolution: u32,
    /// Keep static casters' depth in a cache atlas and redraw a region only when its light or
    /// its casters change; off, every region is redrawn every frame (for comparison).
    pub cache: bool,
    /// View depth the directional cascades cover (world units).
    pub directional_distance: f32,
}

impl Default for ShadowConfig {
    fn default() -> Self {
        Self {
            enabled: true,
            atlas_size: 8192,
            min_resolution: 64,
            max_resolution: 2048,
            cascade_resolution: 2048,
            cache: true,
            directional_distance: 60.0,
        }
    }
}

/// What the shadow pass decided and drew in one frame.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ShadowReport {
    /// Lights that asked for a shadow.
    pub requested: u32,
    /// Lights that got one.
    pub shadowed: u32,
    /// `(side, regions)`: how many regions (spot lights, cube faces, cascades) have each side,
    /// smallest side first.
    pub resolution_histogram: Vec<(u32, u32)>,
    /// `(light, asked side, granted side)` of lights the full atlas degraded this frame.
    pub degraded: Vec<(u32, u32, u32)>,
    /// Lights that asked for a shadow and got none (the atlas was full even at the smallest
    /// side).
    pub evicted: Vec<u32>,
    /// Whether the atlas was packed afresh this frame (every region then moves and redraws).
    pub repacked: bool,
    /// Region work and caster draws.
    pub cache: cache::CacheCounts,
    /// Every region of the frame: its light, its face and where it is.
    pub regions: Vec<(cache::RegionKey, atlas::AtlasRect)>,
    /// CPU time of the frame's shadow planning and uploads (requests, allocation, views,
    /// caster culling, cache decisions, view records), in milliseconds.
    pub cpu_plan_ms: f64,
}
