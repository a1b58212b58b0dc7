//! The shadow tests' scene: a floor, a box and a pillar, lit by one spot, one point or one
//! directional light, seen from above; and an independent CPU ray cast that says which floor
//! points each light reaches.

use glam::Vec3;
use renderer::frame::FrameCamera;
use renderer::scene::procedural::SceneBuilder;
use renderer::scene::{Aabb, LightKind, Scene, SceneLight};

/// Top of the floor slab.
pub const FLOOR_Y: f32 = 0.0;
/// Half the floor's side.
pub const FLOOR_HALF: f32 = 6.0;

/// The occluders, in world space: the box and the pillar.
pub fn occluders() -> [Aabb; 2] {
    [
        Aabb {
            min: Vec3::new(-2.0, 0.0, -1.0),
            max: Vec3::new(-0.5, 1.2, 0.5),
        },
        Aabb {
            min: Vec3::new(1.5, 0.0, 0.5),
            max: Vec3::new(2.1, 3.0, 1.1),
        },
    ]
}

/// The floor, the box and the pillar (instances 0, 1 and 2).
pub fn scene() -> Scene {
    let mut b = SceneBuilder::new();
    let grey = b.material("floor", Vec3::splat(0.6), 0.9);
    let white = b.material("occluder", Vec3::splat(0.8), 0.6);
    b.cuboid(
        Vec3::new(-FLOOR_HALF, -0.2, -FLOOR_HALF),
        Vec3::new(FLOOR_HALF, FLOOR_Y, FLOOR_HALF),
        grey,
    );
    for o in occluders() {
        b.cuboid(o.min, o.max, white);
    }
    b.build()
}

/// The three test lights: a spot, a point and a directional light, each casting a shadow.
pub fn lights() -> [SceneLight; 3] {
    let spot_at = Vec3::new(-3.5, 4.0, 2.5);
    [
        SceneLight {
            kind: LightKind::Spot {
                inner_cone: 0.6,
                outer_cone: 0.9,
            },
            position: spot_at,
            direction: (Vec3::new(-0.5, 0.0, 0.0) - spot_at).normalize(),
            color: Vec3::ONE,
            intensity: 60.0,
            range: Some(14.0),
            casts_shadow: true,
        },
        SceneLight {
            kind: LightKind::Point,
            position: Vec3::new(0.6, 2.2, -0.4),
            direction: Vec3::NEG_Y,
            color: Vec3::ONE,
            intensity: 12.0,
            range: Some(12.0),
            casts_shadow: true,
        },
        SceneLight {
            kind: LightKind::Directional,
            position: Vec3::ZERO,
            direction: Vec3::new(0.45, -1.0, 0.3).normalize(),
            color: Vec3::ONE,
            intensity: 3.0,
            range: None,
            casts_shadow: true,
        },
    ]
}

/// The camera looking down at the floor from above and to the side.
pub fn camera(aspect: f32) -> FrameCamera {
    let eye = Vec3::new(0.0, 9.0, 7.0);
    FrameCamera::look_at(
        eye,
        Vec3::ZERO,
        Vec3::Y,
        45f32.to_radians(),
        aspect,
        (0.1, 60.0),
    )
}

/// Whether the segment from `a` to `b` passes through `boxes` (slab test).
pub fn segment_blocked(a: Vec3, b: Vec3, boxes: &[Aabb]) -> bool {
    let d = b - a;
    boxes.iter().any(|bx| {
        let (mut t0, mut t1) = (1.0e-4_f32, 1.0_f32 - 1.0e-4);
        for axis in 0..3 {
            let (o, v) = (a[axis], d[axis]);
            if v.abs() < 1.0e-9 {
                if o < bx.min[axis] || o > bx.max[axis] {
                    return false;
                }
                continue;
            }
            let (mut n, mut f) = ((bx.min[axis] - o) / v, (bx.max[axis] - o) / v);
            if n > f {
                std::mem::swap(&mut n, &mut f);
            }
            t0 = t0.max(n);
            t1 = t1.min(f);
            if t0 > t1 {
                return false;
            }
        }
        true
    })
}

/// Whether `light` reaches floor point `p` unblocked by the occluders.
pub fn reaches(light: &SceneLight, p: Vec3) -> bool {
    let from = match light.kind {
        LightKind::Directional => p - light.direction * 100.0,
        _ => light.position,
    };
    !segment_blocked(p, from, &occluders())
}

