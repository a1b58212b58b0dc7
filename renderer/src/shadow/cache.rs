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
use super::grid::{CasterGrid, RegionTest};
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

/// Casters below which every full cull tests them all (the grid costs more than it saves).
const GRID_MIN_CASTERS: usize = 256;

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
/// tests; told which casters changed ([`CasterChanges::Only`]), it does not compare them
/// either, and a frame costs what changed and what reaches the changed regions.
#[derive(Debug, Default)]
pub struct ShadowCache {
    regions: HashMap<RegionKey, RegionState>,
    /// The last frame's casters.
    casters: Vec<Caster>,
    /// The grid of `casters`, while none changed.
    grid: Option<CasterGrid>,
    /// Frames planned so far.
    frame: u64,
}

impl ShadowCache {
    /// Forgets every region (the atlases were recreated).
    pub fn clear(&mut self) {
        self.regions.clear();
        self.casters.clear();
        self.grid = None;
    }

    /// Plans `regions` against `casters`: cached when `cached`, else every region is drawn
    /// directly. Regions absent from `regions` are forgotten.
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
        let nothing_changed = changed.as_ref().is_some_and(Vec::is_empty);
        // Uncached frames leave nothing behind in the static cache.
        if !cached {
            self.regions.clear();
        }
        if !nothing_changed {
            self.grid = None;
        }
        // A region new or with another view culls every caster: through the grid, built
        // when a frame needs it and kept while no caster changes.
        let full_culls = changed.is_none()
            || regions.iter().any(|r| {
                (self.regions.get(&r.key))
                    .is_none_or(|o| o.clip_from_world != r.view.clip_from_world)
            });
        if full_culls && self.grid.is_none() && casters.len() >= GRID_MIN_CASTERS {
            let boxes: Vec<Aabb> = casters.iter().map(|c| c.bounds).collect();
            self.grid = Some(CasterGrid::new(&boxes));
        }
        let grid = self.grid.as_ref();
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
                    let changed = changed.as_deref();
                    let (work, state) =
                        region_work(region, old, (casters, grid), changed, cached, self.frame);
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

/// The work of a region that is new, moved, or reached by a changed caster, and its new state.
fn region_work(
    region: &RegionInput,
    old: Option<&RegionState>,
    (casters, grid): (&[Caster], Option<&CasterGrid>),
    changed: Option<&[u32]>,
    cached: bool,
    frame: u64,
) -> (RegionWork, RegionState) {
    let reaching = reaching(region, old, (casters, grid), changed);
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

/// Which casters differ from the last frame's (indices, ascending); `None` when the list
/// itself changed (another length), and every region culls afresh.
fn changed_casters(last: &[Caster], now: &[Caster]) -> Option<Vec<u32>> {
    (last.len() == now.len()).then(|| {
        (0..now.len() as u32)
            .filter(|&i| last[i as usize] != now[i as usize])
            .collect()
    })
}

/// The casters reaching `region` (indices, ascending): the old list with only the changed
/// casters re-tested when the region's view is unchanged, else every caster tested (those
/// `grid` finds near the region's frustum, with a grid).
fn reaching(
    region: &RegionInput,
    old: Option<&RegionState>,
    (casters, grid): (&[Caster], Option<&CasterGrid>),
    changed: Option<&[u32]>,
) -> Vec<u32> {
    let test = RegionTest::new(region.view.clip_from_world);
    let reaches = |&i: &u32| test.reaches(&casters[i as usize].bounds);
    let reused = old.filter(|o| o.clip_from_world == region.view.clip_from_world);
    match (reused, changed) {
        (Some(o), Some(changed)) => {
            let mut list: Vec<u32> = o
                .reaching
                .iter()
                .copied()
                .filter(|i| changed.binary_search(i).is_err())
                .chain(changed.iter().copied().filter(reaches))
                .collect();
            list.sort_unstable();
            list
        }
        _ => match grid.and_then(|g| g.candidates(&test)) {
            Some(near) => near.into_iter().filter(reaches).collect(),
            None => (0..casters.len() as u32).filter(reaches).collect(),
        },
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
#[path = "cache_tests.rs"]
mod tests;
