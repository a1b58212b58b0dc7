//! How the caller steers instance creation and adapter choice.

/// Environment variable holding a case-insensitive substring of the adapter name to use.
pub const ADAPTER_ENV: &str = "RENDERER_ADAPTER";

/// Options for [`super::GpuContext::new`].
#[derive(Debug, Clone)]
pub struct GpuOptions {
    /// Backends to search. Defaults to the primary ones (Vulkan, Metal, DX12), or `WGPU_BACKEND`.
    pub backends: wgpu::Backends,
    /// Instance flags. Defaults to none, or `WGPU_VALIDATION`/`WGPU_DEBUG` from the environment.
    pub flags: wgpu::InstanceFlags,
    /// Case-insensitive substring of the adapter name to pick. `None` uses the preference order.
    pub adapter_name: Option<String>,
}

impl Default for GpuOptions {
    fn default() -> Self {
        Self {
            backends: wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY),
            flags: wgpu::InstanceFlags::empty().with_env(),
            adapter_name: None,
        }
    }
}

impl GpuOptions {
    /// Default options, with the adapter filter taken from `RENDERER_ADAPTER` when set.
    pub fn from_env() -> Self {
        Self {
            adapter_name: std::env::var(ADAPTER_ENV).ok().filter(|s| !s.is_empty()),
            ..Self::default()
        }
    }

    /// Options for tests: wgpu validation and the Khronos layer on.
    ///
    /// `InstanceFlags::DEBUG` is set too, because only with it does wgpu-hal register the
    /// `VK_EXT_debug_utils` messenger that turns layer reports into log records; without it the
    /// layer prints to stdout, where no test can see it. The price is one known false positive of
    /// the Debian 1.3.239 layer ("Invalid source language operand: 10"), which the test harness
    /// filters by its exact text.
    pub fn validated() -> Self {
        Self {
            flags: wgpu::InstanceFlags::VALIDATION | wgpu::InstanceFlags::DEBUG,
            ..Self::from_env()
        }
    }

    /// Picks the adapter whose name contains `name` (case-insensitive).
    #[must_use]
    pub fn with_adapter_name(mut self, name: Option<String>) -> Self {
        if name.is_some() {
            self.adapter_name = name;
        }
        self
    }

    pub(crate) fn create_instance(&self) -> wgpu::Instance {
        let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
        desc.backends = self.backends;
        desc.flags = self.flags;
        wgpu::Instance::new(desc)
    }
}
