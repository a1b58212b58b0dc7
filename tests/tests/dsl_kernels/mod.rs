//! DSL modules for the GPU execution tests, and the draw helpers that run them.

pub mod bindings;

use renderer::shader::ShaderProgram;
use renderer::{GpuContext, readback};
use wgpu::util::DeviceExt as _;

/// Inclusive prefix sum of each 256-element block, Hillis–Steele in workgroup memory.
#[shader_dsl::shader]
pub mod prefix_sum {
    pub const BLOCK: u32 = 256;

    #[storage(group = 0, binding = 0)]
    static INPUT: [u32];
    #[storage(group = 0, binding = 1, read_write)]
    static OUTPUT: [u32];
    #[workgroup]
    static SCRATCH: [u32; BLOCK];

    #[compute(workgroup_size(256, 1, 1))]
    pub fn scan(#[builtin(local_invocation_index)] lid: u32, #[builtin(workgroup_id)] wg: UVec3) {
        let base = wg.x * BLOCK;
        SCRATCH[lid] = INPUT[base + lid];
        workgroup_barrier();
        let mut offset = 1u32;
        while offset < BLOCK {
            let mut v = SCRATCH[lid];
            if lid >= offset {
                v += SCRATCH[lid - offset];
            }
            workgroup_barrier();
            SCRATCH[lid] = v;
            workgroup_barrier();
            offset *= 2u32;
        }
        OUTPUT[base + lid] = SCRATCH[lid];
    }
}

/// Per 8×8 tile: min and max depth over every sample of a 4× multisampled depth texture, as f32
/// bits reduced with workgroup atomics (order-preserving for non-negative floats).
#[shader_dsl::shader]
pub mod depth_bounds {
    const INFINITY_BITS: u32 = 0x7f80_0000;

    #[texture(group = 0, binding = 0)]
    static DEPTH: TextureDepthMultisampled2d;
    #[storage(group = 0, binding = 1, read_write)]
    static BOUNDS: [UVec2];
    #[workgroup]
    static WG_MIN: Atomic<u32>;
    #[workgroup]
    static WG_MAX: Atomic<u32>;

    #[compute(workgroup_size(8, 8, 1))]
    pub fn reduce(
        #[builtin(global_invocation_id)] gid: UVec3,
        #[builtin(local_invocation_index)] lid: u32,
        #[builtin(workgroup_id)] wg: UVec3,
        #[builtin(num_workgroups)] groups: UVec3,
    ) {
        if lid == 0u32 {
            WG_MIN.store(INFINITY_BITS);
            WG_MAX.store(0u32);
        }
        workgroup_barrier();
        let size = DEPTH.dimensions();
        if gid.x < size.x && gid.y < size.y {
            for s in 0u32..4u32 {
                let bits = DEPTH.load(gid.xy(), s).to_bits();
                WG_MIN.fetch_min(bits);
                WG_MAX.fetch_max(bits);
            }
        }
        workgroup_barrier();
        if lid == 0u32 {
            BOUNDS[wg.y * groups.x + wg.x] = UVec2::new(WG_MIN.load(), WG_MAX.load());
        }
    }
}

/// Stream compaction of the values at or above a threshold. The scalarized variant appends with
/// one atomic per subgroup (ballot for the count, exclusive add for each lane's slot); the plain
/// one with one atomic per element.
#[shader_dsl::shader(axes(scalarize: bool = [false, true] => "scalar"), requires(subgroup = scalarize))]
pub mod compaction {
    pub const WORKGROUP: u32 = 64;

    pub struct Params {
        pub count: u32,
        pub threshold: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static PARAMS: Params;
    #[storage(group = 0, binding = 1)]
    static INPUT: [u32];
    #[storage(group = 0, binding = 2, read_write)]
    static OUTPUT: [u32];
    #[storage(group = 0, binding = 3, read_write)]
    static COUNTER: Atomic<u32>;

    #[compute(workgroup_size(64, 1, 1))]
    pub fn compact(
        #[builtin(global_invocation_id)] gid: UVec3,
        #[builtin(subgroup_invocation_id)] lane: u32,
    ) {
        let i = gid.x;
        let mut keep = false;
        let mut value = 0u32;
        if i < PARAMS.count {
            value = INPUT[i];
            keep = value >= PARAMS.threshold;
        }
        if scalarize {
            let ballot = subgroup_ballot(keep);
            let total = ballot.x.count_ones()
                + ballot.y.count_ones()
                + ballot.z.count_ones()
                + ballot.w.count_ones();
            let slot_in_subgroup = subgroup_exclusive_add(select(keep, 1u32, 0u32));
            let mut base = 0u32;
            if lane == 0u32 {
                base = COUNTER.fetch_add(total);
            }
            base = subgroup_broadcast_first(base);
            if keep {
                OUTPUT[base + slot_in_subgroup] = value;
            }
        } else {
            if keep {
                let slot = COUNTER.fetch_add(1u32);
                OUTPUT[slot] = value;
            }
        }
    }
}

/// One triangle, shaded by pixel position, for the MSAA coverage test.
#[shader_dsl::shader]
pub mod triangle {
    pub struct Corners {
        pub ndc: Mat3,
        pub size: Vec2,
    }

