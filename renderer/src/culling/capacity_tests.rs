//! Unit tests of the CPU entry bound: the cases whose answer is known by hand.

use glam::{Mat4, Vec3};

use super::*;

fn grid() -> GridView {
    GridView {
        view: Mat4::IDENTITY,
        projection: glam::camera::rh::proj::directx::perspective(
            std::f32::consts::FRAC_PI_2,
            1.0,
            0.1,
            100.0,
        ),
        width: 256,
        height: 256,
        tile: 16,
    }
}

const TILED: ListLayout = ListLayout::Tiled { lists_per_tile: 1 };

#[test]
fn a_small_sphere_at_the_centre_touches_the_four_tiles_around_it() {
    // Radius 0.01 at depth 10 projects to about a quarter of a pixel at the centre, where four
    // tiles meet; the pixel of margin keeps exactly those four.
    assert_eq!(
        entry_bound([(Vec3::new(0.0, 0.0, -10.0), 0.01)], &grid(), TILED),
        4
    );
}

#[test]
fn a_sphere_inside_one_tile_counts_one_tile_per_list() {
    // Centre of tile (2, 2): pixels 40..48 → NDC x = 2·40/256 − 1.
    let x = 2.0 * 40.0 / 256.0 - 1.0;
    let center = Vec3::new(x * 10.0, -x * 10.0, -10.0);
    assert_eq!(entry_bound([(center, 0.01)], &grid(), TILED), 1);
    let two = ListLayout::Tiled { lists_per_tile: 2 };
    assert_eq!(entry_bound([(center, 0.01)], &grid(), two), 2);
}

#[test]
fn behind_the_eye_counts_nothing_and_through_the_eye_counts_every_tile() {
    assert_eq!(
        entry_bound([(Vec3::new(0.0, 0.0, 5.0), 1.0)], &grid(), TILED),
        0
    );
    assert_eq!(
        entry_bound([(Vec3::new(0.0, 0.0, -0.5), 1.0)], &grid(), TILED),
        256
    );
    assert_eq!(
        entry_bound([(Vec3::ZERO, f32::INFINITY)], &grid(), TILED),
        256
    );
}

#[test]
fn off_screen_spheres_count_nothing() {
    assert_eq!(
        entry_bound([(Vec3::new(50.0, 0.0, -10.0), 1.0)], &grid(), TILED),
        0
    );
}

#[test]
fn a_sphere_covering_the_screen_counts_every_tile_and_its_slices() {
    let big = [(Vec3::new(0.0, 0.0, -20.0), 15.0)];
    assert_eq!(entry_bound(big, &grid(), TILED), 256);
    let clustered = ListLayout::Clustered {
        slices: 32,
        near: 0.1,
        far: 100.0,
    };
    // Depth span 5..35: slices 17 (5 starts in ⌊32·ln 50/ln 1000⌋ = 18, minus one) to
    // 28 (35: ⌊32·ln 350/ln 1000⌋ = 27, plus one): 12 slices.
    assert_eq!(entry_bound(big, &grid(), clustered), 256 * 12);
}

#[test]
fn the_bound_adds_over_items() {
    let one = entry_bound([(Vec3::new(0.0, 0.0, -10.0), 2.0)], &grid(), TILED);
    let two = entry_bound(
        [
            (Vec3::new(0.0, 0.0, -10.0), 2.0),
            (Vec3::new(0.0, 0.0, -10.0), 2.0),
        ],
        &grid(),
        TILED,
    );
    assert_eq!(two, 2 * one);
}

/// 256 × 256 pixels over view `x`, `y` in `[−8, 8]`: 16 pixels, one tile, per view unit.
fn orthographic_grid() -> GridView {
    GridView {
        projection: glam::camera::rh::proj::directx::orthographic(-8.0, 8.0, -8.0, 8.0, 0.1, 100.0),
        ..grid()
    }
}

#[test]
fn an_orthographic_sphere_covers_the_same_tiles_at_every_depth() {
    // Radius 1.5 at the centre spans pixels 128 ± 24, widened by a pixel: 103..153, tiles 6 to
    // 9 either way, 16 tiles, near or far.
    for z in [-1.0, -10.0, -90.0] {
        let sphere = [(Vec3::new(0.0, 0.0, z), 1.5)];
        assert_eq!(
            entry_bound(sphere, &orthographic_grid(), TILED),
            16,
            "z {z}"
        );
    }
    // Centre of tile (2, 2) (pixel 40: view x = −8 + 40 / 16) with a small radius: one tile,
    // however far.
    for z in [-2.0, -80.0] {
        let sphere = [(Vec3::new(-5.5, 5.5, z), 0.1)];
        assert_eq!(entry_bound(sphere, &orthographic_grid(), TILED), 1, "z {z}");
    }
    // Behind the camera's plane: nothing; off the sides: nothing.
    let behind = [(Vec3::new(0.0, 0.0, 5.0), 1.0)];
    assert_eq!(entry_bound(behind, &orthographic_grid(), TILED), 0);
    let aside = [(Vec3::new(12.0, 0.0, -10.0), 1.0)];
    assert_eq!(entry_bound(aside, &orthographic_grid(), TILED), 0);
}
