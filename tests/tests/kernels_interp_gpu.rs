//! `shaders_gen` compute kernels beyond culling, run by the DSL's host interpreter, against the
//! same kernels on the GPU and an independent CPU answer, at subgroup sizes 4, 8, 32 and 64 and
//! under several schedules; each with a mutation (a deleted barrier) that must be caught.
//!
//! - `particle_sort`: the bitonic sort in workgroup memory (a barrier after every step), host
//!   steps planned as `renderer::passes::particles::GpuSort` plans them.
//! - `particle_sim`: `update`, `spawn` (births popped from the dead list with atomics) and
//!   `compact`, stepped as `ParticleSimulation` steps; particles are compared by identity
//!   (emitter, spawn index), as slots follow the order the atomics ran in.
//! - `particle_atlas`: `size_particles`, `plan_atlas` and `allocate_regions` from the GPU
//!   simulation's particles; classes, sort keys and the plan compare exactly, region corners as
//!   sets per class (which region a particle gets follows the order of the atomics).

use codegen::interp::{Dispatch, EvalError, Schedule};
use std::collections::HashMap;

use glam::{UVec2, Vec3};
use renderer::frame::FrameCamera;
use renderer::particles::schedule::spawn_batches;
use renderer::particles::{FIXED_STEP, ParticleSystem, dust, smoke, sparks};
use renderer::passes::gpu_sort::{GpuSort, padded_count};
use renderer::passes::particles::atlas::STATE_WORDS;
use renderer::passes::particles::{ParticleAtlas, ParticleSimulation};
use renderer::readback::read_buffer;
use shaders_gen::particles::particle_atlas::{AtlasParams, HIDDEN, WORKGROUP as ATLAS_WORKGROUP};
use shaders_gen::particles::particle_common::GpuParticle;
use shaders_gen::particles::particle_sim::{SimParams, SpawnBatch, WORKGROUP as SIM_WORKGROUP};
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
        gpu.queue()
            .write_buffer(&sort.keys, 0, bytemuck::cast_slice(padded));
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        sort.record_in(&mut renderer::graph::PassEncoder::untimed(&mut encoder));
        gpu.queue().submit([encoder.finish()]);
        read_buffer::<UVec2>(gpu.device(), gpu.queue(), &sort.keys).expect("readback")
    })
}

/// The sort on the host: `sort_local`, then per stage `k` its global steps and `merge_local`.
fn host_sort(
    c: &codegen::Compiled,
    pairs: &[UVec2],
    subgroup_size: u32,
    schedule: Schedule,
) -> Result<Vec<UVec2>, EvalError> {
    host_sort_with(c, pairs, subgroup_size, schedule, true)
}

/// [`host_sort`] without data-race detection (to see what a race does to the result).
fn host_sort_unchecked(
    c: &codegen::Compiled,
    pairs: &[UVec2],
    schedule: Schedule,
) -> Result<Vec<UVec2>, EvalError> {
    host_sort_with(c, pairs, 32, schedule, false)
}

