//! Decals in the culling kernels: oriented boxes in the same item buffer and cell lists as the
//! lights, against the CPU reference's box culling (`reference::cull_boxes`), in every method
//! and variant the software driver runs.
//!
//! For every run: the lights' lists are exactly those of the same run without decals; each
//! cell's decal list is strictly ascending (the layer order shading applies); it differs from
//! the reference only by boxes the reference calls borderline; every box that contains a
//! sample's surface point is in that sample's list (conservative, independently of the
//! reference); and the boxes are tested as boxes: their lists are far shorter than their
//! bounding spheres' would be.

use renderer::culling::clustered::ClusterCullConfig;
use renderer::culling::lists::CullReadback;
use renderer::culling::reference::{CellLists, ClusterGrid, Method, cull, cull_boxes, exact};
use renderer::culling::tiled::TileCullConfig;
use renderer::decals::OrientedBox;
use tests::cull_run::{
    GpuMethod, msaa_cases, run_method, run_with_boxes, symmetric_difference, tiled_methods,
};
use tests::cull_scene::{CullScene, decal_boxes, scene};

fn tiled(tile: u32, msaa: u32, depth_mask: bool, transparent: bool, brute: bool) -> GpuMethod {
    GpuMethod::Tiled(TileCullConfig {
        tile,
        msaa,
        depth_mask,
        transparent_lists: transparent,
        brute_force: brute,
        coarse_slots: None,
        index_capacity: 1 << 20,
        item_capacity: 1 << 12,
    })
}

fn clustered(grid: ClusterGrid, msaa: u32, skip_empty: bool, brute: bool) -> GpuMethod {
    GpuMethod::Clustered(ClusterCullConfig {
        grid,
        msaa,
        vis64: false,
        skip_empty,
        brute_force: brute,
        coarse_slots: None,
        index_capacity: 1 << 20,
        item_capacity: 1 << 12,
    })
}

/// What one checked run found.
struct Checked {
    decal_entries: usize,
    close_calls: usize,
}

/// Runs `gpu_method` with the scene's lights and `boxes`, and checks everything the module doc
/// promises against the reference's `method`.
fn check(
    s: &CullScene,
    boxes: &[OrientedBox],
    gpu_method: GpuMethod,
    method: Method,
    brute: bool,
) -> Checked {
    let what = format!("{gpu_method:?}");
    let with = run_with_boxes(s, gpu_method, boxes);
    let without = run_method(s, gpu_method);
    assert_eq!(with.counters.dropped, 0, "{what}");
    assert_eq!(
        with.all_lists(),
        without.all_lists(),
        "{what}: decals change no light list"
    );
    let views = s.boxes_view(boxes);
    let reference = cull_boxes(&s.camera, &s.depth, &views, method, !brute);
    let lists = with.all_decal_lists();
    for (c, list) in lists.iter().enumerate() {
        assert!(
            list.windows(2).all(|w| w[0] < w[1]),
            "{what}: cell {c}'s decals are not in layer order: {list:?}"
        );
    }
    let close_calls = compare(&lists, &reference, method, &what);
    assert_conservative(s, &views, &lists, method, &what);
    Checked {
        decal_entries: lists.iter().map(Vec::len).sum(),
        close_calls,
    }
}

