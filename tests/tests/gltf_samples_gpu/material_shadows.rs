//! Alpha-masked shadow casters cut out in the shadow atlas: a horizontal quad whose base colour
//! texture is transparent on its −X half (read through `TEXCOORD_1` and a transform) hangs over
//! a floor under a slanted directional light. The floor under the hole is lit, under the solid
//! half shadowed; the same quad made opaque shadows both.

use glam::{Vec2, Vec3, Vec4};
use renderer::frame::{FrameCamera, RenderPath};
use renderer::scene::procedural::SceneBuilder;
use renderer::scene::{
    AlphaMode, Filter, Image, LightKind, Material, SceneLight, TextureRef, TextureSampler,
    UvTransform, Wrap,
};
use tests::frames::render_frame_from;
use tests::gpu::gpu_test;

use super::quads::{Quad, add_quad, config, pixel, rgb};

/// Luminances at the floor under the hole, under the solid half, and beside the shadow.
fn floor_luminances(path: RenderPath, masked: bool, gpu: &renderer::GpuContext) -> [i32; 3] {
    let mut b = SceneBuilder::new();
    let floor = b.material("floor", Vec3::splat(0.8), 1.0);
    b.cuboid(Vec3::new(-4.0, 0.0, -4.0), Vec3::new(7.0, 0.0, 4.0), floor);
    // Alpha 0 then 1 along u; the quad's TEXCOORD_1 runs over u ∈ [0, 0.5], scaled by 2.
    let image = b.image(Image {
        width: 2,
        height: 1,
        rgba8: vec![255, 255, 255, 0, 255, 255, 255, 255],
    });
    let quad_material = b.add_material(Material {
        base_color: Vec4::ONE,
        base_color_texture: Some(TextureRef {
            tex_coord: 1,
            sampler: TextureSampler {
                wrap_u: Wrap::ClampToEdge,
                wrap_v: Wrap::ClampToEdge,
                mag_filter: Filter::Nearest,
                min_filter: Filter::Nearest,
                mipmap_filter: None,
            },
            transform: UvTransform {
                scale: Vec2::new(2.0, 1.0),
                ..UvTransform::IDENTITY
            },
            ..TextureRef::new(image)
        }),
        alpha_mode: if masked {
            AlphaMode::Mask { cutoff: 0.5 }
        } else {
            AlphaMode::Opaque
        },
        double_sided: true,
        ..Material::gltf_default()
    });
    let mut scene = b.build();
    add_quad(
        &mut scene,
        &Quad {
            min: Vec3::new(-1.0, 1.0, -1.0),
            max: Vec3::new(1.0, 1.0, 1.0),
            uv0: |_| Vec2::new(0.9, 0.5),
            uv1: Some(|st| Vec2::new(st.x * 0.5, st.y)),
            color: None,
            material: quad_material,
        },
    );
    // Travelling +X 2 per 1 down: the quad's shadow falls on x ∈ [1, 3], the hole's on [1, 2].
    let light = SceneLight {
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: Vec3::new(2.0, -1.0, 0.0).normalize(),
        color: Vec3::ONE,
        intensity: 3.0,
        range: None,
        casts_shadow: true,
    };
    let camera = FrameCamera::look_at(
        Vec3::new(2.0, 6.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::NEG_Z,
        70f32.to_radians(),
        super::quads::W as f32 / super::quads::H as f32,
        (0.1, 20.0),
    );
    let frame = render_frame_from(gpu, &scene, config(path), &[light], &camera);
    if let Some(dir) = std::env::var_os("MATERIAL_INPUTS_DUMP") {
        let name = format!("masked_caster_{masked}_{}.png", path.name());
        let (w, h) = (super::quads::W, super::quads::H);
        image::save_buffer(
            std::path::Path::new(&dir).join(name),
            &frame.rgba,
            w,
            h,
            image::ColorType::Rgba8,
        )
        .expect("png");
    }
    [
        Vec3::new(1.5, 0.0, 0.0),
        Vec3::new(2.5, 0.0, 0.0),
        Vec3::new(1.5, 0.0, 2.5),
    ]
    .map(|p| {
        let [r, g, b] = rgb(&frame.rgba, pixel(&camera, p));
        (r * 3 + g * 6 + b) / 10
    })
}

#[test]
fn masked_casters_cut_out_in_the_shadow_atlas() {
    gpu_test(|gpu| {
        for path in [RenderPath::NaivePrez, RenderPath::Tbdr] {
            let [hole, solid, lit] = floor_luminances(path, true, gpu);
            let name = path.name();
            assert!(lit > 60, "{name}: the unshadowed floor is dark ({lit})");
            assert!(
                hole * 10 > lit * 8,
                "{name}: the floor under the hole ({hole}) is not lit like beside it ({lit})"
            );
            assert!(
                solid * 10 < lit * 3,
                "{name}: under the solid half {solid}, lit {lit}"
            );
            let [hole, solid, lit] = floor_luminances(path, false, gpu);
            assert!(
                hole * 10 < lit * 3 && solid * 10 < lit * 3,
                "{name}: opaque: under the hole {hole}, solid {solid}, lit {lit}"
            );
        }
    });
}
