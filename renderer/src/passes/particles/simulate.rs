//! A particle system on the GPU: the pool of slots, the dead and live lists, and one fixed step
//! of `particle_sim` (update, spawn, compact) recorded at a time.

use shaders_gen::particles::particle_sim::{self, GpuParticle, SimParams, SpawnBatch};
use wgpu::util::DeviceExt as _;

use crate::GpuContext;
use crate::frame_data::RenderError;
use crate::gpu::requirements::storage_binding_records;
use crate::graph::PassEncoder;
use crate::particles::ParticleSystem;
use crate::particles::schedule::{FIXED_STEP, spawn_batches};

/// What the counters say after a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg(any(test, feature = "internals"))]
pub struct SimCounters {
    /// Free slots.
    pub dead: u32,
    /// Live particles (the live list's length).
    pub alive: u32,
    /// Births refused since the start because the pool was full.
    pub starved: u32,
}

/// A simulated particle system: its buffers and pipelines.
#[derive(Debug)]
pub struct ParticleSimulation {
    system: ParticleSystem,
    /// Steps recorded so far (the spawn schedule's clock).
    steps: std::sync::atomic::AtomicU64,
    update: wgpu::ComputePipeline,
    spawn: wgpu::ComputePipeline,
    compact: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    batches: wgpu::Buffer,
    /// `GpuEmitter` per emitter (one zeroed record when there are none).
    pub emitters: wgpu::Buffer,
    /// `GpuParticle` per slot.
    pub particles: wgpu::Buffer,
    /// Counters (`i32`): dead-list length, live-list length, refused births.
    pub counters: wgpu::Buffer,
    /// The live slots after `compact`, first `alive` entries.
    pub alive: wgpu::Buffer,
}

const STORAGE: wgpu::BufferUsages = wgpu::BufferUsages::STORAGE
    .union(wgpu::BufferUsages::COPY_DST)
    .union(wgpu::BufferUsages::COPY_SRC);

fn buffer(
    device: &wgpu::Device,
    label: &str,
    contents: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents,
        usage,
    })
}

impl ParticleSimulation {
    /// The most slots a pool may have on `device`: what one storage binding of particles holds,
    /// and what one dispatch of a thread per slot reaches.
    pub fn max_capacity(device: &wgpu::Device) -> u32 {
        let records = storage_binding_records(device, size_of::<GpuParticle>());
        let threads = u64::from(device.limits().max_compute_workgroups_per_dimension)
            * u64::from(particle_sim::WORKGROUP);
        records.min(threads).min(u64::from(u32::MAX)) as u32
    }

