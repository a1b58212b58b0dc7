//! Shadow casters culled per region on the GPU (`shadow_cull`): the casters' slots, boxes and
//! the frame's work live in buffers the dispatch reads, and it writes every work item's run of
//! indirect arguments and cast records, which the caster pipelines draw with two multi-draws
//! per item (opaque, then alpha-masked casters).
//!
//! The slot layout and the boxes follow the scene across frames: a frame where nothing moved
//! writes only the regions' volumes and the work, one where instances moved writes their
//! draws' boxes, and an added draw takes a spare slot. A frame's work is split into chunks
//! whose arguments fit [`CasterCulling::BUDGET_SLOTS`] and one storage binding, each culled
//! and then drawn in turn. Chunks cost a compute pass and two depth passes over the atlas
//! each (about 40 µs of GPU and 70 µs of CPU on an H100), so the budget is generous.

use crate::frame_data::InputError;
use std::ops::Range;

use shaders_gen::shadow::shadow_cull::{
    self, CasterSlot, DrawBox, Frustum, RegionVolume, ShadowCullParams, ShadowWork,
};

use super::casters::CasterCache;
use super::slots::{SlotLayout, caster_box, caster_kind, slot_record};
use super::work::WorkItem;
use crate::GpuContext;
use crate::frame_data::{FrameInputs, RenderError};
use crate::graph::PassEncoder;
use crate::readback_ring::ReadbackRing;
use crate::shader::ShaderProgram;
use crate::shadow::cache::RegionPlan;
use crate::shadow::region_test::RegionTest;

/// A region's volume for the GPU.
fn region_volume(r: &RegionPlan) -> RegionVolume {
    let (p, bounds) = RegionTest::new(r.region.view.clip_from_world).volume();
    let (min, max) = bounds.map_or((glam::Vec4::ZERO, glam::Vec4::ZERO), |b| {
        (b.min.extend(1.0), b.max.extend(0.0))
    });
    RegionVolume::new(Frustum::new(p[0], p[1], p[2], p[3], p[4], p[5]), min, max)
}

/// A storage buffer of at least `bytes`.
fn storage(
    device: &wgpu::Device,
    label: &str,
    bytes: u64,
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(16),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | extra,
        mapped_at_creation: false,
    })
}

/// A buffer of `T` records that is replaced by a larger one when a write does not fit.
#[derive(Debug)]
struct Records {
    buffer: wgpu::Buffer,
    capacity: usize,
    label: &'static str,
    extra: wgpu::BufferUsages,
}

impl Records {
    fn new(
        device: &wgpu::Device,
        label: &'static str,
        capacity: usize,
        size: usize,
        extra: wgpu::BufferUsages,
    ) -> Self {
        Self {
            buffer: storage(device, label, (capacity * size) as u64, extra),
            capacity,
            label,
            extra,
        }
    }

    /// Makes room for `count` records of `size` bytes, with room to spare within the
    /// device's largest storage binding; `true` when the buffer was replaced.
    fn reserve(&mut self, device: &wgpu::Device, count: usize, size: usize) -> bool {
        if count <= self.capacity {
            return false;
        }
        let bindable = device.limits().max_storage_buffer_binding_size as usize / size;
        self.capacity = count.next_power_of_two().min(bindable).max(count);
        self.buffer = storage(
            device,
            self.label,
            (self.capacity * size) as u64,
            self.extra,
        );
        true
    }
}

/// One chunk of a frame's work: its parameters and bind group.
#[derive(Debug)]
struct Chunk {
    params: wgpu::Buffer,
    group: wgpu::BindGroup,
}

