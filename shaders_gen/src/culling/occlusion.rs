//! Occlusion culling of the scene's draws against a depth pyramid, the second phase of
//! two-phase culling (Haar and Aaltonen 2015).
//!
//! Each frame, the first phase (`instance_cull::cull_frustum` with history) draws the slots
//! that were visible last frame into the pre-Z depth. `depth_pyramid_seed` and
//! `depth_pyramid_reduce` then build a pyramid of that depth: level 0 is half the frame on
//! each axis rounded up to a power of two, each texel the farthest depth (the largest value:
//! wgpu depth, 1.0 = far) over its 2×2 pixels (clamped to the frame) and every MSAA sample;
//! each level above halves it, down to 1×1.
//! `cull_occlusion` tests every slot in the frustum against it: a box whose nearest depth lies
//! beyond the farthest depth the pyramid holds over the box's screen rectangle is hidden. The
//! slots found visible that did not draw in the first phase draw in the second (`LATE_ARGS`);
//! every slot that drew in either is drawn by the passes after pre-Z (`FINAL_ARGS`); and the
//! test's verdict is the next frame's history.
//!
//! Nothing visible is ever left out: what the first phase drew is in the depth, so the pyramid
//! is never nearer than this frame's true depth, and what it left out is tested against it. A
//! box that reaches behind the eye or across the near plane is never hidden.

/// The first texel of each depth-pyramid level from the depth buffer, or with `vis64` from
/// the compute rasteriser's samples (the visibility path under
/// `VisibilityRaster::Compute`, whose frame may have no depth buffer).
#[shader_dsl::shader(
    axes(
        msaa: u32 = [1, 2, 4, 8] => "msaa",
        vis64: bool = [false, true] => "vis64",
    ),
    uses(crate::visibility::samples64::vis64_sample),
)]
pub mod depth_pyramid_seed {
    /// The frame's size (`vis64`: the samples are `(y × width + x) × msaa + s`).
    pub struct SeedFrame {
        pub size: UVec2,
        pub pad: UVec2,
    }

    #[texture(group = 0, binding = 0)]
    #[when(msaa == 1 && !vis64)]
    static DEPTH: TextureDepth2d;
    #[texture(group = 0, binding = 0)]
    #[when(msaa > 1 && !vis64)]
    static DEPTH_MS: TextureDepthMultisampled2d;
    /// The compute rasteriser's samples as `(low, high)` word pairs: the depth is
    /// `bitcast(!high)`, the far plane where both words are 0.
    #[storage(group = 0, binding = 0)]
    #[when(vis64)]
    static VIS64: [UVec2];
    #[uniform(group = 0, binding = 2)]
    #[when(vis64)]
    static FRAME: SeedFrame;
    #[texture(group = 0, binding = 1)]
    static LEVEL: StorageTexture2d<R32Float, Write>;

    /// Depth-buffer value of sample `s` of pixel `p`.
    fn sample_depth(p: UVec2, s: u32) -> f32 {
        let mut d = 1.0;
        if vis64 {
            d = vis64_depth(VIS64[(p.y * FRAME.size.x + p.x) * msaa + s]);
        } else if msaa == 1 {
            d = DEPTH.load(p, 0u32);
        } else {
            d = DEPTH_MS.load(p, s);
        }
        d
    }

    /// One texel of level 0: the farthest sample of its 2×2 pixels (clamped to the frame).
    #[compute(workgroup_size(8, 8, 1))]
    pub fn seed(#[builtin(global_invocation_id)] gid: UVec3) {
        let texel = gid.xy();
        let size = LEVEL.dimensions();
        if texel.x < size.x && texel.y < size.y {
            let mut pixels = UVec2::new(1u32, 1u32);
            if vis64 {
                pixels = FRAME.size;
            } else if msaa == 1 {
                pixels = DEPTH.dimensions();
            } else {
                pixels = DEPTH_MS.dimensions();
            }
            let last = pixels - UVec2::new(1u32, 1u32);
            let mut farthest = 0.0;
            for k in 0u32..4u32 {
                let p = (texel * 2u32 + UVec2::new(k & 1u32, k >> 1u32)).min(last);
                for s in 0u32..msaa {
                    farthest = farthest.max(sample_depth(p, s));
                }
            }
            LEVEL.store(texel, Vec4::new(farthest, 0.0, 0.0, 0.0));
        }
    }
}

