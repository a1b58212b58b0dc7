//! Forward shading on the GPU against plain-Rust references: the PBR light loop and falloff
//! (naive variant) against a CPU evaluation of the formulas, the tiled and clustered light-list
//! lookups against naive (complete lists) and against the CPU with deliberately partial lists,
//! the tonemapper against its CPU curve + sRGB encode, and the light-count heatmap's ramp.

mod forward_kernels;
mod forward_reference;
mod forward_scene;

use forward_kernels::{dispatch_tonemap, draw_forward, draw_heatmap, draw_prez, draw_tonemap};
use forward_reference::{Light, aces_cpu, neutral_cpu, ramp_cpu, shade_cpu, srgb_encode};
use forward_scene::{
    FAR, FROXELS, NEAR, SIZE, SLICES, SURFACE, TILE, froxel, inputs, key, quad, quad_point, scene,
};
use glam::{Mat4, UVec2, Vec3, Vec4, Vec4Swizzles as _};
use shaders_gen::forward::{forward, heatmap, prez, tonemap, tonemap_compute};
use tests::gpu::gpu_test;

/// Compares a GPU image with the CPU radiance at every pixel. Tolerance: f32 on both sides,
/// but the GPU interpolates the world position barycentrically and lavapipe's `pow`,
/// `normalize` and division are LLVM approximations (a few ulp); the GGX lobe amplifies relative
/// errors of `n·h` by at most ~10 here. 2e-3 relative (+1e-5 absolute) is ~100× the error
/// observed, and far below any formula slip (a wrong k, a missing π or a squared window changes
/// values by tens of percent).
fn assert_matches_cpu(image: &[[f32; 4]], expected: impl Fn(u32, u32) -> Vec3, what: &str) {
    let mut worst = 0.0f32;
    for y in 0..SIZE {
        for x in 0..SIZE {
            let got = Vec4::from(image[(y * SIZE + x) as usize]);
            let want = expected(x, y);
            for c in 0..3 {
                let err = (got[c] - want[c]).abs();
                let bound = 2e-3 * want[c].abs() + 1e-5;
                assert!(
                    err <= bound,
                    "{what}: pixel ({x},{y}) channel {c}: GPU {} vs CPU {}",
                    got[c],
                    want[c]
                );
                worst = worst.max(err / want[c].abs().max(1e-3));
            }
            assert_eq!(got.w, 1.0, "{what}: opaque alpha at ({x},{y})");
        }
    }
    eprintln!("{what}: worst relative error {worst:e}");
}

fn gpu_lights(lights: &[Light]) -> Vec<forward::GpuLight> {
    lights.iter().map(Light::gpu).collect()
}

#[test]
fn naive_forward_matches_cpu_brdf_and_falloff() {
    let s = scene();
    let (lights, directional) = (gpu_lights(&s.lights), gpu_lights(&s.directional));
    let vertices = quad();
    let image = gpu_test(|gpu| {
        draw_forward(
            gpu,
            key(forward::List::List0, false),
            &inputs(&s, &lights, &directional, &[], &[], &vertices),
        )
    });
    let all: Vec<Light> = s.directional.iter().chain(&s.lights).copied().collect();
    assert_matches_cpu(
        &image,
        |x, y| shade_cpu(quad_point(&s, x, y), Vec3::Z, s.eye, &SURFACE, &all),
        "naive",
    );
    // The scene exercises what it claims: the windowed light fades out inside the image and
    // the spot cone has an edge.
    let centre = shade_cpu(Vec3::ZERO, Vec3::Z, s.eye, &SURFACE, &all);
    assert!(centre.x > 0.1, "lit centre {centre}");
    let windowed = &s.lights[2];
    let far_corner = quad_point(&s, SIZE - 1, SIZE - 1);
    assert!(windowed.position.distance(far_corner) > windowed.range);
}

/// Every tile and every froxel lists every light, in order.
fn complete_lists(count: u32, cells: u32) -> (Vec<UVec2>, Vec<u32>) {
    (
        vec![UVec2::new(0, count); cells as usize],
        (0..count).collect(),
    )
}

