//! The culling kernels run by the DSL's host interpreter equal the same kernels on the GPU and
//! the independent CPU reference, at subgroup sizes 4, 8, 32 and 64 and under two schedules;
//! and a deleted barrier in `tile_cull` makes the host lists wrong. Clustered culling
//! (`cluster_cull`) likewise.
//!
//! The three dispatches (`cull_prepare::tile_depth`, `coarse_cull`, `tile_cull::cull`) are
//! compiled from `shaders_gen`'s source text and given the GPU run's parameters, lights and
//! depth samples. Lists are compared as sets: their order follows the order the atomics ran in.

use codegen::interp::{EvalError, Schedule};
use renderer::culling::clustered::ClusterCullConfig;
use renderer::culling::lists::CullReadback;
use renderer::culling::reference::ClusterGrid;
use renderer::culling::reference::{Method, cull};
use renderer::culling::tiled::TileCullConfig;
use tests::cull_interp::{
    CLUSTERED_SOURCE, HostRun, PREPARE_SOURCE, TILED_SOURCE, compile, run_on_host,
};
use tests::cull_run::{GpuMethod, run_method, symmetric_difference};
use tests::cull_scene::{CullScene, scene};

fn config(msaa: u32) -> TileCullConfig {
    TileCullConfig {
        tile: 16,
        msaa,
        depth_mask: false,
        transparent_lists: false,
        brute_force: false,
        coarse_slots: None,
        index_capacity: 4096,
        item_capacity: 256,
    }
}

fn lists(r: &CullReadback) -> Vec<Vec<u32>> {
    r.all_lists()
}

const TILED: Method = Method::Tiled {
    tile: 16,
    transparent: false,
};

/// Cells where two runs' lists differ by an item the reference does not call borderline.
fn sure_differences(s: &CullScene, a: &[Vec<u32>], b: &[Vec<u32>]) -> Vec<(usize, u32)> {
    sure_differences_in(s, TILED, a, b)
}

fn sure_differences_in(
    s: &CullScene,
    method: Method,
    a: &[Vec<u32>],
    b: &[Vec<u32>],
) -> Vec<(usize, u32)> {
    let reference = cull(&s.camera, &s.depth, &s.lights_view(), method);
    let mut out = vec![];
    for (c, (x, y)) in a.iter().zip(b).enumerate() {
        for item in symmetric_difference(x, y) {
            if !reference.borderline[c].iter().any(|l| l.light == item) {
                out.push((c, item));
            }
        }
    }
    out
}

#[test]
fn host_culling_equals_the_gpu_and_the_reference_at_every_subgroup_size() {
    let prepare = compile(PREPARE_SOURCE);
    let fine = compile(TILED_SOURCE);
    for msaa in [1, 4] {
        let s = scene(11 + u64::from(msaa), 64, 48, msaa, 24);
        let gpu = lists(&run_method(&s, GpuMethod::Tiled(config(msaa))));
        let reference = cull(&s.camera, &s.depth, &s.lights_view(), TILED);
        assert!(
            gpu.iter().map(Vec::len).sum::<usize>() > 20,
            "the scene lists too little to compare"
        );
        for (subgroup_size, schedule) in [
            (4, Schedule::InOrder),
            (8, Schedule::Reversed),
            (32, Schedule::InOrder),
            (64, Schedule::Reversed),
        ] {
            let run = HostRun {
                subgroup_size,
                schedule,
            };
            let started = std::time::Instant::now();
            let host = run_on_host(&s, GpuMethod::Tiled(config(msaa)), (&prepare, &fine), run)
                .unwrap_or_else(|e| panic!("MSAA {msaa}, {run:?}: {e}"));
            // Reported, not asserted (timings are for benchmarks). The run includes setting
            // up the GPU method once for its parameters; that setup is timed apart.
            let total = started.elapsed();
            let setup = std::time::Instant::now();
            let _ = tests::cull_interp::method_params(&s, GpuMethod::Tiled(config(msaa)));
            let setup = setup.elapsed();
            eprintln!(
                "host culling, 64×48, MSAA {msaa}, {} lights, {run:?}: {:.0} ms for the three \
                 dispatches ({:.0} ms with the GPU parameter setup)",
                s.lights.len(),
                total.saturating_sub(setup).as_secs_f64() * 1e3,
                total.as_secs_f64() * 1e3
            );
            let host = lists(&host);
            let what = format!("MSAA {msaa}, subgroup {subgroup_size}, {schedule:?}");
            assert_eq!(host.len(), gpu.len(), "{what}: cells");
            assert_eq!(
                sure_differences(&s, &host, &gpu),
                vec![],
                "{what}: host vs GPU"
            );
            assert_eq!(
                sure_differences(&s, &host, &reference.lists),
                vec![],
                "{what}: host vs reference"
            );
        }
    }
}