    /// Validates `system` and uploads an empty pool (every slot on the dead list).
    pub fn new(gpu: &GpuContext, system: ParticleSystem) -> Result<Self, RenderError> {
        let device = gpu.device();
        system.validate(Self::max_capacity(device))?;
        let variant = particle_sim::variant(particle_sim::VariantKey::ALL[0]);
        let program = gpu.program(variant)?;
        let capacity = system.capacity;
        let emitters: Vec<_> = system.emitters.iter().map(|e| e.gpu()).collect();
        let emitters = if emitters.is_empty() {
            vec![bytemuck::Zeroable::zeroed()]
        } else {
            emitters
        };
        // Every slot free: the dead list holds them all, the last slot on top.
        let dead: Vec<u32> = (0..capacity).rev().collect();
        let counters = [capacity as i32, 0, 0, 0];
        let particles = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("particles"),
            size: u64::from(capacity) * size_of::<GpuParticle>() as u64,
            usage: STORAGE,
            mapped_at_creation: false,
        });
        let alive = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("live particles"),
            size: u64::from(capacity) * 4,
            usage: STORAGE,
            mapped_at_creation: false,
        });
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("particle step"),
            size: size_of::<SimParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let batch_slots = system.emitters.len().max(1);
        let batches = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("particle births"),
            size: (batch_slots * size_of::<SpawnBatch>()) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let emitters = buffer(device, "emitters", bytemuck::cast_slice(&emitters), STORAGE);
        let dead = buffer(
            device,
            "dead particles",
            bytemuck::cast_slice(&dead),
            STORAGE,
        );
        let counters = buffer(
            device,
            "particle counters",
            bytemuck::cast_slice(&counters),
            STORAGE,
        );
        let bind_group = particle_sim::Group0 {
            params: params.as_entire_buffer_binding(),
            emitters: emitters.as_entire_buffer_binding(),
            batches: batches.as_entire_buffer_binding(),
            particles: particles.as_entire_buffer_binding(),
            dead: dead.as_entire_buffer_binding(),
            counters: counters.as_entire_buffer_binding(),
            alive: alive.as_entire_buffer_binding(),
        }
        .bind_group(
            device,
            program.layout(particle_sim::Group0::GROUP),
            program.variant,
            "particle simulation",
        )?;
        Ok(Self {
            update: program.compute_pipeline(device, "update")?,
            spawn: program.compute_pipeline(device, "spawn")?,
            compact: program.compute_pipeline(device, "compact")?,
            system,
            steps: std::sync::atomic::AtomicU64::new(0),
            bind_group,
            params,
            batches,
            emitters,
            particles,
            counters,
            alive,
        })
    }

    /// The system simulated.
    pub fn system(&self) -> &ParticleSystem {
        &self.system
    }

    /// Records the next fixed step into `encoder`, then rebuilds the live list. Its parameters
    /// go through `queue.write_buffer`, so record at most one step per submission.
    pub fn record_step(&self, queue: &wgpu::Queue, encoder: &mut PassEncoder<'_>) {
        let births = self.write_step(queue);
        self.encode_step(encoder, births);
    }

    /// Writes the next fixed step's parameters and births, and advances the step clock;
    /// returns the step's births for [`Self::encode_step`].
    pub fn write_step(&self, queue: &wgpu::Queue) -> u32 {
        use std::sync::atomic::Ordering;
        let step = self.steps.fetch_add(1, Ordering::Relaxed);
        let batches = spawn_batches(&self.system.emitters, step);
        let spawn_total: u32 = batches.iter().map(|b| b.count).sum();
        let params = SimParams::new(
            self.system.capacity,
            spawn_total,
            batches.len() as u32,
            self.system.seed,
            FIXED_STEP,
            0,
            0,
            0,
        );
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        if !batches.is_empty() {
            queue.write_buffer(&self.batches, 0, bytemuck::cast_slice(&batches));
        }
        spawn_total
    }

    /// Records the step [`Self::write_step`] prepared (`spawn_total` births): update and
    /// spawn, then the live list.
    pub fn encode_step(&self, encoder: &mut PassEncoder<'_>, spawn_total: u32) {
        let capacity = self.system.capacity;
        let groups = |threads: u32| threads.div_ceil(particle_sim::WORKGROUP);
        {
            let mut pass = encoder.begin_compute("particle update and spawn");
            pass.set_bind_group(0, &self.bind_group, &[]);
            pass.set_pipeline(&self.update);
            pass.dispatch_workgroups(groups(capacity), 1, 1);
            if spawn_total > 0 {
                pass.set_pipeline(&self.spawn);
                pass.dispatch_workgroups(groups(spawn_total), 1, 1);
            }
        }
        encoder.clear_buffer(&self.counters, 4, Some(4));
        let mut pass = encoder.begin_compute("particle compact");
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_pipeline(&self.compact);
        pass.dispatch_workgroups(groups(capacity), 1, 1);
    }

    /// Records and submits `steps` steps, one submission each.
    pub fn advance(&self, gpu: &GpuContext, steps: u32) {
        for _ in 0..steps {
            let mut encoder =
                gpu.device()
                    .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                        label: Some("particle steps"),
                    });
            self.record_step(gpu.queue(), &mut PassEncoder::untimed(&mut encoder));
            gpu.queue().submit([encoder.finish()]);
        }
    }

    /// Reads the counters back (blocking; for tools and tests).
    #[cfg(any(test, feature = "internals"))]
    pub fn read_counters(&self, gpu: &GpuContext) -> Result<SimCounters, RenderError> {
        let c: Vec<i32> = crate::readback::read_buffer(gpu.device(), gpu.queue(), &self.counters)?;
        Ok(SimCounters {
            dead: c[0].max(0) as u32,
            alive: c[1].max(0) as u32,
            starved: c[2].max(0) as u32,
        })
    }

    /// Reads every slot back (blocking; for tools and tests).
    #[cfg(any(test, feature = "internals"))]
    pub fn read_slots(&self, gpu: &GpuContext) -> Result<Vec<GpuParticle>, RenderError> {
        Ok(crate::readback::read_buffer(
            gpu.device(),
            gpu.queue(),
            &self.particles,
        )?)
    }

    /// Reads every live particle back (blocking; for tools and tests), in slot order.
    #[cfg(any(test, feature = "internals"))]
    pub fn read_alive(&self, gpu: &GpuContext) -> Result<Vec<GpuParticle>, RenderError> {
        let all = self.read_slots(gpu)?;
        Ok(all.into_iter().filter(|p| p.alive != 0).collect())
    }
}