#[test]
fn tiled_and_clustered_with_complete_lists_equal_naive() {
    let s = scene();
    let (lights, directional) = (gpu_lights(&s.lights), gpu_lights(&s.directional));
    let vertices = quad();
    let n = lights.len() as u32;
    let tiles = SIZE.div_ceil(TILE).pow(2);
    let (tile_grid, tile_indices) = complete_lists(n, tiles);
    let (cluster_grid, cluster_indices) = complete_lists(n, FROXELS);
    let (naive, tiled, clustered, scalar) = gpu_test(|gpu| {
        let run = |k, grid: &[UVec2], indices: &[u32]| {
            draw_forward(
                gpu,
                k,
                &inputs(&s, &lights, &directional, grid, indices, &vertices),
            )
        };
        let scalar = gpu.capabilities().subgroup.is_some().then(|| {
            (
                run(key(forward::List::List1, true), &tile_grid, &tile_indices),
                run(
                    key(forward::List::List2, true),
                    &cluster_grid,
                    &cluster_indices,
                ),
            )
        });
        (
            run(key(forward::List::List0, false), &[], &[]),
            run(key(forward::List::List1, false), &tile_grid, &tile_indices),
            run(
                key(forward::List::List2, false),
                &cluster_grid,
                &cluster_indices,
            ),
            scalar,
        )
    });
    // Same lights in the same order through the same function: only the loop bound's source
    // differs, so the images agree to rounding (exact on lavapipe).
    let close = |a: &[[f32; 4]], b: &[[f32; 4]], what: &str| {
        for (i, (p, q)) in a.iter().zip(b).enumerate() {
            for c in 0..4 {
                assert!(
                    (p[c] - q[c]).abs() <= 1e-6 * p[c].abs().max(1.0),
                    "{what} differs from naive at pixel {i}: {p:?} vs {q:?}"
                );
            }
        }
    };
    close(&naive, &tiled, "tiled");
    close(&naive, &clustered, "clustered");
    let (tiled_scalar, clustered_scalar) = scalar.expect("lavapipe has SUBGROUP");
    close(&naive, &tiled_scalar, "tiled scalarized");
    close(&naive, &clustered_scalar, "clustered scalarized");
}

/// The subset of lights cell `cell` lists in the partial-list tests: a different, non-empty or
/// empty subset per cell, so reading the wrong cell shows.
fn partial_subset(cell: u32, count: u32) -> Vec<u32> {
    (0..count)
        .filter(|&l| (cell.wrapping_mul(2_654_435_761) >> (l * 3 + 5)) & 1 == 1)
        .collect()
}

fn partial_lists(cells: u32, count: u32) -> (Vec<UVec2>, Vec<u32>) {
    let mut grid = Vec::new();
    let mut indices = Vec::new();
    for cell in 0..cells {
        let list = partial_subset(cell, count);
        grid.push(UVec2::new(indices.len() as u32, list.len() as u32));
        indices.extend(list);
    }
    (grid, indices)
}

/// `cluster_cull`'s slice of a view depth.
fn slice_of(d: f32) -> u32 {
    let t = (d / NEAR).ln() / (FAR / NEAR).ln();
    ((t * SLICES as f32).floor().max(0.0) as u32).min(SLICES - 1)
}

#[test]
fn tiled_and_clustered_read_their_partial_lists() {
    let s = scene();
    let (lights, directional) = (gpu_lights(&s.lights), gpu_lights(&s.directional));
    let vertices = quad();
    let n = lights.len() as u32;
    let tiles_x = SIZE.div_ceil(TILE);
    let (tile_grid, tile_indices) = partial_lists(tiles_x * tiles_x, n);
    let (cluster_grid, cluster_indices) = partial_lists(FROXELS, n);
    let scalar = gpu_test(|gpu| gpu.capabilities().subgroup.is_some());
    for scalarize in [false, true].into_iter().filter(|&sc| !sc || scalar) {
        let (naive, tiled, clustered) = gpu_test(|gpu| {
            let run = |k, grid: &[UVec2], indices: &[u32]| {
                draw_forward(
                    gpu,
                    k,
                    &inputs(&s, &lights, &directional, grid, indices, &vertices),
                )
            };
            (
                run(key(forward::List::List0, false), &[], &[]),
                run(
                    key(forward::List::List1, scalarize),
                    &tile_grid,
                    &tile_indices,
                ),
                run(
                    key(forward::List::List2, scalarize),
                    &cluster_grid,
                    &cluster_indices,
                ),
            )
        });
        assert_ne!(tiled, naive, "partial tile lists must change the image");
        assert_ne!(
            clustered, naive,
            "partial froxel lists must change the image"
        );
        let expected = |cell: u32, x: u32, y: u32| {
            let mut used: Vec<Light> = s.directional.clone();
            used.extend(
                partial_subset(cell, n)
                    .iter()
                    .map(|&l| s.lights[l as usize]),
            );
            shade_cpu(quad_point(&s, x, y), Vec3::Z, s.eye, &SURFACE, &used)
        };
        assert_matches_cpu(
            &tiled,
            |x, y| expected((y / TILE) * tiles_x + x / TILE, x, y),
            &format!("tiled partial (scalarize {scalarize})"),
        );
        // The quad is at view depth 3 everywhere: slice 3 of 8 (t·8 = 3.11, far from an edge).
        let k = slice_of(3.0);
        assert_eq!(k, 3);
        assert_matches_cpu(
            &clustered,
            |x, y| expected(froxel(x, y, k), x, y),
            &format!("clustered partial (scalarize {scalarize})"),
        );
    }
}

