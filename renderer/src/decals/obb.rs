//! Oriented boxes: a decal's volume, the tests culling needs (against a plane, against an
//! axis-aligned box by separating axes) and the projection of a point into the box.

use glam::{Mat4, Vec3};

/// A box: centre, three orthonormal axes and the half extent along each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrientedBox {
    /// The box's centre.
    pub center: Vec3,
    /// Unit axes, mutually orthogonal (the matrix's columns normalised).
    pub axes: [Vec3; 3],
    /// Half the box's extent along each of `axes`.
    pub half: Vec3,
}

/// Shortest half extent a box may have.
const MIN_HALF: f32 = 0.5e-6;

impl OrientedBox {
    /// The box `m` makes of the unit cube `[−0.5, 0.5]³`, or `None` when `m` is not finite, has
    /// a zero (or tiny) scale, shears, or projects (its last row is not `0 0 0 1`).
    pub fn from_matrix(m: Mat4) -> Option<Self> {
        if !m.is_finite() || m.row(3) != glam::Vec4::W {
            return None;
        }
        let cols = [
            m.x_axis.truncate(),
            m.y_axis.truncate(),
            m.z_axis.truncate(),
        ];
        let lengths = cols.map(Vec3::length);
        if lengths.iter().any(|&l| l * 0.5 < MIN_HALF) {
            return None;
        }
        let axes = [0, 1, 2].map(|i| cols[i] / lengths[i]);
        let sheared = (0..3).any(|i| axes[i].dot(axes[(i + 1) % 3]).abs() > 1e-4);
        if sheared {
            return None;
        }
        Some(Self {
            center: m.w_axis.truncate(),
            axes,
            half: Vec3::from_array(lengths) * 0.5,
        })
    }

    /// The bounding sphere: centre and radius.
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        (self.center, self.half.length())
    }

    /// The box moved by a rigid transform (a view matrix).
    pub fn transformed(&self, rigid: Mat4) -> Self {
        Self {
            center: rigid.transform_point3(self.center),
            axes: self.axes.map(|a| rigid.transform_vector3(a).normalize()),
            half: self.half,
        }
    }

    /// Half the box's extent along unit direction `n`.
    pub fn radius_along(&self, n: Vec3) -> f32 {
        (0..3)
            .map(|i| self.half[i] * self.axes[i].dot(n).abs())
            .sum()
    }

    /// Whether the whole box lies on the negative side of the plane `n · p + d = 0` (`n` unit).
    pub fn outside_plane(&self, n: Vec3, d: f32) -> bool {
        n.dot(self.center) + d < -self.radius_along(n)
    }

    /// Whether the box and the axis-aligned box `[min, max]` overlap (separating-axis theorem:
    /// the three world axes, the box's three and their nine cross products). Exact up to
    /// rounding; touching counts as overlapping.
    pub fn intersects_aabb(&self, min: Vec3, max: Vec3) -> bool {
        let c = (min + max) * 0.5;
        let h = (max - min) * 0.5;
        let t = self.center - c;
        let world = [Vec3::X, Vec3::Y, Vec3::Z];
        let mut axes: Vec<Vec3> = Vec::with_capacity(15);
        axes.extend(world);
        axes.extend(self.axes);
        for a in world {
            for b in self.axes {
                let cross = a.cross(b);
                // Parallel edges give no new axis (the face axes cover them).
                if cross.length_squared() > 1e-10 {
                    axes.push(cross.normalize());
                }
            }
        }
        axes.iter().all(|&n| {
            let aabb_radius = h.x * n.x.abs() + h.y * n.y.abs() + h.z * n.z.abs();
            t.dot(n).abs() <= aabb_radius + self.radius_along(n)
        })
    }

    /// Point `p` in the box's frame, scaled so the box spans `[−0.5, 0.5]` on each axis.
    pub fn local(&self, p: Vec3) -> Vec3 {
        let d = p - self.center;
        Vec3::new(
            d.dot(self.axes[0]),
            d.dot(self.axes[1]),
            d.dot(self.axes[2]),
        ) / (self.half * 2.0)
    }

    /// Whether `p` lies inside the box (boundary included).
    pub fn contains(&self, p: Vec3) -> bool {
        self.local(p).abs().max_element() <= 0.5
    }
}

#[cfg(test)]
mod tests {
    use glam::Quat;

    use super::*;

    /// A small seeded generator (a 64-bit LCG), uniform floats in `[lo, hi)`.
    struct Lcg(u64);

    impl Lcg {
        fn f(&mut self, lo: f32, hi: f32) -> f32 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            lo + (hi - lo) * ((self.0 >> 40) as f32 / (1u64 << 24) as f32)
        }

