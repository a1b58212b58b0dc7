//! The shadow atlas on the GPU (lavapipe, 320×240, atlas 2048, MSAA 1 unless stated), on the
//! floor + box + pillar scene of `tests::shadow_scene`:
//!
//! - **Against an independent CPU ray cast**, for the spot, point and directional light alone
//!   (no ambient), two rules:
//!   - *coarse*: per floor pixel, visibility = luminance with the shadow / luminance without
//!     it (linear after decoding sRGB; the image is tonemapped, which keeps 0 at 0 and lit at
//!     lit). A pixel disagrees when the ray cast says lit and visibility < ½, or unlit and
//!     visibility > ½. Left out: pixels within [`BAND`] (3) pixels of a reference shadow edge
//!     and pixels the light hardly reaches unshadowed (below 8/255). Zero disagreements, and at
//!     least 300 lit and 300 shadowed pixels compared.
//!   - *band* ([`tests::shadow_bounds`]): the partial shadow is confined to a band predicted
//!     from geometry, [`shadow_bounds::band_texels`] (2.9 to 4.4) texels of the shadow view
//!     around the ray-cast edge; outside it every lit floor pixel equals its unshadowed value and every
//!     shadowed one is black, within [`shadow_bounds::TOLERANCE`] (1/255). Acne (partly
//!     shadowed texels on lit floor) and peter-panning (light between a caster's base and its
//!     shadow, or an edge moved more than the band) fail it, however faint; the shadowed pixels
//!     near a caster's base (the contact line) are checked like any other.
//! - **Cube seams**: a point light whose face edges and corners cross the floor inside the
//!   box's and the pillar's shadows; zero leaks within [`SEAM`] of a face edge.
//! - **Caching**: an unchanged frame does no shadow work and is byte-identical; a moving
//!   dynamic caster recomposes exactly the regions it reaches (checked with a clip-space test of
//!   its own) and the frame is byte-identical to an uncached renderer's; uncached, every frame
//!   redraws every region.
//! - **Culled paths equal naive-prez with shadows** (tiled, 2.5D, clustered at MSAA 1 and 4):
//!   largest channel difference 0.
//! - **A full atlas** degrades and evicts lights, and the frame still renders.
//!
//! Set `SHADOW_GPU_DUMP` to a directory to get the frames and an overlay of the comparison
//! (compared pixels green lit / blue shadowed, disagreements red) as PNGs there.

use glam::{Mat4, Vec3};
use renderer::GpuContext;
use renderer::demo::procedural_lights;
use renderer::frame::create_target;
use renderer::frame::{FrameCamera, RenderPath, Renderer, RendererConfig};
use renderer::passes::shadow::ShadowPass;
use renderer::scene::{Aabb, SceneLight};
use renderer::shadow::ShadowReport;
use renderer::shadow::cache::RegionWork;
use tests::frames::{largest_difference, render_frame_from, render_one_frame};
use tests::gpu::gpu_test;
use tests::shadow_bounds::{self, Tight};
use tests::shadow_scene::{self, Comparison};

const W: u32 = 320;
const H: u32 = 240;
/// Pixels within this distance of a reference shadow edge are not compared.
const BAND: u32 = 3;

fn config(path: RenderPath) -> RendererConfig {
    let mut c = RendererConfig {
        width: W,
        height: H,
        msaa: 1,
        path,
        ambient: renderer::frame::Ambient::OFF,
        ..Default::default()
    };
    c.shadows.atlas_size = 2048;
    c
}

fn camera() -> FrameCamera {
    shadow_scene::camera(W as f32 / H as f32)
}

/// Writes `rgba` to `$SHADOW_GPU_DUMP/name.png` when that variable is set (for looking at a
/// failure).
fn dump(name: &str, rgba: &[u8]) {
    if let Some(dir) = std::env::var_os("SHADOW_GPU_DUMP") {
        let path = std::path::Path::new(&dir).join(format!("{name}.png"));
        image::save_buffer(&path, rgba, W, H, image::ColorType::Rgba8).expect("png");
    }
}

