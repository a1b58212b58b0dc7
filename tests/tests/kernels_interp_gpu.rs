//! `shaders_gen` compute kernels beyond culling, run by the DSL's host interpreter, against the
//! same kernels on the GPU and an independent CPU answer, at subgroup sizes 4, 8, 32 and 64 and
//! under several schedules; each with a mutation (a deleted barrier) that must be caught.
//!
//! `particle_sort`: the bitonic sort in workgroup memory (a barrier after every step), host
//! steps planned as `renderer::passes::particles::GpuSort` plans them.

use codegen::interp::{Dispatch, EvalError, Schedule};
use glam::UVec2;
use renderer::passes::particles::{GpuSort, sort::padded_count};
use renderer::readback::read_buffer;
use shaders_gen::particles::particle_sort::{BLOCK, SortParams, WORKGROUP};
use tests::cull_scene::Rng;
use tests::gpu::gpu_test;

const SORT_SOURCE: &str = include_str!("../../shaders_gen/src/particles/sort.rs");

fn compile(source: &str) -> codegen::Compiled {
    codegen::compile_source(source).unwrap_or_else(|e| panic!("{e}"))
}

/// The pairs a sort test sorts: few distinct keys, so payloads decide many orders; padded to
/// the sort's size with `u32::MAX` pairs, as the renderer pads.
fn pairs(items: u32, seed: u64) -> Vec<UVec2> {
    let mut rng = Rng::new(seed);
    let mut pairs: Vec<UVec2> = (0..items)
        .map(|i| UVec2::new((rng.next_u64() % 97) as u32 * 1000, i ^ 0x55))
        .collect();
    pairs.resize(padded_count(items) as usize, UVec2::splat(u32::MAX));
    pairs
}

fn gpu_sort(padded: &[UVec2], items: u32) -> Vec<UVec2> {
    gpu_test(|gpu| {
        let sort = GpuSort::new(gpu, items, wgpu::BufferUsages::empty()).expect("sort");
        gpu.queue
            .write_buffer(&sort.keys, 0, bytemuck::cast_slice(padded));
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        sort.record_in(&mut encoder);
        gpu.queue.submit([encoder.finish()]);
        read_buffer::<UVec2>(&gpu.device, &gpu.queue, &sort.keys).expect("readback")
    })
}

/// The sort on the host: `sort_local`, then per stage `k` its global steps and `merge_local`.
fn host_sort(
    c: &codegen::Compiled,
    pairs: &[UVec2],
    subgroup_size: u32,
    schedule: Schedule,
) -> Result<Vec<UVec2>, EvalError> {
    let n = pairs.len() as u32;
    let mut steps = vec![("sort_local", 0, 0, n / BLOCK)];
    let mut k = BLOCK * 2;
    while k <= n {
        let mut j = k / 2;
        while j >= BLOCK {
            steps.push(("merge_global", k, j, (n / 2).div_ceil(WORKGROUP)));
            j /= 2;
        }
        steps.push(("merge_local", k, 0, n / BLOCK));
        k *= 2;
    }
    let mut keys: Vec<u8> = bytemuck::cast_slice(pairs).to_vec();
    for (entry, k, j, groups) in steps {
        let mut d = Dispatch::new(&c.module, &c.keys[0].env, entry)?
            .with_subgroup_size(subgroup_size)?
            .with_schedule(schedule);
        d.set_buffer("PARAMS", bytemuck::bytes_of(&SortParams::new(k, j, n, 0)))?;
        d.set_buffer("KEYS", &keys)?;
        d.run([groups, 1, 1])?;
        keys = d.buffer("KEYS")?;
    }
    Ok(bytemuck::pod_collect_to_vec(&keys))
}

const RUNS: [(u32, Schedule); 4] = [
    (4, Schedule::InOrder),
    (8, Schedule::Reversed),
    (32, Schedule::Shuffled(5)),
    (64, Schedule::Reversed),
];

#[test]
fn host_bitonic_sort_equals_the_gpu_and_the_cpu_sort() {
    let c = compile(SORT_SOURCE);
    // Two blocks: the block sort, one global step and one local merge.
    let items = 1000;
    let padded = pairs(items, 9);
    let gpu = gpu_sort(&padded, items);
    let mut cpu = padded.clone();
    cpu.sort_by_key(|p| (p.x, p.y));
    assert_eq!(gpu, cpu, "the GPU sort");
    for (subgroup_size, schedule) in RUNS {
        let started = std::time::Instant::now();
        let host = host_sort(&c, &padded, subgroup_size, schedule)
            .unwrap_or_else(|e| panic!("subgroup {subgroup_size}, {schedule:?}: {e}"));
        eprintln!(
            "host sort of {} pairs, subgroup {subgroup_size}, {schedule:?}: {:.0} ms",
            padded.len(),
            started.elapsed().as_secs_f64() * 1e3
        );
        assert_eq!(host, gpu, "subgroup {subgroup_size}, {schedule:?}");
    }
}

#[test]
fn a_deleted_barrier_in_the_block_sort_leaves_it_unsorted() {
    let barrier = "exchange_local(t, base, k, j);\n                workgroup_barrier();";
    assert!(SORT_SOURCE.contains(barrier), "the mutation site moved");
    let mutated = compile(&SORT_SOURCE.replacen(barrier, "exchange_local(t, base, k, j);", 1));
    let padded = pairs(1000, 9);
    let mut cpu = padded.clone();
    cpu.sort_by_key(|p| (p.x, p.y));
    for schedule in [Schedule::InOrder, Schedule::Reversed] {
        let host = host_sort(&mutated, &padded, 32, schedule).expect("the mutated sort runs");
        assert_ne!(host, cpu, "{schedule:?} hid the missing barrier");
    }
}
