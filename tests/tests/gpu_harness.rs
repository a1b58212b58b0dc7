//! The GPU context and test harness, proven on real work: a compute dispatch and a render pass
//! whose results are read back and checked against plain Rust (the dispatch also against the
//! DSL's host interpreter), and deliberate misuses that the
//! harness must catch (one wgpu validation error, one Vulkan validation-layer error, a
//! validation-layer warning).

use renderer::demo::test_pattern;
use renderer::readback;
use renderer::shader::ShaderProgram;
use shaders_gen::bootstrap::{square_plus_index, test_pattern::PatternParams};
use tests::gpu::{GpuTestFailure, gpu_test, try_gpu_test};
use wgpu::util::DeviceExt as _;

#[test]
fn compute_dispatch_matches_cpu() {
    // Not a multiple of the workgroup size, so the bounds check in the kernel matters.
    let input: Vec<u32> = (0..1000u32)
        .map(|i| i.wrapping_mul(2_654_435_761) >> 16)
        .collect();
    let expected: Vec<u32> = input
        .iter()
        .enumerate()
        .map(|(i, &x)| x.wrapping_mul(x).wrapping_add(i as u32))
        .collect();
    let output = gpu_test(|gpu| {
        let device = gpu.device();
        let variant = square_plus_index::variant(square_plus_index::VariantKey::ALL[0]);
        let program = ShaderProgram::new(device, gpu.capabilities(), variant).expect("variant");
        let pipeline = program
            .compute_pipeline(device, "square_plus_index")
            .expect("entry point");
        let input_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("input"),
            contents: bytemuck::cast_slice(&input),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let output_buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("output"),
            size: (input.len() * 4) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &program.bind_group_layouts[0],
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: input_buffer.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: output_buffer.as_entire_binding(),
                },
            ],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(
                (input.len() as u32).div_ceil(square_plus_index::WORKGROUP),
                1,
                1,
            );
        }
        gpu.queue().submit([encoder.finish()]);
        readback::read_buffer::<u32>(device, gpu.queue(), &output_buffer).expect("readback")
    });
    assert_eq!(output, expected);
    // The same kernel on the DSL's host interpreter, at four subgroup sizes.
    let compiled = codegen::compile_source_all(include_str!("../../shaders_gen/src/bootstrap.rs"))
        .expect("parses")
        .into_iter()
        .find(|(name, _)| name == "square_plus_index")
        .expect("the module")
        .1
        .expect("compiles");
    for subgroup_size in [4, 8, 32, 64] {
        let mut d = codegen::interp::Dispatch::new(
            &compiled.module,
            &compiled.keys[0].env,
            "square_plus_index",
        )
        .and_then(|d| d.with_subgroup_size(subgroup_size))
        .expect("dispatch");
        d.set_buffer("INPUT", bytemuck::cast_slice(&input))
            .expect("input");
        d.set_buffer("OUTPUT", &vec![0u8; input.len() * 4])
            .expect("output");
        d.run([
            (input.len() as u32).div_ceil(square_plus_index::WORKGROUP),
            1,
            1,
        ])
        .expect("host run");
        let host: Vec<u32> = bytemuck::pod_collect_to_vec(&d.buffer("OUTPUT").expect("output"));
        assert_eq!(host, output, "host, subgroup size {subgroup_size}");
    }
}

/// The CPU recomputation of `fs_pattern` at pixel (x, y).
fn expected_pattern_pixel(params: &PatternParams, x: u32, y: u32) -> [f32; 4] {
    let [w, h] = params.size.to_array();
    let (cx, cy) = ((w / 2) as i32, (h / 2) as i32);
    let (dx, dy) = (x as i32 - cx, y as i32 - cy);
    let dist_sq = (dx * dx + dy * dy) as u32;
    if dist_sq >= params.ring_radii_sq.x && dist_sq < params.ring_radii_sq.y {
        return [1.0; 4];
    }
    let checker = ((x / params.cell + y / params.cell) & 1) as f32;
    [
        (x as f32 + 0.5) / w as f32,
        (y as f32 + 0.5) / h as f32,
        0.25 + 0.5 * checker,
        1.0,
    ]
}

