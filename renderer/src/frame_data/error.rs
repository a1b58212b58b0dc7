//! Why the renderer cannot be set up or cannot render a frame.

use crate::culling::CullError;
use crate::graph::GraphError;
use crate::shader::VariantError;

/// Why the renderer cannot be set up or cannot render.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    #[error("MSAA {asked} is not supported by this device (supported: {supported:?})")]
    SampleCount { asked: u32, supported: Vec<u32> },
    #[error("scalarize was requested but the device has no SUBGROUP feature")]
    NoSubgroup,
    #[error("render() was called before prepare_scene()")]
    NoScene,
    #[error(
        "the light heatmap shows culled lists; the naive path has none (use tiled, 2.5D or clustered)"
    )]
    HeatmapNeedsLists,
    #[error(
        "pass `{pass}` needs the {input} of an earlier pass, and no earlier pass of this frame \
         produced it; put a pass that does before it"
    )]
    MissingInput {
        pass: &'static str,
        input: &'static str,
    },
    #[error("no pass named `{0}` in this renderer's pass list")]
    NoSuchPass(String),
    #[error("{0:?} is not a view of this renderer (never added, or removed)")]
    NoSuchView(super::ViewId),
    #[error("{0:?} is listed twice in one frame; draw a view once per frame")]
    ViewTwice(super::ViewId),
    #[error(transparent)]
    Variant(#[from] VariantError),
    #[error(transparent)]
    Excluded(#[from] codegen::rt::ExcludedVariant),
    #[error(transparent)]
    Cull(#[from] CullError),
    #[error(transparent)]
    Graph(#[from] GraphError),
    /// A generated bind-group builder refused a resource (outside the graph's recording, where
    /// [`GraphError::Bind`] names the pass).
    #[error(transparent)]
    Bind(#[from] shader_bind::BindError),
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
    /// A material program that cannot be registered, or a material that cannot use one.
    #[error(transparent)]
    Material(#[from] crate::materials::MaterialError),
    #[error(
        "a frame capture reads the pre-Z depth; the naive path has none (use naive-prez or a culled path)"
    )]
    CaptureNeedsDepth,
    #[error(transparent)]
    Readback(#[from] crate::GpuError),
    #[error("GPU timing failed: {0}")]
    Profiler(String),
    #[error(
        "{count} lights do not fit this device's light buffer (at most {max}: the storage \
         binding size limit); use fewer lights"
    )]
    TooManyLights { count: usize, max: usize },
    #[error(
        "the scene has {count} blended draws; this device sorts at most {max} back to front in \
         one pass (its dispatch limit)"
    )]
    TooManyBlendedDraws { count: u32, max: u32 },
    #[error(
        "the scene has {slots} shadow-caster slots; this device culls at most {max} per shadow \
         region (its storage-binding and dispatch limits)"
    )]
    TooManyShadowCasters { slots: u32, max: u32 },
    #[error("a GPU sort of {asked} items; this device's dispatches take at most {max}")]
    SortTooLarge { asked: u32, max: u32 },
    #[error(
        "instance {index} is not in the scene: the prepared scene has {count} instance slots \
         (its nodes with a mesh in `Scene::instances` order, then instances added), and a \
         removed one is gone; call prepare_scene first"
    )]
    NoSuchInstance { index: usize, count: usize },
    #[error(
        "the instance handle names instance slot {index}, whose instance was removed, or an \
         earlier scene's instance"
    )]
    StaleInstance { index: usize },
    #[error("mesh {mesh} does not exist: the prepared scene has {count} meshes")]
    NoSuchMesh { mesh: usize, count: usize },
    #[error("primitive {primitive} is past the instance's mesh's {count} primitives")]
    NoSuchPrimitive { primitive: usize, count: usize },
    #[error("mesh {mesh} was removed; add it again (add_mesh) for a new index")]
    MeshRemoved { mesh: usize },
    #[error("mesh {mesh} still has {instances} instances: remove them first")]
    MeshInUse { mesh: usize, instances: usize },
    #[error("an instance transform must be finite; this one has a NaN or an infinity")]
    NotFiniteTransform,
    #[error(
        "shadow atlas of {asked}² texels: use a size from {min} to this device's largest \
         texture side, {max}"
    )]
    ShadowAtlasSize { asked: u32, min: u32, max: u32 },
    #[error(transparent)]
    Decals(#[from] crate::decals::DecalError),
    #[error(transparent)]
    Particles(#[from] crate::particles::ParticleError),
    #[error(
        "RendererConfig::tile {0} does not suit the deferred paths (RenderPath::Tbdr, \
         TbdrPerSample, Deferred): use 8 or 16 (one invocation per pixel, and a tile's \
         per-sample colours in workgroup memory)"
    )]
    TbdrTile(u32),
    #[error(
        "FrameView::ShadingFrequency shows which pixels deferred shading shades per sample; set \
         RendererConfig::path to RenderPath::Tbdr, TbdrPerSample or Deferred"
    )]
    ShadingFrequencyNeedsTbdr,
    #[error(
        "light cutoff {0}: use a finite illuminance of 0 or more (0 keeps lights without a \
         range infinite; the default is 0.001)"
    )]
    LightCutoff(f32),
    #[error(
        "frame size {width}x{height}: use 1 to {max} pixels a side (this device's largest \
         texture side)"
    )]
    FrameSize { width: u32, height: u32, max: u32 },
    #[error(
        "the target texture is {actual:?} {actual_format:?}; this renderer draws {expected:?} \
         {expected_format:?} (resize the renderer or the target, or set \
         RendererConfig::output_format)"
    )]
    TargetMismatch {
        actual: (u32, u32),
        actual_format: wgpu::TextureFormat,
        expected: (u32, u32),
        expected_format: wgpu::TextureFormat,
    },
    #[error(
        "the GPU device was lost ({0}); create a new GpuContext and Renderer, and prepare the \
         scene, lights and decals again"
    )]
    DeviceLost(String),
    #[error(
        "the GPU ran out of memory recording this frame ({0}); use a smaller frame size, MSAA \
         count, atlas or light count"
    )]
    OutOfMemory(String),
}
