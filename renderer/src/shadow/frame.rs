//! One frame's shadow plan: which lights ask for a shadow and how large
//! ([`super::resolution`]), where they go ([`super::atlas`]), their views ([`super::views`]),
//! and what each region needs drawn ([`super::cache`]). GPU-free: the shadow pass turns the plan
//! into draws.

use std::collections::HashMap;

use glam::{Mat4, Vec4};

use super::atlas::{AtlasRect, ShadowAtlas, ShadowGrant, ShadowRequest};
use super::cache::{
    CacheCounts, Caster, CasterChanges, RegionInput, RegionKey, RegionPlan, ShadowCache,
};
use super::resolution::{Hysteresis, desired_log2, projected_radius_px};
use super::views::{CameraLens, LightView, cascade_views, cube_views, spot_view};
use super::{ShadowConfig, ShadowReport};
use crate::scene::{Aabb, LightKind, SceneLight};

/// Guard band of cube faces, in texels: the PCF footprint (a 3×3 grid of bilinear taps, ±1.5
/// texels) plus half a texel.
pub const CUBE_GUARD: u32 = 2;
/// Light ids of directional lights start here (punctual lights use their index).
pub const DIRECTIONAL_ID: u32 = 1 << 31;

/// What a frame's plan is made from.
#[derive(Debug, Clone, Copy)]
pub struct PlanInputs<'a> {
    pub config: &'a ShadowConfig,
    /// Point and spot lights, in the light buffer's order.
    pub punctual: &'a [SceneLight],
    pub directional: &'a [SceneLight],
    pub camera_view: Mat4,
    pub camera_projection: Mat4,
    pub camera_near: f32,
    pub viewport_height: f32,
    /// Bounds of every caster (the scene), for infinite ranges and cascade depth.
    pub scene_bounds: Aabb,
    pub casters: &'a [Caster],
    /// Which casters changed since the last plan, where the caller knows.
    pub caster_changes: CasterChanges<'a>,
}

/// One view as the GPU record (`shadow_atlas::ShadowView`) needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewRecord {
    pub view: LightView,
    /// The region in atlas UV: corner and size.
    pub rect_uv: Vec4,
    /// 1, 6 or 4 on a light's first view (what follows it), repeated on the others.
    pub faces: u32,
}

/// A frame's plan.
#[derive(Debug, Clone, Default)]
pub struct FramePlan {
    /// Every region of a shadowed light, in `views` order, with its work.
    pub regions: Vec<RegionPlan>,
    /// The GPU view records, region for region.
    pub views: Vec<ViewRecord>,
    /// Per punctual light: index of its first view, or `None`.
    pub punctual_shadow: Vec<Option<u32>>,
    pub directional_shadow: Vec<Option<u32>>,
    pub report: ShadowReport,
}

impl FramePlan {
    /// Whether any region needs a draw or a copy.
    #[cfg(any(test, feature = "internals"))]
    pub fn has_work(&self) -> bool {
        let c = self.report.cache;
        c.redrawn + c.copied > 0
    }
}

/// The shadow state across frames: hysteresis per light, the atlas allocation, the cache.
#[derive(Debug, Default)]
pub struct ShadowPlanner {
    atlas: Option<ShadowAtlas>,
    hysteresis: HashMap<u32, Hysteresis>,
    cache: ShadowCache,
}

impl ShadowPlanner {
    /// Forgets the cache (the atlases were recreated) but keeps resolutions.
    #[cfg(any(test, feature = "internals"))]
    pub fn invalidate(&mut self) {
        self.cache.clear();
        self.atlas = None;
    }

