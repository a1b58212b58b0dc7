//! The compute rasteriser (`ComputeRasterPass`) against the hardware raster it runs beside, on
//! lavapipe: the triangle ID of every sample, on the courtyard (large walls and floor crossing
//! the eye plane, rasterised by tiles) and a generated city (thousands of small triangles,
//! rasterised one invocation each), at MSAA 1 and 4, with both of its ways of working (the
//! default small-triangle limit, and every triangle by tiles).
//!
//! Both rasterisers see the same opaque triangles (alpha modes are made opaque here: the
//! compute rasteriser leaves masked draws to the hardware); they may differ only on samples
//! within rounding of an edge (the hardware snaps vertices to a sub-pixel grid, the compute
//! rasteriser evaluates edges in floating point) or of a depth tie. The stated tolerance is
//! 0.1% of samples (measured: at most 0.052%, 7 of 13,500 on the courtyard at MSAA 1);
//! neither a hole nor a different surface fits in it, nor depth planes that lose precision to
//! cancellation (computed without the reference depth, the city differs on 0.16%).
//!
//! A grid of square quads placed so that their vertical, horizontal and diagonal edges pass
//! exactly through pixel centres, drawn once as it is and once mirrored (a negative scale,
//! whose front faces wind clockwise), must give exactly the hardware's IDs at MSAA 1: ties on
//! shared edges go by the top-left rule on both, and no sample is lost or doubled.
//!
//! Mutations, each of which fails here: the edge tie rule dropped (`d > 0.0` only) or
//! reversed for horizontal edges, the mirrored winding ignored (the grid test), the sample
//! pattern's first MSAA 4 position at the pixel centre (the scene test: 1,514 of 61,440
//! samples differ on the courtyard).

use glam::{Mat4, Vec2, Vec3, Vec4};
use renderer::extend::{ComputeRasterCounts, ComputeRasterPass};
use renderer::frame::default_camera;
use renderer::frame::{
    FrameCamera, RenderPath, Renderer, RendererConfig, VisibilityRaster, create_target,
};
use renderer::passes::visibility::VisShadePass;
use renderer::scene::{Aabb, AlphaMode, Instance, Mesh, Primitive, Scene};
use tests::gpu::gpu_test;
use tests::host_replay::BindingsProbe;

/// Not multiples of the 16-pixel tiles: the screen's last tiles are partial.
const WIDTH: u32 = 150;
const HEIGHT: u32 = 90;
/// Samples allowed to differ, as a fraction of all samples.
const TOLERANCE: f64 = 0.001;

/// `scene` with every material opaque.
fn opaque(mut scene: Scene) -> Scene {
    for m in &mut scene.materials {
        m.alpha_mode = AlphaMode::Opaque;
    }
    scene
}

/// The hardware raster's IDs (`IDS`/`IDS_MS` as the shading kernel bound them) and the compute
/// rasteriser's, per sample, for one frame.
fn both_ids(
    scene: &Scene,
    camera: &FrameCamera,
    msaa: u32,
    small_area: u32,
) -> (Vec<u32>, Vec<u32>) {
    let (hardware, compute, counts) = both_ids_at(scene, camera, (WIDTH, HEIGHT, msaa), small_area);
    if small_area == 0 {
        assert!(
            counts.large > 0 && counts.tiles >= counts.large,
            "every triangle by tiles"
        );
    }
    (hardware, compute)
}

