//! Typed errors of GPU context creation, each saying what to do about it.

/// Why a GPU context could not be created.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GpuError {
    /// No adapter exists on the searched backends ([`GpuOptions::backends`]).
    ///
    /// [`GpuOptions::backends`]: super::GpuOptions::backends
    #[error(
        "no GPU adapter found (searched backends: {backends:?}). Install a Vulkan driver: on \
         Debian/Ubuntu without a GPU, `apt-get install mesa-vulkan-drivers libvulkan1` gives the \
         software driver lavapipe (`cargo xtask test` installs it when run as root)"
    )]
    NoAdapter {
        /// The backends searched.
        backends: wgpu::Backends,
    },

    /// [`GpuOptions::adapter_name`](super::GpuOptions::adapter_name) matches no adapter name.
    #[error(
        "no adapter name contains {wanted:?} (GpuOptions::adapter_name, set directly or by \
         GpuOptions::from_env from RENDERER_ADAPTER); adapters \
         found: {available:?}"
    )]
    AdapterNotFound {
        /// The name filter (a case-insensitive substring).
        wanted: String,
        /// Names of the adapters on the searched backends, best first.
        available: Vec<String>,
    },

    /// The chosen adapter allows less than the renderer needs of a `wgpu::Limits` field.
    #[error(
        "adapter {adapter:?} lacks the limit {limit} = {needed} the renderer needs (it has \
         {available}); pick another adapter (GpuOptions::adapter_name, set directly or by \
         GpuOptions::from_env from RENDERER_ADAPTER)"
    )]
    InsufficientLimit {
        /// The adapter's name.
        adapter: String,
        /// The field of `wgpu::Limits`.
        limit: &'static str,
        /// What the renderer needs.
        needed: u64,
        /// What the adapter allows.
        available: u64,
    },

    /// A device given to [`GpuContext::from_parts`](super::GpuContext::from_parts) was opened
    /// with limits below [`minimum_limits`](super::requirements::minimum_limits).
    #[error(
        "the device given to GpuContext::from_parts lacks limits the renderer needs: {}. \
         Open it with at least `renderer::gpu::requirements::minimum_limits()` in \
         `wgpu::DeviceDescriptor::required_limits` (`requirements::for_adapter(&adapter)` gives \
         the features and limits the renderer asks of an adapter){}",
        list(missing),
        if *adapter_can { "; the adapter allows them" } else { "; the adapter itself does not allow them: use another adapter" }
    )]
    DeviceLimits {
        /// Each limit below the renderer's minimum.
        missing: Vec<MissingLimit>,
        /// Whether the device's adapter allows every missing limit.
        adapter_can: bool,
    },

    /// wgpu refused to open a device on the chosen adapter.
    #[error("adapter {adapter:?} refused the device request: {source}")]
    RequestDevice {
        /// The adapter's name.
        adapter: String,
        /// wgpu's reason.
        #[source]
        source: wgpu::RequestDeviceError,
    },

    /// Polling the device while waiting for submitted work failed (a readback, `wait_idle`).
    #[error("waiting for the GPU failed: {0}")]
    Poll(#[source] wgpu::PollError),

    /// wgpu-profiler could not be created or could not end a frame; the text is its error.
    #[error("GPU timing failed: {0}")]
    Profiler(String),

    /// Mapping a staging buffer to read results back failed.
    #[error("mapping a readback buffer failed: {0}")]
    Map(#[source] wgpu::BufferAsyncError),

    /// A mapped staging buffer's contents could not be accessed; the text is wgpu's error.
    #[error("reading a mapped readback buffer failed: {0}")]
    MapRange(String),

    /// A blocking readback was called in a browser, whose page cannot wait for the GPU; the
    /// text names it. Use its `_async` form (`readback::read_texture_rgba8_async`).
    #[error("{0} blocks until the GPU is done, which a browser page cannot: use its async form")]
    BlockingInBrowser(&'static str),
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
