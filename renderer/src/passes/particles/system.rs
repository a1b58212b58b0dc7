//! Everything the particle passes share for one particle system: the simulation, the atlas
//! layout, the sort, the `ParticleView` uniform, the lit atlas and the sprite textures. The
//! simulation pass builds it (and rebuilds it when the systems change) and hands it on through
//! [`crate::frame_data::ParticleResources`].

use std::sync::Arc;

use shaders_gen::particles::particle_draw::ParticleView;
use wgpu::util::DeviceExt as _;

use super::{GpuSort, ParticleAtlas, ParticleSimulation};
use crate::GpuContext;
use crate::frame_data::{FrameInputs, ListGeometry, ParticleInput, RenderError};
use crate::particles::ParticleError;
use crate::particles::sprites::{SPRITE_LAYERS, SPRITE_SIDE, sprite_levels, sprite_texels};

/// The lighting atlas's format: three small floats in 32 bits.
pub const ATLAS_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg11b10Ufloat;
/// The atlas side [`crate::frame_data::RendererConfig::particle_atlas_side`] 0 stands for
/// (raised when the capacity needs more).
pub const DEFAULT_ATLAS_SIDE: u32 = 2048;

/// One particle system's GPU state.
#[derive(Debug)]
pub struct ParticleGpu {
    /// The simulation: the main view's own; a further view's shares the main view's
    /// ([`ParticleGpu::with_simulation`]), which only the main view steps.
    pub sim: Arc<ParticleSimulation>,
    pub atlas: ParticleAtlas,
    pub sort: GpuSort,
    /// The `ParticleView` uniform.
    pub view: wgpu::Buffer,
    /// The lit atlas, `ATLAS_FORMAT`.
    pub lit_atlas: wgpu::Texture,
    /// The lighting kernel's output, the atlas's texels as rows (copied into `lit_atlas`).
    pub lit_texels: wgpu::Buffer,
    /// The sprite texture array (a layer per `ParticleTexture`).
    pub sprites: wgpu::TextureView,
    /// Trilinear, clamped: sprites and the atlas's bilinear taps.
    pub sampler: wgpu::Sampler,
    /// Which [`ParticleInput`] this was built for.
    pub generation: u64,
}

impl ParticleGpu {
    /// Builds the GPU state of `input` with an atlas of `side` texels (0: the default) and runs
    /// its warm-up steps.
    pub fn new(gpu: &GpuContext, input: &ParticleInput, side: u32) -> Result<Self, RenderError> {
        let sim = Arc::new(ParticleSimulation::new(gpu, (*input.system).clone())?);
        let system = Self::with_simulation(gpu, sim, input.generation, side)?;
        system.sim.advance(gpu, input.warmup_steps);
        Ok(system)
    }

    /// The layout, sort, view and lit atlas of a view of `sim` (another view's simulation,
    /// stepped there), built for particle input `generation`, with an atlas of `side` texels
    /// (0: the default).
    pub fn with_simulation(
        gpu: &GpuContext,
        sim: Arc<ParticleSimulation>,
        generation: u64,
        side: u32,
    ) -> Result<Self, RenderError> {
        let device = gpu.device();
        let capacity = sim.system().capacity;
        let max = GpuSort::max_items(device);
        if capacity > max {
            let asked = capacity;
            return Err(ParticleError::TooMany { asked, max }.into());
        }
        let sort = GpuSort::new(gpu, capacity, wgpu::BufferUsages::empty())?;
        let side = if side == 0 {
            ParticleAtlas::min_side(capacity).max(DEFAULT_ATLAS_SIDE)
        } else {
            side
        };
        let atlas = ParticleAtlas::new(gpu, &sim, &sort, side)?;
        let lit_atlas = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("particle lighting atlas"),
            size: wgpu::Extent3d {
                width: side,
                height: side,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: ATLAS_FORMAT,
            usage: wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_DST
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let lit_texels = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("particle lighting atlas texels"),
            size: u64::from(side) * u64::from(side) * 4,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let view = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("particle view"),
            size: size_of::<ParticleView>() as u64,
            // COPY_SRC: tools and tests read the view the particle kernels saw.
            usage: wgpu::BufferUsages::UNIFORM
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Ok(Self {
            sim,
            atlas,
            sort,
            view,
            lit_atlas,
            lit_texels,
            sprites: sprite_array(gpu),
            sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("particles"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                ..Default::default()
            }),
            generation,
        })
    }

    /// Writes the frame's `ParticleView`: the camera, the lights, and the geometry of the
    /// particle lists (`lists`; none on the naive paths).
    pub fn write_view(&self, frame: &FrameInputs, lists: Option<crate::culling::Method>) {
        let (c, camera) = (&frame.config, &frame.camera);
        let g = ListGeometry::new(lists, c, camera);
        let view = ParticleView::new(
            camera.view,
            camera.projection * camera.view,
            camera.projection.inverse(),
            camera.view.row(0).truncate().normalize(),
            self.atlas.side,
            camera.view.row(1).truncate().normalize(),
            frame.lights.punctual.len() as u32,
            camera.eye,
            frame.lights.directional.len() as u32,
            c.ambient.sky,
            g.tile,
            c.ambient.ground,
            g.tiles,
            frame.screen(),
            g.slices,
            g.near,
            g.far,
            c.soft_particle_distance,
            c.msaa,
            camera.eye_homogeneous(),
        );
        frame
            .gpu
            .queue()
            .write_buffer(&self.view, 0, bytemuck::bytes_of(&view));
    }
}

/// The built-in sprites as a texture array with its mip levels.
fn sprite_array(gpu: &GpuContext) -> wgpu::TextureView {
    let texture = gpu.device().create_texture_with_data(
        gpu.queue(),
        &wgpu::TextureDescriptor {
            label: Some("particle sprites"),
            size: wgpu::Extent3d {
                width: SPRITE_SIDE,
                height: SPRITE_SIDE,
                depth_or_array_layers: SPRITE_LAYERS,
            },
            mip_level_count: sprite_levels(),
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        &sprite_texels(),
    );
    texture.create_view(&wgpu::TextureViewDescriptor {
        dimension: Some(wgpu::TextureViewDimension::D2Array),
        ..Default::default()
    })
}
