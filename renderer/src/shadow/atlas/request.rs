//! What a light asks of the shadow atlas for one frame, and what it gets: requests, regions,
//! grants and the frame's plan, and a request as the atlas uses it after clean-up.

/// Which light and what it needs, for one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowRequest {
    /// Stable id of the light (the same light keeps its id from frame to frame).
    pub light: u32,
    /// Number of square regions: 1 (spot), 6 (point, cube faces) or 4 (directional cascades).
    /// Zero is treated as one.
    pub faces: u32,
    /// Desired power-of-two side of each region, in texels (after hysteresis). Sides below the
    /// atlas' minimum side are raised to it.
    pub side: u32,
    /// Larger is more important; the directional light uses `f32::INFINITY`. NaN counts as
    /// `f32::NEG_INFINITY` (least important).
    pub importance: f32,
}

/// A square region of the atlas, in atlas texels (`x`, `y`: top-left corner).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AtlasRect {
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Side in texels.
    pub side: u32,
}

/// What a light got this frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ShadowGrant {
    /// Stable id of the light.
    pub light: u32,
    /// Side of each region (may be smaller than asked, see [`AtlasPlan::degraded`]).
    pub side: u32,
    /// One region per face, in face order.
    pub rects: Vec<AtlasRect>,
    /// The rects or side differ from last frame's grant, or the light had none: its cached
    /// depth is invalid and must be redrawn.
    pub moved: bool,
}

/// The outcome of [`ShadowAtlas::plan`](super::ShadowAtlas::plan) for one frame.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct AtlasPlan {
    /// Lights that got a shadow, in request order.
    pub grants: Vec<ShadowGrant>,
    /// `(light, asked side, granted side)` of lights that got a smaller side than they asked.
    pub degraded: Vec<(u32, u32, u32)>,
    /// Lights that asked and got no shadow, in request order.
    pub evicted: Vec<u32>,
    /// The atlas was packed afresh this frame (every grant is then `moved`).
    pub repacked: bool,
}

/// A request after clean-up: faces and side as used for allocation, plus the raw request.
#[derive(Debug, Clone, Copy)]
pub(super) struct Wanted {
    pub(super) request: ShadowRequest,
    pub(super) faces: u32,
    pub(super) side: u32,
    pub(super) importance: f32,
}

impl Wanted {
    /// Texels of all faces at `side` (u128: `faces × side²` of any `u32` inputs fits, and so
    /// does any sum of them).
    pub(super) fn area(&self, side: u32) -> u128 {
        u128::from(self.faces) * u128::from(side) * u128::from(side)
    }
}
