//! DSL kernels executed on the GPU and checked against plain Rust: a workgroup prefix sum, an
//! MSAA 4 depth min/max reduction with workgroup atomics, subgroup ballot + exclusive-add
//! compaction against its non-subgroup variant, a vertex + fragment pair at MSAA 1 and 4, and
//! host structs with `Vec3` fields round-tripped through uniform and storage buffers; the
//! generated bind-group builders (`bind_groups`); the host interpreter and the GPU on a module
//! using libraries of other crates (`cross_crate`), and on `u64` and 64-bit atomics (`int64`).

#[path = "dsl_gpu/bind_groups.rs"]
mod bind_groups;
#[path = "dsl_gpu/cross_crate.rs"]
mod cross_crate;
mod dsl_kernels;
#[path = "dsl_gpu/int64.rs"]
mod int64;

use codegen::rt::Variant;
use dsl_kernels::{compaction, depth_bounds, layout_probe, prefix_sum};
use renderer::shader::ShaderProgram;
use renderer::{GpuContext, readback};
use tests::gpu::gpu_test;
use wgpu::util::DeviceExt as _;

fn storage(gpu: &GpuContext, label: &str, bytes: &[u8], extra: wgpu::BufferUsages) -> wgpu::Buffer {
    gpu.device()
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytes,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | extra,
        })
}

fn uniform(gpu: &GpuContext, bytes: &[u8]) -> wgpu::Buffer {
    gpu.device()
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("uniform"),
            contents: bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        })
}

fn bind(
    gpu: &GpuContext,
    program: &ShaderProgram,
    group: usize,
    resources: &[wgpu::BindingResource<'_>],
) -> wgpu::BindGroup {
    let entries: Vec<_> = program
        .variant
        .group(group as u32)
        .zip(resources)
        .map(|(b, r)| wgpu::BindGroupEntry {
            binding: b.binding,
            resource: r.clone(),
        })
        .collect();
    gpu.device().create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &program.bind_group_layouts[group],
        entries: &entries,
    })
}

fn dispatch(
    gpu: &GpuContext,
    variant: &'static Variant,
    entry: &str,
    resources: &[wgpu::BindingResource<'_>],
    groups: [u32; 3],
) {
    let program =
        ShaderProgram::new(gpu.device(), gpu.capabilities(), variant).expect("supported variant");
    let pipeline = program
        .compute_pipeline(gpu.device(), entry)
        .expect("entry point");
    let bind_group = bind(gpu, &program, 0, resources);
    let mut encoder = gpu.device().create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(groups[0], groups[1], groups[2]);
    }
    gpu.queue().submit([encoder.finish()]);
}

#[test]
fn workgroup_prefix_sum_matches_cpu() {
    let n = prefix_sum::BLOCK * 5;
    let input: Vec<u32> = (0..n).map(|i| (i * 7919) % 1000).collect();
    let expected: Vec<u32> = input
        .chunks(prefix_sum::BLOCK as usize)
        .flat_map(|block| {
            block
                .iter()
                .scan(0u32, |acc, &x| {
                    *acc += x;
                    Some(*acc)
                })
                .collect::<Vec<_>>()
        })
        .collect();
    let output = gpu_test(|gpu| {
        let input_buffer = storage(
            gpu,
            "input",
            bytemuck::cast_slice(&input),
            wgpu::BufferUsages::empty(),
        );
        let output_buffer = storage(
            gpu,
            "output",
            &vec![0u8; input.len() * 4],
            wgpu::BufferUsages::empty(),
        );
        let variant = prefix_sum::variant(prefix_sum::VariantKey::ALL[0]);
        dispatch(
            gpu,
            variant,
            "scan",
            &[
                input_buffer.as_entire_binding(),
                output_buffer.as_entire_binding(),
            ],
            [5, 1, 1],
        );
        readback::read_buffer::<u32>(gpu.device(), gpu.queue(), &output_buffer).expect("readback")
    });
    assert_eq!(output, expected);
}

/// The per-sample depth the fill shader writes at pixel (x, y), sample s, computed on the CPU.
fn fill_depth(x: u32, y: u32, s: u32) -> f32 {
    ((x * 37 + y * 101 + s * 53) % 997) as f32 / 1000.0
}

