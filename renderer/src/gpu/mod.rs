//! The headless GPU context: instance, adapter choice, device and queue.
//!
//! [`GpuContext::new`] picks an adapter (discrete, then integrated, then CPU; or the one whose
//! name contains `RENDERER_ADAPTER` / `--adapter`), requests exactly the features and limits the
//! renderer uses and the adapter has ([`requirements`]), and reports what it found
//! ([`AdapterReport`]). It must not own any rendering state: passes and scenes live elsewhere.

pub(crate) mod adapter;
mod error;
mod options;
pub mod requirements;
mod scalarize;

pub use adapter::{AdapterReport, Capabilities, SubgroupSize, enumerate_adapters, rank_adapters};
pub use error::{GpuError, MissingLimit};
pub use options::{ADAPTER_ENV, GpuOptions};
pub use scalarize::{
    RECORDS as SCALARIZE_RECORDS, ScalarizeRecord, ScalarizedKernel, scalarize_auto,
};

/// A headless wgpu instance, the chosen adapter, and its device and queue.
#[derive(Debug, Clone)]
pub struct GpuContext {
    instance: wgpu::Instance,
    adapter: wgpu::Adapter,
    device: wgpu::Device,
    queue: wgpu::Queue,
    /// What the adapter is and which optional capabilities the device was created with.
    report: AdapterReport,
    /// Why the device was lost, once it is ([`GpuContext::lost`]).
    lost: DeviceLoss,
    /// The programs and pipelines compiled on the device ([`GpuContext::program`]).
    programs: crate::shader::store::SharedProgramStore,
}

/// What a context has compiled ([`GpuContext::compiled`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CompiledCounts {
    /// Shader programs (a variant's module and layouts) compiled so far: one per variant and
    /// source, however many renderers use it.
    pub programs: usize,
    /// Compute and render pipelines built from them so far.
    pub pipelines: usize,
}

/// Where the device-lost callback leaves its reason.
type DeviceLoss = std::sync::Arc<std::sync::Mutex<Option<String>>>;

/// An engine's device-lost callback, called after the context records the loss.
pub type DeviceLostCallback = Box<dyn Fn(wgpu::DeviceLostReason, &str) + Send + 'static>;

/// Registers the callback that records `device`'s loss and then calls `also` (the engine's;
/// wgpu keeps one callback per device, so this replaces any set before).
fn watch_for_loss(device: &wgpu::Device, also: Option<DeviceLostCallback>) -> DeviceLoss {
    let lost = DeviceLoss::default();
    let sink = std::sync::Arc::clone(&lost);
    device.set_device_lost_callback(move |reason, message| {
        *sink
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner) =
            Some(format!("{reason:?}: {message}"));
        if let Some(engine) = &also {
            engine(reason, &message);
        }
    });
    lost
}

