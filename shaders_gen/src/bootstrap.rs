//! Hand-written bootstrap shaders, used until the shader DSL generates them.
//!
//! They prove the GPU context end to end: a compute kernel whose result is checked number by
//! number, and a full-screen test pattern whose pixels a CPU can recompute exactly. They use
//! integer arithmetic wherever a CPU reference must match bit for bit.

/// Host mirror of `PatternParams` in [`TEST_PATTERN_WGSL`] (uniform address space).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PatternParams {
    /// Target size in pixels.
    pub size: [u32; 2],
    /// Checker cell size in pixels.
    pub cell: u32,
    /// Padding before the 8-aligned `ring_radii_sq` (WGSL inserts it implicitly).
    pub _pad: u32,
    /// Squared inner and outer ring radii, in pixels².
    pub ring_radii_sq: [u32; 2],
}

/// Full-screen triangle and a test pattern: red = x/width, green = y/height, blue = a checker
/// board, and a white ring around the centre.
pub const TEST_PATTERN_WGSL: &str = r"
struct PatternParams {
    size: vec2<u32>,
    cell: u32,
    _pad: u32,
    ring_radii_sq: vec2<u32>,
}

@group(0) @binding(0) var<uniform> params: PatternParams;

@vertex
fn vs_fullscreen(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((index << 1u) & 2u), f32(index & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs_pattern(@builtin(position) position: vec4<f32>) -> @location(0) vec4<f32> {
    let pixel = vec2<u32>(position.xy);
    let uv = position.xy / vec2<f32>(params.size);
    let cell = pixel / params.cell;
    let checker = f32((cell.x + cell.y) & 1u);
    let centre = vec2<i32>(params.size / 2u);
    let offset = vec2<i32>(pixel) - centre;
    let dist_sq = u32(offset.x * offset.x + offset.y * offset.y);
    if dist_sq >= params.ring_radii_sq.x && dist_sq < params.ring_radii_sq.y {
        return vec4<f32>(1.0, 1.0, 1.0, 1.0);
    }
    // uv.y counts from the top of the image, as pixel rows do.
    return vec4<f32>(uv.x, uv.y, 0.25 + 0.5 * checker, 1.0);
}
";

/// `output[i] = input[i] * input[i] + i`, 64 invocations per workgroup.
pub const SQUARE_PLUS_INDEX_WGSL: &str = r"
@group(0) @binding(0) var<storage, read> input: array<u32>;
@group(0) @binding(1) var<storage, read_write> output: array<u32>;

@compute @workgroup_size(64)
fn square_plus_index(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if i < arrayLength(&output) {
        output[i] = input[i] * input[i] + i;
    }
}
";

/// Workgroup size of [`SQUARE_PLUS_INDEX_WGSL`].
pub const SQUARE_PLUS_INDEX_WORKGROUP: u32 = 64;
