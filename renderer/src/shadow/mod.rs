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
    /// Trim the sizes above to the output ([`ShadowConfig::fitted`]): on, a small output does
    /// not pay for an atlas sized for 1080p (the default 8192² atlas and its static cache are
    /// 512 MiB). Sizes are only ever lowered, never raised.
    pub fit_to_output: bool,
}

/// The smallest atlas side [`ShadowConfig::fitted`] trims to: room for 1,024 regions of the
/// default smallest side.
pub const FITTED_ATLAS_FLOOR: u32 = 2048;

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
            fit_to_output: true,
        }
    }
}

impl ShadowConfig {
    /// The settings a `width`×`height` output uses. With `fit_to_output` on, a region needs no
    /// more texels across than the output has pixels, so the largest region side and the
    /// cascade side are capped at the smallest power of two at least the output's larger side,
    /// and the atlas at four times that (four cascades of it) but not below
    /// [`FITTED_ATLAS_FLOOR`]. At 1920×1080 that is 2048 and 8192, the defaults themselves;
    /// at 256×256, 256 and 2048. Off, the settings are returned unchanged.
    pub fn fitted(self, width: u32, height: u32) -> Self {
        if !self.fit_to_output {
            return self;
        }
        let side = width
            .max(height)
            .max(self.min_resolution)
            .checked_next_power_of_two()
            .unwrap_or(u32::MAX);
        Self {
            atlas_size: self
                .atlas_size
                .min(side.saturating_mul(4).max(FITTED_ATLAS_FLOOR)),
            max_resolution: self.max_resolution.min(side),
            cascade_resolution: self.cascade_resolution.min(side),
            ..self
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

#[cfg(test)]
mod fitted_tests {
    use super::{FITTED_ATLAS_FLOOR, ShadowConfig};

    #[test]
    fn fitting_keeps_the_defaults_at_1080p_and_trims_small_outputs() {
        let defaults = ShadowConfig::default();
        assert_eq!(defaults.fitted(1920, 1080), defaults);
        assert_eq!(defaults.fitted(2048, 2048), defaults);
        let small = defaults.fitted(96, 64);
        assert_eq!(
            (
                small.atlas_size,
                small.max_resolution,
                small.cascade_resolution
            ),
            (FITTED_ATLAS_FLOOR, 128, 128)
        );
        let mid = defaults.fitted(640, 480);
        assert_eq!(
            (mid.atlas_size, mid.max_resolution, mid.cascade_resolution),
            (4096, 1024, 1024)
        );
        // Never raised, and off means unchanged.
        let chosen = ShadowConfig {
            atlas_size: 1024,
            max_resolution: 256,
            cascade_resolution: 64,
            ..defaults
        };
        assert_eq!(chosen.fitted(4096, 4096), chosen);
        let off = ShadowConfig {
            fit_to_output: false,
            ..defaults
        };
        assert_eq!(off.fitted(96, 64), off);
    }
}