impl GpuContext {
    /// Creates the instance, picks an adapter and opens a device on it.
    pub async fn new(options: &GpuOptions) -> Result<Self, GpuError> {
        let instance = options.create_instance();
        let adapters = instance.enumerate_adapters(options.backends).await;
        let adapter = adapter::choose(adapters, options)?;
        let report = AdapterReport::new(&adapter);
        let (required_features, required_limits) = requirements::for_adapter(&adapter)?;
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("renderer device"),
                required_features,
                required_limits,
                experimental_features: wgpu::ExperimentalFeatures::disabled(),
                memory_hints: wgpu::MemoryHints::Performance,
                trace: wgpu::Trace::Off,
            })
            .await
            .map_err(|source| GpuError::RequestDevice {
                adapter: report.name.clone(),
                source,
            })?;
        Ok(Self {
            lost: watch_for_loss(&device, None),
            instance,
            adapter,
            device,
            queue,
            report,
            programs: Default::default(),
        })
    }

    /// Wraps an engine's own instance, adapter, device and queue, after checking that the device
    /// has every limit the renderer needs ([`requirements::minimum_limits`]):
    /// [`GpuError::DeviceLimits`] names each one it lacks, with what to ask. The capabilities are
    /// those of the adapter the device was created with, less the features the engine did not
    /// enable, so variant selection never asks for more than the device has (no feature is
    /// required: a path that needs one reports it when configured).
    ///
    /// This registers the device's lost callback, which replaces one the engine set; to keep
    /// the engine's, pass it to [`GpuContext::from_parts_with_loss_callback`].
    pub fn from_parts(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
        device: wgpu::Device,
        queue: wgpu::Queue,
    ) -> Result<Self, GpuError> {
        Self::wrap(instance, adapter, device, queue, None)
    }

    /// [`GpuContext::from_parts`], calling `on_lost` when the device is lost, after the context
    /// records the loss ([`GpuContext::lost`]).
    pub fn from_parts_with_loss_callback(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
        device: wgpu::Device,
        queue: wgpu::Queue,
        on_lost: impl Fn(wgpu::DeviceLostReason, &str) + Send + 'static,
    ) -> Result<Self, GpuError> {
        Self::wrap(instance, adapter, device, queue, Some(Box::new(on_lost)))
    }

    fn wrap(
        instance: wgpu::Instance,
        adapter: wgpu::Adapter,
        device: wgpu::Device,
        queue: wgpu::Queue,
        on_lost: Option<DeviceLostCallback>,
    ) -> Result<Self, GpuError> {
        let missing = requirements::missing_limits(&device.limits());
        if !missing.is_empty() {
            let adapter_can = requirements::missing_limits(&adapter.limits()).is_empty();
            return Err(GpuError::DeviceLimits {
                missing,
                adapter_can,
            });
        }
        let mut report = AdapterReport::new(&adapter);
        let enabled = device.features();
        let caps = &mut report.capabilities;
        if !enabled.contains(wgpu::Features::SUBGROUP) {
            caps.subgroup = None;
        }
        caps.timestamp_query &= enabled.contains(wgpu::Features::TIMESTAMP_QUERY);
        caps.timestamp_inside_passes &= enabled.contains(
            wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
                | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES,
        );
        if !enabled.contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES) {
            caps.msaa_depth32float.retain(|c| matches!(c, 1 | 4));
            caps.msaa_rgba16float.retain(|c| matches!(c, 1 | 4));
            caps.msaa_r32uint.retain(|&c| c == 1);
        }
        caps.max_workgroup_invocations = caps
            .max_workgroup_invocations
            .min(device.limits().max_compute_invocations_per_workgroup);
        Ok(Self {
            lost: watch_for_loss(&device, on_lost),
            instance,
            adapter,
            device,
            queue,
            report,
            programs: Default::default(),
        })
    }

    /// Blocking form of [`GpuContext::new`] for tools and tests. Not in a browser, where
    /// nothing may block the page's thread: await [`GpuContext::new`] there.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn new_blocking(options: &GpuOptions) -> Result<Self, GpuError> {
        pollster::block_on(Self::new(options))
    }

    /// The wgpu instance the adapter came from.
    pub fn instance(&self) -> &wgpu::Instance {
        &self.instance
    }

    /// The adapter the device was opened on.
    pub fn adapter(&self) -> &wgpu::Adapter {
        &self.adapter
    }

    /// The device every renderer resource lives on.
    pub fn device(&self) -> &wgpu::Device {
        &self.device
    }

    /// The device's queue, which the renderer submits its frames to.
    pub fn queue(&self) -> &wgpu::Queue {
        &self.queue
    }

    /// What the adapter is and which optional capabilities the device was created with.
    pub fn report(&self) -> &AdapterReport {
        &self.report
    }

    /// The optional capabilities of the device that was created.
    pub fn capabilities(&self) -> &Capabilities {
        &self.report.capabilities
    }

    /// Why the device was lost (destroyed, a driver reset or removal), or `None` while it works.
    /// A lost device stays lost: make a new context, renderer and scene.
    pub fn lost(&self) -> Option<String> {
        self.lost
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .clone()
    }

    /// `variant` compiled on this device, checked against its capabilities. Each variant (and
    /// each hot-reloaded source of it) is compiled once per context; later calls, from any
    /// renderer on the context, return a copy sharing the module, the layouts and the
    /// pipelines built from them. A copy has its own binding log.
    pub fn program(
        &self,
        variant: &'static codegen::rt::Variant,
    ) -> Result<crate::shader::ShaderProgram, crate::shader::VariantError> {
        self.programs
            .program(&self.device, self.capabilities(), variant)
    }

    /// How many programs and pipelines the context has compiled (all of them kept).
    pub fn compiled(&self) -> CompiledCounts {
        let (programs, pipelines) = self.programs.counts();
        CompiledCounts {
            programs,
            pipelines,
        }
    }

    /// Lets go of every compiled program and pipeline the context keeps: each is destroyed
    /// once no renderer holds it (a renderer keeps its own), and compiled again when a renderer
    /// asks for it. For an engine done with a configuration's programs, and for leak checks.
    pub fn release_compiled(&self) {
        self.programs.release();
    }

    /// Waits until all submitted GPU work is done.
    pub fn wait_idle(&self) -> Result<(), GpuError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(GpuError::Poll)
    }
}
