//! The culling kernels on the GPU against the independent CPU reference, in every variant the
//! software driver runs: tiled and 2.5D (tile 8/16/32 × MSAA 1/4 × hierarchical or brute force,
//! with and without transparent lists), clustered (MSAA 1/4 × skip-empty × hierarchical or brute
//! force), lists far longer than any workgroup could hold, the super-tile fallback, and a full
//! index list.
//!
//! Tolerance: a GPU tile list may differ from the reference's only by lights the reference marks
//! borderline (sphere-test margin within `1e-4 · (|c| + r)`, see `methods::tolerance`); every
//! other light must match exactly. Independently of the reference's lists, no light that really
//! reaches a sample may be missing from the sample's GPU list.

use glam::UVec2;
use renderer::culling::clustered::ClusterCullConfig;
use renderer::culling::hierarchy::{CullItems, DepthInput};
use renderer::culling::lists::{CullReadback, GUARD_WORD, GUARD_WORDS};
use renderer::culling::reference::{CellLists, ClusterGrid, Method, cull, cull_brute_force, exact};
use renderer::culling::tiled::{TileCullConfig, TiledCulling};
use shaders_gen::culling::tile_cull::CullSphere;
use tests::cull_run::{GpuMethod, msaa_cases, run_method, symmetric_difference, tiled_methods};
use tests::cull_scene::{CullScene, scene};
use tests::depth_upload::write_msaa_depth;
use tests::gpu::gpu_test;

fn run_gpu(s: &CullScene, config: TileCullConfig) -> CullReadback {
    run_method(s, GpuMethod::Tiled(config))
}

fn config(tile: u32, msaa: u32, brute_force: bool) -> TileCullConfig {
    TileCullConfig {
        tile,
        msaa,
        depth_mask: false,
        transparent_lists: false,
        brute_force,
        coarse_slots: None,
        index_capacity: 1 << 20,
        item_capacity: 1 << 15,
    }
}

/// The reference's lists for a GPU run with or without the super-tile level.
fn reference_for(s: &CullScene, method: Method, brute_force: bool) -> CellLists {
    let lights = s.lights_view();
    if brute_force {
        cull_brute_force(&s.camera, &s.depth, &lights, method)
    } else {
        cull(&s.camera, &s.depth, &lights, method)
    }
}

/// Every GPU list equals the reference's except for lights the reference calls borderline;
/// returns how many such close calls there were.
fn assert_matches_reference(got: &[Vec<u32>], reference: &CellLists, what: &str) -> usize {
    assert_eq!(got.len(), reference.lists.len(), "{what}: cell count");
    let mut close_calls = 0;
    for (c, got) in got.iter().enumerate() {
        for light in symmetric_difference(got, &reference.lists[c]) {
            let close_call = reference.borderline[c].iter().any(|b| b.light == light);
            assert!(
                close_call,
                "cell {c} ({what}): light {light} is {} on the GPU but the reference is sure",
                if got.contains(&light) {
                    "listed"
                } else {
                    "missing"
                }
            );
            close_calls += 1;
        }
    }
    close_calls
}

#[test]
fn tiled_kernel_matches_cpu_reference_in_every_variant() {
    check_against_reference(false);
}

#[test]
fn depth_mask_kernel_matches_cpu_reference_in_every_variant() {
    check_against_reference(true);
}

fn check_against_reference(depth_mask: bool) {
    for (seed, msaa) in msaa_cases(11) {
        let s = scene(seed, 160, 96, msaa, 300);
        for method in tiled_methods(depth_mask) {
            let (tile, transparent) = (method.tile(), method.transparent_lists());
            for brute_force in [false, true] {
                let gpu = run_gpu(
                    &s,
                    TileCullConfig {
                        depth_mask,
                        transparent_lists: transparent,
                        ..config(tile, msaa, brute_force)
                    },
                );
                assert_eq!(gpu.counters.coarse_fallbacks, 0);
                assert_eq!(gpu.counters.dropped, 0);
                let lists = gpu.all_lists();
                let what = format!("{method:?}, MSAA {msaa}, brute force {brute_force}");
                let reference = reference_for(&s, method, brute_force);
                let close_calls = assert_matches_reference(&lists, &reference, &what);
                assert!(close_calls < 10, "too many close calls: {close_calls}");
                assert_conservative(&s, &lists, method);
            }
        }
    }
}

