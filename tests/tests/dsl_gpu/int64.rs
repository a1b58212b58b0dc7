//! `u64` on the GPU against the DSL's host interpreter: arithmetic that wraps, shifts by the
//! amount's low 6 bits, division by zero, `i32 as u64` sign-extending, `u64 as u32`
//! truncating, `f32 as u64` saturating, constants the printer folds, and the visibility
//! buffer's `Atomic<u64>` `fetch_min` from many invocations. The device must have
//! `SHADER_INT64` and `SHADER_INT64_ATOMIC_MIN_MAX` (lavapipe has both).

use codegen::interp::Dispatch;
use renderer::readback::read_buffer;
use tests::gpu::gpu_test;
use wgpu::util::DeviceExt;

const KERNEL: &str = r#"#[shader] mod m {
    #[storage(group = 0, binding = 0)]
    static IN: [u32];
    #[storage(group = 0, binding = 1, read_write)]
    static OUT: [u64];
    #[storage(group = 0, binding = 2, read_write)]
    static VIS64: [Atomic<u64>];
    #[compute(workgroup_size(32))]
    fn main(#[builtin(global_invocation_id)] gid: UVec3) {
        let i = gid.x;
        VIS64[i % 16u32].fetch_min((((i * 2654435761u32) >> 20u32) as u64) << 32u32 | i as u64);
        if i != 0u32 {
            return;
        }
        let a = (IN[0] as u64) << 32u32 | IN[1] as u64;
        let b = IN[2] as u64;
        let s = IN[3];
        OUT[0] = a + a * b - 7;
        OUT[1] = a << s;
        OUT[2] = a >> s;
        OUT[3] = a / (b - b) + a % (b - b);
        OUT[4] = (IN[4] as i32) as u64;
        OUT[5] = ((a as u32) as u64) | ((a as i32 as u32 as u64) << 1u32);
        OUT[6] = (f32::from_bits(IN[5]) * 1e20) as u64;
        OUT[7] = f32::from_bits(IN[6]) as u64;
        OUT[8] = (a as f32) as u64;
        OUT[9] = select(a > b, a.min(b), a.max(b)) ^ !0u64;
        OUT[10] = (a as i32) as u64;
        OUT[11] = (a as f32).to_bits() as u64;
        OUT[12] = a << IN[7];
        OUT[13] = a >> (IN[7] + 1u32);
        OUT[14] = a / b + a % b * a * a - (a + 1);
        OUT[15] = ((IN[4] as i32) as u64 as u32) as u64;
        OUT[16] = (u64::MAX as f32).to_bits() as u64;
        OUT[17] = (a > b) as u64 + (a == a) as u64 * 2u64;
        OUT[18] = 18446744073709551615u64 / 3u64 + 0xffff_ffff_ffff_ffffu64 as u32 as u64;
        OUT[19] = (true as u64) << 63u32 | a ^ (a >> 7u32) & 0x00ff00ff00ff00ffu64;
        OUT[20] = (-1.5 as u64) + ((a >> 40u32) as f32 * 1.5) as u64;
        OUT[21] = (IN[4] as i32 as u64) >> 60u32;
    }
}
"#;

const INPUT: [u32; 8] = [
    0xdead_beef,
    0x1234_5678,
    0x9abc,
    70,
    (-3i32) as u32,
    0x4f00_0000,
    0xbf80_0000,
    63,
];
const OUT_LEN: usize = 22;
const SLOTS: usize = 16;
const GROUPS: u32 = 2;

#[test]
fn u64_on_the_gpu_equals_the_interpreter() {
    let c = codegen::compile_source(KERNEL).unwrap_or_else(|e| panic!("{e}"));
    let v = &c.variants[0];
    assert!(v.reflection.features.int64);
    let cleared = vec![0xff_u8; SLOTS * 8];
    let mut d = Dispatch::new(&c.module, &c.keys[0].env, "main").expect("dispatch");
    d.set_buffer("IN", bytemuck::cast_slice(&INPUT))
        .expect("IN");
    d.set_buffer("OUT", &[0; OUT_LEN * 8]).expect("OUT");
    d.set_buffer("VIS64", &cleared).expect("VIS64");
    d.run([GROUPS, 1, 1]).expect("runs");
    let host_out: Vec<u64> = bytemuck::pod_collect_to_vec(&d.buffer("OUT").expect("OUT"));
    let host_vis: Vec<u64> = bytemuck::pod_collect_to_vec(&d.buffer("VIS64").expect("VIS64"));
    let (gpu_out, gpu_vis) = gpu_test(|gpu| {
        let device = gpu.device();
        let needed = wgpu::Features::SHADER_INT64 | wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX;
        assert!(
            device.features().contains(needed),
            "the test device lacks {needed:?}"
        );
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("int64"),
            source: wgpu::ShaderSource::Wgsl(v.wgsl.as_str().into()),
        });
        let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("int64"),
            layout: None,
            module: &module,
            entry_point: Some("main"),
            compilation_options: Default::default(),
            cache: None,
        });
        let buffer = |label, contents: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
            })
        };
        let input = buffer("IN", bytemuck::cast_slice(&INPUT));
        let out = buffer("OUT", &[0; OUT_LEN * 8]);
        let vis = buffer("VIS64", &cleared);
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("int64"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: input.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: out.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: vis.as_entire_binding(),
                },
            ],
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.dispatch_workgroups(GROUPS, 1, 1);
        }
        gpu.queue().submit([encoder.finish()]);
        (
            read_buffer::<u64>(device, gpu.queue(), &out).expect("OUT"),
            read_buffer::<u64>(device, gpu.queue(), &vis).expect("VIS64"),
        )
    });
    for (i, (h, g)) in host_out.iter().zip(&gpu_out).enumerate() {
        assert_eq!(
            h, g,
            "OUT[{i}]: interpreter {h:#018x}, GPU {g:#018x}\n{}",
            v.wgsl
        );
    }
    assert_eq!(host_vis, gpu_vis);
    // A few against plain Rust, so that both sides are not wrong together.
    let a = 0xdead_beef_1234_5678_u64;
    assert_eq!(host_out[1], a << (70 & 63));
    assert_eq!(host_out[3], a);
    assert_eq!(host_out[4], u64::MAX - 2);
    assert_eq!(host_out[7], 0);
    let expected_vis: Vec<u64> = (0..SLOTS as u32)
        .map(|s| {
            (s..GROUPS * 32)
                .step_by(SLOTS)
                .map(|i| (u64::from(i.wrapping_mul(2_654_435_761) >> 20) << 32) | u64::from(i))
                .min()
                .expect("a slot has invocations")
        })
        .collect();
    assert_eq!(host_vis, expected_vis);
}
