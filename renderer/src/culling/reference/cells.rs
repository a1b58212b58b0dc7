//! A culling method's cells: the froxel grid, the methods and how they index their cells, and
//! the lists each cell gets.

/// Number of depth cells in a 2.5D tile mask.
pub const DEPTH_MASK_CELLS: u32 = 32;
/// Edge of a super-tile in pixels.
pub const SUPER_TILE_PIXELS: u32 = 128;

/// A froxel grid: the screen tiles of `tile`×`tile` pixels × `slices` exponential depth slices
/// between `near` and `far` (view depth). Samples nearer than `near` fall in slice 0, farther
/// than `far` in slice `slices − 1`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClusterGrid {
    pub tile: u32,
    pub slices: u32,
    pub near: f32,
    pub far: f32,
}

impl ClusterGrid {
    /// The depth slice of view depth `d`.
    pub fn slice(&self, d: f32) -> u32 {
        let t = (d / self.near).ln() / (self.far / self.near).ln();
        ((t * self.slices as f32).floor().max(0.0) as u32).min(self.slices - 1)
    }

    /// View depth where slice `k` starts (slice 0 starts at 0; slice `slices` means infinity).
    pub fn slice_start(&self, k: u32) -> f32 {
        match k {
            0 => 0.0,
            k if k >= self.slices => f32::INFINITY,
            k => self.near * (self.far / self.near).powf(k as f32 / self.slices as f32),
        }
    }
}

/// A culling method and its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// One frustum per `tile`×`tile` pixel tile, bounded by the tile's depth range (and, without
    /// MSAA, by the view-space box of that frustum). With
    /// `transparent`, a second list per tile (cells `tiles..2·tiles`) for blended surfaces,
    /// from the near plane to the tile's farthest sample (the far plane when any of its samples
    /// is sky).
    Tiled { tile: u32, transparent: bool },
    /// Tiled, plus a 32-cell depth mask per tile from the geometry, ANDed with each light's
    /// (opaque lists only).
    Depth25 { tile: u32, transparent: bool },
    /// One frustum per froxel (without MSAA narrowed by the froxel's view-space bounding box).
    /// With `skip_empty`, froxels holding no depth sample get no lights, and the others are
    /// clipped to their tile's sample depth range.
    Clustered { grid: ClusterGrid, skip_empty: bool },
}

impl Method {
    /// Tiled without transparent lists.
    pub fn tiled(tile: u32) -> Self {
        Self::Tiled {
            tile,
            transparent: false,
        }
    }

    /// 2.5D without transparent lists.
    pub fn depth25(tile: u32) -> Self {
        Self::Depth25 {
            tile,
            transparent: false,
        }
    }

    /// Whether the method writes a second, transparent list per tile (tiled and 2.5D with
    /// blended surfaces).
    pub fn transparent_lists(&self) -> bool {
        matches!(
            *self,
            Self::Tiled {
                transparent: true,
                ..
            } | Self::Depth25 {
                transparent: true,
                ..
            }
        )
    }

    /// Tile edge in pixels.
    pub fn tile(&self) -> u32 {
        match *self {
            Self::Tiled { tile, .. } | Self::Depth25 { tile, .. } => tile,
            Self::Clustered { grid, .. } => grid.tile,
        }
    }

    /// Cell grid dimensions `[tiles x, tiles y, lists per tile]` for a `width`×`height` target.
    pub fn dims(&self, width: u32, height: u32) -> [u32; 3] {
        let t = self.tile();
        let lists = match *self {
            Self::Tiled { transparent, .. } | Self::Depth25 { transparent, .. } => {
                1 + u32::from(transparent)
            }
            Self::Clustered { grid, .. } => grid.slices,
        };
        [width.div_ceil(t), height.div_ceil(t), lists]
    }

    /// The cell holding the (opaque) sample at pixel `(x, y)` with view depth `view_depth`.
    pub fn cell_of(&self, width: u32, height: u32, x: u32, y: u32, view_depth: f32) -> usize {
        let [dx, dy, _] = self.dims(width, height);
        let t = self.tile();
        let tile = (y / t) * dx + x / t;
        match *self {
            Self::Tiled { .. } | Self::Depth25 { .. } => tile as usize,
            Self::Clustered { grid, .. } => (grid.slice(view_depth) * dx * dy + tile) as usize,
        }
    }
}

/// A light whose test result was within the `f32` tolerance: a GPU may decide either way.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Borderline {
    pub light: u32,
    /// The margin of the sphere test (see [`super::frustum::sphere_margin`]).
    pub margin: f32,
}

/// Per cell: the lights that pass, and the lights too close to call.
#[derive(Debug, Clone, PartialEq)]
pub struct CellLists {
    pub dims: [u32; 3],
    /// Sorted light indices per cell.
    pub lists: Vec<Vec<u32>>,
    /// Per cell, the lights (listed or not) whose result is within tolerance.
    pub borderline: Vec<Vec<Borderline>>,
}

impl CellLists {
    /// Total number of list entries.
    pub fn total_entries(&self) -> usize {
        self.lists.iter().map(Vec::len).sum()
    }
}
