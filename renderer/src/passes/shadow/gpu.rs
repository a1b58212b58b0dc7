//! The shadow pass's GPU objects: the shadow atlas and its static cache (both
//! [`SHADOW_FORMAT`], reversed Z), the caster, clear and copy pipelines, the view buffers, and
//! the recording of a frame's work items (culled on the GPU and drawn by multi-draws, or
//! listed on the CPU and drawn one by one).

use std::sync::Arc;

use shaders_gen::shadow::{shadow_caster, shadow_compose};

use super::super::{MASK_STREAMS, MeshPipeline, SceneDraws, mesh_pipeline};
use super::culling::CullDispatches;
use super::work::{Start, WorkItem};
use crate::frame_data::{PreparedScene, RenderError};
use crate::scene::{AlphaMode, VertexStreams};
use crate::shader::ShaderProgram;
use crate::shadow::atlas::AtlasRect;

/// The atlas format: 32-bit float depth (reversed Z keeps its precision where it matters).
pub const SHADOW_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Slope-scaled depth bias of casters (reversed Z: negative pushes them away from the light).
const SLOPE_BIAS: f32 = -1.5;
/// Constant depth bias of casters, in units of the depth format's precision at the caster.
const CONSTANT_BIAS: i32 = -8;

/// The caster pipelines: depth only for opaque materials; alpha-masked ones (the `alpha_mask`
/// variant, group 2 the scene's material group, `PreparedScene::mask_group`) discard texels below their cutoff.
#[derive(Debug, Clone)]
pub struct CasterPipelines {
    pub opaque: wgpu::RenderPipeline,
    pub masked: wgpu::RenderPipeline,
}

/// Pipelines and layouts, shared by every frame.
#[derive(Debug)]
pub struct ShadowPipelines {
    caster_program: ShaderProgram,
    /// Kept with its pipeline (the masked caster variant).
    _masked_caster_program: ShaderProgram,
    compose_program: ShaderProgram,
    pub caster: CasterPipelines,
    pub clear: wgpu::RenderPipeline,
    pub copy: wgpu::RenderPipeline,
}

impl ShadowPipelines {
    pub fn new(gpu: &crate::GpuContext) -> Result<Self, RenderError> {
        let device = &gpu.device;
        let caps = gpu.capabilities();
        let caster_variant =
            |alpha_mask| shadow_caster::variant(shadow_caster::VariantKey { alpha_mask });
        let caster_program = ShaderProgram::new(device, caps, caster_variant(false))?;
        let masked_program = ShaderProgram::new(device, caps, caster_variant(true))?;
        let compose_program = ShaderProgram::new(device, caps, &shadow_compose::VARIANTS[0])?;
        let mut depth = region_depth(wgpu::CompareFunction::Greater);
        depth.bias = wgpu::DepthBiasState {
            constant: CONSTANT_BIAS,
            slope_scale: SLOPE_BIAS,
            clamp: 0.0,
        };
        let caster_pipeline = |program, masked: bool| {
            mesh_pipeline(
                device,
                program,
                &MeshPipeline {
                    label: if masked {
                        "shadow casters masked"
                    } else {
                        "shadow casters"
                    },
                    vertex_entry: if masked {
                        "vs_caster_mask"
                    } else {
                        "vs_caster"
                    },
                    streams: if masked {
                        &MASK_STREAMS
                    } else {
                        &[wgpu::VertexFormat::Float32x3]
                    },
                    // Both faces cast: thin and open meshes must not leak light.
                    double_sided: true,
                    // Nothing is culled, so the winding (mirrored draws) changes nothing here.
                    mirrored: false,
                    depth: depth.clone(),
                    msaa: 1,
                    // Opaque casters write depth without a fragment stage; masked ones discard.
                    fragment: masked.then_some(("fs_caster_mask", &[][..])),
                },
            )
        };
        let caster = CasterPipelines {
            opaque: caster_pipeline(&caster_program, false),
            masked: caster_pipeline(&masked_program, true),
        };
        // The clear draw binds nothing (its layout is empty), so it can run on either atlas.
        let empty = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("shadow clear"),
            bind_group_layouts: &[],
            immediate_size: 0,
        });
        let clear = region_pipeline(device, &compose_program.module, &empty, None);
        let copy = region_pipeline(
            device,
            &compose_program.module,
            &compose_program.pipeline_layout,
            Some("fs_copy_static"),
        );
        Ok(Self {
            caster_program,
            _masked_caster_program: masked_program,
            compose_program,
            caster,
            clear,
            copy,
        })
    }
}

