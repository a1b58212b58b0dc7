// Golden: subgroup builtins and every subgroup operation, behind an axis. Variants without the
// capability drop the subgroup builtin parameters and the guarded code, and fall back to
// storage-buffer atomics.
#[shader_dsl::shader(axes(wave: bool = [false, true]), requires(subgroup = wave))]
pub mod subgroups {
    pub struct Counters {
        pub total: Atomic<u32>,
        pub max_value: Atomic<u32>,
    }

    #[storage(group = 0, binding = 0)]
    static INPUT: [u32];
    #[storage(group = 0, binding = 1, read_write)]
    static OUTPUT: [u32];
    #[storage(group = 0, binding = 2, read_write)]
    static COUNTERS: Counters;

    #[compute(workgroup_size(64))]
    pub fn compact(
        #[builtin(global_invocation_id)] gid: UVec3,
        #[builtin(subgroup_size)] lanes: u32,
        #[builtin(subgroup_invocation_id)] lane: u32,
    ) {
        let value = INPUT[gid.x];
        let keep = value % 3u32 == 0u32;
        if wave {
            let ballot = subgroup_ballot(keep);
            let kept = ballot.x.count_ones() + ballot.y.count_ones() + ballot.z.count_ones() + ballot.w.count_ones();
            let slot = subgroup_exclusive_add(select(keep, 1u32, 0u32));
            let running = subgroup_inclusive_add(value);
            let mut base = 0u32;
            if lane == 0u32 {
                base = COUNTERS.total.fetch_add(kept);
            }
            base = subgroup_broadcast_first(base);
            if keep {
                OUTPUT[base + slot] = value;
            }
            let hi = subgroup_max(value);
            let lo = subgroup_min(value);
            let sum = subgroup_add(value);
            if subgroup_all(hi >= lo) && subgroup_any(keep) && lane + 1u32 == lanes {
                COUNTERS.max_value.fetch_max(hi + sum * 0u32 + running * 0u32);
            }
            let neighbour = subgroup_shuffle(value, (lane + 1u32) % lanes);
            OUTPUT[gid.x + 1024u32] = neighbour;
        } else {
            if keep {
                let slot = COUNTERS.total.fetch_add(1u32);
                OUTPUT[slot] = value;
            }
            COUNTERS.max_value.fetch_max(value);
        }
    }
}
