//! Shadow casters culled per atlas region on the GPU (`shadow_cull`, drawn with two
//! multi-draws per region) draw exactly what the CPU lists: a city lit by a sun (four
//! cascades) and shadowed street lights, edited frame after frame (an instance added in a
//! spare caster slot, one marked dynamic and moved over the static cache, one removed, the
//! camera turned so every cascade moves), against the same frames on a device without
//! `INDIRECT_FIRST_INSTANCE`, where the renderer tests every caster against every region on
//! the CPU and draws them one by one, and against GPU culling switched off. The shadow atlases
//! are compared texel for texel, with the static cache on and off; the casts the GPU counted
//! equal the CPU's list, and culling leaves most of them out.

use glam::{Mat4, Quat, Vec3};
use renderer::GpuContext;
use renderer::demo::pick_shadowed;
use renderer::frame::{FrameCamera, RenderPath, Renderer, RendererConfig};
use renderer::scene::SceneLight;
use renderer::shadow::ShadowReport;
use tests::frames::render_one_frame;
use tests::gpu::gpu_test;
use tests::shadow_probe::{ShadowAtlasProbe, ShadowAtlasReader};

use super::blended::without_indirect_first_instance;
use super::edits::{lights_with_sun, mesh};
use super::{SIZE, city, config, street_camera, street_lights};

/// The city's street lights with six of them shadowed, and a sun.
fn shadowed_lights(lights: &[SceneLight], camera: &FrameCamera) -> Vec<SceneLight> {
    let mut street = lights.to_vec();
    let picked = pick_shadowed(&mut street, camera, SIZE.1 as f32, 6);
    assert_eq!(picked, 6, "six street lights are in view to shadow");
    lights_with_sun(&street)
}

fn shadow_config(cull: bool, cache: bool) -> RendererConfig {
    let mut c = config(RenderPath::Tiled, 1, cull);
    c.shadows.atlas_size = 2048;
    c.shadows.max_resolution = 512;
    c.shadows.cascade_resolution = 512;
    c.shadows.cache = cache;
    c
}

/// One renderer and the probe reading its shadow atlas.
struct Session {
    renderer: Renderer,
    atlas: ShadowAtlasReader,
    gpu: GpuContext,
}

impl Session {
    fn new(gpu: &GpuContext, config: RendererConfig, lights: &[SceneLight]) -> Self {
        let scene = &city(600).scene;
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer.prepare_scene(scene).expect("the city fits");
        renderer.set_lights(lights).expect("lights fit");
        let atlas = ShadowAtlasProbe::insert(&mut renderer).expect("a shadow pass");
        Self {
            renderer,
            atlas,
            gpu: gpu.clone(),
        }
    }

    /// Renders from `camera`; the frame's shadow report and shadow atlas.
    fn frame(&mut self, camera: &FrameCamera) -> (ShadowReport, Vec<f32>) {
        let frame = render_one_frame(&self.gpu, &mut self.renderer, camera);
        let atlas = self.atlas.read(&self.gpu).expect("the atlas copy");
        (frame.report.shadows.expect("a shadow report"), atlas.atlas)
    }
}

/// Texels inside `report`'s regions that differ between two atlases of side 2048.
fn differing_in_regions(a: &[f32], b: &[f32], report: &ShadowReport) -> usize {
    assert_eq!(a.len(), b.len());
    let side = 2048;
    let mut wrong = 0;
    for (_, r) in &report.regions {
        for y in r.y..r.y + r.side {
            for x in r.x..r.x + r.side {
                let i = (y * side + x) as usize;
                wrong += usize::from(a[i].to_bits() != b[i].to_bits());
            }
        }
    }
    wrong
}

/// Texels that differ between two atlases.
fn differing(a: &[f32], b: &[f32]) -> usize {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .filter(|(x, y)| x.to_bits() != y.to_bits())
        .count()
}

