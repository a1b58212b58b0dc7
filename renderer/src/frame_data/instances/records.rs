//! The instance table's GPU side: the draw records buffer (the `view` library's `DRAWS`, group 1
//! of every geometry pass), written where instances change and grown by doubling on the GPU.

use std::ops::Range;

use shaders_gen::forward::forward;
use shaders_gen::shared::view;

use super::InstanceTable;
use crate::GpuContext;

impl InstanceTable {
    /// Group 1 (the draw records) of `program`, whose layout differs from the geometry passes'
    /// (a compute program's, visible to its compute stage).
    pub fn draw_group_for(
        &self,
        device: &wgpu::Device,
        program: &crate::shader::ShaderProgram,
    ) -> Result<wgpu::BindGroup, shader_bind::BindError> {
        let part = view::Group1 {
            draws: self.records.as_entire_buffer_binding(),
        };
        program.bind_group(
            device,
            view::Group1::GROUP,
            &shader_bind::Resources::of(&part),
            "draw records",
        )
    }

    /// Writes the records of `draws` where their instances are.
    pub(super) fn write_records(&self, gpu: &GpuContext, draws: Range<usize>) {
        if draws.is_empty() {
            return;
        }
        let records: Vec<forward::Draw> = self.draws[draws.clone()]
            .iter()
            .map(|d| d.uniform(self.states[d.instance].world_from_mesh))
            .collect();
        let at = (draws.start * size_of::<forward::Draw>()) as u64;
        gpu.queue()
            .write_buffer(&self.records, at, bytemuck::cast_slice(&records));
    }

    /// A records buffer of `capacity` records, the current ones copied over on the GPU.
    #[expect(
        clippy::expect_used,
        reason = "the table's first group bound a smaller buffer of the same usage on the same \
                  layout and variant, so a larger one binds too"
    )]
    pub(super) fn grow_records(&mut self, gpu: &GpuContext, capacity: usize) {
        let records = records_buffer(gpu.device(), capacity);
        if !self.draws.is_empty() {
            let bytes = (self.draws.len() * size_of::<forward::Draw>()) as u64;
            let mut encoder = gpu.device().create_command_encoder(&Default::default());
            encoder.copy_buffer_to_buffer(&self.records, 0, &records, 0, bytes);
            gpu.queue().submit([encoder.finish()]);
        }
        self.draw_group = draw_group(gpu.device(), &self.layout, &records)
            .expect("a larger records buffer binds where the first one did");
        self.records = records;
        self.capacity = capacity.max(1);
    }
}

pub(super) fn records_buffer(device: &wgpu::Device, capacity: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("draw records"),
        // A storage binding is never empty.
        size: (capacity.max(1) * size_of::<forward::Draw>()) as u64,
        usage: wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

/// Group 1 of the geometry programs on `layout` (the scene's, made from the forward variant):
/// the `view` library's `DRAWS`, numbered from that variant.
pub(super) fn draw_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    records: &wgpu::Buffer,
) -> Result<wgpu::BindGroup, shader_bind::BindError> {
    let part = view::Group1 {
        draws: records.as_entire_buffer_binding(),
    };
    shader_bind::Resources::of(&part).build(
        device,
        layout,
        super::super::material_groups::forward_variant(),
        view::Group1::GROUP,
        "draw records",
    )
}