/// Depth state of atlas drawing: writes, `compare`.
fn region_depth(compare: wgpu::CompareFunction) -> wgpu::DepthStencilState {
    wgpu::DepthStencilState {
        format: SHADOW_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(compare),
        stencil: Default::default(),
        bias: Default::default(),
    }
}

/// A pipeline covering the viewport with `vs_region` at depth 0, writing depth always: a
/// clear without a fragment stage, a copy with `fs_copy_static`.
fn region_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    fragment: Option<&str>,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(fragment.unwrap_or("shadow clear")),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_region"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: Some(region_depth(wgpu::CompareFunction::Always)),
        multisample: wgpu::MultisampleState::default(),
        fragment: fragment.map(|entry| wgpu::FragmentState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            targets: &[],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The atlases and the view buffers.
#[derive(Debug)]
pub struct ShadowTargets {
    /// Sampled by shading, drawn by the pass.
    pub atlas: wgpu::Texture,
    pub atlas_view: wgpu::TextureView,
    /// Static casters' depth (cached mode only).
    pub static_atlas: Option<wgpu::TextureView>,
    pub sampler: wgpu::Sampler,
    /// `SHADOW_VIEWS` for shading.
    pub views: wgpu::Buffer,
    /// `VIEWS` of the caster pipeline (one clip matrix per region).
    pub caster_views: wgpu::Buffer,
    /// Group 0 of the copy pipeline (the static atlas).
    pub copy_group: Option<wgpu::BindGroup>,
    /// Views `views` and `caster_views` hold.
    pub capacity: usize,
}

impl ShadowTargets {
    /// Atlases of `size`² texels (the static cache when `cached`) and buffers for `capacity`
    /// views.
    pub fn new(
        device: &wgpu::Device,
        pipelines: &ShadowPipelines,
        size: u32,
        cached: bool,
        capacity: usize,
    ) -> Self {
        let atlas = atlas_texture(device, "shadow atlas", size);
        let static_atlas = cached.then(|| {
            atlas_texture(device, "shadow static cache", size).create_view(&Default::default())
        });
        let capacity = capacity.max(1);
        let (views, caster_views) = view_buffers(device, capacity);
        let copy_group = static_atlas.as_ref().map(|view| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("shadow static cache"),
                layout: &pipelines.compose_program.bind_group_layouts[0],
                entries: &super::super::entries(&[wgpu::BindingResource::TextureView(view)]),
            })
        });
        Self {
            atlas_view: atlas.create_view(&Default::default()),
            atlas,
            static_atlas,
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("shadow comparison"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                compare: Some(wgpu::CompareFunction::GreaterEqual),
                ..Default::default()
            }),
            views,
            caster_views,
            copy_group,
            capacity,
        }
    }

    /// Replaces the view buffers with ones for `capacity` views (the atlases stay).
    pub fn grow(&mut self, device: &wgpu::Device, capacity: usize) {
        (self.views, self.caster_views) = view_buffers(device, capacity);
        self.capacity = capacity;
    }
}

/// `SHADOW_VIEWS` and the casters' `VIEWS`, for `capacity` views.
fn view_buffers(device: &wgpu::Device, capacity: usize) -> (wgpu::Buffer, wgpu::Buffer) {
    let views = storage(
        device,
        "shadow views",
        capacity * size_of::<shaders_gen::forward::forward::ShadowView>(),
    );
    let caster_views = storage(
        device,
        "shadow caster views",
        capacity * size_of::<shadow_caster::CasterView>(),
    );
    (views, caster_views)
}

