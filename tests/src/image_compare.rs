//! Image comparisons that bound every pixel, for the image tests.
//!
//! A pixel's difference is the largest absolute difference of its compared 8-bit channels.
//! Fractions of an image are counted in pixels, never in channel values: a pixel differs when
//! any one of its channels differs beyond the tolerance.
//!
//! [`compare_to_reference`] is the rule of the committed reference images: every pixel within
//! [`ReferenceBound::tolerance`] per channel, except a stated number of pixels that may differ
//! more, and only the way a rasterised edge moved by one pixel does: each channel within the
//! range its reference neighbourhood (3×3) spans, widened by the tolerance.

/// Each pixel's largest difference over its first `channels` channels (3: RGB, 4: RGBA) of two
/// RGBA8 images of one size.
pub fn pixel_differences(a: &[u8], b: &[u8], channels: usize) -> Vec<u8> {
    assert_eq!(a.len(), b.len(), "images of different sizes");
    a.chunks_exact(4)
        .zip(b.chunks_exact(4))
        .map(|(p, q)| {
            (0..channels)
                .map(|c| p[c].abs_diff(q[c]))
                .max()
                .unwrap_or(0)
        })
        .collect()
}

/// `(mean, 99th percentile, largest)` of per-pixel differences `d`.
pub fn stats(d: &[u8]) -> (f64, u8, u8) {
    let mut s = d.to_vec();
    s.sort_unstable();
    let mean = s.iter().map(|&x| f64::from(x)).sum::<f64>() / s.len().max(1) as f64;
    let at = |q: usize| s.get(s.len() * q / 100).copied().unwrap_or(0);
    (mean, at(99), s.last().copied().unwrap_or(0))
}

/// The largest of `d` where `select(i)` holds for pixel index `i`, with that pixel's index, and
/// how many pixels were selected.
pub fn largest_where(d: &[u8], select: impl Fn(usize) -> bool) -> (u8, Option<usize>, usize) {
    let mut worst = (0, None, 0);
    for (i, &x) in d.iter().enumerate().filter(|(i, _)| select(*i)) {
        worst.2 += 1;
        if worst.1.is_none() || x > worst.0 {
            (worst.0, worst.1) = (x, Some(i));
        }
    }
    worst
}

/// The bound of a reference image comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceBound {
    /// Largest difference of any channel (RGBA) of any pixel that is not an exception.
    pub tolerance: u8,
    /// Most pixels, per thousand of the image's pixels (rounded down), that may differ beyond
    /// `tolerance` as exceptions.
    pub exceptions_per_mille: usize,
}

/// What a reference comparison found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReferenceDiff {
    /// Pixels of the image.
    pub pixels: usize,
    /// The largest channel difference of any pixel.
    pub largest: u8,
    /// Pixels beyond the tolerance (each an exception if it is within its neighbourhood).
    pub beyond: usize,
    /// Exceptions allowed: `pixels * exceptions_per_mille / 1000`.
    pub allowed: usize,
    /// Pixels beyond the tolerance that are also outside their reference neighbourhood's
    /// range widened by the tolerance: `(x, y, got, want)`.
    pub outside_neighbourhood: Vec<(u32, u32, [u8; 4], [u8; 4])>,
}

impl ReferenceDiff {
    /// Whether the comparison passes: no pixel outside its neighbourhood range and at most
    /// `allowed` pixels beyond the tolerance.
    pub fn passes(&self) -> bool {
        self.outside_neighbourhood.is_empty() && self.beyond <= self.allowed
    }
}