/// The GPU side of shadow-caster culling.
#[derive(Debug)]
pub struct CasterCulling {
    program: ShaderProgram,
    pipeline: wgpu::ComputePipeline,
    /// What the layout follows: scene id and placement revision, instance table id.
    follows: Option<(u32, u64, u32)>,
    layout: SlotLayout,
    /// Draws placed in the layout so far (later ones are new).
    placed: usize,
    boxes: Records,
    slots: Records,
    regions: Records,
    work: Records,
    args: Records,
    casts: Records,
    /// `COUNTS`: the casts drawn, then two per work item (opaque, masked) when compacting.
    counts: Records,
    /// Whether drawn casts are packed and counted (the device draws a GPU-written count).
    compact: bool,
    /// Bind groups per chunk, made for the buffers as they are now (cleared when one changes).
    chunks: Vec<Chunk>,
    /// This frame's chunks: ranges of work items.
    pub frame_chunks: Vec<Range<u32>>,
    readback: ReadbackRing,
    /// The newest count of casts drawn that arrived.
    pub last_drawn: Option<u32>,
    device: wgpu::Device,
}

impl CasterCulling {
    /// Argument slots one chunk may hold at most (20 bytes of arguments and 8 of casts
    /// each: 224 MiB), allocated only as far as a frame's work needs them.
    pub const BUDGET_SLOTS: usize = 8 << 20;

    pub fn new(gpu: &GpuContext) -> Result<Self, RenderError> {
        let device = gpu.device();
        let variant = &shadow_cull::VARIANTS[0];
        let program = gpu.program(variant)?;
        let pipeline = program.compute_pipeline(device, "cull_casters")?;
        let none = wgpu::BufferUsages::empty();
        let read_back = wgpu::BufferUsages::COPY_SRC;
        Ok(Self {
            pipeline,
            follows: None,
            layout: SlotLayout::default(),
            placed: 0,
            boxes: Records::new(
                device,
                "shadow caster boxes",
                64,
                size_of::<DrawBox>(),
                none,
            ),
            slots: Records::new(
                device,
                "shadow caster slots",
                64,
                size_of::<CasterSlot>(),
                none,
            ),
            regions: Records::new(
                device,
                "shadow region volumes",
                16,
                size_of::<RegionVolume>(),
                none,
            ),
            work: Records::new(device, "shadow work", 16, size_of::<ShadowWork>(), none),
            args: Records::new(
                device,
                "shadow caster args",
                256,
                20,
                wgpu::BufferUsages::INDIRECT | read_back,
            ),
            casts: Records::new(device, "shadow casts", 256, 8, read_back),
            counts: Records::new(
                device,
                "shadow cast counts",
                64,
                4,
                wgpu::BufferUsages::INDIRECT | read_back,
            ),
            compact: (device.features()).contains(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT),
            chunks: Vec::new(),
            frame_chunks: Vec::new(),
            readback: ReadbackRing::new(device, "shadow casts drawn", 1),
            last_drawn: None,
            device: device.clone(),
            program,
        })
    }

    /// The slot layout.
    pub fn layout(&self) -> &SlotLayout {
        &self.layout
    }

    /// The cast records the caster pipelines read (the caster group binds it).
    pub fn casts(&self) -> &wgpu::Buffer {
        &self.casts.buffer
    }

    /// The indirect arguments of this frame's chunks, five words per slot.
    pub fn args(&self) -> &wgpu::Buffer {
        &self.args.buffer
    }

    /// Brings the layout and boxes to `frame`'s casters: `changed` is what the caster cache
    /// reported (`None`: rebuilt, so everything is written).
    pub fn follow(&mut self, frame: &FrameInputs, cache: &CasterCache, changed: Option<&[u32]>) {
        let (scene, table) = (&frame.scene, &frame.instances);
        let key = (scene.id, scene.placement_revision, table.id());
        let queue = frame.gpu.queue();
        let same = self.follows == Some(key) && self.placed <= table.draws.len();
        let changed = changed.filter(|_| same);
        let Some(changed) = changed.filter(|c| self.place_new(frame, c)) else {
            self.rebuild(frame, cache, key);
            return;
        };
        for &d in changed {
            if let Some(c) = cache.casters.get(d as usize) {
                let at = u64::from(d) * size_of::<DrawBox>() as u64;
                queue.write_buffer(&self.boxes.buffer, at, bytemuck::bytes_of(&caster_box(c)));
            }
        }
    }