impl ShadowPipelines {
    /// Group 0 of the caster pipelines: the regions' clip matrices and the cast records.
    pub fn caster_group(
        &self,
        device: &wgpu::Device,
        caster_views: &wgpu::Buffer,
        casts: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow caster views and casts"),
            layout: &self.caster_program.bind_group_layouts[0],
            entries: &super::super::entries(&[
                caster_views.as_entire_binding(),
                casts.as_entire_binding(),
            ]),
        })
    }
}

fn atlas_texture(device: &wgpu::Device, label: &str, size: u32) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size,
            height: size,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: SHADOW_FORMAT,
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT
            | wgpu::TextureUsages::TEXTURE_BINDING
            | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    })
}

/// A storage buffer the CPU writes (and tools and tests read back).
fn storage(device: &wgpu::Device, label: &str, bytes: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes as u64,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// Where a frame's casts come from.
pub enum CastSource {
    /// Culled on the GPU, chunk by chunk: each work item draws its run of `dispatches.stride`
    /// argument slots, the first `opaque` with the opaque pipeline, the rest masked.
    Culled {
        dispatches: CullDispatches,
        args: wgpu::Buffer,
        opaque: u32,
    },
    /// Listed on the CPU (`CastList`), drawn one by one: per item, its first cast and count.
    Listed {
        casts: Vec<shadow_caster::Cast>,
        runs: Vec<(u32, u32)>,
    },
}

/// What the recording of one frame needs.
pub struct Recording {
    pub items: Vec<WorkItem>,
    pub casts: CastSource,
    pub scene: Arc<PreparedScene>,
    pub instances: Arc<crate::frame_data::InstanceTable>,
    pub caster: CasterPipelines,
    pub clear: wgpu::RenderPipeline,
    pub copy: wgpu::RenderPipeline,
    pub caster_group: wgpu::BindGroup,
    pub copy_group: Option<wgpu::BindGroup>,
    pub static_atlas: Option<wgpu::TextureView>,
}

impl Recording {
    /// Records the work items in order: per chunk of GPU-culled work, the culling dispatch,
    /// then the chunk's static-cache redraws, then its draws into the shadow atlas.
    pub fn record(&self, encoder: &mut wgpu::CommandEncoder, atlas: &wgpu::TextureView) {
        match &self.casts {
            CastSource::Culled { dispatches, .. } => {
                dispatches.clear_counts(encoder);
                for (c, chunk) in dispatches.chunks.iter().enumerate() {
                    dispatches.cull(encoder, c);
                    self.record_items(encoder, atlas, chunk.start as usize..chunk.end as usize);
                }
            }
            CastSource::Listed { .. } => self.record_items(encoder, atlas, 0..self.items.len()),
        }
    }

    /// Items `range`: the static cache's, then the shadow atlas's.
    fn record_items(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        atlas: &wgpu::TextureView,
        range: std::ops::Range<usize>,
    ) {
        let (into_static, into_atlas): (Vec<usize>, Vec<usize>) =
            range.partition(|&i| self.items[i].in_static_cache());
        let runs = [
            (into_static, self.static_atlas.as_ref()),
            (into_atlas, Some(atlas)),
        ];
        for (items, view) in runs {
            let Some(view) = view.filter(|_| !items.is_empty()) else {
                continue;
            };
            let label = if view == atlas {
                "shadow atlas"
            } else {
                "shadow static cache"
            };
            let mut pass = depth_pass(encoder, label, view);
            self.start_regions(&mut pass, &items);
            self.draw_casters(&mut pass, &items);
        }
    }

    /// Clears or copies the regions of `items` (indices into the frame's items), each
    /// pipeline set once.
    fn start_regions(&self, pass: &mut wgpu::RenderPass<'_>, items: &[usize]) {
        for copies in [false, true] {
            let mut set = false;
            for item in items.iter().map(|&i| &self.items[i]) {
                if (item.start == Start::CopyStatic) != copies {
                    continue;
                }
                if !set {
                    pass.set_pipeline(if copies { &self.copy } else { &self.clear });
                    if let Some(g) = self.copy_group.as_ref().filter(|_| copies) {
                        pass.set_bind_group(0, g, &[]);
                    }
                    set = true;
                }
                set_region(pass, item.rect);
                pass.draw(0..3, 0..1);
            }
        }
    }

    /// Draws the casters of `items` into their regions, after the regions started: the
    /// scene's streams, the caster group and each pipeline bound once per pass. Culled on the
    /// GPU, an item is two multi-draws (opaque, then masked casters, each of its run's part);
    /// listed, its casts one by one.
    fn draw_casters<'a>(&'a self, pass: &mut wgpu::RenderPass<'a>, items: &[usize]) {
        pass.set_bind_group(0, &self.caster_group, &[]);
        let mask_group = Some(self.scene.mask_group());
        let first_item = items.first().copied().unwrap_or(0);
        match &self.casts {
            CastSource::Culled {
                dispatches,
                args,
                opaque,
            } => {
                // Runs are numbered from the chunk's first item.
                let chunk_start = (dispatches.chunks.iter())
                    .find(|c| c.contains(&(first_item as u32)))
                    .map_or(0, |c| c.start as usize);
                let parts = [
                    ((&self.caster.opaque, None), 0, *opaque),
                    (
                        (&self.caster.masked, mask_group),
                        *opaque,
                        dispatches.stride - opaque,
                    ),
                ];
                for (k, (state, offset, slots)) in parts.into_iter().enumerate() {
                    if slots == 0 {
                        continue;
                    }
                    let mut draws =
                        SceneDraws::new(pass, &self.scene, &self.instances, VertexStreams::Mask);
                    for &i in items {
                        let item = &self.items[i];
                        set_region(draws.pass(), item.rect);
                        let run = (i - chunk_start) as u64;
                        let at = run * u64::from(dispatches.stride) + u64::from(offset);
                        if dispatches.compact {
                            let count_at = 4 * (1 + 2 * i as u64 + k as u64);
                            let count = (&dispatches.counts, count_at);
                            draws.multi_draw_count(state, args, at, count, slots);
                        } else {
                            draws.multi_draw(state.0, state.1, args, at, slots);
                        }
                    }
                }
            }
            CastSource::Listed { casts, runs } => {
                let mut draws =
                    SceneDraws::new(pass, &self.scene, &self.instances, VertexStreams::Mask);
                for &i in items {
                    set_region(draws.pass(), self.items[i].rect);
                    let (first, count) = runs[i];
                    let listed = &casts[first as usize..(first + count) as usize];
                    for (cast, c) in (first..).zip(listed) {
                        let Some(draw) = self.instances.draws.get(c.draw as usize) else {
                            continue;
                        };
                        let masked = (self.scene.materials.get(draw.material))
                            .is_some_and(|m| matches!(m.alpha_mode, AlphaMode::Mask { .. }));
                        let (pipeline, group) = if masked {
                            (&self.caster.masked, mask_group)
                        } else {
                            (&self.caster.opaque, None)
                        };
                        draws.draw(pipeline, group, draw.geometry, cast);
                    }
                }
            }
        }
    }
}

fn set_region(pass: &mut wgpu::RenderPass<'_>, rect: AtlasRect) {
    let (x, y, s) = (rect.x as f32, rect.y as f32, rect.side as f32);
    pass.set_viewport(x, y, s, s, 0.0, 1.0);
    pass.set_scissor_rect(rect.x, rect.y, rect.side, rect.side);
}

/// A depth-only render pass over `view` that keeps its contents.
fn depth_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}
