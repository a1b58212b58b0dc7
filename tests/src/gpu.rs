//! The GPU test harness: a validated device per test, and errors that fail the test.
//!
//! - The device is created with `InstanceFlags::VALIDATION`, which loads the Khronos Vulkan
//!   validation layer, and `InstanceFlags::DEBUG`, without which wgpu-hal registers no debug
//!   messenger and the layer's reports never reach the process.
//! - Validation-layer messages reach wgpu-hal's debug callback, which logs them; a process-wide
//!   logger captures every error-level record from wgpu and naga, and every warning of the
//!   layer (`VALIDATION [..]` at warning level): a GPU test requires 0 of either.
//! - One known false positive is dropped by its exact text: the Debian 1.3.239 layer rejects the
//!   WGSL source-language operand (10) that naga writes into SPIR-V under DEBUG
//!   ([`KNOWN_FALSE_POSITIVES`]).
//! - Uncaptured wgpu errors are captured through `Device::on_uncaptured_error`.
//! - GPU tests in one process run one at a time, so every captured error belongs to the test
//!   that is running.
//!
//! There is no skip: no adapter, or no validation layer, is a failure with instructions.
//!
//! On NVIDIA drivers, a test binary that opens many devices can exhaust glibc's static TLS
//! surplus ("libnvidia-tls.so: cannot allocate memory in static TLS block", then "no adapter");
//! run it with `GLIBC_TUNABLES=glibc.rtld.optional_static_tls=65536`.

use std::sync::{Arc, Mutex, MutexGuard, OnceLock, PoisonError};

use renderer::{GpuContext, GpuOptions};

/// Set to `1` to run GPU tests without the Khronos layer (for example on a GPU machine where it
/// cannot be installed). wgpu's own validation stays on.
pub const ALLOW_NO_LAYER_ENV: &str = "RENDERER_TEST_ALLOW_NO_VALIDATION_LAYER";

/// Why a GPU test failed before or after its body ran.
#[derive(Debug)]
pub enum GpuTestFailure {
    /// No adapter, or no device could be opened.
    NoDevice(renderer::GpuError),
    /// The Khronos validation layer is not installed.
    NoValidationLayer,
    /// The test body caused validation or uncaptured wgpu errors.
    Errors(Vec<String>),
}

impl std::fmt::Display for GpuTestFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NoDevice(e) => write!(
                f,
                "GPU test has no device: {e}\nGPU tests never skip: `cargo xtask test` installs \
                 Mesa's software Vulkan driver on Debian/Ubuntu when run as root."
            ),
            Self::NoValidationLayer => write!(
                f,
                "GPU tests run under the Khronos Vulkan validation layer, which is not installed. \
                 Install the Debian/Ubuntu package vulkan-validationlayers (`cargo xtask test` \
                 does this as root), or set {ALLOW_NO_LAYER_ENV}=1 to run with wgpu's own \
                 validation only."
            ),
            Self::Errors(errors) => {
                writeln!(f, "GPU test caused {} validation error(s):", errors.len())?;
                for e in errors {
                    writeln!(f, "- {e}")?;
                }
                Ok(())
            }
        }
    }
}

/// Runs `body` with a validated device, and panics (failing the test) on any error.
pub fn gpu_test<R>(body: impl FnOnce(&GpuContext) -> R) -> R {
    try_gpu_test(body).unwrap_or_else(|failure| panic!("{failure}"))
}

/// Runs `body` with a validated device and returns what went wrong instead of panicking, so a
/// test can prove that a deliberate misuse is caught.
pub fn try_gpu_test<R>(body: impl FnOnce(&GpuContext) -> R) -> Result<R, GpuTestFailure> {
    let _serial = gpu_lock();
    let captured = captured_errors();
    captured
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .clear();
    if !validation_layer_available() && std::env::var(ALLOW_NO_LAYER_ENV).as_deref() != Ok("1") {
        return Err(GpuTestFailure::NoValidationLayer);
    }
    let gpu =
        GpuContext::new_blocking(&GpuOptions::validated()).map_err(GpuTestFailure::NoDevice)?;
    let sink = Arc::clone(captured);
    gpu.device().on_uncaptured_error(Arc::new(move |error| {
        sink.lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push(format!("wgpu: {error}"));
    }));
    let result = body(&gpu);
    // Let all submitted work finish and every object be destroyed while still listening, so
    // errors at submission, execution or teardown are caught too.
    let waited = gpu.wait_idle();
    drop(gpu);
    let mut errors = std::mem::take(&mut *captured.lock().unwrap_or_else(PoisonError::into_inner));
    if let Err(e) = waited {
        errors.push(format!("waiting for the device: {e}"));
    }
    if errors.is_empty() {
        Ok(result)
    } else {
        Err(GpuTestFailure::Errors(errors))
    }
}