/// `shadowed` with compared pixels tinted (green lit, blue shadowed) and disagreements red.
fn overlay(c: &Comparison, shadowed: &[u8]) -> Vec<u8> {
    let mut out = shadowed.to_vec();
    for p in &c.checked {
        let i = ((p.y * W + p.x) * 4) as usize;
        let colour = match (p.disagrees(), p.reference_lit) {
            (true, _) => [255, 0, 0],
            (false, true) => [out[i] / 2, 160, out[i + 2] / 2],
            (false, false) => [0, 0, 160],
        };
        out[i..i + 3].copy_from_slice(&colour);
    }
    out
}

/// Renders `light` alone with and without its shadow and compares with the ray cast: the
/// coarse comparison and the band rule ([`shadow_bounds::check_band`]).
fn compare(gpu: &GpuContext, name: &str, light: SceneLight) -> (Comparison, Tight) {
    let scene = shadow_scene::scene();
    let c = config(RenderPath::NaivePrez);
    let camera = camera();
    let mut renderer = Renderer::new(gpu, c).expect("renderer");
    renderer.prepare_scene(&scene).expect("the scene fits");
    renderer.set_lights(&[light]).expect("lights fit");
    let shadowed = render_one_frame(gpu, &mut renderer, &camera);
    let regions = shadow_bounds::regions_of(&renderer);
    let report = shadowed.report.shadows.clone().expect("shadow report");
    assert_eq!(
        (report.requested, report.shadowed),
        (1, 1),
        "{name}: {report:?}"
    );
    // The same light without its shadow, on the same renderer.
    renderer
        .set_lights(&[SceneLight {
            casts_shadow: false,
            ..light
        }])
        .expect("lights fit");
    let unshadowed = render_one_frame(gpu, &mut renderer, &camera);
    let report_off = unshadowed.report.shadows.clone().expect("shadow report");
    assert_eq!(
        report_off.shadowed, 0,
        "{name}: the reference has no shadow"
    );
    let cmp = shadow_scene::compare_with_ray_cast(
        &camera,
        &light,
        &shadowed.rgba,
        &unshadowed.rgba,
        (W, H),
        BAND,
    );
    dump(&format!("{name}_shadowed"), &shadowed.rgba);
    dump(&format!("{name}_unshadowed"), &unshadowed.rgba);
    dump(&format!("{name}_overlay"), &overlay(&cmp, &shadowed.rgba));
    eprintln!(
        "{name}: {} lit and {} shadowed pixels compared, {} in the {BAND}-pixel edge band, {} \
         too dark, {} disagree; resolution {:?}",
        cmp.lit(),
        cmp.shadowed(),
        cmp.in_band,
        cmp.dark,
        cmp.disagreements().len(),
        report.resolution_histogram,
    );
    let tight = shadow_bounds::check_band(
        &camera,
        &light,
        &regions,
        &shadowed.rgba,
        &unshadowed.rgba,
        (W, H),
    );
    eprintln!(
        "{name}: band rule: {} lit and {} shadowed pixels checked ({} within {} of a contact \
         line), {} in the band, {} wrong; partial shadows reach {:.2} texels, {:.2} texels from \
         their band",
        tight.lit,
        tight.shadowed,
        tight.contact,
        shadow_bounds::CONTACT,
        tight.in_band,
        tight.wrong.len(),
        tight.widest_partial,
        tight.closest_to_band
    );
    (cmp, tight)
}

#[test]
fn shadows_match_a_cpu_ray_cast_for_each_light() {
    gpu_test(|gpu| {
        let names = ["spot", "point", "directional"];
        // Every light is compared before any assertion, so a failure prints all three.
        let results: Vec<(&str, SceneLight, Comparison, Tight)> = names
            .iter()
            .zip(shadow_scene::lights())
            .map(|(name, light)| {
                let (cmp, tight) = compare(gpu, name, light);
                (*name, light, cmp, tight)
            })
            .collect();
        for (name, light, cmp, tight) in &results {
            shadow_scene::assert_agrees(name, light, cmp);
            // Each light's shadows start at a visible contact line (measured: 38 to 101 pixels).
            shadow_bounds::assert_band(name, tight, 20);
        }
    });
}

