//! The cache's decisions over frames: nothing to do when nothing changed, recomposition for
//! moving dynamic casters and redraws for moving static ones, moved and vanished regions,
//! uncached frames, and plans that never leave a region stale (against a reference that
//! culls every caster afresh).

use glam::Vec3;

use super::*;
use crate::shadow::views::cube_views;

/// A small seeded generator (a 64-bit LCG), uniform floats in `[lo, hi)`.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0 >> 33
    }

    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * (self.next() as f32 / (1u64 << 31) as f32)
    }
}

/// The six faces of a point light at the origin with range 10, side by side.
fn faces() -> Vec<RegionInput> {
    cube_views(Vec3::ZERO, 10.0, 256, 2)
        .iter()
        .enumerate()
        .map(|(face, view)| RegionInput {
            key: RegionKey {
                light: 0,
                face: face as u32,
            },
            rect: AtlasRect {
                x: face as u32 * 256,
                y: 0,
                side: 256,
            },
            view: *view,
        })
        .collect()
}

fn cube_at(draw: u32, centre: Vec3, dynamic: bool, version: u64) -> Caster {
    Caster {
        draw,
        bounds: Aabb {
            min: centre - 0.5,
            max: centre + 0.5,
        },
        dynamic,
        version,
    }
}

/// A floor under the light, a static box on +X and a dynamic box on −X.
fn casters() -> Vec<Caster> {
    vec![
        Caster {
            draw: 0,
            bounds: Aabb {
                min: Vec3::new(-8.0, -3.0, -8.0),
                max: Vec3::new(8.0, -2.0, 8.0),
            },
            dynamic: false,
            version: 0,
        },
        cube_at(1, Vec3::new(4.0, 0.0, 0.0), false, 0),
        cube_at(2, Vec3::new(-4.0, 0.0, 0.0), true, 0),
    ]
}

fn counts(plans: &[RegionPlan]) -> CacheCounts {
    CacheCounts::of(plans)
}

#[test]
fn an_unchanged_frame_leaves_every_region_untouched() {
    let mut cache = ShadowCache::default();
    let first = cache.plan(&faces(), &casters(), true);
    assert_eq!(counts(&first).redrawn, 6, "a new region is drawn");
    let second = cache.plan(&faces(), &casters(), true);
    assert_eq!(
        counts(&second),
        CacheCounts {
            untouched: 6,
            ..Default::default()
        }
    );
}

#[test]
fn a_moving_dynamic_caster_recomposes_only_the_faces_it_reaches() {
    let mut cache = ShadowCache::default();
    cache.plan(&faces(), &casters(), true);
    let mut moved = casters();
    // From −X to −Z: the −X face (1) loses it and the −Z face (5) gains it.
    moved[2] = cube_at(2, Vec3::new(0.0, 0.0, -4.0), true, 1);
    let plans = cache.plan(&faces(), &moved, true);
    let composed: Vec<u32> = plans
        .iter()
        .filter(|p| p.work != RegionWork::Untouched)
        .map(|p| p.region.key.face)
        .collect();
    assert_eq!(composed, [1, 5]);
    for p in plans.iter().filter(|p| p.work != RegionWork::Untouched) {
        assert_eq!(
            p.work,
            RegionWork::Compose {
                redraw_static: false
            },
            "static depth stays cached"
        );
    }
}

#[test]
fn a_moving_static_caster_redraws_the_static_depth_it_reaches() {
    let mut cache = ShadowCache::default();
    cache.plan(&faces(), &casters(), true);
    let mut moved = casters();
    moved[1] = cube_at(1, Vec3::new(4.0, 0.5, 0.0), false, 1);
    let plans = cache.plan(&faces(), &moved, true);
    let redrawn: Vec<u32> = plans
        .iter()
        .filter(|p| {
            matches!(
                p.work,
                RegionWork::Compose {
                    redraw_static: true,
                    ..
                }
            )
        })
        .map(|p| p.region.key.face)
        .collect();
    assert_eq!(redrawn, [0], "only the +X face sees the box");
}

#[test]
fn a_moved_region_or_view_is_redrawn_and_a_vanished_one_forgotten() {
    let mut cache = ShadowCache::default();
    let mut regions = faces();
    cache.plan(&regions, &casters(), true);
    regions[3].rect.x += 1;
    regions[4].view = cube_views(Vec3::X * 0.1, 10.0, 256, 2)[4];
    let plans = cache.plan(&regions[..5], &casters(), true);
    assert_eq!(counts(&plans).redrawn, 2);
    assert_eq!(counts(&plans).untouched, 3);
    let back = cache.plan(&regions, &casters(), true);
    assert_eq!(
        counts(&back).redrawn,
        1,
        "face 5 was forgotten, so it is new"
    );
}

#[test]
fn uncached_frames_draw_every_region() {
    let mut cache = ShadowCache::default();
    for _ in 0..2 {
        let plans = cache.plan(&faces(), &casters(), false);
        assert_eq!(counts(&plans).redrawn, 6);
        assert!(plans.iter().all(|p| p.work == RegionWork::Direct));
    }
}

/// The static and dynamic casters (draw and version) that reach `region`, tested one by one
/// with the exact test: what a region's depth depends on.
fn reaching(region: &RegionInput, casters: &[Caster]) -> [Vec<(u32, u64)>; 2] {
    let test = RegionTest::new(region.view.clip_from_world);
    let of = |dynamic: bool| {
        (casters.iter())
            .filter(|c| c.dynamic == dynamic && test.reaches(&c.bounds))
            .map(|c| (c.draw, c.version))
            .collect()
    };
    [of(false), of(true)]
}

