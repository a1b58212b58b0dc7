//! The renderer's spot-light sphere ([`LightSphere::spot`]) against the reference's own,
//! found by search from the sector's geometry: it holds every sampled point of the sector and
//! is the smallest such sphere (same centre and radius within a part in 10⁴).

use glam::Vec3;

use super::{sector_points, spot_bounding_sphere};
use crate::culling::reference::LightSphere;

/// Outer-cone cosines from a pencil beam to a hemisphere, with both sides of 45° (where the
/// smallest sphere changes from passing through the apex to passing through the rim only).
const COSINES: [f32; 10] = [1.0, 0.999, 0.99, 0.9, 0.75, 0.7072, 0.7070, 0.5, 0.2, 0.0];

fn lights() -> Vec<(Vec3, Vec3, f32)> {
    vec![
        (
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.3, -1.0, 0.2).normalize(),
            4.0,
        ),
        (Vec3::new(-20.0, 5.0, 0.5), Vec3::X, 0.25),
        (Vec3::ZERO, Vec3::new(-1.0, 1.0, -1.0).normalize(), 150.0),
    ]
}

#[test]
fn the_reference_sphere_holds_its_sector_and_matches_the_limits() {
    for (apex, axis, range) in lights() {
        // A segment: its midpoint, half its length. A hemisphere: the apex, the range.
        let pencil = spot_bounding_sphere(apex, axis, 0.0, range);
        assert!(pencil.center.distance(apex + axis * (range / 2.0)) < 1e-4 * range);
        assert!((pencil.radius - range / 2.0).abs() < 1e-4 * range);
        let half = spot_bounding_sphere(apex, axis, std::f32::consts::FRAC_PI_2, range);
        assert!(half.center.distance(apex) < 1e-4 * range);
        assert!((half.radius - range).abs() < 1e-4 * range);
        for cos in COSINES {
            let angle = cos.acos();
            let s = spot_bounding_sphere(apex, axis, angle, range);
            for p in sector_points(apex, axis, angle, range, 6, 24) {
                assert!(
                    s.center.distance(p) <= s.radius,
                    "sector point {p} outside the reference sphere {s:?} (cos {cos})"
                );
            }
        }
    }
}

#[test]
fn the_renderer_spot_sphere_is_the_smallest_holding_the_cone() {
    for (apex, axis, range) in lights() {
        for cos in COSINES {
            let renderer = LightSphere::spot(apex, axis, cos, range);
            let reference = spot_bounding_sphere(apex, axis, cos.acos(), range);
            for p in sector_points(apex, axis, cos.acos(), range, 8, 64) {
                let d = renderer.center.distance(p);
                assert!(
                    d <= renderer.radius * (1.0 + 1e-5) + 1e-6,
                    "cos {cos}, range {range}: sector point {p} lies {d} from the renderer's \
                     centre, outside its radius {}",
                    renderer.radius
                );
            }
            let tolerance = 1e-4 * range;
            assert!(
                (renderer.radius - reference.radius).abs() <= tolerance
                    && renderer.center.distance(reference.center) <= tolerance,
                "cos {cos}, range {range}: the renderer's sphere {renderer:?} is not the smallest, \
                 {reference:?}"
            );
        }
    }
}