/// A ramp of HDR colours through the tone curves' shoulders and toes (16 × 4 texels).
fn tonemap_input() -> ((u32, u32), Vec<[f32; 4]>) {
    let size = (16u32, 4u32);
    let hdr = (0..size.0 * size.1)
        .map(|i| {
            let t = i as f32 / 8.0;
            [t * 0.05, t * t * 0.1, (i % 5) as f32 * 0.7, 1.0]
        })
        .collect();
    (size, hdr)
}

/// The CPU's tonemap of `hdr` texel by texel: `curve` (0 ACES, 1 PBR Neutral) after
/// `exposure`, to 8 bits, sRGB-encoded or linear.
fn tonemap_cpu(hdr: &[[f32; 4]], exposure: f32, curve: u32, srgb: bool) -> Vec<[u8; 4]> {
    hdr.iter()
        .map(|px| {
            let c = Vec3::new(px[0], px[1], px[2]) * exposure;
            let mapped = match curve {
                0 => Vec3::new(aces_cpu(c.x), aces_cpu(c.y), aces_cpu(c.z)),
                _ => neutral_cpu(c),
            };
            let byte = |x: f32| {
                if srgb {
                    srgb_encode(x)
                } else {
                    (x.clamp(0.0, 1.0) * 255.0).round() as u8
                }
            };
            [byte(mapped.x), byte(mapped.y), byte(mapped.z), 255]
        })
        .collect()
}

/// Every texel of `bytes` within one 8-bit step of `want`.
fn assert_within_one_step(bytes: &[u8], want: &[[u8; 4]], what: &str) {
    assert_eq!(bytes.len(), want.len() * 4, "{what}: texel count");
    for (i, want) in want.iter().enumerate() {
        let got = &bytes[i * 4..i * 4 + 4];
        for c in 0..4 {
            assert!(
                (i32::from(got[c]) - i32::from(want[c])).abs() <= 1,
                "{what} texel {i} channel {c}: GPU {got:?} vs CPU {want:?}"
            );
        }
    }
}

#[test]
fn tonemap_matches_cpu_curve_and_srgb_encode() {
    let (size, hdr) = tonemap_input();
    let exposure = 1.5;
    for curve in tonemap::Curve::ALL {
        let bytes =
            gpu_test(|gpu| draw_tonemap(gpu, tonemap::VariantKey { curve }, exposure, size, &hdr));
        let want = tonemap_cpu(&hdr, exposure, curve.value(), true);
        assert_within_one_step(&bytes, &want, &format!("fragment {curve:?}"));
    }
}

/// The compute kernel encodes sRGB itself (a storage image cannot be sRGB): every variant
/// against the CPU's curve and encoding, sRGB and linear.
#[test]
fn compute_tonemap_matches_cpu_curve_and_srgb_encode() {
    let (size, hdr) = tonemap_input();
    let exposure = 1.5;
    for curve in tonemap_compute::Curve::ALL {
        for srgb in [false, true] {
            let key = tonemap_compute::VariantKey { curve, srgb };
            let bytes = gpu_test(|gpu| dispatch_tonemap(gpu, key, exposure, size, &hdr));
            let want = tonemap_cpu(&hdr, exposure, curve.value(), srgb);
            assert_within_one_step(&bytes, &want, &format!("compute {key:?}"));
        }
    }
}

fn assert_ramp_pixel(bytes: &[u8], x: u32, y: u32, t: f32, what: &str) {
    let want = ramp_cpu(t) * 255.0;
    let at = ((y * SIZE + x) * 4) as usize;
    let got = &bytes[at..at + 4];
    for c in 0..3 {
        assert!(
            (f32::from(got[c]) - want[c]).abs() <= 1.0,
            "{what} pixel ({x},{y}): GPU {got:?} vs ramp({t}) = {want}"
        );
    }
    assert_eq!(got[3], 255);
}