    pub struct VsOut {
        #[builtin(position)]
        pub position: Vec4,
    }

    pub struct FsOut {
        #[location(0)]
        pub color: Vec4,
    }

    #[uniform(group = 0, binding = 0)]
    static CORNERS: Corners;

    #[vertex]
    pub fn vs(#[builtin(vertex_index)] vi: u32) -> VsOut {
        let c = CORNERS.ndc[vi];
        VsOut {
            position: Vec4::new(c.x, c.y, 0.0, 1.0),
        }
    }

    #[fragment]
    pub fn fs(#[builtin(position)] position: Vec4) -> FsOut {
        let uv = position.xy() / CORNERS.size;
        FsOut {
            color: Vec4::new(uv.x, uv.y, 0.5, 1.0),
        }
    }
}

/// Copies a uniform struct and two storage structs into an output array, field by field as a
/// whole-struct assignment, to prove host and WGSL layouts agree (vec3 fields included).
#[shader_dsl::shader]
pub mod layout_probe {
    pub struct Probe {
        pub a: Vec3,
        pub b: f32,
        pub c: Vec3,
        pub d: UVec2,
        pub e: Vec2,
        pub f: Vec4,
        pub g: Mat4,
        pub h: u32,
    }

    #[uniform(group = 0, binding = 0)]
    static UNIFORM_PROBE: Probe;
    #[storage(group = 0, binding = 1)]
    static STORAGE_PROBES: [Probe];
    #[storage(group = 0, binding = 2, read_write)]
    static OUT: [Probe];

    #[compute(workgroup_size(1, 1, 1))]
    pub fn copy() {
        OUT[0] = UNIFORM_PROBE;
        OUT[1] = STORAGE_PROBES[0];
        OUT[2] = STORAGE_PROBES[1];
    }
}

fn program(gpu: &GpuContext, variant: &'static codegen::rt::Variant) -> ShaderProgram {
    ShaderProgram::new(gpu.device(), gpu.capabilities(), variant).expect("supported variant")
}

pub use tests::depth_upload::write_msaa_depth;

/// Draws the triangle with pixel-space corners `tri` into a `size`² Rgba8Unorm target with
/// `samples`× MSAA (resolved), and reads it back.
pub fn draw_triangle(gpu: &GpuContext, size: u32, samples: u32, tri: &[[f32; 2]; 3]) -> Vec<u8> {
    let device = gpu.device();
    let p = program(gpu, triangle::variant(triangle::VariantKey::ALL[0]));
    // WGSL mat3x3 columns are 16 bytes apart; the host type stores them as Vec4s.
    let ndc = |c: [f32; 2]| {
        glam::Vec4::new(
            2.0 * c[0] / size as f32 - 1.0,
            1.0 - 2.0 * c[1] / size as f32,
            0.0,
            0.0,
        )
    };
    let corners = triangle::Corners::new(
        [ndc(tri[0]), ndc(tri[1]), ndc(tri[2])],
        glam::Vec2::splat(size as f32),
    );
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("corners"),
        contents: bytemuck::bytes_of(&corners),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &p.bind_group_layouts[0],
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: params.as_entire_binding(),
        }],
    });
    let format = wgpu::TextureFormat::Rgba8Unorm;
    let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("triangle"),
        layout: Some(&p.pipeline_layout),
        vertex: wgpu::VertexState {
            module: &p.module,
            entry_point: Some("vs"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState {
            count: samples,
            ..Default::default()
        },
        fragment: Some(wgpu::FragmentState {
            module: &p.module,
            entry_point: Some("fs"),
            compilation_options: Default::default(),
            targets: &[Some(format.into())],
        }),
        multiview_mask: None,
        cache: None,
    });
    let texture = |samples: u32, usage| {
        device.create_texture(&wgpu::TextureDescriptor {
            label: Some("triangle target"),
            size: wgpu::Extent3d {
                width: size,
                height: size,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: samples,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage,
            view_formats: &[],
        })
    };
    let resolved = texture(
        1,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
    );
    let msaa = (samples > 1).then(|| texture(samples, wgpu::TextureUsages::RENDER_ATTACHMENT));
    let resolved_view = resolved.create_view(&Default::default());
    let msaa_view = msaa.as_ref().map(|t| t.create_view(&Default::default()));
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("triangle"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: msaa_view.as_ref().unwrap_or(&resolved_view),
                depth_slice: None,
                resolve_target: msaa_view.as_ref().map(|_| &resolved_view),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.draw(0..3, 0..1);
    }
    gpu.queue().submit([encoder.finish()]);
    readback::read_texture_rgba8(device, gpu.queue(), &resolved).expect("readback")
}
