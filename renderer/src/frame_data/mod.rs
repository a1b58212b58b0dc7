//! What every pass of a frame may read, below the passes: the renderer's configuration, the
//! camera, the prepared scene and its draw lists and batches, the lights, the decals, the particle systems, the
//! shared texture formats, the
//! graph resources passes hand each other ([`FrameResources`]) and the frame report.
//!
//! Passes (`crate::passes`) import this module and never `crate::frame`; `frame` orchestrates
//! them. Nothing here knows any particular pass.

mod camera;
mod change_log;
mod config;
mod decals;
mod draw_batches;
mod error;
mod formats;
mod inputs;
mod instances;
mod lights;
mod material_groups;
mod material_inputs;
mod material_params;
mod report;
mod resources;
mod scene;
mod views;
mod visibility_handles;

#[cfg(any(test, feature = "internals"))]
pub use camera::frustum_planes;
pub use camera::{CameraUniform, FrameCamera, box_in_frustum, farness};
pub use config::{
    Ambient, FrameView, ParticleLighting, RenderPath, RendererConfig, VisibilityRaster,
};
#[cfg(any(test, feature = "internals"))]
pub use config::{DEFAULT_LIGHT_CUTOFF, EdgeThresholds};
#[cfg(any(test, feature = "internals"))]
pub use decals::cull_box;
pub use decals::{DecalUpload, GpuDecals};
#[cfg(any(test, feature = "internals"))]
pub use draw_batches::{BatchKey, DrawPlace, NoRoom};
pub use draw_batches::{BatchLayout, DrawBatch, NO_DRAW, draw_place};
pub use error::{ConfigError, DeviceError, InputError, RenderError};
pub use formats::{DEPTH_FORMAT, GBUFFER_FORMATS, HDR_FORMAT, VISIBILITY_FORMAT};
pub(crate) use formats::{output_view, target_takes};
pub use inputs::{FrameInputs, ParticleInput};
pub use instances::{DrawItem, InstanceEditError, InstanceHandle, InstanceState, InstanceTable};
#[cfg(any(test, feature = "internals"))]
pub use lights::effective_range;
pub use lights::{LightSet, with_effective_ranges};
#[cfg(any(test, feature = "internals"))]
pub use material_groups::material_record;
#[cfg(any(test, feature = "internals"))]
pub use material_inputs::{sampler_descriptor, uv_map};
pub use report::{FrameReport, ParticleReport, SceneDrawReport};
pub use resources::{
    BlendedDraws, FrameResources, GBufferHandles, LightListHandles, ListGeometry, OcclusionDraws,
    OcclusionPacked, OverlayEraser, ParticleResources, SceneDrawList, ShadowResources,
};
pub use scene::PreparedScene;
#[cfg(any(test, feature = "internals"))]
pub use scene::{MeshDraw, PlannedDraw, draw_plan, is_mirrored};
pub use views::{ViewId, ViewTarget};
pub use visibility_handles::{VisibilityHandles, VisibilitySamples};
