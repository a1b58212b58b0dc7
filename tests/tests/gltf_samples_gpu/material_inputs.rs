//! Material inputs on the GPU, on scenes built in code where each quad shows one rule as a
//! colour: `COLOR_0` multiplies the base colour (and its alpha masks), each texture reads its
//! own UV set through its own `KHR_texture_transform` and sampler (wrap modes), magnification
//! follows the sampler's filter (nearest: hard texel edges; linear: a ramp), the mip chain is
//! sampled only where the sampler has a mipmap filter, and alpha-masked casters cut out in the
//! shadow atlas. Every quad reads green (or masks) only when its rule is honoured and red (or
//! shows) when it is not; each is checked on every render path.

use glam::{Vec2, Vec3, Vec4};
use renderer::frame::{FrameCamera, RenderPath};
use renderer::scene::procedural::SceneBuilder;
use renderer::scene::{
    Aabb, AlphaMode, Filter, Image, Material, Scene, TextureRef, TextureSampler, UvTransform, Wrap,
};
use tests::frames::render_frame_from;
use tests::gpu::gpu_test;

use super::quads::{H, Quad, W, add_quad, config, head_on_light, pixel, rgb};

fn nearest(wrap: Wrap) -> TextureSampler {
    TextureSampler {
        wrap_u: wrap,
        wrap_v: wrap,
        mag_filter: Filter::Nearest,
        min_filter: Filter::Nearest,
        mipmap_filter: None,
    }
}

/// A texture reference reading `TEXCOORD_1` through `transform` with `wrap`, nearest filters.
fn second_set(image: usize, wrap: Wrap, transform: UvTransform) -> TextureRef {
    TextureRef {
        tex_coord: 1,
        sampler: nearest(wrap),
        transform,
        ..TextureRef::new(image)
    }
}

/// What each quad of [`inputs_scene`] is, where its centre is, and what it must show.
struct Check {
    name: &'static str,
    center: Vec3,
    expect: Expect,
}

enum Expect {
    /// Green well above red and blue.
    Green,
    /// The sky: the quad is masked away.
    Sky,
    /// Uniform over the quad's inner part (a mip level averaging the checker): largest minus
    /// smallest luminance below 40.
    Uniform,
    /// Pure checker texels: the luminance spans more than 120.
    Aliased,
    /// A black and a white texel magnified across the quad, nearest: along its middle row no
    /// pixel lies between them (more than 30 from both).
    HardEdge,
    /// The same, linear: at least 3 pixels of that row lie between them (5 measured at 160×120;
    /// nearest leaves none).
    Ramp,
}

const RED_GREEN: [u8; 8] = [255, 0, 0, 255, 0, 255, 0, 255];
const BLACK_WHITE: [u8; 8] = [0, 0, 0, 255, 255, 255, 255, 255];