/// Compares RGBA8 image `got` with `want`, both `width` pixels wide, under `bound`:
///
/// - every pixel has each channel within `bound.tolerance` of the reference, or
/// - it is one of at most `bound.exceptions_per_mille` ‰ of the pixels, and each of its
///   channels lies within `[min − tolerance, max + tolerance]` of that channel over the
///   reference's 3×3 neighbourhood of the pixel (what an edge moved by one pixel gives: the
///   colour of a neighbour, or a blend of neighbours). So even an exception's difference is
///   bounded: by its neighbourhood's range plus the tolerance, 0 plus the tolerance in a flat
///   region.
pub fn compare_to_reference(
    got: &[u8],
    want: &[u8],
    width: u32,
    bound: ReferenceBound,
) -> ReferenceDiff {
    assert_eq!(got.len(), want.len(), "images of different sizes");
    let pixels = got.len() / 4;
    let height = (pixels / width as usize) as u32;
    let t = bound.tolerance;
    let at = |img: &[u8], x: u32, y: u32| -> [u8; 4] {
        let i = (y * width + x) as usize * 4;
        [img[i], img[i + 1], img[i + 2], img[i + 3]]
    };
    let mut out = ReferenceDiff {
        pixels,
        allowed: pixels * bound.exceptions_per_mille / 1000,
        ..Default::default()
    };
    for y in 0..height {
        for x in 0..width {
            let (g, w) = (at(got, x, y), at(want, x, y));
            let d = (0..4).map(|c| g[c].abs_diff(w[c])).max().unwrap_or(0);
            out.largest = out.largest.max(d);
            if d <= t {
                continue;
            }
            out.beyond += 1;
            let (mut lo, mut hi) = (w, w);
            for v in y.saturating_sub(1)..=(y + 1).min(height - 1) {
                for u in x.saturating_sub(1)..=(x + 1).min(width - 1) {
                    let n = at(want, u, v);
                    for c in 0..4 {
                        lo[c] = lo[c].min(n[c]);
                        hi[c] = hi[c].max(n[c]);
                    }
                }
            }
            let inside =
                (0..4).all(|c| g[c] >= lo[c].saturating_sub(t) && g[c] <= hi[c].saturating_add(t));
            if !inside {
                out.outside_neighbourhood.push((x, y, g, w));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4×4 image: left half black, right half white, opaque.
    fn halves() -> Vec<u8> {
        (0..16)
            .flat_map(|i| {
                let v = if i % 4 < 2 { 0 } else { 255 };
                [v, v, v, 255]
            })
            .collect()
    }

    const BOUND: ReferenceBound = ReferenceBound {
        tolerance: 3,
        exceptions_per_mille: 125,
    };

    #[test]
    fn an_edge_moved_by_a_pixel_is_an_exception_and_counts_in_pixels() {
        let want = halves();
        let mut got = want.clone();
        // Pixel (2, 0) takes its left neighbour's black: within its neighbourhood.
        got[8..11].copy_from_slice(&[0, 0, 0]);
        let d = compare_to_reference(&got, &want, 4, BOUND);
        assert_eq!((d.beyond, d.allowed, d.largest), (1, 2, 255));
        assert!(d.passes(), "{d:?}");
        // Three pixels, whose 9 channel values are fewer than 12.5% of the 64: still fails.
        got[24..27].copy_from_slice(&[0, 0, 0]);
        got[40..43].copy_from_slice(&[0, 0, 0]);
        let d = compare_to_reference(&got, &want, 4, BOUND);
        assert_eq!(d.beyond, 3);
        assert!(!d.passes(), "{d:?}");
    }

    #[test]
    fn a_colour_no_neighbour_has_fails_however_few() {
        let want = halves();
        let mut got = want.clone();
        // Pixel (0, 0), in the flat black region, turns grey by 5: beyond tolerance 3.
        got[..3].copy_from_slice(&[5, 5, 5]);
        let d = compare_to_reference(&got, &want, 4, BOUND);
        assert_eq!(
            d.outside_neighbourhood,
            vec![(0, 0, [5, 5, 5, 255], [0, 0, 0, 255])]
        );
        assert!(!d.passes());
        // By 3, within tolerance.
        got[..3].copy_from_slice(&[3, 3, 3]);
        assert!(compare_to_reference(&got, &want, 4, BOUND).passes());
    }
}
