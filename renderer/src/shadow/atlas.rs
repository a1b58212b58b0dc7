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

use std::collections::{BTreeMap, BTreeSet};

use etagere::{AllocId, AllocatorOptions, AtlasAllocator, size2};

/// Largest atlas side [`ShadowAtlas::new`] accepts: etagere needs sides below `u16::MAX` and an
/// area that fits an `i32`.
pub const MAX_ATLAS_SIZE: u32 = 32768;

/// Most columns of a global fit's allocator: each column starts as one etagere shelf, and
/// shelves are indexed with `u16` too.
const MAX_COLUMNS: u32 = 1024;

/// Most regions held at once. etagere indexes its items with `u16`, and each region can split
/// one free item in two, so the count stays well below that.
const MAX_REGIONS: u64 = 16384;

/// Which light and what it needs, for one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowRequest {
    /// Stable id of the light (the same light keeps its id from frame to frame).
    pub light: u32,
    /// Number of square regions: 1 (spot), 6 (point, cube faces) or 4 (directional cascades).
    /// Zero is treated as one.
    pub faces: u32,
    /// Desired power-of-two side of each region, in texels (after hysteresis). Sides below the
    /// atlas' minimum side are raised to it.
    pub side: u32,
    /// Larger is more important; the directional light uses `f32::INFINITY`. NaN counts as
    /// `f32::NEG_INFINITY` (least important).
    pub importance: f32,
}

/// A square region of the atlas, in atlas texels (`x`, `y`: top-left corner).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AtlasRect {
    /// Left column.
    pub x: u32,
    /// Top row.
    pub y: u32,
    /// Side in texels.
    pub side: u32,
}

/// What a light got this frame.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ShadowGrant {
    /// Stable id of the light.
    pub light: u32,
    /// Side of each region (may be smaller than asked, see [`AtlasPlan::degraded`]).
    pub side: u32,
    /// One region per face, in face order.
    pub rects: Vec<AtlasRect>,
    /// The rects or side differ from last frame's grant, or the light had none: its cached
    /// depth is invalid and must be redrawn.
    pub moved: bool,
}

/// The outcome of [`ShadowAtlas::plan`] for one frame.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct AtlasPlan {
    /// Lights that got a shadow, in request order.
    pub grants: Vec<ShadowGrant>,
    /// `(light, asked side, granted side)` of lights that got a smaller side than they asked.
    pub degraded: Vec<(u32, u32, u32)>,
    /// Lights that asked and got no shadow, in request order.
    pub evicted: Vec<u32>,
    /// The atlas was packed afresh this frame (every grant is then `moved`).
    pub repacked: bool,
}

/// The regions a light holds.
#[derive(Debug, Clone)]
struct Held {
    side: u32,
    rects: Vec<AtlasRect>,
    ids: Vec<AllocId>,
}

/// A request after clean-up: faces and side as used for allocation, plus the raw request.
#[derive(Debug, Clone, Copy)]
struct Wanted {
    request: ShadowRequest,
    faces: u32,
    side: u32,
    importance: f32,
}

impl Wanted {
    /// Texels of all faces at `side` (u128: `faces × side²` of any `u32` inputs fits, and so
    /// does any sum of them).
    fn area(&self, side: u32) -> u128 {
        u128::from(self.faces) * u128::from(side) * u128::from(side)
    }
}

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
    pub const fn size(&self) -> u32 {
        self.size
    }

    /// Smallest region side a light gets before it is evicted.
    #[must_use]
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

/// One light in a global fit.
#[derive(Debug, Clone, Copy)]
struct FitEntry {
    wanted: Wanted,
    side: u32,
    alive: bool,
}

/// State of a global fit: the sides so far, and the order in which lights give way.
#[derive(Debug)]
struct Fit {
    entries: Vec<FitEntry>,
    /// Indices into `entries`, least important first (among equals, later requests first).
    order: Vec<usize>,
    /// Entries of `order` before this one are at the minimum side (or evicted).
    degrade_cursor: usize,
    /// Entries of `order` before this one are evicted.
    evict_cursor: usize,
    min_side: u32,
    area: u128,
    regions: u64,
    atlas_area: u128,
}

