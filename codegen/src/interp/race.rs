//! Data races on workgroup memory: an invocation reading or writing an element another
//! invocation wrote since the last barrier, with no barrier between, is an error naming both
//! places (WGSL leaves such a race undefined; on hardware it is a missing `workgroup_barrier()`
//! that works or not by the timing of the day). Atomics are exempt: they are made for it.
//!
//! The same tracker can also refuse reads of elements that no invocation of the workgroup
//! wrote ([`EvalError::Unwritten`]), the trace of an append that skipped a slot.
//!
//! The tracker is shared by the invocations of one workgroup (coroutines on one thread); the
//! scheduler starts a new epoch at every barrier it releases.

use std::collections::BTreeMap;

use super::error::EvalError;

/// Where an element of workgroup memory was last written.
#[derive(Debug, Clone, Copy)]
struct Write {
    invocation: u32,
    epoch: u64,
    line: usize,
    column: usize,
}

/// The writes to workgroup memory since the workgroup started.
#[derive(Debug, Default)]
pub(crate) struct Tracker {
    /// Report races.
    races: bool,
    /// Report reads of elements nothing wrote.
    unwritten: bool,
    epoch: u64,
    /// By static and path (array indices, fields, components) from it.
    writes: BTreeMap<(usize, Vec<i64>), Write>,
}

/// One access to check: who, where in the source, what.
pub(crate) struct Access<'a> {
    pub invocation: u32,
    pub line: usize,
    pub column: usize,
    pub global: usize,
    pub path: &'a [i64],
    /// The static's name, for the message.
    pub name: &'a str,
}

fn place(name: &str, path: &[i64]) -> String {
    let mut s = name.to_owned();
    for i in path {
        s.push_str(&format!("[{i}]"));
    }
    s
}

impl Tracker {
    pub fn new(races: bool, unwritten: bool) -> Self {
        Tracker {
            races,
            unwritten,
            ..Tracker::default()
        }
    }

    /// A barrier was released: earlier writes are ordered before everything after it.
    pub fn barrier(&mut self) {
        self.epoch += 1;
    }

    /// The write of this epoch by another invocation that overlaps `a`'s place: the place
    /// itself, a part of it, or a whole it is part of.
    fn conflict(&self, a: &Access) -> Option<(Vec<i64>, Write)> {
        if !self.races {
            return None;
        }
        self.overlapping(a, |w| w.epoch == self.epoch && w.invocation != a.invocation)
    }

    /// A write that overlaps `a`'s place and passes `other`.
    fn overlapping(&self, a: &Access, other: impl Fn(&Write) -> bool) -> Option<(Vec<i64>, Write)> {
        // Writes to the place or its parts.
        let start = (a.global, a.path.to_vec());
        for ((g, p), w) in self.writes.range(start..) {
            if *g != a.global || !p.starts_with(a.path) {
                break;
            }
            if other(w) {
                return Some((p.clone(), *w));
            }
        }
        // Writes to a whole the place is part of.
        (0..a.path.len()).find_map(|n| {
            let key = (a.global, a.path[..n].to_vec());
            self.writes
                .get(&key)
                .filter(|w| other(w))
                .map(|w| (key.1.clone(), *w))
        })
    }

    fn race(a: &Access, written: &[i64], w: Write, verb: &str) -> EvalError {
        EvalError::Race(format!(
            "invocation {} wrote `{}` at {}:{} and invocation {} {verb} `{}` at {}:{} with no \
             barrier between; add a workgroup_barrier() after the write",
            w.invocation,
            place(a.name, written),
            w.line,
            w.column,
            a.invocation,
            place(a.name, a.path),
            a.line,
            a.column
        ))
    }

    /// Checks a read.
    pub fn read(&self, a: &Access) -> Result<(), EvalError> {
        if let Some((p, w)) = self.conflict(a) {
            return Err(Self::race(a, &p, w, "reads"));
        }
        if self.unwritten && self.overlapping(a, |_| true).is_none() {
            return Err(EvalError::Unwritten(format!(
                "invocation {} reads `{}` at {}:{}, which no invocation of its workgroup wrote \
                 (WGSL reads zero there); look for the write that missed it",
                a.invocation,
                place(a.name, a.path),
                a.line,
                a.column
            )));
        }
        Ok(())
    }

    /// Checks a write and records it.
    pub fn write(&mut self, a: &Access) -> Result<(), EvalError> {
        if let Some((p, w)) = self.conflict(a) {
            return Err(Self::race(a, &p, w, "writes"));
        }
        self.writes.insert(
            (a.global, a.path.to_vec()),
            Write {
                invocation: a.invocation,
                epoch: self.epoch,
                line: a.line,
                column: a.column,
            },
        );
        Ok(())
    }
}
