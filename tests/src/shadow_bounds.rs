//! Tight shadow bounds for the shadow tests: where a shadow may be partial, predicted on the CPU
//! from geometry, and what every floor pixel outside that region must show.
//!
//! A shadow-map texel covers a patch of the floor whose size depends on the light's view, the
//! region's resolution and the angle the light meets the floor at: its *footprint*. The filter
//! reads the shadow map within a fixed number of texels of a point's projection, so a floor
//! point can be partly shadowed only where a point the ray cast judges the other way lies within
//! that many texels of it, measured in the texels of the view that shadows it
//! ([`texel_distance_to_flip`]). Outside that band a lit floor pixel must equal its unshadowed
//! value (acne shows as partly shadowed texels on lit floor) and a shadowed one must be black
//! (peter-panning shows as light between a caster's base and its shadow, or a shadow edge moved
//! away from where the ray cast puts it).
//!
//! The texel mapping comes from each region's `clip_from_world` and side, the view and
//! resolution the renderer chose; the lit/unlit verdicts come from
//! [`crate::shadow_scene::reaches`], the independent ray cast.

use glam::{Mat4, Vec2, Vec3};
use renderer::scene::SceneLight;

use crate::shadow_scene::{FLOOR_Y, occluders, reaches};

/// One shadow-map region of a light: its world → clip transform (reversed Z), side in texels,
/// and for a directional cascade the camera view depth where it ends (0 otherwise).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Region {
    pub clip_from_world: Mat4,
    pub side: u32,
    pub split_far: f32,
}

/// Fraction of a cascade's depth range over which it hands over to the next (dithered), as the
/// renderer documents it.
pub const CASCADE_BLEND: f32 = 0.15;

impl Region {
    /// Texel coordinates of world point `p` in this region, if `p` lies inside its clip volume.
    pub fn texel(&self, p: Vec3) -> Option<Vec2> {
        let c = self.clip_from_world * p.extend(1.0);
        if c.w <= 0.0 {
            return None;
        }
        let n = c.truncate() / c.w;
        let inside = n.x.abs() <= 1.0 && n.y.abs() <= 1.0 && (0.0..=1.0).contains(&n.z);
        inside.then(|| Vec2::new(n.x * 0.5 + 0.5, 0.5 - n.y * 0.5) * self.side as f32)
    }

    /// Texels per world unit along the floor at `p`, as the 2×2 derivative of texel
    /// coordinates with respect to the floor's `(x, z)` (columns), by central differences.
    pub fn floor_jacobian(&self, p: Vec3) -> Option<glam::Mat2> {
        let h = 1.0e-3;
        let d = |v: Vec3| Some((self.texel(p + v)? - self.texel(p - v)?) / (2.0 * h));
        Some(glam::Mat2::from_cols(d(Vec3::X * h)?, d(Vec3::Z * h)?))
    }

    /// Longest floor distance one texel spans at `p` (the footprint's long axis), world units.
    pub fn footprint(&self, p: Vec3) -> Option<f32> {
        let inv = self.floor_jacobian(p)?.inverse();
        Some(
            inv.x_axis.length().max(inv.y_axis.length()).max(
                // The diagonal directions, so a skewed footprint is not underestimated.
                ((inv.x_axis + inv.y_axis) / 2f32.sqrt())
                    .length()
                    .max(((inv.x_axis - inv.y_axis) / 2f32.sqrt()).length()),
            ),
        )
    }
}

/// Of `regions` (all of one light), the one that may shadow `p` with the coarsest texels there
/// (largest footprint). Any region whose clip volume holds `p` may, except that cascades (those
/// with a `split_far`) are limited to the one whose depth range holds `p`'s camera view depth
/// `view_depth`, and the next one in the last [`CASCADE_BLEND`] of that range. A point near a
/// cube-face edge lies in two faces, and may be shadowed by either.
pub fn coarsest_at(regions: &[Region], p: Vec3, view_depth: f32) -> Option<Region> {
    let mut start = 0.0;
    let mut allowed = Vec::new();
    for (i, r) in regions.iter().enumerate() {
        if r.split_far <= 0.0 {
            allowed.push(i);
            continue;
        }
        if view_depth <= r.split_far && allowed.is_empty() {
            allowed.push(i);
            if view_depth >= r.split_far - CASCADE_BLEND * (r.split_far - start) {
                allowed.push(i + 1);
            }
        }
        start = r.split_far;
    }
    allowed
        .into_iter()
        .filter_map(|i| regions.get(i))
        .filter_map(|r| Some((r.footprint(p)?, *r)))
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, r)| r)
}

/// Angles searched around a point.
const DIRECTIONS: usize = 48;
/// Radial step of the search, in texels.
const STEP: f32 = 0.125;

