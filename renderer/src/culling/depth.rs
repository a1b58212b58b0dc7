//! A CPU copy of a (possibly multisampled) depth buffer, the standard sample positions of each
//! count, and the cull efficiency measured over such a buffer: what a frame capture reads back
//! and what the CPU reference (`reference`, tests and tools only) checks against.

/// Depth samples, row by row, `samples` per pixel.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthBuffer {
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    /// `depth[((y * width) + x) * samples + s]`, wgpu convention (1.0 = far, sky).
    pub depth: Vec<f32>,
}

impl DepthBuffer {
    #[cfg(any(test, feature = "internals"))]
    pub fn get(&self, x: u32, y: u32, s: u32) -> f32 {
        self.depth[((y * self.width + x) * self.samples + s) as usize]
    }

    /// Whether the sample holds a surface (anything nearer than the far plane).
    pub fn is_surface(depth: f32) -> bool {
        depth < 1.0
    }

    /// Sub-pixel position of sample `s` (Vulkan/D3D standard sample locations).
    #[cfg(any(test, feature = "internals"))]
    pub fn sample_offset(&self, s: u32) -> (f32, f32) {
        standard_sample_offset(self.samples, s)
    }
}

/// Sub-pixel position of sample `s` of `samples` (Vulkan/D3D standard sample locations; the
/// pixel centre without multisampling).
pub fn standard_sample_offset(samples: u32, s: u32) -> (f32, f32) {
    const X2: [(f32, f32); 2] = [(0.75, 0.75), (0.25, 0.25)];
    const X4: [(f32, f32); 4] = [
        (0.375, 0.125),
        (0.875, 0.375),
        (0.125, 0.625),
        (0.625, 0.875),
    ];
    const X8: [(f32, f32); 8] = [
        (0.5625, 0.3125),
        (0.4375, 0.6875),
        (0.8125, 0.5625),
        (0.3125, 0.1875),
        (0.1875, 0.8125),
        (0.0625, 0.4375),
        (0.6875, 0.9375),
        (0.9375, 0.0625),
    ];
    match samples {
        2 => X2[s as usize],
        4 => X4[s as usize],
        8 => X8[s as usize],
        _ => (0.5, 0.5),
    }
}

/// Cull efficiency of a method: entries listed for the samples over lights that reach them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Efficiency {
    /// Σ over surface samples of the number of lights in the sample's cell list.
    pub listed: u64,
    /// Σ over surface samples of the number of lights whose sphere contains the sample.
    pub reaching: u64,
}

impl Efficiency {
    /// `listed / reaching`: 1 is perfect, larger means more wasted light evaluations.
    pub fn ratio(&self) -> f64 {
        self.listed as f64 / self.reaching.max(1) as f64
    }
}
