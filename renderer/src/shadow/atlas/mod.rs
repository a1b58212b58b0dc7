//! Where each shadowed light's depth regions sit in the one square shadow atlas, frame after
//! frame.
//!
//! A spot light needs one square region, a point light six (its cube faces) and the
//! directional light four (its cascades), all of one side per light. Rendered depth is cached
//! in the atlas, so [`ShadowAtlas::plan`] keeps every region where it was whenever the light
//! asks for the same thing as last frame, and only moves what must move. When the atlas is
//! too full it falls back to a global fit that degrades (halves) the sides of the least
//! important lights, then evicts the least important lights, and packs everything afresh; an
//! unchanged full frame after such a fit reuses it instead of repacking every frame.
//!
//! Space comes from [`etagere::AtlasAllocator`]. It tracks every allocation on its own and
//! merges freed neighbours back into free space, which suits this workload: few, large,
//! long-lived regions freed one light at a time. [`etagere::BucketedAtlasAllocator`] only
//! reclaims a bucket once all of its items are gone, which would strand atlas space here.
//! A global fit splits the allocator into columns as wide as its largest region (etagere's
//! `num_columns`), which packs power-of-two squares far more tightly than full-width shelves;
//! later frames keep allocating from that allocator until the next global fit.
//!
//! The requests and grants are in `request`, the regions a light holds and their etagere
//! allocations in `regions`, and the global fit in `fit`.

mod fit;
mod regions;
mod request;

#[cfg(test)]
mod fit_tests;
#[cfg(test)]
mod tests;

pub use request::{AtlasPlan, AtlasRect, ShadowGrant, ShadowRequest};

use std::collections::{BTreeMap, BTreeSet};

use etagere::AtlasAllocator;

use fit::{Fit, fit_key};
use regions::{Held, MAX_REGIONS, allocate, empty_allocator, release};
use request::Wanted;

/// Largest atlas side [`ShadowAtlas::new`] accepts: etagere needs sides below `u16::MAX` and an
/// area that fits an `i32`.
pub const MAX_ATLAS_SIZE: u32 = 32768;

/// Requests (as `(light, faces, side)` sorted by light) and outcome of the last global fit that
/// degraded or evicted something; the held regions are that fit's as long as this is kept.
#[derive(Debug, Clone)]
struct FitMemo {
    key: Vec<(u32, u32, u32)>,
    degraded: Vec<(u32, u32, u32)>,
    evicted: Vec<u32>,
}

/// The shadow atlas' allocator state across frames: which light holds which regions.
#[derive(Clone)]
pub struct ShadowAtlas {
    size: u32,
    min_side: u32,
    allocator: AtlasAllocator,
    held: BTreeMap<u32, Held>,
    memo: Option<FitMemo>,
}

impl std::fmt::Debug for ShadowAtlas {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        // `etagere::AtlasAllocator` has no `Debug`; its content is what `held` lists.
        f.debug_struct("ShadowAtlas")
            .field("size", &self.size)
            .field("min_side", &self.min_side)
            .field("held", &self.held)
            .field("memo", &self.memo)
            .finish_non_exhaustive()
    }
}

impl ShadowAtlas {
    /// An empty atlas of `size`² texels whose lights lose their shadow rather than go below
    /// `min_side` texels per region. `size` is clamped to `1..=MAX_ATLAS_SIZE` and `min_side`
    /// to `1..=size`.
    #[must_use]
    pub fn new(size: u32, min_side: u32) -> Self {
        let size = size.clamp(1, MAX_ATLAS_SIZE);
        Self {
            size,
            min_side: min_side.clamp(1, size),
            allocator: empty_allocator(size),
            held: BTreeMap::new(),
            memo: None,
        }
    }

    /// Side of the atlas in texels.
    #[must_use]
    #[cfg(any(test, feature = "internals"))]
    pub const fn size(&self) -> u32 {
        self.size
    }

    /// Smallest region side a light gets before it is evicted.
    #[must_use]
    #[cfg(any(test, feature = "internals"))]
    pub const fn min_side(&self) -> u32 {
        self.min_side
    }

    /// Places this frame's requests in the atlas. Never fails: what does not fit is degraded
    /// or evicted.
    ///
    /// 1. Lights that asked last frame but not now free their regions.
    /// 2. A light whose last grant has the same side and face count keeps its rects.
    /// 3. Other lights free their old regions and get new ones, most important first.
    /// 4. If one of those allocations fails, a global fit packs all requests afresh into an
    ///    empty atlas: the least important light above the minimum side is halved, one step at
    ///    a time, and once every light is at the minimum side the least important lights are
    ///    evicted, until everything packs (largest sides first). Every grant is then moved.
    /// 5. If the requests (light, faces, side) equal those of the last global fit that degraded
    ///    or evicted something, that fit's result is reused as is.
    ///
    /// Later requests of a light id already seen this frame are ignored.
    pub fn plan(&mut self, requests: &[ShadowRequest]) -> AtlasPlan {
        let wanted = self.clean(requests);
        if let Some(plan) = self.reuse_fit(&wanted) {
            return plan;
        }
        self.memo = None;
        self.free_absent(&wanted);
        match self.incremental(&wanted) {
            Some(plan) => plan,
            None => self.global_fit(&wanted),
        }
    }