#[test]
fn heatmap_colours_counts_on_the_ramp_with_a_legend() {
    let s = scene();
    let max_count = 12u32;
    let tiles_x = SIZE.div_ceil(TILE);
    // Tile t lists t lights (counts 0..15, saturating past 12).
    let tile_grid: Vec<UVec2> = (0..tiles_x * tiles_x).map(|t| UVec2::new(0, t)).collect();
    let cells = FROXELS;
    let cluster_grid: Vec<UVec2> = (0..cells).map(|c| UVec2::new(0, c % 13)).collect();
    // Depth of view distance 3 for the clustered variant: slice 3.
    let clip = s.projection * Vec4::new(0.0, 0.0, -3.0, 1.0);
    let depth = clip.z / clip.w;
    let params = heatmap::HeatmapParams::new(
        s.projection.inverse(),
        UVec2::splat(SIZE),
        UVec2::splat(tiles_x),
        TILE,
        SLICES,
        NEAR,
        FAR,
        max_count,
        0,
    );
    let (tiled, clustered, sky) = gpu_test(|gpu| {
        let k = |list| heatmap::VariantKey {
            list,
            msaa: heatmap::Msaa::Msaa1,
        };
        (
            draw_heatmap(gpu, k(heatmap::List::List1), &params, &tile_grid, 0.0),
            draw_heatmap(gpu, k(heatmap::List::List2), &params, &cluster_grid, depth),
            draw_heatmap(gpu, k(heatmap::List::List2), &params, &cluster_grid, 1.0),
        )
    });
    let legend_top = SIZE - heatmap::LEGEND_ROWS;
    for y in (0..legend_top).step_by(5) {
        for x in (0..SIZE).step_by(3) {
            let tile = (y / TILE) * tiles_x + x / TILE;
            let t = tile as f32 / max_count as f32;
            assert_ramp_pixel(&tiled, x, y, t, "tiled");
            let k = slice_of(3.0);
            let cell = froxel(x, y, k);
            assert_ramp_pixel(
                &clustered,
                x,
                y,
                (cell % 13) as f32 / max_count as f32,
                "clustered",
            );
            assert_ramp_pixel(&sky, x, y, 0.0, "sky");
        }
    }
    for image in [&tiled, &clustered, &sky] {
        for y in legend_top..SIZE {
            for x in 0..SIZE {
                let t = x as f32 / (SIZE - 1) as f32;
                assert_ramp_pixel(image, x, y, t, "legend");
            }
        }
    }
}

#[test]
fn prez_writes_the_projected_depth_of_a_tilted_quad() {
    let s = scene();
    // The quad tilted 30° about X and pushed back: its depth varies down the image.
    let world = Mat4::from_translation(Vec3::new(0.0, 0.0, -1.0))
        * Mat4::from_rotation_x(30f32.to_radians());
    let vertices: Vec<[f32; 5]> = quad()
        .iter()
        .map(|v| [v[0] * 2.0, v[1] * 2.0, v[2], v[6], v[7]])
        .collect();
    let depth = gpu_test(|gpu| {
        draw_prez(
            gpu,
            SIZE,
            &prez::Camera::new(
                s.view,
                s.projection,
                s.projection * s.view,
                s.eye,
                s.eye.extend(1.0),
            ),
            &prez::Draw::new(world, world.inverse().transpose(), 0, 1.0),
            &vertices,
        )
    });
    // CPU: intersect the pixel-centre ray with the tilted plane, project, take z/w.
    let normal = world.transform_vector3(Vec3::Z);
    let origin = world.transform_point3(Vec3::ZERO);
    let view_projection = s.projection * s.view;
    let inv = view_projection.inverse();
    let mut spread = (f32::MAX, f32::MIN);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let ndc = Vec4::new(
                2.0 * (x as f32 + 0.5) / SIZE as f32 - 1.0,
                1.0 - 2.0 * (y as f32 + 0.5) / SIZE as f32,
                0.5,
                1.0,
            );
            let p = inv * ndc;
            let dir = p.xyz() / p.w - s.eye;
            let t = (origin - s.eye).dot(normal) / dir.dot(normal);
            let hit = s.eye + dir * t;
            let clip = view_projection * hit.extend(1.0);
            let want = clip.z / clip.w;
            let got = depth[(y * SIZE + x) as usize];
            // Depth is interpolated linearly in screen space in f32: a few ulp of [0, 1].
            assert!(
                (got - want).abs() <= 1e-5,
                "pixel ({x},{y}): depth {got} vs CPU {want}"
            );
            spread = (spread.0.min(want), spread.1.max(want));
        }
    }
    assert!(spread.1 - spread.0 > 1e-3, "depth varies: {spread:?}");
}