/// One level of the depth pyramid from the level below.
#[shader_dsl::shader()]
pub mod depth_pyramid_reduce {
    #[texture(group = 0, binding = 0, unfilterable)]
    static BELOW: Texture2d<f32>;
    #[texture(group = 0, binding = 1)]
    static LEVEL: StorageTexture2d<R32Float, Write>;

    /// One texel: the farthest of its 2×2 texels below (clamped to the level below).
    #[compute(workgroup_size(8, 8, 1))]
    pub fn reduce(#[builtin(global_invocation_id)] gid: UVec3) {
        let texel = gid.xy();
        let size = LEVEL.dimensions();
        if texel.x < size.x && texel.y < size.y {
            let last = BELOW.dimensions() - UVec2::new(1u32, 1u32);
            let mut farthest = 0.0;
            for k in 0u32..4u32 {
                let t = (texel * 2u32 + UVec2::new(k & 1u32, k >> 1u32)).min(last);
                farthest = farthest.max(BELOW.load(t, 0u32).x);
            }
            LEVEL.store(texel, Vec4::new(farthest, 0.0, 0.0, 0.0));
        }
    }
}

/// The second phase: every slot in the frustum against the depth pyramid.
#[shader_dsl::shader(uses(crate::shared::box_frustum))]
pub mod occlusion_cull {
    pub const WORKGROUP: u32 = 64;
    /// A slot without a draw (as `instance_cull::NO_DRAW`).
    pub const NO_DRAW: u32 = 0xFFFF_FFFF;

    /// The view, the frame and the pyramid.
    pub struct OcclusionParams {
        pub clip_from_world: Mat4,
        pub frustum: Frustum,
        /// The frame in pixels.
        pub screen: UVec2,
        /// Levels of the pyramid (level 0 is half the frame).
        pub levels: u32,
        /// Slots to cull.
        pub slot_count: u32,
        /// How far outside a plane a box may reach and still be kept, in world units.
        pub slack: f32,
        pub pad0: u32,
        pub pad1: u32,
        pub pad2: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: OcclusionParams;
    #[storage(group = 0, binding = 1)]
    static BOXES: [DrawBox];
    #[storage(group = 0, binding = 2)]
    static SLOT_DRAWS: [u32];
    #[storage(group = 0, binding = 3)]
    static EARLY_ARGS: [u32];
    #[storage(group = 0, binding = 4, read_write)]
    static LATE_ARGS: [u32];
    #[storage(group = 0, binding = 5, read_write)]
    static FINAL_ARGS: [u32];
    #[storage(group = 0, binding = 6, read_write)]
    static HISTORY: [u32];
    /// Two counters: the first phase's draws (`instance_cull`), then the slots drawn in either
    /// phase (here).
    #[storage(group = 0, binding = 7, read_write)]
    static VISIBLE: [Atomic<u32>];
    #[texture(group = 0, binding = 8, unfilterable)]
    static PYRAMID: Texture2d<f32>;