#[test]
fn msaa4_depth_bounds_with_workgroup_atomics_match_cpu() {
    let (w, h, samples) = (40u32, 24u32, 4u32);
    let depths: Vec<f32> = (0..h)
        .flat_map(|y| (0..w).flat_map(move |x| (0..samples).map(move |s| fill_depth(x, y, s))))
        .collect();
    let tiles = (w.div_ceil(8), h.div_ceil(8));
    let mut expected = vec![[f32::INFINITY, 0.0f32]; (tiles.0 * tiles.1) as usize];
    for y in 0..h {
        for x in 0..w {
            for s in 0..samples {
                let t = &mut expected[((y / 8) * tiles.0 + x / 8) as usize];
                let d = fill_depth(x, y, s);
                t[0] = t[0].min(d);
                t[1] = t[1].max(d);
            }
        }
    }
    let bounds = gpu_test(|gpu| {
        let depth = dsl_kernels::write_msaa_depth(gpu, w, h, samples, &depths);
        let view = depth.create_view(&Default::default());
        let out = storage(
            gpu,
            "bounds",
            &vec![0u8; expected.len() * 8],
            wgpu::BufferUsages::empty(),
        );
        let variant = depth_bounds::variant(depth_bounds::VariantKey::ALL[0]);
        dispatch(
            gpu,
            variant,
            "reduce",
            &[
                wgpu::BindingResource::TextureView(&view),
                out.as_entire_binding(),
            ],
            [tiles.0, tiles.1, 1],
        );
        readback::read_buffer::<[u32; 2]>(gpu.device(), gpu.queue(), &out).expect("readback")
    });
    let got: Vec<[f32; 2]> = bounds
        .iter()
        .map(|b| [f32::from_bits(b[0]), f32::from_bits(b[1])])
        .collect();
    assert_eq!(got, expected, "depth values are exact f32s: no tolerance");
}

fn run_compaction(gpu: &GpuContext, scalarize: bool, input: &[u32], threshold: u32) -> Vec<u32> {
    let params = compaction::Params::new(input.len() as u32, threshold);
    let params_buffer = uniform(gpu, bytemuck::bytes_of(&params));
    let input_buffer = storage(
        gpu,
        "input",
        bytemuck::cast_slice(input),
        wgpu::BufferUsages::empty(),
    );
    let output_buffer = storage(
        gpu,
        "output",
        &vec![0u8; input.len() * 4],
        wgpu::BufferUsages::empty(),
    );
    let counter = storage(gpu, "counter", &[0u8; 4], wgpu::BufferUsages::empty());
    let variant = compaction::variant(compaction::VariantKey { scalarize });
    assert_eq!(
        variant.features.subgroup, scalarize,
        "only the scalarized variant needs SUBGROUP"
    );
    dispatch(
        gpu,
        variant,
        "compact",
        &[
            params_buffer.as_entire_binding(),
            input_buffer.as_entire_binding(),
            output_buffer.as_entire_binding(),
            counter.as_entire_binding(),
        ],
        [(input.len() as u32).div_ceil(compaction::WORKGROUP), 1, 1],
    );
    let count =
        readback::read_buffer::<u32>(gpu.device(), gpu.queue(), &counter).expect("readback")[0];
    let mut out =
        readback::read_buffer::<u32>(gpu.device(), gpu.queue(), &output_buffer).expect("readback");
    out.truncate(count as usize);
    out.sort_unstable();
    out
}

#[test]
fn subgroup_ballot_compaction_matches_atomic_compaction_and_cpu() {
    let input: Vec<u32> = (0..1000u32)
        .map(|i| i.wrapping_mul(2_654_435_761) >> 22)
        .collect();
    let threshold = 700;
    let mut expected: Vec<u32> = input.iter().copied().filter(|&x| x >= threshold).collect();
    expected.sort_unstable();
    let (plain, scalar) = gpu_test(|gpu| {
        assert!(
            gpu.capabilities().subgroup.is_some(),
            "this test needs SUBGROUP (lavapipe has it)"
        );
        (
            run_compaction(gpu, false, &input, threshold),
            run_compaction(gpu, true, &input, threshold),
        )
    });
    assert_eq!(plain, expected);
    assert_eq!(
        scalar, plain,
        "scalarized and plain variants select the same set"
    );
}

/// Expected resolved colour of pixel (x, y): shading at the pixel centre times the fraction of
/// the standard sample positions inside the triangle.
///
/// The corners lie on a 1/16-pixel grid, which the rasterizer's 8-bit sub-pixel fixed point holds
/// exactly, and the edge functions are evaluated exactly here in f64; so coverage is decided
/// exactly on both sides as long as no sample lies on an edge, which this asserts.
fn expected_triangle_pixel(
    x: u32,
    y: u32,
    size: u32,
    samples: u32,
    tri: &[[f32; 2]; 3],
) -> [f32; 4] {
    let inside = |px: f64, py: f64| {
        let e = |a: [f32; 2], b: [f32; 2]| {
            let (ax, ay, bx, by) = (
                f64::from(a[0]),
                f64::from(a[1]),
                f64::from(b[0]),
                f64::from(b[1]),
            );
            (bx - ax) * (py - ay) - (by - ay) * (px - ax)
        };
        let (e0, e1, e2) = (e(tri[0], tri[1]), e(tri[1], tri[2]), e(tri[2], tri[0]));
        assert!(
            e0 != 0.0 && e1 != 0.0 && e2 != 0.0,
            "sample ({px}, {py}) lies on an edge"
        );
        (e0 > 0.0 && e1 > 0.0 && e2 > 0.0) || (e0 < 0.0 && e1 < 0.0 && e2 < 0.0)
    };
    let positions: &[(f32, f32)] = match samples {
        4 => &[
            (0.375, 0.125),
            (0.875, 0.375),
            (0.125, 0.625),
            (0.625, 0.875),
        ],
        _ => &[(0.5, 0.5)],
    };
    let covered = positions
        .iter()
        .filter(|(ox, oy)| inside(f64::from(x) + f64::from(*ox), f64::from(y) + f64::from(*oy)))
        .count();
    let shade = [
        (x as f32 + 0.5) / size as f32,
        (y as f32 + 0.5) / size as f32,
        0.5,
        1.0,
    ];
    shade.map(|c| (c * 255.0).round() * covered as f32 / positions.len() as f32)
}