    /// Places draws added since the last frame in spare slots (their boxes are among the
    /// changed ones); `false` when a part is full or the box buffer must grow.
    fn place_new(&mut self, frame: &FrameInputs, changed: &[u32]) -> bool {
        let table = &frame.instances;
        let count = table.draws.len();
        if count > self.boxes.capacity {
            return false;
        }
        let placed = self.placed;
        for &d in changed.iter().filter(|&&d| d as usize >= placed) {
            let Some(kind) = caster_kind(&frame.scene, table, d as usize) else {
                continue;
            };
            let Some(slot) = self.layout.place(d, kind) else {
                return false;
            };
            let at = (slot * size_of::<CasterSlot>()) as u64;
            let record = slot_record(table, d);
            frame
                .gpu
                .queue()
                .write_buffer(&self.slots.buffer, at, bytemuck::bytes_of(&record));
        }
        self.placed = count;
        true
    }

    fn rebuild(&mut self, frame: &FrameInputs, cache: &CasterCache, key: (u32, u64, u32)) {
        let (device, queue) = (frame.gpu.device(), frame.gpu.queue());
        let table = &frame.instances;
        self.layout = SlotLayout::new(&frame.scene, table);
        let records: Vec<CasterSlot> = self
            .layout
            .draws
            .iter()
            .map(|&d| slot_record(table, d))
            .collect();
        let boxes: Vec<DrawBox> = cache.casters.iter().map(caster_box).collect();
        let mut replaced = self
            .slots
            .reserve(device, records.len(), size_of::<CasterSlot>());
        replaced |= self.boxes.reserve(
            device,
            boxes.len() + boxes.len() / 8 + 8,
            size_of::<DrawBox>(),
        );
        queue.write_buffer(&self.slots.buffer, 0, bytemuck::cast_slice(&records));
        if !boxes.is_empty() {
            queue.write_buffer(&self.boxes.buffer, 0, bytemuck::cast_slice(&boxes));
        }
        if replaced {
            self.chunks.clear();
        }
        self.placed = table.draws.len();
        self.follows = Some(key);
    }

    /// Writes `items`' work and the regions' volumes, and splits the work into chunks.
    /// A single work item needing more arguments than the device binds is an error.
    pub fn prepare(
        &mut self,
        gpu: &GpuContext,
        items: &[WorkItem],
        regions: &[RegionPlan],
        cull: bool,
    ) -> Result<(), RenderError> {
        self.frame_chunks.clear();
        if items.is_empty() {
            return Ok(());
        }
        let device = gpu.device();
        let stride = self.layout.stride().max(1) as usize;
        let max_binding = device.limits().max_storage_buffer_binding_size as usize;
        // One dispatch covers a run with at most 65,535 workgroups along x.
        let dispatchable = 65_535 * shadow_cull::WORKGROUP as usize;
        let bindable = (max_binding / 20)
            .min(dispatchable)
            .min(Self::BUDGET_SLOTS.max(stride));
        if stride > bindable {
            return Err(RenderError::Input(InputError::TooManyShadowCasters {
                slots: stride as u32,
                max: bindable as u32,
            }));
        }
        let per_chunk = (bindable / stride).clamp(1, 65_535);
        let runs = items.len().min(per_chunk);
        let mut replaced = self.args.reserve(device, runs * stride, 20);
        replaced |= self.casts.reserve(device, runs * stride, 8);
        replaced |= self
            .regions
            .reserve(device, regions.len(), size_of::<RegionVolume>());
        replaced |= self
            .work
            .reserve(device, items.len(), size_of::<ShadowWork>());
        replaced |= self.counts.reserve(device, 1 + 2 * items.len(), 4);
        if replaced {
            self.chunks.clear();
        }
        let volumes: Vec<RegionVolume> = regions.iter().map(region_volume).collect();
        let work: Vec<ShadowWork> = items
            .iter()
            .map(|i| ShadowWork::new(i.view, i.casters, 0, 0))
            .collect();
        gpu.queue()
            .write_buffer(&self.regions.buffer, 0, bytemuck::cast_slice(&volumes));
        gpu.queue()
            .write_buffer(&self.work.buffer, 0, bytemuck::cast_slice(&work));
        let mut first = 0;
        while first < items.len() {
            let end = (first + per_chunk).min(items.len());
            let c = self.frame_chunks.len();
            if c == self.chunks.len() {
                self.chunks.push(self.chunk(device)?);
            }
            let params = ShadowCullParams::new(
                stride as u32,
                first as u32,
                (end - first) as u32,
                u32::from(cull),
                self.layout.opaque,
                u32::from(self.compact),
                0,
                0,
            );
            gpu.queue()
                .write_buffer(&self.chunks[c].params, 0, bytemuck::bytes_of(&params));
            self.frame_chunks.push(first as u32..end as u32);
            first = end;
        }
        Ok(())
    }