/// [`both_ids`] at another frame size, with what the compute rasteriser counted.
fn both_ids_at(
    scene: &Scene,
    camera: &FrameCamera,
    (width, height, msaa): (u32, u32, u32),
    small_area: u32,
) -> (Vec<u32>, Vec<u32>, ComputeRasterCounts) {
    // The frame's own raster is the hardware's, whose IDs the pass is compared with.
    let config = RendererConfig {
        width,
        height,
        msaa,
        path: RenderPath::Visibility,
        visibility_raster: VisibilityRaster::Hardware,
        ..Default::default()
    };
    gpu_test(|gpu| {
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer.prepare_scene(scene).expect("the scene fits");
        let raster = ComputeRasterPass::new(gpu, &config)
            .expect("lavapipe has 64-bit atomic min/max")
            .with_small_area(small_area);
        renderer
            .insert_pass_after("visibility", Box::new(raster))
            .expect("the compute rasteriser joins the frame");
        let program = renderer
            .pass::<VisShadePass>()
            .expect("the visibility path shades in compute")
            .program()
            .clone();
        renderer
            .insert_pass_after("visibility shading", Box::new(BindingsProbe::new(&program)))
            .expect("the probe joins the frame");
        let target = create_target(gpu.device(), &config);
        renderer.render(camera, &target).expect("frame");
        renderer.finish();
        let pass = renderer.pass::<ComputeRasterPass>().expect("the pass runs");
        let counts = pass.read_counts(gpu).expect("counters read back");
        assert_eq!(counts.overflow, 0, "no large triangle left out: {counts:?}");
        let compute = pass.read_ids(gpu).expect("samples read back");
        let bound = renderer
            .pass::<BindingsProbe>()
            .expect("the probe runs")
            .take(gpu)
            .expect("the kernel's bindings read back");
        // The target is loaded, not cleared, and sky samples keep what it held: a new
        // renderer's first frame, as here, finds it zeroed by wgpu, so they read 0.
        let name = if msaa == 1 { "IDS" } else { "IDS_MS" };
        let ids = bound.texture(name).expect("the IDs are bound");
        let hardware: Vec<u32> = ids
            .bytes
            .chunks_exact(4)
            .map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]]))
            .collect();
        eprintln!("MSAA {msaa}, small area {small_area}: {counts:?}");

        (hardware, compute, counts)
    })
}

/// Fails unless the two agree within [`TOLERANCE`]; returns how many samples differ.
fn assert_agree(what: &str, hardware: &[u32], compute: &[u32]) -> usize {
    assert_eq!(
        hardware.len(),
        compute.len(),
        "{what}: one ID per sample each"
    );
    let covered = hardware.iter().filter(|&&id| id != 0).count();
    let differ = hardware.iter().zip(compute).filter(|(h, c)| h != c).count();
    let holes = hardware
        .iter()
        .zip(compute)
        .filter(|&(&h, &c)| h != 0 && c == 0)
        .count();
    let fraction = differ as f64 / hardware.len() as f64;
    eprintln!(
        "{what}: {differ} of {} samples differ ({covered} covered, {holes} left empty by compute)",
        hardware.len()
    );
    assert!(
        covered > hardware.len() / 4,
        "{what}: the view sees the scene"
    );
    assert!(
        fraction <= TOLERANCE,
        "{what}: {differ} of {} samples differ ({holes} empty in compute only)",
        hardware.len()
    );
    differ
}

#[test]
fn compute_raster_sees_what_the_hardware_raster_sees() {
    let courtyard = opaque(renderer::scene::procedural::courtyard());
    let camera = default_camera(&courtyard, WIDTH as f32 / HEIGHT as f32);
    let city = renderer::scene::procedural::builtin("city:1500")
        .expect("the city generates")
        .expect("a built-in scene");
    let city_camera = default_camera(&city.scene, WIDTH as f32 / HEIGHT as f32);
    let city = opaque(city.scene);
    let mut tiles_only_differ = 0;
    for msaa in [1, 4] {
        for (name, scene, camera) in [
            ("courtyard", &courtyard, &camera),
            ("city", &city, &city_camera),
        ] {
            let small = renderer::extend::DEFAULT_SMALL_AREA;
            let (hardware, compute) = both_ids(scene, camera, msaa, small);
            assert_agree(&format!("{name}, MSAA {msaa}"), &hardware, &compute);
            if name == "city" {
                // Every triangle by tiles: the same IDs as the small-triangle path.
                let (_, tiled) = both_ids(scene, camera, msaa, 0);
                tiles_only_differ += assert_agree(
                    &format!("{name}, MSAA {msaa}, tiles only"),
                    &hardware,
                    &tiled,
                );
                assert_eq!(tiled, compute, "{name}, MSAA {msaa}: both ways, one result");
            }
        }
    }
    eprintln!("tiles only: {tiles_only_differ} samples differ in all");
}

/// Side of the grid test's square screen, in pixels.
const GRID_SCREEN: u32 = 64;