#[test]
fn a_deleted_barrier_in_tile_cull_makes_the_host_lists_wrong() {
    let barrier = "lists_reset(lid);\n        workgroup_barrier();";
    assert!(TILED_SOURCE.contains(barrier), "the mutation site moved");
    let mutated = TILED_SOURCE.replacen(barrier, "lists_reset(lid);", 1);
    let prepare = compile(PREPARE_SOURCE);
    let fine = compile(&mutated);
    let s = scene(12, 64, 48, 1, 24);
    let gpu = lists(&run_method(&s, GpuMethod::Tiled(config(1))));
    // Run in reverse: the invocations that reset the list counters run last and wipe out the
    // counts the others made.
    let run = HostRun {
        subgroup_size: 32,
        schedule: Schedule::Reversed,
    };
    let host =
        run_on_host(&s, GpuMethod::Tiled(config(1)), (&prepare, &fine), run).map(|r| lists(&r));
    match host {
        Ok(host) => {
            let wrong = sure_differences(&s, &host, &gpu);
            eprintln!("the missing barrier changed {} list entries", wrong.len());
            assert_ne!(wrong, vec![], "the missing barrier went unnoticed");
        }
        // A kernel error (a list index out of bounds) is as good a failure; a setup error is not.
        Err(e) => assert!(
            matches!(e, EvalError::Invocation { .. }),
            "the run failed before the kernel did: {e}"
        ),
    }
}

#[test]
fn host_clustered_culling_equals_the_gpu_and_the_reference() {
    let grid = ClusterGrid {
        tile: 16,
        slices: 16,
        near: tests::cull_scene::NEAR,
        far: tests::cull_scene::FAR,
    };
    let method = Method::Clustered {
        grid,
        skip_empty: false,
    };
    let config = ClusterCullConfig {
        grid,
        msaa: 1,
        vis64: false,
        skip_empty: false,
        brute_force: false,
        coarse_slots: None,
        index_capacity: 1 << 14,
        item_capacity: 256,
    };
    let prepare = compile(PREPARE_SOURCE);
    let fine = compile(CLUSTERED_SOURCE);
    // 72×40 is not a multiple of the tile: partial tiles on the right and at the bottom.
    let s = scene(41, 72, 40, 1, 24);
    let gpu = lists(&run_method(&s, GpuMethod::Clustered(config)));
    let reference = cull(&s.camera, &s.depth, &s.lights_view(), method);
    assert!(gpu.iter().map(Vec::len).sum::<usize>() > 20);
    for (subgroup_size, schedule) in [
        (4, Schedule::InOrder),
        (8, Schedule::Shuffled(3)),
        (32, Schedule::Reversed),
        (64, Schedule::Reversed),
    ] {
        let run = HostRun {
            subgroup_size,
            schedule,
        };
        let host = run_on_host(&s, GpuMethod::Clustered(config), (&prepare, &fine), run)
            .unwrap_or_else(|e| panic!("{run:?}: {e}"));
        let host = lists(&host);
        assert_eq!(host.len(), gpu.len(), "{run:?}: froxels");
        assert_eq!(
            sure_differences_in(&s, method, &host, &gpu),
            vec![],
            "{run:?}: host vs GPU"
        );
        assert_eq!(
            sure_differences_in(&s, method, &host, &reference.lists),
            vec![],
            "{run:?}: host vs reference"
        );
    }
}
