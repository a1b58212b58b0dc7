//! The names of a renderer's further views (`Renderer::add_view`), below the passes and the
//! errors that name them.

use super::FrameCamera;

/// A further view of a renderer ([`Renderer::add_view`](crate::frame::Renderer::add_view)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct ViewId(pub(crate) u32);

/// A further view to draw in a frame: which, from where, into what (a texture of the view's
/// `output_format` and size, with `RENDER_ATTACHMENT`, and `COPY_DST` for the compute
/// tonemap).
#[derive(Debug, Clone, Copy)]
pub struct ViewTarget<'a> {
    /// The view ([`crate::frame::Renderer::add_view`]).
    pub view: ViewId,
    /// Its camera this frame.
    pub camera: &'a FrameCamera,
    /// The texture it draws into.
    pub target: &'a wgpu::Texture,
}
