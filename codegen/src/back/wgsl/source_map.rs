//! Source map: which Rust span produced each byte range of the printed WGSL.

use proc_macro2::Span;
use std::ops::Range;

/// Byte ranges of the WGSL text and the Rust spans that produced them.
#[derive(Debug, Clone, Default)]
pub struct SourceMap {
    entries: Vec<(Range<usize>, Span)>,
}

impl SourceMap {
    /// Records that `range` was printed for `span`.
    pub fn record(&mut self, range: Range<usize>, span: Span) {
        if !range.is_empty() {
            self.entries.push((range, span));
        }
    }

    /// The span of the smallest recorded range containing `range` (or, failing that, its
    /// start).
    pub fn lookup(&self, range: Range<usize>) -> Option<Span> {
        let best = |pred: &dyn Fn(&Range<usize>) -> bool| {
            self.entries
                .iter()
                .filter(|(r, _)| pred(r))
                .min_by_key(|(r, _)| r.len())
                .map(|(_, s)| *s)
        };
        best(&|r| r.start <= range.start && range.end <= r.end)
            .or_else(|| best(&|r| r.contains(&range.start)))
    }

    /// Number of recorded ranges.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}
