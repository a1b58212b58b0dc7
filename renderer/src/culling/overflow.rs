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

/// The index-list capacity to use next frame after a frame reported `counters`, or `None` if
/// the current one sufficed: what the frame requested with 25% headroom, as a power of two.
/// Lists themselves have no per-cell limit, so the index list is the only thing that can run
/// out.
pub fn grow_for(counters: &CullCounters, current_index: u32) -> Option<u32> {
    if counters.requested_entries <= current_index {
        return None;
    }
    let needed = (f64::from(counters.requested_entries) * 1.25).ceil() as u64;
    Some(
        u32::try_from(needed.next_power_of_two())
            .unwrap_or(u32::MAX)
            .max(current_index),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counters(requested: u32) -> CullCounters {
        CullCounters {
            requested_entries: requested,
            ..CullCounters::default()
        }
    }

    #[test]
    fn enough_room_means_no_growth() {
        assert_eq!(grow_for(&counters(4000), 4096), None);
        assert_eq!(grow_for(&counters(4096), 4096), None);
    }

    #[test]
    fn index_list_grows_with_headroom() {
        assert_eq!(grow_for(&counters(5000), 4096), Some(8192));
        assert_eq!(grow_for(&counters(7000), 4096), Some(16384), "25% headroom");
    }

    #[test]
    fn growth_saturates_instead_of_wrapping() {
        assert_eq!(grow_for(&counters(u32::MAX), 1 << 20), Some(u32::MAX));
    }
}