impl Fit {
    fn new(wanted: &[Wanted], min_side: u32, size: u32) -> Self {
        let entries: Vec<FitEntry> = wanted
            .iter()
            .map(|w| FitEntry {
                wanted: *w,
                side: w.side,
                alive: true,
            })
            .collect();
        let mut order: Vec<usize> = (0..entries.len()).rev().collect();
        order.sort_by(|&a, &b| {
            entries[a]
                .wanted
                .importance
                .total_cmp(&entries[b].wanted.importance)
        });
        Self {
            area: entries.iter().map(|e| e.wanted.area(e.side)).sum(),
            regions: entries.iter().map(|e| u64::from(e.wanted.faces)).sum(),
            entries,
            order,
            degrade_cursor: 0,
            evict_cursor: 0,
            min_side,
            atlas_area: u128::from(size) * u128::from(size),
        }
    }

    /// Quick necessary conditions: total area and region count.
    fn may_fit(&self) -> bool {
        self.area <= self.atlas_area && self.regions <= MAX_REGIONS
    }

    /// One step: halves the least important side above the minimum, or else evicts the least
    /// important light. `false` when nothing is left.
    fn shrink(&mut self) -> bool {
        while let Some(&index) = self.order.get(self.degrade_cursor) {
            let entry = &mut self.entries[index];
            if entry.side > self.min_side {
                let new_side = (entry.side / 2).max(self.min_side);
                self.area = self.area - entry.wanted.area(entry.side) + entry.wanted.area(new_side);
                entry.side = new_side;
                return true;
            }
            self.degrade_cursor += 1;
        }
        let Some(&index) = self.order.get(self.evict_cursor) else {
            return false;
        };
        self.evict_cursor += 1;
        let entry = &mut self.entries[index];
        entry.alive = false;
        self.area -= entry.wanted.area(entry.side);
        self.regions -= u64::from(entry.wanted.faces);
        true
    }

    /// Packs the living entries, largest sides first, into a fresh allocator.
    fn pack(&self, size: u32) -> Option<(AtlasAllocator, BTreeMap<u32, Held>)> {
        let mut living: Vec<&FitEntry> = self.entries.iter().filter(|e| e.alive).collect();
        // Stable: among equal sides, more important first, then request order.
        living.sort_by(|a, b| {
            b.side
                .cmp(&a.side)
                .then(b.wanted.importance.total_cmp(&a.wanted.importance))
        });
        // Columns as wide as the largest side: each size class then leaves at most one
        // partly filled shelf per column instead of one across the whole atlas, and smaller
        // squares stack into narrow columns instead of wasting the height of a tall shelf.
        // On 8192² with mixed 64..2048 sides this packs 96-99% of the area instead of 70-85%.
        let largest = living.first().map_or(size, |e| e.side).clamp(1, size);
        let options = AllocatorOptions {
            num_columns: side_i32((size / largest).min(MAX_COLUMNS)),
            ..AllocatorOptions::default()
        };
        let mut allocator =
            AtlasAllocator::with_options(size2(side_i32(size), side_i32(size)), &options);
        let mut held = BTreeMap::new();
        for entry in living {
            let regions = allocate(&mut allocator, entry.wanted.faces, entry.side)?;
            held.insert(entry.wanted.request.light, regions);
        }
        Some((allocator, held))
    }

    /// `(degraded, evicted)` in request order.
    fn outcome(&self) -> (Vec<(u32, u32, u32)>, Vec<u32>) {
        let degraded = self
            .entries
            .iter()
            .filter(|e| e.alive && e.side < e.wanted.side)
            .map(|e| (e.wanted.request.light, e.wanted.request.side, e.side))
            .collect();
        let evicted = self
            .entries
            .iter()
            .filter(|e| !e.alive)
            .map(|e| e.wanted.request.light)
            .collect();
        (degraded, evicted)
    }
}