/// Directions within this relative closeness of a cube face edge
/// ([`shadow_scene::cube_edge_closeness`]) count as seam pixels: about 4 texels of a 256-texel
/// face.
const SEAM: f32 = 0.03;
/// Directions with all three magnitudes within this relative closeness count as near a cube
/// corner ([`shadow_scene::near_cube_corner`]).
const CORNER: f32 = 0.08;

#[test]
fn cube_seams_do_not_leak() {
    gpu_test(|gpu| {
        let light = shadow_scene::seam_light();
        let (cmp, tight) = compare(gpu, "seam", light);
        // The seam light's shadows start at no visible contact line.
        shadow_bounds::assert_band("seam", &tight, 0);
        let seam: Vec<_> = cmp
            .checked
            .iter()
            .filter(|c| shadow_scene::cube_edge_closeness(c.p - light.position) < SEAM)
            .collect();
        // Near the corner of three faces, in the box's shadow.
        let corner = cmp
            .checked
            .iter()
            .filter(|c| !c.reference_lit)
            .filter(|c| shadow_scene::near_cube_corner(c.p - light.position, CORNER))
            .count();
        let seam_lit = seam.iter().filter(|c| c.reference_lit).count();
        let leaks: Vec<String> = seam
            .iter()
            .filter(|c| c.leaks())
            .map(|c| format!("({}, {}) at {:.3}", c.x, c.y, c.p))
            .collect();
        eprintln!(
            "seam: {} pixels within {SEAM} of a face edge ({seam_lit} lit, {} shadowed, {corner} \
             shadowed within {CORNER} of a corner), {} leak",
            seam.len(),
            seam.len() - seam_lit,
            leaks.len()
        );
        assert!(
            leaks.is_empty(),
            "{} seam pixels leak light (reference unlit, visibility > 0.5):\n{}",
            leaks.len(),
            leaks.join("\n")
        );
        assert!(
            seam_lit > 100 && seam.len() - seam_lit > 100 && corner > 10,
            "too few seam pixels compared"
        );
        shadow_scene::assert_agrees("seam", &light, &cmp);
    });
}

/// A renderer kept across frames, with its target.
struct Session {
    renderer: Renderer,
    target: wgpu::Texture,
    gpu: GpuContext,
}

impl Session {
    fn new(gpu: &GpuContext, config: RendererConfig, lights: &[SceneLight]) -> Self {
        let mut renderer = Renderer::new(gpu, config).expect("renderer");
        renderer
            .prepare_scene(&shadow_scene::scene())
            .expect("the scene fits the device");
        renderer.set_lights(lights).expect("lights fit");
        Self {
            target: create_target(gpu.device(), &config),
            renderer,
            gpu: gpu.clone(),
        }
    }

    /// Renders a frame; its pixels and shadow report.
    fn frame(&mut self) -> (Vec<u8>, ShadowReport) {
        let report = self
            .renderer
            .render(&camera(), &self.target)
            .expect("frame");
        self.renderer.finish();
        let rgba = renderer::readback::read_texture_rgba8(
            self.gpu.device(),
            self.gpu.queue(),
            &self.target,
        )
        .expect("readback");
        (rgba, report.shadows.expect("shadow report"))
    }

    /// The regions of the last frame: the view of each and whether it was recomposed.
    fn regions(&self) -> Vec<(Mat4, &RegionWork)> {
        let pass = self.renderer.pass::<ShadowPass>().expect("shadow pass");
        pass.plan()
            .regions
            .iter()
            .map(|r| (r.region.view.clip_from_world, &r.work))
            .collect()
    }
}

/// Regions of a frame, from its resolution histogram.
fn regions(report: &ShadowReport) -> u32 {
    report.resolution_histogram.iter().map(|(_, n)| n).sum()
}

/// The scene's three lights, with cascades small enough that all three fit a 2048 atlas.
fn cache_config(cache: bool) -> RendererConfig {
    let mut c = config(RenderPath::NaivePrez);
    c.shadows.cache = cache;
    c.shadows.cascade_resolution = 512;
    c
}

