//! A frame's shadow casts: one `shadow_caster::Cast` record (draw, region view) per caster drawn
//! into a region, in the order the recording draws them, so the caster programs find both the
//! draw's record and the region's clip matrix from the instance index alone.

use shaders_gen::shadow::shadow_caster::Cast;

use crate::shadow::cache::{RegionPlan, RegionWork};

/// The casts of a frame's regions, and where each region's run of them starts.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CastList {
    pub casts: Vec<Cast>,
    /// Per region (in plan order): the first cast of its static-cache redraw and the first of
    /// its draw into the shadow atlas (dynamic casters over a composed region, or every caster
    /// of a direct one).
    pub first: Vec<[u32; 2]>,
}

impl CastList {
    /// The casts of `regions`, region `v` drawing through view `v`.
    pub fn new(regions: &[RegionPlan]) -> Self {
        let mut list = Self::default();
        for (view, region) in regions.iter().enumerate() {
            let view = view as u32;
            let (redrawn, atlas): (&[u32], &[u32]) = match &region.work {
                RegionWork::Untouched => (&[], &[]),
                RegionWork::Compose {
                    redraw_static,
                    static_casters,
                    dynamic_casters,
                } => (
                    if *redraw_static { static_casters } else { &[] },
                    dynamic_casters,
                ),
                RegionWork::Direct { casters } => (&[], casters),
            };
            let first_static = list.push(redrawn, view);
            let first_atlas = list.push(atlas, view);
            list.first.push([first_static, first_atlas]);
        }
        list
    }

    /// Appends a cast of every draw of `draws` through `view`; returns the first one's index.
    fn push(&mut self, draws: &[u32], view: u32) -> u32 {
        let first = self.casts.len() as u32;
        self.casts
            .extend(draws.iter().map(|&draw| Cast::new(draw, view)));
        first
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shadow::atlas::AtlasRect;
    use crate::shadow::cache::{RegionInput, RegionKey};
    use crate::shadow::views::cube_views;

    fn region(work: RegionWork) -> RegionPlan {
        RegionPlan {
            region: RegionInput {
                key: RegionKey { light: 0, face: 0 },
                rect: AtlasRect {
                    x: 0,
                    y: 0,
                    side: 64,
                },
                view: cube_views(glam::Vec3::ZERO, 10.0, 64, 2)[0],
            },
            work,
        }
    }

    #[test]
    fn casts_follow_the_recording_order_with_each_region_view() {
        let regions = [
            region(RegionWork::Direct {
                casters: vec![4, 7],
            }),
            region(RegionWork::Untouched),
            region(RegionWork::Compose {
                redraw_static: true,
                static_casters: vec![1, 2],
                dynamic_casters: vec![9],
            }),
            region(RegionWork::Compose {
                redraw_static: false,
                static_casters: vec![3],
                dynamic_casters: vec![5],
            }),
        ];
        let list = CastList::new(&regions);
        let pairs: Vec<(u32, u32)> = list.casts.iter().map(|c| (c.draw, c.view)).collect();
        assert_eq!(pairs, [(4, 0), (7, 0), (1, 2), (2, 2), (9, 2), (5, 3)]);
        assert_eq!(list.first, [[0, 0], [2, 2], [2, 4], [5, 5]]);
    }
}