/// The distance, in texels of `region` at floor point `p`, from `p` to the nearest floor point
/// whose ray-cast verdict for `light` differs from `p`'s (`lit`), searched up to `limit` texels
/// along [`DIRECTIONS`] directions in texel space (steps of [`STEP`] texels, mapped back to the
/// floor through the inverse of the region's floor Jacobian at `p`); `None` when there is none
/// within `limit`. A point under a caster (inside its footprint on the floor) is never a flip:
/// next to a caster's lit wall the map holds the wall, which meets the floor at the contact line
/// and must not shadow the floor it stands on (acne there is what the depth bias prevents), and
/// next to a wall facing away the point is in shadow like its neighbours.
pub fn texel_distance_to_flip(
    region: &Region,
    light: &SceneLight,
    p: Vec3,
    lit: bool,
    limit: f32,
) -> Option<f32> {
    let inv = region.floor_jacobian(p)?.inverse();
    let mut best: Option<f32> = None;
    for k in 0..DIRECTIONS {
        let a = k as f32 / DIRECTIONS as f32 * std::f32::consts::TAU;
        let dir = Vec2::new(a.cos(), a.sin());
        let mut r = STEP;
        while r <= limit && best.is_none_or(|b| r < b) {
            let floor = inv * (dir * r);
            let q = Vec3::new(p.x + floor.x, FLOOR_Y, p.z + floor.y);
            if !under_caster(q) && reaches(light, q) != lit {
                best = Some(r);
                break;
            }
            r += STEP;
        }
    }
    best
}

/// Whether floor point `q` lies under a caster (inside its footprint).
fn under_caster(q: Vec3) -> bool {
    occluders()
        .iter()
        .any(|b| (b.min.x..=b.max.x).contains(&q.x) && (b.min.z..=b.max.z).contains(&q.z))
}

/// World distance on the floor from `p` to the nearest base outline (the footprint's border on
/// the floor) of an occluder: where a caster meets the floor, the contact line.
pub fn distance_to_contact(p: Vec3) -> f32 {
    occluders()
        .iter()
        .map(|b| {
            let dx = (b.min.x - p.x).max(p.x - b.max.x);
            let dz = (b.min.z - p.z).max(p.z - b.max.z);
            if dx <= 0.0 && dz <= 0.0 {
                (-dx).min(-dz)
            } else {
                Vec2::new(dx.max(0.0), dz.max(0.0)).length()
            }
        })
        .fold(f32::INFINITY, f32::min)
}

/// Partial-shadow band around a ray-cast shadow edge at floor point `p`, in texels of the view
/// that shadows it: the filter's reach (a 3×3 grid of bilinear taps one texel apart reads up to
/// 2 texels from the lookup point), the normal offset (the lookup point is lifted 1.5 texels
/// along the floor's normal, which moves its projection by 1.5 · sin θ texels, θ the angle
/// between the normal and the direction to the light), half a texel for the caster's
/// rasterisation into the map (a texel holds the depth at its centre), the search's step
/// ([`STEP`]: it overestimates a distance by up to one step), and a quarter texel for measuring
/// it through the projection linearised at `p` (at a cube-face edge the two faces' grids
/// differ; measured: 3 pixels on the seam light's −X/−Z edge 0.07 texels beyond the band
/// without it).
pub fn band_texels(light: &SceneLight, p: Vec3) -> f32 {
    let to_light = match light.kind {
        renderer::scene::LightKind::Directional => -light.direction,
        _ => light.position - p,
    }
    .normalize();
    let sin = (1.0 - to_light.y * to_light.y).max(0.0).sqrt();
    2.0 + 1.5 * sin + 0.5 + STEP + 0.25
}
/// How far [`texel_distance_to_flip`] searches, in texels: beyond the band, to measure how wide
/// partial shadows actually are.
pub const SEARCH_TEXELS: f32 = 8.0;
/// Largest channel difference outside the band: a lit floor pixel from its unshadowed value, a
/// shadowed one from black (no ambient light).
pub const TOLERANCE: u8 = 1;
/// Floor points within this world distance of a caster's base outline count as contact
/// points: about three texel footprints of the scene's views.
pub const CONTACT: f32 = 0.1;

/// One floor pixel outside the band that is not what the ray cast says.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wrong {
    pub x: u32,
    pub y: u32,
    pub p: Vec3,
    pub reference_lit: bool,
    /// Lit: largest channel difference from the unshadowed frame; unlit: largest channel.
    pub difference: u8,
    /// Distance to the nearest ray-cast flip, texels (`None`: beyond [`SEARCH_TEXELS`]).
    pub texels: Option<f32>,
}

/// A frame's shadows against the band rule.
#[derive(Debug, Clone)]
pub struct Tight {
    /// Floor pixels checked outside the band, lit and shadowed.
    pub lit: usize,
    pub shadowed: usize,
    /// Shadowed pixels checked within [`CONTACT`] of a caster's base.
    pub contact: usize,
    /// Floor pixels within the band (left out).
    pub in_band: usize,
    /// Checked pixels that are wrong: acne (reference lit) or leaks (reference unlit).
    pub wrong: Vec<Wrong>,
    /// Of the pixels that differ beyond [`TOLERANCE`] from the ray cast's verdict, the largest
    /// distance to a flip, in texels (how wide the partial shadow measured; infinity when one
    /// lies beyond the search).
    pub widest_partial: f32,
    /// Of the same pixels, the largest distance minus the pixel's band
    /// ([`band_texels`]): how close the widest partial shadow comes to its band (≤ 0 inside).
    pub closest_to_band: f32,
}

