//! `fma_rate::fma_chains`, the FMA-throughput calibration kernel, run by the DSL's host
//! interpreter against the same workgroup on lavapipe and against plain Rust, at subgroup sizes
//! 4, 8, 32 and 64 (it has no subgroup operations: the result must not depend on them).

use codegen::interp::{Dispatch, Schedule};
use renderer::readback;
use renderer::shader::ShaderProgram;
use shaders_gen::calibrate::fma_rate::{self, CHAINS, ITERATIONS, WORKGROUP};
use tests::gpu::gpu_test;

/// `SINK` of one workgroup on the GPU.
fn gpu_sink() -> Vec<f32> {
    gpu_test(|gpu| {
        let device = gpu.device();
        let variant = fma_rate::variant(fma_rate::VariantKey::ALL[0]);
        let program = ShaderProgram::new(device, gpu.capabilities(), variant).expect("variant");
        let pipeline = program
            .compute_pipeline(device, "fma_chains")
            .expect("entry point");
        let sink = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sink"),
            size: u64::from(WORKGROUP) * 4,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sink"),
            layout: &program.bind_group_layouts[0],
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: sink.as_entire_binding(),
            }],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(1, 1, 1);
        }
        gpu.queue().submit([encoder.finish()]);
        readback::read_buffer::<f32>(device, gpu.queue(), &sink).expect("readback")
    })
}

/// What one invocation stores, in plain Rust (each step rounded twice, as written).
fn cpu_sink(x: u32) -> f32 {
    let seed = x as f32 * 0.000_001;
    // The chains' starts, as the kernel writes them.
    let starts: [f32; CHAINS as usize] = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7];
    starts
        .iter()
        .map(|start| {
            let mut v = seed + start;
            for _ in 0..ITERATIONS {
                v = v * 0.9999 + 0.0001;
            }
            v
        })
        .sum()
}

#[test]
fn host_fma_chains_equal_the_gpu_and_plain_rust() {
    let gpu = gpu_sink();
    let cpu: Vec<f32> = (0..WORKGROUP).map(cpu_sink).collect();
    // The GPU may fuse each multiply-add (one rounding instead of two): over 4,096 steps a
    // chain drifts by up to a few thousand half-ulps of 1. Measured: below 1e-5 of the value on
    // lavapipe, 1.9e-5 on an H100.
    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * b.abs().max(1.0);
    for (i, (g, c)) in gpu.iter().zip(&cpu).enumerate() {
        assert!(close(*g, *c), "invocation {i}: GPU {g}, CPU {c}");
    }
    let source = include_str!("../../shaders_gen/src/calibrate.rs");
    let c = codegen::compile_source(source).expect("fma_rate compiles");
    let runs = [
        (4, Schedule::InOrder),
        (8, Schedule::Reversed),
        (32, Schedule::Shuffled(1)),
        (64, Schedule::InOrder),
    ];
    for (subgroup_size, schedule) in runs {
        let started = std::time::Instant::now();
        let mut d = Dispatch::new(&c.module, &c.keys[0].env, "fma_chains")
            .and_then(|d| d.with_subgroup_size(subgroup_size))
            .expect("dispatch")
            .with_schedule(schedule);
        d.set_buffer("SINK", &vec![0; WORKGROUP as usize * 4])
            .expect("sink");
        d.run([1, 1, 1]).expect("host run");
        let host: Vec<f32> = bytemuck::pod_collect_to_vec(&d.buffer("SINK").expect("sink"));
        let statements = u64::from(WORKGROUP) * u64::from(ITERATIONS) * u64::from(CHAINS);
        let secs = started.elapsed().as_secs_f64();
        eprintln!(
            "host fma_chains, one workgroup, subgroup {subgroup_size}: {:.0} ms, {:.1} M \
             multiply-add statements/s",
            secs * 1e3,
            statements as f64 / secs / 1e6
        );
        // The host rounds as written, as plain Rust does: the same bits.
        assert_eq!(host, cpu, "subgroup {subgroup_size}");
        assert!(host.iter().zip(&gpu).all(|(h, g)| close(*g, *h)));
    }
}