#[test]
fn render_pass_matches_cpu_pattern() {
    let (width, height) = (96, 64);
    let frame = gpu_test(|gpu| test_pattern::render(gpu, width, height).expect("render"));
    let params = test_pattern::params(width, height);
    let mut ring_pixels = 0;
    for y in 0..height {
        for x in 0..width {
            let expected = expected_pattern_pixel(&params, x, y);
            ring_pixels += usize::from(expected == [1.0; 4]);
            let at = ((y * width + x) * 4) as usize;
            let got = &frame.rgba[at..at + 4];
            for (channel, (&g, e)) in got.iter().zip(expected).enumerate() {
                // Tolerance: one unorm8 step. The GPU may round an f32 that lies near a .5
                // boundary of value*255 the other way from the CPU; anything more is a bug.
                let e = (e * 255.0).round();
                assert!(
                    (f32::from(g) - e).abs() <= 1.0,
                    "pixel ({x},{y}) channel {channel}: got {g}, expected {e}"
                );
            }
        }
    }
    assert!(
        ring_pixels > 50,
        "the ring must be visible ({ring_pixels} pixels)"
    );
}

#[test]
fn wgpu_validation_error_fails_the_test() {
    let failure = try_gpu_test(|gpu| {
        let buffer = |label, size| {
            gpu.device().create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let (small, large) = (buffer("small", 16), buffer("large", 256));
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        // Deliberately out of bounds: 64 bytes from a 16-byte buffer.
        encoder.copy_buffer_to_buffer(&small, 0, &large, 0, 64);
        gpu.queue().submit([encoder.finish()]);
    });
    match failure {
        Err(GpuTestFailure::Errors(errors)) => assert!(
            errors
                .iter()
                .any(|e| e.starts_with("wgpu:") && e.contains("overrun")),
            "expected a copy-overrun error, got {errors:#?}"
        ),
        other => panic!("the out-of-bounds copy was not caught: {other:?}"),
    }
}

#[test]
fn vulkan_validation_layer_error_fails_the_test() {
    let failure = try_gpu_test(|gpu| {
        // SAFETY: the raw device outlives this block; the buffer, if the driver made one, is
        // destroyed before returning. Size 0 is invalid on purpose (VUID-VkBufferCreateInfo-size-00912).
        unsafe {
            let hal = gpu
                .device()
                .as_hal::<wgpu::hal::api::Vulkan>()
                .expect("GPU tests run on the Vulkan backend");
            let raw = hal.raw_device();
            let info = ash::vk::BufferCreateInfo::default()
                .size(0)
                .usage(ash::vk::BufferUsageFlags::TRANSFER_SRC);
            if let Ok(buffer) = raw.create_buffer(&info, None) {
                raw.destroy_buffer(buffer, None);
            }
        }
    });
    match failure {
        Err(GpuTestFailure::Errors(errors)) => assert!(
            errors
                .iter()
                .any(|e| e.contains("VUID-VkBufferCreateInfo-size")),
            "expected the layer's VUID-VkBufferCreateInfo-size error, got {errors:#?}"
        ),
        other => panic!("the layer did not report the zero-size buffer: {other:?}"),
    }
}

/// wgpu-hal logs the layer's warnings as `VALIDATION [..]` records at warning level, as it logs
/// its errors at error level (the test above shows that path end to end): a warning of the layer
/// fails the test too, while wgpu's and naga's other warnings are only echoed.
#[test]
fn a_validation_layer_warning_fails_the_test_and_other_warnings_do_not() {
    let failure = try_gpu_test(|_| {
        log::warn!(
            target: "wgpu_hal::vulkan::instance",
            "VALIDATION [TEST-Warning (0x1)]\n\tValidation Warning: a deliberate layer warning"
        );
    });
    match failure {
        Err(GpuTestFailure::Errors(errors)) => assert!(
            errors.iter().any(|e| e.contains("TEST-Warning")),
            "expected the deliberate warning, got {errors:#?}"
        ),
        other => panic!("the layer warning did not fail the test: {other:?}"),
    }
    let other = try_gpu_test(|_| {
        log::warn!(target: "wgpu_core::device", "an ordinary wgpu warning");
    });
    assert!(other.is_ok(), "{:?}", other.err().map(|e| e.to_string()));
}

#[test]
fn an_engines_own_device_reports_only_what_it_enabled() {
    gpu_test(|gpu| {
        // A device opened with the renderer's least limits and no optional feature at all, as
        // an engine might.
        let (device, queue) =
            pollster::block_on(gpu.adapter().request_device(&wgpu::DeviceDescriptor {
                required_limits: renderer::gpu::requirements::minimum_limits(),
                ..Default::default()
            }))
            .expect("a device with the least limits");
        let wrapped = renderer::GpuContext::from_parts(
            gpu.instance().clone(),
            gpu.adapter().clone(),
            device,
            queue,
        )
        .expect("the least limits are enough");
        let caps = wrapped.capabilities();
        assert_eq!(caps.subgroup, None, "SUBGROUP was not enabled");
        assert!(!caps.timestamp_query);
        assert!(caps.msaa_depth32float.iter().all(|c| matches!(c, 1 | 4)));
        // Asking for a subgroup variant on it is a typed error, not a wgpu failure.
        let key = shaders_gen::forward::forward::VariantKey {
            list: shaders_gen::forward::forward::List::List1,
            blend: false,
            scalarize: true,
            msaa: shaders_gen::forward::forward::Msaa::Msaa0,
            vis64: false,
        };
        let variant = shaders_gen::forward::forward::variant(key).expect("a generated variant");
        let err = ShaderProgram::new(wrapped.device(), caps, variant).unwrap_err();
        assert!(err.to_string().contains("SUBGROUP"), "{err}");
    });
}

#[test]
fn an_engines_device_with_webgpu_default_limits_is_refused_naming_what_to_ask() {
    gpu_test(|gpu| {
        let (device, queue) = pollster::block_on(
            gpu.adapter()
                .request_device(&wgpu::DeviceDescriptor::default()),
        )
        .expect("a default device");
        let err = renderer::GpuContext::from_parts(
            gpu.instance().clone(),
            gpu.adapter().clone(),
            device,
            queue,
        )
        .expect_err("8 storage buffers per stage are too few");
        let renderer::gpu::GpuError::DeviceLimits {
            missing,
            adapter_can,
        } = &err
        else {
            panic!("not a limits error: {err}");
        };
        assert_eq!(
            missing,
            &[renderer::gpu::MissingLimit {
                limit: "max_storage_buffers_per_shader_stage",
                needed: 10,
                available: 8,
            }],
            "{err}"
        );
        assert!(*adapter_can, "lavapipe allows 10: {err}");
        let text = err.to_string();
        assert!(
            text.contains("max_storage_buffers_per_shader_stage = 10 (the device has 8)")
                && text.contains("minimum_limits()"),
            "{text}"
        );
    });
}

#[test]
fn an_engines_device_lost_callback_runs_after_the_renderer_records_the_loss() {
    gpu_test(|gpu| {
        let (device, queue) =
            pollster::block_on(gpu.adapter().request_device(&wgpu::DeviceDescriptor {
                required_limits: renderer::gpu::requirements::minimum_limits(),
                ..Default::default()
            }))
            .expect("a device");
        let (tx, rx) = std::sync::mpsc::channel();
        let wrapped = renderer::GpuContext::from_parts_with_loss_callback(
            gpu.instance().clone(),
            gpu.adapter().clone(),
            device,
            queue,
            move |reason, message| {
                tx.send(format!("{reason:?}: {message}")).ok();
            },
        )
        .expect("the device has the limits");
        assert_eq!(wrapped.lost(), None);
        wrapped.device().destroy();
        let _ = wrapped.device().poll(wgpu::PollType::wait_indefinitely());
        let engine_saw = rx
            .recv_timeout(std::time::Duration::from_secs(10))
            .expect("the engine's callback ran");
        assert!(engine_saw.starts_with("Destroyed"), "{engine_saw}");
        assert_eq!(wrapped.lost().as_deref(), Some(engine_saw.as_str()));
    });
}
