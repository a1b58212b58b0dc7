//! GPU particles against the CPU: the fixed-step simulation (spawn from the dead list, update,
//! kill, compact) equals the CPU reference particle for particle after hundreds of steps, a
//! full pool refuses and counts the same births, and the bitonic sort equals the CPU sort.

use std::collections::HashMap;

use glam::{UVec2, Vec3};
use renderer::demo::Rng;
use renderer::particles::reference::{CpuParticle, CpuSimulation};
use renderer::particles::{ParticleSystem, dust, smoke, sparks};
use renderer::passes::gpu_sort::{GpuSort, padded_count};
use renderer::passes::particles::ParticleSimulation;
use renderer::readback::read_buffer;
use tests::gpu::gpu_test;

/// Smoke, sparks and dust at different places and rates.
fn system(capacity: u32) -> ParticleSystem {
    ParticleSystem {
        emitters: vec![
            smoke(Vec3::new(-1.0, 0.0, 0.0), 120.0),
            sparks(Vec3::new(1.0, 0.5, 0.0), 300.0),
            dust(Vec3::new(0.0, 1.0, -2.0), 60.0),
        ],
        capacity,
        seed: 0x5eed,
    }
}

/// Whether `p` is so near the end of its life that one rounding of its lifetime (a fused
/// multiply-add on the GPU, separate on the CPU) could decide whether it is still alive.
fn at_deaths_door(age: f32, lifetime: f32) -> bool {
    (lifetime - age).abs() < 1e-4
}

#[test]
fn gpu_simulation_equals_the_cpu_reference_particle_for_particle() {
    let steps = 300;
    let mut cpu = CpuSimulation::new(system(20_000));
    for _ in 0..steps {
        cpu.step();
    }
    let gpu_particles = gpu_test(|gpu| {
        let sim = ParticleSimulation::new(gpu, system(20_000)).expect("simulation");
        sim.advance(gpu, steps);
        let counters = sim.read_counters(gpu).expect("counters");
        let alive = sim.read_alive(gpu).expect("particles");
        assert_eq!(
            counters.alive as usize,
            alive.len(),
            "the live list is complete"
        );
        assert_eq!(
            counters.dead + counters.alive,
            20_000,
            "every slot is live or free"
        );
        assert_eq!(counters.starved, 0);
        alive
    });
    let by_id: HashMap<(u32, u32), &CpuParticle> = cpu
        .particles
        .iter()
        .map(|p| ((p.emitter, p.index), p))
        .collect();
    assert!(cpu.particles.len() > 1000, "{} live", cpu.particles.len());
    let mut matched = 0;
    for g in &gpu_particles {
        let Some(c) = by_id.get(&(g.emitter, g.index)) else {
            assert!(
                at_deaths_door(g.age, g.lifetime),
                "GPU particle {}/{} is not alive on the CPU",
                g.emitter,
                g.index
            );
            continue;
        };
        matched += 1;
        // Trigonometry and powf have the device's error bounds; 300 steps of integration carry
        // them along. A millimetre (relative to the distance from the origin) is far below a
        // texel of any particle.
        let tolerance = 1e-3 * (1.0 + c.position.length());
        assert!(
            g.position.distance(c.position) < tolerance,
            "particle {}/{}: GPU {} CPU {}",
            g.emitter,
            g.index,
            g.position,
            c.position
        );
        assert!(g.velocity.distance(c.velocity) < 1e-3 * (1.0 + c.velocity.length()));
        assert!((g.age - c.age).abs() < 1e-4 && (g.lifetime - c.lifetime).abs() < 1e-5);
    }
    let missing = cpu.particles.len() - matched;
    let excused = cpu
        .particles
        .iter()
        .filter(|c| at_deaths_door(c.age, c.lifetime))
        .count();
    assert!(
        missing <= excused,
        "{missing} CPU particles are not alive on the GPU"
    );
}

/// 29 steps fill a pool of 100 before any particle dies (the shortest life is 30 steps), so
/// which births the GPU refused (whichever threads found no slot) cannot change the counts.
#[test]
fn a_full_pool_refuses_the_same_number_of_births() {
    let mut cpu = CpuSimulation::new(system(100));
    for _ in 0..29 {
        cpu.step();
    }
    assert!(cpu.starved > 0, "the test needs a pool that fills");
    gpu_test(|gpu| {
        let sim = ParticleSimulation::new(gpu, system(100)).expect("simulation");
        sim.advance(gpu, 29);
        let counters = sim.read_counters(gpu).expect("counters");
        assert_eq!(counters.alive, 100);
        assert_eq!(counters.dead, 0);
        assert_eq!(u64::from(counters.starved), cpu.starved);
    });
}

#[test]
fn a_system_past_the_device_limits_is_a_clear_error() {
    gpu_test(|gpu| {
        let max = ParticleSimulation::max_capacity(gpu.device());
        let err = ParticleSimulation::new(gpu, system(max.saturating_add(1)))
            .expect_err("over the limit");
        let text = err.to_string();
        assert!(text.contains("lower the capacity"), "{text}");
        let mut bad = system(100);
        bad.emitters[1].drag = -1.0;
        let text = ParticleSimulation::new(gpu, bad)
            .expect_err("negative drag")
            .to_string();
        assert!(
            text.contains("emitter 1") && text.contains("drag"),
            "{text}"
        );
    });
}

#[test]
fn gpu_bitonic_sort_equals_the_cpu_sort() {
    // Sizes: under one block, several blocks (global merge steps), and not a power of two.
    for (items, seed) in [(300u32, 1u64), (5000, 2), (40_000, 3)] {
        let mut rng = Rng::new(seed);
        // Few distinct keys, so payloads decide many orders.
        let pairs: Vec<UVec2> = (0..items)
            .map(|i| UVec2::new((rng.next_u64() % 97) as u32 * 1000, i ^ 0x55))
            .collect();
        let n = padded_count(items);
        let mut padded = pairs.clone();
        padded.resize(n as usize, UVec2::splat(u32::MAX));
        let sorted = gpu_test(|gpu| {
            let sort = GpuSort::new(gpu, items, wgpu::BufferUsages::empty()).expect("sort");
            assert_eq!(sort.count, n);
            gpu.queue()
                .write_buffer(&sort.keys, 0, bytemuck::cast_slice(&padded));
            let mut encoder = gpu.device().create_command_encoder(&Default::default());
            sort.record_in(&mut renderer::graph::PassEncoder::untimed(&mut encoder));
            gpu.queue().submit([encoder.finish()]);
            read_buffer::<UVec2>(gpu.device(), gpu.queue(), &sort.keys).expect("readback")
        });
        let mut expected = padded;
        expected.sort_by_key(|p| (p.x, p.y));
        assert_eq!(sorted, expected, "{items} items");
    }
}
