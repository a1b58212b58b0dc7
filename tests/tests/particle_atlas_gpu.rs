//! The particle lighting atlas's layout on the GPU: every visible particle gets a square region
//! whose side follows the rule (a quarter of its projected width, clamped to 2–32 texels,
//! rounded up to a power of two), no two regions overlap, hidden particles get none, and an
//! atlas too small for the frame shrinks every region, reports it, and still drops nothing.

use glam::Vec3;
use renderer::frame::FrameCamera;
use renderer::particles::{ParticleSystem, dust, smoke, sparks};
use renderer::passes::particles::{AtlasReport, GpuSort, ParticleAtlas, ParticleSimulation};
use renderer::readback::read_buffer;
use shaders_gen::particles::particle_atlas::HIDDEN;
use shaders_gen::particles::particle_common::GpuParticle;
use tests::gpu::gpu_test;

const HEIGHT: u32 = 360;

fn system() -> ParticleSystem {
    ParticleSystem {
        emitters: vec![
            smoke(Vec3::new(-1.0, 0.0, 0.0), 200.0),
            sparks(Vec3::new(1.0, 0.5, 0.0), 300.0),
            dust(Vec3::new(0.0, 1.0, -1.0), 100.0),
        ],
        capacity: 2000,
        seed: 11,
    }
}

fn camera(distance: f32) -> FrameCamera {
    let (eye, target) = (Vec3::new(0.0, 1.0, distance), Vec3::new(0.0, 1.0, 0.0));
    FrameCamera::look_at(
        eye,
        target,
        Vec3::Y,
        60f32.to_radians(),
        16.0 / 9.0,
        (0.1, 100.0),
    )
}

/// The rule, on the CPU: the side class (side `2 << class`) for a particle, or `None` when it
/// is not in front of the camera; and whether its projected size is within a hair of a class
/// boundary (where f32 rounding may pick either side).
fn expected_class(
    p: &GpuParticle,
    system: &ParticleSystem,
    camera: &FrameCamera,
) -> Option<(u32, bool)> {
    let e = &system.emitters[p.emitter as usize];
    let life = (p.age / p.lifetime).clamp(0.0, 1.0);
    let size = e.size[0] + (e.size[1] - e.size[0]) * life;
    let depth = -(camera.view * p.position.extend(1.0)).z;
    if depth <= camera.near {
        return None;
    }
    let pixels = 2.0 * size * camera.projection.y_axis.y * HEIGHT as f32 * 0.5 / depth;
    let side = (pixels * 0.25).clamp(2.0, 32.0);
    let class = (0..5).find(|&c| (2u32 << c) as f32 >= side).unwrap_or(4);
    let near_boundary = (0..5).any(|c| ((2u32 << c) as f32 - side).abs() < 1e-3 * side);
    Some((class, near_boundary))
}

/// Lays the atlas out for `camera` after `steps` steps; returns the slots, their regions and
/// the report.
fn layout(
    side: u32,
    camera: &FrameCamera,
    steps: u32,
) -> (Vec<GpuParticle>, Vec<u32>, AtlasReport) {
    gpu_test(|gpu| {
        let sim = ParticleSimulation::new(gpu, system()).expect("simulation");
        sim.advance(gpu, steps);
        let sort = GpuSort::new(gpu, 2000, wgpu::BufferUsages::empty()).expect("sort");
        let atlas = ParticleAtlas::new(gpu, &sim, &sort, side).expect("atlas");
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        atlas.record(gpu.queue(), &mut encoder, camera, HEIGHT);
        gpu.queue().submit([encoder.finish()]);
        let slots = sim.read_slots(gpu).expect("slots");
        let regions: Vec<u32> =
            read_buffer(gpu.device(), gpu.queue(), &atlas.regions).expect("regions");
        (slots, regions, atlas.read_report(gpu).expect("report"))
    })
}