/// Every GPU decal list equals the reference's but for borderline boxes; with skip-empty
/// clustering a froxel whose occupancy differs (a sample on a slice boundary) is a close call,
/// which the conservative check covers.
fn compare(lists: &[Vec<u32>], reference: &CellLists, method: Method, what: &str) -> usize {
    let skip_empty = matches!(
        method,
        Method::Clustered {
            skip_empty: true,
            ..
        }
    );
    let mut close_calls = 0;
    for (c, got) in lists.iter().enumerate() {
        let want = &reference.lists[c];
        if skip_empty && got.is_empty() != want.is_empty() {
            close_calls += 1;
            continue;
        }
        for item in symmetric_difference(got, want) {
            assert!(
                reference.borderline[c].iter().any(|b| b.light == item),
                "{what}: cell {c}: decal {item} is {} on the GPU but the reference is sure",
                if got.contains(&item) {
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

/// Every box containing a sample's surface point is in the sample's list (or, within `f32`
/// noise of a slice boundary, in the neighbouring slice's).
fn assert_conservative(
    s: &CullScene,
    views: &[OrientedBox],
    lists: &[Vec<u32>],
    method: Method,
    what: &str,
) {
    let (w, h) = (s.camera.width, s.camera.height);
    let mut checked = 0;
    exact::for_each_surface_sample_pub(&s.camera, &s.depth, |x, y, p| {
        let depths = [-p.z, -p.z * (1.0 - 1e-4), -p.z * (1.0 + 1e-4)];
        let cells: Vec<usize> = depths
            .iter()
            .map(|&d| method.cell_of(w, h, x, y, d))
            .collect();
        for (i, b) in views.iter().enumerate() {
            // Strictly inside, by more than f32 noise: the box must be listed.
            let local = b.local(p).abs().max_element();
            if local < 0.5 - 1e-4 {
                checked += 1;
                let listed = cells
                    .iter()
                    .any(|&c| lists[c].binary_search(&(i as u32)).is_ok());
                assert!(
                    listed,
                    "{what}: decal {i} contains the surface at pixel ({x},{y}) but cell {} \
                     lacks it",
                    cells[0]
                );
            }
        }
    });
    assert!(checked > 0, "{what}: no box covers any surface sample");
}

/// The boxes' entries when culled as their bounding spheres, by the reference.
fn sphere_entries(s: &CullScene, boxes: &[OrientedBox], method: Method) -> usize {
    let spheres: Vec<_> = s
        .boxes_view(boxes)
        .iter()
        .map(|b| {
            let (center, radius) = b.bounding_sphere();
            renderer::culling::reference::LightSphere { center, radius }
        })
        .collect();
    cull(&s.camera, &s.depth, &spheres, method).total_entries()
}

#[test]
fn decal_boxes_match_the_reference_in_every_tiled_and_depth_mask_variant() {
    for (seed, msaa) in msaa_cases(61) {
        let s = scene(seed, 160, 96, msaa, 200);
        let boxes = decal_boxes(seed, 120, 12);
        for depth_mask in [false, true] {
            for method in tiled_methods(depth_mask) {
                let (tile, transparent) = (method.tile(), method.transparent_lists());
                for brute in [false, true] {
                    let gpu = tiled(tile, msaa, depth_mask, transparent, brute);
                    let found = check(&s, &boxes, gpu, method, brute);
                    assert!(found.close_calls < 10, "{gpu:?}: {}", found.close_calls);
                    if !brute && !transparent {
                        let spheres = sphere_entries(&s, &boxes, method);
                        assert!(
                            found.decal_entries * 10 < spheres * 9,
                            "{method:?}: boxes must be tested as boxes: {} entries, their \
                                 spheres {spheres}",
                            found.decal_entries
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn decal_boxes_match_the_reference_in_every_clustered_variant() {
    let grid = ClusterGrid {
        tile: 16,
        slices: 32,
        near: tests::cull_scene::NEAR,
        far: tests::cull_scene::FAR,
    };
    for (seed, msaa) in msaa_cases(71) {
        let s = scene(seed, 150, 90, msaa, 200);
        let boxes = decal_boxes(seed, 120, 12);
        for skip_empty in [false, true] {
            for brute in [false, true] {
                let method = Method::Clustered { grid, skip_empty };
                let gpu = clustered(grid, msaa, skip_empty, brute);
                let found = check(&s, &boxes, gpu, method, brute);
                assert!(found.close_calls < 20, "{gpu:?}: {}", found.close_calls);
                if !brute && skip_empty {
                    let spheres = sphere_entries(&s, &boxes, method);
                    assert!(
                        found.decal_entries * 10 < spheres * 9,
                        "{method:?}: {} entries, spheres {spheres}",
                        found.decal_entries
                    );
                }
            }
        }
    }
}

/// 700 boxes overlapping one spot: a tile's hits no longer fit workgroup memory, so the kernels
/// write in arrival order and sort each decal list afterwards. The lists are still complete and
/// in layer order.
#[test]
fn a_crowd_of_decals_past_the_hit_cache_is_listed_completely_in_layer_order() {
    let s = scene(81, 128, 96, 1, 50);
    let boxes = decal_boxes(81, 20, 700);
    let grid = ClusterGrid {
        tile: 16,
        slices: 32,
        near: tests::cull_scene::NEAR,
        far: tests::cull_scene::FAR,
    };
    for (gpu, method) in [
        (tiled(16, 1, false, false, false), Method::tiled(16)),
        (
            clustered(grid, 1, true, false),
            Method::Clustered {
                grid,
                skip_empty: true,
            },
        ),
    ] {
        let found = check(&s, &boxes, gpu, method, false);
        let readback: CullReadback = run_with_boxes(&s, gpu, &boxes);
        let longest = readback
            .all_decal_lists()
            .iter()
            .map(Vec::len)
            .max()
            .unwrap_or(0);
        assert!(
            longest > 512,
            "{method:?}: the crowd must overflow: {longest}"
        );
        assert!(found.close_calls < 20, "{method:?}: {}", found.close_calls);
    }
}

/// A full index list drops a tile's light and decal lists together, counts them, and leaves
/// every other tile's lists whole.
#[test]
fn a_full_index_list_drops_decal_lists_whole_and_counts_them() {
    let s = scene(91, 128, 96, 1, 100);
    let boxes = decal_boxes(91, 150, 0);
    let roomy = run_with_boxes(&s, tiled(16, 1, false, false, false), &boxes);
    let total = roomy.counters.requested_entries;
    let capacity = total / 3;
    let tight = GpuMethod::Tiled(TileCullConfig {
        index_capacity: capacity,
        ..match tiled(16, 1, false, false, false) {
            GpuMethod::Tiled(c) => c,
            GpuMethod::Clustered(_) => unreachable!("tiled"),
        }
    });
    let cut = run_with_boxes(&s, tight, &boxes);
    let stored: u32 = cut.grid.iter().map(|g| g.y).sum();
    assert_eq!(stored + cut.counters.dropped, total, "nothing lost unseen");
    assert!(cut.counters.dropped > 0 && stored > 0);
    let cells = cut.cells();
    for c in 0..cells {
        let (lights, decals) = (cut.grid[c].y, cut.grid[cells + c].y);
        let (all_lights, all_decals) = (roomy.grid[c].y, roomy.grid[cells + c].y);
        assert!(
            (lights, decals) == (all_lights, all_decals) || (lights, decals) == (0, 0),
            "tile {c}: its lists are whole or dropped together"
        );
        if decals > 0 {
            assert_eq!(cut.cell_decals(c), roomy.cell_decals(c), "tile {c}");
        }
    }
}
