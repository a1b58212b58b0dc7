//! The benchmark's lights: seeded point lights whose ranges keep a fixed light density, moved a
//! little every frame so that no frame is a cached replay.
//!
//! Ranges shrink as the count grows so that, on average, `density` lights reach any point of
//! the light box (the scene bounds grown by 20%, where `procedural_lights` places them): more
//! lights means a larger or busier level, not the same room lit ever more brightly. The culled
//! paths then shade a similar number of lights per sample at every count, while naive forward
//! still loops over all of them — which is the comparison the benchmark is for.

use glam::Vec3;
use renderer::demo::procedural_lights;
use renderer::scene::{Aabb, SceneLight};

/// Spread of ranges around the mean: uniform in `[0.75, 1.25] × r0`.
const RANGE_SPREAD: (f32, f32) = (0.75, 1.25);

/// A seeded light set and its motion.
#[derive(Debug, Clone)]
pub struct MovingLights {
    base: Vec<SceneLight>,
    /// Mean range, for the motion's amplitude.
    r0: f32,
}

impl MovingLights {
    /// `count` lights in `bounds` with ranges such that `density` lights reach a point on average.
    pub fn new(bounds: Aabb, count: usize, density: f32, seed: u64) -> Self {
        let r0 = mean_range(bounds, count, density);
        let base = procedural_lights(
            bounds,
            count,
            seed,
            r0 * RANGE_SPREAD.0,
            r0 * RANGE_SPREAD.1,
        );
        Self { base, r0 }
    }

    /// The lights at `frame`: each circles its seeded position (a quarter of the mean range
    /// across) with its own phase.
    pub fn at(&self, frame: u32) -> Vec<SceneLight> {
        let t = frame as f32 * 0.05;
        let amplitude = 0.25 * self.r0;
        self.base
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let phase = i as f32 * 0.618_034 * std::f32::consts::TAU;
                let offset = Vec3::new(
                    (t + phase).cos(),
                    0.5 * (1.3 * t + phase).sin(),
                    (t + phase).sin(),
                );
                SceneLight {
                    position: l.position + amplitude * offset,
                    ..*l
                }
            })
            .collect()
    }
}

/// Mean range `r0` with `count · (4/3)π · E[r³] = density · V` for the light box's volume `V`
/// (each side at least a quarter of the longest, so a flat scene still gets a 3-D box).
pub fn mean_range(bounds: Aabb, count: usize, density: f32) -> f32 {
    let extent = (bounds.max - bounds.min) * 1.2;
    let longest = extent.max_element().max(1e-6);
    let side = extent.max(Vec3::splat(longest * 0.25));
    let volume = side.x * side.y * side.z;
    // E[r³] for r uniform in [a, b]·r0 is (b⁴ − a⁴) / (4 (b − a)) · r0³.
    let (a, b) = RANGE_SPREAD;
    let cube_mean = (b.powi(4) - a.powi(4)) / (4.0 * (b - a));
    let sphere = 4.0 / 3.0 * std::f32::consts::PI * cube_mean;
    (density * volume / (count.max(1) as f32 * sphere)).cbrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Aabb {
        Aabb {
            min: Vec3::splat(-1.0),
            max: Vec3::splat(1.0),
        }
    }

    #[test]
    fn ranges_keep_the_density() {
        // Monte Carlo: lights reaching random points of the inner box, on average.
        let (count, density) = (4096, 16.0);
        let lights = MovingLights::new(cube(), count, density, 3).at(0);
        let mut rng = renderer::demo::Rng::new(9);
        let probes = 400;
        let mut reached = 0usize;
        for _ in 0..probes {
            let p = Vec3::new(
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
                rng.range(-0.5, 0.5),
            );
            reached += lights
                .iter()
                .filter(|l| l.position.distance(p) <= l.range.unwrap_or(0.0))
                .count();
        }
        let mean = reached as f32 / probes as f32;
        assert!(
            (mean - density).abs() < density * 0.2,
            "{mean} lights reach a point on average, asked for {density}"
        );
    }

    #[test]
    fn more_lights_get_smaller_ranges() {
        let r1 = mean_range(cube(), 1024, 16.0);
        let r8 = mean_range(cube(), 8192, 16.0);
        assert!(
            (r1 / r8 - 2.0).abs() < 1e-3,
            "8× the lights halves the range"
        );
    }

    #[test]
    fn lights_move_between_frames_and_repeat_by_seed() {
        let a = MovingLights::new(cube(), 64, 8.0, 1);
        let b = MovingLights::new(cube(), 64, 8.0, 1);
        assert_eq!(a.at(5), b.at(5), "seeded");
        assert_ne!(a.at(0), a.at(1), "moving");
    }
}
