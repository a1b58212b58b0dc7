//! The main view's drawn slots packed per batch on the GPU (`draw_compact`), where the device
//! draws with a count read from a buffer (`MULTI_DRAW_INDIRECT_COUNT`): after a culling
//! dispatch writes a slot list's instance counts, three dispatches pack its drawn slots to the
//! front of each batch in slot order and count them, and the geometry passes draw each batch
//! with one `multi_draw_indexed_indirect_count` over its drawn slots only, instead of an empty
//! draw per culled slot.
//!
//! One [`Compaction`] serves a batch layout's slot lists (the frustum's, and occlusion
//! culling's late and both-phases lists): the slots' batches, the batch ranges and the scan's
//! scratch are shared, and each list has its packed arguments and counts ([`PackedArgs`]).

use shaders_gen::culling::draw_compact::{self, BLOCK, CompactParams, NO_BATCH};
use wgpu::util::DeviceExt as _;

use crate::GpuContext;
use crate::frame_data::{BatchLayout, RenderError};
use crate::graph::PassEncoder;
use crate::shader::ShaderProgram;

/// The compaction kernels.
#[derive(Debug)]
pub struct CompactKernels {
    program: ShaderProgram,
    scan_blocks: wgpu::ComputePipeline,
    scan_sums: wgpu::ComputePipeline,
    scatter: wgpu::ComputePipeline,
}

impl CompactKernels {
    pub fn new(gpu: &GpuContext) -> Result<Self, RenderError> {
        let device = gpu.device();
        let variant = draw_compact::variant(draw_compact::VariantKey::ALL[0]);
        let program = gpu.program(variant)?;
        Ok(Self {
            scan_blocks: program.compute_pipeline(device, "scan_blocks")?,
            scan_sums: program.compute_pipeline(device, "scan_sums")?,
            scatter: program.compute_pipeline(device, "scatter")?,
            program,
        })
    }
}

/// One slot list packed: its drawn slots' arguments per batch, from the batch's first slot on,
/// and each batch's count (a `u32` per batch, at `4 × batch` bytes).
#[derive(Debug, Clone)]
pub struct PackedArgs {
    pub args: wgpu::Buffer,
    pub counts: wgpu::Buffer,
    /// The slot list it packs.
    source: wgpu::Buffer,
    group: wgpu::BindGroup,
}

/// The compaction of one batch layout's slot lists.
#[derive(Debug)]
pub struct Compaction {
    /// The batch ranges it was built for.
    batches: Vec<(u32, u32)>,
    slot_count: u32,
    block_count: u32,
    /// One per slot list, in the order given.
    pub packed: Vec<PackedArgs>,
}

/// Each batch's slots: first, one past the last.
fn batch_ranges(layout: &BatchLayout) -> Vec<(u32, u32)> {
    (layout.batches.iter())
        .map(|b| (b.first_slot, b.first_slot + b.slot_count))
        .collect()
}