/// Every light whose sphere contains a sample's surface point is in that sample's GPU list.
fn assert_conservative(s: &CullScene, lists: &[Vec<u32>], method: Method) {
    let lights = s.lights_view();
    let grid = exact::LightGrid::new(&s.camera, &s.depth, &lights);
    exact::for_each_surface_sample_pub(&s.camera, &s.depth, |x, y, p| {
        let t = method.cell_of(s.camera.width, s.camera.height, x, y, -p.z);
        // A sample within f32 noise of a depth-slice boundary may be binned either way.
        let neighbours = slice_neighbours(method, s, x, y, -p.z);
        for light in exact::lights_reaching(&grid, &lights, p) {
            // A light touching the point within f32 noise may be culled by either side.
            let l = lights[light as usize];
            let slack = l.center.distance(p) - l.radius;
            let listed = lists[t].binary_search(&light).is_ok()
                || neighbours
                    .iter()
                    .any(|&n| lists[n].binary_search(&light).is_ok());
            assert!(
                listed || slack.abs() < 1e-3 * (1.0 + l.radius),
                "{method:?}: light {light} reaches pixel ({x},{y}) but the GPU list of cell {t} lacks it"
            );
        }
    });
}

#[test]
fn a_full_index_list_drops_whole_tiles_counts_them_and_writes_nothing_out_of_bounds() {
    let s = scene(21, 128, 96, 1, 400);
    let unconstrained = run_gpu(&s, config(16, 1, false));
    let found: Vec<u32> = unconstrained.grid.iter().map(|g| g.y).collect();
    let total: u32 = found.iter().sum();
    let index_capacity = total / 3;
    let constrained = run_gpu(
        &s,
        TileCullConfig {
            index_capacity,
            ..config(16, 1, false)
        },
    );
    let c = constrained.counters;
    assert_eq!(c.max_cell_items, *found.iter().max().unwrap_or(&0));
    assert_eq!(
        c.requested_entries, total,
        "the host learns how much room it needed"
    );
    let stored: u32 = constrained.grid.iter().map(|g| g.y).sum();
    assert!(stored <= index_capacity && stored > 0, "stored {stored}");
    assert_eq!(
        stored + c.dropped,
        total,
        "every found entry is either stored or counted as dropped"
    );
    for (g, &n) in constrained.grid.iter().zip(&found) {
        assert!(
            g.y == n || g.y == 0,
            "a tile's list is complete or empty, never cut short: {} of {n}",
            g.y
        );
        assert!(
            g.x + g.y <= index_capacity || g.y == 0,
            "tile range {g} exceeds the capacity"
        );
    }
    let guard = &constrained.indices[index_capacity as usize..];
    assert_eq!(guard.len(), GUARD_WORDS as usize);
    assert!(
        guard.iter().all(|&w| w == GUARD_WORD),
        "the guard region after the capacity is untouched"
    );
}

/// 16,384 lights of radius up to 200 in 8×8 tiles: every tile lists thousands of lights, far
/// more than a workgroup could gather, and every list is complete.
#[test]
fn sixteen_thousand_large_lights_in_8px_tiles_are_listed_completely() {
    let s = tests::cull_scene::scene_with_radii(51, 96, 64, 1, 16_384, 0.5, 200.0);
    for brute_force in [false, true] {
        let method = Method::tiled(8);
        let roomy = TileCullConfig {
            index_capacity: 1 << 22,
            ..config(8, 1, brute_force)
        };
        let gpu = run_gpu(&s, roomy);
        assert_eq!(gpu.counters.dropped, 0);
        let lists = gpu.all_lists();
        let longest = lists.iter().map(Vec::len).max().unwrap_or(0);
        assert!(
            longest > 4096,
            "the scene must be dense: longest list {longest}"
        );
        let what = format!("16,384 lights, brute force {brute_force}");
        let close_calls =
            assert_matches_reference(&lists, &reference_for(&s, method, brute_force), &what);
        assert!(close_calls < 40, "too many close calls: {close_calls}");
    }
}

/// Every light covers every tile and every froxel: each list holds every light.
#[test]
fn lights_covering_every_cell_are_in_every_list() {
    let mut s = scene(53, 96, 64, 1, 2048);
    for l in &mut s.lights {
        l.radius = 1.0e4;
    }
    let n = s.lights.len();
    let tiled = run_gpu(&s, config(8, 1, false));
    assert_eq!(tiled.counters.dropped, 0);
    let surface_tiles = reference_for(&s, Method::tiled(8), false);
    for (c, got) in tiled.all_lists().iter().enumerate() {
        let want = if surface_tiles.lists[c].is_empty() {
            0
        } else {
            n
        };
        assert_eq!(got.len(), want, "tile {c}");
    }
    let grid = ClusterGrid {
        tile: 8,
        slices: 32,
        near: tests::cull_scene::NEAR,
        far: tests::cull_scene::FAR,
    };
    let config = ClusterCullConfig {
        grid,
        msaa: 1,
        vis64: false,
        skip_empty: false,
        brute_force: false,
        coarse_slots: None,
        index_capacity: 1 << 24,
        item_capacity: 4096,
    };
    let clustered = run_method(&s, GpuMethod::Clustered(config));
    assert_eq!(clustered.counters.dropped, 0);
    for (c, got) in clustered.all_lists().iter().enumerate() {
        assert_eq!(got.len(), n, "froxel {c}");
    }
}

