//! The bitonic sort of `(key, payload)` pairs on the GPU (`particle_sort`): a buffer of a
//! power of two of pairs, at least one block, sorted ascending by key then payload. Blended
//! particles (back to front) and the scene's blended draws (`scene_cull`) sort with it.

use crate::frame_data::InputError;
use std::sync::Arc;

use shaders_gen::particles::particle_sort::{self, SortParams};

use crate::GpuContext;
use crate::frame_data::RenderError;
use crate::graph::PassEncoder;
use crate::shader::ShaderProgram;

/// The sort's program and pipelines, shared by every sort built from them.
#[derive(Debug)]
pub struct SortKernels {
    program: ShaderProgram,
    /// `sort_local`, `merge_local`, `merge_global`.
    pipelines: [wgpu::ComputePipeline; 3],
}

impl SortKernels {
    pub fn new(gpu: &GpuContext) -> Result<Arc<Self>, RenderError> {
        let device = gpu.device();
        let variant = particle_sort::variant(particle_sort::VariantKey::ALL[0]);
        let program = gpu.program(variant)?;
        Ok(Arc::new(Self {
            pipelines: [
                program.compute_pipeline(device, "sort_local")?,
                program.compute_pipeline(device, "merge_local")?,
                program.compute_pipeline(device, "merge_global")?,
            ],
            program,
        }))
    }
}

/// One dispatch of the sort: its kernel, its parameters' bind group and its workgroups.
#[derive(Debug)]
struct Step {
    kernel: Kernel,
    bind_group: wgpu::BindGroup,
    groups: u32,
}

#[derive(Debug, Clone, Copy)]
enum Kernel {
    SortLocal,
    MergeLocal,
    MergeGlobal,
}

/// A sort of `keys` (a buffer of `count` `UVec2` pairs) in place.
#[derive(Debug)]
pub struct GpuSort {
    kernels: Arc<SortKernels>,
    steps: Vec<Step>,
    /// The pairs sorted: the buffer the sort was built for.
    pub keys: wgpu::Buffer,
    pub count: u32,
    _params: wgpu::Buffer,
}

/// Pairs a sort needs for `n` items: the next power of two, at least one block.
pub fn padded_count(n: u32) -> u32 {
    n.max(particle_sort::BLOCK).next_power_of_two()
}

/// The dispatches sorting `count` pairs: the block sort, then for each stage `k` its global
/// steps (`j` down to one block) and its local finish.
fn plan(count: u32) -> Vec<(Kernel, u32, u32)> {
    let block = particle_sort::BLOCK;
    let mut plan = vec![(Kernel::SortLocal, 0, 0)];
    let mut k = block * 2;
    while k <= count {
        let mut j = k / 2;
        while j >= block {
            plan.push((Kernel::MergeGlobal, k, j));
            j /= 2;
        }
        plan.push((Kernel::MergeLocal, k, 0));
        k *= 2;
    }
    plan
}

/// Every step's parameters in one uniform buffer, a step per aligned slot; and the slot size.
fn params_buffer(
    device: &wgpu::Device,
    plan: &[(Kernel, u32, u32)],
    count: u32,
) -> (wgpu::Buffer, u64) {
    let stride = u64::from(device.limits().min_uniform_buffer_offset_alignment).max(16);
    let mut bytes = vec![0u8; plan.len() * stride as usize];
    for (i, &(_, k, j)) in plan.iter().enumerate() {
        let p = SortParams::new(k, j, count, 0);
        let at = i * stride as usize;
        bytes[at..at + size_of::<SortParams>()].copy_from_slice(bytemuck::bytes_of(&p));
    }
    let buffer = wgpu::util::DeviceExt::create_buffer_init(
        device,
        &wgpu::util::BufferInitDescriptor {
            label: Some("sort steps"),
            contents: &bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        },
    );
    (buffer, stride)
}

impl GpuSort {
    /// The most items one sort takes on `device` (its dispatches' workgroup limit).
    pub fn max_items(device: &wgpu::Device) -> u32 {
        let groups = device.limits().max_compute_workgroups_per_dimension;
        let pairs = u64::from(groups) * u64::from(particle_sort::WORKGROUP) * 2;
        // The largest power of two within the limit.
        1u32 << pairs.min(1 << 31).ilog2()
    }

    /// A sort of `items` pairs, padded to [`padded_count`], in a new buffer with `extra_usage`
    /// besides storage and copies. Pad entries are for the caller to fill (`u32::MAX` keys
    /// sort last).
    pub fn new(
        gpu: &GpuContext,
        items: u32,
        extra_usage: wgpu::BufferUsages,
    ) -> Result<Self, RenderError> {
        let kernels = SortKernels::new(gpu)?;
        Self::with_kernels(gpu, &kernels, items, extra_usage)
    }

    /// [`GpuSort::new`] with kernels built before (shared by several sorts).
    pub fn with_kernels(
        gpu: &GpuContext,
        kernels: &Arc<SortKernels>,
        items: u32,
        extra_usage: wgpu::BufferUsages,
    ) -> Result<Self, RenderError> {
        let device = gpu.device();
        let max = Self::max_items(device);
        if items > max {
            return Err(RenderError::Input(InputError::SortTooLarge {
                asked: items,
                max,
            }));
        }
        let count = padded_count(items);
        let keys = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sort pairs"),
            size: u64::from(count) * 8,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_DST
                | wgpu::BufferUsages::COPY_SRC
                | extra_usage,
            mapped_at_creation: false,
        });
        let plan = plan(count);
        let (params, stride) = params_buffer(device, &plan, count);
        let program = &kernels.program;
        let steps = plan
            .iter()
            .enumerate()
            .map(|(i, &(kernel, _, _))| {
                let bind_group = particle_sort::Group0 {
                    params: wgpu::BufferBinding {
                        buffer: &params,
                        offset: i as u64 * stride,
                        size: wgpu::BufferSize::new(size_of::<SortParams>() as u64),
                    },
                    keys: keys.as_entire_buffer_binding(),
                }
                .bind_group(
                    device,
                    program.layout(particle_sort::Group0::GROUP),
                    program.variant,
                    "sort step",
                )?;
                Ok(Step {
                    kernel,
                    groups: match kernel {
                        Kernel::MergeGlobal => (count / 2).div_ceil(particle_sort::WORKGROUP),
                        Kernel::SortLocal | Kernel::MergeLocal => count / particle_sort::BLOCK,
                    },
                    bind_group,
                })
            })
            .collect::<Result<Vec<_>, RenderError>>()?;
        Ok(Self {
            kernels: Arc::clone(kernels),
            steps,
            keys,
            count,
            _params: params,
        })
    }

    /// Dispatches every step of the sort in `pass`.
    pub fn record(&self, pass: &mut wgpu::ComputePass<'_>) {
        for step in &self.steps {
            pass.set_pipeline(&self.kernels.pipelines[step.kernel as usize]);
            pass.set_bind_group(0, &step.bind_group, &[]);
            pass.dispatch_workgroups(step.groups, 1, 1);
        }
    }

    /// Dispatches in a compute pass of its own.
    pub fn record_in(&self, encoder: &mut PassEncoder<'_>) {
        let mut pass = encoder.begin_compute("sort");
        self.record(&mut pass);
    }
}