/// A grid of 4 × 7 square quads, 8 pixels a side, whose corners sit on pixel centres of a
/// [`GRID_SCREEN`]-pixel screen seen by [`grid_camera`] (NDC = world x and y), right of the
/// screen's centre; each quad's diagonal also runs through pixel centres.
fn grid_mesh() -> Mesh {
    let ndc = |px: f32, py: f32| {
        let size = GRID_SCREEN as f32;
        Vec3::new(px * 2.0 / size - 1.0, 1.0 - py * 2.0 / size, 0.0)
    };
    let (columns, rows) = (4u32, 7u32);
    let mut positions = Vec::new();
    for j in 0..=rows {
        for i in 0..=columns {
            positions.push(ndc(32.5 + 8.0 * i as f32, 4.5 + 8.0 * j as f32));
        }
    }
    let corner = |i: u32, j: u32| j * (columns + 1) + i;
    let mut indices = Vec::new();
    for j in 0..rows {
        for i in 0..columns {
            // Counter-clockwise seen from +Z (the screen's y runs down as j grows).
            let (a, b) = (corner(i, j + 1), corner(i + 1, j + 1));
            let (c, d) = (corner(i + 1, j), corner(i, j));
            indices.extend_from_slice(&[a, b, c, a, c, d]);
        }
    }
    let n = positions.len();
    let bounds = positions
        .iter()
        .fold(Aabb::EMPTY, |b, &p| b.union(Aabb { min: p, max: p }));
    Mesh {
        name: "pixel-centre grid".into(),
        primitives: vec![Primitive {
            normals: vec![Vec3::Z; n],
            uvs: vec![Vec2::ZERO; n],
            uvs1: Vec::new(),
            colors: Vec::new(),
            tangents: vec![Vec4::new(1.0, 0.0, 0.0, 1.0); n],
            indices,
            material: None,
            bounds,
            positions,
        }],
    }
}

/// Looks down −Z from z = 1, orthographic, NDC x and y equal to world x and y.
fn grid_camera() -> FrameCamera {
    FrameCamera::orthographic(Mat4::from_translation(Vec3::Z), (1.0, 1.0), (0.5, 1.5))
}

#[test]
fn compute_raster_breaks_ties_as_the_hardware_does() {
    let mesh = grid_mesh();
    let right = mesh.primitives[0].bounds;
    let mirror = Mat4::from_scale(Vec3::new(-1.0, 1.0, 1.0));
    let scene = Scene {
        meshes: vec![mesh],
        materials: Vec::new(),
        images: Vec::new(),
        // As it is on the right, mirrored on the left.
        instances: vec![
            Instance {
                mesh: 0,
                world_from_mesh: Mat4::IDENTITY,
            },
            Instance {
                mesh: 0,
                world_from_mesh: mirror,
            },
        ],
        cameras: Vec::new(),
        lights: Vec::new(),
        bounds: right.union(right.transformed(mirror)),
        warnings: Vec::new(),
    };
    let screen = (GRID_SCREEN, GRID_SCREEN, 1);
    // 81-pixel boxes: by tiles at the default limit, one invocation each above it.
    for small_area in [renderer::extend::DEFAULT_SMALL_AREA, 100] {
        let (hardware, compute, counts) = both_ids_at(&scene, &grid_camera(), screen, small_area);
        // The two ways of rasterising: every triangle by tiles, or none.
        let by_tiles = small_area < 81;
        assert_eq!(
            counts.large == 0,
            !by_tiles,
            "small area {small_area}: {counts:?}"
        );
        let ids: std::collections::BTreeSet<u32> = hardware.iter().copied().collect();
        assert_eq!(
            ids.len(),
            2 * 4 * 7 * 2 + 1,
            "every triangle of both grids, and sky"
        );
        let differ: Vec<usize> = (0..hardware.len())
            .filter(|&i| hardware[i] != compute[i])
            .collect();
        assert!(
            differ.is_empty(),
            "small area {small_area}: {} samples differ, the first at pixel {:?}: hardware {}, compute {}",
            differ.len(),
            differ
                .first()
                .map(|&i| (i as u32 % GRID_SCREEN, i as u32 / GRID_SCREEN)),
            differ.first().map_or(0, |&i| hardware[i]),
            differ.first().map_or(0, |&i| compute[i]),
        );
    }
}