/// `(light, faces, side)` of the raw requests, sorted by light.
fn fit_key(wanted: &[Wanted]) -> Vec<(u32, u32, u32)> {
    let mut key: Vec<_> = wanted
        .iter()
        .map(|w| (w.request.light, w.request.faces, w.request.side))
        .collect();
    key.sort_unstable();
    key
}

/// `size` as etagere's `i32`; sides are at most [`MAX_ATLAS_SIZE`] by construction here, and
/// anything larger saturates (and then fails to allocate instead of wrapping).
fn side_i32(side: u32) -> i32 {
    i32::try_from(side).unwrap_or(i32::MAX)
}

/// A fresh allocator covering the whole `size`² atlas.
fn empty_allocator(size: u32) -> AtlasAllocator {
    AtlasAllocator::new(size2(side_i32(size), side_i32(size)))
}

/// Allocates `faces` regions of `side`²; on failure frees what it took and returns `None`.
fn allocate(allocator: &mut AtlasAllocator, faces: u32, side: u32) -> Option<Held> {
    let mut held = Held {
        side,
        rects: Vec::new(),
        ids: Vec::new(),
    };
    for _ in 0..faces {
        let Some(allocation) = allocator.allocate(size2(side_i32(side), side_i32(side))) else {
            release(allocator, &held.ids);
            return None;
        };
        // etagere may hand out a slightly larger rectangle (shelf and item rounding); the
        // region is its top-left `side`² corner. Its corner is never negative.
        let min = allocation.rectangle.min;
        held.rects.push(AtlasRect {
            x: min.x.unsigned_abs(),
            y: min.y.unsigned_abs(),
            side,
        });
        held.ids.push(allocation.id);
    }
    Some(held)
}

