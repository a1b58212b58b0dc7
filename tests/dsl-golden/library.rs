// Golden: a library (a struct, a const, a binding it owns, a workgroup variable and a helper
// over an axis) merged into a compute module that uses it.

#[library(axes(scalarize: bool = [false, true]), requires(subgroup = scalarize))]
pub mod append {
    pub struct Item {
        pub center: Vec3,
        pub radius: f32,
    }
    pub const CAPACITY: u32 = 64;

    #[storage(group = 0, binding = 1, read_write)]
    static OUT: [u32];
    #[workgroup]
    static COUNT: Atomic<u32>;

    fn push(visible: bool, item: u32, lane: u32) {
        if scalarize {
            let ballot = subgroup_ballot(visible);
            let total = ballot.x.count_ones();
            if total > 0u32 {
                let rank = subgroup_exclusive_add(select(visible, 1u32, 0u32));
                let mut base = 0u32;
                if lane == 0u32 {
                    base = COUNT.fetch_add(total);
                }
                base = subgroup_broadcast_first(base);
                if visible && base + rank < CAPACITY {
                    OUT[base + rank] = item;
                }
            }
        } else {
            if visible {
                let slot = COUNT.fetch_add(1u32);
                if slot < CAPACITY {
                    OUT[slot] = item;
                }
            }
        }
    }
}

#[shader(
    axes(scalarize: bool = [false, true] => "scalar"),
    requires(subgroup = scalarize),
    uses(crate::append),
)]
pub mod keep_near {
    #[storage(group = 0, binding = 0)]
    static ITEMS: [Item];

    #[compute(workgroup_size(64, 1, 1))]
    pub fn main(
        #[builtin(local_invocation_index)] lid: u32,
        #[builtin(subgroup_invocation_id)] lane: u32,
    ) {
        let mut lane_id = 0u32;
        if scalarize {
            lane_id = lane;
        }
        let visible = ITEMS[lid].center.z - ITEMS[lid].radius < 10.0;
        push(visible, lid, lane_id);
    }
}
