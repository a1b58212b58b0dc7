//! The main view's blended draws back to front on the GPU, for one multi-draw: every frame
//! `blended_keys` keys each blended draw by its box centre's farness (hidden outside the
//! frustum), the bitonic sort (`passes::gpu_sort`) orders the keys, and `blended_args` writes
//! the draws' indirect arguments in that order. The CPU uploads the frame's frustum and eye and
//! nothing per draw; the templates are written again only when the blended draws change.

use crate::frame_data::InputError;
use std::sync::Arc;

use shaders_gen::culling::blended_order::{self, BlendedParams};
use shaders_gen::culling::instance_cull::Frustum;

use crate::GpuContext;
use crate::frame_data::{FrameCamera, InstanceTable, RenderError};
use crate::passes::gpu_sort::{GpuSort, SortKernels};
use crate::shader::ShaderProgram;

/// The ordering kernels, their parameters and the sort kernels, shared by every scene.
#[derive(Debug)]
pub struct BlendedKernels {
    program: ShaderProgram,
    keys: wgpu::ComputePipeline,
    args: wgpu::ComputePipeline,
    params: wgpu::Buffer,
    sort: Arc<SortKernels>,
}

impl BlendedKernels {
    pub fn new(gpu: &GpuContext) -> Result<Self, RenderError> {
        let device = gpu.device();
        let variant = blended_order::variant(blended_order::VariantKey::ALL[0]);
        let program = gpu.program(variant)?;
        Ok(Self {
            keys: program.compute_pipeline(device, "blended_keys")?,
            args: program.compute_pipeline(device, "blended_args")?,
            params: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("blended order params"),
                size: size_of::<BlendedParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            sort: SortKernels::new(gpu)?,
            program,
        })
    }
}

/// One scene's blended draws on the GPU: their argument templates, the sort of their keys and
/// the ordered arguments the forward pass draws.
#[derive(Debug)]
pub struct BlendedOrder {
    /// The blended draws the templates hold, ascending (the batch layout's list).
    pub draws: Vec<u32>,
    templates: wgpu::Buffer,
    sort: Arc<GpuSort>,
    /// `draws.len()` arguments of five words, back to front, hidden draws with no instance.
    pub args: wgpu::Buffer,
    /// `count`, for drawing with a count buffer.
    pub count_buffer: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

impl BlendedOrder {
    /// The order of `draws` (the blended draws of `table`, ascending, at least one) whose
    /// world boxes `boxes` holds.
    pub fn new(
        gpu: &GpuContext,
        kernels: &BlendedKernels,
        table: &InstanceTable,
        draws: &[u32],
        boxes: &wgpu::Buffer,
    ) -> Result<Self, RenderError> {
        let count = draws.len() as u32;
        let max = GpuSort::max_items(gpu.device());
        if count > max {
            return Err(RenderError::Input(InputError::TooManyBlendedDraws {
                count,
                max,
            }));
        }
        let usage = wgpu::BufferUsages::empty();
        let sort = GpuSort::with_kernels(gpu, &kernels.sort, count, usage)?;
        let words: Vec<u32> = draws
            .iter()
            .flat_map(|&d| table.draws[d as usize].geometry.indirect_args(d))
            .collect();
        let device = gpu.device();
        let templates = wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("blended draw templates"),
                contents: bytemuck::cast_slice(&words),
                usage: wgpu::BufferUsages::STORAGE,
            },
        );
        let args = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("blended draw args"),
            size: (words.len() * 4) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT,
            mapped_at_creation: false,
        });
        let bind_group = bind_group(device, kernels, boxes, &templates, &sort.keys, &args)?;
        let count_buffer = wgpu::util::DeviceExt::create_buffer_init(
            device,
            &wgpu::util::BufferInitDescriptor {
                label: Some("blended draw count"),
                contents: bytemuck::bytes_of(&count),
                usage: wgpu::BufferUsages::INDIRECT,
            },
        );
        Ok(Self {
            count_buffer,
            draws: draws.to_vec(),
            templates,
            sort: Arc::new(sort),
            args,
            bind_group,
        })
    }

    /// Binds `boxes` again (the box buffer grew).
    pub fn rebind(
        &mut self,
        device: &wgpu::Device,
        kernels: &BlendedKernels,
        boxes: &wgpu::Buffer,
    ) -> Result<(), shader_bind::BindError> {
        self.bind_group = bind_group(
            device,
            kernels,
            boxes,
            &self.templates,
            &self.sort.keys,
            &self.args,
        )?;
        Ok(())
    }

    /// The blended draws, hence the arguments the forward pass draws.
    pub fn count(&self) -> u32 {
        self.draws.len() as u32
    }

    /// Writes this frame's parameters: `camera`'s frustum and eye; with `cull`, draws outside
    /// the frustum are hidden.
    pub fn prepare(
        &self,
        queue: &wgpu::Queue,
        kernels: &BlendedKernels,
        camera: &FrameCamera,
        cull: bool,
    ) {
        let [left, right, bottom, top, near, far] = camera.frustum_planes();
        let params = BlendedParams::new(
            Frustum::new(left, right, bottom, top, near, far),
            camera.eye_homogeneous(),
            self.count(),
            self.sort.count,
            u32::from(cull),
            0,
        );
        queue.write_buffer(&kernels.params, 0, bytemuck::bytes_of(&params));
    }

    /// What records the keys, their sort and the ordered arguments into a compute pass.
    pub fn recorder(
        &self,
        kernels: &Arc<BlendedKernels>,
    ) -> impl FnOnce(&mut wgpu::ComputePass<'_>) + 'static {
        let (kernels, sort) = (Arc::clone(kernels), Arc::clone(&self.sort));
        let group = self.bind_group.clone();
        let count = self.count();
        move |pass| {
            let groups = |n: u32| n.div_ceil(blended_order::WORKGROUP);
            pass.set_pipeline(&kernels.keys);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(groups(sort.count), 1, 1);
            sort.record(pass);
            pass.set_pipeline(&kernels.args);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(groups(count), 1, 1);
        }
    }
}

/// Group 0 of `blended_order`, through the module's generated builder.
fn bind_group(
    device: &wgpu::Device,
    kernels: &BlendedKernels,
    boxes: &wgpu::Buffer,
    templates: &wgpu::Buffer,
    keys: &wgpu::Buffer,
    args: &wgpu::Buffer,
) -> Result<wgpu::BindGroup, shader_bind::BindError> {
    blended_order::Group0 {
        params: kernels.params.as_entire_buffer_binding(),
        boxes: boxes.as_entire_buffer_binding(),
        templates: templates.as_entire_buffer_binding(),
        keys: keys.as_entire_buffer_binding(),
        args: args.as_entire_buffer_binding(),
    }
    .bind_group(
        device,
        kernels.program.layout(0),
        kernels.program.variant,
        "blended order",
    )
}