fn host_sort_with(
    c: &codegen::Compiled,
    pairs: &[UVec2],
    subgroup_size: u32,
    schedule: Schedule,
    races: bool,
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
            .with_schedule(schedule)
            .with_race_detection(races)
            .with_unwritten_read_check(races);
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
fn a_deleted_barrier_in_the_block_sort_is_caught() {
    let barrier = "exchange_local(t, base, k, j);\n                workgroup_barrier();";
    assert!(SORT_SOURCE.contains(barrier), "the mutation site moved");
    let mutated = compile(&SORT_SOURCE.replacen(barrier, "exchange_local(t, base, k, j);", 1));
    let padded = pairs(1000, 9);
    let mut cpu = padded.clone();
    cpu.sort_by_key(|p| (p.x, p.y));
    // Race detection names the two places that are no longer ordered.
    let err = host_sort(&mutated, &padded, 32, Schedule::InOrder).unwrap_err();
    let text = err.to_string();
    assert!(matches!(err.cause(), EvalError::Race(_)), "{text}");
    assert!(text.contains("BLOCK_KEYS["), "{text}");
    eprintln!("{text}");
    // Without it, the sort comes out wrong under either schedule.
    for schedule in [Schedule::InOrder, Schedule::Reversed] {
        let host = host_sort_unchecked(&mutated, &padded, schedule).expect("the mutated sort runs");
        assert_ne!(host, cpu, "{schedule:?} hid the missing barrier");
    }
}

const SIM_SOURCE: &str = include_str!("../../shaders_gen/src/particles/simulate.rs");
const COMMON_SOURCE: &str = include_str!("../../shaders_gen/src/particles/common.rs");

fn particle_system() -> ParticleSystem {
    ParticleSystem {
        emitters: vec![
            smoke(Vec3::new(-1.0, 0.0, 0.0), 120.0),
            sparks(Vec3::new(1.0, 0.5, 0.0), 300.0),
            dust(Vec3::new(0.0, 1.0, -2.0), 60.0),
        ],
        // Room for every birth: which births a full pool refuses follows the order of the
        // atomics, which differs between the GPU and the host.
        capacity: 1024,
        seed: 0x5eed,
    }
}

/// `steps` fixed steps of `system` on the host: each `update`, `spawn` when there are births,
/// the live count cleared, `compact`. The slots and the counters afterwards.
fn host_particles(
    c: &codegen::Compiled,
    system: &ParticleSystem,
    steps: u64,
    subgroup_size: u32,
    schedule: Schedule,
) -> Result<(Vec<GpuParticle>, Vec<i32>), EvalError> {
    let capacity = system.capacity;
    let emitters: Vec<_> = system.emitters.iter().map(|e| e.gpu()).collect();
    let dead: Vec<u32> = (0..capacity).rev().collect();
    let mut buffers: Vec<(&str, Vec<u8>)> = vec![
        ("EMITTERS", bytemuck::cast_slice(&emitters).to_vec()),
        (
            "PARTICLES",
            vec![0; capacity as usize * size_of::<GpuParticle>()],
        ),
        ("DEAD", bytemuck::cast_slice(&dead).to_vec()),
        (
            "COUNTERS",
            bytemuck::cast_slice(&[capacity as i32, 0, 0, 0]).to_vec(),
        ),
        ("ALIVE", vec![0; capacity as usize * 4]),
        ("PARAMS", vec![]),
        ("BATCHES", vec![]),
    ];
    let groups = |threads: u32| threads.div_ceil(SIM_WORKGROUP);
    for step in 0..steps {
        let batches = spawn_batches(&system.emitters, step);
        let births: u32 = batches.iter().map(|b| b.count).sum();
        let params = SimParams::new(
            capacity,
            births,
            batches.len() as u32,
            system.seed,
            FIXED_STEP,
            0,
            0,
            0,
        );
        let slots: Vec<SpawnBatch> = if batches.is_empty() {
            vec![bytemuck::Zeroable::zeroed()]
        } else {
            batches
        };
        for (name, bytes) in &mut buffers {
            match *name {
                "PARAMS" => *bytes = bytemuck::bytes_of(&params).to_vec(),
                "BATCHES" => *bytes = bytemuck::cast_slice(&slots).to_vec(),
                _ => {}
            }
        }
        let mut kernels = vec![("update", groups(capacity))];
        if births > 0 {
            kernels.push(("spawn", groups(births)));
        }
        kernels.push(("compact", groups(capacity)));
        for (entry, workgroups) in kernels {
            if entry == "compact" {
                // The live count starts each compaction at zero (the host clears it).
                let counters = &mut buffers[3].1;
                counters[4..8].copy_from_slice(&0i32.to_le_bytes());
            }
            let mut d = Dispatch::new(&c.module, &c.keys[0].env, entry)?
                .with_subgroup_size(subgroup_size)?
                .with_schedule(schedule)
                .with_unwritten_read_check(true);
            for (name, bytes) in &buffers {
                d.set_buffer(name, bytes)?;
            }
            d.run([workgroups, 1, 1])?;
            for (name, bytes) in &mut buffers {
                *bytes = d.buffer(name)?;
            }
        }
    }
    Ok((
        bytemuck::pod_collect_to_vec(&buffers[1].1),
        bytemuck::pod_collect_to_vec(&buffers[3].1),
    ))
}

#[test]
fn host_particle_simulation_equals_the_gpu_particle_for_particle() {
    let mut modules =
        codegen::compile_source_all_with(SIM_SOURCE, &[COMMON_SOURCE]).expect("parses");
    let (_, c) = modules.swap_remove(0);
    let c = c.unwrap_or_else(|e| panic!("{e}"));
    let steps = 30;
    let (gpu, gpu_counters) = gpu_test(|gpu| {
        let sim = ParticleSimulation::new(gpu, particle_system()).expect("simulation");
        sim.advance(gpu, steps as u32);
        let c = sim.read_counters(gpu).expect("counters");
        (
            sim.read_alive(gpu).expect("particles"),
            [c.dead, c.alive, c.starved],
        )
    });
    assert!(gpu.len() > 100, "{} live particles", gpu.len());
    assert_eq!(gpu_counters[2], 0, "the pool refused births");
    for (subgroup_size, schedule) in RUNS {
        let run = format!("subgroup {subgroup_size}, {schedule:?}");
        let (slots, counters) =
            host_particles(&c, &particle_system(), steps, subgroup_size, schedule)
                .unwrap_or_else(|e| panic!("{run}: {e}"));
        assert_eq!(
            [counters[0], counters[1], counters[2]].map(|c| c as u32),
            gpu_counters,
            "{run}: dead, alive and refused counts"
        );
        let host: HashMap<(u32, u32), &GpuParticle> = slots
            .iter()
            .filter(|p| p.alive != 0)
            .map(|p| ((p.emitter, p.index), p))
            .collect();
        assert_eq!(host.len(), gpu.len(), "{run}: live particles");
        for g in &gpu {
            let h = host.get(&(g.emitter, g.index)).unwrap_or_else(|| {
                panic!("{run}: particle {}/{} only on the GPU", g.emitter, g.index)
            });
            // Both are f32; the GPU's sin, cos and pow have their own error bounds.
            let tolerance = 1e-4 * (1.0 + g.position.length());
            assert!(
                h.position.distance(g.position) < tolerance && (h.age - g.age).abs() < 1e-5,
                "{run}: particle {}/{}: host {} GPU {}",
                g.emitter,
                g.index,
                h.position,
                g.position
            );
        }
    }
}

const ATLAS_SOURCE: &str = include_str!("../../shaders_gen/src/particles/atlas.rs");

/// What the atlas kernels read and write, as bytes: the GPU simulation's buffers, and the
/// atlas's outputs after the GPU's layout.
struct AtlasRun {
    params: AtlasParams,
    emitters: Vec<u8>,
    particles: Vec<u8>,
    alive: Vec<u8>,
    counters: Vec<u8>,
    key_count: u32,
    /// The GPU's results: keys, regions, state, owners.
    gpu: [Vec<u8>; 4],
}

fn atlas_on_gpu(camera: &FrameCamera, height: u32) -> AtlasRun {
    let mut system = particle_system();
    system.capacity = 512;
    gpu_test(|gpu| {
        let sim = ParticleSimulation::new(gpu, system.clone()).expect("simulation");
        sim.advance(gpu, 40);
        let sort = GpuSort::new(gpu, system.capacity, wgpu::BufferUsages::empty()).expect("sort");
        let side = ParticleAtlas::min_side(system.capacity) * 2;
        let atlas = ParticleAtlas::new(gpu, &sim, &sort, side).expect("atlas");
        let read = |b: &wgpu::Buffer| -> Vec<u8> {
            read_buffer::<u8>(gpu.device(), gpu.queue(), b).expect("readback")
        };
        let (emitters, particles, alive, counters) = (
            read(&sim.emitters),
            read(&sim.particles),
            read(&sim.alive),
            read(&sim.counters),
        );
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        atlas.record(gpu.queue(), &mut encoder, camera, height);
        gpu.queue().submit([encoder.finish()]);
        AtlasRun {
            params: AtlasParams::new(
                camera.view,
                camera.projection.y_axis.y * height as f32 * 0.5,
                camera.near,
                side / 2,
                sort.count,
                u32::from(camera.orthographic),
            ),
            emitters,
            particles,
            alive,
            counters,
            key_count: sort.count,
            gpu: [
                read(&sort.keys),
                read(&atlas.regions),
                read(&atlas.state),
                read(&atlas.owners),
            ],
        }
    })
}

/// The three atlas kernels on the host from the GPU simulation's buffers: keys, regions,
/// state and owners.
fn atlas_on_host(
    c: &codegen::Compiled,
    run: &AtlasRun,
    subgroup_size: u32,
    schedule: Schedule,
) -> Result<[Vec<u8>; 4], EvalError> {
    let capacity = run.particles.len() / size_of::<GpuParticle>();
    let mut buffers: Vec<(&str, Vec<u8>)> = vec![
        ("PARAMS", bytemuck::bytes_of(&run.params).to_vec()),
        ("EMITTERS", run.emitters.clone()),
        ("PARTICLES", run.particles.clone()),
        ("ALIVE", run.alive.clone()),
        ("COUNTERS", run.counters.clone()),
        ("KEYS", vec![0; run.key_count as usize * 8]),
        ("REGIONS", vec![0; capacity * 4]),
        ("STATE", vec![0; STATE_WORDS * 4]),
        ("OWNERS", vec![0; capacity * 4]),
    ];
    let groups = |n: u32| n.div_ceil(ATLAS_WORKGROUP);
    for (entry, workgroups) in [
        ("size_particles", groups(run.key_count)),
        ("plan_atlas", 1),
        ("allocate_regions", groups(capacity as u32)),
    ] {
        let mut d = Dispatch::new(&c.module, &c.keys[0].env, entry)?
            .with_subgroup_size(subgroup_size)?
            .with_schedule(schedule)
            .with_unwritten_read_check(true);
        for (name, bytes) in &buffers {
            d.set_buffer(name, bytes)?;
        }
        d.run([workgroups, 1, 1])?;
        for (name, bytes) in &mut buffers {
            *bytes = d.buffer(name)?;
        }
    }
    let take = |name: &str| {
        buffers
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, b)| b.clone())
            .unwrap_or_default()
    };
    Ok([take("KEYS"), take("REGIONS"), take("STATE"), take("OWNERS")])
}

