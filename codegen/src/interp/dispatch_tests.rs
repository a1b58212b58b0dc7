//! Whole dispatches: workgroup memory and barriers under every schedule (and a deleted barrier
//! caught), atomics across workgroups (64-bit `fetch_min`/`fetch_max` too), matrices, textures,
//! and errors that name the invocation and the line. Subgroup operations are in `dispatch_subgroup_tests`.

use super::{Dispatch, EvalError, Schedule};

pub(super) fn compile(src: &str) -> crate::Compiled {
    crate::compile_source(src).unwrap_or_else(|e| panic!("{e}\n{src}"))
}

pub(super) fn words(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

pub(super) fn bytes(words: &[u32]) -> Vec<u8> {
    words.iter().flat_map(|w| w.to_le_bytes()).collect()
}

/// Runs `entry` over `groups` workgroups with `OUT` holding `out_len` zero words (and `IN`
/// holding `input` when given); `OUT` afterwards.
pub(super) fn run(
    c: &crate::Compiled,
    schedule: Schedule,
    subgroup: u32,
    groups: u32,
    input: Option<&[u32]>,
    out_len: usize,
) -> Result<Vec<u32>, EvalError> {
    let mut d = Dispatch::new(&c.module, &c.keys[0].env, "main")?
        .with_subgroup_size(subgroup)?
        .with_schedule(schedule);
    d.set_buffer("OUT", &bytes(&vec![0; out_len]))?;
    if let Some(input) = input {
        d.set_buffer("IN", &bytes(input))?;
    }
    d.run([groups, 1, 1])?;
    Ok(words(&d.buffer("OUT")?))
}

const SCHEDULES: [Schedule; 3] = [Schedule::InOrder, Schedule::Reversed, Schedule::Shuffled(7)];

/// Each invocation writes its slot of workgroup memory, then reads its neighbours'.
fn neighbours(barrier: &str) -> String {
    format!(
        "#[shader] mod m {{
            #[storage(group = 0, binding = 0, read_write)]
            static OUT: [u32];
            #[workgroup]
            static SLOTS: [u32; 16];
            #[compute(workgroup_size(16, 1, 1))]
            fn main(#[builtin(local_invocation_index)] lid: u32, #[builtin(workgroup_id)] wg: UVec3) {{
                SLOTS[lid] = lid * 10u32 + wg.x;
                {barrier}
                let left = SLOTS[(lid + 15u32) % 16u32];
                let right = SLOTS[(lid + 1u32) % 16u32];
                OUT[wg.x * 16u32 + lid] = left + right;
            }}
        }}"
    )
}

fn neighbours_expected(groups: u32) -> Vec<u32> {
    (0..groups)
        .flat_map(|g| (0..16u32).map(move |l| ((l + 15) % 16) * 10 + g + ((l + 1) % 16) * 10 + g))
        .collect()
}

#[test]
fn workgroup_memory_after_a_barrier_is_the_same_under_every_schedule() {
    let c = compile(&neighbours("workgroup_barrier();"));
    for schedule in SCHEDULES {
        assert_eq!(
            run(&c, schedule, 32, 3, None, 48),
            Ok(neighbours_expected(3)),
            "{schedule:?}"
        );
    }
}

#[test]
fn a_deleted_barrier_gives_a_wrong_answer_under_some_schedule() {
    let c = compile(&neighbours(""));
    for schedule in [Schedule::InOrder, Schedule::Reversed] {
        let mut d = Dispatch::new(&c.module, &c.keys[0].env, "main")
            .unwrap()
            .with_schedule(schedule)
            .with_race_detection(false);
        d.set_buffer("OUT", &bytes(&[0; 16])).unwrap();
        d.run([1, 1, 1]).unwrap();
        let out = words(&d.buffer("OUT").unwrap());
        assert_ne!(
            out,
            neighbours_expected(1),
            "{schedule:?} hid the missing barrier"
        );
    }
}