/// Checks every live particle's region against the rule (less `shrink` classes) and that the
/// regions tile without overlap inside a `side`² atlas.
fn check_layout(side: u32, camera: &FrameCamera, steps: u32, shrink: u32) -> AtlasReport {
    let (slots, regions, report) = layout(side, camera, steps);
    let system = system();
    let mut taken = vec![false; (side * side) as usize];
    let mut visible = 0;
    for (slot, p) in slots.iter().enumerate().filter(|(_, p)| p.alive != 0) {
        let region = regions[slot];
        let Some((class, near_boundary)) = expected_class(p, &system, camera) else {
            assert_eq!(region, HIDDEN, "slot {slot} is behind the camera");
            continue;
        };
        visible += 1;
        let (x, y, got) = (region & 0xfff, (region >> 12) & 0xfff, region >> 24);
        let want = class.saturating_sub(shrink);
        assert!(
            got == want || (near_boundary && got.abs_diff(want) == 1),
            "slot {slot}: class {got}, the rule says {want}"
        );
        let s = 2 << got;
        assert!(
            x % s == 0 && y % s == 0,
            "slot {slot}: region ({x}, {y}) is not aligned"
        );
        assert!(
            x + s <= side && y + s <= side,
            "slot {slot}: region leaves the atlas"
        );
        for ty in y..y + s {
            for tx in x..x + s {
                let t = &mut taken[(ty * side + tx) as usize];
                assert!(!*t, "slot {slot}: texel ({tx}, {ty}) is already taken");
                *t = true;
            }
        }
    }
    assert_eq!(report.visible, visible, "{report:?}");
    assert_eq!(report.per_class.iter().sum::<u32>(), visible);
    let used = taken.iter().filter(|&&t| t).count() as u32;
    assert_eq!(report.cells_used * 4, used, "{report:?}");
    report
}

#[test]
fn regions_follow_the_size_rule_and_never_overlap() {
    let report = check_layout(1024, &camera(6.0), 120, 0);
    assert_eq!(report.shrink, 0, "{report:?}");
    assert_eq!(report.shrunk_frames, 0);
    assert!(report.visible > 300, "{report:?}");
    let classes_used = report.per_class.iter().filter(|&&n| n > 0).count();
    assert!(classes_used >= 3, "a spread of sizes: {report:?}");
}

#[test]
fn a_full_atlas_shrinks_every_region_and_reports_it() {
    // Close up, most particles want 16 or 32 texels: far more than 128² holds.
    let side = ParticleAtlas::min_side(2000);
    assert_eq!(side, 128);
    let close = camera(1.2);
    let (_, _, wanted) = layout(4096, &close, 120);
    let shrink = wanted_shrink(&wanted, side);
    let report = check_layout(side, &close, 120, shrink);
    assert!(report.shrink > 0, "{report:?}");
    assert_eq!(report.shrink, shrink, "the least shrink that fits");
    assert_eq!(report.shrunk_frames, 1, "the frame that shrank is reported");
    assert_eq!(report.visible, wanted.visible, "nothing is dropped");
    assert!(report.cells_used <= (side / 2) * (side / 2));
}

/// The shrink the plan should pick: the smallest that fits the classes into `side`².
fn wanted_shrink(report: &AtlasReport, side: u32) -> u32 {
    let capacity = (side / 2) * (side / 2);
    (0..5)
        .find(|&s| {
            let cells: u32 = (0..5)
                .map(|c: u32| report.per_class[c as usize] << (2 * c.saturating_sub(s)))
                .sum();
            cells <= capacity
        })
        .unwrap_or(4)
}

#[test]
fn an_atlas_too_small_for_the_pool_is_a_clear_error() {
    gpu_test(|gpu| {
        let sim = ParticleSimulation::new(gpu, system()).expect("simulation");
        let sort = GpuSort::new(gpu, 2000, wgpu::BufferUsages::empty()).expect("sort");
        let err = ParticleAtlas::new(gpu, &sim, &sort, 64).expect_err("too small");
        assert!(err.to_string().contains("from 128"), "{err}");
        assert!(
            ParticleAtlas::new(gpu, &sim, &sort, 300).is_err(),
            "not a power of two"
        );
    });
}
