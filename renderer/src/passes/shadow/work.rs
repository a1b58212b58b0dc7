//! A frame's shadow work as the recording walks it: one item per region and atlas it draws
//! into (a region's static redraw into the static cache comes before its composition in the
//! shadow atlas), each naming the casters it draws, and, where the CPU lists the casters
//! itself (a device that cannot draw indirectly with a first instance), those lists.

use shaders_gen::shadow::shadow_caster::Cast;
use shaders_gen::shadow::shadow_cull::{ALL_CASTERS, DYNAMIC_CASTERS, STATIC_CASTERS};

use crate::shadow::atlas::AtlasRect;
use crate::shadow::cache::{Caster, RegionPlan, RegionWork};
use crate::shadow::region_test::RegionTest;

/// Which atlas an item draws into, and how the region starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// The static cache, cleared.
    ClearStatic,
    /// The shadow atlas, with the static cache's depth copied in.
    CopyStatic,
    /// The shadow atlas, cleared.
    Clear,
}

/// One region's draw into one atlas.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WorkItem {
    /// The region's index in the frame's plan (and its view's in the view buffers).
    pub view: u32,
    pub rect: AtlasRect,
    pub start: Start,
    /// `ALL_CASTERS`, `STATIC_CASTERS` or `DYNAMIC_CASTERS` of `shadow_cull`.
    pub casters: u32,
}

impl WorkItem {
    /// Whether it draws into the static cache.
    pub fn in_static_cache(&self) -> bool {
        self.start == Start::ClearStatic
    }

    /// Whether `c` is one of its casters (its instance static or dynamic as it asks).
    pub fn wants(&self, c: &Caster) -> bool {
        match self.casters {
            STATIC_CASTERS => !c.dynamic,
            DYNAMIC_CASTERS => c.dynamic,
            _ => true,
        }
    }
}

/// The work items of `regions`, in recording order.
pub fn work_items(regions: &[RegionPlan]) -> Vec<WorkItem> {
    let mut items = Vec::new();
    for (view, r) in regions.iter().enumerate() {
        let item = |start, casters| WorkItem {
            view: view as u32,
            rect: r.region.rect,
            start,
            casters,
        };
        match r.work {
            RegionWork::Untouched => {}
            RegionWork::Compose { redraw_static } => {
                if redraw_static {
                    items.push(item(Start::ClearStatic, STATIC_CASTERS));
                }
                items.push(item(Start::CopyStatic, DYNAMIC_CASTERS));
            }
            RegionWork::Direct => items.push(item(Start::Clear, ALL_CASTERS)),
        }
    }
    items
}

/// Casts listed on the CPU: one `Cast` (draw, region view) per caster an item draws, in item
/// order, and where each item's run starts.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CastList {
    pub casts: Vec<Cast>,
    /// Per item: its first cast and its cast count.
    pub runs: Vec<(u32, u32)>,
}

impl CastList {
    /// The casts of `items`: every caster an item wants that reaches its region (with
    /// `cull`; without, every caster it wants), tested one by one as `shadow_cull` does.
    pub fn new(items: &[WorkItem], regions: &[RegionPlan], casters: &[Caster], cull: bool) -> Self {
        let mut list = Self::default();
        for item in items {
            let test = RegionTest::new(regions[item.view as usize].region.view.clip_from_world);
            let first = list.casts.len() as u32;
            let drawn = casters
                .iter()
                .filter(|c| !c.bounds.is_empty() && item.wants(c))
                .filter(|c| !cull || test.reaches(&c.bounds));
            list.casts
                .extend(drawn.map(|c| Cast::new(c.draw, item.view)));
            list.runs.push((first, list.casts.len() as u32 - first));
        }
        list
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::scene::Aabb;
    use crate::shadow::cache::{RegionInput, RegionKey};
    use crate::shadow::views::cube_views;

    fn region(face: usize, work: RegionWork) -> RegionPlan {
        RegionPlan {
            region: RegionInput {
                key: RegionKey {
                    light: 0,
                    face: face as u32,
                },
                rect: AtlasRect {
                    x: 64 * face as u32,
                    y: 0,
                    side: 64,
                },
                view: cube_views(Vec3::ZERO, 10.0, 64, 2)[face],
            },
            work,
        }
    }

    #[test]
    fn items_follow_the_plan_and_lists_hold_what_each_item_wants_and_reaches() {
        // Faces 0 (+X), 1 (−X), 2, 3: direct, untouched, redrawn and composed, composed.
        let regions = [
            region(0, RegionWork::Direct),
            region(1, RegionWork::Untouched),
            region(
                2,
                RegionWork::Compose {
                    redraw_static: true,
                },
            ),
            region(
                3,
                RegionWork::Compose {
                    redraw_static: false,
                },
            ),
        ];
        let items = work_items(&regions);
        let summary: Vec<(u32, Start, u32)> =
            items.iter().map(|i| (i.view, i.start, i.casters)).collect();
        assert_eq!(
            summary,
            [
                (0, Start::Clear, ALL_CASTERS),
                (2, Start::ClearStatic, STATIC_CASTERS),
                (2, Start::CopyStatic, DYNAMIC_CASTERS),
                (3, Start::CopyStatic, DYNAMIC_CASTERS)
            ]
        );
        let cube = |draw, at: Vec3, dynamic| Caster {
            draw,
            bounds: Aabb {
                min: at - 0.5,
                max: at + 0.5,
            },
            dynamic,
            version: 0,
        };
        // +X static, +X dynamic, +Y (face 2) static and dynamic, −Y (face 3) dynamic, and
        // an empty box (a blended draw) on +X.
        let casters = [
            cube(10, Vec3::X * 4.0, false),
            cube(11, Vec3::X * 4.0, true),
            cube(12, Vec3::Y * 4.0, false),
            cube(13, Vec3::Y * 4.0, true),
            cube(14, Vec3::NEG_Y * 4.0, true),
            Caster {
                bounds: Aabb::EMPTY,
                ..cube(15, Vec3::X * 4.0, false)
            },
        ];
        let list = CastList::new(&items, &regions, &casters, true);
        let draws: Vec<(u32, u32)> = list.casts.iter().map(|c| (c.draw, c.view)).collect();
        assert_eq!(draws, [(10, 0), (11, 0), (12, 2), (13, 2), (14, 3)]);
        assert_eq!(list.runs, [(0, 2), (2, 1), (3, 1), (4, 1)]);
        // Without culling every caster an item wants, but never an empty box.
        let all = CastList::new(&items, &regions, &casters, false);
        assert_eq!(all.runs, [(0, 5), (5, 2), (7, 3), (10, 3)]);
    }
}