#[test]
fn a_deleted_barrier_is_a_data_race_naming_the_write_and_the_read() {
    let c = compile(&neighbours(""));
    for schedule in SCHEDULES {
        let err = run(&c, schedule, 32, 1, None, 16).unwrap_err();
        let text = err.to_string();
        assert!(
            matches!(err.cause(), EvalError::Race(_)),
            "{schedule:?}: {text}"
        );
        // The write is on line 8 (`SLOTS[lid] = ..`), the reads on lines 10 and 11.
        assert!(text.contains("wrote `SLOTS["), "{text}");
        assert!(text.contains(" at 8:"), "{schedule:?}: {text}");
        assert!(
            text.contains(" at 10:") || text.contains(" at 11:"),
            "{schedule:?}: {text}"
        );
    }
    // With the barrier, the same accesses are ordered: no race.
    let fixed = compile(&neighbours("workgroup_barrier();"));
    assert!(run(&fixed, Schedule::Reversed, 32, 1, None, 16).is_ok());
}

#[test]
fn workgroup_memory_starts_at_zero_in_every_workgroup() {
    let c = compile(
        "#[shader] mod m {
            #[storage(group = 0, binding = 0, read_write)]
            static OUT: [u32];
            #[workgroup]
            static SUM: Atomic<u32>;
            #[compute(workgroup_size(8, 1, 1))]
            fn main(#[builtin(local_invocation_index)] lid: u32, #[builtin(workgroup_id)] wg: UVec3) {
                SUM.fetch_add(lid + 1u32);
                workgroup_barrier();
                if lid == 0u32 { OUT[wg.x] = SUM.load(); }
            }
        }",
    );
    assert_eq!(run(&c, Schedule::Reversed, 32, 3, None, 3), Ok(vec![36; 3]));
}

#[test]
fn storage_atomics_count_across_workgroups() {
    let c = compile(
        "#[shader] mod m {
            #[storage(group = 0, binding = 0, read_write)]
            static OUT: [Atomic<u32>];
            #[compute(workgroup_size(32, 1, 1))]
            fn main(#[builtin(global_invocation_id)] id: UVec3) {
                OUT[0].fetch_add(1u32);
                OUT[1].fetch_max(id.x);
                OUT[2].fetch_or(1u32 << (id.x % 32u32));
                let old = OUT[3].swap(id.x);
                OUT[4].fetch_add(old);
            }
        }",
    );
    let out = run(&c, Schedule::InOrder, 32, 4, None, 5).unwrap();
    // In order, each swap returns the previous invocation's index: 0 + 0 + 1 + .. + 126.
    assert_eq!(out, vec![128, 127, u32::MAX, 127, (0..127).sum()]);
}

#[test]
fn an_out_of_bounds_write_names_the_invocation_and_the_line() {
    let c = compile(
        "#[shader] mod m {
            #[storage(group = 0, binding = 0, read_write)]
            static OUT: [u32];
            #[compute(workgroup_size(4, 1, 1))]
            fn main(#[builtin(global_invocation_id)] id: UVec3) {
                OUT[id.x + 1u32] = id.x;
            }
        }",
    );
    let err = run(&c, Schedule::InOrder, 32, 1, None, 4).unwrap_err();
    let text = err.to_string();
    assert_eq!(
        *err.cause(),
        EvalError::OutOfBounds { index: 4, len: 4 },
        "{text}"
    );
    assert!(
        text.contains("invocation 3 of workgroup [0, 0, 0]"),
        "{text}"
    );
    assert!(text.contains("(at 6:"), "{text}");
}

#[test]
fn a_barrier_some_invocations_skip_is_a_uniformity_error_with_both_places() {
    let c = compile(
        "#[shader] mod m {
            #[storage(group = 0, binding = 0, read_write)]
            static OUT: [u32];
            #[compute(workgroup_size(8, 1, 1))]
            fn main(#[builtin(local_invocation_index)] lid: u32) {
                if lid < 4u32 {
                    workgroup_barrier();
                } else {
                    storage_barrier();
                }
                OUT[lid] = 1u32;
            }
        }",
    );
    let err = run(&c, Schedule::InOrder, 32, 1, None, 8).unwrap_err();
    let text = err.to_string();
    assert!(matches!(err.cause(), EvalError::Uniformity(_)), "{text}");
    assert!(
        text.contains("invocations 0–3 workgroupBarrier at 7:21")
            && text.contains("invocations 4–7 storageBarrier at 9:21"),
        "{text}"
    );
}