/// Super-tiles with more candidates than slots fall back to testing every light, and the lists
/// stay exactly those of the reference.
#[test]
fn super_tiles_out_of_slots_fall_back_to_every_light() {
    let s = scene(55, 160, 96, 1, 300);
    let method = Method::tiled(16);
    let gpu = run_gpu(
        &s,
        TileCullConfig {
            coarse_slots: Some(8),
            ..config(16, 1, false)
        },
    );
    assert!(gpu.counters.coarse_fallbacks > 0, "{:?}", gpu.counters);
    assert_eq!(gpu.counters.dropped, 0);
    let lists = gpu.all_lists();
    let close_calls =
        assert_matches_reference(&lists, &reference_for(&s, method, false), "fallback");
    assert!(close_calls < 10, "too many close calls: {close_calls}");
}

/// Cells of the slices next to the sample's when its view depth is within `1e-4` (relative) of a
/// slice boundary: GPU and CPU logarithms may bin it on either side.
fn slice_neighbours(method: Method, s: &CullScene, x: u32, y: u32, depth: f32) -> Vec<usize> {
    let Method::Clustered { grid, .. } = method else {
        return Vec::new();
    };
    [depth * (1.0 - 1e-4), depth * (1.0 + 1e-4)]
        .into_iter()
        .map(|d| method.cell_of(s.camera.width, s.camera.height, x, y, d))
        .filter(|&c| {
            grid.slices > 1 && c != method.cell_of(s.camera.width, s.camera.height, x, y, depth)
        })
        .collect()
}

/// Under the compute rasteriser the light culling reads its buffer of samples
/// (`cull_prepare`'s `vis64` variants) instead of a depth buffer: the same depths give the same
/// lists, froxel for froxel, with and without empty froxels skipped (which depends on which
/// froxels hold a sample) and with sky samples among them.
#[test]
fn clustered_lists_from_the_compute_rasterisers_samples_equal_the_depth_buffers() {
    let grid = ClusterGrid {
        tile: 16,
        slices: 32,
        near: tests::cull_scene::NEAR,
        far: tests::cull_scene::FAR,
    };
    for (seed, msaa) in msaa_cases(71) {
        let s = scene(seed, 150, 90, msaa, 300);
        let sky = s.depth.depth.iter().filter(|&&d| d >= 1.0).count();
        assert!(sky > 0, "the scene has sky samples");
        for skip_empty in [false, true] {
            let config = |vis64| ClusterCullConfig {
                grid,
                msaa,
                vis64,
                skip_empty,
                brute_force: false,
                coarse_slots: None,
                index_capacity: 1 << 20,
                item_capacity: 4096,
            };
            let sorted = |vis64| {
                let lists = run_method(&s, GpuMethod::Clustered(config(vis64))).all_lists();
                lists
                    .into_iter()
                    .map(|mut l| {
                        l.sort_unstable();
                        l
                    })
                    .collect::<Vec<_>>()
            };
            let (depth, samples) = (sorted(false), sorted(true));
            let listed = depth.iter().filter(|l| !l.is_empty()).count();
            assert!(listed > 0, "MSAA {msaa}: some froxel lists a light");
            let differ = depth.iter().zip(&samples).filter(|(a, b)| a != b).count();
            assert_eq!(
                differ,
                0,
                "MSAA {msaa}, skip empty {skip_empty}: {differ} of {} froxels differ",
                depth.len()
            );
        }
    }
}

