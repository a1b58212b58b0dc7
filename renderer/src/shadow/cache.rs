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

use glam::Mat4;

use super::atlas::AtlasRect;
use super::region_test::RegionTest;
use super::views::LightView;
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

/// Which casters differ from the list the cache planned with last.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CasterChanges<'a> {
    /// Not known: every caster is compared with last frame's.
    Unknown,
    /// These casters (indices, ascending) changed or are new; every other one is as it was,
    /// and none was dropped. The caller knows this from the instance table's change log, so
    /// a frame costs what changed, not what the scene holds.
    Only(&'a [u32]),
}

/// The work of one region.
#[derive(Debug, Clone, PartialEq)]
pub enum RegionWork {
    /// Its depth in the shadow atlas is still right: no draw, no copy.
    Untouched,
    /// Cached: when `redraw_static`, clear the region in the static cache and draw its
    /// static casters there; then copy the static region into the shadow atlas and draw its
    /// dynamic casters over it.
    Compose { redraw_static: bool },
    /// Uncached: clear the region in the shadow atlas and draw every caster there.
    Direct,
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
    /// Casters drawn into regions (a caster drawn into two regions counts twice). Culled
    /// on the GPU, they are counted there and arrive a frame or two later: the newest count
    /// that has arrived when the frame has work, 0 when it has none.
    pub draws: u32,
}

impl CacheCounts {
    /// The region counts of `plans` (`draws` is the shadow pass's to fill).
    pub fn of(plans: &[RegionPlan]) -> Self {
        let mut c = Self::default();
        for p in plans {
            match p.work {
                RegionWork::Untouched => c.untouched += 1,
                RegionWork::Compose { redraw_static } => {
                    c.copied += 1;
                    c.redrawn += u32::from(redraw_static);
                }
                RegionWork::Direct => c.redrawn += 1,
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
    /// The last frame that planned the region (older regions are forgotten).
    frame: u64,
}

/// The regions' cached state across frames.
///
/// A region whose view is unchanged is tested only against the casters that changed since the
/// last frame (moved, switched between static and dynamic, added or removed), in their old and
/// new state; not told which changed, the cache compares every caster with last frame's once,
/// and told ([`CasterChanges::Only`]), it does not even do that.
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
    #[cfg(any(test, feature = "internals"))]
    pub fn clear(&mut self) {
        self.regions.clear();
        self.casters.clear();
    }

    /// Plans `regions` against `casters`: cached when `cached`, else every region is drawn
    /// directly. Regions absent from `regions` are forgotten.
    #[cfg(any(test, feature = "internals"))]
    pub fn plan(
        &mut self,
        regions: &[RegionInput],
        casters: &[Caster],
        cached: bool,
    ) -> Vec<RegionPlan> {
        self.plan_changes(regions, casters, cached, CasterChanges::Unknown)
    }

    /// [`ShadowCache::plan`], told which casters changed since the last plan.
    pub fn plan_changes(
        &mut self,
        regions: &[RegionInput],
        casters: &[Caster],
        cached: bool,
        changes: CasterChanges<'_>,
    ) -> Vec<RegionPlan> {
        let changed = match changes {
            CasterChanges::Unknown => changed_casters(&self.casters, casters),
            CasterChanges::Only(list) => Some(self.with_new_casters(list, casters)),
        };
        // Uncached frames leave nothing behind in the static cache.
        if !cached {
            self.regions.clear();
        }
        self.frame += 1;
        let mut plans = Vec::with_capacity(regions.len());
        for region in regions {
            let kept = self.regions.get(&region.key).filter(|o| {
                o.rect == region.rect && o.clip_from_world == region.view.clip_from_world
            });
            let work = match (cached, kept, changed.as_deref()) {
                (false, ..) => RegionWork::Direct,
                (true, Some(_), Some(changed)) => self
                    .touched(region, changed, casters)
                    .map_or(RegionWork::Untouched, |redraw_static| RegionWork::Compose {
                        redraw_static,
                    }),
                // New, moved or resized, or every caster may have changed.
                (true, ..) => RegionWork::Compose {
                    redraw_static: true,
                },
            };
            if cached {
                let state = RegionState {
                    rect: region.rect,
                    clip_from_world: region.view.clip_from_world,
                    frame: self.frame,
                };
                self.regions.insert(region.key, state);
            }
            plans.push(RegionPlan {
                region: *region,
                work,
            });
        }
        let frame = self.frame;
        self.regions.retain(|_, s| s.frame == frame);
        match changes {
            CasterChanges::Unknown => {
                self.casters.clear();
                self.casters.extend_from_slice(casters);
            }
            CasterChanges::Only(_) => {
                let kept = self.casters.len().min(casters.len());
                self.casters.extend_from_slice(&casters[kept..]);
                for &i in changed.iter().flatten() {
                    self.casters[i as usize] = casters[i as usize];
                }
            }
        }
        plans
    }

    /// What `changed` casters (indices into `casters`, this frame's list) did to an unmoved
    /// `region`, each in its last plan's state and its new one: `None` when none may reach it,
    /// `Some(true)` when a static one may (its static depth is drawn again), `Some(false)`
    /// when only dynamic ones may (the region is composed again).
    fn touched(&self, region: &RegionInput, changed: &[u32], casters: &[Caster]) -> Option<bool> {
        let test = RegionTest::new(region.view.clip_from_world);
        let mut dynamic = false;
        for &i in changed {
            let states = [self.casters.get(i as usize), casters.get(i as usize)];
            for c in states.into_iter().flatten() {
                if test.may_reach(&c.bounds) {
                    if !c.dynamic {
                        return Some(true);
                    }
                    dynamic = true;
                }
            }
        }
        dynamic.then_some(false)
    }

    /// `list`, with every caster past the last plan's list (new ones) added, ascending and
    /// within `casters`.
    fn with_new_casters(&self, list: &[u32], casters: &[Caster]) -> Vec<u32> {
        let new = self.casters.len().min(casters.len())..casters.len();
        let mut changed: Vec<u32> = (list.iter().copied())
            .filter(|&i| (i as usize) < casters.len())
            .chain(new.map(|i| i as u32))
            .collect();
        changed.sort_unstable();
        changed.dedup();
        changed
    }
}

/// Which casters differ from the last frame's or are new (indices, ascending); `None` when
/// the list got shorter (another scene), and every region is drawn again.
fn changed_casters(last: &[Caster], now: &[Caster]) -> Option<Vec<u32>> {
    (last.len() <= now.len()).then(|| {
        (0..now.len() as u32)
            .filter(|&i| last.get(i as usize) != Some(&now[i as usize]))
            .collect()
    })
}

#[cfg(test)]
#[path = "cache_tests.rs"]
mod tests;