#[test]
fn matrices_multiply_as_glam_does() {
    let c = compile(
        "#[shader] mod m {
            #[storage(group = 0, binding = 0)]
            static IN: [Mat4];
            #[storage(group = 0, binding = 1, read_write)]
            static OUT: [Vec4];
            #[compute(workgroup_size(1, 1, 1))]
            fn main() {
                let m = IN[0];
                let n = IN[1];
                let v = Vec4::new(1.0, -2.0, 0.5, 1.0);
                OUT[0] = m * v;
                OUT[1] = (m * n) * v;
                OUT[2] = v * m;
                OUT[3] = m.transpose() * v;
            }
        }",
    );
    let m = glam::Mat4::from_cols_array(&std::array::from_fn(|i| (i as f32 * 0.37).sin()));
    let n =
        glam::Mat4::from_rotation_y(0.3) * glam::Mat4::from_translation(glam::vec3(1.0, 2.0, -3.0));
    let v = glam::vec4(1.0, -2.0, 0.5, 1.0);
    let mut d = Dispatch::new(&c.module, &c.keys[0].env, "main").unwrap();
    d.set_buffer("IN", bytemuck::cast_slice(&[m, n])).unwrap();
    d.set_buffer("OUT", &[0; 64]).unwrap();
    d.run([1, 1, 1]).unwrap();
    let out: Vec<glam::Vec4> = bytemuck::cast_slice::<u8, f32>(&d.buffer("OUT").unwrap())
        .chunks(4)
        .map(glam::Vec4::from_slice)
        .collect();
    let want = [m * v, (m * n) * v, m.transpose() * v, m.transpose() * v];
    for (got, want) in out.iter().zip(want) {
        assert!(got.abs_diff_eq(want, 1e-5), "{got} vs {want}");
    }
}

