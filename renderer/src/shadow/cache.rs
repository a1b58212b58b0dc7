//! What each atlas region needs this frame: a redraw of its static casters into the static
//! cache, a recomposition (the static depth copied into the shadow atlas, then the dynamic
//! casters drawn over it), or nothing at all.
//!
//! A region's static depth stays valid while its light's view (projection and region), its
//! rectangle and the set of static casters that can reach it (with their versions) stay the
//! same. Its composed depth in the shadow atlas stays valid while the static depth does and the
//! dynamic casters that reach it (with their versions) are the same ones. Casters are culled per
//! region, against the region's view frustum.

use std::collections::HashMap;
use std::hash::{Hash as _, Hasher as _};

use glam::Mat4;

use super::atlas::AtlasRect;
use super::views::{Frustum, LightView};
use crate::scene::Aabb;

/// A region's identity from frame to frame: the light's stable id and the face (0 for spot
/// lights, the cube face or the cascade).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct RegionKey {
    pub light: u32,
    pub face: u32,
}

/// A region as the frame places it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RegionInput {
    pub key: RegionKey,
    pub rect: AtlasRect,
    pub view: LightView,
}

/// A shadow caster this frame: one draw of the prepared scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Caster {
    /// Index into the prepared scene's draws.
    pub draw: u32,
    /// World bounds this frame.
    pub bounds: Aabb,
    pub dynamic: bool,
    /// The instance's version (bumped when it moves or changes between static and dynamic).
    pub version: u64,
}

/// The work of one region.
#[derive(Debug, Clone, PartialEq)]
pub enum RegionWork {
    /// Its depth in the shadow atlas is still right: no draw, no copy.
    Untouched,
    /// Cached: when `redraw_static`, clear the region in the static cache and draw
    /// `static_casters` there; then copy the static region into the shadow atlas and draw
    /// `dynamic_casters` over it.
    Compose {
        redraw_static: bool,
        static_casters: Vec<u32>,
        dynamic_casters: Vec<u32>,
    },
    /// Uncached: clear the region in the shadow atlas and draw every caster there.
    Direct { casters: Vec<u32> },
}

/// One region's plan.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionPlan {
    pub region: RegionInput,
    pub work: RegionWork,
}

/// What a frame's plan amounts to, for the frame report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CacheCounts {
    /// Regions whose static casters were drawn again (or, uncached, every region).
    pub redrawn: u32,
    /// Regions recomposed from the static cache (copy + dynamic casters).
    pub copied: u32,
    /// Regions left alone.
    pub untouched: u32,
    /// Caster draw calls.
    pub draws: u32,
}

impl CacheCounts {
    /// The counts of `plans`.
    pub fn of(plans: &[RegionPlan]) -> Self {
        let mut c = Self::default();
        for p in plans {
            match &p.work {
                RegionWork::Untouched => c.untouched += 1,
                RegionWork::Compose {
                    redraw_static,
                    static_casters,
                    dynamic_casters,
                } => {
                    c.copied += 1;
                    if *redraw_static {
                        c.redrawn += 1;
                        c.draws += static_casters.len() as u32;
                    }
                    c.draws += dynamic_casters.len() as u32;
                }
                RegionWork::Direct { casters } => {
                    c.redrawn += 1;
                    c.draws += casters.len() as u32;
                }
            }
        }
        c
    }
}

/// What the cache remembers of a region.
#[derive(Debug, Clone, PartialEq)]
struct RegionState {
    rect: AtlasRect,
    clip_from_world: Mat4,
    /// Indices into the frame's casters that reach the region, ascending.
    reaching: Vec<u32>,
    static_signature: u64,
    dynamic_signature: u64,
    /// The last frame that planned the region (older regions are forgotten).
    frame: u64,
}