    /// Plans one frame.
    pub fn plan(&mut self, input: &PlanInputs<'_>) -> FramePlan {
        let c = input.config;
        let requests = self.requests(input);
        let atlas = self
            .atlas
            .get_or_insert_with(|| ShadowAtlas::new(c.atlas_size, c.min_resolution));
        let atlas_plan = atlas.plan(&requests);
        let mut plan = FramePlan {
            punctual_shadow: vec![None; input.punctual.len()],
            directional_shadow: vec![None; input.directional.len()],
            ..Default::default()
        };
        let mut regions = Vec::new();
        for grant in &atlas_plan.grants {
            let first = plan.views.len() as u32;
            let views = light_views(input, grant);
            for (face, (view, rect)) in views.iter().zip(&grant.rects).enumerate() {
                plan.views.push(ViewRecord {
                    view: *view,
                    rect_uv: rect_uv(*rect, c.atlas_size),
                    faces: grant.rects.len() as u32,
                });
                regions.push(RegionInput {
                    key: RegionKey {
                        light: grant.light,
                        face: face as u32,
                    },
                    rect: *rect,
                    view: *view,
                });
            }
            let slot = if grant.light >= DIRECTIONAL_ID {
                plan.directional_shadow
                    .get_mut((grant.light - DIRECTIONAL_ID) as usize)
            } else {
                plan.punctual_shadow.get_mut(grant.light as usize)
            };
            if let Some(s) = slot {
                *s = Some(first);
            }
        }
        plan.regions =
            self.cache
                .plan_changes(&regions, input.casters, c.cache, input.caster_changes);
        let mut histogram: HashMap<u32, u32> = HashMap::new();
        for g in &atlas_plan.grants {
            *histogram.entry(g.side).or_default() += g.rects.len() as u32;
        }
        let mut resolution_histogram: Vec<(u32, u32)> = histogram.into_iter().collect();
        resolution_histogram.sort_unstable();
        plan.report = ShadowReport {
            requested: requests.len() as u32,
            shadowed: atlas_plan.grants.len() as u32,
            resolution_histogram,
            degraded: atlas_plan.degraded,
            evicted: atlas_plan.evicted,
            repacked: atlas_plan.repacked,
            cache: CacheCounts::of(&plan.regions),
            regions: regions.iter().map(|r| (r.key, r.rect)).collect(),
            cpu_plan_ms: 0.0,
        };
        plan
    }

    /// The frame's requests: every light that casts a shadow and can be seen lighting
    /// something, sized by its influence on screen (with hysteresis).
    fn requests(&mut self, input: &PlanInputs<'_>) -> Vec<ShadowRequest> {
        let c = input.config;
        let mut requests = Vec::new();
        for (i, l) in input.punctual.iter().enumerate() {
            if !l.casts_shadow {
                continue;
            }
            let radius = reach(l, &input.scene_bounds);
            let px = projected_radius_px(
                l.position,
                radius,
                input.camera_view,
                input.camera_projection,
                input.viewport_height,
            );
            if px <= 0.0 {
                continue;
            }
            let point = matches!(l.kind, LightKind::Point);
            // A cube face spans a quarter of the light's circle of influence on screen.
            let wanted = desired_log2(px, c.min_resolution, c.max_resolution) - f32::from(point);
            let side = self
                .hysteresis
                .entry(i as u32)
                .or_default()
                .update(wanted.max((c.min_resolution.max(1) as f32).log2()));
            requests.push(ShadowRequest {
                light: i as u32,
                faces: if point { 6 } else { 1 },
                side,
                importance: px,
            });
        }
        for (i, l) in input.directional.iter().enumerate() {
            if l.casts_shadow {
                requests.push(ShadowRequest {
                    light: DIRECTIONAL_ID + i as u32,
                    faces: 4,
                    side: c.cascade_resolution,
                    importance: f32::INFINITY,
                });
            }
        }
        requests
    }
}

/// The views of a granted light, face for face.
fn light_views(input: &PlanInputs<'_>, grant: &ShadowGrant) -> Vec<LightView> {
    if grant.light >= DIRECTIONAL_ID {
        let Some(l) = input
            .directional
            .get((grant.light - DIRECTIONAL_ID) as usize)
        else {
            return Vec::new();
        };
        let world_from_view = input.camera_view.inverse();
        return cascade_views(
            world_from_view,
            CameraLens::of(input.camera_projection),
            input.camera_near,
            input.config.directional_distance,
            l.direction,
            grant.side,
            &input.scene_bounds,
        )
        .to_vec();
    }
    let Some(l) = input.punctual.get(grant.light as usize) else {
        return Vec::new();
    };
    let range = reach(l, &input.scene_bounds);
    match l.kind {
        LightKind::Spot { outer_cone, .. } => {
            vec![spot_view(
                l.position,
                l.direction,
                outer_cone,
                range,
                grant.side,
            )]
        }
        _ => cube_views(l.position, range, grant.side, CUBE_GUARD).to_vec(),
    }
}

/// A light's reach: its range, but no farther than the scene's farthest corner (nothing beyond
/// can receive or cast its shadow), which also bounds an infinite range. A range far larger
/// than the scene (the effective range of a bright light without one) would otherwise push
/// the near plane past the casters and spread depth precision over empty space.
pub fn reach(l: &SceneLight, scene: &Aabb) -> f32 {
    let far = (scene.min - l.position)
        .abs()
        .max((scene.max - l.position).abs())
        .length()
        .max(1.0e-3);
    l.range.map_or(far, |r| r.min(far))
}

/// `rect` in UV of an `atlas`-texel atlas.
fn rect_uv(rect: AtlasRect, atlas: u32) -> Vec4 {
    let s = atlas.max(1) as f32;
    Vec4::new(
        rect.x as f32 / s,
        rect.y as f32 / s,
        rect.side as f32 / s,
        rect.side as f32 / s,
    )
}
