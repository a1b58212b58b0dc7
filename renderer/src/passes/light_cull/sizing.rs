//! Sizing the index list before the frame: the CPU bound of [`crate::culling::capacity`] over
//! the frame's lights and decals, for the lists the frame's cullers write, so no frame drops an
//! entry while the bound fits one storage binding.

use crate::culling::capacity::{GridView, ListLayout, entry_bound};
use crate::culling::hierarchy::box_sphere;
use crate::frame_data::{FrameInputs, RenderPath};

/// The index-list capacity for a frame that may need `bound` entries, holding `current` now,
/// where one storage binding holds `limit`: `bound` as a power of two, up to `limit`; never less
/// than `current`. Warns when `bound` passes `limit` (entries past it are dropped and reported).
pub(super) fn grown_capacity(bound: u64, current: u32, limit: u32) -> u32 {
    if bound <= u64::from(current) {
        return current;
    }
    if bound > u64::from(limit) {
        log::warn!(
            "this frame's light and decal lists may need up to {bound} entries, more than one \
             storage binding holds ({limit}); entries past it are dropped and reported"
        );
    }
    let grown = u32::try_from(bound.next_power_of_two()).unwrap_or(u32::MAX);
    grown.min(limit).max(current)
}

/// The most entries one frame's lists can take: those of `path`'s culler (with a blended list
/// per tile when `blended`), or of the particles' clustered lists (`particle_lists`), whichever
/// is larger, as the two share one capacity.
pub(super) fn frame_entry_bound(
    frame: &FrameInputs,
    path: RenderPath,
    blended: bool,
    particle_lists: bool,
    slices: u32,
) -> u64 {
    let c = &frame.config;
    let grid = GridView {
        view: frame.camera.view,
        projection: frame.camera.projection,
        width: c.width,
        height: c.height,
        tile: c.tile,
    };
    let clustered = ListLayout::Clustered {
        slices,
        near: frame.camera.near,
        far: frame.camera.far,
    };
    let layout = match path {
        RenderPath::Tiled | RenderPath::Depth25 => Some(ListLayout::Tiled {
            lists_per_tile: if blended { 2 } else { 1 },
        }),
        RenderPath::Clustered => Some(clustered),
        _ => None,
    };
    let items = || {
        let lights = frame.lights.spheres.iter().map(|s| (s.center, s.radius));
        // A decal enters a list only if the sphere the kernels test it by does.
        let decals = frame.decals.boxes.iter().map(box_sphere);
        lights.chain(decals)
    };
    let main = layout.map_or(0, |l| entry_bound(items(), &grid, l));
    let particles = if particle_lists {
        entry_bound(items(), &grid, clustered)
    } else {
        0
    };
    main.max(particles)
}