/// The regions' cached state across frames.
///
/// Culling is incremental: a region whose view is unchanged re-tests only the casters that
/// changed since the last frame (moved, switched between static and dynamic), so a frame where
/// nothing moved costs one comparison per caster and per region, not casters × regions frustum
/// tests.
#[derive(Debug, Default)]
pub struct ShadowCache {
    regions: HashMap<RegionKey, RegionState>,
    /// The last frame's casters.
    casters: Vec<Caster>,
    /// Frames planned so far.
    frame: u64,
}

impl ShadowCache {
    /// Forgets every region (the atlases were recreated).
    pub fn clear(&mut self) {
        self.regions.clear();
        self.casters.clear();
    }

    /// Plans `regions` against `casters`: cached when `cached`, else every region is drawn
    /// directly. Regions absent from `regions` are forgotten.
    pub fn plan(
        &mut self,
        regions: &[RegionInput],
        casters: &[Caster],
        cached: bool,
    ) -> Vec<RegionPlan> {
        let changed = changed_casters(&self.casters, casters);
        let nothing_changed = changed.as_ref().is_some_and(|m| !m.contains(&true));
        // Uncached frames leave nothing behind in the static cache.
        if !cached {
            self.regions.clear();
        }
        self.frame += 1;
        let mut plans = Vec::with_capacity(regions.len());
        for region in regions {
            let old = self.regions.get_mut(&region.key);
            let work = match old {
                // Same view, same rectangle, no caster changed: the region is as it was.
                Some(o)
                    if nothing_changed
                        && o.rect == region.rect
                        && o.clip_from_world == region.view.clip_from_world =>
                {
                    o.frame = self.frame;
                    RegionWork::Untouched
                }
                old => {
                    let old = old.map(|o| &*o);
                    let (work, state) =
                        region_work(region, old, casters, changed.as_deref(), cached, self.frame);
                    if cached {
                        self.regions.insert(region.key, state);
                    }
                    work
                }
            };
            plans.push(RegionPlan {
                region: *region,
                work,
            });
        }
        let frame = self.frame;
        self.regions.retain(|_, s| s.frame == frame);
        self.casters.clear();
        self.casters.extend_from_slice(casters);
        plans
    }
}

/// The work of a region that is new, moved, or reached by a changed caster, and its new state.
fn region_work(
    region: &RegionInput,
    old: Option<&RegionState>,
    casters: &[Caster],
    changed: Option<&[bool]>,
    cached: bool,
    frame: u64,
) -> (RegionWork, RegionState) {
    let reaching = reaching(region, old, casters, changed);
    let (statics, dynamics): (Vec<&Caster>, Vec<&Caster>) = reaching
        .iter()
        .map(|&i| &casters[i as usize])
        .partition(|c| !c.dynamic);
    let (static_signature, dynamic_signature) = (signature(&statics), signature(&dynamics));
    let work = if cached {
        cached_work(
            old,
            region,
            static_signature,
            dynamic_signature,
            &statics,
            &dynamics,
        )
    } else {
        RegionWork::Direct {
            casters: reaching.iter().map(|&i| casters[i as usize].draw).collect(),
        }
    };
    let state = RegionState {
        rect: region.rect,
        clip_from_world: region.view.clip_from_world,
        reaching,
        static_signature,
        dynamic_signature,
        frame,
    };
    (work, state)
}

/// Which casters differ from the last frame's, as a mask; `None` when the list itself changed
/// (another length), and every region culls afresh.
fn changed_casters(last: &[Caster], now: &[Caster]) -> Option<Vec<bool>> {
    (last.len() == now.len()).then(|| last.iter().zip(now).map(|(a, b)| a != b).collect())
}