#[test]
fn vertex_fragment_pair_msaa1_and_msaa4() {
    let size = 48u32;
    // Pixel-space corners on the 1/16 grid, chosen so no sample lies exactly on an edge.
    let tri = [[3.3125f32, 4.75], [44.3125, 12.125], [17.0625, 43.875]];
    for samples in [1u32, 4] {
        let rgba = gpu_test(|gpu| dsl_kernels::draw_triangle(gpu, size, samples, &tri));
        let mut edge_pixels = 0;
        for y in 0..size {
            for x in 0..size {
                let want = expected_triangle_pixel(x, y, size, samples, &tri);
                let at = ((y * size + x) * 4) as usize;
                let got = &rgba[at..at + 4];
                // Alpha is 1 wherever the triangle is, so resolved alpha is 255·k/samples: the
                // coverage k must match exactly (it proves the standard sample positions).
                let k_got = (f32::from(got[3]) * samples as f32 / 255.0).round();
                let k_want = (want[3] * samples as f32 / 255.0).round();
                assert_eq!(
                    k_got, k_want,
                    "MSAA {samples}, pixel ({x},{y}): covered samples"
                );
                let partial = k_want > 0.0 && k_want < samples as f32;
                edge_pixels += usize::from(partial);
                // One unorm8 step for rounding the shading; on partly covered pixels Vulkan
                // leaves the resolve's rounding to the implementation (NVIDIA rounds up to 1.25
                // steps away from lavapipe), so two steps there.
                let tolerance = if partial { 2.0 } else { 1.0 };
                for c in 0..3 {
                    let g = f32::from(got[c]);
                    assert!(
                        (g - want[c]).abs() <= tolerance,
                        "MSAA {samples}, pixel ({x},{y}) channel {c}: got {g}, want {}",
                        want[c]
                    );
                }
            }
        }
        if samples == 4 {
            assert!(
                edge_pixels > 20,
                "MSAA 4 must produce partially covered edge pixels ({edge_pixels})"
            );
        }
    }
}

#[test]
fn host_structs_with_vec3_round_trip_through_uniform_and_storage() {
    use glam::{Mat4, UVec2, Vec2, Vec3, Vec4};
    use layout_probe::Probe;
    let a = Probe::new(
        Vec3::new(1.5, -2.0, 3.25),
        4.0,
        Vec3::new(5.0, 6.5, -7.0),
        UVec2::new(8, 9),
        Vec2::new(10.0, 11.0),
        Vec4::new(12.0, 13.0, 14.0, 15.0),
        Mat4::from_cols_array(&std::array::from_fn(|i| i as f32 * 0.5)),
        16,
    );
    let b = Probe::new(
        Vec3::splat(-1.0),
        0.25,
        Vec3::Z,
        UVec2::new(1, 2),
        Vec2::ONE,
        Vec4::W,
        Mat4::IDENTITY,
        3,
    );
    let out = gpu_test(|gpu| {
        let u = uniform(gpu, bytemuck::bytes_of(&a));
        let s = storage(
            gpu,
            "probes",
            bytemuck::cast_slice(&[b, a]),
            wgpu::BufferUsages::empty(),
        );
        let o = storage(
            gpu,
            "out",
            &vec![0u8; 3 * size_of::<Probe>()],
            wgpu::BufferUsages::empty(),
        );
        let variant = layout_probe::variant(layout_probe::VariantKey::ALL[0]);
        dispatch(
            gpu,
            variant,
            "copy",
            &[
                u.as_entire_binding(),
                s.as_entire_binding(),
                o.as_entire_binding(),
            ],
            [1, 1, 1],
        );
        readback::read_buffer::<Probe>(gpu.device(), gpu.queue(), &o).expect("readback")
    });
    for (got, want) in out.iter().zip([a, b, a]) {
        assert_eq!(
            (got.a, got.b, got.c, got.d, got.e, got.f, got.g, got.h),
            (
                want.a, want.b, want.c, want.d, want.e, want.f, want.g, want.h
            )
        );
    }
}