/// Bilinear sampling, clamp-to-edge and repeat addressing, depth comparison (PCF) and storage
/// texture writes, against values worked out by hand.
#[test]
fn textures_sample_compare_and_store_as_the_rules_say() {
    use super::{Address, Compare, HostSampler, HostTexture};
    use crate::interp::Value;
    let c = compile(
        "#[shader] mod m {
            #[texture(group = 0, binding = 0)]
            static COLOR: Texture2d<f32>;
            #[texture(group = 0, binding = 1)]
            static DEPTH: TextureDepth2d;
            #[sampler(group = 0, binding = 2)]
            static LINEAR: Sampler;
            #[sampler(group = 0, binding = 3)]
            static SHADOW: SamplerComparison;
            #[texture(group = 0, binding = 4)]
            static DST: StorageTexture2d<Rgba32Float, Write>;
            #[storage(group = 0, binding = 5, read_write)]
            static OUT: [f32];
            #[compute(workgroup_size(1, 1, 1))]
            fn main() {
                // Between the four texels of a 2x2 texture, at a texel centre, past the edge.
                OUT[0] = COLOR.sample_level(LINEAR, Vec2::new(0.5, 0.5), 0.0).x;
                OUT[1] = COLOR.sample_level(LINEAR, Vec2::new(0.25, 0.25), 0.0).x;
                OUT[2] = COLOR.sample_level(LINEAR, Vec2::new(-1.0, 0.25), 0.0).x;
                // Depth 0.2 | 0.8, reference 0.5 compared `reference <= texel`: it passes
                // against the second texel only; half of each between them.
                OUT[3] = DEPTH.sample_compare_level(SHADOW, Vec2::new(0.5, 0.5), 0.5);
                OUT[4] = DEPTH.sample_compare_level(SHADOW, Vec2::new(0.75, 0.5), 0.5);
                DST.store(UVec2::new(1u32, 0u32), Vec4::new(1.0, 2.0, 3.0, 4.0));
            }
        }",
    );
    let mut d = Dispatch::new(&c.module, &c.keys[0].env, "main").unwrap();
    let rgba = |x: f32| Value::Vector(vec![Value::F32(x); 4]);
    d.set_texture(
        "COLOR",
        HostTexture {
            width: 2,
            height: 2,
            layers: 1,
            samples: 1,
            texels: vec![rgba(0.0), rgba(1.0), rgba(2.0), rgba(3.0)],
        },
    )
    .unwrap();
    d.set_texture("DEPTH", HostTexture::depth(2, 1, 1, &[0.2, 0.8]))
        .unwrap();
    let clamp = HostSampler {
        linear: true,
        address: Address::ClampToEdge,
        compare: None,
    };
    d.set_sampler("LINEAR", clamp).unwrap();
    d.set_sampler(
        "SHADOW",
        HostSampler {
            compare: Some(Compare::LessEqual),
            ..clamp
        },
    )
    .unwrap();
    d.set_texture(
        "DST",
        HostTexture {
            width: 2,
            height: 1,
            layers: 1,
            samples: 1,
            texels: vec![rgba(0.0), rgba(0.0)],
        },
    )
    .unwrap();
    d.set_buffer("OUT", &[0; 20]).unwrap();
    d.run([1, 1, 1]).unwrap();
    let out: Vec<f32> = words(&d.buffer("OUT").unwrap())
        .into_iter()
        .map(f32::from_bits)
        .collect();
    // Centre: the mean of 0, 1, 2, 3; texel (0, 0)'s centre: 0; past the left edge at row 0.5:
    // clamped to column 0 between rows 0 and 1 at weight 0: texel (0, 0) = 0.
    assert_eq!(out, vec![1.5, 0.0, 0.0, 0.5, 1.0]);
    let dst = d.texture("DST").unwrap();
    assert_eq!(
        dst.texels[1],
        Value::Vector(
            vec![1.0, 2.0, 3.0, 4.0]
                .into_iter()
                .map(Value::F32)
                .collect()
        )
    );
    assert_eq!(dst.texels[0], rgba(0.0));
}

/// The visibility buffer's packing: every invocation `fetch_min`s (and `fetch_max`es) its
/// `key << 32 | id` into a slot shared with others; each slot ends at the CPU's minimum (and
/// maximum) over the invocations that share it, whatever the order they run in. Keys repeat (ties
/// broken by the id), cross bit 31 (an unsigned comparison) and are never 0, so a cleared slot
/// (`u64::MAX`, both words) is above every value.
#[test]
fn u64_atomic_min_max_pack_keys_and_ids() {
    let c = compile(
        "#[shader] mod m {
            #[storage(group = 0, binding = 0)]
            static IN: [u32];
            #[storage(group = 0, binding = 1, read_write)]
            static VIS64: [Atomic<u64>];
            #[storage(group = 0, binding = 2, read_write)]
            static FAR64: [Atomic<u64>];
            #[compute(workgroup_size(32, 1, 1))]
            fn main(#[builtin(global_invocation_id)] gid: UVec3) {
                let id = gid.x;
                let packed: u64 = ((IN[id] as u64) << 32u32) | (id as u64);
                let slot = id % 8u32;
                VIS64[slot].fetch_min(packed);
                let _ = FAR64[slot].fetch_max(packed);
            }
        }",
    );
    assert!(c.variants[0].reflection.features.int64);
    let n = 4 * 32;
    let keys: Vec<u32> = (0..n)
        .map(|i: u32| ((i.wrapping_mul(2_654_435_761) >> 13) % 3 + 1) * 0x4000_0000 + (i % 3))
        .collect();
    let packed = |i: u32| (u64::from(keys[i as usize]) << 32) | u64::from(i);
    let u64s = |b: &[u8]| -> Vec<u64> {
        b.chunks_exact(8)
            .map(|w| u64::from_le_bytes(w.try_into().unwrap()))
            .collect()
    };
    let expected_min: Vec<u64> = (0..8)
        .map(|s| (s..n).step_by(8).map(packed).min().unwrap())
        .collect();
    let expected_max: Vec<u64> = (0..8)
        .map(|s| (s..n).step_by(8).map(packed).max().unwrap())
        .collect();
    // The keys decide: a slot's minimum is not its first invocation's.
    assert!(
        (0..8).any(|s| expected_min[s] != packed(s as u32)),
        "{expected_min:x?}"
    );
    assert!(
        expected_max.iter().all(|m| m >> 63 == 1),
        "{expected_max:x?}"
    );
    for schedule in SCHEDULES {
        let mut d = Dispatch::new(&c.module, &c.keys[0].env, "main")
            .unwrap()
            .with_schedule(schedule);
        d.set_buffer("IN", &bytes(&keys)).unwrap();
        let max: Vec<u8> = [u64::MAX; 8].iter().flat_map(|w| w.to_le_bytes()).collect();
        d.set_buffer("VIS64", &max).unwrap();
        d.set_buffer("FAR64", &[0; 64]).unwrap();
        d.run([4, 1, 1]).unwrap();
        assert_eq!(
            u64s(&d.buffer("VIS64").unwrap()),
            expected_min,
            "{schedule:?}"
        );
        assert_eq!(
            u64s(&d.buffer("FAR64").unwrap()),
            expected_max,
            "{schedule:?}"
        );
    }
}

