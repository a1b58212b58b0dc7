//! The atlas plan's invariants, checked on every plan of every test, and incremental
//! planning: grants kept, moved and freed from frame to frame, and odd requests cleaned up.

use super::*;

const SIZE: u32 = 8192;
pub(super) const MIN: u32 = 64;

pub(super) fn spot(light: u32, side: u32, importance: f32) -> ShadowRequest {
    ShadowRequest {
        light,
        faces: 1,
        side,
        importance,
    }
}

pub(super) fn point(light: u32, side: u32, importance: f32) -> ShadowRequest {
    ShadowRequest {
        light,
        faces: 6,
        side,
        importance,
    }
}

pub(super) fn directional(light: u32, side: u32) -> ShadowRequest {
    ShadowRequest {
        light,
        faces: 4,
        side,
        importance: f32::INFINITY,
    }
}

/// Every invariant a plan must hold: regions in bounds, pairwise disjoint, one per face of
/// the grant's side, grants in request order, no light both granted and evicted, every
/// cleaned-up request either granted or evicted.
fn check(atlas: &ShadowAtlas, requests: &[ShadowRequest], plan: &AtlasPlan) {
    let size = atlas.size();
    let mut rects = Vec::new();
    for grant in &plan.grants {
        let request = requests
            .iter()
            .find(|r| r.light == grant.light)
            .expect("granted light asked");
        assert_eq!(
            grant.rects.len() as u32,
            request.faces.max(1),
            "light {}",
            grant.light
        );
        assert!(grant.side >= atlas.min_side() && grant.side <= request.side.max(atlas.min_side()));
        for rect in &grant.rects {
            assert_eq!(rect.side, grant.side);
            assert!(
                rect.x + rect.side <= size && rect.y + rect.side <= size,
                "{rect:?} out of {size}"
            );
            rects.push(*rect);
        }
        assert!(!plan.evicted.contains(&grant.light));
    }
    for (i, a) in rects.iter().enumerate() {
        for b in &rects[i + 1..] {
            let apart = a.x + a.side <= b.x
                || b.x + b.side <= a.x
                || a.y + a.side <= b.y
                || b.y + b.side <= a.y;
            assert!(apart, "{a:?} overlaps {b:?}");
        }
    }
    let mut lights = BTreeSet::new();
    let order: Vec<u32> = requests
        .iter()
        .map(|r| r.light)
        .filter(|l| lights.insert(*l))
        .collect();
    let granted: Vec<u32> = plan.grants.iter().map(|g| g.light).collect();
    let expected: Vec<u32> = order
        .iter()
        .copied()
        .filter(|l| granted.contains(l))
        .collect();
    assert_eq!(granted, expected, "grants in request order");
    for light in &order {
        assert!(
            granted.contains(light) ^ plan.evicted.contains(light),
            "light {light}"
        );
    }
    for &(light, asked, got) in &plan.degraded {
        assert!(got < asked.max(atlas.min_side()));
        assert_eq!(
            plan.grants
                .iter()
                .find(|g| g.light == light)
                .map(|g| g.side),
            Some(got)
        );
    }
}

pub(super) fn plan(atlas: &mut ShadowAtlas, requests: &[ShadowRequest]) -> AtlasPlan {
    let plan = atlas.plan(requests);
    check(atlas, requests, &plan);
    plan
}

pub(super) fn grant(plan: &AtlasPlan, light: u32) -> &ShadowGrant {
    plan.grants
        .iter()
        .find(|g| g.light == light)
        .expect("light granted")
}

#[test]
fn allocates_spot_point_and_directional() {
    let mut atlas = ShadowAtlas::new(SIZE, MIN);
    let requests = [spot(1, 512, 3.0), point(2, 256, 2.0), directional(3, 2048)];
    let plan = plan(&mut atlas, &requests);
    assert_eq!(plan.grants.len(), 3);
    assert_eq!(grant(&plan, 1).rects.len(), 1);
    assert_eq!(grant(&plan, 2).rects.len(), 6);
    assert_eq!(grant(&plan, 3).rects.len(), 4);
    assert_eq!(grant(&plan, 3).side, 2048);
    assert!(plan.grants.iter().all(|g| g.moved));
    assert!(plan.degraded.is_empty() && plan.evicted.is_empty() && !plan.repacked);
}

#[test]
fn empty_requests_give_an_empty_plan() {
    let mut atlas = ShadowAtlas::new(SIZE, MIN);
    assert_eq!(plan(&mut atlas, &[]), AtlasPlan::default());
    plan(&mut atlas, &[spot(1, 512, 1.0)]);
    assert_eq!(plan(&mut atlas, &[]), AtlasPlan::default());
}

