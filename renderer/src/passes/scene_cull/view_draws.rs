//! A prepared scene's draws on the GPU for the main view: the batch layout, each slot's draw
//! and indirect arguments, and each draw's world box, kept across frames and updated only
//! where instances moved.

use std::sync::Arc;

use shaders_gen::culling::instance_cull::DrawBox;
use wgpu::util::DeviceExt as _;

use crate::GpuContext;
use crate::frame_data::{
    BatchLayout, FrameInputs, InstanceState, PreparedScene, mirroring_changed,
};
use crate::scene::Aabb;
use crate::shader::ShaderProgram;

#[derive(Debug)]
pub struct ViewDraws {
    pub scene: Arc<PreparedScene>,
    /// The instances the boxes and the layout follow.
    instances: Arc<Vec<InstanceState>>,
    pub layout: Arc<BatchLayout>,
    /// Every slot's arguments, instance count 1 (all drawn).
    all_drawn: Vec<u32>,
    /// Whether `args` holds `all_drawn` (no culling since it was written).
    args_all_drawn: bool,
    pub args: wgpu::Buffer,
    slot_draws: wgpu::Buffer,
    boxes: wgpu::Buffer,
    pub bind_group: wgpu::BindGroup,
    /// The diagonal of every draw's box together (the culling slack scales with it).
    pub extent: f32,
}

/// The world box of every draw of `scene` where `instances` put them.
fn world_boxes(scene: &PreparedScene, instances: &[InstanceState]) -> Vec<DrawBox> {
    scene
        .draws
        .iter()
        .map(|d| {
            let world = instances.get(d.instance).map_or(d.local_bounds, |i| {
                d.local_bounds.transformed(i.world_from_mesh)
            });
            draw_box(world)
        })
        .collect()
}

fn draw_box(b: Aabb) -> DrawBox {
    DrawBox::new(b.min.extend(0.0), b.max.extend(0.0))
}

/// Every slot's arguments with instance count 1.
fn arguments(scene: &PreparedScene, layout: &BatchLayout) -> Vec<u32> {
    layout
        .slot_draws
        .iter()
        .flat_map(|&d| {
            let g = scene.draws[d as usize].geometry;
            [g.index_count, 1, g.first_index, g.base_vertex as u32, d]
        })
        .collect()
}

/// A buffer of `words` (at least one word, so an empty scene still binds).
fn buffer(
    device: &wgpu::Device,
    label: &str,
    words: &[u32],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let padded: &[u32] = if words.is_empty() { &[0; 5] } else { words };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(padded),
        usage: usage | wgpu::BufferUsages::COPY_DST,
    })
}

impl ViewDraws {
    /// The draws of `frame`'s scene where its instances are, every slot drawn.
    pub fn new(gpu: &GpuContext, shared: &CullShared, frame: &FrameInputs) -> Self {
        let device = &gpu.device;
        let scene = Arc::clone(&frame.scene);
        let layout = BatchLayout::new(&scene, &frame.instances);
        let boxes = world_boxes(&scene, &frame.instances);
        let extent = boxes.iter().fold(Aabb::EMPTY, |b, d| {
            b.with_point(d.min.truncate()).with_point(d.max.truncate())
        });
        let extent = if extent.is_empty() {
            0.0
        } else {
            (extent.max - extent.min).length()
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let all_drawn = arguments(&scene, &layout);
        let args = buffer(
            device,
            "scene draw args",
            &all_drawn,
            storage | wgpu::BufferUsages::INDIRECT,
        );
        let slot_draws = buffer(device, "scene slot draws", &layout.slot_draws, storage);
        let box_words: &[u32] = bytemuck::cast_slice(&boxes);
        let boxes = buffer(device, "scene draw boxes", box_words, storage);
        let bind_group = bind_group(device, shared, [&slot_draws, &args, &boxes]);
        Self {
            scene,
            instances: Arc::clone(&frame.instances),
            layout: Arc::new(layout),
            all_drawn,
            args_all_drawn: true,
            args,
            slot_draws,
            boxes,
            bind_group,
            extent,
        }
    }

    /// Follows moved instances: rewrites the boxes of their draws, and rebuilds the layout
    /// (slots and arguments) when one's mirroring changed.
    pub fn follow_instances(
        &mut self,
        gpu: &GpuContext,
        shared: &CullShared,
        instances: &Arc<Vec<InstanceState>>,
    ) {
        if Arc::ptr_eq(&self.instances, instances) {
            return;
        }
        let (before, after) = (&self.instances, instances);
        if mirroring_changed(before, after) {
            let layout = BatchLayout::new(&self.scene, after);
            let storage = wgpu::BufferUsages::STORAGE;
            self.all_drawn = arguments(&self.scene, &layout);
            let usage = storage | wgpu::BufferUsages::INDIRECT;
            self.args = buffer(&gpu.device, "scene draw args", &self.all_drawn, usage);
            self.slot_draws = buffer(&gpu.device, "scene slot draws", &layout.slot_draws, storage);
            self.layout = Arc::new(layout);
            self.args_all_drawn = true;
            let buffers = [&self.slot_draws, &self.args, &self.boxes];
            self.bind_group = bind_group(&gpu.device, shared, buffers);
        }
        for (index, state) in after.iter().enumerate() {
            if before
                .get(index)
                .is_some_and(|b| b.version == state.version)
            {
                continue;
            }
            let range = self.scene.draws_of_instance(index);
            let boxes: Vec<DrawBox> = self.scene.draws[range.clone()]
                .iter()
                .map(|d| draw_box(d.local_bounds.transformed(state.world_from_mesh)))
                .collect();
            let at = range.start as u64 * size_of::<DrawBox>() as u64;
            if !boxes.is_empty() {
                gpu.queue
                    .write_buffer(&self.boxes, at, bytemuck::cast_slice(&boxes));
            }
        }
        self.instances = Arc::clone(instances);
    }

    /// Makes every slot draw (culling is off this frame), writing the arguments only if a
    /// culled frame changed them.
    pub fn draw_every_slot(&mut self, queue: &wgpu::Queue) {
        if !self.args_all_drawn && !self.all_drawn.is_empty() {
            queue.write_buffer(&self.args, 0, bytemuck::cast_slice(&self.all_drawn));
        }
        self.args_all_drawn = true;
    }

    /// Notes that the dispatch will rewrite the arguments' instance counts this frame.
    pub fn culled(&mut self) {
        self.args_all_drawn = false;
    }
}

/// What every scene's culling binds besides its own buffers: the program, the frustum
/// parameters and the visible counter (the pass's).
#[derive(Debug)]
pub struct CullShared {
    pub program: ShaderProgram,
    pub params: wgpu::Buffer,
    pub visible: wgpu::Buffer,
}

/// Group 0 of `instance_cull`: parameters, boxes, slot draws, arguments, visible counter.
fn bind_group(
    device: &wgpu::Device,
    shared: &CullShared,
    [slot_draws, args, boxes]: [&wgpu::Buffer; 3],
) -> wgpu::BindGroup {
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("scene culling"),
        layout: &shared.program.bind_group_layouts[0],
        entries: &crate::passes::entries(&[
            shared.params.as_entire_binding(),
            boxes.as_entire_binding(),
            slot_draws.as_entire_binding(),
            args.as_entire_binding(),
            shared.visible.as_entire_binding(),
        ]),
    })
}