#[test]
fn clustered_kernel_matches_cpu_reference_in_every_variant() {
    let grid = ClusterGrid {
        tile: 16,
        slices: 32,
        near: tests::cull_scene::NEAR,
        far: tests::cull_scene::FAR,
    };
    // 150×90 is not a multiple of the tile: the last column and row of tiles are partial.
    for (seed, msaa) in msaa_cases(31) {
        let s = scene(seed, 150, 90, msaa, 300);
        for skip_empty in [false, true] {
            let method = Method::Clustered { grid, skip_empty };
            for brute_force in [false, true] {
                let config = ClusterCullConfig {
                    grid,
                    msaa,
                    vis64: false,
                    skip_empty,
                    brute_force,
                    coarse_slots: None,
                    index_capacity: 1 << 20,
                    item_capacity: 4096,
                };
                let gpu = run_method(&s, GpuMethod::Clustered(config));
                assert_eq!(
                    (gpu.counters.coarse_fallbacks, gpu.counters.dropped),
                    (0, 0)
                );
                let lists = gpu.all_lists();
                let reference = reference_for(&s, method, brute_force);
                let mut close_calls = 0;
                for (c, got) in lists.iter().enumerate() {
                    let want = &reference.lists[c];
                    if skip_empty && (got.is_empty() != want.is_empty()) {
                        // Occupancy of a froxel can differ when a sample sits on a slice
                        // boundary; the conservative check below covers those samples.
                        close_calls += 1;
                        continue;
                    }
                    for light in symmetric_difference(got, want) {
                        let close_call = reference.borderline[c].iter().any(|b| b.light == light);
                        assert!(
                            close_call,
                            "froxel {c} ({method:?}, MSAA {msaa}, brute force {brute_force}): light {light} ({:?}) is {} on the GPU but the reference is sure",
                            s.lights_view()[light as usize],
                            if got.contains(&light) {
                                "listed"
                            } else {
                                "missing"
                            }
                        );
                        close_calls += 1;
                    }
                }
                assert!(close_calls < 20, "too many close calls: {close_calls}");
                assert_conservative(&s, &lists, method);
            }
        }
    }
}

#[test]
fn overflow_reported_asynchronously_then_buffers_grow_for_the_next_frame() {
    use renderer::culling::lists::CullCounters;
    use renderer::culling::overflow::grow_for;
    use renderer::readback_ring::ReadbackRing;
    let s = scene(41, 128, 96, 1, 400);
    let reference = run_gpu(&s, config(16, 1, false)).all_lists();
    let (first, second, grown) = gpu_test(|gpu| {
        let (w, h) = (s.camera.width, s.camera.height);
        let depth = write_msaa_depth(gpu, w, h, 1, &s.depth.depth);
        let view = depth.create_view(&Default::default());
        let small = TileCullConfig {
            index_capacity: 256,
            ..config(16, 1, false)
        };
        let mut culling = TiledCulling::new(gpu, small, w, h).expect("setup");
        let items: Vec<CullSphere> = s
            .lights
            .iter()
            .map(|l| CullSphere::new(l.center, l.radius))
            .collect();
        let mut readback = ReadbackRing::new(gpu.device(), "counters", CullCounters::WORDS);
        let frame = |culling: &mut TiledCulling, readback: &mut ReadbackRing, n: u64| {
            culling
                .upload(
                    gpu,
                    s.camera.view,
                    s.camera.projection,
                    UVec2::new(w, h),
                    CullItems::lights(&items),
                )
                .expect("upload");
            let mut encoder = gpu.device().create_command_encoder(&Default::default());
            culling
                .levels
                .encode(
                    gpu.device(),
                    &mut renderer::graph::PassEncoder::untimed(&mut encoder),
                    DepthInput::Texture(&view),
                    false,
                )
                .expect("the culling buffers bind");
            let counters = (&culling.levels.lists.counters, CullCounters::WORDS * 4);
            assert!(readback.record(&mut encoder, &[counters], n));
            gpu.queue().submit([encoder.finish()]);
            readback.after_submit();
        };
        frame(&mut culling, &mut readback, 1);
        // The frame loop polls without blocking; here we give the GPU a bounded time to finish.
        let mut arrived = None;
        for _ in 0..1000 {
            arrived = readback.poll(gpu.device());
            if arrived.is_some() {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        let (n, words) = arrived.expect("the counters arrive within 2 s");
        let first = CullCounters::from_words(&words);
        assert_eq!(n, 1);
        let caps = grow_for(&first, culling.levels.shape.index_capacity)
            .expect("an overflowing frame must grow the index list");
        culling.levels.grow(gpu.device(), caps);
        frame(&mut culling, &mut readback, 2);
        (
            first,
            culling.levels.lists.read_back(gpu).expect("readback"),
            caps,
        )
    });
    assert!(first.dropped > 0, "frame 1 overflows: {first:?}");
    assert!(grown >= first.requested_entries);
    assert_eq!(
        second.counters.dropped, 0,
        "frame 2 has room for everything"
    );
    assert_eq!(
        second.all_lists(),
        reference,
        "frame 2 lists what an unconstrained run lists"
    );
}

#[test]
fn an_index_list_larger_than_a_binding_is_a_clear_error() {
    use renderer::culling::{CullError, max_index_entries};
    gpu_test(|gpu| {
        let too_big = max_index_entries(gpu.device()) + 1;
        let config = TileCullConfig {
            index_capacity: too_big,
            ..config(16, 1, false)
        };
        match TiledCulling::new(gpu, config, 64, 64) {
            Err(CullError::IndexListTooLarge {
                entries,
                max_entries,
            }) => {
                assert_eq!((entries, max_entries), (too_big, too_big - 1));
            }
            other => panic!("expected IndexListTooLarge, got {other:?}"),
        }
    });
}
