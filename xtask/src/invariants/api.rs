//! "Engines see the renderer's public API only, and its errors speak that API": the viewer, the
//! web demo and the engine example (the workspace's embedders) never turn on the renderer's
//! `internals` feature, and no renderer message names a command-line flag, which an engine does
//! not have.

/// The manifests of crates that embed the renderer as an engine would (workspace-relative).
pub const EMBEDDER_MANIFESTS: &[&str] = &[
    "viewer/Cargo.toml",
    "web/Cargo.toml",
    "examples/engine/Cargo.toml",
    "examples/engine/app/Cargo.toml",
    "examples/engine/shaders/Cargo.toml",
];

/// Where an embedder's manifest turns on the renderer's `internals` feature, and what to do.
pub fn embedders_using_internals(manifests: &[(String, String)]) -> Vec<String> {
    manifests
        .iter()
        .flat_map(|(path, text)| {
            text.lines().enumerate().filter_map(move |(i, line)| {
                let code = line.split('#').next().unwrap_or_default();
                (code.contains("renderer") && code.contains("\"internals\"")).then(|| {
                    format!(
                        "{path}:{}: turns on `internals`; use the public API, or make what is \
                         missing public and documented",
                        i + 1
                    )
                })
            })
        })
        .collect()
}

/// Renderer source lines whose string literals name a command-line flag (`--name`), and what
/// to do.
pub fn messages_naming_flags(sources: &[(String, String)]) -> Vec<String> {
    sources
        .iter()
        .flat_map(|(path, text)| {
            text.lines().enumerate().filter_map(move |(i, line)| {
                let code = line.trim_start();
                if code.starts_with("//") {
                    return None;
                }
                let flag = quoted_parts(line).find_map(|part| flag_in(part))?;
                Some(format!(
                    "{path}:{}: a message names `{flag}`; name the API field or function",
                    i + 1
                ))
            })
        })
        .collect()
}

/// The parts of `line` inside double quotes (a string that continues on the next line counts
/// to the end of this one).
fn quoted_parts(line: &str) -> impl Iterator<Item = &str> {
    line.split('"').skip(1).step_by(2)
}

/// The first `--flag` in `text`: two dashes then a lower-case letter, at a word start.
fn flag_in(text: &str) -> Option<&str> {
    text.match_indices("--").find_map(|(at, _)| {
        let before = text[..at].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '-') {
            return None;
        }
        let rest = &text[at + 2..];
        let len = rest
            .find(|c: char| !(c.is_ascii_lowercase() || c == '-'))
            .unwrap_or(rest.len());
        (len > 0 && rest.starts_with(|c: char| c.is_ascii_lowercase()))
            .then(|| &text[at..at + 2 + len])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(path: &str, text: &str) -> Vec<(String, String)> {
        vec![(path.to_owned(), text.to_owned())]
    }

    #[test]
    fn an_embedder_turning_on_internals_fails_and_one_without_passes() {
        let bad = file(
            "viewer/Cargo.toml",
            "[dependencies]\nrenderer = { workspace = true, features = [\"demo\", \"internals\"] }\n",
        );
        assert_eq!(embedders_using_internals(&bad).len(), 1);
        let good = file(
            "viewer/Cargo.toml",
            "[dependencies]\nrenderer = { workspace = true, features = [\"demo\"] }\n# not \"internals\" renderer\n",
        );
        assert!(embedders_using_internals(&good).is_empty());
    }

    #[test]
    fn a_message_naming_a_flag_fails_and_api_names_pass() {
        let bad = file(
            "renderer/src/x.rs",
            "    #[error(\"pick another adapter (a tool's --adapter)\")]\n",
        );
        let found = messages_naming_flags(&bad);
        assert_eq!(found.len(), 1);
        assert!(found[0].contains("`--adapter`"), "{}", found[0]);
        let good = file(
            "renderer/src/x.rs",
            "// a comment may say --adapter\n    #[error(\"set GpuOptions::adapter; x--y and -- alone are no flags\")]\n    let n = a -- b;\n",
        );
        assert!(messages_naming_flags(&good).is_empty());
    }
}
