//! The DSL's generated bind-group builders: resources given by binding name, numbered from the
//! variant's reflection (a library's part included, bindings out of order, a texture, a sampler,
//! a binding one variant lacks), run on the GPU against plain Rust; and the builders' refusals,
//! each naming the binding.

use super::dsl_kernels::bindings::{bound_by_name, scale_lib};
use renderer::shader::ShaderProgram;
use renderer::{GpuContext, readback};
use shader_bind::{BindError, Resources};
use tests::gpu::gpu_test;
use wgpu::util::DeviceExt as _;

const N: usize = 64;
const FACTOR: f32 = 3.0;
const BIAS: f32 = 0.5;

/// The test's resources: input, output, scale, offsets, a 64×1 texture of `i / 4` in red.
struct Inputs {
    input: wgpu::Buffer,
    output: wgpu::Buffer,
    scale: wgpu::Buffer,
    offsets: wgpu::Buffer,
    texels: wgpu::TextureView,
    nearest: wgpu::Sampler,
}

fn input(i: usize) -> f32 {
    i as f32 * 0.5 - 7.0
}
fn offset(i: usize) -> f32 {
    100.0 + i as f32
}
fn texel(i: usize) -> f32 {
    i as f32 / 4.0
}

fn buffer(gpu: &GpuContext, label: &str, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    gpu.device()
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage: usage | wgpu::BufferUsages::COPY_SRC,
        })
}

fn inputs(gpu: &GpuContext) -> Inputs {
    let storage = wgpu::BufferUsages::STORAGE;
    let floats = |f: fn(usize) -> f32| (0..N).map(f).collect::<Vec<f32>>();
    let texture = gpu.device().create_texture_with_data(
        gpu.queue(),
        &wgpu::TextureDescriptor {
            label: Some("texels"),
            size: wgpu::Extent3d {
                width: N as u32,
                height: 1,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba16Float,
            usage: wgpu::TextureUsages::TEXTURE_BINDING,
            view_formats: &[],
        },
        wgpu::util::TextureDataOrder::LayerMajor,
        bytemuck::cast_slice(
            &(0..N)
                .flat_map(|i| [texel(i), 0.0, 0.0, 1.0].map(|v| half::f16::from_f32(v).to_bits()))
                .collect::<Vec<u16>>(),
        ),
    );
    Inputs {
        input: buffer(gpu, "input", bytemuck::cast_slice(&floats(input)), storage),
        output: buffer(gpu, "output", &[0; N * 4], storage),
        scale: buffer(
            gpu,
            "scale",
            bytemuck::bytes_of(&scale_lib::Scale::new(FACTOR, BIAS)),
            wgpu::BufferUsages::UNIFORM,
        ),
        offsets: buffer(
            gpu,
            "offsets",
            bytemuck::cast_slice(&floats(offset)),
            storage,
        ),
        texels: texture.create_view(&Default::default()),
        nearest: gpu
            .device()
            .create_sampler(&wgpu::SamplerDescriptor::default()),
    }
}

fn group0(r: &Inputs) -> bound_by_name::Group0<'_> {
    bound_by_name::Group0 {
        input: r.input.as_entire_buffer_binding(),
        output: r.output.as_entire_buffer_binding(),
        scale_lib: scale_lib::Group0 {
            scale: r.scale.as_entire_buffer_binding(),
        },
    }
}

fn group1(r: &Inputs, offsets: bool) -> bound_by_name::Group1<'_> {
    bound_by_name::Group1 {
        texels: &r.texels,
        nearest: &r.nearest,
        offsets: offsets.then(|| r.offsets.as_entire_buffer_binding()),
    }
}

fn program(gpu: &GpuContext, offset: bool) -> ShaderProgram {
    let key = bound_by_name::VariantKey { offset };
    ShaderProgram::new(
        gpu.device(),
        gpu.capabilities(),
        bound_by_name::variant(key),
    )
    .expect("supported variant")
}

/// Runs the kernel of the variant with `offset` on `r`, both groups from the builders, and
/// reads the output back.
fn run(gpu: &GpuContext, offset: bool, give_offsets: bool, r: &Inputs) -> Vec<f32> {
    let program = program(gpu, offset);
    let pipeline = program
        .compute_pipeline(gpu.device(), "main")
        .expect("entry point");
    let (device, variant) = (gpu.device(), program.variant);
    let g0 = group0(r)
        .bind_group(device, program.layout(0), variant, "group 0")
        .expect("group 0 binds");
    let g1 = group1(r, give_offsets)
        .bind_group(device, program.layout(1), variant, "group 1")
        .expect("group 1 binds");
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &g0, &[]);
        pass.set_bind_group(1, &g1, &[]);
        pass.dispatch_workgroups(1, 1, 1);
    }
    gpu.queue().submit([encoder.finish()]);
    readback::read_buffer::<f32>(device, gpu.queue(), &r.output).expect("readback")
}

