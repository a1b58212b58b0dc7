//! Running one culling kernel on a [`CullScene`]: its depth written sample by sample, its lights
//! (and decal boxes) uploaded, the three dispatches, and the lists read back; and the helpers
//! the culling tests compare lists with.

use glam::UVec2;
use renderer::culling::clustered::{ClusterCullConfig, ClusteredCulling};
use renderer::culling::hierarchy::{CullBox, CullItems, CullSphere, DepthInput};
use renderer::culling::lists::CullReadback;
use renderer::culling::reference::Method;
use renderer::culling::tiled::{TileCullConfig, TiledCulling};
use renderer::decals::OrientedBox;
use renderer::graph::PassEncoder;

use crate::cull_scene::CullScene;
use crate::depth_upload::write_msaa_depth;
use crate::gpu::gpu_test;

/// A GPU culling method and its configuration.
#[derive(Debug, Clone, Copy)]
pub enum GpuMethod {
    Tiled(TileCullConfig),
    Clustered(ClusterCullConfig),
}

/// `(seed, sample count)` for every MSAA count the adapter supports for `Depth32Float`: 1 and 4
/// on lavapipe, 1/2/4/8 on the NVIDIA machines. The variants for the other counts are still
/// validated by naga and spirv-val at build time.
pub fn msaa_cases(seed: u64) -> Vec<(u64, u32)> {
    let counts = gpu_test(|gpu| gpu.capabilities().msaa_depth32float.clone());
    assert!(
        counts.contains(&1) && counts.contains(&4),
        "WebGPU guarantees MSAA 1 and 4: {counts:?}"
    );
    counts
        .into_iter()
        .filter(|c| [1, 2, 4, 8].contains(c))
        .map(|c| (seed + u64::from(c), c))
        .collect()
}

/// The tiled (with `depth_mask`, 2.5D) methods the culling tests cover: tiles of 8, 16 and 32
/// pixels, and transparent lists (blended surfaces) with the 16-pixel tile only, to bound the
/// run time.
pub fn tiled_methods(depth_mask: bool) -> Vec<Method> {
    [(8, false), (16, false), (16, true), (32, false)]
        .into_iter()
        .map(|(tile, transparent)| {
            if depth_mask {
                Method::Depth25 { tile, transparent }
            } else {
                Method::Tiled { tile, transparent }
            }
        })
        .collect()
}

/// The culling box of a world-space oriented box (centre, axes scaled by the half extents).
pub fn cull_box(b: &OrientedBox) -> CullBox {
    CullBox::new(
        b.center.extend(1.0),
        (b.axes[0] * b.half.x).extend(0.0),
        (b.axes[1] * b.half.y).extend(0.0),
        (b.axes[2] * b.half.z).extend(0.0),
    )
}

/// Culls the scene's lights and `boxes` (world space) with `method` and reads the lists back.
pub fn run_with_boxes(s: &CullScene, method: GpuMethod, boxes: &[OrientedBox]) -> CullReadback {
    gpu_test(|gpu| {
        let (w, h) = (s.camera.width, s.camera.height);
        let depth = write_msaa_depth(gpu, w, h, s.depth.samples, &s.depth.depth);
        let view = depth.create_view(&Default::default());
        let spheres: Vec<CullSphere> = s
            .lights
            .iter()
            .map(|l| CullSphere::new(l.center, l.radius))
            .collect();
        let decals: Vec<CullBox> = boxes.iter().map(cull_box).collect();
        let items = CullItems {
            lights: &spheres,
            decals: &decals,
        };
        let mut encoder = gpu.device().create_command_encoder(&Default::default());
        let (cam, d, screen) = (&s.camera, gpu.device(), UVec2::new(w, h));
        let levels = match method {
            GpuMethod::Tiled(config) => {
                let culling = TiledCulling::new(gpu, config, w, h).expect("culling setup");
                culling
                    .upload(gpu, cam.view, cam.projection, screen, items)
                    .expect("upload");
                culling.levels
            }
            GpuMethod::Clustered(config) => {
                let culling = ClusteredCulling::new(gpu, config, w, h).expect("culling setup");
                culling
                    .upload(gpu, cam.view, cam.projection, screen, items)
                    .expect("upload");
                culling.levels
            }
        };
        // A hierarchy built for the compute rasteriser's samples reads the same depths packed
        // as that rasteriser packs them.
        let samples = levels
            .shape
            .vis64
            .then(|| compute_raster_samples(gpu, &s.depth.depth));
        let input = match &samples {
            Some(buffer) => DepthInput::Samples(buffer),
            None => DepthInput::Texture(&view),
        };
        levels
            .encode(d, &mut PassEncoder::untimed(&mut encoder), input, false)
            .expect("the culling buffers bind");
        gpu.queue().submit([encoder.finish()]);
        levels.lists.read_back(gpu).expect("readback")
    })
}

/// `depths` (`(y × w + x) × samples + s`) as the compute rasteriser's buffer holds them: a
/// `u64` a sample, `(!depth_bits << 32) | !id` (ID 1 here), 0 where the depth is 1.0 (sky).
pub fn compute_raster_samples(gpu: &renderer::GpuContext, depths: &[f32]) -> wgpu::Buffer {
    use wgpu::util::DeviceExt as _;
    let words: Vec<u64> = depths
        .iter()
        .map(|&d| {
            if d >= 1.0 {
                0
            } else {
                (u64::from(!d.to_bits()) << 32) | u64::from(!1u32)
            }
        })
        .collect();
    gpu.device()
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("compute raster samples (test)"),
            contents: bytemuck::cast_slice(&words),
            usage: wgpu::BufferUsages::STORAGE,
        })
}

/// Culls the scene's lights with `method` and reads the lists back.
pub fn run_method(s: &CullScene, method: GpuMethod) -> CullReadback {
    run_with_boxes(s, method, &[])
}

/// Items in exactly one of two sorted lists, sorted.
pub fn symmetric_difference(a: &[u32], b: &[u32]) -> Vec<u32> {
    let (mut i, mut j, mut d) = (0, 0, Vec::new());
    while i < a.len() || j < b.len() {
        match (a.get(i), b.get(j)) {
            (Some(x), Some(y)) if x == y => (i, j) = (i + 1, j + 1),
            (Some(x), Some(y)) if x < y => {
                d.push(*x);
                i += 1;
            }
            (Some(_), Some(y)) | (None, Some(y)) => {
                d.push(*y);
                j += 1;
            }
            (Some(x), None) => {
                d.push(*x);
                i += 1;
            }
            (None, None) => break,
        }
    }
    d
}
