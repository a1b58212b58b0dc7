//! Adapter discovery, ranking and reporting.

use super::error::GpuError;
use super::options::GpuOptions;
use super::requirements;

/// Range of subgroup (wave) sizes the adapter may run with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SubgroupSize {
    /// Smallest subgroup size, in invocations.
    pub min: u32,
    /// Largest subgroup size, in invocations (equal to `min` on a fixed-width device).
    pub max: u32,
}

/// The optional capabilities this project uses, as the device will have them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Capabilities {
    /// `Some` when `Features::SUBGROUP` is available: scalarized shader variants can run.
    pub subgroup: Option<SubgroupSize>,
    /// `Features::TIMESTAMP_QUERY`: per-pass GPU timings.
    pub timestamp_query: bool,
    /// Timestamps inside encoders and passes, which nested profiler scopes use.
    pub timestamp_inside_passes: bool,
    /// MSAA sample counts usable for `Depth32Float` attachments.
    pub msaa_depth32float: Vec<u32>,
    /// MSAA sample counts usable for `Rgba16Float` attachments.
    pub msaa_rgba16float: Vec<u32>,
    /// MSAA sample counts usable for `R32Uint` attachments (the visibility buffer).
    pub msaa_r32uint: Vec<u32>,
    /// Largest compute workgroup (invocations) the device allows.
    pub max_workgroup_invocations: u32,
    /// `SHADER_INT64` and `SHADER_INT64_ATOMIC_MIN_MAX`: 64-bit atomic min/max on storage
    /// buffers, which the compute rasteriser needs.
    pub int64_atomic_min_max: bool,
    /// Vulkan with `PASSTHROUGH_SHADERS`: a variant whose SPIR-V wgpu would write invalid (a
    /// `sample_mask` built-in) is given to the driver as its own SPIR-V instead
    /// ([`crate::shader::ShaderProgram`]).
    pub spirv_passthrough: bool,
    /// The adapter is a browser's WebGPU: shader source gets the `enable` directives its
    /// features need (`codegen::web::browser_directives`), which naga does not take.
    pub browser: bool,
}

impl Capabilities {
    /// MSAA counts usable for a frame: those both the depth and the colour target support.
    pub fn msaa_counts(&self) -> Vec<u32> {
        self.msaa_depth32float
            .iter()
            .copied()
            .filter(|c| self.msaa_rgba16float.contains(c))
            .collect()
    }
}

/// What an adapter is, and what the renderer can use on it.
#[derive(Debug, Clone)]
pub struct AdapterReport {
    /// The adapter's name (what [`GpuOptions::adapter_name`] matches).
    pub name: String,
    /// The backend it runs on.
    pub backend: wgpu::Backend,
    /// Discrete, integrated, virtual, CPU or other.
    pub device_type: wgpu::DeviceType,
    /// Driver name, as wgpu reports it (may be empty).
    pub driver: String,
    /// Driver version details, as wgpu reports it (may be empty).
    pub driver_info: String,
    /// What the renderer can use on it.
    pub capabilities: Capabilities,
}

impl AdapterReport {
    /// Queries `adapter`'s info, optional features and format support.
    pub fn new(adapter: &wgpu::Adapter) -> Self {
        let info = adapter.get_info();
        let features = requirements::optional_features(adapter);
        let subgroup = features
            .contains(wgpu::Features::SUBGROUP)
            .then_some(SubgroupSize {
                min: info.subgroup_min_size,
                max: info.subgroup_max_size,
            });
        let sample_counts = |format: wgpu::TextureFormat| {
            let mut counts = adapter
                .get_texture_format_features(format)
                .flags
                .supported_sample_counts();
            if !features.contains(wgpu::Features::TEXTURE_ADAPTER_SPECIFIC_FORMAT_FEATURES) {
                // Without adapter-specific format features WebGPU guarantees only 1 and 4, and
                // only 1 for integer formats.
                let integer = format.sample_type(None, None) == Some(wgpu::TextureSampleType::Uint);
                counts.retain(|&c| c == 1 || (c == 4 && !integer));
            }
            counts
        };
        Self {
            name: info.name,
            backend: info.backend,
            device_type: info.device_type,
            driver: info.driver,
            driver_info: info.driver_info,
            capabilities: Capabilities {
                subgroup,
                timestamp_query: features.contains(wgpu::Features::TIMESTAMP_QUERY),
                timestamp_inside_passes: features.contains(
                    wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS
                        | wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES,
                ),
                msaa_depth32float: sample_counts(wgpu::TextureFormat::Depth32Float),
                msaa_rgba16float: sample_counts(wgpu::TextureFormat::Rgba16Float),
                msaa_r32uint: sample_counts(wgpu::TextureFormat::R32Uint),
                max_workgroup_invocations: requirements::workgroup_invocations(adapter),
                int64_atomic_min_max: features.contains(
                    wgpu::Features::SHADER_INT64 | wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX,
                ),
                spirv_passthrough: info.backend == wgpu::Backend::Vulkan
                    && features.contains(wgpu::Features::PASSTHROUGH_SHADERS),
                browser: info.backend == wgpu::Backend::BrowserWebGpu,
            },
        }
    }
}

