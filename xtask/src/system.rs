//! System packages the tests need: a Vulkan driver, the Khronos validation layer, spirv-val, Xvfb
//! and a font.
//!
//! On a Debian/Ubuntu machine where we run as root, missing packages are installed with apt;
//! anywhere else the command stops and names the packages to install.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context as _, Result, bail};

/// A system requirement, the Debian packages that provide it, and whether it is present.
#[derive(Debug)]
struct Requirement {
    what: &'static str,
    packages: &'static [&'static str],
    present: fn() -> bool,
}

const REQUIREMENTS: &[Requirement] = &[
    Requirement {
        what: "a Vulkan adapter (a GPU driver, or Mesa's software driver lavapipe)",
        packages: &["mesa-vulkan-drivers", "libvulkan1"],
        present: has_vulkan_adapter,
    },
    Requirement {
        what: "the Khronos Vulkan validation layer",
        packages: &["vulkan-validationlayers"],
        present: has_validation_layer,
    },
    Requirement {
        what: "spirv-val (SPIR-V validation of generated shaders)",
        packages: &["spirv-tools"],
        present: has_spirv_val,
    },
    Requirement {
        what: "Xvfb and the X11 client libraries (the viewer's windowed test)",
        packages: &[
            "xvfb",
            "xauth",
            "libxcursor1",
            "libxrandr2",
            "libxi6",
            "libx11-xcb1",
            "libxkbcommon-x11-0",
        ],
        present: has_xvfb,
    },
    Requirement {
        what: "a TrueType font (the benchmark's charts and their tests)",
        packages: &["fonts-dejavu-core"],
        present: has_chart_font,
    },
];

fn has_chart_font() -> bool {
    crate::bench::charts::FONT_PATHS
        .iter()
        .any(|p| Path::new(p).is_file())
}

/// Makes sure every requirement of `cargo xtask test` is present, installing what is missing
/// where we can.
pub fn ensure_test_requirements() -> Result<()> {
    ensure(&REQUIREMENTS.iter().collect::<Vec<_>>(), "test")
}

/// Makes sure a Vulkan adapter exists (the software driver is enough), installing Mesa's where
/// we can: what `cargo xtask demo` and `render` need.
pub fn ensure_vulkan_adapter() -> Result<()> {
    ensure(&[&REQUIREMENTS[0]], "demo")
}

/// Installs the packages of the missing `requirements` (Debian/Ubuntu as root), or stops naming
/// them and the command to run.
#[expect(
    clippy::print_stdout,
    reason = "progress report of a command-line tool"
)]
fn ensure(requirements: &[&Requirement], command: &str) -> Result<()> {
    let missing: Vec<&Requirement> = requirements
        .iter()
        .copied()
        .filter(|r| !(r.present)())
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    let packages: Vec<&str> = missing.iter().flat_map(|r| r.packages).copied().collect();
    let needs = missing
        .iter()
        .map(|r| r.what)
        .collect::<Vec<_>>()
        .join("; ");
    if !(is_debian_like() && is_root()) {
        bail!(
            "missing: {needs}.\nInstall the Debian/Ubuntu packages: sudo apt-get install {}\n\
             (cargo xtask {command} installs them itself when run as root on Debian/Ubuntu)",
            packages.join(" ")
        );
    }
    println!("xtask: missing {needs}; installing {}", packages.join(" "));
    apt(&["update"])?;
    let mut install = vec!["install", "-y", "--no-install-recommends"];
    install.extend(&packages);
    apt(&install)?;
    if let Some(still) = missing.iter().find(|r| !(r.present)()) {
        bail!(
            "installed {} but still missing {}",
            packages.join(" "),
            still.what
        );
    }
    Ok(())
}

/// Gives the process a private `XDG_RUNTIME_DIR` when it has none, so that Mesa does not print
/// "XDG_RUNTIME_DIR is invalid or not set" on every device it opens. Child processes (the
/// tests) inherit it. Call before any thread starts.
pub fn private_runtime_dir() -> Result<()> {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|d| Path::new(&d).is_dir()) {
        return Ok(());
    }
    #[cfg(unix)]
    let user = {
        use std::os::unix::fs::MetadataExt as _;
        std::fs::metadata("/proc/self").map_or(0, |m| m.uid())
    };
    #[cfg(not(unix))]
    let user = 0;
    let dir = std::env::temp_dir().join(format!("xtask-runtime-{user}"));
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700))
            .with_context(|| format!("making {} private", dir.display()))?;
    }
    // SAFETY: called first thing in `main`, before any other thread exists.
    unsafe { std::env::set_var("XDG_RUNTIME_DIR", &dir) };
    Ok(())
}

fn apt(args: &[&str]) -> Result<()> {
    let status = Command::new("apt-get")
        .args(args)
        .env("DEBIAN_FRONTEND", "noninteractive")
        .status()
        .context("running apt-get")?;
    if !status.success() {
        bail!("apt-get {} failed with {status}", args.join(" "));
    }
    Ok(())
}

fn has_vulkan_adapter() -> bool {
    let options = renderer::GpuOptions {
        backends: wgpu::Backends::VULKAN,
        ..renderer::GpuOptions::default()
    };
    !pollster::block_on(renderer::gpu::enumerate_adapters(&options)).is_empty()
}

fn has_xvfb() -> bool {
    let on_path = Command::new("xvfb-run")
        .arg("--help")
        .output()
        .is_ok_and(|o| o.status.success() || !o.stdout.is_empty() || !o.stderr.is_empty());
    let libraries = Command::new("ldconfig")
        .arg("-p")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
        .unwrap_or_default();
    on_path
        && [
            "libxkbcommon-x11.so.0",
            "libXcursor.so.1",
            "libXrandr.so.2",
            "libXi.so.6",
            "libX11-xcb.so.1",
        ]
        .iter()
        .all(|l| libraries.contains(l))
}

fn has_spirv_val() -> bool {
    Command::new("spirv-val")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Looks for the layer manifest where the Vulkan loader looks for explicit layers.
fn has_validation_layer() -> bool {
    layer_search_dirs()
        .iter()
        .any(|dir| dir.join("VkLayer_khronos_validation.json").is_file())
}

fn layer_search_dirs() -> Vec<PathBuf> {
    let env_paths = |var: &str| -> Vec<PathBuf> {
        std::env::var_os(var)
            .map(|v| std::env::split_paths(&v).collect())
            .unwrap_or_default()
    };
    let mut dirs = env_paths("VK_LAYER_PATH");
    dirs.extend(env_paths("VK_ADD_LAYER_PATH"));
    let mut data_dirs = env_paths("XDG_DATA_HOME");
    let xdg = env_paths("XDG_DATA_DIRS");
    if xdg.is_empty() {
        data_dirs.extend(["/usr/local/share", "/usr/share"].map(PathBuf::from));
    } else {
        data_dirs.extend(xdg);
    }
    data_dirs.extend(["/etc", "/etc/xdg"].map(PathBuf::from));
    dirs.extend(data_dirs.iter().map(|d| d.join("vulkan/explicit_layer.d")));
    dirs
}

fn is_debian_like() -> bool {
    Path::new("/etc/debian_version").exists()
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}
