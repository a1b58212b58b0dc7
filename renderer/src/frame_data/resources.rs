//! The graph resources passes hand each other within a frame: each pass reads the handles
//! earlier passes put here and adds its own. A new kind of shared result (a shadow atlas, a
//! decal list) is a new field here, not a change to the orchestrator.

use crate::culling::Method;
use crate::frame_data::{ConfigError, RenderError, VisibilityHandles};
use crate::graph::{
    Buffer, BufferAccess, CompiledGraph, Handle, ImportAccess, PassBuilder, PassContext,
    RenderGraph, Texture,
};
use shaders_gen::shared::{light_lists, shadow_atlas};

/// The per-cell light lists of a culled frame.
#[derive(Debug, Clone)]
pub struct LightListHandles {
    /// `(offset, count)` per cell.
    pub grid: Handle<Buffer>,
    /// Light indices the grid points into.
    pub indices: Handle<Buffer>,
    /// How cells map to the screen (tiles or froxels), for the passes that look lists up.
    pub method: Method,
    /// The grid's buffer itself, for copies recorded after the graph (frame capture).
    pub grid_buffer: wgpu::Buffer,
}

impl LightListHandles {
    /// Declares that `pass` reads the lists, as a pass that binds them ([`Self::bindings`])
    /// must; with none (a naive frame), nothing.
    pub fn read_by(lists: Option<&Self>, pass: &mut PassBuilder<'_>) {
        if let Some(l) = lists {
            pass.read_buffer(l.grid, BufferAccess::StorageRead)
                .read_buffer(l.indices, BufferAccess::StorageRead);
        }
    }

    /// The `light_lists` library's part of a lit pass's group 0 (its generated builder), the
    /// lists resolved in `ctx`; with no lists (a naive frame), the part a variant without lists
    /// takes (both bindings absent).
    pub fn bindings<'a>(lists: Option<&Self>, ctx: &'a PassContext<'_>) -> light_lists::Group0<'a> {
        light_lists::Group0 {
            grid: lists.map(|l| ctx.buffer(l.grid).as_entire_buffer_binding()),
            indices: lists.map(|l| ctx.buffer(l.indices).as_entire_buffer_binding()),
        }
    }
}

/// How cells map to the screen, as the passes that look lists up need it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ListGeometry {
    /// Tile size in pixels (the configured tile when there are no lists).
    pub tile: u32,
    /// Tiles across and down.
    pub tiles: glam::UVec2,
    /// Depth slices (clustered; 1 otherwise).
    pub slices: u32,
    /// Grid entries from a tile's opaque list to its transparent one (tiled with blended
    /// surfaces; 0 otherwise).
    pub blend_cell_offset: u32,
    /// View depths where slice 1 and the last slice start (the camera's planes otherwise).
    pub near: f32,
    /// See `near`.
    pub far: f32,
    /// Grid entries from a cell's light list to its decal list: the lists of one item type
    /// (tiles × lists per tile; 0 without lists).
    pub decal_section: u32,
}

impl ListGeometry {
    /// The geometry of `method` (or of no lists) for a `config`-sized frame seen by `camera`.
    pub fn new(
        method: Option<Method>,
        config: &super::RendererConfig,
        camera: &super::FrameCamera,
    ) -> Self {
        let tile = method.map_or(config.tile, |m| m.tile());
        let tiles = glam::UVec2::new(config.width.div_ceil(tile), config.height.div_ceil(tile));
        let blend_cell_offset = if method.is_some_and(|m| m.transparent_lists()) {
            tiles.x * tiles.y
        } else {
            0
        };
        let (mut slices, mut near, mut far) = (1, camera.near, camera.far);
        if let Some(Method::Clustered { grid: g, .. }) = method {
            slices = g.slices;
            (near, far) = (g.near, g.far);
        }
        let lists_per_tile = match method {
            Some(Method::Clustered { grid, .. }) => grid.slices,
            Some(m) => 1 + u32::from(m.transparent_lists()),
            None => 0,
        };
        Self {
            decal_section: tiles.x * tiles.y * lists_per_tile,
            tile,
            tiles,
            slices,
            blend_cell_offset,
            near,
            far,
        }
    }
}