impl Compaction {
    /// Packs `sources` (slot lists of `layout`, five words a slot).
    pub fn new(
        gpu: &GpuContext,
        kernels: &CompactKernels,
        layout: &BatchLayout,
        sources: &[&wgpu::Buffer],
    ) -> Result<Self, shader_bind::BindError> {
        let device = gpu.device();
        let batches = batch_ranges(layout);
        let slot_count = layout.slot_count();
        let block_count = slot_count.div_ceil(BLOCK).max(1);
        let mut slot_batch = vec![NO_BATCH; slot_count as usize];
        for (b, &(first, end)) in batches.iter().enumerate() {
            slot_batch[first as usize..end as usize].fill(b as u32);
        }
        let init = |label: &str, bytes: &[u8], usage| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage,
            })
        };
        let storage = wgpu::BufferUsages::STORAGE;
        let params = CompactParams::new(slot_count, block_count, 0, 0);
        let params = init(
            "draw compaction params",
            bytemuck::bytes_of(&params),
            wgpu::BufferUsages::UNIFORM,
        );
        let slot_batch = init(
            "draw compaction slot batches",
            bytemuck::cast_slice(&non_empty(slot_batch)),
            storage,
        );
        let ranges: Vec<[u32; 2]> = batches.iter().map(|&(a, b)| [a, b]).collect();
        let ranges = init(
            "draw compaction batches",
            bytemuck::cast_slice(&non_empty(ranges)),
            storage,
        );
        let sizes = (slot_count, block_count, batches.len() as u64);
        let shared = [&params, &slot_batch, &ranges];
        let packed = (sources.iter())
            .map(|&source| pack_list(device, kernels, shared, source, sizes))
            .collect::<Result<_, _>>()?;
        Ok(Self {
            batches,
            slot_count,
            block_count,
            packed,
        })
    }

    /// Whether it still packs `sources` for `layout` (the same batch ranges and lists).
    pub fn fits(&self, layout: &BatchLayout, sources: &[&wgpu::Buffer]) -> bool {
        self.batches == batch_ranges(layout)
            && self.packed.len() == sources.len()
            && (self.packed.iter().zip(sources)).all(|(p, s)| p.source == **s)
    }

    /// Records the packing of list `list` (after its culling dispatch, before its draws).
    pub fn record(&self, kernels: &CompactKernels, encoder: &mut PassEncoder<'_>, list: usize) {
        let Some(packed) = self.packed.get(list) else {
            return;
        };
        // A batch of no slot writes no count.
        encoder.clear_buffer(&packed.counts, 0, None);
        let mut pass = encoder.begin_compute("draw compaction");
        pass.set_bind_group(0, &packed.group, &[]);
        pass.set_pipeline(&kernels.scan_blocks);
        pass.dispatch_workgroups(self.block_count, 1, 1);
        pass.set_pipeline(&kernels.scan_sums);
        pass.dispatch_workgroups(1, 1, 1);
        pass.set_pipeline(&kernels.scatter);
        let groups = self.slot_count.div_ceil(draw_compact::WORKGROUP);
        pass.dispatch_workgroups(groups.max(1), 1, 1);
    }
}

/// A zeroed buffer of `words` `u32`s (at least one).
fn zeroed(
    device: &wgpu::Device,
    label: &str,
    words: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: words.max(1) * 4,
        usage,
        mapped_at_creation: false,
    })
}

/// The packing of slot list `source`: its own scratch (no list's scan waits on another's), its
/// packed arguments and counts, and the bind group over them and the `shared` parameters, slot
/// batches and batch ranges; `sizes` are the slots, blocks and batches.
fn pack_list(
    device: &wgpu::Device,
    kernels: &CompactKernels,
    shared: [&wgpu::Buffer; 3],
    source: &wgpu::Buffer,
    (slot_count, block_count, batch_count): (u32, u32, u64),
) -> Result<PackedArgs, shader_bind::BindError> {
    let storage = wgpu::BufferUsages::STORAGE;
    let prefix = zeroed(
        device,
        "draw compaction prefix",
        u64::from(block_count * BLOCK),
        storage,
    );
    let block_sums = zeroed(
        device,
        "draw compaction block sums",
        u64::from(block_count.next_multiple_of(BLOCK)),
        storage,
    );
    let args = zeroed(
        device,
        "scene draw args, packed",
        u64::from(slot_count) * 5,
        storage | wgpu::BufferUsages::INDIRECT,
    );
    let counts = zeroed(
        device,
        "scene draw counts",
        batch_count,
        storage | wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
    );
    let [params, slot_batch, ranges] = shared;
    let group = draw_compact::Group0 {
        params: params.as_entire_buffer_binding(),
        args: source.as_entire_buffer_binding(),
        slot_batch: slot_batch.as_entire_buffer_binding(),
        batches: ranges.as_entire_buffer_binding(),
        prefix: prefix.as_entire_buffer_binding(),
        block_sums: block_sums.as_entire_buffer_binding(),
        packed: args.as_entire_buffer_binding(),
        counts: counts.as_entire_buffer_binding(),
    }
    .bind_group(
        device,
        kernels.program.layout(0),
        kernels.program.variant,
        "draw compaction",
    )?;
    Ok(PackedArgs {
        args,
        counts,
        source: source.clone(),
        group,
    })
}

/// `v`, or one zeroed element where it is empty (a storage buffer is never empty).
fn non_empty<T: Copy + bytemuck::Zeroable>(mut v: Vec<T>) -> Vec<T> {
    if v.is_empty() {
        v.push(T::zeroed());
    }
    v
}