    /// The farthest depth of the pyramid over pixels `lo..=hi`: at the lowest level where the
    /// rectangle spans at most 2×2 texels, the largest of those texels. Level `l` texel `t`
    /// covers pixels `t·2^(l+1)` to `(t+1)·2^(l+1) − 1`, and a pixel of the frame always has a
    /// texel at every level (level 0's sides are powers of two at least half the frame's).
    fn farthest_over(lo: UVec2, hi: UVec2) -> f32 {
        let mut level = 0u32;
        let mut a = lo >> UVec2::new(1u32, 1u32);
        let mut b = hi >> UVec2::new(1u32, 1u32);
        while level + 1u32 < PARAMS.levels && (b.x - a.x > 1u32 || b.y - a.y > 1u32) {
            level = level + 1u32;
            a = a >> UVec2::new(1u32, 1u32);
            b = b >> UVec2::new(1u32, 1u32);
        }
        let mut farthest = 0.0;
        for k in 0u32..4u32 {
            let t = UVec2::new(
                select((k & 1u32) != 0u32, b.x, a.x),
                select(k >= 2u32, b.y, a.y),
            );
            farthest = farthest.max(PYRAMID.load(t, level).x);
        }
        farthest
    }

    /// Whether `b` lies wholly behind what the pyramid holds over its screen rectangle.
    fn occluded(b: DrawBox) -> bool {
        if b.min.x > b.max.x {
            return false;
        }
        let mut lo = Vec2::new(1.0e30, 1.0e30);
        let mut hi = Vec2::new(-1.0e30, -1.0e30);
        let mut nearest = 1.0;
        let mut crosses_eye = false;
        for k in 0u32..8u32 {
            let corner = Vec3::new(
                select((k & 1u32) != 0u32, b.max.x, b.min.x),
                select((k & 2u32) != 0u32, b.max.y, b.min.y),
                select((k & 4u32) != 0u32, b.max.z, b.min.z),
            );
            let clip = PARAMS.clip_from_world * corner.extend(1.0);
            if clip.w <= 1.0e-6 {
                crosses_eye = true;
            } else {
                let ndc = clip.xyz() / clip.w;
                lo = lo.min(ndc.xy());
                hi = hi.max(ndc.xy());
                nearest = nearest.min(ndc.z);
            }
        }
        if crosses_eye || nearest <= 0.0 {
            return false;
        }
        let screen = Vec2::new(PARAMS.screen.x as f32, PARAMS.screen.y as f32);
        // NDC y points up; pixel rows go down.
        let top_left = Vec2::new(lo.x * 0.5 + 0.5, 0.5 - hi.y * 0.5) * screen;
        let bottom_right = Vec2::new(hi.x * 0.5 + 0.5, 0.5 - lo.y * 0.5) * screen;
        let last = screen - Vec2::new(1.0, 1.0);
        let p0 = top_left.floor().clamp(Vec2::new(0.0, 0.0), last);
        let p1 = bottom_right.floor().clamp(Vec2::new(0.0, 0.0), last);
        let farthest = farthest_over(
            UVec2::new(p0.x as u32, p0.y as u32),
            UVec2::new(p1.x as u32, p1.y as u32),
        );
        nearest > farthest
    }

    /// One slot: visible (in the frustum and not hidden) or not; drawn late when visible and
    /// not drawn early; drawn after pre-Z when drawn in either phase.
    #[compute(workgroup_size(64, 1, 1))]
    pub fn cull_occlusion(#[builtin(global_invocation_id)] gid: UVec3) {
        let slot = gid.x;
        if slot < PARAMS.slot_count {
            let draw = SLOT_DRAWS[slot];
            let mut visible = false;
            if draw != NO_DRAW {
                let b = BOXES[draw];
                visible = draw_in_frustum(PARAMS.frustum, b, PARAMS.slack) && !occluded(b);
            }
            let early = EARLY_ARGS[slot * 5u32 + 1u32] != 0u32;
            LATE_ARGS[slot * 5u32 + 1u32] = select(visible && !early, 1u32, 0u32);
            FINAL_ARGS[slot * 5u32 + 1u32] = select(visible || early, 1u32, 0u32);
            HISTORY[slot] = select(visible, 1u32, 0u32);
            if visible || early {
                VISIBLE[1].fetch_add(1);
            }
        }
    }
}
