//! Frame capture for tools (the benchmark's cull efficiency): the data a captured frame reads
//! back. The depth-probe pass records it; see `crate::passes::depth_probe`.

pub use crate::passes::depth_probe::capture::{FrameCapture, SurfaceProbe};
