//! The material atlas against the hardware sampler: for every wrap mode pair, filter
//! combination, colour and data texture, and levels from magnified to past the last, a
//! texture sampled through `atlas_sample` (wrapping, level choice and filtering in the shader,
//! each level at its own bordered rectangle among other textures) equals the same texture
//! sampled on its own by the device's sampler with the glTF sampler's modes. The reference's
//! mip levels are made here, independently of the renderer's.

use glam::Vec2;
use renderer::GpuContext;
use renderer::demo::Rng;
use renderer::frame_data::sampler_descriptor;
use renderer::readback::read_buffer;
use renderer::scene::{AtlasGrowth, AtlasKey, Filter, Image, MaterialAtlas, TextureSampler, Wrap};
use renderer::shader::ShaderProgram;
use wgpu::util::DeviceExt as _;

use tests::gpu::gpu_test;

/// Samples material texture `PROBE.texture` of the atlas and the reference texture at the same
/// coordinates and derivatives.
#[shader_dsl::shader(uses(shaders_gen::shared::material_atlas))]
pub mod atlas_probe {
    pub struct ProbeSample {
        pub uv: Vec2,
        pub ddx: Vec2,
        pub ddy: Vec2,
    }

    pub struct ProbeParams {
        pub texture: u32,
        pub colour: u32,
        pub count: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static PROBE: ProbeParams;
    #[storage(group = 0, binding = 1)]
    static SAMPLES: [ProbeSample];
    #[storage(group = 0, binding = 2, read_write)]
    static FROM_ATLAS: [Vec4];
    #[storage(group = 0, binding = 3, read_write)]
    static FROM_SAMPLER: [Vec4];
    #[texture(group = 0, binding = 4)]
    static REFERENCE: Texture2d<f32>;
    #[sampler(group = 0, binding = 5)]
    static REFERENCE_SAMPLER: Sampler;

