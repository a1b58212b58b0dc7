//! Why the renderer cannot be set up or cannot render a frame, split by what the caller can do
//! about it: change the configuration ([`ConfigError`]), fix what it handed over
//! ([`InputError`]), or deal with the device ([`DeviceError`]).

use crate::culling::CullError;
use crate::graph::GraphError;
use crate::shader::VariantError;

/// Why the renderer cannot be set up or cannot render. Nothing was drawn or changed: the
/// renderer keeps its previous scene, lights, configuration and views.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RenderError {
    /// The configuration asks for what this renderer or device cannot do: change the
    /// [`RendererConfig`](super::RendererConfig), a view's configuration, the pass list or the
    /// material program, or use a device with the feature or limit named.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// What the engine handed over is wrong or does not fit: a scene, material, light list,
    /// decal set, particle system, handle, view or target. Fix the input; the renderer is as it
    /// was.
    #[error(transparent)]
    Input(#[from] InputError),
    /// The device failed: lost (create a new [`GpuContext`](crate::GpuContext) and renderer),
    /// out of memory (ask for less), or a readback or GPU timing that failed.
    #[error(transparent)]
    Device(#[from] DeviceError),
}

impl RenderError {
    /// Whether the device was lost: the renderer cannot be used again.
    pub fn is_device_lost(&self) -> bool {
        matches!(self, Self::Device(DeviceError::DeviceLost(_)))
    }
}

/// Converts the errors of the renderer's parts into the [`RenderError`] category they belong
/// to, so `?` works across them.
macro_rules! categorised {
    ($($source:ty => $category:ident :: $variant:ident),* $(,)?) => {$(
        impl From<$source> for RenderError {
            fn from(e: $source) -> Self {
                Self::from($category::$variant(e))
            }
        }
    )*};
}

categorised!(
    VariantError => ConfigError::Variant,
    codegen::rt::ExcludedVariant => ConfigError::Excluded,
    CullError => ConfigError::Cull,
    GraphError => ConfigError::Graph,
    shader_bind::BindError => ConfigError::Bind,
    crate::scene::SceneError => InputError::Scene,
    crate::materials::MaterialError => InputError::Material,
    crate::decals::DecalError => InputError::Decals,
    crate::particles::ParticleError => InputError::Particles,
    crate::GpuError => DeviceError::Readback,
);

/// A configuration this renderer or device cannot draw: change the configuration, the pass
/// list or the material program, or use a device with what is named.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ConfigError {
    /// A pass's buffer for this frame size is larger than the device binds.
    #[error(
        "the {pass} pass needs a {bytes}-byte {buffer} buffer; this device binds at most {max} \
         bytes in one storage binding (lower the frame size or the MSAA count)"
    )]
    BufferTooLarge {
        /// The pass's name.
        pass: &'static str,
        /// Which of its buffers.
        buffer: &'static str,
        /// Its size at this frame size.
        bytes: u64,
        /// The device's `max_storage_buffer_binding_size`.
        max: u64,
    },
    /// `RendererConfig::msaa` is a count the device (depth and colour target together) or the
    /// path's shaders do not have.
    #[error("MSAA {asked} is not supported by this device (supported: {supported:?})")]
    SampleCount {
        /// The sample count asked for.
        asked: u32,
        /// The counts that would work.
        supported: Vec<u32>,
    },
    /// `RendererConfig::scalarize` is on, but the device lacks `Features::SUBGROUP`.
    #[error("scalarize was requested but the device has no SUBGROUP feature")]
    NoSubgroup,
    /// A heatmap view (`FrameView::Heatmap`, `DecalHeatmap`) on `RenderPath::Naive` or
    /// `NaivePrez`, which build no lists.
    #[error(
        "the light heatmap shows culled lists; the naive path has none (use tiled, 2.5D or clustered)"
    )]
    HeatmapNeedsLists,
    /// While the frame graph was built, a pass found a resource it reads missing: the pass list
    /// (for example after `insert_pass_after` or a custom list) lacks the pass that makes it.
    #[error(
        "pass `{pass}` needs the {input} of an earlier pass, and no earlier pass of this frame \
         produced it; put a pass that does before it"
    )]
    MissingInput {
        /// The pass that needs it.
        pass: &'static str,
        /// What it needs (for example "depth buffer", "HDR colour").
        input: &'static str,
    },
    /// `insert_pass_after` named a pass this renderer's pass list does not have.
    #[error("no pass named `{0}` in this renderer's pass list")]
    NoSuchPass(
        /// The pass name given.
        String,
    ),
    /// A shader variant the configuration picks cannot run on this device.
    #[error(transparent)]
    Variant(
        /// Which variant, and what it lacks.
        VariantError,
    ),
    /// The configuration picks a shader variant key the DSL module excludes from its matrix.
    #[error(transparent)]
    Excluded(
        /// The module and the excluded key.
        codegen::rt::ExcludedVariant,
    ),
    /// Light culling cannot be set up with these settings (tile size, MSAA, cluster grid,
    /// list capacities).
    #[error(transparent)]
    Cull(
        /// The culling setting refused.
        CullError,
    ),
    /// A pass built an invalid frame graph, or executing it failed (an unbound import, a bind
    /// group).
    #[error(transparent)]
    Graph(
        /// The pass and the graph mistake.
        GraphError,
    ),
    /// A generated bind-group builder refused a resource (outside the graph's recording, where
    /// [`GraphError::Bind`] names the pass).
    #[error(transparent)]
    Bind(
        /// The binding refused, and why.
        shader_bind::BindError,
    ),
    /// A frame capture was asked for (`capture_next_frame`) on a path without the depth
    /// pre-pass.
    #[error(
        "a frame capture reads the pre-Z depth; the naive path has none (use naive-prez or a culled path)"
    )]
    CaptureNeedsDepth,
    /// Shadows are on and `ShadowConfig::atlas_size` is outside `min..=max`.
    #[error(
        "shadow atlas of {asked}² texels: use a size from {min} to this device's largest \
         texture side, {max}"
    )]
    ShadowAtlasSize {
        /// The atlas side asked for, in texels.
        asked: u32,
        /// The smallest side: `min_resolution`, or the cascade side (capped at
        /// `max_resolution`) if larger.
        min: u32,
        /// The device's largest 2D texture side.
        max: u32,
    },
    /// A deferred path with a `RendererConfig::tile` other than 8 or 16.
    #[error(
        "RendererConfig::tile {0} does not suit the deferred paths (RenderPath::Tbdr, \
         TbdrPerSample, Deferred): use 8 or 16 (one invocation per pixel, and a tile's \
         per-sample colours in workgroup memory)"
    )]
    TbdrTile(
        /// The tile side given, in pixels.
        u32,
    ),
    /// `FrameView::ShadingFrequency` on a path that is not deferred.
    #[error(
        "FrameView::ShadingFrequency shows which pixels deferred shading shades per sample; set \
         RendererConfig::path to RenderPath::Tbdr, TbdrPerSample, Deferred or Visibility"
    )]
    ShadingFrequencyNeedsTbdr,
    /// `RendererConfig::light_cutoff` is negative, NaN or infinite.
    #[error(
        "light cutoff {0}: use a finite illuminance of 0 or more (0 keeps lights without a \
         range infinite; the default is 0.001)"
    )]
    LightCutoff(
        /// The cutoff given.
        f32,
    ),
    /// A path needs more of a device limit than the device has.
    #[error(
        "RenderPath::{path:?} needs {limit} of {needs} or more; this device has {device} (use \
         another path, or a device that allows more)"
    )]
    PathNeedsLimit {
        /// The path.
        path: super::RenderPath,
        /// The `wgpu::Limits` field.
        limit: &'static str,
        /// What the path needs.
        needs: u64,
        /// What the device allows.
        device: u64,
    },
    /// A frame size (configuration or `resize`) of 0 or past the device's largest texture side.
    #[error(
        "frame size {width}x{height}: use 1 to {max} pixels a side (this device's largest \
         texture side)"
    )]
    FrameSize {
        /// The width asked for, in pixels.
        width: u32,
        /// The height asked for, in pixels.
        height: u32,
        /// The device's largest 2D texture side.
        max: u32,
    },
}

