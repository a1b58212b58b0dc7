//! `cargo xtask web`: builds the web demo (the `web` crate for `wasm32-unknown-unknown` in
//! release, or the dev profile with `--dev`, its JavaScript bindings by `wasm-bindgen`'s own
//! library, and `web/index.html`) into `target/web/`, then serves that folder on loopback until
//! stopped. Adds the wasm target with rustup where it is missing; `cargo xtask test` builds the
//! demo with the dev profile before the browser frame test reads it.

use std::path::PathBuf;
use std::process::Command;

use anyhow::{Context as _, Result, ensure};

#[derive(Debug, clap::Args)]
pub struct Args {
    /// Build `target/web/` and stop, without serving it.
    #[arg(long)]
    pub build_only: bool,
    /// Loopback port to serve the page on.
    #[arg(long, default_value_t = 8000)]
    pub port: u16,
    /// Build with the dev profile: minutes faster to build from scratch (the DSL compiler's
    /// host build is the tests'), larger (7.8 MB against 4.8) and slower to run. The browser
    /// test's build.
    #[arg(long)]
    pub dev: bool,
}

/// Which cargo profile the module is built with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Profile {
    /// `--release`: what `cargo xtask web` serves.
    Release,
    /// The dev profile: what `cargo xtask test` builds for the browser test.
    Dev,
}

/// What a build wrote and how big the module is.
#[derive(Debug)]
pub struct Built {
    /// The folder holding `index.html` and `pkg/`.
    pub dir: PathBuf,
    /// The wasm module's size in bytes, and gzipped.
    pub wasm_bytes: u64,
    pub wasm_gzipped: u64,
}

#[expect(
    clippy::print_stdout,
    reason = "progress report of a command-line tool"
)]
pub fn run(args: &Args) -> Result<()> {
    let built = build(if args.dev {
        Profile::Dev
    } else {
        Profile::Release
    })?;
    println!(
        "web: {} (wasm {:.2} MB, {:.2} MB gzipped)",
        built.dir.display(),
        built.wasm_bytes as f64 / 1e6,
        built.wasm_gzipped as f64 / 1e6
    );
    if args.build_only {
        return Ok(());
    }
    let files = ::tests::browser::files_under(&built.dir).map_err(anyhow::Error::msg)?;
    let listener = std::net::TcpListener::bind(("127.0.0.1", args.port))
        .with_context(|| format!("binding 127.0.0.1:{}", args.port))?;
    println!(
        "web: open http://127.0.0.1:{}/ in a browser with WebGPU (Chromium: \
         --enable-unsafe-webgpu); Ctrl-C stops",
        args.port
    );
    let (results, _unused) = std::sync::mpsc::channel();
    ::tests::browser::serve_files(&listener, &files, &results);
    Ok(())
}

/// The folder the web demo is built into: `target/web` of the workspace (or of
/// `CARGO_TARGET_DIR`), where `tests::browser` looks for it too.
pub fn out_dir() -> PathBuf {
    target_dir().join("web")
}

fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR").map_or_else(
        || crate::workspace::workspace_root().join("target"),
        PathBuf::from,
    )
}

/// Builds the demo into [`out_dir`]: the wasm module of `profile`, its bindings and the page.
pub fn build(profile: Profile) -> Result<Built> {
    let root = crate::workspace::workspace_root();
    crate::system::ensure_wasm_target()?;
    let mut cargo = Command::new(env!("CARGO"));
    cargo.args([
        "build",
        "-p",
        "web-demo",
        "--target",
        crate::system::WASM_TARGET,
    ]);
    if profile == Profile::Release {
        cargo.arg("--release");
    }
    let status = cargo
        .current_dir(&root)
        .status()
        .context("running cargo build -p web-demo")?;
    ensure!(
        status.success(),
        "cargo build -p web-demo failed with {status}"
    );
    let folder = match profile {
        Profile::Release => "release",
        Profile::Dev => "debug",
    };
    let module = target_dir()
        .join(crate::system::WASM_TARGET)
        .join(folder)
        .join("web_demo.wasm");
    let dir = out_dir();
    let pkg = dir.join("pkg");
    if pkg.exists() {
        std::fs::remove_dir_all(&pkg).with_context(|| format!("clearing {}", pkg.display()))?;
    }
    // What `wasm-bindgen --target web --no-typescript` writes: the module and its ES module,
    // whose `init()` fetches the module beside it (the library's default omits that path).
    wasm_bindgen_cli_support::Bindgen::new()
        .input_path(&module)
        .web(true)?
        .typescript(false)
        .omit_default_module_path(false)
        .generate(&pkg)
        .with_context(|| format!("writing the bindings of {}", module.display()))?;
    std::fs::copy(root.join("web/index.html"), dir.join("index.html"))
        .context("copying web/index.html")?;
    let wasm = std::fs::read(pkg.join("web_demo_bg.wasm")).context("reading the built module")?;
    Ok(Built {
        dir,
        wasm_bytes: wasm.len() as u64,
        wasm_gzipped: gzipped_len(&wasm)?,
    })
}

/// The size of `bytes` gzipped at the default level, as a web server would send them.
fn gzipped_len(bytes: &[u8]) -> Result<u64> {
    use std::io::Write as _;
    let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    encoder.write_all(bytes)?;
    Ok(encoder.finish()?.len() as u64)
}

#[cfg(test)]
mod tests {
    /// The version `lock` (a `Cargo.lock`) holds for package `name` (the first, where several).
    fn locked_version(lock: &str, name: &str) -> Option<String> {
        let mut lines = lock.lines();
        while let Some(line) = lines.next() {
            if line.trim() == format!("name = \"{name}\"") {
                let version = lines.next()?.trim().strip_prefix("version = \"")?;
                return Some(version.trim_end_matches('"').to_owned());
            }
        }
        None
    }

    /// The bindings generator and the crate the module is built with are one version: a
    /// mismatch fails only when the bindings are written, with wasm-bindgen's schema error.
    #[test]
    fn the_bindings_generator_matches_the_wasm_bindgen_crate() {
        let root = crate::workspace::workspace_root();
        let lock = std::fs::read_to_string(root.join("Cargo.lock")).expect("Cargo.lock");
        let crate_version = locked_version(&lock, "wasm-bindgen").expect("wasm-bindgen locked");
        assert_eq!(
            locked_version(&lock, "wasm-bindgen-cli-support").as_deref(),
            Some(crate_version.as_str()),
            "pin wasm-bindgen-cli-support to wasm-bindgen's version in Cargo.toml"
        );
    }

    #[test]
    fn the_locked_version_is_the_named_package_s() {
        let lock = "[[package]]\nname = \"wasm-bindgen-futures\"\nversion = \"0.4.80\"\n\n\
                    [[package]]\nname = \"wasm-bindgen\"\nversion = \"0.2.130\"\n";
        assert_eq!(
            locked_version(lock, "wasm-bindgen").as_deref(),
            Some("0.2.130")
        );
        assert_eq!(locked_version(lock, "js-sys"), None);
    }
}