    /// First request of each light, with faces and side made usable.
    fn clean(&self, requests: &[ShadowRequest]) -> Vec<Wanted> {
        let mut seen = BTreeSet::new();
        requests
            .iter()
            .filter(|request| seen.insert(request.light))
            .map(|request| Wanted {
                request: *request,
                faces: request.faces.max(1),
                side: request.side.max(self.min_side),
                importance: if request.importance.is_nan() {
                    f32::NEG_INFINITY
                } else {
                    request.importance
                },
            })
            .collect()
    }

    /// Rule 5: the same requests as the last degrading fit get that fit's regions again.
    fn reuse_fit(&self, wanted: &[Wanted]) -> Option<AtlasPlan> {
        let memo = self.memo.as_ref()?;
        if memo.key != fit_key(wanted) {
            return None;
        }
        Some(AtlasPlan {
            grants: self.grants(wanted, |_| false),
            degraded: memo.degraded.clone(),
            evicted: memo.evicted.clone(),
            repacked: false,
        })
    }

    /// Rule 1: frees the regions of lights that no longer ask.
    fn free_absent(&mut self, wanted: &[Wanted]) {
        let asking: BTreeSet<u32> = wanted.iter().map(|w| w.request.light).collect();
        let gone: Vec<u32> = self
            .held
            .keys()
            .copied()
            .filter(|light| !asking.contains(light))
            .collect();
        for light in gone {
            if let Some(held) = self.held.remove(&light) {
                release(&mut self.allocator, &held.ids);
            }
        }
    }

    /// Rules 2 and 3: keeps unchanged grants, reallocates the others most important first.
    /// `None` when an allocation fails (the state is then half-updated; the global fit that
    /// follows replaces all of it).
    fn incremental(&mut self, wanted: &[Wanted]) -> Option<AtlasPlan> {
        let mut fresh = Vec::new();
        for w in wanted {
            let light = w.request.light;
            let keep = self
                .held
                .get(&light)
                .is_some_and(|held| held.side == w.side && held.rects.len() == w.faces as usize);
            if !keep {
                if let Some(old) = self.held.remove(&light) {
                    release(&mut self.allocator, &old.ids);
                }
                fresh.push(*w);
            }
        }
        // Stable sort: among equal importance, request order.
        fresh.sort_by(|a, b| b.importance.total_cmp(&a.importance));
        let mut regions: u64 = self.held.values().map(|held| held.rects.len() as u64).sum();
        for w in &fresh {
            regions += u64::from(w.faces);
            if regions > MAX_REGIONS {
                return None;
            }
            let held = allocate(&mut self.allocator, w.faces, w.side)?;
            self.held.insert(w.request.light, held);
        }
        let moved: BTreeSet<u32> = fresh.iter().map(|w| w.request.light).collect();
        Some(AtlasPlan {
            grants: self.grants(wanted, |light| moved.contains(&light)),
            ..AtlasPlan::default()
        })
    }

    /// Rule 4: degrades and evicts until all remaining requests pack into a fresh allocator,
    /// which then replaces the current one.
    fn global_fit(&mut self, wanted: &[Wanted]) -> AtlasPlan {
        let mut fit = Fit::new(wanted, self.min_side, self.size);
        let (allocator, held) = loop {
            if fit.may_fit()
                && let Some(packed) = fit.pack(self.size)
            {
                break packed;
            }
            if !fit.shrink() {
                // Nothing left to degrade or evict means nothing is left at all, and an empty
                // fit always packs; this only keeps the loop total.
                break (empty_allocator(self.size), BTreeMap::new());
            }
        };
        self.allocator = allocator;
        self.held = held;
        let (degraded, evicted) = fit.outcome();
        if !degraded.is_empty() || !evicted.is_empty() {
            self.memo = Some(FitMemo {
                key: fit_key(wanted),
                degraded: degraded.clone(),
                evicted: evicted.clone(),
            });
        }
        AtlasPlan {
            grants: self.grants(wanted, |_| true),
            degraded,
            evicted,
            repacked: true,
        }
    }

    /// Grants of the requesting lights that hold regions, in request order.
    fn grants(&self, wanted: &[Wanted], moved: impl Fn(u32) -> bool) -> Vec<ShadowGrant> {
        wanted
            .iter()
            .filter_map(|w| {
                let light = w.request.light;
                self.held.get(&light).map(|held| ShadowGrant {
                    light,
                    side: held.side,
                    rects: held.rects.clone(),
                    moved: moved(light),
                })
            })
            .collect()
    }
}