/// Checks `shadowed` and `unshadowed` (`w`×`h` RGBA8 frames through `camera`, `light` alone, no
/// ambient; `regions` its shadow views) against the band rule: every floor pixel farther than
/// [`band_texels`] from a ray-cast flip (in texels of the coarsest region holding its point),
/// lit within [`TOLERANCE`] of unshadowed, shadowed within [`TOLERANCE`] of black. Left out:
/// pixels the light hardly reaches unshadowed (8/255, as the coarse comparison), pixels next to
/// an occluder's silhouette on screen (a neighbour's centre does not see the floor, so the
/// rasteriser may cover the pixel with the occluder), and points no region holds.
pub fn check_band(
    camera: &renderer::frame::FrameCamera,
    light: &SceneLight,
    regions: &[Region],
    shadowed: &[u8],
    unshadowed: &[u8],
    (w, h): (u32, u32),
) -> Tight {
    use crate::shadow_scene::{floor_point, luminance, min_unshadowed_luminance};
    let floor: Vec<Option<Vec3>> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| floor_point(camera, x, y, w, h))
        .collect();
    let mut out = Tight {
        lit: 0,
        shadowed: 0,
        contact: 0,
        in_band: 0,
        wrong: Vec::new(),
        widest_partial: 0.0,
        closest_to_band: f32::NEG_INFINITY,
    };
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let i = (y * w + x) as usize;
            let Some(p) = floor[i] else { continue };
            let all_floor = (y - 1..=y + 1)
                .all(|v| (x - 1..=x + 1).all(|u| floor[(v * w + u) as usize].is_some()));
            if !all_floor || luminance(unshadowed, i) <= min_unshadowed_luminance() {
                continue;
            }
            let view_depth = -camera.view.transform_point3(p).z;
            let Some(region) = coarsest_at(regions, p, view_depth) else {
                continue;
            };
            let lit = reaches(light, p);
            let (s, u) = (&shadowed[i * 4..i * 4 + 3], &unshadowed[i * 4..i * 4 + 3]);
            let difference = if lit {
                (0..3).map(|c| s[c].abs_diff(u[c])).max().unwrap_or(0)
            } else {
                s.iter().copied().max().unwrap_or(0)
            };
            // A pixel within tolerance needs only to know whether a flip lies within its band;
            // a wrong one is searched to the full distance for the report.
            let band = band_texels(light, p);
            let limit = if difference > TOLERANCE {
                SEARCH_TEXELS
            } else {
                band.min(SEARCH_TEXELS)
            };
            let texels = texel_distance_to_flip(&region, light, p, lit, limit);
            if difference > TOLERANCE {
                let t = texels.unwrap_or(f32::INFINITY);
                out.widest_partial = out.widest_partial.max(t);
                out.closest_to_band = out.closest_to_band.max(t - band);
            }
            if texels.is_some_and(|t| t <= band) {
                out.in_band += 1;
                continue;
            }
            if lit {
                out.lit += 1;
            } else {
                out.shadowed += 1;
                out.contact += usize::from(distance_to_contact(p) <= CONTACT);
            }
            if difference > TOLERANCE {
                out.wrong.push(Wrong {
                    x,
                    y,
                    p,
                    reference_lit: lit,
                    difference,
                    texels,
                });
            }
        }
    }
    out
}

/// The shadow regions of `renderer`'s last frame, for its only shadowed light.
pub fn regions_of(renderer: &renderer::frame::Renderer) -> Vec<Region> {
    let pass = renderer
        .pass::<renderer::passes::shadow::ShadowPass>()
        .expect("shadow pass");
    pass.plan()
        .regions
        .iter()
        .map(|r| Region {
            clip_from_world: r.region.view.clip_from_world,
            side: r.region.rect.side,
            split_far: r.region.view.split_far,
        })
        .collect()
}

/// Asserts the band rule held: no wrong pixel, and enough lit and shadowed pixels (300 each)
/// and at least `min_contact` shadowed pixels at a contact line were checked.
pub fn assert_band(name: &str, t: &Tight, min_contact: usize) {
    let wrong: Vec<String> = t
        .wrong
        .iter()
        .take(20)
        .map(|w| {
            format!(
                "({}, {}) at {:.3}: reference {}, off by {}/255, {} texels from a flip",
                w.x,
                w.y,
                w.p,
                if w.reference_lit {
                    "lit (acne)"
                } else {
                    "unlit (leak)"
                },
                w.difference,
                w.texels.map_or("> 8".into(), |d| format!("{d:.2}"))
            )
        })
        .collect();
    assert!(
        t.wrong.is_empty(),
        "{name}: {} floor pixels outside the band differ from the ray cast by \
         more than {TOLERANCE}/255:\n{}",
        t.wrong.len(),
        wrong.join("\n")
    );
    assert!(
        t.lit > 300 && t.shadowed > 300 && t.contact >= min_contact,
        "{name}: too few pixels checked ({} lit, {} shadowed, {} at a contact line)",
        t.lit,
        t.shadowed,
        t.contact
    );
}
