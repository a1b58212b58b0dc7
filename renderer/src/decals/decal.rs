//! A decal item: an oriented box, its material, how it fades and where it layers.

use glam::{Mat4, Vec3};

use super::{DecalError, DecalMaterial, OrientedBox};

/// A decal: its material projected along the box's −Z axis onto the surfaces inside the box.
///
/// The box is `world_from_box` applied to the unit cube `[−0.5, 0.5]³`. Local +Z points out of
/// the surface (towards whoever looks at the decal); the image's +X runs along local +X and its
/// top along local +Y.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decal {
    /// Unit cube to world: the box's position, orientation and size (metres); no shear.
    pub world_from_box: Mat4,
    /// Index into [`DecalSet::materials`].
    pub material: usize,
    /// Opacity multiplier, 0 to 1.
    pub blend: f32,
    /// Radians between the surface normal and the box's +Z axis: whole up to `[0]`, gone from
    /// `[1]` (surfaces running along the projection axis would smear the image).
    pub angle_fade: [f32; 2],
    /// Camera distances: whole up to `[0]`, gone from `[1]`.
    pub distance_fade: [f32; 2],
    /// Layering: higher keys are applied over lower ones; equal keys keep their order in the set.
    pub sort_key: i32,
}

impl Decal {
    /// Fades that suit most decals: whole up to 60° off the projection axis, gone at 80°; no
    /// distance fade.
    pub const DEFAULT_ANGLE_FADE: [f32; 2] = [
        std::f32::consts::FRAC_PI_3,
        4.0 * std::f32::consts::PI / 9.0,
    ];
    /// Distance fade that never fades (both distances `f32::MAX`).
    pub const NO_DISTANCE_FADE: [f32; 2] = [f32::MAX, f32::MAX];

    /// A decal of `material` through `world_from_box`, whole, with the default fades and key 0.
    pub fn new(world_from_box: Mat4, material: usize) -> Self {
        Self {
            world_from_box,
            material,
            blend: 1.0,
            angle_fade: Self::DEFAULT_ANGLE_FADE,
            distance_fade: Self::NO_DISTANCE_FADE,
            sort_key: 0,
        }
    }

    /// The decal's box in world space.
    pub fn bounds(&self) -> Option<OrientedBox> {
        OrientedBox::from_matrix(self.world_from_box)
    }
}

/// Decals and the materials they use.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DecalSet {
    /// The materials [`Decal::material`] indexes.
    pub materials: Vec<DecalMaterial>,
    /// The decals, in the order equal sort keys keep.
    pub decals: Vec<Decal>,
}

impl DecalSet {
    /// Checks every decal: its material exists, its box is a finite rotation and scale with no
    /// side shorter than 1e-6, its blend is in 0..=1 and its fades run from start to end.
    pub fn validate(&self) -> Result<(), DecalError> {
        for m in &self.materials {
            m.check()?;
        }
        for (index, d) in self.decals.iter().enumerate() {
            let fail = |reason: String| Err(DecalError::Decal { index, reason });
            if d.material >= self.materials.len() {
                return fail(format!(
                    "material {} does not exist ({} materials)",
                    d.material,
                    self.materials.len()
                ));
            }
            if d.bounds().is_none() {
                return fail(
                    "its box must be a finite rotation, translation and non-zero scale (no \
                     shear, no side under 1e-6)"
                        .into(),
                );
            }
            if !(0.0..=1.0).contains(&d.blend) {
                return fail(format!("blend {} is outside 0..=1", d.blend));
            }
            for (name, [a, b]) in [("angle", d.angle_fade), ("distance", d.distance_fade)] {
                if a.is_nan() || b.is_nan() || a < 0.0 || a > b {
                    return fail(format!(
                        "{name} fade [{a}, {b}] must run from a start ≥ 0 to an end ≥ start"
                    ));
                }
            }
        }
        Ok(())
    }

    /// Decal indices in application order: by sort key, then by position in the set.
    pub fn layer_order(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.decals.len()).collect();
        order.sort_by_key(|&i| (self.decals[i].sort_key, i));
        order
    }
}

/// `world_from_box` for a box centred at `center`, its +Z along `normal` (out of the surface),
/// rolled by `roll` radians about it, `size` wide, high and deep.
pub fn box_on_surface(center: Vec3, normal: Vec3, roll: f32, size: Vec3) -> Mat4 {
    let z = normal.normalize_or(Vec3::Z);
    let helper = if z.y.abs() < 0.9 { Vec3::Y } else { Vec3::X };
    let x0 = helper.cross(z).normalize();
    let y0 = z.cross(x0);
    let (s, c) = roll.sin_cos();
    let x = x0 * c + y0 * s;
    let y = z.cross(x);
    Mat4::from_cols(
        (x * size.x).extend(0.0),
        (y * size.y).extend(0.0),
        (z * size.z).extend(0.0),
        center.extend(1.0),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decals::DecalImage;

    fn set(decals: Vec<Decal>) -> DecalSet {
        DecalSet {
            materials: vec![DecalMaterial {
                name: "m".into(),
                base_color: DecalImage::solid(4, 4, [255; 4]),
                normal: None,
                orm: None,
                emissive: None,
            }],
            decals,
        }
    }

    #[test]
    fn bad_decals_say_which_and_why() {
        let ok = Decal::new(Mat4::from_scale(Vec3::splat(2.0)), 0);
        assert!(set(vec![ok]).validate().is_ok());
        let cases = [
            (Decal { material: 3, ..ok }, "material 3"),
            (Decal { blend: 1.5, ..ok }, "blend"),
            (
                Decal {
                    world_from_box: Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0)),
                    ..ok
                },
                "scale",
            ),
            (
                Decal {
                    angle_fade: [1.0, 0.5],
                    ..ok
                },
                "angle fade",
            ),
        ];
        for (bad, words) in cases {
            let e = set(vec![ok, bad]).validate().unwrap_err().to_string();
            assert!(e.starts_with("decal 1:") && e.contains(words), "{e}");
        }
    }

    #[test]
    fn layers_follow_the_key_then_the_order_given() {
        let d = |key| Decal {
            sort_key: key,
            ..Decal::new(Mat4::IDENTITY, 0)
        };
        assert_eq!(
            set(vec![d(2), d(-1), d(2), d(0)]).layer_order(),
            [1, 3, 0, 2]
        );
    }

    #[test]
    fn a_box_on_a_surface_points_out_of_it_with_its_size() {
        let m = box_on_surface(Vec3::ONE, Vec3::Y, 0.3, Vec3::new(2.0, 1.0, 0.5));
        let b = OrientedBox::from_matrix(m).unwrap();
        assert!((b.axes[2] - Vec3::Y).length() < 1e-6);
        assert!((b.half - Vec3::new(1.0, 0.5, 0.25)).length() < 1e-6);
        assert!(b.contains(Vec3::ONE + Vec3::Y * 0.2));
        assert!(!b.contains(Vec3::ONE + Vec3::Y * 0.3));
    }
}