/// `uniform_load()`: invocation 0's write and every invocation's atomic add, then one value for
/// the whole workgroup, which bounds a loop with barriers in it.
const UNIFORM_LOAD: &str = "#[shader] mod m {
    #[storage(group = 0, binding = 0, read_write)]
    static OUT: [u32];
    #[workgroup]
    static ROUNDS: u32;
    #[workgroup]
    static COUNT: Atomic<u32>;
    #[compute(workgroup_size(8, 1, 1))]
    fn main(#[builtin(local_invocation_index)] lid: u32, #[builtin(workgroup_id)] wg: UVec3) {
        if lid == 0u32 {
            ROUNDS = wg.x + 2u32;
        }
        COUNT.fetch_add(1u32);
        let rounds = ROUNDS.uniform_load();
        let count = COUNT.uniform_load();
        let mut sum = 0u32;
        for r in 0u32..rounds {
            workgroup_barrier();
            sum += r;
        }
        OUT[wg.x * 8u32 + lid] = sum * 100u32 + count;
    }
}";

#[test]
fn uniform_load_is_a_barrier_then_one_value_for_the_workgroup() {
    let c = compile(UNIFORM_LOAD);
    let wgsl = &c.variants[0].wgsl;
    assert!(
        wgsl.contains("workgroupUniformLoad(&ROUNDS)")
            && wgsl.contains("workgroupUniformLoad(&COUNT)"),
        "{wgsl}"
    );
    // Workgroup g: g + 2 rounds summing 0..g + 2, and all 8 invocations counted.
    let expected: Vec<u32> = (0..2u32)
        .flat_map(|g| vec![(0..g + 2).sum::<u32>() * 100 + 8; 8])
        .collect();
    for schedule in SCHEDULES {
        assert_eq!(
            run(&c, schedule, 32, 2, None, 16).unwrap(),
            expected,
            "{schedule:?}"
        );
    }
}

#[test]
fn uniform_load_some_invocations_skip_is_a_uniformity_error() {
    let skipped = UNIFORM_LOAD.replace(
        "let rounds = ROUNDS.uniform_load();",
        "let mut rounds = 1u32;\n        if lid < 4u32 { rounds = ROUNDS.uniform_load(); }",
    );
    let c = compile(&skipped);
    let err = run(&c, Schedule::InOrder, 32, 1, None, 8).unwrap_err();
    let text = err.to_string();
    assert!(matches!(err.cause(), EvalError::Uniformity(_)), "{text}");
    assert!(text.contains("workgroupUniformLoad"), "{text}");
}