/// Region corners by class, sorted: what must agree however the atomics ordered the particles.
fn corners_by_class(regions: &[u32]) -> Vec<(u32, u32)> {
    let mut out: Vec<(u32, u32)> = regions
        .iter()
        .filter(|&&r| r != HIDDEN && r != 0)
        .map(|&r| (r >> 24, r & 0xff_ffff))
        .collect();
    out.sort_unstable();
    out
}

#[test]
fn host_particle_atlas_layout_equals_the_gpu() {
    let mut modules =
        codegen::compile_source_all_with(ATLAS_SOURCE, &[COMMON_SOURCE]).expect("parses");
    let (_, c) = modules.swap_remove(0);
    let c = c.unwrap_or_else(|e| panic!("{e}"));
    let camera = FrameCamera::look_at(
        Vec3::new(0.0, 1.0, 4.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::Y,
        60f32.to_radians(),
        16.0 / 9.0,
        (0.1, 100.0),
    );
    let run = atlas_on_gpu(&camera, 360);
    let words = |b: &[u8]| -> Vec<u32> { bytemuck::pod_collect_to_vec(b) };
    let [gpu_keys, gpu_regions, gpu_state, gpu_owners] = run.gpu.clone().map(|b| words(&b));
    let alive = words(&run.counters)[1] as usize;
    assert!(alive > 100, "{alive} live particles");
    let visible = words(&run.alive)[..alive]
        .iter()
        .filter(|&&slot| gpu_regions[slot as usize] != HIDDEN)
        .count();
    assert!(visible > 100, "{visible} particles in view");
    for (subgroup_size, schedule) in RUNS {
        let what = format!("subgroup {subgroup_size}, {schedule:?}");
        let [keys, regions, state, owners] = atlas_on_host(&c, &run, subgroup_size, schedule)
            .unwrap_or_else(|e| panic!("{what}: {e}"))
            .map(|b| words(&b));
        assert_eq!(keys, gpu_keys, "{what}: sort keys");
        assert_eq!(state, gpu_state, "{what}: class counts, shrink and plan");
        assert_eq!(
            corners_by_class(&regions),
            corners_by_class(&gpu_regions),
            "{what}: the regions handed out"
        );
        // Each live particle has the same class (or is hidden) on both.
        for &slot in &words(&run.alive)[..alive] {
            let (h, g) = (regions[slot as usize], gpu_regions[slot as usize]);
            assert_eq!(
                (h == HIDDEN, h >> 24),
                (g == HIDDEN, g >> 24),
                "{what}: slot {slot}"
            );
        }
        let mut o = owners.clone();
        let mut go = gpu_owners.clone();
        o.sort_unstable();
        go.sort_unstable();
        assert_eq!(o, go, "{what}: region owners");
    }
}
