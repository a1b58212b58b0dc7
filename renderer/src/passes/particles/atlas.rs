//! The particle lighting atlas's layout on the GPU (`particle_atlas`): each visible particle's
//! square region, sized from its projected size and allocated in the same frame, shrunk
//! together when they do not all fit, and reported.

use shaders_gen::particles::particle_atlas::{self, AtlasParams};

use super::{GpuSort, ParticleSimulation};
use crate::GpuContext;
use crate::frame_data::FrameCamera;
use crate::frame_data::RenderError;
use crate::graph::PassEncoder;
use crate::particles::ParticleError;

/// Words of the `STATE` buffer (see `particle_atlas`).
pub const STATE_WORDS: usize = 32;
/// Byte offset of the draw's indirect arguments in `STATE`.
pub const DRAW_ARGS_OFFSET: u64 = 24 * 4;
/// Byte offset of the lighting dispatch's indirect arguments in `STATE`.
pub const DISPATCH_ARGS_OFFSET: u64 = 28 * 4;

/// What one frame's atlas layout came to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AtlasReport {
    /// Visible particles per side class (sides 2, 4, 8, 16, 32), before any shrink.
    pub per_class: [u32; 5],
    /// Classes every region was shrunk by so that all fit (0: none).
    pub shrink: u32,
    /// 2×2-texel cells used.
    pub cells_used: u32,
    pub visible: u32,
    /// Frames so far that had to shrink.
    pub shrunk_frames: u32,
}

impl AtlasReport {
    /// The report in `STATE`'s words (at least [`STATE_WORDS`]).
    pub fn from_words(s: &[u32]) -> Self {
        Self {
            per_class: [s[0], s[1], s[2], s[3], s[4]],
            shrink: s[15],
            cells_used: s[16],
            visible: s[17],
            shrunk_frames: s[18],
        }
    }
}

/// Sizing, planning and allocation of the particle lighting atlas.
#[derive(Debug)]
pub struct ParticleAtlas {
    /// Atlas side, texels.
    pub side: u32,
    size: wgpu::ComputePipeline,
    plan: wgpu::ComputePipeline,
    allocate: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    /// Per slot: `x | y << 12 | class << 24` (texels; side `2 << class`), or `HIDDEN`.
    pub regions: wgpu::Buffer,
    /// The kernels' counters and plan (see `particle_atlas`).
    pub state: wgpu::Buffer,
    /// Region owners, class by class (see `particle_atlas`).
    pub owners: wgpu::Buffer,
    key_count: u32,
    capacity: u32,
}

impl ParticleAtlas {
    /// The smallest atlas side that holds `capacity` particles at 2×2 texels each.
    pub fn min_side(capacity: u32) -> u32 {
        let cells_across = (f64::from(capacity).sqrt().ceil() as u32).next_power_of_two();
        (cells_across * 2).max(64)
    }

    /// An atlas of `side` texels (a power of two, at least [`Self::min_side`]) for `sim`'s
    /// particles, writing sort keys into `sort`.
    pub fn new(
        gpu: &GpuContext,
        sim: &ParticleSimulation,
        sort: &GpuSort,
        side: u32,
    ) -> Result<Self, RenderError> {
        let device = gpu.device();
        let capacity = sim.system().capacity;
        let (min, max) = (
            Self::min_side(capacity),
            device.limits().max_texture_dimension_2d,
        );
        // Region corners pack 12 bits a coordinate.
        let max = max.min(4096);
        if !side.is_power_of_two() || side < min || side > max {
            return Err(ParticleError::AtlasSize {
                asked: side,
                min,
                max,
            }
            .into());
        }
        let variant = particle_atlas::variant(particle_atlas::VariantKey::ALL[0]);
        let program = gpu.program(variant)?;
        let storage = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC;
        let new_buffer = |label, size| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: storage,
                mapped_at_creation: false,
            })
        };
        let regions = new_buffer("particle regions", u64::from(capacity) * 4);
        // The state ends with the draw's and the lighting's indirect arguments.
        let state = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("particle atlas state"),
            size: STATE_WORDS as u64 * 4,
            usage: storage | wgpu::BufferUsages::INDIRECT,
            mapped_at_creation: false,
        });
        let owners = new_buffer("particle region owners", u64::from(capacity) * 4);
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("particle atlas"),
            size: size_of::<AtlasParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let bind_group = particle_atlas::Group0 {
            params: params.as_entire_buffer_binding(),
            emitters: sim.emitters.as_entire_buffer_binding(),
            particles: sim.particles.as_entire_buffer_binding(),
            alive: sim.alive.as_entire_buffer_binding(),
            counters: sim.counters.as_entire_buffer_binding(),
            keys: sort.keys.as_entire_buffer_binding(),
            regions: regions.as_entire_buffer_binding(),
            state: state.as_entire_buffer_binding(),
            owners: owners.as_entire_buffer_binding(),
        }
        .bind_group(
            device,
            program.layout(particle_atlas::Group0::GROUP),
            program.variant,
            "particle atlas",
        )?;
        Ok(Self {
            side,
            size: program.compute_pipeline(device, "size_particles")?,
            plan: program.compute_pipeline(device, "plan_atlas")?,
            allocate: program.compute_pipeline(device, "allocate_regions")?,
            bind_group,
            params,
            regions,
            state,
            owners,
            key_count: sort.count,
            capacity,
        })
    }

    /// Records sizing, planning and allocation for `camera` on a target `height` pixels high,
    /// after the simulation's step. Keeps the count of frames that shrank; clears the rest.
    #[cfg(any(test, feature = "internals"))]
    pub fn record(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        camera: &FrameCamera,
        height: u32,
    ) {
        self.write_params(queue, camera, height);
        self.encode(&mut PassEncoder::untimed(encoder));
    }

    /// Writes the frame's layout parameters for [`Self::encode`].
    pub fn write_params(&self, queue: &wgpu::Queue, camera: &FrameCamera, height: u32) {
        let params = AtlasParams::new(
            camera.view,
            camera.projection.y_axis.y * height as f32 * 0.5,
            camera.near,
            self.side / 2,
            self.key_count,
            u32::from(camera.orthographic),
        );
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
    }

    /// Records sizing, planning and allocation with the parameters last written.
    pub fn encode(&self, encoder: &mut PassEncoder<'_>) {
        // The counters and plan, not the shrunk-frames count (word 18) nor the owner bases
        // after it, which every plan writes.
        encoder.clear_buffer(&self.state, 0, Some(18 * 4));
        let groups = |threads: u32| threads.div_ceil(particle_atlas::WORKGROUP);
        let mut pass = encoder.begin_compute("particle atlas layout");
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_pipeline(&self.size);
        pass.dispatch_workgroups(groups(self.key_count), 1, 1);
        pass.set_pipeline(&self.plan);
        pass.dispatch_workgroups(1, 1, 1);
        pass.set_pipeline(&self.allocate);
        pass.dispatch_workgroups(groups(self.capacity), 1, 1);
    }

    /// Reads the layout's report back (blocking; for tools and tests).
    #[cfg(any(test, feature = "internals"))]
    pub fn read_report(&self, gpu: &GpuContext) -> Result<AtlasReport, RenderError> {
        let s: Vec<u32> = crate::readback::read_buffer(gpu.device(), gpu.queue(), &self.state)?;
        Ok(AtlasReport::from_words(&s))
    }
}
