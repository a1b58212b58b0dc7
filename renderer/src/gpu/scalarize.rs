//! Whether to use the subgroup (scalarized) variant of a kernel, from what the benchmark
//! measured on each kind of adapter: scalarization is a choice made per kernel and adapter by
//! measurement, not a rule (it made the old culling kernels 1.04–1.32× slower on the H100 and
//! the forward shader 5% faster).
//!
//! [`scalarize_auto`] answers "auto": a kernel is scalarized only on an adapter whose vendor a
//! benchmark recorded it faster on, and only when the device has SUBGROUP. Kernels without a
//! record run plain, the safe choice. The culling kernels have no subgroup variants any more
//! (the hierarchy's kernels were written plain after the scalarized ones measured slower).

use super::GpuContext;

/// The kernels with a scalarized variant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum ScalarizedKernel {
    /// The forward shader's light loop (a uniform list per subgroup read with broadcasts).
    Forward,
}

/// One benchmark result: on adapters of `vendor`, the scalarized `kernel` was faster or not.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ScalarizeRecord {
    /// PCI vendor id (`wgpu::AdapterInfo::vendor`).
    pub vendor: u32,
    /// The kernel measured.
    pub kernel: ScalarizedKernel,
    /// Whether its scalarized variant was faster than the plain one there.
    pub faster: bool,
    /// Where the figure comes from.
    pub measured: &'static str,
}

/// NVIDIA's PCI vendor id.
const NVIDIA: u32 = 0x10de;

/// What the benchmarks recorded (BENCHMARKS.md has the runs).
pub const RECORDS: &[ScalarizeRecord] = &[ScalarizeRecord {
    vendor: NVIDIA,
    kernel: ScalarizedKernel::Forward,
    faster: true,
    measured: "H100, courtyard 1920×1080 MSAA 1, 4,096 lights: forward 15.43 ms scalarized \
               against 16.23 ms plain (0.95×); 0.94–0.97× on DamagedHelmet",
}];

/// Whether "auto" scalarizes `kernel` on `gpu`'s adapter.
pub fn scalarize_auto(gpu: &GpuContext, kernel: ScalarizedKernel) -> bool {
    gpu.capabilities().subgroup.is_some() && recorded_faster(gpu.adapter.get_info().vendor, kernel)
}

fn recorded_faster(vendor: u32, kernel: ScalarizedKernel) -> bool {
    RECORDS
        .iter()
        .any(|r| r.vendor == vendor && r.kernel == kernel && r.faster)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_recorded_wins_scalarize() {
        assert!(recorded_faster(NVIDIA, ScalarizedKernel::Forward));
        // Mesa's lavapipe (0x10005) and anything unmeasured run plain.
        assert!(!recorded_faster(0x10005, ScalarizedKernel::Forward));
        assert!(!recorded_faster(0x1002, ScalarizedKernel::Forward));
    }
}