/// Quads at z = 0 before a camera at z = 5; see [`Check`]s for what each shows.
fn inputs_scene() -> (Scene, Vec<Check>) {
    let mut b = SceneBuilder::new();
    let red_green = b.image(Image {
        width: 2,
        height: 1,
        rgba8: RED_GREEN.to_vec(),
    });
    let black_white = b.image(Image {
        width: 2,
        height: 1,
        rgba8: BLACK_WHITE.to_vec(),
    });
    let checker = b.image(Image {
        width: 2,
        height: 2,
        rgba8: [[0, 0, 0, 255], [255; 4], [255; 4], [0, 0, 0, 255]].concat(),
    });
    let base = Material {
        base_color: Vec4::ONE,
        metallic: 0.0,
        roughness: 1.0,
        double_sided: true,
        ..Material::gltf_default()
    };
    let white = b.add_material(base.clone());
    let masked = b.add_material(Material {
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        ..base.clone()
    });
    let textured = |b: &mut SceneBuilder, t: TextureRef| {
        b.add_material(Material {
            base_color_texture: Some(t),
            ..base.clone()
        })
    };
    let offset = |x: f32| UvTransform {
        offset: Vec2::new(x, 0.0),
        ..UvTransform::IDENTITY
    };
    // Each reads red through TEXCOORD_0 (each quad's `uv0` below is red after the same
    // transform and wrap) or with its rule ignored.
    let repeat = textured(&mut b, second_set(red_green, Wrap::Repeat, offset(0.5)));
    let mirror = textured(
        &mut b,
        second_set(
            red_green,
            Wrap::MirroredRepeat,
            UvTransform {
                scale: Vec2::new(4.0, 1.0),
                ..UvTransform::IDENTITY
            },
        ),
    );
    let clamp = textured(
        &mut b,
        second_set(red_green, Wrap::ClampToEdge, offset(2.0)),
    );
    let rotate = textured(
        &mut b,
        second_set(
            red_green,
            Wrap::Repeat,
            UvTransform {
                rotation: std::f32::consts::FRAC_PI_2,
                ..UvTransform::IDENTITY
            },
        ),
    );
    // Emissive checkers on black: the mip chain where the sampler filters mips, level 0 only
    // where it has no mipmap filter.
    let emissive = |b: &mut SceneBuilder, mipmap_filter| {
        b.add_material(Material {
            base_color: Vec4::new(0.0, 0.0, 0.0, 1.0),
            emissive: Vec3::ONE,
            emissive_texture: Some(TextureRef {
                sampler: TextureSampler {
                    mipmap_filter,
                    ..nearest(Wrap::Repeat)
                },
                ..TextureRef::new(checker)
            }),
            ..base.clone()
        })
    };
    let mipmapped = emissive(&mut b, Some(Filter::Linear));
    let level0 = emissive(&mut b, None);
    // The black and white texels emitted and magnified, clamped so the quad's ends are flat.
    let magnified = |b: &mut SceneBuilder, filter| {
        b.add_material(Material {
            base_color: Vec4::new(0.0, 0.0, 0.0, 1.0),
            emissive: Vec3::ONE,
            emissive_texture: Some(TextureRef {
                sampler: TextureSampler {
                    mag_filter: filter,
                    ..nearest(Wrap::ClampToEdge)
                },
                ..TextureRef::new(black_white)
            }),
            ..base.clone()
        })
    };
    let mag_nearest = magnified(&mut b, Filter::Nearest);
    let mag_linear = magnified(&mut b, Filter::Linear);
    let mut scene = b.build();
    scene.bounds = Aabb::EMPTY;
    let at = |x: f32, y: f32| (Vec3::new(x, y, 0.0), Vec3::new(x + 1.0, y + 1.0, 0.0));
    let red_uv0: fn(Vec2) -> Vec2 = |_| Vec2::new(0.25, 0.5);
    let mut checks = Vec::new();
    let mut quad = |name, (min, max): (Vec3, Vec3), q: Quad, expect| {
        add_quad(&mut scene, &Quad { min, max, ..q });
        checks.push(Check {
            name,
            center: (min + max) * 0.5,
            expect,
        });
    };
    let plain = |material| Quad {
        min: Vec3::ZERO,
        max: Vec3::ZERO,
        uv0: red_uv0,
        uv1: None,
        color: None,
        material,
    };
    quad(
        "vertex colour × white base colour",
        at(-3.5, 0.5),
        Quad {
            color: Some(Vec4::new(0.0, 1.0, 0.0, 1.0)),
            ..plain(white)
        },
        Expect::Green,
    );
    quad(
        "masked material, vertex alpha 0",
        at(-3.5, -1.0),
        Quad {
            color: Some(Vec4::new(1.0, 1.0, 1.0, 0.0)),
            ..plain(masked)
        },
        Expect::Sky,
    );
    // TEXCOORD_1 u = −0.75, offset 0.5: −0.25, repeated 0.75 (mirrored or clamped: red).
    let repeat_uv1: fn(Vec2) -> Vec2 = |_| Vec2::new(-0.75, 0.5);
    quad(
        "repeat",
        at(-2.0, 0.5),
        Quad {
            // TEXCOORD_0: 0.75 + 0.5 repeated is 0.25, red.
            uv0: |_| Vec2::new(0.75, 0.5),
            uv1: Some(repeat_uv1),
            ..plain(repeat)
        },
        Expect::Green,
    );
    // u = 0.3 scaled by 4: 1.2, mirrored 0.8 (repeated 0.2: red; clamped: green, below).
    let mirror_uv1: fn(Vec2) -> Vec2 = |_| Vec2::new(0.3, 0.5);
    quad(
        "mirrored repeat",
        at(-0.5, 0.5),
        Quad {
            // TEXCOORD_0: 0.05 × 4 is 0.2, red.
            uv0: |_| Vec2::new(0.05, 0.5),
            uv1: Some(mirror_uv1),
            ..plain(mirror)
        },
        Expect::Green,
    );
    // u = 0.3 offset 2: 2.3, clamped 1 (repeated or mirrored 0.3: red).
    quad(
        "clamp to edge",
        at(1.0, 0.5),
        Quad {
            // TEXCOORD_0: −1.9 + 2 is 0.1, red.
            uv0: |_| Vec2::new(-1.9, 0.5),
            uv1: Some(mirror_uv1),
            ..plain(clamp)
        },
        Expect::Green,
    );
    // (0.3, 0.75) turned a quarter counter-clockwise: u' = v = 0.75 (unturned 0.3, turned the
    // other way −0.75 → 0.25: red).
    let rotate_uv1: fn(Vec2) -> Vec2 = |_| Vec2::new(0.3, 0.75);
    quad(
        "rotation",
        at(2.5, 0.5),
        Quad {
            // TEXCOORD_0 (0.75, 0.25) turned: u' = 0.25, red.
            uv0: |_| Vec2::new(0.75, 0.25),
            uv1: Some(rotate_uv1),
            ..plain(rotate)
        },
        Expect::Green,
    );
    // 64 checker repeats over about 20 pixels.
    let dense: fn(Vec2) -> Vec2 = |st| st * 64.0;
    quad(
        "mip chain",
        at(-2.0, -1.5),
        Quad {
            uv0: dense,
            ..plain(mipmapped)
        },
        Expect::Uniform,
    );
    quad(
        "no mipmap filter",
        at(-0.5, -1.5),
        Quad {
            uv0: dense,
            ..plain(level0)
        },
        Expect::Aliased,
    );
    // One black and one white texel across about 20 pixels: texel centres at u = 0.25, 0.75.
    let across: fn(Vec2) -> Vec2 = |st| Vec2::new(st.x, 0.5);
    quad(
        "nearest magnification",
        at(1.0, -1.5),
        Quad {
            uv0: across,
            ..plain(mag_nearest)
        },
        Expect::HardEdge,
    );
    quad(
        "linear magnification",
        at(2.5, -1.5),
        Quad {
            uv0: across,
            ..plain(mag_linear)
        },
        Expect::Ramp,
    );
    (scene, checks)
}