/// The scene's draws for the main view's geometry passes (pre-Z, forward, G-buffer): the batch
/// layout and each slot's `DrawIndexedIndirect` arguments, whose instance counts the culling
/// pass set (1 drawn, 0 culled).
#[derive(Debug, Clone)]
pub struct SceneDrawList {
    pub layout: std::sync::Arc<super::BatchLayout>,
    /// The arguments in the graph: read them (`BufferAccess::Indirect`) so culling runs first.
    pub args: Handle<Buffer>,
    /// The arguments' buffer, five `u32` per slot.
    pub args_buffer: wgpu::Buffer,
    /// The arguments slot by slot, packed or not (five `u32` a slot; an instance count of 0
    /// where culling left the slot out): what a kernel that walks the draws reads, written
    /// before `args` is.
    pub slot_args: wgpu::Buffer,
    /// Draw each batch with one `multi_draw_indexed_indirect`; otherwise (the device cannot
    /// draw indirectly with a first instance) every slot directly, culling nothing.
    pub indirect: bool,
    /// Where the slots are packed (`passes::scene_cull::compact`): each batch's drawn count, a
    /// `u32` per batch; `args_buffer` then holds each batch's drawn slots from its first slot
    /// on, and a batch is drawn with `multi_draw_indexed_indirect_count`.
    pub counts: Option<wgpu::Buffer>,
    /// With occlusion culling, what its second phase needs; `args` are then the first
    /// phase's until the occlusion pass replaces them with `OcclusionDraws::all`.
    pub occlusion: Option<OcclusionDraws>,
    /// The blended draws to draw this frame, back to front from the main camera (those in
    /// its frustum with `cull_draws`).
    pub blended: BlendedDraws,
}

impl SceneDrawList {
    /// What occlusion culling's second half draws (the late pre-Z, the late visibility
    /// raster): this list with the late slots' arguments (packed, with their counts, where
    /// the slots are packed); `None` without occlusion culling.
    pub fn late_half(&self) -> Option<SceneDrawList> {
        let occlusion = self.occlusion.as_ref()?;
        let mut list = self.clone();
        list.slot_args = occlusion.late_buffer.clone();
        match &occlusion.packed {
            Some(packed) => {
                list.args = packed.late;
                list.args_buffer = packed.late_args.clone();
                list.counts = Some(packed.late_counts.clone());
            }
            None => {
                list.args = occlusion.late;
                list.args_buffer = occlusion.late_buffer.clone();
                list.counts = None;
            }
        }
        Some(list)
    }
}

/// A frame's blended draws, back to front from the main camera.
#[derive(Debug, Clone)]
pub enum BlendedDraws {
    /// Ordered on the GPU ("blended order"): `count` draws' indirect arguments in
    /// `args_buffer`, back to front, one multi-draw; those outside the frustum (with
    /// `cull_draws`) draw no instance.
    Sorted {
        /// The arguments in the graph: read them (`BufferAccess::Indirect`) so the order is
        /// written first.
        args: Handle<Buffer>,
        args_buffer: wgpu::Buffer,
        count: u32,
        count_buffer: wgpu::Buffer,
    },
    /// Ordered on the CPU, on a device that cannot draw indirectly with a first instance:
    /// the draws, those in the frustum only with `cull_draws`.
    Listed(std::sync::Arc<[u32]>),
}

/// Occlusion culling's second phase as scene culling hands it on: the inputs of the test and
/// the arguments it writes.
#[derive(Debug, Clone)]
pub struct OcclusionDraws {
    /// The draws' world boxes and each slot's draw (as the first phase reads them).
    pub boxes: wgpu::Buffer,
    pub slot_draws: wgpu::Buffer,
    pub slot_count: u32,
    /// The frustum test's slack, in world units.
    pub slack: f32,
    /// Whether each slot was visible (written by the second phase for the next frame).
    pub history: wgpu::Buffer,
    /// The second phase's arguments: the slots found visible that the first did not draw.
    pub late: Handle<Buffer>,
    pub late_buffer: wgpu::Buffer,
    /// Every slot drawn in either phase.
    pub all: Handle<Buffer>,
    pub all_buffer: wgpu::Buffer,
    /// Two counters: slots drawn in the first phase, and in either (cleared by scene culling).
    pub visible: wgpu::Buffer,
    /// The first phase's arguments, slot by slot (what it drew, whether or not the list the
    /// pre-Z draws is packed).
    pub first_buffer: wgpu::Buffer,
    /// Where the slots are packed: the late and both-phases lists' packing, lists 1 and 2 of
    /// the compaction.
    pub packed: Option<OcclusionPacked>,
}