/// Frees regions this allocator handed out (each id exactly once: callers drop the `Held`).
fn release(allocator: &mut AtlasAllocator, ids: &[AllocId]) {
    for &id in ids {
        allocator.deallocate(id);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SIZE: u32 = 8192;
    const MIN: u32 = 64;

    fn spot(light: u32, side: u32, importance: f32) -> ShadowRequest {
        ShadowRequest {
            light,
            faces: 1,
            side,
            importance,
        }
    }

    fn point(light: u32, side: u32, importance: f32) -> ShadowRequest {
        ShadowRequest {
            light,
            faces: 6,
            side,
            importance,
        }
    }

    fn directional(light: u32, side: u32) -> ShadowRequest {
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
            assert!(
                grant.side >= atlas.min_side() && grant.side <= request.side.max(atlas.min_side())
            );
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

    fn plan(atlas: &mut ShadowAtlas, requests: &[ShadowRequest]) -> AtlasPlan {
        let plan = atlas.plan(requests);
        check(atlas, requests, &plan);
        plan
    }

    fn grant(plan: &AtlasPlan, light: u32) -> &ShadowGrant {
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
    fn degrades_least_important_first() {
        let mut atlas = ShadowAtlas::new(1024, MIN);
        let requests = [spot(1, 1024, 3.0), spot(2, 1024, 2.0), spot(3, 1024, 1.0)];
        let plan = plan(&mut atlas, &requests);
        assert!(plan.repacked && plan.evicted.is_empty());
        assert!(plan.grants.iter().all(|g| g.moved));
        // Light 3 goes to the minimum, then light 2, and only then light 1 is halved once.
        assert_eq!(grant(&plan, 3).side, 64);
        assert_eq!(grant(&plan, 2).side, 64);
        assert_eq!(grant(&plan, 1).side, 512);
        assert_eq!(
            plan.degraded,
            vec![(1, 1024, 512), (2, 1024, 64), (3, 1024, 64)]
        );
    }

    #[test]
    fn evicts_least_important_once_all_are_at_the_minimum() {
        // 256² holds sixteen 64² regions; three point lights need eighteen.
        let mut atlas = ShadowAtlas::new(256, MIN);
        let requests = [point(1, 128, 1.0), point(2, 128, 3.0), point(3, 128, 2.0)];
        let plan = plan(&mut atlas, &requests);
        assert_eq!(plan.evicted, vec![1]);
        assert_eq!(plan.degraded, vec![(2, 128, 64), (3, 128, 64)]);
        assert!(plan.repacked);
    }

    #[test]
    fn directional_is_degraded_and_evicted_last() {
        let mut atlas = ShadowAtlas::new(4096, MIN);
        let requests = [spot(1, 4096, 5.0), directional(9, 1024), spot(2, 4096, 1.0)];
        let roomy = plan(&mut atlas, &requests);
        assert_eq!(roomy.degraded, vec![(1, 4096, 2048), (2, 4096, 64)]);
        assert_eq!(grant(&roomy, 9).side, 1024);
        // Far too little room: only the directional light survives.
        let mut tiny = ShadowAtlas::new(128, MIN);
        let requests = [spot(1, 64, 5.0), directional(9, 2048), spot(2, 2048, 1.0)];
        let full = plan(&mut tiny, &requests);
        assert_eq!(full.evicted, vec![1, 2]);
        assert_eq!(full.degraded, vec![(9, 2048, 64)]);
    }

    #[test]
    fn oversize_requests_are_degraded() {
        let mut atlas = ShadowAtlas::new(1024, MIN);
        // 6 × 1024² does not fit 1024²; 6 × 256² does (two shelves of four).
        let plan_a = plan(&mut atlas, &[point(1, 1024, 1.0)]);
        assert_eq!(plan_a.degraded, vec![(1, 1024, 256)]);
        // A single region larger than the atlas.
        let plan_b = plan(&mut atlas, &[spot(2, 1 << 20, 1.0)]);
        assert_eq!(plan_b.degraded, vec![(2, 1 << 20, 1024)]);
        // Larger than anything: evicted.
        let huge = ShadowRequest {
            light: 3,
            faces: u32::MAX,
            side: u32::MAX,
            importance: 1.0,
        };
        let plan_c = plan(&mut atlas, &[huge, ShadowRequest { light: 4, ..huge }]);
        assert_eq!(plan_c.evicted, vec![3, 4]);
        assert!(plan_c.grants.is_empty());
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

    #[test]
    fn a_full_atlas_reuses_its_fit() {
        let mut atlas = ShadowAtlas::new(2048, MIN);
        let requests = [
            directional(0, 1024),
            point(1, 512, 2.0),
            point(2, 512, 1.0),
            spot(3, 1024, 0.5),
        ];
        let first = plan(&mut atlas, &requests);
        assert!(first.repacked && !first.degraded.is_empty());
        for _ in 0..3 {
            let again = plan(&mut atlas, &requests);
            assert!(!again.repacked);
            assert_eq!(
                (&again.degraded, &again.evicted),
                (&first.degraded, &first.evicted)
            );
            for (a, b) in first.grants.iter().zip(&again.grants) {
                assert_eq!((a.light, a.side, &a.rects), (b.light, b.side, &b.rects));
                assert!(!b.moved);
            }
        }
        // Same requests in another order and importance still match the fit.
        let reordered = [
            spot(3, 1024, 7.0),
            point(2, 512, 1.0),
            point(1, 512, 2.0),
            directional(0, 1024),
        ];
        let again = plan(&mut atlas, &reordered);
        assert!(!again.repacked && again.grants.iter().all(|g| !g.moved));
        assert_eq!(again.grants[0].light, 3);
        // A different request goes through the normal path again.
        let changed = [
            directional(0, 1024),
            point(1, 512, 2.0),
            point(2, 256, 1.0),
            spot(3, 1024, 0.5),
        ];
        let third = plan(&mut atlas, &changed);
        assert!(third.repacked);
    }

    #[test]
    fn fragmentation_falls_back_to_a_repack_without_degrading() {
        // Sixteen 256² regions fill a 1024² atlas in four shelves of four.
        let mut atlas = ShadowAtlas::new(1024, MIN);
        let sixteen: Vec<ShadowRequest> = (0..16).map(|light| spot(light, 256, 1.0)).collect();
        let first = plan(&mut atlas, &sixteen);
        assert_eq!(
            grant(&first, 4).rects[0],
            AtlasRect {
                x: 0,
                y: 256,
                side: 256
            }
        );
        assert_eq!(
            grant(&first, 12).rects[0],
            AtlasRect {
                x: 0,
                y: 768,
                side: 256
            }
        );
        // Rows 1 and 3 leave: half the atlas is free, but only as two 256-high strips, so a
        // 512² region does not fit until everything is packed afresh.
        let mut next: Vec<ShadowRequest> = (0..4)
            .chain(8..12)
            .map(|light| spot(light, 256, 1.0))
            .collect();
        next.push(spot(100, 512, 1.0));
        let second = plan(&mut atlas, &next);
        assert!(second.repacked && second.grants.iter().all(|g| g.moved));
        assert!(second.degraded.is_empty() && second.evicted.is_empty());
        // Nothing was degraded, so an identical next frame keeps everything by rule 2.
        let third = plan(&mut atlas, &next);
        assert!(!third.repacked && third.grants.iter().all(|g| !g.moved));
        assert_eq!(
            second.grants,
            third
                .grants
                .iter()
                .map(|g| ShadowGrant {
                    moved: true,
                    ..g.clone()
                })
                .collect::<Vec<_>>()
        );
    }

    #[test]
    fn a_global_fit_fills_the_atlas_with_mixed_sides() {
        // Exactly the atlas' area: three 512² and four 256² regions in 1024². Allocated
        // smallest first into full-width shelves this does not fit; the global fit packs it
        // into 512-wide columns without degrading anything.
        let mut atlas = ShadowAtlas::new(1024, MIN);
        let mut requests: Vec<ShadowRequest> = (0..4).map(|l| spot(l, 256, 2.0)).collect();
        requests.extend((4..7).map(|l| spot(l, 512, 1.0)));
        let first = plan(&mut atlas, &requests);
        assert!(first.repacked);
        assert!(first.degraded.is_empty() && first.evicted.is_empty());
        let again = plan(&mut atlas, &requests);
        assert!(!again.repacked && again.grants.iter().all(|g| !g.moved));
    }

    /// Small deterministic generator so the stress test needs no crate.
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self, below: u32) -> u32 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((self.0 >> 33) % u64::from(below)) as u32
        }
    }

    #[test]
    fn random_frames_keep_every_invariant() {
        let mut rng = Lcg(7);
        let mut atlas = ShadowAtlas::new(4096, MIN);
        let mut lights: Vec<ShadowRequest> = Vec::new();
        let (mut repacks, mut steady, mut degraded) = (0, 0, 0);
        for frame in 0..400 {
            for light in &mut lights {
                if rng.next(10) == 0 {
                    light.side = MIN << rng.next(6);
                }
            }
            if rng.next(4) == 0 && lights.len() < 40 {
                let faces = [1, 1, 6, 4][rng.next(4) as usize];
                lights.push(ShadowRequest {
                    light: frame,
                    faces,
                    side: MIN << rng.next(6),
                    importance: rng.next(100) as f32,
                });
            }
            if rng.next(6) == 0 && !lights.is_empty() {
                let index = rng.next(lights.len() as u32) as usize;
                lights.remove(index);
            }
            let first = plan(&mut atlas, &lights);
            let second = plan(&mut atlas, &lights);
            assert!(
                !second.repacked && second.grants.iter().all(|g| !g.moved),
                "frame {frame}"
            );
            for (a, b) in first.grants.iter().zip(&second.grants) {
                assert_eq!((a.light, &a.rects), (b.light, &b.rects));
            }
            repacks += usize::from(first.repacked);
            steady += usize::from(!first.repacked);
            degraded += usize::from(!first.degraded.is_empty());
        }
        assert!(
            repacks > 0 && steady > 0 && degraded > 0,
            "{repacks} repacks, {steady} steady, {degraded} degraded"
        );
    }
}
