//! System packages the tests need: a Vulkan driver, the Khronos validation layer, spirv-val,
//! Xvfb and Chromium (the benchmark charts' font is embedded in the binary); and the Rust
//! wasm32 target, added with rustup.
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
    /// On Debian 12 (bookworm), install the packages from bookworm-backports: its own
    /// versions are too old.
    backports: bool,
}

/// The oldest Mesa whose software Vulkan driver the tests accept: Mesa 22.3's lavapipe keeps
/// about 2.2 MB per draw call every frame (measured: 20 MB a frame of the committed scene, 340
/// MB a frame of the courtyard, while wgpu's live objects and the frame graph's pool stay
/// flat), so the 1,000-frame soak test ran the machine out of memory; Mesa 25.0's does not.
const MIN_SOFTWARE_MESA: u32 = 24;

const REQUIREMENTS: &[Requirement] = &[
    Requirement {
        what: "a Vulkan adapter (a GPU driver, or Mesa's software driver lavapipe)",
        packages: &["mesa-vulkan-drivers", "libvulkan1"],
        present: has_vulkan_adapter,
        backports: false,
    },
    Requirement {
        what: "a hardware Vulkan adapter, or Mesa's software driver from Mesa 24 or later (older \
               lavapipe retains memory every draw call)",
        packages: &["mesa-vulkan-drivers"],
        present: has_hardware_or_recent_software_adapter,
        backports: true,
    },
    Requirement {
        what: "the Khronos Vulkan validation layer",
        packages: &["vulkan-validationlayers"],
        present: has_validation_layer,
        backports: false,
    },
    Requirement {
        what: "spirv-val (SPIR-V validation of generated shaders)",
        packages: &["spirv-tools"],
        present: has_spirv_val,
        backports: false,
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
        backports: false,
    },
    Requirement {
        what: "Chromium (every shader variant compiled by a browser's WebGPU, headless)",
        packages: &["chromium"],
        present: has_chromium,
        backports: false,
    },
];

/// Makes sure every requirement of `cargo xtask test` is present, installing what is missing
/// where we can.
pub fn ensure_test_requirements() -> Result<()> {
    ensure(&REQUIREMENTS.iter().collect::<Vec<_>>(), "test")
}

/// Makes sure a Vulkan adapter exists (any software driver is enough for a few frames),
/// installing Mesa's where we can: what `cargo xtask demo` and `render` need.
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
    let (newer, current): (Vec<&Requirement>, Vec<&Requirement>) = missing
        .iter()
        .partition(|r| r.backports && debian_codename().as_deref() == Some("bookworm"));
    if !newer.is_empty() {
        add_bookworm_backports()?;
    }
    apt(&["update"])?;
    for (group, release) in [(current, None), (newer, Some("bookworm-backports"))] {
        let packages: Vec<&str> = group.iter().flat_map(|r| r.packages).copied().collect();
        if packages.is_empty() {
            continue;
        }
        let mut install = vec!["install", "-y", "--no-install-recommends"];
        if let Some(release) = release {
            install.extend(["-t", release]);
        }
        install.extend(&packages);
        apt(&install)?;
    }
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

/// The Vulkan adapters of this machine.
fn vulkan_adapters() -> Vec<wgpu::Adapter> {
    let options = renderer::GpuOptions {
        backends: wgpu::Backends::VULKAN,
        ..renderer::GpuOptions::default()
    };
    pollster::block_on(renderer::gpu::enumerate_adapters(&options))
}

fn has_vulkan_adapter() -> bool {
    !vulkan_adapters().is_empty()
}

/// Whether a hardware Vulkan adapter exists, or the software one is lavapipe from Mesa
/// [`MIN_SOFTWARE_MESA`] or later (its driver info reads "Mesa 25.0.7 (LLVM 15.0.6)").
fn has_hardware_or_recent_software_adapter() -> bool {
    vulkan_adapters().iter().any(|a| {
        let info = a.get_info();
        info.device_type != wgpu::DeviceType::Cpu
            || mesa_major(&info.driver_info).is_some_and(|m| m >= MIN_SOFTWARE_MESA)
    })
}

/// The major version in a Mesa driver-info string ("Mesa 22.3.6 (LLVM 15.0.6)" gives 22).
fn mesa_major(driver_info: &str) -> Option<u32> {
    let rest = driver_info.split("Mesa ").nth(1)?;
    rest.split('.').next()?.trim().parse().ok()
}

/// The Debian release's code name (`VERSION_CODENAME` of `/etc/os-release`).
fn debian_codename() -> Option<String> {
    let release = std::fs::read_to_string("/etc/os-release").ok()?;
    release
        .lines()
        .find_map(|l| l.strip_prefix("VERSION_CODENAME="))
        .map(|v| v.trim_matches('"').to_owned())
}

