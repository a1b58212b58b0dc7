//! Subgroup operations in whole dispatches: collectives at every subgroup size against a
//! plain-Rust answer, the active lanes of a partial last round, lanes at two different
//! operations (a uniformity error), and an append that skips a slot (an unwritten read).

use super::dispatch_tests::{bytes, compile, run, words};
use super::{Dispatch, EvalError, SUBGROUP_SIZES, Schedule};

/// Per subgroup: the exclusive prefix sum of `IN`, the total, the ballot of odd values, the
/// minimum and the first lane's value.
const SUBGROUPS: &str = "#[shader] mod m {
    #[storage(group = 0, binding = 0)]
    static IN: [u32];
    #[storage(group = 0, binding = 1, read_write)]
    static OUT: [u32];
    #[compute(workgroup_size(64, 1, 1))]
    fn main(#[builtin(global_invocation_id)] id: UVec3, #[builtin(subgroup_size)] size: u32) {
        let v = IN[id.x];
        let prefix = subgroup_exclusive_add(v);
        let total = subgroup_add(v);
        let ballot = subgroup_ballot((v & 1u32) == 1u32);
        let low = subgroup_min(v);
        let first = subgroup_broadcast_first(v);
        let base = id.x * 6u32;
        OUT[base] = prefix;
        OUT[base + 1u32] = total;
        OUT[base + 2u32] = ballot.x;
        OUT[base + 3u32] = low;
        OUT[base + 4u32] = first;
        OUT[base + 5u32] = size;
    }
}";

/// Subgroups never span workgroups (of 64 here): a subgroup of 128 holds one workgroup.
fn subgroups_expected(input: &[u32], size: usize) -> Vec<u32> {
    let mut out = vec![];
    for lanes in input.chunks(64).flat_map(|w| w.chunks(size)) {
        let mut prefix = 0;
        for &v in lanes {
            let ballot = lanes
                .iter()
                .enumerate()
                .filter(|(l, x)| *l < 32 && *x % 2 == 1)
                .fold(0u32, |b, (l, _)| b | 1 << l);
            out.extend([
                prefix,
                lanes.iter().sum(),
                ballot,
                *lanes.iter().min().unwrap(),
                lanes[0],
                size as u32,
            ]);
            prefix += v;
        }
    }
    out
}

#[test]
fn subgroup_collectives_match_plain_rust_at_every_subgroup_size() {
    let c =
        compile(&SUBGROUPS.replace("#[shader] mod m {", "#[shader(requires(subgroup))] mod m {"));
    let input: Vec<u32> = (0..128u32).map(|i| (i * 7919) % 101).collect();
    for size in SUBGROUP_SIZES {
        for schedule in [Schedule::InOrder, Schedule::Shuffled(size.into())] {
            assert_eq!(
                run(&c, schedule, size, 2, Some(&input), 128 * 6),
                Ok(subgroups_expected(&input, size as usize)),
                "subgroup size {size}, {schedule:?}"
            );
        }
    }
}

/// A loop whose last round some lanes skip: the subgroup operations in that round run over the
/// lanes still in the loop, as on hardware (`tbdr`'s light-list append does this), while the
/// lanes that left wait at the barrier after the loop, and every lane goes on past it.
#[test]
fn subgroup_operations_in_a_partial_last_round_use_the_active_lanes() {
    let c = compile(
        "#[shader(requires(subgroup))] mod m {
            #[storage(group = 0, binding = 0, read_write)]
            static OUT: [u32];
            #[compute(workgroup_size(16, 1, 1))]
            fn main(#[builtin(local_invocation_index)] lid: u32) {
                let mut i = lid;
                let mut round = 0u32;
                while i < 20u32 {
                    let rank = subgroup_exclusive_add(1u32);
                    let lanes = subgroup_add(1u32);
                    OUT[i * 2u32] = rank;
                    OUT[i * 2u32 + 1u32] = lanes;
                    i += 16u32;
                    round += 1u32;
                }
                workgroup_barrier();
                OUT[40u32 + lid] = round;
            }
        }",
    );
    for size in [4u32, 8, 16, 32] {
        let out = run(&c, Schedule::Reversed, size, 1, None, 56).unwrap();
        let rounds: Vec<u32> = (0..16).map(|lid| if lid < 4 { 2 } else { 1 }).collect();
        assert_eq!(out[40..], rounds, "rounds after the barrier, size {size}");
        for i in 0..20u32 {
            let lid = i % 16;
            // Round 0: all 16 lanes; round 1: lanes 0..4 only.
            let active = if i < 16 { 16 } else { 4 };
            let sub = size.min(16);
            let first = lid / sub * sub;
            let lanes = (first + sub).min(active) - first;
            assert_eq!(
                out[(i * 2) as usize],
                lid - first,
                "rank of item {i}, size {size}"
            );
            assert_eq!(
                out[(i * 2 + 1) as usize],
                lanes,
                "lanes of item {i}, size {size}"
            );
        }
    }
}

