//! The read-only inputs of one frame, as every pass sees them while it prepares and adds itself
//! to the graph.

use std::sync::Arc;

use super::{
    CameraUniform, FrameCamera, GpuDecals, InstanceTable, LightSet, PreparedScene, RendererConfig,
};
use crate::GpuContext;

/// The particle systems a renderer was given ([`crate::frame::Renderer::set_particles`]).
#[derive(Debug, Clone)]
pub struct ParticleInput {
    pub system: Arc<crate::particles::ParticleSystem>,
    /// Fixed steps simulated before the first frame that shows them.
    pub warmup_steps: u32,
    /// Changes whenever the systems are replaced (the particle passes rebuild then).
    pub generation: u64,
}

/// One frame's inputs.
#[derive(Debug, Clone)]
pub struct FrameInputs {
    /// The renderer's device.
    pub gpu: GpuContext,
    /// The configuration of the view being drawn.
    pub config: RendererConfig,
    /// The camera of the view being drawn.
    pub camera: FrameCamera,
    /// The scene as uploaded: geometry, draws and materials.
    pub scene: Arc<PreparedScene>,
    /// The scene's instances and their draws this frame. Passes keep what they derive from
    /// it by its revision, never the table itself (the renderer edits it in place between
    /// frames).
    pub instances: Arc<InstanceTable>,
    /// The lights, uploaded, with their effective ranges.
    pub lights: Arc<LightSet>,
    /// Decals in layer order, with their atlas.
    pub decals: Arc<GpuDecals>,
    /// The particle systems, when the renderer has any.
    pub particles: Option<ParticleInput>,
    /// The camera uniform, already written for this frame.
    pub camera_uniform: CameraUniform,
    /// Probe stride when a tool asked this frame to capture its depth and light grid.
    pub capture: Option<u32>,
    /// Counts rendered frames, from 1.
    pub index: u64,
    /// The usages of the texture this view is drawn into (the tonemap writes it from a compute
    /// kernel where it has `STORAGE_BINDING` or `COPY_DST`).
    pub target_usage: wgpu::TextureUsages,
    /// The format that texture is stored as: the configuration's output format, or its linear
    /// twin (`Rgba8Unorm` for `Rgba8UnormSrgb`, which can be a storage image).
    pub target_format: wgpu::TextureFormat,
}

impl FrameInputs {
    /// The target size as a vector.
    pub fn screen(&self) -> glam::UVec2 {
        glam::UVec2::new(self.config.width, self.config.height)
    }
}
