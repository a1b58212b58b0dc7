//! The scene of the forward-shading tests: a camera over a 4×4 quad, its punctual and
//! directional lights and material, the clustered grid, and the inputs of a forward draw.

use glam::camera::rh;
use glam::{Mat4, UVec2, Vec3, Vec4, Vec4Swizzles as _};
use shaders_gen::forward::forward;
use shaders_gen::shared::material_table::NO_TEXTURE;

use crate::forward_kernels::ForwardInputs;
use crate::forward_reference::{Light, Surface};

pub const SIZE: u32 = 64;

pub const SURFACE: Surface = Surface {
    albedo: Vec3::new(0.8, 0.6, 0.4),
    metallic: 0.3,
    roughness: 0.5,
    emissive: Vec3::new(0.05, 0.0, 0.0),
    ambient: Vec3::splat(0.02),
};

fn punctual_lights() -> Vec<Light> {
    let point = |position: Vec3, range: f32, color: Vec3, intensity: f32| Light {
        kind: 0,
        position,
        direction: Vec3::NEG_Z,
        color,
        intensity,
        range,
        cos_inner: 1.0,
        cos_outer: 1.0,
    };
    vec![
        point(Vec3::new(0.5, 0.3, 1.0), 4.0, Vec3::new(1.0, 0.9, 0.8), 2.0),
        // Infinite range: pure inverse square.
        point(
            Vec3::new(-0.7, -0.4, 0.6),
            0.0,
            Vec3::new(0.3, 0.5, 1.0),
            0.5,
        ),
        // Range 1.2 at height 0.4: the smooth window fades it out across the image.
        point(
            Vec3::new(-0.5, 0.6, 0.4),
            1.2,
            Vec3::new(0.2, 1.0, 0.3),
            1.0,
        ),
        // Behind the quad: contributes nothing.
        point(Vec3::new(0.0, 0.0, -0.5), 0.0, Vec3::ONE, 5.0),
        Light {
            kind: 1,
            position: Vec3::new(0.2, -0.2, 2.0),
            direction: Vec3::new(0.1, 0.0, -1.0).normalize(),
            color: Vec3::new(1.0, 0.8, 0.6),
            intensity: 6.0,
            range: 5.0,
            cos_inner: 15f32.to_radians().cos(),
            cos_outer: 30f32.to_radians().cos(),
        },
    ]
}

fn directional_lights() -> Vec<Light> {
    vec![Light {
        kind: 2,
        position: Vec3::ZERO,
        direction: Vec3::new(-0.3, -0.5, -1.0).normalize(),
        color: Vec3::new(0.9, 0.9, 1.0),
        intensity: 0.8,
        range: 0.0,
        cos_inner: 1.0,
        cos_outer: 1.0,
    }]
}

pub struct Scene {
    pub view: Mat4,
    pub projection: Mat4,
    pub eye: Vec3,
    pub lights: Vec<Light>,
    pub directional: Vec<Light>,
}

pub fn scene() -> Scene {
    let eye = Vec3::new(0.0, 0.0, 3.0);
    Scene {
        view: rh::view::look_at_mat4(eye, Vec3::ZERO, Vec3::Y),
        projection: rh::proj::directx::perspective(60f32.to_radians(), 1.0, 0.1, 100.0),
        eye,
        lights: punctual_lights(),
        directional: directional_lights(),
    }
}

/// A 4×4 quad in the z = 0 plane facing +Z (covers the whole view).
pub fn quad() -> Vec<[f32; 12]> {
    let v = |x: f32, y: f32| {
        [
            x,
            y,
            0.0,
            0.0,
            0.0,
            1.0,
            (x + 2.0) / 4.0,
            (2.0 - y) / 4.0,
            1.0,
            0.0,
            0.0,
            1.0,
        ]
    };
    vec![
        v(-2.0, -2.0),
        v(2.0, -2.0),
        v(2.0, 2.0),
        v(-2.0, -2.0),
        v(2.0, 2.0),
        v(-2.0, 2.0),
    ]
}

/// Clustered grid of the tests (the tiles × `SLICES` depth slices), with `near`/`far` as
/// `cluster_cull` takes them.
pub const SLICES: u32 = 8;
pub const TILE: u32 = 16;
/// Tiles across (and down: the target is square).
const TILES_X: u32 = SIZE.div_ceil(TILE);
/// Grid entries of the clustered lists.
pub const FROXELS: u32 = TILES_X * TILES_X * SLICES;

/// The clustered grid entry of pixel `(x, y)` in slice `k`.
pub fn froxel(x: u32, y: u32, k: u32) -> u32 {
    k * TILES_X * TILES_X + (y / TILE) * TILES_X + x / TILE
}
pub const NEAR: f32 = 0.5;
pub const FAR: f32 = 50.0;

pub fn inputs<'a>(
    s: &Scene,
    lights: &'a [forward::GpuLight],
    directional: &'a [forward::GpuLight],
    grid: &'a [UVec2],
    indices: &'a [u32],
    vertices: &'a [[f32; 12]],
) -> ForwardInputs<'a> {
    let tiles = UVec2::splat(SIZE.div_ceil(TILE));
    // Every texture read through TEXCOORD_0 as it is: no KHR_texture_transform.
    let identity_uv = forward::UvMap::new(Vec3::X, 0, Vec3::Y);
    ForwardInputs {
        size: SIZE,
        camera: forward::Camera::new(
            s.view,
            s.projection,
            s.projection * s.view,
            s.eye,
            s.eye.extend(1.0),
        ),
        lighting: forward::Lighting::new(
            SURFACE.ambient,
            lights.len() as u32,
            // A uniform ambient (sky = ground): the reference's `ambient · albedo`.
            SURFACE.ambient,
            tiles,
            TILE,
            SLICES,
            0,
            NEAR,
            FAR,
            directional.len() as u32,
            0,
            0,
        ),
        lights,
        directional,
        grid,
        indices,
        draw: forward::Draw::new(Mat4::IDENTITY, Mat4::IDENTITY, 0, 1.0),
        material: forward::GpuMaterial::new(
            SURFACE.albedo.extend(1.0),
            SURFACE.emissive,
            SURFACE.metallic,
            SURFACE.roughness,
            1.0,
            1.0,
            0.5,
            identity_uv,
            identity_uv,
            identity_uv,
            identity_uv,
            identity_uv,
            NO_TEXTURE,
            NO_TEXTURE,
            NO_TEXTURE,
            NO_TEXTURE,
            NO_TEXTURE,
            0,
            0,
            // glTF PBR's program.
            0,
        ),
        vertices,
    }
}

/// The world point of the quad (z = 0) seen at the centre of pixel (x, y).
pub fn quad_point(s: &Scene, x: u32, y: u32) -> Vec3 {
    let ndc = Vec4::new(
        2.0 * (x as f32 + 0.5) / SIZE as f32 - 1.0,
        1.0 - 2.0 * (y as f32 + 0.5) / SIZE as f32,
        0.5,
        1.0,
    );
    let inv = (s.projection * s.view).inverse();
    let far = inv * ndc;
    let dir = far.xyz() / far.w - s.eye;
    s.eye + dir * (-s.eye.z / dir.z)
}

pub fn key(list: forward::List, scalarize: bool) -> forward::VariantKey {
    forward::VariantKey {
        list,
        blend: false,
        scalarize,
        msaa: forward::Msaa::Msaa0,
        vis64: false,
    }
}
