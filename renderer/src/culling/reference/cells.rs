//! The lists each cell gets (the grid and methods are [`crate::culling::vocabulary`]'s).

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