#[test]
fn lanes_of_one_subgroup_at_two_subgroup_operations_are_a_uniformity_error() {
    let c = compile(
        "#[shader(requires(subgroup))] mod m {
            #[storage(group = 0, binding = 0, read_write)]
            static OUT: [u32];
            #[compute(workgroup_size(8, 1, 1))]
            fn main(#[builtin(local_invocation_index)] lid: u32) {
                if lid == 1u32 {
                    OUT[lid] = subgroup_add(1u32);
                }
                OUT[lid] = subgroup_add(2u32);
            }
        }",
    );
    let err = run(&c, Schedule::InOrder, 8, 1, None, 8).unwrap_err();
    let text = err.to_string();
    assert!(matches!(err.cause(), EvalError::Uniformity(_)), "{text}");
    assert!(text.contains("invocation 1 subgroupAdd at 7:32"), "{text}");
}

/// Odd invocations append their index to `LIST`, one atomic per subgroup and each lane at its
/// rank (`rank_op`); after a barrier, invocation `i` below the count copies `LIST[i]` to `OUT`.
fn subgroup_append(rank_op: &str) -> String {
    format!(
        "#[shader(requires(subgroup))] mod m {{
            #[storage(group = 0, binding = 0, read_write)]
            static OUT: [u32];
            #[workgroup]
            static COUNT: Atomic<u32>;
            #[workgroup]
            static LIST: [u32; 64];
            #[compute(workgroup_size(32, 1, 1))]
            fn main(#[builtin(local_invocation_index)] lid: u32) {{
                let one = select((lid & 1u32) == 1u32, 1u32, 0u32);
                let rank = {rank_op}(one);
                let hits = subgroup_add(one);
                let mut base = 0u32;
                if subgroup_broadcast_first(lid) == lid {{
                    base = COUNT.fetch_add(hits);
                }}
                base = subgroup_broadcast_first(base);
                if one == 1u32 {{
                    LIST[base + rank] = lid;
                }}
                workgroup_barrier();
                if lid < COUNT.load() {{
                    OUT[lid] = LIST[lid];
                }}
            }}
        }}"
    )
}

#[test]
fn an_append_that_skips_a_slot_is_an_unwritten_read_naming_the_line() {
    let checked = |c: &crate::Compiled, subgroup: u32| -> Result<Vec<u32>, EvalError> {
        let mut d = Dispatch::new(&c.module, &c.keys[0].env, "main")?
            .with_subgroup_size(subgroup)?
            .with_unwritten_read_check(true);
        d.set_buffer("OUT", &bytes(&[0; 32]))?;
        d.run([1, 1, 1])?;
        Ok(words(&d.buffer("OUT")?))
    };
    let good = compile(&subgroup_append("subgroup_exclusive_add"));
    let off_by_one = compile(&subgroup_append("subgroup_inclusive_add"));
    for subgroup in [4, 8, 32] {
        let mut out = checked(&good, subgroup).unwrap();
        out[..16].sort_unstable();
        let odd: Vec<u32> = (0..16).map(|i| 2 * i + 1).collect();
        assert_eq!(out[..16], odd, "subgroup {subgroup}");
        let err = checked(&off_by_one, subgroup).unwrap_err();
        let text = err.to_string();
        assert!(
            matches!(err.cause(), EvalError::Unwritten(_)),
            "subgroup {subgroup}: {text}"
        );
        // Line 23 reads `LIST[lid]`; slot 0 is the one the inclusive add skipped.
        assert!(text.contains("reads `LIST[0]` at 23:"), "{text}");
    }
    // Unchecked (the default), the same kernel runs and reads WGSL's zero.
    let mut d = Dispatch::new(&off_by_one.module, &off_by_one.keys[0].env, "main")
        .unwrap()
        .with_subgroup_size(8)
        .unwrap();
    d.set_buffer("OUT", &bytes(&[7; 32])).unwrap();
    d.run([1, 1, 1]).unwrap();
    assert_eq!(words(&d.buffer("OUT").unwrap())[0], 0);
}