fn inputs_camera() -> FrameCamera {
    FrameCamera::look_at(
        Vec3::new(0.0, 0.0, 5.0),
        Vec3::ZERO,
        Vec3::Y,
        60f32.to_radians(),
        W as f32 / H as f32,
        (0.1, 20.0),
    )
}

fn luminance([r, g, b]: [i32; 3]) -> i32 {
    (r * 3 + g * 6 + b) / 10
}

/// What is wrong with `check` in `rgba`, if anything.
fn failure(rgba: &[u8], camera: &FrameCamera, check: &Check) -> Option<String> {
    let c = rgb(rgba, pixel(camera, check.center));
    let wrong = |what: &str| Some(format!("{}: {what}", check.name));
    match check.expect {
        Expect::Green => (c[1] < c[0] + 40 || c[1] < c[2] + 40)
            .then(|| wrong(&format!("{c:?} is not green")))
            .flatten(),
        Expect::Sky => (c != rgb(rgba, (0, 0)))
            .then(|| wrong(&format!("{c:?} is not the sky")))
            .flatten(),
        Expect::HardEdge | Expect::Ramp => {
            let (x0, _) = pixel(camera, check.center - Vec3::new(0.45, 0.0, 0.0));
            let (x1, y) = pixel(camera, check.center + Vec3::new(0.45, 0.0, 0.0));
            let row: Vec<i32> = (x0..=x1).map(|x| luminance(rgb(rgba, (x, y)))).collect();
            let (lo, hi) = (
                *row.iter().min().unwrap_or(&0),
                *row.iter().max().unwrap_or(&0),
            );
            let between = row.iter().filter(|&&l| l > lo + 30 && l < hi - 30).count();
            if hi - lo < 120 {
                wrong(&format!(
                    "the texels are not both there: luminance {lo}..{hi}"
                ))
            } else if matches!(check.expect, Expect::HardEdge) && between > 0 {
                wrong(&format!(
                    "{between} pixels between the texels: filtered, not nearest"
                ))
            } else if matches!(check.expect, Expect::Ramp) && between < 3 {
                wrong(&format!(
                    "{between} pixels between the texels: not a linear ramp"
                ))
            } else {
                None
            }
        }
        Expect::Uniform | Expect::Aliased => {
            let lum: Vec<i32> = (-6..=6)
                .flat_map(|dy| (-6..=6).map(move |dx| (dx, dy)))
                .map(|(dx, dy)| {
                    let (x, y) = pixel(camera, check.center);
                    luminance(rgb(rgba, ((x as i32 + dx) as u32, (y as i32 + dy) as u32)))
                })
                .collect();
            let spread = lum.iter().max().unwrap_or(&0) - lum.iter().min().unwrap_or(&0);
            let uniform = matches!(check.expect, Expect::Uniform);
            if uniform && spread >= 40 {
                wrong(&format!("luminance spans {spread}, not one averaged level"))
            } else if !uniform && spread <= 120 {
                wrong(&format!(
                    "luminance spans only {spread}: not level 0's texels"
                ))
            } else {
                None
            }
        }
    }
}

#[test]
fn vertex_colours_uv_sets_transforms_wraps_and_mips_on_every_path() {
    gpu_test(|gpu| {
        let (scene, checks) = inputs_scene();
        let camera = inputs_camera();
        let mut failures = Vec::new();
        for path in RenderPath::ALL {
            let frame = render_frame_from(gpu, &scene, config(path), &[head_on_light()], &camera);
            if let Some(dir) = std::env::var_os("MATERIAL_INPUTS_DUMP") {
                let file = std::path::Path::new(&dir).join(format!("inputs_{}.png", path.name()));
                image::save_buffer(file, &frame.rgba, W, H, image::ColorType::Rgba8).expect("png");
            }
            failures.extend(
                checks
                    .iter()
                    .filter_map(|c| failure(&frame.rgba, &camera, c))
                    .map(|f| format!("{}: {f}", path.name())),
            );
        }
        assert!(failures.is_empty(), "{failures:#?}");
    });
}
