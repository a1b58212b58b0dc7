//! Overflow handling without stalling the frame: the counters of each culling dispatch come back
//! through a [`crate::readback_ring::ReadbackRing`]; a later frame picks up whatever has arrived,
//! and [`grow_for`] decides the capacities for the next frame.
//!
//! Nothing is dropped silently: every result that arrives is returned to the caller, which
//! reports it, and a grown capacity takes effect on the next frame.

use super::lists::CullCounters;

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