/// Occlusion culling's late and both-phases slot lists packed (`passes::scene_cull::compact`):
/// where their packed arguments and per-batch counts are, and how to record their packing.
#[derive(Clone)]
pub struct OcclusionPacked {
    /// Records the packing of both lists, once the late cull has written them.
    pub record: std::sync::Arc<dyn Fn(&mut crate::graph::PassEncoder<'_>) + Send + Sync>,
    /// The packed late list in the graph, its arguments and its counts.
    pub late: Handle<Buffer>,
    pub late_args: wgpu::Buffer,
    pub late_counts: wgpu::Buffer,
    /// The packed both-phases list in the graph, its arguments and its counts.
    pub all: Handle<Buffer>,
    pub all_args: wgpu::Buffer,
    pub all_counts: wgpu::Buffer,
}

impl std::fmt::Debug for OcclusionPacked {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OcclusionPacked")
            .field("late", &self.late)
            .field("all", &self.all)
            .finish_non_exhaustive()
    }
}

impl SceneDrawList {
    /// Bytes of one slot's arguments.
    pub const ARGS_BYTES: u64 = 20;
}

/// The shadow atlas as shading passes bind it (the `shadow_atlas` library's group 0 part,
/// [`ShadowResources::bindings`]).
#[derive(Debug, Clone)]
pub struct ShadowResources {
    /// The atlas in the graph: read it so the shadow pass runs first.
    pub atlas: Handle<Texture>,
    /// `SHADOW_VIEWS`: the views lights' `shadow` indices point at.
    pub views: wgpu::Buffer,
    /// `SHADOW_ATLAS`.
    pub atlas_view: wgpu::TextureView,
    /// `SHADOW_SAMPLER`: the comparison sampler.
    pub sampler: wgpu::Sampler,
    /// The regions of this frame: `(x, y, side, light id)` in atlas texels (debug views).
    pub regions: std::sync::Arc<Vec<[u32; 4]>>,
}

impl ShadowResources {
    /// The `shadow_atlas` library's part of every group 0 that shades with shadows (its
    /// generated builder: views, atlas, comparison sampler).
    pub fn bindings(&self) -> shadow_atlas::Group0<'_> {
        shadow_atlas::Group0 {
            shadow_views: self.views.as_entire_buffer_binding(),
            shadow_atlas: &self.atlas_view,
            shadow_sampler: &self.sampler,
        }
    }
}

/// The particle systems' buffers of a frame, as the particle lighting, draw and view passes
/// bind them (`particle_light`, `particle_draw`).
#[derive(Debug, Clone)]
pub struct ParticleResources {
    /// The particle slots after this frame's simulation step.
    pub simulated: Handle<Buffer>,
    /// The layout after this frame's sizing, allocation and sort (the sorted keys stand for
    /// regions, owners, state and draw arguments too, which the same pass writes).
    pub laid_out: Handle<Buffer>,
    /// `GpuEmitter` per emitter.
    pub emitters: wgpu::Buffer,
    /// `GpuParticle` per slot.
    pub particles: wgpu::Buffer,
    /// Packed region per slot.
    pub regions: wgpu::Buffer,
    /// Sorted `(key, slot)` pairs, visible particles first, back to front.
    pub keys: wgpu::Buffer,
    /// The layout's counters and plan (`particle_atlas::STATE`), ending with the indirect
    /// arguments of the draw and of the lighting dispatch.
    pub state: wgpu::Buffer,
    /// Region owners, class by class.
    pub owners: wgpu::Buffer,
    /// The camera, lights and grid the particle passes read (`ParticleView`).
    pub view: wgpu::Buffer,
    /// Atlas side, texels.
    pub atlas_side: u32,
    /// The lighting kernel's output: the atlas's texels as rows of `u32`.
    pub lit_texels: wgpu::Buffer,
    /// The atlas texture (`Rg11b10Ufloat`) the texels are copied into.
    pub atlas_texture: wgpu::Texture,
    /// The atlas in the graph, once the lighting pass has written it this frame.
    pub lit_atlas: Option<Handle<Texture>>,
    /// The sprite texture array (`SPRITES`).
    pub sprites: wgpu::TextureView,
    /// The sampler of the sprites and of the atlas's bilinear taps.
    pub sampler: wgpu::Sampler,
}