/// The floor point seen through pixel `(x, y)` of a `w`×`h` frame, if the camera sees the
/// floor's top there without an occluder in front.
pub fn floor_point(camera: &FrameCamera, x: u32, y: u32, w: u32, h: u32) -> Option<Vec3> {
    let ndc = glam::Vec2::new(
        (x as f32 + 0.5) / w as f32 * 2.0 - 1.0,
        1.0 - (y as f32 + 0.5) / h as f32 * 2.0,
    );
    let inv = (camera.projection * camera.view).inverse();
    let far = inv.project_point3(ndc.extend(0.5));
    let dir = (far - camera.eye).normalize();
    if dir.y >= -1.0e-6 {
        return None;
    }
    let t = (FLOOR_Y - camera.eye.y) / dir.y;
    let p = camera.eye + dir * t;
    let on_floor = p.x.abs() < FLOOR_HALF && p.z.abs() < FLOOR_HALF;
    (on_floor && !segment_blocked(camera.eye, p, &occluders())).then_some(p)
}

/// An 8-bit sRGB value as linear intensity.
pub fn srgb_to_linear(c: u8) -> f32 {
    let c = f32::from(c) / 255.0;
    if c <= 0.040_45 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear luminance (Rec. 709 weights) of pixel `i` of an sRGB RGBA8 image. The frame is
/// tonemapped (ACES) before the sRGB encoding, so this is linear in the tonemapped value only:
/// 0 stays 0 and fully lit stays fully lit, which is all the lit/unlit comparison needs.
pub fn luminance(rgba: &[u8], i: usize) -> f32 {
    let p = &rgba[i * 4..i * 4 + 3];
    0.2126 * srgb_to_linear(p[0]) + 0.7152 * srgb_to_linear(p[1]) + 0.0722 * srgb_to_linear(p[2])
}

/// Per pixel of a `w`×`h` frame: the floor point seen there and whether `light` reaches it,
/// or `None` where the camera does not see the floor.
pub fn reference_map(
    camera: &FrameCamera,
    light: &SceneLight,
    w: u32,
    h: u32,
) -> Vec<Option<(Vec3, bool)>> {
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| floor_point(camera, x, y, w, h).map(|p| (p, reaches(light, p))))
        .collect()
}

/// One floor pixel that took part in a comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Checked {
    pub x: u32,
    pub y: u32,
    /// The floor point seen through the pixel's centre.
    pub p: Vec3,
    /// The CPU ray cast's verdict.
    pub reference_lit: bool,
    /// Shadowed over unshadowed luminance.
    pub visibility: f32,
}

impl Checked {
    /// Reference lit but visibility below ½ (a false shadow), or reference unlit but
    /// visibility above ½ (a leak).
    pub fn disagrees(&self) -> bool {
        if self.reference_lit {
            self.visibility < 0.5
        } else {
            self.visibility > 0.5
        }
    }

    /// Reference unlit and visibility above ½.
    pub fn leaks(&self) -> bool {
        !self.reference_lit && self.visibility > 0.5
    }
}

/// A frame's shadows compared with the CPU ray cast, pixel by pixel.
#[derive(Debug, Clone, Default)]
pub struct Comparison {
    /// Floor pixels compared.
    pub checked: Vec<Checked>,
    /// Floor pixels left out because they lie within the band of a reference shadow edge.
    pub in_band: usize,
    /// Floor pixels left out because the light hardly reaches them even unshadowed.
    pub dark: usize,
}

impl Comparison {
    /// Compared pixels the reference says are lit.
    pub fn lit(&self) -> usize {
        self.checked.iter().filter(|c| c.reference_lit).count()
    }

    /// Compared pixels the reference says are shadowed.
    pub fn shadowed(&self) -> usize {
        self.checked.iter().filter(|c| !c.reference_lit).count()
    }

    pub fn disagreements(&self) -> Vec<Checked> {
        self.checked
            .iter()
            .copied()
            .filter(Checked::disagrees)
            .collect()
    }
}

/// Smallest unshadowed luminance a compared pixel needs: 8/255 before the sRGB encoding.
pub fn min_unshadowed_luminance() -> f32 {
    srgb_to_linear(8)
}

/// Compares `shadowed` (the frame with `light` casting its shadow) and `unshadowed` (the same
/// frame with `casts_shadow = false`), both `w`×`h` sRGB RGBA8 frames seen through `camera`
/// with `light` alone and no ambient light, against the CPU ray cast.
///
/// Per floor pixel, visibility is shadowed over unshadowed [`luminance`]; pixels whose
/// unshadowed luminance is at most [`min_unshadowed_luminance`] are left out (`dark`), and so
/// are pixels within `band` pixels (Chebyshev distance) of a floor pixel the reference judges
/// the other way (`in_band`): the shadow edge, where filtering and the rasteriser's sampling
/// legitimately differ from a ray through the pixel's centre.
pub fn compare_with_ray_cast(
    camera: &FrameCamera,
    light: &SceneLight,
    shadowed: &[u8],
    unshadowed: &[u8],
    (w, h): (u32, u32),
    band: u32,
) -> Comparison {
    let reference = reference_map(camera, light, w, h);
    let at = |x: u32, y: u32| reference[(y * w + x) as usize];
    let mut out = Comparison::default();
    for y in 0..h {
        for x in 0..w {
            let Some((p, lit)) = at(x, y) else {
                continue;
            };
            let i = (y * w + x) as usize;
            let unshadowed = luminance(unshadowed, i);
            if unshadowed <= min_unshadowed_luminance() {
                out.dark += 1;
                continue;
            }
            let (x0, x1) = (x.saturating_sub(band), (x + band).min(w - 1));
            let (y0, y1) = (y.saturating_sub(band), (y + band).min(h - 1));
            let near_edge = (y0..=y1)
                .any(|v| (x0..=x1).any(|u| at(u, v).is_some_and(|(_, other)| other != lit)));
            if near_edge {
                out.in_band += 1;
                continue;
            }
            out.checked.push(Checked {
                x,
                y,
                p,
                reference_lit: lit,
                visibility: luminance(shadowed, i) / unshadowed,
            });
        }
    }
    out
}

