//! How many shadow texels a light deserves this frame: the projected size of its influence
//! sphere on screen ([`screen_radius_px`]), the wanted region side as a continuous log2
//! ([`desired_log2`]), and a hysteresis ([`Hysteresis`]) that turns that value into a
//! power-of-two side which does not flicker when the light hovers around a size boundary.
//!
//! Everything here is plain arithmetic on the CPU: no GPU object, no allocation.

use glam::{Mat4, Vec3};

/// How far (in log2 units, i.e. octaves of side) the wanted size must move away from the
/// current level before [`Hysteresis::update`] switches level.
pub const HYSTERESIS_LOG2: f32 = 0.75;

/// Highest level [`Hysteresis`] returns (`1 << 31` is the largest power of two in a `u32`).
const MAX_LEVEL: u32 = 31;

/// The vertical field of view (radians) of a perspective projection.
pub fn projection_fovy(projection: Mat4) -> f32 {
    2.0 * (1.0 / projection.y_axis.y).atan()
}

/// Projected radius, in pixels, of the sphere of influence (`center`, `radius`, world space) of
/// a light seen through a perspective camera.
///
/// `view` is the world-to-view matrix (right-handed, the camera looks down −Z), `fovy_radians`
/// the vertical field of view and `viewport_height` the height of the viewport in pixels.
///
/// - Camera inside the sphere (view distance `d <= radius`): the light covers the whole screen,
///   the result is `viewport_height`.
/// - Sphere entirely behind the camera (view-space `z > radius`): the result is 0.
/// - Otherwise the standard approximation of a sphere projected near the screen centre: the
///   sphere's silhouette cone has half-angle θ with `tan θ = r / sqrt(d² − r²)`, and a
///   view-space tangent `t` maps to `t / tan(fovy / 2) · h / 2` pixels, so
///   `r / (sqrt(d² − r²) · tan(fovy / 2)) · h / 2`. It ignores the stretching of off-centre
///   spheres, which only matters near the screen border of wide fields of view.
///
/// The result is clamped to `[0, viewport_height]` (so it is continuous when the camera enters
/// the sphere) and is never NaN: degenerate inputs (NaN, non-positive field of view) give
/// `viewport_height` when the sphere may be visible.
#[must_use]
pub fn screen_radius_px(
    center: Vec3,
    radius: f32,
    view: Mat4,
    fovy_radians: f32,
    viewport_height: f32,
) -> f32 {
    let height = if viewport_height.is_finite() {
        viewport_height.max(0.0)
    } else {
        0.0
    };
    let radius = radius.max(0.0);
    let centre = view.transform_point3(center);
    let distance = centre.length();
    if centre.z > radius {
        return 0.0;
    }
    if distance <= radius {
        return height;
    }
    let tan_half_fov = (fovy_radians * 0.5).tan();
    let tangent = radius / (distance * distance - radius * radius).sqrt();
    let pixels = tangent / tan_half_fov * height * 0.5;
    if pixels.is_nan() || tan_half_fov <= 0.0 {
        return height;
    }
    pixels.clamp(0.0, height)
}

/// Projected radius, in pixels, of a sphere (`center`, `radius`, world space) seen through
/// `projection`: [`screen_radius_px`] for a perspective projection; for an orthographic one
/// (last row `(0, 0, 0, 1)`), whose screen size does not shrink with distance, the radius times
/// the projection's vertical scale, `r · m11 · h / 2` (0 when the sphere lies wholly behind
/// the camera's plane). Clamped to `[0, viewport_height]`, never NaN.
#[must_use]
pub fn projected_radius_px(
    center: Vec3,
    radius: f32,
    view: Mat4,
    projection: Mat4,
    viewport_height: f32,
) -> f32 {
    if projection.row(3) != glam::Vec4::W {
        return screen_radius_px(
            center,
            radius,
            view,
            projection_fovy(projection),
            viewport_height,
        );
    }
    let height = if viewport_height.is_finite() {
        viewport_height.max(0.0)
    } else {
        0.0
    };
    let radius = radius.max(0.0);
    if view.transform_point3(center).z > radius {
        return 0.0;
    }
    let pixels = radius * projection.y_axis.y.abs() * height * 0.5;
    if pixels.is_nan() {
        return height;
    }
    pixels.clamp(0.0, height)
}

/// Continuous log2 of the region side a light wants for a projected radius of
/// `screen_radius_px` pixels: one shadow texel per screen pixel across the light's influence,
/// so `side ≈ 2 · screen_radius_px`, clamped to `[log2 min, log2 max]`.
///
/// `min` is taken as at least 1 and `max` as at least `min`; a non-positive or NaN radius gives
/// `log2 min`.
#[must_use]
pub fn desired_log2(screen_radius_px: f32, min: u32, max: u32) -> f32 {
    let min = min.max(1);
    let low = (min as f32).log2();
    let high = (max.max(min) as f32).log2();
    // `f32::max` returns the other operand for NaN, so NaN and -inf (radius 0) land on `low`.
    (2.0 * screen_radius_px).log2().max(low).min(high)
}

