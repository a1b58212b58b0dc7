//! The regions a light holds, as etagere allocations: allocating a light's faces all or
//! nothing, and freeing them.

use etagere::{AllocId, AtlasAllocator, size2};

use super::request::AtlasRect;

/// Most regions held at once. etagere indexes its items with `u16`, and each region can split
/// one free item in two, so the count stays well below that.
pub(super) const MAX_REGIONS: u64 = 16384;

/// The regions a light holds.
#[derive(Debug, Clone)]
pub(super) struct Held {
    pub(super) side: u32,
    pub(super) rects: Vec<AtlasRect>,
    pub(super) ids: Vec<AllocId>,
}

/// `size` as etagere's `i32`; sides are at most [`MAX_ATLAS_SIZE`](super::MAX_ATLAS_SIZE) by construction here, and
/// anything larger saturates (and then fails to allocate instead of wrapping).
pub(super) fn side_i32(side: u32) -> i32 {
    i32::try_from(side).unwrap_or(i32::MAX)
}

/// A fresh allocator covering the whole `size`² atlas.
pub(super) fn empty_allocator(size: u32) -> AtlasAllocator {
    AtlasAllocator::new(size2(side_i32(size), side_i32(size)))
}

/// Allocates `faces` regions of `side`²; on failure frees what it took and returns `None`.
pub(super) fn allocate(allocator: &mut AtlasAllocator, faces: u32, side: u32) -> Option<Held> {
    let mut held = Held {
        side,
        rects: Vec::new(),
        ids: Vec::new(),
    };
    for _ in 0..faces {
        let Some(allocation) = allocator.allocate(size2(side_i32(side), side_i32(side))) else {
            release(allocator, &held.ids);
            return None;
        };
        // etagere may hand out a slightly larger rectangle (shelf and item rounding); the
        // region is its top-left `side`² corner. Its corner is never negative.
        let min = allocation.rectangle.min;
        held.rects.push(AtlasRect {
            x: min.x.unsigned_abs(),
            y: min.y.unsigned_abs(),
            side,
        });
        held.ids.push(allocation.id);
    }
    Some(held)
}

/// Frees regions this allocator handed out (each id exactly once: callers drop the `Held`).
pub(super) fn release(allocator: &mut AtlasAllocator, ids: &[AllocId]) {
    for &id in ids {
        allocator.deallocate(id);
    }
}
