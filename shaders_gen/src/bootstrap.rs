//! The smallest real shaders: a full-screen test pattern and a compute kernel. They prove the
//! GPU context end to end (`cargo xtask demo`, the GPU harness tests), using integer arithmetic
//! wherever a CPU reference must match bit for bit.

/// Full-screen triangle and a test pattern: red = x / width, green = y / height, blue = a
/// checker board, and a white ring around the centre.
#[shader_dsl::shader]
pub mod test_pattern {
    pub struct PatternParams {
        /// Target size in pixels.
        pub size: UVec2,
        /// Checker cell size in pixels.
        pub cell: u32,
        /// Squared inner and outer ring radii, in pixels².
        pub ring_radii_sq: UVec2,
    }

    pub struct VsOut {
        #[builtin(position)]
        pub position: Vec4,
    }

    pub struct FsOut {
        #[location(0)]
        pub color: Vec4,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: PatternParams;

    #[vertex]
    pub fn vs_fullscreen(#[builtin(vertex_index)] index: u32) -> VsOut {
        let uv = Vec2::new(((index << 1u32) & 2u32) as f32, (index & 2u32) as f32);
        VsOut {
            position: Vec4::new(uv.x * 2.0 - 1.0, uv.y * 2.0 - 1.0, 0.0, 1.0),
        }
    }

    #[fragment]
    pub fn fs_pattern(#[builtin(position)] position: Vec4) -> FsOut {
        let x = position.x as u32;
        let y = position.y as u32;
        let size = PARAMS.size;
        let checker = ((x / PARAMS.cell + y / PARAMS.cell) & 1u32) as f32;
        let dx = x as i32 - (size.x / 2u32) as i32;
        let dy = y as i32 - (size.y / 2u32) as i32;
        let dist_sq = (dx * dx + dy * dy) as u32;
        if dist_sq >= PARAMS.ring_radii_sq.x && dist_sq < PARAMS.ring_radii_sq.y {
            return FsOut {
                color: Vec4::new(1.0, 1.0, 1.0, 1.0),
            };
        }
        // Pixel rows count from the top, so green grows downwards.
        FsOut {
            color: Vec4::new(
                position.x / size.x as f32,
                position.y / size.y as f32,
                0.25 + 0.5 * checker,
                1.0,
            ),
        }
    }
}

/// `OUTPUT[i] = INPUT[i] * INPUT[i] + i`, 64 invocations per workgroup.
#[shader_dsl::shader]
pub mod square_plus_index {
    pub const WORKGROUP: u32 = 64;

    #[storage(group = 0, binding = 0)]
    static INPUT: [u32];
    #[storage(group = 0, binding = 1, read_write)]
    static OUTPUT: [u32];

    #[compute(workgroup_size(64, 1, 1))]
    pub fn square_plus_index(#[builtin(global_invocation_id)] id: UVec3) {
        let i = id.x;
        if i < OUTPUT.len() {
            OUTPUT[i] = INPUT[i] * INPUT[i] + i;
        }
    }
}