fn gpu_lock() -> MutexGuard<'static, ()> {
    static LOCK: Mutex<()> = Mutex::new(());
    // A panicking GPU test poisons the lock; later tests must still run.
    LOCK.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Whether the Vulkan loader can find `VK_LAYER_KHRONOS_validation`.
pub fn validation_layer_available() -> bool {
    // SAFETY: loading the system Vulkan loader library; wgpu-hal does the same.
    let Ok(entry) = (unsafe { ash::Entry::load() }) else {
        return false;
    };
    // SAFETY: a plain query on a loaded entry.
    let Ok(layers) = (unsafe { entry.enumerate_instance_layer_properties() }) else {
        return false;
    };
    layers.iter().any(|layer| {
        layer
            .layer_name_as_c_str()
            .is_ok_and(|name| name == c"VK_LAYER_KHRONOS_validation")
    })
}

/// Validation-layer reports that are wrong, matched by exact text. Each needs a reason.
pub const KNOWN_FALSE_POSITIVES: &[&str] = &[
    // Debian's vulkan-validationlayers 1.3.239 predates SourceLanguage WGSL (10), which naga
    // writes into OpSource when InstanceFlags::DEBUG is set; newer layers accept it.
    "Invalid source language operand: 10",
];

type ErrorSink = Arc<Mutex<Vec<String>>>;

/// The process-wide list of errors captured since the running test began.
fn captured_errors() -> &'static ErrorSink {
    static SINK: OnceLock<ErrorSink> = OnceLock::new();
    SINK.get_or_init(|| {
        let sink = ErrorSink::default();
        let logger = CapturingLogger {
            sink: Arc::clone(&sink),
            last_report_captured: false.into(),
            last_report_suppressed: false.into(),
        };
        if log::set_boxed_logger(Box::new(logger)).is_ok() {
            // wgpu-hal asks the layer for warnings only when the log level allows them.
            log::set_max_level(log::LevelFilter::Warn);
        }
        sink
    })
}

/// Records error-level messages from wgpu and naga and the Khronos layer's warnings (its
/// reports reach the log through wgpu-hal as `VALIDATION [..]` records), and echoes warnings and
/// errors to stderr.
struct CapturingLogger {
    sink: ErrorSink,
    /// wgpu-hal logs a report's objects and labels as follow-up records starting with a tab;
    /// they belong to the report before them and share its fate: captured or echoed, and
    /// suppressed with it.
    last_report_captured: std::sync::atomic::AtomicBool,
    last_report_suppressed: std::sync::atomic::AtomicBool,
}

impl log::Log for CapturingLogger {
    fn enabled(&self, metadata: &log::Metadata<'_>) -> bool {
        metadata.level() <= log::Level::Warn
    }

    fn log(&self, record: &log::Record<'_>) {
        if !self.enabled(record.metadata()) {
            return;
        }
        use std::sync::atomic::Ordering::Relaxed;
        let target = record.target();
        let text = record.args().to_string();
        let is_detail = text.starts_with('\t');
        if !is_detail {
            let from_gpu_stack = target.starts_with("wgpu") || target.starts_with("naga");
            let layer_warning = record.level() == log::Level::Warn
                && target.starts_with("wgpu_hal::vulkan")
                && text.starts_with("VALIDATION [");
            let captured = from_gpu_stack && (record.level() == log::Level::Error || layer_warning);
            let suppressed = KNOWN_FALSE_POSITIVES.iter().any(|fp| text.contains(fp));
            self.last_report_captured.store(captured, Relaxed);
            self.last_report_suppressed
                .store(captured && suppressed, Relaxed);
        }
        if !self.last_report_captured.load(Relaxed) {
            eprintln!("[{}] {target}: {text}", record.level());
            return;
        }
        if self.last_report_suppressed.load(Relaxed) {
            if !is_detail {
                eprintln!("[suppressed known false positive] {target}: {text}");
            }
            return;
        }
        eprintln!("[{}] {target}: {text}", record.level());
        let mut sink = self.sink.lock().unwrap_or_else(PoisonError::into_inner);
        match sink.last_mut() {
            Some(report) if is_detail => {
                report.push('\n');
                report.push_str(&text);
            }
            _ => sink.push(format!("{target}: {text}")),
        }
    }

    fn flush(&self) {}
}