#[test]
fn an_unchanged_frame_does_no_shadow_work() {
    gpu_test(|gpu| {
        let mut s = Session::new(gpu, cache_config(true), &shadow_scene::lights());
        let (first, r1) = s.frame();
        let (second, r2) = s.frame();
        eprintln!(
            "frame 1: {:?}, {:?}\nframe 2: {:?}",
            r1.resolution_histogram, r1.cache, r2.cache
        );
        assert_eq!((r1.requested, r1.shadowed), (3, 3), "{r1:?}");
        let total = regions(&r1);
        assert_eq!(total, 1 + 6 + 4);
        assert_eq!(r1.cache.redrawn, total);
        let c = r2.cache;
        assert_eq!((c.draws, c.redrawn, c.copied), (0, 0, 0), "{r2:?}");
        assert_eq!(c.untouched, total);
        assert!(first == second, "the second frame's image differs");
    });
}

#[test]
fn a_moving_dynamic_caster_recomposes_only_the_regions_it_reaches() {
    let lights = shadow_scene::lights();
    let box_at = shadow_scene::occluders()[0];
    let shift = Vec3::new(0.25, 0.0, -0.15);
    let moved = |m: Mat4| Mat4::from_translation(shift) * m;
    let moved_box = Aabb {
        min: box_at.min + shift,
        max: box_at.max + shift,
    };
    gpu_test(|gpu| {
        let mut s = Session::new(gpu, cache_config(true), &lights);
        let (_, r1) = s.frame();
        let total = regions(&r1);
        let the_box = s.renderer.scene_instance(1).expect("instance 1");
        s.renderer
            .set_instance_dynamic(the_box, true)
            .expect("instance");
        let (_, r2) = s.frame();
        let box_from = s.renderer.instances()[1].world_from_mesh;
        s.renderer
            .set_instance_transform(the_box, moved(box_from))
            .expect("instance");
        let (cached, r3) = s.frame();
        eprintln!(
            "static: {:?}\ndynamic: {:?}\nmoved: {:?}",
            r1.cache, r2.cache, r3.cache
        );
        // Marking the box dynamic takes it out of the static depth of every region it reaches.
        assert!(r2.cache.redrawn > 0 && r2.cache.redrawn < total, "{r2:?}");
        let c = r3.cache;
        assert_eq!(c.redrawn, 0, "no static caster moved: {r3:?}");
        assert!(c.copied > 0 && c.copied < total, "{r3:?}");
        assert_eq!(c.copied + c.untouched, total);
        // Exactly the regions whose view the box reaches, before or after the move, are
        // recomposed (box_in_view is the clip-space plane test, done independently).
        for (i, (clip, work)) in s.regions().into_iter().enumerate() {
            let reached = shadow_scene::box_in_view(clip, &box_at)
                || shadow_scene::box_in_view(clip, &moved_box);
            let copied = matches!(work, RegionWork::Compose { .. });
            assert_eq!(copied, reached, "region {i}: {work:?}");
        }

        let mut fresh = Session::new(gpu, cache_config(false), &lights);
        let the_box = fresh.renderer.scene_instance(1).expect("instance 1");
        fresh
            .renderer
            .set_instance_dynamic(the_box, true)
            .expect("instance");
        fresh
            .renderer
            .set_instance_transform(the_box, moved(box_from))
            .expect("instance");
        let (uncached, r) = fresh.frame();
        assert_eq!(r.resolution_histogram, r3.resolution_histogram);
        let worst = largest_difference(&cached, &uncached);
        let differing = cached
            .chunks(4)
            .zip(uncached.chunks(4))
            .filter(|(a, b)| a != b)
            .count();
        eprintln!("cached vs uncached: {differing} pixels differ, at most {worst}/255");
        dump("moved_cached", &cached);
        dump("moved_uncached", &uncached);
        assert_eq!(worst, 0, "{differing} pixels differ, by up to {worst}/255");
    });
}