/// Asserts that no compared pixel disagrees and that enough pixels of each kind were compared.
/// Disagreements of a point light list how close each lies to a cube face edge
/// ([`cube_edge_closeness`], 0 on the edge).
pub fn assert_agrees(name: &str, light: &SceneLight, cmp: &Comparison) {
    let bad: Vec<String> = cmp
        .disagreements()
        .iter()
        .map(|c| {
            let seam =
                (light.kind == LightKind::Point).then(|| cube_edge_closeness(c.p - light.position));
            format!(
                "({}, {}) at {:.3} reference {} visibility {:.2}{}",
                c.x,
                c.y,
                c.p,
                if c.reference_lit { "lit" } else { "unlit" },
                c.visibility,
                seam.map_or(String::new(), |s| format!(" face-edge closeness {s:.4}"))
            )
        })
        .collect();
    assert!(
        bad.is_empty(),
        "{name}: {} pixels disagree with the ray cast:\n{}",
        bad.len(),
        bad.join("\n")
    );
    assert!(
        cmp.lit() > 300 && cmp.shadowed() > 300,
        "{name}: too few pixels compared ({} lit, {} shadowed)",
        cmp.lit(),
        cmp.shadowed()
    );
}

/// How close direction `d` (from a point light) lies to an edge of its cube face: the major
/// axis's magnitude minus the second largest, over the major's. 0 on a face edge (and at a
/// corner), 1 on a face's axis.
pub fn cube_edge_closeness(d: Vec3) -> f32 {
    let mut a = d.abs().to_array();
    a.sort_by(|x, y| y.total_cmp(x));
    (a[0] - a[1]) / a[0].max(f32::MIN_POSITIVE)
}

/// Whether direction `d` lies near a cube corner: all three magnitudes within `closeness` of
/// the major one (relative).
pub fn near_cube_corner(d: Vec3, closeness: f32) -> bool {
    let a = d.abs();
    let major = a.max_element();
    a.min_element() >= major * (1.0 - closeness)
}

/// A point light placed for the cube-seam test, 3 above the floor at `(0.5, 1.5)`: the corner
/// of its −Y face with the −X and −Z faces meets the floor at `(−2.5, 0, −1.5)`, deep in the
/// box's shadow, and the −X/−Z face edge runs from there along the middle of that shadow (the
/// box lies on the light's diagonal); the +X/−Y edge (`x = 3.5`) crosses the pillar's shadow,
/// which reaches the floor's border since the pillar is as tall as the light is high.
pub fn seam_light() -> SceneLight {
    SceneLight {
        kind: LightKind::Point,
        position: Vec3::new(0.5, 3.0, 1.5),
        direction: Vec3::NEG_Y,
        color: Vec3::ONE,
        intensity: 12.0,
        range: Some(12.0),
        casts_shadow: true,
    }
}

/// Whether `light` can reach world box `b` through the view `clip_from_world` (reversed-Z
/// clip volume `−w ≤ x, y ≤ w`, `0 ≤ z ≤ w`): false only when all eight corners lie beyond
/// one clip plane. Computed in clip space, independently of the renderer's frustum planes.
pub fn box_in_view(clip_from_world: glam::Mat4, b: &Aabb) -> bool {
    let corners: Vec<glam::Vec4> = (0..8)
        .map(|i| {
            let c = Vec3::new(
                if i & 1 == 0 { b.min.x } else { b.max.x },
                if i & 2 == 0 { b.min.y } else { b.max.y },
                if i & 4 == 0 { b.min.z } else { b.max.z },
            );
            clip_from_world * c.extend(1.0)
        })
        .collect();
    let outside: [fn(glam::Vec4) -> bool; 6] = [
        |c| c.x < -c.w,
        |c| c.x > c.w,
        |c| c.y < -c.w,
        |c| c.y > c.w,
        |c| c.z < 0.0,
        |c| c.z > c.w,
    ];
    !outside.iter().any(|out| corners.iter().all(|c| out(*c)))
}
