//! The particle stage of the particle tests: a floor, a back wall and a pillar, smoke rising in
//! front of the pillar, coloured point lights round it (one casting a shadow) and a dim
//! directional light, seen from a fixed camera.

use glam::{Vec3, Vec4};
use renderer::demo::procedural_lights;
use renderer::frame::FrameCamera;
use renderer::particles::{ParticleSystem, smoke};
use renderer::scene::procedural::SceneBuilder;
use renderer::scene::{LightKind, Scene, SceneLight};

/// The frame size the camera's aspect is made for.
pub const WIDTH: u32 = 160;
pub const HEIGHT: u32 = 120;

/// A floor, a back wall and a pillar; smoke rising in front of the pillar.
pub fn stage() -> Scene {
    let mut b = SceneBuilder::new();
    let stone = b.material("stone", Vec3::new(0.6, 0.58, 0.55), 0.8);
    let wall = b.material("wall", Vec3::new(0.5, 0.52, 0.6), 0.7);
    b.cuboid(Vec3::new(-3.0, -0.1, -3.0), Vec3::new(3.0, 0.0, 3.0), stone)
        .cuboid(Vec3::new(-3.0, 0.0, -3.0), Vec3::new(3.0, 3.0, -2.8), wall)
        .cuboid(Vec3::new(0.6, 0.0, -1.2), Vec3::new(1.0, 2.5, -0.8), wall);
    b.build()
}

/// Coloured point lights round the smoke (one casting a shadow) and a dim directional light.
pub fn lights(scene: &Scene) -> Vec<SceneLight> {
    let mut lights = procedural_lights(scene.bounds, 24, 7, 1.5, 3.5);
    lights.push(SceneLight {
        kind: LightKind::Point,
        position: Vec3::new(-0.8, 1.2, 0.6),
        direction: Vec3::NEG_Z,
        color: Vec3::new(1.0, 0.6, 0.3),
        intensity: 3.0,
        range: Some(4.0),
        casts_shadow: true,
    });
    lights.push(SceneLight {
        kind: LightKind::Directional,
        position: Vec3::ZERO,
        direction: Vec3::new(-0.3, -1.0, -0.4).normalize(),
        color: Vec3::new(0.6, 0.7, 1.0),
        intensity: 0.4,
        range: None,
        casts_shadow: false,
    });
    lights
}

pub fn particles() -> ParticleSystem {
    let mut plume = smoke(Vec3::new(0.0, 0.0, 0.0), 40.0);
    plume.color = [
        Vec4::new(0.8, 0.8, 0.8, 0.6),
        Vec4::new(0.9, 0.9, 0.95, 0.0),
    ];
    ParticleSystem {
        emitters: vec![plume],
        capacity: 512,
        seed: 11,
    }
}

pub fn camera() -> FrameCamera {
    FrameCamera::look_at(
        Vec3::new(0.0, 1.4, 4.0),
        Vec3::new(0.0, 1.1, 0.0),
        Vec3::Y,
        50f32.to_radians(),
        WIDTH as f32 / HEIGHT as f32,
        (0.1, 30.0),
    )
}

/// Simulation steps before the frame: smoke has risen and spread.
pub const WARMUP: u32 = 150;
