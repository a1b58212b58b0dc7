//! Overflow handling without stalling the frame: the counters of each culling dispatch are copied
//! to a small ring of staging buffers and mapped asynchronously; a later frame picks up whatever
//! has arrived, and [`grow_for`] decides the capacities for the next frame.
//!
//! Nothing is dropped silently: every result that arrives is returned to the caller, which
//! reports it, and a grown capacity takes effect on the next frame.

use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};

use super::lists::CullCounters;

const FREE: u8 = 0;
const RECORDED: u8 = 1;
const MAPPING: u8 = 2;
const MAPPED: u8 = 3;
const FAILED: u8 = 4;

#[derive(Debug)]
struct Slot {
    buffer: wgpu::Buffer,
    state: Arc<AtomicU8>,
    frame: u64,
}

/// A ring of staging buffers that brings the culling counters back asynchronously.
#[derive(Debug)]
pub struct CounterReadback {
    slots: Vec<Slot>,
}

impl CounterReadback {
    /// Frames that may be in flight before a frame's counters are skipped.
    pub const DEPTH: usize = 3;

    pub fn new(device: &wgpu::Device) -> Self {
        let slots = (0..Self::DEPTH)
            .map(|_| Slot {
                buffer: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("cull counters readback"),
                    size: CullCounters::WORDS * 4,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                state: Arc::new(AtomicU8::new(FREE)),
                frame: 0,
            })
            .collect();
        Self { slots }
    }

    /// Records a copy of `counters` for `frame`. Returns `false` when every slot is still in
    /// flight (the GPU is more than [`Self::DEPTH`] frames behind); that frame is not sampled.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        counters: &wgpu::Buffer,
        frame: u64,
    ) -> bool {
        let Some(slot) = self
            .slots
            .iter_mut()
            .find(|s| s.state.load(Ordering::Acquire) == FREE)
        else {
            return false;
        };
        encoder.copy_buffer_to_buffer(counters, 0, &slot.buffer, 0, CullCounters::WORDS * 4);
        slot.state.store(RECORDED, Ordering::Release);
        slot.frame = frame;
        true
    }

    /// Starts mapping what was recorded; call after submitting the encoder.
    pub fn after_submit(&mut self) {
        for slot in &self.slots {
            if slot
                .state
                .compare_exchange(RECORDED, MAPPING, Ordering::AcqRel, Ordering::Acquire)
                .is_ok()
            {
                let state = Arc::clone(&slot.state);
                slot.buffer
                    .slice(..)
                    .map_async(wgpu::MapMode::Read, move |result| {
                        state.store(
                            if result.is_ok() { MAPPED } else { FAILED },
                            Ordering::Release,
                        );
                    });
            }
        }
    }

    /// Without blocking, returns the counters of the newest frame whose copy has arrived.
    pub fn poll(&mut self, device: &wgpu::Device) -> Option<(u64, CullCounters)> {
        // Non-blocking: only runs callbacks of work that is already done.
        let _ = device.poll(wgpu::PollType::Poll);
        let mut newest: Option<(u64, CullCounters)> = None;
        for slot in &mut self.slots {
            match slot.state.load(Ordering::Acquire) {
                MAPPED => {
                    let words: Option<Vec<u32>> = slot
                        .buffer
                        .slice(..)
                        .get_mapped_range()
                        .ok()
                        .map(|bytes| bytemuck::pod_collect_to_vec(&bytes));
                    slot.buffer.unmap();
                    slot.state.store(FREE, Ordering::Release);
                    if let Some(w) = words
                        && newest.is_none_or(|(f, _)| slot.frame > f)
                    {
                        newest = Some((slot.frame, CullCounters::from_words(&w)));
                    }
                }
                FAILED => slot.state.store(FREE, Ordering::Release),
                _ => {}
            }
        }
        newest
    }
}

/// Capacities of a culling pass's lists.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Capacities {
    /// Most items one cell may list.
    pub per_cell: u32,
    /// Entries of the index list.
    pub index: u32,
}

/// The capacities to use next frame after a frame reported `counters`, or `None` if the current
/// ones sufficed. The index list grows to a power of two with 25% headroom; the per-cell limit
/// grows to a power of two up to the kernel's `per_cell_limit`, past which overflow remains and
/// is reported (a smaller tile or the 2.5D / clustered method is the cure).
pub fn grow_for(
    counters: &CullCounters,
    current: Capacities,
    per_cell_limit: u32,
) -> Option<Capacities> {
    let mut next = current;
    if counters.max_cell_items > current.per_cell && current.per_cell < per_cell_limit {
        next.per_cell = counters
            .max_cell_items
            .next_power_of_two()
            .min(per_cell_limit);
    }
    // The entries the next frame will need with the new per-cell limit is at most what this
    // frame requested scaled by how much the per-cell limit grew; requested already counts each
    // cell up to the old limit.
    let scale = f64::from(next.per_cell) / f64::from(current.per_cell.max(1));
    let needed = (f64::from(counters.requested_entries) * scale * 1.25).ceil() as u64;
    if counters.requested_entries > current.index
        || (next.per_cell > current.per_cell && needed > u64::from(current.index))
    {
        next.index = u32::try_from(needed.next_power_of_two())
            .unwrap_or(u32::MAX)
            .max(current.index);
    }
    (next != current).then_some(next)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counters(requested: u32, max_cell: u32) -> CullCounters {
        CullCounters {
            requested_entries: requested,
            overflow_cells: 0,
            dropped: 0,
            max_cell_items: max_cell,
        }
    }

    #[test]
    fn enough_room_means_no_growth() {
        let caps = Capacities {
            per_cell: 256,
            index: 4096,
        };
        assert_eq!(grow_for(&counters(4000, 200), caps, 1024), None);
    }

    #[test]
    fn index_list_grows_with_headroom() {
        let caps = Capacities {
            per_cell: 256,
            index: 4096,
        };
        let next = grow_for(&counters(5000, 100), caps, 1024).expect("must grow");
        assert_eq!(
            next,
            Capacities {
                per_cell: 256,
                index: 8192
            }
        );
    }

    #[test]
    fn per_cell_limit_grows_up_to_the_kernel_limit_and_index_follows() {
        let caps = Capacities {
            per_cell: 64,
            index: 1 << 16,
        };
        let next = grow_for(&counters(60_000, 300), caps, 1024).expect("must grow");
        assert_eq!(next.per_cell, 512);
        assert!(
            next.index >= 60_000 * 8,
            "index list grows with the per-cell limit: {next:?}"
        );
        let at_limit = Capacities {
            per_cell: 1024,
            index: 1 << 20,
        };
        assert_eq!(
            grow_for(&counters(1000, 5000), at_limit, 1024),
            None,
            "nothing more to grow"
        );
    }
}
