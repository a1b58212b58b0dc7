//! A prepared scene's draws on the GPU for the main view: the batch layout, each slot's draw
//! and indirect arguments, and each draw's world box, kept across frames and updated only
//! where instances moved.

use std::sync::Arc;

use shaders_gen::culling::instance_cull::{self, DrawBox};

use super::blended::{BlendedKernels, BlendedOrder};
use crate::GpuContext;
use crate::frame_data::{
    BatchLayout, FrameCamera, FrameInputs, InstanceTable, NO_DRAW, PreparedScene, RenderError,
    box_in_frustum, draw_place, farness,
};
use crate::scene::Aabb;
use crate::shader::ShaderProgram;

#[derive(Debug)]
pub struct ViewDraws {
    pub scene: Arc<PreparedScene>,
    /// The instance table (its id) and its revision the boxes and the layout follow, and the
    /// scene's placement revision they were placed at.
    table: u32,
    placement: u64,
    revision: u64,
    pub layout: Arc<BatchLayout>,
    /// Every slot's arguments, instance count 1 (all drawn; spare slots draw nothing).
    all_drawn: Vec<u32>,
    /// Whether `args` holds `all_drawn` (no culling since it was written).
    args_all_drawn: bool,
    pub args: wgpu::Buffer,
    pub occlusion: OcclusionBuffers,
    pub slot_draws: wgpu::Buffer,
    /// Every draw's world box (empty for a removed instance's), and its GPU copy with room
    /// for `box_capacity` boxes.
    boxes: Vec<DrawBox>,
    pub box_buffer: wgpu::Buffer,
    box_capacity: usize,
    pub bind_group: wgpu::BindGroup,
    /// Every box together (the culling slack scales with its diagonal).
    bounds: Aabb,
    /// The blended draws' order on the GPU (none without blended draws).
    pub blended: Option<BlendedOrder>,
}

/// The box of draw `d` where `table` puts it (a removed instance's is empty and never drawn:
/// it holds no slot).
fn draw_box(table: &InstanceTable, d: usize) -> DrawBox {
    let b = table.draws[d].world_bounds(&table.states);
    DrawBox::new(b.min.extend(0.0), b.max.extend(0.0))
}

/// Slot `slot`'s arguments with instance count 1 (all zero for an empty slot).
fn slot_arguments(table: &InstanceTable, layout: &BatchLayout, slot: usize) -> [u32; 5] {
    match layout.slot_draws[slot] {
        NO_DRAW => [0; 5],
        d => table.draws[d as usize].geometry.indirect_args(d),
    }
}

