//! The frame graph executing on a device: passes recorded in dependency order with real GPU
//! work, transients pooled across frames, per-pass GPU timings returned as data, and an unbound
//! import reported as an error.

use renderer::graph::{
    BufferAccess, BufferDesc, GraphError, ImportAccess, PassTiming, RenderGraph, TextureAccess,
    TextureDesc, TransientPool,
};
use renderer::readback;
use renderer::shader::ShaderProgram;
use shaders_gen::bootstrap::square_plus_index;
use tests::gpu::gpu_test;

const N: u32 = 256;

/// fill (copy input) → square (compute) → copy to the imported output; plus an unread pass.
fn build(
    input: &wgpu::Buffer,
    square: std::sync::Arc<(ShaderProgram, wgpu::ComputePipeline)>,
) -> (
    RenderGraph,
    renderer::graph::Handle<renderer::graph::Buffer>,
) {
    let mut g = RenderGraph::new();
    let mut output = g.import_buffer(
        "output",
        BufferDesc {
            size: u64::from(N) * 4,
        },
        ImportAccess::ReadWrite,
    );
    let mut staged = g.create_buffer(
        "staged input",
        BufferDesc {
            size: u64::from(N) * 4,
        },
    );
    let mut squared = g.create_buffer(
        "squared",
        BufferDesc {
            size: u64::from(N) * 4,
        },
    );
    let mut unused = g.create_texture(
        "debug view",
        TextureDesc::new_2d(8, 8, wgpu::TextureFormat::Rgba8Unorm),
    );
    let source = input.clone();
    let staged_h = staged;
    g.add_pass("stage input")
        .write_buffer(&mut staged, BufferAccess::CopyDst)
        .execute(move |ctx| {
            let dst = ctx.buffer(staged_h).clone();
            ctx.encoder
                .copy_buffer_to_buffer(&source, 0, &dst, 0, u64::from(N) * 4);
        });
    let (staged_r, squared_h) = (staged, squared);
    g.add_pass("square")
        .read_buffer(staged, BufferAccess::StorageRead)
        .write_buffer(&mut squared, BufferAccess::StorageWrite)
        .execute(move |ctx| {
            let (program, pipeline) = &*square;
            let bind_group = ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: None,
                layout: &program.bind_group_layouts[0],
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: ctx.buffer(staged_r).as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: ctx.buffer(squared_h).as_entire_binding(),
                    },
                ],
            });
            let mut pass = ctx.encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(N / square_plus_index::WORKGROUP, 1, 1);
        });
    g.add_pass("debug (nothing reads it)")
        .write_texture(&mut unused, TextureAccess::ColorAttachment)
        .execute(|_| panic!("a culled pass must never record"));
    let (squared_r, output_h) = (squared, output);
    g.add_pass("publish")
        .read_buffer(squared, BufferAccess::CopySrc)
        .write_buffer(&mut output, BufferAccess::CopyDst)
        .execute(move |ctx| {
            let (src, dst) = (ctx.buffer(squared_r).clone(), ctx.buffer(output_h).clone());
            ctx.encoder
                .copy_buffer_to_buffer(&src, 0, &dst, 0, u64::from(N) * 4);
        });
    (g, output_h)
}

#[test]
fn graph_executes_pools_and_times_passes() {
    let input: Vec<u32> = (0..N).map(|i| i * 3 + 1).collect();
    let expected: Vec<u32> = input
        .iter()
        .enumerate()
        .map(|(i, x)| x * x + i as u32)
        .collect();
    gpu_test(|gpu| {
        let device = gpu.device();
        let make = |usage| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: None,
                size: u64::from(N) * 4,
                usage,
                mapped_at_creation: false,
            })
        };
        let input_buffer = make(wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST);
        gpu.queue()
            .write_buffer(&input_buffer, 0, bytemuck::cast_slice(&input));
        let output_buffer = make(wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST);
        let variant = square_plus_index::variant(square_plus_index::VariantKey::ALL[0]);
        let program = ShaderProgram::new(device, gpu.capabilities(), variant).expect("variant");
        let pipeline = program
            .compute_pipeline(device, "square_plus_index")
            .expect("entry");
        let square = std::sync::Arc::new((program, pipeline));
        let mut pool = TransientPool::new();
        // Encoder-level debug groups (wgpu-profiler's default) crash Mesa 22.3's lavapipe in
        // vkCmdBeginDebugUtilsLabelEXT under the validation layer (SIGSEGV); timestamps work.
        let settings = wgpu_profiler::GpuProfilerSettings {
            enable_debug_groups: false,
            ..Default::default()
        };
        let mut profiler = wgpu_profiler::GpuProfiler::new(device, settings).expect("profiler");
        let mut stats = Vec::new();
        let mut timings = Vec::new();
        for _frame in 0..2 {
            let (graph, output) = build(&input_buffer, square.clone());
            let mut compiled = graph.compile().expect("valid graph");
            assert_eq!(compiled.pass_order(), ["stage input", "square", "publish"]);
            compiled.bind_buffer(output, &output_buffer);
            let mut encoder = device.create_command_encoder(&Default::default());
            stats.push(
                compiled
                    .execute(device, &mut encoder, &mut pool, &profiler)
                    .expect("execute"),
            );
            profiler.resolve_queries(&mut encoder);
            gpu.queue().submit([encoder.finish()]);
            profiler.end_frame().expect("profiler frame");
            gpu.wait_idle().expect("wait");
            if let Some(results) =
                profiler.process_finished_frame(gpu.queue().get_timestamp_period())
            {
                timings = PassTiming::from_profiler(&results);
            }
            let out = readback::read_buffer::<u32>(device, gpu.queue(), &output_buffer)
                .expect("readback");
            assert_eq!(out, expected);
            gpu.queue()
                .write_buffer(&output_buffer, 0, &vec![0u8; (N * 4) as usize]);
        }
        // Frame 1 creates the two transient buffers (their lifetimes overlap in "square"); frame
        // 2 reuses both.
        assert_eq!((stats[0].created, stats[0].reused), (2, 0));
        assert_eq!((stats[1].created, stats[1].reused), (0, 2));
        if gpu.capabilities().timestamp_inside_passes {
            let names: Vec<&str> = timings.iter().map(|t| t.pass.as_str()).collect();
            assert_eq!(names, ["stage input", "square", "publish"]);
            assert!(
                timings
                    .iter()
                    .all(|t| t.gpu_ms >= 0.0 && t.gpu_ms.is_finite())
            );
        }
    });
}

#[test]
fn executing_with_an_unbound_import_is_an_error() {
    gpu_test(|gpu| {
        let mut g = RenderGraph::new();
        let mut target = g.import_texture(
            "target",
            TextureDesc::new_2d(8, 8, wgpu::TextureFormat::Rgba8Unorm),
            ImportAccess::ReadWrite,
        );
        g.add_pass("draw")
            .write_texture(&mut target, TextureAccess::ColorAttachment)
            .finish();
        let compiled = g.compile().expect("valid graph");
        let profiler =
            wgpu_profiler::GpuProfiler::new(gpu.device(), Default::default()).expect("profiler");
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        let err = compiled
            .execute(
                gpu.device(),
                &mut encoder,
                &mut TransientPool::new(),
                &profiler,
            )
            .unwrap_err();
        assert_eq!(
            err,
            GraphError::ImportNotBound {
                resource: "target".into()
            }
        );
    });
}