#[test]
fn uncached_frames_redraw_every_region() {
    gpu_test(|gpu| {
        let mut s = Session::new(gpu, cache_config(false), &shadow_scene::lights());
        let mut first = None;
        for frame in 0..3 {
            let (rgba, r) = s.frame();
            assert!(
                *first.get_or_insert_with(|| rgba.clone()) == rgba,
                "frame {frame} differs from the first"
            );
            let total = regions(&r);
            assert_eq!(total, 11);
            let c = r.cache;
            assert_eq!(
                (c.redrawn, c.copied, c.untouched),
                (total, 0, 0),
                "frame {frame}: {r:?}"
            );
            // Casters are culled and counted on the GPU; the count arrives a frame later.
            assert!(frame == 0 || c.draws > 0, "frame {frame}: {c:?}");
        }
    });
}

#[test]
fn culled_paths_equal_naive_with_shadows() {
    let scene = shadow_scene::scene();
    let mut lights = shadow_scene::lights().to_vec();
    lights.extend(
        procedural_lights(scene.bounds, 4, 5, 2.0, 5.0)
            .into_iter()
            .map(|l| SceneLight {
                casts_shadow: true,
                ..l
            }),
    );
    gpu_test(|gpu| {
        for msaa in [1, 4] {
            let frame = |path| {
                let c = RendererConfig {
                    msaa,
                    path,
                    ..cache_config(true)
                };
                let f = render_frame_from(gpu, &scene, c, &lights, &camera());
                let dropped = f.culling.map_or(0, |c| c.dropped);
                assert_eq!(dropped, 0, "{path:?} dropped lights");
                let r = f.report.shadows.expect("shadow report");
                assert_eq!((r.requested, r.shadowed), (7, 7), "{path:?}: {r:?}");
                f.rgba
            };
            let naive = frame(RenderPath::NaivePrez);
            dump(&format!("paths_msaa{msaa}"), &naive);
            for path in [
                RenderPath::Tiled,
                RenderPath::Depth25,
                RenderPath::Clustered,
            ] {
                let culled = frame(path);
                let worst = largest_difference(&naive, &culled);
                eprintln!(
                    "MSAA {msaa}, {}: at most {worst}/255 from naive-prez",
                    path.name()
                );
                assert_eq!(worst, 0, "{path:?} at MSAA {msaa}: differs from naive-prez");
            }
        }
    });
}

#[test]
fn a_full_atlas_degrades_and_evicts_but_renders() {
    let scene = shadow_scene::scene();
    let lights: Vec<SceneLight> = procedural_lights(scene.bounds, 12, 9, 3.0, 6.0)
        .into_iter()
        .map(|l| SceneLight {
            casts_shadow: true,
            ..l
        })
        .collect();
    let mut c = config(RenderPath::Clustered);
    c.shadows.atlas_size = 256;
    c.shadows.max_resolution = 256;
    c.shadows.cascade_resolution = 64;
    gpu_test(|gpu| {
        let f = render_frame_from(gpu, &scene, c, &lights, &camera());
        let r = f.report.shadows.expect("shadow report");
        eprintln!(
            "full atlas: {} requested, {} shadowed, degraded {:?}, evicted {:?}, regions {:?}",
            r.requested, r.shadowed, r.degraded, r.evicted, r.resolution_histogram
        );
        assert!(r.requested > 2, "{r:?}");
        assert!(!r.evicted.is_empty() || !r.degraded.is_empty(), "{r:?}");
        for &(light, asked, granted) in &r.degraded {
            assert!(granted < asked, "light {light}: {asked} → {granted}");
            assert!(
                !r.evicted.contains(&light),
                "light {light} degraded and evicted"
            );
        }
        assert_eq!(r.shadowed as usize + r.evicted.len(), r.requested as usize);
        assert_eq!(regions(&r), 6 * r.shadowed);
        let texels: u32 = r.resolution_histogram.iter().map(|(s, n)| s * s * n).sum();
        assert!(texels <= 256 * 256, "{r:?}");
        assert!(f.rgba.chunks(4).any(|p| p[0] > 8 || p[1] > 8 || p[2] > 8));
    });
}
