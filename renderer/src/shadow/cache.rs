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
#[derive(Debug, Clone, Copy, PartialEq)]
struct RegionState {
    rect: AtlasRect,
    clip_from_world: Mat4,
    static_signature: u64,
    dynamic_signature: u64,
}

/// The regions' cached state across frames.
#[derive(Debug, Default)]
pub struct ShadowCache {
    regions: HashMap<RegionKey, RegionState>,
}

impl ShadowCache {
    /// Forgets every region (the atlases were recreated).
    pub fn clear(&mut self) {
        self.regions.clear();
    }

    /// Plans `regions` against `casters`: cached when `cached`, else every region is drawn
    /// directly. Regions absent from `regions` are forgotten.
    pub fn plan(
        &mut self,
        regions: &[RegionInput],
        casters: &[Caster],
        cached: bool,
    ) -> Vec<RegionPlan> {
        let mut next = HashMap::with_capacity(regions.len());
        let plans = regions
            .iter()
            .map(|region| {
                let frustum = Frustum::from_clip(region.view.clip_from_world);
                let reaching: Vec<&Caster> = casters
                    .iter()
                    .filter(|c| frustum.intersects_aabb(&c.bounds))
                    .collect();
                let (statics, dynamics): (Vec<&Caster>, Vec<&Caster>) =
                    reaching.iter().partition(|c| !c.dynamic);
                let state = RegionState {
                    rect: region.rect,
                    clip_from_world: region.view.clip_from_world,
                    static_signature: signature(&statics),
                    dynamic_signature: signature(&dynamics),
                };
                let work = if cached {
                    self.cached_work(region.key, &state, &statics, &dynamics)
                } else {
                    RegionWork::Direct {
                        casters: reaching.iter().map(|c| c.draw).collect(),
                    }
                };
                // Uncached frames leave nothing behind in the static cache.
                if cached {
                    next.insert(region.key, state);
                }
                RegionPlan {
                    region: *region,
                    work,
                }
            })
            .collect();
        self.regions = next;
        plans
    }

    fn cached_work(
        &self,
        key: RegionKey,
        state: &RegionState,
        statics: &[&Caster],
        dynamics: &[&Caster],
    ) -> RegionWork {
        let old = self.regions.get(&key);
        let static_valid = old.is_some_and(|o| {
            o.rect == state.rect
                && o.clip_from_world == state.clip_from_world
                && o.static_signature == state.static_signature
        });
        let composed_valid =
            static_valid && old.is_some_and(|o| o.dynamic_signature == state.dynamic_signature);
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