    #[compute(workgroup_size(64, 1, 1))]
    pub fn probe(#[builtin(global_invocation_id)] gid: UVec3) {
        if gid.x < PROBE.count {
            let s = SAMPLES[gid.x];
            FROM_ATLAS[gid.x] =
                atlas_sample(PROBE.texture, PROBE.colour != 0u32, s.uv, s.ddx, s.ddy);
            FROM_SAMPLER[gid.x] = REFERENCE.sample_grad(REFERENCE_SAMPLER, s.uv, s.ddx, s.ddy);
        }
    }
}

/// A deterministic image of `w` × `h` with sharp detail at every scale.
fn image(w: u32, h: u32, seed: u32) -> Image {
    let mut rgba8 = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h {
        for x in 0..w {
            for c in 0..4u32 {
                let v = (x * 73 + y * 151 + c * 57 + seed * 29) ^ (x * y + seed);
                rgba8.push((v.wrapping_mul(2_654_435_761) >> 24) as u8);
            }
        }
    }
    Image {
        width: w,
        height: h,
        rgba8,
    }
}

/// Level `k + 1` of a power-of-two chain: each texel the mean of four, colour channels in linear
/// light (the sRGB curve of IEC 61966-2-1), alpha and data as stored.
fn halve(level: &[u8], w: u32, h: u32, colour: bool) -> Vec<u8> {
    let decode = |v: u8, c: usize| {
        let x = f32::from(v) / 255.0;
        if !colour || c == 3 {
            x
        } else if x <= 0.04045 {
            x / 12.92
        } else {
            ((x + 0.055) / 1.055).powf(2.4)
        }
    };
    let encode = |x: f32, c: usize| {
        let y = if !colour || c == 3 {
            x
        } else if x <= 0.003_130_8 {
            x * 12.92
        } else {
            1.055 * x.powf(1.0 / 2.4) - 0.055
        };
        (y.clamp(0.0, 1.0) * 255.0).round() as u8
    };
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let mut out = Vec::with_capacity((nw * nh * 4) as usize);
    for y in 0..nh {
        for x in 0..nw {
            for c in 0..4 {
                let mut sum = 0.0;
                let mut n = 0.0;
                for (sx, sy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let (px, py) = ((2 * x + sx).min(w - 1), (2 * y + sy).min(h - 1));
                    sum += decode(level[((py * w + px) * 4) as usize + c], c);
                    n += 1.0;
                }
                out.push(encode(sum / n, c));
            }
        }
    }
    out
}

/// `image` as a texture of its own with a full chain, the format decoding sRGB for colour.
fn reference_texture(gpu: &GpuContext, image: &Image, colour: bool) -> wgpu::TextureView {
    let (mut w, mut h) = (image.width, image.height);
    let mut level = image.rgba8.clone();
    let mut chain = level.clone();
    let mut levels = 1;
    while w > 1 || h > 1 {
        level = halve(&level, w, h, colour);
        (w, h) = ((w / 2).max(1), (h / 2).max(1));
        chain.extend_from_slice(&level);
        levels += 1;
    }
    gpu.device()
        .create_texture_with_data(
            gpu.queue(),
            &wgpu::TextureDescriptor {
                label: Some("reference"),
                size: wgpu::Extent3d {
                    width: image.width,
                    height: image.height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: levels,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: if colour {
                    wgpu::TextureFormat::Rgba8UnormSrgb
                } else {
                    wgpu::TextureFormat::Rgba8Unorm
                },
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            &chain,
        )
        .create_view(&Default::default())
}

/// Coordinates from −2.5 to 3.5 (every wrap period kind), derivatives from 4× magnified to
/// beyond the last level, in every direction, up to 2:1 anisotropic.
fn samples(size: Vec2, count: u32) -> Vec<atlas_probe::ProbeSample> {
    let mut rng = Rng::new(0x9e37_79b9);
    (0..count)
        .map(|_| {
            let uv = Vec2::new(rng.range(-2.5, 3.5), rng.range(-2.5, 3.5));
            let lod = rng.range(-2.0, 8.0);
            let along = Vec2::from_angle(rng.range(0.0, std::f32::consts::TAU));
            let texels = 2f32.powf(lod);
            let ddx = along * texels / size.max_element();
            let ddy = along.perp() * texels * rng.range(0.5, 1.0) / size.max_element();
            atlas_probe::ProbeSample::new(uv, ddx, ddy)
        })
        .collect()
}

fn sampler(
    wrap_u: Wrap,
    wrap_v: Wrap,
    mag: Filter,
    min: Filter,
    mip: Option<Filter>,
) -> TextureSampler {
    TextureSampler {
        wrap_u,
        wrap_v,
        mag_filter: mag,
        min_filter: min,
        mipmap_filter: mip,
    }
}

/// Every texture the test probes: three images (two of them packed around the third), each
/// wrap pair, and the glTF filter combinations, as colour and as data.
fn keys() -> Vec<AtlasKey> {
    use Filter::{Linear, Nearest};
    use Wrap::{ClampToEdge, MirroredRepeat, Repeat};
    let wraps = [Repeat, MirroredRepeat, ClampToEdge];
    let filters = [
        (Linear, Linear, Some(Linear)),
        (Nearest, Nearest, Some(Nearest)),
        (Linear, Linear, None),
        (Nearest, Linear, Some(Nearest)),
        (Linear, Nearest, Some(Linear)),
    ];
    let mut keys = Vec::new();
    for (i, wrap_u) in wraps.into_iter().enumerate() {
        for (j, wrap_v) in wraps.into_iter().enumerate() {
            let (mag, min, mip) = filters[(i * 3 + j) % filters.len()];
            keys.push(AtlasKey {
                image: (i + j) % 3,
                sampler: sampler(wrap_u, wrap_v, mag, min, mip),
                colour: (i + j) % 2 == 0,
            });
        }
    }
    for (f, (mag, min, mip)) in filters.into_iter().enumerate() {
        keys.push(AtlasKey {
            image: f % 3,
            sampler: sampler(Repeat, ClampToEdge, mag, min, mip),
            colour: f % 2 == 1,
        });
    }
    keys
}

#[test]
fn atlas_textures_sample_as_the_hardware_sampler_for_every_wrap_filter_and_level() {
    let images = vec![image(32, 16, 1), image(8, 8, 2), image(16, 32, 3)];
    gpu_test(|gpu| {
        let atlas = MaterialAtlas::new(gpu.device(), gpu.queue(), &images, &keys()).expect("atlas");
        assert_eq!(atlas.pages(), (256, 1));
        probe(gpu, &atlas, &images, &keys());
    });
}

/// 24 images of 64², colour and data in turn: more than one layer of 256².
fn several_layers() -> (Vec<Image>, Vec<AtlasKey>) {
    let images: Vec<Image> = (0..24).map(|i| image(64, 64, 10 + i)).collect();
    let keys: Vec<AtlasKey> = (0..images.len())
        .map(|image| AtlasKey {
            image,
            sampler: TextureSampler::default(),
            colour: image % 2 == 0,
        })
        .collect();
    (images, keys)
}

/// Textures that fill several layers: each still samples as on its own.
#[test]
fn an_atlas_of_several_layers_samples_every_texture_as_the_hardware_sampler() {
    let (images, keys) = several_layers();
    gpu_test(|gpu| {
        let atlas = MaterialAtlas::new(gpu.device(), gpu.queue(), &images, &keys).expect("atlas");
        let (side, layers) = atlas.pages();
        assert!(side == 256 && layers >= 3, "{side}² × {layers}");
        probe(gpu, &atlas, &images, &keys);
    });
}

/// The same textures added to an atlas a few at a time: each addition goes into the pages'
/// free space or new layers (the old ones copied on the GPU), every texture keeps its index,
/// and every texture samples as on its own.
#[test]
fn an_atlas_grown_in_place_samples_every_texture_as_the_hardware_sampler() {
    // The images and keys of the test above, so only the placement differs.
    let (images, keys) = several_layers();
    gpu_test(|gpu| {
        let (device, queue) = (gpu.device(), gpu.queue());
        let mut atlas = MaterialAtlas::new(device, queue, &images, &keys[..2]).expect("atlas");
        assert_eq!(atlas.pages(), (256, 1));
        for chunk in [2..3, 3..10, 10..24] {
            let before: Vec<Option<u32>> =
                keys[..chunk.start].iter().map(|k| atlas.index(k)).collect();
            let growth = atlas
                .add(device, queue, &images, &keys[chunk.clone()])
                .expect("room");
            assert_eq!(growth, AtlasGrowth::Grown);
            let after: Vec<Option<u32>> =
                keys[..chunk.start].iter().map(|k| atlas.index(k)).collect();
            assert_eq!(before, after, "textures held keep their indices");
        }
        let held = atlas
            .add(device, queue, &images, &keys[5..7])
            .expect("held");
        assert_eq!(held, AtlasGrowth::Held);
        let (side, layers) = atlas.pages();
        // Grown past its first layer, so the copy of old layers ran.
        assert!(side == 256 && layers >= 2, "{side}² × {layers}");
        assert_eq!(atlas.additions(), 3);
        probe(gpu, &atlas, &images, &keys);
    });
}

/// Samples every key of `atlas` both ways and asserts they agree.
fn probe(gpu: &GpuContext, atlas: &MaterialAtlas, images: &[Image], keys: &[AtlasKey]) {
    let program = ShaderProgram::new(
        gpu.device(),
        gpu.capabilities(),
        atlas_probe::variant(atlas_probe::VariantKey::ALL[0]),
    )
    .expect("the probe runs everywhere");
    let pipeline = gpu
        .device()
        .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("atlas probe"),
            layout: Some(&program.pipeline_layout),
            module: &program.module,
            entry_point: Some("probe"),
            compilation_options: Default::default(),
            cache: None,
        });
    let atlas_group = atlas_probe::Group2 {
        material_atlas: atlas.bindings(),
    }
    .bind_group(gpu.device(), program.layout(2), program.variant, "atlas")
    .expect("the atlas binds");
    let mut worst_overall = 0.0f32;
    for key in keys {
        let image = &images[key.image];
        let size = Vec2::new(image.width as f32, image.height as f32);
        let probes = samples(size, 2048);
        let index = atlas.index(key).expect("the atlas holds every key");
        let storage = |label, contents: &[u8], usage| {
            gpu.device()
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage,
                })
        };
        let params = storage(
            "probe params",
            bytemuck::bytes_of(&atlas_probe::ProbeParams::new(
                index,
                u32::from(key.colour),
                probes.len() as u32,
            )),
            wgpu::BufferUsages::UNIFORM,
        );
        let input = storage(
            "probe samples",
            bytemuck::cast_slice(&probes),
            wgpu::BufferUsages::STORAGE,
        );
        let out = vec![glam::Vec4::ZERO; probes.len()];
        let out_usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
        let from_atlas = storage("from atlas", bytemuck::cast_slice(&out), out_usage);
        let from_sampler = storage("from sampler", bytemuck::cast_slice(&out), out_usage);
        let reference = reference_texture(gpu, image, key.colour);
        let reference_sampler = gpu
            .device()
            .create_sampler(&sampler_descriptor(key.sampler));
        let group = gpu.device().create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("probe"),
            layout: &program.bind_group_layouts[0],
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: params.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: input.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: from_atlas.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: from_sampler.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::TextureView(&reference),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: wgpu::BindingResource::Sampler(&reference_sampler),
                },
            ],
        });
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.set_bind_group(2, &atlas_group, &[]);
            pass.dispatch_workgroups((probes.len() as u32).div_ceil(64), 1, 1);
        }
        gpu.queue().submit([encoder.finish()]);
        let got: Vec<glam::Vec4> =
            read_buffer(gpu.device(), gpu.queue(), &from_atlas).expect("read");
        let want: Vec<glam::Vec4> =
            read_buffer(gpu.device(), gpu.queue(), &from_sampler).expect("read");
        let mut errors: Vec<f32> = got
            .iter()
            .zip(&want)
            .map(|(a, b)| (*a - *b).abs().max_element())
            .collect();
        errors.sort_by(f32::total_cmp);
        let worst = errors[errors.len() - 1];
        let p99 = errors[errors.len() * 99 / 100];
        eprintln!(
            "{key:?}: p99 {:.2} worst {:.2} /255",
            p99 * 255.0,
            worst * 255.0
        );
        // The reference varies, so equal outputs mean something.
        let (low, high) = want
            .iter()
            .fold((f32::MAX, f32::MIN), |(l, h), v| (l.min(v.x), h.max(v.x)));
        assert!(high - low > 0.3, "{key:?}: the reference barely varies");
        // Measured on lavapipe: at most 1.66 / 255 (the two chains' rounding and the
        // filter weights' precision).
        assert!(
            worst <= 2.0 / 255.0,
            "{key:?}: the atlas differs from the sampler by {} / 255 (99th percentile {})",
            worst * 255.0,
            p99 * 255.0
        );
        worst_overall = worst_overall.max(worst);
    }
    eprintln!(
        "worst difference of all textures: {:.2} / 255",
        worst_overall * 255.0
    );
}
