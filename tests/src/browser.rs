//! Headless Chromium for tests: [`run_page`] serves a page and its files on loopback, opens it
//! in Debian's `chromium` with WebGPU on (its built-in SwiftShader Vulkan driver: no GPU
//! needed), and returns what the page POSTs to `/result`.
//!
//! `cargo xtask test` installs `chromium` where it is missing (Debian, as root). A machine
//! without it fails the test loudly, naming the package; it never skips.

use std::io::{BufRead as _, BufReader, Read as _, Write as _};
use std::net::{TcpListener, TcpStream};
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

/// A file the page may fetch: its path under `/`, its content type, its bytes.
#[derive(Debug, Clone)]
pub struct ServedFile {
    /// Path without the leading `/` (`index.html`, `variants.json`).
    pub path: String,
    /// `Content-Type`.
    pub content_type: &'static str,
    /// The body.
    pub bytes: Vec<u8>,
}

/// The Chromium binary: `$CHROMIUM`, or Debian's `/usr/bin/chromium`.
pub fn chromium_path() -> Result<PathBuf, String> {
    let path = std::env::var_os("CHROMIUM")
        .map_or_else(|| PathBuf::from("/usr/bin/chromium"), PathBuf::from);
    if path.exists() {
        Ok(path)
    } else {
        Err(format!(
            "no Chromium at {} (install Debian's `chromium` package, or set CHROMIUM; \
             `cargo xtask test` installs it as root on Debian)",
            path.display()
        ))
    }
}

/// Opens `page` (a path of `files` with an optional query, `index.html?path=tiled`) in headless
/// Chromium and returns the body the page POSTs to `/result`, or an error if Chromium cannot
/// start or the page posts nothing within `timeout`.
pub fn run_page(files: Vec<ServedFile>, page: &str, timeout: Duration) -> Result<String, String> {
    let chromium = chromium_path()?;
    let listener =
        TcpListener::bind("127.0.0.1:0").map_err(|e| format!("binding loopback: {e}"))?;
    let port = listener
        .local_addr()
        .map_err(|e| format!("loopback address: {e}"))?
        .port();
    let (sender, results) = mpsc::channel();
    // The server thread lives until the test process ends; it only answers loopback requests.
    std::thread::spawn(move || serve_files(&listener, &files, &sender));
    let profile = tempdir()?;
    let mut child = Command::new(&chromium)
        .args([
            "--headless=new",
            "--no-sandbox",
            "--enable-unsafe-webgpu",
            "--enable-features=Vulkan",
            "--use-webgpu-adapter=swiftshader",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-quic",
            "--disable-default-apps",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("http://127.0.0.1:{port}/{page}"))
        .stdout(Stdio::null())
        .stderr(log_file(&profile)?)
        .spawn()
        .map_err(|e| format!("starting {}: {e}", chromium.display()))?;
    let outcome = results.recv_timeout(timeout);
    let _ = child.kill();
    let _ = child.wait();
    let stderr = std::fs::read_to_string(profile.join(LOG)).unwrap_or_default();
    let _ = std::fs::remove_dir_all(&profile);
    outcome.map_err(|_| {
        format!(
            "the page posted no result within {timeout:?}; Chromium's last output:\n{}",
            tail(&stderr, 40)
        )
    })
}

/// Answers `listener`'s requests with `files` until it closes: each `GET` of a file's path,
/// and each `POST /result` body sent on to `results`.
pub fn serve_files(listener: &TcpListener, files: &[ServedFile], results: &mpsc::Sender<String>) {
    for stream in listener.incoming().flatten() {
        let _ = serve(stream, files, results);
    }
}

/// Every file under `dir` (recursively), served under its path relative to `dir`, with its
/// content type from its extension (`application/wasm` for `.wasm`, which browsers need to
/// compile a module while it downloads).
pub fn files_under(dir: &std::path::Path) -> Result<Vec<ServedFile>, String> {
    let mut files = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(folder) = pending.pop() {
        let entries =
            std::fs::read_dir(&folder).map_err(|e| format!("reading {}: {e}", folder.display()))?;
        for entry in entries {
            let path = entry
                .map_err(|e| format!("reading {}: {e}", folder.display()))?
                .path();
            if path.is_dir() {
                pending.push(path);
                continue;
            }
            let relative = path
                .strip_prefix(dir)
                .map_err(|e| format!("{}: {e}", path.display()))?;
            let content_type = match path.extension().and_then(|e| e.to_str()) {
                Some("html") => "text/html; charset=utf-8",
                Some("js") => "text/javascript",
                Some("wasm") => "application/wasm",
                Some("json") => "application/json",
                _ => "application/octet-stream",
            };
            files.push(ServedFile {
                path: relative.to_string_lossy().replace('\\', "/"),
                content_type,
                bytes: std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?,
            });
        }
    }
    Ok(files)
}

/// Answers one request: a served file, the posted result (sent on), or 404.
fn serve(
    stream: TcpStream,
    files: &[ServedFile],
    results: &mpsc::Sender<String>,
) -> std::io::Result<()> {
    let mut reader = BufReader::new(stream.try_clone()?);
    let mut request = String::new();
    reader.read_line(&mut request)?;
    let mut length = 0usize;
    loop {
        let mut line = String::new();
        if reader.read_line(&mut line)? == 0 || line.trim().is_empty() {
            break;
        }
        if let Some((name, value)) = line.split_once(':')
            && name.eq_ignore_ascii_case("content-length")
        {
            length = value.trim().parse().unwrap_or(0);
        }
    }
    let mut parts = request.split_whitespace();
    let (method, path) = (parts.next().unwrap_or(""), parts.next().unwrap_or("/"));
    // The query is the page's; `/` is its index.
    let path = path.split('?').next().unwrap_or("").trim_start_matches('/');
    let path = if path.is_empty() { "index.html" } else { path };
    let mut stream = stream;
    if method == "POST" && path == "result" {
        let mut body = vec![0; length];
        reader.read_exact(&mut body)?;
        respond(&mut stream, "200 OK", "text/plain", b"ok")?;
        let _ = results.send(String::from_utf8_lossy(&body).into_owned());
        return Ok(());
    }
    match files.iter().find(|f| f.path == path) {
        Some(f) => respond(&mut stream, "200 OK", f.content_type, &f.bytes),
        None => respond(&mut stream, "404 Not Found", "text/plain", b"not found"),
    }
}

fn respond(
    stream: &mut TcpStream,
    status: &str,
    content_type: &str,
    body: &[u8],
) -> std::io::Result<()> {
    write!(
        stream,
        "HTTP/1.1 {status}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\n\
         Cache-Control: no-store\r\nConnection: close\r\n\r\n",
        body.len()
    )?;
    stream.write_all(body)?;
    stream.flush()
}

/// Where Chromium's stderr goes, in its profile folder (a file, so a chatty browser never
/// blocks on a full pipe).
const LOG: &str = "stderr.log";

fn log_file(profile: &std::path::Path) -> Result<std::fs::File, String> {
    std::fs::File::create(profile.join(LOG)).map_err(|e| format!("creating Chromium's log: {e}"))
}

fn tail(text: &str, lines: usize) -> String {
    let all: Vec<&str> = text.lines().collect();
    all[all.len().saturating_sub(lines)..].join("\n")
}

/// A fresh profile folder for one Chromium run.
fn tempdir() -> Result<PathBuf, String> {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let dir = std::env::temp_dir().join(format!("chromium-test-{}-{nanos}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| format!("creating {}: {e}", dir.display()))?;
    Ok(dir)
}
