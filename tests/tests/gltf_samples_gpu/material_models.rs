//! Khronos's material-input models, checked where their READMEs say what must show, and against
//! the same model with the rule baked in on the CPU (transforms applied to the vertex UVs, the
//! second UV set copied into the first), which draws without the GPU path under test.
//! `MATERIAL_INPUTS_DUMP=<dir>` writes the frames as PNGs.

use renderer::frame::framing_camera;
use renderer::frame::{FrameCamera, RenderPath, RendererConfig};
use renderer::scene::{Scene, TextureRef, UvTransform};
use tests::frames::{largest_difference, render_frame_from};
use tests::gpu::gpu_test;

use super::quads::head_on_light;
use super::sample;

const W: u32 = 320;
const H: u32 = 240;

fn config(path: RenderPath) -> RendererConfig {
    RendererConfig {
        width: W,
        height: H,
        msaa: 1,
        path,
        ..Default::default()
    }
}

fn camera(scene: &Scene) -> FrameCamera {
    framing_camera(scene.bounds, W as f32 / H as f32)
}

/// Renders `scene` lit head-on on `path`, dumping it as `name` when asked.
fn render(gpu: &renderer::GpuContext, scene: &Scene, path: RenderPath, name: &str) -> Vec<u8> {
    let frame = render_frame_from(gpu, scene, config(path), &[head_on_light()], &camera(scene));
    if let Some(dir) = std::env::var_os("MATERIAL_INPUTS_DUMP") {
        let file = std::path::Path::new(&dir).join(format!("{name}_{}.png", path.name()));
        image::save_buffer(file, &frame.rgba, W, H, image::ColorType::Rgba8).expect("png");
    }
    frame.rgba
}

fn rgb(rgba: &[u8], x: u32, y: u32) -> [i32; 3] {
    let i = ((y * W + x) * 4) as usize;
    [rgba[i], rgba[i + 1], rgba[i + 2]].map(i32::from)
}

/// Pixels of the window `(x0, y0)..(x1, y1)` (exclusive) whose colour passes `pick`.
fn count(rgba: &[u8], (x0, y0, x1, y1): (u32, u32, u32, u32), pick: fn([i32; 3]) -> bool) -> usize {
    (y0..y1)
        .flat_map(|y| (x0..x1).map(move |x| (x, y)))
        .filter(|&(x, y)| pick(rgb(rgba, x, y)))
        .count()
}

/// Every texture reference of `scene`'s materials, mutably.
fn texture_refs(scene: &mut Scene) -> impl Iterator<Item = &mut TextureRef> {
    scene.materials.iter_mut().flat_map(|m| {
        [
            &mut m.base_color_texture,
            &mut m.normal_texture,
            &mut m.metallic_roughness_texture,
            &mut m.occlusion_texture,
            &mut m.emissive_texture,
        ]
        .into_iter()
        .flatten()
    })
}

/// TextureTransformTest: the top row's quads show their colour (green "U", blue "V", cyan
/// "UV"; yellow where the offset is ignored), and every quad draws as the same model with each
/// base colour transform applied to the vertex UVs on the CPU.
#[test]
fn texture_transform_test() {
    gpu_test(|gpu| {
        let scene = sample("TextureTransformTest/TextureTransformTest.gltf");
        let mut baked = scene.clone();
        let Scene {
            meshes, materials, ..
        } = &mut baked;
        for p in meshes.iter_mut().flat_map(|m| &mut m.primitives) {
            let t = p
                .material
                .and_then(|m| materials[m].base_color_texture.as_mut())
                .expect("every quad is textured");
            assert_eq!(t.tex_coord, 0);
            let m = t.transform.matrix();
            for uv in &mut p.uvs {
                *uv = m.transform_point2(*uv);
            }
        }
        for t in texture_refs(&mut baked) {
            t.transform = UvTransform::IDENTITY;
        }
        for path in [RenderPath::NaivePrez, RenderPath::Deferred] {
            let frame = render(gpu, &scene, path, "texture_transform");
            // Top row: (x, y) of the U, V and UV quads' lower-right, clear of the tick.
            let tops = [((70, 100), 1), ((140, 100), 2), ((210, 100), 1)];
            for ((x, y), channel) in tops {
                let c = rgb(&frame, x, y);
                assert!(
                    c[channel] > 60 && c[0] < 30,
                    "{}: ({x}, {y}) is {c:?}, not the quad's own colour (yellow: offset ignored)",
                    path.name()
                );
            }
            let reference = render(gpu, &baked, path, "texture_transform_baked");
            let d = largest_difference(&frame, &reference);
            assert!(
                d <= 24,
                "{}: differs from the CPU-baked transforms by {d}",
                path.name()
            );
        }
    });
}