#[test]
fn unchanged_requests_keep_their_rects() {
    let mut atlas = ShadowAtlas::new(SIZE, MIN);
    let requests = [spot(1, 512, 3.0), point(2, 256, 2.0), directional(3, 2048)];
    let first = plan(&mut atlas, &requests);
    for _ in 0..3 {
        let next = plan(&mut atlas, &requests);
        assert!(next.grants.iter().all(|g| !g.moved));
        for (a, b) in first.grants.iter().zip(&next.grants) {
            assert_eq!((a.light, a.side, &a.rects), (b.light, b.side, &b.rects));
        }
        // Importance changes alone move nothing.
        let shuffled = [spot(1, 512, 0.5), point(2, 256, 9.0), directional(3, 2048)];
        assert!(plan(&mut atlas, &shuffled).grants.iter().all(|g| !g.moved));
    }
}

#[test]
fn a_side_change_moves_only_that_light() {
    let mut atlas = ShadowAtlas::new(SIZE, MIN);
    let before = [spot(1, 512, 3.0), point(2, 256, 2.0), spot(3, 1024, 1.0)];
    let first = plan(&mut atlas, &before);
    let after = [spot(1, 512, 3.0), point(2, 512, 2.0), spot(3, 1024, 1.0)];
    let second = plan(&mut atlas, &after);
    assert!(!second.repacked);
    assert!(grant(&second, 2).moved);
    assert_eq!(grant(&second, 2).side, 512);
    for light in [1, 3] {
        assert!(!grant(&second, light).moved);
        assert_eq!(grant(&second, light).rects, grant(&first, light).rects);
    }
    // A face-count change moves too.
    let third = plan(
        &mut atlas,
        &[spot(1, 512, 3.0), point(2, 512, 2.0), point(3, 1024, 1.0)],
    );
    assert!(grant(&third, 3).moved && !grant(&third, 1).moved && !grant(&third, 2).moved);
}

#[test]
fn absent_lights_free_their_regions() {
    let mut atlas = ShadowAtlas::new(1024, MIN);
    let first = plan(&mut atlas, &[spot(1, 1024, 1.0)]);
    assert_eq!(
        grant(&first, 1).rects,
        vec![AtlasRect {
            x: 0,
            y: 0,
            side: 1024
        }]
    );
    // Light 1 is gone: light 2 takes the whole atlas without a repack.
    let second = plan(&mut atlas, &[spot(2, 1024, 1.0)]);
    assert!(!second.repacked && second.degraded.is_empty());
    assert_eq!(
        grant(&second, 2).rects,
        vec![AtlasRect {
            x: 0,
            y: 0,
            side: 1024
        }]
    );
    assert!(grant(&second, 2).moved);
    // Coming back is a new grant.
    let third = plan(&mut atlas, &[spot(1, 512, 1.0), spot(2, 1024, 1.0)]);
    assert!(third.repacked || !grant(&third, 2).moved);
}

#[test]
fn odd_requests_do_not_panic() {
    let mut atlas = ShadowAtlas::new(2048, MIN);
    let requests = [
        ShadowRequest {
            light: 1,
            faces: 0,
            side: 0,
            importance: 1.0,
        },
        ShadowRequest {
            light: 2,
            faces: 3,
            side: 100,
            importance: -1.0,
        },
        ShadowRequest {
            light: 1,
            faces: 6,
            side: 512,
            importance: 9.0,
        },
        ShadowRequest {
            light: 4,
            faces: 5000,
            side: 64,
            importance: -2.0,
        },
        ShadowRequest {
            light: 5,
            faces: 1,
            side: 3000,
            importance: f32::NAN,
        },
    ];
    for frame in 0..3 {
        let plan = plan(&mut atlas, &requests);
        // The duplicate of light 1 is ignored; its side is raised to the minimum and its
        // zero faces count as one.
        assert_eq!(grant(&plan, 1).side, 64);
        assert_eq!(grant(&plan, 1).rects.len(), 1);
        // NaN importance is the least important, then -2: those two are evicted.
        assert_eq!(plan.evicted, vec![4, 5]);
        assert_eq!(plan.degraded, vec![(2, 100, 64)]);
        assert_eq!(plan.repacked, frame == 0);
    }
    for (size, min) in [(0, 0), (u32::MAX, u32::MAX), (100, 7), (1, 1)] {
        let mut atlas = ShadowAtlas::new(size, min);
        assert!(atlas.size() >= 1 && atlas.size() <= MAX_ATLAS_SIZE);
        assert!(atlas.min_side() >= 1 && atlas.min_side() <= atlas.size());
        plan(
            &mut atlas,
            &[
                spot(1, 4096, 1.0),
                point(2, 64, 1.0),
                directional(3, 1 << 14),
            ],
        );
    }
}