/// Input the renderer cannot use: a scene, material, light list, decal set, particle system,
/// handle, view or target that is wrong or does not fit this device.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum InputError {
    /// A frame, or a call that needs the prepared scene (adding meshes or instances, say),
    /// came before `prepare_scene`.
    #[error("render() was called before prepare_scene()")]
    NoScene,
    /// A view id that was never added or was removed (`render_views`, `reconfigure_view`,
    /// `remove_view`).
    #[error("{0:?} is not a view of this renderer (never added, or removed)")]
    NoSuchView(
        /// The id given.
        super::ViewId,
    ),
    /// `render_views` lists the same view twice.
    #[error("{0:?} is listed twice in one frame; draw a view once per frame")]
    ViewTwice(
        /// The repeated view.
        super::ViewId,
    ),
    /// A scene, mesh, material or image is inconsistent or past the device's limits, or an
    /// edit names something the prepared scene does not have.
    #[error(transparent)]
    Scene(
        /// What is wrong, and where.
        crate::scene::SceneError,
    ),
    /// A material program that cannot be registered, or a material that cannot use one.
    #[error(transparent)]
    Material(
        /// The program or material, and why.
        crate::materials::MaterialError,
    ),
    /// More lights than one storage binding of the light buffer holds on this device.
    #[error(
        "{count} lights do not fit this device's light buffer (at most {max}: the storage \
         binding size limit); use fewer lights"
    )]
    TooManyLights {
        /// Lights given.
        count: usize,
        /// Lights the device holds.
        max: usize,
    },
    /// More blended draws than the GPU sort orders in one pass on this device.
    #[error(
        "the scene has {count} blended draws; this device sorts at most {max} back to front in \
         one pass (its dispatch limit)"
    )]
    TooManyBlendedDraws {
        /// The scene's blended draws.
        count: u32,
        /// The most the device sorts.
        max: u32,
    },
    /// More shadow-caster slots than one shadow region's culling dispatch covers.
    #[error(
        "the scene has {slots} shadow-caster slots; this device culls at most {max} per shadow \
         region (its storage-binding and dispatch limits)"
    )]
    TooManyShadowCasters {
        /// Caster slots: one per opaque or masked draw, plus spare slots.
        slots: u32,
        /// The most the device culls per region.
        max: u32,
    },
    /// A GPU sort of more items than one dispatch covers on this device.
    #[error("a GPU sort of {asked} items; this device's dispatches take at most {max}")]
    SortTooLarge {
        /// Items to sort.
        asked: u32,
        /// The most the device sorts.
        max: u32,
    },
    /// `scene_instance` was given an index past the scene's instances, or of one removed.
    #[error(
        "instance {index} is not in the scene: the prepared scene has {count} instance slots \
         (its nodes with a mesh in `Scene::instances` order, then instances added), and a \
         removed one is gone; call prepare_scene first"
    )]
    NoSuchInstance {
        /// The index given.
        index: usize,
        /// The prepared scene's instance slots.
        count: usize,
    },
    /// An instance handle whose instance was removed, or that belongs to an earlier scene.
    #[error(
        "the instance handle names instance slot {index}, whose instance was removed, or an \
         earlier scene's instance"
    )]
    StaleInstance {
        /// The handle's slot.
        index: usize,
    },
    /// `add_instance` named a mesh index past the prepared scene's meshes.
    #[error("mesh {mesh} does not exist: the prepared scene has {count} meshes")]
    NoSuchMesh {
        /// The mesh index given.
        mesh: usize,
        /// Meshes in the prepared scene.
        count: usize,
    },
    /// `set_instance_material` named a primitive past those of the instance's mesh.
    #[error("primitive {primitive} is past the instance's mesh's {count} primitives")]
    NoSuchPrimitive {
        /// The primitive index given.
        primitive: usize,
        /// Primitives of the mesh.
        count: usize,
    },
    /// `add_instance` named a mesh removed with `remove_mesh`.
    #[error("mesh {mesh} was removed; add it again (add_mesh) for a new index")]
    MeshRemoved {
        /// The removed mesh's index.
        mesh: usize,
    },
    /// `remove_mesh` on a mesh that live instances still draw.
    #[error("mesh {mesh} still has {instances} instances: remove them first")]
    MeshInUse {
        /// The mesh index.
        mesh: usize,
        /// Its live instances.
        instances: usize,
    },
    /// An instance transform given has a NaN or infinite element.
    #[error("an instance transform must be finite; this one has a NaN or an infinity")]
    NotFiniteTransform,
    /// A decal set or decal image that is invalid or does not fit.
    #[error(transparent)]
    Decals(
        /// The decal problem.
        crate::decals::DecalError,
    ),
    /// A particle system that cannot run.
    #[error(transparent)]
    Particles(
        /// The particle system problem.
        crate::particles::ParticleError,
    ),
    /// The render target's size or format differs from the configuration's (an sRGB output
    /// format also takes a target stored as its linear twin).
    #[error(
        "the target texture is {actual:?} {actual_format:?}; this renderer draws {expected:?} \
         {expected_format:?} (resize the renderer or the target, or set \
         RendererConfig::output_format; an sRGB format also takes a target stored as its linear \
         twin, with the sRGB format among its view formats)"
    )]
    TargetMismatch {
        /// The target's (width, height), in pixels.
        actual: (u32, u32),
        /// The target's format.
        actual_format: wgpu::TextureFormat,
        /// The configuration's (width, height), in pixels.
        expected: (u32, u32),
        /// `RendererConfig::output_format`.
        expected_format: wgpu::TextureFormat,
    },
}

