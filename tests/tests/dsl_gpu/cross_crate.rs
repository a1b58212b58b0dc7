//! The host interpreter with libraries of other crates and a library graph: the engine
//! example's `engine_lit` module (`examples/engine`), compiled from its source text with the
//! libraries its `uses(..)` reaches (its library crate's `surface`, which uses `shaders_gen`'s
//! `octahedral`, and `shaders_gen`'s `pbr`), run by `codegen::interp` and, from the WGSL of
//! the same compilation, on the GPU: both variants, the same points, within float rounding.

use codegen::interp::Dispatch;
use renderer::GpuContext;
use shaders_gen::shared::pbr::GpuLight;
use tests::gpu::gpu_test;
use wgpu::util::DeviceExt as _;

const ENGINE_LIT: &str = include_str!("../../../examples/engine/shaders/src/lib.rs");
const LIBRARIES: [&str; 3] = [
    include_str!("../../../examples/engine/shader-lib/src/lib.rs"),
    include_str!("../../../shaders_gen/src/shared/normals.rs"),
    include_str!("../../../shaders_gen/src/shared/brdf.rs"),
];
const POINTS: usize = 64;

/// `engine_lit::Point`: position, roughness, normal, metallic.
fn points() -> Vec<[f32; 8]> {
    (0..POINTS)
        .map(|i| {
            let t = i as f32 / POINTS as f32;
            let a = t * std::f32::consts::TAU;
            let n = glam::Vec3::new(a.cos(), 0.6, a.sin()).normalize();
            [
                t * 2.0 - 1.0,
                0.1 * t,
                -0.5,
                0.2 + 0.7 * t,
                n.x,
                n.y,
                n.z,
                t,
            ]
        })
        .collect()
}

fn light() -> GpuLight {
    GpuLight {
        position: glam::Vec3::new(0.3, 1.5, 1.0),
        range: 6.0,
        color: glam::Vec3::new(1.0, 0.9, 0.7),
        intensity: 12.0,
        kind: 0,
        shadow: u32::MAX,
        ..Default::default()
    }
}

/// `surface::Tint`: colour, strength.
const TINT: [f32; 4] = [0.2, 0.4, 0.9, 0.25];

fn gpu_run(gpu: &GpuContext, wgsl: &str) -> Vec<[f32; 4]> {
    let device = gpu.device();
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("engine_lit"),
        source: wgpu::ShaderSource::Wgsl(wgsl.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("engine_lit"),
        layout: None,
        module: &module,
        entry_point: Some("main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let init = |contents: &[u8], usage| {
        device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: None,
            contents,
            usage,
        })
    };
    let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC;
    let points = init(bytemuck::cast_slice(&points()), storage);
    let light = init(bytemuck::bytes_of(&light()), storage);
    let out = init(&vec![0u8; POINTS * 16], storage);
    let tint = init(bytemuck::cast_slice(&TINT), wgpu::BufferUsages::UNIFORM);
    let group = |index: u32, buffers: &[&wgpu::Buffer]| {
        let entries: Vec<_> = buffers
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry {
                binding: i as u32,
                resource: b.as_entire_binding(),
            })
            .collect();
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &pipeline.get_bind_group_layout(index),
            entries: &entries,
        })
    };
    let (g0, g1) = (group(0, &[&points, &light, &out]), group(1, &[&tint]));
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &g0, &[]);
        pass.set_bind_group(1, &g1, &[]);
        pass.dispatch_workgroups(1, 1, 1);
    }
    gpu.queue().submit([encoder.finish()]);
    renderer::readback::read_buffer::<[f32; 4]>(device, gpu.queue(), &out).expect("readback")
}

#[test]
fn the_interpreter_runs_a_module_using_libraries_of_other_crates_as_the_gpu_does() {
    let mut modules =
        codegen::compile_source_all_with(ENGINE_LIT, &LIBRARIES).unwrap_or_else(|e| panic!("{e}"));
    let (name, compiled) = modules.swap_remove(0);
    let c = compiled.unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(c.keys.len(), 2, "both `packed` variants");
    let mut largest = 0.0f32;
    for (k, key) in c.keys.iter().enumerate() {
        let variant = &c.variants[c.key_variant[k].expect("no exclusion")];
        let on_gpu = gpu_test(|gpu| gpu_run(gpu, &variant.wgsl));
        let mut d = Dispatch::new(&c.module, &key.env, "main").unwrap_or_else(|e| panic!("{e}"));
        d.set_buffer("POINTS", bytemuck::cast_slice(&points()))
            .unwrap();
        d.set_buffer("LIGHT", bytemuck::bytes_of(&light())).unwrap();
        d.set_buffer("OUT", &vec![0u8; POINTS * 16]).unwrap();
        d.set_buffer("TINT", bytemuck::cast_slice(&TINT)).unwrap();
        d.run([1, 1, 1]).unwrap_or_else(|e| panic!("{e}"));
        let on_host: Vec<[f32; 4]> = bytemuck::cast_slice(&d.buffer("OUT").unwrap()).to_vec();
        for (i, (h, g)) in on_host.iter().zip(&on_gpu).enumerate() {
            for c in 0..4 {
                let diff = (h[c] - g[c]).abs();
                largest = largest.max(diff);
                assert!(
                    diff <= 1.0e-4 * (1.0 + g[c].abs()),
                    "variant {k}, point {i}, channel {c}: host {} GPU {}",
                    h[c],
                    g[c]
                );
            }
        }
        // Something was lit: the comparison is not of zeros.
        assert!(on_gpu.iter().any(|p| p[0] > 0.05), "{on_gpu:?}");
    }
    eprintln!("largest host-GPU difference {largest:e}");
}