/// The casters reaching `region` (indices, ascending): the old list with only the changed
/// casters re-tested when the region's view is unchanged, else every caster tested.
fn reaching(
    region: &RegionInput,
    old: Option<&RegionState>,
    casters: &[Caster],
    changed: Option<&[bool]>,
) -> Vec<u32> {
    let frustum = || Frustum::from_clip(region.view.clip_from_world);
    let reused = old.filter(|o| o.clip_from_world == region.view.clip_from_world);
    match (reused, changed) {
        (Some(o), Some(mask)) => {
            let f = frustum();
            let mut list: Vec<u32> = o
                .reaching
                .iter()
                .copied()
                .filter(|&i| !mask[i as usize])
                .chain(
                    mask.iter()
                        .enumerate()
                        .filter(|&(i, &m)| m && f.intersects_aabb(&casters[i].bounds))
                        .map(|(i, _)| i as u32),
                )
                .collect();
            list.sort_unstable();
            list
        }
        _ => {
            let f = frustum();
            (0..casters.len() as u32)
                .filter(|&i| f.intersects_aabb(&casters[i as usize].bounds))
                .collect()
        }
    }
}

/// A cached region's work, from its old state (if it had one) and its new one.
fn cached_work(
    old: Option<&RegionState>,
    region: &RegionInput,
    static_signature: u64,
    dynamic_signature: u64,
    statics: &[&Caster],
    dynamics: &[&Caster],
) -> RegionWork {
    let static_valid = old.is_some_and(|o| {
        o.rect == region.rect
            && o.clip_from_world == region.view.clip_from_world
            && o.static_signature == static_signature
    });
    let composed_valid =
        static_valid && old.is_some_and(|o| o.dynamic_signature == dynamic_signature);
    if composed_valid {
        return RegionWork::Untouched;
    }
    RegionWork::Compose {
        redraw_static: !static_valid,
        static_casters: if static_valid {
            Vec::new()
        } else {
            statics.iter().map(|c| c.draw).collect()
        },
        dynamic_casters: dynamics.iter().map(|c| c.draw).collect(),
    }
}

/// A hash of which casters (and which versions of them) reach a region.
fn signature(casters: &[&Caster]) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    casters.len().hash(&mut h);
    for c in casters {
        c.draw.hash(&mut h);
        c.version.hash(&mut h);
    }
    h.finish()
}

#[cfg(test)]
mod tests {
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
        for p in &plans {
            if let RegionWork::Compose {
                redraw_static,
                dynamic_casters,
                ..
            } = &p.work
            {
                assert!(!redraw_static, "static depth stays cached");
                let reaches = p.region.key.face == 5;
                assert_eq!(dynamic_casters.contains(&2), reaches);
            }
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
    fn uncached_frames_draw_every_region_with_what_reaches_it() {
        let mut cache = ShadowCache::default();
        for _ in 0..2 {
            let plans = cache.plan(&faces(), &casters(), false);
            assert_eq!(counts(&plans).redrawn, 6);
            let down = &plans[3].work;
            assert_eq!(
                down,
                &RegionWork::Direct { casters: vec![0] },
                "−Y sees the floor"
            );
        }
    }

    /// Random motions over many frames: the incrementally culled lists always equal culling
    /// every caster afresh.
    #[test]
    fn incremental_culling_equals_culling_afresh() {
        let mut rng = Lcg(7);
        let regions = faces();
        let mut casters: Vec<Caster> = (0..40)
            .map(|i| {
                let p = Vec3::new(
                    rng.range(-12.0, 12.0),
                    rng.range(-12.0, 12.0),
                    rng.range(-12.0, 12.0),
                );
                cube_at(i, p, i % 3 == 0, 0)
            })
            .collect();
        let mut incremental = ShadowCache::default();
        for frame in 0..60 {
            for _ in 0..(frame % 4) {
                let i = (rng.next() % casters.len() as u64) as usize;
                let c = &mut casters[i];
                let step = Vec3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), 0.0);
                c.bounds = Aabb {
                    min: c.bounds.min + step,
                    max: c.bounds.max + step,
                };
                c.version += 1;
            }
            incremental.plan(&regions, &casters, true);
            for r in &regions {
                let fresh = reaching(r, None, &casters, None);
                assert_eq!(
                    incremental.regions[&r.key].reaching, fresh,
                    "frame {frame}, face {}",
                    r.key.face
                );
            }
        }
    }
}
