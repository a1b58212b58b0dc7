//! Transient resources: which virtual resources share a physical object (the plan), and the pool
//! of physical objects kept across frames.
//!
//! WebGPU has no memory aliasing, so sharing is by descriptor: two transients share a slot when
//! their descriptors are equal and their lifetimes do not overlap. The pool then hands each slot
//! an object with that descriptor and at least its usage, reusing last frame's objects.

use super::context::PoolObject;
use super::nodes::{Lifetime, ResourceDesc, ResourceNode, Usage};

/// One physical object of this frame: its descriptor, its usage and when it is busy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct SlotPlan {
    pub desc: ResourceDesc,
    pub usage: Usage,
    /// The last position at which the current occupant is used.
    pub busy_until: usize,
}

/// Assigns every used transient a slot, greedily by first use: optimal for interval lifetimes.
pub(crate) fn plan_slots(
    resources: &[ResourceNode],
    lifetimes: &[Option<Lifetime>],
    usages: &[Usage],
) -> (Vec<SlotPlan>, Vec<Option<usize>>) {
    let mut transients: Vec<(usize, Lifetime)> = resources
        .iter()
        .enumerate()
        .filter(|(_, r)| r.import.is_none())
        .filter_map(|(i, _)| lifetimes[i].map(|l| (i, l)))
        .collect();
    transients.sort_by_key(|&(i, l)| (l.first, i));
    let mut slots: Vec<SlotPlan> = Vec::new();
    let mut slot_of = vec![None; resources.len()];
    for (resource, lifetime) in transients {
        let desc = resources[resource].desc;
        let free = slots
            .iter()
            .position(|s| s.desc == desc && s.busy_until < lifetime.first);
        let slot = free.unwrap_or_else(|| {
            slots.push(SlotPlan {
                desc,
                usage: usages[resource],
                busy_until: 0,
            });
            slots.len() - 1
        });
        let s = &mut slots[slot];
        s.busy_until = lifetime.last;
        s.usage = union(s.usage, usages[resource]);
        slot_of[resource] = Some(slot);
    }
    (slots, slot_of)
}

fn union(a: Usage, b: Usage) -> Usage {
    match (a, b) {
        (Usage::Texture(x), Usage::Texture(y)) => Usage::Texture(x | y),
        (Usage::Buffer(x), Usage::Buffer(y)) => Usage::Buffer(x | y),
        // Slots only ever hold one kind of descriptor.
        (a, _) => a,
    }
}

#[derive(Debug)]
struct PoolEntry {
    desc: ResourceDesc,
    usage: Usage,
    object: PoolObject,
    /// The frame that last used it.
    last_frame: u64,
    in_use: bool,
}

/// How the pool did this frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PoolStats {
    /// Objects reused from earlier frames.
    pub reused: usize,
    /// Objects created this frame.
    pub created: usize,
    /// Objects dropped after going unused for [`TransientPool::KEEP_FRAMES`] frames.
    pub evicted: usize,
    /// Objects held after this frame.
    pub held: usize,
}

/// Physical transient textures and buffers, kept across frames.
#[derive(Debug, Default)]
pub struct TransientPool {
    entries: Vec<PoolEntry>,
    frame: u64,
}

impl TransientPool {
    /// Frames an unused object is kept before it is dropped.
    pub const KEEP_FRAMES: u64 = 3;

    /// An empty pool; objects are created by the first executions.
    pub fn new() -> Self {
        Self::default()
    }

    /// Gives each slot a physical object, creating what is missing.
    pub(crate) fn acquire(
        &mut self,
        device: &wgpu::Device,
        slots: &[SlotPlan],
    ) -> (Vec<PoolObject>, PoolStats) {
        self.frame += 1;
        let mut stats = PoolStats::default();
        for e in &mut self.entries {
            e.in_use = false;
        }
        let objects = slots
            .iter()
            .enumerate()
            .map(|(i, slot)| {
                let found = self
                    .entries
                    .iter_mut()
                    .find(|e| !e.in_use && e.desc == slot.desc && covers(e.usage, slot.usage));
                if let Some(e) = found {
                    e.in_use = true;
                    e.last_frame = self.frame;
                    stats.reused += 1;
                    return e.object.clone();
                }
                stats.created += 1;
                let object = create(device, slot, i);
                self.entries.push(PoolEntry {
                    desc: slot.desc,
                    usage: slot.usage,
                    object: object.clone(),
                    last_frame: self.frame,
                    in_use: true,
                });
                object
            })
            .collect();
        let before = self.entries.len();
        let frame = self.frame;
        self.entries
            .retain(|e| e.in_use || frame - e.last_frame < Self::KEEP_FRAMES);
        stats.evicted = before - self.entries.len();
        stats.held = self.entries.len();
        (objects, stats)
    }
}

fn covers(have: Usage, need: Usage) -> bool {
    match (have, need) {
        (Usage::Texture(h), Usage::Texture(n)) => h.contains(n),
        (Usage::Buffer(h), Usage::Buffer(n)) => h.contains(n),
        _ => false,
    }
}

fn create(device: &wgpu::Device, slot: &SlotPlan, index: usize) -> PoolObject {
    let label = format!("graph transient {index}");
    match (slot.desc, slot.usage) {
        (ResourceDesc::Texture(d), Usage::Texture(usage)) => {
            PoolObject::Texture(d.create(device, &label, usage))
        }
        (ResourceDesc::Buffer(d), Usage::Buffer(usage)) => {
            PoolObject::Buffer(device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(&label),
                size: d.size,
                usage,
                mapped_at_creation: false,
            }))
        }
        _ => unreachable!("a slot's usage always matches its descriptor's kind"),
    }
}