/// The device failed under the renderer.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DeviceError {
    /// A readback (such as `take_capture`) or waiting for the GPU (such as
    /// `wait_for_frames_in_flight`) failed.
    #[error(transparent)]
    Readback(
        /// The GPU error.
        crate::GpuError,
    ),
    /// The renderer's GPU profiler could not be created or could not end a frame.
    #[error("GPU timing failed: {0}")]
    Profiler(
        /// wgpu-profiler's error, as text.
        String,
    ),
    /// The device was lost before or while the frame was recorded; the renderer cannot be
    /// used again ([`RenderError::is_device_lost`]).
    #[error(
        "the GPU device was lost ({0}); create a new GpuContext and Renderer, and prepare the \
         scene, lights and decals again"
    )]
    DeviceLost(
        /// The loss reason wgpu reported.
        String,
    ),
    /// An allocation failed while the frame was recorded; nothing was drawn.
    #[error(
        "the GPU ran out of memory recording this frame ({0}); use a smaller frame size, MSAA \
         count, atlas or light count"
    )]
    OutOfMemory(
        /// wgpu's error, as text.
        String,
    ),
}

impl ConfigError {
    /// `asked` is not among the sample counts a shader's `msaa` axis has (1, 2, 4 and 8).
    pub(crate) fn shader_sample_count(asked: u32) -> RenderError {
        RenderError::Config(Self::SampleCount {
            asked,
            supported: vec![1, 2, 4, 8],
        })
    }
}