/// Random motions, switches between static and dynamic, and additions over many frames:
/// wherever the static or dynamic casters reaching a region (with their versions) differ from
/// last frame's, the plan redraws or recomposes it; a region it redraws has a changed caster
/// near it; and a cache told which casters changed plans as one that compares them all.
#[test]
fn plans_follow_every_change_that_reaches_a_region_and_only_those() {
    let mut rng = Lcg(7);
    let regions = faces();
    let cube = |rng: &mut Lcg, i: u32| {
        let p = Vec3::new(
            rng.range(-12.0, 12.0),
            rng.range(-12.0, 12.0),
            rng.range(-12.0, 12.0),
        );
        cube_at(i, p, i.is_multiple_of(3), 0)
    };
    let mut casters: Vec<Caster> = (0..40).map(|i| cube(&mut rng, i)).collect();
    // One cache compares every caster with the last frame's; the other is told which changed
    // (and casters are appended, as added instances append draws).
    let mut compared = ShadowCache::default();
    let mut told = ShadowCache::default();
    compared.plan(&regions, &casters, true);
    told.plan(&regions, &casters, true);
    let (mut redraws, mut recomposes, mut untouched) = (0, 0, 0);
    for frame in 0..120 {
        let last = casters.clone();
        let mut changed = Vec::new();
        for _ in 0..(frame % 4) {
            let i = (rng.next() % casters.len() as u64) as usize;
            let c = &mut casters[i];
            let step = Vec3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), 0.0);
            c.bounds = Aabb {
                min: c.bounds.min + step,
                max: c.bounds.max + step,
            };
            c.dynamic ^= frame % 5 == 1;
            c.version += 1;
            changed.push(i as u32);
        }
        if frame % 7 == 3 {
            let new = cube(&mut rng, casters.len() as u32);
            changed.push(casters.len() as u32);
            casters.push(new);
        }
        changed.sort_unstable();
        changed.dedup();
        let plans = compared.plan(&regions, &casters, true);
        // Now and then not told: the cache compares with the list it kept.
        let changes = if frame % 10 == 0 {
            CasterChanges::Unknown
        } else {
            CasterChanges::Only(&changed)
        };
        assert_eq!(
            told.plan_changes(&regions, &casters, true, changes),
            plans,
            "frame {frame}: told the changes, the plan is the same"
        );
        for (r, plan) in regions.iter().zip(&plans) {
            let tally = match check_plan(r, plan, (&last, &casters), &changed, frame) {
                RegionWork::Compose {
                    redraw_static: true,
                } => &mut redraws,
                RegionWork::Compose { .. } => &mut recomposes,
                _ => &mut untouched,
            };
            *tally += 1;
        }
    }
    assert!(
        redraws > 20 && recomposes > 20 && untouched > 200,
        "the flight exercises every decision: {redraws} redraws, {recomposes} \
         recompositions, {untouched} untouched"
    );
}

/// Checks one region's plan against the casters reaching it last frame and now; returns its
/// work.
fn check_plan(
    r: &RegionInput,
    plan: &RegionPlan,
    (last, casters): (&[Caster], &[Caster]),
    changed: &[u32],
    frame: u32,
) -> RegionWork {
    let [statics, dynamics] = reaching(r, casters);
    let [last_statics, last_dynamics] = reaching(r, last);
    let face = r.key.face;
    match plan.work {
        RegionWork::Compose {
            redraw_static: true,
        } => {}
        RegionWork::Compose { .. } => {
            assert_eq!(statics, last_statics, "frame {frame}, face {face}");
        }
        RegionWork::Untouched => {
            assert_eq!(statics, last_statics, "frame {frame}, face {face}");
            assert_eq!(dynamics, last_dynamics, "frame {frame}, face {face}");
        }
        RegionWork::Direct => panic!("a cached plan draws no region directly"),
    }
    if plan.work != RegionWork::Untouched {
        let test = RegionTest::new(r.view.clip_from_world);
        let near = |c: &Caster| test.may_reach(&c.bounds);
        assert!(
            changed
                .iter()
                .any(|&i| { near(&casters[i as usize]) || last.get(i as usize).is_some_and(near) }),
            "frame {frame}, face {face}: redrawn without a change near it"
        );
    }
    plan.work.clone()
}

/// A caster moved in a frame the cache was told of, then moved back in a frame it was not:
/// the list it compares with must be the told frame's, or it would miss the move back.
#[test]
fn a_caster_moved_while_told_and_back_while_not_leaves_the_face_it_left() {
    let mut cache = ShadowCache::default();
    let start = casters();
    cache.plan(&faces(), &start, true);
    let mut moved = start.clone();
    moved[2] = cube_at(2, Vec3::new(0.0, 0.0, -4.0), true, 0);
    let plans = cache.plan_changes(&faces(), &moved, true, CasterChanges::Only(&[2]));
    assert_ne!(
        plans[5].work,
        RegionWork::Untouched,
        "the −Z face gains the box"
    );
    // Back without telling: the cache compares with the told frame's list, and the −Z face
    // loses the box again.
    let plans = cache.plan(&faces(), &start, true);
    let composed: Vec<u32> = (plans.iter())
        .filter(|p| p.work != RegionWork::Untouched)
        .map(|p| p.region.key.face)
        .collect();
    assert_eq!(composed, [1, 5]);
}