impl std::fmt::Display for AdapterReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let caps = &self.capabilities;
        writeln!(
            f,
            "{} ({:?}, {:?})",
            self.name, self.backend, self.device_type
        )?;
        writeln!(
            f,
            "  driver:            {} {}",
            self.driver, self.driver_info
        )?;
        match caps.subgroup {
            Some(s) if s.min == s.max => writeln!(f, "  SUBGROUP:          yes, size {}", s.min)?,
            Some(s) => writeln!(f, "  SUBGROUP:          yes, size {}..={}", s.min, s.max)?,
            None => writeln!(f, "  SUBGROUP:          no")?,
        }
        let yes_no = |b: bool| if b { "yes" } else { "no" };
        writeln!(
            f,
            "  TIMESTAMP_QUERY:   {} (inside passes: {})",
            yes_no(caps.timestamp_query),
            yes_no(caps.timestamp_inside_passes)
        )?;
        writeln!(f, "  MSAA Depth32Float: {:?}", caps.msaa_depth32float)?;
        writeln!(f, "  MSAA Rgba16Float:  {:?}", caps.msaa_rgba16float)?;
        writeln!(f, "  MSAA R32Uint:      {:?}", caps.msaa_r32uint)?;
        writeln!(
            f,
            "  INT64 atomic min/max: {}",
            yes_no(caps.int64_atomic_min_max)
        )?;
        write!(
            f,
            "  workgroup max:     {} invocations",
            caps.max_workgroup_invocations
        )
    }
}

/// Every adapter on the given backends, best first (see [`rank_adapters`]).
pub async fn enumerate_adapters(options: &GpuOptions) -> Vec<wgpu::Adapter> {
    let instance = options.create_instance();
    let mut adapters = instance.enumerate_adapters(options.backends).await;
    rank_adapters(&mut adapters);
    adapters
}

/// Orders adapters by preference: discrete GPU, integrated, virtual, CPU, other; Vulkan first
/// among equals, then by name so the order is stable.
pub fn rank_adapters(adapters: &mut [wgpu::Adapter]) {
    adapters.sort_by_cached_key(|a| {
        let info = a.get_info();
        (
            device_type_rank(info.device_type),
            info.backend != wgpu::Backend::Vulkan,
            info.name,
        )
    });
}

fn device_type_rank(device_type: wgpu::DeviceType) -> u8 {
    match device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Cpu => 3,
        wgpu::DeviceType::Other => 4,
    }
}

pub(super) fn choose(
    mut adapters: Vec<wgpu::Adapter>,
    options: &GpuOptions,
) -> Result<wgpu::Adapter, GpuError> {
    if adapters.is_empty() {
        return Err(GpuError::NoAdapter {
            backends: options.backends,
        });
    }
    rank_adapters(&mut adapters);
    let Some(wanted) = &options.adapter_name else {
        return Ok(adapters.swap_remove(0));
    };
    let needle = wanted.to_lowercase();
    match adapters
        .iter()
        .position(|a| a.get_info().name.to_lowercase().contains(&needle))
    {
        Some(i) => Ok(adapters.swap_remove(i)),
        None => Err(GpuError::AdapterNotFound {
            wanted: wanted.clone(),
            available: adapters.iter().map(|a| a.get_info().name).collect(),
        }),
    }
}
