//! "No hand-written source file over 500 lines": the size at which a file stops being read as
//! one thing. Tests live in their own files to stay under it. There are no exceptions: the last
//! one (the TBDR shader module) split once a DSL library could use another.

/// The most lines a hand-written `.rs` file may have.
pub const MAX_LINES: usize = 500;

/// The folders of a crate whose `.rs` files are hand-written sources.
pub const SOURCE_FOLDERS: &[&str] = &["src", "tests", "benches", "examples", "fuzz_targets"];

/// Every file of `files` (workspace-relative path, text) over [`MAX_LINES`] lines, with its
/// line count.
pub fn long_files(files: &[(String, String)]) -> Vec<(String, usize)> {
    files
        .iter()
        .map(|(path, text)| (path.clone(), text.lines().count()))
        .filter(|&(_, lines)| lines > MAX_LINES)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(path: &str, lines: usize) -> (String, String) {
        (path.to_owned(), "x\n".repeat(lines))
    }

    #[test]
    fn a_file_over_the_limit_fails_and_one_at_it_passes() {
        let long = long_files(&[file("a/src/long.rs", 501), file("a/src/ok.rs", 500)]);
        assert_eq!(long, [("a/src/long.rs".to_owned(), 501)]);
    }
}
