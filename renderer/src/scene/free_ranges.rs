//! Free space in a growable run of elements (vertices, indices, records), by range: gfx-rs's
//! best-fit [`range_alloc::RangeAllocator`], made cloneable so the scene that holds it can be
//! copied on write while a frame still holds the old one.

use std::ops::Range;

use range_alloc::RangeAllocator;

/// Which ranges of `0..capacity` are taken.
#[derive(Debug)]
pub(crate) struct FreeRanges(RangeAllocator<u64>);

impl FreeRanges {
    /// `0..capacity`, with `0..taken` taken.
    pub(crate) fn new(capacity: u64, taken: u64) -> Self {
        let mut ranges = Self(RangeAllocator::new(0..capacity));
        ranges.take(taken);
        ranges
    }

    /// The room: one past the last element.
    pub(crate) fn capacity(&self) -> u64 {
        self.0.initial_range().end
    }

    /// Elements taken.
    pub(crate) fn taken(&self) -> u64 {
        self.capacity() - self.0.total_available()
    }

    /// Takes `length` elements where they fit best, or `None` when no free range is that long.
    /// An empty length takes the empty range at 0.
    pub(crate) fn take(&mut self, length: u64) -> Option<Range<u64>> {
        if length == 0 {
            return Some(0..0);
        }
        self.0.allocate_range(length).ok()
    }

    /// Gives `range` back (an empty one is nothing).
    pub(crate) fn give_back(&mut self, range: Range<u64>) {
        if !range.is_empty() {
            self.0.free_range(range);
        }
    }

    /// Room up to `capacity` (no less than now).
    pub(crate) fn grow_to(&mut self, capacity: u64) {
        if capacity > self.capacity() {
            self.0.grow_to(capacity);
        }
    }

    /// One past the last element taken: what a copy into a larger run must keep.
    pub(crate) fn end_taken(&self) -> u64 {
        self.0.allocated_ranges().map(|r| r.end).max().unwrap_or(0)
    }
}

impl Clone for FreeRanges {
    /// The same taken and free ranges: everything taken, then every gap between taken ranges
    /// given back.
    fn clone(&self) -> Self {
        let capacity = self.capacity();
        let mut copy = Self::new(capacity, capacity);
        let mut next = 0;
        for taken in self.0.allocated_ranges() {
            copy.give_back(next..taken.start);
            next = taken.end;
        }
        copy.give_back(next..capacity);
        copy
    }
}

#[cfg(test)]
mod tests {
    use super::FreeRanges;

    #[test]
    fn ranges_given_back_are_taken_again_and_clones_keep_the_gaps() {
        let mut ranges = FreeRanges::new(100, 40);
        assert_eq!(ranges.take(10), Some(40..50));
        ranges.give_back(10..20);
        ranges.give_back(30..40);
        // 0..10, 20..30 and 40..50 are taken.
        assert_eq!(ranges.taken(), 30);
        let copy = ranges.clone();
        for r in [&mut ranges, &mut copy.clone()] {
            // Best fit: the 10-long gaps before the 50-long tail.
            assert_eq!(r.take(10), Some(10..20));
            assert_eq!(r.take(10), Some(30..40));
            assert_eq!(r.take(60), None);
            r.grow_to(110);
            assert_eq!(r.take(60), Some(50..110));
            assert_eq!(r.end_taken(), 110);
        }
        assert_eq!(copy.taken(), 30);
        assert_eq!(copy.end_taken(), 50);
        assert_eq!(ranges.take(0), Some(0..0));
    }
}