#[test]
fn bind_groups_built_by_name_number_every_binding_from_the_reflection() {
    gpu_test(|gpu| {
        let r = inputs(gpu);
        // The variant without offsets ignores the offsets it is given.
        for (offset, give_offsets) in [(false, false), (false, true), (true, true)] {
            let out = run(gpu, offset, give_offsets, &r);
            for (i, got) in out.iter().enumerate() {
                let extra = if offset { self::offset(i) } else { 0.0 };
                let want = input(i) * FACTOR + BIAS + texel(i) + extra;
                assert!(
                    (got - want).abs() < 1e-4,
                    "offset {offset}, element {i}: {got}, expected {want}"
                );
            }
        }
    });
}

/// The error a builder gives for group `g` of the variant with `offset`.
fn refusal(gpu: &GpuContext, offset: bool, g: u32, resources: &Resources<'_>) -> BindError {
    let program = program(gpu, offset);
    let e = resources
        .build(
            gpu.device(),
            program.layout(g),
            program.variant,
            g,
            "refused",
        )
        .expect_err("the builder must refuse it");
    assert!(e.to_string().contains("bound_by_name::"), "{e}");
    e
}

fn mismatch_of(e: &BindError) -> (&'static str, String) {
    match e {
        BindError::Mismatch {
            binding, expected, ..
        } => (*binding, expected.clone()),
        other => panic!("expected a mismatch, got {other:?}"),
    }
}

#[test]
fn bind_group_builders_refuse_what_does_not_fit_naming_the_binding() {
    gpu_test(|gpu| {
        let r = inputs(gpu);
        // A `#[when]` binding the variant has, left empty.
        let e = refusal(gpu, true, 1, &Resources::of(&group1(&r, false)));
        assert!(
            matches!(
                e,
                BindError::Missing {
                    binding: "OFFSETS",
                    index: 9,
                    group: 1,
                    ..
                }
            ),
            "{e:?}"
        );
        // A uniform buffer where a storage buffer is bound.
        let mut wrong = group0(&r);
        wrong.input = r.scale.as_entire_buffer_binding();
        let (binding, expected) = mismatch_of(&refusal(gpu, false, 0, &Resources::of(&wrong)));
        assert_eq!(binding, "INPUT");
        assert!(expected.contains("storage buffer"), "{expected}");
        // A uniform range smaller than the library's struct.
        let mut short = group0(&r);
        short.scale_lib.scale = wgpu::BufferBinding {
            buffer: &r.scale,
            offset: 0,
            size: wgpu::BufferSize::new(4),
        };
        let (binding, expected) = mismatch_of(&refusal(gpu, false, 0, &Resources::of(&short)));
        assert_eq!(binding, "SCALE");
        assert!(expected.contains("at least 8 bytes"), "{expected}");
        // Integer texels where float texels are sampled.
        let uint = gpu
            .device()
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("uint texels"),
                size: wgpu::Extent3d {
                    width: 4,
                    height: 1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::R32Uint,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&Default::default());
        let mut texels = group1(&r, false);
        texels.texels = &uint;
        let (binding, _) = mismatch_of(&refusal(gpu, false, 1, &Resources::of(&texels)));
        assert_eq!(binding, "TEXELS");
        // The written output over the read input: one buffer read and written by one dispatch
        // (a usage conflict for WebGPU and wgpu alike), whatever the ranges.
        let mut aliased = group0(&r);
        aliased.output = r.input.as_entire_buffer_binding();
        let e = refusal(gpu, false, 0, &Resources::of(&aliased));
        assert!(
            matches!(
                e,
                BindError::WritableAlias {
                    writable: "OUTPUT",
                    other: "INPUT",
                    group: 0,
                    ..
                }
            ),
            "{e:?}"
        );
        let variant = program(gpu, false).variant;
        let both = buffer(
            gpu,
            "input and output",
            &[0; N * 8],
            wgpu::BufferUsages::STORAGE,
        );
        let range = |offset: usize| wgpu::BufferBinding {
            buffer: &both,
            offset: offset as u64,
            size: wgpu::BufferSize::new((N * 4) as u64),
        };
        let mut split = group0(&r);
        (split.input, split.output) = (range(0), range(N * 4));
        let e = Resources::of(&split)
            .entries(variant, 0)
            .expect_err("read and written in one dispatch");
        assert!(matches!(e, BindError::WritableAlias { .. }), "{e:?}");
        // One buffer read through two bindings (storage and uniform) is fine.
        let shared = buffer(
            gpu,
            "read twice",
            &[0; N * 4],
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::UNIFORM,
        );
        let mut read_twice = group0(&r);
        read_twice.input = shared.as_entire_buffer_binding();
        read_twice.scale_lib.scale = wgpu::BufferBinding {
            buffer: &shared,
            offset: 0,
            size: wgpu::BufferSize::new(8),
        };
        assert!(Resources::of(&read_twice).entries(variant, 0).is_ok());
        // A group the variant does not have.
        let e = Resources::of(&group1(&r, false))
            .entries(variant, 3)
            .expect_err("no group 3");
        assert!(matches!(e, BindError::NoGroup { group: 3, .. }), "{e:?}");
    });
}