#[test]
fn shadow_casters_culled_per_region_on_the_gpu_draw_what_the_cpu_lists() {
    let base = city(600);
    let camera = street_camera(&base.scene);
    let lights = shadowed_lights(&street_lights(&base), &camera);
    let (tower, dome) = (mesh(&base.scene, "tower"), mesh(&base.scene, "dome"));
    let ahead = |x: f32, z: f32, s: f32| {
        let at = camera.eye + Vec3::new(x, -1.7, z);
        Mat4::from_scale_rotation_translation(Vec3::splat(s), Quat::from_rotation_y(0.4), at)
    };
    let turned = FrameCamera {
        view: Mat4::from_rotation_y(0.5) * camera.view,
        ..camera
    };
    gpu_test(|gpu| {
        assert!(
            gpu.device()
                .features()
                .contains(wgpu::Features::MULTI_DRAW_INDIRECT_COUNT),
            "the test device packs culled casts (it draws counts written on the GPU)"
        );
        let listing = without_indirect_first_instance(gpu);
        let chunked = with_small_storage_bindings(gpu, true);
        let unpacked = with_small_storage_bindings(gpu, false);
        // The cached run's atlases, step by step: the uncached run must draw the same depth.
        let mut cached_atlases: Vec<Vec<f32>> = Vec::new();
        let mut last_uncached: Option<Vec<f32>> = None;
        for cache in [true, false] {
            // GPU culling (casts packed), every caster drawn into every region, the CPU's
            // lists, and GPU culling in chunks of a few regions, packed and not.
            let mut sessions = [
                Session::new(gpu, shadow_config(true, cache), &lights),
                Session::new(gpu, shadow_config(false, cache), &lights),
                Session::new(&listing, shadow_config(true, cache), &lights),
                Session::new(&chunked, shadow_config(true, cache), &lights),
                Session::new(&unpacked, shadow_config(true, cache), &lights),
            ];
            let mut handles = [(); 5].map(|()| Vec::new());
            // 1: a static tower added; 2: a dome added, marked dynamic and moved; 3: the dome
            // moved (the regions it leaves are composed again); 4: the tower removed (the
            // regions it leaves are drawn again); 5: the camera turned (every cascade moves);
            // 6: back; 7: nothing (the same work as 6); 8: the dome moved again, over static
            // depth drawn while it was there.
            for step in 0..9 {
                let view = if step == 5 { &turned } else { &camera };
                for (s, handles) in sessions.iter_mut().zip(&mut handles) {
                    let r = &mut s.renderer;
                    match step {
                        1 => handles.push(r.add_instance(tower, ahead(8.0, -4.0, 1.5)).unwrap()),
                        2 => {
                            let h = r.add_instance(dome, ahead(6.0, 3.0, 2.0)).unwrap();
                            r.set_instance_dynamic(h, true).unwrap();
                            r.set_instance_transform(h, ahead(9.0, 2.0, 2.0)).unwrap();
                            handles.push(h);
                        }
                        3 => r
                            .set_instance_transform(handles[1], ahead(4.0, 6.0, 2.5))
                            .unwrap(),
                        4 => r.remove_instance(handles[0]).unwrap(),
                        8 => r
                            .set_instance_transform(handles[1], ahead(7.0, -1.0, 2.0))
                            .unwrap(),
                        _ => {}
                    }
                }
                let frames: Vec<(ShadowReport, Vec<f32>)> =
                    sessions.iter_mut().map(|s| s.frame(view)).collect();
                let [
                    (culled, atlas),
                    (unculled, every),
                    (listed, cpu),
                    (_, chunks),
                    (_, plain),
                ] = &frames[..]
                else {
                    unreachable!()
                };
                assert_eq!(work(culled), work(listed), "step {step}");
                assert_eq!(work(culled), work(unculled), "step {step}");
                let others = [
                    ("every caster", every),
                    ("the CPU's lists", cpu),
                    ("culling in chunks", chunks),
                    ("culling in chunks, unpacked", plain),
                ];
                for (name, other) in others {
                    let wrong = differing(atlas, other);
                    assert_eq!(
                        wrong, 0,
                        "cache {cache}, step {step}: {wrong} texels differ from {name}"
                    );
                }
                if cache {
                    cached_atlases.push(atlas.clone());
                } else {
                    // Only the frame's regions: texels outside them are unused, and an
                    // uncached frame clears the whole atlas where a cached one keeps them.
                    let wrong = differing_in_regions(atlas, &cached_atlases[step], culled);
                    assert_eq!(
                        wrong, 0,
                        "step {step}: {wrong} texels differ from the cached frame"
                    );
                    // Every edit shows in the atlas, so a cache that misses one fails above.
                    let changed = last_uncached
                        .as_ref()
                        .map_or(0, |last| differing(atlas, last));
                    if [1, 3, 4, 8].contains(&step) {
                        assert!(
                            changed > 100,
                            "step {step}: the edit changes {changed} texels"
                        );
                    }
                    last_uncached = Some(atlas.clone());
                }
                eprintln!(
                    "cache {cache}, step {step}: {} regions redrawn, {} copied; casts: GPU \
                     (a frame late) {}, every caster (a frame late) {}, CPU {}",
                    culled.cache.redrawn,
                    culled.cache.copied,
                    culled.cache.draws,
                    unculled.cache.draws,
                    listed.cache.draws
                );
                // Uncached, steps 6 and 7 draw the same work: the GPU's count of step 6
                // arrives by step 7 and equals the CPU's list; culling leaves most casts out.
                if !cache && step == 7 {
                    assert_eq!(culled.cache.draws, listed.cache.draws);
                    assert!(
                        culled.cache.draws * 4 < unculled.cache.draws,
                        "culling leaves most casts out"
                    );
                }
            }
            let atlas_texels = frames_nonzero(&mut sessions[0], &camera);
            assert!(
                atlas_texels > 10_000,
                "the atlas holds depth ({atlas_texels} texels)"
            );
        }
    });
}

/// The same adapter with storage bindings of at most 128 KiB: the shadow culling's arguments
/// for the city's casters then fit five regions at a time, so a frame culls and draws in
/// chunks; without `packing` (`MULTI_DRAW_INDIRECT_COUNT`), every slot is drawn, with no
/// instance where culled.
fn with_small_storage_bindings(gpu: &GpuContext, packing: bool) -> GpuContext {
    let (features, limits) =
        renderer::gpu::requirements::for_adapter(gpu.adapter()).expect("requirements");
    let limits = wgpu::Limits {
        max_storage_buffer_binding_size: 128 << 10,
        ..limits
    };
    let (device, queue) =
        pollster::block_on(gpu.adapter().request_device(&wgpu::DeviceDescriptor {
            label: Some("device with small storage bindings"),
            required_features: if packing {
                features
            } else {
                features - wgpu::Features::MULTI_DRAW_INDIRECT_COUNT
            },
            required_limits: limits,
            ..Default::default()
        }))
        .expect("a device with small storage bindings");
    GpuContext::from_parts(gpu.instance().clone(), gpu.adapter().clone(), device, queue)
        .expect("the device has the renderer's limits")
}

/// Texels of the atlas with depth written, after one more frame.
fn frames_nonzero(s: &mut Session, camera: &FrameCamera) -> usize {
    let (_, atlas) = s.frame(camera);
    atlas.iter().filter(|&&d| d > 0.0).count()
}

/// The report's region work: redrawn, copied, untouched.
fn work(r: &ShadowReport) -> (u32, u32, u32) {
    (r.cache.redrawn, r.cache.copied, r.cache.untouched)
}
