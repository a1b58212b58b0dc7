//! What a frame reports back to the engine. The orchestrator fills the timings and CPU times;
//! each pass adds its own section (light culling its counters).

use crate::culling::lists::CullCounters;
use crate::graph::PassTiming;

/// What a frame reports back.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FrameReport {
    /// Per-pass GPU times of the newest frame whose timestamps have arrived.
    pub timings: Option<Vec<PassTiming>>,
    /// CPU time to build, compile and encode the frame graph, in milliseconds.
    pub cpu_graph_ms: f64,
    /// CPU time of the passes' per-frame preparation before that (uniforms, culling items;
    /// grows with the light count), in milliseconds.
    pub cpu_upload_ms: f64,
    /// CPU time to finish the command buffer and submit it, in milliseconds. The three CPU
    /// fields together are the renderer's CPU cost of a frame.
    pub cpu_submit_ms: f64,
    /// Whether this frame compiled its graph; false when the graph had the last compiled
    /// one's shape and reused its plan (`graph::GraphCache`). The graph's DOT is drawn on
    /// request: `Renderer::graph_dot`.
    pub graph_compiled: bool,
    /// Culling counters of the newest frame whose copy has arrived (read asynchronously).
    /// `dropped > 0` means lights were left out of some lists that frame; the renderer logs a
    /// warning and grows the index list for the next frame where the device allows.
    pub culling: Option<CullCounters>,
    /// What the shadow pass decided and drew this frame (absent without one).
    pub shadows: Option<crate::shadow::ShadowReport>,
    /// The particles of the newest frame whose counters have arrived (read asynchronously;
    /// absent without particles).
    pub particles: Option<ParticleReport>,
    /// The scene's draws for the main view and how many the GPU culling kept (read
    /// asynchronously, like the culling counters).
    pub scene_draws: Option<SceneDrawReport>,
    /// What the frame graph's transient pool reused, created and held this frame: `held` stays
    /// flat across frames of one configuration.
    pub pool: crate::graph::PoolStats,
    /// The further views' reports (`Renderer::render_views`), in the order they were drawn;
    /// empty for a frame of the main view alone.
    pub views: Vec<FrameReport>,
}

/// The scene's opaque and masked draws in the main view's batches, and what culling kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SceneDrawReport {
    /// Opaque and masked draws, each in a slot of the batches.
    pub draws: u32,
    /// Slots in the batches: the draws and the spare slots kept for instances an engine adds
    /// (they draw nothing).
    pub slots: u32,
    /// Batches, one multi-draw each in every geometry pass.
    pub batches: u32,
    /// Blended draws (sorted and drawn apart).
    pub blended: u32,
    /// Slots the newest culled frame whose count has arrived drew (absent while culling is
    /// off or no count has arrived yet); with occlusion culling, in either phase.
    pub visible: Option<u32>,
    /// Whether the scene's draws are occlusion-culled too.
    pub occlusion: bool,
    /// Whether the culled slots are packed on the GPU before they are drawn, so each batch draws
    /// only its drawn slots, as many as a GPU-written count says (culling on, on a device with
    /// `MULTI_DRAW_INDIRECT_COUNT`); otherwise every slot is drawn, the culled ones empty.
    pub packed: bool,
}

/// What the particle passes counted in one frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ParticleReport {
    /// Live particles.
    pub alive: u32,
    /// Births refused since the start because every slot was taken (raise the capacity).
    pub starved: u32,
    /// Particles in front of the camera, drawn and lit.
    pub visible: u32,
    /// Classes every atlas region was shrunk by this frame so that all fit (0: none); the
    /// renderer logs a warning when it is not 0.
    pub atlas_shrink: u32,
    /// Frames so far whose atlas had to shrink.
    pub shrunk_frames: u32,
    /// 2×2-texel atlas cells lit this frame.
    pub atlas_cells: u32,
}
