//! The CPU culling reference checked against the exact answer: on seeded scenes with depth
//! discontinuities, every light that reaches a sample is in that sample's cell list (up to the
//! stated `f32` tolerance), and the cull-efficiency ordering holds.

use renderer::culling::reference::{
    CellLists, ClusterGrid, Method, cull,
    exact::{LightGrid, cull_efficiency, lights_reaching},
};
use tests::cull_scene::{CullScene, FAR, NEAR, scene};

fn methods() -> Vec<Method> {
    let grid = ClusterGrid {
        tile: 16,
        slices: 32,
        near: NEAR,
        far: FAR,
    };
    let mut m: Vec<Method> = [8, 16, 32]
        .into_iter()
        .flat_map(|tile| [Method::tiled(tile), Method::depth25(tile)])
        .collect();
    m.push(Method::Clustered {
        grid,
        skip_empty: false,
    });
    m.push(Method::Clustered {
        grid,
        skip_empty: true,
    });
    m
}

/// Asserts that no light reaching a sample is missing from the sample's list.
fn assert_conservative(s: &CullScene, method: Method, lists: &CellLists) {
    let lights = s.lights_view();
    let grid = LightGrid::new(&s.camera, &s.depth, &lights);
    let mut checked = 0usize;
    renderer::culling::reference::exact::for_each_surface_sample_pub(
        &s.camera,
        &s.depth,
        |x, y, p| {
            let cell = method.cell_of(s.camera.width, s.camera.height, x, y, -p.z);
            for light in lights_reaching(&grid, &lights, p) {
                checked += 1;
                let listed = lists.lists[cell].binary_search(&light).is_ok();
                let close_call = lists.borderline[cell].iter().any(|b| b.light == light);
                assert!(
                    listed || close_call,
                    "{method:?}: light {light} reaches sample at pixel ({x},{y}) (view {p}) but is \
                 missing from cell {cell}"
                );
            }
        },
    );
    assert!(
        checked > 1000,
        "{method:?}: too few light/sample pairs checked ({checked})"
    );
}

#[test]
fn every_method_is_conservative_msaa1_and_msaa4() {
    // 100×70 is not a multiple of the tiles or the froxel grid: edge cells are partial.
    for (seed, samples, w, h) in [(1, 1, 128, 96), (2, 4, 128, 96), (4, 1, 100, 70)] {
        let s = scene(seed, w, h, samples, 200);
        let lights = s.lights_view();
        for method in methods() {
            let lists = cull(&s.camera, &s.depth, &lights, method);
            assert_conservative(&s, method, &lists);
        }
    }
}

#[test]
fn special_lights_are_handled() {
    let s = scene(3, 128, 96, 1, 0);
    let lights = s.lights_view();
    let lists = cull(&s.camera, &s.depth, &lights, Method::tiled(16));
    let count = |light: u32| lists.lists.iter().filter(|l| l.contains(&light)).count();
    let (behind, _near, huge, zero) = (0, 1, 2, 3);
    assert_eq!(
        count(behind),
        0,
        "a light behind the camera touches no tile"
    );
    let surface_tiles = lists.lists.iter().filter(|l| !l.is_empty()).count();
    assert_eq!(
        count(huge),
        surface_tiles,
        "a huge light is in every tile with a surface"
    );
    assert_eq!(
        count(zero),
        0,
        "a zero-radius light in mid-air touches nothing"
    );
    let crowded = lists.lists.iter().map(Vec::len).max().unwrap_or(0);
    assert!(
        crowded >= 64,
        "the crowded spot puts 64+ lights in one tile ({crowded})"
    );
}

