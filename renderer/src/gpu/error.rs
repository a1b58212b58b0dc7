//! Typed errors of GPU context creation, each saying what to do about it.

/// Why a GPU context could not be created.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GpuError {
    #[error(
        "no GPU adapter found (searched backends: {backends:?}). Install a Vulkan driver: on \
         Debian/Ubuntu without a GPU, `apt-get install mesa-vulkan-drivers libvulkan1` gives the \
         software driver lavapipe (`cargo xtask test` installs it when run as root)"
    )]
    NoAdapter { backends: wgpu::Backends },

    #[error(
        "no adapter name contains {wanted:?} (GpuOptions::adapter_name, from RENDERER_ADAPTER \
         or a tool's --adapter); adapters \
         found: {available:?}"
    )]
    AdapterNotFound {
        wanted: String,
        available: Vec<String>,
    },

    #[error(
        "adapter {adapter:?} lacks the limit {limit} = {needed} the renderer needs (it has \
         {available}); pick another adapter (GpuOptions::adapter_name, from RENDERER_ADAPTER or \
         a tool's --adapter)"
    )]
    InsufficientLimit {
        adapter: String,
        limit: &'static str,
        needed: u64,
        available: u64,
    },

    #[error(
        "the device given to GpuContext::from_parts lacks limits the renderer needs: {}. \
         Open it with at least `renderer::gpu::requirements::minimum_limits()` in \
         `wgpu::DeviceDescriptor::required_limits` (`requirements::for_adapter(&adapter)` gives \
         the features and limits the renderer asks of an adapter){}",
        list(missing),
        if *adapter_can { "; the adapter allows them" } else { "; the adapter itself does not allow them: use another adapter" }
    )]
    DeviceLimits {
        missing: Vec<MissingLimit>,
        /// Whether the device's adapter allows every missing limit.
        adapter_can: bool,
    },

    #[error("adapter {adapter:?} refused the device request: {source}")]
    RequestDevice {
        adapter: String,
        #[source]
        source: wgpu::RequestDeviceError,
    },

    #[error("waiting for the GPU failed: {0}")]
    Poll(#[source] wgpu::PollError),

    #[error("GPU timing failed: {0}")]
    Profiler(String),

    #[error("mapping a readback buffer failed: {0}")]
    Map(#[source] wgpu::BufferAsyncError),

    #[error("reading a mapped readback buffer failed: {0}")]
    MapRange(String),
}

/// `items` as a comma-separated list.
fn list<T: std::fmt::Display>(items: &[T]) -> String {
    items
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// A limit a device has below what the renderer needs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MissingLimit {
    /// The field of `wgpu::Limits`.
    pub limit: &'static str,
    /// What the renderer needs (a largest alignment for the `min_*_alignment` limits).
    pub needed: u64,
    /// What the device has.
    pub available: u64,
}

impl std::fmt::Display for MissingLimit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} = {} (the device has {})",
            self.limit, self.needed, self.available
        )
    }
}