/// The multisampled G-buffer of the deferred paths (`frame_data::GBUFFER_FORMATS`). Only the
/// samples a surface covers are written; where the depth buffer holds 1.0 (sky) the targets are
/// not cleared and hold anything: read them only where the depth is below 1.
#[derive(Debug, Clone, Copy)]
pub struct GBufferHandles {
    /// Albedo (sRGB) and metalness.
    pub albedo: Handle<Texture>,
    /// Octahedral shading and geometric normals.
    pub normals: Handle<Texture>,
    /// Base radiance (ambient and emissive) and roughness.
    pub radiance: Handle<Texture>,
    /// View depth, where deferred shading puts the shaded point.
    pub view_depth: Handle<Texture>,
}

/// What the passes of one frame have produced so far.
#[derive(Debug)]
pub struct FrameResources {
    /// The caller's target texture (imported). It may be stored as the output format's
    /// linear twin ([`FrameInputs::target_format`](crate::frame_data::FrameInputs)): view it
    /// with `format: Some(config.output_format)` to draw into it.
    pub output: Handle<Texture>,
    /// The multisampled depth buffer (pre-Z, the visibility raster pass's, or the naive forward
    /// pass's own; under the compute rasteriser, resolved from its samples only for a pass that
    /// reads it).
    pub depth: Option<Handle<Texture>>,
    /// The culled light lists.
    pub light_lists: Option<LightListHandles>,
    /// The resolved linear HDR colour.
    pub hdr: Option<Handle<Texture>>,
    /// The shadow atlas (absent when the frame has no shadow pass).
    pub shadows: Option<ShadowResources>,
    /// The multisampled HDR colour the forward pass resolved into `hdr` (MSAA only, not on the
    /// deferred paths), for passes that draw more over it.
    pub hdr_multisampled: Option<Handle<Texture>>,
    /// On the deferred paths with MSAA: the multisampled overlay of what is drawn over the
    /// deferred image (blended surfaces, particles), premultiplied colour over transparent
    /// black, never resolved by a render pass. Draw into it with `One, OneMinusSrcAlpha` for
    /// alpha (as [`wgpu::BlendState::ALPHA_BLENDING`] and `PREMULTIPLIED_ALPHA_BLENDING` do);
    /// the `overlay` pass resolves it and lays it over `hdr` (into a new texture) after the
    /// particles, and takes (empties) this field.
    ///
    /// The overlay is kept between frames and loaded, not cleared: a pass that draws into it
    /// must add an eraser ([`FrameResources::add_overlay_eraser`]) that draws the same geometry
    /// again in transparent black once the overlay has been laid over the image.
    pub hdr_overlay: Option<Handle<Texture>>,
    /// Light lists covering every depth slice, for particles: the frame's clustered lists, or
    /// on the tiled paths lists of their own (absent on the naive paths and without particles).
    pub particle_lists: Option<LightListHandles>,
    /// The particles of this frame (absent without particles).
    pub particles: Option<ParticleResources>,
    /// In a further view of the frame: the particle slots the main view's simulation step
    /// wrote this frame, which this view lays out for itself (`Renderer::add_view`).
    pub main_particles: Option<Handle<Buffer>>,
    /// The G-buffer (deferred paths).
    pub gbuffer: Option<GBufferHandles>,
    /// Which pixels the deferred base pass shades per sample, a bit each, row-major (the
    /// traditional deferred path). The light volumes read it after the base pass wrote `hdr`,
    /// which orders them.
    pub deferred_edges: Option<wgpu::Buffer>,
    /// How the geometry passes draw the scene this frame: its batches and their indirect
    /// arguments, culled for the view (`passes::scene_cull`).
    pub scene_draws: Option<SceneDrawList>,
    /// The visibility buffer (the visibility path): the triangle each sample sees.
    pub visibility: Option<VisibilityHandles>,
    overlay_erasers: OverlayErasers,
    imports: Vec<(Handle<Buffer>, wgpu::Buffer)>,
    texture_imports: Vec<(Handle<Texture>, wgpu::Texture)>,
}