/// VertexColorTest: in the "Test" row the vertex colours zero the other channels, so no cyan,
/// magenta or yellow X shows in the red, green and blue checks' cells.
#[test]
fn vertex_color_test() {
    gpu_test(|gpu| {
        let scene = sample("VertexColorTest/VertexColorTest.glb");
        for path in [RenderPath::Naive, RenderPath::Tbdr] {
            let frame = render(gpu, &scene, path, "vertex_color");
            // (window, its colour's channel) of the Test row's red, green and blue cells.
            let cells = [
                ((92, 72, 130, 108), 0),
                ((140, 72, 178, 108), 1),
                ((192, 72, 230, 108), 2),
            ];
            for (window, channel) in cells {
                let mut wrong = 0;
                let mut right = 0;
                for y in window.1..window.3 {
                    for x in window.0..window.2 {
                        let c = rgb(&frame, x, y);
                        let others = (0..3)
                            .filter(|&k| k != channel)
                            .map(|k| c[k])
                            .max()
                            .unwrap_or(0);
                        wrong += usize::from(others > 60);
                        right += usize::from(c[channel] > 100 && others < 40);
                    }
                }
                assert!(
                    wrong == 0 && right > 40,
                    "{}: channel {channel} cell {window:?}: {wrong} pixels of an X, {right} of the check",
                    path.name()
                );
            }
        }
    });
}

/// TextureSettingsTest: the "Test" column shows green checks and bars only: no red X (a wrap
/// mode or the double-sided flag ignored shows red there).
#[test]
fn texture_settings_test() {
    gpu_test(|gpu| {
        let scene = sample("TextureSettingsTest/TextureSettingsTest.glb");
        for path in [RenderPath::Naive, RenderPath::Clustered] {
            let frame = render(gpu, &scene, path, "texture_settings");
            let column = (155, 55, 182, 190);
            let red = count(&frame, column, |c| c[0] > c[1] + 40 && c[0] > 80);
            let green = count(&frame, column, |c| c[1] > c[0] + 40 && c[1] > 80);
            assert!(
                red == 0 && green > 300,
                "{}: {red} red, {green} green pixels",
                path.name()
            );
        }
    });
}

/// MultiUVTest: the emissive texture reads `TEXCOORD_1`. Drawn emissive-only (no base colour
/// texture), the model equals the same with `TEXCOORD_1` copied into `TEXCOORD_0` and the
/// emissive reading set 0, and differs from the emissive reading `TEXCOORD_0`'s own data.
#[test]
fn multi_uv_test() {
    gpu_test(|gpu| {
        let mut scene = sample("MultiUVTest/MultiUVTest.glb");
        for m in &mut scene.materials {
            m.base_color_texture = None;
            m.base_color = glam::Vec4::new(0.0, 0.0, 0.0, 1.0);
            assert_eq!(m.emissive_texture.map(|t| t.tex_coord), Some(1));
        }
        let mut copied = scene.clone();
        for p in copied.meshes.iter_mut().flat_map(|m| &mut m.primitives) {
            assert!(!p.uvs1.is_empty(), "the model has TEXCOORD_1");
            p.uvs = std::mem::take(&mut p.uvs1);
        }
        let mut first_set = scene.clone();
        for t in texture_refs(&mut copied).chain(texture_refs(&mut first_set)) {
            t.tex_coord = 0;
        }
        let path = RenderPath::Tiled;
        let frame = render(gpu, &scene, path, "multi_uv");
        let d = largest_difference(&frame, &render(gpu, &copied, path, "multi_uv_copied"));
        assert!(
            d <= 2,
            "TEXCOORD_1 differs from its copy in TEXCOORD_0 by {d}"
        );
        let d = largest_difference(&frame, &render(gpu, &first_set, path, "multi_uv_set0"));
        assert!(
            d > 60,
            "the emissive reads the same through TEXCOORD_0 (difference {d})"
        );
    });
}