    /// A chunk's parameters and bind group over the buffers as they are.
    fn chunk(&self, device: &wgpu::Device) -> Result<Chunk, RenderError> {
        let params = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("shadow cull params"),
            size: size_of::<ShadowCullParams>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let group = shadow_cull::Group0 {
            params: params.as_entire_buffer_binding(),
            boxes: self.boxes.buffer.as_entire_buffer_binding(),
            slots: self.slots.buffer.as_entire_buffer_binding(),
            regions: self.regions.buffer.as_entire_buffer_binding(),
            work: self.work.buffer.as_entire_buffer_binding(),
            args: self.args.buffer.as_entire_buffer_binding(),
            casts: self.casts.buffer.as_entire_buffer_binding(),
            counts: self.counts.buffer.as_entire_buffer_binding(),
        }
        .bind_group(
            device,
            self.program.layout(shadow_cull::Group0::GROUP),
            self.program.variant,
            "shadow cull",
        )?;
        Ok(Chunk { params, group })
    }

    /// Writes casts listed on the CPU into the cast buffer (growing it).
    pub fn write_casts(
        &mut self,
        gpu: &GpuContext,
        casts: &[shaders_gen::shadow::shadow_caster::Cast],
    ) {
        if self.casts.reserve(gpu.device(), casts.len(), 8) {
            self.chunks.clear();
        }
        if !casts.is_empty() {
            gpu.queue()
                .write_buffer(&self.casts.buffer, 0, bytemuck::cast_slice(casts));
        }
    }

    /// What the recording needs to cull this frame's chunks.
    pub fn dispatches(&self) -> CullDispatches {
        CullDispatches {
            pipeline: self.pipeline.clone(),
            groups: (self.chunks.iter().take(self.frame_chunks.len()))
                .map(|c| c.group.clone())
                .collect(),
            chunks: self.frame_chunks.clone(),
            stride: self.layout.stride(),
            counts: self.counts.buffer.clone(),
            compact: self.compact,
        }
    }

    /// After the frame's passes are recorded: copies the count for the report.
    pub fn after_execute(&mut self, encoder: &mut wgpu::CommandEncoder, frame: u64) {
        if !self.frame_chunks.is_empty() {
            self.readback
                .record(encoder, &[(&self.counts.buffer, 4)], frame);
        }
    }

    /// After submitting: starts the copy and picks up the newest count that arrived.
    pub fn after_submit(&mut self) {
        self.readback.after_submit();
        self.poll();
    }

    /// Picks up the newest count that arrived, without waiting.
    pub fn poll(&mut self) {
        if let Some((_, words)) = self.readback.poll(&self.device) {
            self.last_drawn = words.first().copied();
        }
    }
}

/// The culling dispatches of a frame, for the recording.
pub struct CullDispatches {
    pipeline: wgpu::ComputePipeline,
    groups: Vec<wgpu::BindGroup>,
    pub chunks: Vec<Range<u32>>,
    pub stride: u32,
    /// `COUNTS`, and whether the draws read their count from it.
    pub counts: wgpu::Buffer,
    pub compact: bool,
}

impl CullDispatches {
    /// Clears the counts; call once before the first chunk.
    pub fn clear_counts(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.clear_buffer(&self.counts, 0, None);
    }

    /// Culls chunk `c`: every slot of each of its work items.
    pub fn cull(&self, encoder: &mut PassEncoder<'_>, c: usize) {
        let mut pass = encoder.begin_compute("shadow caster culling");
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.groups[c], &[]);
        pass.dispatch_workgroups(self.stride.div_ceil(shadow_cull::WORKGROUP), 1, 1);
    }
}
