//! The generators' source of choices: SplitMix64 from a seed, or a fuzzer's bytes first.

/// A small deterministic generator (SplitMix64); proptest draws the seeds. Built with
/// [`Rng::from_bytes`], it first spends a fuzzer's bytes as its choices (one byte for a choice
/// among at most 256), so a mutated byte changes one decision, then continues as SplitMix64.
#[derive(Debug, Clone)]
pub struct Rng {
    state: u64,
    tape: Vec<u8>,
    read: usize,
}

impl Rng {
    /// From a seed.
    pub fn new(seed: u64) -> Rng {
        Rng {
            state: seed ^ 0x9e37_79b9_7f4a_7c15,
            tape: Vec::new(),
            read: 0,
        }
    }

    /// Choices from `bytes` first (a coverage-guided fuzzer's input), then SplitMix64.
    pub fn from_bytes(bytes: &[u8]) -> Rng {
        Rng {
            tape: bytes.to_vec(),
            ..Rng::new(bytes.len() as u64)
        }
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        if let Some(chunk) = self.tape.get(self.read..self.read + 8) {
            self.read += 8;
            let mut word = [0; 8];
            word.copy_from_slice(chunk);
            return u64::from_le_bytes(word);
        }
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `0..n`.
    pub fn below(&mut self, n: usize) -> usize {
        if n <= 256
            && let Some(&byte) = self.tape.get(self.read)
        {
            self.read += 1;
            return usize::from(byte) % n;
        }
        (self.next_u64() % n as u64) as usize
    }

    /// True with probability `p` percent.
    pub fn chance(&mut self, p: usize) -> bool {
        self.below(100) < p
    }

    /// One of the items.
    pub fn pick<'a, X>(&mut self, items: &'a [X]) -> &'a X {
        &items[self.below(items.len())]
    }
}