        fn v(&mut self, lo: f32, hi: f32) -> Vec3 {
            Vec3::new(self.f(lo, hi), self.f(lo, hi), self.f(lo, hi))
        }
    }

    fn random_box(rng: &mut Lcg) -> OrientedBox {
        let rotation = Quat::from_euler(
            glam::EulerRot::XYZ,
            rng.f(-3.0, 3.0),
            rng.f(-3.0, 3.0),
            rng.f(-3.0, 3.0),
        );
        let m = Mat4::from_scale_rotation_translation(rng.v(0.05, 2.0), rotation, rng.v(-2.0, 2.0));
        OrientedBox::from_matrix(m).unwrap()
    }

    #[test]
    fn degenerate_sheared_or_infinite_matrices_are_not_boxes() {
        assert!(OrientedBox::from_matrix(Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0))).is_none());
        let shear = Mat4::from_cols_array(&[
            1.0, 0.0, 0.0, 0.0, 0.5, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ]);
        assert!(OrientedBox::from_matrix(shear).is_none());
        assert!(OrientedBox::from_matrix(Mat4::from_translation(Vec3::splat(f32::NAN))).is_none());
        let b = OrientedBox::from_matrix(Mat4::from_scale(Vec3::new(2.0, 4.0, 6.0))).unwrap();
        assert_eq!(b.half, Vec3::new(1.0, 2.0, 3.0));
    }

    /// Points inside both a random box and a random axis-aligned box mean the test must say
    /// they overlap; and when it says they do not, no sampled point is in both.
    #[test]
    fn separating_axes_never_miss_an_overlap() {
        let mut rng = Lcg(11);
        let mut overlaps = 0;
        for _ in 0..400 {
            let b = random_box(&mut rng);
            let lo = rng.v(-2.5, 1.5);
            let hi = lo + rng.v(0.3, 3.0);
            let says = b.intersects_aabb(lo, hi);
            let mut shared = false;
            for _ in 0..400 {
                let u = rng.v(-0.5, 0.5);
                let p = b.center
                    + b.axes[0] * u.x * 2.0 * b.half.x
                    + b.axes[1] * u.y * 2.0 * b.half.y
                    + b.axes[2] * u.z * 2.0 * b.half.z;
                if p.cmpge(lo).all() && p.cmple(hi).all() {
                    shared = true;
                    break;
                }
            }
            assert!(says || !shared, "missed an overlap: {b:?} vs {lo} {hi}");
            overlaps += usize::from(shared);
        }
        assert!(
            overlaps > 50,
            "the random cases overlap often enough ({overlaps})"
        );
    }

    #[test]
    fn separating_axes_separate_a_rotated_box_beside_a_corner() {
        // A thin box rotated 45° about Z, near the corner of the unit cube but clear of it:
        // the face axes of either box alone do not separate them, an edge cross product does.
        let m = Mat4::from_scale_rotation_translation(
            Vec3::new(2.0, 0.1, 2.0),
            Quat::from_rotation_z(std::f32::consts::FRAC_PI_4),
            Vec3::new(1.2, -1.2, 0.0) * 1.05,
        );
        let b = OrientedBox::from_matrix(m).unwrap();
        assert!(!b.intersects_aabb(Vec3::splat(-1.0), Vec3::splat(1.0)));
        let closer = OrientedBox {
            center: Vec3::new(0.9, -0.9, 0.0),
            ..b
        };
        assert!(closer.intersects_aabb(Vec3::splat(-1.0), Vec3::splat(1.0)));
    }

    #[test]
    fn plane_test_and_local_coordinates_agree_with_the_corners() {
        let mut rng = Lcg(5);
        for _ in 0..200 {
            let b = random_box(&mut rng);
            let n = rng.v(-1.0, 1.0).normalize();
            let d = rng.f(-2.0, 2.0);
            let corners: Vec<Vec3> = (0..8)
                .map(|k| {
                    let s = Vec3::new(
                        if k & 1 == 0 { -1.0 } else { 1.0 },
                        if k & 2 == 0 { -1.0 } else { 1.0 },
                        if k & 4 == 0 { -1.0 } else { 1.0 },
                    );
                    b.center
                        + b.axes[0] * s.x * b.half.x
                        + b.axes[1] * s.y * b.half.y
                        + b.axes[2] * s.z * b.half.z
                })
                .collect();
            let all_out = corners.iter().all(|c| n.dot(*c) + d < -1e-4);
            let any_in = corners.iter().any(|c| n.dot(*c) + d > 1e-4);
            if all_out {
                assert!(b.outside_plane(n, d));
            }
            if any_in {
                assert!(!b.outside_plane(n, d));
            }
            for c in &corners {
                assert!((b.local(*c).abs() - Vec3::splat(0.5)).abs().max_element() < 1e-4);
            }
        }
    }
}