/// Adds Debian's bookworm-backports archive to apt's sources, from the mirror the machine's
/// own sources name for bookworm (packages come from it only when asked for with
/// `-t bookworm-backports`).
fn add_bookworm_backports() -> Result<()> {
    let mirror = debian_mirror().context(
        "no Debian mirror for bookworm in /etc/apt/sources.list or /etc/apt/sources.list.d; \
         add bookworm-backports to apt's sources and install mesa-vulkan-drivers from it",
    )?;
    let list = Path::new("/etc/apt/sources.list.d/xtask-bookworm-backports.list");
    let line = format!("deb {mirror} bookworm-backports main\n");
    std::fs::write(list, line).with_context(|| format!("writing {}", list.display()))
}

/// The URI of the first apt source of the machine that serves bookworm's main archive.
fn debian_mirror() -> Option<String> {
    let mut files = vec![PathBuf::from("/etc/apt/sources.list")];
    if let Ok(dir) = std::fs::read_dir("/etc/apt/sources.list.d") {
        let mut listed: Vec<PathBuf> = dir.filter_map(|e| e.ok().map(|e| e.path())).collect();
        listed.retain(|f| f.extension().is_some_and(|e| e == "list" || e == "sources"));
        listed.sort();
        files.extend(listed);
    }
    files
        .iter()
        .filter_map(|f| std::fs::read_to_string(f).ok())
        .find_map(|text| bookworm_mirror_in(&text))
}

/// The URI serving bookworm (not its security updates) in one apt sources file: one-line
/// (`deb URI bookworm main`) or deb822 (`URIs:` with `Suites: bookworm ...`).
fn bookworm_mirror_in(text: &str) -> Option<String> {
    for line in text.lines() {
        if let ["deb", uri, "bookworm", ..] = line.split_whitespace().collect::<Vec<_>>()[..] {
            return Some(uri.to_owned());
        }
    }
    text.split("\n\n").find_map(|stanza| {
        let field = |name: &str| stanza.lines().find_map(|l| l.strip_prefix(name));
        let serves =
            field("Suites:").is_some_and(|s| s.split_whitespace().any(|s| s == "bookworm"));
        let uri = field("URIs:")?.split_whitespace().next()?;
        serves.then(|| uri.to_owned())
    })
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

/// The Rust target of the renderer in a browser.
pub const WASM_TARGET: &str = "wasm32-unknown-unknown";

/// Adds [`WASM_TARGET`] to the toolchain with rustup where it is missing.
#[expect(
    clippy::print_stdout,
    reason = "progress report of a command-line tool"
)]
pub fn ensure_wasm_target() -> Result<()> {
    let installed = Command::new("rustup")
        .args(["target", "list", "--installed"])
        .output()
        .context("running rustup (the wasm32 target is added with it)")?;
    if String::from_utf8_lossy(&installed.stdout)
        .lines()
        .any(|l| l.trim() == WASM_TARGET)
    {
        return Ok(());
    }
    println!("xtask: adding the Rust target {WASM_TARGET}");
    let status = Command::new("rustup")
        .args(["target", "add", WASM_TARGET])
        .status()
        .context("running rustup target add")?;
    if !status.success() {
        bail!("rustup target add {WASM_TARGET} failed with {status}");
    }
    Ok(())
}

/// Debian's Chromium, where `tests::browser` looks for it (`$CHROMIUM` overrides both).
fn has_chromium() -> bool {
    std::env::var_os("CHROMIUM").map_or_else(
        || Path::new("/usr/bin/chromium").is_file(),
        |p| Path::new(&p).is_file(),
    )
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mesa_versions_and_mirrors_are_read() {
        assert_eq!(mesa_major("Mesa 22.3.6 (LLVM 15.0.6)"), Some(22));
        assert_eq!(mesa_major("Mesa 25.0.7-2~bpo12+1 (LLVM 15.0.6)"), Some(25));
        assert_eq!(mesa_major("580.159.04"), None);
        let deb822 = "Types: deb\nURIs: http://mirror.example/debian\nSuites: bookworm \
                      bookworm-updates\nComponents: main\n\nTypes: deb\nURIs: \
                      http://mirror.example/debian-security\nSuites: bookworm-security\n";
        assert_eq!(
            bookworm_mirror_in(deb822).as_deref(),
            Some("http://mirror.example/debian")
        );
        let one_line = "deb http://mirror.example/security bookworm-security main\n\
                        deb http://mirror.example/debian bookworm main contrib\n";
        assert_eq!(
            bookworm_mirror_in(one_line).as_deref(),
            Some("http://mirror.example/debian")
        );
        assert_eq!(bookworm_mirror_in("deb http://x/ubuntu noble main\n"), None);
    }
}
