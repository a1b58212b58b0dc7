//! Small GPU → CPU copies without stalling a frame: each frame's words are copied into one of a
//! ring of staging buffers and mapped asynchronously; a later frame picks up whatever has
//! arrived (culling counters, particle counters).

use std::sync::Arc;
use std::sync::atomic::{AtomicU8, Ordering};

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

/// A ring of staging buffers that brings a few words back from the GPU asynchronously.
#[derive(Debug)]
pub struct ReadbackRing {
    slots: Vec<Slot>,
    bytes: u64,
}

impl ReadbackRing {
    /// Frames that may be in flight before a frame's counters are skipped.
    pub const DEPTH: usize = 3;

    /// A ring bringing back `words` 32-bit words a frame.
    pub fn new(device: &wgpu::Device, label: &str, words: u64) -> Self {
        let slots = (0..Self::DEPTH)
            .map(|_| Slot {
                buffer: device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: words * 4,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }),
                state: Arc::new(AtomicU8::new(FREE)),
                frame: 0,
            })
            .collect();
        Self {
            slots,
            bytes: words * 4,
        }
    }

    /// Records copies of `sources` (each `(buffer, bytes)` from its start, laid one after the
    /// other, together the ring's words) for `frame`. Returns `false` when every slot is still
    /// in flight (the GPU is more than [`Self::DEPTH`] frames behind); that frame is not sampled.
    pub fn record(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        sources: &[(&wgpu::Buffer, u64)],
        frame: u64,
    ) -> bool {
        let Some(slot) = self
            .slots
            .iter_mut()
            .find(|s| s.state.load(Ordering::Acquire) == FREE)
        else {
            return false;
        };
        let mut at = 0;
        for &(buffer, bytes) in sources {
            let bytes = bytes.min(self.bytes - at);
            encoder.copy_buffer_to_buffer(buffer, 0, &slot.buffer, at, bytes);
            at += bytes;
        }
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

    /// Without blocking, returns the words of the newest frame whose copy has arrived.
    pub fn poll(&mut self, device: &wgpu::Device) -> Option<(u64, Vec<u32>)> {
        // Non-blocking: only runs callbacks of work that is already done.
        let _ = device.poll(wgpu::PollType::Poll);
        let mut newest: Option<(u64, Vec<u32>)> = None;
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
                        && newest.as_ref().is_none_or(|(f, _)| slot.frame > *f)
                    {
                        newest = Some((slot.frame, w));
                    }
                }
                FAILED => slot.state.store(FREE, Ordering::Release),
                _ => {}
            }
        }
        newest
    }
}
