//! Order-preserving compaction of a view's indirect arguments: the slots culling kept, packed
//! to the front of their batch in slot order, and each batch's count, so a geometry pass draws
//! each batch with one `multi_draw_indexed_indirect_count` over its drawn slots only.

/// Compaction of per-slot `DrawIndexedIndirect` arguments (five words; instance count 0 where
/// culled) into `PACKED`, batch by batch.
///
/// A global exclusive scan of the drawn flags, in three dispatches: `scan_blocks` scans each
/// block of [`draw_compact::BLOCK`] slots in workgroup memory (four slots an invocation) into
/// `PREFIX` and writes the block's total to `BLOCK_SUMS`; `scan_sums` (one workgroup) turns the
/// totals into each block's offset, a block of them at a time with a carry; `scatter` gives
/// each drawn slot its place, the drawn slots before it in its batch, and writes its arguments
/// there, and the batch's last slot writes the batch's count to `COUNTS`. Slots keep their
/// order inside a batch, so drawing the packed arguments draws what the slots draw, in the same
/// order (coplanar surfaces resolve as without compaction).
#[shader_dsl::shader]
pub mod draw_compact {
    /// Invocations per workgroup.
    pub const WORKGROUP: u32 = 256;
    /// Slots per block of `scan_blocks` (four per invocation).
    pub const BLOCK: u32 = 1024;
    /// A slot in no batch.
    pub const NO_BATCH: u32 = 0xFFFF_FFFF;

    pub struct CompactParams {
        pub slot_count: u32,
        /// `slot_count` in blocks, rounded up.
        pub block_count: u32,
        pub pad0: u32,
        pub pad1: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: CompactParams;
    /// Every slot's arguments, five words each (word 1: instance count, 0 where culled).
    #[storage(group = 0, binding = 1)]
    static ARGS: [u32];
    /// Each slot's batch (`NO_BATCH` for none).
    #[storage(group = 0, binding = 2)]
    static SLOT_BATCH: [u32];
    /// Each batch's slots: first, one past the last.
    #[storage(group = 0, binding = 3)]
    static BATCHES: [UVec2];
    /// Per slot, the drawn slots before it in its block (`block_count · BLOCK` words).
    #[storage(group = 0, binding = 4, read_write)]
    static PREFIX: [u32];
    /// Per block, its drawn slots; after `scan_sums`, the drawn slots before it (`block_count`
    /// rounded up to `BLOCK` words).
    #[storage(group = 0, binding = 5, read_write)]
    static BLOCK_SUMS: [u32];
    /// The packed arguments: batch `b`'s drawn slots from its first slot on, in slot order.
    #[storage(group = 0, binding = 6, read_write)]
    static PACKED: [u32];
    /// Per batch, its drawn slots (the host clears them first).
    #[storage(group = 0, binding = 7, read_write)]
    static COUNTS: [u32];
    #[workgroup]
    static SUMS: [u32; 256];

    /// 1 where slot `slot` draws, else 0.
    fn drawn(slot: u32) -> u32 {
        let mut flag = 0u32;
        if slot < PARAMS.slot_count && ARGS[slot * 5u32 + 1u32] != 0u32 {
            flag = 1u32;
        }
        flag
    }

    /// The sum of `value` over the invocations before `t` (an exclusive scan in workgroup
    /// memory, doubling strides); `SUMS[255]` holds the total afterwards. Uniform control flow.
    fn exclusive_scan(t: u32, value: u32) -> u32 {
        SUMS[t] = value;
        workgroup_barrier();
        let mut stride = 1u32;
        while stride < 256u32 {
            let mut below = 0u32;
            if t >= stride {
                below = SUMS[t - stride];
            }
            workgroup_barrier();
            SUMS[t] = SUMS[t] + below;
            workgroup_barrier();
            stride = stride * 2u32;
        }
        SUMS[t] - value
    }

    /// Each block's drawn flags scanned into `PREFIX`, its total into `BLOCK_SUMS`.
    #[compute(workgroup_size(256, 1, 1))]
    pub fn scan_blocks(
        #[builtin(local_invocation_index)] t: u32,
        #[builtin(workgroup_id)] group: UVec3,
    ) {
        let first = group.x * BLOCK + t * 4u32;
        let flags = UVec4::new(
            drawn(first),
            drawn(first + 1u32),
            drawn(first + 2u32),
            drawn(first + 3u32),
        );
        let before = exclusive_scan(t, flags.x + flags.y + flags.z + flags.w);
        PREFIX[first] = before;
        PREFIX[first + 1u32] = before + flags.x;
        PREFIX[first + 2u32] = before + flags.x + flags.y;
        PREFIX[first + 3u32] = before + flags.x + flags.y + flags.z;
        if t == 255u32 {
            BLOCK_SUMS[group.x] = SUMS[255];
        }
    }

    /// The block totals into each block's offset (one workgroup, `BLOCK` totals at a time).
    #[compute(workgroup_size(256, 1, 1))]
    pub fn scan_sums(#[builtin(local_invocation_index)] t: u32) {
        let mut carry = 0u32;
        let mut base = 0u32;
        while base < PARAMS.block_count {
            let at = base + t * 4u32;
            let sums = UVec4::new(
                BLOCK_SUMS[at],
                BLOCK_SUMS[at + 1u32],
                BLOCK_SUMS[at + 2u32],
                BLOCK_SUMS[at + 3u32],
            );
            let before = carry + exclusive_scan(t, sums.x + sums.y + sums.z + sums.w);
            BLOCK_SUMS[at] = before;
            BLOCK_SUMS[at + 1u32] = before + sums.x;
            BLOCK_SUMS[at + 2u32] = before + sums.x + sums.y;
            BLOCK_SUMS[at + 3u32] = before + sums.x + sums.y + sums.z;
            carry = carry + SUMS[255];
            // Every invocation has read the total before the next round writes `SUMS`.
            workgroup_barrier();
            base = base + BLOCK;
        }
    }

    /// The drawn slots before `slot` in the whole list.
    fn global_prefix(slot: u32) -> u32 {
        PREFIX[slot] + BLOCK_SUMS[slot / BLOCK]
    }

    /// Each drawn slot's arguments to its place in its batch; each batch's count.
    #[compute(workgroup_size(256, 1, 1))]
    pub fn scatter(#[builtin(global_invocation_id)] gid: UVec3) {
        let slot = gid.x;
        if slot < PARAMS.slot_count {
            let batch = SLOT_BATCH[slot];
            if batch != NO_BATCH {
                let range = BATCHES[batch];
                let start = global_prefix(range.x);
                let place = global_prefix(slot) - start;
                let flag = drawn(slot);
                if flag == 1u32 {
                    let to = (range.x + place) * 5u32;
                    let from = slot * 5u32;
                    for k in 0u32..5u32 {
                        PACKED[to + k] = ARGS[from + k];
                    }
                }
                if slot + 1u32 == range.y {
                    COUNTS[batch] = place + flag;
                }
            }
        }
    }
}
