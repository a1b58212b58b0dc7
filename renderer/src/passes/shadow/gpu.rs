//! The shadow pass's GPU objects: the shadow atlas and its static cache (both
//! [`SHADOW_FORMAT`], reversed Z), the caster, clear and copy pipelines, and the view
//! buffers (the recording is `record`'s).

use shaders_gen::shadow::{shadow_caster, shadow_compose};

use super::super::{MASK_STREAMS, MeshPipeline, mesh_pipeline};
use crate::frame_data::RenderError;
use crate::shader::ShaderProgram;

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
        let device = gpu.device();
        let caster_variant =
            |alpha_mask| shadow_caster::variant(shadow_caster::VariantKey { alpha_mask });
        let caster_program = gpu.program(caster_variant(false))?;
        let masked_program = gpu.program(caster_variant(true))?;
        let compose_program = gpu.program(&shadow_compose::VARIANTS[0])?;
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
                    depth: Some(depth.clone()),
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
        let clear = region_pipeline(device, &compose_program, &empty, None);
        let copy = region_pipeline(
            device,
            &compose_program,
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

/// A pipeline of `program` under `layout` covering the viewport with `vs_region` at depth 0, writing depth always: a
/// clear without a fragment stage, a copy with `fs_copy_static`.
fn region_pipeline(
    device: &wgpu::Device,
    program: &ShaderProgram,
    layout: &wgpu::PipelineLayout,
    fragment: Option<&str>,
) -> wgpu::RenderPipeline {
    let module = &program.module;
    program.render_pipeline(
        device,
        &wgpu::RenderPipelineDescriptor {
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
        },
    )
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
    ) -> Result<Self, RenderError> {
        let atlas = atlas_texture(device, "shadow atlas", size);
        let static_atlas = cached.then(|| {
            atlas_texture(device, "shadow static cache", size).create_view(&Default::default())
        });
        let capacity = capacity.max(1);
        let (views, caster_views) = view_buffers(device, capacity);
        let compose = &pipelines.compose_program;
        let copy_group = static_atlas
            .as_ref()
            .map(|view| {
                shadow_compose::Group0 { static_atlas: view }.bind_group(
                    device,
                    compose.layout(shadow_compose::Group0::GROUP),
                    compose.variant,
                    "shadow static cache",
                )
            })
            .transpose()?;
        Ok(Self {
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
        })
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
    ) -> Result<wgpu::BindGroup, RenderError> {
        let program = &self.caster_program;
        let group = shadow_caster::Group0 {
            views: caster_views.as_entire_buffer_binding(),
            casts: casts.as_entire_buffer_binding(),
        }
        .bind_group(
            device,
            program.layout(shadow_caster::Group0::GROUP),
            program.variant,
            "shadow caster views and casts",
        )?;
        Ok(group)
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