/// A storage buffer of `bytes` (at least 4).
fn buffer(
    device: &wgpu::Device,
    label: &str,
    bytes: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(4),
        usage: usage | wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// A batch layout built afresh, with its slots and arguments on the GPU.
struct LaidOut {
    layout: Arc<BatchLayout>,
    all_drawn: Vec<u32>,
    args: wgpu::Buffer,
    occlusion: OcclusionBuffers,
    slot_draws: wgpu::Buffer,
}

/// What occlusion culling keeps per slot: the second phase's arguments, the arguments of
/// every slot drawn in either phase, and whether each slot was visible last frame (all zero
/// for a new layout: its first frame draws everything in the second phase).
#[derive(Debug, Clone)]
pub struct OcclusionBuffers {
    pub late: wgpu::Buffer,
    pub all: wgpu::Buffer,
    pub history: wgpu::Buffer,
}

impl LaidOut {
    fn new(gpu: &GpuContext, scene: &PreparedScene, table: &InstanceTable) -> Self {
        let layout = BatchLayout::new(scene, table);
        let all_drawn: Vec<u32> = (0..layout.slot_draws.len())
            .flat_map(|slot| slot_arguments(table, &layout, slot))
            .collect();
        let bytes = |words: usize| (words * 4) as u64;
        let indirect = wgpu::BufferUsages::INDIRECT;
        let args = buffer(
            gpu.device(),
            "scene draw args",
            bytes(all_drawn.len()),
            indirect,
        );
        gpu.queue()
            .write_buffer(&args, 0, bytemuck::cast_slice(&all_drawn));
        let copy = |label: &str| {
            let b = buffer(gpu.device(), label, bytes(all_drawn.len()), indirect);
            gpu.queue()
                .write_buffer(&b, 0, bytemuck::cast_slice(&all_drawn));
            b
        };
        let occlusion = OcclusionBuffers {
            late: copy("scene draw args, late"),
            all: copy("scene draw args, both phases"),
            history: buffer(
                gpu.device(),
                "scene slot history",
                bytes(layout.slot_draws.len()),
                wgpu::BufferUsages::empty(),
            ),
        };
        let slot_draws = buffer(
            gpu.device(),
            "scene slot draws",
            bytes(layout.slot_draws.len()),
            wgpu::BufferUsages::empty(),
        );
        gpu.queue()
            .write_buffer(&slot_draws, 0, bytemuck::cast_slice(&layout.slot_draws));
        Self {
            layout: Arc::new(layout),
            all_drawn,
            args,
            occlusion,
            slot_draws,
        }
    }
}

impl ViewDraws {
    /// The draws of `frame`'s scene where its instances are, every slot drawn.
    pub fn new(
        gpu: &GpuContext,
        shared: &CullShared,
        frame: &FrameInputs,
    ) -> Result<Self, RenderError> {
        let table = &frame.instances;
        let boxes: Vec<DrawBox> = (0..table.draws.len()).map(|d| draw_box(table, d)).collect();
        let box_capacity = boxes.len() + boxes.len() / 4 + 16;
        let box_buffer = buffer(
            gpu.device(),
            "scene draw boxes",
            (box_capacity * size_of::<DrawBox>()) as u64,
            wgpu::BufferUsages::empty(),
        );
        gpu.queue()
            .write_buffer(&box_buffer, 0, bytemuck::cast_slice(&boxes));
        let bounds = boxes
            .iter()
            .filter(|d| d.min.x <= d.max.x)
            .fold(Aabb::EMPTY, |b, d| {
                b.with_point(d.min.truncate()).with_point(d.max.truncate())
            });
        let scene = Arc::clone(&frame.scene);
        let slots = LaidOut::new(gpu, &scene, table);
        let bind_group = bind_group(
            gpu.device(),
            shared,
            [
                &slots.slot_draws,
                &slots.args,
                &box_buffer,
                &slots.occlusion.history,
            ],
        )?;
        let mut draws = Self {
            scene,
            table: table.id(),
            placement: frame.scene.placement_revision,
            revision: table.revision,
            layout: slots.layout,
            all_drawn: slots.all_drawn,
            args_all_drawn: true,
            args: slots.args,
            occlusion: slots.occlusion,
            slot_draws: slots.slot_draws,
            bind_group,
            boxes,
            box_buffer,
            box_capacity,
            bounds,
            blended: None,
        };
        draws.follow_blended(gpu, shared, table)?;
        Ok(draws)
    }

    /// How far outside a frustum plane a box may reach and still be kept: rounding never
    /// removes a box that touches the frustum (it scales with every box together).
    pub fn slack(&self) -> f32 {
        let extent = if self.bounds.is_empty() {
            0.0
        } else {
            (self.bounds.max - self.bounds.min).length()
        };
        1e-5 * (1.0 + extent)
    }

    /// The blended draws that meet `camera`'s frustum (all of them without `cull`), back to
    /// front from its homogeneous eye ([`crate::frame_data::FrameCamera::eye_homogeneous`]):
    /// by distance from a perspective camera's eye, by depth along an orthographic camera's
    /// parallel rays. Ties keep scene order. It reads the boxes kept here, so it costs a test
    /// and a key per blended draw and a sort of those in view, and never walks the instances.
    pub fn blended_back_to_front(&self, camera: &FrameCamera, cull: bool) -> Vec<u32> {
        let planes = camera.frustum_planes();
        let eye = camera.eye_homogeneous();
        let mut order: Vec<(f32, u32)> = self
            .layout
            .blended
            .iter()
            .filter_map(|&d| {
                let b = self.boxes.get(d as usize)?;
                let world = Aabb {
                    min: b.min.truncate(),
                    max: b.max.truncate(),
                };
                if world.is_empty() {
                    return None;
                }
                let slack = 1e-4 * (world.max - world.min).length();
                (!cull || box_in_frustum(&planes, world, slack))
                    .then(|| (farness(eye, world.center()), d))
            })
            .collect();
        order.sort_by(|a, b| b.0.total_cmp(&a.0));
        order.into_iter().map(|(_, d)| d).collect()
    }

    /// Builds the layout afresh and uploads its slots and arguments.
    fn lay_out(
        &mut self,
        gpu: &GpuContext,
        shared: &CullShared,
        table: &InstanceTable,
    ) -> Result<(), shader_bind::BindError> {
        let slots = LaidOut::new(gpu, &self.scene, table);
        self.layout = slots.layout;
        self.all_drawn = slots.all_drawn;
        self.args = slots.args;
        self.occlusion = slots.occlusion;
        self.slot_draws = slots.slot_draws;
        self.args_all_drawn = true;
        self.rebind(gpu.device(), shared)
    }

    fn rebind(
        &mut self,
        device: &wgpu::Device,
        shared: &CullShared,
    ) -> Result<(), shader_bind::BindError> {
        let buffers = [
            &self.slot_draws,
            &self.args,
            &self.box_buffer,
            &self.occlusion.history,
        ];
        self.bind_group = bind_group(device, shared, buffers)?;
        if let Some(b) = &mut self.blended {
            b.rebind(device, &shared.blended, &self.box_buffer)?;
        }
        Ok(())
    }

    /// Whether these draws can follow `frame`'s scene and instances: the same instance
    /// table, and a scene whose materials batch draws as they did (else every draw is
    /// placed again).
    pub fn follows(&self, frame: &FrameInputs) -> bool {
        self.table == frame.instances.id()
            && self.scene.id == frame.scene.id
            && self.placement == frame.scene.placement_revision
    }

    /// Follows the instance table: for every instance added, removed or changed since the
    /// last frame (as its change log names them), rewrites its draws' boxes and moves its
    /// draws to their batches' slots (spare slots, written one by one), building the layout
    /// again only when a batch is full or new.
    pub fn follow_instances(
        &mut self,
        gpu: &GpuContext,
        shared: &CullShared,
        table: &InstanceTable,
    ) -> Result<(), RenderError> {
        if table.revision == self.revision {
            return Ok(());
        }
        let changed = table
            .changed_since(self.revision)
            .unwrap_or_else(|| (0..table.states.len()).collect());
        let mut relayout = false;
        let mut changed_slots = Vec::new();
        let mut changed_boxes = Vec::new();
        let layout = Arc::make_mut(&mut self.layout);
        for state in changed.into_iter().filter_map(|i| table.states.get(i)) {
            for d in state.draws() {
                if !relayout {
                    match layout.place(d as u32, draw_place(&self.scene, table, d)) {
                        Ok(slots) => changed_slots.extend(slots),
                        Err(_) => relayout = true,
                    }
                }
                let b = draw_box(table, d);
                if d >= self.boxes.len() {
                    self.boxes.resize(d + 1, b);
                }
                self.boxes[d] = b;
                if b.min.x <= b.max.x {
                    self.bounds = self
                        .bounds
                        .with_point(b.min.truncate())
                        .with_point(b.max.truncate());
                }
            }
            changed_boxes.push(state.draws());
        }
        self.revision = table.revision;
        self.write_boxes(gpu, shared, &changed_boxes)?;
        if relayout {
            self.lay_out(gpu, shared, table)?;
            return self.follow_blended(gpu, shared, table);
        }
        for slot in changed_slots {
            let args = slot_arguments(table, &self.layout, slot as usize);
            let at = slot as usize * 5;
            self.all_drawn[at..at + 5].copy_from_slice(&args);
            let draw = self.layout.slot_draws[slot as usize];
            let queue = gpu.queue();
            queue.write_buffer(
                &self.slot_draws,
                u64::from(slot) * 4,
                bytemuck::bytes_of(&draw),
            );
            let o = &self.occlusion;
            for buffer in [&self.args, &o.late, &o.all] {
                queue.write_buffer(buffer, (at * 4) as u64, bytemuck::cast_slice(&args));
            }
        }
        self.follow_blended(gpu, shared, table)
    }

    /// Builds the blended draws' order again where the layout's blended draws changed.
    fn follow_blended(
        &mut self,
        gpu: &GpuContext,
        shared: &CullShared,
        table: &InstanceTable,
    ) -> Result<(), RenderError> {
        let list = &self.layout.blended;
        if self.blended.as_ref().map_or(&[][..], |b| &b.draws) == list.as_slice() {
            return Ok(());
        }
        self.blended = if list.is_empty() {
            None
        } else {
            let kernels = &shared.blended;
            Some(BlendedOrder::new(
                gpu,
                kernels,
                table,
                list,
                &self.box_buffer,
            )?)
        };
        Ok(())
    }

    /// Uploads the boxes of `ranges`, or every box into a buffer twice as large when they
    /// outgrew it.
    fn write_boxes(
        &mut self,
        gpu: &GpuContext,
        shared: &CullShared,
        ranges: &[std::ops::Range<usize>],
    ) -> Result<(), shader_bind::BindError> {
        let stride = size_of::<DrawBox>();
        if self.boxes.len() > self.box_capacity {
            self.box_capacity = self.boxes.len().max(2 * self.box_capacity);
            let bytes = (self.box_capacity * stride) as u64;
            let usage = wgpu::BufferUsages::empty();
            self.box_buffer = buffer(gpu.device(), "scene draw boxes", bytes, usage);
            gpu.queue()
                .write_buffer(&self.box_buffer, 0, bytemuck::cast_slice(&self.boxes));
            return self.rebind(gpu.device(), shared);
        }
        for r in ranges.iter().filter(|r| !r.is_empty()) {
            let bytes = bytemuck::cast_slice(&self.boxes[r.clone()]);
            gpu.queue()
                .write_buffer(&self.box_buffer, (r.start * stride) as u64, bytes);
        }
        Ok(())
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
/// parameters and the visible counter (the pass's), and the blended order's kernels.
#[derive(Debug)]
pub struct CullShared {
    pub program: ShaderProgram,
    pub params: wgpu::Buffer,
    pub visible: wgpu::Buffer,
    /// The blended draws' ordering and sort kernels.
    pub blended: Arc<BlendedKernels>,
}

/// Group 0 of `instance_cull`, through the module's generated builder.
fn bind_group(
    device: &wgpu::Device,
    shared: &CullShared,
    [slot_draws, args, boxes, history]: [&wgpu::Buffer; 4],
) -> Result<wgpu::BindGroup, shader_bind::BindError> {
    instance_cull::Group0 {
        params: shared.params.as_entire_buffer_binding(),
        boxes: boxes.as_entire_buffer_binding(),
        slot_draws: slot_draws.as_entire_buffer_binding(),
        args: args.as_entire_buffer_binding(),
        visible: shared.visible.as_entire_buffer_binding(),
        history: history.as_entire_buffer_binding(),
    }
    .bind_group(
        device,
        shared.program.layout(0),
        shared.program.variant,
        "scene culling",
    )
}