/// Erases what one pass drew into [`FrameResources::hdr_overlay`]: called by the overlay pass
/// after it read the overlay, it adds a graph pass that writes the given overlay handle,
/// drawing the pass's geometry again in transparent black over every sample it may have
/// touched (more is harmless), without blending or a depth test.
pub type OverlayEraser = Box<dyn FnOnce(&mut RenderGraph, &mut Handle<Texture>) + Send + Sync>;

/// The erasers of a frame, in the order their passes drew.
#[derive(Default)]
struct OverlayErasers(Vec<OverlayEraser>);

impl std::fmt::Debug for OverlayErasers {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} overlay erasers", self.0.len())
    }
}

impl FrameResources {
    /// A frame's resources before any pass ran: only the `output` target.
    pub fn new(output: Handle<Texture>) -> Self {
        Self {
            output,
            depth: None,
            light_lists: None,
            hdr: None,
            shadows: None,
            hdr_multisampled: None,
            hdr_overlay: None,
            particle_lists: None,
            particles: None,
            main_particles: None,
            gbuffer: None,
            scene_draws: None,
            deferred_edges: None,
            visibility: None,
            overlay_erasers: OverlayErasers::default(),
            imports: Vec::new(),
            texture_imports: Vec::new(),
        }
    }

    /// Registers the eraser of what a pass drew into [`FrameResources::hdr_overlay`] this
    /// frame; the overlay pass runs it after reading the overlay.
    pub fn add_overlay_eraser(&mut self, eraser: OverlayEraser) {
        self.overlay_erasers.0.push(eraser);
    }

    /// Runs the erasers no overlay pass ran this frame (a pass list without one, or an engine
    /// pass that took the overlay before it) over [`FrameResources::hdr_overlay`], so the kept
    /// overlay is transparent again for the next frame. An error where erasers are left and the
    /// overlay was taken: what they would erase can no longer be reached.
    pub(crate) fn run_left_erasers(&mut self, graph: &mut RenderGraph) -> Result<(), RenderError> {
        let erasers = self.take_overlay_erasers();
        if erasers.is_empty() {
            return Ok(());
        }
        let Some(mut overlay) = self.hdr_overlay else {
            return Err(RenderError::Config(ConfigError::MissingInput {
                pass: "overlay erase",
                input: "the overlay its erasers draw into (a pass took hdr_overlay without \
                        running FrameResources' erasers)",
            }));
        };
        for erase in erasers {
            erase(graph, &mut overlay);
        }
        self.hdr_overlay = Some(overlay);
        Ok(())
    }

    /// The erasers registered this frame, taken (the overlay pass runs them).
    pub(crate) fn take_overlay_erasers(&mut self) -> Vec<OverlayEraser> {
        std::mem::take(&mut self.overlay_erasers.0)
    }

    /// Imports a buffer a pass owns across frames; it is bound when the graph is compiled.
    pub fn import_buffer(
        &mut self,
        graph: &mut RenderGraph,
        name: &str,
        buffer: &wgpu::Buffer,
        access: ImportAccess,
    ) -> Handle<Buffer> {
        let desc = crate::graph::BufferDesc {
            size: buffer.size(),
        };
        let handle = graph.import_buffer(name, desc, access);
        self.imports.push((handle, buffer.clone()));
        handle
    }

    /// Imports a texture a pass owns across frames; it is bound when the graph is compiled.
    pub fn import_texture(
        &mut self,
        graph: &mut RenderGraph,
        name: &str,
        texture: &wgpu::Texture,
        access: ImportAccess,
    ) -> Handle<Texture> {
        let mut desc =
            crate::graph::TextureDesc::new_2d(texture.width(), texture.height(), texture.format());
        desc.sample_count = texture.sample_count();
        desc.layers = texture.depth_or_array_layers();
        let handle = graph.import_texture(name, desc, access);
        self.texture_imports.push((handle, texture.clone()));
        handle
    }

    /// Binds every buffer and texture imported through [`Self::import_buffer`] and
    /// [`Self::import_texture`].
    pub fn bind_imports(&self, compiled: &mut CompiledGraph) {
        for (handle, buffer) in &self.imports {
            compiled.bind_buffer(*handle, buffer);
        }
        for (handle, texture) in &self.texture_imports {
            compiled.bind_texture(*handle, texture);
        }
    }
}
