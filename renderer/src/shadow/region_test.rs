//! Whether a caster reaches a shadow region: [`RegionTest::reaches`], its box inside every
//! plane of the region's clip volume and overlapping the volume's world box (the planes alone
//! keep boxes beside a frustum's corners). The GPU culls casters per region with the same
//! test (`shadow_cull`, fed by [`RegionTest::volume`]); the CPU asks
//! [`RegionTest::may_reach`], a little wider, to find the regions a changed caster touches, so
//! floating-point differences between the two can never leave a drawn caster's region stale.

use glam::{Mat4, Vec3, Vec4};

use super::views::Frustum;
use crate::scene::Aabb;

/// The test of boxes against one region's clip volume.
#[derive(Debug, Clone, Copy)]
pub struct RegionTest {
    frustum: Frustum,
    /// The volume's world box; `None` for a volume reaching infinity.
    bounds: Option<Aabb>,
}

impl RegionTest {
    pub fn new(clip_from_world: Mat4) -> Self {
        Self {
            frustum: Frustum::from_clip(clip_from_world),
            bounds: clip_box(clip_from_world),
        }
    }

    /// Whether `b` may reach the volume (never false for a box inside it; empty boxes reach
    /// nothing).
    pub fn reaches(&self, b: &Aabb) -> bool {
        self.frustum.intersects_aabb(b)
            && self
                .bounds
                .is_none_or(|v| b.min.cmple(v.max).all() && b.max.cmpge(v.min).all())
    }

    /// [`RegionTest::reaches`] for `b` grown by a margin far above `f32` rounding (a
    /// millionth of its largest coordinate, at least a millionth of a unit): true wherever
    /// the GPU's test of `b` can be.
    pub fn may_reach(&self, b: &Aabb) -> bool {
        if b.is_empty() {
            return false;
        }
        let scale = b.min.abs().max(b.max.abs()).max_element().max(1.0);
        let margin = Vec3::splat(scale * 1e-6);
        self.reaches(&Aabb {
            min: b.min - margin,
            max: b.max + margin,
        })
    }

    /// The volume as the GPU tests it: the six planes (normal and offset, pointing inwards;
    /// left, right, bottom, top, near, far) and the world box, `None` when it reaches infinity.
    pub fn volume(&self) -> ([Vec4; 6], Option<Aabb>) {
        let planes = self.frustum.planes().map(|p| p.normal.extend(p.d));
        (planes, self.bounds)
    }
}

/// The world box of the clip volume of `clip_from_world` (x, y in [-1, 1], z in [0, 1]), or
/// `None` where a corner is not finite.
fn clip_box(clip_from_world: Mat4) -> Option<Aabb> {
    let world_from_clip = clip_from_world.inverse();
    let mut b = Aabb::EMPTY;
    for i in 0..8 {
        let corner = Vec4::new(
            if i & 1 == 0 { -1.0 } else { 1.0 },
            if i & 2 == 0 { -1.0 } else { 1.0 },
            if i & 4 == 0 { 0.0 } else { 1.0 },
            1.0,
        );
        let p = world_from_clip * corner;
        if p.w.abs() < 1e-12 {
            return None;
        }
        let p = p.truncate() / p.w;
        if !p.is_finite() {
            return None;
        }
        b = b.with_point(p);
    }
    Some(b)
}

#[cfg(test)]
mod tests {
    use glam::{Vec3, camera::rh};

    use super::RegionTest;
    use crate::scene::Aabb;
    use crate::shadow::views::cube_views;

    #[test]
    fn the_wider_test_keeps_every_box_the_exact_one_keeps_and_boxes_near_the_border() {
        let face = cube_views(Vec3::new(3.0, 2.0, -1.0), 20.0, 256, 2)[0].clip_from_world;
        let look = rh::view::look_at_mat4(Vec3::new(0.0, 200.0, 0.0), Vec3::ZERO, Vec3::Z);
        let ortho = rh::proj::directx::orthographic(-60.0, 60.0, -60.0, 60.0, 1.0, 400.0) * look;
        let (mut kept, mut widened) = (0, 0);
        for clip in [face, ortho] {
            let test = RegionTest::new(clip);
            for i in 0..4_000u32 {
                let f = |k: u32| {
                    ((i.wrapping_mul(2_654_435_761).rotate_left(k) % 2_000) as f32) / 10.0 - 100.0
                };
                let at = Vec3::new(f(0), f(7), f(13));
                let half = Vec3::splat(0.05 + (i % 13) as f32 * 0.3);
                let b = Aabb {
                    min: at - half,
                    max: at + half,
                };
                assert!(!test.reaches(&b) || test.may_reach(&b), "{b:?}");
                kept += usize::from(test.reaches(&b));
                widened += usize::from(test.may_reach(&b) && !test.reaches(&b));
            }
            assert!(!test.may_reach(&Aabb::EMPTY));
        }
        assert!(kept > 100, "the views reach some boxes ({kept})");
        assert!(
            widened < kept / 50,
            "the margin is small ({widened} of {kept})"
        );
    }
}