#[test]
fn depth_mask_and_clusters_beat_plain_tiles() {
    for lights in [256, 1024] {
        let s = scene(7, 192, 128, 1, lights);
        let view_lights = s.lights_view();
        let efficiency = |method| {
            let lists = cull(&s.camera, &s.depth, &view_lights, method);
            cull_efficiency(&s.camera, &s.depth, &view_lights, method, &lists).ratio()
        };
        let tiled = efficiency(Method::tiled(16));
        let depth25 = efficiency(Method::depth25(16));
        let grid = ClusterGrid {
            tile: 16,
            slices: 32,
            near: NEAR,
            far: FAR,
        };
        let clustered = efficiency(Method::Clustered {
            grid,
            skip_empty: true,
        });
        assert!(tiled >= 1.0 && depth25 >= 1.0 && clustered >= 1.0);
        assert!(
            depth25 <= tiled,
            "2.5D ({depth25}) must not list more than tiled ({tiled})"
        );
        assert!(
            clustered <= tiled,
            "clustered ({clustered}) must beat tiled ({tiled})"
        );
    }
}

#[test]
fn spot_bounding_sphere_contains_its_cone() {
    use glam::Vec3;
    use renderer::culling::reference::LightSphere;
    use tests::cull_scene::Rng;
    let mut rng = Rng::new(5);
    for cos_outer in [0.99f32, 0.9, 0.75, 0.5, 0.2, 0.0] {
        let (apex, dir, range) = (
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.3, -1.0, 0.2).normalize(),
            4.0,
        );
        let sphere = LightSphere::spot(apex, dir, cos_outer, range);
        let naive_radius = range;
        assert!(
            sphere.radius <= naive_radius + 1e-5,
            "never worse than the point-light sphere"
        );
        let (u, v) = (dir.any_orthonormal_pair().0, dir.any_orthonormal_pair().1);
        let sin_outer = (1.0 - cos_outer * cos_outer).sqrt();
        for _ in 0..2000 {
            // A random point of the cone: within the angle and within range of the apex.
            let t = rng.range(0.0, 1.0).sqrt() * range;
            let a = rng.range(0.0, std::f32::consts::TAU);
            let s = rng.range(0.0, 1.0).sqrt() * sin_outer;
            let c = (1.0 - s * s).sqrt();
            let p = apex + t * (c * dir + s * (a.cos() * u + a.sin() * v));
            assert!(
                sphere.center.distance(p) <= sphere.radius * (1.0 + 1e-5) + 1e-5,
                "cone point {p} outside the bounding sphere (cos {cos_outer})"
            );
        }
    }
}

/// Prints the cull-efficiency table (listed ÷ reaching, and lights per non-empty cell) for every
/// method and tile size on the fixed scene with 1,024 and 4,096 lights, and checks its ordering.
/// Run with `--nocapture` to see it.
#[test]
#[expect(clippy::print_stdout, reason = "the table is this test's report")]
fn cull_efficiency_table() {
    println!("| lights | method | tile | listed/reaching | lights per non-empty cell |");
    println!("|---:|---|---:|---:|---:|");
    for lights in [1024, 4096] {
        let s = scene(7, 256, 144, 1, lights);
        let view_lights = s.lights_view();
        let row = |name: &str, tile: &str, method| {
            let lists = cull(&s.camera, &s.depth, &view_lights, method);
            let e = cull_efficiency(&s.camera, &s.depth, &view_lights, method, &lists);
            let non_empty: Vec<usize> = lists
                .lists
                .iter()
                .map(Vec::len)
                .filter(|&n| n > 0)
                .collect();
            let per_cell = non_empty.iter().sum::<usize>() as f64 / non_empty.len().max(1) as f64;
            println!(
                "| {lights} | {name} | {tile} | {:.2} | {per_cell:.1} |",
                e.ratio()
            );
            e.ratio()
        };
        for tile in [8, 16, 32] {
            let tiled = row("tiled", &tile.to_string(), Method::tiled(tile));
            let depth25 = row("2.5D", &tile.to_string(), Method::depth25(tile));
            assert!(
                depth25 <= tiled,
                "2.5D must not list more than tiled at tile {tile}"
            );
        }
        let grid = ClusterGrid {
            tile: 16,
            slices: 32,
            near: NEAR,
            far: FAR,
        };
        row(
            "clustered 16x8x24",
            "-",
            Method::Clustered {
                grid,
                skip_empty: false,
            },
        );
        row(
            "clustered 16x8x24, skip empty",
            "-",
            Method::Clustered {
                grid,
                skip_empty: true,
            },
        );
    }
}