/// Per-light hysteresis on the region size: keeps the current power-of-two level (log2 of the
/// side) until the wanted size is clearly elsewhere.
///
/// Rule of [`Hysteresis::update`]: the first call takes the rounded wanted level; afterwards
/// the level changes only when the wanted log2 is more than [`HYSTERESIS_LOG2`] (0.75) away
/// from the current level, and then to the rounded wanted value. A light hovering around a
/// rounding boundary (say between 8.4 and 8.6) therefore keeps one side instead of switching
/// between 256 and 512 each frame, which would move its atlas region and force a redraw.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Hysteresis {
    /// log2 of the current side; `None` before the first update.
    level: Option<u32>,
}

impl Hysteresis {
    /// A hysteresis that has not seen any size yet.
    #[must_use]
    #[cfg(any(test, feature = "internals"))]
    pub const fn new() -> Self {
        Self { level: None }
    }

    /// Current level (log2 of the side), `None` before the first [`update`](Self::update).
    #[must_use]
    #[cfg(any(test, feature = "internals"))]
    pub const fn level(&self) -> Option<u32> {
        self.level
    }

    /// Feeds this frame's wanted log2 (see [`desired_log2`]) and returns the side in texels
    /// (`1 << level`), following the rule documented on [`Hysteresis`]. A NaN input keeps the
    /// current level (level 0 before any level exists); levels are clamped to `0..=31`.
    pub fn update(&mut self, desired_log2: f32) -> u32 {
        let rounded = || {
            // Saturating float-to-int cast: negative values give 0, NaN gives 0.
            let level = desired_log2.round() as u32;
            level.min(MAX_LEVEL)
        };
        let level = match self.level {
            None => rounded(),
            Some(current) if (desired_log2 - current as f32).abs() > HYSTERESIS_LOG2 => rounded(),
            Some(current) => current,
        };
        self.level = Some(level);
        1 << level
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FOVY: f32 = std::f32::consts::FRAC_PI_2;
    const HEIGHT: f32 = 1080.0;

    fn radius_at(center: Vec3, radius: f32) -> f32 {
        screen_radius_px(center, radius, Mat4::IDENTITY, FOVY, HEIGHT)
    }

    #[test]
    fn orthographic_size_does_not_shrink_with_distance() {
        // ±4 units across 1,080 rows: 135 pixels per unit, so radius 2 is 270 pixels anywhere
        // in front of the camera.
        let ortho = glam::camera::rh::proj::directx::orthographic(-4.0, 4.0, -4.0, 4.0, 0.1, 500.0);
        for z in [-1.0, -50.0, -400.0] {
            let px =
                projected_radius_px(Vec3::new(1.0, 0.0, z), 2.0, Mat4::IDENTITY, ortho, HEIGHT);
            assert!((px - 270.0).abs() < 1e-2, "z {z}: {px}");
        }
        let behind =
            projected_radius_px(Vec3::new(0.0, 0.0, 5.0), 2.0, Mat4::IDENTITY, ortho, HEIGHT);
        assert_eq!(behind, 0.0);
        // A perspective projection keeps `screen_radius_px`'s answer.
        let persp = glam::camera::rh::proj::directx::perspective(FOVY, 1.0, 0.1, 500.0);
        let c = Vec3::new(0.0, 0.0, -10.0);
        let px = projected_radius_px(c, 1.0, Mat4::IDENTITY, persp, HEIGHT);
        assert!((px - radius_at(c, 1.0)).abs() < 1e-3, "{px}");
    }

    #[test]
    fn camera_inside_the_sphere_covers_the_screen() {
        assert_eq!(radius_at(Vec3::ZERO, 1.0), HEIGHT);
        assert_eq!(radius_at(Vec3::new(0.5, 0.0, 0.5), 1.0), HEIGHT);
        // Inside a sphere whose centre is behind the camera still covers the screen.
        assert_eq!(radius_at(Vec3::new(0.0, 0.0, 0.9), 1.0), HEIGHT);
    }

    #[test]
    fn sphere_behind_the_camera_is_invisible() {
        assert_eq!(radius_at(Vec3::new(0.0, 0.0, 10.0), 1.0), 0.0);
        assert_eq!(radius_at(Vec3::new(3.0, -2.0, 1.01), 1.0), 0.0);
        // Straddling the camera plane still counts.
        assert!(radius_at(Vec3::new(5.0, 0.0, 0.5), 1.0) > 0.0);
    }

    #[test]
    fn view_matrix_is_applied() {
        let eye = Vec3::new(10.0, 0.0, 0.0);
        // Camera at `eye` looking at the origin: its −Z turned onto world −X.
        let rotation = glam::Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
        let view = Mat4::from_rotation_translation(rotation, eye).inverse();
        let in_front = screen_radius_px(Vec3::ZERO, 1.0, view, FOVY, HEIGHT);
        let behind = screen_radius_px(Vec3::new(20.0, 0.0, 0.0), 1.0, view, FOVY, HEIGHT);
        assert!((in_front - radius_at(Vec3::new(0.0, 0.0, -10.0), 1.0)).abs() < 1e-3);
        assert_eq!(behind, 0.0);
    }

    #[test]
    fn matches_the_documented_formula() {
        let (r, d) = (1.0_f32, 10.0_f32);
        let expected = r / (d * d - r * r).sqrt() / (FOVY * 0.5).tan() * HEIGHT * 0.5;
        let got = radius_at(Vec3::new(0.0, 0.0, -d), r);
        assert!((got - expected).abs() < 1e-3, "{got} vs {expected}");
    }

    #[test]
    fn shrinks_monotonically_with_distance() {
        let mut previous = f32::INFINITY;
        for step in 1..200 {
            let distance = 1.0 + step as f32 * 0.25;
            let px = radius_at(Vec3::new(0.0, 0.0, -distance), 1.0);
            assert!(px <= previous, "at {distance}: {px} > {previous}");
            assert!(px > 0.0 && px <= HEIGHT);
            previous = px;
        }
        // Continuous into the "inside" case.
        assert!(radius_at(Vec3::new(0.0, 0.0, -1.0001), 1.0) > HEIGHT * 0.99);
    }

    #[test]
    fn degenerate_inputs_do_not_produce_nan() {
        let center = Vec3::new(0.0, 0.0, -10.0);
        for value in [
            screen_radius_px(center, 1.0, Mat4::IDENTITY, 0.0, HEIGHT),
            screen_radius_px(center, f32::NAN, Mat4::IDENTITY, FOVY, HEIGHT),
            screen_radius_px(center, 1.0, Mat4::IDENTITY, FOVY, f32::NAN),
            screen_radius_px(Vec3::NAN, 1.0, Mat4::IDENTITY, FOVY, HEIGHT),
        ] {
            assert!(!value.is_nan());
            assert!((0.0..=HEIGHT).contains(&value));
        }
    }

    #[test]
    fn desired_log2_is_twice_the_radius_clamped() {
        assert!((desired_log2(128.0, 64, 2048) - 8.0).abs() < 1e-6);
        assert!((desired_log2(300.0, 64, 2048) - 600.0_f32.log2()).abs() < 1e-6);
        assert_eq!(desired_log2(1.0, 64, 2048), 6.0);
        assert_eq!(desired_log2(0.0, 64, 2048), 6.0);
        assert_eq!(desired_log2(f32::NAN, 64, 2048), 6.0);
        assert_eq!(desired_log2(1e9, 64, 2048), 11.0);
        // Inverted bounds do not panic: max is raised to min.
        assert_eq!(desired_log2(1e9, 256, 16), 8.0);
    }

    #[test]
    fn hysteresis_first_update_rounds() {
        let mut h = Hysteresis::new();
        assert_eq!(h.level(), None);
        assert_eq!(h.update(8.4), 256);
        assert_eq!(h.level(), Some(8));
        let mut h = Hysteresis::default();
        assert_eq!(h.update(8.6), 512);
    }

    #[test]
    fn hysteresis_does_not_flicker_around_a_boundary() {
        let mut h = Hysteresis::new();
        assert_eq!(h.update(8.45), 256);
        for frame in 0..100 {
            let wobble = if frame % 2 == 0 { 8.55 } else { 8.45 };
            assert_eq!(h.update(wobble + (frame % 3) as f32 * 0.1), 256);
        }
        // Exactly 0.75 away is not enough.
        assert_eq!(h.update(8.75), 256);
        assert_eq!(h.update(7.25), 256);
    }

    #[test]
    fn hysteresis_switches_after_a_big_change() {
        let mut h = Hysteresis::new();
        assert_eq!(h.update(8.0), 256);
        assert_eq!(h.update(8.8), 512);
        // Now at level 9: coming back to 8.4 is within the band, stays.
        assert_eq!(h.update(8.4), 512);
        assert_eq!(h.update(8.2), 256);
        assert_eq!(h.update(11.0), 2048);
        assert_eq!(h.update(6.0), 64);
    }

    #[test]
    fn hysteresis_handles_odd_inputs() {
        let mut h = Hysteresis::new();
        assert_eq!(h.update(f32::NAN), 1);
        assert_eq!(h.update(100.0), 1 << 31);
        assert_eq!(h.update(f32::NAN), 1 << 31);
        assert_eq!(h.update(-5.0), 1);
    }
}
